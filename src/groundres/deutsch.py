"""Lag damping the Deutsch criterion asks for, per body mode.

Deutsch criterion (Deutsch 1946, "Ground vibrations of helicopters", J. Aero.
Sci. 13(5); in the form of Johnson 2013, "Rotorcraft Aeromechanics", ch. 17):
at exact tuning of a body mode omega_b with the regressive lag mode,
omega_b = Omega (1 - nu), light damping needs

* planar (one body direction):   C_b C_lag >= (N/4) S^2 omega_b^2 (1 - nu)/nu,
* isotropic hub (both directions): C_h C_lag >= (N/2) S^2 omega_h^2 (1 - nu)/nu,

with C_b the body damper and omega_b the body frequency with the rotor mass
included. It is an approximation; :func:`groundres.damping_search.exact_minimum` finds the exact
minimum from the roots, on the same internal grid and from the sweep's own
verdict at the installed damper, so that the two never contradict each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .params import Body, Rotor


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
    limitation : str or None
        Why the criterion does not apply as stated, None where it does. It
        assumes N >= 3 identical blades: "blades differ" (the rotor is smeared
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
    """The smallest working lag damper [N m s/rad] and the number of failed ones.

    A blade without a damper (0) on a rotor where other blades have one counts
    as a failed damper, not as the installed value; when no blade has a damper
    the installed value is 0 and none has failed.
    """
    values = [b.lag_damping for b in rotor.blades]
    working = [v for v in values if v > 0]
    if not working:
        return 0.0, 0
    return float(min(working)), len(values) - len(working)


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


def deutsch(rotor: Rotor, body: Body) -> list[DeutschEntry]:
    """Deutsch-criterion lag damping for each body mode (see module docstring).

    Dissimilar blades are smeared: every property is averaged over the blades
    (the constant-coefficient approximation, which Hammond 1974 shows can
    miss the instability a failed damper causes; the exact value does not).
    Their entries, and those of a two-bladed rotor, say why the criterion does
    not apply (``limitation``) and give no verdict; the installed value is the
    smallest working damper (:func:`installed_lag_damping`).
    """
    from dataclasses import fields

    from .params import Blade

    blade = Blade(
        # (each divided by N first: the sum of N values near the largest float overflows)
        **{
            f.name: float(sum(getattr(b, f.name) / len(rotor.blades) for b in rotor.blades))
            for f in fields(Blade)
        }
    )
    n = rotor.n_blades
    k1 = blade.lag_stiffness / blade.blade_inertia
    k2 = blade.hinge_offset * blade.blade_static_moment / blade.blade_inertia
    s = blade.blade_static_moment
    installed, failed = installed_lag_damping(rotor)
    limitation = None if rotor.identical else "blades differ"
    if n < 3:
        limitation = "two blades"
    entries = []
    modes = []
    for a, b_ in (("x", "y"), ("pitch", "roll")):
        if body.pair_isotropic(a, b_):
            modes.append((f"{a}-{b_}", a, "isotropic", n / 2))
        else:
            modes += [(d, d, "planar", n / 4) for d in (a, b_) if d in body.dofs]
    for name, dof, form, factor in modes:
        eq = _hub_equivalent(rotor, body, dof)
        if eq is None:
            continue
        mass, stiffness, damping = eq
        wb = math.sqrt(stiffness / mass)
        tuning = nu = required = None
        if k2 < 1 and wb > 0:
            tuning = (wb + math.sqrt(k2 * wb**2 + k1 * (1 - k2))) / (1 - k2)
            nu = 1 - wb / tuning
            if nu <= 0 or nu >= 1:
                tuning = nu = None
        if nu is not None:
            product = factor * s**2 * wb**2 * (1 - nu) / nu
            required = math.inf if damping == 0 else product / damping
        entries.append(
            DeutschEntry(name, form, wb, tuning, nu, damping, required, installed, failed, limitation)
        )
    return entries


def deutsch_in_si(system, unit: float) -> list[DeutschEntry]:
    """Deutsch entries of equations computed in a mass unit [kg]
    (:func:`groundres.limits.mass_unit`), dampers given back in SI."""
    entries = deutsch(system.rotor, system.body)
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
