"""Flatten one Modelica model with pymoca and collect what the FMU needs to know of each variable.

pymoca's flattening drops two things of components whose type is a derived type such as
``Bicycle.Units.Angle``: the description string and the ``input``/``output`` prefix of a
top-level component. Both are restored here from the declarations in the parsed library.

pymoca reports Modelica errors of the model (an undeclared name, an unknown class, a function
that is not defined) as Python exceptions of its own or of CasADi; they are turned into one
Modelica-level message here: ``file:line: class: what is wrong`` (pymoca keeps no source
positions, so the line is that of the first use of the name inside the class).
"""
from __future__ import annotations

import contextlib
import gc
import re
from dataclasses import dataclass, field

from cosim.errors import ModelicaError
from cosim.compiler.library import Library
from cosim.compiler import pymoca_patches

BUILTIN = ("Real", "Integer", "Boolean", "String")


@dataclass
class Declaration:
    """What a flat variable carries from its declaration."""

    name: str
    type: str  # Real, Integer, Boolean
    prefixes: list[str]
    description: str = ""
    unit: str | None = None
    display_unit: str | None = None
    quantity: str | None = None
    min: float | None = None
    max: float | None = None
    fixed: bool | str | None = None  # None: not given; "expression": given, but not a literal
    owner: str | None = None  # the class that declares the variable
    final: bool = False  # declared or modified ``final``: its value cannot be changed
    # A top-level variable's declaration equation that is a plain reference (``delta = steer.angle``):
    # the referenced name; None otherwise (see ode.py, states named by their top-level alias).
    binding: str | None = None


@dataclass
class FlatModel:
    """A flattened model: pymoca's CasADi model plus declarations of every flat variable."""

    name: str
    casadi: object  # pymoca.backends.casadi.model.Model
    declarations: dict[str, Declaration] = field(default_factory=dict)
    library: Library | None = None

    def locate(self, flat_name: str, attribute: str | None = None) -> str:
        """``file:line`` where the variable ``flat_name`` is declared, or where ``attribute``
        (e.g. ``fixed``) is given for it: in its declaring class, else in the model."""
        if self.library is None:
            return self.name
        last = re.escape(flat_name.rsplit(".", 1)[-1].split("[")[0])
        first = re.escape(flat_name.split(".")[0].split("[")[0])
        decl = self.declarations.get(flat_name)
        owner = decl.owner if decl is not None and decl.owner else self.name
        candidates = []
        if attribute:
            candidates += [(owner, rf"\b{last}\b.*\b{attribute}\s*="), (self.name, rf"\b{first}\b.*\b{attribute}\s*=")]
        candidates += [(owner, rf"\b{last}\b\s*[\[(=;\"]"), (owner, rf"\b{last}\b")]
        return self.library.where(candidates)[0]


def _literal(node):
    value = getattr(node, "value", None)
    return value if isinstance(value, (int, float, str, bool)) else None


def _binding_reference(symbol) -> str | None:
    """The name in a declaration equation ``v = a.b`` of ``symbol`` as written in its class, if
    it is a plain component reference (no sign, factor or subscript); None otherwise."""
    from pymoca import ast

    modification = getattr(symbol, "class_modification", None)
    for argument in getattr(modification, "arguments", None) or []:
        element = argument.value
        if not isinstance(element, ast.ElementModification) or str(element.component) != "value":
            continue
        values = element.modifications
        reference = values[-1] if values else None
        if not isinstance(reference, ast.ComponentRef):
            return None
        parts, node = [], reference
        while True:
            if any(index is not None for indices in node.indices for index in indices):
                return None
            parts.append(node.name)
            if not node.child:
                break
            node = node.child[0]
        return ".".join(parts)
    return None


class _Declarations:
    """Looks up the declaring component of a flat name through the class hierarchy."""

    def __init__(self, library: Library):
        self.library = library
        # Look-ups are memoized (one flatten asks once per flat variable: scanning the members of
        # the model for each was quadratic in its size); the tree does not change meanwhile.
        self._classes: dict[str, object] = {}
        self._members: dict[str, dict] = {}

    def _class(self, name: str):
        if name in self._classes:
            return self._classes[name]
        node = self.library.tree
        for part in name.split("."):
            node = node.classes.get(part)
            if node is None:
                break
        self._classes[name] = node
        return node

    def members(self, class_name: str) -> dict:
        """``name -> (symbol, declaring class)`` of the components of a class, own and inherited
        (the first of :meth:`symbols` for a name that occurs twice)."""
        found = self._members.get(class_name)
        if found is None:
            found = {}
            for name, symbol, owner in self.symbols(class_name):
                found.setdefault(name, (symbol, owner))
            self._members[class_name] = found
        return found

    def resolve(self, type_name: str, scope: str) -> str | None:
        parts = scope.split(".")
        for n in range(len(parts), -1, -1):
            candidate = ".".join(parts[:n] + [type_name]) if n else type_name
            if self._class(candidate) is not None:
                return candidate
        return None

    def symbols(self, class_name: str):
        """Own and inherited components of a class, as (name, symbol, declaring class)."""
        cls = self._class(class_name)
        if cls is None:
            return
        for base in cls.extends:
            base_name = self.resolve(str(base.component), class_name.rsplit(".", 1)[0])
            if base_name:
                yield from self.symbols(base_name)
        for name, symbol in cls.symbols.items():
            yield name, symbol, class_name

    def find(self, class_name: str, flat_name: str):
        """The declaring symbol of ``flat_name`` inside ``class_name`` and the class that
        declares it (``(None, None)`` if not found)."""
        head, _, rest = flat_name.partition(".")
        member = self.members(class_name).get(head)
        if member is None:
            return None, None
        symbol, owner = member
        if not rest:
            return symbol, owner
        type_name = self.resolve(str(symbol.type), owner)
        return self.find(type_name, rest) if type_name else (None, None)

    def composition(self, class_name: str) -> list[str]:
        """``class_name``, its base classes and the classes of its components, recursively."""
        found, stack = [], [class_name]
        while stack:
            name = stack.pop()
            cls = self._class(name)
            if cls is None or name in found:
                continue
            found.append(name)
            scope = name.rsplit(".", 1)[0] if "." in name else ""
            for base in cls.extends:
                resolved = self.resolve(str(base.component), scope)
                if resolved:
                    stack.append(resolved)
            for symbol in cls.symbols.values():
                if str(symbol.type) not in BUILTIN:
                    resolved = self.resolve(str(symbol.type), name)
                    if resolved:
                        stack.append(resolved)
        return found

    def declares(self, class_name: str, name: str) -> bool:
        """True if ``class_name`` (or a base class) declares a component or class ``name``."""
        cls = self._class(class_name)
        if cls is not None and name in cls.classes:
            return True
        return name in self.members(class_name)

    def base_prefixes(self, symbol, owner: str) -> list[str]:
        """The prefixes (``input``, ``output``, ...) that the short class definitions behind a
        component's type add, e.g. ``input`` for ``connector RealInput = input Real``."""
        found, name, seen = [], str(symbol.type), 0
        while name not in BUILTIN and seen < 20:
            resolved = self.resolve(name, owner)
            cls = self._class(resolved) if resolved else None
            if cls is None or not getattr(cls, "is_short_class_definition", False) or not cls.extends:
                break
            found += [p for p in getattr(cls, "_cosim_base_prefixes", []) if p not in found]
            name, owner = str(cls.extends[0].component), resolved
            seen += 1
        return found

    def base_type(self, symbol, owner: str) -> str:
        """Real, Integer or Boolean behind a (possibly derived) type."""
        name = str(symbol.type)
        seen = 0
        while name not in BUILTIN and seen < 20:
            resolved = self.resolve(name, owner)
            cls = self._class(resolved) if resolved else None
            if cls is None or not cls.extends:
                break
            name, owner = str(cls.extends[0].component), resolved
            seen += 1
        return name if name in BUILTIN else "Real"


# pymoca's messages for Modelica errors found while flattening: (pattern, what to say).
_FLATTEN_ERRORS = [
    (r"Type (?P<name>\S+) of symbol (?P<symbol>\S+) not found in (?P<scope>\S+)",
     "unknown class '{name}' (the type of component '{symbol}')"),
    (r"Unable to resolve (?P<name>\S+) in scope (?P<scope>\S+)", "undeclared name '{name}'"),
    (r"Extends name (?P<name>\S+) not found in scope (?P<scope>\S+)", "unknown class '{name}' in 'extends'"),
    (r'Trying to modify symbol "(?P<name>[^"]+)", which does not exist in class (?P<scope>\S+)',
     "modification of '{name}', which {scope} does not declare"),
    # raised by cosim's pymoca_patches, which applies a record binding b = rb element-wise
    (r"Unsupported record binding (?P<name>\S+) = (?P<expr>.+?) in scope (?P<scope>\S+): (?P<what>.*)",
     ("record binding '{name} = {expr}' is not supported ({what}): bind the record to another record "
      "component ({name} = r) or give its elements as modifiers ({name}(m = ..., I = ...))")),
    (r"Unsupported redeclare of (?P<name>\S+) in scope (?P<scope>\S+): (?P<what>.*)",
     "replaceable '{name}': {what}"),
]

# Operators pymoca's CasADi generator handles itself; any other call must be a Modelica function
# of the model or a CasADi elementary function (sin, sqrt, ...).
_GENERATOR_OPERATORS = {"der", "-", "+", "*", "/", "^", "not", "and", "or", "<", ">", "<=", ">=", "==", "!=",
                        "<>", "min", "max", "abs", "mtimes", "transpose", "sum", "linspace", "fill", "zeros",
                        "ones", "identity", "diagonal", "cat", "delay", "_pymoca_interp1d", "_pymoca_interp2d"}


# Modelica built-ins for events, discrete time and initialization, which cosim's continuous-time
# compiler does not support (a call of one would otherwise read as an undefined function).
UNSUPPORTED_BUILTINS = {"pre", "edge", "change", "sample", "initial", "terminal", "reinit", "assert", "terminate",
                        "delay", "spatialDistribution", "cardinality", "ndims", "size", "String", "Integer",
                        "div", "mod", "rem", "ceil", "floor", "integer", "semiLinear", "inStream", "actualStream",
                        "getInstanceName", "scalar", "vector", "matrix", "product", "outerProduct", "symmetric",
                        "cross", "skew", "array"}
# Built-ins that only guide a tool's event handling or homotopy: their value is an argument.
PASS_THROUGH = {"noEvent": 0, "smooth": 1, "homotopy": 0}


def _builtin(operator: str) -> bool:
    import casadi as ca

    return operator in _GENERATOR_OPERATORS or hasattr(ca.MX, operator)


def _scope_classes(library: Library, scope: str, model_name: str) -> list[str]:
    """Class names to search for the source of an error reported in ``scope``: pymoca names
    either a class or an instance path (``Model.component``); the model comes last."""
    lookup = _Declarations(library)
    found = []
    if lookup._class(scope) is not None:
        found.append(scope)
    elif scope.startswith(model_name + "."):
        cls = model_name
        for part in scope[len(model_name) + 1:].split("."):
            symbol, owner = lookup.find(cls, part)
            resolved = lookup.resolve(str(symbol.type), owner) if symbol is not None else None
            if resolved is None:
                break
            cls = resolved
        found.append(cls)
    return found + [model_name]


def _flatten_error(library: Library, model_name: str, exc: Exception) -> ModelicaError:
    """A Modelica-level message for an exception of pymoca's flattening."""
    try:
        return _explain_flatten_error(library, model_name, exc)
    except Exception:  # the explanation must not hide the error it explains
        return ModelicaError(f"{library.file_of(model_name)}: cannot flatten {model_name}: {_clean(str(exc), exc)}")


def _explain_flatten_error(library: Library, model_name: str, exc: Exception) -> ModelicaError:
    text = str(exc).strip()
    for pattern, what in _FLATTEN_ERRORS:
        match = re.search(pattern, text)
        if not match:
            continue
        name, scope = match.group("name"), match.group("scope")
        broken = library.broken_error(name, scope, user=model_name)
        if broken is not None:
            return broken
        classes = _scope_classes(library, scope, model_name)
        if what.startswith("modification"):  # written where the component is declared: search the model
            classes = [model_name] + _Declarations(library).composition(model_name)
        where, inside = library.where([(c, rf"\b{re.escape(name)}\b") for c in classes])
        suffix = f" (in {model_name})" if inside != model_name else ""
        return ModelicaError(f"{where}: {inside}: {what.format(**match.groupdict())}{suffix}")
    return ModelicaError(f"{library.file_of(model_name)}: cannot flatten {model_name}: {_clean(text, exc)}")


class _Uses:
    """Names a part of the syntax tree refers to: component references (dotted, without
    indices), called functions and for-loop indices."""

    def __init__(self, node):
        self.references: list[str] = []
        self.calls: list[str] = []
        self.indices: set[str] = set()
        self._visit(node, 0)

    def _visit(self, node, depth):
        from pymoca import ast

        if depth > 200:
            return
        if isinstance(node, (list, tuple)):
            for item in node:
                self._visit(item, depth + 1)
            return
        if isinstance(node, dict):
            for item in node.values():
                self._visit(item, depth + 1)
            return
        if not isinstance(node, ast.Node) or isinstance(node, (ast.Class, ast.Symbol)):
            return
        if isinstance(node, ast.ComponentRef):
            self.references.append(str(node))
            self._visit(node.indices, depth + 1)
            for child in node.child:
                self._visit(child.indices, depth + 1)
            return
        if isinstance(node, ast.ForIndex):
            self.indices.add(node.name)
        if isinstance(node, ast.Expression):
            operator = node.operator
            self.calls.append(str(operator) if isinstance(operator, ast.ComponentRef) else operator)
            self._visit(node.operands, depth + 1)
            return
        for key, value in node.__dict__.items():
            if key not in ("parent", "parent_instance", "scope"):
                self._visit(value, depth + 1)


def _class_using(library: Library, model_name: str, name: str, call: bool) -> str:
    """The class of the model (itself, a base class or the class of a component) whose equations
    use ``name`` (as a variable, or as a function when ``call``) without declaring it."""
    lookup = _Declarations(library)
    head = name.split(".")[0]
    for class_name in lookup.composition(model_name):
        cls = lookup._class(class_name)
        uses = _Uses([cls.equations, cls.initial_equations, cls.statements, cls.initial_statements])
        used = name in uses.calls if call else any(r == name or r.split(".")[0] == head for r in uses.references)
        if used and not lookup.declares(class_name, head) and head not in uses.indices:
            return class_name
    return model_name


def _undefined_names(flat_tree, model_name: str) -> tuple[list[str], list[str]]:
    """Undeclared variables and undefined functions the flat equations of ``model_name`` use."""
    flat_class = flat_tree.classes[model_name]
    uses = _Uses([flat_class.equations, flat_class.initial_equations, flat_class.statements,
                  flat_class.initial_statements])
    known = set(flat_class.symbols) | {"time"}
    undeclared = [r for r in dict.fromkeys(uses.references)
                  if r not in known and r not in uses.indices and r.split("[")[0] not in known]
    undefined = [c for c in dict.fromkeys(uses.calls)
                 if c is not None and c not in flat_tree.classes and not _builtin(c)]
    return undeclared, undefined


def _translate_error(library: Library, model_name: str, flat_tree, exc: Exception) -> ModelicaError:
    """A Modelica-level message for an exception of pymoca's CasADi generator."""
    try:
        return _explain_translate_error(library, model_name, flat_tree, exc)
    except Exception:  # the explanation must not hide the error it explains
        return ModelicaError(f"{library.file_of(model_name)}: cannot translate {model_name}: {_clean(str(exc), exc)}")


def _explain_translate_error(library: Library, model_name: str, flat_tree, exc: Exception) -> ModelicaError:
    undeclared, undefined = _undefined_names(flat_tree, model_name)
    text = str(exc).strip()
    if isinstance(exc, KeyError) and exc.args and isinstance(exc.args[0], str) and not undeclared:
        undeclared.append(exc.args[0])
    unknown = re.match(r"Unknown function (\S+)", text)
    if unknown and not any(u == unknown.group(1) or u.startswith(unknown.group(1) + ".") for u in undefined):
        undefined.insert(0, unknown.group(1))
    builtins = [c for c in undefined if c in UNSUPPORTED_BUILTINS]
    if builtins:
        name = builtins[0]
        owner = _class_using(library, model_name, name, True)
        call = rf"\b{re.escape(name)}\s*\("
        where, owner = library.where([(owner, call), (model_name, call)])
        suffix = f" (in {model_name})" if owner != model_name else ""
        return ModelicaError(f"{where}: {owner}: the built-in '{name}()' is not supported by cosim's compiler "
                             f"(continuous-time models without events or array reductions){suffix}")
    lookup = _Declarations(library)
    for name in undeclared:
        head = name.split(".")[0]
        for class_name in lookup.composition(model_name):
            enumeration = lookup._class(class_name).classes.get(head) if lookup._class(class_name) else None
            if enumeration is not None and getattr(enumeration, "enumeration", False):
                where, owner = library.where([(class_name, rf"\b{re.escape(head)}\b")])
                return ModelicaError(f"{where}: {class_name}: enumeration types ('{head}') are not supported by "
                                     "pymoca's CasADi back end: use Integer constants")
    for names, call in ((undefined, True), (undeclared, False)):
        if not names:
            continue
        name = names[0]
        broken = library.broken_error(name, model_name, user=model_name)
        if broken is not None:
            return broken
        owner = _class_using(library, model_name, name, call)
        pattern = rf"\b{re.escape(name)}\s*\(" if call else rf"\b{re.escape(name)}\b"
        where, owner = library.where([(owner, pattern), (model_name, pattern)])
        suffix = f" (in {model_name})" if owner != model_name else ""
        others = f"; also {', '.join(repr(n) for n in names[1:])}" if len(names) > 1 else ""
        if call:
            what = (f"call of undefined function '{name}': no function of that name is declared in the "
                    "model or the library, and it is not a built-in function")
        else:
            what = f"undeclared variable '{name}'"
        return ModelicaError(f"{where}: {owner}: {what}{others}{suffix}")
    return ModelicaError(f"{library.file_of(model_name)}: cannot translate {model_name}: {_clean(text, exc)}")


def _clean(text: str, exc: Exception) -> str:
    """The informative part of a pymoca or CasADi message (no C++ source positions)."""
    mismatch = re.search(r"Dimension mismatch for \((.*?)\), x is (\d+x\d+), while y is (\d+x\d+)", text)
    if mismatch:
        return (f"array sizes do not match in an equation or expression: {mismatch.group(2)} and "
                f"{mismatch.group(3)} (operation {mismatch.group(1)})")
    if re.search(r"Assertion \"n(row|col)>=0\" failed", text):
        return "an array has a negative size (check the dimensions and the parameters they use)"
    text = re.sub(r"(Error in [^\n]*? at )?\.\.\./casadi/\S+:\d+:\s*", "", text)
    text = re.sub(r"Assertion \"(.*?)\" failed:\s*", r"CasADi assertion \1 failed: ", text)
    text = " ".join(text.split())
    return text[:500] or type(exc).__name__


def _pass_through(node):
    """``node`` with ``noEvent(e)``, ``smooth(p, e)`` and ``homotopy(actual, simplified)``
    replaced by ``e`` (``actual``): the runtime has no events to suppress and solves no homotopy."""
    from pymoca import ast

    if isinstance(node, list):
        return [_pass_through(item) for item in node]
    operator = str(node.operator) if isinstance(node, ast.Expression) else None
    if operator in PASS_THROUGH and len(node.operands) > PASS_THROUGH[operator]:
        return _pass_through(node.operands[PASS_THROUGH[operator]])
    if isinstance(node, ast.Node) and not isinstance(node, (ast.Class, ast.Symbol)):
        for key, value in list(node.__dict__.items()):
            if key not in ("parent", "parent_instance", "scope") and isinstance(value, (list, ast.Node)):
                setattr(node, key, _pass_through(value))
    return node


def _strip_pass_through(flat_class) -> None:
    import copy

    calls = _Uses([flat_class.equations, flat_class.initial_equations]).calls
    if any(c in PASS_THROUGH for c in calls):  # copies: the flat equations may share nodes with the library
        flat_class.equations = _pass_through(copy.deepcopy(flat_class.equations))
        flat_class.initial_equations = _pass_through(copy.deepcopy(flat_class.initial_equations))
    for symbol in flat_class.symbols.values():
        for attribute in ("value", "start"):
            value = getattr(symbol, attribute, None)
            if isinstance(value, _expression_types()) and any(c in PASS_THROUGH for c in _Uses(value).calls):
                setattr(symbol, attribute, _pass_through(copy.deepcopy(value)))


def _expression_types():
    from pymoca import ast

    return (ast.Expression, ast.Array, ast.IfExpression)


def _nested_der(node) -> str | None:
    """The argument of the first ``der(der(...))`` in ``node`` (None if there is none)."""
    from pymoca import ast

    if isinstance(node, list):
        return next((found for item in node if (found := _nested_der(item))), None)
    if isinstance(node, ast.Expression):
        if str(node.operator) == "der" and node.operands and isinstance(node.operands[0], ast.Expression) \
                and str(node.operands[0].operator) == "der":
            inner = node.operands[0].operands
            return str(inner[0]) if inner else "?"
        return _nested_der(node.operands)
    if isinstance(node, ast.Node) and not isinstance(node, (ast.Class, ast.Symbol, ast.ComponentRef)):
        return next((found for key, value in node.__dict__.items() if key not in ("parent", "scope")
                     and (found := _nested_der(value))), None)
    return None


def _unsupported(library: Library, flat_tree, model_name: str) -> ModelicaError | None:
    """A message for a construct of the flat model that the compiler does not support (events,
    algorithm sections, String variables and parameters, Integer states, der(der(x))), else None."""
    from pymoca import ast

    flat_class = flat_tree.classes[model_name]
    lookup = _Declarations(library)
    classes = lookup.composition(model_name) or [model_name]

    def refuse(pattern: str, what: str) -> ModelicaError:
        where, owner = library.where([(c, pattern) for c in classes])
        inside = f" (in {model_name})" if owner and owner != model_name else ""
        return ModelicaError(f"{where}: {owner or model_name}: {what}{inside}")

    continuous = "cosim compiles continuous-time models (no events, no discrete-time variables)"
    for equation in list(flat_class.equations) + list(flat_class.initial_equations):
        if isinstance(equation, ast.WhenEquation):
            return refuse(r"\bwhen\b", f"when-equations are not supported: {continuous}")
        if isinstance(equation, ast.Function):
            name = equation.name
            return refuse(rf"\b{re.escape(str(name))}\s*\(",
                          f"'{name}(...)' as an equation is not supported: {continuous}")
    if flat_class.statements or flat_class.initial_statements:
        return refuse(r"\balgorithm\b", "algorithm sections are supported only inside functions: "
                      "write the model's algorithm as equations")
    nested = _nested_der([flat_class.equations, flat_class.initial_equations])
    if nested:
        return refuse(r"\bder\s*\(\s*der\b", f"der(der({nested})) is not supported: introduce a variable "
                      f"for der({nested}) (e.g. v = der({nested}); ... der(v) ...)")
    for name, symbol in flat_class.symbols.items():
        variability = set(symbol.prefixes) & {"parameter", "constant"}
        if str(symbol.type) == "String" and variability != {"constant"}:
            # an FMU built here has Real, Integer and Boolean variables only: a String parameter
            # could be neither listed nor set, so it is refused rather than dropped without a word
            short = re.escape(name.rsplit(".", 1)[-1])
            if "parameter" in variability:
                return refuse(rf"\bparameter\b[^;]*\b{short}\b",
                              f"String parameter '{name}' is not supported: the FMUs built here have Real, "
                              "Integer and Boolean variables only (a String constant is allowed)")
            return refuse(rf"\bString\b[^;]*\b{short}\b",
                          f"String variable '{name}' is not supported (only String constants)")
        if "discrete" in symbol.prefixes:
            return refuse(r"\bdiscrete\b", f"discrete variable '{name}' is not supported: {continuous}")
    return None


def _check_declared_values(flat: FlatModel) -> None:
    """Refuse a state of type Integer or Boolean and a parameter whose declared value lies
    outside its own ``min``/``max``."""
    m = flat.casadi
    for v in m.states:
        decl = flat.declarations.get(v.symbol.name())
        if decl is not None and decl.type in ("Integer", "Boolean"):
            raise ModelicaError(f"{flat.locate(decl.name)}: {flat.name}: der() of the {decl.type} variable "
                                f"'{decl.name}': only Real variables can be states")
    for v in m.parameters:
        decl = flat.declarations.get(v.symbol.name())
        value = v.value
        if decl is None or isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        low, high = decl.min, decl.max
        low = low if isinstance(low, (int, float)) and not isinstance(low, bool) else None
        high = high if isinstance(high, (int, float)) and not isinstance(high, bool) else None
        if low is not None and high is not None and low > high:
            raise ModelicaError(f"{flat.locate(decl.name, 'min')}: {flat.name}: parameter '{decl.name}' has "
                                f"min = {low:g} > max = {high:g}")
        if (low is not None and value < low) or (high is not None and value > high):
            bounds = f"[{'-inf' if low is None else f'{low:g}'}, {'inf' if high is None else f'{high:g}'}]"
            raise ModelicaError(f"{flat.locate(decl.name)}: {flat.name}: the value {value:g} of parameter "
                                f"'{decl.name}' is outside its declared range {bounds}")


# Python's cyclic garbage collector, at its default thresholds (a collection of the young
# generation every 700 allocations), ran thousands of times over the million live objects of
# pymoca's trees of a large model: a third of flatten at 1000 states, two thirds of
# make_explicit at 2000. The objects of a build live until it ends, so collections find little.
COLLECTION_THRESHOLDS = (50_000, 20, 100)


@contextlib.contextmanager
def fewer_collections():
    """Run the block with the garbage collector's thresholds raised to
    ``COLLECTION_THRESHOLDS`` (never lowered); the previous thresholds are restored after."""
    old = gc.get_threshold()
    gc.set_threshold(*(max(a, b) for a, b in zip(old, COLLECTION_THRESHOLDS)))
    try:
        yield
    finally:
        gc.set_threshold(*old)


def flatten(library: Library, model_name: str) -> FlatModel:
    """Flatten ``model_name`` and generate its CasADi form.

    Raises
    ------
    UnknownModelError
        If the library has no such model.
    ModelicaError
        If the model (or a class it uses) is in a file that did not parse, or pymoca cannot
        flatten or translate it: an undeclared name, an unknown class, an undefined function.
    """
    with fewer_collections():
        return _flatten(library, model_name)


def _flatten(library: Library, model_name: str) -> FlatModel:
    from pymoca import ast, tree
    from pymoca.backends.casadi._options import _merge_default_options
    from pymoca.backends.casadi.generator import Generator, GeneratorWalker

    pymoca_patches.apply()
    library.entry(model_name)
    try:
        with pymoca_patches.scopes_kept():
            flat = tree.flatten(library.tree, ast.ComponentRef.from_string(model_name))
    except RecursionError:
        raise ModelicaError(f"{library.file_of(model_name)}: cannot flatten {model_name}: "
                            "the model is nested too deeply (a class that contains or extends itself?)") from None
    except Exception as exc:
        raise _flatten_error(library, model_name, exc) from None
    flat_class = flat.classes[model_name]
    lookup = _Declarations(library)
    declarations = {}
    for name, symbol in flat_class.symbols.items():
        declared, owner = lookup.find(model_name, name)
        prefixes = list(symbol.prefixes)
        binding = None
        if declared is not None and "." not in name:
            binding = _binding_reference(declared)
            declared_prefixes = list(declared.prefixes) + lookup.base_prefixes(declared, owner)
            for causality in ("input", "output"):
                if causality in declared_prefixes and causality not in prefixes:
                    prefixes.append(causality)
            symbol.prefixes = prefixes
        description = symbol.comment or (declared.comment if declared is not None else "") or ""
        fixed = None
        if getattr(symbol, "_cosim_fixed_given", False):
            fixed = _literal(symbol.fixed)
            fixed = fixed if isinstance(fixed, bool) else "expression"
        declarations[name] = Declaration(
            name=name,
            type=lookup.base_type(declared, owner) if declared is not None else str(symbol.type),
            prefixes=prefixes,
            description=description,
            unit=_literal(symbol.unit),
            display_unit=_literal(symbol.displayUnit),
            quantity=_literal(symbol.quantity),
            min=_literal(symbol.min),
            max=_literal(symbol.max),
            fixed=fixed,
            final=bool(getattr(symbol, "final", False)),
            owner=owner,
            binding=binding,
        )
    unsupported = _unsupported(library, flat, model_name)
    if unsupported is not None:
        raise unsupported
    _strip_pass_through(flat_class)
    try:
        generator = Generator(flat, model_name, _merge_default_options({}))
        GeneratorWalker().walk(generator, flat)
    except RecursionError:
        raise ModelicaError(f"{library.file_of(model_name)}: cannot translate {model_name}: "
                            "expressions nested too deeply") from None
    except Exception as exc:
        raise _translate_error(library, model_name, flat, exc) from None
    result = FlatModel(name=model_name, casadi=generator.model, declarations=declarations, library=library)
    _check_declared_values(result)
    return result
