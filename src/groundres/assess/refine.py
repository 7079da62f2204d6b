"""Extremes of each mode between the sweep's speeds, for the margins (:mod:`groundres.assess.margins`).

A mode's least damping ratio or largest real part at the sweep's speeds is
refined by a golden-section search, batched over the modes, in the bracket of
its neighbouring speeds where the mode still vibrates (up to where a creeping
root starts to vibrate, interpolated), following the root that continues the
mode's (:func:`groundres.assess.stability.continuing_roots`); an unstable range
too narrow to hold any of the sweep's speeds is searched inside. A golden
section needs no derivative and is not misled where two roots cross: the
extreme there is a kink.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..modes.identify import damping_ratio
from .stability import continuing_roots, growth_threshold, interpolated


@dataclass(frozen=True)
class Least:
    """An extreme of a mode over a range: ``value`` (a damping ratio [-], or a real part
    [1/s]) at ``speed`` [rad/s]; ``neutral`` where its real part there is within the growth
    threshold of zero (round-off: neither growth nor decay; a damping ratio is then 0)."""

    value: float
    speed: float
    neutral: bool = False


#: Without ``every`` (:func:`groundres.assess.margins.margins`), the modes refined: those
#: whose extreme at the sweep's speeds lies within this share of the overall one (plus the
#: growth threshold, or 1e-3 of damping ratio) of it; a refinement moves an extreme by far
#: less between the sweep's speeds.
NEAR = 0.25


class Refiner:
    """Extremes of each mode's damping ratio or real part between the sweep's speeds."""

    def __init__(self, roots_at, modes, speeds, unique, xtol, every, by_root, stillness, floor=0.0):
        self.roots_at, self.modes, self.speeds, self.unique, self.xtol = roots_at, modes, speeds, unique, xtol
        self.every, self.by_root, self.stillness, self.floor = every, by_root, stillness, floor

    def _edge(self, i: int, k: int, e: int) -> float:
        """Where root ``e`` starts vibrating between speeds ``i`` (where it counts) and its
        neighbour ``k`` (where it creeps), its stillness interpolated linearly."""
        s, w = self.stillness[:, e], self.speeds
        return float(w[i] + (w[k] - w[i]) * s[i] / (s[i] - s[k]))

    def growth(self, rows):
        """(value, speed, mode): the growth margin, the largest real part of the counting
        roots over the sweep, refined along the root that holds it at the sweep's speeds (up to
        where it starts vibrating): a root goes on across a veering, where labels move."""
        modes, speeds = self.modes, self.speeds
        real = np.where(self.by_root, modes.root_real_part, -np.inf)
        if not np.isfinite(real).any():
            return None
        i, e = np.unravel_index(int(np.argmax(real)), real.shape)
        value, at = float(real[i, e]), float(speeds[i])
        mode = modes.labels[int(modes.root_label[i, e])]
        ends = []
        for k in (i - 1, i + 1):
            if not 0 <= k < len(speeds):
                ends.append(float(speeds[i]))
            else:
                ends.append(float(speeds[k]) if self.by_root[k, e] else self._edge(i, k, e))
        a, b = max(ends[0], self.floor), ends[1]
        if b > a and speeds[i] > 0:
            near = [k for k in (i - 1, i, i + 1) if 0 <= k < len(speeds)]
            w, lam = speeds[near], modes.root_eigenvalue[near, e]
            if not self.unique:  # (a frequency known modulo the rotor speed: unwrapped between neighbours)
                cycles = np.divide(lam.imag - lam.imag[0], w, out=np.zeros(len(w)), where=w > 0)
                turn = np.angle(np.exp(2j * np.pi * cycles))
                lam = lam.real + 1j * (lam.imag[0] + turn * w / (2 * np.pi))

            def fun(x):
                target = np.interp(x, w, lam.real) + 1j * np.abs(np.interp(x, w, lam.imag))
                roots = np.asarray(self.roots_at(x)).reshape(len(x), -1)
                return -continuing_roots(roots, target, x, self.unique)[0].real

            refined, where = golden(fun, np.array([a]), np.array([b]), self.xtol)
            if -refined[0] > value:
                value, at = -float(refined[0]), float(where[0])
        return value, at, mode

    def within(self, found, counts, span, ranges, what, sign) -> None:
        """Update ``found`` (per mode, Least or None) with each mode's extreme inside the
        unstable ranges (start, end, {label: root at the range's peak, or None}) [rad/s] that
        hold none of the sweep's speeds, searched by golden section over the range within
        ``span``, following the root given (the sweep's modes interpolated where None): the
        modes that grow there and vibrate at the sweep's speed nearest it (or whose root there
        is known).
        """
        lo, hi = span
        columns, a, b, targets = [], [], [], []
        for start, end, roots in ranges:
            s, e = max(start, lo, self.floor), min(end, hi)
            i = int(np.argmin(np.abs(self.speeds - 0.5 * (start + end))))
            for label, root in roots.items() if e > s else ():
                j = self.modes.labels.index(label)
                if root is not None or counts[i, j]:
                    columns.append(j)
                    a.append(s)
                    b.append(e)
                    targets.append(root)
        if not columns:
            return
        values, where = golden(
            lambda w: sign * self._values(w, columns, what, targets), np.array(a), np.array(b), self.xtol
        )
        for j, value, at in zip(columns, values, where):
            if found[j] is None or value < sign * found[j].value:
                neutral = value == 0.0 if what == "ratio" else bool(abs(value) <= growth_threshold(at))
                found[j] = Least(sign * float(value), float(at), neutral)

    def _values(self, w, columns, what, targets=None):
        """Damping ratio or real part of each column's mode at its speed ``w`` (batched), the
        root continuing its target (``targets``: a root each, or None where the sweep's modes
        are interpolated)."""
        roots = np.asarray(self.roots_at(w))
        roots = roots.reshape(len(w), -1)
        expected = interpolated(self.modes, self.speeds, w, columns)
        if targets is not None:
            expected = np.array([e if t is None else complex(t) for e, t in zip(expected, targets)])
            expected = expected.real + 1j * np.abs(expected.imag)
        best, cand = continuing_roots(roots, expected, w, self.unique)
        if what == "real":
            return best.real
        ratio = damping_ratio(best, scale=np.abs(cand).max(axis=1))
        return np.where(np.abs(best.real) <= growth_threshold(w), 0.0, ratio)  # (neutral: round-off)

    def overall(self, rows, field, ratio, counts, span):
        """(value, speed, mode): the least damping ratio over ``span`` of every vibrating
        root, from the modes' own (``rows``, their ``field``) and refined over every root
        between the sweep's speeds around the grid's least, where every mode counts there
        (across a veering, where labels move, the roots go on)."""
        best = [(getattr(m, field).value, getattr(m, field).speed, m.mode) for m in rows if getattr(m, field)]
        if not best:
            return None
        value, at, mode = min(best)
        speeds = self.speeds
        lo, hi = span
        inside = (speeds >= lo) & (speeds <= hi)
        grid = np.where(inside[:, None] & counts, ratio, np.inf)
        i = int(np.argmin(np.nanmin(grid, axis=1)))
        a, b = max(speeds[max(i - 1, 0)], lo, self.floor), min(speeds[min(i + 1, len(speeds) - 1)], hi)
        ends = [int(np.argmin(np.abs(speeds - x))) for x in (a, b)]
        if not (b > a and speeds[i] > 0) or not all(counts[k].all() for k in ends):
            return value, at, mode  # (a creeping root near: the modes' own extremes stand)

        def fun(w):
            roots = np.asarray(self.roots_at(w)).reshape(len(w), -1)
            return np.array([self._least_ratio_at(r, x) for r, x in zip(roots, w)])

        refined, where = golden(fun, np.array([a]), np.array([b]), self.xtol)
        if refined[0] < value:
            value, at = float(refined[0]), float(where[0])
        return value, at, mode

    def _least_ratio_at(self, roots, w: float) -> float:
        """The least damping ratio at ``w`` [rad/s] over the roots that continue the modes
        (every root where frequencies are unique), a neutral root's as 0."""
        if self.unique:
            cand = roots.real + 1j * np.abs(roots.imag)
            scale = np.abs(cand).max()
        else:
            targets = interpolated(self.modes, self.speeds, w)
            k = len(targets)
            cand, every = continuing_roots(
                np.broadcast_to(roots, (k, len(roots))), targets, np.full(k, w), False
            )
            scale = np.abs(every).max()
        ratio = damping_ratio(cand, scale=scale)
        return float(np.where(np.abs(cand.real) <= growth_threshold(w), 0.0, ratio).min())

    def least(self, ratio, counts, span) -> list:
        """Per mode, its least damping ratio over ``span`` [rad/s] (Least, or None)."""
        return self._extreme(ratio, counts, span, "ratio", sign=1.0)

    def largest(self, real, counts) -> list:
        """Per mode, its largest real part over the sweep (Least, or None)."""
        return self._extreme(real, counts, (self.speeds[0], self.speeds[-1]), "real", sign=-1.0)

    def _extreme(self, values, counts, span, what, sign) -> list:
        lo, hi = span
        speeds = self.speeds
        inside = (speeds >= lo) & (speeds <= hi)
        out = [None] * values.shape[1]
        columns, brackets, found = [], [], {}
        for j in range(values.shape[1]):
            ok = inside & counts[:, j] & np.isfinite(values[:, j])
            if not ok.any():
                continue
            i = int(np.flatnonzero(ok)[np.argmin(sign * values[ok, j])])
            found[j] = (float(values[i, j]), float(speeds[i]))
            # the bracket: the neighbours where the mode counts too and its label stays on
            # its branch (a label that moves to another branch has no root to follow between)
            moved = self.modes.exchange[:, j]
            a = b = speeds[i]
            if i > 0 and not moved[i]:  # (towards a neighbour where the mode is still: up to where it starts)
                a = speeds[i - 1] if counts[i - 1, j] else self._edge(i, i - 1, self.modes.branch[i, j])
            if i + 1 < len(speeds) and not moved[i + 1]:
                b = speeds[i + 1] if counts[i + 1, j] else self._edge(i, i + 1, self.modes.branch[i, j])
            a, b = max(a, lo, self.floor), min(b, hi)
            if b > a and speeds[i] > 0:
                columns.append(j)
                brackets.append((a, b))
        if found and not self.every:  # only the modes that can hold the overall extreme
            best = min(sign * v for v, _ in found.values())
            slack = NEAR * abs(best) + (1e-3 if what == "ratio" else float(growth_threshold(speeds[-1])))
            chosen = {j for j, (v, _) in found.items() if sign * v <= best + slack}
            kept = [(j, ab) for j, ab in zip(columns, brackets) if j in chosen]
            columns, brackets = [j for j, _ in kept], [ab for _, ab in kept]
        else:
            chosen = set(range(values.shape[1]))
        if columns:
            a, b = (np.array(x, float) for x in zip(*brackets))
            refined = golden(lambda w: sign * self._values(w, columns, what), a, b, self.xtol)
            for j, value, at in zip(columns, *refined):
                if value < sign * found[j][0]:  # (the refined extreme beats the sweep's)
                    found[j] = (sign * float(value), float(at))
        # the span's ends themselves, where they fall between the sweep's speeds (a search only
        # nears an end, and the extreme over a span may lie at an end no bracket reaches)
        ends = []
        for j in range(values.shape[1]):
            if found and j not in chosen:
                continue
            for end in (lo, hi):
                i = int(np.argmin(np.abs(speeds - end)))
                near = self.modes.exchange[max(i, 1) : i + 2, j].any() if len(speeds) > 1 else False
                if end not in speeds and end > max(self.floor, 0.0) and counts[i, j] and not near:
                    ends.append((j, end))
        if ends:
            cols, w = zip(*ends)
            for j, value, at in zip(cols, sign * self._values(np.array(w, float), list(cols), what), w):
                if j not in found or value < sign * found[j][0]:
                    found[j] = (sign * float(value), float(at))
        for j, (value, at) in found.items():
            neutral = value == 0.0 if what == "ratio" else bool(abs(value) <= growth_threshold(at))
            out[j] = Least(float(value), float(at), neutral)
        return out


def golden(fun, a, b, xtol, most: int = 60):
    """Minima of ``fun`` (batched: ``fun(x)`` for an array of k points, one per bracket) over
    the brackets [a, b] (k,), by golden-section search to ``xtol`` of the speed (of the bracket's
    upper end as given: a search that closes on a speed near rest does not narrow its step with
    it, where a periodic analysis costs most); the value and where, (k,) each, the better of the
    last two points."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = a.copy(), b.copy()
    scale = np.maximum(np.abs(b), 1e-300)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = fun(c), fun(d)
    for _ in range(most):
        if np.all(b - a <= xtol * scale):
            break
        left = fc <= fd
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        d_new = np.where(left, c, a + g * (b - a))
        c_new = np.where(left, b - g * (b - a), d)
        x = np.where(left, c_new, d_new)
        fx = fun(x)
        fc, fd = np.where(left, fx, fd), np.where(left, fc, fx)
        c, d = c_new, d_new
    first = fc <= fd
    return np.where(first, fc, fd), np.where(first, c, d)
