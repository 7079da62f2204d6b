"""The exact minimum lag damping: the smallest damper for which no root grows in the sweep.

The search scans the sweep and an internal grid (:mod:`groundres.assess.scan`),
dense near the tuning speeds and spread from half the lowest body frequency
to the stop (a periodic search only near the tuning speeds and the unstable
ranges, :func:`search_windows`), and bisects on the lag damping set on every
working damper (:func:`minimum_lag_damping`). A periodic search solves every
trial damping on one system without the working dampers, the damping a
per-speed coefficient (:meth:`groundres.model.system.System.lag_damping_split`).
It starts from the installed damper and the sweep's verdict there, so that
the two agree. A Floquet search is costly: its work is estimated with the
sweep's before anything runs (:func:`groundres.solve.floquet.cost.check_work`,
over :func:`periodic_search_grid`).
"""

from __future__ import annotations

import math

import numpy as np

from ..solve.floquet import cost
from . import resolution, scan, stability

#: Relative accuracy of the exact minimum lag damping, by method option
#: (:attr:`groundres.methods.Method.option`).
RTOL = {"eigen": 1e-4, "floquet": 1e-3}


def lowest_search_speed(deutsch):
    """Half the lowest body frequency [rad/s]: below it the regressive lag mode,
    at Omega (1 - nu) < Omega, meets no body mode, and lag damping decides nothing."""
    body = [e.body_frequency for e in deutsch if e.body_frequency]
    return 0.5 * min(body) if body else 0.0


#: Speeds spread geometrically from the search's lowest speed to the sweep's stop,
#: beside the internal grid: strong lag damping moves the worst speed from the
#: tuning speed down towards the body frequency, which may lie below the dense
#: cluster (nu > 1/3) and between the uniform points of a wide sweep.
SEARCH_FILL = {False: 200, True: 12}


#: Geometric speeds added in each window of a periodic search (:func:`search_windows`).
WINDOW_FILL = 6


def search_windows(deutsch, ranges=()) -> list[tuple[float, float]]:
    """Where a periodic search looks [rad/s]: near each tuning speed Omega_t, from the
    body frequency (or Omega_t / CLUSTER_WIDTH if lower) to CLUSTER_WIDTH Omega_t,
    and over the sweep's unstable ranges. Ground resonance lives there: strong lag
    damping moves the worst speed from the tuning speed down towards the body
    frequency, and weaker damping widens the ranges about their peaks."""
    out = [
        (
            min(e.tuning_speed / scan.CLUSTER_WIDTH, 0.9 * e.body_frequency),
            e.tuning_speed * scan.CLUSTER_WIDTH,
        )
        for e in deutsch
        if e.tuning_speed is not None and e.body_frequency
    ]
    return out + [(float(a), float(b)) for a, b in ranges]


def periodic_search_grid(speeds, probe, deutsch):
    """The speeds a periodic search scans before the sweep is known (:func:`search_grid` over the
    windows near the tuning speeds): what its work is estimated over."""
    return search_grid(speeds, probe, True, lowest_search_speed(deutsch), search_windows(deutsch))


def search_grid(speeds, probe, periodic, low=0.0, windows=()):
    """Speeds the damping search scans, from ``low`` up.

    Eigen-analysis: the internal grid and the sweep's, with :data:`SEARCH_FILL`
    speeds spread geometrically from ``low`` (or the first turning speed) to
    the stop. Periodic (every speed is an integration): only the speeds that
    matter, those of the sweep (at most 60) and of the internal grid inside the
    ``windows`` (:func:`search_windows`) with :data:`WINDOW_FILL` more in each;
    without windows inside the sweep, the eigen-analysis' choice with
    :data:`SEARCH_FILL` [True] speeds.
    """
    if periodic and len(speeds) > 60:
        speeds = speeds[np.unique(np.linspace(0, len(speeds) - 1, 60).round().astype(int))]
    grid = np.union1d(speeds, probe)
    moving = grid[grid > 0]
    inside = []
    if periodic and len(moving):
        top, floor = moving.max(), max(low, 0.5 * moving.min())
        for a, b in windows:
            a, b = max(a, floor), min(b, top)
            if a < b:
                inside.append(grid[(grid >= a) & (grid <= b)])
                inside.append(np.geomspace(a, b, WINDOW_FILL))
    if inside:
        grid = np.unique(np.concatenate(inside))
    elif len(moving):
        # (a periodic fill stays above half the first turning speed, as its grid does)
        bottom = max(low, 0.5 * moving.min()) if periodic else (low if low > 0 else moving.min())
        if bottom < moving.max():
            grid = np.union1d(grid, np.geomspace(bottom, moving.max(), SEARCH_FILL[periodic]))
    # the rotor at rest is no speed for the search: its roots do not depend on lag damping
    inside = grid[(grid > 0) & (grid >= low)]
    return inside if len(inside) else grid[-1:]


def exact_minimum(solver, case, speeds, probe, deutsch, assessed):
    """Smallest lag damping (on every working damper the search sizes:
    :attr:`groundres.model.system.System.searched`) for a stable sweep.

    The search scans the sweep and an internal grid dense near the tuning
    speeds from half the lowest body frequency up, refines the worst speeds
    (:func:`minimum_lag_damping`), and starts from the
    installed damper and the sweep's verdict there, so that the two agree:
    installed >= the result exactly when the sweep is stable. A sweep
    unstable wholly below that speed has no answer (None): lag damping does
    not decide its stability there.

    Returns
    -------
    value : float or None
        In SI: [N m s/rad] for blade lag dampers, [N s/m] for damper rods.
    why_none : tuple or None
        Where ``value`` is None: ("below", speed [rad/s]) for a sweep unstable
        below the search's lowest speed, ("cap", damping in the same unit)
        where no damping up to the largest tried makes it stable, ("afforded", damping)
        where that largest is the strongest a Floquet scan of the search's speeds can follow
        within the work limit (:func:`groundres.solve.floquet.cost.affordable_damping`).
    """
    periodic = solver.method.periodic
    low = lowest_search_speed(deutsch)
    if any(b < low for _, b in assessed.unstable_ranges):
        return None, ("below", low)
    # (computed in the equations' mass unit, groundres.model.units.MassUnit: SI values near
    # the largest float would overflow in the products below)
    unit = solver.system.mass_unit
    system = solver.system
    blades = case.rotor.blades
    installed = max(system.damper_values()) if any(system.damper_values()) else 0.0
    # (a rod's N s/m act on the blades through its lever: scales in the searched damper's units)
    lever = max(system.damper_lever(), 1e-300)
    inertia = unit.from_si(max(b.blade_inertia for b in blades)) / lever
    # the largest lag damping the model resolves (resolution.check_resolution), and a
    # cap beyond which more damping is no design answer (periodic analyses stop
    # earlier: a strong damper makes the equations stiff for the explicit integrator)
    tau = float(stability.growth_threshold(np.array([speeds.min(), speeds.max()])).min())
    resolved = 0.5 * inertia * tau / (resolution.ROUND_OFF * resolution.EPS)
    top = speeds.max()
    finite = [
        _in_searched(e, system, unit)
        for e in deutsch
        if e.required_lag_damping not in (None, np.inf)
        and e.tuning_speed is not None
        and speeds.min() <= e.tuning_speed <= top
    ]
    finite = [f for f in finite if f > 0]
    # (and four times the Deutsch requirement of a resonance the sweep reaches,
    # whatever the installed damper)
    cap = (20 if periodic else 100) * max(installed, 2 * inertia * top * (0.05 if periodic else 1.0))
    cap = min(max([cap] + [4 * f for f in finite]), resolved)
    guess = min(max(finite) if finite else max(installed, inertia * top * 1e-3), 0.5 * cap)
    guess = max(guess, 1e-12 * cap)
    # the installed dampers belong to the family searched when the working ones are equal
    working = {v for v in system.damper_values() if v > 0}
    anchor = (installed, not assessed.stable) if len(working) <= 1 and installed <= cap else None

    trials = {}

    def trial(lag_damping):
        if lag_damping not in trials:  # (one solver per damping tried, for its repeated scans)
            trials.clear()
            trials[lag_damping] = solver.with_lag_damping(lag_damping, in_unit=True)
        return trials[lag_damping]

    def excess(lag_damping, w):
        w = np.atleast_1d(np.asarray(w, dtype=float))
        # (neutral roots never grow: left out, they cannot hide the peak that decides)
        return stability.growth_of(trial(lag_damping))(w, neutral=False) - stability.growth_threshold(w)

    def rough(lag_damping, w):  # (scans look with it; excess decides)
        w = np.atleast_1d(np.asarray(w, dtype=float))
        threshold = stability.growth_threshold(w)
        return tuple(v - threshold for v in stability.rough_growth_of(trial(lag_damping))(w, neutral=False))

    grid = search_grid(speeds, probe, periodic, low, search_windows(deutsch, assessed.unstable_ranges))
    reason = "cap"
    if periodic:  # (no stronger damper than a Floquet scan can follow within the work limit)
        afford = cost.affordable_damping(system.with_lag_damping, grid, cap)
        if afford < cap:
            cap, reason = afford, "afforded"
            guess = min(guess, 0.5 * cap)
    value = minimum_lag_damping(
        excess,
        grid,
        guess,
        cap=cap,
        rtol=RTOL[solver.method.option],
        anchor=anchor,
        seeds=assessed.peak_speeds,
        periodic=periodic,
        rough=None if solver.rough_real_parts is None else rough,
    )
    return (None, (reason, unit.to_si(cap))) if value is None else (unit.to_si(value), None)


def _in_searched(entry, system, unit) -> float:
    """A Deutsch requirement [N m s/rad, SI] as a value of the searched damper in the
    equations' mass unit: itself for blade dampers; for rods, what the rods must add to
    the blades' own dampers, per unit of the entry's rod lever."""
    required = unit.from_si(entry.required_lag_damping)
    if system.searched == "blades":
        return required
    own = min((b.lag_damping for b in system.rotor.blades if b.lag_damping > 0), default=0.0)
    lever = entry.rod_lever or 1.0
    return (required - own) / lever


def minimum_lag_damping(
    excess, grid, start, cap, rtol=1e-4, anchor=None, seeds=(), periodic=False, rough=None
):
    """Smallest lag damping that makes the sweep stable, by bisection.

    Parameters
    ----------
    excess : callable
        ``excess(lag_damping, speeds) -> array``: largest real part minus the
        growth threshold [1/s] at those speeds with that lag damping.
    grid : ndarray
        Speeds [rad/s] scanned for the worst one: the sweep's and an internal
        grid dense near the tuning speeds (:func:`groundres.assess.scan.probe_speeds`),
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
    periodic : bool
        A periodic (Floquet) scan is costly: the bisection trusts the watched peaks within
        a factor 2 of the damping they were scanned at, and a full scan
        confirms the result; if it finds another peak, the bisection goes on
        between there and the smallest damping shown stable (the last of four
        rounds confirming every verdict).
    rough : callable, optional
        ``rough(lag_damping, speeds) -> (values, lower, upper)``: ``excess``
        at a looser accuracy and bounds of it, for the scans to look with
        (:class:`groundres.assess.scan.PeakWatch`); every verdict is ``excess``'s.

    Returns
    -------
    float or None
        0.0 if stable without lag damping; None if even ``cap`` is unstable.
    """
    watch = scan.PeakWatch(excess, grid, periodic, seeds, rough=rough)
    eager = not periodic
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
