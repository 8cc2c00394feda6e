"""The import graph of webline keeps its layers (docs/architecture.md): every import, at module
level, inside a function or under ``TYPE_CHECKING``, points to the same layer or one below, and
no set of modules imports itself round in a cycle.

Run as a script (``python tests/unit/test_layers.py``, as ``make lint`` does) it prints every
violation and exits 1 if there is one.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"

#: Layers, lowest first; a module belongs to the first entry that is it or a package above it.
#: ``webline`` itself (the front door, ``webline/__init__.py``) re-exports model and sim entry
#: points, so it sits just above sim; the layers above may use it.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("webline.units", "webline.unit_registry", "webline.errors", "webline.version",
     "webline.data", "webline.files", "webline.verdict", "webline.limits", "webline.extras"),
    ("webline.spec",),
    ("webline.line", "webline.physics", "webline.profiles"),
    ("webline.model",),
    ("webline.control",),
    ("webline.sim.elements",),
    ("webline.sim.drives",),
    ("webline.sim.core",),
    ("webline.sim.linear",),
    ("webline.sim.results",),
    ("webline.sim.branches.loop",),
    ("webline.sim.branches",),
    ("webline.sim",),
    ("webline.sim.sweeps",),
    ("webline",),
    ("webline.fmu",),
    ("webline.analysis",),
    ("webline.gym",),
    ("webline.report.text",),
    ("webline.report.plots",),
    ("webline.report",),
    ("webline.twin.traces",),
    ("webline.twin.fitting",),
    ("webline.twin.tuning",),
    ("webline.twin",),
    ("webline.studies",),
    ("webline.cli", "webline.cli_analyze", "webline.cli_benchmark", "webline.cli_branches",
     "webline.cli_export",
     "webline.cli_common",
     "webline.cli_roll", "webline.cli_sweep", "webline.cli_tune",
     "webline.cli_twin", "webline.cli_warm", "webline.cli_hints"),
)


def module_files(src: Path = SRC) -> dict[str, Path]:
    """Dotted name -> file of every module under ``src/webline``."""
    out = {}
    for path in sorted((src / "webline").rglob("*.py")):
        parts = list(path.relative_to(src).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def imports_of(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """webline modules ``name`` imports anywhere in its file (``from p import m`` counts as an
    import of module ``p.m`` where that is a module, else of ``p``)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            for a in node.names:
                found.add(f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base)
    return {m for m in found if m in modules and m != name}


def missing_imports(src: Path = SRC) -> list[str]:
    """'module -> name' for every import of a ``webline`` module that does not exist (a path
    left behind by a move: a lazy import would only fail when its function runs)."""
    modules = module_files(src)
    out = []
    for name, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and not node.level and node.module:
                targets = [node.module]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            out += [f"{name} -> {t}" for t in targets
                    if t.split(".")[0] == "webline" and t not in modules]
    return sorted(out)


def layer_of(module: str) -> int:
    """Index in ``LAYERS`` of the most specific entry that is ``module`` or contains it."""
    best, depth = -1, -1
    for k, entries in enumerate(LAYERS):
        for entry in entries:
            if (module == entry or module.startswith(entry + ".")) and entry.count(".") > depth:
                best, depth = k, entry.count(".")
    if best < 0:
        raise AssertionError(f"{module} is in no layer: add it to LAYERS and docs/architecture.md")
    return best


def graph(src: Path = SRC) -> dict[str, set[str]]:
    modules = module_files(src)
    return {name: imports_of(name, path, modules) for name, path in modules.items()}


def upward_imports(edges: dict[str, set[str]]) -> list[str]:
    """'a -> b' for every import of a module in a higher layer."""
    return sorted(f"{a} (layer {layer_of(a)}) -> {b} (layer {layer_of(b)})"
                  for a, targets in edges.items() for b in targets
                  if layer_of(b) > layer_of(a))


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
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
                out.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_every_module_is_in_a_layer() -> None:
    for name in graph():
        layer_of(name)


def test_no_import_points_up() -> None:
    found = upward_imports(graph())
    assert not found, "imports that point up a layer:\n" + "\n".join(found)


def test_every_webline_import_exists() -> None:
    found = missing_imports()
    assert not found, "imports of modules that do not exist:\n" + "\n".join(found)


def test_no_import_cycle() -> None:
    found = cycles(graph())
    assert not found, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_checks_catch_what_they_are_for(tmp_path: Path) -> None:
    """The walker sees a lazy upward import and a TYPE_CHECKING cycle in a made-up package."""
    pkg = tmp_path / "webline"
    (pkg / "sim" / "core").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "line.py").write_text("def f():\n    from webline.sim.core import plan\n")
    (pkg / "sim" / "__init__.py").write_text("")
    (pkg / "sim" / "core" / "__init__.py").write_text("")
    (pkg / "sim" / "core" / "plan.py").write_text("from . import kernel\n")
    (pkg / "sim" / "core" / "kernel.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .plan import Plan\n")
    edges = graph(tmp_path)
    core = layer_of("webline.sim.core")
    assert upward_imports(edges) == [
        f"webline.line (layer 2) -> webline.sim.core.plan (layer {core})"]
    assert cycles(edges) == [["webline.sim.core.kernel", "webline.sim.core.plan"]]


if __name__ == "__main__":
    found = graph()
    problems = (upward_imports(found) + [" <-> ".join(c) for c in cycles(found)]
                + missing_imports())
    print("\n".join(problems) or f"layers ok: {len(found)} modules, "
          f"{sum(map(len, found.values()))} imports, none upward, no cycle")
    sys.exit(1 if problems else 0)
