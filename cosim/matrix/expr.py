"""Small, safe arithmetic expressions for matrix specs (``"=p * tau"``, ``"sqrt(m*g*(h - R)/J)"``).

Only numbers, strings, names, ``+ - * / // % **``, comparisons, ``and or not``, ``x if c else y``
and calls of the functions in :data:`FUNCTIONS` are allowed; anything else is refused with a
message naming the expression.
"""
from __future__ import annotations

import ast
import math
import operator
from functools import lru_cache

from ..errors import ParameterError


class ExpressionError(ParameterError):
    """An expression that cannot be parsed or evaluated; the message quotes it."""


def _weave_speed(parameter_set: str) -> float:
    from ..analytic.parameters import load_parameters
    from ..analytic.whipple import weave_speed

    return float(weave_speed(load_parameters(parameter_set)))


def _capsize_speed(parameter_set: str) -> float:
    from ..analytic.parameters import load_parameters
    from ..analytic.whipple import capsize_speed

    return float(capsize_speed(load_parameters(parameter_set)))


FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "atan": math.atan, "atan2": math.atan2,
    "radians": math.radians, "degrees": math.degrees, "abs": abs, "min": min, "max": max,
    "round": round, "float": float, "int": int,
    # speeds [m/s] of the linear Whipple model for a Meijaard parameter set (bundled name or file)
    "weave_speed": _weave_speed, "capsize_speed": _capsize_speed,
}
CONSTANTS = {"pi": math.pi, "e": math.e, "inf": math.inf, "true": True, "false": False}

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg, ast.Not: operator.not_}
_COMPARE = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge,
            ast.Eq: operator.eq, ast.NotEq: operator.ne}


@lru_cache(maxsize=4096)
def _parse(text: str) -> ast.Expression:
    try:
        return ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"expression '{text}': {exc.msg}") from None


def names(text: str) -> set[str]:
    """Variable names an expression uses (functions and constants excluded)."""
    tree = _parse(text)
    found = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    return found - set(FUNCTIONS) - set(CONSTANTS)


def evaluate(text: str, variables: dict):
    """Value of ``text`` with ``variables`` in scope."""
    tree = _parse(text)

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str, bool)):
            return node.value
        if isinstance(node, ast.Name):
            if node.id in variables:
                return variables[node.id]
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            known = ", ".join(sorted(variables)) or "none"
            raise ExpressionError(f"expression '{text}': unknown name '{node.id}' (variables: {known})")
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _UNARY[type(node.op)](ev(node.operand))
        if isinstance(node, ast.BoolOp):
            values = [ev(v) for v in node.values]
            return all(values) if isinstance(node.op, ast.And) else any(values)
        if isinstance(node, ast.Compare):
            left = ev(node.left)
            for op, right_node in zip(node.ops, node.comparators):
                if type(op) not in _COMPARE:
                    break
                right = ev(right_node)
                if not _COMPARE[type(op)](left, right):
                    return False
                left = right
            else:
                return True
        if isinstance(node, ast.IfExp):
            return ev(node.body) if ev(node.test) else ev(node.orelse)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS \
                and not node.keywords:
            return FUNCTIONS[node.func.id](*[ev(a) for a in node.args])
        raise ExpressionError(f"expression '{text}': '{ast.unparse(node)}' is not allowed "
                              f"(numbers, names, arithmetic, comparisons and {', '.join(sorted(FUNCTIONS))})")

    try:
        return ev(tree)
    except ExpressionError:
        raise
    except (ArithmeticError, ValueError, TypeError) as exc:
        raise ExpressionError(f"expression '{text}': {exc}") from None


def resolve(value, variables: dict):
    """A spec value: strings starting with ``=`` are expressions, lists/dicts are resolved inside."""
    if isinstance(value, str) and value.startswith("="):
        return evaluate(value[1:], variables)
    if isinstance(value, list):
        return [resolve(v, variables) for v in value]
    if isinstance(value, dict):
        return {k: resolve(v, variables) for k, v in value.items()}
    return value
