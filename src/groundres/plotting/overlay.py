"""Coleman diagrams of several analyses overlaid: one colour per mode, one line style per entry.

Frequency and real part (or damping ratio) against rotor speed, and a strip
with each entry's unstable ranges. A mode has its colour of the Coleman
diagram (:func:`groundres.plotting.coleman.label_colour`) in every entry; an
entry has its line style (a marker too beyond five entries), the baseline
(entry 1) solid, widest and faintest, each later entry narrower on top, so
that lines that coincide show as a thin line inside a wider one. Speeds are
on one axis for all entries: the first case's unit, or divided by its
reference speed (:func:`groundres.plotting.axes.speed_scale`).
"""

from __future__ import annotations

import numpy as np

from ..assess.stability import growth_threshold
from ..model.units import FREQUENCY_UNITS, SPEED_UNITS
from .axes import canvas, checked_limits, checked_modes, legend, speed_scale, title_line
from .coleman import label_colour, label_stretches
from .titles import TITLE_LINE, figure_title, literal

#: Line styles of the entries, in order (the baseline solid); beyond them the same again
#: with a marker.
ENTRY_DASHES = ["-", (0, (5, 2)), (0, (1, 1.3)), (0, (6, 2, 1, 2)), (0, (3, 1, 1, 1, 1, 1))]
_ENTRY_MARKERS = ["o", "s", "^", "D", "v", "P", "X"]
#: The colour of the unstable ranges (as in the Coleman diagram).
UNSTABLE = "#d62728"
#: A small unstable bump: the largest positive real part below this share of the span
#: (as in the Coleman diagram) adds a panel of the real parts near zero.
_SMALL_BUMP = 0.06
#: Widest and narrowest line [pt] (the baseline, the last entry).
_WIDEST, _NARROWEST = 3.2, 1.1


def entry_style(number: int) -> dict:
    """The line style of entry ``number`` (1-based)."""
    k = number - 1
    style = {"linestyle": ENTRY_DASHES[k % len(ENTRY_DASHES)]}
    if k >= len(ENTRY_DASHES):
        style["marker"] = _ENTRY_MARKERS[(k // len(ENTRY_DASHES) - 1) % len(_ENTRY_MARKERS)]
    return style


def _width(k: int, n: int) -> tuple[float, float]:
    """Line width and opacity of the k-th (0-based) of n entries."""
    share = k / (n - 1) if n > 1 else 1.0
    return _WIDEST + (_NARROWEST - _WIDEST) * share, 0.55 + 0.45 * share


def _roots(ax, x, values, labels, shown, style):
    """Each tracked root's real part, continuous, in the style of its mode's label at each speed.

    values, labels : (n_s, n_e) real parts and label names; a root's line
    changes style half-way between two speeds where its label changes, and
    is left out where its mode is not shown.
    """
    for _, _, _, xs, ys, label, _ in label_stretches(x, values, labels):
        if label in shown:
            ax.plot(xs, ys, **style(label))


def _broken(x, y, moved):
    """x, y with a gap (NaN) before every point flagged in ``moved`` (a frequency jump, or the label
    moving to another branch)."""
    if moved is None or not moved[1:].any():
        return x, y
    at = np.flatnonzero(moved[1:]) + 1
    return np.insert(x, at, np.nan), np.insert(y, at, np.nan)


def overlay_diagram(
    comparison,
    fig=None,
    show_damping_ratio=False,
    *,
    speed_axis="auto",
    frequency_limits=None,
    real_limits=None,
    modes=None,
    ax=None,
):
    """Draw the entries of a comparison on one Coleman diagram.

    Parameters
    ----------
    comparison : groundres.results.comparison.Comparison
    fig : matplotlib Figure or SubFigure, optional
        An empty figure or subfigure to draw in (three or four axes are added); a new
        figure if None. ValueError if it already holds axes.
    show_damping_ratio : bool
        Damping ratio [-] instead of real part [1/s] in the lower panel.
    speed_axis : {"auto", "unit", "normalised"}
        "unit": the first case's unit; "normalised": divided by the first
        case's reference speed (ValueError without one); "auto": normalised
        where every case has the first case's reference, else its unit.
    frequency_limits, real_limits : (float, float), optional
        Ranges of the frequency axis (in its units as shown) and of the lower
        panel (1/s, or the damping ratio).
    modes : sequence of str, optional
        Labels of the modes to draw (of any entry); the unstable ranges show
        regardless.
    ax : matplotlib Axes, or two of them, optional
        Instead of ``fig``: axes of your own, the frequencies in the first, the
        real part (or damping ratio) in the second where two are given (no strip
        of unstable ranges: they are shaded).

    Returns
    -------
    matplotlib Figure
        The figure drawn in (that of ``ax`` where given).
    """
    given = canvas(fig, ax, (1, 2))
    entries = comparison.entries
    results = [e.result for e in entries]
    if frequency_limits is not None:
        frequency_limits = checked_limits(frequency_limits, "frequency_limits")
    if real_limits is not None:
        real_limits = checked_limits(real_limits, "real_limits")
    shown = checked_modes(modes, comparison.labels)
    factor, unit = speed_scale(*results, kind=speed_axis)
    n = len(entries)
    lowers = [r.damping_ratio if show_damping_ratio else r.real_part for r in results]
    columns = [[r.labels.index(lab) for lab in shown if lab in r.labels] for r in results]
    finite = np.concatenate(
        [lower[:, c][np.isfinite(lower[:, c])].ravel() for lower, c in zip(lowers, columns)]
    )
    span = float(finite.max() - finite.min()) if finite.size else 0.0
    # (the growth of the modes shown, above the growth threshold: round-off never earns a panel)
    growing = [
        np.where(r.real_part[:, c] > growth_threshold(r.rotor_speed)[:, None], r.real_part[:, c], 0.0)
        for r, c in zip(results, columns)
        if c
    ]
    bump = max((float(g.max()) for g in growing), default=0.0)
    zoom = (not show_damping_ratio) and real_limits is None and 0 < bump < _SMALL_BUMP * span
    if given is not None:  # the caller's axes: no zoom, no strip
        fig = given[0].figure
        show_damping_ratio = show_damping_ratio and len(given) == 2
        axes = given
        ax_f, ax_d, ax_s, ax_z = given[0], (given[1] if len(given) == 2 else None), None, None
    else:
        heights = [3, 2] + ([1.2] if zoom else []) + [0.35 + 0.22 * n]
        if fig is None:
            from matplotlib.figure import Figure

            fig = Figure(figsize=(11, 7.5 + 0.8 * zoom + 0.2 * n), layout="constrained")
        axes = list(fig.subplots(len(heights), 1, sharex=True, height_ratios=heights))
        ax_f, ax_d, ax_s = axes[0], axes[1], axes[-1]
        ax_z = axes[2] if zoom else None
    colours = {label: label_colour(label, i) for i, label in enumerate(comparison.labels)}
    top, lo, hi = 1e-12, np.inf, -np.inf
    for k, entry in enumerate(entries):
        r = entry.result
        lw, alpha = _width(k, n)
        w = r.rotor_speed / factor
        lo, hi = min(lo, w[0]), max(hi, w[-1])
        freq = r.frequency / factor
        moved = r.modes.harmonic_change if r.frame == "nonrotating" else r.modes.harmonic_change_rotating
        every = max(1, len(w) // 10)

        def style(label, number=entry.number, lw=lw, alpha=alpha, every=every):
            return dict(
                entry_style(number), color=colours[label], lw=lw, alpha=alpha, markevery=every, ms=2 + lw
            )

        for label in shown:
            if label not in r.labels:
                continue
            j = r.labels.index(label)
            # (a gap where the label moves harmonic or to another branch: no vertical step is drawn)
            ax_f.plot(*_broken(w, freq[:, j], moved[:, j] | r.modes.exchange[:, j]), **style(label))
            if show_damping_ratio:
                ax_d.plot(w, r.damping_ratio[:, j], **style(label))
            if np.isfinite(freq[:, j]).any():
                top = max(top, float(np.nanmax(freq[:, j])))
        if not show_damping_ratio:  # every root, continuous (a mode's own real part jumps at exchanges)
            labels = np.asarray(r.labels, dtype=object)[r.modes.root_label]
            for panel in (ax_d, ax_z):
                if panel is not None:
                    _roots(panel, w, r.modes.root_real_part, labels, shown, style)
        panels = [p for p in (ax_f, ax_d, ax_z) if p is not None]
        for s, e in r.stability.unstable_ranges:
            for panel in panels:
                panel.axvspan(s / factor, e / factor, color=UNSTABLE, alpha=0.06, lw=0)
            if ax_s is not None:
                row = n - k
                ax_s.broken_barh(
                    [(s / factor, (e - s) / factor)], (row - 0.3, 0.6), color=UNSTABLE, alpha=0.8
                )
                ax_s.plot(
                    [0.5 * (s + e) / factor], [row], "|", color=UNSTABLE, ms=9, mew=1.5
                )  # (a narrow one shows)
        if not r.stability.unstable_ranges and ax_s is not None:
            ax_s.text(0.005, n - k, "stable", transform=ax_s.get_yaxis_transform(), va="center", color="0.4")
    ends = np.array([lo, hi])
    ax_f.plot(ends, ends, ":", color="0.45", lw=1.0)
    ax_f.plot(ends, 2 * ends, ":", color="0.75", lw=1.0)
    for panel in (ax_d, ax_z):
        if panel is not None:
            panel.axhline(0.0, color="0.3", lw=0.8)
    if ax_z is not None:
        ax_z.set_ylim(-2.0 * bump, 1.6 * bump)
        ax_z.set_ylabel("near zero [1/s]")
    ax_f.set_ylim(frequency_limits or (0, 1.05 * top))
    if real_limits is not None and ax_d is not None:
        ax_d.set_ylim(*real_limits)
    ax_f.set_xlim(lo, hi) if hi > lo else ax_f.set_xlim(0.95 * lo - 1e-3, 1.05 * lo + 1e-3)
    if ax_s is not None:
        ax_s.set_ylim(0.4, n + 0.6)
        ax_s.set_axisbelow(True)  # (the grid behind the bars)
        ax_s.set_yticks(range(1, n + 1), [str(n + 1 - t) for t in range(1, n + 1)])
        ax_s.set_ylabel("unstable\n(entry)")
    _labels(ax_f, ax_d, ax_s or axes[-1], results, unit, show_damping_ratio)
    for panel in axes:
        panel.grid(True, color="0.9", lw=0.6)
    if ax_s is not None:
        ax_s.grid(False, axis="y")
    size = 10 if given is None else 9
    ax_f.set_title(_title(entries, title_line(ax_f, size)), fontsize=size)
    legend(fig, ax_f, given, *_legend(entries, shown, colours))
    return fig


def _labels(ax_f, ax_d, bottom, results, unit, show_damping_ratio) -> None:
    frames = {r.frame for r in results}
    frame = f"{frames.pop()} frame" if len(frames) == 1 else "each entry's frame"
    if unit == "-":
        ax_f.set_ylabel(f"modal frequency / reference [-]\n({frame})")
        sweep = results[0].case.sweep
        ref = sweep.reference / SPEED_UNITS[sweep.unit]
        bottom.set_xlabel(f"rotor speed / reference [-]  (reference {ref:g} {sweep.unit}, entry 1's)")
    else:
        ax_f.set_ylabel(f"modal frequency [{FREQUENCY_UNITS[unit]}]\n({frame})")
        bottom.set_xlabel(f"rotor speed [{unit}]")
    if ax_d is not None:
        ax_d.set_ylabel("damping ratio [-]" if show_damping_ratio else "real part [1/s]\n(modal damping)")


def _title(entries, line: int) -> str:
    titles = list(dict.fromkeys(e.case.title for e in entries))
    first = (
        figure_title(titles[0], min(line, TITLE_LINE))
        if len(titles) == 1
        else f"Coleman diagrams of {len(titles)} cases compared"
    )
    return f"{first}\n{len(entries)} entries, entry 1 the baseline (solid, widest)"


def _legend(entries, shown, colours) -> tuple[list, list]:
    """The legend's handles and labels: the entries (line styles), then the modes (colours)."""
    from matplotlib.lines import Line2D

    n = len(entries)
    blank = Line2D([], [], ls="")
    handles, labels = [blank], ["entries"]
    for k, e in enumerate(entries):
        lw, _ = _width(k, n)
        handles.append(Line2D([], [], color="0.2", lw=min(lw, 2.2), ms=4, **entry_style(e.number)))
        labels.append(f"{e.number}  {literal(e.case_name)}" + (f"\n    ({e.detail})" if e.detail else ""))
    handles.append(blank)
    labels.append("\nmodes")
    for label in shown:
        handles.append(Line2D([], [], color=colours[label], lw=2.2))
        labels.append(label)
    handles += [
        Line2D([], [], ls=":", color="0.45", lw=1.0),
        Line2D([], [], ls=":", color="0.75", lw=1.0),
    ]
    labels += ["1/rev", "2/rev"]
    return handles, labels
