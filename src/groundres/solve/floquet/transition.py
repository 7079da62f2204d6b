"""Transition matrices of the periodic equations on a fixed azimuth grid.

The blade-coordinate equations are integrated in the azimuth psi = Omega t as
q'' = (F_a(psi) + F_b(psi) / Omega + F_c(psi) / Omega^2) [q; q'], with the
F matrices evaluated exactly at the nodes of a fixed azimuth grid, once for
all speeds and every damping set along the damping directions (:mod:`groundres.solve.floquet.coefficients`).

The integrator is the eighth-order Runge-Kutta method of Dormand and Prince
(the twelve stages of DOP853) on a fixed grid, chosen on evidence: for
multipliers to 1e-10 it needs three to five times fewer stage evaluations
than a sixth-order method (Butcher 1964, kept as
:data:`groundres.solve.floquet.tableau.BUTCHER6` for comparison).
Two paths compute the same matrices:

* the compiled kernel (:mod:`groundres.solve.floquet.compiled`, wherever it has been
  compiled), which integrates each speed's transition matrix step by step and
  estimates its error from the method's embedded estimators, so that a speed
  whose estimate is too large is integrated once more with the step count
  the estimate predicts (:func:`integrate`);
* NumPy, which forms every step's propagator for all steps and speeds of a
  batch at once and multiplies them together by pairwise reduction; its step
  count comes from a Richardson estimate against a coarser grid. It serves
  while the kernel compiles (the first run on a machine) and is the
  reference the kernel is tested against (the same grid, the same matrices
  to round-off).

The step count is chosen per speed (a first guess from the fastest rate of
the system per radian), and speeds with the same step count are integrated
together. ``benchmarks/bench_floquet.py`` compares it with SciPy's adaptive DOP853.
"""

from __future__ import annotations

import numpy as np

from ...errors import SpeedRangeError
from ...model.system import System
from .coefficients import (
    GRID_CACHE_SIZE,
    directions_of,
    grid_nodes,
    grid_values,
    node_coefficients,
    per_speed,
    rates_per_radian,
)
from .tableau import DOP8
from .vectorised import ordered_product, plan_runs, transition_pairwise

#: First guess of step * (fastest rate per radian + HARMONIC_RATE).
STEP_SCALE = 1.0
#: Rate [1/rad] added for the azimuth variation of the coefficients themselves.
HARMONIC_RATE = 2.0
#: Accuracy asked of the transition matrix (entries, relative to ``max(1, |Phi|)``).
TOLERANCE = 5e-11
#: Smallest step count per interval of the NumPy reference's Richardson ladder.
BASE_STEPS = 32
#: Smallest step count per interval with the embedded estimate (:func:`compiled_ladder`).
LEAST_STEPS = 16
#: Largest step count per interval.
MAX_STEPS = 1 << 20
#: Steps over an interval per (radians of the fastest motion)^(9/8) (:func:`estimated_steps`).
STEPS_FACTOR = 1.4


#: Slowest rotor speed [rad/s] a periodic analysis takes: its azimuth-domain coefficients grow
#: as 1/Omega^2, which overflows below about 1e-154 rad/s once multiplied by a stiffness.
SLOWEST = 1e-100


def check_slowest(speeds) -> None:
    """SpeedRangeError for a moving speed below :data:`SLOWEST` (the rotor at rest is fine)."""
    speeds = np.asarray(speeds, dtype=float)
    moving = speeds[speeds > 0]
    if len(moving) and moving.min() < SLOWEST:
        raise SpeedRangeError(
            float(moving.min()),
            f"is too close to zero (the periodic equations' coefficients grow as 1/Omega^2; "
            f"the slowest speed taken is {SLOWEST:.0e} rad/s)",
        )


def transition(
    system: System,
    speeds,
    angle: float,
    steps: int,
    blocks: int = 1,
    tableau=DOP8,
    damping=None,
    compiled: bool | None = None,
    cumulative: bool = False,
):
    """Azimuth-domain transition matrices over equal parts of [0, angle], for a batch of speeds.

    Parameters
    ----------
    system : System
        With ``damping``, a split system carrying damping directions
        (:meth:`groundres.model.system.System.split_damping`).
    speeds : ndarray (n_s,)
        Rotor speeds [rad/s] integrated together.
    angle : float
        Azimuth interval [rad].
    steps : int
        Fixed steps over the interval (a multiple of ``blocks``).
    blocks : int
        Number of equal consecutive parts of the interval.
    tableau : Tableau
    damping : ndarray (n_s,) or (n_s, d), optional
        Damping along the system's damping directions at each speed [in the
        system's units] (:func:`groundres.solve.floquet.coefficients.per_speed`).
    compiled : bool or None
        The compiled kernel (True; DOP8 only), NumPy with every step's
        propagator formed at once (False), or the kernel where it is ready
        (None, :func:`use_kernel`).
    cumulative : bool
        Transition matrices from 0 to the end of each part instead of over each part.

    Returns
    -------
    ndarray (blocks, n_s, 2n, 2n)
        Transition matrix of y = [q; dq/dpsi] over each part; their ordered
        product (:func:`ordered_product`) is the one over [0, angle] (with
        ``cumulative``, the last one is).
    """
    if use_kernel(tableau, compiled):
        return transition_estimated(system, speeds, angle, steps, blocks, damping, cumulative)[0]
    parts = transition_pairwise(system, speeds, angle, steps, blocks, tableau, damping)
    return prefix_products(parts) if cumulative else parts


def use_kernel(tableau, compiled: bool | None = None) -> bool:
    """Whether the compiled kernel integrates: DOP8, and ``compiled``, or (None) where the
    kernel is ready (:func:`groundres.solve.floquet.compiled.kernel`; until then, the first run on a
    machine, NumPy serves while it compiles in the background)."""
    if tableau is not DOP8 or compiled is False:
        return False
    from .compiled import kernel

    return compiled is True or kernel() is not None


def prefix_products(parts):
    """Q_k ... Q_0 for every k: (K, ...) -> (K, ...)."""
    out = np.empty_like(parts)
    out[0] = parts[0]
    for k in range(1, len(parts)):
        out[k] = parts[k] @ out[k - 1]
    return out


def transition_estimated(
    system: System, speeds, angle: float, steps: int, blocks: int = 1, damping=None, cumulative=False
):
    """:func:`transition` by the compiled kernel, with the embedded error estimate of each speed.

    With ``cumulative``, the transition matrices from 0 to the end of each part.

    Returns
    -------
    parts : ndarray (blocks, n_s, 2n, 2n)
    error : ndarray (n_s,)
        Sum of the steps' estimated errors, relative to ``max(1, |Phi|)``
        (:func:`groundres.solve.floquet.compiled.propagate`).
    """
    from .compiled import propagate  # (numba is imported only where periodic analyses run)

    speeds = np.asarray(speeds, dtype=float)
    directions = directions_of(damping)
    tail = system.direction_halves
    coef = node_coefficients(speeds, damping, tail)
    h = angle / steps
    m = 2 * system.size
    out = np.empty((blocks, len(speeds), m, m))
    error = np.zeros(len(speeds))
    before = None  # (cumulative) the transition matrix up to the run's start
    room = GRID_CACHE_SIZE // grid_values(system.size, 1, len(DOP8.c), directions)  # steps a run
    for b0, b1, runs in plan_runs(steps, blocks, room):
        acc = None
        for s0, s1 in runs:
            nodes = grid_nodes(system, angle, steps, DOP8, s0, s1, directions)
            got, err = propagate(nodes, coef, h, DOP8, b1 - b0 if len(runs) == 1 else 1, cumulative, tail)
            error += err
            acc = got if acc is None else got @ acc
        out[b0:b1] = acc if before is None or not cumulative else acc @ before
        before = out[b1 - 1]
    return out, error


def estimated_steps(system: System, speeds, angle: float, rate=None, tolerance=TOLERANCE) -> np.ndarray:
    """Steps over [0, angle] the step control will settle on at each speed, estimated (n_s,).

    The error of an order-p method over S steps of an interval spanning
    angle * rate radians of the fastest motion goes as S (angle rate / S)^(p+1),
    so S ~ (angle rate)^((p+1)/p) tolerance^(-1/p); the factor is fitted to
    DOP8 at :data:`TOLERANCE` with the embedded estimate (the compiled path)
    on the shipped and benchmark cases: the steps settled on lie within a
    factor 0.6 to 2 of it, 1 at the median.
    """
    rate = (rates_per_radian(system, speeds) if rate is None else rate) + HARMONIC_RATE
    loose = (TOLERANCE / tolerance) ** (1 / ESTIMATE_ORDER)
    with np.errstate(over="ignore"):  # (a rate near the largest float needs more steps than any: inf)
        return np.maximum(LEAST_STEPS, STEPS_FACTOR * loose * (angle * rate) ** (9 / 8))


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


#: Sum of the embedded estimates accepted, per unit of the tolerance asked: the
#: estimate (:mod:`groundres.solve.floquet.compiled`) overstated the actual error of the
#: transition matrix 7 to 5000 times on the shipped and benchmark cases and on
#: dissimilar blades with flap on a pitching and rolling body, so an estimate
#: of 5 x the tolerance keeps the actual error below it (tests/test_propagate.py
#: checks this against a finer grid).
ESTIMATE_SLACK = 5.0
#: Order of the embedded estimate's sum in the step (error ~ steps^-ESTIMATE_ORDER).
ESTIMATE_ORDER = 7


def compiled_ladder(least: int = LEAST_STEPS):
    """Step counts with the embedded estimate: c 2^k for c in 8, 10, 12, 14 (at most
    25 % apart), from ``least``."""
    out = sorted({c << k for c in (8, 10, 12, 14) for k in range(1, 18) if least <= c << k <= MAX_STEPS})
    return np.array(out)


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
    least=None,
    damping=None,
    compiled: bool | None = None,
    cumulative: bool = False,
):
    """Transition over [0, angle], step count adapted per speed.

    With the compiled kernel (:func:`use_kernel`), the embedded estimate of
    each speed's error decides (:func:`transition_estimated`,
    :data:`ESTIMATE_SLACK`); a speed that fails is integrated again with the
    step count the estimate predicts (error ~ S^-7). With NumPy each speed is
    integrated with S steps and with fewer steps S' on the same ladder; the
    Richardson estimate ``|Phi_S - Phi_S'| / ((S/S')^p - 1)`` of the error of
    Phi_S decides, and the last result serves as the next comparison. Both
    meet the tolerance; their step counts differ.

    Parameters
    ----------
    blocks_for : callable, optional
        ``blocks_for(steps, indices) -> int``: into how many equal parts the
        interval is split for the speeds ``indices`` integrated with ``steps``
        (a divisor of ``steps``); 1 by default.
    accept : callable, optional
        ``accept(indices, phi, parts, steps, error)`` is called once for every
        speed with its final result: ``phi`` (k, 2n, 2n) over the interval,
        ``parts`` (blocks, k, 2n, 2n) over its parts, ``error`` (k,) the
        estimate of the largest error of an entry of ``phi``, relative to
        ``max(1, |phi|)`` (embedded, or Richardson's).
    rate : ndarray, optional
        Fastest rate per radian at each speed, if known (:func:`rates_per_radian`).
    least : ndarray, optional
        Fewest steps at each speed (the samples its harmonics need).
    damping : ndarray, optional
        Damping per speed along the system's damping directions (:func:`transition`).
    compiled : bool or None
        The compiled kernel, NumPy, or the kernel where it is ready (:func:`use_kernel`).
    cumulative : bool
        ``parts`` given to ``accept`` run from 0 to the end of each part (:func:`transition`).

    Returns
    -------
    phi : ndarray (n_s, 2n, 2n)
    steps : int ndarray (n_s,)
    """
    speeds = np.asarray(speeds, dtype=float)
    blocks_for = blocks_for or (lambda count, sel: 1)
    embedded = use_kernel(tableau, compiled)
    ladder_ = compiled_ladder() if embedded else ladder(BASE_STEPS)
    damping = per_speed(damping, len(speeds))
    rate = rates_per_radian(system, speeds, damping=damping) if rate is None else rate
    need = estimated_steps(system, speeds, angle, rate, tolerance)
    if need.max() > MAX_STEPS:  # refused before any work: the ladder would climb to its top in vain
        i = int(np.argmax(need))
        raise SpeedRangeError(
            float(speeds[i]), f"needs about {need[i]:.2g} steps per period (at most {MAX_STEPS} are taken)"
        )
    guess = (need if embedded else angle * (rate + HARMONIC_RATE)) / scale
    if least is not None:
        guess = np.maximum(guess, least)
    steps = ladder_[np.minimum(np.searchsorted(ladder_, guess), len(ladder_) - 1)]
    n2 = 2 * system.size
    p = ESTIMATE_ORDER if embedded else tableau.order
    bound = tolerance * (ESTIMATE_SLACK if embedded else 1.0)
    phi = np.empty((len(speeds), n2, n2))
    previous = {}  # speed index -> (steps, phi) of its last rejected run (Richardson)
    pending = np.arange(len(speeds))

    def run(sel, count, blocks):
        c = None if damping is None else damping[sel]
        if embedded:
            return transition_estimated(system, speeds[sel], angle, int(count), blocks, c, cumulative)
        parts = transition(system, speeds[sel], angle, int(count), blocks, tableau, c, False, cumulative)
        return parts, None

    for attempt in range(10):
        if not len(pending):
            break
        retry = []
        for count in np.unique(steps[pending]):
            sel = pending[steps[pending] == count]
            # a step count too small for the explicit method blows up: caught below
            with np.errstate(over="ignore", invalid="ignore"):
                parts, estimate = run(sel, count, blocks_for(int(count), sel))
                fine_phi = parts[-1] if cumulative else ordered_product(parts)
                if estimate is None:
                    size = np.maximum(np.abs(fine_phi).max((-1, -2)), 1.0)
                    estimate = _estimate(
                        lambda i, c, b: run(i, c, b)[0], sel, count, fine_phi, size, previous, ladder_, p
                    )
            phi[sel] = fine_phi
            done = []
            pos = np.searchsorted(ladder_, count)
            for j, i in enumerate(sel):
                finite = bool(np.isfinite(estimate[j]) and np.isfinite(fine_phi[j]).all())
                if finite:
                    want = count * (estimate[j] / bound) ** (1 / p) * 1.1
                    more = ladder_[min(np.searchsorted(ladder_, want), len(ladder_) - 1)]
                else:  # the explicit method went unstable: many more steps
                    more = ladder_[min(pos + 3, len(ladder_) - 1)]
                    if more == count or attempt == 9:
                        raise SpeedRangeError(float(speeds[i]), f"needs more than {count} steps per period")
                if (not finite or estimate[j] > bound) and more > count and attempt < 9:
                    steps[i] = more
                    previous[i] = (count, fine_phi[j])
                    retry.append(i)
                else:
                    done.append(j)
            if accept is not None and done:
                done = np.array(done)
                accept(sel[done], fine_phi[done], parts[:, done], int(count), estimate[done])
        pending = np.array(sorted(retry), int)
    return phi, steps
