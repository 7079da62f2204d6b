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

import numpy as np

from .assess import damping_search, resolution, scan, stability
from .assess.deutsch import deutsch_in_si
from .assess.resolution import ModelRangeError  # noqa: F401  (re-exported: the command line maps it to exit 2)
from .model.body import ROTATING_PAIRS
from .model.params import SPEED_UNITS, Case
from .model.system import System
from .modes import identify
from .modes.identify import Modes
from .results.sweep import SweepResult
from .solve import modal
from .solve.floquet import exponents, transition

METHOD_NAMES = {"multiblade": "multiblade-eigen", "rotating": "rotating-eigen", "floquet": "floquet"}
_ISOTROPIC_PAIRS = ROTATING_PAIRS  # (the pairs that turn with the rotor in rotating axes)


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
        self.unit = unit  # the mass unit the system is computed in [kg] (resolution.mass_unit)
        self.nr_coords = system.multiblade_coordinates()
        self.iso = [p for p in _ISOTROPIC_PAIRS if system.body.pair_isotropic(*p)]

    def with_lag_damping(self, scale_to: float, in_unit: bool = False):
        """The same case with the working dampers a search sizes set to ``scale_to`` (blade
        lag dampers [N m s/rad], or damper rods [N s/m]: :attr:`groundres.model.system.System.searched`)
        (in the equations' mass unit if ``in_unit``, :func:`groundres.assess.resolution.mass_unit`).

        Blades without a lag damper keep none (a failed damper stays failed),
        unless no blade has one, in which case all get it
        (:meth:`groundres.model.system.System.with_lag_damping`).
        """
        value = scale_to if in_unit else scale_to / self.unit
        return type(self)(self.system.with_lag_damping(value), self.unit)

    def _fit(self, band: float):
        """Coefficients of the form's matrices fitted at 0, band / 2 and band [rad/s]."""
        fits = self.__dict__.setdefault("_fits", {})
        if band not in fits:
            m, c, k = self.form(band * np.array([0.0, 0.5, 1.0]))
            k1, k2 = 4 * k[1] - 3 * k[0] - k[2], 2 * (k[2] - 2 * k[1] + k[0])
            fits[band] = (m[0], c[0], c[2] - c[0], k[0], k1, k2)
        return fits[band]

    def _fitted(self, speeds):
        """The time-invariant form's matrices at any speeds from their exact quadratic dependence.

        Mass is constant, damping linear and stiffness quadratic in Omega (the
        transforms add Omega and Omega^2 terms), so three speeds give them
        everywhere: a scan of thousands of speeds costs a few array products.
        The fit's round-off is that of the matrices at its largest speed, so
        each speed uses the fit at the power of two just above it (within a
        factor 4 of its own matrices' round-off, at any spread of speeds).
        """
        speeds = np.asarray(speeds, dtype=float)
        with np.errstate(divide="ignore"):
            band = np.exp2(np.ceil(np.log2(np.maximum(speeds, 1e-300))))
        m0 = self._fit(float(band[0]))[0] if len(speeds) else self._fit(1.0)[0]
        m = np.broadcast_to(m0, speeds.shape + m0.shape)
        c, k = np.empty(m.shape), np.empty(m.shape)
        for b in np.unique(band):
            sel = band == b
            _, c0, c1, k0, k1, k2 = self._fit(float(b))
            x = (speeds[sel] / b)[:, None, None]
            c[sel], k[sel] = c0 + x * c1, k0 + x * (k1 + x * k2)
        return m, c, k

    def _scan_roots(self, speeds):
        mats = self._fitted(speeds)
        return modal.block_eigenvalues(*mats, self._blocks(mats), split=True)

    def growth(self, speeds, neutral=True):
        """Largest real part of all roots [1/s] at each speed (roots only, batched);
        without ``neutral``, of the roots that are not neutral
        (:func:`groundres.assess.stability.largest_real_part`)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        return stability.largest_real_part(np.concatenate(self._scan_roots(speeds), -1).real, speeds, neutral)

    #: ``rough_growth(speeds, neutral) -> (value, lower, upper)``: a cheaper :meth:`growth`
    #: for scans, with bounds of the true value (None: growth is cheap enough).
    rough_growth = None

    def closeness(self, speeds):
        """Nearest approach of two roots of one block (:func:`groundres.solve.modal.closest_pair`)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        floor = np.maximum(speeds, 1e-3)
        return np.min([modal.closest_pair(r, floor) for r in self._scan_roots(speeds)], axis=0)

    def weights(self, speeds):
        """Kinetic weights [kg, kg m^2] (the mass-matrix diagonal in SI)."""
        weights = self.system.kinetic_weights(speeds)
        with np.errstate(over="ignore"):
            si = weights * self.unit
        # (only their ratios matter: beyond floating point they stay in the mass unit)
        return si if np.isfinite(si).all() else weights

    def accuracy(self) -> dict:
        """How the last sweep's roots were found, and how accurately (for provenance)."""
        return {"roots": "eigenvalues of each coupled block's state matrix (LAPACK geev, numpy.linalg.eig)"}

    def identify(self, sol: modal.Eigensolution, speeds) -> Modes:
        """Labels and frequencies of a tracked solution (:func:`groundres.modes.identify.identify`)."""
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

    def with_lag_damping(self, value, in_unit=False):
        new = super().with_lag_damping(value, in_unit)
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
        return modal.block_eigenvalues(*mats, self._blocks(mats))

    def sweep(self, speeds, progress=None):
        mats = self.system.rotating_axes(speeds)
        raw = modal.track(modal.solve(*mats, self._blocks(mats)), speeds)
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

    def __init__(self, system, unit=1.0, split=None, lag_damping=None):
        super().__init__(system, unit)
        # a trial lag damping of the damping search: the equations without the working
        # dampers with the family's symmetry, shared by every trial (one set of node
        # matrices), and the damping
        self.split, self.lag_damping = split, lag_damping

    def with_lag_damping(self, value, in_unit=False):
        value = value if in_unit else value / self.unit
        if self.split is None:
            split = self.system.lag_damping_split()
            # (the family's symmetry: working dampers alike and nonzero, failed ones failed)
            self.split = (split, exponents.symmetry(split.with_lag_damping(1.0)))
        return _Floquet(self.system.with_lag_damping(value), self.unit, self.split, value)

    def _solve(self, speeds, **kw):
        """Floquet analysis at ``speeds`` (a trial damping: on the shared split system)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        if self.lag_damping is None:
            return exponents.solve(self.system, speeds, **kw)
        split, sym = self.split
        return exponents.solve(split, speeds, damping=self.lag_damping, sym=sym, **kw)

    def roots(self, speeds):
        return self._solve(speeds, harmonics=0).exponent

    def growth(self, speeds, neutral=True):
        """Largest real part [1/s]: exact without the lifted problem
        (:func:`groundres.solve.floquet.exponents.solve`);
        without ``neutral``, of the roots that are not neutral
        (:func:`groundres.assess.stability.largest_real_part`).
        """
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        real = self._solve(speeds, harmonics=0, lift=False).exponent.real
        return stability.largest_real_part(real, speeds, neutral)

    def rough_growth(self, speeds, neutral=True):
        """:meth:`growth` at the scan's loose tolerance
        (:data:`groundres.solve.floquet.exponents.SCAN_TOLERANCE`)
        and bounds of the true value given that tolerance: (value, lower, upper) [1/s].
        For scans that only look where to evaluate :meth:`growth` (:class:`groundres.assess.scan.PeakWatch`).
        """
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        fs = self._solve(speeds, harmonics=0, lift=False, tolerance=exponents.SCAN_TOLERANCE, bounds=True)
        real = fs.exponent.real
        return tuple(
            stability.largest_real_part(real, speeds, neutral, bound)
            for bound in (None, fs.real_lower, fs.real_upper)
        )

    solved = None

    compiled = None  # (whether the sweep's transition matrices came from the compiled kernel)

    def accuracy(self):
        control = (
            "the embedded fifth- and third-order error estimate of DOP853 (compiled kernel)"
            if self.compiled
            else "a Richardson error estimate against a coarser grid (NumPy, while the compiled kernel "
            "was not ready)"
        )
        out = {
            "roots": "Floquet exponents of transition matrices over the symmetry interval, integrated "
            "with fixed steps of the Dormand-Prince eighth-order tableau, the step count of each "
            f"speed set by {control}",
            "transition_tolerance": exponents.TOLERANCE,
            "transition_tolerance_note": "largest error of an entry, relative to max(1, |Phi|)",
            "harmonics": exponents.HARMONICS,
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
        self.compiled = transition.use_kernel(exponents.DOP8)
        fs = self.solved = exponents.solve(self.system, speeds, progress=progress, compiled=self.compiled)
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
    return _SOLVERS[form or choose_method(case)](*resolution.system_in_mass_unit(case.rotor, case.body))


def _smallest_damping_ratio_at(solver, modes: Modes, speeds, w: float) -> float:
    """Smallest damping ratio at speed ``w`` over the roots that continue the modes.

    For each mode, the root nearest its eigenvalue interpolated from the
    sweep, with its frequency shifted by the multiple of Omega that brings it
    nearest (none for a multiblade analysis, whose frequencies are unique:
    there every root counts). One solve at ``w`` for all modes.
    """
    roots = np.asarray(solver.roots(np.array([w])))[0]
    if isinstance(solver, _Multiblade):
        cand = roots.real + 1j * np.abs(roots.imag)
        return float(identify.damping_ratio(cand, scale=np.abs(cand).max()).min())
    lam = modes.eigenvalue  # (n_s, n_m)
    target = np.array(
        [
            complex(np.interp(w, speeds, lam[:, k].real), np.interp(w, speeds, lam[:, k].imag))
            for k in range(lam.shape[1])
        ]
    )
    m = np.rint((target.imag[:, None] - roots.imag[None, :]) / w)
    cand = roots.real[None, :] + 1j * np.abs(roots.imag[None, :] + m * w)
    best = cand[np.arange(len(target)), np.argmin(np.abs(cand - target[:, None]), axis=1)]
    return float(identify.damping_ratio(best, scale=np.abs(cand).max()).min())


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
        "auto", "eigen" or "floquet"; defaults to the case's choice.
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
        sweep whose estimated work is beyond the limit (:mod:`groundres.assess.resolution`).
    """
    form = choose_method(case, method)
    frame = frame or case.sweep.frame
    speeds = case.sweep.speeds if speeds is None else np.unique(np.asarray(speeds, dtype=float))
    system, unit = resolution.system_in_mass_unit(case.rotor, case.body)
    unit_of_speed = (case.sweep.unit, SPEED_UNITS[case.sweep.unit])
    resolution.check_resolution(
        case.rotor, case.body, system, speeds, stability.growth_threshold, unit_of_speed
    )
    solver = _SOLVERS[form](system, unit)
    deutsch = deutsch_in_si(system, unit)
    probe = scan.probe_speeds(speeds, [e.tuning_speed for e in deutsch], solver.kind)
    if solver.kind == "floquet":
        transition.check_slowest(speeds)
        low = damping_search.lowest_search_speed(deutsch)
        windows = damping_search.search_windows(deutsch)  # (and the ranges, which the sweep will find)
        search = damping_search.search_grid(speeds, probe, True, low, windows) if lag_damping_search else None
        damping_search.check_work(
            solver, speeds, probe, search, unit_of_speed, time_invariant_form(case) is not None
        )
    report = progress or (lambda stage, done, total: None)
    report("sweep", 0, len(speeds))
    modes = solver.identify(solver.sweep(speeds, lambda done, total: report("sweep", done, total)), speeds)
    report("range ends", 0, None)
    max_real = modes.real_part.max(-1)
    ratios = modes.damping_ratio

    def min_ratio_at(w):
        return _smallest_damping_ratio_at(solver, modes, speeds, w)

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
        floor=resolution.lowest_periodic_speed(system, speeds, probe) if solver.kind == "floquet" else 0.0,
        rough_growth=solver.rough_growth,
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
