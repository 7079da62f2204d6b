"""Which roots make one mode: conjugate pairs, and pairs of real roots.

A mode is a conjugate pair of roots, or two real roots where it is
overdamped. For a periodic system the conjugate of an exponent is found
through the multipliers (exponents are conjugate modulo Omega).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from .participation import ZERO


def _best_matching(items, cost):
    """Pairs of ``items`` of least total ``cost[a, b]`` (all pairings up to 10 items, else greedy)."""
    items = list(items)
    if len(items) > 10:
        out, left = [], items
        while len(left) > 1:
            a, b = min(((a, b) for a in left for b in left if a < b), key=lambda p: cost[p])
            out.append((a, b))
            left = [i for i in left if i not in (a, b)]
        return out

    def best(left):
        if len(left) < 2:
            return 0.0, []
        first, rest = left[0], left[1:]
        options = []
        for i, b in enumerate(rest):
            total, pairs = best(rest[:i] + rest[i + 1 :])
            options.append((total + cost[first, b], [(first, b)] + pairs))
        return min(options, key=lambda o: o[0])

    return best(items)[1]


def _pair_one(z, frac, sigma, still, shapes, previous=None):
    """Group the roots of one block at one speed into modes.

    ``z`` is each root's pairing key (the eigenvalue, or the Floquet
    multiplier): keys above the real axis pair with the nearest conjugate
    below it. Real keys pair by least total cost over all pairings. Two roots
    whose motion is at zero frequency (``still`` near 1: an overdamped
    oscillator) cost 1 - MAC of their shapes (``shapes``, weighted harmonics,
    one row per root), plus one if both lie on the same side of the median of
    the still roots: the two roots of one overdamped oscillator move alike,
    one slow and one fast; two roots of one degenerate cluster do neither
    (their shapes are any basis of the cluster). Two real keys whose motion is at a nonzero frequency (an
    overdamped cyclic lag seen at Omega from nonrotating axes, a parametric
    root at Omega/2) are the halves of a conjugate pair of that frequency that
    the periodic analysis cannot tell apart: they also cost the relative
    difference of their real parts ``sigma``, as the time-invariant analysis
    of the same system would pair them. A zero-frequency root with a moving
    one costs one more. Real roots that were paired at the previous speed
    (``previous``: each column's partner there, or None) stay paired while
    both are real, so that a mode's roots do not change partners (and its
    real part jump) from one speed to the next. Returns a list of
    (representative, other): the representative has Im z >= 0, or the larger
    real part of two real roots (the less damped, whatever the method).
    """
    small = ZERO * np.maximum(np.abs(z), 1e-300)
    upper = np.flatnonzero(z.imag > small)
    lower = np.flatnonzero(z.imag < -small)
    rest = list(np.flatnonzero(np.abs(z.imag) <= small))
    pairs = []
    if len(upper) and len(lower):
        r, c = linear_sum_assignment(np.abs(z[upper][:, None] - z[lower][None, :].conj()))
        pairs += [(upper[i], lower[j]) for i, j in zip(r, c)]
        rest += [upper[i] for i in set(range(len(upper))) - set(r)]
        rest += [lower[j] for j in set(range(len(lower))) - set(c)]
    else:
        rest += list(upper) + list(lower)
    if previous is not None:
        kept = [(a, int(previous[a])) for a in rest if int(previous[a]) in rest and a < previous[a]]
        pairs += kept
        done = {i for p in kept for i in p}
        rest = [a for a in rest if a not in done]
    if rest:
        idx = np.array(rest)
        content = np.abs(frac[idx][:, None] - frac[idx][None, :]).sum(-1)
        sg = sigma[idx]
        apart = np.abs(sg[:, None] - sg[None, :]) / (np.abs(sg[:, None]) + np.abs(sg[None, :]) + 1e-300)
        st = still[idx]
        both_still = st[:, None] * st[None, :]
        both_moving = (1 - st[:, None]) * (1 - st[None, :])
        v = shapes[idx]
        gram = np.abs(v.conj() @ v.T) ** 2
        norm = np.real(np.einsum("ij,ij->i", v.conj(), v))
        mac = gram / np.maximum(np.outer(norm, norm), 1e-300)
        # two still roots on the same side of the still roots' median value
        # (or of equal value) belong to two oscillators, not one
        still_sg = sg[st > 0.5]
        mid = np.median(still_sg) if len(still_sg) else 0.0
        same_side = ((sg[:, None] - mid) * (sg[None, :] - mid) >= 0) | (apart < 1e-3)
        cost = (
            both_still * (1 - mac + same_side)
            + both_moving * (content + apart)
            + (1 - both_still - both_moving)
        )
        local = _best_matching(range(len(idx)), cost)
        pairs += [(idx[a], idx[b]) for a, b in local]
    key = lambda j: (z[j].imag >= 0, sigma[j])  # noqa: E731
    return [(a, b) if key(a) >= key(b) else (b, a) for a, b in pairs]


def pair_roots(z, frac, sigma, still, shapes, carry=None):
    """Representative and other root of every mode at every speed: (n_s, n_e/2) each.

    ``carry`` (n_s,) says where the previous speed's pairs of real roots may be
    kept (not after the rotor at rest, whose degenerate roots pair anyhow).
    """
    n_s, n_e = z.shape
    half = n_e // 2
    small = ZERO * np.maximum(np.abs(z), 1e-300)
    upper = z.imag > small
    reps = np.argsort(~upper, axis=-1, kind="stable")[:, :half]
    partner = np.argmin(np.abs(z[:, :, None] - z[:, None, :].conj()), axis=-1)
    others = np.take_along_axis(partner, reps, -1)
    # all roots in conjugate pairs, each found once (else the careful way)
    taken = np.zeros((n_s, n_e), int)
    np.put_along_axis(taken, others, 1, axis=-1)
    plain = (upper.sum(-1) == half) & (taken.sum(-1) == half) & ~(taken.astype(bool) & upper).any(-1)
    carry = np.ones(n_s, bool) if carry is None else carry
    for k in np.flatnonzero(~plain):  # in speed order: real roots keep their partners
        previous = None
        if k > 0 and carry[k]:
            previous = np.empty(n_e, int)
            previous[reps[k - 1]] = others[k - 1]
            previous[others[k - 1]] = reps[k - 1]
        reps[k], others[k] = zip(*_pair_one(z[k], frac[k], sigma[k], still[k], shapes[k], previous))
    return reps, others
