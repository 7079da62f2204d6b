"""Draw docs/images/conventions.png: axes and positive directions of groundres.

Run: python3 docs/make_sketch.py
"""

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Circle, FancyArrowPatch, Rectangle

OUT = Path(__file__).parent / "images" / "conventions.png"


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


if __name__ == "__main__":
    main()
