"""The house rules as tests: no import circle, no import against the layering, a cheap
``import trcopt`` and ``trcopt --help``, and no module over 500 lines.

Every ``import`` statement of the package counts, also those inside functions: a lazy import is
still a dependency. ``from trcopt.a import b`` depends on ``trcopt.a.b`` when that is a module,
else on ``trcopt.a``.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "trcopt"

BASE = {"units", "errors", "codes", "modes", "geometry", "solution", "lazy", "progress", "textlines"}
# room → the rooms it may import (besides itself). Lower rooms never import higher ones; timing and
# io know only tool-path segments; geometry knows no program text; nothing imports pipeline or cli
# except the command line itself.
ALLOWED: dict[str, set[str]] = {
    "units": set(),
    "lazy": set(),
    "textlines": set(),
    "progress": set(),
    "errors": {"codes"},
    "codes": set(),
    "modes": set(),
    "geometry": set(),
    "solution": {"errors", "codes"},
    "config": BASE,
    "path": BASE,
    "trajectory": BASE | {"config", "path"},
    "io": BASE | {"config", "path", "trajectory"},
    "timing": BASE | {"config", "path", "trajectory"},
    "kinematics": BASE,
    "nc": BASE | {"config"},
    "compensation": BASE | {"config", "path", "nc"},
    "controllers": BASE | {"config", "path", "nc", "compensation", "io"},
    "verify": BASE | {"config", "path"},
    "optimize": BASE | {"config", "path", "nc", "compensation", "verify", "timing", "trajectory"},
    "pipeline": BASE | {"config", "path", "nc", "compensation", "controllers", "verify", "optimize", "timing", "io",
                        "kinematics", "trajectory"},
    "batch": BASE | {"config", "path", "nc", "pipeline", "io", "controllers"},
    "cli": BASE | {"config", "path", "nc", "compensation", "controllers", "verify", "optimize", "timing", "io",
                   "kinematics", "pipeline", "batch", "__init__", "trajectory"},
    "__main__": {"cli"},
    "__init__": BASE | {"config", "path"},
}
HEAVY = ("numpy", "scipy", "casadi", "toppra", "clarabel", "matplotlib", "ezdxf")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in PACKAGE.rglob("*.py")}


def _imports(path: Path, modules: dict[str, Path]) -> set[str]:
    """The trcopt modules ``path`` imports (anywhere in the file)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.split(".")[0] == "trcopt")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "trcopt":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                found.add(sub if sub in modules else target)
    while True:  # a name inside a module resolves to the module
        unresolved = {m for m in found if m not in modules}
        if not unresolved:
            return found - {name}
        found = (found - unresolved) | {m.rpartition(".")[0] for m in unresolved}


def _room(module: str) -> str:
    parts = module.split(".")
    return "__init__" if len(parts) == 1 else parts[1]


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    modules = _modules()
    return {m: _imports(p, modules) for m, p in modules.items()}


def test_every_room_has_a_rule(graph: dict[str, set[str]]) -> None:
    assert {_room(m) for m in graph} <= set(ALLOWED)


def test_no_import_against_the_layering(graph: dict[str, set[str]]) -> None:
    wrong = sorted(
        f"{m} imports {t}"
        for m, targets in graph.items()
        for t in targets
        if _room(t) != _room(m) and _room(t) not in ALLOWED[_room(m)]
    )
    assert wrong == []


def test_no_import_circle(graph: dict[str, set[str]]) -> None:
    # Tarjan's strongly connected components; a package's __init__ importing its own modules is
    # the normal direction, a module importing its package's __init__ back closes a circle
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []
    counter = [0]
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    assert circles == []


def test_the_layer_check_sees_a_violation(graph: dict[str, set[str]]) -> None:
    # the rules are live: the scan finds the imports it judges
    assert "trcopt.geometry.vec" in graph["trcopt.geometry.primitives"]
    assert "trcopt.controllers.base" in graph["trcopt.controllers.siemens"]
    assert "pipeline" not in ALLOWED["timing"] and "nc" not in ALLOWED["io"] and "nc" not in ALLOWED["geometry"]


def test_no_module_over_500_lines() -> None:
    long = sorted(
        f"{p.relative_to(ROOT)} ({n})"
        for p in PACKAGE.rglob("*.py")
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 500
    )
    assert long == []


@pytest.mark.parametrize(
    "code",
    [
        "import trcopt",
        "import trcopt.cli as c; import contextlib, io\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try: c.main(['--help'])\n"
        "    except SystemExit: pass",
        "import trcopt.optimize.corners.strategies as s; s.get('optimal')",
        "import trcopt.cli as c; import contextlib, io\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try: c.main(['plan', '--help'])\n"
        "    except SystemExit: pass",
    ],
    ids=["import trcopt", "trcopt --help", "corner strategy registry", "trcopt plan --help"],
)
def test_cheap_entry_points_load_no_numerical_library(code: str) -> None:
    probe = code + "\nimport sys\nprint(sorted(m for m in sys.modules if m.split('.')[0] in " + repr(HEAVY) + "))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip().splitlines()[-1] == "[]"
