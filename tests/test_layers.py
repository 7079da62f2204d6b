"""The house holds its shape: layers whose imports point one way, no circles, no re-exports.

The package's folders follow the work (docs/develop.md, "Layout"): each layer
may import its own and the layers below it, never one above. Every import is
read from the source (module level and inside functions alike), so a lazy
import that points up fails too.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import groundres

PACKAGE = Path(groundres.__file__).parent

#: Layers from the ground up; a module may import only from its own layer and those below.
#: (plotting sits below results: a result's .plot() hands its data to plotting/.)
LAYERS = [
    ("core", {"_version", "errors", "methods"}),
    ("symbolic", {"symbolic"}),
    ("model", {"model"}),
    ("solve", {"solve"}),
    ("modes", {"modes"}),
    ("assess", {"assess"}),
    ("plotting", {"plotting"}),
    ("results", {"results"}),
    ("pipeline", {"analysis", "nonlinear_runs"}),
    ("studies and pages", {"studies", "pages"}),
    ("cli", {"cli"}),
]
LEVEL = {part: level for level, (_, parts) in enumerate(LAYERS) for part in parts}
#: The only folders that may import each of these third-party packages.
HOMES = {
    "sympy": {"symbolic", "cli"},  # (groundres equations prints the derived matrices)
    "matplotlib": {"plotting", "cli"},
    "dask": {"studies"},
    "distributed": {"studies"},
    "click": {"cli"},
    "rich": {"cli"},
    "jinja2": {"pages"},
}
#: A module longer than this should be split by concept (docs/develop.md).
MAX_LINES = 500


def modules():
    """(dotted name relative to groundres, path) of every module of the package."""
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield ".".join(parts), path


def imports(name: str, path: Path):
    """(target, line) of every import in the module: groundres modules as dotted names
    relative to the package ("" is the package itself), other packages by their
    top-level name. ``from package import module`` names the module."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                top = alias.name.split(".")[0]
                yield (
                    (alias.name.removeprefix("groundres").lstrip(".") if top == "groundres" else top),
                    node.lineno,
                )
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            elif node.module.split(".")[0] == "groundres":
                target = node.module.removeprefix("groundres").lstrip(".")
            else:
                yield node.module.split(".")[0], node.lineno
                continue
            for alias in node.names:
                module = ".".join(filter(None, [target, alias.name]))
                yield (module if module in _internal() else target), node.lineno


def _internal() -> set:
    return {name for name, _ in modules()}


def layer_of(name: str) -> int | None:
    return LEVEL.get(name.split(".")[0]) if name else None


INTERNAL = _internal()


def test_every_module_has_a_layer():
    lost = [name for name in INTERNAL if name and layer_of(name) is None]
    assert not lost, f"modules on no layer (add them to LAYERS and docs/develop.md): {lost}"


@pytest.mark.parametrize("name, path", list(modules()), ids=lambda x: x if isinstance(x, str) else "")
def test_imports_point_down(name, path):
    if not name:  # (groundres/__init__.py loads the public API by name, on first use)
        return
    mine = layer_of(name)
    up = []
    for target, line in imports(name, path):
        if target == "":
            up.append(f"line {line}: the package itself (import the module that defines the name)")
        elif target in INTERNAL:
            level = layer_of(target)
            if level > mine:
                up.append(f"line {line}: {target} ({LAYERS[level][0]})")
        elif target in HOMES and name.split(".")[0] not in HOMES[target]:
            up.append(f"line {line}: {target} (only in {', '.join(sorted(HOMES[target]))})")
    assert not up, f"{name} ({LAYERS[mine][0]}) imports what it may not: {up}"


def test_every_third_party_home_uses_it():
    """The homes above are real (a rule about a package nobody imports would hold nothing)."""
    users = {target for name, path in modules() for target, _ in imports(name, path) if target in HOMES}
    assert users == set(HOMES), set(HOMES) - users


def test_no_import_cycles():
    graph = {name: set() for name in INTERNAL}
    for name, path in modules():
        for target, _ in imports(name, path):
            if target in INTERNAL and target != name:
                graph[name].add(target)
    # a folder whose __init__ is a docstring is imported with any of its modules, and imports
    # nothing back: no cycle runs through it (cli/ and the package's own face hold code)
    empty = {name for name, path in modules() if path.name == "__init__.py" and name not in ("", "cli")}
    for name in graph:
        graph[name] -= {t for t in graph[name] if t in empty and name.startswith(t + ".")}
    seen, stack, cycles = {}, [], []

    def visit(node):
        seen[node] = "open"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if seen.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt) :] + [nxt])
            elif nxt not in seen:
                visit(nxt)
        stack.pop()
        seen[node] = "done"

    for node in sorted(graph):
        if node not in seen:
            visit(node)
    assert not cycles, f"import cycles: {cycles}"


@pytest.mark.parametrize("name, path", list(modules()), ids=lambda x: x if isinstance(x, str) else "")
def test_modules_stay_small_and_define_what_they_hold(name, path):
    text = path.read_text(encoding="utf-8")
    generated = name.startswith("symbolic.generated_")  # (one derivation's code, written by codegen)
    assert generated or text.count("\n") <= MAX_LINES, (
        f"{name}: {text.count(chr(10))} lines; split it by concept"
    )
    tree = ast.parse(text)
    body = [n for n in tree.body if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
    defines = [n for n in body if not isinstance(n, (ast.Import, ast.ImportFrom))]
    if path.name == "__init__.py" and name not in ("", "cli"):  # (a folder: its docstring says what it holds)
        assert not body, f"{name}/__init__.py holds more than its docstring"
        return
    assert defines, f"{name} only imports: a module that re-exports another's names"


@pytest.mark.parametrize("name, path", list(modules()), ids=lambda x: x if isinstance(x, str) else "")
def test_no_module_hands_on_names_it_imports(name, path):
    """A name imported at module level is used there (no "re-exported for callers")."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    exported = set()  # (the package's face lists its public names in __all__)
    for node in tree.body if name == "" else ():
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
            exported |= {e.value for e in ast.walk(node.value) if isinstance(e, ast.Constant)}
    unused = [
        alias.asname or alias.name
        for node in tree.body
        if isinstance(node, ast.ImportFrom) and node.module != "__future__"
        for alias in node.names
        if (alias.asname or alias.name) not in used | exported
    ]
    assert not unused, f"{name} imports {unused} without using them"


def test_import_groundres_stays_light():
    """The public API loads on first use: importing the package (or its core) pulls in
    neither SymPy, matplotlib, the CLI library nor Dask."""
    heavy = ("sympy", "matplotlib", "click", "dask", "distributed")
    code = (
        f"import sys, groundres, groundres.analysis; print(sorted(m for m in {heavy!r} if m in sys.modules))"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert proc.stdout.strip() == "[]"
