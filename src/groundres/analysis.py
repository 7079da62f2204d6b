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

from dataclasses import replace

import numpy as np

from .assess import damping_search, margins, resolution, scan, stability
from .assess.deutsch import deutsch_in_si
from .assess.limit_cycles import predict
from .errors import CaseError, MethodError, ParameterError, brief, shown
from .methods import Method, choose_method, time_invariant
from .model.params import Case
from .model.schema import load_case
from .model.system import System
from .model.units import SPEED_UNITS
from .modes.identify import identify_solution
from .results.comparison import Comparison, Entry, case_name, entry_details
from .results.limit_cycles import LimitCycleResult
from .results.simulation import Simulation
from .results.sweep import SweepResult
from .solve.floquet import cost
from .solve.simulate import (
    default_initial,
    fit_growth,
    initial_state,
    integrate,
    run_duration,
    settling_time,
)
from .solve.solvers import solver_for


def analyze(
    case: Case,
    *,
    frame: str | None = None,
    method: str | None = None,
    speeds=None,
    progress=None,
    lag_damping_search: bool = True,
    margins_of_every_mode: bool = True,
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
        for an eigen-analysis); "range ends", "lag damping" and "margins" are
        called with ``(0, None)`` when they start and ``(1, 1)`` when they end.
    lag_damping_search : bool
        Search the exact minimum lag damping (:mod:`groundres.assess.damping_search`);
        without it ``exact_lag_damping`` is None with the reason ("skipped", None).
    margins_of_every_mode : bool
        Refine every mode's margins between the sweep's speeds
        (:func:`groundres.assess.margins.margins`); without it only the overall least
        damping ratio and growth margin are refined, the other modes' values taken at
        the sweep's speeds (what a study records; a periodic analysis costs about half).

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
        search = damping_search.periodic_search_grid(speeds, probe, deutsch) if lag_damping_search else None
        cost.check_work(system, speeds, probe, search, unit_of_speed, time_invariant(case) is not None)
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
            roots, modes, speeds, w, unique=method is Method.MULTIBLADE
        )

    floor = cost.lowest_periodic_speed(system, speeds, probe) if method.periodic else 0.0
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
        floor=floor,
        rough_growth=stability.rough_growth_of(solver),
    )
    between = _growing_between(solver, speeds, assessed)
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
    # the modes neutral at rest, from the analysis at rest (time-invariant for every method)
    rest = solver.sweep(np.zeros(1))
    at_rest = identify_solution(
        rest, np.zeros(1), solver.coordinates, system.kinetic_weights(np.zeros(1)), solver.isotropic_pairs
    )
    exact, no_exact = None, ("skipped", None)
    if lag_damping_search:
        report("lag damping", 0, None)
        exact, no_exact = damping_search.exact_minimum(solver, case, speeds, probe, deutsch, assessed)
        report("lag damping", 1, 1)
    result = SweepResult(
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
        between=between,
        trim=solver.system.trim(speeds) if case.rotor.aero is not None else None,
    )
    report("margins", 0, None)
    result.margins = margins.margins(
        result,
        solver.roots,
        margins.neutral_at_rest(at_rest),
        method is Method.MULTIBLADE,
        method.periodic,
        every=margins_of_every_mode,
        floor=floor,
    )
    if between:
        result.stability = _least_between(result)
    report("margins", 1, 1)
    return result


def _growing_between(solver, speeds, assessed) -> dict:
    """(start, end) -> {label: root at the peak} of the modes that grow at the peak of each
    unstable range holding none of the sweep's speeds, identified at that speed on their own (a
    cheap analysis of one speed): the sweep's modes, interpolated across such a range, could
    name the wrong ones."""
    out = {}
    for (start, end), peak in zip(assessed.unstable_ranges, assessed.peak_speeds):
        if ((speeds >= start) & (speeds <= end)).any() or not peak > 0:
            continue
        w = np.array([float(peak)])
        at = identify_solution(
            solver.sweep(w), w, solver.coordinates, solver.system.kinetic_weights(w), solver.isotropic_pairs
        )
        real = at.real_part[0]
        grows = real > stability.growth_threshold(w)[0]
        grows = grows if grows.any() else real == real.max()
        out[(start, end)] = {
            label: complex(lam) for label, lam, g in zip(at.labels, at.eigenvalue[0], grows) if g
        }
    return out


def _least_between(result):
    """The result's smallest damping ratio over the sweep, taken from its margins inside the unstable
    ranges that hold none of the sweep's speeds (:func:`_growing_between`): there each growing mode
    is followed from its root identified at the range's peak, where the sweep's modes,
    interpolated across the range, may lead the refinement to another root or harmonic."""
    assessed = result.stability
    least = assessed.min_damping_ratio

    def inside(w):
        return any(a <= w <= b for a, b in result.between)

    candidates = [
        (x.value, x.speed)
        for m in result.margins.modes
        for x in (m.operating, m.run_up)
        if x is not None and inside(x.speed) and any(m.mode in roots for roots in result.between.values())
    ]
    if not candidates:
        return assessed
    best = min(candidates)
    if inside(least[1]) or best[0] < least[0]:
        return replace(assessed, min_damping_ratio=(float(best[0]), float(best[1])))
    return assessed


def simulate(case: Case, speed: float, *, duration=None, initial=None, progress=None) -> Simulation:
    """Integrate the periodic blade-coordinate equations of a case in time at one rotor speed.

    The integration (:func:`groundres.solve.simulate.integrate`, SciPy's DOP853)
    is independent of the eigen- and Floquet analyses: its measured growth rate
    checks their largest real part, which the result carries beside it.

    Parameters
    ----------
    case : Case
    speed : float
        Rotor speed [rad/s].
    duration : float, optional
        [s]; by default 40 revolutions, or longer (up to 400) until the least
        stable root outgrows the next by e^8 (:func:`groundres.solve.simulate.run_duration`).
    initial : dict, optional
        Initial displacements [m, rad] and rates (``NAME_rate``) by coordinate
        name ("x", "pitch", "lag1", "flap3", "roll_rate"); by default 0.01 on
        every body coordinate and on lag1.
    progress : callable, optional
        ``progress(done, total)`` in simulated seconds, about every percent.

    Returns
    -------
    Simulation
        ``.plot()``, ``.to_xarray()``, ``.growth_rate()``
        (:class:`groundres.results.simulation.Simulation`).

    Raises
    ------
    ParameterError
        A speed, duration or initial state that cannot be simulated (its message
        says which and what is allowed).
    ModelRangeError
        Equations that overflow at that speed, or an integration that takes far
        more steps than estimated.

    Examples
    --------
    >>> sim = simulate(load_case("hammond-1974-one-damper"), 26.7, duration=30.0)  # doctest: +SKIP
    >>> sim.growth_rate(), sim.predicted_growth  # doctest: +SKIP
    """
    if (
        isinstance(speed, bool)
        or not isinstance(speed, (int, float))
        or not (np.isfinite(speed) and speed > 0)
    ):
        raise ParameterError("speed", speed, "must be a finite number > 0 [rad/s]")
    unit = case.sweep.unit
    factor = SPEED_UNITS[unit]
    system = System.in_mass_unit(case.rotor, case.body)
    resolution.check_representable(system, speed, "speed", (unit, factor))
    values = default_initial(system) if initial is None else dict(initial)
    q0, v0 = initial_state(system, values)
    name = f"{speed / factor:g} {unit}"
    given = duration
    duration = run_duration(system, speed, duration, speed_name=name)
    method = choose_method(case)
    roots = np.asarray(solver_for(case, method).roots(speed)).ravel()
    if given is None:  # (longer where the least stable root stands out slowly)
        duration = run_duration(system, speed, None, settling_time(roots), speed_name=name)
    # (no longer than the motion's growth leaves inside double precision; a neutral root's
    # round-off is no growth)
    growth = float(roots.real.max())
    growth = 0.0 if stability.is_neutral(growth, speed) else growth
    duration = fit_growth(duration, growth, values, given is not None, speed, name)
    history = integrate(
        system, speed, duration, (q0, v0), progress=progress, speed_text=name, growth=max(growth, 0.0)
    )
    return Simulation(case, history, values, method, float(roots.real.max()))


def limit_cycles(case: Case, *, linear: bool = True, progress=None) -> LimitCycleResult:
    """Limit cycles of a case whose lag dampers follow nonlinear laws, predicted from their
    describing functions (:mod:`groundres.assess.limit_cycles`), at ``[limit_cycle] points``
    speeds over the sweep and blade lag amplitudes from ``amplitude_min`` to ``amplitude_max``.

    ``linear``: also the linear analysis (the laws at small motion), drawn beside the cycles.

    Identical blades with one law are solved by multiblade eigen-analysis of the equivalent
    system; blades that differ (a failed damper, different laws, two blades) by Floquet analysis,
    each blade's law at its own amplitude (:mod:`groundres.assess.periodic_cycles`).

    Raises
    ------
    CaseError
        A case without a nonlinear law, or whose Floquet analysis the model cannot resolve.

    Examples
    --------
    >>> found = limit_cycles(load_case("my-rotor-with-a-relief-valve.toml"))  # doctest: +SKIP
    >>> found.threshold_words(found.smallest_threshold())  # doctest: +SKIP
    """
    if not case.rotor.nonlinear:
        raise CaseError(
            "[rotor.lag_damper]: limit cycles need a nonlinear lag damper law on at least one blade (none "
            "is given, or every blade's damper is failed)"
        )
    options = case.limit_cycle
    speeds = np.linspace(case.sweep.start, case.sweep.stop, options.points)
    if progress is not None:
        progress("limit cycles", 0, None)
    prediction = predict(case, speeds, searched=options.searched)
    if progress is not None:
        progress("limit cycles", 1, 1)
    confirmations = []
    if options.confirm:  # (each listed speed's cycles against runs of the nonlinear equations)
        from .assess.confirm import confirm, run_length

        at_speeds = predict(case, list(options.confirm), searched=options.searched)
        cycles = at_speeds.cycles
        try:  # (every run's length checked before the first runs)
            for cycle in cycles:
                run_length(
                    case, cycle.speed, cycle.frequency, case.simulation.duration, case.simulation.window
                )
        except ParameterError as err:  # (the run's length or window, from the case file)
            raise CaseError(f"[simulation] {err}") from None
        for i, speed in enumerate(at_speeds.speeds):  # (a speed without cycles: said so)
            if not at_speeds.at(float(speed)):
                none = {"stable": None, "predicted": None, "confirmed": None, "runs": []}
                confirmations.append({"speed": float(speed), **none, "verdict": at_speeds.verdict(i)})
        for i, cycle in enumerate(cycles):
            report = progress and (lambda d, t, i=i: progress("confirm", i + d / t, len(cycles)))
            others = [c for c in cycles if c.speed == cycle.speed and c is not cycle]
            confirmations.append(
                confirm(case, cycle, case.simulation.duration, case.simulation.window, report, others)
            )
        confirmations.sort(key=lambda e: e["speed"])
    sweep = analyze(case, lag_damping_search=False, progress=progress) if linear else None
    return LimitCycleResult(case, prediction, sweep, confirmations)


def compare(cases, methods=None, frame: str | None = None, progress=None) -> Comparison:
    """Analyse every case by every method, for comparison with the first.

    Parameters
    ----------
    cases : sequence of Case or str
        Cases, or paths of case files or shipped case names.
    methods : sequence of str, optional
        "auto", "eigen" or "floquet" (:data:`groundres.methods.OPTIONS`) for each analysis
        of each case [default:
        each case's own]. The entries are the cases by the methods, case by
        case: (case 1, method 1), (case 1, method 2), ..., (case 2, method 1).
    frame : str, optional
        "nonrotating" or "rotating" for every entry [default: each case's own].
    progress : callable, optional
        ``progress(entry, stage, done, total)``: ``entry`` the 1-based number,
        the rest as :func:`groundres.analysis.analyze` reports.

    Returns
    -------
    Comparison

    Raises
    ------
    ParameterError
        For fewer than two entries (key ``entries``).
    MethodError
        For a method that cannot analyse an entry's case (the message names the entry).

    Examples
    --------
    >>> c = compare(["hammond-one-damper-isotropic"], methods=["eigen", "floquet"])  # doctest: +SKIP
    >>> [(r["quantity"], r["difference"]) for r in c.differences()]  # doctest: +SKIP
    """
    cases = [c if isinstance(c, Case) else load_case(c) for c in cases]
    methods = list(methods) if methods else [None]
    if len(cases) * len(methods) < 2:
        raise ParameterError(
            "entries",
            len(cases) * len(methods),
            f"{len(cases)} case(s) by {len(methods)} method(s): a comparison needs two or more "
            "entries (give two cases, or two methods)",
        )
    done = []  # (case, method, result): an entry asked twice is analysed once (identical results)
    plan = []
    for k, case in enumerate(cases):
        for method in methods:
            number = len(plan) + 1
            same = next((r for c, m, r in done if c == case and c.text == case.text and m == method), None)
            if same is None:
                report = progress and (lambda stage, d, t, number=number: progress(number, stage, d, t))
                try:
                    same = analyze(case, frame=frame, method=method, progress=report)
                except MethodError as err:  # (which entry could not be analysed so)
                    asked = f" by method {shown(method)}" if method else ""
                    entry = f"entry {number} ({brief(case_name(case))}{asked})"
                    raise MethodError(err.key, err.value, err.allowed, entry) from None
                done.append((case, method, same))
            plan.append((k, method, same))
    details = entry_details([r for _, _, r in plan])
    return Comparison(
        tuple(
            Entry(i + 1, case_name(cases[k]), detail, k, m, r)
            for i, (detail, (k, m, r)) in enumerate(zip(details, plan))
        )
    )
