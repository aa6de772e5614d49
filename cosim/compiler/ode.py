"""Residual DAE -> explicit ODE.

pymoca gives residual equations ``0 = r(der(x), x, z, u, p, t)``. The unknowns
``w = [der(x); z]`` are matched to the equations (structural analysis), ordered into blocks
(block-triangular form) and solved block by block: a block linear in its unknowns is solved
symbolically. pymoca does no index reduction, so an equation that determines no unknown (a
constraint on states: index > 1) is reported with the variables involved.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import casadi as ca
import numpy as np

from cosim.errors import ModelStructureError, ParameterError
from cosim.compiler.flatten import FlatModel


@dataclass
class Symbolic:
    """One symbol of the explicit model with what the FMU needs to know about it."""

    name: str
    start: object = None  # float, SX expression of p, or None
    python_type: type = float


@dataclass
class ExplicitModel:
    """``der(x) = f(t, x, u, p)``, ``z = g(t, x, u, p)``, ``c = h(p)``, ``x0 = s(p)`` in CasADi SX."""

    name: str
    t: ca.SX
    x: ca.SX
    u: ca.SX
    p: ca.SX
    xdot: ca.SX
    z: ca.SX
    c: ca.SX
    x0: ca.SX
    states: list[Symbolic]
    inputs: list[Symbolic]
    parameters: list[Symbolic]
    calculated: list[Symbolic]
    algebraics: list[Symbolic]


def _column(symbols):
    return ca.vertcat(*symbols) if symbols else ca.SX(0, 1)


def _maximum_matching(rows: list[list[int]], ncols: int) -> tuple[list[int], list[int]]:
    """Maximum bipartite matching (augmenting paths). Returns row->col and col->row (-1 = none)."""
    row_match = [-1] * len(rows)
    col_match = [-1] * ncols

    def augment(r, seen):
        for col in rows[r]:
            if col in seen:
                continue
            seen.add(col)
            if col_match[col] < 0 or augment(col_match[col], seen):
                row_match[r], col_match[col] = col, r
                return True
        return False

    for r in range(len(rows)):
        augment(r, set())
    return row_match, col_match


def _element_names(name: str, shape: tuple[int, int]) -> list[str]:
    """Scalar names of an array variable in column-major order (the order of ``vec``)."""
    rows, cols = shape
    if (rows, cols) == (1, 1):
        return [name]
    if cols == 1:
        return [f"{name}[{i + 1}]" for i in range(rows)]
    return [f"{name}[{i + 1},{j + 1}]" for j in range(cols) for i in range(rows)]


class _Translator:
    """Maps pymoca's MX symbols to scalar SX symbols (arrays are split into their elements)
    and MX expressions to SX expressions."""

    def __init__(self, mx_symbols, model_name: str = "the model"):
        self.model_name = model_name
        self.mx = list(mx_symbols)
        self.elements: dict[str, list] = {}
        self.sx = []
        for s in self.mx:
            scalars = [ca.SX.sym(n) for n in _element_names(s.name(), s.shape)]
            self.elements[s.name()] = scalars
            self.sx.append(ca.reshape(ca.vertcat(*scalars), *s.shape))

    def __call__(self, expressions):
        if not expressions:
            return ca.SX(0, 1)
        mx = ca.vertcat(*[ca.vec(ca.MX(e)) for e in expressions])
        try:
            f = ca.Function("translate", self.mx, [mx], {"allow_free": False})
        except RuntimeError as exc:
            free = re.search(r"variables \[(.*?)\] are free", str(exc))
            names = free.group(1) if free else "unknown symbols"
            raise ModelStructureError(f"{self.model_name}: the equations use {names}, which are not "
                                      "variables, parameters or constants of the model") from None
        return f(*self.sx)

    def scalars(self, variables) -> list:
        return [e for v in variables for e in self.elements[v.symbol.name()]]


def _numbers(value, size: int) -> list[float] | None:
    """The element values of a literal (scalar or array) value; None for an expression."""
    if isinstance(value, (ca.MX, ca.SX)):
        return None
    try:
        array = np.asarray(value, dtype=float).ravel(order="F")
    except (TypeError, ValueError):
        return None
    if array.size == 1 and size > 1:
        array = np.repeat(array, size)
    return [float(a) for a in array] if array.size == size else None


def make_explicit(flat: FlatModel) -> ExplicitModel:
    """Turn the flattened model into explicit ODE form.

    Raises
    ------
    ModelStructureError
        Unbalanced model, structurally singular (index > 1) system, algebraic loop that is
        not linear, unsupported constructs (delay, initial equations).
    ParameterError
        A parameter without value.
    """
    m = flat.casadi
    name = flat.name
    if getattr(m, "delay_states", None):
        raise ModelStructureError(f"{name}: delay() is not supported; use a Pade approximation (Bicycle.Rider)")
    if m.initial_equations:
        raise ModelStructureError(
            f"{name}: initial equations are not supported; give the states start values with fixed = true")

    _refuse_initialization_attributes(flat)

    for v in m.parameters:
        if isinstance(v.value, float) and math.isnan(v.value):
            raise ParameterError(f"{name}: parameter '{v.symbol.name()}' has no value")
    constants = [v for v in m.constants]

    alg = [v for v in m.alg_states]
    mx_symbols = ([m.time] + [v.symbol for v in m.states] + [v.symbol for v in m.der_states]
                  + [v.symbol for v in alg] + [v.symbol for v in m.inputs]
                  + [v.symbol for v in m.parameters] + [v.symbol for v in constants])
    tr = _Translator(mx_symbols, name)
    pick = tr.scalars
    t = tr.sx[0]
    x, xd, z, u = pick(m.states), pick(m.der_states), pick(alg), pick(m.inputs)
    consts = pick(constants)
    const_values = []
    for v in constants:
        numbers = _numbers(v.value, v.symbol.numel())
        const_values += [ca.SX(n) for n in numbers] if numbers is not None else ca.vertsplit(tr([v.value]))

    tunable = [v for v in m.parameters if _numbers(v.value, v.symbol.numel()) is not None]
    calculated = [v for v in m.parameters if _numbers(v.value, v.symbol.numel()) is None]
    p, csym = pick(tunable), pick(calculated)

    # Calculated parameters as expressions of the tunable ones (bindings may chain).
    cexpr = tr([v.value for v in calculated]) if calculated else ca.SX(0, 1)
    cexpr = ca.substitute(cexpr, _column(consts), ca.vertcat(*const_values)) if consts else cexpr
    for _ in range(len(csym) + 1):
        if not calculated or not ca.depends_on(cexpr, ca.vertcat(*csym)):
            break
        cexpr = ca.substitute(cexpr, ca.vertcat(*csym), cexpr)
    else:
        names = ", ".join(v.symbol.name() for v in calculated)
        raise ModelStructureError(f"{name}: parameter bindings are cyclic among: {names}")

    def known(expr):
        """Replace constants and calculated parameters by their values/expressions of p."""
        if consts:
            expr = ca.substitute(expr, ca.vertcat(*consts), ca.vertcat(*const_values))
        if calculated:
            expr = ca.substitute(expr, ca.vertcat(*csym), cexpr)
        return expr

    residual = known(tr(m.equations))
    w = xd + z
    neq, nw = residual.numel(), len(w)
    if neq != nw:
        raise ModelStructureError(
            f"{name}: the model is unbalanced: {neq} equations for {nw} unknowns "
            f"({len(xd)} state derivatives, {len(z)} algebraic variables)")

    W = _column(w)
    jac = ca.jacobian(residual, W)
    sp = jac.sparsity()
    rows = [[] for _ in range(neq)]
    for r, c in zip(*sp.get_triplet()):
        rows[r].append(c)
    row_match, col_match = _maximum_matching(rows, nw)
    if -1 in row_match:
        _structural_error(name, residual, rows, row_match, col_match, w, x, m)

    solution = _solve_blocks(name, residual, W, w, sp)
    xdot = solution[: len(xd)]
    zsol = solution[len(xd):]

    x0, state_starts = [], []
    for v in m.states:
        numbers = _numbers(v.start, v.symbol.numel())
        if numbers is not None:
            x0 += [ca.SX(n) for n in numbers]
            state_starts += numbers
        else:
            x0 += ca.vertsplit(known(tr([v.start])))
            state_starts += [None] * v.symbol.numel()
    P = _column(p)
    x0 = ca.vertcat(*x0) if x0 else ca.SX(0, 1)
    for label, expr in (("start values of states", x0), ("calculated parameters", cexpr)):
        free = ca.symvar(expr)
        bad = [s.name() for s in free if not any(ca.is_equal(s, q) for q in p)]
        if bad:
            raise ModelStructureError(f"{name}: {label} depend on non-parameters: {', '.join(bad)}")

    def symbols(variables, starts=None):
        found = []
        for v in variables:
            python_type = getattr(v, "python_type", float)
            for k, element in enumerate(tr.elements[v.symbol.name()]):
                start = starts(v, k) if starts else None
                found.append(Symbolic(element.name(), start, python_type))
        return found

    def literal(attr, default=None):
        def element(v, k):
            numbers = _numbers(getattr(v, attr), v.symbol.numel())
            return numbers[k] if numbers is not None else default
        return element

    return ExplicitModel(
        name=name, t=t, x=_column(x), u=_column(u), p=P,
        xdot=ca.vertcat(*xdot) if xdot else ca.SX(0, 1),
        z=ca.vertcat(*zsol) if zsol else ca.SX(0, 1),
        c=cexpr, x0=x0,
        states=symbols(m.states, lambda v, k, it=iter(state_starts): next(it)),
        inputs=symbols(m.inputs, literal("start", 0.0)),
        parameters=symbols(tunable, literal("value")),
        calculated=symbols(calculated),
        algebraics=symbols(alg),
    )


def _refuse_initialization_attributes(flat: FlatModel) -> None:
    """Refuse ``fixed`` attributes that would need an initialization problem to be solved.

    The FMU starts every state exactly at its start value (``initial = "exact"``), computed
    from the parameters; it solves no initialization problem. That is what ``fixed = true``
    means, and what Modelica tools do for a state without a ``fixed`` attribute when no
    initial equation determines it (they fix its start value). The compiler refuses (rather than
    honours with an initial solve) the attributes that ask for more, because without initial
    equations there is nothing to solve: an explicit ``fixed = false`` on a state (its start
    value is only a guess; some initial equation must determine it), ``fixed = false`` on a
    parameter (a parameter computed during initialization) and ``fixed = true`` on a variable
    that is not a state (an initial equation ``v = start``). Initial equations themselves are
    refused before this check. Taking the start value as exact instead would silently start
    the model from a state its author said was not the initial one.

    Raises
    ------
    ModelStructureError
        Naming the variable and the file (and line) where its ``fixed`` is given.
    """
    m = flat.casadi
    states = {v.symbol.name(): v for v in m.states}
    parameters = {v.symbol.name() for v in list(m.parameters) + list(m.constants)}
    inputs = {v.symbol.name() for v in m.inputs}
    for name, decl in flat.declarations.items():
        if decl.fixed is None or name in inputs:
            continue
        given = "fixed = <expression>" if decl.fixed == "expression" else f"fixed = {str(decl.fixed).lower()}"
        if name in states and decl.fixed is not True:
            start = states[name].start
            start = f" {start:g}" if isinstance(start, (int, float)) else ""
            problem = (f"state '{name}' has {given}: its start value{start} is then only a guess for an "
                       "initial solve, which needs initial equations")
            remedy = "give it fixed = true (the start value is the initial value) or remove fixed = false"
        elif name in parameters and decl.fixed is not True:
            problem = f"parameter '{name}' has {given}: it would be computed by initial equations"
            remedy = "give the parameter a value (binding) instead"
        elif name not in states and name not in parameters and decl.fixed is not False:
            problem = (f"'{name}' is not a state but has {given}: that is an initial equation "
                       f"{name} = start")
            remedy = "remove fixed (only states are started from their start values)"
        else:
            continue
        raise ModelStructureError(
            f"{flat.locate(name, 'fixed')}: {flat.name}: {problem}; cosim solves no initialization "
            f"problem (initial equations are not supported): {remedy}")


def _structural_error(name, residual, rows, row_match, col_match, w, x, m):
    """Explain a structurally singular system: which equations determine nothing, which
    unknowns are left over, and which states the surplus equations constrain (index > 1)."""
    unmatched_rows = [r for r, c in enumerate(row_match) if c < 0]
    # Dulmage-Mendelsohn: equations reachable from the surplus ones by alternating paths.
    over_rows, seen_cols = set(unmatched_rows), set()
    frontier = list(unmatched_rows)
    while frontier:
        r = frontier.pop()
        for c in rows[r]:
            if c not in seen_cols:
                seen_cols.add(c)
                if col_match[c] >= 0 and col_match[c] not in over_rows:
                    over_rows.add(col_match[c])
                    frontier.append(col_match[c])
    undetermined = [w[c].name() for c, r in enumerate(col_match) if r < 0]
    states = set()
    for r in over_rows:
        for s in ca.symvar(residual[r]):
            if any(ca.is_equal(s, xi) for xi in x):
                states.add(s.name())
    eq_text = "\n  ".join(f"0 = {residual[r]}" for r in sorted(over_rows))
    index_hint = ""
    if states:
        index_hint = (f"\nThe equations constrain the states {', '.join(sorted(states))} without an "
                      "unknown to solve for: the DAE has index > 1. pymoca does no index reduction; "
                      "write the model in index-1 form (e.g. momentum form, or differentiate the constraint).")
    raise ModelStructureError(
        f"{name}: the system is structurally singular.\nEquations that determine no unknown:\n  {eq_text}\n"
        f"Variables left undetermined: {', '.join(undetermined) or '(none)'}{index_hint}")


def _solve_blocks(name, residual, W, w, sp):
    """Solve the residual for all unknowns, block by block in block-triangular order."""
    nb, rowperm, colperm, rowblock, colblock, _, _ = sp.btf()
    blocks = [(rowperm[rowblock[b]:rowblock[b + 1]], colperm[colblock[b]:colblock[b + 1]]) for b in range(nb)]
    solved = {}  # column -> SX expression in terms of knowns only
    remaining = list(blocks)
    rows_of = {}
    for r, c in zip(*sp.get_triplet()):
        rows_of.setdefault(r, set()).add(c)
    while remaining:
        progress = False
        for block in list(remaining):
            brows, bcols = block
            needed = set().union(*(rows_of.get(r, set()) for r in brows)) - set(bcols)
            if not needed.issubset(solved):
                continue
            expr = residual[brows]
            if needed:
                cols = sorted(needed)
                expr = ca.substitute(expr, ca.vertcat(*[w[c] for c in cols]), ca.vertcat(*[solved[c] for c in cols]))
            wb = ca.vertcat(*[w[c] for c in bcols])
            jb = ca.jacobian(expr, wb)
            if ca.depends_on(jb, wb):
                eqs = "\n  ".join(f"0 = {residual[r]}" for r in brows)
                raise ModelStructureError(
                    f"{name}: nonlinear algebraic loop in {', '.join(w[c].name() for c in bcols)}; "
                    f"solving it is not supported yet. Equations:\n  {eqs}")
            r0 = ca.substitute(expr, wb, ca.SX.zeros(wb.shape))
            sol = -r0 / jb if len(bcols) == 1 else -ca.solve(jb, r0)
            for k, c in enumerate(bcols):
                solved[c] = ca.simplify(sol[k]) if len(bcols) == 1 else sol[k]
            remaining.remove(block)
            progress = True
        if not progress:  # cannot happen for a block-triangular form; guard against endless loops
            raise ModelStructureError(f"{name}: could not order the equations into solvable blocks")
    return [solved[c] for c in range(len(w))]
