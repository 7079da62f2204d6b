"""The one-call pipelines, from a case to a result: wiring only, the physics lives below.

    >>> from groundres import analyze, load_case
    >>> result = analyze(load_case("hammond-1974"))   # doctest: +SKIP
    >>> result.stability.stable                        # doctest: +SKIP
    True

:func:`analyze` sweeps the rotor speed: it chooses the method
(:func:`groundres.methods.choose_method`), checks what the model can resolve
(:mod:`groundres.assess.resolution`) and what a periodic analysis costs
(:mod:`groundres.solve.floquet.cost`), solves (:mod:`groundres.solve.solvers`),
names the roots (:mod:`groundres.modes.identify`), finds the unstable ranges
and worst values (:mod:`groundres.assess.stability`), the Deutsch requirement
(:mod:`groundres.assess.deutsch`) and the exact minimum lag damping
(:mod:`groundres.assess.damping_search`), and returns a
:class:`~groundres.results.sweep.SweepResult`.
"""

from __future__ import annotations

import numpy as np

from .assess import damping_search, resolution, scan, stability
from .assess.deutsch import deutsch_in_si
from .methods import choose_method, time_invariant
from .model.params import Case
from .model.units import SPEED_UNITS
from .modes.identify import identify_solution
from .results.sweep import SweepResult
from .solve.floquet.cost import lowest_periodic_speed
from .solve.solvers import solver_for


def analyze(
    case: Case,
    *,
    frame: str | None = None,
    method: str | None = None,
    speeds=None,
    progress=None,
    lag_damping_search: bool = True,
) -> SweepResult:
    """Analyse a case over its speed sweep.

    Parameters
    ----------
    case : Case
    frame : str, optional
        "nonrotating" or "rotating"; defaults to the case's choice.
    method : str, optional
        "auto", "eigen" or "floquet" (:data:`groundres.methods.OPTIONS`); defaults to the
        case's choice.
    speeds : array, optional
        Rotor speeds [rad/s] instead of the case's sweep (increasing).
    progress : callable, optional
        ``progress(stage, done, total)`` as the work advances: stage "sweep"
        counts speeds (several calls for a periodic analysis, one at its end
        for an eigen-analysis); "range ends" and "lag damping" are called with
        ``(0, None)`` when they start and ``(1, 1)`` when they end.
    lag_damping_search : bool
        Search the exact minimum lag damping (:mod:`groundres.assess.damping_search`);
        without it ``exact_lag_damping`` is None with the reason ("skipped", None).

    Returns
    -------
    SweepResult

    Raises
    ------
    MethodError
        For "eigen" on a case with periodic coefficients in every frame.
    ModelRangeError
        For a case the model cannot resolve in double precision, or a Floquet
        sweep whose estimated work is beyond the limit (:mod:`groundres.assess.resolution`,
        :mod:`groundres.solve.floquet.cost`).
    """
    method = choose_method(case, method)
    frame = frame or case.sweep.frame
    speeds = case.sweep.speeds if speeds is None else np.unique(np.asarray(speeds, dtype=float))
    solver = solver_for(case, method)
    system = solver.system
    unit_of_speed = (case.sweep.unit, SPEED_UNITS[case.sweep.unit])
    resolution.check_resolution(
        case.rotor, case.body, system, speeds, stability.growth_threshold, unit_of_speed
    )
    deutsch = deutsch_in_si(system)
    probe = scan.probe_speeds(speeds, [e.tuning_speed for e in deutsch], method.periodic)
    if method.periodic:
        damping_search.check_work(
            solver,
            speeds,
            probe,
            deutsch,
            lag_damping_search,
            unit_of_speed,
            time_invariant(case) is not None,
        )
    report = progress or (lambda stage, done, total: None)
    report("sweep", 0, len(speeds))
    solution = solver.sweep(speeds, lambda done, total: report("sweep", done, total))
    modes = identify_solution(
        solution,
        speeds,
        solver.coordinates,
        system.kinetic_weights(speeds),  # (relative weights: in the equations' own unit)
        solver.isotropic_pairs,
        stability.growth_threshold(speeds),
    )
    report("range ends", 0, None)

    def min_ratio_at(w):  # (one solve at w for all modes)
        roots = np.asarray(solver.roots(np.array([w])))[0]
        return stability.smallest_damping_ratio_at(
            roots, modes, speeds, w, unique=method.form == "multiblade"
        )

    assessed = stability.assess(
        speeds,
        modes.real_part.max(-1),
        modes.damping_ratio.min(-1),
        stability.growth_of(solver),
        lambda w: float(solver.roots(w).real.max()),
        min_ratio_at,
        probe,
        method.periodic,
        closeness=solver.closeness,
        floor=lowest_periodic_speed(system, speeds, probe) if method.periodic else 0.0,
        rough_growth=stability.rough_growth_of(solver),
    )
    report("range ends", 1, 1)
    accuracy = {
        **solver.accuracy(),
        "growth_threshold": {
            "per_radian": stability.GROWTH_PER_RADIAN,
            "floor": stability.GROWTH_FLOOR,
            "unit": "1/s",
            "note": "a root grows when its real part exceeds per_radian * rotor speed + floor",
        },
    }
    exact, no_exact = None, ("skipped", None)
    if lag_damping_search:
        report("lag damping", 0, None)
        exact, no_exact = damping_search.exact_minimum(solver, case, speeds, probe, deutsch, assessed)
        report("lag damping", 1, 1)
    return SweepResult(
        case=case,
        method=method,
        frame=frame,
        rotor_speed=speeds,
        modes=modes,
        stability=assessed,
        deutsch=deutsch,
        exact_lag_damping=exact,
        no_exact_lag_damping=no_exact,
        coordinates=solver.coordinates,
        weights=solver.weights(speeds),
        accuracy=accuracy,
    )
