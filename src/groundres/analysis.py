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

from . import floquet, modal, stability
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
        mats = self.system.multiblade(speeds)
        return np.abs(np.diagonal(mats[0], axis1=-2, axis2=-1))

    def _finish(self, sol, speeds):
        """Labels and frequencies of tracked roots, harmonics kept continuous along branches."""
        weights = self.weights(speeds)
        found = modal.identify(sol, self.nr_coords, weights, speeds, self.iso)
        labelled = modal.Eigensolution(
            sol.eigenvalue,
            sol.vector,
            np.zeros(sol.vector.shape[-1], int),
            [np.arange(len(self.nr_coords))],
            sol.harmonics,
            sol.orders,
        )
        return labelled, found


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

    def sweep(self, speeds):
        mats = self.system.multiblade(speeds)
        sol = modal.track(modal.solve(*mats, self._blocks(mats)), speeds)
        weights = np.abs(np.diagonal(mats[0], axis1=-2, axis2=-1))
        return sol, modal.identify(sol, self.nr_coords, weights, speeds, self.iso)

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

    def sweep(self, speeds):
        mats = self.system.rotating_axes(speeds)
        raw = modal.track(modal.solve(*mats, modal.coupling_blocks(*mats)), speeds)
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
        harmonics, orders = self.system.nonrotating_harmonics(q, phase, self.samples // 2 - 1)
        sol = modal.Eigensolution(raw.eigenvalue, raw.vector, raw.block, raw.blocks, harmonics, orders)
        return self._finish(sol, speeds)


class _Floquet(_Solver):
    """Periodic equations: Floquet exponents and periodic eigenvectors."""

    samples = 32

    def roots(self, speeds):
        return floquet.solve(self.system, np.atleast_1d(speeds), samples=0).exponent

    coupled_roots = roots

    def sweep(self, speeds):
        fs = floquet.solve(self.system, speeds, samples=self.samples)
        sym = fs.symmetry
        n = self.system.size
        # branches: multipliers and monodromy eigenvectors vary continuously with speed
        disp = fs.vector[:, :n, :]
        disp = disp / np.maximum(np.linalg.norm(disp, axis=1, keepdims=True), 1e-300)
        order = modal.track_order(fs.multiplier, disp, np.zeros(2 * n, int), speeds)
        rho, vectors, disp = _reorder(order, fs.multiplier, fs.vector, disp)
        # exponents with the multiplier's phase unwrapped along each branch
        dt = sym.angle / speeds[:, None]
        phase = np.unwrap(np.angle(rho), axis=0)
        exponent = (np.log(np.abs(rho)) + 1j * phase) / dt
        # one period of p = x exp(-lambda t): Phi(psi_s) v over [0, Delta), then by symmetry
        psi0 = sym.angle * np.arange(self.samples) / self.samples
        y = fs.sampled @ vectors[None]  # (K, n_s, 2n, 2n)
        t = psi0[:, None, None, None] / speeds[None, :, None, None]
        q = y[:, :, :n, :] * np.exp(-exponent[None, :, None, :] * t)
        parts, gk = [], np.eye(n)
        for _ in range(self.system.n_blades // sym.shift):
            parts.append(gk @ q)
            gk = sym.g @ gk
        full = np.concatenate(parts, axis=0)
        phase = 2 * np.pi * np.arange(len(full)) / len(full)
        harmonics, orders = self.system.nonrotating_harmonics(full, phase, len(full) // 2 - 1)
        sol = modal.Eigensolution(exponent, disp, np.zeros(2 * n, int), [np.arange(n)], harmonics, orders)
        return self._finish(sol, speeds)


_SOLVERS = {"multiblade": _Multiblade, "rotating": _Rotating, "floquet": _Floquet}


def root_solver(case: Case, form: str | None = None):
    """The solver of a case's roots (``.roots(speeds)``) by method form."""
    return _SOLVERS[form or choose_method(case)](System(case.rotor, case.body))


def _extremes(roots):
    """Largest real part and smallest damping ratio at each speed."""
    max_real = roots.real.max(-1)
    size = np.abs(roots)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(size > 1e-12 * max(size.max(), 1e-300), -roots.real / size, np.inf)
    return max_real, ratio.min(-1)


def analyze(case: Case, *, frame: str | None = None, method: str | None = None, speeds=None) -> SweepResult:
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

    Returns
    -------
    SweepResult
    """
    form = choose_method(case, method)
    frame = frame or case.sweep.frame
    solver = _SOLVERS[form](System(case.rotor, case.body))
    speeds = case.sweep.speeds if speeds is None else np.unique(np.asarray(speeds, dtype=float))
    sol, found = solver.sweep(speeds)
    modes = modal.modes(sol, found, speeds)
    max_real, min_ratio = _extremes(found.eigenvalue)

    def min_ratio_at(w):
        return float(_extremes(solver.sweep(np.array([w]))[1].eigenvalue)[1][0])

    assessed = stability.assess(
        speeds,
        max_real,
        min_ratio,
        lambda w: float(solver.roots(w).real.max()),
        min_ratio_at,
    )
    deutsch = stability.deutsch(case.rotor, case.body)
    exact = _minimum_lag_damping(solver, case, speeds, deutsch)
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
    )


def _minimum_lag_damping(solver, case, speeds, deutsch):
    """Smallest lag damping (on every blade that has a damper) for a stable sweep."""
    periodic = not isinstance(solver, _Multiblade)
    count = 60 if periodic else 200
    scan = speeds[np.unique(np.linspace(0, len(speeds) - 1, min(len(speeds), count)).round().astype(int))]

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
