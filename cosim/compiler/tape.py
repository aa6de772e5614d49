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

# The operations of cosim_tape.h (their names without TAPE_) with their number of operands.
_ARITY = {"ASSIGN": 1, "ADD": 2, "SUB": 2, "MUL": 2, "DIV": 2, "NEG": 1, "TWICE": 1, "SQ": 1, "INV": 1,
          "EXP": 1, "LOG": 1, "POW": 2, "CONSTPOW": 2, "SQRT": 1, "SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1,
          "ACOS": 1, "ATAN": 1, "ATAN2": 2, "SINH": 1, "COSH": 1, "TANH": 1, "ASINH": 1, "ACOSH": 1,
          "ATANH": 1, "LT": 2, "LE": 2, "EQ": 2, "NE": 2, "NOT": 1, "AND": 2, "OR": 2, "IF_ELSE_ZERO": 2,
          "FLOOR": 1, "CEIL": 1, "FMOD": 2, "REMAINDER": 2, "FABS": 1, "SIGN": 1, "COPYSIGN": 2, "FMIN": 2,
          "FMAX": 2, "ERF": 1, "LOG1P": 1, "EXPM1": 1, "HYPOT": 2}
#: CasADi operation -> (the operation of cosim_tape.h, its number of operands); INPUT, OUTPUT and
#: CONST, which read no work entries, are written apart.
OPERATIONS = {getattr(ca, f"OP_{name}"): (f"TAPE_{name}", arity) for name, arity in _ARITY.items()}
_NAMES = {code: name for name, code in vars(ca).items() if name.startswith("OP_") and isinstance(code, int)}
# A constant the tables cannot hold as a decimal number (old MSVC has no constant NAN or INFINITY
# for a static initializer): an instruction CONST with this b, its value made by the interpreter.
_SPECIAL = {"inf": 1, "-inf": 2, "nan": 3}


def _constant(value: float) -> tuple[str, int]:
    """A double as (C source that reads back as the same bits, 0), or ("0", the code of
    :data:`_SPECIAL`) for an infinity or NaN."""
    if math.isnan(value):
        return "0", _SPECIAL["nan"]
    if math.isinf(value):
        return "0", _SPECIAL["inf" if value > 0 else "-inf"]
    return repr(float(value)), 0  # the shortest decimal that reads back as the same double


def tape_tables(f: ca.Function, name: str, model_name: str = "the model") -> str:
    """C definitions of the tape ``name`` (a ``static const cosim_tape``) of the SX function ``f``
    with one output; its inputs are ``arg[0..n_in-1]`` of :c:func:`cosim_tape_run`.

    Raises
    ------
    BuildError
        If ``f`` uses an operation no tape has (CasADi's ``erfinv``, calls of other functions),
        naming it.
    """
    if not f.is_a("SXFunction") or f.n_out() != 1 or not f.sparsity_out(0).is_dense():
        raise ValueError(f"a tape needs an SX function with one dense output, got {f.class_name()} {f.name()}")
    rows, constants = [], []
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        inputs, outputs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_INPUT:
            rows.append(f"{{TAPE_INPUT,{outputs[0]},{inputs[0]},{inputs[1]}}}")
        elif op == ca.OP_OUTPUT:
            rows.append(f"{{TAPE_OUTPUT,{inputs[0]},{outputs[0]},{outputs[1]}}}")
        elif op == ca.OP_CONST:
            text, special = _constant(f.instruction_constant(k))
            rows.append(f"{{TAPE_CONST,{outputs[0]},{len(constants)},{special}}}")
            constants.append(text)
        elif op in OPERATIONS and len(inputs) == OPERATIONS[op][1] and len(outputs) == 1:
            operation, arity = OPERATIONS[op]
            rows.append(f"{{{operation},{outputs[0]},{inputs[0]},{inputs[1] if arity == 2 else 0}}}")
        else:
            raise BuildError(f"{model_name}: its local variables use the operation "
                             f"{_NAMES.get(op, op)}, which `cosim build` cannot compute yet")
    rows = rows or ["{TAPE_ASSIGN,0,0,0}"]  # (an empty initializer is not C99; never run: n = 0)
    lines = [f"static const cosim_tape_instruction {name}_code[{len(rows)}] = {{",
             *(",".join(rows[i:i + 8]) + "," for i in range(0, len(rows), 8)), "};",
             f"static const double {name}_constants[{max(1, len(constants))}] = {{{', '.join(constants) or '0'}}};",
             f"static const cosim_tape {name} = {{{f.n_instructions()}, {name}_code, {name}_constants, "
             f"{max(1, f.sz_w())}}};"]
    return "\n".join(lines) + "\n"
