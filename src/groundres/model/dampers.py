"""Lag damper rods: from a blade to the hub, to the next blade, or to the next but one.

A rod runs between a point on blade k (``start_x``, ``start_y``, ``start_z``:
from its hinge along the span, towards the leading edge, up, in the blade's
axes) and a point on the hub (``end_*`` from the rotor centre, in the axes
of blade k at rest) or on blade k + j (``end_*`` from that blade's hinge, in
its own axes), j = 1 (``blade-to-blade``) or 2 (``blade-to-next-but-one``).
Blade k + j is the one 2 pi j / N ahead in the rotor's turn. A damper of
coefficient c [N s/m] along the rod dissipates (c/2) l'^2 and a rod spring k
[N/m] stores (k/2) (l - l_0)^2, with l the rod's length as the blades lag and
flap: they add c g g' to the damping matrix and k g g' to the stiffness, g
the gradient of l at rest (:func:`groundres.symbolic.derive.derive_rod`).
Both ends turn with the rotor and move with the body together, so only the
blades' own angles change the length, and the matrices are constant in the
blades' (rotating) coordinates.

A rod between mirror-image points of two blades acts on their relative lag
alone (g = (g, -g)): it leaves collective lag undamped and damps the cyclic
lag of order n by 2 (1 - cos(2 pi n j / N)) c g^2 per blade. Attached at
different distances from the two hinges it adds a small collective part.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import ParameterError
from .validate import lengths, non_negative

#: Damper kinds and the blades each spans (0: to the hub).
KINDS = {"blade-to-hub": 0, "blade-to-blade": 1, "blade-to-next-but-one": 2}
GEOMETRY = ("start_x", "start_y", "start_z", "end_x", "end_y", "end_z")
#: A rod shorter than this fraction of its attachments' distance from the shaft has coincident ends.
COINCIDENT = 1e-9


@dataclass(frozen=True)
class Damper:
    """One damper rod starting at blade ``blade`` (1-based); see the module for the geometry.

    Parameters
    ----------
    blade : int
        The blade the rod starts at.
    kind : str
        One of :data:`KINDS`.
    damping : float
        Damping along the rod [N s/m].
    stiffness : float
        Stiffness along the rod [N/m].
    start_x, start_y, start_z, end_x, end_y, end_z : float
        The two ends [m].
    """

    blade: int
    kind: str
    damping: float = 0.0
    stiffness: float = 0.0
    start_x: float = 0.0
    start_y: float = 0.0
    start_z: float = 0.0
    end_x: float = 0.0
    end_y: float = 0.0
    end_z: float = 0.0

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ParameterError("kind", self.kind, f"must be one of {list(KINDS)}")
        non_negative(self, "damping", "stiffness")
        lengths(self, *GEOMETRY)

    @property
    def span(self) -> int:
        """Blades from start to end (0: the end is on the hub)."""
        return KINDS[self.kind]

    def blades(self, n_blades: int) -> tuple:
        """0-based indices of the blade(s) the rod joins: (k,) or (k, k + j)."""
        k = self.blade - 1
        return (k,) if self.span == 0 else (k, (k + self.span) % n_blades)

    def turned(self, shift: int, n_blades: int) -> Damper:
        """The same rod starting ``shift`` blades further on."""
        return replace(self, blade=(self.blade - 1 + shift) % n_blades + 1)

    def gradient(self, offsets, n_blades: int) -> np.ndarray:
        """Gradient of the rod's length at rest: (lag, flap) of each blade it joins, (2 or 4,).

        ``offsets``: every blade's hinge offset [m].
        """
        from ..symbolic.codegen import generated

        ends = {name: getattr(self, name) for name in GEOMETRY}
        k = self.blade - 1
        if self.span == 0:
            return generated("rod_to_hub")(hinge_offset=offsets[k], **ends)
        other = (k + self.span) % n_blades
        return generated("rod_to_blade")(
            hinge_offset=offsets[k],
            end_hinge_offset=offsets[other],
            spacing=2 * math.pi * self.span / n_blades,
            **ends,
        )

    def length(self, offsets, n_blades: int) -> float:
        """The rod's length at rest [m]."""
        k = self.blade - 1
        start = np.array([offsets[k] + self.start_x, self.start_y, self.start_z])
        end = np.array([self.end_x, self.end_y, self.end_z])
        if self.span:
            angle = 2 * math.pi * self.span / n_blades
            c, s = math.cos(angle), math.sin(angle)
            x = offsets[(k + self.span) % n_blades] + end[0]
            end = np.array([c * x - s * end[1], s * x + c * end[1], end[2]])
        return float(np.linalg.norm(start - end))

    def check(self, offsets, n_blades: int) -> None:
        """ParameterError for a rod this rotor cannot have (no such blade, ends on one blade,
        ends that coincide)."""
        if isinstance(self.blade, bool) or not isinstance(self.blade, int) or not 1 <= self.blade <= n_blades:
            raise ParameterError("blade", self.blade, f"must be a blade of the rotor, 1 to {n_blades}")
        if self.span and self.span % n_blades == 0:
            raise ParameterError(
                "kind", self.kind, f"joins blade {self.blade} to itself on a rotor of {n_blades} blades"
            )
        scale = max(abs(offsets[self.blade - 1]) + abs(self.start_x), abs(self.end_x), 1e-300)
        if self.length(offsets, n_blades) <= COINCIDENT * scale:
            raise ParameterError(
                "end_x", self.end_x, f"the rod's two ends coincide (blade {self.blade}): it has no length"
            )


def matrices(rotor, n_body: int, flap: bool) -> np.ndarray:
    """Damping and stiffness of the rotor's damper rods on the blade coordinates
    (body, then lag of blades 1..N, then flap): (2, n, n)."""
    n_blades = rotor.n_blades
    kinds = 2 if flap else 1
    n = n_body + kinds * n_blades
    out = np.zeros((2, n, n))
    offsets = [b.hinge_offset for b in rotor.blades]
    for damper in rotor.dampers:
        g = damper.gradient(offsets, n_blades).reshape(-1, 2)  # (blades, (lag, flap))
        index, value = [], []
        for blade, (lag, flap_part) in zip(damper.blades(n_blades), g):
            index.append(n_body + blade)
            value.append(lag)
            if flap:
                index.append(n_body + n_blades + blade)
                value.append(flap_part)
        outer = np.outer(value, value)
        ix = np.ix_(index, index)
        out[0][ix] += damper.damping * outer
        out[1][ix] += damper.stiffness * outer
    return out


DAMPER_KEYS = tuple(f.name for f in fields(Damper) if f.name != "blade")
