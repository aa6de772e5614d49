"""Every connector of the Bicycle library is balanced (MLS 9.3.1), counted from the parsed source.

The specification requires, for each non-partial non-expandable connector class, as many flow
scalars as scalars that are neither ``parameter``, ``constant``, ``input``, ``output``, ``stream``
nor ``flow``. This test counts both from pymoca's parse tree of each file, independently of any
compiler's connector check (rumoca 0.10.2 skips components of derived types such as
``Bicycle.Units.Angle`` and counts a built-in ``input Real`` as a potential). Array sizes that
depend on a constant of the connector (``n``) are counted for its default value and the two next
ones, so that a count that is equal only for one ``n`` fails too.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from pymoca import ast, parser

from cosim.compiler.library import DEFAULT_LIBRARY

BUILTIN = {"Real", "Integer", "Boolean", "String"}
CAUSAL = {"input", "output", "stream"}


def _classes(tree, prefix=""):
    """(dotted name, class) of every class in a parse tree, nested ones included."""
    for name, cls in tree.classes.items():
        if name in BUILTIN or name in ("StateSelect", "Clock"):
            continue
        dotted = f"{prefix}{name}"
        yield dotted, cls
        yield from _classes(cls, dotted + ".")


#: Comments and strings, blanked before looking for the keyword below.
_NOT_CODE = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/', re.DOTALL)


def _connectors():
    found = []
    for path in sorted(DEFAULT_LIBRARY.rglob("*.mo")):
        text = path.read_text(encoding="utf-8")
        if not re.search(r"\bconnector\b", _NOT_CODE.sub(" ", text)):
            continue  # no connector class is defined without the keyword: the parse is skipped
        for name, cls in _classes(parser.parse(text)):
            if cls.type == "connector" and cls.symbols and not getattr(cls, "partial", False):
                found.append(pytest.param(path, name, cls, id=name))
    return found


CONNECTORS = _connectors()


def _integer(expression, constants: dict[str, int]) -> int:
    """The value of an array dimension: a literal, a constant of the connector, or a sum,
    difference or product of those."""
    if isinstance(expression, ast.Primary):
        return int(expression.value)
    if isinstance(expression, ast.ComponentRef):
        return constants[expression.name]
    if isinstance(expression, ast.Expression) and len(expression.operands) == 2:
        a, b = (_integer(op, constants) for op in expression.operands)
        return {"+": a + b, "-": a - b, "*": a * b}[expression.operator]
    raise AssertionError(f"array dimension {expression!r} is not an integer expression of the connector's constants")


def _binding(symbol) -> int:
    """The literal value of an Integer constant (pymoca's parser keeps ``= 6`` as a ``value``
    modification)."""
    for argument in symbol.class_modification.arguments:
        element = argument.value
        if getattr(element, "component", None) is not None and element.component.name == "value":
            return int(element.modifications[0].value)
    raise AssertionError(f"constant {symbol.name} has no literal value")


def _size(symbol, constants: dict[str, int]) -> int:
    size = 1
    for dims in symbol.dimensions or []:
        for d in dims:
            if d is not None and not (isinstance(d, ast.Primary) and d.value is None):
                size *= _integer(d, constants)
    return size


def _counts(cls, constants: dict[str, int]) -> tuple[int, int]:
    flows = potentials = 0
    for symbol in cls.symbols.values():
        prefixes = set(symbol.prefixes)
        if prefixes & {"parameter", "constant"}:
            continue
        size = _size(symbol, constants)
        if "flow" in prefixes:
            flows += size
        elif not prefixes & CAUSAL:
            potentials += size
    return flows, potentials


def test_the_library_has_connectors_with_flows():
    """The test below sees the physical connectors (it would pass vacuously on none)."""
    names = {p.values[1] for p in CONNECTORS}
    assert {"Bicycle.Mechanics.Interfaces.Frame_a", "Bicycle.Mechanics.Interfaces.Frame_b",
            "Bicycle.Linear.RollSteer_a", "Bicycle.Linear.RollSteer_b"} <= names


@pytest.mark.parametrize("path, name, cls", CONNECTORS)
def test_connector_is_balanced(path: Path, name: str, cls):
    defaults = {}
    for symbol_name, symbol in cls.symbols.items():
        if "constant" in symbol.prefixes or "parameter" in symbol.prefixes:
            if symbol.type.name == "Integer":
                defaults[symbol_name] = _binding(symbol)
    for shift in (0, 1, 2):
        constants = {k: v + shift for k, v in defaults.items()}
        flows, potentials = _counts(cls, constants)
        assert flows == potentials, (
            f"{path}: connector {name} is unbalanced for {constants or 'its sizes'}: {flows} flow scalars, "
            f"{potentials} scalars that are neither parameter, constant, input, output, stream nor flow")
