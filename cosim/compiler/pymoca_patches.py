"""Work-arounds for pymoca 0.12 flattening bugs, applied once before the first flattening.

Name capture in modifications: in ``frame(m = m)`` pymoca resolves the right-hand ``m`` in
the enclosing model correctly (to the flat name ``m``) but two later passes re-prefix every
reference with the component path when such a name exists there, so the binding becomes
``frame.m = frame.m``. References that the modification resolver already made flat are
marked here, and both re-prefixing passes leave marked references alone.
"""
from __future__ import annotations

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


def apply() -> None:
    """Install the patches (idempotent)."""
    global _applied
    if _applied:
        return
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
    _applied = True
