"""The helicopter on its landing gear: the body's coordinates and its own matrices.

Body coordinates: the translations x (forward), y (left), z (up) of a
reference point, the pivot, and the rotations about it: pitch (nose up, about
-y), roll (right side down, about +x) and yaw (nose left, about +z, with the
rotor's turn). Any subset may be chosen. The hub centre is at
(``hub_x``, ``hub_y``, ``hub_height``) from the pivot, in body axes. Blades
are never part of the body: the model adds them through their own energy.

Two forms, exclusive in one case:

* **modal**: each coordinate its own mass (or inertia), spring and damper
  (``mass_x``, ``stiffness_pitch``, ``damping_yaw``, ...); the pivot is the
  body's centre of mass and its matrices are diagonal.
* **rigid**: a rigid body (``mass``, the inertia tensor ``inertia_xx`` ...
  ``inertia_yz`` about its centre of mass, the centre of mass at
  (``centre_x``, ``centre_y``, ``centre_z``) from the pivot) standing on gear
  legs (:class:`Leg`: where each meets the body, its stiffness and damping
  along the ground axes). Its mass, damping and stiffness matrices are full
  and coupled, derived from the energies
  (:func:`groundres.symbolic.derive.derive_rigid_body`,
  :func:`~groundres.symbolic.derive.derive_leg`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..errors import ParameterError
from .validate import finite, lengths, non_negative, positive

BODY_DOFS = ("x", "y", "z", "pitch", "roll", "yaw")
#: Coordinates that translate (their inertia is a mass).
TRANSLATIONS = ("x", "y", "z")
#: Pairs that turn with the rotor in rotating axes (pitch and roll turn like x and y).
ROTATING_PAIRS = (("x", "y"), ("pitch", "roll"))
#: Keys of the rigid form (besides its legs).
RIGID_KEYS = (
    "mass",
    "inertia_xx",
    "inertia_yy",
    "inertia_zz",
    "inertia_xy",
    "inertia_xz",
    "inertia_yz",
    "centre_x",
    "centre_y",
    "centre_z",
)
#: Keys of the modal form.
MODAL_KEYS = tuple(
    f"{kind}_{d}"
    for d in BODY_DOFS
    for kind in (("mass" if d in TRANSLATIONS else "inertia"), "stiffness", "damping")
)
#: A body matrix whose smallest eigenvalue is below this fraction of its largest is singular.
SINGULAR = 1e-12


@dataclass(frozen=True)
class Leg:
    """One gear leg (an oleo, a wheel, a skid's contact): a point of the body on springs
    and dampers along the ground axes.

    Parameters
    ----------
    position_x, position_y, position_z : float
        Where the leg meets the body, from the pivot in body axes [m].
    stiffness_x, stiffness_y, stiffness_z : float
        Springs along x, y, z [N/m].
    damping_x, damping_y, damping_z : float
        Dampers along x, y, z [N s/m].
    """

    position_x: float
    position_y: float
    position_z: float = 0.0
    stiffness_x: float = 0.0
    stiffness_y: float = 0.0
    stiffness_z: float = 0.0
    damping_x: float = 0.0
    damping_y: float = 0.0
    damping_z: float = 0.0

    def __post_init__(self):
        lengths(self, "position_x", "position_y", "position_z")
        non_negative(self, *(f"{k}_{a}" for k in ("stiffness", "damping") for a in "xyz"))
        if not any(getattr(self, f"stiffness_{a}") > 0 for a in "xyz"):
            raise ParameterError(
                "stiffness_z", self.stiffness_z, "a leg needs a stiffness > 0 along some axis"
            )

    def matrix(self, kind: str) -> np.ndarray:
        """The leg's ``kind`` ("stiffness" or "damping") matrix on all six body coordinates."""
        return self.along(*(getattr(self, f"{kind}_{a}") for a in "xyz"))

    def along(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
        """The matrix (6, 6) of springs (or dampers) ``x``, ``y``, ``z`` along the ground axes at
        this leg; linear in them (``along(z=1.0)`` times ``stiffness_z`` is that spring's share)."""
        from ..symbolic.codegen import generated

        return generated("leg_matrix")(
            position_x=self.position_x,
            position_y=self.position_y,
            position_z=self.position_z,
            along_x=x,
            along_y=y,
            along_z=z,
        )


@dataclass(frozen=True)
class Body:
    """The helicopter on its landing gear, in the modal or the rigid form (see the module).

    Parameters
    ----------
    dofs : tuple of str
        A subset of BODY_DOFS in any order; stored in BODY_DOFS order.
    mass_x, mass_y, mass_z : float
        Modal form: translating masses [kg].
    inertia_pitch, inertia_roll, inertia_yaw : float
        Modal form: inertias about the pivot [kg m^2].
    stiffness_x, ... stiffness_yaw : float
        Modal form: [N/m] for translations, [N m/rad] for rotations.
    damping_x, ... damping_yaw : float
        Modal form: [N s/m], [N m s/rad].
    hub_height, hub_x, hub_y : float
        The hub centre from the pivot [m].
    mass : float
        Rigid form: the body's mass [kg].
    inertia_xx, inertia_yy, inertia_zz, inertia_xy, inertia_xz, inertia_yz : float
        Rigid form: the inertia tensor about the centre of mass in body axes
        [kg m^2] (products of inertia as the tensor's entries: J_xy = -sum m x y).
    centre_x, centre_y, centre_z : float
        Rigid form: the centre of mass from the pivot [m].
    gear : tuple of Leg
        Rigid form: the legs.
    """

    dofs: tuple = ("x", "y")
    mass_x: float = 0.0
    mass_y: float = 0.0
    mass_z: float = 0.0
    inertia_pitch: float = 0.0
    inertia_roll: float = 0.0
    inertia_yaw: float = 0.0
    stiffness_x: float = 0.0
    stiffness_y: float = 0.0
    stiffness_z: float = 0.0
    stiffness_pitch: float = 0.0
    stiffness_roll: float = 0.0
    stiffness_yaw: float = 0.0
    damping_x: float = 0.0
    damping_y: float = 0.0
    damping_z: float = 0.0
    damping_pitch: float = 0.0
    damping_roll: float = 0.0
    damping_yaw: float = 0.0
    hub_height: float = 0.0
    hub_x: float = 0.0
    hub_y: float = 0.0
    mass: float = 0.0
    inertia_xx: float = 0.0
    inertia_yy: float = 0.0
    inertia_zz: float = 0.0
    inertia_xy: float = 0.0
    inertia_xz: float = 0.0
    inertia_yz: float = 0.0
    centre_x: float = 0.0
    centre_y: float = 0.0
    centre_z: float = 0.0
    gear: tuple = ()

    def __post_init__(self):
        dofs = tuple(self.dofs)
        if not dofs:
            raise ParameterError("dofs", list(dofs), f"needs at least one of {list(BODY_DOFS)}")
        for d in dofs:
            if d not in BODY_DOFS:
                raise ParameterError("dofs", list(dofs), f"each entry must be one of {list(BODY_DOFS)}")
        if len(set(dofs)) != len(dofs):
            raise ParameterError("dofs", list(dofs), "each degree of freedom may appear once")
        # a subset: its order carries no meaning, the model's coordinates follow BODY_DOFS
        object.__setattr__(self, "dofs", tuple(d for d in BODY_DOFS if d in dofs))
        object.__setattr__(self, "gear", tuple(self.gear))
        lengths(self, "hub_height", "hub_x", "hub_y")
        if self.form == "rigid":
            self._check_rigid()
        else:
            for d in self.dofs:
                positive(self, self.inertia_key(d))
                non_negative(self, f"stiffness_{d}", f"damping_{d}")

    @property
    def form(self) -> str:
        """ "rigid" (a rigid body on gear legs) or "modal"."""
        return "rigid" if self.gear or self.mass else "modal"

    def _check_rigid(self):
        given = [k for k in MODAL_KEYS if getattr(self, k)]
        if given:
            raise ParameterError(
                given[0],
                getattr(self, given[0]),
                "the modal form (mass_x, stiffness_x, ...) and the rigid form (mass, inertia_xx, ..., "
                "[[body.gear]]) are exclusive: give one",
            )
        positive(self, "mass")
        for name in RIGID_KEYS[1:7]:
            if not finite(getattr(self, name)):
                raise ParameterError(name, getattr(self, name), "must be a finite number [kg m^2]")
        lengths(self, "centre_x", "centre_y", "centre_z")
        if not self.gear:
            raise ParameterError("gear", [], "a rigid body needs at least one [[body.gear]] leg")
        # (the tensor about the axes the body turns about: roll x, pitch y, yaw z)
        axes = [i for i, d in enumerate(("roll", "pitch", "yaw")) if d in self.dofs]
        tensor = self.inertia_tensor()[np.ix_(axes, axes)]
        if axes and np.linalg.eigvalsh(tensor).min() <= 0:
            diagonal = [("inertia_xx", "roll"), ("inertia_yy", "pitch"), ("inertia_zz", "yaw")]
            bad = [k for i, (k, _) in enumerate(diagonal) if i in axes and getattr(self, k) <= 0]
            if bad:
                raise ParameterError(
                    bad[0],
                    getattr(self, bad[0]),
                    f"must be > 0 [kg m^2]: the body turns about this axis "
                    f"({dict(diagonal)[bad[0]]} is in dofs)",
                )
            used = [k for i, (k, _) in enumerate(diagonal) if i in axes]
            products = {(0, 1): "inertia_xy", (0, 2): "inertia_xz", (1, 2): "inertia_yz"}
            used += [k for (i, j), k in products.items() if i in axes and j in axes]
            raise ParameterError(
                ", ".join(used),
                tuple(getattr(self, k) for k in used),
                "the inertia tensor about the axes the body turns about must be positive definite "
                "(all its principal inertias > 0): the products of inertia are too large for these "
                "moments of inertia",
            )
        self._check_held("stiffness")

    def _check_held(self, kind: str) -> None:
        """Every chosen coordinate meets some stiffness of the legs (else a free rigid motion),
        resolved in double precision beside the largest."""
        if _resolved(self._leg_matrix(kind)):
            return
        # the legs as they stand, each spring 1: do they hold every coordinate at all?
        unit = self._leg_matrix(kind, lambda leg, a: float(getattr(leg, f"{kind}_{a}") > 0))
        if _resolved(unit):
            raise self._spread_error(kind)
        values, vectors = np.linalg.eigh(unit)
        dof = self.dofs[int(np.argmax(np.abs(vectors[:, 0])))]
        what = "a rotation only at a distance from the pivot" if dof not in TRANSLATIONS else "along its axis"
        raise ParameterError(
            "dofs",
            list(self.dofs),
            f"the gear legs hold no {kind} against '{dof}' (a leg resists {what}), or hold it so "
            f"little against their other {kind} (legs very far from the centre of mass) that it is "
            "lost to round-off: place the legs so that they hold it, or leave it out of dofs",
        )

    def _leg_matrix(self, kind: str, value=None) -> np.ndarray:
        """The legs' ``kind`` matrix on the chosen coordinates; ``value(leg, axis)`` in place of
        each leg's own ``kind``_axis if given."""
        keep = [BODY_DOFS.index(d) for d in self.dofs]
        value = value or (lambda leg, a: getattr(leg, f"{kind}_{a}"))
        # (a value near the largest float times a lever overflows: the caller finds the matrix
        # unusable and names the leg, so the overflow itself is no warning)
        with np.errstate(over="ignore", invalid="ignore"):
            total = sum(leg.along(*(value(leg, a) for a in "xyz")) for leg in self.gear)
        return total[np.ix_(keep, keep)]

    def _spread_error(self, kind: str) -> ParameterError:
        """The legs hold every coordinate, but one leg's ``kind`` lies so far from the others'
        that their matrix is singular in double precision: the error naming it (the value
        farthest, in decades, from the middle of the legs' values)."""
        given = [
            (abs(math.log10(getattr(leg, f"{kind}_{a}"))), n, a, getattr(leg, f"{kind}_{a}"))
            for n, leg in enumerate(self.gear, start=1)
            for a in "xyz"
            if getattr(leg, f"{kind}_{a}") > 0
        ]
        middle = float(np.median([math.log10(v) for *_, v in given]))
        _, n, axis, value = max(given, key=lambda g: (abs(math.log10(g[3]) - middle), -g[1]))
        key = f"{kind}_{axis}"
        others = max(v for _, m, a, v in given if (m, a) != (n, axis))
        large = math.log10(value) > middle
        matrix = self._leg_matrix(kind)
        values = np.linalg.eigvalsh(matrix) if np.isfinite(matrix).all() else np.zeros(1)  # (overflowed)
        ratio = max(values.min(), 0.0) / max(abs(values).max(), 1e-300)
        if ratio > 0:  # (the value that would leave the smallest eigenvalue resolved, with a margin)
            guess = value * (ratio / (10 * SINGULAR) if large else 10 * SINGULAR / ratio)
        else:
            guess = others / (10 * SINGULAR) if large else others * 10 * SINGULAR

        def trial(leg, a):
            return guess if (leg is self.gear[n - 1] and a == axis) else getattr(leg, f"{kind}_{a}")

        unit = "N/m" if kind == "stiffness" else "N s/m"
        allowed = (
            f"; here {'up to' if large else 'at least'} about {guess:.2g} {unit}"
            if _resolved(self._leg_matrix(kind, trial))
            else ""
        )
        return ParameterError(
            f"gear[{n}].{key}",
            value,
            f"so {'large' if large else 'small'} against the legs' other {kind} values (up to "
            f"{others:.3g} {unit}) that the body's {kind} matrix cannot be resolved in double "
            f"precision (its smallest eigenvalue is below {SINGULAR:.0e} of its largest, lost to "
            f"round-off): keep the legs' {kind} values within about {1 / SINGULAR:.0e} of each "
            f"other{allowed}",
        )

    def inertia_tensor(self) -> np.ndarray:
        """Rigid form: the inertia tensor about the centre of mass [kg m^2], (3, 3)."""
        return np.array(
            [
                [self.inertia_xx, self.inertia_xy, self.inertia_xz],
                [self.inertia_xy, self.inertia_yy, self.inertia_yz],
                [self.inertia_xz, self.inertia_yz, self.inertia_zz],
            ]
        )

    @staticmethod
    def inertia_key(dof: str) -> str:
        """Modal form: the mass or inertia parameter of a body degree of freedom."""
        return f"mass_{dof}" if dof in TRANSLATIONS else f"inertia_{dof}"

    def value(self, kind: str, dof: str) -> float:
        """Modal form: ``kind`` is "inertia" (mass or inertia), "stiffness" or "damping"."""
        key = self.inertia_key(dof) if kind == "inertia" else f"{kind}_{dof}"
        return getattr(self, key)

    def full_matrices(self) -> np.ndarray:
        """Mass, damping, stiffness on all six coordinates, (3, 6, 6) (blades excluded)."""
        if self.form == "modal":
            return np.stack(
                [
                    np.diag([self.value(kind, d) for d in BODY_DOFS])
                    for kind in ("inertia", "damping", "stiffness")
                ]
            )
        from ..symbolic.codegen import generated

        mass = generated("rigid_body_mass")(**{k: getattr(self, k) for k in RIGID_KEYS})
        damping = sum(leg.matrix("damping") for leg in self.gear)
        stiffness = sum(leg.matrix("stiffness") for leg in self.gear)
        return np.stack([mass, damping, stiffness])

    def matrices(self) -> np.ndarray:
        """Mass, damping, stiffness on the chosen coordinates, (3, n_body, n_body)."""
        keep = [BODY_DOFS.index(d) for d in self.dofs]
        return self.full_matrices()[:, keep][:, :, keep]

    @property
    def isotropic(self) -> bool:
        """True when the support looks the same in every direction of the rotor plane.

        x and y both present or both absent, likewise pitch and roll; the hub
        on the vertical through the pivot where the body turns; and the body's matrices unchanged
        when the pairs are turned about the vertical (each pair's members
        alike, and any coupling between pairs or with z and yaw turning with
        them).
        """
        for a, b in ROTATING_PAIRS:
            if (a in self.dofs) != (b in self.dofs):
                return False
        if self._hub_off_axis():
            return False
        turn = self.turn(1.0)
        mats = self.matrices()
        if not np.isfinite(mats).all():  # (a value that overflowed: the checks of the case say which)
            return False
        scale = max(np.abs(mats).max(), 1e-300)
        with np.errstate(over="ignore", invalid="ignore"):  # (near the largest float: not alike)
            turned = turn.T @ mats @ turn
        return bool(np.isfinite(turned).all() and np.abs(turned - mats).max() <= 1e-12 * scale)

    def _hub_off_axis(self) -> bool:
        """The hub away from the vertical through the pivot, where the body turns: then the
        body's rotations move it differently in different directions."""
        return bool(self.hub_x or self.hub_y) and bool({"pitch", "roll", "yaw"} & set(self.dofs))

    def hub_in_plane(self) -> np.ndarray:
        """The hub centre's displacement along x and y per unit of each body coordinate, small
        rotations (module docstring's axes): (2, n_body) [m per m or rad]."""
        h, hx, hy = self.hub_height, self.hub_x, self.hub_y
        per = {"x": (1.0, 0.0), "y": (0.0, 1.0), "z": (0.0, 0.0)}
        per.update({"pitch": (-h, 0.0), "roll": (0.0, -h), "yaw": (-hy, hx)})
        return np.array([per[d] for d in self.dofs], dtype=float).T

    def turn(self, angle: float) -> np.ndarray:
        """The body coordinates turned about the vertical by ``angle`` [rad]: (n_body, n_body)."""
        out = np.eye(len(self.dofs))
        index = {d: i for i, d in enumerate(self.dofs)}
        c, s = math.cos(angle), math.sin(angle)
        for a, b in ROTATING_PAIRS:
            if a in index:
                i, j = index[a], index[b]
                out[i, i], out[i, j], out[j, i], out[j, j] = c, -s, s, c
        return out

    def pair_isotropic(self, a: str, b: str) -> bool:
        """Whether the pair (a, b) is present and looks the same in every direction (modal form:
        equal inertia, stiffness and damping; rigid form: the whole body isotropic)."""
        if a not in self.dofs or b not in self.dofs or self._hub_off_axis():
            return False
        if self.form == "rigid":
            return self.isotropic
        return all(
            math.isclose(self.value(k, a), self.value(k, b), rel_tol=1e-12, abs_tol=0.0)
            for k in ("inertia", "stiffness", "damping")
        )


def _resolved(matrix: np.ndarray) -> bool:
    """Whether a symmetric positive semi-definite ``matrix`` has every eigenvalue above
    :data:`SINGULAR` of its largest (none lost to round-off)."""
    if not np.isfinite(matrix).all():  # (a value that overflowed: nothing is resolved)
        return False
    values = np.linalg.eigvalsh(matrix)
    return bool(values.min() > SINGULAR * max(np.abs(values).max(), 1e-300))


BODY_KEYS = tuple(f.name for f in fields(Body) if f.name not in ("dofs", "gear"))
LEG_KEYS = tuple(f.name for f in fields(Leg))
