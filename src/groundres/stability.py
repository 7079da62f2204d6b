"""Stability over a speed sweep: unstable ranges, margins, damping requirements.

A real part counts as positive above ``GROWTH_PER_RADIAN * Omega`` (growth of
more than one millionth per radian of rotor rotation) plus ``GROWTH_FLOOR``
(1e-9 1/s, for the rotor at rest), so that neutral modes of undamped cases
and near-repeated eigenvalues do not turn into instabilities through
round-off. Unstable ranges come from the largest real part on the sweep and
on an internal grid (:mod:`groundres.scan`), with the local maxima refined
(ranges narrower than the grid) and, for eigen-analyses, the places where two
roots meet (undamped coalescences); their ends come from root finding, not
from the grid spacing. Between the rotor at rest and the first speed that
turns, no search goes below half that speed (a periodic analysis just above
rest is the costliest of the sweep).

Deutsch criterion (Deutsch 1946, "Ground vibrations of helicopters", J. Aero.
Sci. 13(5); in the form of Johnson 2013, "Rotorcraft Aeromechanics", ch. 17):
at exact tuning of a body mode omega_b with the regressive lag mode,
omega_b = Omega (1 - nu), light damping needs

* planar (one body direction):   C_b C_lag >= (N/4) S^2 omega_b^2 (1 - nu)/nu,
* isotropic hub (both directions): C_h C_lag >= (N/2) S^2 omega_h^2 (1 - nu)/nu,

with C_b the body damper and omega_b the body frequency with the rotor mass
included. It is an approximation; :func:`minimum_lag_damping` finds the exact
minimum from the roots, on the same internal grid and from the sweep's own
verdict at the installed damper, so that the two never contradict each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from . import scan
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
    peak_speeds : tuple of float
        Speed [rad/s] of the largest real part inside each unstable range.
    open_below : float or None
        Where the first range begins at the lowest speed the analysis reaches
        above rest (a periodic analysis costs more the slower the rotor: see
        :func:`groundres.analysis.lowest_periodic_speed`), that speed [rad/s]:
        the range may begin lower. None otherwise.
    """

    unstable_ranges: list
    max_real_part: tuple
    min_damping_ratio: tuple
    peak_speeds: tuple = ()
    open_below: float | None = None

    @property
    def stable(self) -> bool:
        return not self.unstable_ranges


def _refine_max(fun, speeds, values, i, xtol=1e-6):
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
    res = minimize_scalar(lambda w: -fun(w), bounds=(lo, hi), method="bounded", options={"xatol": xtol * hi})
    if -res.fun > values[i]:
        return float(-res.fun), float(res.x)
    return float(values[i]), float(speeds[i])


def find_ranges(grid, values, excess, kind="eigen", peaks=8, closeness=None, floor=0.0):
    """Intervals where ``excess`` (largest real part minus the growth threshold) is positive.

    Parameters
    ----------
    grid : ndarray (n,)
        Speeds [rad/s], increasing: the sweep's and an internal grid
        (:func:`groundres.scan.probe_speeds`).
    values : ndarray (n,)
        ``excess`` on the grid [1/s].
    excess : callable
        ``excess(speeds) -> values`` at any speeds (arrays).
    kind : "eigen" or "floquet"
        Accuracy of the refined peaks (:data:`groundres.scan.PEAK_XTOL`).
    peaks : int
        Local maxima of the grid values refined to find ranges narrower than
        the grid (the largest first).
    closeness : callable, optional
        ``closeness(speeds)``: nearest approach of two roots
        (:func:`groundres.modal.closest_pair`). An undamped coalescence range
        has no bump outside it (its roots are neutral until they meet), but
        its roots approach: the deepest local minima of the closeness are
        refined to where the roots meet, and the growth is probed beside it.
    floor : float
        Lowest speed [rad/s] analysed between rest and the grid's first turning
        speed (:func:`_start_above_rest`); 0 for no limit but round-off.

    Returns
    -------
    ranges : list of (float, float)
        Interior ends to 1e-10 relative; ranges open at an end of the grid report that end.
    peak_speeds : list of float
        Speed of the largest excess inside each range.
    open_below : float or None
        The first range's start where it grows at the lowest speed tried above
        rest (``floor``): the range may begin lower.
    """
    grid, values = np.asarray(grid, float), np.asarray(values, float)
    n = len(grid)
    found = []  # (start, end, peak speed, peak value)
    open_at = None
    i = 0
    while i < n:
        if values[i] <= 0:
            i += 1
            continue
        j = i
        while j + 1 < n and values[j + 1] > 0:
            j += 1
        if i == 0:
            start = grid[0]
        elif grid[i - 1] <= 0:  # the range begins somewhere between rest and grid[i]
            start, open_at = _start_above_rest(excess, grid[i], floor)
        else:
            start = _end(excess, grid[i - 1], grid[i])
        end = grid[-1] if j == n - 1 else scan.crossing(excess, grid[j], grid[j + 1])
        k = i + int(np.argmax(values[i : j + 1]))
        found.append([float(start), float(end), float(grid[k]), float(values[k])])
        i = j + 1
    for i in scan.local_maxima(values, peaks):
        if values[i] > 0 or grid[i] <= 0:
            continue
        lo, hi = scan.bracket(grid, i)
        if hi <= lo:
            continue
        top, at = scan.zoom_max(excess, lo, hi, scan.PEAK_XTOL[kind])
        if top <= 0 or any(a <= at <= b for a, b, _, _ in found):
            continue
        # a range narrower than the grid: its ends on either side of the peak
        start = lo if float(excess(np.array([lo]))[0]) > 0 else scan.crossing(excess, lo, at)
        end = hi if float(excess(np.array([hi]))[0]) > 0 else scan.crossing(excess, at, hi)
        found.append([float(start), float(end), at, top])
    if closeness is not None:
        near = np.asarray(closeness(grid), float)
        for i in scan.local_maxima(-near, peaks):
            lo, hi = scan.bracket(grid, i)
            if grid[i] <= 0 or hi <= lo:
                continue
            _, meet = scan.zoom_max(lambda w: -np.asarray(closeness(w)), lo, hi, 1e-12)
            if any(a * (1 - 1e-6) <= meet <= b * (1 + 1e-6) for a, b, _, _ in found):
                continue  # the meeting point of a range already found (one of its ends)
            side = meet * 10.0 ** -np.arange(10.0, 3.0, -1.0)
            probe = np.clip(np.concatenate([meet - side, meet + side]), lo, hi)
            v = np.asarray(excess(probe), float)
            if v.max() <= 0:
                continue
            at = float(probe[int(np.argmax(v))])
            start, end = _end(excess, lo, at), _end(lambda w: excess(-np.asarray(w)), -hi, -at)
            found.append([float(start), -float(end), at, float(v.max())])
    ranges, peaks = _merged(found)
    return ranges, peaks, (open_at if ranges and open_at is not None and ranges[0][0] == open_at else None)


def _merged(found):
    """Ranges (start, end, peak speed, peak value) sorted, overlapping ones joined."""
    out = []
    for a, b, w, v in sorted(found):
        if out and a <= out[-1][1] * (1 + 1e-9):
            last = out[-1]
            last[1] = max(last[1], b)
            if v > last[3]:
                last[2], last[3] = w, v
        else:
            out.append([a, b, w, v])
    return [(a, b) for a, b, _, _ in out], [w for _, _, w, _ in out]


#: Halvings of the first turning speed tried below it, at most (2^-40: round-off).
REST_HALVINGS = 40


def _start_above_rest(excess, first, floor):
    """Where a range that is open at ``first`` (the grid's first speed above
    rest) begins: the speeds first / 2, first / 4, ... down to ``floor`` are
    tried in one call, then the crossing refined between the last stable one
    and the next. A range still growing at the lowest speed tried starts there
    (:attr:`Stability.open_below` says so).

    Returns
    -------
    (start, open_at) : (float, float or None)
        ``open_at`` is ``start`` where the range is still open there.
    """
    floor = max(floor, first * 2.0**-REST_HALVINGS)
    count = max(1, int(np.floor(np.log2(first / floor))))
    w = first * 2.0 ** -np.arange(1, count + 1)
    v = np.asarray(excess(w), float)
    calm = np.flatnonzero(v <= 0)
    if not len(calm):
        return float(w[-1]), float(w[-1])
    j = int(calm[0])
    return scan.crossing(excess, float(w[j]), float(first if j == 0 else w[j - 1])), None


def _end(excess, lo, hi):
    """The rising crossing in [lo, hi], or lo if excess is already positive there."""
    if float(excess(np.array([lo]))[0]) > 0:
        return lo
    return scan.crossing(excess, lo, hi)


def assess(
    speeds,
    max_real,
    min_damping,
    growth,
    max_real_at,
    min_damping_at,
    probe=None,
    kind="eigen",
    closeness=None,
    floor=0.0,
):
    """Unstable ranges and refined worst values for a sweep.

    Parameters
    ----------
    speeds : ndarray (n_s,)
        The sweep [rad/s].
    max_real, min_damping : ndarray (n_s,)
        Largest real part [1/s] and smallest damping ratio [-] at each sweep speed.
    growth : callable
        ``growth(speeds) -> largest real part`` at any speeds (arrays, roots only).
    max_real_at, min_damping_at : callable
        The same quantities at one speed, as accurate as the sweep's (to refine the worst values).
    probe : ndarray, optional
        Internal speeds between the sweep's (:func:`groundres.scan.probe_speeds`).
    kind : "eigen" or "floquet"
    closeness : callable, optional
        Nearest approach of two roots at given speeds (:func:`find_ranges`).
    floor : float
        Lowest speed [rad/s] analysed above rest (:func:`find_ranges`).
    """
    speeds = np.asarray(speeds, float)
    probe = np.zeros(0) if probe is None else np.asarray(probe, float)
    grid = np.concatenate([speeds, probe])
    values = np.concatenate([max_real, growth(probe) if len(probe) else np.zeros(0)])
    order = np.argsort(grid, kind="stable")
    grid, values = grid[order], values[order] - growth_threshold(grid[order])

    def excess(w):
        w = np.asarray(w, float)
        return growth(w) - growth_threshold(w)

    ranges, peak_speeds, open_below = find_ranges(
        grid, values, excess, kind, closeness=closeness, floor=floor
    )
    i = int(np.argmax(values))
    sweep_i = int(np.argmin(np.abs(speeds - grid[i])))
    xtol = 1e-6
    if grid[i] in speeds:
        worst = _refine_max(max_real_at, speeds, max_real, sweep_i, xtol)
    else:  # the worst speed lies between the sweep's: refine there
        lo, hi = scan.bracket(grid, i)
        res = minimize_scalar(
            lambda w: -max_real_at(w), bounds=(lo, hi), method="bounded", options={"xatol": xtol * hi}
        )
        worst = (float(-res.fun), float(res.x))
    at = worst[1]
    if worst[0] > growth_threshold(at) and not any(a <= at <= b for a, b in ranges):
        # the refined worst value grows where no range was found: its range, narrower than the grid
        lo, hi = scan.bracket(grid, i)
        lo, hi = min(lo, at), max(hi, at)
        start = _end(excess, lo, at) if float(excess(np.array([at]))[0]) > 0 else at
        end = hi if float(excess(np.array([hi]))[0]) > 0 or start == at else scan.crossing(excess, at, hi)
        ranges, peak_speeds = zip(*sorted(list(zip(ranges, peak_speeds)) + [((start, end), at)]))
        ranges, peak_speeds = list(ranges), list(peak_speeds)
    j = int(np.nanargmin(min_damping))
    low = _refine_max(lambda w: -min_damping_at(w), speeds, -min_damping, j, xtol)
    return Stability(
        unstable_ranges=ranges,
        max_real_part=worst,
        min_damping_ratio=(-low[0], low[1]),
        peak_speeds=tuple(peak_speeds),
        open_below=open_below if ranges and open_below == ranges[0][0] else None,
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
    h2 = h * h
    # rotor inertia about the pivot, averaged over azimuth (all blades alike)
    e = b.hinge_offset
    j_rotor = n * (
        b.blade_mass * h2 + (b.blade_inertia + 2 * b.blade_static_moment * e + b.blade_mass * e * e) / 2
    )
    j = body.value("inertia", dof) + j_rotor
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


def minimum_lag_damping(excess, grid, start, cap, rtol=1e-4, anchor=None, seeds=(), kind="eigen"):
    """Smallest lag damping that makes the sweep stable, by bisection.

    Parameters
    ----------
    excess : callable
        ``excess(lag_damping, speeds) -> array``: largest real part minus the
        growth threshold [1/s] at those speeds with that lag damping.
    grid : ndarray
        Speeds [rad/s] scanned for the worst one: the sweep's and an internal
        grid dense near the tuning speeds (:func:`groundres.scan.probe_speeds`),
        so that the answer does not depend on the sweep's spacing.
    start : float
        A first guess [N m s/rad] (> 0).
    cap : float
        Largest lag damping tried [N m s/rad].
    rtol : float
        Relative accuracy of the result.
    anchor : (float, bool), optional
        The installed lag damping and whether the sweep found it unstable: the
        search brackets from it, so that installed >= result exactly when the
        sweep is stable.
    seeds : iterable of float
        Speeds where the sweep grows (the peaks of its ranges), watched first.
    kind : "eigen" or "floquet"
        A Floquet scan is costly: the bisection trusts the watched peaks within
        a factor 2 of the damping they were scanned at, and a full scan
        confirms the result; if it finds another peak, the bisection goes on
        between there and the smallest damping shown stable (the last of four
        rounds confirming every verdict).

    Returns
    -------
    float or None
        0.0 if stable without lag damping; None if even ``cap`` is unstable.
    """
    watch = scan.PeakWatch(excess, grid, kind, seeds)
    eager = kind == "eigen"
    proven = [None]  # the smallest damping a full scan (or the sweep) has shown stable

    def stable(c, confirm):
        if watch.watched(c) > 0:
            return False
        # the watched peaks are trusted within a factor 2 of the damping their scan was made at
        if not confirm and watch.scanned is not None and 0.5 * watch.scanned <= c <= 2 * watch.scanned:
            return True
        if watch.full(c) > 0:
            return False
        proven[0] = c if proven[0] is None else min(proven[0], c)
        return True

    # bracket [lo, hi]: lo unstable (or zero), hi stable (None: not known yet)
    if anchor is not None and anchor[1]:
        lo, hi = anchor[0], None
    else:
        if stable(0.0, confirm=True):
            return 0.0
        lo, hi = 0.0, None
        if anchor is not None and anchor[0] > 0:  # the sweep found the installed damper stable
            hi = proven[0] = anchor[0]
            if start < hi:  # the first guess splits a wide bracket
                if stable(start, eager):
                    hi = start
                else:
                    lo = start
    for round_ in range(4):
        confirm = eager or round_ == 3  # the last round confirms every verdict
        if hi is None:  # up from lo, doubling
            hi = max(2 * lo, start)
            while not stable(hi, confirm):
                lo, hi = hi, 2 * hi
                if hi > cap:
                    return None
        for _ in range(400):  # (bounded: halving from a guess, then bisection to rtol)
            if hi - lo <= rtol * hi or (lo == 0 and hi < 1e-12 * start):
                break
            mid = math.sqrt(lo * hi) if 0 < 4 * lo < hi else 0.5 * (lo + hi)
            if stable(mid, confirm):
                hi = mid
            else:
                lo = mid
        if confirm or hi == proven[0] or stable(hi, confirm=True):
            return hi
        # the confirming scan found a peak the bisection had not watched: on
        # between there and the smallest damping shown stable
        lo, hi = hi, proven[0]
    return hi
