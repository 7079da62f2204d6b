"""`groundres phasors`: phasor diagrams, whirl and animated shapes at one speed."""

from __future__ import annotations

import contextlib

import click

from .common import (
    Steps,
    case_at_speed,
    check_out,
    fail_user,
    invocation,
    make_console,
    out_option,
    output_dir,
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
@out_option("groundres-out/<case name>-phasors")
def command(case, speed, labels, gif, out):
    """Phasor diagrams, rate phases, whirl and animated shapes of modes of CASE at one speed.

    Writes phasors_<mode>.png (nonrotating and rotating frames), mode_<mode>.gif,
    and phasors.csv / phasors.json with every coordinate's displacement and rate,
    the rate's lead over the displacement split into quadrature (neutral) and
    in-phase (growth) parts, and the whirl decomposition of the rotor (with
    case.toml and provenance.json).
    """
    import json

    import numpy as np

    from .. import io
    from ..analysis import analyze

    console = make_console()
    the_case, w = case_at_speed(case, speed)
    out_dir = output_dir(case, out, "phasors")
    check_out(out_dir)
    with Steps(console, STAGES) as steps, contextlib.ExitStack() as stack:
        result = analyze(the_case, speeds=np.union1d(the_case.sweep.speeds, [w]), progress=steps.callback)
        i = int(np.argmin(np.abs(result.rotor_speed - w)))
        for label in labels:
            if label not in result.labels:
                choices = ", ".join(result.labels)
                fail_user(f"--mode {label!r}: not a mode of this case; choose from {choices}")
        if not labels:
            worst = result.labels[int(np.argmax(result.real_part[i]))]
            others = [lab for lab in result.labels if lab == "regressive lag" or lab.startswith("body")]
            chosen = [worst] + others
            labels = list(dict.fromkeys(chosen))
        speed_text = f"{speed:g} {the_case.sweep.unit}" + (
            f" ({w / the_case.sweep.reference:.3g} ref)" if the_case.sweep.reference else ""
        )
        report, rows = {}, []
        folder = stack.enter_context(io.output_folder(out_dir))
        for label in labels:
            shape = result.mode(label, w)
            slug = label.replace(" ", "-")
            from ..plotting.phasors import phasor_diagram

            with steps.step(f"Phasor diagrams of {label}"):
                io.write_figure(phasor_diagram(shape, speed_text=speed_text), folder / f"phasors_{slug}.png")
            frames = {f: [p.as_dict() for p in shape.phasors(f)] for f in ("nonrotating", "rotating")}
            for frame, items in frames.items():
                rows += [{"mode": label, "frame": frame, **item} for item in items]
            lam = shape.eigenvalue
            report[label] = {
                "rotor_speed": shape.rotor_speed,
                "eigenvalue": {"real": lam.real, "imag": lam.imag},
                "unstable": bool(shape.unstable),
                "in_phase_fraction_expected": lam.real / abs(lam) if abs(lam) else None,
                "phasors": frames,
                "whirl": shape.whirl(),
            }
            if gif:
                from ..plotting.animation import mode_animation

                anim = mode_animation(shape)
                with io.atomic_path(folder / f"mode_{slug}.gif") as tmp:
                    from matplotlib.animation import PillowWriter

                    task = f"Animated shape of {label} [frames]"
                    anim.save(
                        tmp,
                        writer=PillowWriter(fps=15),
                        dpi=70,
                        progress_callback=steps.callback and (lambda i, n, task=task: steps(task, i + 1, n)),
                    )
        io.write_text(folder / "phasors.json", json.dumps(report, indent=2) + "\n")
        io.write_csv(folder / "phasors.csv", list(rows[0]), [list(r.values()) for r in rows])
        io.write_provenance(
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
    for label in labels:
        r = report[label]
        com = r["whirl"]["centre_of_mass"]
        lead = np.nanmean(
            [p["rate_lead_deg"] for p in r["phasors"]["nonrotating"] if p["displacement_amplitude"] > 1e-3]
        )
        console.print(
            f"{label}: {'[red]unstable[/red]' if r['unstable'] else 'stable'}, "
            f"rates lead displacements by {lead:.2f} deg; rotor centre of mass whirls {com['direction']} "
            f"at {com['frequency']:.4g} rad/s"
        )
    console.print(
        f"Wrote {out_dir}/phasors_*.png"
        + (", mode_*.gif" if gif else "")
        + ", phasors.csv, phasors.json, case.toml, provenance.json"
    )
