"""Coleman diagram: modal frequency and real part against rotor speed.

Every label is one line, coloured by the label. Where two branches exchange
their character (a veering: the labels move from one tracked root to the
other) each branch is drawn continuously and changes colour half-way between
the two speeds, at a marker; in the frequency panel a periodic system's
label may instead move to another harmonic of its root, and then the label's
own line is drawn. Lines that lie on top of each other (an articulated
rotor's collective and differential lag) are drawn dashed over each other so
that both show. When the unstable bump is small against the spread of real
parts a third panel shows the real parts near zero.
"""

from __future__ import annotations

import textwrap

import numpy as np

from ..assess.stability import growth_threshold
from ..model.units import FREQUENCY_UNITS, SPEED_UNITS
from .axes import canvas, checked_limits, checked_modes, legend, speed_scale, title_line
from .titles import TITLE_LINE, figure_title

_COLOURS = {
    "body x": "#222222",
    "body y": "#7f7f7f",
    "body pitch": "#8c564b",
    "body roll": "#bcbd22",
    "body forward whirl": "#222222",
    "body backward whirl": "#7f7f7f",
    "body forward tilt": "#8c564b",
    "body backward tilt": "#bcbd22",
    "regressive lag": "#d62728",
    "progressive lag": "#1f77b4",
    "collective lag": "#2ca02c",
    "differential lag": "#9467bd",
    "regressive flap": "#ff7f0e",
    "progressive flap": "#17becf",
    "coning": "#e377c2",
    "differential flap": "#aec7e8",
}
_EXTRA = ["#ff9896", "#98df8a", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5", "#ffbb78"]
#: A small unstable bump: the largest positive real part below this share of the span.
_SMALL_BUMP = 0.06
#: A range narrower than this share of the speed axis is also marked by a line and a triangle.
_NARROW = 0.005


def label_colour(label: str, i: int = 0) -> str:
    """A stable colour for a mode label."""
    return _COLOURS.get(label, _EXTRA[i % len(_EXTRA)])


def line_style(label: str) -> str:
    return "--" if "flap" in label or label == "coning" else "-"


#: Dashes of a stretch of line that lies on another drawn before it.
_OVER = (0, (4, 3))


def _covered(values, tol, other=None):
    """Where each column lies on an earlier column (within ``tol``): (n_s, n).

    ``other`` (n_s, n), if given: only columns with a different value there
    count (the two roots of one mode lie on each other by nature).
    """
    near = np.abs(values[:, :, None] - values[:, None, :]) <= tol
    near &= np.tril(np.ones(near.shape[1:], bool), -1)  # [i, j]: j drawn before i
    if other is not None:
        near &= other[:, :, None] != other[:, None, :]
    return near.any(-1)


def _draw(ax, xs, ys, covered, style, colour, label=None):
    """A polyline; its stretches on a line drawn before it are dashed, so both show."""
    if len(xs) < 2:
        if len(xs) == 1:  # a single speed
            ax.plot(xs, ys, linestyle="", marker=".", color=colour, label=label)
        return
    covered = np.asarray(covered, bool)
    on = covered[:-1] & covered[1:]  # per segment
    start = 0
    for k in range(1, len(on) + 1):
        if k == len(on) or on[k] != on[start]:
            ax.plot(
                xs[start : k + 1],
                ys[start : k + 1],
                linestyle=_OVER if on[start] else style,
                color=colour,
                lw=1.6,
                label=label,
            )
            label = None
            start = k


def _segments(x, y, succ, exchange, label, moved=None):
    """Pieces of one label's line: (xs, ys, grid index of each vertex or -1) in order.

    Between speeds where the label stays on its branch the piece is the
    label's own. Where it moves to another branch (an exchange) the piece
    follows the branch it leaves up to half-way, and a separate piece the
    branch it joins from half-way, where that is smoother than the label's
    own step (at a veering it is; where the label's content sits at another
    harmonic on the other branch it is not, and the label's own line is
    drawn). Where ``moved`` (n_s, n_m) flags that the label's frequency moved
    to another harmonic the line stops and starts again: no line is drawn
    across a jump.
    """
    n_s = len(x)
    pieces, marks = [], []
    xs, ys, at = [x[0]], [y[0, label]], [0]  # at: grid index of each vertex (-1 half-way)

    def restart(s):
        nonlocal xs, ys, at
        pieces.append((xs, ys, at))
        xs, ys, at = [x[s + 1]], [y[s + 1, label]], [s + 1]

    for s in range(n_s - 1):
        own = abs(y[s + 1, label] - y[s, label])
        if moved is not None and moved[s + 1, label]:  # another harmonic: a gap, a marker after it
            if exchange[s + 1, label]:
                marks.append((x[s + 1], y[s + 1, label]))
            restart(s)
            continue
        if not exchange[s + 1, label]:
            xs.append(x[s + 1])
            ys.append(y[s + 1, label])
            at.append(s + 1)
            continue
        out = succ[s, label] if succ[s, label] >= 0 else label
        mid_x = 0.5 * (x[s] + x[s + 1])
        if abs(y[s + 1, out] - y[s, label]) <= own:  # along the branches, colour changes half-way
            xs.append(mid_x)
            ys.append(0.5 * (y[s, label] + y[s + 1, out]))
            at.append(-1)
            marks.append((xs[-1], ys[-1]))
            pieces.append((xs, ys, at))
            # the branch this label joins, from half-way (a branch that only
            # now becomes a mode of its own, e.g. two real roots turning into
            # a conjugate pair, starts here)
            into = np.flatnonzero(succ[s] == label)
            if len(into) and abs(y[s + 1, label] - y[s, int(into[0])]) <= own:
                src = int(into[0])
                xs, ys = [mid_x, x[s + 1]], [0.5 * (y[s, src] + y[s + 1, label]), y[s + 1, label]]
                at = [-1, s + 1]
            else:
                xs, ys, at = [x[s + 1]], [y[s + 1, label]], [s + 1]
        else:  # the label's own line, marked
            marks.append((mid_x, 0.5 * (y[s, label] + y[s + 1, label])))
            xs.append(x[s + 1])
            ys.append(y[s + 1, label])
            at.append(s + 1)
    pieces.append((xs, ys, at))
    return pieces, marks


def label_stretches(x, values, labels):
    """The stretches of each tracked root over which its label holds.

    values, labels : (n_s, n_e). Yields ``(column, start, stop, xs, ys, label,
    next_label)`` for the speeds ``start:stop`` of each column, the stretch
    extended half-way to the neighbouring speed on each side where the label
    changes (``next_label``: the label after the stretch, None at the end).
    """
    n_s, n_e = values.shape
    for c in range(n_e):
        y, lab = values[:, c], labels[:, c]
        start = 0
        for stop in [*(np.flatnonzero(lab[1:] != lab[:-1]) + 1), n_s]:
            xs, ys = list(x[start:stop]), list(y[start:stop])
            if start > 0:  # from half-way after the change
                xs.insert(0, 0.5 * (x[start - 1] + x[start]))
                ys.insert(0, 0.5 * (y[start - 1] + y[start]))
            if stop < n_s:  # to half-way before the next
                xs.append(0.5 * (x[stop - 1] + x[stop]))
                ys.append(0.5 * (y[stop - 1] + y[stop]))
            yield c, start, stop, xs, ys, lab[start], (lab[stop] if stop < n_s else None)
            start = stop


def root_lines(ax, x, values, labels, styles, colours, scale, show=None):
    """Each tracked root's line, coloured by the label of its mode at each speed.

    values, labels : (n_s, n_e). Where a root's label changes the line turns
    colour half-way between the two speeds, at a marker. ``show`` (n_m,) bool,
    if given: only the roots of these modes are drawn. Returns the markers.
    """
    marks = []
    show = np.ones(len(styles), bool) if show is None else show
    hidden = ~show[labels]
    covered = _covered(np.where(hidden, np.nan, values), 0.004 * max(scale, 1e-12), labels)
    for c, start, stop, xs, ys, i, after in label_stretches(x, values, labels):
        # (the half-way ends lie on no other line)
        cov = [False] * int(start > 0) + list(covered[start:stop, c]) + [False] * int(after is not None)
        if after is not None and (show[i] or show[after]):
            marks.append((xs[-1], ys[-1]))
        if show[i]:
            _draw(ax, xs, ys, cov, styles[i], colours[i])
    return marks


def coleman_diagram(
    result,
    fig=None,
    show_damping_ratio=False,
    *,
    speed_axis="auto",
    frequency_limits=None,
    real_limits=None,
    modes=None,
    ax=None,
):
    """Draw the Coleman diagram of a sweep result.

    Parameters
    ----------
    result : SweepResult
    fig : matplotlib Figure or SubFigure, optional
        An empty figure or subfigure to draw in (two or three axes are added, the
        legend on the right); a new figure if None. ValueError if it already holds axes.
    show_damping_ratio : bool
        Plot the damping ratio instead of the real part in the lower panel.
    speed_axis : {"auto", "unit", "normalised"}
        Rotor speeds (and frequencies) in the case's ``[sweep] unit``, or
        divided by its ``reference`` speed ("normalised": ValueError if the
        case has none); "auto" normalises where the case has a reference.
    frequency_limits : (float, float), optional
        Range of the frequency axis, in its units as shown (the case's
        frequency unit, e.g. cycles/min for rpm, or per reference speed).
    real_limits : (float, float), optional
        Range of the lower panel: real part [1/s], or damping ratio [-] with
        ``show_damping_ratio``. The near-zero panel is then left out.
    modes : sequence of str, optional
        Labels of the modes to draw (ValueError for a label the result does
        not have); the unstable ranges are shaded whichever modes they are of.
    ax : matplotlib Axes, or a pair of them, optional
        Instead of ``fig``: one Axes (the frequencies only) or two (the
        frequencies, then the real part or damping ratio) that the caller made,
        with the legend beside the first.

    Returns
    -------
    matplotlib Figure
        The figure drawn in (that of ``ax`` where given).

    Examples
    --------
    >>> fig = coleman_diagram(result, modes=["regressive lag", "body x"],
    ...                       frequency_limits=(0, 2))  # doctest: +SKIP
    """
    if frequency_limits is not None:
        frequency_limits = checked_limits(frequency_limits, "frequency_limits")
    if real_limits is not None:
        real_limits = checked_limits(real_limits, "real_limits")
    show = np.isin(result.labels, checked_modes(modes, result.labels))
    factor, unit = speed_scale(result, kind=speed_axis)
    given = canvas(fig, ax, (1, 2))
    if given is None:
        if fig is None:
            from matplotlib.figure import Figure

            fig = Figure(figsize=(10, 8), layout="constrained")
    else:
        fig = given[0].figure
        show_damping_ratio = show_damping_ratio and len(given) == 2
    w = result.rotor_speed / factor
    freq = result.frequency / factor
    lower = result.damping_ratio if show_damping_ratio else result.real_part
    normalised = unit == "-"
    f_unit = "-" if normalised else FREQUENCY_UNITS[unit]
    modes = result.modes
    grows = result.real_part > growth_threshold(result.rotor_speed)[:, None]
    grows &= show
    finite = lower[:, show][np.isfinite(lower[:, show])]
    span = float(finite.max() - finite.min()) if finite.size else 0.0
    shown_real = result.real_part[:, show]
    bump = float(shown_real.max()) if shown_real.size else 0.0
    zoom = (not show_damping_ratio) and real_limits is None and grows.any() and 0 < bump < _SMALL_BUMP * span
    if given is not None:  # the caller's axes: the frequencies, and the lower panel where two
        ax_f, ax_d, ax_z = given[0], (given[1] if len(given) == 2 else None), None
    elif zoom:
        ax_f, ax_d, ax_z = fig.subplots(3, 1, sharex=True, height_ratios=[3, 2, 1.2])
    else:
        ax_f, ax_d = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
        ax_z = None
    panels = [ax for ax in (ax_f, ax_d, ax_z) if ax is not None]

    x_span = (w[-1] - w[0]) if len(w) > 1 else 1.0  # (in the axis's units, as w)
    narrow = []  # ranges too narrow to see as a band: a line and a marker each
    for s, e in result.stability.unstable_ranges:
        for ax in panels:
            ax.axvspan(s / factor, e / factor, color="#d62728", alpha=0.12, lw=0)
        if (e - s) / factor < _NARROW * x_span:
            narrow.append(0.5 * (s + e) / factor)
            for ax in panels:
                ax.axvline(narrow[-1], color="#d62728", alpha=0.5, lw=0.8)
            ax_f.plot(
                [narrow[-1]],
                [1.0],
                "v",
                color="#d62728",
                ms=7,
                transform=ax_f.get_xaxis_transform(),
                clip_on=False,
            )
    margins = getattr(result, "margins", None)
    operating = margins is not None and margins.operating_given
    required = None if margins is None else margins.required_damping_ratio
    if operating:  # the operating range: a band with its edges
        lo, hi = (x / factor for x in margins.operating_range)
        for ax in panels:
            ax.axvspan(lo, hi, color="#1f77b4", alpha=0.07, lw=0)
            for edge in (lo, hi):
                ax.axvline(edge, color="#1f77b4", lw=0.9, ls="--", alpha=0.6)
    if required is not None and show_damping_ratio:  # (show_damping_ratio: there is a lower panel)
        ax_d.axhline(required, color="0.1", lw=1.3, ls="-.")
    n_s = len(w)
    succ = modes.successor() if n_s > 1 else np.zeros((0, len(result.labels)), int)
    exchange = modes.exchange
    harmonic = (
        result.modes.harmonic_change if result.frame == "nonrotating" else modes.harmonic_change_rotating
    )

    colours = [label_colour(label, i) for i, label in enumerate(result.labels)]
    styles = [line_style(label) for label in result.labels]
    marks_f, marks_d = [], []
    shown_freq = freq[:, show]
    top_f = max(np.nanmax(shown_freq) if np.isfinite(shown_freq).any() else 0.0, 1e-12)
    by_label = [(ax_f, freq, harmonic, 0.004 * top_f, marks_f)]
    if show_damping_ratio:
        by_label.append((ax_d, lower, None, 0.004 * max(span, 1e-12), marks_d))
    mostly_covered = np.zeros(len(result.labels), bool)
    for ax, values, moved, tol, marks_out in by_label:
        covered = _covered(np.where(show, np.nan_to_num(values), np.nan), tol)  # (hidden: on nothing)
        if ax is ax_f:
            mostly_covered = covered.mean(0) > 0.5
        for i in np.flatnonzero(show):
            pieces, marks = _segments(w, values, succ, exchange, i, moved)
            for xs, ys, at in pieces:
                _draw(ax, xs, ys, [covered[a, i] if a >= 0 else False for a in at], styles[i], colours[i])
            marks_out.extend(marks)
    if not show_damping_ratio:  # every root: continuous, coloured by its mode's label
        for panel, scale in ((ax_d, span), (ax_z, 3.6 * bump)):
            if panel is not None:
                marks = root_lines(
                    panel, w, modes.root_real_part, modes.root_label, styles, colours, scale, show
                )
                marks_d += marks if panel is ax_d else []
    for i in np.flatnonzero(grows.any(0)):  # the growing stretches, highlighted
        ax_f.plot(w, np.where(grows[:, i], freq[:, i], np.nan), "-", color=colours[i], lw=4.0, alpha=0.5)
    handles_extra = []
    from matplotlib.lines import Line2D

    if marks_f or marks_d:
        for panel, marks in ((ax_f, marks_f), (ax_d, marks_d)):
            if marks:
                mx, my = np.array(marks).T
                panel.plot(mx, my, "o", ms=4.5, mfc="white", mec="0.2", mew=0.9, zorder=5)
        handles_extra.append(
            (Line2D([], [], ls="", marker="o", ms=4.5, mfc="white", mec="0.2"), "branches exchange labels")
        )
    flagged = np.argwhere(harmonic & show)
    if len(flagged):
        ax_f.plot(w[flagged[:, 0]], freq[flagged[:, 0], flagged[:, 1]], "x", ms=6, color="0.15", zorder=6)
        handles_extra.append(
            (Line2D([], [], ls="", marker="x", ms=6, color="0.15"), "frequency moves to another harmonic")
        )
    # 1/rev (and 2/rev) references
    ends = np.array([w[0], w[-1]])
    ax_f.plot(ends, ends, ":", color="0.45", lw=1.0, label="1/rev")
    ax_f.plot(ends, 2 * ends, ":", color="0.75", lw=1.0, label="2/rev")
    for ax in panels[1:]:
        ax.axhline(0.0, color="0.3", lw=0.8)
    if not show_damping_ratio and ax_d is not None:
        # neutral roots of undamped cases sit at zero up to round-off: keep a visible scale
        floor = 0.02 * max(np.nanmax(result.frequency) if np.isfinite(result.frequency).any() else 0, 1e-12)
        if real_limits is None and span < floor and np.nanmax(np.abs(lower[:, show])) < floor:
            ax_d.set_ylim(-floor, floor)
    if real_limits is not None and ax_d is not None:
        ax_d.set_ylim(*real_limits)
    if ax_z is not None:
        ax_z.set_ylim(-2.0 * bump, 1.6 * bump)
        ax_z.set_ylabel("near zero [1/s]")
    top = np.nanmax(shown_freq) if np.isfinite(shown_freq).any() else 1.0
    ax_f.set_ylim(frequency_limits or (0, 1.05 * top))
    if w[-1] > w[0]:
        ax_f.set_xlim(w[0], w[-1])
    else:  # a single speed
        ax_f.set_xlim(0.95 * w[0] - 1e-3, 1.05 * w[0] + 1e-3)
    frame = "nonrotating" if result.frame == "nonrotating" else "rotating"
    ax_f.set_ylabel(
        f"modal frequency / reference [-]\n({frame} frame)"
        if normalised
        else f"modal frequency [{f_unit}]\n({frame} frame)"
    )
    if show_damping_ratio:
        ax_d.set_ylabel("damping ratio [-]")
    elif ax_d is not None:
        ax_d.set_ylabel("real part [1/s]\n(modal damping)")
    bottom = panels[-1]
    if normalised:
        ref = result.case.sweep.reference / SPEED_UNITS[result.case.sweep.unit]
        bottom.set_xlabel(f"rotor speed / reference [-]  (reference {ref:g} {result.case.sweep.unit})")
    else:
        bottom.set_xlabel(f"rotor speed [{unit}]")
    for panel in panels:
        panel.grid(True, color="0.9", lw=0.6)
    ranges = result.stability.unstable_ranges
    if ranges:
        text = "unstable: " + ", ".join(f"{s / factor:.4g} to {e / factor:.4g}" for s, e in ranges)
        text += " [-]" if normalised else f" {unit}"
    else:
        text = "stable over the whole sweep"
    size = 10 if given is None else 9
    line = min(TITLE_LINE, title_line(ax_f, size))  # (a subfigure's or the caller's axes may be narrow)
    state = "\n".join(textwrap.wrap(f"{result.method}, {frame} frame; {text}", line))
    ax_f.set_title(f"{figure_title(result.case.title, line)}\n{state}", fontsize=size)
    handles = [
        Line2D([], [], color=colours[i], lw=1.6, linestyle=_OVER if mostly_covered[i] else styles[i])
        for i in np.flatnonzero(show)
    ]
    labels = [result.labels[i] for i in np.flatnonzero(show)]
    more, more_labels = ax_f.get_legend_handles_labels()  # the 1/rev lines
    handles += more
    labels += more_labels
    for h, t in handles_extra:
        handles.append(h)
        labels.append(t)
    if ranges:
        from matplotlib.patches import Patch

        handles.append(Patch(color="#d62728", alpha=0.12))
        labels.append("unstable range")
    if narrow:
        handles.append(Line2D([], [], color="#d62728", marker="v", ms=7, lw=0.8, alpha=0.7))
        labels.append(f"narrow unstable range\n(under {_NARROW:.1%} of the axis)")
    if operating:
        from matplotlib.patches import Patch

        handles.append(Patch(facecolor="#1f77b4", alpha=0.15, edgecolor="#1f77b4", ls="--"))
        labels.append("operating range")
    if required is not None:
        handles.append(Line2D([], [], color="0.1", lw=1.3, ls="-."))
        text = f"required damping ratio\n{100 * required:.3g} %"
        labels.append(text if show_damping_ratio else text + " (drawn on the\ndamping-ratio panel)")
    legend(fig, ax_f, given, handles, labels)
    return fig
