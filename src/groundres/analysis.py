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

from . import floquet, identify, modal, stability
from .identify import Modes
from .params import Case
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

    def __init__(self, system: System):
        self.system = system
        self.nr_coords = system.multiblade_coordinates()
        self.iso = [p for p in _ISOTROPIC_PAIRS if system.body.pair_isotropic(*p)]

    def with_lag_damping(self, scale_to: float):
        """The same case with the lag dampers that work set to ``scale_to``.

        Blades without a lag damper keep none (a failed damper stays failed),
        unless no blade has one, in which case all get it.
        """
        blades = self.system.rotor.blades
        working = [b.lag_damping > 0 for b in blades]
        if not any(working):
            working = [True] * len(blades)
        new = tuple(replace(b, lag_damping=scale_to) if w else b for b, w in zip(blades, working))
        return type(self)(System(replace(self.system.rotor, blades=new), self.system.body))

    def weights(self, speeds):
        return self.system.kinetic_weights(speeds)

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
            self.weights(speeds),
            speeds,
            block=sol.block,
            blocks=sol.blocks,
            key=sol.key,
            isotropic_pairs=self.iso,
            threshold=stability.growth_threshold(speeds),
        )


class _Multiblade(_Solver):
    def __init__(self, system):
        super().__init__(system)
        self.blocks = None

    def _blocks(self, mats):
        if self.blocks is None:
            self.blocks = modal.coupling_blocks(*mats)
        return self.blocks

    def roots(self, speeds):
        mats = self.system.multiblade(np.atleast_1d(speeds))
        return modal.block_eigenvalues(*mats, self._blocks(mats))

    def coupled_roots(self, speeds):
        """Roots of the blocks that contain a body coordinate (the only ones lag damping can destabilise)."""
        mats = self.system.multiblade(np.atleast_1d(speeds))
        n_body = self.system.n_body
        return modal.block_eigenvalues(*mats, [b for b in self._blocks(mats) if b.min() < n_body])

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

    def roots(self, speeds):
        mats = self.system.rotating_axes(np.atleast_1d(speeds))
        return modal.block_eigenvalues(*mats, modal.coupling_blocks(*mats))

    coupled_roots = roots

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

    def roots(self, speeds):
        return floquet.solve(self.system, np.atleast_1d(speeds), harmonics=0).exponent

    coupled_roots = roots

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
    return _SOLVERS[form or choose_method(case)](System(case.rotor, case.body))


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
    return float(np.nan_to_num(identify.damping_ratio(best, scale=np.abs(cand).max()), nan=np.inf))


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
    """
    form = choose_method(case, method)
    frame = frame or case.sweep.frame
    solver = _SOLVERS[form](System(case.rotor, case.body))
    speeds = case.sweep.speeds if speeds is None else np.unique(np.asarray(speeds, dtype=float))
    report = progress or (lambda stage, done, total: None)
    report("sweep", 0, len(speeds))
    modes = solver.identify(solver.sweep(speeds, lambda done, total: report("sweep", done, total)), speeds)
    report("range ends", 0, None)
    max_real = modes.real_part.max(-1)
    ratios = np.nan_to_num(modes.damping_ratio, nan=np.inf)  # (a root at the origin has none)

    def min_ratio_at(w):
        label = int(np.argmin(ratios[np.argmin(np.abs(speeds - w))]))
        return _damping_ratio_near(solver, modes, speeds, label, w)

    assessed = stability.assess(
        speeds,
        max_real,
        ratios.min(-1),
        lambda w: float(solver.roots(w).real.max()),
        min_ratio_at,
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
    deutsch = stability.deutsch(case.rotor, case.body)
    report("lag damping", 0, None)
    exact = _minimum_lag_damping(solver, case, speeds, deutsch)
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
        coordinates=solver.nr_coords,
        weights=solver.weights(speeds),
        accuracy=accuracy,
    )


def _minimum_lag_damping(solver, case, speeds, deutsch):
    """Smallest lag damping (on every blade that has a damper) for a stable sweep.

    The search looks at speeds from half the lowest body frequency up: the
    regressive lag mode, at Omega (1 - nu), meets a body mode only above it,
    and a periodic analysis of the slowest speeds is the costliest of all.
    """
    periodic = not isinstance(solver, _Multiblade)
    count = 60 if periodic else 200
    body = [e.body_frequency for e in deutsch if e.body_frequency]
    low = 0.5 * min(body) if body else 0.0
    above = speeds[speeds >= low] if (speeds >= low).any() else speeds[-1:]
    scan = above[np.unique(np.linspace(0, len(above) - 1, min(len(above), count)).round().astype(int))]

    def growth(lag_damping):
        trial = solver.with_lag_damping(lag_damping)

        def excess(w):
            return trial.coupled_roots(w).real.max(-1) - stability.growth_threshold(w)

        coarse = excess(scan)
        i = int(np.argmax(coarse))
        fine = np.linspace(scan[max(i - 1, 0)], scan[min(i + 1, len(scan) - 1)], 11 if periodic else 41)
        return float(max(coarse[i], excess(fine).max()))

    blades = case.rotor.blades
    finite = [e.required_lag_damping for e in deutsch if e.required_lag_damping not in (None, np.inf)]
    installed = max(b.lag_damping for b in blades)
    inertia = max(b.blade_inertia for b in blades)
    guess = max(finite + [installed, inertia * speeds[-1] * 1e-3])
    # Beyond a few times the Deutsch value (or the installed damper) more lag
    # damping is no design answer; periodic analyses stop earlier because a
    # very strong damper makes the equations stiff for the explicit integrator.
    cap = (20 if periodic else 100) * max(guess, 2 * inertia * speeds[-1] * (0.05 if periodic else 1.0))
    return stability.minimum_lag_damping(growth, guess, cap=cap, rtol=1e-3 if periodic else 1e-4)
