"""The layers of the package, read from its imports (every ``import``/``from ... import`` of
``cosim``, absolute or relative, at module level or inside a function).

A module may import its own part of the package and the parts of lower layers, never a part of
its own layer or above; no two modules import each other, directly or around a circle, except
the block registry (:mod:`cosim.cosimulation.registry`, which names the blocks and controllers
that register with it). ``cosim/__init__.py`` names the public API by strings and imports nothing
of it, so it is at the bottom; ``__main__`` modules are entry points, at the top.
"""
from __future__ import annotations

import ast
from functools import lru_cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Parts of the package (top-level modules and subpackages) by layer, lowest first. The parts of
#: one layer do not import each other.
LAYERS: list[tuple[str, ...]] = [
    ("cosim", "errors", "processes", "native", "cli_options", "statespace", "progress", "plotting"),
    ("outputs", "folder_lock"),
    ("analytic",),  # formulas only
    ("compiler",),
    ("fmu", "diagram", "wasm"),  # generic FMI tools: no bicycle
    ("nonlinear", "cosimulation"),
    ("bicycle", "engines"),  # bicycle physics over FMUs; the FMI/SSP engines beside cosim's master
    ("figures", "studies", "matrix"),
    ("app",),
    ("cli",),
    ("__main__",),  # python -m cosim
]
#: The one circle that may stay: blocks and controllers register with the registry, which lists them.
ALLOWED_CIRCLES = [{"cosim.cosimulation.registry", "cosim.cosimulation.blocks", "cosim.cosimulation.controllers"}]


def module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules(root: Path) -> dict[str, Path]:
    """Module name -> file of every module of the ``cosim`` package under ``root``."""
    return {module_name(p, root): p for p in sorted((root / "cosim").rglob("*.py"))}


@lru_cache(maxsize=8)
def imports(root: Path) -> list[tuple[str, str, str]]:
    """(importer, imported module, "file:line") of every import of ``cosim`` under ``root``; a name
    taken from a package is the submodule of that name where there is one."""
    known = modules(root)
    found = []
    for name, path in known.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(base + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
            else:
                continue
            where = f"{path.relative_to(root)}:{node.lineno}"
            for target in targets:
                if target == "cosim" or target.startswith("cosim."):
                    while target not in known and "." in target:  # an attribute of a module
                        target = target.rpartition(".")[0]
                    found.append((name, target, where))
    return found


def part(module: str) -> str:
    """The part of the package a module belongs to (its subpackage or top-level module)."""
    if module.rpartition(".")[2] == "__main__":
        return "__main__"
    pieces = module.split(".")
    return pieces[1] if len(pieces) > 1 else "cosim"


def layer(module: str) -> int:
    for k, parts in enumerate(LAYERS):
        if part(module) in parts:
            return k
    raise LookupError(f"{module}: its part '{part(module)}' of the package is in no layer of LAYERS")


def back_arrows(root: Path) -> list[str]:
    """One line per import of a part of the same or a higher layer."""
    bad = []
    for importer, imported, where in imports(root):
        if part(importer) != part(imported) and layer(imported) >= layer(importer):
            bad.append(f"{where}: {importer} (layer {layer(importer)}, {part(importer)}) imports {imported} "
                       f"(layer {layer(imported)}, {part(imported)})")
    return bad


def circles(root: Path) -> list[set[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    graph: dict[str, set[str]] = {m: set() for m in modules(root)}
    for importer, imported, _ in imports(root):
        if importer != imported:
            graph[importer].add(imported)
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def circle_text(component: set[str], root: Path) -> str:
    ties = sorted({f"{where}: {a} -> {b}" for a, b, where in imports(root) if a in component and b in component and a != b})
    return f"circle of {', '.join(sorted(component))}:\n  " + "\n  ".join(ties)


MODULES = sorted(modules(ROOT))


@lru_cache(maxsize=1)
def _back_arrows_of_the_package() -> tuple[str, ...]:
    return tuple(back_arrows(ROOT))


@pytest.mark.parametrize("module", MODULES, ids=MODULES)
def test_module_imports_only_lower_layers(module):
    layer(module)  # every part of the package has its layer
    bad = [line for line in _back_arrows_of_the_package() if line.split(": ", 1)[1].startswith(f"{module} ")]
    assert not bad, "imports against the layering:\n" + "\n".join(bad)


def test_no_circles_but_the_block_registry():
    found = [c for c in circles(ROOT) if c not in ALLOWED_CIRCLES]
    assert not found, "\n".join(circle_text(c, ROOT) for c in found)


def test_generic_fmu_tools_know_no_bicycle():
    """fmu/ imports nothing above it (the state-space type of the base included), and analytic/
    only the base (errors, outputs)."""
    below = {"fmu": {"fmu", "compiler", "errors", "outputs", "processes", "folder_lock", "native", "statespace",
                     "progress"},
             "analytic": {"analytic", "errors", "outputs"}}
    bad = [f"{where}: {a} imports {b}" for a, b, where in imports(ROOT)
           if part(a) in below and part(b) not in below[part(a)]]
    assert not bad, "\n".join(bad)


def _tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in {"cosim/__init__.py": "", **files}.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


@pytest.mark.parametrize("files, expected", [
    pytest.param({"cosim/errors.py": "def f():\n    from cosim.cli import main\n", "cosim/cli.py": ""},
                 "cosim/errors.py:2: cosim.errors (layer 0, errors) imports cosim.cli (layer 9, cli)",
                 id="deferred-back-arrow"),
    pytest.param({"cosim/fmu/__init__.py": "", "cosim/fmu/linearize.py": "from ..bicycle import twins\n",
                  "cosim/bicycle/__init__.py": "", "cosim/bicycle/twins.py": ""},
                 "cosim/fmu/linearize.py:1: cosim.fmu.linearize (layer 4, fmu) imports cosim.bicycle.twins "
                 "(layer 6, bicycle)", id="relative-back-arrow"),
    pytest.param({"cosim/fmu/__init__.py": "", "cosim/fmu/access.py": "import cosim.diagram.svg\n",
                  "cosim/diagram/__init__.py": "", "cosim/diagram/svg.py": ""},
                 "cosim/fmu/access.py:1: cosim.fmu.access (layer 4, fmu) imports cosim.diagram.svg (layer 4, diagram)",
                 id="sideways-in-one-layer"),
])
def test_back_arrow_of_a_synthetic_tree_is_found(tmp_path, files, expected):
    assert back_arrows(_tree(tmp_path, files)) == [expected]


def test_circle_of_a_synthetic_tree_is_found(tmp_path):
    root = _tree(tmp_path, {"cosim/matrix/__init__.py": "", "cosim/matrix/a.py": "from cosim.matrix.b import x\n",
                            "cosim/matrix/b.py": "def x():\n    from . import a\n"})
    assert back_arrows(root) == []
    assert circles(root) == [{"cosim.matrix.a", "cosim.matrix.b"}]
    assert "cosim/matrix/b.py:2: cosim.matrix.b -> cosim.matrix.a" in circle_text(circles(root)[0], root)


def test_a_part_without_a_layer_is_refused(tmp_path):
    root = _tree(tmp_path, {"cosim/attic/__init__.py": ""})
    with pytest.raises(LookupError, match="'attic' of the package is in no layer"):
        layer("cosim.attic")
    assert "cosim.attic" in modules(root)
