"""Command line: parse, call the API, write and print, set the exit code.

Exit status: 0 on success, 2 on a bad case file or option (one readable
message, no traceback), 1 on any other failure. Set GROUNDRES_DEBUG=1 to see
tracebacks of unexpected failures.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

DEFAULT_CASE = "hammond-undamped"


class _UserError(click.ClickException):
    exit_code = 2

    def show(self, file=None):
        click.echo(f"error: {self.message}", err=True)


def _fail_user(message: str):
    raise _UserError(message)


def _output_dir(case: str | None, out) -> Path:
    """--out, or groundres-out/<case name>."""
    return Path(out) if out else Path("groundres-out") / (Path(case).stem if case else DEFAULT_CASE)


def _case_at_speed(case: str | None, speed: float):
    """The case and a --speed (in the case's unit) in rad/s."""
    from .params import SPEED_UNITS

    the_case = _load(case)
    if not speed > 0:
        _fail_user(f"--speed = {speed!r}: must be > 0 (in {the_case.sweep.unit})")
    return the_case, speed * SPEED_UNITS[the_case.sweep.unit]


def _load(case: str | None):
    from .config import CaseError, load_case

    try:
        return load_case(case or DEFAULT_CASE)
    except CaseError as err:
        _fail_user(str(err))


class _Group(click.Group):
    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except (click.ClickException, click.exceptions.Exit, click.Abort, SystemExit):
            raise
        except BrokenPipeError:  # output piped into a program that stopped reading
            sys.stderr.close()
            sys.exit(0)
        except Exception as err:  # noqa: BLE001 - the one place failures become exit codes
            from .analysis import MethodError
            from .config import CaseError
            from .transition import SpeedRangeError

            if isinstance(err, (CaseError, MethodError, SpeedRangeError)):
                raise _UserError(str(err)) from None
            if os.environ.get("GROUNDRES_DEBUG"):
                raise
            click.echo(f"error: {type(err).__name__}: {err}", err=True)
            sys.exit(1)


_OUT = click.option(
    "--out",
    "out",
    type=click.Path(file_okay=False),
    default=None,
    help="Output directory [default: groundres-out/<case name>].",
)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="groundres")
def main():
    """groundres: helicopter ground resonance from equations it derives itself.

    Run `groundres run` for the built-in default case, `groundres cases` for the
    shipped cases, `groundres run CASE.toml --out DIR` for your own.
    """


def _console():
    from rich.console import Console

    return Console(stderr=False, highlight=False)


def _status(console, text):
    """A spinner while something slow runs (only on a terminal)."""
    import contextlib

    if console.is_terminal:
        return console.status(text)
    return contextlib.nullcontext()


def _first_run() -> bool:
    from .symbolic import codegen

    return not codegen._paths()[0].exists()


@main.command()
@click.argument("case", required=False)
@_OUT
@click.option(
    "--frame",
    type=click.Choice(["nonrotating", "rotating"]),
    default=None,
    help="Frame of the reported frequencies (overrides the case).",
)
@click.option(
    "--method",
    type=click.Choice(["auto", "eigen", "floquet"]),
    default=None,
    help="Analysis method (overrides the case).",
)
@click.option("--damping-ratio", is_flag=True, help="Plot damping ratio instead of real part.")
def run(case, out, frame, method, damping_ratio):
    """Analyse CASE (a TOML file or a shipped case name) over its speed sweep.

    Writes summary.json, modes.csv, modes.nc and coleman.png into --out. With
    no CASE, runs the built-in default, the shipped case 'hammond-undamped'.
    """
    console = _console()
    if case is None:
        console.print(f"No case given: running the built-in default case [bold]{DEFAULT_CASE}[/bold].")
    the_case = _load(case)
    out_dir = _output_dir(case, out)
    pool = _picture_process()
    try:
        from .analysis import analyze

        label = (
            "Deriving the equations of motion (first run only), then analysing"
            if _first_run()
            else "Analysing"
        )
        with _status(console, f"{label} {the_case.title}..."):
            result = analyze(the_case, frame=frame, method=method)
        with _status(console, "Writing results..."):
            _write_all(result, out_dir, damping_ratio, pool)
    finally:
        pool.shutdown(cancel_futures=True)
    _print_result(console, result, out_dir)


def _warm_plotting() -> None:
    """Import the plotting stack (runs in the picture process while the analysis runs)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.backends.backend_agg  # noqa: F401
    import matplotlib.figure  # noqa: F401

    from .plotting import coleman  # noqa: F401


def _render_coleman(result, path: Path, damping_ratio: bool) -> None:
    from . import io

    io.write_figure(result.plot(show_damping_ratio=damping_ratio), path)


def _picture_process():
    """A one-worker pool that starts importing matplotlib at once."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    context = multiprocessing.get_context("fork") if sys.platform.startswith("linux") else None
    pool = ProcessPoolExecutor(max_workers=1, mp_context=context)
    pool.submit(_warm_plotting)
    return pool


def _write_all(result, out_dir: Path, damping_ratio: bool, pool=None):
    """Write the four outputs; the picture renders in the picture process meanwhile."""
    from . import io

    picture = pool.submit(_render_coleman, result, out_dir / "coleman.png", damping_ratio) if pool else None
    io.write_summary(result, out_dir / "summary.json")
    io.write_modes_csv(result, out_dir / "modes.csv")
    io.write_modes_netcdf(result, out_dir / "modes.nc")
    if picture is None:
        _render_coleman(result, out_dir / "coleman.png", damping_ratio)
    else:
        picture.result()


def _fmt_speed(w, sweep):
    """A speed [rad/s] in the case's unit, with its ratio to the reference."""
    from .params import SPEED_UNITS

    text = f"{w / SPEED_UNITS[sweep.unit]:.5g} {sweep.unit}"
    if sweep.reference:
        text += f" ({w / sweep.reference:.4g} ref)"
    return text


def _print_result(console, result, out_dir):
    from rich.table import Table

    summary = result.summary()
    sweep = result.case.sweep
    console.print(
        f"[bold]{result.case.title}[/bold]  ({summary['method']}, frequencies in the {result.frame} frame)"
    )
    if summary["stable"]:
        console.print(
            "[green]Stable[/green] over the whole sweep "
            f"{_fmt_speed(result.rotor_speed[0], sweep)} to {_fmt_speed(result.rotor_speed[-1], sweep)}."
        )
    else:
        table = Table(title="Unstable rotor-speed ranges", title_justify="left")
        for col in ("from", "to", "modes"):
            table.add_column(col)
        for r in summary["unstable_ranges"]:
            table.add_row(_fmt_speed(r["start"], sweep), _fmt_speed(r["end"], sweep), ", ".join(r["modes"]))
        console.print(table)
    mr, md = summary["max_real_part"], summary["min_damping_ratio"]
    console.print(
        f"Largest real part {mr['value']:.4g} 1/s ({mr['mode']}) at {_fmt_speed(mr['speed'], sweep)}; "
        f"smallest damping ratio {md['value']:.4g} ({md['mode']}) at {_fmt_speed(md['speed'], sweep)}."
    )
    lag = summary["lag_damping"]
    table = Table(
        title="Lag damping [N m s/rad] by the Deutsch criterion, per body mode", title_justify="left"
    )
    for col in ("body", "form", "omega_b [rad/s]", "tuning speed", "nu", "needs", "installed", "ok"):
        table.add_column(col)
    for e in lag["deutsch"]:
        need = e["required_lag_damping"]
        need_text = (
            "none (no coalescence)"
            if need is None
            else ("infinite (body undamped)" if need == "infinite" else f"{need:.5g}")
        )
        ok = {True: "[green]yes[/green]", False: "[red]no[/red]", None: "-"}[e["satisfied"]]
        table.add_row(
            e["body_mode"],
            e["form"],
            f"{e['body_frequency']:.4g}",
            "-" if e["tuning_speed"] is None else _fmt_speed(e["tuning_speed"], sweep),
            "-" if e["lag_frequency_per_rev"] is None else f"{e['lag_frequency_per_rev']:.4g}",
            need_text,
            f"{e['installed_lag_damping']:.5g}",
            ok,
        )
    console.print(table)
    if not result.case.rotor.identical:
        console.print(
            "Blades differ: the Deutsch rows use the rotor's average blade (smeared damper), "
            "which can miss what a failed damper does; the exact value below governs."
        )
    exact = lag["exact_minimum"]
    which = "every blade" if result.case.rotor.identical else "every working damper"
    if exact is None:
        console.print(
            f"Exact minimum lag damping (on {which}): none, up to a large multiple of the installed "
            "damper, makes the sweep stable with the installed body damping."
        )
    else:
        console.print(
            f"Exact minimum lag damping (on {which}, from the roots): {exact:.5g} N m s/rad "
            f"(installed {lag['installed']:.5g})."
        )
    console.print(f"Wrote {out_dir}/summary.json, modes.csv, modes.nc, coleman.png")


@main.command()
@click.argument("case", required=False)
@click.option("--speed", type=float, required=True, help="Rotor speed, in the case's sweep unit.")
@click.option("--time", "duration", type=float, default=None, help="Duration [s] [default: 40 revolutions].")
@click.option(
    "--initial",
    multiple=True,
    metavar="NAME=VALUE",
    help="Initial displacement (m, rad) or rate (NAME_rate), e.g. x=0.01, lag1=0.02; repeatable "
    "[default: x, y, pitch, roll present = 0.01 and lag1 = 0.01].",
)
@_OUT
def simulate(case, speed, duration, initial, out):
    """Integrate the periodic equations of CASE in time at one rotor speed.

    Writes simulation.png (body and blade motion) and simulation.csv, and
    compares the measured growth rate with the largest real part from the
    eigen- or Floquet analysis.
    """
    import numpy as np

    from . import io
    from . import simulate as sim_module
    from .analysis import choose_method, root_solver
    from .plotting.timehistory import time_history
    from .system import System

    console = _console()
    the_case, w = _case_at_speed(case, speed)
    duration = duration or 40 * 2 * np.pi / w
    if not duration > 0:
        _fail_user(f"--time = {duration!r}: must be > 0 [s]")
    system = System(the_case.rotor, the_case.body)
    values = {}
    for item in initial:
        key, sep, value = item.partition("=")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            _fail_user(f"--initial {item!r}: expected NAME=NUMBER, e.g. x=0.01")
        if not sep:
            _fail_user(f"--initial {item!r}: expected NAME=NUMBER, e.g. x=0.01")
    if not values:
        values = {d: 0.01 for d in the_case.body.dofs} | {"lag1": 0.01}
    try:
        q0, v0 = sim_module.initial_state(system, values)
    except KeyError as err:
        _fail_user(f"--initial {err.args[0]}")
    name = Path(case).stem if case else DEFAULT_CASE
    out_dir = Path(out) if out else Path("groundres-out") / name
    with _status(console, f"Simulating {duration:.4g} s at {speed:g} {the_case.sweep.unit}..."):
        sim = sim_module.simulate(system, w, duration, (q0, v0))
        growth = sim.growth_rate()
        method = choose_method(the_case)
        predicted = float(root_solver(the_case, method).roots(w).real.max())
    fig = time_history(sim, title=the_case.title, growth=growth, predicted=predicted)
    io.write_figure(fig, out_dir / "simulation.png")
    header = ["time"] + [c.symbol if c.kind == "body" else f"{c.kind}{c.name}" for c in sim.coordinates]
    io.write_csv(out_dir / "simulation.csv", header, np.column_stack([sim.time, sim.displacement]))
    console.print(
        f"Measured growth rate {growth:.6g} 1/s; largest real part ({method}) {predicted:.6g} 1/s"
        f" ({100 * (growth - predicted) / abs(predicted) if predicted else 0:+.3f} %)."
    )
    console.print(f"Wrote {out_dir}/simulation.png, simulation.csv")


@main.command()
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
@_OUT
def phasors(case, speed, labels, gif, out):
    """Phasor diagrams, rate phases, whirl and animated shapes of modes of CASE at one speed.

    Writes phasors_<mode>.png (nonrotating and rotating frames), mode_<mode>.gif,
    and phasors.csv / phasors.json with every coordinate's displacement and rate,
    the rate's lead over the displacement split into quadrature (neutral) and
    in-phase (growth) parts, and the whirl decomposition of the rotor.
    """
    import json

    import numpy as np

    from . import io
    from .analysis import analyze

    console = _console()
    the_case, w = _case_at_speed(case, speed)
    out_dir = _output_dir(case, out)
    with _status(console, f"Analysing {the_case.title}..."):
        result = analyze(the_case, speeds=np.union1d(the_case.sweep.speeds, [w]))
    i = int(np.argmin(np.abs(result.rotor_speed - w)))
    for label in labels:
        if label not in result.labels:
            _fail_user(f"--mode {label!r}: not a mode of this case; choose from {', '.join(result.labels)}")
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
        from .plotting.phasors import phasor_diagram

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
            from .plotting.animation import mode_animation

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


@main.command()
@click.argument("name", required=False)
def cases(name):
    """List the shipped cases, or print the case file NAME."""
    import tomllib

    from rich.table import Table

    from .config import shipped_cases

    shipped = shipped_cases()
    console = _console()
    if name:
        if name not in shipped:
            _fail_user(f"case {name!r}: no such shipped case; choose one of {', '.join(shipped)}")
        click.echo(shipped[name], nl=False)
        return
    table = Table(title="Shipped cases (run with: groundres run NAME)", title_justify="left")
    table.add_column("name")
    table.add_column("title")
    for key, text in shipped.items():
        table.add_row(
            key + (" (default)" if key == DEFAULT_CASE else ""), tomllib.loads(text).get("title", "")
        )
    console.print(table)


@main.command()
@click.argument("case", required=False)
@click.option("--latex", is_flag=True, help="Print LaTeX instead of text.")
@click.option(
    "--form",
    type=click.Choice(["auto", "blade", "multiblade"]),
    default="auto",
    help="Blade coordinates (periodic) or multiblade coordinates (identical blades).",
)
def equations(case, latex, form):
    """Print the mass, damping and stiffness matrices derived for CASE.

    Blade-coordinate form: the contribution of blade k at azimuth psi_k (body
    dofs, lag, flap). Multiblade form (identical blades): the exact
    time-invariant matrices, rows premultiplied by T' (cyclic rows are N/2
    times the averaged equations).
    """
    import sympy as sp

    from .symbolic.codegen import blade_equations
    from .symbolic.derive import LOCAL_DOFS
    from .symbolic.multiblade import multiblade_equations

    the_case = _load(case)
    eq = blade_equations()
    rotor, body = the_case.rotor, the_case.body
    if form == "auto":
        form = "multiblade" if rotor.identical and rotor.n_blades >= 3 else "blade"
    show = sp.latex if latex else (lambda m: sp.pretty(m, wrap_line=False, use_unicode=True))
    click.echo(f"# {the_case.title}")
    if form == "multiblade":
        names, *mats = multiblade_equations(eq, rotor.n_blades, body.dofs, rotor.flap)
        click.echo(f"# multiblade coordinates q = [{', '.join(names)}];  M q'' + C q' + K q = 0")
        click.echo("# symbols: m, S, I blade mass, static moment, inertia; e hinge offset; h hub height;")
        click.echo(
            "#   K_zeta, C_zeta lag spring, damper; K_beta, C_beta flap;"
            " M_, J_, K_, C_ body; Omega rotor speed"
        )
    else:
        kinds = ("lag", "flap") if rotor.flap else ("lag",)
        keep = [LOCAL_DOFS.index(d) for d in body.dofs] + [LOCAL_DOFS.index(k) for k in kinds]
        names = list(body.dofs) + [f"{k}_k" for k in kinds]
        blade_mats = eq.at_azimuth(sp.Symbol("psi_k"))
        mats = [m.extract(keep, keep) for m in blade_mats]
        click.echo(
            f"# contribution of blade k (azimuth psi_k) to q = [{', '.join(names)}];  add the body's own"
        )
        click.echo("# diagonal M_, C_, K_ on the body rows; sum over the blades for the body rows")
    for title, mat in zip(("mass", "damping", "stiffness"), mats):
        click.echo(f"\n{title} matrix:")
        click.echo(show(mat))


if __name__ == "__main__":  # pragma: no cover
    main()
