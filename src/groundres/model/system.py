"""Mass, damping and stiffness matrices of a rotor on its body, batched over speeds.

The blade-coordinate equations (body coordinates, then lag of blades 1..N, then
flap of blades 1..N) have periodic coefficients; :meth:`System.matrices` gives
them at any azimuth. :meth:`System.multiblade` and :meth:`System.rotating_axes`
give the time-invariant forms where they exist (see :mod:`groundres.model.mbc`).
"""

from __future__ import annotations

import copy
from dataclasses import replace
from functools import cached_property

import numpy as np

from ..symbolic.codegen import BLADE_ARGUMENTS, blade_function
from . import airform, dampers, mbc
from . import inflow as inflow_module
from . import trim as trim_module
from .body import BODY_DOFS, Body
from .mbc import Coordinate
from .params import Rotor
from .units import BLADE_UNITS, ROD_UNITS, SI, MassUnit

_LOCAL = {name: i for i, name in enumerate(BODY_DOFS + ("lag", "flap") + inflow_module.STATES)}
#: Systems frozen at one speed's trim (:meth:`System.frozen`) a system keeps.
FROZEN_KEPT = 8


def searched(rotor: Rotor) -> str:
    """What a lag damping search sizes on ``rotor`` (:attr:`System.searched`)."""
    rods = rotor.dampers
    if rods and (any(d.damping > 0 for d in rods) or not any(b.lag_damping > 0 for b in rotor.blades)):
        return "rods"
    return "blades"


def searched_unit(rotor: Rotor) -> str:
    """The unit of the damper a lag damping search sizes on ``rotor`` (:func:`searched`): a
    rod's along it [N s/m], or a blade's rotational one [N m s/rad]."""
    return ROD_UNITS["damping"] if searched(rotor) == "rods" else BLADE_UNITS["lag_damping"]


def working(values) -> list:
    """Which dampers work: those with damping, or all of them where none has."""
    out = [v > 0 for v in values]
    return out if any(out) else [True] * len(out)


class System:
    """The linear equations of one rotor on one body.

    Parameters
    ----------
    rotor : Rotor
    body : Body
    mass_unit : MassUnit
        The unit the masses, inertias, springs and dampers of ``rotor`` and
        ``body`` are given in, and so every coefficient of the equations
        (:class:`groundres.model.units.MassUnit`): SI unless given.
        :meth:`in_mass_unit` chooses it for a case.
    """

    def __init__(self, rotor: Rotor, body: Body, mass_unit: MassUnit = SI):
        self.rotor, self.body, self.mass_unit = rotor, body, mass_unit
        self.n_blades = rotor.n_blades
        #: The inflow states of dynamic inflow (none otherwise), after the body's coordinates.
        self.inflow_states = inflow_module.states(rotor.aero)
        #: The nonrotating coordinates, shared by every blade: the body's, then the inflow states.
        self.n_body = len(body.dofs) + len(self.inflow_states)
        #: Coordinates that enter the equations only through their rates (the inflow states,
        #: velocities): their positions are no state, and the solvers drop them exactly.
        self.integrals = np.arange(len(body.dofs), self.n_body)
        self.blade_kinds = ("lag", "flap") if rotor.flap else ("lag",)
        self.size = self.n_body + self.n_blades * len(self.blade_kinds)
        self._local = [_LOCAL[d] for d in body.dofs + self.inflow_states] + [
            _LOCAL[k] for k in self.blade_kinds
        ]
        self._global = [
            list(range(self.n_body))
            + [self.n_body + j * self.n_blades + k for j in range(len(self.blade_kinds))]
            for k in range(self.n_blades)
        ]
        # Scatter plan: entries of blade matrices that land on a blade row or
        # column are written once; body-body entries are summed over blades.
        nl = len(self._local)
        glob = np.array(self._global)  # (N, nl)
        rows = np.broadcast_to(glob[:, :, None], (self.n_blades, nl, nl))
        cols = np.broadcast_to(glob[:, None, :], (self.n_blades, nl, nl))
        own = ~((rows < self.n_body) & (cols < self.n_body))
        self._scatter = (np.flatnonzero(own.ravel()), rows[own], cols[own])
        self.grid_cache = {}
        self._trims = None  # (a TrimTable, made when first asked)
        #: Whether its trims are alike from blade to blade: blades alike but for their dampers
        #: (no load at the trim), or those of the system it holds the trims of.
        statics = [replace(b, lag_damping=0.0, flap_damping=0.0) for b in rotor.blades]
        self.trims_alike = all(b == statics[0] for b in statics[1:])
        self._frozen = None  # (a Trim of one speed: the system frozen at it, see frozen())
        self._frozen_systems = {}
        #: The dampers the lag damping search sizes (:attr:`searched`) that work: those
        #: with damping, or all of them where none has.
        self.working = working(self.damper_values(every=True))
        #: Damping matrices D_j (d, n, n), constant in azimuth, along which a split
        #: system takes dampings c_j set per speed, C = C_0 + sum_j c_j D_j
        #: (:meth:`split_damping`); none (d = 0) in a plain system. A direction whose
        #: :attr:`direction_halves` entry is 0 is a stiffness matrix S_j instead:
        #: K = K_0 + sum_j k_j S_j.
        self.damping_directions = np.zeros((0, self.size, self.size))
        #: Per direction, the half of [q; q'] it multiplies: 1 damping, 0 stiffness (none
        #: listed: every direction is a damping one).
        self.direction_halves = ()

    @classmethod
    def in_mass_unit(cls, rotor: Rotor, body: Body) -> System:
        """The equations of ``rotor`` on ``body`` (SI) computed in the mass unit their inertias
        call for (:meth:`groundres.model.units.MassUnit.of`): exact, and safe from overflow."""
        unit = MassUnit.of(rotor, body)
        return cls(*unit.scale(rotor, body), unit)

    @cached_property
    def coordinates(self) -> list[Coordinate]:
        """Blade coordinates: body and inflow (nonrotating), then each blade's lag, flap."""
        body = self._nonrotating_coordinates()
        blades = [
            Coordinate(kind, str(k + 1), frame="rotating")
            for kind in self.blade_kinds
            for k in range(self.n_blades)
        ]
        return body + blades

    @cached_property
    def air_sources(self) -> list:
        """A rotor in air's blade arrays as monomials of the trim state times fixed arrays
        (:func:`groundres.model.airform.sources`), found once."""
        return airform.sources(self)

    @property
    def local_indices(self) -> list[int]:
        """Where each coordinate a blade touches sits among a blade's local coordinates
        (LOCAL_DOFS, then the inflow states): the body's, the inflow states, lag, flap."""
        return list(self._local)

    def _nonrotating_coordinates(self) -> list[Coordinate]:
        return [Coordinate("body", d) for d in self.body.dofs] + [
            Coordinate("inflow", d) for d in self.inflow_states
        ]

    def blade_harmonics(self, speeds) -> np.ndarray:
        """Harmonic matrices of each blade, shape (n_s, N, 3, 5, n_loc, n_loc).

        Axis 2 is mass, damping, stiffness; axis 3 the azimuth harmonics
        (1, cos psi, sin psi, cos 2 psi, sin 2 psi) of that blade.
        """
        speeds = np.asarray(speeds, dtype=float)
        if self.rotor.aero is not None:  # (monomials of the trim state times fixed arrays)
            return airform.blade_arrays(self, speeds)
        sel = (slice(None),) + np.ix_(range(3), range(5), self._local, self._local)

        def one(k):
            blade = self.rotor.blades[k]
            values = {name: getattr(blade, name) for name in BLADE_ARGUMENTS if hasattr(blade, name)}
            hub = {k: getattr(self.body, k) for k in ("hub_height", "hub_x", "hub_y")}
            return np.moveaxis(blade_function()(speeds, **hub, **values), -1, 0)[sel]

        if self.rotor.blades_alike:
            first = one(0)
            return np.broadcast_to(first[:, None], (len(speeds), self.n_blades) + first.shape[1:])
        return np.stack([one(k) for k in range(self.n_blades)], axis=1)

    def trim(self, speeds) -> trim_module.Trim:
        """The hover trim at ``speeds`` [rad/s] of a rotor in air (:mod:`groundres.model.trim`;
        thrust and torque in SI), each speed found once (:class:`groundres.model.trim.TrimTable`);
        of a system frozen at one speed's trim (:meth:`frozen`), that trim at every speed."""
        speeds = np.asarray(speeds, dtype=float)
        if self._frozen is not None:
            return self._frozen.at(speeds)
        return self._trim_table()(speeds)

    def _trim_table(self) -> trim_module.TrimTable:
        """The trims this system has found (made when first asked; shared with systems that
        differ from it in their dampers only, :meth:`_damped`)."""
        if self._trims is None:
            self._trims = trim_module.TrimTable(self.rotor, self.body, self.mass_unit.kg)
        return self._trims

    def body_matrices(self) -> np.ndarray:
        """Body-only mass, damping, stiffness on the nonrotating coordinates, shape (3, n_body,
        n_body) (nothing on the inflow states: the inflow's own terms come with the blades)."""
        own = self.body.matrices()
        if not self.inflow_states:
            return own
        out = np.zeros((3, self.n_body, self.n_body))
        out[:, : own.shape[1], : own.shape[2]] = own
        return out

    @cached_property
    def rod_matrices(self) -> np.ndarray:
        """Damping and stiffness of the damper rods on these coordinates, (2, n, n):
        constant (:mod:`groundres.model.dampers`)."""
        return dampers.matrices(self.rotor, self.n_body, self.rotor.flap)

    def matrices(self, speeds, phase=0.0, harmonics=None):
        """Blade-coordinate matrices at blade-1 azimuth ``phase`` (= Omega t).

        Parameters
        ----------
        speeds : array (n_s,)
            Rotor speeds [rad/s].
        phase : float or array broadcastable to (..., n_s)
            Azimuth of blade 1 [rad] at the instant wanted.
        harmonics : array, optional
            ``blade_harmonics(speeds)``, if already computed.

        Returns
        -------
        ndarray, shape (3, ..., n_s, n, n)
            Mass, damping and stiffness.
        """
        speeds = np.asarray(speeds, dtype=float)
        if harmonics is None:
            harmonics = self.blade_harmonics(speeds)
        phase = np.broadcast_to(
            np.asarray(phase, dtype=float), np.broadcast_shapes(np.shape(phase), speeds.shape)
        )
        psi = mbc.blade_azimuths(self.n_blades, phase)
        weights = np.stack(
            [np.ones_like(psi), np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)], axis=-1
        )
        blades = np.einsum("...skh,skghij->g...skij", weights, harmonics)
        out = np.zeros((3,) + phase.shape + (self.size, self.size))
        out[..., : self.n_body, : self.n_body] += self.body_matrices().reshape(
            (3,) + (1,) * phase.ndim + (self.n_body, self.n_body)
        )
        nb = self.n_body
        out[..., :nb, :nb] += blades[..., :nb, :nb].sum(-3)
        flat, rows, cols = self._scatter
        out[..., rows, cols] = blades.reshape(blades.shape[:-3] + (-1,))[..., flat]
        if self.rotor.dampers:
            out[1:] += self.rod_matrices.reshape((2,) + (1,) * phase.ndim + (self.size, self.size))
        return out

    def frozen(self, speed: float) -> System:
        """This system with its trim held at the trim of ``speed`` [rad/s] (a rotor in air).

        In vacuum the matrices are exact polynomials in the rotor speed (mass
        constant, damping linear, stiffness quadratic), which the periodic
        analysis builds on; in air the trim changes with the speed, but with the
        trim held they are such polynomials again, and equal this system's at
        ``speed``. The last few are kept (with their node grids).
        """
        if self.rotor.aero is None:
            return self
        key = float(speed)
        if key not in self._frozen_systems:
            if len(self._frozen_systems) >= FROZEN_KEPT:
                self._frozen_systems.pop(next(iter(self._frozen_systems)))
            held = copy.copy(self)
            held.grid_cache, held._trims, held._frozen_systems = {}, None, {}
            held._frozen = self.trim(np.array([key]))
            self._frozen_systems[key] = held
        return self._frozen_systems[key]

    @property
    def searched(self) -> str:
        """What a lag damping search sizes: "rods" (the damper rods' damping along the rod
        [N s/m]) where some rod has damping, or the rotor has rods and no blade damper;
        else "blades" (each blade's rotational lag damper [N m s/rad])."""
        return searched(self.rotor)

    def damper_values(self, every: bool = False) -> list:
        """The installed values of the dampers a search sizes (:attr:`searched`): the working
        ones, or ``every`` one (failed ones at 0)."""
        parts = self.rotor.dampers if self.searched == "rods" else self.rotor.blades
        values = [p.damping if self.searched == "rods" else p.lag_damping for p in parts]
        return values if every else [v for v, w in zip(values, self.working) if w]

    def damper_lever(self) -> float:
        """Lag damping [N m s/rad] a blade sees per unit of the searched damper, at most
        (1 for blade dampers; g^2 of the rods' lag gradients, summed per blade, for rods):
        the scale that turns a rod's N s/m into the blades' N m s/rad."""
        if self.searched == "blades":
            return 1.0
        per_blade = np.zeros(self.n_blades)
        offsets = [b.hinge_offset for b in self.rotor.blades]
        for damper, w in zip(self.rotor.dampers, self.working):
            if w:
                lag = damper.gradient(offsets, self.n_blades)[::2]
                per_blade[list(damper.blades(self.n_blades))] += lag**2
        return float(per_blade.max())

    def with_lag_damping(self, value: float) -> System:
        """The same equations with ``value`` (in :attr:`mass_unit`) on every working damper a
        search sizes (:attr:`searched`: each blade's lag damper, or the damper rods' damping).

        A failed damper (none on a blade, a rod without damping, while others have
        one) stays failed.
        """
        if self.searched == "rods":
            rods = tuple(
                replace(d, damping=value) if w else d for d, w in zip(self.rotor.dampers, self.working)
            )
            return self._damped(System(replace(self.rotor, dampers=rods), self.body, self.mass_unit))
        blades = tuple(
            replace(b, lag_damping=value) if w else b for b, w in zip(self.rotor.blades, self.working)
        )
        return self._damped(System(replace(self.rotor, blades=blades), self.body, self.mass_unit))

    def _damped(self, other: System) -> System:
        """``other``, which differs from this system only in its dampers, sharing its trims
        (dampers hold no load at the trim: the blades are still there)."""
        return other.holding_trim_of(self)

    def holding_trim_of(self, other: System) -> System:
        """This system with the hover trims of ``other`` (in air; itself in vacuum): a rotor
        whose lag dampers follow laws is trimmed once, with each law at its small-motion values,
        and every equivalent system of the law (another damper and spring on the lag) moves
        about that trim."""
        if self.rotor.aero is not None:
            self._trims = other._trim_table()
            self.trims_alike = other.trims_alike
            self.__dict__.pop("air_sources", None)
        return self

    def lag_damping_split(self) -> System:
        """The equations without their working lag dampers, carrying dC/dc.

        The damping matrix is affine in the lag damping c set on every working
        damper: C(c) = C_0 + c dC/dc, with C_0 that of the returned system and
        dC/dc its one damping direction (:meth:`split_damping`).
        """
        off = self.with_lag_damping(0.0).split_damping([self.with_lag_damping(1.0)])
        off.working = list(self.working)  # (without dampers it would mark every blade working)
        return off

    def split_damping(self, units, stiffness=()) -> System:
        """This system, whose dampings are off, carrying the damping directions of ``units``
        and after them the stiffness directions of ``stiffness``.

        ``units`` are systems that differ from this one only by a unit damping
        in one place each (a damper coefficient of 1 where this one has 0):
        D_j = C(units[j]) - C(self); ``stiffness`` systems differ by a unit spring
        instead: S_j = K(stiffness[j]) - K(self). Each must be constant in azimuth (a damper
        or spring between parts that turn together, or on the body) and leave the other
        matrices alone; ValueError otherwise.
        """
        psi = np.array([0.0, 0.7, 2.1])[:, None]
        own = self.matrices(np.ones(1), psi)[:, :, 0]  # (3, azimuths, n, n)
        directions = []
        for which, systems in ((1, units), (2, stiffness)):
            for unit in systems:
                other = unit.matrices(np.ones(1), psi)[:, :, 0]
                d = other[which] - own[which]
                scale = max(np.abs(other).max(), 1.0)
                rest = [i for i in range(3) if i != which]
                moved = np.abs(other[rest] - own[rest]).max()
                if moved > 1e-13 * scale or np.abs(d - d[0]).max() > 1e-13 * scale:
                    raise ValueError("a direction must leave the other matrices alone and be constant")
                directions.append(d[0])
        split = self._damped(System(self.rotor, self.body, self.mass_unit))
        split.damping_directions = np.array(directions).reshape(len(directions), self.size, self.size)
        split.direction_halves = (1,) * len(units) + (0,) * len(stiffness) if len(stiffness) else ()
        return split

    # -- time-invariant forms -------------------------------------------------

    def _blade_transform(self, basis_per_kind):
        """Block-diagonal T: identity on the body, the given basis per blade kind."""
        n = self.size
        t = np.zeros(basis_per_kind[0].shape[:-2] + (n, n))
        t[..., : self.n_body, : self.n_body] = np.eye(self.n_body)
        for j in range(len(self.blade_kinds)):
            s = slice(self.n_body + j * self.n_blades, self.n_body + (j + 1) * self.n_blades)
            t[..., s, s] = basis_per_kind[j]
        return t

    def multiblade_coordinates(self) -> list[Coordinate]:
        """Coordinates of the multiblade form."""
        body = self._nonrotating_coordinates()
        names = mbc.multiblade_names(self.n_blades)
        return body + [Coordinate(kind, name, n) for kind in self.blade_kinds for name, n in names]

    def multiblade(self, speeds, phase=0.0, harmonics=None):
        """Equations in multiblade coordinates (time-invariant for identical blades, N >= 3);
        ``harmonics`` as in :meth:`matrices`.

        Returns
        -------
        ndarray, shape (3, n_s, n, n)
            Mass, damping, stiffness at blade-1 azimuth ``phase``.
        """
        speeds = np.asarray(speeds, dtype=float)
        m, c, k = self.matrices(speeds, phase, harmonics)
        basis, d1, d2 = mbc.multiblade_basis(self.n_blades, np.broadcast_to(phase, speeds.shape))
        w = speeds[:, None, None]
        kinds = len(self.blade_kinds)
        t = self._blade_transform([basis] * kinds)
        t_dot = self._blade_transform([w * d1] * kinds)
        t_dot[..., : self.n_body, : self.n_body] = 0.0
        t_ddot = self._blade_transform([w**2 * d2] * kinds)
        t_ddot[..., : self.n_body, : self.n_body] = 0.0
        return np.stack(mbc.transform_equations(m, c, k, t, t_dot, t_ddot))

    def rotating_axes(self, speeds, phase=0.0, harmonics=None):
        """Equations with the body in rotating axes (time-invariant for an isotropic body);
        ``harmonics`` as in :meth:`matrices`.

        The pairs (x, y) and (pitch, roll), and the inflow states forward and left,
        turn with the rotor; a body with only one of a pair is anisotropic and has
        no such form.
        """
        speeds = np.asarray(speeds, dtype=float)
        for a, b in (("x", "y"), ("pitch", "roll")):
            if (a in self.body.dofs) != (b in self.body.dofs):
                raise ValueError(f"rotating axes need both {a} and {b} in the body dofs")
        m, c, k = self.matrices(speeds, phase, harmonics)
        phase = np.broadcast_to(phase, speeds.shape)
        rot, d_rot, d2_rot = mbc.rotation_basis(phase)
        n = self.size
        t = np.broadcast_to(np.eye(n), speeds.shape + (n, n)).copy()
        t_dot = np.zeros_like(t)
        t_ddot = np.zeros_like(t)
        w = speeds[:, None, None]
        index = {d: i for i, d in enumerate(self.body.dofs)}
        for a, b in (("x", "y"), ("pitch", "roll")):
            if a in index:
                ij = np.ix_([index[a], index[b]], [index[a], index[b]])
                t[(slice(None),) + ij] = rot
                t_dot[(slice(None),) + ij] = w * d_rot
                t_ddot[(slice(None),) + ij] = w**2 * d2_rot
        if self.inflow_states:
            # the inflow pair turns too, as velocities: v = T v_r gives v' = T v_r' + T' v_r, so
            # its damping takes M T' (not 2 M T') and its positions (no state) take nothing
            pair = list(self.integrals[1:])
            ij = (slice(None),) + np.ix_(pair, pair)
            t[ij], t_dot[ij] = rot, w * d_rot / 2
        mass, damping, stiffness = mbc.transform_equations(m, c, k, t, t_dot, t_ddot)
        stiffness[..., self.integrals] = 0.0
        return np.stack((mass, damping, stiffness))

    # -- nonrotating view of periodic motion ------------------------------------

    def to_multiblade(self, q, phase):
        """Blade-coordinate displacements -> multiblade coordinates at blade-1 azimuths.

        Parameters
        ----------
        q : ndarray (K, ..., n, m)
            Displacements in blade coordinates at K instants.
        phase : ndarray (K,)
            Azimuth of blade 1 at those instants [rad].
        """
        basis, _, _ = mbc.multiblade_basis(self.n_blades, np.asarray(phase, dtype=float))
        scale = np.array(
            [1.0 if name in ("0", "d") else 2.0 for name, _ in mbc.multiblade_names(self.n_blades)]
        )
        inverse = scale[:, None] * np.swapaxes(basis, -1, -2) / self.n_blades  # (K, N, N)
        inverse = inverse.reshape(inverse.shape[:1] + (1,) * (q.ndim - 3) + inverse.shape[1:])
        out = np.array(q, dtype=complex)
        for j in range(len(self.blade_kinds)):
            s = slice(self.n_body + j * self.n_blades, self.n_body + (j + 1) * self.n_blades)
            out[..., s, :] = inverse @ q[..., s, :]
        return out

    def multiblade_spectrum(self, q):
        """Harmonics of periodic blade-coordinate motion in multiblade coordinates.

        Parameters
        ----------
        q : ndarray (K, ..., n, m)
            One revolution of a periodic displacement p(psi) (e.g. a Floquet mode
            times exp(-lambda t)) in blade coordinates, at the K equally spaced
            azimuths psi_s = 2 pi s / K of blade 1.

        Returns
        -------
        ndarray (K, ..., n, m)
            Amplitude of each multiblade coordinate at frequency offset
            o * Omega, order o at index o mod K.
        """
        phase = 2 * np.pi * np.arange(len(q)) / len(q)
        return np.fft.fft(self.to_multiblade(q, phase), axis=0) / len(q)

    def nonrotating_harmonics(self, q, max_order):
        """Harmonics -max_order..max_order (< K/2) of :meth:`multiblade_spectrum`.

        Returns
        -------
        harmonics : ndarray (n_s, n, 2 max_order + 1, m)
            For q of shape (K, n_s, n, m): amplitude of each multiblade
            coordinate at frequency offset order * Omega.
        orders : ndarray (2 max_order + 1,)
        """
        orders = np.arange(-max_order, max_order + 1)
        coeff = self.multiblade_spectrum(q)[orders % len(q)]  # (M, n_s, n, m)
        return np.moveaxis(coeff, 0, 2), orders

    def kinetic_weights(self, speeds) -> np.ndarray:
        """Kinetic weight of each multiblade coordinate (mass-matrix diagonal), (n_s, n)."""
        return np.abs(np.diagonal(self.multiblade(np.asarray(speeds, dtype=float))[0], axis1=-2, axis2=-1))
