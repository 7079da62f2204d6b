"""`groundres phasors`: phasor diagrams, whirl and animated shapes at one speed."""

from __future__ import annotations

import contextlib

import click

from ..errors import shown
from ..model.units import fmt_frequency, ref_note
from .common import (
    FORMAT,
    Steps,
    case_at_speed,
    check_out,
    fail_user,
    invocation,
    make_console,
    out_name,
    out_option,
    output_dir,
    plain,
)
from .run import STAGES


@click.command("phasors")
@click.argument("case", required=False)
@click.option("--speed", type=float, required=True, help="Rotor speed, in the case's sweep unit.")
@click.option(
    "--mode",
    "labels",
    multiple=True,
    metavar="LABEL",
    help="Mode label, repeatable [default: the least stable mode, the regressive lag and body modes].",
)
@click.option(
    "--gif/--no-gif", default=True, help="Also write an animated mode shape per mode [default: on]."
)
@click.option(
    "--scale",
    type=click.Choice(["panel", "common"]),
    default="panel",
    show_default=True,
    help="Phasor panels each to its largest displacement, or all to one physical scale (m, rad).",
)
@out_option("groundres-out/<case name>-phasors")
@FORMAT
def command(case, speed, labels, gif, scale, out, fmt):
    """Phasor diagrams, rate phases, whirl and animated shapes of modes of CASE at one speed.

    Writes phasors_<mode>.<format> (nonrotating and rotating frames; png
    unless --format says), mode_<mode>.gif (always GIF), and phasors.csv /
    phasors.json with every coordinate's displacement and rate, the rate's
    lead over the displacement split into quadrature (neutral) and in-phase
    (growth) parts, and the whirl decomposition of the rotor (with case.toml
    and provenance.json).
    """
    import numpy as np

    from ..analysis import analyze
    from ..results import files, folders
    from ..results.shapes import phasor_header

    console = make_console()
    the_case, w = case_at_speed(case, speed)
    out_dir = output_dir(case, out, "phasors")
    check_out(out_dir, out)
    with Steps(console, STAGES) as steps, contextlib.ExitStack() as stack:
        result = analyze(
            the_case,
            speeds=np.union1d(the_case.sweep.speeds, [w]),
            progress=steps.callback,
            lag_damping_search=False,  # (phasors show the modes: no damping requirement)
        )
        i = int(np.argmin(np.abs(result.rotor_speed - w)))
        for label in labels:
            if label not in result.labels:
                choices = ", ".join(result.labels)
                fail_user(f"--mode {shown(label)}: not a mode of this case; choose from {choices}")
        if not labels:
            worst = result.labels[int(np.argmax(result.real_part[i]))]
            others = [lab for lab in result.labels if lab == "regressive lag" or lab.startswith("body")]
            chosen = [worst] + others
            labels = list(dict.fromkeys(chosen))
        speed_text = f"{speed:g} {the_case.sweep.unit}" + (
            f" ({w / the_case.sweep.reference:.3g} ref)" if the_case.sweep.reference else ""
        )
        report, rows = {}, []
        folder = stack.enter_context(folders.output_folder(out_dir, out_name(out)))
        for label in labels:
            shape = result.mode(label, w)
            slug = label.replace(" ", "-")
            from ..plotting.phasors import phasor_diagram

            with steps.step(f"Phasor diagrams of {label}"):
                fig = phasor_diagram(shape, speed_text=speed_text, scale=scale)
                files.write_figure(fig, folder / f"phasors_{slug}.{fmt}")
            frames = {f: [p.as_dict() for p in shape.phasors(f)] for f in ("nonrotating", "rotating")}
            for frame, items in frames.items():
                rows += [{"mode": label, "frame": frame, **item} for item in items]
            report[label] = _report_entry(shape, frames, the_case.sweep)
            if gif:
                from ..plotting.animation import mode_animation, write_gif

                anim = mode_animation(shape, speed_text=speed_text)
                task = f"Animated shape of {label} [frames]"
                with files.atomic_path(folder / f"mode_{slug}.gif") as tmp:
                    write_gif(
                        anim, tmp, progress=steps.callback and (lambda i, n, task=task: steps(task, i, n))
                    )
        files.write_json(folder / "phasors.json", report)
        files.write_csv(folder / "phasors.csv", phasor_header(rows[0]), [list(r.values()) for r in rows])
        folders.write_provenance(
            folder,
            the_case,
            command="phasors",
            method=result.method,
            frame="nonrotating and rotating",
            accuracy=result.accuracy,
            rotor_speed={"value": float(result.rotor_speed[i]), "unit": "rad/s"},
            modes=list(labels),
            **invocation(),
        )
    console.print(f"Modes of {plain(the_case.title)} at {plain(speed_text)}:")
    for label in labels:
        r = report[label]
        com = r["whirl"]["centre_of_mass"]
        lead = np.mean(
            [p["rate_lead_deg"] for p in r["phasors"]["nonrotating"] if p["displacement_amplitude"] > 1e-3]
        )
        state = "[red]unstable[/red]" if r["unstable"] else ("neutral" if r["neutral"] else "stable")
        console.print(
            f"{plain(label)}: {state}, rates lead displacements by {lead:.2f} deg; rotor centre of mass "
            f"whirls {com['direction']} at {fmt_frequency(com['frequency'], the_case.sweep)}"
        )
    if ref_note(the_case.sweep):
        console.print(plain(ref_note(the_case.sweep)))
    gifs = ", mode_*.gif" if gif else ""
    console.print(
        f"Wrote {plain(out_dir)}/phasors_*.{fmt}{gifs}, phasors.csv, phasors.json, case.toml, provenance.json"
    )


#: Units of phasors.json (SI, the data contract; the console speaks the case's unit).
REPORT_UNITS = {
    "rotor_speed": "rad/s",
    "eigenvalue": "1/s (imaginary part: rad/s, seen from nonrotating axes)",
    "whirl frequency": "rad/s",
    "displacement_amplitude": "m (body x, y) or rad (angles), relative to the reference coordinate",
    "rate_amplitude": "m/s or rad/s, relative to the reference coordinate",
    "phases": "deg",
    "fractions": "-",
}


def _report_entry(shape, frames, sweep) -> dict:
    """One mode of phasors.json: strict JSON, a reason beside every null."""
    from ..model.units import SPEED_UNITS

    lam = shape.eigenvalue
    no_motion = "the coordinate does not move in this mode (zero displacement): no phase"
    frames = {f: [dict(item) for item in items] for f, items in frames.items()}
    for items in frames.values():
        for item in items:
            if item["displacement_amplitude"] == 0:
                for key in (
                    "displacement_phase_deg",
                    "rate_phase_deg",
                    "rate_lead_deg",
                    "rate_quadrature_fraction",
                    "rate_in_phase_fraction",
                ):
                    item[key] = None
                    item[f"{key}_reason"] = no_motion
    entry = {
        "rotor_speed": shape.rotor_speed,
        "rotor_speed_in_case_unit": shape.rotor_speed / SPEED_UNITS[sweep.unit],
        "case_unit": sweep.unit,
        "units": dict(REPORT_UNITS),
        "eigenvalue": {"real": lam.real, "imag": lam.imag},
        "neutral": bool(shape.neutral),
        "unstable": bool(shape.unstable),
        "in_phase_fraction_expected": lam.real / abs(lam) if abs(lam) else None,
    }
    if entry["in_phase_fraction_expected"] is None:
        entry["in_phase_fraction_expected_reason"] = "root at the origin: no phase"
    entry["phasors"] = frames
    entry["whirl"] = shape.whirl()
    return entry
