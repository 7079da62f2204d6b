"""The picture of a design study: stability over the varied keys.

Two keys: a filled map of the growth margin, the largest real part of the
vibrating modes (blue decays, red grows, the colour scale symmetric about
zero; :mod:`groundres.assess.margins`), with the stability boundary drawn
bold where it crosses zero between the grid's points,
the case's own design point marked and the Deutsch requirement drawn where
it applies; with failures, one map for the worst failure at each point and
one per failure. One key: the growth margin and the least damping ratio
over the operating range against the key, a line per failure.
More keys: small multiples over the third key's values (the worst failure).
"""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import ScalarFormatter

from .titles import figure_title

#: Most panels of one picture (a study with more values of its third key shows some of them).
MAX_PANELS = 12
_FAILURE = "failure"


def failure_name(failure) -> str:
    """A failure entry as a reader says it."""
    return "all dampers working" if failure == "none" else f"{failure}: lag damper failed"


def _suptitle(fig, text):
    """The figure's title, wrapped to the figure's width."""
    import textwrap

    width = int(fig.get_figwidth() * 11)
    fig.suptitle("\n".join(textwrap.wrap(figure_title(text), width)), fontsize=10)


def failure_groups(ds, variable: str = "growth_margin") -> list[tuple[str, object]]:
    """(name, data) of each failure, those with identical measures drawn once (the single
    failures of alike blades are the same rotor turned: "blades 1, 2, 3, 4")."""
    groups = []
    for f in ds[_FAILURE].values:
        part = ds.sel({_FAILURE: f})
        for group in groups:
            if (
                f != "none"
                and group[0][0] != "none"
                and np.array_equal(group[1][variable].values, part[variable].values, equal_nan=True)
            ):
                group[0].append(f)
                break
        else:
            groups.append(([f], part))
    out = []
    for names, part in groups:
        if len(names) == 1:
            out.append((failure_name(names[0]), part))
        else:
            blades = ", ".join(n.split()[-1] for n in names)
            if names[0].startswith("blade "):
                out.append((f"blades {blades}: one lag damper failed (each the same rotor turned)", part))
            else:
                kind = names[0].rpartition(" rod ")[0]
                out.append((f"{kind} rods {blades}: one failed (each the same rotor turned)", part))
    return out


def _label(ds, key) -> str:
    unit = ds[key].attrs.get("units", "")
    return f"{key} [{unit}]" if unit and unit != "1" else key


def _worst(ds):
    if _FAILURE not in ds.dims:
        return ds
    # (a failure that could not be computed leaves the worst unknown: NaN, not skipped)
    return ds.assign(
        growth_margin=ds.growth_margin.max(_FAILURE, skipna=False),
        least_damping_ratio=ds.least_damping_ratio.min(_FAILURE, skipna=False),
        stable=ds.stable.all(_FAILURE),
    ).drop_dims(_FAILURE)


def study_map(ds, design: dict | None = None, deutsch=None, title: str = ""):
    """The study's figure (a matplotlib Figure).

    Parameters
    ----------
    ds : xarray.Dataset
        A study (:func:`groundres.studies.study.study`).
    design : dict, optional
        The case's own value of each varied key: marked.
    deutsch : (lag_key, other_key, other_values, required), optional
        The lag damping the Deutsch criterion asks for at each value of the
        other key [N m s/rad]: drawn on two-key maps; a str instead says why
        the criterion does not apply.
    """
    from matplotlib.figure import Figure

    keys = [d for d in ds.growth_margin.dims if d != _FAILURE]
    failures = list(ds[_FAILURE].values) if _FAILURE in ds.dims else []
    if len(keys) == 1:
        fig = Figure(figsize=(8.0, 9.0 if _has_cycles(ds) else 6.5), layout="constrained")
        _one_key(fig, ds, keys[0], failures, design)
    else:
        panels = _panels(ds, keys, failures)
        cols = min(3, len(panels))
        rows = -(-len(panels) // cols)
        fig = Figure(figsize=(4.6 * cols + 1.2, 4.0 * rows + 0.8), layout="constrained")
        axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
        scale = (
            float(np.nanmax(np.abs(ds.growth_margin.values)))
            if np.isfinite(ds.growth_margin.values).any()
            else 1.0
        )
        scale = scale or 1.0
        image = None
        for ax, (name, part) in zip(axes, panels):
            # (the criterion is for identical blades: drawn where every damper works)
            working = not failures or name.startswith(failure_name("none"))
            # (the design point where the panel's further keys hold its own values)
            here = (
                design
                if all(
                    design and np.isclose(design.get(k, np.nan), v)
                    for k, v in part.attrs.get("at", {}).items()
                )
                else None
            )
            image = _two_keys(ax, part, keys[0], keys[1], scale, here, deutsch if working else None)
            ax.set_title(name, fontsize=9)
        for ax in axes[len(panels) :]:
            ax.set_visible(False)
        if image is not None:
            bar = fig.colorbar(image, ax=axes[: len(panels)].tolist(), shrink=0.9)
            bar.set_label("growth margin [1/s] (red grows)")
        if isinstance(deutsch, str):
            fig.text(0.01, 0.003, f"Deutsch criterion: {deutsch}", fontsize=8, va="bottom")
    _suptitle(fig, title or ds.attrs.get("title", "groundres study"))
    return fig


def _panels(ds, keys, failures):
    """(title, 2-key data set) for each panel."""
    extra = keys[2:]
    out = []
    base = [("worst of the single failures" if failures else "", _worst(ds))]
    if failures and not extra:
        base += failure_groups(ds)
    for name, part in base:
        if not extra:
            out.append((name, part))
            continue
        stack = part.stack(_panel=extra)
        for i in range(min(stack.sizes["_panel"], MAX_PANELS)):
            one = stack.isel(_panel=i)
            where = ", ".join(f"{_label(ds, k)} = {float(one[k]):.4g}" for k in extra)
            at = {k: float(one[k]) for k in extra}
            out.append(
                ((name + "; " if name else "") + where, one.drop_vars(["_panel", *extra]).assign_attrs(at=at))
            )
    if len(out) > MAX_PANELS:  # (said on the last panel shown)
        name, part = out[MAX_PANELS - 1]
        out[MAX_PANELS - 1] = (f"{name} (and {len(out) - MAX_PANELS} more panels not shown)", part)
    return out[:MAX_PANELS]


def _two_keys(ax, part, xkey, ykey, scale, design, deutsch):
    x, y = np.asarray(part[xkey], float), np.asarray(part[ykey], float)
    stable = np.asarray(part.stable.transpose(ykey, xkey), bool)
    # (a stable point's growth margin above zero is a neutral root's round-off, within the
    # growth threshold: drawn as zero, white, never as growth)
    z = np.asarray(part.growth_margin.transpose(ykey, xkey), float)
    z = np.where(stable & (z > 0), 0.0, z)
    levels = np.linspace(-scale, scale, 21)
    image = None
    if len(x) > 1 and len(y) > 1:
        image = ax.contourf(x, y, np.clip(z, -scale, scale), levels=levels, cmap="RdBu_r", extend="both")
        if 0 < stable.mean() < 1:  # (the growth margin, continuous across the boundary, signed by
            # the verdict: its zero lies between the grid's stable and unstable points)
            tiny = 1e-300
            signed = np.where(stable, np.minimum(z, -tiny), np.maximum(z, tiny))
            ax.contour(x, y, signed, levels=[0.0], colors="black", linewidths=2.2)
            ax.plot([], [], color="black", linewidth=2.2, label="stability boundary")
    else:
        image = ax.scatter(*np.meshgrid(x, y), c=z, cmap="RdBu_r", vmin=-scale, vmax=scale)
    bad = ~np.isfinite(z)
    if bad.any():  # (failed points: no colour of their own, so marked)
        gx, gy = np.meshgrid(x, y)
        ax.plot(gx[bad], gy[bad], "kx", markersize=6, linestyle="none", label="failed point (see error)")
    _mark_design(ax, design, xkey, ykey)
    _draw_deutsch(ax, deutsch, xkey, ykey)
    ax.set_xlim(x.min(), x.max()) if len(x) > 1 else None
    ax.set_ylim(y.min(), y.max()) if len(y) > 1 else None
    ax.set_xlabel(_label(part, xkey))
    ax.set_ylabel(_label(part, ykey))
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper right", framealpha=0.85)
    return image


def _one_key(fig, ds, key, failures, design):
    cycles = _has_cycles(ds)
    axes = fig.subplots(3 if cycles else 2, 1, sharex=True)
    ax_real, ax_ratio = axes[0], axes[1]
    x = np.asarray(ds[key], float)
    series = failure_groups(ds) if failures else [("", ds)]
    for name, part in series:
        label = name or None
        ax_real.plot(x, part.growth_margin.values, marker=".", label=label)
        ax_ratio.plot(x, 100 * part.least_damping_ratio.values, marker=".", label=label)
    if failures:
        worst = _worst(ds)
        ax_real.plot(x, worst.growth_margin.values, color="black", linewidth=2.2, label="worst")
        ax_ratio.plot(x, 100 * worst.least_damping_ratio.values, color="black", linewidth=2.2, label="worst")
    ax_real.axhline(0.0, color="black", linewidth=0.8)
    required = ds.attrs.get("required_damping_ratio")
    if required is not None and np.isfinite(required):
        ax_ratio.axhline(100 * required, color="0.1", linestyle="-.", linewidth=1.3, label="required")
    ax_ratio.axhline(0.0, color="black", linewidth=0.8)
    ax_real.set_ylabel("growth margin [1/s]\n(largest real part of the vibrating modes)")
    ax_ratio.set_ylabel("least damping ratio over the\noperating range [%]")
    if cycles:
        _cycle_panel(axes[2], x, series, failures)
    axes[-1].set_xlabel(_label(ds, key))
    for ax in axes:
        if design and key in design:
            ax.axvline(design[key], color="goldenrod", linestyle=":", label="design point")
        ax.grid(alpha=0.3)
    if ax_real.get_legend_handles_labels()[0]:
        ax_real.legend(fontsize=8)


def _has_cycles(ds) -> bool:
    """Whether a study holds limit cycles (a case with a nonlinear lag damper law)."""
    return any(
        name in ds and np.isfinite(ds[name].values).any()
        for name in ("smallest_threshold", "largest_stable_cycle")
    )


def _cycle_panel(ax, x, series, failures):
    """The smallest threshold (dashed) and the largest stable cycle (solid) against the key [deg];
    a threshold of 0 (at some speed any disturbance grows) as a triangle on the axis's floor; a
    value that is an upper bound (a cycle below the amplitudes searched) as an open triangle."""
    floors = []
    for i, (name, part) in enumerate(series):
        color = f"C{i}"
        suffix = f" ({name})" if failures else ""
        for variable, style, words, bound in (
            ("smallest_threshold", "--", "smallest threshold", "below_searched_speed_count"),
            ("largest_stable_cycle", "-", "largest stable cycle", "stable_below_searched_speed_count"),
        ):
            values = np.degrees(np.asarray(part[variable].values, float))
            shown = np.where(values > 0, values, np.nan)
            if np.isfinite(shown).any():
                ax.plot(x, shown, style, marker=".", color=color, label=words + suffix)
            if bound in part:  # (studies written before the bound was recorded have none)
                at_most = np.isfinite(shown) & (np.asarray(part[bound].values, float) > 0)
                if at_most.any():
                    ax.plot(
                        np.asarray(x)[at_most],
                        shown[at_most],
                        "v",
                        markerfacecolor="none",
                        color=color,
                        markersize=8,
                        linestyle="none",
                        label=f"{words}: at most (a cycle below the amplitudes searched)" + suffix,
                    )
            if (values == 0).any():
                floors.append((np.asarray(x)[values == 0], color, suffix))
    ax.set_yscale("log")
    if floors:
        if not ax.get_lines():
            ax.set_ylim(0.01, 10.0)
        bottom, top = ax.get_ylim()
        for where, color, suffix in floors:
            ax.plot(
                where,
                np.full(len(where), bottom),
                "v",
                color=color,
                clip_on=False,
                label="grows from any disturbance at some speed" + suffix,
            )
        ax.set_ylim(bottom, top)
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(ScalarFormatter())
    ax.set_ylabel("limit cycles: lag amplitude of\nthe blade that moves most [deg]")
    ax.legend(fontsize=8)


def boundary_map(ds, keys, design: dict | None = None, deutsch=None, title: str = ""):
    """The figure of a boundary search (:func:`groundres.studies.study.boundary`).

    ``keys``: the study's varied keys in order (the boundary key among them),
    which set the axes as in :func:`study_map`: the boundary against the first
    other key, a line per failure (and per value of any further key).
    """
    from matplotlib.figure import Figure

    key = ds.attrs["boundary_key"]
    others = [k for k in keys if k != key]
    fig = Figure(figsize=(8.0, 6.8), layout="constrained")
    ax = fig.subplots()
    if not others:  # (one value per failure, identical ones once: a point each, and what it means)
        groups = failure_groups(ds, "boundary") if _FAILURE in ds.dims else [("", ds)]
        start, stop = ds.attrs["boundary_range"]
        lo, hi = sorted((start, stop))
        for i, (_, part) in enumerate(groups):
            value = float(np.asarray(part.boundary.values, float).ravel()[0])
            stable = bool(np.asarray(part.stable_at_start.values).ravel()[0])
            error = str(np.asarray(part.error.values).ravel()[0])
            if error:
                text, where = "failed (see boundary.nc)", lo
            elif np.isnan(value):
                text, where = f"{'stable' if stable else 'unstable'} over the whole range", lo
            else:
                ax.plot(value, i, "o", color="#1f77b4", markersize=8)
                side = "smaller" if stable == (start < stop) else "larger"
                text, where = f"{value:.5g}: stable at {side} values", value
            ax.annotate(text, (where, i), fontsize=8, xytext=(8, 6), textcoords="offset points")
        ax.set_yticks(range(len(groups)), [name for name, _ in groups], fontsize=8)
        ax.set_ylim(-0.5, len(groups) - 0.5)
        ax.set_xlabel(f"{key} [{ds.boundary.attrs.get('units', '')}] at the stability boundary")
        ax.set_xlim(lo, hi)
        ax.grid(alpha=0.3)
    else:
        first, rest = others[0], others[1:]
        stack = ds.stack(_line=rest) if rest else ds.expand_dims(_line=[0])
        groups = failure_groups(stack, "boundary") if _FAILURE in ds.dims else [(None, stack)]
        for f, part in groups:
            for i in range(min(part.sizes["_line"], 8)):
                one = part.isel(_line=i)
                name = [f] if f is not None else []
                name += [f"{k} = {float(one[k]):.4g}" for k in rest]
                along, at = np.asarray(one[first], float), np.asarray(one.boundary, float)
                x, y = (at, along) if keys.index(key) < keys.index(first) else (along, at)
                label = ", ".join(name) or "boundary"
                failed = np.asarray(one.error.values, str) != ""
                start, stop = ds.attrs["boundary_range"]
                if failed.all():
                    label += ": failed (see error in boundary.nc)"
                elif np.isnan(at[~failed]).all():  # (nothing to draw: the legend says which side it is on)
                    whole = "stable" if np.asarray(one.stable_at_start)[~failed].all() else "unstable"
                    label += f": {whole} over the whole range"
                else:
                    at_start = np.asarray(one.stable_at_start)[np.isfinite(at)].all()
                    side = "smaller" if at_start == (start < stop) else "larger"
                    label += f": stable at {side} {key}"
                ax.plot(x, y, marker="o", markersize=3, linewidth=1.8, label=label)
        span = sorted(ds.attrs["boundary_range"])
        if keys.index(key) < keys.index(first):
            ax.set_xlim(*span)
            ax.set_xlabel(f"{key} [{ds.boundary.attrs.get('units', '')}] at the stability boundary")
            ax.set_ylabel(_label(ds, first))
        else:
            ax.set_ylim(*span)
            ax.set_ylabel(f"{key} [{ds.boundary.attrs.get('units', '')}] at the stability boundary")
            ax.set_xlabel(_label(ds, first))
        xkey, ykey = (key, first) if keys.index(key) < keys.index(first) else (first, key)
        _mark_design(ax, design, xkey, ykey)
        _draw_deutsch(ax, deutsch, xkey, ykey)
        if isinstance(deutsch, str):
            ax.text(0.01, 0.01, f"Deutsch criterion: {deutsch}", transform=ax.transAxes, fontsize=8)
        ax.grid(alpha=0.3)
        fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", fontsize=7)
    failed = int((np.asarray(ds.error.values, str) != "").sum())
    missing = int(np.isnan(np.asarray(ds.boundary.values, float)).sum()) - failed
    notes = (
        [f"{missing} line(s) have no boundary in the range (stable or unstable throughout)"]
        if missing
        else []
    )
    notes += [f"{failed} line(s) failed (their reasons in boundary.nc)"] if failed else []
    if notes:
        ax.set_title("; ".join(notes), fontsize=8)
    _suptitle(fig, title or ds.attrs.get("title", "groundres stability boundary"))
    return fig


def _mark_design(ax, design, xkey, ykey):
    """The case's own values of the two keys, a star."""
    if design and xkey in design and ykey in design:
        ax.plot(
            design[xkey],
            design[ykey],
            marker="*",
            markersize=14,
            color="gold",
            markeredgecolor="black",
            linestyle="none",
            label="design point",
        )


def _draw_deutsch(ax, deutsch, xkey, ykey):
    """The Deutsch requirement (lag damping against the other key), dashed, where it applies."""
    if not isinstance(deutsch, tuple) or {deutsch[0], deutsch[1]} != {xkey, ykey}:
        return
    lag, _, values, required = deutsch
    ok = np.isfinite(required)
    if ok.any():
        x, y = (required, values) if lag == xkey else (values, required)
        ax.plot(
            x[ok],
            y[ok],
            color="#2ca02c",
            linewidth=1.8,
            linestyle="--",
            label="Deutsch requirement (all dampers working)",
        )
