"""Residual DAE -> explicit ODE.

pymoca gives residual equations ``0 = r(der(x), x, z, u, p, t)``. The unknowns
``w = [der(x); z]`` are matched to the equations (structural analysis), ordered into blocks
(block-triangular form) and solved block by block: a block linear in its unknowns is solved
symbolically. pymoca does no index reduction, so an equation that determines no unknown (a
constraint on states: index > 1) is reported with the variables involved.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca

from ..errors import ModelStructureError, ParameterError
from .flatten import FlatModel


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


def _column(symbols, name):
    return ca.vertcat(*symbols) if symbols else ca.SX(0, 1)


def _is_number(value) -> bool:
    if isinstance(value, (int, float, bool)):
        return True
    if isinstance(value, (ca.MX, ca.SX, ca.DM)):
        return False
    try:
        float(value)
        return True
    except (TypeError, ValueError):
        return False


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


class _Translator:
    """Maps pymoca's MX symbols to SX symbols and MX expressions to SX expressions."""

    def __init__(self, mx_symbols):
        self.mx = list(mx_symbols)
        self.sx = [ca.SX.sym(s.name(), *s.shape) for s in self.mx]

    def __call__(self, expressions):
        if not expressions:
            return ca.SX(0, 1)
        mx = ca.vertcat(*[ca.vec(ca.MX(e)) for e in expressions])
        f = ca.Function("translate", self.mx, [mx], {"allow_free": False})
        return f(*self.sx)


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

    for v in m.parameters:
        if isinstance(v.value, float) and math.isnan(v.value):
            raise ParameterError(f"{name}: parameter '{v.symbol.name()}' has no value")
    constants = [v for v in m.constants]

    alg = [v for v in m.alg_states]
    mx_symbols = ([m.time] + [v.symbol for v in m.states] + [v.symbol for v in m.der_states]
                  + [v.symbol for v in alg] + [v.symbol for v in m.inputs]
                  + [v.symbol for v in m.parameters] + [v.symbol for v in constants])
    tr = _Translator(mx_symbols)
    sx = dict(zip([s.name() for s in mx_symbols], tr.sx))
    pick = lambda vs: [sx[v.symbol.name()] for v in vs]
    t = tr.sx[0]
    x, xd, z, u = pick(m.states), pick(m.der_states), pick(alg), pick(m.inputs)
    consts = pick(constants)
    const_values = [ca.DM(v.value) if _is_number(v.value) else tr([v.value]) for v in constants]

    tunable = [v for v in m.parameters if _is_number(v.value)]
    calculated = [v for v in m.parameters if not _is_number(v.value)]
    p, csym = pick(tunable), pick(calculated)

    # Calculated parameters as expressions of the tunable ones (bindings may chain).
    cexpr = tr([v.value for v in calculated]) if calculated else ca.SX(0, 1)
    cexpr = ca.substitute(cexpr, _column(consts, "k"), ca.vertcat(*const_values)) if consts else cexpr
    for _ in range(len(calculated) + 1):
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

    W = _column(w, "w")
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

    start_exprs = []
    for v in m.states:
        start_exprs.append(v.start if _is_number(v.start) else None)
    x0 = []
    for v in m.states:
        x0.append(ca.SX(float(v.start)) if _is_number(v.start) else known(tr([v.start])))
    P = _column(p, "p")
    x0 = ca.vertcat(*x0) if x0 else ca.SX(0, 1)
    for label, expr in (("start values of states", x0), ("calculated parameters", cexpr)):
        free = ca.symvar(expr)
        bad = [s.name() for s in free if not any(ca.is_equal(s, q) for q in p)]
        if bad:
            raise ModelStructureError(f"{name}: {label} depend on non-parameters: {', '.join(bad)}")

    def sym(v, start):
        return Symbolic(v.symbol.name(), start, getattr(v, "python_type", float))

    return ExplicitModel(
        name=name, t=t, x=_column(x, "x"), u=_column(u, "u"), p=P,
        xdot=ca.vertcat(*xdot) if xdot else ca.SX(0, 1),
        z=ca.vertcat(*zsol) if zsol else ca.SX(0, 1),
        c=cexpr, x0=x0,
        states=[sym(v, float(v.start) if _is_number(v.start) else None) for v in m.states],
        inputs=[sym(v, float(v.start) if _is_number(v.start) else 0.0) for v in m.inputs],
        parameters=[sym(v, v.value) for v in tunable],
        calculated=[sym(v, None) for v in calculated],
        algebraics=[sym(v, None) for v in alg],
    )


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
