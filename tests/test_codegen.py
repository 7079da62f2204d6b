"""The generated equations are package code that a fresh derivation reproduces; nothing else runs.

Provenance: the reference is every derivation of groundres.symbolic.derive (the blade's
equations, the rigid body's mass matrix, a gear leg's matrix, the damper rods' length
gradients: codegen.derive_all()), run afresh here (tens of seconds), against the committed
modules groundres/symbolic/generated_numpy.py and generated_sympy.py (regenerate with
``python -m groundres.symbolic.codegen``).

Why three comparisons
    The text is compared byte for byte, so that editing derive.py or the printing in codegen.py
    without regenerating fails. The text depends on SymPy's printers and common-subexpression
    elimination, which may change between SymPy releases, so that comparison runs only on the
    SymPy release that wrote the files (named in their header; the generation does not depend on
    PYTHONHASHSEED). On any release two more checks run: the rebuilt symbolic matrices equal the
    fresh ones exactly (the expanded difference is zero), and the NumPy function equals the fresh
    matrices evaluated at random parameter sets to 1e-12 relative (a few products and sums in
    float64 round at ~1e-16; a wrong coefficient or term is off by far more).
"""

import ast
import hashlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import groundres
from groundres.symbolic import codegen
from groundres.symbolic.derive import BLADE_SYMBOLS, rotor_speed

PACKAGE = Path(groundres.__file__).resolve().parent
SYMBOLIC = PACKAGE / "symbolic"
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def fresh():
    return codegen.derive_all()


def recorded_sympy_version(name):
    head = (SYMBOLIC / name).read_text(encoding="utf-8")[:1000]
    return re.search(r"with SymPy (\S+?)\.\s", head).group(1)


@pytest.mark.parametrize("name", [codegen.NUMPY_MODULE, codegen.SYMPY_MODULE])
def test_committed_module_is_what_the_derivation_generates(fresh, name):
    recorded = recorded_sympy_version(name)
    if recorded != sp.__version__:
        pytest.skip(f"{name} was written with SymPy {recorded}, this is {sp.__version__}: text may differ")
    expected = codegen.generated_sources(fresh)[name].encode("utf-8")
    assert (SYMBOLIC / name).read_bytes() == expected, (
        f"{name} is stale: run `python -m groundres.symbolic.codegen` and commit the result"
    )


def test_rebuilt_symbolic_matrices_equal_the_fresh_derivation(fresh):
    rebuilt = codegen.blade_equations()
    for group in codegen.GROUPS:
        for new, ref in zip(getattr(rebuilt, group), getattr(fresh["blade_harmonics"], group), strict=True):
            assert (new - ref).expand() == sp.zeros(*ref.shape), group
    for name in ("rigid_body_mass", "leg_matrix", "rod_to_hub", "rod_to_blade"):
        ref = fresh[name]
        assert (codegen.symbolic(name) - ref).applyfunc(sp.simplify) == sp.zeros(*ref.shape), name


def test_numpy_function_equals_the_fresh_derivation_at_random_parameters(fresh):
    rng = np.random.default_rng(20240611)
    symbols = [rotor_speed] + [BLADE_SYMBOLS[name] for name in codegen.BLADE_ARGUMENTS[1:]]
    signed = [codegen.BLADE_ARGUMENTS.index(k) for k in ("hub_height", "hub_x", "hub_y")]
    for _ in range(3):
        values = rng.uniform(0.1, 50.0, len(symbols))
        values[signed] *= rng.choice([-1.0, 1.0], len(signed))  # the hub may be anywhere
        numeric = codegen.blade_function()(*values)
        subs = dict(zip(symbols, [sp.Float(v, 30) for v in values]))
        for g, group in enumerate(codegen.GROUPS):
            for h, matrix in enumerate(getattr(fresh["blade_harmonics"], group)):
                ref = np.array(matrix.xreplace(subs).evalf(30).tolist(), dtype=float)
                scale = np.abs(ref).max(initial=0.0)
                np.testing.assert_allclose(numeric[g, h], ref, rtol=1e-12, atol=1e-12 * scale)


@pytest.mark.parametrize("name", ["rigid_body_mass", "leg_matrix", "rod_to_hub", "rod_to_blade"])
def test_body_leg_and_rod_functions_equal_the_fresh_derivation(fresh, name):
    rng = np.random.default_rng(7)
    symbols = codegen._functions()[name][0]
    for _ in range(3):
        values = {arg: rng.uniform(-2.0, 2.0) for arg in symbols}
        if name == "rigid_body_mass":
            values["mass"] = rng.uniform(0.5, 3.0)
        numeric = codegen.generated(name)(**values)
        subs = {symbols[arg]: sp.Float(v, 30) for arg, v in values.items()}
        ref = np.array(fresh[name].xreplace(subs).evalf(30).tolist(), dtype=float).reshape(numeric.shape)
        np.testing.assert_allclose(numeric, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


def test_numpy_module_does_not_import_sympy():
    code = "import sys; import groundres.symbolic.generated_numpy; print('sympy' in sys.modules)"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert proc.stdout.strip() == "False"


def old_cache_key():
    """The file name key of the removed disk cache, computed as it did (hash of the sources)."""
    digest = hashlib.sha256()
    for name in ("derive.py", "codegen.py"):
        digest.update((SYMBOLIC / name).read_bytes())
    return digest.hexdigest()[:16]


def plant(folder: Path, marker: Path):
    """Files a writable cache folder could hold; any of them running writes the marker."""
    folder.mkdir(parents=True, exist_ok=True)
    payload = f"open({str(marker)!r}, 'a').write({str(folder)!r} + '\\n')"
    for key in (old_cache_key(), "0" * 16):
        (folder / f"blade_{key}.py").write_text(
            f"{payload}\ndef blade_harmonics(*args):\n    {payload}\n    raise SystemExit(0)\n"
        )
        srepr = [f"__import__('os').system('touch {marker}')"]
        (folder / f"blade_{key}.json").write_text(json.dumps({"mass": srepr, "damping": [], "stiffness": []}))
    for name in ("generated_numpy.py", "generated_sympy.py", "codegen.py", "derive.py"):
        (folder / name).write_text(payload + "\n")


def test_nothing_from_a_writable_folder_is_imported_or_evaluated(tmp_path):
    marker = tmp_path / "ran"
    home, xdg, custom = tmp_path / "home", tmp_path / "xdg", tmp_path / "custom"
    for folder in (home / ".cache" / "groundres", xdg / "groundres", custom):
        plant(folder, marker)
    env = {**os.environ, "HOME": str(home), "XDG_CACHE_HOME": str(xdg), "GROUNDRES_CACHE_DIR": str(custom)}
    work = tmp_path / "work"
    work.mkdir()
    for args in (["run", "--out", str(tmp_path / "out")], ["equations", "hammond-1974"]):
        proc = subprocess.run(
            [sys.executable, "-m", "groundres.cli", *args], cwd=work, env=env, capture_output=True, text=True
        )
        assert proc.returncode == 0, proc.stderr
        assert not marker.exists(), f"`groundres {args[0]}` ran a planted file: {marker.read_text()}"
    assert (tmp_path / "out" / "summary.json").exists()
    assert "mass matrix" in proc.stdout


#: Calls and imports that would run text or files as code; none belongs in the package.
FORBIDDEN_CALLS = {"eval", "exec", "compile", "__import__"}
FORBIDDEN_NAMES = {
    "spec_from_file_location",
    "module_from_spec",
    "exec_module",
    "SourceFileLoader",
    "run_path",
    "parse_expr",
}
FORBIDDEN_MODULES = {"runpy", "importlib.util", "importlib.machinery", "pickle", "marshal"}


def test_package_source_runs_no_text_or_file_as_code():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        where = path.relative_to(PACKAGE)
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                if node.func.id in FORBIDDEN_CALLS:
                    found.append(f"{where}:{node.lineno} {node.func.id}()")
                if node.func.id == "import_module" and str(where) != "__init__.py":
                    found.append(f"{where}:{node.lineno} import_module()")
            name = node.attr if isinstance(node, ast.Attribute) else getattr(node, "id", None)
            if name in FORBIDDEN_NAMES:
                found.append(f"{where}:{node.lineno} {name}")
            if isinstance(node, ast.Import | ast.ImportFrom):
                modules = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module]
                modules += [f"{node.module}.{a.name}" for a in node.names if isinstance(node, ast.ImportFrom)]
                found += [f"{where}:{node.lineno} import {m}" for m in modules if m in FORBIDDEN_MODULES]
    assert found == []
