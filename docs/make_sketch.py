"""Draw docs/images/conventions.png (axes and positive directions of groundres) and
docs/images/rods-gear.png (damper rod geometry and a body on gear legs).

Run: python3 docs/make_sketch.py
"""

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Circle, FancyArrowPatch, Rectangle

OUT = Path(__file__).parent / "images" / "conventions.png"
RODS_GEAR = Path(__file__).parent / "images" / "rods-gear.png"


def arrow(ax, start, end, colour="k", **kw):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=14, color=colour, lw=1.6, **kw))


def top_view(ax):
    ax.set_title("top view (z out of the page)", fontsize=10)
    # screen coordinates: x forward points up, y left points left
    to_screen = lambda x, y: (-y, x)  # noqa: E731
    arrow(ax, (0, 0), to_screen(1.35, 0))
    ax.text(*to_screen(1.45, 0.05), "x (forward)", ha="center")
    arrow(ax, (0, 0), to_screen(0, 1.35))
    ax.text(*to_screen(0.08, 1.42), "y (left)", ha="right")
    ax.add_patch(Circle((0, 0), 1.0, fill=False, ls=":", color="0.5"))
    ax.add_patch(Arc((0, 0), 2.3, 2.3, theta1=200, theta2=250, color="tab:blue", lw=1.6))
    arrow(
        ax,
        (1.15 * np.cos(np.radians(246)), 1.15 * np.sin(np.radians(246))),
        (1.15 * np.cos(np.radians(252)), 1.15 * np.sin(np.radians(252))),
        "tab:blue",
    )
    ax.text(-0.95, -0.95, "rotor turns\ncounter-clockwise\n(Omega about +z)", color="tab:blue", fontsize=8)
    psi, zeta, e = np.radians(40), np.radians(14), 0.25
    hinge = np.array(to_screen(e * np.cos(psi), e * np.sin(psi)))
    ref = np.array(to_screen(np.cos(psi), np.sin(psi)))
    ax.plot([0, hinge[0]], [0, hinge[1]], color="k", lw=2.5)
    ax.plot([hinge[0], ref[0]], [hinge[1], ref[1]], color="0.6", lw=1.0, ls="--")
    tip = hinge + 0.75 * np.array(to_screen(np.cos(psi - zeta), np.sin(psi - zeta)))
    ax.plot([hinge[0], tip[0]], [hinge[1], tip[1]], color="tab:red", lw=3)
    ax.add_patch(Arc((0, 0), 0.7, 0.7, theta1=90, theta2=90 + np.degrees(psi), color="k"))
    ax.text(-0.12, 0.48, "psi_k", fontsize=9, ha="right")
    ax.add_patch(
        Arc(hinge, 1.0, 1.0, theta1=90 + np.degrees(psi - zeta), theta2=90 + np.degrees(psi), color="tab:red")
    )
    ax.text(
        tip[0] - 0.05,
        tip[1] + 0.12,
        "lag zeta > 0 (blade falls behind)",
        color="tab:red",
        fontsize=8,
        ha="center",
    )
    ax.text(hinge[0] + 0.05, hinge[1] - 0.12, "hinge, offset e", fontsize=8)
    ax.text(
        0.3,
        1.15,
        "blade k at psi_k = Omega t + 2 pi (k-1)/N,\nmeasured from +x towards +y;\ndashed: blade at zero lag",
        fontsize=8,
        ha="left",
    )


def side_view(ax):
    ax.set_title("side view from the right (y into the page)", fontsize=10)
    arrow(ax, (-1.4, -0.9), (-0.9, -0.9))
    ax.text(-0.88, -0.95, "x", fontsize=9)
    arrow(ax, (-1.4, -0.9), (-1.4, -0.4))
    ax.text(-1.45, -0.35, "z", fontsize=9)
    ax.add_patch(Rectangle((-0.8, -0.35), 1.6, 0.45, fill=False, color="0.4"))
    ax.plot(0, -0.12, "ko")
    ax.text(0.05, -0.22, "pivot (body c.g.)", fontsize=8)
    ax.plot([0, 0], [-0.12, 0.7], "k", lw=2)
    ax.text(0.05, 0.3, "hub_height h", fontsize=8)
    ax.plot([-0.9, 0.9], [0.72, 0.72], color="0.3", lw=2)
    beta = np.radians(12)
    ax.plot([0.15, 0.15 + 0.8 * np.cos(beta)], [0.72, 0.72 + 0.8 * np.sin(beta)], color="tab:green", lw=3)
    ax.text(0.55, 0.95, "flap beta > 0 (up)", color="tab:green", fontsize=8)
    ax.add_patch(Arc((0, -0.12), 0.9, 0.9, theta1=90, theta2=130, color="tab:purple", lw=1.6))
    arrow(
        ax,
        (0.45 * np.cos(np.radians(125)), -0.12 + 0.45 * np.sin(np.radians(125))),
        (0.45 * np.cos(np.radians(131)), -0.12 + 0.45 * np.sin(np.radians(131))),
        "tab:purple",
    )
    ax.text(-0.75, 0.32, "pitch theta > 0:\nnose up,\nhub moves aft", color="tab:purple", fontsize=8)
    ax.text(0.82, -0.3, "nose", fontsize=8)


def rear_view(ax):
    ax.set_title("rear view (x into the page)", fontsize=10)
    arrow(ax, (0.9, -0.9), (0.4, -0.9))
    ax.text(0.35, -0.95, "y", fontsize=9, ha="right")
    arrow(ax, (0.9, -0.9), (0.9, -0.4))
    ax.text(0.92, -0.35, "z", fontsize=9)
    ax.add_patch(Rectangle((-0.6, -0.35), 1.2, 0.45, fill=False, color="0.4"))
    ax.plot(0, -0.12, "ko")
    ax.plot([0, 0], [-0.12, 0.7], "k", lw=2)
    ax.plot([-0.9, 0.9], [0.72, 0.72], color="0.3", lw=2)
    ax.add_patch(Arc((0, -0.12), 0.9, 0.9, theta1=50, theta2=90, color="tab:orange", lw=1.6))
    arrow(
        ax,
        (0.45 * np.cos(np.radians(55)), -0.12 + 0.45 * np.sin(np.radians(55))),
        (0.45 * np.cos(np.radians(49)), -0.12 + 0.45 * np.sin(np.radians(49))),
        "tab:orange",
    )
    ax.text(0.3, 0.3, "roll phi > 0:\nright side down,\nhub moves right", color="tab:orange", fontsize=8)
    ax.text(-0.62, -0.48, "left", fontsize=8)
    ax.text(0.45, -0.48, "right", fontsize=8)


def rods_view(ax):
    ax.set_title("damper rods, top view (x forward up the page, y left)", fontsize=10)
    to_screen = lambda x, y: np.array((-y, x))  # noqa: E731
    e, n = 0.22, 4
    ax.add_patch(Circle((0, 0), e, fill=False, color="0.4"))
    for k in range(n):
        psi = 2 * np.pi * k / n
        c, s_ = np.cos(psi), np.sin(psi)
        hinge = to_screen(e * c, e * s_)
        tip = to_screen(1.35 * c, 1.35 * s_)
        ax.plot([0, hinge[0]], [0, hinge[1]], color="k", lw=2)
        ax.plot([hinge[0], tip[0]], [hinge[1], tip[1]], color="0.25", lw=3)
        ax.text(*(to_screen(1.45 * c, 1.45 * s_) + (-0.05, -0.03)), f"blade {k + 1}", fontsize=8, ha="center")
    # a blade-to-blade rod from blade 1 (leading-edge side) to blade 2 (trailing-edge side)
    a, b = 0.45, 0.1

    def on_blade(k, along, across):
        psi = 2 * np.pi * k / n
        x = (e + along) * np.cos(psi) - across * np.sin(psi)
        y = (e + along) * np.sin(psi) + across * np.cos(psi)
        return to_screen(x, y)

    start, end = on_blade(0, a, b), on_blade(1, a, -b)
    ax.plot([start[0], end[0]], [start[1], end[1]], color="tab:red", lw=2.5)
    ax.plot(*start, "o", color="tab:red")
    ax.plot(*end, "o", color="tab:red")
    ax.text(
        *(start + (-1.3, 0.3)), "blade-to-blade rod\n(blade = 1, to blade 2)", color="tab:red", fontsize=8
    )
    hinge = on_blade(0, 0, 0)
    ax.annotate("", start, on_blade(0, 0, b), arrowprops=dict(arrowstyle="<->", color="tab:blue"))
    ax.text(*(on_blade(0, a / 2, 0) + (0.06, 0.1)), "start_x (along the span)", color="tab:blue", fontsize=8)
    ax.annotate("", on_blade(0, 0, b), hinge, arrowprops=dict(arrowstyle="<->", color="tab:blue"))
    ax.text(*(hinge + (0.08, 0.02)), "start_y (to the leading edge)", color="tab:blue", fontsize=7)
    ax.text(*(end + (-0.55, -0.35)), "end_x, end_y = (a, -b)\non blade 2, from its hinge", fontsize=7)
    # a blade-to-hub rod on blade 3
    s3, h3 = on_blade(2, 0.35, 0.12), to_screen(-0.05, -0.15)
    ax.plot([s3[0], h3[0]], [s3[1], h3[1]], color="tab:green", lw=2.5)
    ax.plot(*h3, "s", color="tab:green")
    ax.text(
        *(h3 + (0.1, -0.15)),
        "blade-to-hub rod: end_* on the hub,\nfrom the centre, in blade 3's axes",
        color="tab:green",
        fontsize=7,
    )
    ax.text(
        -1.65, -1.62, "rotor turns counter-clockwise: blade k + 1 is 2 pi / N ahead of blade k", fontsize=8
    )


def gear_view(ax):
    ax.set_title("body on gear legs, side view from the right", fontsize=10)
    ax.plot([-1.6, 1.6], [-1.0, -1.0], color="0.5", lw=1)
    ax.add_patch(Rectangle((-1.1, -0.55), 2.2, 0.75, fill=False, color="0.4"))
    pivot, centre, hub = np.array((0.0, -0.95)), np.array((0.1, -0.2)), np.array((0.0, 0.75))
    ax.plot(*pivot, "ko")
    ax.text(*(pivot + (0.06, 0.02)), "pivot (reference point)", fontsize=8)
    ax.plot(*centre, "o", color="tab:purple")
    ax.text(*(centre + (0.07, 0.0)), "centre of mass\n(centre_x, centre_z)", color="tab:purple", fontsize=8)
    ax.plot([hub[0], hub[0]], [0.2, hub[1]], "k", lw=2)
    ax.plot([-1.3, 1.3], [hub[1] + 0.02, hub[1] + 0.02], color="0.3", lw=2)
    ax.plot(*hub, "k^")
    ax.text(*(hub + (0.06, -0.2)), "hub (hub_x, hub_height)", fontsize=8)
    for x in (-0.8, 0.8):
        top = np.array((x, -0.55))
        ax.plot([x, x], [-0.55, -0.75], "k", lw=1.5)
        zig = np.array([[x, -0.75], [x - 0.06, -0.8], [x + 0.06, -0.86], [x - 0.06, -0.92], [x, -0.97]])
        ax.plot(zig[:, 0], zig[:, 1], color="tab:orange", lw=1.5)
        ax.plot(*top, "s", color="tab:orange")
        hor = np.array(
            [[x + 0.02, -0.62], [x + 0.08, -0.57], [x + 0.14, -0.67], [x + 0.2, -0.57], [x + 0.26, -0.62]]
        )
        ax.plot(hor[:, 0], hor[:, 1], color="tab:orange", lw=1.2)
    ax.text(
        0.85,
        -0.5,
        "[[body.gear]] leg: position_*\nfrom the pivot; springs and\ndampers along x, y, z to the ground",
        color="tab:orange",
        fontsize=7,
    )
    arrow(ax, (-1.55, 0.9), (-1.55, 1.3))
    arrow(ax, (-1.55, 0.9), (-1.15, 0.9))
    ax.text(-1.12, 0.86, "x (forward)", fontsize=9)
    ax.text(-1.6, 1.33, "z", fontsize=9)


def draw_rods_gear():
    fig = Figure(figsize=(12, 5.2), layout="constrained")
    axes = fig.subplots(1, 2)
    for ax, draw in zip(axes, (rods_view, gear_view)):
        draw(ax)
        ax.set_aspect("equal")
        ax.set_xlim(-1.7, 1.7)
        ax.set_ylim(-1.6, 1.6)
        ax.axis("off")
    fig.suptitle("Damper rods ([[rotor.damper]]) and a rigid body on gear legs ([[body.gear]])", fontsize=11)
    fig.savefig(RODS_GEAR, dpi=110)


def main():
    fig = Figure(figsize=(13, 4.6), layout="constrained")
    axes = fig.subplots(1, 3, width_ratios=[1.3, 1, 1])
    for ax, draw in zip(axes, (top_view, side_view, rear_view)):
        draw(ax)
        ax.set_aspect("equal")
        ax.set_xlim(-1.6, 1.6)
        ax.set_ylim(-1.2, 1.6)
        ax.axis("off")
    fig.suptitle(
        "groundres conventions: x forward, y left, z up (right-handed); lag against the rotation", fontsize=11
    )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=110)
    draw_rods_gear()


if __name__ == "__main__":
    main()
