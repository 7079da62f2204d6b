"""Limit cycles of a rotor whose blades differ, by Floquet analysis of the equivalent system.

A failed damper, blades with different laws, or a two-bladed rotor make the
equations periodic, and the blades move differently on a cycle: the blade
beside a failed damper swings several times as far as the others. So each
blade's law is taken at that blade's own amplitude and frequency. The search
variable is the amplitude a of the blade that moves most; blade k moves at
A_k = a s_k, s_k its share (its largest rotating-frame component over the
largest blade's), at the frequency of that component
(:func:`groundres.assess.cycle_shapes.blade_spectra`). At each point (speed, a)
the shares and frequencies are iterated to a fixed point with those of the
least stable Floquet root with lag motion, whose real part is g(a); the
search for g(a) = 0 is the multiblade route's
(:func:`groundres.assess.limit_cycles.predict`).

The equivalent system is the equations without the laws' dampers (and springs,
for the laws whose equivalent stiffness changes with amplitude: the friction
link and the table) carrying one damping direction per blade with a law and
one stiffness direction per such spring
(:meth:`groundres.model.system.System.split_damping`): one set of node matrices
serves every point, and every point of a step is one batch of the Floquet
kernel. The equivalent system has no cyclic symmetry (the blades' dampers
differ), so the transition matrices span a whole revolution.

Scanning in amplitude, each point starts from the shares and frequencies found
at the amplitude before it at the same speed; a refinement step starts from
the nearest amplitude already solved at its speed.
"""

from __future__ import annotations

import math

import numpy as np

from ..methods import Method
from ..model import describing
from ..model.system import System
from ..solve.floquet import exponents
from ..solve.floquet.symmetry import Symmetry
from ..solve.solvers import solver_for
from .cycle_shapes import blade_spectra, make_cycle

#: Fixed-point steps on each blade's share and frequency at a point, their tolerance (shares
#: absolute, frequencies relative), and the steps the acceleration combines.
ITERATIONS = 30
SHARE_TOL = 1e-9
DEPTH = 3
#: A scan's point may stop short of SHARE_TOL once its unknowns move by at most this, and takes
#: at most SCAN_ITERATIONS steps (the ends of every sign change are evaluated again in full).
LOOSE = 1e-3
SCAN_ITERATIONS = 8
#: Slowest blade frequency the laws are evaluated at, per rotor speed.
SLOWEST = 1e-3
#: Laws whose equivalent stiffness changes with amplitude (a stiffness direction each).
SPRUNG = ("friction-link", "table")
#: Harmonics of each root's periodic eigenvector kept around its dominant one (the blades' spectra
#: and the lag content need only the few nearest).
HARMONICS = 4
#: A root has lag motion when its lag coordinates hold this share of its largest amplitude.
LAG_SHARE = 1e-6


class PeriodicEquivalent:
    """The periodic equations of ``case`` with each law replaced by its equivalent linear
    damper at its own blade's amplitude and frequency (module docstring)."""

    #: Amplitudes of the scan per decade (each continued from the last), and the bracket [log]
    #: the search stops at (the exponents' real parts are exact to about 1e-10 of the rates).
    per_decade, bracket = 8, 1e-9

    def __init__(self, case):
        rotor = case.rotor
        self.case = case
        self.laws = [e.law if e is not None else None for e in rotor.lag_laws]
        n = self.n = rotor.n_blades
        self.working = [k for k in range(n) if self.laws[k] is not None]
        if not self.working:
            raise ValueError("limit cycles need a blade with a damper law")
        self.sprung = [k for k in self.working if self.laws[k].law in SPRUNG]
        trimmed = solver_for(case, Method.FLOQUET).system  # (in air: the small-motion trim, held)
        unit = trimmed.mass_unit
        # (a law whose equivalent stiffness is constant keeps it in the equations themselves)
        held = [
            0.0 if law is None or k in self.sprung else float(describing.equivalent(law, 0.0, 1.0)[1])
            for k, law in enumerate(self.laws)
        ]

        def built(damping, stiffness):
            equations = rotor.equivalent(list(damping), list(stiffness))
            return System(*unit.scale(equations, case.body), unit).holding_trim_of(trimmed)

        eye, zeros = np.eye(n), np.zeros(n)
        base = built(zeros, held)
        self.system = base.split_damping(
            [built(eye[k], held) for k in self.working], [built(zeros, held + eye[k]) for k in self.sprung]
        )
        self.symmetry = Symmetry(n, 2 * math.pi, np.eye(self.system.size))
        self.speeds = None
        self._memory = None  # (speed index, log amplitude, shares, frequencies) of the points solved

    def prepare(self, speeds):
        """Hold ``speeds`` [rad/s] for :meth:`scan` and :meth:`neutrality`."""
        self.speeds = np.asarray(speeds, dtype=float)
        self._memory = None

    def scan(self, amplitudes):
        """g at every speed held and every amplitude, (n_s, n_a): amplitude after amplitude, all
        speeds in one batch, each point continued from the amplitude before it."""
        n_s = len(self.speeds)
        at = np.arange(n_s)
        out = np.empty((n_s, len(amplitudes)))
        guess = None
        for i, a in enumerate(amplitudes):
            out[:, i], state = self.neutrality(at, np.full(n_s, a), guess, sign_only=True)
            guess = state["shares"], state["frequencies"]
        return out

    def _guess(self, at, amplitudes):
        """Shares and frequencies to start from: the nearest amplitude solved at the same speed,
        or (none solved) equal shares at each blade's own lag frequency."""
        speeds = self.speeds[at]
        blades = self.case.rotor.blades
        freq = np.stack([b.lag_frequency(speeds) * speeds for b in blades], axis=1)
        shares = np.ones((len(at), self.n))
        if self._memory is None:
            return shares, freq
        where, logs, known_shares, known_freq = self._memory
        key = np.log(amplitudes)
        order = np.lexsort((logs, where))
        where, logs = where[order], logs[order]
        # (one sorted key per point: speed index first, then log amplitude)
        span = max(1.0, float(np.abs(logs).max()), float(np.abs(key).max())) * 4 + 1
        sorted_keys = where * span + logs
        wanted = at * span + key
        right = np.clip(np.searchsorted(sorted_keys, wanted), 0, len(order) - 1)
        left = np.clip(right - 1, 0, len(order) - 1)
        nearer = np.where(
            (where[left] == at) & (np.abs(sorted_keys[left] - wanted) < np.abs(sorted_keys[right] - wanted)),
            left,
            right,
        )
        found = where[nearer] == at
        pick = order[nearer]
        shares[found], freq[found] = known_shares[pick[found]], known_freq[pick[found]]
        return shares, freq

    def _remember(self, at, amplitudes, shares, frequencies):
        entry = (at, np.log(amplitudes), shares, frequencies)
        if self._memory is None:
            self._memory = entry
        else:
            self._memory = tuple(np.concatenate([old, new]) for old, new in zip(self._memory, entry))

    def _values(self, amplitudes, shares, frequencies, speeds):
        """Each blade's equivalent damping and stiffness (m, N) [SI] (NaN without a law)."""
        damping = np.full(shares.shape, np.nan)
        stiffness = np.full(shares.shape, np.nan)
        slowest = SLOWEST * speeds
        for k in self.working:
            damping[:, k], stiffness[:, k] = describing.equivalent(
                self.laws[k], amplitudes * shares[:, k], np.maximum(frequencies[:, k], slowest)
            )
        return damping, stiffness

    def neutrality(self, at, amplitudes, guess=None, sign_only: bool = False):
        """g at the points (speed index ``at``, amplitude [rad] of the blade that moves most),
        each blade's share and frequency iterated to the least stable root's (each point until
        its own settle, :func:`_settle`); and the state of the last step at every point.

        ``sign_only``: a point also stops once its unknowns move by at most :data:`LOOSE` and its
        g keeps its sign beyond doubt (its size ten times its last change), and the transition
        matrices are integrated to the scan's tolerance
        (:data:`groundres.solve.floquet.exponents.SCAN_TOLERANCE`): all a scan needs (the search
        evaluates the ends of each sign change again, in full).
        """
        at, amplitudes = np.asarray(at), np.asarray(amplitudes, dtype=float)
        shares, freq = self._guess(at, amplitudes) if guess is None else (guess[0].copy(), guess[1].copy())
        speeds = self.speeds[at]
        state = {}

        def step(active, x):
            share, frequency = _split(x, self.n)
            values = self._values(amplitudes[active], share, frequency, speeds[active])
            found = self._least_stable(*values, speeds[active], sign_only)
            for key, value in found.items():
                state.setdefault(key, np.zeros((len(at),) + value.shape[1:], value.dtype))[active] = value
            return _joined(found["shares"], found["frequencies"]), found["root"].real

        x = _settle(step, _joined(shares, freq), sign_only)
        shares, freq = _split(x, self.n)
        state["damping"], state["stiffness"] = self._values(amplitudes, shares, freq, speeds)
        self._remember(at, amplitudes, shares, freq)
        return state["root"].real, state

    def small_motion(self):
        """g of small motion at every speed held: each law at its slope at rest (the linear
        analysis's damper), (n_s,)."""
        damping = np.full((len(self.speeds), self.n), np.nan)
        stiffness = damping.copy()
        for k in self.working:
            damping[:, k], stiffness[:, k] = self.laws[k].small_motion()
        return self._least_stable(damping, stiffness, self.speeds)["root"].real

    def _least_stable(self, damping, stiffness, speeds, rough: bool = False) -> dict:
        """The Floquet root with lag motion of largest real part at every point, each blade's law
        replaced by its ``damping`` and ``stiffness`` (m, N) [SI], with its blades' spectra."""
        system = self.system
        values = np.concatenate([damping[:, self.working], stiffness[:, self.sprung]], axis=1)
        # (without the lifted problem: the least stable roots, the only ones the search reads, are
        # resolved whatever the most damped do; a slow rotor's lifted problem costs twenty times more)
        options = {"tolerance": exponents.SCAN_TOLERANCE} if rough else {}  # (a scan needs signs)
        fs = exponents.solve(
            system, speeds, damping=values, sym=self.symmetry, harmonics=HARMONICS, lift=False, **options
        )
        coords = system.multiblade_coordinates()
        lag = np.array([c.kind == "lag" for c in coords])
        size = np.abs(fs.harmonics).max(axis=2)  # (m, n, roots)
        has_lag = size[:, lag, :].max(axis=1) > LAG_SHARE * size.max(axis=1)
        # (of a conjugate pair, the root of positive frequency, as the multiblade route takes)
        upper = fs.exponent.imag >= 0
        score = np.where(has_lag & upper, fs.exponent.real, np.where(has_lag, -1e300, -np.inf))
        j = np.argmax(score, axis=1)
        rows = np.arange(len(j))
        root = fs.exponent[rows, j]
        harmonics = fs.harmonics[rows, :, :, j]  # (m, n, H)
        spectra = blade_spectra(system, harmonics, fs.orders, root.imag, speeds)
        self.orders = fs.orders  # (the harmonics' orders: the same at every point)
        largest = spectra[0].max(axis=1, keepdims=True)
        n = system.size
        vector = fs.vector[rows, :, j]  # (m, 2n): [q; dq/dpsi] at t = 0
        start = np.concatenate([vector[:, :n], speeds[:, None] * vector[:, n:]], axis=1)
        return {
            "root": root,
            "harmonics": harmonics,
            "start": start,
            "spectra": np.stack(spectra, axis=1),  # (m, 4, N)
            "shares": spectra[0] / np.maximum(largest, 1e-300),
            "frequencies": spectra[1],
        }

    def cycle(self, speed, amplitude, stable, state, j):
        """The cycle at point ``j`` of the last state, scaled to ``amplitude``."""
        return make_cycle(
            self.system,
            speed,
            amplitude,
            stable,
            state["root"][j],
            tuple(state["spectra"][j]),
            state["harmonics"][j],
            state["start"][j],
            [law is not None for law in self.laws],
            state["damping"][j],
            state["stiffness"][j],
            self.orders,
        )


def _joined(shares, frequencies):
    """The fixed point's unknowns: shares, then log frequencies, (m, 2N)."""
    return np.concatenate([shares, np.log(np.maximum(frequencies, 1e-300))], axis=1)


def _split(x, n):
    return x[:, :n], np.exp(x[:, n:])


def _settle(step, x, sign_only: bool):
    """The fixed point x = G(x) of ``step(active, x) -> (G(x), g)`` at every point, by Anderson
    acceleration of depth :data:`DEPTH` (Walker and Ni 2011, "Anderson acceleration for
    fixed-point iterations"): each point until its unknowns move by at most :data:`SHARE_TOL`,
    or (``sign_only``) its g keeps its sign beyond doubt; at most :data:`ITERATIONS` steps
    (:data:`SCAN_ITERATIONS` with ``sign_only``). Returns, at every point, the x its last step
    was evaluated at (the state ``step`` left describes that x; a point stopped by the step limit
    is not moved on to an x nobody evaluated). Shares (the first half of x) stay in [0, 1]."""
    x = x.copy()
    evaluated = x.copy()
    n = x.shape[1] // 2
    active = np.arange(len(x))
    values, residuals = [], []  # (the last steps' G(x) and G(x) - x at every point)
    g_last = np.full(len(x), np.nan)
    for _ in range(SCAN_ITERATIONS if sign_only else ITERATIONS):
        mapped, g = step(active, x[active])
        evaluated[active] = x[active]
        full_mapped = np.full(x.shape, np.nan)
        full_mapped[active] = mapped
        residual = full_mapped - x
        values, residuals = (values + [full_mapped])[-DEPTH - 1 :], (residuals + [residual])[-DEPTH - 1 :]
        moved = np.abs(residual[active]).max(-1)
        settled = moved <= SHARE_TOL
        if sign_only:
            settled |= (moved <= LOOSE) & (np.abs(g) > 10 * np.abs(g - g_last[active]))
        g_last[active] = g
        new = mapped.copy()  # (the shares are clipped below: not the step's own array)
        if len(residuals) > 1:  # (the combination of the last steps whose residual is least)
            d_f = np.stack([residuals[i + 1] - residuals[i] for i in range(len(residuals) - 1)], -1)[active]
            d_g = np.stack([values[i + 1] - values[i] for i in range(len(values) - 1)], -1)[active]
            gram = np.einsum("pdi,pdj->pij", d_f, d_f)
            gram += 1e-12 * np.trace(gram, axis1=1, axis2=2)[:, None, None] * np.eye(gram.shape[-1]) + 1e-300
            gamma = np.linalg.solve(gram, np.einsum("pdi,pd->pi", d_f, residual[active])[..., None])[..., 0]
            new = mapped - np.einsum("pdi,pi->pd", d_g, gamma)
            new = np.where(np.isfinite(new).all(-1, keepdims=True), new, mapped)
        new[:, :n] = np.clip(new[:, :n], 0.0, 1.0)  # (an extrapolated share outside [0, 1] means nothing)
        x[active] = np.where(settled[:, None], mapped, new)
        active = active[~settled]
        if not len(active):
            break
    return evaluated
