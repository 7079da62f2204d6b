"""Time simulation of the periodic blade-coordinate equations with nonlinear lag damper laws.

The structure is the linear system of the case with every law's blade left
without its damper (its own root spring kept): M(t) q'' + C(t) q' + K(t) q.
Each law then adds its moment (:meth:`groundres.model.damper_laws.DamperLaw.moment`)
on its blade's lag, against it:

    M(t) q'' + C(t) q' + K(t) q = -sum_k e_k M_k(zeta_k, zeta_k', s_k),

with e_k the unit vector of blade k's lag and s_k the friction link's slider,
a state of its own (s_k' from :meth:`~groundres.model.damper_laws.DamperLaw.slider_rate`).
The equations' harmonics are formed once, as for the linear simulation
(:func:`groundres.solve.simulate.harmonic_matrices`).

Stiff-aware: a friction law's regularisation (a slope F / v_eps at rest) and a
friction link's slider (a time constant c_reg / k_l) can be far faster than
any motion of the rotor. Where the law's fastest rate exceeds
:data:`STIFF_RATIO` times the structure's (:func:`law_rate`), the integration
is implicit (SciPy's Radau, fifth order); otherwise DOP853.

The settled motion is measured as the prediction measures it
(:func:`components`): each blade's lag over a window, its two largest
frequency components in the rotating frame (FFT peaks, refined and fitted by
least squares), the larger one's amplitude being the amplitude the law sees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

from ..model.system import System
from .simulate import at_azimuth, fastest_rate, harmonic_matrices

#: The law's rate over the structure's beyond which the integration is implicit.
STIFF_RATIO = 10.0
#: Default relative tolerances, explicit and implicit (:func:`integrate`).
RTOL, STIFF_RTOL = 1e-9, 1e-7


@dataclass
class NonlinearHistory:
    """The motion :func:`integrate` found: time [s], displacements and rates (n_t, n) SI, the
    sliders (n_t, N) [rad] (zero where a blade has none), the right-hand-side evaluations and the
    method."""

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    slider: np.ndarray
    coordinates: list
    rotor_speed: float
    evaluations: int
    method: str
    #: Where a blade's lag passed :data:`LIMIT` and the run stopped [s] (None: it ran its course).
    stopped: float | None = None
    #: The integration's absolute tolerance [m, rad]: motion below about a thousand times it is
    #: the integration's error, not a result.
    atol: float = 0.0

    def lag(self, blade: int) -> np.ndarray:
        """Blade ``blade``'s (1-based) lag angle over time [rad]."""
        names = [c.short for c in self.coordinates]
        return self.displacement[:, names.index(f"lag{blade}")]


def structure(case) -> System:
    """The case's equations with every law's blade without its damper (its root spring kept),
    in their mass unit; in air about the hover trim of the laws at small motion."""
    rotor = case.rotor
    n = rotor.n_blades
    bare = rotor.equivalent([0.0] * n, [0.0] * n) if rotor.lag_laws else rotor
    # (in air, about the small-motion system's hover trim, as the linear analysis and the limit
    # cycles: the laws move the blades about it)
    return System.in_mass_unit(bare, case.body).holding_trim_of(System.in_mass_unit(rotor, case.body))


def law_rate(case, speed: float) -> float:
    """The fastest rate a law imposes on its blade [1/s]: a friction regularisation's slope over
    the blade's inertia about the hinge seen as a damper, c / I; a slider's k_l / c_reg."""
    rates = [0.0]
    for blade, entry in zip(case.rotor.blades, case.rotor.lag_laws):
        if entry is None:
            continue
        law = entry.law
        if law.has_slider:
            rates.append(law.link_stiffness / law.regularisation_damping)
        damping, _ = law.small_motion()
        rates.append(damping / blade.blade_inertia)
    return max(rates)


class Equations:
    """The equations with the laws at ``speed`` [rad/s]: x' = rhs(t, x) for the state x = [q, q',
    sliders] (SI lengths and angles; the equations' mass unit), and its Jacobian."""

    def __init__(self, case, speed: float):
        self.system = system = structure(case)
        self.speed, self.n = speed, system.size
        self.mats = harmonic_matrices(system, speed)
        names = [c.short for c in system.coordinates]
        self.laws = [
            (names.index(f"lag{k + 1}"), e.law, k) for k, e in enumerate(case.rotor.lag_laws) if e is not None
        ]
        self.sliders = [(i, law, k) for i, law, k in self.laws if law.has_slider]
        for _, law, k in self.laws:
            if not law.simulable:
                raise ValueError(
                    f"blade {k + 1}'s lag damper is a table of measured properties, which gives no "
                    "moment in time (use a friction link)"
                )
        self.scale = system.mass_unit.from_si(1.0)  # (a moment [N m] in the equations' mass unit)

    def _at(self, t):
        return at_azimuth(self.mats, self.speed * t)

    def rhs(self, t, x):
        n = self.n
        m, c, k = self._at(t)
        q, v, s = x[:n], x[n : 2 * n], x[2 * n :]
        force = -(c @ v + k @ q)
        ds = np.zeros(len(self.sliders))
        j = 0
        for i, law, _ in self.laws:
            slider = s[j] if law.has_slider else 0.0
            force[i] -= self.scale * float(law.moment(q[i], v[i], slider))
            if law.has_slider:
                ds[j] = float(law.slider_rate(q[i], slider))
                j += 1
        return np.concatenate([v, np.linalg.solve(m, force), ds])

    def jacobian(self, t, x):
        """d rhs / dx: the structure's matrices with the laws' slopes on their blades' lag."""
        n, n_s = self.n, len(self.sliders)
        m, c, k = self._at(t)
        q, v, s = x[:n], x[n : 2 * n], x[2 * n :]
        out = np.zeros((2 * n + n_s, 2 * n + n_s))
        out[:n, n : 2 * n] = np.eye(n)
        stiffness, damping, coupling = k.copy(), c.copy(), np.zeros((n, n_s))
        j = 0
        for i, law, _ in self.laws:
            slider = s[j] if law.has_slider else 0.0
            d_angle, d_rate, d_slider = (self.scale * d for d in law.slopes(q[i], v[i], slider))
            stiffness[i, i] += d_angle
            damping[i, i] += d_rate
            if law.has_slider:
                coupling[i, j] = d_slider
                out[2 * n + j, i], out[2 * n + j, 2 * n + j] = law.slider_slopes(q[i], slider)
                j += 1
        inverse = np.linalg.inv(m)
        out[n : 2 * n, :n] = -inverse @ stiffness
        out[n : 2 * n, n : 2 * n] = -inverse @ damping
        out[n : 2 * n, 2 * n :] = -inverse @ coupling
        return out


#: Pieces a run is integrated in (progress is reported after each).
PIECES = 20
#: A run stops where a blade's lag passes this [rad]: far beyond the small angles the structure
#: holds, motion that grows there only grows on (and would leave double precision).
LIMIT = math.pi / 2


def integrate(
    case, speed: float, duration: float, initial, rtol: float | None = None, points: int = 8000, progress=None
):
    """Integrate the equations with the laws from ``initial`` = (q0, v0) (SI, the coordinates of
    :func:`structure`) over ``duration`` [s] at ``speed`` [rad/s]; sliders start at rest.
    ``progress(done, total)`` [s simulated] is called after each of :data:`PIECES` pieces.

    ``rtol``: by default 1e-9 (DOP853), or 1e-7 where the law is stiff (Radau, with the laws'
    Jacobian): a slider's stick-slip kinks hold a tighter implicit integration to many small
    steps, and 1e-7 already gives a settled amplitude within 1e-8 of 1e-9's (measured on
    hammond-friction-link)."""
    equations = Equations(case, speed)
    system, n, n_b, sliders = equations.system, equations.n, equations.system.n_blades, equations.sliders
    q0, v0 = (np.asarray(a, dtype=float) for a in initial)
    stiff = law_rate(case, speed) > STIFF_RATIO * fastest_rate(system, speed)
    method = "Radau" if stiff else "DOP853"
    rtol = (STIFF_RTOL if stiff else RTOL) if rtol is None else rtol
    times = np.linspace(0.0, duration, points)
    size = max(np.abs(np.concatenate([q0, v0])).max(), 1e-12)
    state = np.concatenate([q0, v0, np.zeros(len(sliders))])
    ends = np.linspace(0.0, duration, PIECES + 1)
    values, evaluations, stopped = [state[:, None]], 0, None
    lags = [i for i, c in enumerate(system.coordinates) if c.kind == "lag"]

    def beyond(t, x):  # (zero where the largest blade lag reaches LIMIT)
        return LIMIT - np.abs(x[lags]).max()

    beyond.terminal = True
    for a, b in zip(ends[:-1], ends[1:]):  # (pieces end on output instants: none is lost or doubled)
        inside = times[(times > a) & (times <= b)]
        sol = solve_ivp(
            equations.rhs,
            (a, b),
            state,
            method=method,
            t_eval=inside,
            dense_output=True,
            events=beyond,
            **({"jac": equations.jacobian} if stiff else {}),
            rtol=rtol,
            atol=rtol * 1e-3 * size,
        )
        if not sol.success:
            raise RuntimeError(f"time integration failed: {sol.message}")
        evaluations += int(sol.nfev)
        values.append(sol.y)
        if sol.status == 1:  # (a blade passed LIMIT: the run ends there)
            stopped = float(sol.t_events[0][0])
            break
        state = sol.sol(b)
        if progress is not None:
            progress(float(b), float(duration))
    y = np.concatenate(values, axis=1)
    times = times[: y.shape[1]]
    slider = np.zeros((len(times), n_b))
    for j, (_, _, k) in enumerate(sliders):
        slider[:, k] = y[2 * n + j]
    if progress is not None and stopped is not None:
        progress(float(duration), float(duration))
    return NonlinearHistory(
        times,
        y[:n].T,
        y[n : 2 * n].T,
        slider,
        system.coordinates,
        float(speed),
        evaluations,
        method,
        stopped,
        rtol * 1e-3 * size,
    )


def components(time, signal, count: int = 2):
    """The ``count`` largest frequency components of ``signal`` over ``time`` (equally spaced):
    [(frequency [rad/s], amplitude)], largest first. FFT peaks (Hann window), each refined by
    a parabola through its bin and neighbours, then all fitted together by least squares
    (cos and sin at each frequency, and a constant), the frequencies refined with them."""
    t = np.asarray(time, float) - time[0]
    x = np.asarray(signal, float) - np.mean(signal)
    dt = t[1] - t[0]
    spectrum = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    freqs = 2 * np.pi * np.fft.rfftfreq(len(x), dt)
    peaks = [
        i
        for i in range(1, len(spectrum) - 1)
        if spectrum[i] >= spectrum[i - 1] and spectrum[i] > spectrum[i + 1]
    ]
    peaks = sorted(peaks, key=lambda i: -spectrum[i])[:count]
    found = []
    for i in peaks:
        a, b, c = np.log(spectrum[i - 1 : i + 2] + 1e-300)
        shift = 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c != 0 else 0.0
        found.append(freqs[i] + shift * (freqs[1] - freqs[0]))

    def fit(frequencies):  # (cos and sin at each frequency, and a constant: linear least squares)
        basis = np.stack([np.ones_like(t)] + [f(w * t) for w in frequencies for f in (np.cos, np.sin)], 1)
        coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
        return coef, basis @ coef - x

    if found:  # (the frequencies refined where the fit's residual is least: the FFT's bins are coarse)
        found = list(least_squares(lambda f: fit(f)[1], found, x_scale=freqs[1], xtol=1e-14).x)
    coef, _ = fit(found)
    amplitudes = [float(np.hypot(coef[1 + 2 * j], coef[2 + 2 * j])) for j in range(len(found))]
    out = sorted(zip(found, amplitudes), key=lambda p: -p[1])
    return [(float(w), a) for w, a in out]
