"""Mode shapes: phasors of every coordinate and of its rate, whirl, motion in time.

A mode of a time-invariant system moves every coordinate as Re(a e^(lambda t));
a mode of a periodic system as e^(lambda t) times a periodic function, i.e. a
sum of harmonics a_m e^((lambda + i m Omega) t). The phasor of a coordinate in a
frame is its complex amplitude at the harmonic that dominates the mode in that
frame (the one its frequency was identified from); the rate phasor is that
amplitude times lambda + i m Omega. For a neutral mode every rate leads its
displacement by exactly 90 degrees; a growing mode's rate has a component in
phase with the displacement, of relative size ``Re(lambda)/|lambda|`` (the seed
paper's observation: the in-phase part is the energy exchange that feeds the
instability).

Phases are measured from the coordinate of largest kinetic weight
(sqrt(mass) x amplitude), so they do not depend on how the eigenvector was
scaled.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import mbc


@dataclass(frozen=True)
class Phasor:
    """One coordinate of a mode in one frame.

    Attributes
    ----------
    name : str
        Coordinate, e.g. "x", "lag_1c", "lag blade 2", "x_r" (rotating axes).
    kind : str
        "body", "lag" or "flap".
    displacement, rate : complex
        Amplitudes, scaled so that the reference coordinate's displacement is
        1 (unit: m for translations, rad for angles; rates per second).
    """

    name: str
    kind: str
    displacement: complex
    rate: complex

    @property
    def rate_lead(self) -> float:
        """Phase of the rate relative to the displacement [deg], in (-180, 180]."""
        if self.displacement == 0:
            return float("nan")
        return float(np.degrees(np.angle(self.rate / self.displacement)))

    @property
    def in_phase(self) -> float:
        """Part of the rate in phase with the displacement, as a fraction of ``|rate|``."""
        return float(np.cos(np.radians(self.rate_lead)))

    @property
    def quadrature(self) -> float:
        """Part of the rate 90 degrees ahead of the displacement, as a fraction of ``|rate|``."""
        return float(np.sin(np.radians(self.rate_lead)))

    @property
    def unit(self) -> str:
        """Unit of the displacement (:func:`groundres.model.mbc.unit_of`)."""
        return mbc.unit_of(self.kind, self.name)

    def as_dict(self) -> dict:
        """The phasor as numbers (phases [deg]; NaN where the displacement is zero);
        :data:`PHASOR_UNITS` gives the unit of each entry."""
        return {
            "coordinate": self.name,
            "kind": self.kind,
            "unit": self.unit,
            "displacement_amplitude": float(abs(self.displacement)),
            "displacement_phase_deg": float(np.degrees(np.angle(self.displacement))),
            "rate_amplitude": float(abs(self.rate)),
            "rate_phase_deg": float(np.degrees(np.angle(self.rate))),
            "rate_lead_deg": self.rate_lead,
            "rate_quadrature_fraction": self.quadrature,
            "rate_in_phase_fraction": self.in_phase,
        }


#: Unit of each numeric entry of :meth:`Phasor.as_dict` (displacements in the
#: coordinate's ``unit``, scaled so that the reference coordinate's is 1).
PHASOR_UNITS = {
    "displacement_amplitude": "m or rad",
    "displacement_phase_deg": "deg",
    "rate_amplitude": "m/s or rad/s",
    "rate_phase_deg": "deg",
    "rate_lead_deg": "deg",
    "rate_quadrature_fraction": "-",
    "rate_in_phase_fraction": "-",
}


def phasor_header(keys) -> list[str]:
    """CSV column names with their units, e.g. ``rate_lead_deg [deg]``."""
    return [f"{k} [{PHASOR_UNITS[k]}]" if k in PHASOR_UNITS else k for k in keys]


@dataclass
class ModeShape:
    """One mode at one rotor speed.

    Attributes
    ----------
    label : str
    rotor_speed : float
        [rad/s].
    eigenvalue : complex
        Root with its frequency seen from nonrotating axes [1/s].
    coordinates : list of Coordinate
        Nonrotating coordinates (body, multiblade).
    harmonics : complex ndarray (n, M)
        Amplitude of each coordinate at eigenvalue + i orders[m] Omega.
    orders : int ndarray (M,)
        Harmonic orders relative to the identified one (0).
    weights : ndarray (n,)
        Kinetic weight (mass-matrix diagonal) of each coordinate.
    n_blades : int
    cg_arm : float
        Blade static moment over blade mass, S/m [m]: the arm of the blade's
        centre of mass about its hinge.
    hub_height : float
        [m].
    hub_x, hub_y : float
        The hub centre's other coordinates from the pivot [m].
    rotating_frequency : float, optional
        The mode's frequency seen from rotating axes [rad/s] as identified
        (:mod:`groundres.modes.identify`): the rotating-frame phasors are taken at
        the harmonic with that frequency, so that they and the Coleman
        diagram name the same motion.
    """

    label: str
    rotor_speed: float
    eigenvalue: complex
    coordinates: list
    harmonics: np.ndarray
    orders: np.ndarray
    weights: np.ndarray
    n_blades: int
    cg_arm: float
    hub_height: float
    rotating_frequency: float | None = None
    hub_x: float = 0.0
    hub_y: float = 0.0

    def _hub(self, sym: dict, zero=0):
        """The hub centre's displacement in x and y: the pivot's translation plus the body's
        rotation (roll, -pitch, yaw) times the hub's position from the pivot."""
        h, pitch, roll, yaw = (
            self.hub_height,
            sym.get("pitch", zero),
            sym.get("roll", zero),
            sym.get("yaw", zero),
        )
        return sym.get("x", zero) - h * pitch - self.hub_y * yaw, sym.get(
            "y", zero
        ) - h * roll + self.hub_x * yaw

    @property
    def unstable(self) -> bool:
        from ..assess.stability import growth_threshold

        return self.eigenvalue.real > growth_threshold(self.rotor_speed)

    @property
    def neutral(self) -> bool:
        """Real part within the growth threshold of zero (round-off: neither grows nor decays)."""
        from ..assess.stability import is_neutral

        return bool(is_neutral(self.eigenvalue.real, self.rotor_speed))

    @property
    def state(self) -> str:
        """ "growing", "neutral" or "decaying", by the growth threshold."""
        return "growing" if self.unstable else ("neutral" if self.neutral else "decaying")

    @property
    def vector(self) -> np.ndarray:
        """Amplitudes at the identified harmonic (the nonrotating mode shape)."""
        return self.harmonics[:, int(np.flatnonzero(self.orders == 0)[0])]

    def _reference(self, amplitudes, weights):
        k = int(np.argmax(np.sqrt(weights) * np.abs(amplitudes)))
        return amplitudes[k] if amplitudes[k] != 0 else 1.0

    def phasors(self, frame: str = "nonrotating") -> list[Phasor]:
        """Phasors of every coordinate and its rate in "nonrotating" or "rotating" axes.

        Nonrotating: body coordinates and multiblade coordinates. Rotating:
        each blade, and the body translations and tilts in rotating axes.
        """
        if frame == "nonrotating":
            amp, weights = self.vector, self.weights
            root = self.eigenvalue
            names = [(c.symbol, c.kind) for c in self.coordinates]
        elif frame == "rotating":
            amp, weights, shift, names = self._rotating_view()
            root = self.eigenvalue + 1j * shift * self.rotor_speed
        else:
            raise ValueError(f"frame = {frame!r}: must be 'nonrotating' or 'rotating'")
        if root.imag < 0:  # the same real motion, written with a positive frequency
            amp, root = amp.conj(), root.conjugate()
        amp = amp / self._reference(amp, weights)
        return [Phasor(n, k, complex(a), complex(root * a)) for (n, k), a in zip(names, amp)]

    def _rotating_view(self, samples: int = 64):
        """Dominant harmonic of the motion seen from rotating axes (blades, body axes turning)."""
        psi = 2 * np.pi * np.arange(samples) / samples
        periodic = np.einsum("jm,ms->sj", self.harmonics, np.exp(1j * np.outer(self.orders, psi)))
        q, names, weights = self._to_rotating(periodic, psi)
        shifts = np.arange(-(samples // 2) + 1, samples // 2)
        coeff = np.einsum("sj,ks->kj", q, np.exp(-1j * np.outer(shifts, psi))) / samples
        energy = (np.abs(coeff) ** 2 * weights).sum(-1)
        best = int(np.argmax(energy))
        if self.rotating_frequency is not None:
            # the harmonic the identification chose (the most energetic one at that frequency)
            freq = np.abs(self.eigenvalue.imag + shifts * self.rotor_speed)
            match = np.abs(freq - self.rotating_frequency) <= 1e-6 * max(self.rotor_speed, freq.max())
            if match.any():
                best = int(np.argmax(np.where(match, energy, -1.0)))
        return coeff[best], weights, int(shifts[best]), names

    def _to_rotating(self, p, psi):
        """Nonrotating coordinates (samples, n) -> blades and rotating body axes."""
        coords = self.coordinates
        n = self.n_blades
        body = [i for i, c in enumerate(coords) if c.kind == "body"]
        out, names, weights = [], [], []
        index = {c.name: i for i, c in enumerate(coords) if c.kind == "body"}
        for a, b in (("x", "y"), ("pitch", "roll")):
            if a in index and b in index:
                xa, xb = p[:, index[a]], p[:, index[b]]
                c, s = np.cos(psi), np.sin(psi)
                out += [c * xa + s * xb, -s * xa + c * xb]
                names += [(f"{a}_r", "body"), (f"{b}_r", "body")]
                weights += [self.weights[index[a]], self.weights[index[b]]]
            else:
                for d in (a, b):
                    if d in index:
                        out.append(p[:, index[d]])
                        names.append((d, "body"))
                        weights.append(self.weights[index[d]])
        for d in ("z", "yaw"):  # (turned about the shaft they stay as they are)
            if d in index:
                out.append(p[:, index[d]])
                names.append((d, "body"))
                weights.append(self.weights[index[d]])
        basis, _, _ = mbc.multiblade_basis(n, psi)  # (samples, N blades, N coords)
        for kind in ("lag", "flap"):
            cols = [i for i, c in enumerate(coords) if c.kind == kind]
            if not cols:
                continue
            blades = np.einsum("skj,sj->sk", basis, p[:, cols])
            weight = self.weights[cols[0]] / n  # collective row weight is N I
            for k in range(n):
                out.append(blades[:, k])
                names.append((f"{kind} blade {k + 1}", kind))
                weights.append(weight)
        assert len(body) <= len(out)
        return np.stack(out, -1), names, np.array(weights)

    def whirl(self) -> dict:
        """Collective, forward- and backward-whirl content of the rotor, and the
        direction in which the rotor's centre of mass whirls (nonrotating axes).

        With the mode's time dependence exp(i w t), w >= 0, a cyclic pair (a, b)
        = (q_1c, q_1s) splits into a forward whirl (a + i b)/2, turning with the
        rotor, and a backward whirl (a - i b)/2. The rotor's centre of mass is
        the hub's displacement plus the shift the lag motion gives it,
        (S/(2m)) (lag_1s, -lag_1c); it whirls forward when its forward part is
        the larger. Its ``frequency`` is in rad/s (``frequency_unit``).
        """
        amp = self.vector / self._reference(self.vector, self.weights)
        sym = {c.symbol: a for c, a in zip(self.coordinates, amp)}
        out = {}
        for kind in ("lag", "flap"):
            if f"{kind}_0" not in sym:
                continue
            entry = {"collective": _polar(sym[f"{kind}_0"])}
            if f"{kind}_1c" in sym:
                a, b = sym[f"{kind}_1c"], sym[f"{kind}_1s"]
                entry["forward_whirl"] = _polar((a + 1j * b) / 2)
                entry["backward_whirl"] = _polar((a - 1j * b) / 2)
            if f"{kind}_d" in sym:
                entry["differential"] = _polar(sym[f"{kind}_d"])
            out[kind] = entry
        x, y = self._hub(sym)
        if "lag_1c" in sym:
            x = x + self.cg_arm / 2 * sym["lag_1s"]
            y = y - self.cg_arm / 2 * sym["lag_1c"]
        forward, backward = abs(x + 1j * y) / 2, abs(x - 1j * y) / 2
        if max(forward, backward) <= 1e-12 * max(np.abs(amp).max(), 1e-300):
            direction = "none (the rotor centre of mass does not move)"
        else:
            direction = "forward (with the rotor)" if forward >= backward else "backward (against the rotor)"
        out["centre_of_mass"] = {
            "forward_amplitude": float(forward),
            "backward_amplitude": float(backward),
            "direction": direction,
            "frequency": float(abs(self.eigenvalue.imag)),
            "frequency_unit": "rad/s",
        }
        return out

    def motion(self, times):
        """Motion seen from nonrotating axes at ``times`` [s] (real, growth included).

        Returns
        -------
        dict
            "hub": (n_t, 2) hub displacement in x, y [m] (translation and tilt);
            "lag", "flap": (n_t, N) blade angles [rad] (absent kinds omitted);
            "azimuth": (n_t, N) blade azimuths [rad];
            "body": each body coordinate by name, (n_t,) [m, rad].
        """
        t = np.asarray(times, dtype=float)
        w = self.rotor_speed
        p = np.einsum("jm,mt->tj", self.harmonics, np.exp(1j * np.outer(self.orders, w * t)))
        p = (p * np.exp(self.eigenvalue * t)[:, None]).real  # (n_t, n)
        sym = {c.symbol: p[:, i] for i, c in enumerate(self.coordinates)}
        zero = np.zeros_like(t)
        hub = np.stack(self._hub(sym, zero), 1)
        basis, _, _ = mbc.multiblade_basis(self.n_blades, w * t)
        out = {"hub": hub, "azimuth": mbc.blade_azimuths(self.n_blades, w * t)}
        out["body"] = {c.name: p[:, i] for i, c in enumerate(self.coordinates) if c.kind == "body"}
        for kind in ("lag", "flap"):
            cols = [i for i, c in enumerate(self.coordinates) if c.kind == kind]
            if cols:
                out[kind] = np.einsum("tkj,tj->tk", basis, p[:, cols])
        return out


def _polar(z) -> dict:
    return {"amplitude": float(abs(z)), "phase_deg": float(np.degrees(np.angle(z)))}
