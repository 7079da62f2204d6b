"""Lag damping the Deutsch criterion asks for, per body mode.

Deutsch criterion (Deutsch 1946, "Ground vibrations of helicopters", J. Aero.
Sci. 13(5); in the form of Johnson 2013, "Rotorcraft Aeromechanics", ch. 17):
at exact tuning of a body mode omega_b with the regressive lag mode,
omega_b = Omega (1 - nu), light damping needs

* planar (one body direction):   C_b C_lag >= (N/4) S^2 omega_b^2 (1 - nu)/nu,
* isotropic hub (both directions): C_h C_lag >= (N/2) S^2 omega_h^2 (1 - nu)/nu,

with C_b the body damper and omega_b the body frequency with the rotor mass
included. It is an approximation; :func:`groundres.assess.damping_search.exact_minimum` finds the exact
minimum from the roots, on the same internal grid and from the sweep's own
verdict at the installed damper, so that the two never contradict each other.

C_lag is the lag damping the cyclic lag mode sees, per blade [N m s/rad]: a
blade's own rotational damper, plus its damper rods (:mod:`groundres.model.dampers`).
A rod of coefficient c whose length changes by g_a per radian of lag of its
first blade and g_b of the blade j further on adds c (g_a^2 + g_b^2 +
2 g_a g_b cos(2 pi n j / N)) to cyclic order n; between mirror-image points
(g_b = -g_a) that is 2 (1 - cos(2 pi n j / N)) c g_a^2, and nothing to the
collective mode (n = 0). The criterion's C_lag is order 1's.

A body on gear legs (the rigid form) has coupled modes: each mode of the
body with the rotor's mass and inertia added (undamped) counts with its
modal mass, stiffness and damping referred to the hub's motion in the rotor
plane (a mode that does not move the hub in that plane, heave or yaw about
the shaft, has no entry); an isotropic body's modes come in pairs, each pair
one isotropic entry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..model.body import Body
from ..model.params import Rotor


@dataclass(frozen=True)
class DeutschEntry:
    """Lag damping the Deutsch criterion asks for, for one body mode.

    Attributes
    ----------
    body_mode : str
        "x", "y", "pitch", "roll" (planar form) or "x-y" / "pitch-roll" (isotropic form).
    form : str
        "planar" or "isotropic".
    body_frequency : float
        omega_b [rad/s], rotor mass included (pitch, roll: as seen at the hub).
    tuning_speed : float or None
        Omega where Omega (1 - nu) = omega_b [rad/s]; None if the lag mode never
        reaches the body frequency (nu >= 1 there: no ground resonance).
    lag_frequency : float or None
        nu at the tuning speed [per rev] (nu changes with rotor speed when the
        lag hinge has a spring).
    body_damping : float
        Body damper, referred to the hub [N s/m].
    required_lag_damping : float or None
        [N m s/rad]; inf if the body has no damping; None without tuning.
    installed_lag_damping : float
        The smallest WORKING lag damper on the rotor [N m s/rad]: the blades'
        damper when they are identical; with dissimilar blades the smallest
        non-zero damper (a failed damper, 0, is counted in ``failed_dampers``,
        not taken as installed). 0 when no blade has a damper.
    failed_dampers : int
        Blades without a lag damper on a rotor where other blades have one.
    rod_lever : float
        The cyclic lag damping per blade that the rotor's damper rods give per
        unit of their coefficient [N m s/rad per N s/m = m^2/rad] (0 without
        rods): a rod coefficient of (required - rotational) / rod_lever meets
        the criterion.
    limitation : str or None
        Why the criterion does not apply as stated, None where it does. It
        assumes N >= 3 identical blades: "blades differ", or "damper rods differ"
        (blades alike, but a rod unlike the others: a failed one) (the rotor is smeared
        to its average blade, which can miss the instability a failed damper
        causes) or "two blades" (a two-bladed rotor has no cyclic lag pair
        and periodic coefficients in every frame).
    """

    body_mode: str
    form: str
    body_frequency: float
    tuning_speed: float | None
    lag_frequency: float | None
    body_damping: float
    required_lag_damping: float | None
    installed_lag_damping: float
    failed_dampers: int = 0
    limitation: str | None = None
    rod_lever: float = 0.0

    @property
    def applies(self) -> bool:
        """Whether the criterion applies as stated (N >= 3 identical blades)."""
        return self.limitation is None

    @property
    def satisfied(self) -> bool | None:
        """Installed (smallest working) damper >= required; None where there is
        no verdict (the criterion does not apply, or no tuning): see :attr:`reason`."""
        if not self.applies or self.required_lag_damping is None:
            return None
        return self.installed_lag_damping >= self.required_lag_damping

    @property
    def reason(self) -> str:
        """Why the verdict is what it is, in words."""
        if self.limitation == "damper rods differ":
            return (
                "does not apply: damper rods differ (the criterion assumes every blade alike with its "
                "rods; the required value is for the rotor's average, which can miss a failed rod)"
            )
        if self.limitation == "blades differ":
            return (
                "does not apply: blades differ (the criterion assumes identical blades; the "
                "required value is for the average blade, which can miss a failed damper)"
            )
        if self.limitation is not None:
            return (
                f"does not apply: {self.limitation} (the criterion assumes N >= 3 identical blades; "
                "a two-bladed rotor has no cyclic lag pair and periodic coefficients in every frame)"
            )
        if self.required_lag_damping is None:
            return "no tuning: the regressive lag mode never reaches the body frequency (nu >= 1)"
        if math.isinf(self.required_lag_damping):
            return "body undamped: no finite lag damping suffices"
        return "installed damper >= required" if self.satisfied else "installed damper < required"


def installed_lag_damping(rotor: Rotor) -> tuple[float, int]:
    """The smallest working lag damper [N m s/rad], rods included as the cyclic lag mode sees
    them, and the number of failed rotational dampers.

    A blade without a damper (0) on a rotor where other blades have one counts
    as a failed damper, not as the installed value; when no blade has a damper
    the installed value is 0 and none has failed. Damper rods add their cyclic
    (order 1) damping per blade, averaged over the rotor (:func:`rod_lever`); a rod
    without damping among rods that have some counts as failed too.
    """
    values = [b.lag_damping for b in rotor.blades]
    working = [v for v in values if v > 0]
    rods = _rod_cyclic(rotor, "damping")
    damped = [d.damping > 0 for d in rotor.dampers]
    failed_rods = len(damped) - sum(damped) if any(damped) else 0
    if not working:
        return rods, failed_rods
    return float(min(working)) + rods, len(values) - len(working) + failed_rods


def _rod_cyclic(rotor: Rotor, what: str, order: int = 1) -> float:
    """The cyclic lag damping (``what`` = "damping") or stiffness ("stiffness") per blade of
    the rods, or the damping per unit coefficient of the working rods ("lever"), averaged
    over the rotor [N m s/rad, N m/rad, m^2/rad]."""
    from ..model.system import working

    n = rotor.n_blades
    offsets = [b.hinge_offset for b in rotor.blades]
    total = 0.0
    works = working([d.damping for d in rotor.dampers])
    for d, w in zip(rotor.dampers, works):
        g = d.gradient(offsets, n)[::2]  # (the lag parts)
        if d.span == 0:
            lever = g[0] ** 2
        else:
            lever = g[0] ** 2 + g[1] ** 2 + 2 * g[0] * g[1] * math.cos(2 * math.pi * order * d.span / n)
        coefficient = getattr(d, what) if what != "lever" else float(w)
        total += coefficient * lever
    return float(total / n)


def rod_lever(rotor: Rotor) -> float:
    """Cyclic lag damping per blade per unit rod coefficient [m^2/rad] of the working rods."""
    return _rod_cyclic(rotor, "lever")


def _hub_equivalent(rotor: Rotor, body: Body, dof: str):
    """Mass, stiffness, damping of a body dof as seen at the hub (rotor mass included)."""
    m_rotor = sum(bl.blade_mass for bl in rotor.blades)
    if dof in ("x", "y"):
        return body.value("inertia", dof) + m_rotor, body.value("stiffness", dof), body.value("damping", dof)
    h = body.hub_height
    h2 = h * h
    j = body.value("inertia", dof) + rotor.inertia_about_pivot(h)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        out = tuple(np.float64(x) / h2 for x in (j, body.value("stiffness", dof), body.value("damping", dof)))
    if h2 == 0 or not all(np.isfinite(out)):
        return None  # the hub (almost) at the pivot: body rotation does not move it
    return tuple(float(x) for x in out)


def average_blade(rotor: Rotor):
    """The smeared blade: every property averaged over the blades."""
    from dataclasses import fields

    from ..model.params import Blade

    return Blade(
        # (each divided by N first: the sum of N values near the largest float overflows)
        **{
            f.name: float(sum(getattr(b, f.name) / len(rotor.blades) for b in rotor.blades))
            for f in fields(Blade)
        }
    )


def _lag_spring(rotor: Rotor, blade) -> tuple[float, float]:
    """(k1, k2) of the average blade's cyclic lag frequency nu^2 = k1 / Omega^2 + k2:
    k1 = (K_lag + the rods' cyclic stiffness) / I [1/s^2], k2 = e S / I [-]."""
    k1 = (blade.lag_stiffness + _rod_cyclic(rotor, "stiffness")) / blade.blade_inertia
    k2 = blade.hinge_offset * blade.blade_static_moment / blade.blade_inertia
    return k1, k2


def lag_frequency_per_rev(rotor: Rotor, rotor_speed: float) -> float:
    """Rotating cyclic lag frequency nu [per rev] of the average blade at ``rotor_speed`` [rad/s]:
    nu^2 = (K_lag + rods) / (I Omega^2) + e S / I (the nu of the Deutsch criterion)."""
    k1, k2 = _lag_spring(rotor, average_blade(rotor))
    if not rotor_speed > 0:
        return math.inf
    # (divided twice, not by the square: a speed of 1e-200 or 1e200 rad/s must not under- or overflow)
    return math.sqrt(k1 / rotor_speed / rotor_speed + k2)


def deutsch(rotor: Rotor, body: Body) -> list[DeutschEntry]:
    """Deutsch-criterion lag damping for each body mode (see module docstring).

    Dissimilar blades are smeared: every property is averaged over the blades
    (the constant-coefficient approximation, which Hammond 1974 shows can
    miss the instability a failed damper causes; the exact value does not).
    Their entries, and those of a two-bladed rotor, say why the criterion does
    not apply (``limitation``) and give no verdict; the installed value is the
    smallest working damper (:func:`installed_lag_damping`).
    """
    blade = average_blade(rotor)
    n = rotor.n_blades
    k1, k2 = _lag_spring(rotor, blade)
    s = blade.blade_static_moment
    installed, failed = installed_lag_damping(rotor)
    limitation = (
        None if rotor.identical else "blades differ" if not rotor.blades_alike else "damper rods differ"
    )
    if n < 3:
        limitation = "two blades"
    lever = rod_lever(rotor)
    entries = []
    for name, form, (mass, stiffness, damping) in _body_modes(rotor, body, n):
        wb = math.sqrt(stiffness / mass)
        tuning = nu = required = None
        if k2 < 1 and wb > 0:
            tuning = (wb + math.sqrt(k2 * wb**2 + k1 * (1 - k2))) / (1 - k2)
            nu = 1 - wb / tuning
            if nu <= 0 or nu >= 1:
                tuning = nu = None
        if nu is not None:
            factor = n / 2 if form == "isotropic" else n / 4
            product = factor * s**2 * wb**2 * (1 - nu) / nu
            required = math.inf if damping == 0 else product / damping
        entries.append(
            DeutschEntry(name, form, wb, tuning, nu, damping, required, installed, failed, limitation, lever)
        )
    return entries


def _body_modes(rotor: Rotor, body: Body, n: int) -> list:
    """(name, form, (mass, stiffness, damping) referred to the hub) of each body mode."""
    if body.form == "rigid":
        return _rigid_modes(rotor, body)
    out = []
    for a, b_ in (("x", "y"), ("pitch", "roll")):
        if body.pair_isotropic(a, b_):
            modes = [(f"{a}-{b_}", a, "isotropic")]
        else:
            modes = [(d, d, "planar") for d in (a, b_) if d in body.dofs]
        for name, dof, form in modes:
            eq = _hub_equivalent(rotor, body, dof)
            if eq is not None:
                out.append((name, form, eq))
    return out


def _rigid_modes(rotor: Rotor, body: Body) -> list:
    """Modes of a body on gear legs with the rotor's mass and inertia at the hub, referred to
    the hub's motion in the rotor plane."""
    from scipy.linalg import eigh

    from ..model.body import BODY_DOFS
    from ..symbolic.codegen import generated

    keep = [BODY_DOFS.index(d) for d in body.dofs]
    shaft = rotor.inertia_about_pivot(0.0, "yaw")
    added = generated("rigid_body_mass")(
        mass=sum(b.blade_mass for b in rotor.blades),
        inertia_xx=shaft / 2,
        inertia_yy=shaft / 2,
        inertia_zz=shaft,
        inertia_xy=0.0,
        inertia_xz=0.0,
        inertia_yz=0.0,
        centre_x=body.hub_x,
        centre_y=body.hub_y,
        centre_z=body.hub_height,
    )[np.ix_(keep, keep)]
    mass, damping, stiffness = body.matrices()
    mass = mass + added
    values, vectors = eigh(stiffness, mass)  # (omega^2, ascending; mass-normalised modes)
    # the hub's displacement in the rotor plane per unit body coordinate: translation + rotation x hub
    hub = generated("leg_matrix")  # (T' diag(k) T with k = (1, 1, 0): T's in-plane rows, squared)
    planar = hub(
        position_x=body.hub_x,
        position_y=body.hub_y,
        position_z=body.hub_height,
        along_x=1.0,
        along_y=1.0,
        along_z=0.0,
    )[np.ix_(keep, keep)]
    out, used = [], set()
    for i in range(len(values)):
        if i in used:
            continue
        phi = vectors[:, i]
        reach = float(phi @ planar @ phi)  # |hub displacement in the plane|^2
        scale = float(phi @ mass @ phi)
        if reach <= 1e-9 * scale / max(np.abs(mass).max(), 1e-300) or values[i] <= 0:
            continue
        pair = [j for j in range(i + 1, len(values)) if abs(values[j] - values[i]) <= 1e-9 * values[i]]
        form = "isotropic" if body.isotropic and pair else "planar"
        used |= {i, *pair[:1]} if form == "isotropic" else {i}
        refer = [float(phi @ m @ phi) / reach for m in (mass, stiffness, damping)]
        main = body.dofs[int(np.argmax(np.abs(phi) * np.sqrt(np.diag(mass))))]
        name = f"mode {len(out) + 1} ({'pair, ' if form == 'isotropic' else ''}mostly {main})"
        out.append((name, form, tuple(refer)))
    return out


def deutsch_in_si(system) -> list[DeutschEntry]:
    """Deutsch entries of equations computed in a mass unit (``system.mass_unit``,
    :class:`groundres.model.units.MassUnit`), dampers given back in SI."""
    entries = deutsch(system.rotor, system.body)
    if system.mass_unit.si:
        return entries
    si = system.mass_unit.to_si

    return [
        replace(
            e,
            body_damping=si(e.body_damping),
            required_lag_damping=si(e.required_lag_damping),
            installed_lag_damping=si(e.installed_lag_damping),
        )
        for e in entries
    ]
