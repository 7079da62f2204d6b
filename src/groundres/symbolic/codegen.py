"""The one place where symbolic expressions become code, shipped in the package.

The derivations (:mod:`groundres.symbolic.derive`) take tens of seconds,
so it does not run when groundres is used. The project runs it once and
commits its result as three generated modules of the package:

``generated_numpy.py``
    ``blade_harmonics``, the harmonic coefficient matrices as NumPy
    assignments (no SymPy), used by the numeric core through
    :func:`blade_function`; likewise ``rigid_body_mass``, ``leg_matrix``,
    ``rod_to_hub`` and ``rod_to_blade`` (:func:`generated`) for a body on
    gear legs and damper rods.
``generated_air.py``
    ``blade_in_air``, ``trim_in_air`` and ``inflow_in_air``
    (:mod:`groundres.symbolic.aero`): one blade's equations in air about its
    hover trim, the trim loads, and what dynamic inflow adds, NumPy
    only (long, so imported only for a case in air; the tests check them
    against the derivation at random parameters);
``generated_sympy.py``
    the same matrices as SymPy expressions in plain source, rebuilt by
    :func:`blade_equations` and :func:`symbolic` for ``groundres equations``
    and the tests.

Nothing is read from a cache, imported from a user folder or evaluated from
text: all three modules are ordinary package code. After editing ``derive.py``
(or the printing below), regenerate them from a source checkout with

    python -m groundres.symbolic.codegen           # rewrite the three modules
    python -m groundres.symbolic.codegen --check   # exit 1 if they are stale

``tests/test_codegen.py`` derives afresh and fails if the committed modules
differ from what the derivation gives.
"""

from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path

#: Arguments of the generated blade function, in order (SI units).
BLADE_ARGUMENTS = (
    "rotor_speed",
    "blade_mass",
    "blade_static_moment",
    "blade_inertia",
    "hinge_offset",
    "hub_height",
    "hub_x",
    "hub_y",
    "lag_stiffness",
    "lag_damping",
    "flap_stiffness",
    "flap_damping",
)
#: The span's moments the functions in air take (:data:`groundres.symbolic.aero.SPAN_SYMBOLS`):
#: int rho^k d rho over the lifting span, rho the distance from the hinge [m^(k+1)].
SPAN_ARGUMENTS = tuple(f"span_moment_{k}" for k in range(5))
#: Groups of the coefficient arrays, in order.
GROUPS = ("mass", "damping", "stiffness")
#: The generated modules, next to this file.
NUMPY_MODULE = "generated_numpy.py"
SYMPY_MODULE = "generated_sympy.py"
#: The blade in air and its trim, NumPy only (long: imported only for a case in air).
AIR_MODULE = "generated_air.py"
AIR_FUNCTIONS = ("blade_in_air", "trim_in_air", "inflow_in_air")
#: The inflow states of Pitt-Peters dynamic inflow (velocities down the shaft [m/s]): uniform,
#: and the tip values of the parts growing forward and to the left (docs/theory.md); after
#: LOCAL_DOFS among a blade's local coordinates in ``inflow_in_air``.
INFLOW_STATES = ("uniform", "forward", "left")
#: The trim state the functions in air take at every speed (in the order of the monomials' exponents);
#: their other arguments are the rotor's, the body's and the air's, fixed over a sweep.
AIR_STATE = (
    "rotor_speed",
    "inflow_ratio",
    "coning",
    "trim_lag",
    "cos_coning",
    "sin_coning",
    "cos_trim_lag",
    "sin_trim_lag",
)
_HERE = Path(__file__).resolve().parent

# Generated code is neither formatted nor linted by ruff: its text must stay
# exactly what the generator writes.
_PRAGMAS = ("# fmt: off", "# ruff: noqa")


def _functions():
    """name -> (symbol dict of its arguments (name -> symbol, in order), shape of its array,
    derivation): every generated function (the blade's first)."""
    from . import aero, derive, inflow

    return {
        "blade_harmonics": (
            {"rotor_speed": derive.rotor_speed, **derive.BLADE_SYMBOLS},
            (3, 5, len(derive.LOCAL_DOFS), len(derive.LOCAL_DOFS)),
            derive.derive_blade,
        ),
        "rigid_body_mass": (derive.RIGID_SYMBOLS, (6, 6), derive.derive_rigid_body),
        "leg_matrix": (derive.LEG_SYMBOLS, (6, 6), derive.derive_leg),
        "rod_to_hub": (_rod_symbols(to_hub=True), (2,), lambda: derive.derive_rod(True)),
        "rod_to_blade": (_rod_symbols(to_hub=False), (4,), lambda: derive.derive_rod(False)),
        "blade_in_air": (_fixed_symbols(), None, aero.derive_blade_in_air),
        "trim_in_air": (_fixed_symbols(), None, aero.derive_trim),
        "inflow_in_air": (_fixed_symbols(), None, inflow.derive_inflow_coupling),
    }


def _fixed_symbols() -> dict:
    """The arguments of the functions in air that stay fixed over a sweep (all but AIR_STATE)."""
    from . import aero, derive

    state = ("inflow_ratio", "coning", "trim_lag")
    fixed = {k: v for k, v in aero.AERO_SYMBOLS.items() if k not in state}
    return {**derive.BLADE_SYMBOLS, **fixed, **aero.SPAN_SYMBOLS}


def _rod_symbols(to_hub: bool) -> dict:
    from .derive import ROD_SYMBOLS

    skip = ("end_hinge_offset", "spacing") if to_hub else ()
    return {k: v for k, v in ROD_SYMBOLS.items() if k not in skip}


def blade_function():
    """The generated ``blade_harmonics`` callable (package code, NumPy only).

    ``blade_harmonics(rotor_speed, blade_mass, ...)`` takes BLADE_ARGUMENTS
    (broadcastable arrays, SI) and returns an array of shape
    ``(3, 5, 8, 8) + broadcast shape``: [mass, damping, stiffness] x harmonics
    (1, cos psi, sin psi, cos 2 psi, sin 2 psi) x LOCAL_DOFS x LOCAL_DOFS.
    """
    from .generated_numpy import blade_harmonics

    return blade_harmonics


def generated(name: str):
    """A generated NumPy function by name: ``rigid_body_mass`` (6 x 6), ``leg_matrix`` (6 x 6),
    ``rod_to_hub`` (2,), ``rod_to_blade`` (4,) (:mod:`groundres.symbolic.derive`), each
    taking its arguments by keyword (broadcastable arrays, SI) and returning its array
    with the broadcast shape last."""
    if name in AIR_FUNCTIONS:
        from . import generated_air

        return getattr(generated_air, name)
    from . import generated_numpy

    return getattr(generated_numpy, name)


def air_coefficients(name: str, **fixed):
    """The coefficients of a function in air (one of AIR_FUNCTIONS) for one
    blade: an array (K, ...) over its K monomials of the trim state, from the blade's, the
    body's and the air's arguments (numbers, SI; :func:`_fixed_symbols`)."""
    return generated(name)(**fixed)


@functools.cache
def _exponents(name: str):
    """The monomials of a function in air as two factors, each a product of few distinct powers:
    of (speed, inflow ratio, coning, trim lag), and of (their cosines and sines). Returns the
    highest power p, each distinct factor's rows in a table of the 8 state values' powers 0..p
    (:func:`air_monomials`), (P, 4) and (Q, 4), and each monomial's pair of factors, (K,), (K,)."""
    import numpy as np

    from . import generated_air

    exponents = np.array(getattr(generated_air, f"{name.upper()}_MONOMIALS"), dtype=np.intp)
    top = int(exponents.max())
    rows = exponents + (top + 1) * np.arange(8)  # (row of value j to the power e: j (p + 1) + e)
    plain, plain_of = np.unique(rows[:, :4], axis=0, return_inverse=True)
    circular, circular_of = np.unique(rows[:, 4:], axis=0, return_inverse=True)
    return top, plain, circular, plain_of.reshape(-1), circular_of.reshape(-1)


def air_monomials(name: str, rotor_speed, inflow_ratio, coning, trim_lag):
    """The monomials of the trim state of a function in air at every speed, (n_s, K) (arrays
    (n_s,): [rad/s], [-], [rad], [rad]): a table of the powers of the state and of its cosines
    and sines (repeated products: exact small whole powers), and products of the few distinct
    factors that occur (:func:`_exponents`)."""
    import numpy as np

    top, plain, circular, plain_of, circular_of = _exponents(name)
    state = np.array(np.broadcast_arrays(rotor_speed, inflow_ratio, coning, trim_lag), dtype=float)
    state = state.reshape(4, -1)
    values = np.concatenate(
        [state, np.cos(state[2:3]), np.sin(state[2:3]), np.cos(state[3:]), np.sin(state[3:])]
    )
    powers = np.ones((8, top + 1, values.shape[1]))
    for e in range(1, top + 1):
        powers[:, e] = powers[:, e - 1] * values
    powers = powers.reshape(8 * (top + 1), -1)
    first, second = powers[plain].prod(1), powers[circular].prod(1)  # (P, n_s), (Q, n_s)
    return first.T[:, plain_of] * second.T[:, circular_of]


def air_values(name: str, coefficients, rotor_speed, inflow_ratio, coning, trim_lag):
    """The function in air at every speed: ``sum_k monomial_k(state) coefficients[k]``, shape
    (...) + (n_s,) like the vacuum's functions, from :func:`air_coefficients` and the trim state
    at each speed (arrays (n_s,): [rad/s], [-], [rad], [rad])."""
    import numpy as np

    monomials = air_monomials(name, rotor_speed, inflow_ratio, coning, trim_lag)
    flat = coefficients.reshape(len(coefficients), -1)
    return np.moveaxis((monomials @ flat).reshape((len(monomials),) + coefficients.shape[1:]), 0, -1)


def blade_equations():
    """The symbolic blade equations (BladeEquations), rebuilt from the generated module."""
    import sympy as sp

    from .derive import HARMONICS, LOCAL_DOFS, BladeEquations
    from .generated_sympy import blade_harmonics

    n = len(LOCAL_DOFS)
    groups = [[sp.zeros(n, n) for _ in HARMONICS] for _ in GROUPS]
    for (g, h, i, j), expr in blade_harmonics():
        groups[g][h][i, j] = expr
    return BladeEquations(*(tuple(group) for group in groups))


def symbolic(name: str):
    """A generated function's array as a SymPy matrix (2 indices) or column (1), rebuilt
    from the generated module (``blade_harmonics``: see :func:`blade_equations`)."""
    import sympy as sp

    from . import generated_sympy

    shape = _functions()[name][1]
    out = sp.zeros(shape[0], shape[1] if len(shape) > 1 else 1)
    for index, expr in getattr(generated_sympy, name)():
        out[index if len(index) > 1 else (index[0], 0)] = expr
    return out


def _as_array(name: str, derived):
    """(index, expression) of every nonzero entry of a derivation's result, in index order."""
    if name in AIR_FUNCTIONS:  # (Terms: the coefficients of each monomial of the trim state)
        return list(derived.entries.items())
    if name == "blade_harmonics":
        return [
            ((g, h, i, j), matrix[i, j])
            for g, group in enumerate(GROUPS)
            for h, matrix in enumerate(getattr(derived, group))
            for i in range(matrix.rows)
            for j in range(matrix.cols)
            if matrix[i, j] != 0
        ]
    if derived.cols == 1:
        return [((i,), derived[i, 0]) for i in range(derived.rows) if derived[i, 0] != 0]
    return [
        ((i, j), derived[i, j])
        for i in range(derived.rows)
        for j in range(derived.cols)
        if derived[i, j] != 0
    ]


def _nonzero(name: str, derived):
    """((index), expression) of every nonzero entry, the symbols renamed to the argument
    names (valid, unambiguous Python names: the symbols ``S`` and ``I`` would clash with
    SymPy's)."""
    import sympy as sp

    symbols = _functions()[name][0]
    rename = {symbol: sp.Symbol(arg) for arg, symbol in symbols.items()}
    return [(index, expr.xreplace(rename)) for index, expr in _as_array(name, derived)]


def derive_all() -> dict:
    """name -> derivation result of every generated function (tens of seconds)."""
    return {name: derivation() for name, (_, _, derivation) in _functions().items()}


def _header(what: str) -> list[str]:
    import sympy as sp

    return [
        f'"""{what}',
        "",
        "Generated by ``python -m groundres.symbolic.codegen`` from groundres/symbolic/derive.py",
        f"with SymPy {sp.__version__}. Do not edit: regenerate (tests/test_codegen.py checks it).",
        '"""',
        *_PRAGMAS,
        "",
    ]


def numpy_source(derived: dict, air: bool = False) -> str:
    """Source of ``generated_numpy.py`` (or, ``air``, ``generated_air.py``): one NumPy
    function per derivation."""
    import sympy as sp
    from sympy.printing.numpy import NumPyPrinter

    printer = NumPyPrinter({"fully_qualified_modules": True, "inline": True})
    what = (
        "One blade's equations in air about its hover trim, and the trim loads, as NumPy code."
        if air
        else "Derived matrices (blade equations, rigid body, gear leg, damper rods) as NumPy code."
    )
    lines = [*_header(what), "import numpy"]
    if air:
        lines.append(
            f"\n#: The trim state the monomials run over (codegen.AIR_STATE).\nSTATE = {AIR_STATE!r}"
        )
    for name, (symbols, shape, _) in _functions().items():
        if (name in AIR_FUNCTIONS) != air:
            continue
        if air:  # (the coefficients of the monomials, and the monomials' exponents over STATE)
            shape = derived[name].full_shape
            lines += ["", "", f"{name.upper()}_MONOMIALS = {derived[name].monomials!r}"]
        entries = _nonzero(name, derived[name])
        shared, reduced = sp.cse([expr for _, expr in entries], symbols=sp.numbered_symbols("t_"))
        args = ", ".join(symbols)
        first = next(iter(symbols))
        lines += [
            "",
            "",
            f"def {name}({args}):",
            f'    """Array of shape {shape} + broadcast shape (see codegen)."""',
            f"    broadcast = numpy.broadcast_arrays({args})",
            f"    {args}, = [numpy.asarray(a, dtype=float) for a in broadcast]",
            f"    out = numpy.zeros({shape} + {first}.shape)",
        ]
        lines += [f"    {var} = {printer.doprint(expr)}" for var, expr in shared]
        lines += [
            f"    out[{', '.join(map(str, index))}] = {printer.doprint(expr)}"
            for (index, _), expr in zip(entries, reduced)
        ]
        lines.append("    return out")
    return "\n".join(lines) + "\n"


def sympy_source(derived: dict) -> str:
    """Source of ``generated_sympy.py``: the nonzero entries as SymPy expressions."""
    from sympy.printing.str import StrPrinter

    from . import derive

    class SourcePrinter(StrPrinter):
        # Every number stays exact: a bare fraction would otherwise print as
        # "1/2" and be read by Python as a float. Within products and powers
        # of symbols the printer's own "x/2" is exact already.
        def _print_Rational(self, expr):
            if expr.q == 1:
                return str(expr.p)
            return f"Rational({expr.p}, {expr.q})"

        _print_Half = _print_Rational

    printer = SourcePrinter({"order": None})
    tables = {
        f"derive.{t}": getattr(derive, t)
        for t in ("BLADE_SYMBOLS", "RIGID_SYMBOLS", "LEG_SYMBOLS", "ROD_SYMBOLS")
    }
    functions = []
    for name, (symbols, _, _) in _functions().items():
        if name in AIR_FUNCTIONS:
            continue
        body = [
            f"        ({index}, {printer.doprint(expr)})," for index, expr in _nonzero(name, derived[name])
        ]
        binds = []
        for arg, symbol in symbols.items():
            if arg == "rotor_speed":
                binds.append("    rotor_speed = derive.rotor_speed")
                continue
            table = next(t for t, values in tables.items() if values.get(arg) == symbol)
            binds.append(f'    {arg} = {table}["{arg}"]')
        functions += [
            "",
            "",
            f"def {name}():",
            '    """((index), expression) of every nonzero entry (see codegen)."""',
            *binds,
            "    return (",
            *body,
            "    )",
        ]
    text = "\n".join(functions)
    used = [f for f in ("Rational", "cos", "sin", "sqrt") if f"{f}(" in text]
    imports = [f"from sympy import {', '.join(used)}", ""] if used else []
    lines = [
        *_header(
            "Derived matrices (blade equations, rigid body, gear leg, damper rods) as SymPy expressions."
        ),
        *imports,
        "from . import derive",
    ]
    return "\n".join(lines) + text + "\n"


def generated_sources(derived: dict | None = None) -> dict[str, str]:
    """File name -> text of the two generated modules (derives if not given)."""
    derived = derive_all() if derived is None else derived
    return {
        NUMPY_MODULE: numpy_source(derived),
        SYMPY_MODULE: sympy_source(derived),
        AIR_MODULE: numpy_source(derived, air=True),
    }


def main(argv=None) -> int:
    """Developer command: derive and (re)write the generated modules, or check them."""
    parser = argparse.ArgumentParser(
        prog="python -m groundres.symbolic.codegen",
        description="Derive the blade equations and write the generated modules next to codegen.py.",
    )
    parser.add_argument("--check", action="store_true", help="Only compare; exit 1 if a module is stale.")
    options = parser.parse_args(argv)
    stale = []
    for name, text in generated_sources().items():
        path = _HERE / name
        current = path.read_bytes() if path.exists() else None
        if current == text.encode("utf-8"):
            continue
        stale.append(name)
        if not options.check:
            path.write_bytes(text.encode("utf-8"))
    verb = "stale" if options.check else "rewrote"
    print(f"{verb}: {', '.join(stale)}" if stale else "generated modules are up to date")
    return 1 if options.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
