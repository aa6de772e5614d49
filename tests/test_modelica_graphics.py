"""The graphical layer of the Modelica library (MSL style), read from the source text.

A Modelica tool (OpenModelica, Dymola) draws every class from its annotations: every non-partial
connector, model and block has an ``Icon`` (its own or one inherited through ``extends``) that
shows its name; every package has an icon; every connector of a class has a ``Placement`` on the
border of its icon; every component of a model that has ``connect`` equations (and of every
example) has a ``Placement`` in its diagram, no two of them overlap, and every ``connect`` has a
``Line`` from the one connector to the other.

pymoca's parse tree drops the annotations of components and connect equations, so the source is
read here with a small tokenizer: classes (``within``, nested and short classes), their
``extends``, component declarations, ``connect`` equations and the ``annotation(...)`` after each,
parsed into nested calls, arrays and literals. No renderer is needed.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from cosim.compiler.library import DEFAULT_LIBRARY

# --------------------------------------------------------------------------- tokens

_TOKEN = re.compile(r"""
    (?P<skip>\s+|//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:[^"\\]|\\.)*")
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<name>[A-Za-z_]\w*|'(?:[^'\\]|\\.)+')
  | (?P<op>\.\^|\.\*|\./|\.\+|\.-|<=|>=|==|<>|:=|[-+*/^(){}\[\],;=.:<>])
""", re.VERBOSE | re.DOTALL)


@dataclass(frozen=True)
class Token:
    kind: str
    text: str
    line: int


def tokenize(text: str) -> list[Token]:
    tokens, pos, line = [], 0, 1
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if not match:
            raise SyntaxError(f"line {line}: cannot read {text[pos:pos + 20]!r}")
        if match.lastgroup != "skip":
            tokens.append(Token(match.lastgroup, match.group(), line))
        line += match.group().count("\n")
        pos = match.end()
    return tokens


# --------------------------------------------------------------------------- annotation values

@dataclass
class Call:
    """``name(args)``: a record constructor, graphic primitive or nested annotation."""

    name: str
    args: list = field(default_factory=list)
    kwargs: dict = field(default_factory=dict)

    def get(self, key, default=None):
        """A named argument, or a positional nested modification of that name."""
        if key in self.kwargs:
            return self.kwargs[key]
        return next((a for a in self.args if isinstance(a, Call) and a.name == key), default)


class _Values:
    """Recursive descent over the tokens of an annotation: calls, arrays, strings, numbers,
    Booleans, names, unary minus and + - * / of numbers."""

    def __init__(self, tokens: list[Token]):
        self.tokens, self.i = tokens, 0

    def peek(self, offset=0):
        j = self.i + offset
        return self.tokens[j].text if j < len(self.tokens) else None

    def take(self, expected=None):
        token = self.tokens[self.i]
        if expected is not None and token.text != expected:
            raise SyntaxError(f"line {token.line}: {expected!r} expected, found {token.text!r}")
        self.i += 1
        return token

    def expression(self):
        value = self.term()
        while self.peek() in ("+", "-"):
            op, other = self.take().text, self.term()
            value = value + other if op == "+" else value - other
        return value

    def term(self):
        value = self.factor()
        while self.peek() in ("*", "/"):
            op, other = self.take().text, self.factor()
            value = value * other if op == "*" else value / other
        return value

    def factor(self):
        token = self.take()
        if token.text in ("-", "+"):
            value = self.factor()
            return -value if token.text == "-" else value
        if token.kind == "number":
            return float(token.text)
        if token.kind == "string":
            value = token.text[1:-1]
            while self.peek() == "+" and self.tokens[self.i + 1].kind == "string":  # "a" + "b"
                self.take()
                value += self.take().text[1:-1]
            return value
        if token.text == "{":
            items = []
            while self.peek() != "}":
                items.append(self.expression())
                if self.peek() == ",":
                    self.take()
            self.take("}")
            return items
        if token.text == "(":
            value = self.expression()
            self.take(")")
            return value
        if token.kind == "name":
            if token.text in ("true", "false"):
                return token.text == "true"
            name = token.text
            while self.peek() == ".":
                self.take()
                name += "." + self.take().text
            if self.peek() == "(":
                return self.call(name)
            return name
        raise SyntaxError(f"line {token.line}: unexpected {token.text!r}")

    def call(self, name: str) -> Call:
        self.take("(")
        result = Call(name)
        while self.peek() != ")":
            for prefix in ("each", "final"):
                if self.peek() == prefix:
                    self.take()
            if self.tokens[self.i].kind == "name" and self.peek(1) == "=":
                key = self.take().text
                self.take("=")
                result.kwargs[key] = self.expression()
            else:
                result.args.append(self.expression())
            if self.peek() == ",":
                self.take()
        self.take(")")
        return result


def parse_annotation(tokens: list[Token]) -> Call:
    """``annotation(...)`` tokens (``annotation`` first) as a :class:`Call`."""
    values = _Values(tokens)
    values.take("annotation")
    return values.call("annotation")


# --------------------------------------------------------------------------- classes

CLASS_KEYWORDS = {"model", "block", "connector", "class", "package", "record", "function", "type",
                  "operator"}
PREFIXES = {"encapsulated", "partial", "final", "replaceable", "redeclare", "inner", "outer",
            "expandable", "pure", "impure", "input", "output", "parameter", "constant", "flow",
            "stream", "discrete"}
SECTIONS = {"public", "protected", "equation", "algorithm", "initial"}


@dataclass
class Component:
    name: str
    type: str
    annotation: Call | None
    line: int


@dataclass
class Connect:
    a: str
    b: str
    annotation: Call | None
    line: int


@dataclass
class ModelicaClass:
    name: str  # full dotted name
    kind: str
    partial: bool
    file: Path
    extends: list = field(default_factory=list)  # (base as written, {component: redeclared type}, annotation)
    components: list = field(default_factory=list)
    connects: list = field(default_factory=list)
    annotation: Call | None = None
    short_base: str | None = None  # connector RealInput = input Real

    @property
    def scope(self) -> str:
        return self.name.rsplit(".", 1)[0] if "." in self.name else ""


def _balanced(tokens: list[Token], i: int) -> int:
    """Index after the bracket that closes the one at ``tokens[i]``."""
    depth = 0
    for j in range(i, len(tokens)):
        if tokens[j].text in "({[":
            depth += 1
        elif tokens[j].text in ")}]":
            depth -= 1
            if depth == 0:
                return j + 1
    raise SyntaxError(f"line {tokens[i].line}: unbalanced {tokens[i].text!r}")


def _depth(tokens: list[Token], start: int, end: int) -> int:
    """Bracket depth at ``tokens[end]`` counted from ``tokens[start]``."""
    return sum((t.text in "({[") - (t.text in ")}]") for t in tokens[start:end])


def _statement(tokens: list[Token], i: int) -> int:
    """Index of the ``;`` that ends the statement starting at ``i`` (outside brackets)."""
    j = i
    while tokens[j].text != ";":
        j = _balanced(tokens, j) if tokens[j].text in "({[" else j + 1
    return j


def _annotation_in(tokens: list[Token]) -> Call | None:
    """The ``annotation(...)`` of a statement (outside its brackets), if it has one."""
    j = 0
    while j < len(tokens):
        if tokens[j].text == "annotation" and j + 1 < len(tokens) and tokens[j + 1].text == "(":
            return parse_annotation(tokens[j:_balanced(tokens, j + 1)])
        j = _balanced(tokens, j) if tokens[j].text in "({[" else j + 1
    return None


def _dotted(tokens: list[Token], i: int) -> tuple[str, int]:
    name = tokens[i].text
    i += 1
    while i + 1 < len(tokens) and tokens[i].text == "." and tokens[i + 1].kind == "name":
        name += "." + tokens[i + 1].text
        i += 2
    return name, i


def _redeclares(tokens: list[Token]) -> dict[str, str]:
    """``redeclare [replaceable] Type name`` in a modification: component -> type."""
    found = {}
    for j, token in enumerate(tokens):
        if token.text == "redeclare":
            k = j + 1
            while tokens[k].text in PREFIXES:
                k += 1
            if tokens[k].text in CLASS_KEYWORDS:
                continue
            type_name, k = _dotted(tokens, k)
            found[tokens[k].text] = type_name
    return found


def parse_classes(text: str, file: Path) -> list[ModelicaClass]:
    """Every class a file defines (nested ones included)."""
    tokens = tokenize(text)
    i, within = 0, ""
    if tokens and tokens[0].text == "within":
        end = _statement(tokens, 0)
        within = "".join(t.text for t in tokens[1:end])
        i = end + 1
    found: list[ModelicaClass] = []
    while i < len(tokens):
        i = _parse_class(tokens, i, within, file, found)
    return found


def _parse_class(tokens, i, scope, file, found) -> int:
    """Parse the class definition at ``i`` (prefixes first); return the index after it."""
    partial = False
    while tokens[i].text in PREFIXES:
        partial |= tokens[i].text == "partial"
        i += 1
    kind = tokens[i].text
    if kind not in CLASS_KEYWORDS:
        raise SyntaxError(f"line {tokens[i].line}: class definition expected, found {kind!r}")
    i += 1
    name = tokens[i].text
    full = f"{scope}.{name}" if scope else name
    cls = ModelicaClass(full, kind, partial, file)
    found.append(cls)
    i += 1
    if tokens[i].text == "=":  # short class definition
        end = _statement(tokens, i)
        j = i + 1
        while tokens[j].text in PREFIXES:
            j += 1
        cls.short_base, _ = _dotted(tokens, j)
        cls.annotation = _annotation_in(tokens[i + 1:end])
        return end + 1
    while tokens[i].kind == "string" or tokens[i].text == "+":  # description
        i += 1
    section = "public"
    while True:
        token = tokens[i]
        if token.text == "end" and tokens[i + 1].text == name and tokens[i + 2].text == ";":
            return i + 3
        if token.text in SECTIONS:
            section = "equation" if token.text in ("equation", "algorithm") or \
                tokens[i + 1].text in ("equation", "algorithm") else token.text
            i += 2 if token.text == "initial" else 1
            continue
        j = i
        while tokens[j].text in PREFIXES:
            j += 1
        if tokens[j].text in CLASS_KEYWORDS and section != "equation":
            i = _parse_class(tokens, i, full, file, found)
            continue
        end = _statement(tokens, i)
        statement = tokens[i:end]
        first = statement[0].text
        if first == "annotation":
            cls.annotation = parse_annotation(statement)
        elif first == "extends":
            base, _ = _dotted(statement, 1)
            cls.extends.append((base, _redeclares(statement), _annotation_in(statement[1:])))
        elif first == "connect":
            close = _balanced(statement, 1)
            comma = next(j for j in range(2, close) if statement[j].text == "," and
                         _depth(statement, 2, j) == 0)
            a, b = ("".join(t.text for t in part) for part in (statement[2:comma], statement[comma + 1:close - 1]))
            cls.connects.append(Connect(a, b, _annotation_in(statement[close:]), token.line))
        elif section != "equation" and first not in ("import",):
            k = 0
            while statement[k].text in PREFIXES:
                k += 1
            type_name, k = _dotted(statement, k)
            if statement[k].text == "[":
                k = _balanced(statement, k)
            cls.components.append(Component(statement[k].text, type_name, _annotation_in(statement[k:]),
                                            token.line))
        i = end + 1


def load_classes(root: Path = DEFAULT_LIBRARY) -> dict[str, ModelicaClass]:
    classes = {}
    for path in sorted(root.rglob("*.mo")):
        for cls in parse_classes(path.read_text(encoding="utf-8"), path):
            classes[cls.name] = cls
    return classes


# --------------------------------------------------------------------------- lookup and geometry

class Library:
    def __init__(self, classes: dict[str, ModelicaClass]):
        self.classes = classes

    def resolve(self, name: str, scope: str) -> ModelicaClass | None:
        """The class ``name`` denotes from inside ``scope`` (innermost enclosing scope first)."""
        parts = scope.split(".") if scope else []
        for n in range(len(parts), -1, -1):
            candidate = ".".join(parts[:n] + [name])
            if candidate in self.classes:
                return self.classes[candidate]
        return None

    def bases(self, cls: ModelicaClass) -> list[ModelicaClass]:
        """``cls`` and every class it inherits from (depth first), short-class bases included."""
        found, todo = [], [cls]
        while todo:
            current = todo.pop(0)
            found.append(current)
            names = [b for b, _, _ in current.extends] + ([current.short_base] if current.short_base else [])
            for base in names:
                resolved = self.resolve(base, current.scope)
                if resolved is not None and resolved not in found:
                    todo.append(resolved)
        return found

    def components(self, cls: ModelicaClass) -> dict[str, Component]:
        """Components of ``cls`` with the inherited ones, redeclarations applied to their type."""
        result: dict[str, Component] = {}
        for base in reversed(self.bases(cls)):
            for component in base.components:
                result[component.name] = component
        for base in self.bases(cls):
            for _, redeclared, _ in base.extends:
                for name, type_name in redeclared.items():
                    if name in result:
                        old = result[name]
                        result[name] = Component(old.name, type_name, old.annotation, old.line)
        return result

    def component_class(self, component: Component, owner: ModelicaClass) -> ModelicaClass | None:
        for base in self.bases(owner):
            found = self.resolve(component.type, base.scope)
            if found is not None:
                return found
        return None

    def layer(self, cls: ModelicaClass, layer: str) -> list[Call]:
        """``Icon`` or ``Diagram`` annotations of ``cls`` and of the bases whose graphics it shows
        (not those extended with ``annotation(IconMap(primitivesVisible = false))``), own first."""
        own = cls.annotation.get(layer) if cls.annotation else None
        found = [own] if isinstance(own, Call) else []
        for base_name, _, annotation in cls.extends:
            base = self.resolve(base_name, cls.scope)
            mapping = annotation.get(f"{layer}Map") if annotation else None
            if base is None or (isinstance(mapping, Call) and mapping.get("primitivesVisible") is False):
                continue
            found += self.layer(base, layer)
        if cls.short_base:
            base = self.resolve(cls.short_base, cls.scope)
            found += self.layer(base, layer) if base is not None else []
        return found

    def graphics(self, cls: ModelicaClass, layer: str = "Icon") -> list:
        return [g for value in self.layer(cls, layer) for g in (value.get("graphics") or [])]

    def extent(self, cls: ModelicaClass, layer: str = "Icon") -> list:
        """The coordinate system of a layer: the class's own, else inherited, else the default."""
        for value in self.layer(cls, layer):
            system = value.get("coordinateSystem")
            if isinstance(system, Call) and system.get("extent"):
                return system.get("extent")
        return [[-100.0, -100.0], [100.0, 100.0]]


def transformation(component: Component, icon: bool = False) -> Call | None:
    """The Placement transformation (``iconTransformation`` for the icon layer if there is one)."""
    placement = component.annotation.get("Placement") if component.annotation else None
    if not isinstance(placement, Call):
        return None
    if icon and isinstance(placement.get("iconTransformation"), Call):
        return placement.get("iconTransformation")
    return placement.get("transformation")


def apply(t: Call, point, source_extent=((-100.0, -100.0), (100.0, 100.0))):
    """Map ``point`` of a class's coordinate system ``source_extent`` into the parent through the
    transformation ``t`` (extent, then rotation about the origin, then the origin; MLS 18.6.4)."""
    (x1, y1), (x2, y2) = t.get("extent")
    (sx1, sy1), (sx2, sy2) = source_extent
    x = x1 + (point[0] - sx1) / (sx2 - sx1) * (x2 - x1)
    y = y1 + (point[1] - sy1) / (sy2 - sy1) * (y2 - y1)
    angle = math.radians(t.get("rotation", 0.0))
    ox, oy = t.get("origin", [0.0, 0.0])
    return (ox + x * math.cos(angle) - y * math.sin(angle), oy + x * math.sin(angle) + y * math.cos(angle))


def box(t: Call, source_extent=((-100.0, -100.0), (100.0, 100.0))):
    """Axis-aligned bounding box ``(xmin, ymin, xmax, ymax)`` of a placed class."""
    (sx1, sy1), (sx2, sy2) = source_extent
    corners = [apply(t, p, source_extent) for p in ((sx1, sy1), (sx1, sy2), (sx2, sy1), (sx2, sy2))]
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    return min(xs), min(ys), max(xs), max(ys)


def centre(t: Call):
    """The centre of a placement (the point a connection line ends at)."""
    (x1, y1), (x2, y2) = t.get("extent")
    return apply(t, ((x1 + x2) / 2, (y1 + y2) / 2), t.get("extent"))


def connector_position(library: Library, model: ModelicaClass, reference: str):
    """Where the line of ``reference`` (``conn`` or ``comp.conn``) ends in the diagram of ``model``."""
    first, _, rest = reference.partition(".")
    component = library.components(model)[first]
    t = transformation(component)
    assert t is not None, f"{model.name}.{first} has no Placement"
    if not rest:
        return centre(t)
    cls = library.component_class(component, model)
    inner = transformation(library.components(cls)[rest], icon=True)
    assert inner is not None, f"{cls.name}.{rest} has no Placement"
    return apply(t, centre(inner), library.extent(cls))


# --------------------------------------------------------------------------- the tests

CLASSES = load_classes()
LIBRARY = Library(CLASSES)
DRAWN = [c for c in CLASSES.values() if c.kind in ("connector", "model", "block") and not c.partial]
#: Models with connect equations (their own or inherited) and every example: drawn as diagrams.
ASSEMBLIES = [c for c in CLASSES.values() if c.kind in ("model", "block") and not c.partial
              and (any(base.connects for base in LIBRARY.bases(c)) or c.name.startswith("Bicycle.Examples."))]
#: Packages drawn with an icon: all but the data sets generated into Bicycle.Records (packages of
#: constants) and the short package definitions (``replaceable package Data = ...``).
PACKAGES = [c for c in CLASSES.values() if c.kind == "package" and not c.partial and c.short_base is None
            and not c.name.startswith("Bicycle.Records.")]


def _ids(classes):
    return [c.name for c in classes]


def _texts(graphics) -> list[str]:
    return [g.get("textString") for g in graphics if isinstance(g, Call) and g.name == "Text"]


def _graphical(component: Component, owner: ModelicaClass) -> ModelicaClass | None:
    """The class of a component if it is drawn (a connector, model or block), else None."""
    cls = LIBRARY.component_class(component, owner)
    return cls if cls is not None and cls.kind in ("connector", "model", "block") else None


def test_the_library_is_read():
    assert "Bicycle.Icons" in CLASSES and len(DRAWN) > 60
    assert "Bicycle.Bicycles.WhippleRider" in _ids(ASSEMBLIES)
    assert "Bicycle.Bicycles.WhippleRiderTwist" in _ids(ASSEMBLIES)  # its connects are inherited too


@pytest.mark.parametrize("cls", DRAWN, ids=_ids(DRAWN))
def test_every_class_has_an_icon_with_its_name(cls):
    """An Icon with graphics, own or inherited; models and blocks show ``%name`` in it, connectors
    in their Icon or (MSL: Modelica.Blocks.Interfaces.RealInput) their Diagram layer."""
    icon = LIBRARY.graphics(cls, "Icon")
    assert icon, f"{cls.name} ({cls.file}) has no Icon graphics, neither its own nor inherited"
    names = _texts(icon) + (_texts(LIBRARY.graphics(cls, "Diagram")) if cls.kind == "connector" else [])
    assert any("%name" in (t or "") for t in names), f"{cls.name}: no Text(textString = \"%name\")"
    for graphic in icon:
        assert isinstance(graphic, Call) and graphic.name in (
            "Rectangle", "Ellipse", "Line", "Polygon", "Text", "Bitmap"), f"{cls.name}: {graphic!r}"


@pytest.mark.parametrize("cls", PACKAGES, ids=_ids(PACKAGES))
def test_every_package_has_an_icon(cls):
    assert LIBRARY.graphics(cls, "Icon"), f"{cls.name} ({cls.file}): no Icon, e.g. extends Bicycle.Icons.Package"


WITH_CONNECTORS = [c for c in CLASSES.values() if c.kind in ("model", "block", "connector")]


@pytest.mark.parametrize("cls", WITH_CONNECTORS, ids=_ids(WITH_CONNECTORS))
def test_every_connector_of_a_class_sits_on_its_icon_border(cls):
    """Every connector component has a Placement whose icon-layer box touches the border of the
    class's icon (MSL: Frame_a at {{-116, -16}, {-84, 16}}, RealInput at {{-140, -20}, {-100, 20}})."""
    (ix1, iy1), (ix2, iy2) = LIBRARY.extent(cls)
    for component in cls.components:
        kind = _graphical(component, cls)
        if kind is None or kind.kind != "connector":
            continue
        t = transformation(component, icon=True)
        where = f"{cls.file}:{component.line}: connector {cls.name}.{component.name}"
        assert t is not None, f"{where} has no Placement"
        x1, y1, x2, y2 = box(t, LIBRARY.extent(kind))
        touches = x1 <= ix2 and x2 >= ix1 and y1 <= iy2 and y2 >= iy1
        inside = x1 > ix1 and x2 < ix2 and y1 > iy1 and y2 < iy2
        assert touches and not inside, f"{where}: {(x1, y1, x2, y2)} is not on the border of the icon"


@pytest.mark.parametrize("cls", ASSEMBLIES, ids=_ids(ASSEMBLIES))
def test_every_component_of_an_assembly_is_placed_without_overlap(cls):
    """Every component drawn in the diagram (connector, model or block; inherited ones and the
    model's own connectors included) has a Placement, and no two extents overlap (touching is
    allowed)."""
    placed = []
    for name, component in LIBRARY.components(cls).items():
        component_class = _graphical(component, cls)
        if component_class is None:
            continue
        t = transformation(component)
        assert t is not None, f"{cls.name}.{name} ({component.type}) has no Placement(transformation(...))"
        placed.append((name, box(t, LIBRARY.extent(component_class))))
    for k, (a, (ax1, ay1, ax2, ay2)) in enumerate(placed):
        assert ax2 - ax1 > 0 and ay2 - ay1 > 0, f"{cls.name}.{a}: empty extent"
        for b, (bx1, by1, bx2, by2) in placed[k + 1:]:
            overlap = min(ax2, bx2) - max(ax1, bx1), min(ay2, by2) - max(ay1, by1)
            assert not (overlap[0] > 1e-6 and overlap[1] > 1e-6), \
                f"{cls.name}: the placements of {a} and {b} overlap"


@pytest.mark.parametrize("cls", ASSEMBLIES, ids=_ids(ASSEMBLIES))
def test_every_connect_has_a_line_between_its_connectors(cls):
    """Every ``connect`` has ``Line(points, color)`` whose ends are the two connectors (the centre
    of a connector's placement, through the placement of its component)."""
    for connect in cls.connects:
        line = connect.annotation.get("Line") if connect.annotation else None
        where = f"{cls.file}:{connect.line}: connect({connect.a}, {connect.b})"
        assert isinstance(line, Call), f"{where} has no Line annotation"
        points = line.get("points")
        assert points and len(points) >= 2 and line.get("color"), f"{where}: Line needs points and color"
        for point, reference in ((points[0], connect.a), (points[-1], connect.b)):
            expected = connector_position(LIBRARY, cls, reference)
            assert math.dist(point, expected) < 0.5, \
                f"{where}: the line ends at {point}, the connector {reference} is at {expected}"
