"""`groundres equations`: print the derived matrices."""

from __future__ import annotations

import click

from ..errors import printable
from .common import load


@click.command("equations")
@click.argument("case", required=False)
@click.option("--latex", is_flag=True, help="Print LaTeX instead of text.")
@click.option(
    "--form",
    type=click.Choice(["auto", "blade", "multiblade"]),
    default="auto",
    help="Blade coordinates (periodic) or multiblade coordinates (time-invariant for identical "
    "blades, N >= 3; for other rotors the matrices of identical blades, with a note of what they "
    "leave out) [default: auto, multiblade where they are exact].",
)
def command(case, latex, form):
    """Print the mass, damping and stiffness matrices derived for CASE.

    Blade-coordinate form: the contribution of blade k at azimuth psi_k (body
    dofs, lag, flap). Multiblade form (identical blades): the exact
    time-invariant matrices, rows premultiplied by T' (cyclic rows are N/2
    times the averaged equations). Asked of a rotor whose blades differ (a
    failed damper), the multiblade form prints the matrices of identical
    blades under a note saying so: the differences add periodic terms it
    leaves out (the blade form holds them).
    """
    import sympy as sp

    from ..symbolic.codegen import blade_equations
    from ..symbolic.derive import LOCAL_DOFS
    from ..symbolic.multiblade import multiblade_equations

    the_case = load(case)
    eq = blade_equations()
    rotor, body = the_case.rotor, the_case.body
    if form == "auto":
        form = "multiblade" if rotor.identical and rotor.n_blades >= 3 else "blade"
    show = sp.latex if latex else (lambda m: sp.pretty(m, wrap_line=False, use_unicode=True))
    click.echo(f"# {printable(the_case.title, keep='')}")
    if form == "multiblade" and not rotor.identical:
        click.echo(_not_identical_note(the_case))
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
    _numeric_parts(the_case, show, form)


def _not_identical_note(case) -> str:
    """Why the multiblade matrices printed are not this rotor's (its blades differ), as comment lines."""
    from collections import Counter
    from dataclasses import fields

    from ..methods import Method, time_invariant

    blades = case.rotor.blades
    common = Counter(blades).most_common(1)[0][0]  # (the blade most are like)
    odd = next(((k, b) for k, b in enumerate(blades, start=1) if b != common), None)
    if odd is not None:
        k, blade = odd
        key = next(f.name for f in fields(blade) if getattr(blade, f.name) != getattr(common, f.name))
        why = f"blade {k}'s {key} is {getattr(blade, key):g}, the others' {getattr(common, key):g}"
    else:
        why = "its damper rods do not repeat from blade to blade: a failed or missing rod"
    how = (
        "in rotating axes (its body is isotropic)"
        if time_invariant(case) is Method.ROTATING
        else "by Floquet theory"
    )
    return (
        f"# NOTE: this rotor does not look the same from every blade ({why}),\n"
        "#   so its multiblade equations are periodic. The matrices below are those of identical\n"
        "#   blades (the symbols one blade's values), without the periodic terms the differences\n"
        "#   add; --form blade prints each blade's equations exactly.\n"
        f"#   groundres analyses this case {how}."
    )


def _numeric_parts(case, show, form: str) -> None:
    """What the symbolic matrices above leave out, in numbers: a rigid body's own matrices
    (in place of the diagonal M_, J_, K_, C_), the damper rods' (added on the blades), and in
    air the whole equations about the hover trim at one speed."""
    import numpy as np
    import sympy as sp

    from ..model.system import System

    def matrix(values):
        values = np.asarray(values, float)
        with np.errstate(over="ignore", invalid="ignore"):  # (rounding scales by 1e10: a huge value
            rounded = np.round(values, 10)  # would overflow, and is kept as it is)
        values = np.where(np.isfinite(rounded), rounded, values)
        return show(sp.Matrix(values.tolist()).applyfunc(lambda v: sp.Float(v, 6)))

    if case.body.form == "rigid":
        click.echo(
            f"\n# rigid body on gear legs: its own matrices on [{', '.join(case.body.dofs)}] replace the "
            "diagonal body symbols M_, J_, K_, C_ above (SI)"
        )
        for title, mat in zip(("mass", "damping", "stiffness"), case.body.matrices()):
            click.echo(f"\nbody {title} matrix:")
            click.echo(matrix(mat))
    if case.rotor.dampers:
        system = System(case.rotor, case.body)
        names = [f"{c.kind}_{c.name}" for c in system.coordinates[system.n_body :]]
        click.echo(
            f"\n# damper rods: c g g' and k g g' added in blade coordinates [{', '.join(names)}] "
            "(g: each rod's length gradient; SI), before any multiblade transform"
        )
        for title, mat in zip(("damping", "stiffness"), system.rod_matrices):
            click.echo(f"\nrod {title} matrix:")
            click.echo(matrix(mat[system.n_body :, system.n_body :]))
    if case.rotor.aero is not None:
        _in_air(case, matrix, form)


def _in_air(case, matrix, form: str) -> None:
    """The equations of a rotor in air, in numbers (SI) at the reference speed (else the sweep's
    middle): the symbols above are the structure's about zero, in vacuum."""
    import numpy as np

    from ..model.system import System
    from ..model.units import fmt_speed

    sweep = case.sweep
    speeds = sweep.speeds
    speed = sweep.reference if sweep.reference else float(speeds[len(speeds) // 2])
    system = System(case.rotor, case.body)
    if form == "multiblade":
        mats, coords = system.multiblade(np.array([speed]))[:, 0], system.multiblade_coordinates()
        what = "multiblade"
    else:
        mats, coords = system.matrices(np.array([speed]), 0.0)[:, 0], system.coordinates
        what = "blade coordinates, blade 1 at azimuth 0, of all blades together"
    inflow = (
        "\n#   and three Pitt-Peters inflow states (inflow_*: the air they carry down [m]; rates m/s)"
        if system.inflow_states
        else ""
    )
    click.echo(
        "\n# IN AIR: the symbols above are the structure's equations about zero, in vacuum. The rotor\n"
        f"#   in air is linearised about its hover trim (coning, trim lag) with strip-theory loads{inflow};\n"
        f"#   its whole equations at {fmt_speed(speed, sweep)} ({what}), SI, on\n"
        f"#   q = [{', '.join(c.symbol for c in coords)}]"
    )
    for title, mat in zip(("mass", "damping", "stiffness"), mats):
        click.echo(f"\nin-air {title} matrix:")
        click.echo(matrix(mat))
