"""`groundres damper`: a rotor's lag damper laws and their describing functions."""

from __future__ import annotations

import math

import click

from ..errors import shown
from .common import (
    FORMAT,
    check_out,
    fail_user,
    invocation,
    load,
    make_console,
    out_name,
    out_option,
    output_dir,
    plain,
)

#: Amplitudes drawn and tabulated by default [deg], and how many.
SPAN = (0.01, 20.0)
POINTS = 241
#: Amplitudes the terminal's table shows [deg].
SHOWN = (0.05, 0.2, 1.0, 2.0, 5.0, 10.0)


@click.command("damper")
@click.argument("case", required=False)
@click.option(
    "--frequency",
    type=float,
    default=None,
    help="Frequency of the lag motion [rad/s, rotating frame] [default: each law's blade's "
    "small-motion lag frequency at the sweep's reference speed (its stop without one); a "
    "table law's reference frequency].",
)
@click.option(
    "--amplitudes",
    default=f"{SPAN[0]}:{SPAN[1]}",
    show_default=True,
    help="Lag amplitudes drawn, START:STOP [deg] (a logarithmic spread).",
)
@out_option("groundres-out/<case name>-damper")
@FORMAT
def command(case, frequency, amplitudes, out, fmt):
    """The lag damper laws of CASE: moment against rate, and equivalent damping and stiffness
    against amplitude.

    For a lag motion A cos(w t), c_eq and k_eq give the first harmonic of the law's moment
    (the damping carries the energy dissipated per cycle, pi c_eq w A^2). Writes
    damper.<format> (png unless --format says), damper.json (c_eq [N m s/rad] and k_eq
    [N m/rad] against amplitude for each law, with the frequency), case.toml and
    provenance.json.
    """
    import numpy as np

    from ..model import describing
    from ..results import files, folders

    console = make_console()
    the_case = load(case)
    rotor = the_case.rotor
    entries = _distinct(rotor)
    if not entries:
        fail_user(
            f"CASE {shown(case or 'default')}: its blades have no [rotor.lag_damper] law; give one "
            '(law = "linear", "bilinear", "friction", "tanh", "friction-link" or "table")'
        )
    low, high = _span(amplitudes)
    out_dir = output_dir(case, out, "damper")
    check_out(out_dir, out)
    grid = np.radians(np.geomspace(low, high, POINTS))
    speed = the_case.sweep.reference or the_case.sweep.stop
    rows, report = [], {"frequency_unit": "rad/s", "amplitude_unit": "deg", "laws": []}
    for label, law, blade in entries:
        w = frequency if frequency is not None else _frequency(law, blade, speed)
        if frequency is not None and not (math.isfinite(w) and 0 < w <= 1e9):
            fail_user(f"--frequency = {shown(w)}: must be a finite number > 0, at most 1e9 [rad/s]")
        if not (math.isfinite(w) and w > 0):
            fail_user(
                f"{label}: the lag frequency at the reference speed is {w:.3g} rad/s (no lag spring or "
                "hinge offset holds the blade); give the frequency of the motion with --frequency [rad/s]"
            )
        c_eq, k_eq = describing.equivalent(law, grid, w)
        rows.append((label, law, w))
        report["laws"].append(
            {
                "blades": label,
                "law": law.law,
                "frequency": w,
                "small_motion": dict(zip(("damping", "stiffness"), law.small_motion())),
                "amplitude": np.degrees(grid).tolist(),
                "equivalent_damping": c_eq.tolist(),
                "equivalent_stiffness": k_eq.tolist(),
                "damping_unit": "N m s/rad",
                "stiffness_unit": "N m/rad",
            }
        )
    failed = [
        str(k + 1) for k, b in enumerate(rotor.blades) if rotor.lag_laws[k] is None and b.lag_damping == 0
    ]
    with folders.output_folder(out_dir, out_name(out)) as folder:
        files.write_figure(_stacked(rows, grid, the_case.title), folder / f"damper.{fmt}")
        files.write_json(folder / "damper.json", report)
        folders.write_provenance(folder, the_case, command="damper", **invocation())
    console.print(f"Lag damper laws of {plain(the_case.title)}:")
    for label, law, w in rows:
        console.print(f"  {plain(label)}: law {law.law!r}, at {w:.4g} rad/s")
        c_eq, k_eq = describing.equivalent(law, np.radians(SHOWN), w)
        for a, c, k in zip(SHOWN, c_eq, k_eq):
            console.print(f"    A = {a:5g} deg: c_eq = {c:11.5g} N m s/rad, k_eq = {k:11.5g} N m/rad")
    if failed:
        console.print(f"  blade{'s' if len(failed) > 1 else ''} {', '.join(failed)}: no lag damper (failed)")
    console.print(f"Wrote {plain(str(out_dir))}/ (damper.{fmt}, damper.json)")


def _distinct(rotor) -> list:
    """[(which blades, law, a blade that has it)] for each distinct law of the rotor."""
    found = {}
    for k, entry in enumerate(rotor.lag_laws):
        if entry is not None:
            found.setdefault(entry.law, []).append(k)
    out = []
    for law, blades in found.items():
        names = ", ".join(str(k + 1) for k in blades)
        label = (
            "every blade"
            if len(blades) == rotor.n_blades
            else f"blade{'s' if len(blades) > 1 else ''} {names}"
        )
        out.append((label, law, rotor.blades[blades[0]]))
    return out


def _frequency(law, blade, speed: float) -> float:
    """The default frequency [rad/s]: a table's reference frequency, else the blade's lag
    frequency in the rotating frame at ``speed`` [rad/s] with the law's small-motion values."""
    if law.law == "table":
        return law.reference_frequency
    return float(blade.lag_frequency(speed)) * speed


def _span(text: str) -> tuple[float, float]:
    parts = text.split(":")
    try:
        low, high = (float(p) for p in parts)
    except ValueError:
        fail_user(f"--amplitudes {shown(text)}: must be START:STOP in deg, e.g. 0.01:20")
    if not (math.isfinite(low) and math.isfinite(high) and 1e-6 <= low < high <= 90):
        fail_user(f"--amplitudes {shown(text)}: must be 1e-6 <= START < STOP <= 90 [deg]")
    return low, high


def _stacked(rows, grid, title):
    """One figure of every law's row, each at its own frequency
    (:func:`groundres.plotting.damper.damper_figure`)."""
    from matplotlib.figure import Figure

    from ..plotting.damper import damper_figure

    if len(rows) == 1:
        label, law, w = rows[0]
        return damper_figure([(label, law)], w, grid, title)
    fig = Figure(figsize=(13, 3.6 * len(rows) + 0.6), layout="constrained")
    for i, (sub, (label, law, w)) in enumerate(zip(fig.subfigures(len(rows), 1), rows)):
        damper_figure([(label, law)], w, grid, title if i == 0 else "", fig=sub)
    return fig
