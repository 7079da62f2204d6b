"""The roots of a case at any rotor speeds, one solver per analysis method.

A solver holds the equations of one case (in their mass unit,
:meth:`groundres.model.system.System.in_mass_unit`) and answers, for any
array of speeds at once, with the roots its method finds
(:class:`groundres.methods.Method`):

* :class:`Multiblade`: eigenvalues of the multiblade form (identical blades);
* :class:`Rotating`: eigenvalues with the body in rotating axes (an isotropic
  body), their motion seen again from nonrotating axes;
* :class:`Floquet`: Floquet exponents of the periodic equations
  (:mod:`groundres.solve.floquet.exponents`).

The interface, which :func:`groundres.analysis.analyze`, the damping search
(:mod:`groundres.assess.damping_search`) and the simulation rely on, is that
of :class:`Solver`:

=====================================  =====================================================
``method``                             the :class:`~groundres.methods.Method`
``system``                             the equations, in ``system.mass_unit``
``coordinates``                        nonrotating coordinates of the mode shapes
``isotropic_pairs``                    body pairs (x, y), (pitch, roll) that are isotropic
``roots(speeds)``                      every root at each speed, (n_s, k) [1/s]
``real_parts(speeds)``                 the real parts that decide growth, (n_s, k) [1/s]
``rough_real_parts``                   None, or ``(speeds) -> (real, lower, upper)``: at a
                                       looser accuracy, with bounds of the exact values
``closeness``                          None, or ``(speeds) -> (n_s,)``: the nearest approach
                                       of two roots of one block
``sweep(speeds, progress)``            the tracked :class:`~groundres.solve.modal.Eigensolution`
``with_lag_damping(value, in_unit)``   the same case with another lag damping
``weights(speeds)``                    kinetic weights of the coordinates [kg, kg m^2]
``accuracy()``                         how the roots were found, for provenance
=====================================  =====================================================

Solvers compute; naming the roots (:mod:`groundres.modes`) and judging them
(:mod:`groundres.assess`) happen above.
"""

from __future__ import annotations

import numpy as np

from ..methods import Method
from ..model.airform import AirForm
from ..model.body import ROTATING_PAIRS
from ..model.speedtable import SpeedTable
from ..model.system import System
from . import modal
from .floquet import exponents, transition
from .floquet.symmetry import symmetry
from .floquet.tableau import DOP8
from .parallel import serial_blas

#: In air, batches of at least this many new speeds are assembled from the blades' matrices;
#: shorter ones (a scan's, a search's) summed over the monomials of the trim state.
AIR_BATCH = 64


class Solver:
    """Roots of one case's equations at any speeds (the module docstring gives the interface).

    Parameters
    ----------
    system : System
        The equations, in their mass unit (``system.mass_unit``).
    """

    #: The method this solver's roots are found by.
    method: Method

    #: ``rough_real_parts(speeds) -> (real, lower, upper)``: cheaper :meth:`real_parts` for
    #: scans, with bounds of the exact values (None: :meth:`real_parts` is cheap enough).
    rough_real_parts = None

    #: ``closeness(speeds) -> (n_s,)``: the nearest approach of two roots of one block, which
    #: finds undamped coalescences between scanned speeds (None: the roots are known only
    #: modulo the rotor speed, as Floquet exponents are).
    closeness = None

    def __init__(self, system: System):
        self.system = system
        self.coordinates = system.multiblade_coordinates()
        self.isotropic_pairs = [p for p in ROTATING_PAIRS if system.body.pair_isotropic(*p)]

    def roots(self, speeds) -> np.ndarray:
        """Every root [1/s] at each of ``speeds`` [rad/s], (n_s, k)."""
        raise NotImplementedError

    def real_parts(self, speeds) -> np.ndarray:
        """The real parts [1/s] that decide growth at each of ``speeds``, (n_s, k): batched,
        for scans over thousands of speeds."""
        raise NotImplementedError

    def sweep(self, speeds, progress=None):
        """Roots and eigenvectors at ``speeds``, tracked along branches
        (:class:`groundres.solve.modal.Eigensolution`); ``progress(done, total)`` in speeds."""
        raise NotImplementedError

    def accuracy(self) -> dict:
        """How the last sweep's roots were found, and how accurately (for provenance)."""
        raise NotImplementedError

    def with_lag_damping(self, value: float, in_unit: bool = False):
        """The same case with the working dampers a search sizes set to ``value`` (blade
        lag dampers [N m s/rad], or damper rods [N s/m]: :attr:`groundres.model.system.System.searched`),
        in SI, or in the equations' mass unit if ``in_unit``.

        Blades without a lag damper keep none (a failed damper stays failed),
        unless no blade has one, in which case all get it
        (:meth:`groundres.model.system.System.with_lag_damping`).
        """
        value = value if in_unit else self.system.mass_unit.from_si(value)
        return type(self)(self.system.with_lag_damping(value))

    def weights(self, speeds):
        """Kinetic weights [kg, kg m^2] (the mass-matrix diagonal in SI)."""
        weights = self.system.kinetic_weights(speeds)
        si = self.system.mass_unit.to_si(weights)
        # (only their ratios matter: beyond floating point they stay in the mass unit)
        return si if np.isfinite(si).all() else weights


class _TimeInvariant(Solver):
    """Eigenvalues of a time-invariant form, batched over speeds."""

    def form(self, speeds):
        """Mass, damping and stiffness of the time-invariant form, (3, n_s, n, n) (in air from
        the monomials of the trim state, :meth:`_air_form`)."""
        if self.system.rotor.aero is not None:
            return np.stack(self._air_form(speeds))
        return self.transform(speeds)

    def transform(self, speeds, harmonics=None):
        """The form at ``speeds`` of the system, or of one whose blade harmonic arrays are
        ``harmonics`` (:meth:`groundres.model.system.System.matrices`)."""
        raise NotImplementedError

    def _blocks(self, mats, speeds):
        return modal.coupling_blocks(*mats)

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
        if self.system.rotor.aero is not None:
            # In air the trim changes with the speed: no polynomial in Omega holds the matrices,
            # but monomials of the trim state do; a trial lag damping adds c (dA + Omega dB).
            line = self.__dict__.get("_air_line")
            if line is None:
                return self._air_form(speeds)
            zero, (d_a, d_b), c = line
            m, c0, k0 = zero._air_form(speeds)
            w = speeds[:, None, None]
            return m, c0 + c * (d_a[1] + w * d_b[1]), k0 + c * (d_a[2] + w * d_b[2])
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

    def _air_form(self, speeds):
        """In air: the form at ``speeds`` from monomials of the trim state
        (:class:`groundres.model.airform.AirForm`; long batches assembled, :data:`AIR_BATCH`),
        each speed's kept
        (:class:`groundres.model.speedtable.SpeedTable`: scans and searches, and the trials
        of a damping search, come back to the same speeds); the new ones computed together."""
        if "_forms" not in self.__dict__:
            form = AirForm(self.system, self.transform)

            def compute(speeds, _):  # (a long batch assembled as it is: no bands to build for it)
                with serial_blas():
                    return self.transform(speeds) if len(speeds) >= AIR_BATCH else form(speeds)

            self._forms = SpeedTable(compute, limit=20_000)
        return self._forms(np.asarray(speeds, dtype=float))

    def with_lag_damping(self, value, in_unit=False):
        """As :meth:`Solver.with_lag_damping`; in air the trial's form is the undamped one's plus
        the damping's own, exactly dA + Omega dB times the damping (the dampers hold no load
        at the trim, and the transforms add Omega to a constant damping's stiffness)."""
        new = super().with_lag_damping(value, in_unit)
        if self.system.rotor.aero is not None:
            value = value if in_unit else self.system.mass_unit.from_si(value)
            if "_air_ends" not in self.__dict__:
                zero, one = (super(_TimeInvariant, self).with_lag_damping(c, True) for c in (0.0, 1.0))
                at = np.array([0.0, 1.0])
                delta = one.transform(at) - zero.transform(at)  # (3, 2, n, n): linear in Omega
                self._air_ends = (zero, (delta[:, 0], delta[:, 1] - delta[:, 0]))
            zero, direction = self._air_ends
            new._air_line = (zero, direction, value)
        return new

    def _scan_roots(self, speeds):
        mats = self._fitted(speeds)
        return modal.block_eigenvalues(
            *mats, self._blocks(mats, speeds), split=True, integrals=self.system.integrals
        )

    def roots(self, speeds):
        # (the fitted matrices: a search's single speeds cost an array product, not an assembly)
        mats = self._fitted(np.atleast_1d(np.asarray(speeds, dtype=float)))
        return modal.block_eigenvalues(*mats, self._blocks(mats, speeds), integrals=self.system.integrals)

    def sweep(self, speeds, progress=None):
        """Eigenvalues and eigenvectors of the form at ``speeds``, tracked along branches."""
        mats = self.form(speeds)
        solution = modal.track(modal.solve(*mats, self._blocks(mats, speeds), self.system.integrals), speeds)
        if progress is not None:
            progress(len(speeds), len(speeds))
        return solution

    def real_parts(self, speeds):
        """Real parts of all roots [1/s] at each speed, from the fitted matrices (batched)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        return np.concatenate(self._scan_roots(speeds), -1).real

    def closeness(self, speeds):
        """Nearest approach of two roots of one block (:func:`groundres.solve.modal.closest_pair`)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        floor = np.maximum(speeds, 1e-3)
        return np.min([modal.closest_pair(r, floor) for r in self._scan_roots(speeds)], axis=0)

    def accuracy(self) -> dict:
        """How the last sweep's roots were found, and how accurately (for provenance)."""
        return {"roots": "eigenvalues of each coupled block's state matrix (LAPACK geev, numpy.linalg.eig)"}


class Multiblade(_TimeInvariant):
    """Identical blades (N >= 3): the multiblade form is time-invariant for any body."""

    method = Method.MULTIBLADE

    def __init__(self, system):
        super().__init__(system)
        self.blocks = None

    def _blocks(self, mats, speeds):
        """The coupling blocks, found once (kept only when found at a turning rotor: at rest the
        couplings that grow with the speed vanish)."""
        if self.blocks is not None:
            return self.blocks
        blocks = modal.coupling_blocks(*mats)
        if np.any(np.asarray(speeds) > 0):
            self.blocks = blocks
        return blocks

    def transform(self, speeds, harmonics=None):
        return self.system.multiblade(speeds, harmonics=harmonics)

    def with_lag_damping(self, value, in_unit=False):
        new = super().with_lag_damping(value, in_unit)
        new.blocks = self.blocks
        return new


class Rotating(_TimeInvariant):
    """Isotropic body in rotating axes: time-invariant for any blades."""

    method = Method.ROTATING
    #: Instants over one period at which the motion is seen from nonrotating axes.
    samples = 16

    def transform(self, speeds, harmonics=None):
        return self.system.rotating_axes(speeds, harmonics=harmonics)

    def sweep(self, speeds, progress=None):
        """As :meth:`_TimeInvariant.sweep`, the motion's harmonics seen from nonrotating axes."""
        raw = super().sweep(speeds, progress)
        # one period of the motion seen from nonrotating axes: body axes turned by psi
        phase = 2 * np.pi * np.arange(self.samples) / self.samples
        q = np.broadcast_to(raw.vector, (self.samples,) + raw.vector.shape).copy()
        index = {d: i for i, d in enumerate(self.system.body.dofs)}
        pairs = [(index[a], index[b], raw.vector) for a, b in ROTATING_PAIRS if a in index]
        integrals = self.system.integrals
        if len(integrals):  # (the inflow pair turns as velocities: its rates, then their integrals)
            pairs.append((integrals[1], integrals[2], raw.vector * raw.eigenvalue[:, None, :]))
        c, s = np.cos(phase)[:, None, None], np.sin(phase)[:, None, None]
        for ia, ib, x in pairs:
            xa, xb = x[None, :, ia, :], x[None, :, ib, :]
            q[:, :, ia, :] = c * xa - s * xb
            q[:, :, ib, :] = s * xa + c * xb
        harmonics, orders = self.system.nonrotating_harmonics(q, self.samples // 2 - 1)
        if len(integrals):
            moving = (
                raw.eigenvalue[:, None, :] + 1j * orders[None, :, None] * np.asarray(speeds)[:, None, None]
            )
            pair = list(integrals[1:])
            harmonics[:, pair] = modal.integrated(harmonics[:, pair], moving[:, None])
        one = np.zeros(raw.vector.shape[-1], int)  # labels are in nonrotating coordinates: one block
        return modal.Eigensolution(
            raw.eigenvalue, raw.vector, one, [np.arange(raw.vector.shape[1])], harmonics, orders
        )


class Floquet(Solver):
    """Periodic equations: Floquet exponents and periodic eigenvectors."""

    method = Method.FLOQUET

    def __init__(self, system, split=None, lag_damping=None):
        super().__init__(system)
        # a trial lag damping of the damping search: the equations without the working
        # dampers with the family's symmetry, shared by every trial (one set of node
        # matrices), and the damping
        self.split, self.lag_damping = split, lag_damping
        self.solved = None  # (the last sweep's FloquetSolution)
        self.compiled = None  # (whether the sweep's transition matrices came from the compiled kernel)

    def with_lag_damping(self, value, in_unit=False):
        value = value if in_unit else self.system.mass_unit.from_si(value)
        if self.split is None:
            split = self.system.lag_damping_split()
            # (the family's symmetry: working dampers alike and nonzero, failed ones failed)
            self.split = (split, symmetry(split.with_lag_damping(1.0)))
        return Floquet(self.system.with_lag_damping(value), self.split, value)

    def _solve(self, speeds, **kw):
        """Floquet analysis at ``speeds`` (a trial damping: on the shared split system)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        if self.lag_damping is None:
            return exponents.solve(self.system, speeds, **kw)
        split, sym = self.split
        return exponents.solve(split, speeds, damping=self.lag_damping, sym=sym, **kw)

    def roots(self, speeds):
        return self._solve(speeds, harmonics=0).exponent

    def real_parts(self, speeds):
        """Real parts of the exponents [1/s]: exact without the lifted problem
        (:func:`groundres.solve.floquet.exponents.solve`)."""
        return self._solve(speeds, harmonics=0, lift=False).exponent.real

    def rough_real_parts(self, speeds):
        """:meth:`real_parts` at the scan's loose tolerance
        (:data:`groundres.solve.floquet.exponents.SCAN_TOLERANCE`) and bounds of the exact
        values given that tolerance: (real, lower, upper) [1/s]. For scans that only look
        where to evaluate :meth:`real_parts` (:class:`groundres.assess.scan.PeakWatch`).
        """
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        fs = self._solve(speeds, harmonics=0, lift=False, tolerance=exponents.SCAN_TOLERANCE, bounds=True)
        return fs.exponent.real, fs.real_lower, fs.real_upper

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
        self.compiled = transition.use_kernel(DOP8)
        fs = self.solved = exponents.solve(self.system, speeds, progress=progress, compiled=self.compiled)
        n = self.system.size
        # branches: exponents (modulo Omega) and eigenvectors vary continuously
        # with speed (the multipliers' phases wrap many times over a slow period)
        disp = fs.vector[:, :n, :]
        disp = disp / np.maximum(np.linalg.norm(disp, axis=1, keepdims=True), 1e-300)
        one = np.zeros(fs.exponent.shape[-1], int)  # (one block)
        order = modal.track_order(fs.exponent, disp, one, speeds, periodic=True)
        key, lam, disp, harmonics = _reorder(order, fs.key, fs.exponent, disp, fs.harmonics)
        return modal.Eigensolution(lam, disp, one, [np.arange(n)], harmonics, fs.orders, key)


def _reorder(order, *arrays):
    """Reorder the last (root) axis of arrays by a per-speed order (n_s, n_e)."""
    out = []
    for a in arrays:
        idx = order.reshape(order.shape[:1] + (1,) * (a.ndim - 2) + order.shape[1:])
        out.append(np.take_along_axis(a, np.broadcast_to(idx, a.shape[:-1] + (order.shape[1],)), axis=-1))
    return out


#: The solver of each method.
SOLVERS = {solver.method: solver for solver in (Multiblade, Rotating, Floquet)}


def solver_for(case, method: Method) -> Solver:
    """The solver of ``case``'s roots by ``method``, on its equations in their mass unit."""
    return SOLVERS[method](System.in_mass_unit(case.rotor, case.body))
