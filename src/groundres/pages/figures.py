"""The seed paper's Figures 3 to 13: each figure's caption, statement and the shipped case for it.

The seed paper ("Multibladed rotor helicopter ground resonance including
eigenvector analysis", the project's seed) states its results in words and
rounded numbers ("two instability regions, 0.85-1.2 and 1.3-2.0") for rotors
whose parameters it mostly does not list. Each :class:`Figure` names the
shipped case that stands for it, what the paper says (its caption quoted),
its unstable ranges where it gives numbers, and where the case had to
choose what the paper does not give.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Figure:
    """One of the seed paper's figures and the shipped case that stands for it.

    Attributes
    ----------
    number : int
    caption : str
        The paper's caption, quoted.
    case : str
        Shipped case name.
    kind : str
        "coleman" or "phasors".
    frame : str
        The frame the paper draws ("nonrotating" or "rotating").
    statement : str
        What the paper says of the figure, quoted or closely paraphrased (nothing of groundres's).
    method : str
        "auto", "eigen" or "floquet".
    ranges : tuple or None
        The paper's unstable ranges in units of the reference speed (``()``: the
        paper says stable); None where the paper gives no number.
    configuration_note : str
        Where the case differs from (or is not given by) the paper.
    chosen : str
        What the case had to choose because the paper does not give it (the reason
        an end may lie elsewhere); empty where the paper's configuration is used.
    equals : int or None
        The figure whose analysis this one repeats by another method: the two must
        agree to round-off.
    speeds : tuple
        For phasor figures: (below, inside, above) the instability, in the case's unit.
    """

    number: int
    caption: str
    case: str
    kind: str
    frame: str
    statement: str
    method: str = "auto"
    ranges: tuple | None = None
    configuration_note: str = ""
    chosen: str = ""
    equals: int | None = None
    speeds: tuple = field(default=())


_CHOSEN_ROTOR = "this rotor's parameters (the paper does not list them; the case chooses them)"
_CHOSEN_HUB = (
    "the isotropic hub (the paper does not list it; the case gives it the x properties of Hammond's hub)"
)

FIGURES = (
    Figure(
        3,
        "Articulated isotropic four-bladed rotor, without damping and with anisotropic hub in the "
        "nonrotating frame.",
        "hammond-undamped",
        "coleman",
        "nonrotating",
        "Two instability regions: one between 0.85 and 1.2 and another ranging from 1.3 to 2.0 "
        "(times 155 rpm); the body modes coalesce with the low-frequency lead-lag mode.",
        ranges=((0.85, 1.2), (1.3, 2.0)),
        configuration_note="The paper's reference speed, 155 rpm, is that of Coleman and Feingold "
        "(1958); the "
        "case takes Hammond's (1974) rotor and hub, in SI, with every damper removed.",
    ),
    Figure(
        4,
        "Soft inplane hingeless three-bladed isotropic rotor, without damping and with isotropic hub in the "
        "nonrotating frame.",
        "soft-inplane",
        "coleman",
        "nonrotating",
        "One instability range between 1.2 and 2.4, where the low-frequency lead-lag mode coalesces with "
        "the body modes.",
        ranges=((1.2, 2.4),),
        configuration_note="The paper does not list this rotor's parameters; the case uses a light "
        "helicopter's hingeless blade with nu = 0.6/rev at 155 rpm and a 12 rad/s hub (see the case's "
        "description).",
        chosen=_CHOSEN_ROTOR,
    ),
    Figure(
        5,
        "Stiff inplane hingeless three-bladed isotropic rotor, without damping and with isotropic hub in the "
        "nonrotating frame.",
        "stiff-inplane",
        "coleman",
        "nonrotating",
        "Ground resonance does not take place: the body modes do not coalesce with the low-frequency "
        "lead-lag mode.",
        ranges=(),
        configuration_note="The rotor of Figure 4 with a lag spring ten times stiffer: nu = 1.5/rev "
        "at 155 rpm. "
        "A lag spring makes nu fall as the rotor speeds up (nu^2 = K/(I Omega^2) + e S/I): it passes 1/rev "
        "at 245 rpm (1.58 ref), and the regressive lag mode would meet the body mode at 388 rpm (2.50 ref), "
        "beyond the sweep's 340 rpm (2.19 ref). So the rotor is stable within its sweep, as in the paper; "
        "swept on to 480 rpm it goes unstable from 366 to 416 rpm, soft in plane by then.",
        chosen=_CHOSEN_ROTOR,
    ),
    Figure(
        6,
        "Articulated four-bladed isotropic rotor, with damping and with isotropic hub in the nonrotating "
        "frame.",
        "hammond-1974",
        "coleman",
        "nonrotating",
        "The same basic configuration as Figure 3 with external lead-lag dampers installed on each blade: "
        "the dampers prevent the instability.",
        ranges=(),
        configuration_note="The caption says isotropic hub, the text 'the same basic configuration' "
        "as Figure "
        "3, whose hub is anisotropic; the case is Hammond's (1974) rotor and anisotropic hub with all "
        "dampers working. It damps the hub too (Hammond's landing-gear damping, which the Figure 3 case "
        "leaves out): lag dampers alone cannot stabilise an undamped hub (the Deutsch criterion asks for "
        "the product of the two), so the paper's rotor must have had hub damping too, though it does not "
        "say so.",
    ),
    Figure(
        7,
        "Soft inplane three-bladed isotropic rotor, with damping and with isotropic hub in the nonrotating "
        "frame.",
        "soft-inplane-damped",
        "coleman",
        "nonrotating",
        "An adequate choice of damping frees the helicopter from ground resonance: the modal damping "
        "migrates to the fourth quadrant of the plots.",
        ranges=(),
        configuration_note="The paper gives no damper values; the case damps the gear at 15 % of "
        "critical and "
        "the lag at 1600 N m s/rad, half as much again as the least that keeps this sweep stable.",
        chosen="the dampers",
    ),
    Figure(
        8,
        "Articulated four-bladed anisotropic rotor, with one innoperative damper in the presence of "
        "isotropic "
        "hub in rotating frame.",
        "hammond-one-damper-isotropic",
        "coleman",
        "rotating",
        "One region of instability between 0.9 and 1.4.",
        method="eigen",
        ranges=((0.9, 1.4),),
        configuration_note="Hammond's rotor with blade 1's lag damper inoperative on an isotropic hub, which "
        "the paper does not list: the case gives it the x properties of Hammond's hub in both directions. "
        "With the hub alike in x and y the equations written with the hub in rotating axes have constant "
        "coefficients, so this is an eigen-analysis.",
        chosen=_CHOSEN_HUB,
    ),
    Figure(
        9,
        "Articulated four-bladed anisotropic rotor, with one innoperative damper in the presence of "
        "isotropic "
        "hub in rotating frame, Floquet's analysis.",
        "hammond-one-damper-isotropic",
        "coleman",
        "rotating",
        "The same region of instability as Figure 8, between 0.9 and 1.4, now from Floquet analysis.",
        method="floquet",
        ranges=((0.9, 1.4),),
        configuration_note="The case of Figure 8, analysed by Floquet theory from the periodic equations in "
        "nonrotating axes; the two analyses must agree with each other to round-off.",
        chosen=_CHOSEN_HUB,
        equals=8,
    ),
    Figure(
        10,
        "Articulated four-bladed anisotropic rotor, with one innoperative damper in the presence of "
        "anisotropic "
        "hub in nonrotating frame.",
        "hammond-1974-one-damper",
        "coleman",
        "nonrotating",
        "Floquet analysis is employed for the case where both rotor and hub are anisotropic (the paper "
        "states no range for this figure).",
        configuration_note="Hammond's (1974) rotor and anisotropic hub with blade 1's damper "
        "inoperative: the "
        "equations are periodic in every frame. Hammond reports that the constant-coefficient ('smeared "
        "damper') approximation underestimates this instability; the page shows what that approximation "
        "gives for this case.",
    ),
    Figure(
        11,
        "Phasor diagrams for a three-bladed soft inplane hingeless rotor in the presence of an "
        "isotropic hub in "
        "rotating frame, x and y body modes.",
        "soft-inplane",
        "phasors",
        "nonrotating",
        "For stable rotor speeds the phasors of blade and hub degrees of freedom are 90 degrees out of phase "
        "with their time rates; in the instability regions in-phase or out-of-phase components appear, the "
        "exchange of energy between blades and body.",
        configuration_note="The rotor of Figure 4. The caption says rotating frame, the text nonrotating: "
        "both are drawn (top row nonrotating, bottom row rotating axes).",
        chosen=_CHOSEN_ROTOR,
        speeds=(155.0, 232.5, 325.5),
    ),
    Figure(
        12,
        "Phasor diagrams for a three-bladed soft inplane hingeless rotor in rotating frame, pitch and roll "
        "body modes.",
        "soft-inplane-pitch-roll",
        "phasors",
        "nonrotating",
        "As Figure 11, including pitch and roll body modes: rates 90 degrees out of phase outside the "
        "instability, in-phase components inside it.",
        configuration_note="The blades of Figure 4, flapping too (the paper's first set of equations, with "
        "flap, nu_beta = 1.1/rev), on a body that pitches and rolls about a pivot 1.6 m below the hub; "
        "parameters chosen, not given by the paper.",
        chosen=_CHOSEN_ROTOR,
        speeds=(139.5, 248.0, 372.0),
    ),
    Figure(
        13,
        "Phasor diagrams for a four-bladed articulated rotor in the presence of an anisotropic hub "
        "in rotating "
        "frame.",
        "hammond-undamped",
        "phasors",
        "nonrotating",
        "As Figure 11, for the articulated rotor on an anisotropic hub: rates 90 degrees out of "
        "phase outside "
        "the instability, in-phase components inside it.",
        configuration_note="The case of Figure 3.",
        speeds=(93.0, 248.0, 356.5),
    ),
)

#: The figure numbers, in order.
NUMBERS = tuple(f.number for f in FIGURES)


def figure(number: int) -> Figure:
    """The :class:`Figure` with this number."""
    for f in FIGURES:
        if f.number == number:
            return f
    raise KeyError(number)
