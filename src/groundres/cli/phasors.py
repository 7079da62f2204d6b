"""`groundres phasors`: phasor diagrams, whirl and animated shapes at one speed."""

from __future__ import annotations

import click

from .common import OUT, case_at_speed, fail_user, make_console, output_dir, status


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
@OUT
def command(case, speed, labels, gif, out):
    """Phasor diagrams, rate phases, whirl and animated shapes of modes of CASE at one speed.

    Writes phasors_<mode>.png (nonrotating and rotating frames), mode_<mode>.gif,
    and phasors.csv / phasors.json with every coordinate's displacement and rate,
    the rate's lead over the displacement split into quadrature (neutral) and
    in-phase (growth) parts, and the whirl decomposition of the rotor.
    """
    import json

    import numpy as np

    from .. import io
    from ..analysis import analyze

    console = make_console()
    the_case, w = case_at_speed(case, speed)
    out_dir = output_dir(case, out)
    with status(console, f"Analysing {the_case.title}..."):
        result = analyze(the_case, speeds=np.union1d(the_case.sweep.speeds, [w]))
    i = int(np.argmin(np.abs(result.rotor_speed - w)))
    for label in labels:
        if label not in result.labels:
            fail_user(f"--mode {label!r}: not a mode of this case; choose from {', '.join(result.labels)}")
    if not labels:
        worst = result.labels[int(np.argmax(result.real_part[i]))]
        chosen = [worst] + [lab for lab in result.labels if lab == "regressive lag" or lab.startswith("body")]
        labels = list(dict.fromkeys(chosen))
    speed_text = f"{speed:g} {the_case.sweep.unit}" + (
        f" ({w / the_case.sweep.reference:.3g} ref)" if the_case.sweep.reference else ""
    )
    report, rows = {}, []
    for label in labels:
        shape = result.mode(label, w)
        slug = label.replace(" ", "-")
        from ..plotting.phasors import phasor_diagram

        io.write_figure(phasor_diagram(shape, speed_text=speed_text), out_dir / f"phasors_{slug}.png")
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
            with io.atomic_path(out_dir / f"mode_{slug}.gif") as tmp:
                from matplotlib.animation import PillowWriter

                anim.save(tmp, writer=PillowWriter(fps=15), dpi=70)
    io.write_text(out_dir / "phasors.json", json.dumps(report, indent=2) + "\n")
    io.write_csv(out_dir / "phasors.csv", list(rows[0]), [list(r.values()) for r in rows])
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
        f"Wrote {out_dir}/phasors_*.png" + (", mode_*.gif" if gif else "") + ", phasors.csv, phasors.json"
    )
