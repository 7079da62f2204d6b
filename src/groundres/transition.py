"""Transition matrices of the periodic equations on a fixed azimuth grid.

The blade-coordinate equations M(psi) q'' + C(psi) q' + K(psi) q = 0 are
integrated in the azimuth psi = Omega t. With q' = dq/dpsi they read

    q'' = (F_a(psi) + F_b(psi) / Omega + F_c(psi) / Omega^2) [q; q'],

because the mass matrix does not depend on Omega, damping is C0 + Omega C1 and
stiffness K0 + Omega K1 + Omega^2 K2 (dampers and springs; Coriolis;
centrifugal). The three F matrices are evaluated exactly from the derived
harmonics at the nodes of a fixed azimuth grid, once for all speeds, so that a
step for every speed of a sweep costs a few batched matrix products.

The integrator is the eighth-order Runge-Kutta method of Dormand and Prince
(the twelve stages of DOP853) on a fixed grid, chosen on evidence: for
multipliers to 1e-10 it needs three to five times fewer stage evaluations
than a sixth-order method (Butcher 1964, kept as BUTCHER6 for comparison). The
equations are linear, so every step's propagator is formed independently, for
all steps and speeds of a batch at once, and multiplied together by pairwise
reduction. The step count is chosen per speed: a first guess from the fastest
rate of the system per radian, then a Richardson estimate against a coarser
grid, and more steps where it is not met (:func:`integrate`). Speeds with the
same step count are integrated together. ``benchmarks/bench_floquet.py``
compares it with SciPy's adaptive DOP853.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction as _F

import numpy as np

from . import _dop853
from .parallel import CORES, map_threads
from .system import System

# Butcher (1964) sixth-order, seven-stage explicit Runge-Kutta method.
_C = [0, _F(1, 3), _F(2, 3), _F(1, 3), _F(1, 2), _F(1, 2), 1]
_A = [
    [],
    [_F(1, 3)],
    [0, _F(2, 3)],
    [_F(1, 12), _F(1, 3), _F(-1, 12)],
    [_F(-1, 16), _F(9, 8), _F(-3, 16), _F(-3, 8)],
    [0, _F(9, 8), _F(-3, 8), _F(-3, 4), _F(1, 2)],
    [_F(9, 44), _F(-9, 11), _F(63, 44), _F(18, 11), 0, _F(-16, 11)],
]
_B = [_F(11, 120), 0, _F(27, 40), _F(27, 40), _F(-4, 15), _F(-4, 15), _F(11, 120)]


@dataclass(frozen=True)
class Tableau:
    """An explicit Runge-Kutta method: nodes c, matrix a (lower triangular), weights b."""

    c: np.ndarray
    a: np.ndarray
    b: np.ndarray
    order: int

    @classmethod
    def from_lists(cls, c, a, b, order):
        s = len(c)
        mat = np.zeros((s, s))
        for i, row in enumerate(a):
            mat[i, : len(row)] = [float(v) for v in row]
        return cls(np.array([float(v) for v in c]), mat, np.array([float(v) for v in b]), order)


BUTCHER6 = Tableau.from_lists(_C, _A, _B, 6)
#: Dormand-Prince eighth-order method (DOP853's twelve stages) on a fixed grid:
#: for multipliers to 1e-10 it needs three to five times fewer stage
#: evaluations than BUTCHER6 on the shipped cases (benchmarks/bench_floquet.py).
DOP8 = Tableau.from_lists(_dop853.C, _dop853.A, _dop853.B, 8)
#: First guess of step * (fastest rate per radian + HARMONIC_RATE).
STEP_SCALE = 1.0
#: Rate [1/rad] added for the azimuth variation of the coefficients themselves.
HARMONIC_RATE = 2.0
#: Accuracy asked of the transition matrix (entries, relative to max(1, |Phi|)).
TOLERANCE = 5e-11
#: Smallest step count per interval (the first rung of the step ladder).
BASE_STEPS = 32
#: Largest step count per interval.
MAX_STEPS = 1 << 20
#: Steps over an interval per (radians of the fastest motion)^(9/8) (:func:`estimated_steps`).
STEPS_FACTOR = 3.0


class SpeedRangeError(ValueError):
    """A rotor speed too low (too close to zero, but not zero) for Floquet analysis."""

    def __init__(self, speed: float, why: str):
        super().__init__(
            f"[sweep] Floquet analysis at {speed:.4g} rad/s {why}: the case's dampers or springs "
            "decay too fast for the periodic analysis at that rotor speed; start the sweep at a "
            "speed a few times higher, or use method = 'auto' where the case has a time-invariant form"
        )
        self.speed = speed


def _harmonic_basis(psi):
    """(1, cos psi, sin psi, cos 2 psi, sin 2 psi) along a new last axis."""
    return np.stack([np.ones_like(psi), np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)], -1)


def node_matrices(system: System, psi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F_a, F_b, F_c at azimuths ``psi`` (any shape), each (..., n, 2n).

    q'' = (F_a + F_b / Omega + F_c / Omega^2) [q; q'] with ' = d/dpsi.

    Every coefficient of the blade-coordinate equations is a trigonometric
    polynomial of degree two in the azimuth, so the mass, damping and
    stiffness matrices are fitted exactly from five azimuths (at three
    speeds, which separate C0 + Omega C1 and K0 + Omega K1 + Omega^2 K2) and
    evaluated at the nodes from their harmonics.
    """
    psi = np.asarray(psi, dtype=float)
    theta = 2 * np.pi * np.arange(5) / 5
    probe = np.array([0.0, 1.0, 2.0])
    m, c, k = system.matrices(probe, theta[:, None])  # (5 azimuths, 3 speeds, n, n)
    c0, c1 = c[:, 0], c[:, 1] - c[:, 0]
    k0 = k[:, 0]
    k2 = (k[:, 2] - 2 * k[:, 1] + k0) / 2
    k1 = k[:, 1] - k0 - k2
    n = m.shape[-1]
    values = np.zeros((5, 2, n, 6 * n))  # mass (in the first n columns), right-hand sides
    values[:, 0, :, :n] = m[:, 0]
    values[:, 1] = np.concatenate([k2, c1, k1, c0, k0, np.zeros_like(k0)], -1)
    coeff = np.einsum("hj,jxab->hxab", np.linalg.inv(_harmonic_basis(theta)), values)
    at = np.einsum("...h,hxab->...xab", _harmonic_basis(psi), coeff, optimize=True)
    sol = -np.linalg.solve(at[..., 0, :, :n], at[..., 1, :, :])
    n2 = 2 * n
    return sol[..., :n2], sol[..., n2 : 2 * n2], sol[..., 2 * n2 :]


def frozen_roots(system: System, speeds, probes=2) -> np.ndarray:
    """Roots [1/rad] of the azimuth-domain system held at a few azimuths, (probes, n_s, 2n)."""
    speeds = np.asarray(speeds, dtype=float)
    psi = np.linspace(0, 2 * np.pi, probes, endpoint=False)
    fa, fb, fc = node_matrices(system, psi)
    inv = 1.0 / speeds
    f = fa[:, None] + fb[:, None] * inv[:, None, None] + fc[:, None] * (inv**2)[:, None, None]
    n = f.shape[-2]
    a = np.zeros(f.shape[:-2] + (2 * n, 2 * n))
    a[..., :n, n:] = np.eye(n)
    a[..., n:, :] = f
    return np.linalg.eigvals(a)


def rates_per_radian(system: System, speeds, probes=2) -> np.ndarray:
    """Fastest rate of the azimuth-domain system [1/rad] at each speed (from a few azimuths)."""
    return np.abs(frozen_roots(system, speeds, probes)).max(-1).max(0)


def frozen_rates(system: System, speeds, probes=4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fastest rate per radian and smallest, largest real part [1/s] from one frozen solve.

    (:func:`rates_per_radian` and the real parts at once; azimuths 0, pi/2, pi,
    3 pi/2). The roots of the equations with the azimuth held fixed bound those
    of the periodic system roughly (a blade without damper keeps its neutral
    root, the others their damping), which the lifted Floquet problem needs
    before it has any root.
    """
    speeds = np.asarray(speeds, dtype=float)
    roots = frozen_roots(system, speeds, probes)
    real = roots.real * speeds[:, None]
    return np.abs(roots).max(-1).max(0), real.min(-1).min(0), real.max(-1).max(0)


#: Largest node grid kept on a system [values]; finer grids are evaluated in pieces.
GRID_CACHE_SIZE = 4_000_000


def grid_matrices(
    system: System, angle: float, steps: int, tableau=DOP8, first: int = 0, last: int | None = None
):
    """F_a, F_b, F_c at the stage nodes of steps first..last of a fixed grid: each (k, stages, n, 2n).

    Grids up to GRID_CACHE_SIZE values are kept on the system (a few of them)
    so that repeated analyses reuse them; finer ones are evaluated as asked.
    """
    last = steps if last is None else last
    h = angle / steps
    n = system.size
    if steps * len(tableau.c) * n * 2 * n * 3 > GRID_CACHE_SIZE:
        return node_matrices(system, (np.arange(first, last)[:, None] + tableau.c[None, :]) * h)
    key = (angle, int(steps), id(tableau))
    if key not in system.grid_cache:
        if len(system.grid_cache) > 16:
            system.grid_cache.clear()
        system.grid_cache[key] = node_matrices(system, (np.arange(steps)[:, None] + tableau.c[None, :]) * h)
    return tuple(x[first:last] for x in system.grid_cache[key])


def ordered_product(p):
    """P[-1] @ ... @ P[1] @ P[0] over the first axis, by pairwise reduction."""
    while p.shape[0] > 1:
        if p.shape[0] % 2:
            tail = p[-1:]
            p = np.concatenate([p[1:-1:2] @ p[0:-1:2], tail])
        else:
            p = p[1::2] @ p[0::2]
    return p[0]


def _step_propagators(fa, fb, fc, inv, h, tableau):
    """One-step propagators of the Runge-Kutta method for every step and speed.

    The equation is linear, so each step's propagator P = I + h sum b_i K_i
    (stages started from the identity) is independent of the others and all
    are formed at once: arrays (steps, n_s, 2n, 2n). With y = [q; v] and
    v' = F y, a stage is K_i = [V_i; F_i Y_i]; only the lower halves
    L_i = F_i Y_i are stored, because the upper halves follow from them:
    Y_i = [I_q + h c_i I_v + h^2 sum (A^2)_il L_l ; I_v + h sum a_il L_l].
    """
    steps, stages, n, n2 = fa.shape
    n_s = len(inv)
    coef = np.stack([np.ones_like(inv), inv, inv**2])  # (3, n_s)
    # F at every node and speed with one matrix product, laid out (stages, steps, n_s, n, 2n)
    nodes = np.stack([fa, fb, fc], 2).reshape(steps, stages, 3, n * n2)
    f = np.einsum("tspm,pk->stkm", nodes, coef, optimize=True).reshape(stages, steps, n_s, n, n2)
    a, b, c = tableau.a, tableau.b, tableau.c
    a2 = a @ a
    eye_q, eye_v = np.eye(n2)[:n], np.eye(n2)[n:]
    low = np.empty((stages, steps, n_s, n, n2))
    y = np.empty((steps, n_s, n2, n2))
    for i in range(stages):
        if i == 0:
            low[0] = f[0]  # Y_1 = I
            continue
        weights = np.stack([h * h * a2[i, :i], h * a[i, :i]])
        both = np.tensordot(weights, low[:i], axes=(1, 0))  # (2, steps, n_s, n, 2n)
        y[..., :n, :] = both[0] + (eye_q + h * c[i] * eye_v)
        y[..., n:, :] = both[1] + eye_v
        np.matmul(f[i], y, out=low[i])
    weights = np.stack([h * h * (b @ a), h * b])
    both = np.tensordot(weights, low, axes=(1, 0))
    out = np.empty((steps, n_s, n2, n2))
    out[..., :n, :] = both[0] + (eye_q + h * b.sum() * eye_v)
    out[..., n:, :] = both[1] + eye_v
    return out


#: Stage values formed at once by one task (about 25 MB).
STAGE_BUDGET = 3_000_000


def transition(system: System, speeds, angle: float, steps: int, blocks: int = 1, tableau=DOP8):
    """Azimuth-domain transition matrices over equal parts of [0, angle], for a batch of speeds.

    Parameters
    ----------
    system : System
    speeds : ndarray (n_s,)
        Rotor speeds [rad/s] integrated together.
    angle : float
        Azimuth interval [rad].
    steps : int
        Fixed steps over the interval (a multiple of ``blocks``).
    blocks : int
        Number of equal consecutive parts of the interval.
    tableau : Tableau

    Returns
    -------
    ndarray (blocks, n_s, 2n, 2n)
        Transition matrix of y = [q; dq/dpsi] over each part; their ordered
        product (:func:`ordered_product`) is the one over [0, angle].

    The work is split into tasks (threads) of a few speeds and a run of steps
    each, so that memory stays bounded however fine the grid: whole parts
    where they are short, pieces of a part multiplied together where long.
    """
    speeds = np.asarray(speeds, dtype=float)
    h = angle / steps
    n = system.size
    n2 = 2 * n
    per = steps // blocks
    width = min(len(speeds), -(-len(speeds) // CORES))  # at least one batch per core
    room = max(1, int(STAGE_BUDGET // (len(tableau.c) * n * n2 * width)))  # steps per task
    groups = [speeds[i : i + width] for i in range(0, len(speeds), width)]
    if per <= room:
        k = max(1, room // per)
        runs = [(b, min(b + k, blocks)) for b in range(0, blocks, k)]
    else:
        runs = [(b, b + 1) for b in range(blocks)]

    def task(item):
        w, (b0, b1) = item
        inv = 1.0 / w
        if per <= room:
            nodes = grid_matrices(system, angle, steps, tableau, b0 * per, b1 * per)
            props = _step_propagators(*nodes, inv, h, tableau)  # ((b1-b0) per, k, 2n, 2n)
            return ordered_product(np.swapaxes(props.reshape((b1 - b0, per) + props.shape[1:]), 0, 1))
        out = None
        for s0 in range(b0 * per, b1 * per, room):
            s1 = min(s0 + room, b1 * per)
            p = ordered_product(
                _step_propagators(*grid_matrices(system, angle, steps, tableau, s0, s1), inv, h, tableau)
            )
            out = p if out is None else p @ out
        return out[None]

    items = [(w, r) for w in groups for r in runs]
    done = map_threads(task, items)
    out = np.empty((blocks, len(speeds), n2, n2))
    start = 0
    k = 0
    for g in groups:
        for b0, b1 in runs:
            out[b0:b1, start : start + len(g)] = done[k]
            k += 1
        start += len(g)
    return out


def estimated_steps(system: System, speeds, angle: float, rate=None) -> np.ndarray:
    """Steps over [0, angle] the step control will settle on at each speed, estimated (n_s,).

    The error of an order-p method over S steps of an interval spanning
    angle * rate radians of the fastest motion goes as S (angle rate / S)^(p+1),
    so S ~ (angle rate)^((p+1)/p); the factor is fitted to DOP8 at
    :data:`TOLERANCE` on the shipped cases (within about 30 %).
    """
    rate = (rates_per_radian(system, speeds) if rate is None else rate) + HARMONIC_RATE
    return np.maximum(BASE_STEPS, STEPS_FACTOR * (angle * rate) ** (9 / 8))


def divisor_at_least(count: int, need: int) -> int:
    """The smallest divisor of ``count`` that is >= ``need`` (``count`` if none is)."""
    for d in range(max(1, int(need)), count):
        if count % d == 0:
            return d
    return count


def ladder(samples):
    """Allowed step counts: multiples of ``samples`` growing by factors 1.5 and 4/3."""
    out, k = [], 1
    while k * samples <= MAX_STEPS:
        out.append(k * samples)
        k = 2 if k == 1 else (k * 3 // 2 if k % 2 == 0 else k * 4 // 3)
    return np.array(sorted(set(out)))


def _estimate(run, sel, count, fine_phi, size, previous, ladder_, p):
    """Richardson estimate of the error of each speed's transition matrix (relative)."""
    if all(i in previous for i in sel):
        ref_steps = np.array([previous[i][0] for i in sel])
        ref_phi = np.stack([previous[i][1] for i in sel])
        return np.abs(fine_phi - ref_phi).max((-1, -2)) / ((count / ref_steps) ** p - 1) / size
    pos = np.searchsorted(ladder_, count)
    coarse = ladder_[pos - 2] if pos >= 2 else count // 2
    # The truncation error varies smoothly with speed: the coarse comparison
    # runs on every fourth speed of the batch (and its ends), each speed
    # taking the larger estimate of its sampled neighbours.
    probe = np.unique(np.r_[np.arange(0, len(sel), 4), len(sel) - 1])
    ref_phi = run(sel[probe], coarse, 1)[0]
    sampled_est = np.abs(fine_phi[probe] - ref_phi).max((-1, -2)) / size[probe]
    sampled_est /= (count / coarse) ** p - 1
    right = np.clip(np.searchsorted(probe, np.arange(len(sel))), 0, len(probe) - 1)
    left = np.clip(right - (probe[right] > np.arange(len(sel))), 0, len(probe) - 1)
    return np.maximum(sampled_est[left], sampled_est[right])


def integrate(
    system,
    speeds,
    angle,
    tolerance=TOLERANCE,
    scale=STEP_SCALE,
    tableau=DOP8,
    blocks_for=None,
    accept=None,
    rate=None,
):
    """Transition over [0, angle], step count adapted per speed.

    Each speed is integrated with S steps and with fewer steps S' on the same
    ladder; the Richardson estimate |Phi_S - Phi_S'| / ((S/S')^p - 1) of the
    error of Phi_S decides. A speed that fails is integrated again with the
    step count the estimate predicts (error ~ S^-p), and its last result
    serves as the next comparison.

    Parameters
    ----------
    blocks_for : callable, optional
        ``blocks_for(steps, indices) -> int``: into how many equal parts the
        interval is split for the speeds ``indices`` integrated with ``steps``
        (a divisor of ``steps``); 1 by default.
    accept : callable, optional
        ``accept(indices, phi, parts, steps)`` is called once for every speed
        with its final result: ``phi`` (k, 2n, 2n) over the interval, ``parts``
        (blocks, k, 2n, 2n) over its parts.
    rate : ndarray, optional
        Fastest rate per radian at each speed, if known (:func:`rates_per_radian`).

    Returns
    -------
    phi : ndarray (n_s, 2n, 2n)
    steps : int ndarray (n_s,)
    """
    blocks_for = blocks_for or (lambda count, sel: 1)
    ladder_ = ladder(BASE_STEPS)
    rate = rates_per_radian(system, speeds) if rate is None else rate
    need = estimated_steps(system, speeds, angle, rate)
    if need.max() > MAX_STEPS:  # refused before any work: the ladder would climb to its top in vain
        i = int(np.argmax(need))
        raise SpeedRangeError(
            float(speeds[i]), f"needs about {need[i]:.2g} steps per period (at most {MAX_STEPS} are taken)"
        )
    guess = angle * (rate + HARMONIC_RATE) / scale
    steps = ladder_[np.minimum(np.searchsorted(ladder_, guess), len(ladder_) - 1)]
    n2 = 2 * system.size
    p = tableau.order
    phi = np.empty((len(speeds), n2, n2))
    previous = {}  # speed index -> (steps, phi) of its last rejected run
    pending = np.arange(len(speeds))

    def run(sel, count, blocks):
        return transition(system, speeds[sel], angle, int(count), blocks, tableau)

    for attempt in range(10):
        if not len(pending):
            break
        retry = []
        for count in np.unique(steps[pending]):
            sel = pending[steps[pending] == count]
            # a step count too small for the explicit method blows up: caught below
            with np.errstate(over="ignore", invalid="ignore"):
                parts = run(sel, count, blocks_for(int(count), sel))
                fine_phi = ordered_product(parts)
                size = np.maximum(np.abs(fine_phi).max((-1, -2)), 1.0)
                estimate = _estimate(run, sel, count, fine_phi, size, previous, ladder_, p)
            phi[sel] = fine_phi
            done = []
            pos = np.searchsorted(ladder_, count)
            for j, i in enumerate(sel):
                finite = bool(np.isfinite(estimate[j]) and np.isfinite(fine_phi[j]).all())
                if finite:
                    want = count * (estimate[j] / tolerance) ** (1 / p) * 1.1
                    more = ladder_[min(np.searchsorted(ladder_, want), len(ladder_) - 1)]
                else:  # the explicit method went unstable: many more steps
                    more = ladder_[min(pos + 3, len(ladder_) - 1)]
                    if more == count or attempt == 9:
                        raise SpeedRangeError(float(speeds[i]), f"needs more than {count} steps per period")
                if (not finite or estimate[j] > tolerance) and more > count and attempt < 9:
                    steps[i] = more
                    previous[i] = (count, fine_phi[j])
                    retry.append(i)
                else:
                    done.append(j)
            if accept is not None and done:
                done = np.array(done)
                accept(sel[done], fine_phi[done], parts[:, done], int(count))
        pending = np.array(sorted(retry), int)
    return phi, steps
