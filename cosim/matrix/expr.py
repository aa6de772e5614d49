"""Small, safe arithmetic expressions for matrix specs (``"=p * tau"``, ``"sqrt(m*g*(h - R)/J)"``).

Only numbers, strings, names, ``+ - * / // % **``, comparisons, ``and or not``, ``x if c else y``
and calls of the functions in :data:`FUNCTIONS` are allowed; anything else is refused with a
message naming the expression.

The cost of an expression is bounded, so a spec cannot hang or exhaust the machine (``9**9**9``
would compute an integer of 10^8 digits): at most :data:`MAX_LENGTH` characters and
:data:`MAX_DEPTH` levels of nesting, no integer beyond :data:`MAX_INT_BITS` bits (a power is
refused *before* it is computed when its result would be larger), no string beyond
:data:`MAX_STRING` characters, and no complex result (``(-8)**0.5``).
"""
from __future__ import annotations

import ast
import math
import operator
from functools import lru_cache

from cosim.errors import ParameterError


class ExpressionError(ParameterError):
    """An expression that cannot be parsed or evaluated; the message quotes it."""


def _weave_speed(parameter_set: str) -> float:
    # deferred: `cosim --help` loads this module (the matrix parser); these load numpy
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import weave_speed

    return float(weave_speed(load_parameters(parameter_set)))


def _second_order(key: str, parameter_set: str = "astrom2005") -> float:
    """A parameter of the paper's second-order models (cosim/params/second-order/SET.toml): the
    studies read m, g, h, J from the data set instead of repeating its numbers."""
    from cosim.analytic.parameters import load_second_order  # deferred: `cosim --help` loads this module

    values = load_second_order(parameter_set)
    if key not in values:
        raise ValueError(f"second_order: no parameter {key!r} in the set {parameter_set!r} "
                         f"(it has {', '.join(sorted(values))})")
    return float(values[key])


def _capsize_speed(parameter_set: str) -> float:
    # deferred: `cosim --help` loads this module (the matrix parser); these load numpy
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import capsize_speed

    return float(capsize_speed(load_parameters(parameter_set)))


def _round(value, ndigits=None):
    """round() without the cost of 10**ndigits for an integer with a huge ndigits."""
    if ndigits is not None and isinstance(ndigits, int) and abs(ndigits) > 400:
        raise ValueError(f"round: ndigits = {ndigits} is beyond +-400")
    return round(value) if ndigits is None else round(value, ndigits)


FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "atan": math.atan, "atan2": math.atan2,
    "radians": math.radians, "degrees": math.degrees, "abs": abs, "min": min, "max": max,
    "round": _round, "float": float, "int": int,
    # speeds [m/s] of the linear Whipple model for a Meijaard parameter set (bundled name or file)
    "weave_speed": _weave_speed, "capsize_speed": _capsize_speed,
    # a parameter [SI] of the paper's second-order models: second_order("J") (set astrom2005)
    "second_order": _second_order,
}
CONSTANTS = {"pi": math.pi, "e": math.e, "inf": math.inf, "true": True, "false": False}

MAX_LENGTH = 1000       # characters of an expression
MAX_DEPTH = 100         # nesting levels of its syntax tree (the evaluator recurses once per level)
MAX_INT_BITS = 4096     # bits of an integer value (about 1233 decimal digits)
MAX_STRING = 10_000     # characters of a string value

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg, ast.Not: operator.not_}
_COMPARE = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge,
            ast.Eq: operator.eq, ast.NotEq: operator.ne}


def _quote(text: str) -> str:
    return text if len(text) <= 80 else text[:77] + "..."


def _depth(node: ast.AST) -> int:
    """Nesting depth of a syntax tree (iterative: a deep tree must not overflow the stack here)."""
    deepest, todo = 0, [(node, 1)]
    while todo:
        node, level = todo.pop()
        deepest = max(deepest, level)
        if deepest > MAX_DEPTH:
            return deepest
        todo.extend((child, level + 1) for child in ast.iter_child_nodes(node))
    return deepest


@lru_cache(maxsize=4096)
def _parse(text: str) -> ast.Expression:
    if not isinstance(text, str):
        raise ExpressionError(f"expression {text!r}: must be a string")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"expression '{_quote(text)}': longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"expression '{text}': {exc.msg}") from None
    except (MemoryError, RecursionError, ValueError):  # parser stack exhausted, NUL bytes
        raise ExpressionError(f"expression '{_quote(text)}': cannot be parsed (too deeply nested?)") from None
    if _depth(tree) > MAX_DEPTH:
        raise ExpressionError(f"expression '{_quote(text)}': nested more than {MAX_DEPTH} levels deep")
    return tree


def _int_bits(value) -> int:
    return abs(value).bit_length() if isinstance(value, int) and not isinstance(value, bool) else 0


def _power(text: str, base, exponent):
    """``base ** exponent``, refused before it is computed if the integer result would be huge."""
    if isinstance(base, int) and isinstance(exponent, int) and not isinstance(exponent, bool) and exponent > 0:
        bits = _int_bits(base)
        if bits > 1 and (bits - 1) * exponent > MAX_INT_BITS:
            raise ExpressionError(f"expression '{_quote(text)}': the power {_short(base)}**{_short(exponent)} "
                                  f"exceeds {MAX_INT_BITS} bits (use floats, e.g. {_short(base)}.0**...)")
    return operator.pow(base, exponent)


def _short(value) -> str:
    text = str(value) if _int_bits(value) <= 64 else f"<{_int_bits(value)}-bit integer>"
    return text if len(text) <= 24 else text[:21] + "..."


def _checked(text: str, value):
    """Refuse values whose size could make later operations costly, and complex numbers."""
    if _int_bits(value) > MAX_INT_BITS:
        raise ExpressionError(f"expression '{_quote(text)}': an integer beyond {MAX_INT_BITS} bits")
    if isinstance(value, str) and len(value) > MAX_STRING:
        raise ExpressionError(f"expression '{_quote(text)}': a string longer than {MAX_STRING} characters")
    if isinstance(value, complex):
        raise ExpressionError(f"expression '{_quote(text)}': the result {value} is complex")
    return value


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
            left, right = ev(node.left), ev(node.right)
            if isinstance(node.op, ast.Pow):
                return _checked(text, _power(text, left, right))
            if isinstance(node.op, ast.Mult) and (isinstance(left, str) or isinstance(right, str)):
                count = right if isinstance(left, str) else left
                other = left if isinstance(left, str) else right
                if isinstance(count, int) and count * len(other) > MAX_STRING:
                    raise ExpressionError(f"expression '{_quote(text)}': a string longer than {MAX_STRING} "
                                          "characters")
            if isinstance(node.op, ast.Mod) and isinstance(left, str):
                raise ExpressionError(f"expression '{_quote(text)}': string formatting with % is not allowed")
            return _checked(text, _BINARY[type(node.op)](left, right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _checked(text, _UNARY[type(node.op)](ev(node.operand)))
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
            return _checked(text, FUNCTIONS[node.func.id](*[ev(a) for a in node.args]))
        raise ExpressionError(f"expression '{text}': '{ast.unparse(node)}' is not allowed "
                              f"(numbers, names, arithmetic, comparisons and {', '.join(sorted(FUNCTIONS))})")

    try:
        return ev(tree)
    except ExpressionError:
        raise
    except OverflowError:
        raise ExpressionError(f"expression '{_quote(text)}': the result overflows a float") from None
    except (ArithmeticError, ValueError, TypeError, LookupError, OSError) as exc:
        raise ExpressionError(f"expression '{_quote(text)}': {exc}") from None
    except (RecursionError, MemoryError):
        raise ExpressionError(f"expression '{_quote(text)}': too costly to evaluate") from None


def resolve(value, variables: dict, key: str = ""):
    """A spec value: strings starting with ``=`` are expressions, lists/dicts are resolved inside.

    ``key`` names the value in error messages (``parameters 'v'``); nested keys are appended."""
    if isinstance(value, str) and value.startswith("="):
        try:
            return evaluate(value[1:], variables)
        except ExpressionError as exc:
            raise ExpressionError(f"{key}: {exc}" if key else str(exc)) from None
    if isinstance(value, list):
        return [resolve(v, variables, f"{key}[{k}]" if key else f"[{k}]") for k, v in enumerate(value)]
    if isinstance(value, dict):
        return {k: resolve(v, variables, f"{key} '{k}'" if key else f"'{k}'") for k, v in value.items()}
    return value
