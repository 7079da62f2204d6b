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
linear in k (:meth:`groundres.model.system.System.holding_trim_of`). Blades that
differ (a failed damper, different laws, two blades) are solved by Floquet
analysis, each blade at its own amplitude
(:mod:`groundres.assess.periodic_cycles`); both hand the same search below
g(a) at the amplitude a of the blade that moves most.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..methods import Method
from ..model import describing, mbc
from ..solve import modal
from ..solve.solvers import solver_for
from .cycle_shapes import Cycle, blade_spectra, make_cycle
from .stability import growth_threshold

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
    small_growth : ndarray (n_s,)
        g of small motion: each law at its slope at rest, as the linear analysis takes it [1/s].
    cycles : list of Cycle
        Every neutral amplitude found, by speed then amplitude.
    """

    speeds: np.ndarray
    amplitudes: np.ndarray
    growth: np.ndarray
    small_growth: np.ndarray
    cycles: list = field(default_factory=list)

    def at(self, speed: float) -> list:
        """The cycles at ``speed`` [rad/s] (one of :attr:`speeds`)."""
        return [c for c in self.cycles if c.speed == speed]

    def signs(self, i: int) -> np.ndarray:
        """Along the amplitudes scanned at speed ``i``: +1 where the motion grows, -1 where it
        decays, 0 neutral (:func:`_signs`)."""
        return _signs(self.growth[i], self.speeds[i])

    def small_sign(self, i: int) -> int:
        """Whether small motion grows (+1), decays (-1) or is neutral (0) at speed ``i``: the
        linear analysis's verdict on the least stable root with lag motion."""
        return int(_signs(self.small_growth[i], self.speeds[i]))

    def lead(self, i: int) -> tuple[int, float | None]:
        """The first sign other than neutral along the amplitudes scanned at speed ``i`` and the
        amplitude it starts at [rad] ((0, None): neutral at every amplitude)."""
        signs = self.signs(i)
        moving = np.flatnonzero(signs)
        if not len(moving):
            return 0, None
        return int(signs[moving[0]]), float(self.amplitudes[moving[0]])

    def unbounded(self) -> list:
        """Indices of the speeds at which any disturbance grows without bound: small motion grows,
        so do the amplitudes searched (the first that are not neutral), and no stable cycle holds
        it (no threshold there: the least disturbance that diverges is none)."""
        return [
            i
            for i, speed in enumerate(self.speeds)
            if self.small_sign(i) > 0
            and self.lead(i)[0] > 0
            and not any(c.stable for c in self.at(float(speed)))
        ]

    def below_searched(self) -> list:
        """Indices of the speeds at which small motion does not grow but the amplitudes searched
        do (the first that are not neutral) before any threshold: a threshold lies below the
        amplitude at which the growth starts (:meth:`lead`)."""
        return [i for i in range(len(self.speeds)) if self.small_sign(i) <= 0 and self.lead(i)[0] > 0]

    def stable_below_searched(self) -> list:
        """Indices of the speeds at which small motion grows but the amplitudes searched decay
        (the first that are not neutral): a stable cycle lies below the amplitude at which the
        decay starts (:meth:`lead`)."""
        return [i for i in range(len(self.speeds)) if self.small_sign(i) > 0 and self.lead(i)[0] < 0]

    def verdict(self, i: int) -> str:
        """What happens at speed ``i`` in words, from small motion (the linear analysis) up
        through the amplitudes searched: the cycles in order, stable ones attracting, unstable
        ones thresholds."""
        cycles = sorted(self.at(float(self.speeds[i])), key=lambda c: c.amplitude)
        small, (lead, start) = self.small_sign(i), self.lead(i)
        if small == 0 and lead < 0:  # (a neutral root, such as a stuck friction damper's creep: decays)
            small = -1
        at = None if start is None else f"{math.degrees(start):.3g} deg"
        if start is not None and start == self.amplitudes[0]:
            at += ", the smallest searched"
        if small == lead:
            if not cycles:
                return {
                    1: "grows from any disturbance",
                    -1: "decays from any disturbance searched",
                    0: "neutral at every amplitude searched (within the linear analysis's growth threshold)",
                }[lead]
            words = "grows from any small disturbance" if lead > 0 else "small disturbances decay"
        elif lead == 0:
            state = "grows" if small > 0 else "decays"
            return f"small motion {state}; every amplitude searched is neutral (within the growth threshold)"
        elif small > 0:  # (and the amplitudes searched decay)
            words = f"small motion grows to a stable cycle below {at}"
            if not cycles:
                return words + " (larger ones decay to it)"
        else:  # (the amplitudes searched grow; small motion decays or is neutral)
            if small < 0:
                words = f"small motion decays; a threshold lies below {at}: a disturbance above it grows"
            else:
                words = f"small motion is neutral; from {at}, a disturbance grows"
            if not cycles:
                return words + " without bound"
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

    #: Amplitudes of the scan per decade, and the bracket [log] the search stops at.
    per_decade, bracket = PER_DECADE, BRACKET

    def __init__(self, case):
        rotor = case.rotor
        if not multiblade_applies(case):
            raise ValueError("the multiblade route needs identical blades (N >= 3) with one law")
        self.case, self.law = case, rotor.lag_laws[0].law
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
        self.speeds = self.forms = None

    def directions(self, speeds):
        """(F0, dC, dK) at ``speeds``, each (3, n_s, n, n) in the equations' mass unit per SI unit."""
        f0 = self.base.form(speeds)
        d_c = (self.damped.form(speeds) - f0) / self.c_ref
        d_k = (self.sprung.form(speeds) - f0) / self.k_ref
        if self.blocks is None:
            self.blocks = modal.coupling_blocks(*(f0 + self.c_ref * d_c + self.k_ref * d_k))
        return f0, d_c, d_k

    def prepare(self, speeds):
        """Hold the forms at ``speeds`` [rad/s] for :meth:`neutrality`."""
        self.speeds, self.forms = speeds, self.directions(speeds)

    def small_motion(self):
        """g of small motion at every speed held: the law at its slope at rest (the linear
        analysis's damper), (n_s,)."""
        c0, k0 = self.law.small_motion()
        f0, d_c, d_k = self.forms
        return self._least_stable(f0 + c0 * d_c + k0 * d_k, self.speeds)["root"].real

    def scan(self, amplitudes):
        """g at every speed held (:meth:`prepare`) and every amplitude, (n_s, n_a), all at once."""
        n_s = len(self.speeds)
        at = np.repeat(np.arange(n_s), len(amplitudes))
        return self.neutrality(at, np.tile(amplitudes, n_s))[0].reshape(n_s, len(amplitudes))

    def neutrality(self, at, amplitudes):
        """g at the points (speed index ``at``, blade amplitude [rad]), the law's frequency
        iterated to the root's own (each point until its own frequency settles); and the state
        of the last step at every point (roots, vectors, spectra, the equivalent damper)."""
        law, speeds = self.law, self.speeds
        # (from the blade's own lag frequency in the rotating frame)
        blade = self.case.rotor.blades[0]
        frequency = np.maximum(blade.lag_frequency(speeds[at]) * speeds[at], SLOWEST * speeds[at])
        state = None
        active = np.arange(len(at))
        for _ in range(ITERATIONS):
            f0, d_c, d_k = (x[:, at[active]] for x in self.forms)
            c, k = describing.equivalent(law, amplitudes[active], frequency[active])
            mats = f0 + c[None, :, None, None] * d_c + k[None, :, None, None] * d_k
            found = self._least_stable(mats, speeds[at[active]])
            if state is None:
                state = found
            else:
                for key, value in found.items():
                    state[key][active] = value
            # (a root without oscillation leaves the hysteretic laws' c_eq = W / (pi w A^2)
            # unbounded: the law is taken at a slow oscillation instead)
            new = np.maximum(found["frequency"], SLOWEST * speeds[at[active]])
            settled = np.abs(new - frequency[active]) <= FREQUENCY_RTOL * new
            frequency[active] = new
            active = active[~settled]
            if not len(active):
                break
        state["damping"], state["stiffness"] = describing.equivalent(law, amplitudes, frequency)
        return state["root"].real, state

    def _least_stable(self, mats, speeds) -> dict:
        """The root with lag motion of largest real part at every point, with its blade spectra."""
        system = self.system
        solution = modal.solve(*mats, self.blocks, system.integrals)
        coords = system.multiblade_coordinates()
        lag = np.array([c.kind == "lag" for c in coords])
        values, vectors = solution.eigenvalue, solution.vector
        has_lag = np.abs(vectors[:, lag, :]).max(axis=1) > 1e-6 * np.abs(vectors).max(axis=1)
        upper = values.imag >= 0
        score = np.where(has_lag & upper, values.real, -np.inf)
        j = np.argmax(score, axis=1)
        rows = np.arange(len(j))
        root, vector = values[rows, j], vectors[rows, :, j]
        spectra = blade_spectra(system, vector[:, :, None], np.zeros(1, int), root.imag, speeds)
        top = np.argmax(spectra[0], axis=1)
        return {
            "root": root,
            "vector": vector,
            "spectra": np.stack(spectra, axis=1),  # (m, 4, N)
            "frequency": spectra[1][rows, top],
            "unit_amplitude": spectra[0][rows, top],
        }

    def cycle(self, speed, amplitude, stable, state, j) -> Cycle:
        """The cycle at point ``j`` of the last state, scaled to ``amplitude``."""
        system = self.system
        root, vector = state["root"][j], state["vector"][j]
        n = system.n_blades
        return make_cycle(
            system,
            speed,
            amplitude,
            stable,
            root,
            tuple(state["spectra"][j]),
            vector[:, None],
            _blade_state(system, vector, root.imag, speed),
            [True] * n,
            np.full(n, state["damping"][j]),
            np.full(n, state["stiffness"][j]),
        )


def multiblade_applies(case) -> bool:
    """Whether the multiblade route solves ``case``'s limit cycles: three blades or more, alike,
    each with the same law."""
    rotor = case.rotor
    laws = [e.law if e is not None else None for e in rotor.lag_laws]
    return bool(laws) and None not in laws and len(set(laws)) == 1 and rotor.identical and rotor.n_blades >= 3


def _blade_state(system, vector, frequency, speed):
    """Blade-coordinate displacements and rates at t = 0 (blade 1 at azimuth 0), complex, of a
    multiblade motion ``vector`` exp(i ``frequency`` t) at rotor ``speed``."""
    n_b = system.n_blades
    rate = 1j * frequency * vector
    basis, d_basis, _ = mbc.multiblade_basis(n_b, 0.0)
    n_body = system.n_body
    q0, v0 = np.zeros(system.size, complex), np.zeros(system.size, complex)
    q0[:n_body], v0[:n_body] = vector[:n_body], rate[:n_body]
    for j in range(len(system.blade_kinds)):
        part = slice(n_body + j * n_b, n_body + (j + 1) * n_b)
        q0[part] = basis @ vector[part]
        v0[part] = basis @ rate[part] + speed * (d_basis @ vector[part])
    return np.concatenate([q0, v0])


def equivalent_of(case, periodic: bool | None = None):
    """The equivalent system whose roots :func:`predict` searches: multiblade where it applies,
    else Floquet (:mod:`groundres.assess.periodic_cycles`); ``periodic`` True asks for Floquet
    (a second route on identical blades)."""
    if not periodic and multiblade_applies(case):
        return EquivalentSystem(case)
    from .periodic_cycles import PeriodicEquivalent

    return PeriodicEquivalent(case)


def predict(
    case, speeds=None, searched=SEARCHED, per_decade: int | None = None, periodic: bool | None = None
) -> LimitCycles:
    """Limit cycles of ``case`` at ``speeds`` [rad/s] (default: the sweep's) between the blade lag
    amplitudes ``searched`` [rad] of the blade that moves most, ``per_decade`` amplitudes a decade
    in the scan (default: the route's own), by the route :func:`equivalent_of` picks (module
    docstring)."""
    equivalent = equivalent_of(case, periodic)
    per_decade = equivalent.per_decade if per_decade is None else per_decade
    speeds = case.sweep.speeds if speeds is None else np.asarray(speeds, dtype=float)
    speeds = speeds[speeds > 0]  # (at rest nothing turns: no cycle)
    if not len(speeds):
        return LimitCycles(speeds, np.array(searched, float), np.zeros((0, 2)), np.zeros(0))
    decades = math.log10(searched[1] / searched[0])
    amplitudes = np.geomspace(searched[0], searched[1], max(2, int(math.ceil(decades * per_decade)) + 1))
    equivalent.prepare(speeds)
    growth = equivalent.scan(amplitudes)
    # brackets of a sign change, refined by the Illinois method on log amplitude, all together
    s_i, a_i = _crossings(growth, speeds)
    # (a scan may settle its points only as far as their sign needs: each bracket's ends again,
    # in full, and only the brackets that still change sign kept)
    g_low = equivalent.neutrality(s_i, amplitudes[a_i])[0] if len(s_i) else np.zeros(0)
    g_high = equivalent.neutrality(s_i, amplitudes[a_i + 1])[0] if len(s_i) else np.zeros(0)
    kept = np.sign(g_low) * np.sign(g_high) < 0
    s_i, a_i, g_low, g_high = s_i[kept], a_i[kept], g_low[kept], g_high[kept]
    low, high = np.log(amplitudes[a_i]), np.log(amplitudes[a_i + 1])
    below = g_low > 0  # (grows below: a stable cycle)
    side = np.zeros(len(s_i), int)  # (the end kept twice in a row is halved)
    tight = equivalent.bracket
    for _ in range(SECANT_STEPS if len(s_i) else 0):
        wide = high - low > tight * max(1.0, float(np.abs(np.concatenate([low, high])).max()))
        if not wide.any():
            break
        mid = np.where(g_low != g_high, (low * g_high - high * g_low) / (g_high - g_low), 0.5 * (low + high))
        mid = np.clip(mid, low + 0.01 * (high - low), high - 0.01 * (high - low))
        mid = np.where(wide, mid, 0.5 * (low + high))
        g, _ = equivalent.neutrality(s_i, np.exp(mid))
        same = (g > 0) == below  # (mid on the low end's side)
        low, g_low = np.where(same, mid, low), np.where(same, g, np.where(side == -1, 0.5 * g_low, g_low))
        high, g_high = np.where(same, high, mid), np.where(same, np.where(side == 1, 0.5 * g_high, g_high), g)
        side = np.where(same, 1, -1)
    result = LimitCycles(speeds, amplitudes, growth, equivalent.small_motion())
    if len(s_i):
        found = np.exp(0.5 * (low + high))
        _, state = equivalent.neutrality(s_i, found)
        result.cycles = [
            equivalent.cycle(speeds[s], a, b, state, j) for j, (s, a, b) in enumerate(zip(s_i, found, below))
        ]
    return result


def _signs(growth, speeds):
    """+1 where ``growth`` [1/s] grows, -1 where it decays, 0 within the linear analysis's growth
    threshold of neutral at ``speeds`` [rad/s] (:func:`groundres.assess.stability.growth_threshold`;
    arrays broadcast)."""
    band = growth_threshold(speeds)
    return np.where(growth > band, 1, np.where(growth < -band, -1, 0))


def _crossings(growth, speeds) -> tuple[np.ndarray, np.ndarray]:
    """The brackets (speed index, amplitude index) of the scan's sign changes that carry the
    motion from growing to decaying or back beyond the linear analysis's growth threshold: a
    change of sign within it (round-off about a neutral root) is no cycle. Of the changes between
    two amplitudes outside the threshold, the first is kept."""
    signs = _signs(growth, np.asarray(speeds)[:, None])
    s_i, a_i = np.nonzero(np.sign(growth[:, :-1]) * np.sign(growth[:, 1:]) < 0)
    kept, seen = [], set()
    for k, (s, a) in enumerate(zip(s_i, a_i)):  # (a few per speed at most)
        before = np.flatnonzero(signs[s, : a + 1])
        after = np.flatnonzero(signs[s, a + 1 :])
        if not len(before) or not len(after):
            continue
        if signs[s, before[-1]] != signs[s, a + 1 + after[0]] and (s, before[-1]) not in seen:
            seen.add((s, before[-1]))
            kept.append(k)
    return s_i[kept], a_i[kept]


def disturbance(system, cycle: Cycle, factor: float = 1.0):
    """Blade-coordinate displacements and rates (q0, v0) at t = 0 (blade 1 at azimuth 0) of
    ``factor`` times ``cycle``'s motion: the start of a simulation along the predicted cycle."""
    start = (np.asarray(cycle.start) * factor).real
    return start[: system.size].copy(), start[system.size :].copy()
