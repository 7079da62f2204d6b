"""Limit cycles of a rotor with nonlinear lag dampers, predicted from describing functions.

With each law replaced by its equivalent linear damper at an amplitude A
(:mod:`groundres.model.describing`), the roots of the equations depend on A.
A limit cycle is an amplitude at which the least stable root is neutral:
g(A) = 0, g the largest real part of a root with lag motion. Below and above
it the motion grows or decays at the equivalent system's rate, so the sign
change of g says what the cycle is: g > 0 below and < 0 above, a **stable**
cycle (motion grows to it, or decays to it from above); g < 0 below and > 0
above, an **unstable** cycle, a threshold (a disturbance below it decays, one
above it grows until something not modelled stops it).

The amplitude is that of the blade lag the law sees. A root of the
multiblade equations moves each blade in the rotating frame at the
frequencies w and w +- n Omega (w the root's frequency in the nonrotating
frame, n the harmonics of its cyclic coordinates). Its largest component sets
the law's amplitude A and frequency (the describing function is evaluated
there, and the frequency iterated to a fixed point with the root's own). The
second largest, over the largest, says how good the single-harmonic
approximation is: the law also sees that other frequency (an anisotropic
body mixes the regressive and progressive whirls). The blade's peak (half
peak-to-peak) is the sum of all components; the hub's amplitudes are those of
the body's coordinates in the same eigenvector.

Identical blades with one law on every blade are solved by multiblade
eigen-analysis of the equivalent system, batched over speeds and amplitudes:
its form is exactly F0(Omega) + c dC(Omega) + k dK, linear in the blades' equivalent
damping c and stiffness k. In air every equivalent system moves about one hover
trim, the small-motion system's (the linear analysis's), so the form stays
linear in k (:meth:`groundres.model.system.System.holding_trim_of`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..methods import Method
from ..model import describing, mbc
from ..solve import modal
from ..solve.solvers import solver_for

#: Blade lag amplitudes searched by default [rad]: 0.001 to 30 deg.
SEARCHED = (math.radians(0.001), math.radians(30.0))
#: Amplitudes of the scan per decade (log-spaced).
PER_DECADE = 12
#: Fixed-point steps on the law's frequency at each amplitude, and their relative tolerance.
ITERATIONS = 8
FREQUENCY_RTOL = 1e-12
#: Slowest blade frequency the laws are evaluated at, per rotor speed.
SLOWEST = 1e-3
#: Most steps of the Illinois method on log amplitude, and the bracket [log] at which it stops.
SECANT_STEPS = 60
BRACKET = 1e-13
#: Second component over the first beyond which the single-harmonic approximation is poor.
POOR = 0.2
#: Cycles beyond this blade amplitude leave the small-angle structure [rad].
LARGE = math.radians(10.0)


@dataclass
class Cycle:
    """One limit cycle at one rotor speed (module docstring); SI units, angles in rad."""

    speed: float
    amplitude: float
    stable: bool
    frequency: float
    nonrotating_frequency: float
    peak: float
    hub: dict
    second_component: float
    equivalent_damping: float
    equivalent_stiffness: float
    #: The motion's complex amplitudes on the multiblade coordinates (SI: m, rad), scaled to the
    #: cycle: q(t) = Re(vector exp(i nonrotating_frequency t)).
    vector: np.ndarray = field(default=None, repr=False)

    @property
    def poor(self) -> bool:
        """Whether the single-harmonic approximation is poor here (:data:`POOR`)."""
        return self.second_component > POOR

    @property
    def large(self) -> bool:
        """Whether the cycle is beyond the small angles the structure assumes (:data:`LARGE`)."""
        return self.peak > LARGE


@dataclass
class LimitCycles:
    """Limit cycles over a sweep: the scan of g(A) and the cycles found in it.

    Attributes
    ----------
    speeds : ndarray (n_s,)
        Rotor speeds [rad/s].
    amplitudes : ndarray (n_a,)
        The blade lag amplitudes scanned [rad].
    growth : ndarray (n_s, n_a)
        g(A): the largest real part of a root with lag motion [1/s], the laws at each amplitude.
    cycles : list of Cycle
        Every neutral amplitude found, by speed then amplitude.
    """

    speeds: np.ndarray
    amplitudes: np.ndarray
    growth: np.ndarray
    cycles: list = field(default_factory=list)

    def at(self, speed: float) -> list:
        """The cycles at ``speed`` [rad/s] (one of :attr:`speeds`)."""
        return [c for c in self.cycles if c.speed == speed]

    def verdict(self, i: int) -> str:
        """What happens at speed ``i`` in words (without numbers), from the smallest amplitude
        searched up: the cycles in order, stable ones attracting, unstable ones thresholds."""
        cycles = sorted(self.at(float(self.speeds[i])), key=lambda c: c.amplitude)
        grows = self.growth[i, 0] > 0
        if not cycles:
            return "grows from any disturbance" if grows else "decays from any disturbance searched"
        words = "grows from any small disturbance" if grows else "small disturbances decay"
        for k, cycle in enumerate(cycles):
            last = k == len(cycles) - 1
            if cycle.stable:  # (reached from below, where the motion grows)
                words += " to a stable cycle" + (" (larger ones decay to it)" if last else "")
            else:
                words += ", a disturbance above the threshold grows" + (" without bound" if last else "")
        return words


class EquivalentSystem:
    """The equations of ``case`` with every law replaced by a linear damper of damping c and
    stiffness k (SI), exactly F0 + c dC + k dK at any speeds (module docstring)."""

    def __init__(self, case):
        rotor = case.rotor
        laws = [e.law if e is not None else None for e in rotor.lag_laws]
        if not laws or any(law is None for law in laws) or len(set(laws)) != 1 or not rotor.identical:
            raise NotImplementedError(
                "limit cycles of dissimilar blades (a failed damper, different laws) need the Floquet "
                "analysis of the equivalent system, which is not built yet"
            )
        if rotor.n_blades < 3:
            raise NotImplementedError("limit cycles of a two-bladed rotor need the Floquet analysis")
        self.case, self.law = case, laws[0]
        n = rotor.n_blades
        c0, k0 = self.law.small_motion()
        inertia = rotor.blades[0].blade_inertia
        top = case.sweep.stop
        # (differences over a typical damper and spring: their round-off stays that of the form)
        self.c_ref = max(c0, inertia * top * 1e-2, 1e-300)
        self.k_ref = max(k0, inertia * top * top * 1e-2, 1e-300)

        trimmed = solver_for(case, Method.MULTIBLADE).system  # (in air: the small-motion trim, held)

        def solver(c, k):
            found = solver_for(replace(case, rotor=rotor.equivalent([c] * n, [k] * n)), Method.MULTIBLADE)
            found.system.holding_trim_of(trimmed)
            return found

        self.base = solver(0.0, 0.0)
        self.damped, self.sprung = solver(self.c_ref, 0.0), solver(0.0, self.k_ref)
        self.system = self.base.system
        self.blocks = None

    def directions(self, speeds):
        """(F0, dC, dK) at ``speeds``, each (3, n_s, n, n) in the equations' mass unit per SI unit."""
        f0 = self.base.form(speeds)
        d_c = (self.damped.form(speeds) - f0) / self.c_ref
        d_k = (self.sprung.form(speeds) - f0) / self.k_ref
        if self.blocks is None:
            self.blocks = modal.coupling_blocks(*(f0 + self.c_ref * d_c + self.k_ref * d_k))
        return f0, d_c, d_k


def predict(case, speeds=None, searched=SEARCHED, per_decade: int = PER_DECADE) -> LimitCycles:
    """Limit cycles of ``case`` at ``speeds`` [rad/s] (default: the sweep's) between the blade lag
    amplitudes ``searched`` [rad] (module docstring)."""
    equivalent = EquivalentSystem(case)
    speeds = case.sweep.speeds if speeds is None else np.asarray(speeds, dtype=float)
    speeds = speeds[speeds > 0]  # (at rest nothing turns: no cycle)
    if not len(speeds):
        return LimitCycles(speeds, np.array(searched, float), np.zeros((0, 2)))
    decades = math.log10(searched[1] / searched[0])
    amplitudes = np.geomspace(searched[0], searched[1], max(2, int(math.ceil(decades * per_decade)) + 1))
    forms = equivalent.directions(speeds)
    at = np.repeat(np.arange(len(speeds)), len(amplitudes))
    flat = np.tile(amplitudes, len(speeds))
    growth, _ = _neutrality(equivalent, forms, speeds, at, flat)
    growth = growth.reshape(len(speeds), len(amplitudes))
    # brackets of a sign change, refined by bisection on log amplitude, all together
    s_i, a_i = np.nonzero(np.sign(growth[:, :-1]) * np.sign(growth[:, 1:]) < 0)
    low, high = np.log(amplitudes[a_i]), np.log(amplitudes[a_i + 1])
    below = growth[s_i, a_i] > 0  # (grows below: a stable cycle)
    g_low, g_high = growth[s_i, a_i], growth[s_i, a_i + 1]
    side = np.zeros(len(s_i), int)  # (the Illinois method: the end kept twice in a row is halved)
    for _ in range(SECANT_STEPS if len(s_i) else 0):
        wide = high - low > BRACKET * max(1.0, float(np.abs(np.concatenate([low, high])).max()))
        if not wide.any():
            break
        mid = np.where(g_low != g_high, (low * g_high - high * g_low) / (g_high - g_low), 0.5 * (low + high))
        mid = np.clip(mid, low + 0.01 * (high - low), high - 0.01 * (high - low))
        mid = np.where(wide, mid, 0.5 * (low + high))
        g, _ = _neutrality(equivalent, forms, speeds, s_i, np.exp(mid))
        same = (g > 0) == below  # (mid on the low end's side)
        low, g_low = np.where(same, mid, low), np.where(same, g, np.where(side == -1, 0.5 * g_low, g_low))
        high, g_high = np.where(same, high, mid), np.where(same, np.where(side == 1, 0.5 * g_high, g_high), g)
        side = np.where(same, 1, -1)
    result = LimitCycles(speeds, amplitudes, growth)
    if len(s_i):
        found = np.exp(0.5 * (low + high))
        _, state = _neutrality(equivalent, forms, speeds, s_i, found)
        result.cycles = [
            _cycle(equivalent, speeds[s], a, b, state, j)
            for j, (s, a, b) in enumerate(zip(s_i, found, below))
        ]
    return result


def _neutrality(equivalent, forms, speeds, at, amplitudes):
    """g at the points (speed index ``at``, blade amplitude), the law's frequency iterated to
    the root's own (each point until its own frequency settles); and the state of the last
    step at every point (roots, vectors, components, frequencies)."""
    law = equivalent.law
    # (from the blade's own lag frequency in the rotating frame)
    blade = equivalent.case.rotor.blades[0]
    frequency = np.maximum(blade.lag_frequency(speeds[at]) * speeds[at], SLOWEST * speeds[at])
    state = None
    active = np.arange(len(at))
    for _ in range(ITERATIONS):
        f0, d_c, d_k = (x[:, at[active]] for x in forms)
        c, k = describing.equivalent(law, amplitudes[active], frequency[active])
        mats = f0 + c[None, :, None, None] * d_c + k[None, :, None, None] * d_k
        found = _least_stable(equivalent, mats, speeds[at[active]])
        if state is None:
            state = found
        else:
            for key, value in found.items():
                state[key][active] = value
        # (a root without oscillation leaves the hysteretic laws' c_eq = W / (pi w A^2) unbounded:
        # the law is taken at a slow oscillation instead)
        new = np.maximum(found["frequency"], SLOWEST * speeds[at[active]])
        settled = np.abs(new - frequency[active]) <= FREQUENCY_RTOL * new
        frequency[active] = new
        active = active[~settled]
        if not len(active):
            break
    state["damping"], state["stiffness"] = describing.equivalent(law, amplitudes, frequency)
    return state["root"].real, state


def _least_stable(equivalent, mats, speeds) -> dict:
    """The root with lag motion of largest real part at every point, with its blade components."""
    system = equivalent.system
    solution = modal.solve(*mats, equivalent.blocks, system.integrals)
    coords = system.multiblade_coordinates()
    lag = np.array([c.kind == "lag" for c in coords])
    values, vectors = solution.eigenvalue, solution.vector
    has_lag = np.abs(vectors[:, lag, :]).max(axis=1) > 1e-6 * np.abs(vectors).max(axis=1)
    upper = values.imag >= 0
    score = np.where(has_lag & upper, values.real, -np.inf)
    j = np.argmax(score, axis=1)
    rows = np.arange(len(j))
    root, vector = values[rows, j], vectors[rows, :, j]
    amplitude, frequency, second, peak = blade_components(system, vector, root.imag, speeds)
    return {
        "root": root,
        "vector": vector,
        "frequency": frequency,
        "unit_amplitude": amplitude,
        "second": second,
        "peak": peak,
    }


def blade_components(system, vector, frequency, speeds):
    """Blade lag in the rotating frame of multiblade eigenvectors ``vector`` (m, n) of roots of
    nonrotating ``frequency`` (m,) [rad/s] at ``speeds`` (m,): the largest component's
    amplitude and frequency, the second largest over the largest, and the peak (the sum of all
    components), for the blade that moves most (the largest component's)."""
    coords = system.multiblade_coordinates()
    n_b = system.n_blades
    index = {c.name: i for i, c in enumerate(coords) if c.kind == "lag"}
    phase = 2 * np.pi * np.arange(n_b) / n_b  # (blade k's azimuth offset)
    parts, freqs = [], []
    common = vector[:, index["0"]][:, None] * np.ones(n_b)
    if "d" in index:
        common = common + vector[:, index["d"]][:, None] * (-1.0) ** np.arange(n_b)
    parts.append(common)
    freqs.append(np.abs(frequency))
    for name, i in index.items():
        if not name.endswith("c"):
            continue
        n = int(name[:-1])
        v_c, v_s = vector[:, i][:, None], vector[:, index[f"{n}s"]][:, None]
        turn = np.exp(1j * n * phase)
        parts.append(0.5 * (v_c - 1j * v_s) * turn)
        freqs.append(np.abs(frequency + n * speeds))
        parts.append(0.5 * (v_c + 1j * v_s) * np.conj(turn))
        freqs.append(np.abs(frequency - n * speeds))
    size = np.abs(np.stack(parts, axis=-1))  # (m, blades, components)
    freqs = np.stack(freqs, axis=-1)  # (m, components)
    order = np.sort(size, axis=-1)
    largest, second = order[..., -1], order[..., -2] if size.shape[-1] > 1 else 0 * order[..., -1]
    blade = np.argmax(largest, axis=1)
    rows = np.arange(len(blade))
    top = np.argmax(size[rows, blade], axis=-1)
    amplitude = largest[rows, blade]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(amplitude > 0, second[rows, blade] / amplitude, 0.0)
    return amplitude, freqs[rows, top], ratio, size[rows, blade].sum(-1)


def _cycle(equivalent, speed, amplitude, stable, state, j) -> Cycle:
    """The cycle at point ``j`` of the bisection's last state, scaled to ``amplitude``."""
    system = equivalent.system
    scale = amplitude / state["unit_amplitude"][j]
    vector = state["vector"][j] * scale
    coords = system.multiblade_coordinates()
    hub = {c.name: float(abs(vector[i])) for i, c in enumerate(coords) if c.kind == "body"}
    return Cycle(
        speed=float(speed),
        amplitude=float(amplitude),
        stable=bool(stable),
        frequency=float(state["frequency"][j]),
        nonrotating_frequency=float(abs(state["root"][j].imag)),
        peak=float(state["peak"][j] * scale),
        hub=hub,
        second_component=float(state["second"][j]),
        equivalent_damping=float(state["damping"][j]),
        equivalent_stiffness=float(state["stiffness"][j]),
        vector=vector,
    )


def disturbance(system, cycle: Cycle, factor: float = 1.0):
    """Blade-coordinate displacements and rates (q0, v0) at t = 0 (blade 1 at azimuth 0) of
    ``factor`` times ``cycle``'s motion: the start of a simulation along the predicted cycle."""
    n_b, speed = system.n_blades, cycle.speed
    v = np.asarray(cycle.vector) * factor
    q_mb, rate_mb = v.real, (1j * cycle.nonrotating_frequency * v).real
    basis, d_basis, _ = mbc.multiblade_basis(n_b, 0.0)
    n_body = system.n_body
    q0, v0 = np.zeros(system.size), np.zeros(system.size)
    q0[:n_body], v0[:n_body] = q_mb[:n_body], rate_mb[:n_body]
    for j in range(len(system.blade_kinds)):
        part = slice(n_body + j * n_b, n_body + (j + 1) * n_b)
        q0[part] = basis @ q_mb[part]
        v0[part] = basis @ rate_mb[part] + speed * (d_basis @ q_mb[part])
    return q0, v0


def bracket_threshold(
    case, cycle: Cycle, low: float = 0.8, high: float = 1.25, steps: int = 4, duration=None
):
    """Bracket an unstable cycle (a threshold) by simulation: start the nonlinear equations
    (:func:`groundres.solve.nonlinear.integrate`) along ``cycle``'s motion at factors of it and
    bisect the factor between one that decays and one that grows, ``steps`` times.

    Each run lasts ``duration`` [s] (default 60 periods of the cycle's rotating-frame frequency)
    and is judged by the blade lag's largest component over its last fifth against its first
    fifth. Returns (decays, grows): the factors bracketing the threshold, or None for an end that
    did not behave as its side (the prediction is then off by more than the bracket).
    """
    from ..solve import nonlinear

    system = nonlinear.structure(case)
    duration = 120 * math.pi / cycle.frequency if duration is None else duration

    def grows(factor: float) -> bool:
        history = nonlinear.integrate(
            case, cycle.speed, duration, disturbance(system, cycle, factor), points=4000
        )
        fifth = history.time[-1] / 5
        start, end = history.time <= fifth, history.time >= 4 * fifth
        first = nonlinear.components(history.time[start], history.lag(1)[start], 1)[0][1]
        last = nonlinear.components(history.time[end], history.lag(1)[end], 1)[0][1]
        return last > first

    if grows(low) or not grows(high):
        return (None if grows(low) else low), (high if grows(high) else None)
    for _ in range(steps):
        mid = math.sqrt(low * high)
        low, high = (low, mid) if grows(mid) else (mid, high)
    return low, high
