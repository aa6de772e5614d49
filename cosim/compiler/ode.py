"""Residual DAE -> explicit ODE.

pymoca gives residual equations ``0 = r(der(x), x, z, u, p, t)``. The unknowns
``w = [der(x); z]`` are matched to the equations (structural analysis), ordered into blocks
(block-triangular form) and solved block by block: a block linear in its unknowns is solved
symbolically. pymoca does no index reduction, so an equation that determines no unknown (a
constraint on states: index > 1) is reported with the variables involved.

Initial equations become residuals ``0 = r(t, x, u, p)`` (state derivatives and algebraic
variables replaced by their solution) whose unknowns are the states declared ``fixed = false``;
the FMU solves them by Newton's method at initialization (see ``codegen.start_function``).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import casadi as ca
import numpy as np

from cosim.errors import ModelicaError, ModelStructureError, ParameterError
from cosim.compiler.flatten import FlatModel, fewer_collections


@dataclass
class Symbolic:
    """One symbol of the explicit model with what the FMU needs to know about it."""

    name: str
    start: object = None  # float, SX expression of p, or None
    python_type: type = float
    output: bool = False  # declared ``output`` (an FMU output: directional derivatives are provided)


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
    # Initial equations ``0 = r(t, x, u, p)`` (state derivatives and algebraic variables
    # substituted) and the indices into ``x`` of their unknowns, the states declared
    # ``fixed = false``; their ``x0`` entries are the guesses of the Newton solve. Empty: every
    # state starts at ``x0``.
    init_residual: ca.SX = None
    init_unknowns: list[int] = None
    # The algebraic loops (blocks of more than one unknown), in the order solved: (unknowns of the
    # block, size of the linear system solved for them: the tear variables, see _tear).
    loops: list[tuple[int, int]] = None

    def __post_init__(self):
        if self.init_residual is None:
            self.init_residual = ca.SX(0, 1)
        if self.init_unknowns is None:
            self.init_unknowns = []
        if self.loops is None:
            self.loops = []


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
        not linear, unsupported constructs (delay, ``fixed`` attributes that ask for an
        initialization problem other than states solved from initial equations).
    ModelicaError
        Initial equations that do not determine the states declared ``fixed = false``
        (unbalanced or structurally singular), naming file:line and the variables.
    ParameterError
        A parameter without value.
    """
    with fewer_collections():
        return _make_explicit(flat)


def _make_explicit(flat: FlatModel) -> ExplicitModel:
    m = flat.casadi
    name = flat.name
    if getattr(m, "delay_states", None):
        raise ModelStructureError(f"{name}: delay() is not supported; use a Pade approximation (Bicycle.Rider)")

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

    # Tunable: a parameter with a number for its value that is not final (a final parameter's
    # value cannot be changed, in Modelica as in the FMU: it is a calculated parameter there).
    def is_tunable(v) -> bool:
        declaration = flat.declarations.get(v.symbol.name())
        return _numbers(v.value, v.symbol.numel()) is not None and not (declaration and declaration.final)

    tunable = [v for v in m.parameters if is_tunable(v)]
    calculated = [v for v in m.parameters if not is_tunable(v)]
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
    initial = known(tr(m.initial_equations)) if m.initial_equations else ca.SX(0, 1)

    # The scalar states: each with the flat variable it is an element of (its declaration gives
    # the start value and ``fixed``) and its index in that variable.
    variable_of = [(v.symbol.name(), k) for v in m.states for k in range(v.symbol.numel())]
    algebraic_of = [(v.symbol.name(), k) for v in alg for k in range(v.symbol.numel())]
    underived = _underived(residual, xd)
    kept = [k for k in range(len(x)) if k not in underived]
    # Algebraic variables: the model's, then the declared states whose der() occurs in no equation
    # (in Modelica a state is a variable to which der() is applied).
    z = z + [x[k] for k in sorted(underived)]
    algebraic_of += [variable_of[k] for k in sorted(underived)]
    _refuse_initialization_attributes(flat, {variable_of[k][0] for k in kept})

    state_x = {k: x[k] for k in kept}
    state_xd = {k: xd[k] for k in kept}
    renamed = _top_level_aliases(flat, residual, state_x, variable_of, z, algebraic_of)
    for k, j in renamed.items():
        # The state takes the top-level name; the component's name stays an algebraic variable
        # (equal to the state through the alias equations). Its derivative is named anew.
        state_x[k], z[j] = z[j], x[k]
        state_xd[k] = ca.SX.sym(f"der({state_x[k].name()})")
    if renamed:
        old = _column([xd[k] for k in renamed])
        new = _column([state_xd[k] for k in renamed])
        residual = ca.substitute(residual, old, new)
        initial = ca.substitute(initial, old, new) if initial.numel() else initial
    order = _state_order(flat, kept, variable_of, {k: algebraic_of[j] for k, j in renamed.items()})
    x = [state_x[k] for k in order]
    xd = [state_xd[k] for k in order]

    w = xd + z
    neq, nw = residual.numel(), len(w)
    if neq != nw:
        raise ModelStructureError(
            f"{name}: the model is unbalanced: {neq} equations for {nw} unknowns "
            f"({len(xd)} state derivatives, {len(z)} algebraic variables)")

    W = _column(w)
    # only the structure is needed: the sparsity pattern alone, without the symbolic Jacobian
    # (a tenth of making the nonlinear bicycles explicit; the same pattern for every model)
    sp = ca.jacobian_sparsity(residual, W)
    rows = [[] for _ in range(neq)]
    for r, c in zip(*sp.get_triplet()):
        rows[r].append(c)
    row_match, col_match = _maximum_matching(rows, nw)
    if -1 in row_match:
        _structural_error(name, residual, rows, row_match, col_match, w, x)

    solution, loops = _solve_blocks(name, residual, W, w, sp)
    xdot = solution[: len(xd)]
    zsol = solution[len(xd):]

    x0, state_starts, expressions = [], [], []
    for v in m.states:
        numbers = _numbers(v.start, v.symbol.numel())
        if numbers is not None:
            x0 += [ca.SX(n) for n in numbers]
            state_starts += numbers
        else:
            x0 += [None] * v.symbol.numel()  # filled in below
            expressions.append(v.start)
            state_starts += [None] * v.symbol.numel()
    if expressions:  # translated at once: each translation is a function of all the symbols
        values = iter(ca.vertsplit(known(tr(expressions))))
        x0 = [e if e is not None else next(values) for e in x0]
    x0 = [x0[k] for k in order]
    state_starts = [state_starts[k] for k in order]
    P = _column(p)
    x0 = ca.vertcat(*x0) if x0 else ca.SX(0, 1)
    parameter_ids = {q.element_hash() for q in p}  # a set: comparing with each of p is quadratic
    for label, expr in (("start values of states", x0), ("calculated parameters", cexpr)):
        free = ca.symvar(expr)
        bad = [s.name() for s in free if s.element_hash() not in parameter_ids]
        if bad:
            raise ModelStructureError(f"{name}: {label} depend on non-parameters: {', '.join(bad)}")

    # The states declared fixed = false (the declaration of the flat variable: a renamed state
    # keeps the component's fixed) are the unknowns of the initial equations.
    solved_names = list(dict.fromkeys(variable_of[k][0] for k in order if _fixed(flat, variable_of[k][0]) is False))
    init_residual, init_unknowns = _initial_problem(
        flat, initial, [i for i, k in enumerate(order) if variable_of[k][0] in solved_names], solved_names,
        _column(xd + z), ca.vertcat(*solution) if solution else ca.SX(0, 1), x, t, u, p)

    def output(element_name: str) -> bool:
        declaration = flat.declarations.get(element_name)
        return declaration is not None and "output" in declaration.prefixes

    def symbols(variables, starts=None):
        found = []
        for v in variables:
            python_type = getattr(v, "python_type", float)
            for k, element in enumerate(tr.elements[v.symbol.name()]):
                start = starts(v, k) if starts else None
                found.append(Symbolic(element.name(), start, python_type, output(element.name())))
        return found

    def literal(attr, default=None):
        def element(v, k):
            numbers = _numbers(getattr(v, attr), v.symbol.numel())
            return numbers[k] if numbers is not None else default
        return element

    alg_types = {v.symbol.name(): getattr(v, "python_type", float) for v in list(alg) + list(m.states)}
    return ExplicitModel(
        name=name, t=t, x=_column(x), u=_column(u), p=P,
        xdot=ca.vertcat(*xdot) if xdot else ca.SX(0, 1),
        z=ca.vertcat(*zsol) if zsol else ca.SX(0, 1),
        c=cexpr, x0=x0,
        states=[Symbolic(s.name(), start, float, output(s.name())) for s, start in zip(x, state_starts)],
        inputs=symbols(m.inputs, literal("start", 0.0)),
        parameters=symbols(tunable, literal("value")),
        calculated=symbols(calculated),
        algebraics=[Symbolic(s.name(), None, alg_types[variable], output(s.name()))
                    for s, (variable, _) in zip(z, algebraic_of)],
        init_residual=init_residual,
        init_unknowns=init_unknowns,
        loops=loops,
    )


def _fixed(flat: FlatModel, variable: str):
    """The ``fixed`` attribute given in the declaration of a flat variable (None: not given)."""
    declaration = flat.declarations.get(variable)
    return declaration.fixed if declaration is not None else None


def _underived(residual, xd) -> set[int]:
    """Indices of the state derivatives that occur in no equation.

    pymoca lists a variable as a state when ``der()`` is applied to it anywhere, also in the branch
    of an if-equation that a constant condition drops (``if dep then s = ud; else der(s) = -a;``):
    once the constants are substituted the branch is gone and so is ``der(s)``."""
    if not xd:
        return set()
    if residual.numel() == 0:
        return set(range(len(xd)))
    _, columns = ca.jacobian_sparsity(residual, _column(xd)).get_triplet()
    return set(range(len(xd))) - set(columns)


def _top_level_aliases(flat: FlatModel, residual, state_x: dict, variable_of: list, z: list,
                       algebraic_of: list) -> dict[int, int]:
    """The states of components that take a top-level name: scalar state index -> index in ``z``.

    A joint owns its coordinate (``steer.angle``, ``der(steer.angle) = steer.omega``) and the
    assembly names it for the FMU with a declaration equation ``output Angle delta = steer.angle``.
    A state whose flat variable is dotted takes the name of a top-level algebraic variable whose
    declaration equation is a plain reference (flatten.Declaration.binding) and which equals the
    state through plain alias equations ``a = b`` (either side, no sign or factor; a chain of them
    as connections give). The first declared of several such names is taken. A top-level variable
    equated to a state in the equation section keeps its role (the component bicycles'
    ``phi = frame.phi``: their FMUs keep the state ``frame.phi``)."""
    declarations = flat.declarations
    named = {j for j, (variable, _) in enumerate(algebraic_of)
             if "." not in variable and declarations.get(variable) is not None
             and declarations[variable].binding is not None}
    dotted = [k for k in state_x if "." in variable_of[k][0]]
    if not named or not dotted:
        return {}
    # union-find over the states and algebraic variables joined by alias equations
    members = [state_x[k] for k in dotted] + list(z)
    index = {s.element_hash(): i for i, s in enumerate(members)}
    parent = list(range(len(members)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for equation in ca.vertsplit(residual):
        if equation.is_op(ca.OP_SUB):
            a, b = equation.dep(0), equation.dep(1)
            if a.is_symbolic() and b.is_symbolic():
                i, j = index.get(a.element_hash()), index.get(b.element_hash())
                if i is not None and j is not None:
                    parent[root(i)] = root(j)
    states_of, names_of = {}, {}
    for i, k in enumerate(dotted):
        states_of.setdefault(root(i), []).append(k)
    order = {variable: n for n, variable in enumerate(declarations)}
    for j in named:
        names_of.setdefault(root(len(dotted) + j), []).append(j)
    renamed = {}
    for group, states in states_of.items():
        if len(states) == 1 and group in names_of:  # two states equal: index > 1, reported later
            renamed[states[0]] = min(names_of[group], key=lambda j: (order[algebraic_of[j][0]], algebraic_of[j][1]))
    return renamed


def _state_order(flat: FlatModel, kept: list[int], variable_of: list, renamed: dict) -> list[int]:
    """The order of the states: those with a top-level name (declared at top level, or renamed
    after their top-level alias) in the order of the top-level declarations, then the states that
    keep a dotted name in pymoca's order. Renamed states that the model declares itself come after
    those it inherits. Models that declare their states at top level keep pymoca's order (that of
    their declarations)."""
    order = {variable: n for n, variable in enumerate(flat.declarations)}

    def key(position):
        k = kept[position]
        variable, element = renamed.get(k, variable_of[k])
        if "." in variable or variable not in order:
            return (1, 0, position, 0)
        # pymoca lists a class's own elements before the inherited ones; the names of component
        # states follow the class they extend (a variant's new joint after the bicycle's states)
        declaration = flat.declarations[variable]
        own = k in renamed and declaration.owner == flat.name
        return (0, int(own), order[variable], element)

    return [kept[i] for i in sorted(range(len(kept)), key=key)]


def _initial_problem(flat: FlatModel, residual, unknowns: list[int], unknown_names: list[str], w, solution,
                     x, t, u, p):
    """The initial equations as residuals of ``(t, x, u, p)`` and the indices of their unknowns.

    The unknowns (``unknowns``, indices into ``x``) are the states declared ``fixed = false`` (all
    elements of an array state; ``unknown_names`` are their flat variables); every other state
    starts at its start value. State derivatives and algebraic variables in the initial equations
    are replaced by their solution, so ``der(v) = 0`` (steady state) and an equation on an output
    such as ``frontContactHeight = 0`` are residuals of the states.

    Raises
    ------
    ModelicaError
        Unbalanced (unknowns != initial equations) or structurally singular (an equation that
        involves none of the unknowns it could determine), naming file:line and the variables.
    """
    if residual.numel() == 0 and not unknowns:
        return ca.SX(0, 1), []
    if w.numel():
        residual = ca.substitute(residual, w, solution)
    names = ", ".join(x[k].name() for k in unknowns) or "(none)"
    where = _initial_equation_location(flat, unknown_names)
    if residual.numel() != len(unknowns):
        if not unknowns:
            remedy = "declare the states they determine with fixed = false (their start values are then guesses)"
        elif residual.numel() < len(unknowns):
            remedy = ("add initial equations, or give the states that keep their start value fixed = true")
        else:
            remedy = "remove initial equations, or declare further states with fixed = false"
        raise ModelicaError(
            f"{where}: {flat.name}: the initial equations are unbalanced: {residual.numel()} initial "
            f"equation(s) for {len(unknowns)} unknown(s) (the states declared fixed = false: {names}); {remedy}")
    allowed = [t] + list(x) + list(u) + list(p)
    bad = sorted({s.name() for s in ca.symvar(residual) if not any(ca.is_equal(s, a) for a in allowed)})
    if bad:
        raise ModelStructureError(f"{where}: {flat.name}: the initial equations depend on {', '.join(bad)}, "
                                  "which are not states, inputs, parameters or time")
    free = ca.vertcat(*[x[k] for k in unknowns])
    sp = ca.jacobian(residual, free).sparsity()
    rows = [[] for _ in range(residual.numel())]
    for r, c in zip(*sp.get_triplet()):
        rows[r].append(c)
    row_match, col_match = _maximum_matching(rows, len(unknowns))
    if -1 in row_match:
        surplus = [_shortened(f"0 = {residual[r]}") for r, c in enumerate(row_match) if c < 0]
        left = [x[unknowns[c]].name() for c, r in enumerate(col_match) if r < 0]
        raise ModelicaError(
            f"{where}: {flat.name}: the initial equations do not determine the states declared fixed = false "
            f"({names}): undetermined: {', '.join(left)}; initial equations left without an unknown of their "
            f"own (after substituting the model equations):\n  " + "\n  ".join(surplus))
    return residual, unknowns


def _initial_equation_location(flat: FlatModel, unknown_names: list[str]) -> str:
    """``file:line`` of the ``initial equation`` section (in the model or a class it is made
    of), else of the ``fixed = false`` of the first unknown, else the model's file."""
    library = flat.library
    if library is None:
        return flat.name
    classes = [flat.name] + sorted({d.owner for d in flat.declarations.values() if d.owner and d.owner != flat.name})
    for cls in classes:
        file, line = library.locate(cls, r"\binitial\s+equation\b")
        if line is not None:
            return f"{file}:{line}"
    return flat.locate(unknown_names[0], "fixed") if unknown_names else str(library.file_of(flat.name))


def _shortened(text: str, limit: int = 300) -> str:
    """``text``, cut to ``limit`` characters (substituted equations of a large model are long)."""
    return text if len(text) <= limit else text[: limit - 5] + " ..."


def _refuse_initialization_attributes(flat: FlatModel, states: set[str]) -> None:
    """Refuse ``fixed`` attributes that ask for an initialization problem cosim does not solve.

    A state declared ``fixed = false`` is an unknown of the initial equations (its start value
    is the guess of the Newton solve, see :func:`_initial_problem`); a state with
    ``fixed = true`` or without ``fixed`` starts at its start value (what Modelica tools do for
    a state that no initial equation determines). Still refused: ``fixed = <expression>`` on a
    state (whether it is an unknown would depend on parameters), ``fixed = false`` on a
    parameter (a parameter computed during initialization) and ``fixed = true`` on a variable
    that is not a state (the initial equation ``v = start`` of an algebraic variable).

    ``states`` are the flat variables that are states (a declared state without ``der()`` is not).

    Raises
    ------
    ModelStructureError
        Naming the variable and the file (and line) where its ``fixed`` is given.
    """
    m = flat.casadi
    parameters = {v.symbol.name() for v in list(m.parameters) + list(m.constants)}
    inputs = {v.symbol.name() for v in m.inputs}
    for name, decl in flat.declarations.items():
        if decl.fixed is None or name in inputs:
            continue
        given = "fixed = <expression>" if decl.fixed == "expression" else f"fixed = {str(decl.fixed).lower()}"
        if name in states and decl.fixed == "expression":
            problem = (f"state '{name}' has {given}: whether its start value is the initial value or a guess "
                       "for the initial equations must not depend on parameters")
            remedy = "write fixed = true (start value is the initial value) or fixed = false (solved)"
        elif name in parameters and decl.fixed is not True:
            problem = f"parameter '{name}' has {given}: it would be computed by initial equations"
            remedy = ("give the parameter a value (binding) instead, or make the quantity a state "
                      "with fixed = false and der() = 0")
        elif name not in states and name not in parameters and decl.fixed is not False:
            problem = (f"'{name}' is not a state but has {given}: that is an initial equation "
                       f"{name} = start")
            remedy = ("remove fixed and write the condition as an initial equation that determines a state "
                      "declared fixed = false")
        else:
            continue
        raise ModelStructureError(
            f"{flat.locate(name, 'fixed')}: {flat.name}: {problem}; cosim solves initial equations only for "
            f"states declared fixed = false: {remedy}")


def _structural_error(name, residual, rows, row_match, col_match, w, x):
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


def _isolated(residual, unknown):
    """``e`` if the scalar residual is ``unknown - e`` or ``e - unknown`` with ``e`` free of the
    unknown, else None."""
    if residual.is_op(ca.OP_SUB):
        a, b = residual.dep(0), residual.dep(1)
        if ca.is_equal(a, unknown) and not ca.depends_on(b, unknown):
            return b
        if ca.is_equal(b, unknown) and not ca.depends_on(a, unknown):
            return a
    return None


# Loops of fewer unknowns are solved as one linear system without tearing, as before tearing was
# introduced (the Whipple bicycle's three generalized accelerations): tearing so few unknowns gains
# nothing. A larger loop is solved as one system as well when tearing leaves no unknown to assign
# (WhippleRider's four accelerations, coupled through the full mass matrix).
TEARING_MIN_UNKNOWNS = 4


def _solve_blocks(name, residual, W, w, sp):
    """Solve the residual for all unknowns, block by block in block-triangular order.

    Returns the solution (an expression of the knowns for each unknown) and the algebraic loops
    (see ``ExplicitModel.loops``)."""
    nb, rowperm, colperm, rowblock, colblock, _, _ = sp.btf()
    blocks = [(rowperm[rowblock[b]:rowblock[b + 1]], colperm[colblock[b]:colblock[b + 1]]) for b in range(nb)]
    solved = {}  # column -> SX expression in terms of knowns only
    loops = []
    rows_of = {}
    for r, c in zip(*sp.get_triplet()):
        rows_of.setdefault(r, set()).add(c)
    # The block-triangular form lists the blocks in an order in which each needs only earlier
    # ones: one pass solves them all. (Blocks whose unknowns are not all known yet would wait
    # for a further pass; rescanning the list of blocks for each one was quadratic in the size.)
    remaining = blocks
    while remaining:
        waiting = []
        for block in remaining:
            brows, bcols = block
            needed = set().union(*(rows_of.get(r, set()) for r in brows)) - set(bcols)
            if not all(c in solved for c in needed):  # (set.issubset(dict) copies the dict)
                waiting.append(block)
                continue
            expr = residual[brows]
            if needed:
                cols = sorted(needed)
                expr = ca.substitute([expr], [w[c] for c in cols], [solved[c] for c in cols])[0]
            if len(bcols) == 1:
                # Most equations of an assembly are aliases (connections) or assignments w = e:
                # taken as they are, without a Jacobian (a third of the build of a component bicycle)
                isolated = _isolated(expr, w[bcols[0]])
                if isolated is not None:
                    solved[bcols[0]] = isolated
                    continue
            wb = ca.vertcat(*[w[c] for c in bcols])
            jb = ca.jacobian(expr, wb)
            if ca.depends_on(jb, wb):
                eqs = "\n  ".join(f"0 = {residual[r]}" for r in brows)
                raise ModelStructureError(
                    f"{name}: nonlinear algebraic loop in {', '.join(w[c].name() for c in bcols)}; "
                    f"solving it is not supported yet. Equations:\n  {eqs}")
            if len(bcols) >= TEARING_MIN_UNKNOWNS:
                torn = _solve_torn(expr, [w[c] for c in bcols], jb)
                if torn is not None:
                    values, tears = torn
                    solved.update(zip(bcols, values))
                    loops.append((len(bcols), tears))
                    continue
            r0 = ca.substitute(expr, wb, ca.SX.zeros(wb.shape))
            sol = -r0 / jb if len(bcols) == 1 else -ca.solve(jb, r0)
            for k, c in enumerate(bcols):
                solved[c] = ca.simplify(sol[k]) if len(bcols) == 1 else sol[k]
            if len(bcols) > 1:
                loops.append((len(bcols), len(bcols)))
        if len(waiting) == len(remaining):  # cannot happen for a block-triangular form; no endless loop
            raise ModelStructureError(f"{name}: could not order the equations into solvable blocks")
        remaining = waiting
    return [solved[c] for c in range(len(w))], loops


def _numeric(coefficient) -> float | None:
    """The value of a Jacobian entry that is a nonzero finite number; None for an expression
    (which may be zero at some point: an unknown is never assigned by dividing by it)."""
    if not coefficient.is_constant():
        return None
    value = float(coefficient)
    return value if value != 0 and math.isfinite(value) else None


def _solve_torn(expr, unknowns: list, jacobian):
    """Solve the linear loop ``expr(unknowns) = 0`` by tearing (see :func:`_tear`).

    Every unknown but the tear variables is assigned from one equation, in which its coefficient
    is a number, as an expression of the tear variables; the remaining equations (residual
    equations, linear in the tear variables) give the tear variables: ``J t = -r0``. Returns the
    solution of each unknown and the number of tear variables, or None when tearing leaves as
    many tear variables as unknowns (then the loop is solved as one linear system)."""
    n = len(unknowns)
    coefficients = [{} for _ in range(n)]
    for r, c, a in zip(*jacobian.sparsity().get_triplet(), jacobian.nonzeros()):
        coefficients[r][c] = _numeric(a)
    assignments, tears, residual_rows = _tear([{c: a is not None for c, a in row.items()} for row in coefficients], n)
    if len(tears) >= n:
        return None
    equations = ca.vertsplit(expr)
    value = {}  # unknown -> expression of the tear variables and the knowns
    for v, e in assignments:
        # the other unknowns of the equation are tear variables or assigned before
        others = [c for c in coefficients[e] if c != v and c in value]
        rest = ca.substitute([equations[e]], [unknowns[v]] + [unknowns[c] for c in others],
                             [ca.SX(0)] + [value[c] for c in others])[0]
        value[v] = -rest / coefficients[e][v]
    torn = _column([unknowns[t] for t in tears])
    if tears:
        assigned = [v for v, _ in assignments]
        residual = ca.substitute([_column([equations[e] for e in residual_rows])],
                                 [unknowns[v] for v in assigned], [value[v] for v in assigned])[0]
        jt = ca.jacobian(residual, torn)
        r0 = ca.substitute(residual, torn, ca.SX.zeros(torn.shape))
        tear_values = _solve_linear(jt, r0)
        values = ca.vertsplit(ca.substitute(_column([value[v] for v in assigned]), torn, _column(tear_values)))
        value.update(zip(assigned, values))
        value.update(zip(tears, tear_values))
    return [value[v] for v in range(n)], len(tears)


def _solve_linear(a, b) -> list:
    """``x`` with ``a x + b = 0`` (``a`` square, symbolic), block by block in the block-triangular
    order of ``a``'s structure: a decoupled part is solved on its own, so that a row
    ``J*du_k = 0`` (a held joint) gives ``du_k = 0`` exactly instead of the rounding of a dense
    solve that mixes it with the others."""
    n = a.size1()
    if n == 1:
        return [-b[0] / a[0, 0]]
    nb, rowperm, colperm, rowblock, colblock, _, _ = a.sparsity().btf()
    if nb == 1:
        return ca.vertsplit(-ca.solve(a, b))
    rows_of = {}
    for r, c in zip(*a.sparsity().get_triplet()):
        rows_of.setdefault(r, set()).add(c)
    blocks = [(rowperm[rowblock[k]:rowblock[k + 1]], colperm[colblock[k]:colblock[k + 1]]) for k in range(nb)]
    x = {}
    while blocks:
        waiting = []
        for rows, cols in blocks:
            needed = sorted(set().union(*(rows_of.get(r, set()) for r in rows)) - set(cols))
            if not all(c in x for c in needed):
                waiting.append((rows, cols))
                continue
            rhs = b[rows]
            for c in needed:
                rhs = rhs + a[rows, c] * x[c]
            block = a[rows, cols]
            values = [-rhs[0] / block[0, 0]] if len(cols) == 1 else ca.vertsplit(-ca.solve(block, rhs))
            x.update(zip(cols, values))
        if len(waiting) == len(blocks):  # cannot happen for a block-triangular form
            raise ModelStructureError("could not order a linear system into solvable blocks")
        blocks = waiting
    return [x[c] for c in range(n)]


def _tear(equations: list[dict[int, bool]], n: int) -> tuple[list[tuple[int, int]], list[int], list[int]]:
    """Tear variables and residual equations of a square linear loop (structure only).

    ``equations[e]`` maps each unknown of equation ``e`` (0 .. n-1) to whether it can be assigned
    from ``e`` (its coefficient is a nonzero number). Unknowns are assigned one by one, each from an
    equation in which it is the only one not yet known; when none can be, a tear variable is taken
    as known: an unknown that no remaining equation can assign (it must be one), else the unknown
    whose tearing lets the most unknowns be assigned at once; of equals the one in the most
    remaining equations, then the first. (Counting equations alone would tear the accelerations
    of a body, which occur in all of its equations ``F = f - M*du``, one after the other.)

    In a Kane-style assembly (a root ``du = S*dui + D*ad0`` and ``transpose(T)*F = 0``, bodies
    ``F = f - M*du``, connections aliasing ``du`` and summing ``F``) the tear variables are the
    independent accelerations ``dui`` (or aliases of them among the ``du``).

    Returns the assignments (unknown, equation) in the order to compute them, the tear variables
    and the residual equations (the equations not used by an assignment).
    """
    occurs = [[] for _ in range(n)]
    for e, row in enumerate(equations):
        for v in row:
            occurs[v].append(e)
    left = [len(row) for row in equations]  # unknowns of each equation neither assigned nor torn
    total = [sum(row) for row in equations]  # the sum of their indices: the last one when left == 1
    known = [False] * n
    used = [False] * len(equations)
    assignments, tears = [], []

    def settle(v, queue):
        known[v] = True
        for e in occurs[v]:
            left[e] -= 1
            total[e] -= v
            if left[e] == 1 and not used[e]:
                queue.append(e)

    def propagate(queue):
        while queue:
            e = queue.pop()
            v = total[e]
            if used[e] or left[e] != 1 or not equations[e][v]:
                continue
            used[e] = True
            assignments.append((v, e))
            settle(v, queue)

    def reach(v) -> int:
        """How many unknowns tearing ``v`` would let be assigned (the state is not changed)."""
        count, now_known, now_used, lefts, totals = 0, {v}, set(), {}, {}
        stack = [v]
        while stack:
            y = stack.pop()
            for e in occurs[y]:
                if used[e] or e in now_used:
                    continue
                lefts[e] = lefts.get(e, left[e]) - 1
                totals[e] = totals.get(e, total[e]) - y
                last = totals[e]
                if lefts[e] == 1 and last not in now_known and not known[last] and equations[e][last]:
                    now_used.add(e)
                    now_known.add(last)
                    stack.append(last)
                    count += 1
        return count

    def occurrences(v) -> int:
        return sum(1 for e in occurs[v] if not used[e])

    propagate([e for e in range(len(equations)) if left[e] == 1])
    while not all(known):
        unknown = [v for v in range(n) if not known[v]]
        forced = [v for v in unknown if not any(equations[e][v] for e in occurs[v] if not used[e])]
        if forced:
            tear = forced[0]
        else:
            candidates = sorted(unknown, key=lambda v: -occurrences(v))  # stable: the first of equals first
            tear, best = candidates[0], -1
            for v in candidates:
                found = reach(v)
                if found > best:
                    tear, best = v, found
                if best == len(unknown) - 1:  # tearing it determines all the others
                    break
        tears.append(tear)
        queue = []
        settle(tear, queue)
        propagate(queue)
    return assignments, tears, [e for e in range(len(equations)) if not used[e]]
