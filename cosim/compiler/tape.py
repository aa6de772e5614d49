"""A CasADi SX function as a tape: constant C tables that the runtime interprets (cosim_tape.c).

``eval_locals`` (every local algebraic variable of an assembly, computed only when an importer
reads one) is written as a tape instead of C code: 4000 connector variables of the nonlinear
bicycle with a rider took 0.6 s of gcc at -O0 as code, and take 0.02 s as a table. The
instructions are CasADi's own (``Function.instruction_*``), each interpreted as CasADi's generated C
computes it: a tape gives the same bits as the compiled function.
"""
from __future__ import annotations

import math

import casadi as ca

from cosim.errors import BuildError

# CasADi operation -> the operation of cosim_tape.h (its name without TAPE_)
_OPERATIONS = ("INPUT", "OUTPUT", "CONST", "ASSIGN", "ADD", "SUB", "MUL", "DIV", "NEG", "TWICE", "SQ", "INV",
               "EXP", "LOG", "POW", "CONSTPOW", "SQRT", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ATAN2",
               "SINH", "COSH", "TANH", "ASINH", "ACOSH", "ATANH", "LT", "LE", "EQ", "NE", "NOT", "AND", "OR",
               "IF_ELSE_ZERO", "FLOOR", "CEIL", "FMOD", "REMAINDER", "FABS", "SIGN", "COPYSIGN", "FMIN", "FMAX",
               "ERF", "LOG1P", "EXPM1", "HYPOT")
OPERATIONS = {getattr(ca, f"OP_{name}"): f"TAPE_{name}" for name in _OPERATIONS}
_NAMES = {code: name for name, code in vars(ca).items() if name.startswith("OP_") and isinstance(code, int)}


def _constant(value: float) -> str:
    """A double as C source that reads back as the same bits."""
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "-INFINITY"
    return repr(float(value))  # the shortest decimal that reads back as the same double


def tape_tables(f: ca.Function, name: str, model_name: str = "the model") -> str:
    """C definitions of the tape ``name`` (a ``static const cosim_tape``) of the SX function ``f``
    with one output; its inputs are ``arg[0..n_in-1]`` of :c:func:`cosim_tape_run`.

    Raises
    ------
    BuildError
        If ``f`` uses an operation no tape has (CasADi's ``erfinv``, calls of other functions),
        naming it.
    """
    if not f.is_a("SXFunction") or f.n_out() != 1:
        raise ValueError(f"a tape needs an SX function with one output, got {f.class_name()} {f.name()}")
    rows, constants = [], []
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        inputs, outputs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_INPUT:
            rows.append(f"{{TAPE_INPUT,{outputs[0]},{inputs[0]},{inputs[1]}}}")
        elif op == ca.OP_OUTPUT:
            rows.append(f"{{TAPE_OUTPUT,{inputs[0]},{outputs[0]},{outputs[1]}}}")
        elif op == ca.OP_CONST:
            rows.append(f"{{TAPE_CONST,{outputs[0]},{len(constants)},0}}")
            constants.append(_constant(f.instruction_constant(k)))
        elif op in OPERATIONS:
            a, b = (inputs + [0, 0])[:2]
            rows.append(f"{{{OPERATIONS[op]},{outputs[0]},{a},{b}}}")
        else:
            raise BuildError(f"{model_name}: its local variables use the operation "
                             f"{_NAMES.get(op, op)}, which `cosim build` cannot compute yet")
    lines = [f"static const cosim_tape_instruction {name}_code[{max(1, len(rows))}] = {{",
             *(",".join(rows[i:i + 8]) + "," for i in range(0, len(rows), 8)), "};",
             f"static const double {name}_constants[{max(1, len(constants))}] = {{{', '.join(constants) or '0'}}};",
             f"static const cosim_tape {name} = {{{len(rows)}, {name}_code, {name}_constants, {max(1, f.sz_w())}}};"]
    return "\n".join(lines) + "\n"
