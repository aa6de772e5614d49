"""Imports of the package stand at the top of its modules.

A ``cosim`` import inside a function is allowed only in :mod:`cosim.cli` (each verb loads its
implementation when it runs, so that ``cosim --help`` stays fast) or where a ``# deferred: <why>``
comment stands on its line or on the line above; the imports right below such a line, one after
another, share its comment. The reasons are heavy third-party packages (CasADi, pymoca, fmpy,
scipy, python-control, matplotlib) that importing the module does not load otherwise, and the
block registry, which the blocks import to register with it.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DEFERRED = "# deferred:"


def _internal(node: ast.Import | ast.ImportFrom) -> bool:
    """Whether ``node`` imports from the ``cosim`` package (absolute or relative)."""
    if isinstance(node, ast.ImportFrom):
        return bool(node.level) or (node.module or "").split(".")[0] == "cosim"
    return any(alias.name.split(".")[0] == "cosim" for alias in node.names)


def undeferred_imports(path: Path) -> list[str]:
    """``file:line: text`` of every ``cosim`` import inside a function of ``path`` without a
    ``# deferred:`` reason on its line, on the line above, or above the imports right before it."""
    text = path.read_text()
    lines = text.splitlines()
    found: list[ast.Import | ast.ImportFrom] = []

    def walk(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if in_function and isinstance(child, (ast.Import, ast.ImportFrom)) and _internal(child):
                found.append(child)
            walk(child, in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)))

    walk(ast.parse(text, str(path)), False)
    covered: set[int] = set()  # last lines of imports with a reason
    bad = []
    for node in sorted(found, key=lambda n: n.lineno):
        own = "\n".join(lines[node.lineno - 1:node.end_lineno])
        above = lines[node.lineno - 2] if node.lineno > 1 else ""
        if DEFERRED in own or above.strip().startswith(DEFERRED) or node.lineno - 1 in covered:
            covered.add(node.end_lineno)
        else:
            bad.append(f"{path.name}:{node.lineno}: {lines[node.lineno - 1].strip()}")
    return bad


#: Every module of the package but the command line, whose verbs load their implementations late.
MODULES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "cosim").rglob("*.py") if p != ROOT / "cosim" / "cli.py")


@pytest.mark.parametrize("module", MODULES, ids=MODULES)
def test_package_imports_stand_at_the_top(module):
    """Imports of cosim inside functions are each given a ``# deferred:`` reason."""
    bad = undeferred_imports(ROOT / module)
    assert not bad, ("imports of cosim inside functions without a '# deferred: <why>' comment "
                     "(move them to the top of the module):\n  " + "\n  ".join(bad))


SYNTHETIC = '''\
import json


def plain():
    from cosim.outputs import write_text
    return write_text


def relative():
    from .outputs import write_text
    return write_text


def with_reason_above():
    # deferred: loads CasADi
    from cosim.compiler.build import build
    from cosim.compiler.ode import make_explicit
    return build, make_explicit


def with_reason_on_the_line():
    from cosim.compiler import pymoca_flattening  # deferred: imports pymoca
    return pymoca_flattening


def after_a_gap():
    # deferred: loads CasADi
    from cosim.compiler.build import build

    from cosim.errors import CosimError
    return build, CosimError


def third_party():
    import scipy.linalg
    return scipy.linalg
'''


@pytest.mark.parametrize("code, expected", [
    (SYNTHETIC, ["synthetic.py:5: from cosim.outputs import write_text",
                 "synthetic.py:10: from .outputs import write_text",
                 "synthetic.py:30: from cosim.errors import CosimError"]),
    ("from cosim.outputs import write_text\n\n\ndef f():\n    return write_text\n", []),
    ("def f():\n    import cosim.fmu.access\n    return cosim\n", ["synthetic.py:2: import cosim.fmu.access"]),
], ids=["function-imports", "top-of-module", "plain-import"])
def test_undeferred_imports_are_found(tmp_path, code, expected):
    """The check names each import inside a function without a reason, and only those."""
    path = tmp_path / "synthetic.py"
    path.write_text(code)
    assert undeferred_imports(path) == expected
