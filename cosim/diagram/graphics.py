"""The graphical annotations of MLS chapter 18 as Python objects, inherited through ``extends``.

:class:`Graphics` answers, for a class of a :class:`~cosim.compiler.library.Library`:

- :meth:`Graphics.layer`: its ``Icon`` or ``Diagram`` layer, a coordinate system and the
  graphical primitives (:class:`Line`, :class:`Polygon`, :class:`Rectangle`, :class:`Ellipse`,
  :class:`Text`, :class:`Bitmap`) with the defaults of MLS 18.6; a layer is the union of the base
  classes' graphics (first) and the class's own; the coordinate system is the class's own, else
  the first base's that has one, else the default ``{{-100, -100}, {100, 100}}``;
- :meth:`Graphics.components`: its components (inherited ones first, redeclared types applied)
  with their :class:`Placement`;
- :meth:`Graphics.connections`: its ``connect`` equations with their :class:`Line`;
- :meth:`Graphics.bindings`: the source text of the values of its parameters (for ``%par``).

Class names in declarations are looked up as Modelica does (the enclosing scopes from the
innermost outwards, the first identifier decides). Values are checked against MLS 18: a malformed
annotation (a point that is not ``{x, y}``, a colour outside 0..255, an unknown attribute or
enumeration literal, an expression that is not a literal) is an error naming ``file:line``.
"""
from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field, replace

from cosim.compiler.library import Library
from cosim.diagram.annotations import ClassDef, Expression, Extends, Name, Record, find_class, parse_file
from cosim.errors import ModelicaError, UnknownModelError

Point = tuple[float, float]
Extent = tuple[Point, Point]
Color = tuple[int, int, int]

DEFAULT_EXTENT: Extent = ((-100.0, -100.0), (100.0, 100.0))

#: MLS 18.6 enumerations: type name -> literals.
ENUMERATIONS = {
    "LinePattern": ("None", "Solid", "Dash", "Dot", "DashDot", "DashDotDot"),
    "FillPattern": ("None", "Solid", "Horizontal", "Vertical", "Cross", "Forward", "Backward", "CrossDiag",
                    "HorizontalCylinder", "VerticalCylinder", "Sphere"),
    "BorderPattern": ("None", "Raised", "Sunken", "Engraved"),
    "Smooth": ("None", "Bezier"),
    "Arrow": ("None", "Open", "Filled", "Half"),
    "TextAlignment": ("Left", "Center", "Right"),
    "TextStyle": ("Bold", "Italic", "UnderLine"),
    "EllipseClosure": ("None", "Chord", "Radial"),
}

_ITEM = ("visible", "origin", "rotation")
_FILLED = _ITEM + ("lineColor", "fillColor", "pattern", "fillPattern", "lineThickness")
#: MLS 18.6 primitive -> its attributes.
ATTRIBUTES = {
    "Line": _ITEM + ("points", "color", "pattern", "thickness", "arrow", "arrowSize", "smooth"),
    "Polygon": _FILLED + ("points", "smooth"),
    "Rectangle": _FILLED + ("borderPattern", "extent", "radius"),
    "Ellipse": _FILLED + ("extent", "startAngle", "endAngle", "closure"),
    "Text": _FILLED + ("extent", "textString", "fontSize", "fontName", "textStyle", "textColor",
                       "horizontalAlignment", "string", "index"),
    "Bitmap": _ITEM + ("extent", "fileName", "imageSource"),
}

#: Class kinds whose unplaced components a diagram still draws (at a default position).
DRAWN_KINDS = frozenset({"model", "block", "connector", "class"})


# --------------------------------------------------------------------------- objects

@dataclass(frozen=True, kw_only=True)
class GraphicItem:
    """Attributes of every primitive (MLS 18.6.1): drawn if ``visible``, rotated by ``rotation``
    degrees counterclockwise about the local origin, then moved to ``origin``."""

    visible: bool = True
    origin: Point = (0.0, 0.0)
    rotation: float = 0.0
    where: str = ""


@dataclass(frozen=True, kw_only=True)
class FilledShape(GraphicItem):
    """Outline and fill (MLS 18.6.1.2); ``line_thickness`` in mm."""

    line_color: Color = (0, 0, 0)
    fill_color: Color = (0, 0, 0)
    pattern: str = "Solid"
    fill_pattern: str = "None"
    line_thickness: float = 0.25


@dataclass(frozen=True, kw_only=True)
class Line(GraphicItem):
    """A polyline (MLS 18.6.2); ``arrow`` at (start, end); ``thickness`` in mm."""

    points: tuple = ()
    color: Color = (0, 0, 0)
    pattern: str = "Solid"
    thickness: float = 0.25
    arrow: tuple = ("None", "None")
    arrow_size: float = 3.0
    smooth: str = "None"


@dataclass(frozen=True, kw_only=True)
class Polygon(FilledShape):
    """A closed polygon (MLS 18.6.3)."""

    points: tuple = ()
    smooth: str = "None"


@dataclass(frozen=True, kw_only=True)
class Rectangle(FilledShape):
    """A rectangle with corner radius (MLS 18.6.4)."""

    extent: Extent = DEFAULT_EXTENT
    radius: float = 0.0
    border_pattern: str = "None"


@dataclass(frozen=True, kw_only=True)
class Ellipse(FilledShape):
    """An ellipse or elliptic arc from ``start_angle`` to ``end_angle`` degrees (MLS 18.6.5)."""

    extent: Extent = DEFAULT_EXTENT
    start_angle: float = 0.0
    end_angle: float = 360.0
    closure: str = "Chord"


@dataclass(frozen=True, kw_only=True)
class Text(FilledShape):
    """A text in ``extent`` (MLS 18.6.6); ``font_size`` 0 fits the extent."""

    extent: Extent = DEFAULT_EXTENT
    text_string: str = ""
    font_size: float = 0.0
    font_name: str = ""
    text_style: tuple = ()
    text_color: Color = (0, 0, 0)
    horizontal_alignment: str = "Center"


@dataclass(frozen=True, kw_only=True)
class Bitmap(GraphicItem):
    """An image from ``file_name`` (a ``modelica://`` URI) or ``image_source`` (base64)
    (MLS 18.6.7)."""

    extent: Extent = DEFAULT_EXTENT
    file_name: str = ""
    image_source: str = ""


@dataclass(frozen=True)
class CoordinateSystem:
    """A layer's coordinate system (MLS 18.5): ``extent`` with its corners ordered (lower left,
    upper right); ``given`` says whether the class (not the default) defines it."""

    extent: Extent = DEFAULT_EXTENT
    preserve_aspect_ratio: bool = True
    initial_scale: float = 0.1
    given: bool = False

    @property
    def center(self) -> Point:
        """The centre of the extent."""
        (x1, y1), (x2, y2) = self.extent
        return (x1 + x2) / 2, (y1 + y2) / 2


@dataclass(frozen=True)
class Layer:
    """The icon or diagram layer of a class: its coordinate system and primitives (inherited
    ones first)."""

    coordinate_system: CoordinateSystem = CoordinateSystem()
    graphics: tuple = ()


@dataclass(frozen=True)
class Transformation:
    """Where a component is drawn (MLS 18.4): its class's coordinate system mapped onto
    ``extent`` (corners reversed: flipped), rotated by ``rotation`` degrees counterclockwise about
    ``origin``-relative zero, then moved to ``origin``."""

    extent: Extent
    origin: Point = (0.0, 0.0)
    rotation: float = 0.0


@dataclass(frozen=True)
class Placement:
    """A component's ``Placement`` (MLS 18.4): ``transformation`` in the diagram layer,
    ``icon_transformation`` in the icon layer (of a connector; None: the same as
    ``transformation``)."""

    visible: bool = True
    icon_visible: bool = True
    transformation: Transformation | None = None
    icon_transformation: Transformation | None = None
    where: str = ""

    def for_icon(self) -> Transformation | None:
        """The transformation of the icon layer."""
        return self.icon_transformation or self.transformation


@dataclass(frozen=True)
class ComponentView:
    """A component as a diagram draws it.

    Attributes
    ----------
    name : str
        The component's name.
    type : str or None
        Its class's full name (None if it is not a class of the library).
    type_text : str
        The type as written in the declaration.
    kind : str or None
        The class kind (``model``, ``connector``, ...; None if not found).
    placement : Placement or None
        Its placement annotation.
    modifiers : dict
        Its modifiers (name -> source text).
    prefixes : frozenset
        Its prefixes (``parameter``, ``input``, ...).
    protected : bool
        Declared protected.
    where : str
        ``file:line`` of the declaration.
    """

    name: str
    type: str | None
    type_text: str
    kind: str | None
    placement: Placement | None
    modifiers: dict = field(default_factory=dict)
    prefixes: frozenset = frozenset()
    protected: bool = False
    where: str = ""

    @property
    def is_connector(self) -> bool:
        """True for a component of a connector class."""
        return self.kind == "connector"


@dataclass(frozen=True)
class ConnectionView:
    """A ``connect(a, b)``: its two connectors as written and its :class:`Line` (None without
    one); ``where`` is ``file:line``."""

    a: str
    b: str
    line: Line | None
    where: str = ""


# --------------------------------------------------------------------------- reading values

def modelica_text(value) -> str:
    """A parsed annotation value written back as Modelica (for messages)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"{value:g}"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "{" + ", ".join(modelica_text(v) for v in value) + "}"
    if isinstance(value, Name):
        return value.name
    if isinstance(value, Expression):
        return value.text
    if isinstance(value, Record):
        items = [modelica_text(v) for v in value.positional]
        items += [f"{k} = {modelica_text(v)}" for k, v in value.arguments.items()]
        return f"{value.name}({', '.join(items)})"
    return repr(value)


class _Reader:
    """The arguments of one annotation record, checked; errors name ``file:line``."""

    def __init__(self, record: Record, file: str, context: str = ""):
        self.record, self.file = record, file
        self.where = f"{file}:{record.line}"
        self.label = f"{context}{record.name}"

    def error(self, key: str, expected: str, value) -> ModelicaError:
        return ModelicaError(f"{self.where}: {self.label}({key} = {modelica_text(value)}): {expected}")

    def has(self, key: str) -> bool:
        return key in self.record.arguments

    def raw(self, key: str):
        return self.record.arguments.get(key)

    def number(self, key: str, default: float) -> float:
        value = self.record.arguments.get(key)
        if value is None:
            return default
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(key, "must be a literal number", value)
        return float(value)

    def boolean(self, key: str, default: bool) -> bool:
        value = self.record.arguments.get(key)
        if value is None:
            return default
        if not isinstance(value, bool):
            raise self.error(key, "must be true or false", value)
        return value

    def string(self, key: str, default: str = "") -> str:
        value = self.record.arguments.get(key)
        if value is None:
            return default
        if not isinstance(value, str):
            raise self.error(key, "must be a string literal", value)
        return value

    def point(self, key: str, default: Point) -> Point:
        value = self.record.arguments.get(key)
        if value is None:
            return default
        return self._point(key, value, value)

    def _point(self, key: str, value, whole) -> Point:
        if (not isinstance(value, list) or len(value) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                           for v in value)):
            raise self.error(key, "must be a point {x, y} of literal numbers", whole)
        return float(value[0]), float(value[1])

    def points(self, key: str, minimum: int) -> tuple:
        value = self.record.arguments.get(key)
        if value is None:
            raise ModelicaError(f"{self.where}: {self.label}: '{key}' is missing")
        if not isinstance(value, list):
            raise self.error(key, "must be an array of points {{x1, y1}, {x2, y2}, ...}", value)
        points = tuple(self._point(key, p, value) for p in value)
        if len(points) < minimum:
            raise self.error(key, f"needs at least {minimum} points", value)
        return points

    def extent(self, key: str, default: Extent | None = None, required: bool = False) -> Extent:
        value = self.record.arguments.get(key)
        if value is None:
            if required or default is None:
                raise ModelicaError(f"{self.where}: {self.label}: '{key}' is missing")
            return default
        if not isinstance(value, list) or len(value) != 2:
            raise self.error(key, "must be an extent {{x1, y1}, {x2, y2}}", value)
        return self._point(key, value[0], value), self._point(key, value[1], value)

    def color(self, key: str, default: Color) -> Color:
        value = self.record.arguments.get(key)
        if value is None:
            return default
        if (not isinstance(value, list) or len(value) != 3
                or not all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 255 for v in value)):
            raise self.error(key, "must be a colour {r, g, b} of integers 0..255", value)
        return tuple(value)

    def enum(self, key: str, enumeration: str, default: str, value=None) -> str:
        value = self.record.arguments.get(key) if value is None else value
        if value is None:
            return default
        literals = ENUMERATIONS[enumeration]
        if isinstance(value, Name):
            parts = value.name.split(".")
            if len(parts) >= 2 and parts[-2] == enumeration and parts[-1] in literals:
                return parts[-1]
        raise self.error(key, f"must be one of {enumeration}.{', '.join(literals)}", value)

    def check_attributes(self, allowed: tuple) -> None:
        unknown = [k for k in self.record.arguments if k not in allowed and not k.startswith("__")]
        if unknown:
            raise ModelicaError(f"{self.where}: {self.label}: unknown attribute '{unknown[0]}' "
                                f"(MLS 18.6: {', '.join(allowed)})")
        if self.record.positional:
            raise ModelicaError(f"{self.where}: {self.label}(...): arguments must be named "
                                f"(e.g. {allowed[3]} = ...)")


def _item(r: _Reader) -> dict:
    return {"visible": r.boolean("visible", True), "origin": r.point("origin", (0.0, 0.0)),
            "rotation": r.number("rotation", 0.0), "where": r.where}


def _filled(r: _Reader) -> dict:
    return {**_item(r), "line_color": r.color("lineColor", (0, 0, 0)), "fill_color": r.color("fillColor", (0, 0, 0)),
            "pattern": r.enum("pattern", "LinePattern", "Solid"),
            "fill_pattern": r.enum("fillPattern", "FillPattern", "None"),
            "line_thickness": r.number("lineThickness", 0.25)}


def primitive(record, file: str, context: str = ""):
    """The primitive (:class:`Line`, :class:`Rectangle`, ...) of a record of ``graphics``.

    Raises
    ------
    ModelicaError
        ``file:line`` of a record that is not a primitive or has a malformed attribute.
    """
    if not isinstance(record, Record):
        raise ModelicaError(f"{file}: {context}graphics: {modelica_text(record)} is not a graphical primitive "
                            f"(MLS 18.6: {', '.join(ATTRIBUTES)})")
    if record.name not in ATTRIBUTES:
        raise ModelicaError(f"{file}:{record.line}: {context}graphics: unknown primitive '{record.name}' "
                            f"(MLS 18.6: {', '.join(ATTRIBUTES)})")
    r = _Reader(record, file, context)
    r.check_attributes(ATTRIBUTES[record.name])
    if record.name == "Line":
        arrow = r.raw("arrow")
        if arrow is None:
            arrows = ("None", "None")
        elif isinstance(arrow, list) and len(arrow) == 2:
            arrows = tuple(r.enum("arrow", "Arrow", "None", value=a) for a in arrow)
        else:
            raise r.error("arrow", "must be {Arrow.start, Arrow.end}", arrow)
        return Line(**_item(r), points=r.points("points", 2), color=r.color("color", (0, 0, 0)),
                    pattern=r.enum("pattern", "LinePattern", "Solid"), thickness=r.number("thickness", 0.25),
                    arrow=arrows, arrow_size=r.number("arrowSize", 3.0), smooth=r.enum("smooth", "Smooth", "None"))
    if record.name == "Polygon":
        return Polygon(**_filled(r), points=r.points("points", 3), smooth=r.enum("smooth", "Smooth", "None"))
    if record.name == "Rectangle":
        return Rectangle(**_filled(r), extent=r.extent("extent", required=True), radius=r.number("radius", 0.0),
                         border_pattern=r.enum("borderPattern", "BorderPattern", "None"))
    if record.name == "Ellipse":
        start, end = r.number("startAngle", 0.0), r.number("endAngle", 360.0)
        full = start == 0 and end == 360
        return Ellipse(**_filled(r), extent=r.extent("extent", required=True), start_angle=start, end_angle=end,
                       closure=r.enum("closure", "EllipseClosure", "Chord" if full else "Radial"))
    if record.name == "Text":
        filled = _filled(r)
        style = r.raw("textStyle")
        if style is None:
            styles = ()
        elif isinstance(style, list):
            styles = tuple(r.enum("textStyle", "TextStyle", "Bold", value=s) for s in style)
        else:
            raise r.error("textStyle", "must be an array {TextStyle.Bold, ...}", style)
        text = r.string("textString", r.string("string", ""))
        return Text(**filled, extent=r.extent("extent", required=True), text_string=text,
                    font_size=r.number("fontSize", 0.0), font_name=r.string("fontName"), text_style=styles,
                    text_color=r.color("textColor", filled["line_color"]),
                    horizontal_alignment=r.enum("horizontalAlignment", "TextAlignment", "Center"))
    return Bitmap(**_item(r), extent=r.extent("extent", required=True), file_name=r.string("fileName"),
                  image_source=r.string("imageSource"))


def coordinate_system(record, file: str, context: str) -> CoordinateSystem:
    """The ``coordinateSystem(...)`` of an Icon or Diagram annotation (corners ordered).

    Raises
    ------
    ModelicaError
        ``file:line`` of an extent without area or a malformed attribute.
    """
    if not isinstance(record, Record):
        raise ModelicaError(f"{file}: {context}coordinateSystem must be coordinateSystem(...), "
                            f"got {modelica_text(record)}")
    r = _Reader(record, file, context)
    (x1, y1), (x2, y2) = r.extent("extent", DEFAULT_EXTENT)
    if x1 == x2 or y1 == y2:
        raise r.error("extent", "must span an area", record.get("extent"))
    extent = ((min(x1, x2), min(y1, y2)), (max(x1, x2), max(y1, y2)))
    return CoordinateSystem(extent, r.boolean("preserveAspectRatio", True), r.number("initialScale", 0.1), True)


def transformation(record, file: str, context: str) -> Transformation:
    """A ``transformation(...)``/``iconTransformation(...)`` of a Placement.

    Raises
    ------
    ModelicaError
        ``file:line`` of a transformation without extent or with one of no width or height.
    """
    if not isinstance(record, Record):
        raise ModelicaError(f"{file}: {context}must be transformation(...), got {modelica_text(record)}")
    r = _Reader(record, file, context)
    old = [k for k in ("x", "y", "scale", "aspectRatio", "flipHorizontal", "flipVertical") if r.has(k)]
    if old:
        raise ModelicaError(f"{r.where}: {r.label}: '{old[0]}' is Modelica 1 graphics; "
                            "give extent, origin and rotation (MLS 18.4)")
    r.check_attributes(("origin", "extent", "rotation"))
    (x1, y1), (x2, y2) = extent = r.extent("extent", required=True)
    if x1 == x2 or y1 == y2:
        raise r.error("extent", "must have a width and a height", record.get("extent"))
    return Transformation(extent, r.point("origin", (0.0, 0.0)), r.number("rotation", 0.0))


def placement(record, file: str) -> Placement:
    """A component's ``Placement(...)``.

    Raises
    ------
    ModelicaError
        ``file:line`` of a malformed placement.
    """
    if not isinstance(record, Record):
        raise ModelicaError(f"{file}: Placement must be Placement(...), got {modelica_text(record)}")
    r = _Reader(record, file)
    visible = r.boolean("visible", True)
    found = {}
    for key in ("transformation", "iconTransformation"):
        if r.has(key):
            found[key] = transformation(r.raw(key), file, f"Placement.{key}: ")
    return Placement(visible, r.boolean("iconVisible", visible), found.get("transformation"),
                     found.get("iconTransformation"), r.where)


# --------------------------------------------------------------------------- the library's classes

class Graphics:
    """The graphical annotations of the classes of a library, inheritance resolved.

    Parameters
    ----------
    library : Library
        The parsed library; its class list decides which names exist and where they are
        defined (:meth:`Library.file_of`).
    """

    def __init__(self, library: Library):
        self.library = library
        self._layers: dict = {}
        self._components: dict = {}
        self._connections: dict = {}
        self._bindings: dict = {}
        self._active: set = set()

    # -- classes ---------------------------------------------------------------------------
    def exists(self, name: str) -> bool:
        """True if ``name`` is a class of the library (built-in types included)."""
        return name in self.library.entries

    def kind(self, name: str | None) -> str | None:
        """The kind of the class ``name`` (model, connector, ...), None if unknown."""
        entry = self.library.entries.get(name) if name else None
        return entry.kind if entry is not None else None

    def require(self, name: str) -> ClassDef:
        """The definition of the class ``name`` (the one a command names).

        Raises
        ------
        UnknownModelError
            If there is no such class (one line, with close names where there are some).
        ModelicaError
            If its file does not parse (``file:line:col``).
        """
        if not self.exists(name):
            broken = self.library.broken_error(name, user=name)
            if broken is not None:
                raise broken
            known = [n for n, e in self.library.entries.items() if e.file.suffix == ".mo"]
            close = difflib.get_close_matches(name, known, n=3, cutoff=0.6)
            hint = f"; did you mean {', '.join(close)}?" if close else \
                "; `cosim list` shows the models"
            where = ", ".join(map(str, self.library.paths))
            raise UnknownModelError(f"unknown class '{name}' in the Modelica library at {where}{hint}")
        return self.definition(name)

    def definition(self, name: str) -> ClassDef | None:
        """The definition of the class ``name`` in its file, None for a built-in type.

        Raises
        ------
        ModelicaError
            If its file does not parse (``file:line:col``).
        """
        entry = self.library.entries.get(name)
        if entry is None or entry.file.suffix != ".mo":
            return None
        if entry.file in self.library.errors:
            raise self.library.errors[entry.file]
        cls = find_class(parse_file(entry.file), name)
        if cls is None:
            raise ModelicaError(f"{entry.file}: does not define class '{name}'")
        return cls

    def lookup(self, name: str, scope: str) -> str | None:
        """The full name of the class ``name`` as written inside the class ``scope``, None if
        the library has none (MLS 5.3: the enclosing scopes from the innermost outwards; the
        first identifier decides)."""
        parts, first = scope.split(".") if scope else [], name.split(".")[0]
        for n in range(len(parts), -1, -1):
            if self.exists(".".join(parts[:n] + [first])):
                full = ".".join(parts[:n] + [name])
                return full if self.exists(full) else None
        return None

    def resolve(self, name: str, scope: str, user: str) -> str | None:
        """:meth:`lookup`, and the error of the file that defines the class if it does not parse.

        Raises
        ------
        ModelicaError
            If ``name`` is a class of a file of the library that does not parse (its
            ``file:line:col``, naming ``user``).
        """
        full = self.lookup(name, scope)
        if full is None:
            broken = self.library.broken_error(name, scope, user=user)
            if broken is not None:
                raise broken
        return full

    def bases(self, name: str) -> list:
        """``(full base name, Extends or None)`` of the class ``name``: its extends clauses and
        the class a short definition stands for (None where the library has no such class)."""
        cls = self.definition(name)
        if cls is None:
            return []
        scope = name.rsplit(".", 1)[0] if "." in name else ""
        found = [(self.resolve(e.name, name, name), e) for e in cls.extends]
        if cls.base is not None:
            found.append((self.resolve(cls.base, scope, name), Extends(cls.base, cls.line, cls.base_modifiers)))
        return found

    def _guard(self, key, where: str):
        if key in self._active:
            raise ModelicaError(f"{where}: class '{key[1]}' extends itself (through its base classes)")
        self._active.add(key)

    # -- layers ----------------------------------------------------------------------------
    def layer(self, name: str | None, which: str = "Icon") -> Layer:
        """The ``Icon`` or ``Diagram`` layer of the class ``name`` (bases' graphics first).

        Raises
        ------
        ModelicaError
            ``file:line`` of a malformed annotation, or a class that extends itself.
        """
        if name is None:
            return Layer()
        key = (which, name)
        if key in self._layers:
            return self._layers[key]
        cls = self.definition(name)
        if cls is None:
            return Layer()
        self._guard(key, cls.where)
        try:
            graphics, system = [], None
            for base, extends in self.bases(name):
                if base is None:
                    continue
                inherited = self.layer(base, which)
                mapping = extends.annotation.get(f"{which}Map") if extends.annotation else None
                if not (isinstance(mapping, Record) and mapping.get("primitivesVisible") is False):
                    graphics.extend(inherited.graphics)
                if system is None and inherited.coordinate_system.given:
                    system = inherited.coordinate_system
            own = cls.annotation.get(which) if cls.annotation is not None else None
            if own is not None:
                file = str(cls.source.file)
                if not isinstance(own, Record):
                    raise ModelicaError(f"{cls.annotation.where}: {which} must be {which}(...), "
                                        f"got {modelica_text(own)}")
                context = f"{which}: "
                if own.get("coordinateSystem") is not None:
                    system = coordinate_system(own.get("coordinateSystem"), file, context)
                items = own.get("graphics")
                if items is not None:
                    if isinstance(items, Record):
                        items = [items]
                    if not isinstance(items, list):
                        raise ModelicaError(f"{file}:{own.line}: {which}(graphics = {modelica_text(items)}): "
                                            "must be an array {Line(...), Rectangle(...), ...}")
                    graphics.extend(primitive(item, file, context) for item in items)
            result = Layer(system or CoordinateSystem(), tuple(graphics))
        finally:
            self._active.discard(key)
        self._layers[key] = result
        return result

    # -- components and connections --------------------------------------------------------
    def components(self, name: str | None) -> list:
        """The components of the class ``name`` (inherited ones first) as :class:`ComponentView`.

        Raises
        ------
        ModelicaError
            ``file:line`` of a malformed Placement.
        """
        if name is None:
            return []
        key = ("components", name)
        if key in self._components:
            return self._components[key]
        cls = self.definition(name)
        if cls is None:
            return []
        self._guard(key, cls.where)
        try:
            found: dict = {}
            for base, extends in self.bases(name):
                for view in self.components(base):
                    redeclared = extends.redeclares.get(view.name)
                    if redeclared is not None:
                        full = self.resolve(redeclared, name, name)
                        view = replace(view, type=full, type_text=redeclared, kind=self.kind(full))
                    found[view.name] = view
            file = str(cls.source.file)
            for c in cls.components:
                full = self.resolve(c.type, name, name)
                where = f"{file}:{c.line}"
                placed = None
                if c.annotation is not None and "Placement" in c.annotation:
                    placed = placement(c.annotation.get("Placement"), file)
                if placed is None and c.name in found and "redeclare" in c.prefixes:
                    placed = found[c.name].placement
                found[c.name] = ComponentView(c.name, full, c.type, self.kind(full), placed, dict(c.modifiers),
                                              c.prefixes, c.protected, where)
            result = list(found.values())
        finally:
            self._active.discard(key)
        self._components[key] = result
        return result

    def connections(self, name: str | None) -> list:
        """The ``connect`` equations of the class ``name`` (inherited ones first).

        Raises
        ------
        ModelicaError
            ``file:line`` of a malformed Line annotation.
        """
        if name is None:
            return []
        key = ("connections", name)
        if key in self._connections:
            return self._connections[key]
        cls = self.definition(name)
        if cls is None:
            return []
        self._guard(key, cls.where)
        try:
            result = []
            for base, _ in self.bases(name):
                result.extend(self.connections(base))
            file = str(cls.source.file)
            for c in cls.connections:
                line = None
                if c.annotation is not None and "Line" in c.annotation:
                    line = primitive(c.annotation.get("Line"), file, f"connect({c.a}, {c.b}): ")
                result.append(ConnectionView(c.a, c.b, line, f"{file}:{c.line}"))
        finally:
            self._active.discard(key)
        self._connections[key] = result
        return result

    def bindings(self, name: str | None) -> dict:
        """The values of the class's components as source text (declaration equations, then
        the modifiers of the extends clauses over the bases' values)."""
        if name is None:
            return {}
        key = ("bindings", name)
        if key in self._bindings:
            return self._bindings[key]
        cls = self.definition(name)
        if cls is None:
            return {}
        self._guard(key, cls.where)
        try:
            values: dict = {}
            for base, extends in self.bases(name):
                values.update(self.bindings(base))
                values.update(extends.modifiers)
            for c in cls.components:
                if c.binding is not None:
                    values[c.name] = c.binding
        finally:
            self._active.discard(key)
        self._bindings[key] = values
        return values
