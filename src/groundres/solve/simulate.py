"""Time simulation of the periodic blade-coordinate equations at one rotor speed.

The equations M(t) q'' + C(t) q' + K(t) q = 0 are integrated with SciPy's
DOP853 from given initial conditions. Their coefficients are trigonometric
polynomials of degree two in Omega t, so the full-system harmonic matrices are
formed once and the right-hand side only adds five matrices and solves with M.
This is independent of the Floquet integrator; its measured growth rate is the
check of the largest Floquet exponent that engineers believe.

How long to run (:func:`run_duration`): 40 revolutions, or longer (up to
400) until the least stable root outgrows the next by e^8, and never more
integration steps than :data:`MAX_STEPS` (estimated before integrating,
:func:`estimate_steps`). :func:`groundres.analysis.simulate` runs it for a
case and returns a :class:`groundres.results.simulation.Simulation`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import ModelRangeError, ParameterError
from ..model.body import TRANSLATIONS
from ..model.system import System


@dataclass
class TimeHistory:
    """The motion :func:`integrate` found.

    Attributes
    ----------
    time : ndarray (n_t,)
        [s].
    displacement, velocity : ndarray (n_t, n)
        Coordinates (``coordinates``) and their rates, SI (m, rad; m/s, rad/s).
    coordinates : list of Coordinate
    rotor_speed : float
        [rad/s].
    rtol, atol : float, optional
        Relative and absolute tolerances the integration was run with.
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    coordinates: list
    rotor_speed: float
    rtol: float | None = None
    atol: float | None = None

    def growth_rate(self, start_fraction: float = 0.5) -> float:
        """Measured growth rate [1/s] of the motion.

        The state norm (each coordinate and rate scaled by its largest value; of
        an inflow state, its rate only; where some are largest in the fitted
        part, those only: a coordinate that decays all along, excited at the
        start, carries none of the growing motion and would hide its rate)
        is sampled once per revolution, at the same azimuth, so the periodic
        modulation drops out; the slope of its logarithm over the last part of
        the run (from ``start_fraction`` of the time on) is the growth rate.
        """
        period = 2 * np.pi / self.rotor_speed
        moving = [i for i, c in enumerate(self.coordinates) if c.kind != "inflow"]
        # (an inflow state's displacement is no state: it keeps what its velocity carried)
        state = np.hstack([self.displacement[:, moving], self.velocity])
        late = self.time >= self.time[0] + start_fraction * (self.time[-1] - self.time[0])
        growing = np.argmax(np.abs(state), axis=0) >= np.argmax(late)
        if growing.any():  # (a column that only decays, scaled by its start, would hide the growth)
            state = state[:, growing]
        scale = np.maximum(np.abs(state).max(0), 1e-300)
        norm = np.linalg.norm(state / scale, axis=1)
        revs = np.arange(np.ceil(self.time[0] / period), np.floor(self.time[-1] / period) + 1) * period
        at_rev = np.exp(np.interp(revs, self.time, np.log(norm)))
        keep = revs >= self.time[0] + start_fraction * (self.time[-1] - self.time[0])
        if keep.sum() < 3:
            raise ValueError("the run is too short: simulate for more revolutions")
        slope, _ = np.polyfit(revs[keep], np.log(at_rev[keep]), 1)
        return float(slope)


def harmonic_matrices(system: System, speed: float) -> np.ndarray:
    """Full-system matrices as harmonics of Omega t: shape (3, 5, n, n).

    X(t) = X0 + X1c cos(Omega t) + X1s sin(Omega t) + X2c cos(2 Omega t) + X2s sin(2 Omega t),
    found exactly from five azimuths.
    """
    theta = 2 * np.pi * np.arange(5) / 5
    basis = np.stack([np.ones(5), np.cos(theta), np.sin(theta), np.cos(2 * theta), np.sin(2 * theta)], 1)
    values = system.matrices(np.array([speed]), theta[:, None])[:, :, 0]  # (3, 5, n, n)
    return np.einsum("hj,gjab->ghab", np.linalg.inv(basis), values)


def at_azimuth(mats, azimuth: float):
    """Mass, damping and stiffness (3, n, n) at blade 1's ``azimuth`` [rad] from their harmonics
    (:func:`harmonic_matrices`)."""
    a = azimuth
    w = np.array([1.0, np.cos(a), np.sin(a), np.cos(2 * a), np.sin(2 * a)])
    return np.tensordot(w, mats, axes=(0, 1))


def integrate(
    system: System,
    speed: float,
    duration: float,
    initial,
    rtol: float = 1e-10,
    points: int = 4000,
    progress=None,
    max_steps: float | None = None,
    speed_text: str | None = None,
    growth: float = 0.0,
):
    """Integrate the equations from ``initial`` = (q0, qdot0) over ``duration`` [s].

    Parameters
    ----------
    system : System
    speed : float
        Rotor speed [rad/s].
    duration : float
        [s].
    initial : tuple of ndarray
        Displacements and rates at t = 0 (blade 1 at azimuth 0).
    rtol : float
        Relative tolerance of DOP853.
    points : int
        Output instants (equally spaced; dense output in between steps).
    progress : callable, optional
        ``progress(done, total)`` in simulated seconds, called about every
        percent of ``duration``.
    max_steps : float, optional
        Steps after which the integration stops with
        :class:`~groundres.errors.ModelRangeError` (round-off can keep an
        adaptive step from growing); by default four times the estimate
        (:func:`estimate_steps`), at least 2000 and at most 4 :data:`MAX_STEPS`.
    growth : float
        A rate g [1/s] (the expected growth, >= 0) by which the state is scaled
        while it is integrated: z = x exp(-g t), z' = A(t) z - g z, so that a
        growing motion stays of one size and the tolerances keep their meaning
        (a part that cancels to round-off, such as a collective response to
        cyclic motion, would otherwise hold the step to round-off of a state
        grown by decades). The motion returned is x; g changes only its scaling.

    Raises
    ------
    ModelRangeError
        If the integration takes more than ``max_steps`` steps (its message
        names the speed as ``speed_text`` if given, else in rad/s).
    """
    n = system.size
    mats = harmonic_matrices(system, speed)
    expected = estimate_steps(system, speed, duration)
    if max_steps is None:
        max_steps = min(max(4 * expected, 2000.0), 4 * MAX_STEPS)
    calls = [0, max_steps * _CALLS_PER_STEP]

    step = duration / 100
    reached = [step]

    def rhs(t, x):
        calls[0] += 1
        if calls[0] > calls[1]:
            raise ModelRangeError(
                f"the time integration at {speed_text or f'{speed:.4g} rad/s'} took more than "
                f"{max_steps:.3g} steps "
                f"(estimated {expected:.3g}) and was stopped at t = {t:.4g} s of {duration:.4g} s: "
                "round-off keeps the adaptive step small at this speed; choose a lower speed or a "
                "shorter time"
            )
        if progress is not None and t >= reached[0]:
            reached[0] = t + step
            progress(min(t, duration), duration)
        m, c, k = at_azimuth(mats, speed * t)
        q, v = x[:n], x[n:]
        return np.concatenate([v, np.linalg.solve(m, -(c @ v + k @ q))]) - growth * x

    q0, v0 = (np.asarray(a, dtype=float) for a in initial)
    times = np.linspace(0.0, duration, points)
    atol = rtol * 1e-3 * max(np.abs(np.concatenate([q0, v0])).max(), 1e-12)
    sol = solve_ivp(
        rhs,
        (0.0, duration),
        np.concatenate([q0, v0]),
        method="DOP853",
        t_eval=times,
        rtol=rtol,
        atol=atol,
    )
    if not sol.success:
        raise RuntimeError(f"time integration failed: {sol.message}")
    y = sol.y * np.exp(growth * sol.t)
    return TimeHistory(sol.t, y[:n].T, y[n:].T, system.coordinates, float(speed), rtol, float(atol))


#: The default initial disturbance [m, rad]: every body coordinate and blade 1's lag.
DISTURBANCE = 0.01


def default_initial(system: System) -> dict:
    """The default initial state: :data:`DISTURBANCE` on every body coordinate and on lag1."""
    return {d: DISTURBANCE for d in system.body.dofs} | {"lag1": DISTURBANCE}


def initial_text(values: dict) -> str:
    """An initial state as a reader takes it: "x = 0.01 m, lag1 = 0.01 rad, roll_rate = 0.1 rad/s"."""

    def unit(key):
        base, rate = (key[:-5], "/s") if key.endswith("_rate") else (key, "")
        return ("m" if base in TRANSLATIONS or base.startswith("inflow_") else "rad") + rate

    return ", ".join(f"{k} = {v:g} {unit(k)}" for k, v in values.items())


#: Largest motion [m, rad; m/s, rad/s] a simulation may hold, from its initial values to
#: their growth over the run: with coefficients up to :data:`LARGEST_COEFFICIENT`, their
#: products stay inside double precision. The equations are linear, so the size of the
#: disturbance scales the whole motion and leaves its growth rate unchanged; the model holds
#: for small motions about rest (centimetres, a few degrees), far below this bound.
LARGEST_MOTION = 1e150


def initial_state(system: System, values: dict) -> tuple[np.ndarray, np.ndarray]:
    """Initial displacements and rates from names like "x", "lag1", "flap3", "roll_rate".

    Raises
    ------
    ParameterError
        For a name that is not a coordinate of the system (the message lists the
        names), a value that is not a finite number within +-:data:`LARGEST_MOTION`,
        or values that are all zero.
    """
    names = [c.short for c in system.coordinates]
    q0, v0 = np.zeros(system.size), np.zeros(system.size)
    for key, value in values.items():
        base, rate = (key[:-5], True) if key.endswith("_rate") else (key, False)
        named = f"initial.{key}"  # (each error names its coordinate: [simulation.initial] x, --initial x=)
        if base not in names:
            raise ParameterError(
                named, value, f"not a coordinate; use one of {', '.join(names)} (or NAME_rate)"
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
            raise ParameterError(named, value, "each value must be a finite number [m, rad]")
        if abs(value) > LARGEST_MOTION:
            raise ParameterError(
                named,
                value,
                f"|value| <= {LARGEST_MOTION:.0e} [m, rad; m/s, rad/s for a rate]: the equations are "
                "linear, so the disturbance's size scales the whole motion and leaves its growth rate "
                "unchanged (the model holds for small motions, centimetres and a few degrees); beyond "
                "the bound the motion times the equations' coefficients leaves double precision",
            )
        if not rate and names.index(base) in system.integrals:
            raise ParameterError(
                named,
                value,
                "an inflow state's position is no state (nothing moves by it); give its rate, the "
                f"inflow velocity [m/s]: {key}_rate",
            )
        (v0 if rate else q0)[names.index(base)] = value
    if not (q0.any() or v0.any()):
        raise ParameterError("initial", dict(values), "every value is zero, so nothing would move")
    return q0, v0


#: Steps per period of the fastest motion that DOP853 takes at the default
#: tolerance: 14 to 26 measured on the shipped cases; the larger, rounded, is
#: used to estimate.
STEPS_PER_PERIOD = 25
#: Most integration steps a simulation may be estimated to need (a few
#: minutes at a few milliseconds a step; docs/case-files.md, "Limits").
MAX_STEPS = 100_000
#: Fewest revolutions a run needs for its growth rate: sampled once a
#: revolution over the second half, it needs at least three samples there.
MIN_REVOLUTIONS = 6
#: Right-hand-side evaluations per DOP853 step (12 stages, and a few for the first step's size).
_CALLS_PER_STEP = 13
#: Largest coefficient of M, C, K the integration takes: its error estimates
#: square such values, which must stay inside the floating-point range.
LARGEST_COEFFICIENT = 1e150


def fastest_rate(system: System, speed: float, probes: int = 8) -> float:
    """Fastest rate [rad/s] the integration follows at rotor speed ``speed`` [rad/s].

    The largest magnitude of the roots of the equations frozen at a few
    azimuths, or twice the rotor speed (the harmonic of the coefficients),
    whichever is larger; ``inf`` where a coefficient exceeds ``LARGEST_COEFFICIENT``.
    """
    with np.errstate(all="ignore"):
        mats = harmonic_matrices(system, speed)
        if not np.abs(mats).max() <= LARGEST_COEFFICIENT:  # (also catches nan)
            return float("inf")
        n, fastest = system.size, 2.0 * speed
        for a in 2 * np.pi * np.arange(probes) / probes:
            m, c, k = at_azimuth(mats, a)
            state = np.block(
                [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]]
            )
            if not np.isfinite(state).all():
                return float("inf")
            fastest = max(fastest, float(np.abs(np.linalg.eigvals(state)).max()))
    return fastest


def estimate_steps(system: System, speed: float, duration: float) -> float:
    """Integration steps :func:`integrate` is expected to take over ``duration`` [s]
    (``inf`` if unbounded)."""
    with np.errstate(all="ignore"):
        return float(duration * fastest_rate(system, speed) / (2 * np.pi) * STEPS_PER_PERIOD)


def fit_growth(
    duration: float, growth: float, values: dict, given: bool, speed: float, speed_name=None
) -> float:
    """``duration`` [s], or a default one shortened, over which the motion from ``values`` (the
    initial state) growing at ``growth`` [1/s] (the largest real part) stays within
    :data:`LARGEST_MOTION`.

    Raises
    ------
    ParameterError
        Naming ``duration`` (given, and too long for that growth: the message gives the longest
        that fits) or ``initial`` (too large even for the shortest run that measures growth).
    """
    size = max(abs(v) for v in values.values())
    if not growth > 0 or not size > 0:
        return duration
    longest = math.log(LARGEST_MOTION / size) / growth
    if duration <= longest:
        return duration
    at_speed = f"at {speed_name or f'{speed:.4g} rad/s'}"
    shortest = MIN_REVOLUTIONS * 2 * np.pi / speed
    grows = f"the motion grows at {growth:.4g} 1/s {at_speed} (the largest real part)"
    if longest >= shortest:
        if not given:  # (the default run, shortened to fit)
            return float(longest)
        raise ParameterError(
            "duration",
            duration,
            f"{grows}, by e^{growth * duration:.4g} over this run: from the largest initial value "
            f"({size:g}) it would pass {LARGEST_MOTION:.0e}, beyond what the integration holds; at most "
            f"{longest:.4g} s fits (or a smaller initial disturbance)",
        )
    largest = LARGEST_MOTION * math.exp(-growth * shortest)
    name = max(values, key=lambda k: abs(values[k]))
    raise ParameterError(
        "initial",
        {name: values[name]},
        f"{grows}, by e^{growth * shortest:.4g} over the shortest run that measures growth "
        f"({MIN_REVOLUTIONS} revolutions, {shortest:.4g} s): the initial values must be at most "
        f"{largest:.2g} for the motion to stay within {LARGEST_MOTION:.0e}",
    )


#: A default run lasts at least this many revolutions, at most MOST_REVOLUTIONS.
LEAST_REVOLUTIONS, MOST_REVOLUTIONS = 40, 400
#: e-folds by which the least stable root outgrows the next over the second half of a default run.
SETTLE = 8.0


def settling_time(roots) -> float:
    """Time [s] over which the least stable of ``roots`` outgrows the next distinct one by
    e^SETTLE (the growth rate is measured over the run's second half: twice that); inf if they tie."""
    real = np.sort(np.asarray(roots).real.ravel())[::-1]
    scale = max(np.abs(real).max(), 1e-300)
    below = real[real < real[0] - 1e-9 * scale]
    return 2 * SETTLE / (real[0] - below[0]) if len(below) else float("inf")


def run_duration(system: System, speed: float, duration: float | None, settle=0.0, speed_name=None) -> float:
    """How long to integrate [s]: ``duration``, or by default LEAST_REVOLUTIONS, longer (up to
    MOST_REVOLUTIONS) where the least stable root takes ``settle`` [s] to stand out
    (:func:`settling_time`), once it is long enough to measure growth and short enough to run.

    The integration steps are estimated before integrating (:func:`estimate_steps`); a
    run over :data:`MAX_STEPS` is refused, saying what to change; a longer default than
    LEAST_REVOLUTIONS is shortened to fit. ``speed_name`` names the speed in messages
    (its case's unit; rad/s by default).

    Raises
    ------
    ParameterError
        Naming ``duration``: one that is not a finite number > 0, shorter than
        :data:`MIN_REVOLUTIONS`, or (given or the default) too long to integrate;
        naming ``speed``: one too slow or too fast to simulate, or at which no run
        that measures growth fits.
    """
    at_speed = f"at {speed_name or f'{speed:.4g} rad/s'}"
    given = duration is not None
    if given and not (isinstance(duration, (int, float)) and np.isfinite(duration) and duration > 0):
        raise ParameterError("duration", duration, "must be a finite number > 0 [s]")
    revolution = 2 * np.pi / speed
    if not np.isfinite(LEAST_REVOLUTIONS * revolution):
        raise ParameterError(
            "speed", speed, f"too slow to simulate (a revolution would last {revolution:.3g} s)"
        )
    shortest = MIN_REVOLUTIONS * revolution
    if given and duration < shortest:
        raise ParameterError(
            "duration",
            duration,
            f"must be at least {MIN_REVOLUTIONS} revolutions ({shortest:.4g} s {at_speed}), over whose "
            "second half the growth rate is measured",
        )
    if not given:
        duration = min(max(LEAST_REVOLUTIONS * revolution, settle), MOST_REVOLUTIONS * revolution)
    rate = fastest_rate(system, speed)
    if not np.isfinite(rate):
        raise ParameterError(
            "speed",
            speed,
            f"too fast to simulate: the equations' coefficients, which grow as the speed squared, exceed "
            f"{LARGEST_COEFFICIENT:.0e} (the integration squares them)",
        )
    per_second = rate / (2 * np.pi) * STEPS_PER_PERIOD
    steps = estimate_steps(system, speed, duration)
    if not given and steps > MAX_STEPS and duration > LEAST_REVOLUTIONS * revolution:
        # (a longer default than LEAST_REVOLUTIONS only as far as the step limit allows)
        duration = max(LEAST_REVOLUTIONS * revolution, duration * MAX_STEPS / steps)
        steps = estimate_steps(system, speed, duration)
    if steps <= MAX_STEPS:
        return float(duration)
    cost = (
        f"would take about {steps:.2g} integration steps (fastest motion {rate:.4g} rad/s, about "
        f"{STEPS_PER_PERIOD} steps a period), over the limit of {MAX_STEPS}"
    )
    longest = MAX_STEPS / per_second
    run = (
        f"a run of {duration:.4g} s"
        if given
        else (f"the default run of {duration / revolution:.0f} revolutions ({duration:.4g} s)")
    )
    if longest < shortest:
        raise ParameterError(
            "speed",
            speed,
            f"{run} {cost}; even the shortest run that measures a growth rate "
            f"({MIN_REVOLUTIONS} revolutions, {shortest:.4g} s) is too long {at_speed}: "
            "choose a higher speed",
        )
    # (a shorter run fits: the duration, given or the default, is what to change)
    raise ParameterError("duration", duration, f"{run} {at_speed} {cost}; at most {longest:.4g} s fits")
