"""Work-arounds for pymoca 0.12 flattening bugs, applied once before the first flattening.

Name capture in modifications: in ``frame(m = m)`` pymoca resolves the right-hand ``m`` in
the enclosing model correctly (to the flat name ``m``) but two later passes re-prefix every
reference with the component path when such a name exists there, so the binding becomes
``frame.m = frame.m``. References that the modification resolver already made flat are
marked here, and both re-prefixing passes leave marked references alone.

Functions: pymoca names the CasADi function of a Modelica function by its dotted class name
(``Bicycle.Functions.f``, ``Model.helper`` for a function declared inside a model), which CasADi
refuses as a function name. The generator is given a valid identifier instead.

``fixed``: pymoca gives every variable ``fixed = false`` whether it was written or not, so
``Real x(start = 1)`` (where a tool takes the start value as the initial value) cannot be told
from ``Real x(start = 1, fixed = false)`` (where the start value is only a guess for an initial
solve). Symbols whose ``fixed`` was given explicitly are marked ``_cosim_fixed_given``.
"""
from __future__ import annotations

import re

_applied = False


def _mark_flat(node):
    from pymoca import ast

    if isinstance(node, ast.ComponentRef):
        node._cosim_flat = True
    for operand in getattr(node, "operands", []) or []:
        _mark_flat(operand)
    for value in getattr(node, "values", []) or []:
        _mark_flat(value)
    return node


def _skip_marked(enter):
    def enter_component_ref(self, tree):
        if getattr(tree, "_cosim_flat", False):
            self.depth += 1
            self.cutoff_depth = min(self.cutoff_depth, self.depth)
            return
        return enter(self, tree)

    return enter_component_ref


def casadi_name(name: str) -> str:
    """A valid CasADi function name for a dotted Modelica class name (letters, digits and single
    underscores, starting with a letter)."""
    cleaned = re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")
    return cleaned if cleaned[:1].isalpha() else f"f_{cleaned}"


def _named_functions(get_function):
    def patched_get_function(self, function_name):
        tree = None if function_name in self.functions else self.root.classes.get(function_name)
        if tree is None:
            return get_function(self, function_name)
        original = tree.name
        tree.name = casadi_name(str(original))
        try:
            return get_function(self, function_name)
        finally:
            tree.name = original

    return patched_get_function


def _mark_fixed(resolve):
    def patched_resolve(symbol, arg, **kwargs):
        result = resolve(symbol, arg, **kwargs)
        if getattr(getattr(arg.value, "component", None), "name", None) == "fixed":
            symbol._cosim_fixed_given = True
        return result

    return patched_resolve


def _carry_fixed(to_ast_symbol):
    def patched_to_ast_symbol(isym):
        symbol = to_ast_symbol(isym)
        if getattr(isym, "_cosim_fixed_given", False):
            symbol._cosim_fixed_given = True
        return symbol

    return patched_to_ast_symbol


def apply() -> None:
    """Install the patches (idempotent)."""
    global _applied
    if _applied:
        return
    from pymoca.backends.casadi.generator import Generator
    from pymoca.tree import _flattening as flattening
    from pymoca.tree.instance import InstanceSymbol

    to_ast_value = flattening._to_ast_value

    def patched_to_ast_value(val):
        result = to_ast_value(val)
        return _mark_flat(result) if isinstance(val, InstanceSymbol) else result

    flatten_expression_crefs = flattening._flatten_expression_crefs

    def patched_flatten_expression_crefs(*args, **kwargs):
        return _mark_flat(flatten_expression_crefs(*args, **kwargs))

    flattening._to_ast_value = patched_to_ast_value
    flattening._flatten_expression_crefs = patched_flatten_expression_crefs
    for listener in (flattening.ComponentRefFlattener, flattening._EquationRefResolver):
        listener.enterComponentRef = _skip_marked(listener.enterComponentRef)
    flattening._resolve_modification_attribute = _mark_fixed(flattening._resolve_modification_attribute)
    flattening._instance_to_ast_symbol = _carry_fixed(flattening._instance_to_ast_symbol)
    Generator.get_function = _named_functions(Generator.get_function)
    _applied = True
