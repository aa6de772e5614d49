"""Print sympy expressions as Modelica expressions."""
from __future__ import annotations

import sympy as sm
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.str import StrPrinter


CHAIN = 8  # longest flat sum printed


class ModelicaPrinter(StrPrinter):
    """Modelica syntax: ``^`` for powers (never chained, never with a negative exponent),
    ``sqrt``, real literals for rationals; unary minus only where Modelica allows it."""

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp == sm.S.Half:
            return f"sqrt({self._print(base)})"
        if exp.is_Number and exp < 0:
            positive = sm.Pow(base, -exp, evaluate=False) if exp != -1 else base
            return f"1/{self.parenthesize(positive, PRECEDENCE['Atom'], strict=True)}" \
                if not positive.is_Atom else f"1/{self._print(positive)}"
        b = self._print(base)
        if not (base.is_Symbol or (base.is_Integer and base >= 0) or base.is_Function):
            b = f"({b})"
        if exp.is_Rational and not exp.is_Integer:
            e = number(float(exp))
        else:
            e = self._print(exp)
        if not (exp.is_Number and exp >= 0):
            e = f"({e})"
        return f"{b}^{e}"

    def _print_Rational(self, expr):
        if expr.q == 1:
            return str(expr.p)
        return f"({expr.p}/{expr.q})"

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Integer(self, expr):
        return str(expr.p)

    def _print_Add(self, expr, order=None):
        # Long sums as a balanced tree of parenthesized partial sums: a flat chain of a hundred
        # terms is a parse tree a hundred levels deep, too deep for pymoca's recursive flattening.
        terms = list(expr.args)
        if len(terms) <= CHAIN:
            return super()._print_Add(expr, order)
        half = len(terms) // 2
        left = self._print_Add(sm.Add(*terms[:half], evaluate=False))
        right = self._print_Add(sm.Add(*terms[half:], evaluate=False))
        return f"({left}) + ({right})"

    def _print_Symbol(self, expr):
        return expr.name


_PRINTER = ModelicaPrinter({"order": "none"})


def modelica(expr) -> str:
    """The Modelica text of a sympy expression (no ``*-`` or ``^-``, which Modelica forbids)."""
    text = _PRINTER.doprint(sm.sympify(expr))
    for bad in ("*-", "/-", "^-", "+-", "--"):
        if bad in text.replace(" ", ""):
            raise ValueError(f"unprintable for Modelica ({bad!r}): {text}")
    return text


def number(value: float) -> str:
    """A real literal that round-trips exactly."""
    value = float(value)
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text
