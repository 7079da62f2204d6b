"""One call from a case to a result: wiring only, the physics lives below.

    >>> from groundres import analyze, load_case
    >>> result = analyze(load_case("hammond-1974"))   # doctest: +SKIP
    >>> result.stability.stable                        # doctest: +SKIP
    True

Which method (see ``docs/conventions.md``):

* identical blades, N >= 3: multiblade coordinates make the equations
  time-invariant for any body ("multiblade-eigen");
* otherwise an isotropic body in rotating axes ("rotating-eigen");
* otherwise the equations are periodic in every frame ("floquet").
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from . import floquet, identify, limits, modal, scan, stability
from .identify import Modes
from .limits import ModelRangeError  # noqa: F401  (re-exported: the command line maps it to exit 2)
from .params import SPEED_UNITS, Case
from .results import SweepResult
from .system import System

METHOD_NAMES = {"multiblade": "multiblade-eigen", "rotating": "rotating-eigen", "floquet": "floquet"}
_ISOTROPIC_PAIRS = (("x", "y"), ("pitch", "roll"))


class MethodError(ValueError):
    """The method asked for cannot analyse this case."""


def time_invariant_form(case: Case) -> str | None:
    """Which transform gives constant coefficients: "multiblade", "rotating" or None."""
    if case.rotor.identical and case.rotor.n_blades >= 3:
        return "multiblade"
    if case.body.isotropic:
        return "rotating"
    return None


def choose_method(case: Case, method: str | None = None) -> str:
    """The analysis for a case: "multiblade", "rotating" or "floquet".

    Raises
    ------
    MethodError
        For "eigen" on a case with periodic coefficients in every frame.
    """
    method = method or case.sweep.method
    form = time_invariant_form(case)
    if method == "floquet":
        return "floquet"
    if method == "eigen" and form is None:
        raise MethodError(
            "[sweep] method = 'eigen': this case has periodic coefficients in every frame "
            "(dissimilar blades or N = 2 on an anisotropic body), so it has no eigenvalues; "
            "use 'floquet' or 'auto'"
        )
    return form or "floquet"


def _reorder(order, *arrays):
    """Reorder the last (root) axis of arrays by a per-speed order (n_s, n_e)."""
    out = []
    for a in arrays:
        idx = order.reshape(order.shape[:1] + (1,) * (a.ndim - 2) + order.shape[1:])
        out.append(np.take_along_axis(a, np.broadcast_to(idx, a.shape[:-1] + (order.shape[1],)), axis=-1))
    return out


class _Solver:
    """Roots and their content for one case, at any speeds."""

    kind = "eigen"

    def __init__(self, system: System, unit: float = 1.0):
        self.system = system
        self.unit = unit  # the mass unit the system is computed in [kg] (limits.mass_unit)
        self.nr_coords = system.multiblade_coordinates()
        self.iso = [p for p in _ISOTROPIC_PAIRS if system.body.pair_isotropic(*p)]

    def with_lag_damping(self, scale_to: float):
        """The same case with the lag dampers that work set to ``scale_to`` [N m s/rad].

        Blades without a lag damper keep none (a failed damper stays failed),
        unless no blade has one, in which case all get it.
        """
        blades = self.system.rotor.blades
        working = [b.lag_damping > 0 for b in blades]
        if not any(working):
            working = [True] * len(blades)
        value = scale_to / self.unit
        new = tuple(replace(b, lag_damping=value) if w else b for b, w in zip(blades, working))
        out = type(self)(System(replace(self.system.rotor, blades=new), self.system.body), self.unit)
        out.fit_speed = self.fit_speed
        return out

    #: Speed [rad/s] the matrices of the time-invariant form are fitted at (0, half, all of it).
    fit_speed = 1.0

    def _fitted(self, speeds):
        """The time-invariant form's matrices at any speeds from their exact quadratic dependence.

        Mass is constant, damping linear and stiffness quadratic in Omega (the
        transforms add Omega and Omega^2 terms), so three speeds give them
        everywhere: a scan of thousands of speeds costs a few array products.
        """
        if getattr(self, "_fit", None) is None:
            m, c, k = self.form(self.fit_speed * np.array([0.0, 0.5, 1.0]))
            k1, k2 = 4 * k[1] - 3 * k[0] - k[2], 2 * (k[2] - 2 * k[1] + k[0])
            self._fit = (m[0], c[0], c[2] - c[0], k[0], k1, k2)
        m0, c0, c1, k0, k1, k2 = self._fit
        x = (np.asarray(speeds, dtype=float) / self.fit_speed)[:, None, None]
        return np.broadcast_to(m0, x.shape[:1] + m0.shape), c0 + x * c1, k0 + x * (k1 + x * k2)

    def _scan_roots(self, speeds):
        mats = self._fitted(speeds)
        return modal.block_eigenvalues(*mats, self._blocks(mats), split=True)

    def growth(self, speeds):
        """Largest real part of all roots [1/s] at each speed (roots only, batched)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        return np.max([r.real.max(-1) for r in self._scan_roots(speeds)], axis=0)

    def closeness(self, speeds):
        """Nearest approach of two roots of one block (:func:`groundres.modal.closest_pair`)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        floor = np.maximum(speeds, 1e-3)
        return np.min([modal.closest_pair(r, floor) for r in self._scan_roots(speeds)], axis=0)

    def weights(self, speeds):
        """Kinetic weights [kg, kg m^2] (the mass-matrix diagonal in SI)."""
        return self.system.kinetic_weights(speeds) * self.unit

    def accuracy(self) -> dict:
        """How the last sweep's roots were found, and how accurately (for provenance)."""
        return {"roots": "eigenvalues of each coupled block's state matrix (LAPACK geev, numpy.linalg.eig)"}

    def identify(self, sol: modal.Eigensolution, speeds) -> Modes:
        """Labels and frequencies of a tracked solution (:func:`groundres.identify.identify`)."""
        harmonics = sol.harmonics if sol.harmonics is not None else sol.vector[:, :, None, :]
        orders = sol.orders if sol.orders is not None else np.array([0])
        return identify.identify(
            sol.eigenvalue,
            harmonics,
            orders,
            self.nr_coords,
            self.system.kinetic_weights(speeds),  # (relative weights: in the equations' own unit)
            speeds,
            block=sol.block,
            blocks=sol.blocks,
            key=sol.key,
            isotropic_pairs=self.iso,
            threshold=stability.growth_threshold(speeds),
        )


class _Multiblade(_Solver):
    def __init__(self, system, unit=1.0):
        super().__init__(system, unit)
        self.blocks = None

    def _blocks(self, mats):
        if self.blocks is None:
            self.blocks = modal.coupling_blocks(*mats)
        return self.blocks

    def form(self, speeds):
        return self.system.multiblade(speeds)

    def roots(self, speeds):
        mats = self.system.multiblade(np.atleast_1d(speeds))
        return modal.block_eigenvalues(*mats, self._blocks(mats))

    def sweep(self, speeds, progress=None):
        mats = self.system.multiblade(speeds)
        solution = modal.track(modal.solve(*mats, self._blocks(mats)), speeds)
        if progress is not None:
            progress(len(speeds), len(speeds))
        return solution

    def with_lag_damping(self, value):
        new = super().with_lag_damping(value)
        new.blocks = self.blocks
        return new


class _Rotating(_Solver):
    """Isotropic body in rotating axes: time-invariant for any blades."""

    samples = 16

    def form(self, speeds):
        return self.system.rotating_axes(speeds)

    def _blocks(self, mats):
        return modal.coupling_blocks(*mats)

    def roots(self, speeds):
        mats = self.system.rotating_axes(np.atleast_1d(speeds))
        return modal.block_eigenvalues(*mats, modal.coupling_blocks(*mats))

    def sweep(self, speeds, progress=None):
        mats = self.system.rotating_axes(speeds)
        raw = modal.track(modal.solve(*mats, modal.coupling_blocks(*mats)), speeds)
        if progress is not None:
            progress(len(speeds), len(speeds))
        # one period of the motion seen from nonrotating axes: body axes turned by psi
        phase = 2 * np.pi * np.arange(self.samples) / self.samples
        q = np.broadcast_to(raw.vector, (self.samples,) + raw.vector.shape).copy()
        index = {d: i for i, d in enumerate(self.system.body.dofs)}
        for a, b in _ISOTROPIC_PAIRS:
            if a in index:
                ia, ib = index[a], index[b]
                c, s = np.cos(phase)[:, None, None], np.sin(phase)[:, None, None]
                xa, xb = raw.vector[None, :, ia, :], raw.vector[None, :, ib, :]
                q[:, :, ia, :] = c * xa - s * xb
                q[:, :, ib, :] = s * xa + c * xb
        harmonics, orders = self.system.nonrotating_harmonics(q, self.samples // 2 - 1)
        one = np.zeros(raw.vector.shape[-1], int)  # labels are in nonrotating coordinates: one block
        return modal.Eigensolution(
            raw.eigenvalue, raw.vector, one, [np.arange(raw.vector.shape[1])], harmonics, orders
        )


class _Floquet(_Solver):
    """Periodic equations: Floquet exponents and periodic eigenvectors."""

    kind = "floquet"
    closeness = None  # (exponents are known modulo Omega: ranges come from the grid and its peaks)

    def roots(self, speeds):
        return floquet.solve(self.system, np.atleast_1d(speeds), harmonics=0).exponent

    def growth(self, speeds):
        """Largest real part [1/s]: exact without the lifted problem (:func:`groundres.floquet.solve`)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        return floquet.solve(self.system, speeds, harmonics=0, lift=False).exponent.real.max(-1)

    solved = None

    def accuracy(self):
        out = {
            "roots": "Floquet exponents of transition matrices over the symmetry interval, integrated "
            "with fixed steps of the Dormand-Prince eighth-order tableau, the step count of each "
            "speed set by a Richardson error estimate",
            "transition_tolerance": floquet.TOLERANCE,
            "transition_tolerance_note": "largest error of an entry, relative to max(1, |Phi|)",
            "harmonics": floquet.HARMONICS,
        }
        fs = self.solved
        if fs is not None and (fs.steps > 0).any():
            steps = fs.steps[fs.steps > 0]
            out |= {
                "interval_rad": fs.symmetry.angle,
                "steps_per_interval": {"min": int(steps.min()), "max": int(steps.max())},
                "lifted_speeds": int(fs.lifted.sum()),
            }
        return out

    def sweep(self, speeds, progress=None):
        fs = self.solved = floquet.solve(self.system, speeds, progress=progress)
        n = self.system.size
        # branches: exponents (modulo Omega) and eigenvectors vary continuously
        # with speed (the multipliers' phases wrap many times over a slow period)
        disp = fs.vector[:, :n, :]
        disp = disp / np.maximum(np.linalg.norm(disp, axis=1, keepdims=True), 1e-300)
        order = modal.track_order(fs.exponent, disp, np.zeros(2 * n, int), speeds, periodic=True)
        key, lam, disp, harmonics = _reorder(order, fs.key, fs.exponent, disp, fs.harmonics)
        return modal.Eigensolution(lam, disp, np.zeros(2 * n, int), [np.arange(n)], harmonics, fs.orders, key)


_SOLVERS = {"multiblade": _Multiblade, "rotating": _Rotating, "floquet": _Floquet}


def root_solver(case: Case, form: str | None = None):
    """The solver of a case's roots (``.roots(speeds)``) by method form."""
    unit = limits.mass_unit(case.rotor, case.body)
    system = System(*limits.in_mass_unit(case.rotor, case.body, unit))
    return _SOLVERS[form or choose_method(case)](system, unit)


def _damping_ratio_near(solver, modes: Modes, speeds, label: int, w: float) -> float:
    """Damping ratio at speed ``w`` of the root that continues mode ``label``.

    The root nearest the mode's eigenvalue interpolated from the sweep, with
    its frequency shifted by the multiple of Omega that brings it nearest
    (none for a multiblade analysis, whose frequencies are unique).
    """
    lam = modes.eigenvalue[:, label]
    target = complex(np.interp(w, speeds, lam.real), np.interp(w, speeds, lam.imag))
    roots = np.asarray(solver.roots(np.array([w])))[0]
    if isinstance(solver, _Multiblade):
        cand = roots.real + 1j * np.abs(roots.imag)
    else:
        m = np.rint((target.imag - roots.imag) / w)
        cand = roots.real + 1j * np.abs(roots.imag + m * w)
    best = cand[np.argmin(np.abs(cand - target))]
    return float(identify.damping_ratio(best, scale=np.abs(cand).max()))


def analyze(
    case: Case, *, frame: str | None = None, method: str | None = None, speeds=None, progress=None
) -> SweepResult:
    """Analyse a case over its speed sweep.

    Parameters
    ----------
    case : Case
    frame : str, optional
        "nonrotating" or "rotating"; defaults to the case's choice.
    method : str, optional
        "auto", "eigen" or "floquet"; defaults to the case's choice.
    speeds : array, optional
        Rotor speeds [rad/s] instead of the case's sweep (increasing).
    progress : callable, optional
        ``progress(stage, done, total)`` as the work advances: stage "sweep"
        counts speeds (several calls for a periodic analysis, one at its end
        for an eigen-analysis); "range ends" and "lag damping" are called with
        ``(0, None)`` when they start and ``(1, 1)`` when they end.

    Returns
    -------
    SweepResult

    Raises
    ------
    MethodError
        For "eigen" on a case with periodic coefficients in every frame.
    ModelRangeError
        For a case the model cannot resolve in double precision, or a Floquet
        sweep whose estimated work is beyond the limit (:mod:`groundres.limits`).
    """
    form = choose_method(case, method)
    frame = frame or case.sweep.frame
    speeds = case.sweep.speeds if speeds is None else np.unique(np.asarray(speeds, dtype=float))
    unit = limits.mass_unit(case.rotor, case.body)
    system = System(*limits.in_mass_unit(case.rotor, case.body, unit))
    unit_of_speed = (case.sweep.unit, SPEED_UNITS[case.sweep.unit])
    limits.check_resolution(case.rotor, case.body, system, speeds, stability.growth_threshold, unit_of_speed)
    solver = _SOLVERS[form](system, unit)
    solver.fit_speed = float(max(speeds.max(), 1e-3))
    deutsch = _deutsch(system, unit)
    probe = scan.probe_speeds(speeds, [e.tuning_speed for e in deutsch], solver.kind)
    if solver.kind == "floquet":
        low = _lowest_search_speed(deutsch)
        search = _search_grid(speeds, probe, True, low)
        _check_floquet_work(
            solver, speeds, probe, search, unit_of_speed, time_invariant_form(case) is not None
        )
    report = progress or (lambda stage, done, total: None)
    report("sweep", 0, len(speeds))
    modes = solver.identify(solver.sweep(speeds, lambda done, total: report("sweep", done, total)), speeds)
    report("range ends", 0, None)
    max_real = modes.real_part.max(-1)
    ratios = modes.damping_ratio

    def min_ratio_at(w):
        label = int(np.argmin(ratios[np.argmin(np.abs(speeds - w))]))
        return _damping_ratio_near(solver, modes, speeds, label, w)

    assessed = stability.assess(
        speeds,
        max_real,
        ratios.min(-1),
        solver.growth,
        lambda w: float(solver.roots(w).real.max()),
        min_ratio_at,
        probe,
        solver.kind,
        closeness=solver.closeness,
        floor=lowest_periodic_speed(system, speeds, probe) if solver.kind == "floquet" else 0.0,
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
    report("lag damping", 0, None)
    exact, no_exact = _minimum_lag_damping(solver, case, speeds, probe, deutsch, assessed)
    report("lag damping", 1, 1)
    return SweepResult(
        case=case,
        method=METHOD_NAMES[form],
        frame=frame,
        rotor_speed=speeds,
        modes=modes,
        stability=assessed,
        deutsch=deutsch,
        exact_lag_damping=exact,
        no_exact_lag_damping=no_exact,
        coordinates=solver.nr_coords,
        weights=solver.weights(speeds),
        accuracy=accuracy,
    )


def _deutsch(system, unit):
    """Deutsch entries from the equations' own mass unit, dampers given back in SI."""
    entries = stability.deutsch(system.rotor, system.body)
    if unit == 1.0:
        return entries

    def si(x):
        return None if x is None else x * unit

    return [
        replace(
            e,
            body_damping=si(e.body_damping),
            required_lag_damping=si(e.required_lag_damping),
            installed_lag_damping=si(e.installed_lag_damping),
        )
        for e in entries
    ]


#: Relative accuracy of the exact minimum lag damping, by kind of analysis.
RTOL = {"eigen": 1e-4, "floquet": 1e-3}
#: Work of a Floquet damping search beside its full scans of the grid (about
#: four), in analyses of one speed: the bisection's refinements of the worst
#: speeds; and of the refinements of the sweep's worst values.
_SEARCH_EVALUATIONS, _REFINEMENTS = 600, 40


def _check_floquet_work(solver, speeds, probe, search, speed_unit, time_invariant):
    """Refuse a Floquet analysis whose estimated work is beyond the limit (:mod:`groundres.limits`).

    Sweep (with its lifted problems), the internal grid, the damping search
    (four full scans and its refinements, at the grid's mean cost per speed)
    and the refinements of the worst values.
    """
    system = solver.system
    work, steps = limits.floquet_work(system, speeds)
    work += limits.floquet_work(system, probe, lift=False)[0]
    scans, per = limits.floquet_work(system, search, lift=False)
    typical = scans / max(len(search), 1)
    work += 4 * scans + (_SEARCH_EVALUATIONS + _REFINEMENTS) * typical
    limits.check_floquet_work(work, steps, speeds, speed_unit=speed_unit, time_invariant=time_invariant)


#: Work [steps of a 12-state system] one Floquet analysis below the sweep's
#: first turning speed may cost while a range's start is followed down to rest
#: (some twenty such analyses at most: well inside the work limit).
REST_BUDGET = limits.FLOQUET_WORK_LIMIT / 50


def lowest_periodic_speed(system, speeds, probe) -> float:
    """Lowest speed [rad/s] a Floquet analysis looks at between rest and the
    first turning speed of the sweep and its grid, where a range is open there
    (:func:`groundres.stability.find_ranges`): the slowest of first / 2^k whose
    analysis costs at most :data:`REST_BUDGET` (the cost grows as 1/speed)."""
    grid = np.union1d(speeds, probe)
    moving = grid[grid > 0]
    if not len(moving):
        return 0.0
    first = float(moving.min())
    w = first * 2.0 ** -np.arange(1, stability.REST_HALVINGS + 1)
    work, _ = limits.floquet_work_per_speed(system, w, lift=False)
    ok = np.flatnonzero(work <= REST_BUDGET)
    return float(w[ok[-1]]) if len(ok) else first


def _lowest_search_speed(deutsch):
    """Half the lowest body frequency [rad/s]: below it the regressive lag mode,
    at Omega (1 - nu) < Omega, meets no body mode, and lag damping decides nothing."""
    body = [e.body_frequency for e in deutsch if e.body_frequency]
    return 0.5 * min(body) if body else 0.0


def _search_grid(speeds, probe, periodic, low=0.0):
    """Speeds the damping search scans: the internal grid and the sweep's (at most 60 of
    them for a periodic analysis, whose every speed is an integration), from ``low`` up."""
    if periodic and len(speeds) > 60:
        speeds = speeds[np.unique(np.linspace(0, len(speeds) - 1, 60).round().astype(int))]
    grid = np.union1d(speeds, probe)
    # the rotor at rest is no speed for the search: its roots do not depend on lag damping
    inside = grid[(grid > 0) & (grid >= low)]
    return inside if len(inside) else grid[-1:]


def _minimum_lag_damping(solver, case, speeds, probe, deutsch, assessed):
    """Smallest lag damping (on every blade that has a damper) for a stable sweep.

    The search scans the sweep and an internal grid dense near the tuning
    speeds from half the lowest body frequency up, refines the worst speeds
    (:func:`groundres.stability.minimum_lag_damping`), and starts from the
    installed damper and the sweep's verdict there, so that the two agree:
    installed >= the result exactly when the sweep is stable. A sweep
    unstable wholly below that speed has no answer (None): lag damping does
    not decide its stability there.

    Returns
    -------
    value : float or None
        [N m s/rad] in SI.
    why_none : tuple or None
        Where ``value`` is None: ("below", speed [rad/s]) for a sweep unstable
        below the search's lowest speed, ("cap", damping [N m s/rad]) where no
        damping up to the largest tried makes it stable.
    """
    periodic = solver.kind == "floquet"
    low = _lowest_search_speed(deutsch)
    if any(b < low for _, b in assessed.unstable_ranges):
        return None, ("below", low)
    blades = case.rotor.blades
    installed = max(b.lag_damping for b in blades)
    inertia = max(b.blade_inertia for b in blades)
    # the largest lag damping the model resolves (limits.check_resolution), and a
    # cap beyond which more damping is no design answer (periodic analyses stop
    # earlier: a strong damper makes the equations stiff for the explicit integrator)
    tau = float(stability.growth_threshold(np.array([speeds.min(), speeds.max()])).min())
    resolved = 0.5 * inertia * tau / (limits.ROUND_OFF * limits.EPS)
    top = speeds.max()
    finite = [
        e.required_lag_damping
        for e in deutsch
        if e.required_lag_damping not in (None, np.inf)
        and e.tuning_speed is not None
        and speeds.min() <= e.tuning_speed <= top
    ]
    # (and four times the Deutsch requirement of a resonance the sweep reaches,
    # whatever the installed damper)
    cap = (20 if periodic else 100) * max(installed, 2 * inertia * top * (0.05 if periodic else 1.0))
    cap = min(max([cap] + [4 * f for f in finite]), resolved)
    guess = min(max(finite) if finite else max(installed, inertia * top * 1e-3), 0.5 * cap)
    guess = max(guess, 1e-12 * cap)
    # the installed dampers belong to the family searched when the working ones are equal
    working = {b.lag_damping for b in blades if b.lag_damping > 0}
    anchor = (installed, not assessed.stable) if len(working) <= 1 and installed <= cap else None

    trials = {}

    def excess(lag_damping, w):
        w = np.atleast_1d(np.asarray(w, dtype=float))
        if lag_damping not in trials:  # (one system per damping tried: its grids are reused)
            trials.clear()
            trials[lag_damping] = solver.with_lag_damping(lag_damping)
        return trials[lag_damping].growth(w) - stability.growth_threshold(w)

    value = stability.minimum_lag_damping(
        excess,
        _search_grid(speeds, probe, periodic, low),
        guess,
        cap=cap,
        rtol=RTOL[solver.kind],
        anchor=anchor,
        seeds=assessed.peak_speeds,
        kind=solver.kind,
    )
    return value, (("cap", cap) if value is None else None)
