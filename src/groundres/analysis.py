"""One call from a case to a result: wiring only, the physics lives below.

>>> from groundres import analyze, load_case
>>> result = analyze(load_case("hammond-1974"))   # doctest: +SKIP
>>> result.stability.stable                        # doctest: +SKIP
True
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from . import modal, stability
from .params import Case
from .results import SweepResult
from .system import System

METHOD_NAMES = {"multiblade": "multiblade-eigen", "rotating": "rotating-eigen", "floquet": "floquet"}


class MethodError(ValueError):
    """The method asked for cannot analyse this case (or is not available yet)."""


def time_invariant_form(case: Case) -> str | None:
    """Which transform gives constant coefficients: "multiblade", "rotating" or None.

    Identical blades and N >= 3: multiblade coordinates (any body). Otherwise an
    isotropic body in rotating axes. Otherwise none: the case is periodic.
    """
    if case.rotor.identical and case.rotor.n_blades >= 3:
        return "multiblade"
    if case.body.isotropic:
        return "rotating"
    return None


def choose_method(case: Case, method: str | None = None) -> str:
    """The analysis method for a case: see :func:`time_invariant_form`.

    Raises
    ------
    MethodError
        For "eigen" on a periodic case, or a method not available for the case.
    """
    method = method or case.sweep.method
    form = time_invariant_form(case)
    if method == "eigen" and form is None:
        raise MethodError(
            "[sweep] method = 'eigen': this case has periodic coefficients in every frame "
            "(dissimilar blades or N = 2 on an anisotropic body); use 'floquet' or 'auto'"
        )
    if method == "floquet" or form is None:
        raise MethodError(
            f"[sweep] method = {method!r}: Floquet analysis (needed for dissimilar blades or N = 2 "
            "on an anisotropic body) is not yet supported in this version"
        )
    if form == "rotating":
        raise MethodError(
            f"[sweep] method = {method!r}: rotating-axes eigen-analysis (dissimilar blades or N = 2 "
            "on an isotropic body) is not yet supported in this version"
        )
    return form


class _Model:
    """The time-invariant equations of a case, at any speeds."""

    def __init__(self, case: Case, form: str):
        self.case, self.form = case, form
        self.system = System(case.rotor, case.body)
        self.coordinates = self.system.multiblade_coordinates()

    def matrices(self, speeds):
        return self.system.multiblade(np.atleast_1d(np.asarray(speeds, dtype=float)))

    def with_lag_damping(self, value: float) -> _Model:
        blades = tuple(replace(b, lag_damping=value) for b in self.case.rotor.blades)
        rotor = replace(self.case.rotor, blades=blades)
        return _Model(replace(self.case, rotor=rotor), self.form)


def _extremes(eigenvalues):
    """Largest real part and smallest damping ratio at each speed."""
    max_real = eigenvalues.real.max(-1)
    size = np.abs(eigenvalues)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(size > 1e-12 * max(size.max(), 1e-300), -eigenvalues.real / size, np.nan)
    return max_real, np.nanmin(np.where(np.isnan(ratio), np.inf, ratio), axis=-1)


def analyze(case: Case, *, frame: str | None = None, method: str | None = None) -> SweepResult:
    """Analyse a case over its speed sweep.

    Parameters
    ----------
    case : Case
    frame : str, optional
        "nonrotating" or "rotating"; defaults to the case's choice.
    method : str, optional
        "auto", "eigen" or "floquet"; defaults to the case's choice.

    Returns
    -------
    SweepResult
    """
    form = choose_method(case, method)
    frame = frame or case.sweep.frame
    model = _Model(case, form)
    speeds = case.sweep.speeds
    mats = model.matrices(speeds)
    blocks = modal.coupling_blocks(*mats)
    sol = modal.track(modal.solve(*mats, blocks), speeds)
    iso = [p for p in (("x", "y"), ("pitch", "roll")) if case.body.pair_isotropic(*p)]
    weights = np.abs(np.diagonal(mats[0], axis1=-2, axis2=-1))
    found = modal.modes(sol, modal.identify(sol, model.coordinates, weights, speeds, iso), speeds)

    def extremes_at(model_, w):
        return _extremes(modal.block_eigenvalues(*model_.matrices(w), blocks))

    max_real, min_ratio = _extremes(sol.eigenvalue)
    assessed = stability.assess(
        speeds,
        max_real,
        min_ratio,
        lambda w: float(extremes_at(model, w)[0][0]),
        lambda w: float(extremes_at(model, w)[1][0]),
    )
    deutsch = stability.deutsch(case.rotor, case.body)

    # Blade-only blocks (collective, differential, higher cyclic lag) are
    # stable for any lag damping >= 0: the search needs the body-coupled ones.
    n_body = len(case.body.dofs)
    coupled = [b for b in blocks if b.min() < n_body]

    # The search scans at most 200 speeds, then refines around the worst one.
    scan = speeds[np.unique(np.linspace(0, len(speeds) - 1, min(len(speeds), 200)).round().astype(int))]

    def growth(lag_damping):
        trial = model.with_lag_damping(lag_damping)

        def excess(w):
            roots = modal.block_eigenvalues(*trial.matrices(w), coupled)
            return roots.real.max(-1) - stability.growth_threshold(w)

        coarse = excess(scan)
        i = int(np.argmax(coarse))
        fine = np.linspace(scan[max(i - 1, 0)], scan[min(i + 1, len(scan) - 1)], 41)
        return float(max(coarse[i], excess(fine).max()))

    blade = case.rotor.blades[0]
    finite = [e.required_lag_damping for e in deutsch if e.required_lag_damping not in (None, np.inf)]
    guess = max(finite + [blade.lag_damping, blade.blade_inertia * speeds[-1] * 1e-3])
    critical = 2 * blade.blade_inertia * speeds[-1]  # a lag damper this strong is far beyond design
    exact = stability.minimum_lag_damping(growth, guess, cap=100 * max(critical, guess))
    return SweepResult(
        case=case,
        method=METHOD_NAMES[form],
        frame=frame,
        rotor_speed=speeds,
        modes=found,
        stability=assessed,
        deutsch=deutsch,
        exact_lag_damping=exact,
        coordinates=model.coordinates,
    )
