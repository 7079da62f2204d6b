"""How a computed figure compares with the seed paper's statement: agrees, agrees in kind, or differs.

Unstable ranges are compared in units of the reference speed (155 rpm)
within :data:`RANGE_TOLERANCE`, a stability verdict directly, and the phasor
figures by the phase of each rate against its displacement. "Agrees in
kind" means the same ranges from the same coalescence with ends elsewhere,
because the paper does not give the parameters. Every verdict carries its
reason.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..params import SPEED_UNITS

#: Largest difference of a range end from the paper's, in units of the reference speed, that
#: still agrees: the paper gives its ends to 0.05-0.1 (read off its plots), so 0.06 is half a
#: reading step plus the spread of reading a plotted curve.
RANGE_TOLERANCE = 0.06
#: Largest in-phase part of a rate (as a fraction of the rate) that counts as "90 degrees out
#: of phase": the undamped cases' neutral modes have exactly zero up to round-off.
QUADRATURE_TOLERANCE = 1e-6


@dataclass
class Verdict:
    """How a computed figure compares with the paper's statement."""

    word: str  # "agrees", "agrees in kind" or "differs"
    computed: str  # what groundres finds, in words and numbers
    reason: str  # why the verdict is what it is

    @property
    def css(self) -> str:
        return {"agrees": "agrees", "agrees in kind": "partly"}.get(self.word, "differs")


def ratio_ranges(result) -> list[tuple[float, float]]:
    """The unstable ranges in units of the reference speed."""
    ref = result.case.sweep.reference
    return [(s / ref, e / ref) for s, e in result.stability.unstable_ranges]


def ranges_text(ranges) -> str:
    if not ranges:
        return "stable over the whole sweep"
    parts = [f"{s:.3f} to {e:.3f}" for s, e in ranges]
    return f"unstable from {' and from '.join(parts)} times the reference speed"


def compare_ranges(expected, result) -> Verdict:
    """The paper's ranges (units of the reference speed) against the computed ones."""
    found = ratio_ranges(result)
    sweep = result.case.sweep
    swept = f"(sweep {sweep.start / sweep.reference:.3g} to {sweep.stop / sweep.reference:.3g})"
    computed = f"{ranges_text(found)} {swept}"
    if not expected:
        if not found:
            return Verdict("agrees", computed, "Both stable: no root grows anywhere in the sweep.")
        return Verdict(
            "differs", computed, "The paper finds no instability; groundres finds the ranges above."
        )
    if len(found) != len(expected):
        return Verdict(
            "differs",
            computed,
            f"The paper shows {len(expected)} range(s), groundres {len(found)}.",
        )
    worst = max(max(abs(a - c), abs(b - d)) for (a, b), (c, d) in zip(expected, found))
    if worst <= RANGE_TOLERANCE:
        return Verdict(
            "agrees",
            computed,
            f"The same number of ranges; every end within {worst:.3f} of the paper's "
            f"(tolerance {RANGE_TOLERANCE:g}: the paper's ends are read off its plots to 0.05-0.1).",
        )
    return Verdict(
        "agrees in kind",
        computed,
        f"The same number of ranges from the same coalescence, but an end differs by up to {worst:.2f} "
        "times the reference speed: the paper does not give this rotor's parameters, so the case's "
        "chosen ones place the ends elsewhere.",
    )


def in_phase_text(part: float) -> str:
    """The largest in-phase part of a rate in words: round-off is never printed as a number."""
    if part <= QUADRATURE_TOLERANCE:
        return "every rate 90 degrees ahead of its displacement"
    return f"rates with an in-phase part of up to {part:.3f}"


def phasor_verdict(cells: list[dict]) -> Verdict:
    """The paper's phasor statement against the computed in-phase parts below, inside and above."""
    text = "; ".join(
        f"{c['where']} ({c['speed_text']}): {c['state']}, {in_phase_text(c['in_phase'])}" for c in cells
    )
    outside = [c for c in cells if c["where"] != "inside"]
    inside = [c for c in cells if c["where"] == "inside"]
    misplaced = [c["where"] for c in cells if c["placed"] is False]
    if misplaced:
        return Verdict(
            "differs",
            text,
            f"The speed chosen {', '.join(misplaced)} the instability is not where its name says.",
        )
    quiet = all(c["in_phase"] <= QUADRATURE_TOLERANCE for c in outside)
    feeds = all(c["in_phase"] > QUADRATURE_TOLERANCE and c["state"] == "growing" for c in inside)
    if quiet and feeds:
        return Verdict(
            "agrees",
            text,
            "Outside the instability every rate is 90 degrees ahead of its displacement (in-phase part "
            f"below {QUADRATURE_TOLERANCE:g} of the rate: round-off); inside it the growing mode's "
            "rates have an in-phase part, as the paper says.",
        )
    return Verdict(
        "differs", text, "The rates' phases do not follow the paper's statement (see the numbers)."
    )


def smeared_case(case):
    """The case with every blade's lag damper set to the blades' average (the constant-coefficient
    approximation Hammond 1974 compares with Floquet analysis)."""
    from dataclasses import replace

    blades = case.rotor.blades
    mean = float(np.mean([b.lag_damping for b in blades]))
    rotor = replace(case.rotor, blades=tuple(replace(b, lag_damping=mean) for b in blades))
    return replace(case, rotor=rotor, title=f"{case.title}, smeared dampers"), mean


def speed_place(w: float, ranges, where: str) -> bool:
    """Whether a speed [rad/s] lies where ``where`` says: "inside" a range, else outside all."""
    inside = any(s <= w <= e for s, e in ranges)
    return inside if where == "inside" else not inside


def in_phase_part(shape) -> float:
    """The largest in-phase part (fraction of the rate) over the coordinates that move (>0.1 %)."""
    parts = [abs(p.in_phase) for p in shape.phasors("nonrotating") if abs(p.displacement) > 1e-3]
    return max(parts, default=0.0)


def other_frame(frame: str) -> str:
    return "rotating" if frame == "nonrotating" else "nonrotating"


def speeds_si(fig, case) -> list[float]:
    """A phasor figure's speeds [rad/s] (given in the case's unit)."""
    unit = SPEED_UNITS[case.sweep.unit]
    return [s * unit for s in fig.speeds]
