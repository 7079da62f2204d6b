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

from ..model.units import SPEED_UNITS
from ..results.comparison import overlaps

#: Largest difference of a range end from the paper's, in units of the reference speed, that
#: still agrees: the paper gives its ends to 0.05-0.1 (read off its plots), so 0.06 is half a
#: reading step plus the spread of reading a plotted curve.
RANGE_TOLERANCE = 0.06
#: Largest in-phase part of a rate (as a fraction of the rate) that counts as "90 degrees out
#: of phase": the undamped cases' neutral modes have exactly zero up to round-off.
QUADRATURE_TOLERANCE = 1e-6
#: The verdict words, and how a page colours them.
WORDS = {"agrees": "agrees", "agrees in kind": "partly", "differs": "differs", "nothing to compare": "none"}


@dataclass
class Verdict:
    """How a computed figure compares with the paper's statement."""

    word: str  # one of WORDS
    computed: str  # what groundres finds, in words and numbers
    reason: str  # why the verdict is what it is

    @property
    def css(self) -> str:
        return WORDS[self.word]


def ratio_ranges(result) -> list[tuple[float, float]]:
    """The unstable ranges in units of the reference speed."""
    ref = result.case.sweep.reference
    return [(s / ref, e / ref) for s, e in result.stability.unstable_ranges]


def ranges_text(ranges) -> str:
    if not ranges:
        return "stable over the whole sweep"
    parts = [f"{s:.3f} to {e:.3f}" for s, e in ranges]
    return f"unstable from {' and from '.join(parts)} times the reference speed"


def compare_ranges(expected, result, chosen: str = "") -> Verdict:
    """The paper's ranges (units of the reference speed) against the computed ones.

    "agrees": as many ranges, each end within :data:`RANGE_TOLERANCE`;
    "agrees in kind": as many ranges, each overlapping the paper's and grown
    by the regressive lag mode (the coalescence the paper describes), the ends
    elsewhere because the case chose ``chosen`` (what the paper does not
    give); "differs" otherwise. A stability claim agrees when both are stable.
    """
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
            "differs", computed, f"The paper shows {len(expected)} range(s), groundres {len(found)}."
        )
    worst = max(max(abs(a - c), abs(b - d)) for (a, b), (c, d) in zip(expected, found))
    if worst <= RANGE_TOLERANCE:
        return Verdict(
            "agrees",
            computed,
            f"The same number of ranges; every end within {worst:.3f} of the paper's "
            f"(tolerance {RANGE_TOLERANCE:g}: the paper's ends are read off its plots to 0.05-0.1).",
        )
    modes = [result.unstable_modes(s, e) for s, e in result.stability.unstable_ranges]
    apart = [i + 1 for i, (p, f) in enumerate(zip(expected, found)) if not overlaps(p, f)]
    other = [
        i + 1 for i, m in enumerate(modes) if "regressive lag" not in m and not any("body" in x for x in m)
    ]
    if apart or other or not chosen:
        why = []
        if apart:
            why.append(f"range {', '.join(map(str, apart))} does not overlap the paper's")
        if other:
            why.append(f"range {', '.join(map(str, other))} is grown by another mode")
        if not chosen:
            why.append("the case takes the paper's configuration, so the ends should match")
        return Verdict(
            "differs",
            computed,
            f"An end differs by {worst:.2f} times the reference speed: " + "; ".join(why) + ".",
        )
    return Verdict(
        "agrees in kind",
        computed,
        f"As many ranges as the paper, each overlapping the paper's and grown by the regressive lag mode "
        f"meeting the body modes, but an end differs by up to {worst:.2f} times the reference speed: the "
        f"case had to choose {chosen}.",
    )


def in_phase_text(part: float) -> str:
    """The in-phase part of the rates in words: round-off is never printed as a number."""
    if abs(part) <= QUADRATURE_TOLERANCE:
        return "every rate 90 degrees ahead of its displacement"
    return f"every rate with an in-phase part of {part:+.3f} of it"


def phasor_verdict(cells: list[dict]) -> Verdict:
    """The paper's phasor statement against the computed in-phase parts below, inside and above.

    In an eigenvector each rate is lambda times its displacement, so every
    coordinate's rate has the same in-phase part, cos(arg lambda) = Re lambda /
    abs(lambda): zero for a neutral root, positive for a growing one. The
    paper's observation therefore says that the roots are neutral outside the
    instability and grow inside it; that is what is checked, by the phasors.
    """
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
    quiet = all(abs(c["in_phase"]) <= QUADRATURE_TOLERANCE for c in outside)
    feeds = all(c["in_phase"] > QUADRATURE_TOLERANCE and c["state"] == "growing" for c in inside)
    if quiet and feeds:
        return Verdict(
            "agrees",
            text,
            "Outside the instability every rate is 90 degrees ahead of its displacement (in-phase part "
            f"under {QUADRATURE_TOLERANCE:g} of the rate: round-off); inside it the growing mode's "
            "rates have an in-phase part. In an eigenvector every rate is lambda times its displacement, "
            "so this is the same statement as: neutral roots outside the instability, a growing one "
            "inside (the undamped "
            "case has nothing else); how the blades and body share the motion shows in the pictures.",
        )
    return Verdict(
        "differs", text, "The rates' phases do not follow the paper's statement (see the numbers)."
    )


def smeared_case(case):
    """The case with every blade's lag damper set to the blades' average: the constant-coefficient
    ("smeared damper") approximation that Hammond (1974) sets against Floquet analysis."""
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
    """The in-phase part of the rates (fraction of the rate, signed: positive feeds the motion), the
    largest in size over the coordinates that move (over 0.1 % of the reference coordinate)."""
    parts = [p.in_phase for p in shape.phasors("nonrotating") if abs(p.displacement) > 1e-3]
    return max(parts, key=abs, default=0.0)


def other_frame(frame: str) -> str:
    return "rotating" if frame == "nonrotating" else "nonrotating"


def speeds_si(fig, case) -> list[float]:
    """A phasor figure's speeds [rad/s] (given in the case's unit)."""
    unit = SPEED_UNITS[case.sweep.unit]
    return [s * unit for s in fig.speeds]
