"""Stability over a speed sweep: unstable ranges, margins, damping requirements.

A real part counts as positive above ``GROWTH_PER_RADIAN * Omega`` (growth of
more than one millionth per radian of rotor rotation) plus ``GROWTH_FLOOR``
(1e-9 1/s, for the rotor at rest), so that neutral modes of undamped cases
and near-repeated eigenvalues do not turn into instabilities through
round-off. Ends of unstable ranges inside the sweep are located by root
finding on the largest real part, not by the grid spacing; between the rotor
at rest and the first speed that turns, the search stops at half that speed
(a periodic analysis just above rest is the costliest of the sweep).

Deutsch criterion (Deutsch 1946, "Ground vibrations of helicopters", J. Aero.
Sci. 13(5); in the form of Johnson 2013, "Rotorcraft Aeromechanics", ch. 17):
at exact tuning of a body mode omega_b with the regressive lag mode,
omega_b = Omega (1 - nu), light damping needs

* planar (one body direction):   C_b C_lag >= (N/4) S^2 omega_b^2 (1 - nu)/nu,
* isotropic hub (both directions): C_h C_lag >= (N/2) S^2 omega_h^2 (1 - nu)/nu,

with C_b the body damper and omega_b the body frequency with the rotor mass
included. It is an approximation; :func:`minimum_lag_damping` finds the exact
minimum from the eigenvalues.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .params import Body, Rotor

GROWTH_PER_RADIAN = 1e-6
#: [1/s] added to the threshold: at rest the neutral roots sit at round-off.
GROWTH_FLOOR = 1e-9


def growth_threshold(speeds):
    """Real part [1/s] above which a root counts as unstable at each speed."""
    return GROWTH_PER_RADIAN * np.asarray(speeds, dtype=float) + GROWTH_FLOOR


def is_neutral(real_part, speeds):
    """Whether real parts [1/s] at ``speeds`` [rad/s] are round-off: |real part|
    at or below the growth threshold (neither growth nor decay)."""
    return np.abs(real_part) <= growth_threshold(speeds)


def _below(speeds, i):
    """The lower end of a search below grid point i: the previous speed, or half of
    this one where the previous is the rotor at rest."""
    return speeds[i - 1] if speeds[i - 1] > 0 else 0.5 * speeds[i]


def _crossing(excess, lo, hi, rising):
    """Where ``excess`` changes sign in [lo, hi]; the end it has already crossed at if none."""
    a, b = excess(lo), excess(hi)
    if (a > 0) == (b > 0):
        return lo if rising else hi
    return brentq(excess, lo, hi, xtol=1e-12, rtol=1e-8)


@dataclass(frozen=True)
class Stability:
    """Stability of a sweep.

    Attributes
    ----------
    unstable_ranges : list of (float, float)
        Rotor-speed intervals [rad/s] where some root has a positive real part.
    max_real_part : (float, float)
        Largest real part [1/s] over the sweep and the speed [rad/s] where it occurs.
    min_damping_ratio : (float, float)
        Smallest damping ratio [-] over the sweep and its speed [rad/s].
    """

    unstable_ranges: list
    max_real_part: tuple
    min_damping_ratio: tuple

    @property
    def stable(self) -> bool:
        return not self.unstable_ranges


def _refine_max(fun, speeds, values, i):
    """Maximise fun near grid point i (bounded by its neighbours; never between
    the rotor at rest and the first speed that turns: the value at rest is exact
    and a periodic analysis just above it is the costliest of the sweep)."""
    if speeds[i] <= 0:
        return float(values[i]), float(speeds[i])
    lo, hi = speeds[max(i - 1, 0)], speeds[min(i + 1, len(speeds) - 1)]
    if lo <= 0:
        lo = speeds[i]
    if hi <= lo:
        return values[i], speeds[i]
    res = minimize_scalar(lambda w: -fun(w), bounds=(lo, hi), method="bounded", options={"xatol": 1e-6 * hi})
    if -res.fun > values[i]:
        return float(-res.fun), float(res.x)
    return float(values[i]), float(speeds[i])


def unstable_ranges(speeds, max_real, max_real_at):
    """Intervals where the largest real part exceeds the growth threshold.

    Parameters
    ----------
    speeds : ndarray (n_s,)
        Sweep speeds [rad/s], increasing.
    max_real : ndarray (n_s,)
        Largest real part over all roots at each speed [1/s].
    max_real_at : callable
        ``max_real_at(speed) -> float``, the same quantity at any speed.

    Returns
    -------
    list of (float, float)
        Interior ends to 1e-8 relative; ranges open at a sweep end report that end.
    """
    excess = lambda w: max_real_at(w) - growth_threshold(w)  # noqa: E731
    positive = max_real > growth_threshold(speeds)
    ranges = []
    i, n = 0, len(speeds)
    while i < n:
        if not positive[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and positive[j + 1]:
            j += 1
        start = speeds[0] if i == 0 else _crossing(excess, _below(speeds, i), speeds[i], rising=True)
        end = speeds[-1] if j == n - 1 else brentq(excess, speeds[j], speeds[j + 1], xtol=1e-12, rtol=1e-8)
        ranges.append((float(start), float(end)))
        i = j + 1
    return ranges


def assess(speeds, max_real, min_damping, max_real_at, min_damping_at) -> Stability:
    """Unstable ranges and refined worst values for a sweep."""
    i = int(np.argmax(max_real - growth_threshold(speeds)))
    worst = _refine_max(max_real_at, speeds, max_real, i)
    j = int(np.nanargmin(min_damping))
    low = _refine_max(lambda w: -min_damping_at(w), speeds, -min_damping, j)
    ranges = unstable_ranges(speeds, max_real, max_real_at)
    peak, at = worst
    if peak > growth_threshold(at) and not any(a <= at <= b for a, b in ranges):
        # a range narrower than the grid: the refined peak found it; locate its ends
        excess = lambda w: max_real_at(w) - growth_threshold(w)  # noqa: E731
        lo = speeds[i] if i == 0 else _below(speeds, i)
        hi = speeds[min(i + 1, len(speeds) - 1)]
        start = lo if excess(lo) > 0 else brentq(excess, lo, at, xtol=1e-12, rtol=1e-8)
        end = hi if excess(hi) > 0 else brentq(excess, at, hi, xtol=1e-12, rtol=1e-8)
        ranges = sorted(ranges + [(float(start), float(end))])
    return Stability(
        unstable_ranges=ranges,
        max_real_part=worst,
        min_damping_ratio=(-low[0], low[1]),
    )


# -- damping requirements -------------------------------------------------------


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
    n = rotor.n_blades
    b = rotor.blades[0]
    m_rotor = sum(bl.blade_mass for bl in rotor.blades)
    if dof in ("x", "y"):
        return body.value("inertia", dof) + m_rotor, body.value("stiffness", dof), body.value("damping", dof)
    h = body.hub_height
    if h == 0:
        return None
    # rotor inertia about the pivot, averaged over azimuth (all blades alike)
    e = b.hinge_offset
    j_rotor = n * (
        b.blade_mass * h**2 + (b.blade_inertia + 2 * b.blade_static_moment * e + b.blade_mass * e**2) / 2
    )
    j = body.value("inertia", dof) + j_rotor
    return j / h**2, body.value("stiffness", dof) / h**2, body.value("damping", dof) / h**2


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
        **{f.name: float(np.mean([getattr(b, f.name) for b in rotor.blades])) for f in fields(Blade)}
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


def minimum_lag_damping(growth, start, cap, rtol=1e-4):
    """Smallest lag damping that makes the sweep stable, by bisection.

    Parameters
    ----------
    growth : callable
        ``growth(lag_damping) -> float``: the largest excess of real part over
        the growth threshold anywhere in the sweep (<= 0 means stable).
    start : float
        A first guess [N m s/rad] (> 0).
    cap : float
        Largest lag damping tried [N m s/rad].
    rtol : float
        Relative accuracy of the result.

    Returns
    -------
    float or None
        0.0 if stable without lag damping; None if even ``cap`` is unstable.
    """
    if growth(0.0) <= 0:
        return 0.0
    lo, hi = 0.0, max(start, 1e-9)
    while growth(hi) > 0:
        lo, hi = hi, 2 * hi
        if hi > cap:
            return None
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if growth(mid) > 0:
            lo = mid
        else:
            hi = mid
    return hi
