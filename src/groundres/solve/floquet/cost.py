"""What a periodic analysis costs, estimated before it runs, and the limit beyond which it is refused.

A Floquet analysis integrates one period per speed; the step count grows as
the fastest rate per radian, so as 1/Omega at low speed, and the cost of a
step as the square of the state size (measured: 12 to 44 states), five
times more where a period's grid is too fine to keep (low speeds).
:func:`estimated_cost` foresees the steps and the lifted problems of
:func:`groundres.solve.floquet.exponents.solve` from the frozen system's
rates, :func:`floquet_work` turns them into work, and
:func:`check_floquet_work` refuses a sweep above :data:`FLOQUET_WORK_LIMIT`
with the estimate and what to change (a :class:`~groundres.errors.ModelRangeError`);
:func:`check_work` does so for a whole analysis before it starts.
"""

from __future__ import annotations

import numpy as np

from ...errors import ModelRangeError
from ...model.keys import key_text
from ...model.system import System
from ...model.units import speed_text
from .coefficients import GRID_CACHE_SIZE, frozen_rates, grid_values
from .exponents import LIFT_SPREAD, LIFT_STEP
from .symmetry import symmetry
from .tableau import DOP8
from .transition import MAX_STEPS, check_slowest
from .transition import estimated_steps as transition_steps

#: Estimated Floquet work above which an analysis is refused, in steps of a
#: 12-state system (0.005 to 0.3 ms each on two laptop cores, the estimate
#: being an upper bound: at most a few minutes).
FLOQUET_WORK_LIMIT = 2e6
#: State size of the work unit.
_WORK_STATE = 12
#: Work units per flop-cube of a nonsymmetric eigenvalue problem (measured: a
#: 1500-row problem costs about as much as 5e4 steps).
_EIG_PER_STEP = 1.6e-5
#: Work units of each speed beside its steps, for a 12-state system: its
#: multipliers, periodic eigenvectors, harmonics and their names (about as
#: much as 16 steps), and the memory they take.
_PER_SPEED = 16.0
#: Work of a Floquet damping search beside its full scans of the grid (about
#: four), in analyses of one speed: the bisection's refinements of the worst
#: speeds; and of the refinements of the sweep's worst values.
_SEARCH_EVALUATIONS, _REFINEMENTS = 600, 40
#: Analyses of one speed per coordinate for the margins (:mod:`groundres.assess.margins`):
#: three golden-section refinements (operating range, run-up, largest real part) of each mode.
_MARGIN_EVALUATIONS = 3 * 16


def estimated_cost(system: System, speeds, lift: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Integration steps and lifted-matrix rows at each speed, estimated before any work.

    Returns
    -------
    steps : ndarray (n_s,)
        Steps over the reduced period (zero at rest), twice as many where the
        lifted problem integrates the period a second time.
    rows : ndarray (n_s,)
        Rows of the lifted matrix (0 where the speed needs none).
    """
    speeds = np.asarray(speeds, dtype=float)
    steps, rows = np.zeros(len(speeds)), np.zeros(len(speeds))
    moving = speeds > 0
    if moving.any():
        angle = symmetry(system).angle
        w = speeds[moving]
        if len(w) > 256:  # (smooth in speed: estimated on a sample of it)
            sample = np.unique(np.r_[np.geomspace(w.min(), w.max(), 200), np.linspace(w.min(), w.max(), 56)])
            s_steps, s_rows = estimated_cost(system, sample, lift)
            steps[moving] = np.exp(np.interp(np.log(w), np.log(sample), np.log(s_steps)))
            rows[moving] = np.interp(w, sample, s_rows)
            return steps, rows
        rate, low, high = frozen_rates(system, w)
        spread = 1.25 * (high - low) * angle / w + 2.0
        lifted = (spread > LIFT_SPREAD) & lift
        steps[moving] = transition_steps(system, w, angle, rate) * np.where(lifted, 2.0, 1.0)
        rows[moving] = np.where(lifted, (np.ceil(spread / LIFT_STEP) + 1) * 2 * system.size, 0)
    return steps, rows


def floquet_work_per_speed(system, speeds, lift: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Estimated work of a Floquet analysis at each speed and its steps per period (:func:`floquet_work`)."""
    steps, rows = estimated_cost(system, speeds, lift)
    n = system.size
    # a grid too fine to keep has its coefficient matrices formed again for every
    # speed and every pass, which costs about four times the steps themselves
    fresh = grid_values(n, steps, len(DOP8.c)) > GRID_CACHE_SIZE
    per_step = (2 * n / _WORK_STATE) ** 2 * np.where(fresh, 5.0, 1.0)
    moving = np.asarray(speeds) > 0
    return (steps + _PER_SPEED * moving) * per_step + _EIG_PER_STEP * rows**3, steps


def floquet_work(system, speeds, repeats: float = 1.0, lift: bool = True) -> tuple[float, np.ndarray]:
    """Estimated work of Floquet analyses at ``speeds`` (:func:`estimated_cost`).

    Returns
    -------
    work : float
        In steps of a 12-state system, for ``repeats`` analyses of every speed;
        a lifted matrix of L rows counts as the eigenvalue problem's L^3 flops.
    steps : ndarray (n_s,)
        Estimated integration steps over one (reduced) period at each speed.
    """
    each, steps = floquet_work_per_speed(system, speeds, lift)
    return float(repeats * each.sum()), steps


def check_floquet_work(
    work: float, steps, speeds, what: str = "this sweep", speed_unit=("rad/s", 1.0), time_invariant=None
) -> None:
    """Refuse Floquet work above :data:`FLOQUET_WORK_LIMIT`, with the estimate and what to change.

    ``speed_unit`` (name, rad/s per unit) names speeds as the case does;
    ``time_invariant`` says whether the case has a time-invariant form (then
    method = 'auto' is advised), None if not known.
    """
    if work <= FLOQUET_WORK_LIMIT:
        return
    speeds = np.asarray(speeds, dtype=float)
    i = int(np.argmax(steps))
    advice = {
        True: "; this case has a time-invariant form: method = 'auto' analyses it in seconds",
        False: "",
        None: ", or method = 'auto' where the case has a time-invariant form",
    }[time_invariant]
    raise ModelRangeError(
        f"{key_text('sweep')} Floquet analysis of {what} needs an estimated {work:.2g} integration steps "
        f"(in steps of a 12-state system; {len(speeds)} speeds, up to {steps[i]:.3g} steps per period "
        f"at {speed_text(speeds[i], speed_unit)}), above the limit of {FLOQUET_WORK_LIMIT:.2g} "
        "(a few minutes): use fewer points or start the sweep higher (the steps per period grow as "
        "1/speed)" + advice
    )


#: Work [steps of a 12-state system] one Floquet analysis below the sweep's
#: first turning speed may cost while a range's start is followed down to rest
#: (some twenty such analyses at most: well inside the work limit).
REST_BUDGET = FLOQUET_WORK_LIMIT / 50
#: Halvings of the first turning speed tried below it, at most (2^-40: round-off).
REST_HALVINGS = 40


def lowest_periodic_speed(system, speeds, probe) -> float:
    """Lowest speed [rad/s] a Floquet analysis looks at between rest and the
    first turning speed of the sweep and its grid, where a range is open there
    (:func:`groundres.assess.stability.find_ranges`): the slowest of first / 2^k whose
    analysis costs at most :data:`REST_BUDGET` (the cost grows as 1/speed)."""
    grid = np.union1d(speeds, probe)
    moving = grid[grid > 0]
    if not len(moving):
        return 0.0
    first = float(moving.min())
    w = first * 2.0 ** -np.arange(1, REST_HALVINGS + 1)
    work, _ = floquet_work_per_speed(system, w, lift=False)
    ok = np.flatnonzero(work <= REST_BUDGET)
    return float(w[ok[-1]]) if len(ok) else first


def check_work(system: System, speeds, probe, search, speed_unit, time_invariant) -> None:
    """Refuse a Floquet analysis that cannot run (a speed too near rest,
    :func:`groundres.solve.floquet.transition.check_slowest`) or whose estimated work is
    beyond :data:`FLOQUET_WORK_LIMIT`.

    The work counts the sweep ``speeds`` (with its lifted problems), the internal
    grid ``probe``, the damping search over ``search`` (four full scans and its
    refinements, at the grid's mean cost per speed; None: no search,
    :func:`groundres.assess.damping_search.periodic_search_grid`), the
    refinements of the worst values and those of each mode's margins
    (:mod:`groundres.assess.margins`). ``speed_unit`` and ``time_invariant`` as for
    :func:`check_floquet_work`.
    """
    check_slowest(speeds)
    work, steps = floquet_work(system, speeds)
    probed, _ = floquet_work(system, probe, lift=False)
    typical = probed / max(len(probe), 1) if len(probe) else work / max(len(speeds), 1)
    work += probed + _MARGIN_EVALUATIONS * system.size * typical
    if search is not None:
        scans, _ = floquet_work(system, search, lift=False)
        typical = scans / max(len(search), 1)
        work += 4 * scans + (_SEARCH_EVALUATIONS + _REFINEMENTS) * typical
    check_floquet_work(work, steps, speeds, speed_unit=speed_unit, time_invariant=time_invariant)


#: Share of :data:`FLOQUET_WORK_LIMIT` one full scan of the exact lag-damping search may cost at
#: the strongest damper it tries (it makes a few such scans, and the bisection's evaluations).
SEARCH_SCAN_SHARE = 1 / 8
#: Steps per period a speed of the search may need at the strongest damper tried: room below
#: :data:`groundres.solve.floquet.transition.MAX_STEPS` for the step control's ladder.
SEARCH_STEPS = MAX_STEPS // 4


def affordable_damping(with_damping, grid, upper: float) -> float:
    """The strongest searched damper, at most ``upper`` [the equations' units], whose Floquet scan of
    ``grid`` [rad/s] costs at most :data:`SEARCH_SCAN_SHARE` of the work limit with no speed above
    :data:`SEARCH_STEPS`: a strong damper decays fast, so its periodic equations are stiff for the
    explicit integrator, most at the lowest speeds. ``with_damping(c)`` is the system with the
    damper at ``c``. Halvings of ``upper`` (at most :data:`REST_HALVINGS`), estimated, not run."""
    value = float(upper)
    for _ in range(REST_HALVINGS):
        work, steps = floquet_work(with_damping(value), grid, lift=False)
        if work <= SEARCH_SCAN_SHARE * FLOQUET_WORK_LIMIT and (not len(steps) or steps.max() <= SEARCH_STEPS):
            break
        value *= 0.5
    return value
