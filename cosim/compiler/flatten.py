"""Flatten one Modelica model with pymoca and collect what the FMU needs to know of each variable.

pymoca's flattening drops two things of components whose type is a derived type such as
``Bicycle.Units.Angle``: the description string and the ``input``/``output`` prefix of a
top-level component. Both are restored here from the declarations in the parsed library.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import ModelicaError
from .library import Library

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
    fixed: bool | None = None


@dataclass
class FlatModel:
    """A flattened model: pymoca's CasADi model plus declarations of every flat variable."""

    name: str
    casadi: object  # pymoca.backends.casadi.model.Model
    declarations: dict[str, Declaration] = field(default_factory=dict)


def _literal(node):
    value = getattr(node, "value", None)
    return value if isinstance(value, (int, float, str, bool)) else None


class _Declarations:
    """Looks up the declaring component of a flat name through the class hierarchy."""

    def __init__(self, library: Library):
        self.library = library

    def _class(self, name: str):
        node = self.library.tree
        for part in name.split("."):
            node = node.classes.get(part)
            if node is None:
                return None
        return node

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
        """The declaring symbol of ``flat_name`` inside ``class_name`` (None if not found)."""
        head, _, rest = flat_name.partition(".")
        for name, symbol, owner in self.symbols(class_name):
            if name != head:
                continue
            if not rest:
                return symbol
            type_name = self.resolve(str(symbol.type), owner)
            return self.find(type_name, rest) if type_name else None
        return None

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


def flatten(library: Library, model_name: str) -> FlatModel:
    """Flatten ``model_name`` and generate its CasADi form.

    Raises
    ------
    UnknownModelError
        If the library has no such model.
    ModelicaError
        If pymoca cannot flatten or translate the model.
    """
    from pymoca import ast, tree
    from pymoca.backends.casadi._options import _merge_default_options
    from pymoca.backends.casadi.generator import Generator, GeneratorWalker

    from . import pymoca_patches

    pymoca_patches.apply()
    entry = library.entry(model_name)
    try:
        flat = tree.flatten(library.tree, ast.ComponentRef.from_string(model_name))
    except Exception as exc:
        raise ModelicaError(f"{entry.file}: cannot flatten {model_name}: {exc}") from None
    flat_class = flat.classes[model_name]
    lookup = _Declarations(library)
    declarations = {}
    for name, symbol in flat_class.symbols.items():
        declared = lookup.find(model_name, name)
        prefixes = list(symbol.prefixes)
        if declared is not None and "." not in name:
            for causality in ("input", "output"):
                if causality in declared.prefixes and causality not in prefixes:
                    prefixes.append(causality)
            symbol.prefixes = prefixes
        description = symbol.comment or (declared.comment if declared is not None else "") or ""
        owner = model_name
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
            fixed=_literal(symbol.fixed),
        )
    try:
        generator = Generator(flat, model_name, _merge_default_options({}))
        GeneratorWalker().walk(generator, flat)
    except Exception as exc:
        raise ModelicaError(f"{entry.file}: cannot translate {model_name}: {exc}") from None
    return FlatModel(name=model_name, casadi=generator.model, declarations=declarations)
