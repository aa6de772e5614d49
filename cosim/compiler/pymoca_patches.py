"""Work-arounds for pymoca 0.12 parsing and flattening bugs, applied once before the first parse.

Name capture in modifications: in ``frame(m = m)`` pymoca resolves the right-hand ``m`` in
the enclosing model correctly (to the flat name ``m``) but two later passes re-prefix every
reference with the component path when such a name exists there, so the binding becomes
``frame.m = frame.m``. References that the modification resolver already made flat are
marked here, and both re-prefixing passes leave marked references alone.
Report: docs/pymoca-upstream.md#name-capture.

Functions: pymoca names the CasADi function of a Modelica function by its dotted class name
(``Bicycle.Functions.f``, ``Model.helper`` for a function declared inside a model), which CasADi
refuses as a function name. The generator is given a valid identifier instead.
Report: docs/pymoca-upstream.md#function-names.

``fixed``: pymoca gives every variable ``fixed = false`` whether it was written or not, so
``Real x(start = 1)`` (where a tool takes the start value as the initial value) cannot be told
from ``Real x(start = 1, fixed = false)`` (where the start value is only a guess for an initial
solve). Symbols whose ``fixed`` was given explicitly are marked ``_cosim_fixed_given``.
Report: docs/pymoca-upstream.md#fixed-given.

Short connector classes (``connector RealInput = input Real "...";``, the Modelica Standard
Library's ``Blocks.Interfaces`` style): pymoca's parser drops the ``input``/``output`` of such a
definition, and its flattening turns every component of such a connector type into a connector
with one variable called ``Real``, so ``connect(a.y, b.u)`` becomes ``a.y.Real = b.u.Real``, names
that are not declared. The parser keeps the prefixes here (``_cosim_base_prefixes`` of the class),
and a connector that is just a built-in type stays the scalar (or array) variable it is, so that
its connections are the plain equations ``a.y = b.u``.
Report: docs/pymoca-upstream.md#short-connectors.

Constants of a derived type: pymoca finds the value of a constant referred to from elsewhere
(``parameter Real w = Data.w`` with ``constant Units.Length w = 1.02`` in the package ``Data``)
only when its type is a built-in type; for ``type Length = Real(...)`` the value sits in the
built-in type behind the derived one and the reference stayed the undeclared name
``Data.Benchmark.w``. The value is looked up through the derived types here.
Report: docs/pymoca-upstream.md#derived-type-constants.

Package constants in equations: pymoca resolves the names in equations only against the flat
variables, so ``der(x) = Data.w`` or ``f = Modelica.Constants.g`` left ``Data.w`` undeclared.
A name that is not a flat variable is looked up from the class of the equation; a constant with
a literal value is replaced by that value (MLS 5.6.2: constants are evaluated), anything else is
left for the error message that names it.
Report: docs/pymoca-upstream.md#constants-in-equations.

Modified constants (MLS 7.2): in ``B b(n = 3)`` with ``J j(n = n)`` in B and ``C c(n = n)`` in J,
the right-hand ``n`` of a modifier is that of the enclosing instance (``b.n``, then ``b.j.n``),
whose value is that instance's modifier: ``b.j.n = b.j.c.n = 3``. pymoca found the right symbol but
took its value from the first value modification of its chain, the default of the declaration
(``constant Integer n = 2``): from the second level down a modified constant had its class's
default, in array dimensions, ``for`` ranges, bindings of other constants (``ni = n - 1``) and
expressions (``if j == k then 1 else 0``) alike. (Without a default the value stayed a reference
that the flat model resolved; with defaults the library had to write its nested modifiers out,
``rearFrame(n = n, frame_a(n = n))``.) The value of a constant is now its last value modification,
the outermost one, evaluated in that modification's scope: a literal is taken, a name or an
expression is evaluated through the chain (each link once per flattening; a cycle gives no value),
and what pymoca cannot evaluate stays a reference as before. Names used in an inherited class
(``c(n = n)`` written in the base class of ``extends J`` or of ``extends B(n = m)``) were looked up
in a full instance of the base class made anew from its declarations (the partial instance had
consumed the modifiers of the extends clause and of the component), so they had the defaults as
well: the instance's own components are put into that full instance (:func:`_graft_components`).
Report: docs/pymoca-upstream.md#modified-constants.

Inherited constants: for ``Data.w`` with ``package A extends PartialSet(w = 1.02)``, pymoca's
name lookup finds ``w`` in the class ``PartialSet`` and instantiates that class alone, without the
modifier of ``extends``: the constant had no value. When a constant found so has none, the package
(``Data``) is instantiated in full and the constant's value taken from there.
Report: docs/pymoca-upstream.md#inherited-constants.

Record bindings: pymoca ignores the binding of a record component (``Mass body(b = rb)``,
``parameter Rec rc = rb``) without a word, so the record kept its default values. A binding to
another record component is applied here element by element (``body.b.m = rb.m`` for every
element, nested records included); a binding to any other expression (a record constructor
``Rec(m = 3)``, whose named arguments pymoca's parser drops, a function call, an array of
records) is refused with :class:`RecordBindingError`.
Report: docs/pymoca-upstream.md#record-bindings.

Component redeclarations: for ``replaceable Knife w constrainedby PartialWheel`` redeclared as
``redeclare Torus w``, pymoca adds ``Torus`` as a base class of the instance of ``Knife``, so
the component had the equations of both (``w.y = w.r + w.rc`` and ``w.y = w.r``, an unbalanced
model). The component's type is made the redeclared class alone, as MLS 7.3 prescribes. pymoca
also registered that private class instance in the component's parent under the class name, where
the next component of the same class found it (``extends Two(redeclare Torus a, redeclare Torus
b)``: ``b`` got the bases of both redeclarations); it is unregistered once the component is
instantiated, and made the component's: the names in it lacked the component's name (with
``redeclare Knife w`` the constant ``w.c.n`` of Knife's connector was also looked up as ``c.n``, a
constant without a value).
Reports: docs/pymoca-upstream.md#component-redeclare,
docs/pymoca-upstream.md#two-redeclares.

Constraining clauses: pymoca's parser drops ``constrainedby C(m2)``. For a component
``replaceable K w(m1) constrainedby C(m2)`` the modifiers ``m2`` are kept here in front of ``m1``
(they apply to the default and to every redeclaration) and ``m1`` is dropped when ``w`` is
redeclared (MLS 7.3.2: with a constraining clause the declaration's own modifiers belong to the
default only). For a replaceable class (``replaceable model W = K(m1) constrainedby C(m2)``)
either is refused with :class:`RedeclareError` (``m2`` at all, ``m1`` on a redeclaration), as
pymoca would silently use the wrong modifiers.
Report: docs/pymoca-upstream.md#constraining-clause.

Array constructors: pymoca's CasADi generator keeps ``{a, b}`` as a Python list, which CasADi
accepts only when every element is a literal number and the list is flat. So ``{1, m*x[1]}``,
``{{cos(x[1]), 0}, {0, 1}}``, ``[a, b; c, d]``, ``{{1, 0}, {0, 1}}*x``, ``-{1, 2}`` and ``{m, 0}``
failed. An array with a symbolic element becomes a CasADi column vector (``{...}``) or matrix
(``{{...}, ...}``, rows by the first index) here, and a literal array that is an operand of an
arithmetic operator becomes a constant matrix; a literal array elsewhere (a parameter's value, a
function argument) stays what pymoca makes of it. ``identity(n)`` and ``diagonal(v)`` are made dense
matrices: CasADi's sparse ones made ``parameter Real K[2, 2] = -m*identity(2)`` fail ("Sparsities of
v and vdef must match").
Reports: docs/pymoca-upstream.md#array-constructors,
docs/pymoca-upstream.md#dense-identity.
"""
from __future__ import annotations

import contextlib
import itertools
import re

from cosim.compiler import pymoca_walker

_applied = False


# pymoca bug report: docs/pymoca-upstream.md#name-capture
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


# pymoca bug report: docs/pymoca-upstream.md#function-names
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


# pymoca bug report: docs/pymoca-upstream.md#fixed-given
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


# pymoca caches parse results on disk by text and pymoca version; the parser patch below changes
# the result, so cosim keeps its own cache (a new name whenever a parser patch changes).
PARSE_CACHE_DB = "cosim_model_txt_cache_2.db"


# pymoca bug report: docs/pymoca-upstream.md#short-connectors
def _keep_base_prefix(exit_class_spec_base):
    def patched_exit(self, ctx):
        exit_class_spec_base(self, ctx)
        type_prefix = ctx.base_prefix().type_prefix()
        self.class_node._cosim_base_prefixes = [child.getText() for child in type_prefix.getChildren()]

    return patched_exit


# pymoca bug report: docs/pymoca-upstream.md#constraining-clause
def _keep_constraining_clause(exit_replaceable):
    from pymoca import ast

    def patched_exit(self, ctx):
        exit_replaceable(self, ctx)
        clause = ctx.constraining_clause()
        if clause is None:
            return
        modification = clause.class_modification()
        arguments = list(self.ast[modification].arguments) if modification is not None else []
        element = self.ast[ctx]
        if isinstance(element, ast.ComponentClause):
            for symbol in element.symbol_list:
                own = list(symbol.class_modification.arguments) if symbol.class_modification else []
                symbol._cosim_constrainedby = clause.name().getText()
                symbol._cosim_declaration_arguments = own
                symbol.class_modification = ast.ClassModification(arguments=arguments + own)
        else:
            element._cosim_constrainedby = clause.name().getText()
            element._cosim_constrainedby_arguments = len(arguments)

    return patched_exit


def _builtin_connector(connector_class, builtin_types) -> bool:
    """True for the flat class of a connector that is a built-in type (``= input Real``)."""
    return connector_class is not None and len(connector_class.symbols) == 1 \
        and next(iter(connector_class.symbols)) in builtin_types


# pymoca bug report: docs/pymoca-upstream.md#short-connectors
def _scalar_connectors(add_connector_symbols, builtin_types):
    depth = 0

    def patched_add_connector_symbols(instance, flat_class, prefix):
        # pymoca recurses through nested connectors: snapshot and restore in the outermost call
        # only (a copy of all symbols per call made flattening quadratic in the model's size)
        nonlocal depth
        if depth:
            return add_connector_symbols(instance, flat_class, prefix)
        before = dict(flat_class.symbols)
        depth += 1
        try:
            add_connector_symbols(instance, flat_class, prefix)
        finally:
            depth -= 1
        for name, symbol in list(flat_class.symbols.items()):
            if name in before and symbol is not before[name] \
                    and _builtin_connector(getattr(symbol, "_connector_type", None), builtin_types):
                flat_class.symbols[name] = before[name]  # the variable itself, not a connector stub

    return patched_add_connector_symbols


def _literal_value(node, ast):
    """``node`` as an ``ast.Primary`` if it is a number (or a signed number), else None."""
    if isinstance(node, ast.Primary) and node.value is not None:
        return node
    operands = getattr(node, "operands", None)
    if isinstance(node, ast.Expression) and str(node.operator) in ("-", "+") and operands and len(operands) == 1:
        inner = _literal_value(operands[0], ast)
        if inner is not None and isinstance(inner.value, (int, float)) and not isinstance(inner.value, bool):
            return ast.Primary(value=-inner.value if str(node.operator) == "-" else inner.value)
    return None


def _value_argument(type_instance, builtin_types, depth=0):
    """The value modification (the argument, with its scope) of the built-in type behind a
    (derived) type instance that applies: the last one, as in pymoca's merging of modifications
    (the defaults of the declarations come first, the modifiers of enclosing instances after)."""
    from pymoca import ast
    from pymoca.tree.instance import InstanceClass, InstanceSymbol

    if not isinstance(type_instance, InstanceClass) or depth > 20:
        return None
    found = None
    for name, symbol in type_instance.symbols.items():
        if name in builtin_types and isinstance(symbol, InstanceSymbol):
            for arg in symbol.modification_environment.arguments:
                value = arg.value
                if isinstance(value, ast.ElementModification) and value.component.name == "value" \
                        and value.modifications:
                    found = arg
    for base in getattr(type_instance, "extends", []):
        found = _value_argument(base, builtin_types, depth + 1) or found
    return found


# pymoca bug report: docs/pymoca-upstream.md#derived-type-constants
# pymoca bug report: docs/pymoca-upstream.md#modified-constants
def _constant_values(get_constant_value, flattening, builtin_types):
    """pymoca's _get_constant_value with the value that applies (see the module docstring:
    constants of a derived type, modified constants)."""
    from pymoca import ast
    from pymoca.tree import LookupOptions, RecursionGuard
    from pymoca.tree.instance import InstanceClass, InstanceSymbol

    # id(argument) -> (argument, value): the values found during one flattening (scopes_kept),
    # else during the outermost call. A chain b.j.n -> b.n -> n is evaluated once per link (pymoca's
    # _resolve_name, as patched by _inherited_constants, asks for the value of what it found, and so
    # would every link again); an argument found while it is being evaluated is a cycle.
    evaluated: dict[int, tuple] = {}
    active = [0]

    def evaluate(arg):
        """The value of a value modification in its scope (the instance whose declaration or
        modifier it is), or None if it is not a constant expression pymoca can evaluate."""
        expression = arg.value.modifications[0]
        literal = _literal_value(expression, ast)
        if literal is not None:
            return literal
        scope = arg.scope
        if not isinstance(expression, (ast.ComponentRef, ast.Expression)) or not isinstance(scope, InstanceClass):
            return None
        if isinstance(expression, ast.ComponentRef) and expression.name == "time" and not expression.child:
            return None
        guard, opts = RecursionGuard(), LookupOptions()
        try:
            if isinstance(expression, ast.ComponentRef):
                found = flattening._resolve_name(expression, scope, scope, guard=guard, opts=opts,
                                                 name_flat_class=scope)
                value = flattening._get_constant_value(found) if isinstance(found, InstanceSymbol) else None
            else:
                result = flattening._resolve_expression(expression, scope, scope, guard=guard, opts=opts,
                                                        name_flat_class=scope)
                value = ast.Primary(value=result) if isinstance(result, (bool, int, float, str)) else None
        except Exception:  # not a constant expression pymoca evaluates: the value stays symbolic
            return None
        return value if isinstance(value, ast.Primary) and value.value is not None else None

    def value_of(arg):
        known = _kept_values[-1] if _kept_values else evaluated
        key = id(arg)
        if key in known:
            return known[key][1]
        known[key] = (arg, None)  # a cycle ends in None
        value = evaluate(arg)
        known[key] = (arg, value)
        return value

    def patched_get_constant_value(isym):
        if "constant" not in isym.prefixes:
            return None
        given = isym.value
        if given is not None and not (isinstance(given, ast.Primary) and given.value is None):
            return get_constant_value(isym)  # a value pymoca resolved already
        arg = _value_argument(isym.type, builtin_types)
        if arg is None:
            return get_constant_value(isym)
        active[0] += 1
        try:
            return value_of(arg)
        finally:
            active[0] -= 1
            if not active[0]:
                evaluated.clear()

    return patched_get_constant_value


_NOT_EXPRESSIONS = ("parent", "scope", "operator", "parent_instance")


def _substitute_refs(node, replace, depth=0):
    """Replace, in place, every ``ComponentRef`` of ``node`` for which ``replace`` returns a node."""
    from pymoca import ast

    if depth > 200 or not isinstance(node, ast.Node):
        return
    for key, value in list(vars(node).items()):
        if key in _NOT_EXPRESSIONS:
            continue
        if isinstance(value, list):
            for i, item in enumerate(value):
                new = replace(item) if isinstance(item, ast.ComponentRef) else None
                if new is not None:
                    value[i] = new
                elif isinstance(item, list):
                    for inner in item:
                        _substitute_refs(inner, replace, depth + 1)
                else:
                    _substitute_refs(item, replace, depth + 1)
        elif isinstance(value, ast.ComponentRef) and (new := replace(value)) is not None:
            setattr(node, key, new)
        else:
            _substitute_refs(value, replace, depth + 1)


def _for_indices(node, found, depth=0):
    from pymoca import ast

    if depth > 200 or not isinstance(node, ast.Node):
        return found
    if isinstance(node, ast.ForIndex):
        found.add(node.name)
    for key, value in vars(node).items():
        if key not in _NOT_EXPRESSIONS:
            for item in value if isinstance(value, list) else [value]:
                _for_indices(item, found, depth + 1)
    return found


# pymoca bug report: docs/pymoca-upstream.md#constants-in-equations
def _package_constants_in_equations(collect_and_resolve, flattening):
    from pymoca import ast
    from pymoca.tree import LookupOptions, RecursionGuard
    from pymoca.tree.instance import InstanceSymbol

    def constant_value(ref, instance, flat_class, indices):
        parts, node = [], ref
        while True:
            if any(i is not None for index in node.indices for i in index):
                return None  # an element of a constant array: left as it is
            parts.append(node.name)
            if not node.child:
                break
            node = node.child[0]
        if ref.name in flat_class.symbols or parts[0] in indices or parts == ["time"]:
            return None
        try:
            found = flattening._resolve_name(ast.ComponentRef.from_string(".".join(parts)), instance, flat_class,
                                             guard=RecursionGuard(), opts=LookupOptions(),
                                             name_flat_class=flat_class)
        except Exception:  # not a name of the scope: the error message names it later
            return None
        if not isinstance(found, InstanceSymbol) or "constant" not in found.prefixes:
            return None
        value = flattening._get_constant_value(found)
        return ast.Primary(value=value.value) if isinstance(value, ast.Primary) else None

    def patched_collect_and_resolve(instance, flat_class, prefix):
        counts = len(flat_class.equations), len(flat_class.initial_equations)
        collect_and_resolve(instance, flat_class, prefix)
        for equations, start in ((flat_class.equations, counts[0]), (flat_class.initial_equations, counts[1])):
            for equation in equations[start:]:
                if isinstance(equation, ast.ConnectClause):
                    continue
                indices = _for_indices(equation, set())
                _substitute_refs(equation, lambda ref, indices=indices: constant_value(ref, instance, flat_class,
                                                                                      indices))

    return patched_collect_and_resolve


# pymoca bug report: docs/pymoca-upstream.md#inherited-constants
def _inherited_constants(resolve_name, flattening):
    from pymoca import ast
    from pymoca.tree import LookupOptions, RecursionGuard
    from pymoca.tree.instance import InstanceClass, InstanceSymbol

    def value_from_full_package(name, scope):
        parts = name.to_tuple() if isinstance(name, ast.ComponentRef) else tuple(str(name).split("."))
        if len(parts) < 2 or not isinstance(scope, InstanceClass):
            return None
        package = flattening._find_name(scope, ast.ComponentRef.from_tuple(parts[:-1]), RecursionGuard(),
                                        LookupOptions())
        if not isinstance(package, ast.Class):
            return None
        full = flattening._instantiate_element(package, scope, ast.ClassModification(), guard=RecursionGuard(),
                                               opts=LookupOptions())
        symbol = flattening._find_local_or_inherited_symbol(full, parts[-1]) \
            if isinstance(full, InstanceClass) else None
        return flattening._get_constant_value(symbol) if isinstance(symbol, InstanceSymbol) else None

    def patched_resolve_name(name, scope, flat_class, **kwargs):
        result = resolve_name(name, scope, flat_class, **kwargs)
        if isinstance(result, InstanceSymbol) and "constant" in result.prefixes \
                and flattening._get_constant_value(result) is None:
            try:
                value = value_from_full_package(name, scope)
            except Exception:  # no better answer than pymoca's: keep it (an undeclared name later)
                value = None
            if value is not None:
                result.value = value
        return result

    return patched_resolve_name


def _full_scope_once(resolve_name, resolve_modifications, resolve_dimensions, flattening):
    """pymoca's _resolve_name instantiates its scope fully before the look-up, but does not keep
    an unnamed scope's full instance (its parent's cache is by name, which unnamed extends would
    share), so every name referenced in such a scope instantiated it again: the linear bicycle's
    modifications of its body extends (`extends PartialFrontBody(final S = 0)`, bound to lam, mu,
    ...) made 463 references, 15,000 class instantiations, 2 of its 2.5 s of flattening.

    The full instance of a partial instance (with the same empty modification and look-up
    options) is made once per flattening (:func:`scopes_kept`) and used again while the partial
    instance is unchanged: its signature (:func:`_scope_signature`: its state, modification and
    the identity of every class, symbol and extends it holds) is part of the key, so a partial
    instance that pymoca completes or redeclares into between two symbols (a redeclared package,
    tests/test_pymoca_patches.py) is instantiated afresh. Outside :func:`scopes_kept` the full
    instance lives for one _resolve_modifications or _resolve_dimensions (the modifications or the
    dimensions of one symbol), as before. Keeping it for the whole flattening took a third off
    flattening the nonlinear bicycles (WhippleRider 1.05 s -> 0.65 s) and changed no generated byte
    of any exported model.

    The dimensions of a symbol (``Real Wp[3, n]`` in an inherited class) use the same full
    instances: they made 35 of WhippleRider's 42 full instances of unnamed scopes, a quarter of its
    flattening (0.66 s -> 0.49 s; the same flat model of every model of the library). Look-ups
    elsewhere (equations, with a RecursionGuard of their own) make their full instance anew, as
    pymoca does: a full instance kept for them gave the package of the replaced class
    (``redeclare package Data = B``: ``Data.z`` of A) once a look-up had completed ``Data`` in it.
    Every full instance gets the scope's own components (:func:`_graft_components`)."""
    from pymoca import ast
    from pymoca.tree.instance import InstanceClass, InstantiationState

    windows: list[dict] = []  # one per active _resolve_modifications/_dimensions: key -> (scope, full)

    def windowed(resolve):
        def patched(*args, **kwargs):
            windows.append(_kept_scopes[-1] if _kept_scopes else {})
            try:
                return resolve(*args, **kwargs)
            finally:
                windows.pop()

        return patched

    patched_resolve_modifications = windowed(resolve_modifications)
    patched_resolve_dimensions = windowed(resolve_dimensions)

    def full_instance(scope, guard, opts):
        return flattening._instantiate_class(scope, ast.ClassModification(), scope.parent_instance,
                                             guard=guard, opts=opts, update_parent_instance=False)

    def patched_resolve_name(name, scope, flat_class, **kwargs):
        if isinstance(scope, InstanceClass) and not scope.name \
                and scope.instantiation_state < InstantiationState.FULL and "guard" in kwargs and "opts" in kwargs:
            guard, opts = kwargs["guard"], kwargs["opts"]
            window = windows[-1] if windows else None
            if window is not None:
                # the window holds ``scope`` itself, so its id is not reused while the entry lives
                key = (id(scope), repr(opts), _scope_signature(scope))
                kept = window.get(key)
                if kept is None:
                    kept = window[key] = (scope, full_instance(scope, guard, opts))
                full = kept[1]
            else:
                full = full_instance(scope, guard, opts)  # what pymoca's _resolve_name would make
            _graft_components(full, scope)
            scope = full
        return resolve_name(name, scope, flat_class, **kwargs)

    return patched_resolve_name, patched_resolve_modifications, patched_resolve_dimensions


# The full instances of partial scopes (see _full_scope_once) and the values of modified
# constants (see _constant_values) kept by the flattening in progress.
_kept_scopes: list[dict] = []
_kept_values: list[dict] = []


@contextlib.contextmanager
def scopes_kept():
    """Keep the full instances of unnamed partial scopes and the values of modified constants
    for the block (one flattening)."""
    _kept_scopes.append({})
    _kept_values.append({})
    try:
        yield
    finally:
        _kept_scopes.pop()
        _kept_values.pop()


def _graft_components(full, partial, depth=0) -> None:
    """Put the components of the extends instance ``partial`` (instantiated in full, with the
    modifiers of the extends clause and of the enclosing instances) into its full instance
    ``full`` in place of the ones made anew from the class (with the declarations' defaults
    only), in its bases too (matched by position: both come from the same extends clauses)."""
    from pymoca.tree.instance import InstanceClass, InstantiationState

    if depth > 50 or not isinstance(full, InstanceClass) or not isinstance(partial, InstanceClass):
        return
    for name, symbol in partial.symbols.items():
        if name in full.symbols and symbol.instantiation_state >= InstantiationState.FULL:
            full.symbols[name] = symbol
    if len(full.extends) == len(partial.extends):
        for full_base, partial_base in zip(full.extends, partial.extends):
            _graft_components(full_base, partial_base, depth + 1)


def _scope_signature(scope) -> tuple:
    """What pymoca may change in a partial instance between two symbols: its instantiation
    state, its modification and the objects it holds (classes, symbols, extends), by identity."""
    return (scope.instantiation_state, id(scope.modification_environment),
            len(getattr(scope.modification_environment, "arguments", ()) or ()),
            tuple((id(c), c.instantiation_state) for c in scope.classes.values()),
            tuple(map(id, scope.symbols.values())),
            tuple(map(id, scope.extends)))


class RecordBindingError(Exception):
    """A record binding that cosim's compiler cannot apply (flatten.py names its source line)."""


def _describe(expression) -> str:
    """A short Modelica-like rendering of a binding for a message."""
    from pymoca import ast

    if isinstance(expression, ast.ComponentRef):
        return str(expression)
    if isinstance(expression, ast.Expression) and isinstance(expression.operator, ast.ComponentRef):
        return f"{expression.operator}(...)"
    if isinstance(expression, ast.Array):
        return "{...}"
    return "an expression"


def _is_scalar(symbol) -> bool:
    return all(d is None or getattr(d, "value", 0) is None for dims in symbol.dimensions or [] for d in dims)


# pymoca bug report: docs/pymoca-upstream.md#record-bindings
def _record_bindings(flatten_instance, flattening):
    from pymoca import ast
    from pymoca.tree import LookupOptions, RecursionGuard
    from pymoca.tree.instance import InstanceClass

    def binding_of(symbol):
        """The last (outermost) value modification of a record component, with its scope."""
        found = None
        for arg in symbol.modification_environment.arguments:
            value = arg.value
            if isinstance(value, ast.ElementModification) and value.component.name == "value" \
                    and not value.component.child and value.modifications:
                found = arg
        return found

    def collect(instance, flat_class, prefix):
        for name, symbol in instance.symbols.items():
            if not (isinstance(symbol.type, InstanceClass) and symbol.type.type == "record"):
                continue
            arg = binding_of(symbol)
            if arg is None:
                continue
            target = f"{prefix}.{name}" if prefix else name
            expression = arg.value.modifications[-1]
            scope = arg.scope.full_name if getattr(arg, "scope", None) is not None else instance.full_name
            if not isinstance(expression, ast.ComponentRef) or not _is_scalar(symbol):
                what = "arrays of records" if not _is_scalar(symbol) else "a binding to an expression"
                raise RecordBindingError(
                    f"Unsupported record binding {name} = {_describe(expression)} in scope {scope}: {what}")
            source = flattening._resolve_name(expression, arg.scope or instance, flat_class, guard=RecursionGuard(),
                                              opts=LookupOptions(), name_flat_class=flat_class)
            flat_class._cosim_record_bindings.append((target, source.name, name, str(expression), scope))

    def apply_bindings(flat_class):
        for target, source, name, expression, scope in flat_class._cosim_record_bindings:
            elements = [n for n in flat_class.symbols if n.startswith(target + ".")]
            missing = [n for n in elements if source + n[len(target):] not in flat_class.symbols]
            if not elements or missing:
                raise RecordBindingError(
                    f"Unsupported record binding {name} = {expression} in scope {scope}: "
                    f"'{expression}' has no element '{missing[0][len(target) + 1:]}'" if missing else
                    f"Unsupported record binding {name} = {expression} in scope {scope}: no record elements")
            for element in elements:
                flat_class.symbols[element].value = _mark_flat(ast.ComponentRef(name=source + element[len(target):]))

    def patched_flatten_instance(instance, flat_class, **kwargs):
        depth = getattr(flat_class, "_cosim_depth", 0)
        if depth == 0:
            flat_class._cosim_record_bindings = []
        flat_class._cosim_depth = depth + 1
        try:
            flatten_instance(instance, flat_class, **kwargs)
            collect(instance, flat_class, kwargs.get("prefix", ""))
        finally:
            flat_class._cosim_depth = depth
        if depth == 0:
            # the innermost bindings were collected first; outer ones must win where they overlap
            flat_class._cosim_record_bindings.sort(key=lambda b: b[0].count("."))
            apply_bindings(flat_class)

    return patched_flatten_instance


class RedeclareError(Exception):
    """A redeclaration that cosim's compiler cannot apply (flatten.py names its source line)."""


# pymoca bug report: docs/pymoca-upstream.md#component-redeclare
# pymoca bug report: docs/pymoca-upstream.md#two-redeclares
# pymoca bug report: docs/pymoca-upstream.md#constraining-clause
def _replacing_redeclares(apply_redeclares, instantiate_symbol, builtin_types):
    from pymoca import ast
    from pymoca.tree.instance import InstanceClass, InstanceSymbol

    def redeclared_here(element):
        return any(arg.redeclare and (isinstance(arg.value, ast.ShortClassDefinition) and arg.value.name == element.name
                                      or isinstance(arg.value, ast.ComponentClause)
                                      and arg.value.symbol_list[0].name == element.name)
                   for arg in element.modification_environment.arguments)

    def check_class(element, redeclared):
        """Refuse what pymoca gets wrong for a replaceable class with a constraining clause."""
        declared = element.ast_ref
        constraint = getattr(declared, "_cosim_constrainedby", None)
        if constraint is None:
            return
        scope = declared.parent.full_name if getattr(declared, "parent", None) is not None else element.name
        if getattr(declared, "_cosim_constrainedby_arguments", 0):
            raise RedeclareError(
                f"Unsupported redeclare of {declared.name} in scope {scope}: modifiers of 'constrainedby "
                f"{constraint}(...)' are ignored by pymoca: give them in the declaration or the redeclaration")
        own = [arg for e in declared.extends for arg in getattr(e.class_modification, "arguments", [])]
        if own and redeclared:
            raise RedeclareError(
                f"Unsupported redeclare of {declared.name} in scope {scope}: with 'constrainedby {constraint}' "
                f"the modifiers of the replaced class are dropped by a redeclaration (MLS 7.3.2), which "
                f"pymoca does not do: give them in the redeclaration or as modifiers of the components")

    def patched_apply_redeclares(element, modification_environment, parent_instance, **kwargs):
        symbol = isinstance(element, InstanceSymbol)
        if isinstance(element, InstanceClass):
            check_class(element, redeclared_here(element))
        own = getattr(getattr(element, "ast_ref", None), "_cosim_declaration_arguments", None)
        if symbol and own and redeclared_here(element):
            # MLS 7.3.2: the modifiers of a declaration with a constraining clause are not applied to
            # the class that replaces it (those of the constraining clause are)
            dropped = {id(arg) for arg in own} | {id(arg.value) for arg in own}
            modification_environment.arguments = [
                arg for arg in modification_environment.arguments
                if id(arg) not in dropped and id(arg.value) not in dropped]
            element.modification_environment = modification_environment
        builtin = symbol and not isinstance(element.type, InstanceClass) and element.type.name in builtin_types
        redeclared = apply_redeclares(element, modification_environment, parent_instance, **kwargs)
        if redeclared and symbol and not builtin:
            element._cosim_redeclared = True  # pymoca made the new class the first base of the old type
        return redeclared

    def patched_instantiate_symbol(symbol, parent_instance, **kwargs):
        # pymoca instantiates the replaced class of a redeclared component in the component's parent
        # and registers it there under the class name (parent.classes['Torus']); the next component
        # of that class in the same parent then found this instance, already altered for the first
        # redeclaration (another base inserted, its own contents dropped below), and got the classes
        # of both redeclarations as bases. The instance belongs to this component: unregister it
        # once the component is instantiated.
        classes = dict(parent_instance.classes)
        instantiate_symbol(symbol, parent_instance, **kwargs)
        if getattr(symbol, "_cosim_redeclared", False):
            parent_instance.classes.clear()
            parent_instance.classes.update(classes)
        if getattr(symbol, "_cosim_redeclared", False) and isinstance(symbol.type, InstanceClass) \
                and symbol.type.extends:
            old = symbol.type  # the replaced class: drop its own contents and other bases
            old.extends = old.extends[:1]
            if isinstance(old.extends[0], InstanceClass):
                # the instance of the new class belongs to the component (it was made in the parent):
                # names in it are the component's (w.hub.n, not hub.n)
                old.extends[0].parent_instance = old
            old.symbols.clear()
            for part in ("equations", "initial_equations", "statements", "initial_statements"):
                setattr(old, part, [])
            symbol._cosim_redeclared = False

    return patched_apply_redeclares, patched_instantiate_symbol


def _symbolic(values) -> bool:
    import casadi as ca

    return any(_symbolic(v) if isinstance(v, list) else isinstance(v, (ca.MX, ca.SX)) for v in values)


def _array(values):
    """A Modelica array constructor's elements as one CasADi column vector or matrix."""
    import casadi as ca

    elements = [_array(v) if isinstance(v, list) else v for v in values]
    symbolic = _symbolic(values)
    convert = ca.MX if symbolic else ca.DM
    elements = [convert(e) for e in elements]
    if not any(isinstance(v, list) for v in values) and all(e.numel() == 1 for e in elements):
        return ca.vertcat(*elements)
    columns = [ca.vec(e) for e in elements]
    if len({c.numel() for c in columns}) != 1:
        raise ValueError(f"array constructor with rows of different sizes: {[c.numel() for c in columns]}")
    return ca.horzcat(*columns).T  # row i is element i, as the first index of a Modelica matrix


_ARRAY_OPERATORS = {"-", "+", "*", "/", "^", "mtimes", "transpose", "sum", ".*", "./", ".^", ".+", ".-"}


# pymoca bug report: docs/pymoca-upstream.md#array-constructors
# pymoca bug report: docs/pymoca-upstream.md#dense-identity
def _casadi_arrays(exit_array, exit_expression):
    import casadi as ca
    from pymoca import ast

    def patched_exit_array(self, tree):
        for value in tree.values:  # a bare name ({m, 0}) is looked up on demand, as operands are
            if isinstance(value, ast.ComponentRef) and value not in self.src:
                self.get_mx(value)
        exit_array(self, tree)
        if _symbolic(self.src[tree]):
            self.src[tree] = _array(self.src[tree])

    def patched_exit_expression(self, tree):
        operator = tree.operator.name if isinstance(tree.operator, ast.ComponentRef) else tree.operator
        if operator in _ARRAY_OPERATORS:
            for operand in tree.operands:
                if isinstance(operand, ast.Array) and isinstance(self.src.get(operand), list):
                    self.src[operand] = _array(self.src[operand])
        exit_expression(self, tree)
        if operator in ("identity", "diagonal"):
            # CasADi makes these sparse; a parameter bound to -m*identity(2) must be a dense matrix
            self.src[tree] = ca.densify(self.src[tree])

    return patched_exit_array, patched_exit_expression


def apply() -> None:
    """Install the patches (idempotent)."""
    global _applied
    if _applied:
        return
    from pymoca import parser
    from pymoca.backends.casadi.generator import Generator
    from pymoca.tree import _flattening as flattening
    from pymoca.tree import _instantiation as instantiation
    from pymoca.tree.instance import InstanceSymbol, InstanceTree

    from cosim.compiler import pymoca_flattening  # deferred: imports pymoca

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
    parser.ASTListener.exitClass_spec_base = _keep_base_prefix(parser.ASTListener.exitClass_spec_base)
    parser.ASTListener.exitReplaceable_element = _keep_constraining_clause(parser.ASTListener.exitReplaceable_element)
    parser.ASTListener.exitElement_replaceable = _keep_constraining_clause(parser.ASTListener.exitElement_replaceable)
    flattening._add_connector_symbols = _scalar_connectors(flattening._add_connector_symbols,
                                                           set(InstanceTree.BUILTIN_TYPES))
    flattening._get_constant_value = _constant_values(flattening._get_constant_value, flattening,
                                                      set(InstanceTree.BUILTIN_TYPES))
    flattening._collect_and_resolve_equations = _package_constants_in_equations(
        flattening._collect_and_resolve_equations, flattening)
    resolve_name, flattening._resolve_modifications, flattening._resolve_dimensions = _full_scope_once(
        flattening._resolve_name, flattening._resolve_modifications, flattening._resolve_dimensions, flattening)
    flattening._resolve_name = _inherited_constants(resolve_name, flattening)
    flattening._flatten_instance = pymoca_flattening.flatten_instance  # vendored, see its module
    flattening._flatten_instance = _record_bindings(flattening._flatten_instance, flattening)
    instantiation._apply_redeclares, instantiation._instantiate_symbol = _replacing_redeclares(
        instantiation._apply_redeclares, instantiation._instantiate_symbol, set(InstanceTree.BUILTIN_TYPES))
    Generator.exitArray, Generator.exitExpression = _casadi_arrays(Generator.exitArray, Generator.exitExpression)
    pymoca_walker.install()
    _applied = True
