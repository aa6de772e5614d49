"""A Modelica class's diagram or icon layer drawn as SVG (MLS chapter 18).

Coordinates: Modelica's y axis points up, SVG's down; every point is transformed here (``(x, y)``
of the layer becomes ``(x, -y)`` of the SVG), so the SVG holds no transform attributes except for
text rotation and bitmaps. The ``viewBox`` covers the layer's coordinate-system extent and
everything drawn.

The diagram layer of a class is

1. the graphics of its ``Diagram`` annotation (bases' first) and a light frame of its extent;
2. each component, in a group ``<g data-component="NAME">``: its class's icon (for a connector of
   the class itself: the connector class's diagram layer if it has one, MLS 18.6) mapped into the
   extent of its ``Placement``'s ``transformation`` (flipped where the extent's corners are
   reversed, rotated about its origin; MLS 18.4), with the connectors of that class at their own
   placements (``iconTransformation``, else ``transformation``) and its name: as the icon's
   ``%name`` text, else a label below it. A component without a Placement (whose class is a model,
   block or connector) is drawn at a default position in a grid (inside the extent if no
   component is placed, else below it), inside a dashed box; a class without graphics is drawn as
   a box with the name;
3. each ``connect`` in a group ``<g data-connect="A B">``: its ``Line`` annotation, or without one
   a thin grey straight line between the two connectors where their positions are known.

The icon layer is the ``Icon`` graphics and the public connectors at their icon placements.
Text: ``%name`` (the component's name), ``%class``, ``%%`` and ``%par``/``%{par}`` (the source
text of the parameter's modifier, else of its value in the class) are substituted; ``fontSize``
0 fits the text into its extent. Smooth lines are quadratic Bezier curves through the midpoints
of the segments. What the SVG title says: the layer, the class and what was drawn by default.
"""
from __future__ import annotations

import base64
import html
import math
import re
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlparse

from cosim.compiler.library import Library, load_library
from cosim.diagram.graphics import (DRAWN_KINDS, Bitmap, ComponentView, CoordinateSystem, Ellipse, Graphics,
                                    Layer, Line, Polygon, Rectangle, Text, Transformation)
from cosim.errors import OutputError
from cosim.outputs import check_output, write_text

#: The longer side of the SVG's default size [px].
PIXELS = 900.0
#: Icon nesting (connectors inside connectors ...) drawn at most.
MAX_DEPTH = 6
_DASHES = {"Dash": (4, 2), "Dot": (1, 2), "DashDot": (4, 2, 1, 2), "DashDotDot": (4, 2, 1, 2, 1, 2)}
_IMAGE_TYPES = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".gif": "image/gif",
                ".svg": "image/svg+xml", ".bmp": "image/bmp"}
_SUBSTITUTION = re.compile(r"%(%|\{([^}]*)\}|([A-Za-z_][A-Za-z0-9_]*))")


@dataclass(frozen=True)
class Affine:
    """The affine map ``(x, y) -> (a x + c y + e, b x + d y + f)``; ``m1 @ m2`` applies ``m2``
    first."""

    a: float = 1.0
    b: float = 0.0
    c: float = 0.0
    d: float = 1.0
    e: float = 0.0
    f: float = 0.0

    def __matmul__(self, o: Affine) -> Affine:
        return Affine(self.a * o.a + self.c * o.b, self.b * o.a + self.d * o.b,
                      self.a * o.c + self.c * o.d, self.b * o.c + self.d * o.d,
                      self.a * o.e + self.c * o.f + self.e, self.b * o.e + self.d * o.f + self.f)

    def __call__(self, point) -> tuple[float, float]:
        x, y = point
        return self.a * x + self.c * y + self.e, self.b * x + self.d * y + self.f

    def vector(self, v) -> tuple[float, float]:
        """The image of the vector ``v`` (no translation)."""
        return self.a * v[0] + self.c * v[1], self.b * v[0] + self.d * v[1]

    @property
    def scale(self) -> float:
        """The mean length scale, ``sqrt(|det|)``."""
        return math.sqrt(abs(self.a * self.d - self.b * self.c))

    @staticmethod
    def translate(x: float, y: float) -> Affine:
        """A translation by ``(x, y)``."""
        return Affine(e=x, f=y)

    @staticmethod
    def rotate(degrees: float) -> Affine:
        """A counterclockwise rotation (y up) by ``degrees``; multiples of 90 are exact."""
        quarter = degrees / 90.0
        if quarter == round(quarter):
            c, s = ((1, 0), (0, 1), (-1, 0), (0, -1))[int(round(quarter)) % 4]
        else:
            c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
        return Affine(c, s, -s, c)

    @staticmethod
    def scaling(sx: float, sy: float) -> Affine:
        """A scaling by ``sx`` along x and ``sy`` along y (negative: a flip)."""
        return Affine(sx, 0.0, 0.0, sy)


def placement_matrix(t: Transformation, system: CoordinateSystem) -> Affine:
    """The map from a class's coordinate system into its component's placement (MLS 18.4):
    scaled (uniformly if the class preserves its aspect ratio) and flipped so that the system's
    extent fills ``t.extent`` (reversed corners flip), rotated by ``t.rotation`` about zero, moved
    to ``t.origin``."""
    (cx1, cy1), (cx2, cy2) = system.extent
    (ex1, ey1), (ex2, ey2) = t.extent
    sx, sy = (ex2 - ex1) / (cx2 - cx1), (ey2 - ey1) / (cy2 - cy1)
    if system.preserve_aspect_ratio:
        m = min(abs(sx), abs(sy))
        sx, sy = math.copysign(m, sx), math.copysign(m, sy)
    centre = system.center
    return (Affine.translate(*t.origin) @ Affine.rotate(t.rotation)
            @ Affine.translate((ex1 + ex2) / 2, (ey1 + ey2) / 2) @ Affine.scaling(sx, sy)
            @ Affine.translate(-centre[0], -centre[1]))


@dataclass(frozen=True)
class Drawing:
    """An SVG drawing of a layer.

    Attributes
    ----------
    class_name : str
        The class drawn.
    layer : str
        ``diagram`` or ``icon``.
    svg : str
        The SVG document.
    title : str
        Its title: what was drawn and what was drawn by default.
    notes : tuple of str
        What was drawn by default or not at all (also in the title).
    components, connections : int
        How many components and connections were drawn.
    """

    class_name: str
    layer: str
    svg: str
    title: str
    notes: tuple
    components: int
    connections: int


@dataclass(frozen=True)
class _Names:
    """What ``%name``, ``%class`` and ``%par`` stand for in one icon."""

    name: str
    class_name: str
    values: dict

    def substitute(self, text: str) -> str:
        def one(match: re.Match) -> str:
            if match.group(1) == "%":
                return "%"
            key = match.group(2) if match.group(2) is not None else match.group(3)
            if key == "name":
                return self.name
            if key == "class":
                return self.class_name
            return self.values.get(key, match.group(0))

        return _SUBSTITUTION.sub(one, text)


def _num(v: float) -> str:
    text = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _xy(p) -> str:
    return f"{_num(p[0])},{_num(-p[1])}"


def _rgb(color) -> str:
    return f"rgb({color[0]},{color[1]},{color[2]})"


def _attr(text: str) -> str:
    return html.escape(text, quote=True)


def _polyline(points, closed: bool) -> str:
    d = "M" + " L".join(_xy(p) for p in points)
    return d + " Z" if closed else d


def _bezier(points, closed: bool) -> str:
    """Quadratic Bezier segments through the midpoints of the segments, the points as control
    points (as the tools draw ``Smooth.Bezier``)."""
    mid = [((p[0] + q[0]) / 2, (p[1] + q[1]) / 2) for p, q in zip(points, points[1:] + points[:1])]
    if closed:
        d = f"M{_xy(mid[-1])}"
        for p, m in zip(points, mid):
            d += f" Q{_xy(p)} {_xy(m)}"
        return d + " Z"
    d = f"M{_xy(points[0])} L{_xy(mid[0])}"
    for p, m in zip(points[1:-1], mid[1:-1]):
        d += f" Q{_xy(p)} {_xy(m)}"
    return d + f" L{_xy(points[-1])}"


class _Painter:
    """Collects the SVG elements of one drawing, its definitions and the extent of what is
    drawn."""

    def __init__(self, graphics: Graphics, unit: float):
        self.graphics, self.unit = graphics, unit
        self.body: list[str] = []
        self.defs: dict = {}
        self.box = [math.inf, math.inf, -math.inf, -math.inf]
        self.notes: dict = {}

    def note(self, key: str, item: str) -> None:
        self.notes.setdefault(key, []).append(item)

    def include(self, points) -> None:
        for x, y in points:
            self.box = [min(self.box[0], x), min(self.box[1], y), max(self.box[2], x), max(self.box[3], y)]

    def add(self, element: str) -> None:
        self.body.append(element)

    # -- styles ----------------------------------------------------------------------------
    def stroke(self, color, pattern: str, thickness: float) -> str:
        if pattern == "None":
            return 'stroke="none"'
        width = max(thickness, 0.25) * self.unit
        text = (f'stroke="{_rgb(color)}" stroke-width="{_num(width)}" stroke-linejoin="round" '
                'stroke-linecap="round"')
        if pattern in _DASHES:
            scale = self.unit * max(1.0, thickness / 0.25)
            text += f' stroke-dasharray="{" ".join(_num(v * scale) for v in _DASHES[pattern])}"'
        return text

    def fill(self, shape, m: Affine, extent) -> str:
        pattern = shape.fill_pattern
        if pattern == "None":
            return 'fill="none"'
        if pattern == "Solid":
            return f'fill="{_rgb(shape.fill_color)}"'
        (x1, y1), (x2, y2) = extent
        cx, cy = (x1 + x2) / 2, (y1 + y2) / 2
        line, fill = _rgb(shape.line_color), _rgb(shape.fill_color)
        if pattern in ("HorizontalCylinder", "VerticalCylinder"):
            a, b = ((cx, max(y1, y2)), (cx, min(y1, y2))) if pattern == "HorizontalCylinder" else \
                ((min(x1, x2), cy), (max(x1, x2), cy))
            (ax, ay), (bx, by) = m(a), m(b)
            body = (f'x1="{_num(ax)}" y1="{_num(-ay)}" x2="{_num(bx)}" y2="{_num(-by)}" gradientUnits="userSpaceOnUse">'
                    f'<stop offset="0" stop-color="{line}"/><stop offset="0.5" stop-color="{fill}"/>'
                    f'<stop offset="1" stop-color="{line}"/>')
            return f'fill="url(#{self.definition("linearGradient", body)})"'
        if pattern == "Sphere":
            (px, py) = m((cx, cy))
            radius = max(math.hypot(*m.vector(((x2 - x1) / 2, 0))), math.hypot(*m.vector((0, (y2 - y1) / 2))))
            body = (f'cx="{_num(px)}" cy="{_num(-py)}" r="{_num(radius)}" gradientUnits="userSpaceOnUse">'
                    f'<stop offset="0" stop-color="{fill}"/><stop offset="1" stop-color="{line}"/>')
            return f'fill="url(#{self.definition("radialGradient", body)})"'
        s = 2.5 * self.unit
        body = (f'patternUnits="userSpaceOnUse" width="{_num(s)}" height="{_num(s)}">'
                f'<path d="{_hatch(pattern, s)}" stroke="{fill}" stroke-width="{_num(0.3 * self.unit)}" fill="none"/>')
        return f'fill="url(#{self.definition("pattern", body)})"'

    def definition(self, tag: str, body: str) -> str:
        key = (tag, body)
        if key not in self.defs:
            self.defs[key] = f"d{len(self.defs) + 1}"
        return self.defs[key]

    def defs_text(self) -> str:
        if not self.defs:
            return ""
        items = "".join(f'<{tag} id="{ident}" {body}</{tag}>' for (tag, body), ident in self.defs.items())
        return f"<defs>{items}</defs>"

    # -- primitives ------------------------------------------------------------------------
    def primitive(self, item, m: Affine, names: _Names) -> None:
        if not item.visible:
            return
        m = m @ Affine.translate(*item.origin) @ Affine.rotate(item.rotation)
        if isinstance(item, Line):
            self.line(item, m)
        elif isinstance(item, Polygon):
            points = [m(p) for p in item.points]
            if points[0] == points[-1] and len(points) > 3:
                points = points[:-1]
            self.shape(item, m, points, item.smooth == "Bezier", _bounds(item.points))
        elif isinstance(item, Rectangle):
            self.shape(item, m, [m(p) for p in _rectangle(item.extent, item.radius)], False, item.extent)
        elif isinstance(item, Ellipse):
            self.ellipse(item, m)
        elif isinstance(item, Text):
            self.text(item, m, names)
        elif isinstance(item, Bitmap):
            self.bitmap(item, m)

    def line(self, item: Line, m: Affine) -> None:
        points = [m(p) for p in item.points]
        self.include(points)
        d = _bezier(points, False) if item.smooth == "Bezier" and len(points) > 2 else _polyline(points, False)
        stroke = self.stroke(item.color, item.pattern, item.thickness)
        self.add(f'<path d="{d}" fill="none" {stroke}/>')
        size = item.arrow_size * m.scale
        for kind, tip, before in ((item.arrow[0], points[0], points[1]), (item.arrow[1], points[-1], points[-2])):
            if kind != "None" and item.pattern != "None":
                self.arrow(kind, tip, before, size, item.color, item.thickness)

    def arrow(self, kind: str, tip, before, size: float, color, thickness: float) -> None:
        dx, dy = tip[0] - before[0], tip[1] - before[1]
        length = math.hypot(dx, dy)
        if length == 0 or size <= 0:
            return
        ux, uy = dx / length, dy / length
        base = (tip[0] - ux * size, tip[1] - uy * size)
        left = (base[0] - uy * size / 3, base[1] + ux * size / 3)
        right = (base[0] + uy * size / 3, base[1] - ux * size / 3)
        stroke = self.stroke(color, "Solid", thickness)
        if kind == "Filled":
            self.add(f'<path d="{_polyline([tip, left, right], True)}" fill="{_rgb(color)}" {stroke}/>')
        elif kind == "Open":
            self.add(f'<path d="{_polyline([left, tip, right], False)}" fill="none" {stroke}/>')
        else:  # Half
            self.add(f'<path d="{_polyline([left, tip], False)}" fill="none" {stroke}/>')
        self.include([left, right])

    def shape(self, item, m: Affine, points, smooth: bool, extent) -> None:
        self.include(points)
        d = _bezier(points, True) if smooth else _polyline(points, True)
        self.add(f'<path d="{d}" {self.fill(item, m, extent)} '
                 f'{self.stroke(item.line_color, item.pattern, item.line_thickness)}/>')

    def ellipse(self, item: Ellipse, m: Affine) -> None:
        (x1, y1), (x2, y2) = item.extent
        cx, cy, rx, ry = (x1 + x2) / 2, (y1 + y2) / 2, abs(x2 - x1) / 2, abs(y2 - y1) / 2
        start, end = item.start_angle, item.end_angle
        if end < start:
            end += 360 * math.ceil((start - end) / 360)
        sweep = min(end - start, 360.0)
        steps = max(8, int(math.ceil(sweep / 4)))
        local = [(cx + rx * math.cos(math.radians(start + sweep * k / steps)),
                  cy + ry * math.sin(math.radians(start + sweep * k / steps))) for k in range(steps + 1)]
        full = sweep >= 360
        if full:
            local = local[:-1]
        elif item.closure == "Radial":
            local.append((cx, cy))
        points = [m(p) for p in local]
        self.include(points)
        closed = full or item.closure != "None"
        fill = self.fill(item, m, item.extent) if closed else 'fill="none"'
        self.add(f'<path d="{_polyline(points, closed)}" {fill} '
                 f'{self.stroke(item.line_color, item.pattern, item.line_thickness)}/>')

    def text(self, item: Text, m: Affine, names: _Names) -> None:
        text = names.substitute(item.text_string)
        if not text.strip():
            return
        (x1, y1), (x2, y2) = item.extent
        cx, cy = (x1 + x2) / 2, (y1 + y2) / 2
        centre = m((cx, cy))
        ex = m.vector((abs(x2 - x1), 0.0))
        ey = m.vector((0.0, abs(y2 - y1)))
        width, height = math.hypot(*ex), math.hypot(*ey)
        if width == 0 or height == 0:
            return
        angle = math.degrees(math.atan2(ex[1], ex[0]))
        if angle > 90.0001 or angle <= -90.0001:  # keep text readable: never upside down
            angle += 180 if angle <= 0 else -180
        direction = (math.cos(math.radians(angle)), math.sin(math.radians(angle)))
        lines = text.split("\n")
        longest = max(len(line) for line in lines)
        if item.font_size > 0:
            size = item.font_size * m.scale
        else:
            size = min(height / len(lines), width / (0.6 * max(longest, 1)))
        anchor, offset = {"Left": ("start", -width / 2), "Right": ("end", width / 2)}.get(
            item.horizontal_alignment, ("middle", 0.0))
        x, y = centre[0] + direction[0] * offset, centre[1] + direction[1] * offset
        corners = [m(p) for p in ((x1, y1), (x1, y2), (x2, y1), (x2, y2))]
        self.include(corners)
        style = ""
        if "Bold" in item.text_style:
            style += ' font-weight="bold"'
        if "Italic" in item.text_style:
            style += ' font-style="italic"'
        if "UnderLine" in item.text_style:
            style += ' text-decoration="underline"'
        if item.font_name:
            style += f' font-family="{_attr(item.font_name)}, sans-serif"'
        rotate = f' transform="rotate({_num(-angle)} {_num(x)} {_num(-y)})"' if abs(angle) > 1e-9 else ""
        if len(lines) == 1:
            content = html.escape(text)
            ty = y
        else:  # centred on the extent, one line under the other
            ty = y + size * (len(lines) - 1) / 2
            content = "".join(f'<tspan x="{_num(x)}" dy="{_num(size if k else 0)}">{html.escape(line)}</tspan>'
                              for k, line in enumerate(lines))
        self.add(f'<text x="{_num(x)}" y="{_num(-ty)}" font-size="{_num(size)}" text-anchor="{anchor}" '
                 f'dominant-baseline="central" fill="{_rgb(item.text_color)}"{style}{rotate}>{content}</text>')

    def bitmap(self, item: Bitmap, m: Affine) -> None:
        (x1, y1), (x2, y2) = item.extent
        xmin, xmax, ymin, ymax = min(x1, x2), max(x1, x2), min(y1, y2), max(y1, y2)
        uri = self.image(item)
        corners = [m(p) for p in ((xmin, ymin), (xmin, ymax), (xmax, ymax), (xmax, ymin))]
        self.include(corners)
        if uri is None:
            self.note("bitmap", item.file_name or item.where)
            self.add(f'<path d="{_polyline(corners, True)}" fill="none" stroke="#a0a0a0" '
                     f'stroke-width="{_num(0.25 * self.unit)}" stroke-dasharray="{_num(self.unit)}"/>')
            return
        unit_square = Affine(xmax - xmin, 0.0, 0.0, -(ymax - ymin), xmin, ymax)
        t = Affine(1.0, 0.0, 0.0, -1.0) @ m @ unit_square
        matrix = " ".join(_num(v) if abs(v) >= 1e-3 else f"{v:.6g}" for v in (t.a, t.b, t.c, t.d, t.e, t.f))
        self.add(f'<image x="0" y="0" width="1" height="1" preserveAspectRatio="none" '
                 f'transform="matrix({matrix})" href="{_attr(uri)}"/>')

    def image(self, item: Bitmap) -> str | None:
        if item.image_source:
            return "data:image/png;base64," + "".join(item.image_source.split())
        parsed = urlparse(item.file_name)
        if parsed.scheme != "modelica" or not parsed.netloc:
            return None
        parts = parsed.netloc.split(".") + [p for p in unquote(parsed.path).split("/") if p]
        for root in self.graphics.library.paths:
            file = root.joinpath(*parts)
            if file.is_file() and file.suffix.lower() in _IMAGE_TYPES:
                data = base64.b64encode(file.read_bytes()).decode("ascii")
                return f"data:{_IMAGE_TYPES[file.suffix.lower()]};base64,{data}"
        return None

    # -- icons -----------------------------------------------------------------------------
    def icon(self, type_name: str | None, m: Affine, names: _Names, depth: int, which: str = "Icon") -> tuple:
        """Draw the class's layer ``which`` and its public connectors; ``(drew anything, the
        graphics show %name)``."""
        layer = self.graphics.layer(type_name, which)
        for item in layer.graphics:
            self.primitive(item, m, names)
        named = any(isinstance(g, Text) and g.visible and "%name" in g.text_string for g in layer.graphics)
        drawn = bool(layer.graphics)
        if depth >= MAX_DEPTH:
            return drawn, named
        for c in self.graphics.components(type_name):
            if c.protected or not c.is_connector or c.placement is None:
                continue
            t = c.placement.for_icon()
            if t is None or not c.placement.icon_visible:
                continue
            system = self.graphics.layer(c.type, "Icon").coordinate_system
            self.add(f'<g class="connector" data-connector="{_attr(c.name)}">')
            sub = _Names(c.name, _short(c.type or c.type_text), self.values(c))
            inner, _ = self.icon(c.type, m @ placement_matrix(t, system), sub, depth + 1)
            if not inner:
                self.placeholder(m @ placement_matrix(t, system), system)
            self.add("</g>")
            drawn = True
        return drawn, named

    def values(self, c: ComponentView) -> dict:
        return {**self.graphics.bindings(c.type), **c.modifiers}

    def placeholder(self, m: Affine, system: CoordinateSystem) -> None:
        """A box over the class's extent (for a class that has no graphics)."""
        (x1, y1), (x2, y2) = system.extent
        corners = [m(p) for p in ((x1, y1), (x1, y2), (x2, y2), (x2, y1))]
        self.include(corners)
        self.add(f'<path class="placeholder" d="{_polyline(corners, True)}" fill="#f2f2f2" stroke="#606060" '
                 f'stroke-width="{_num(0.3 * self.unit)}"/>')

    def label(self, text: str, corners, inside: bool = False) -> None:
        """The component's name, below its box (or inside it), upright."""
        xs, ys = [p[0] for p in corners], [p[1] for p in corners]
        width, height = max(xs) - min(xs), max(ys) - min(ys)
        size = min(max(0.25 * min(width, height), 2.5 * self.unit), 5 * self.unit)
        if inside:  # fits the box's width
            size = min(size, 0.9 * width / (0.6 * max(len(text), 1)))
        x = (min(xs) + max(xs)) / 2
        y = (min(ys) + max(ys)) / 2 if inside else min(ys) - 0.8 * size
        self.include([(x - 0.3 * size * len(text), y - size / 2), (x + 0.3 * size * len(text), y + size / 2)])
        self.add(f'<text class="name" x="{_num(x)}" y="{_num(-y)}" font-size="{_num(size)}" text-anchor="middle" '
                 f'dominant-baseline="central" fill="#202020">{html.escape(text)}</text>')


def _hatch(pattern: str, s: float) -> str:
    """The lines of one tile (``s`` wide, SVG coordinates) of a hatched fill."""
    horizontal, vertical = [((0, s / 2), (s, s / 2))], [((s / 2, 0), (s / 2, s))]
    # a diagonal and its two neighbours' ends, so that the tiles join
    forward = [((0, s), (s, 0)), ((-s / 4, s / 4), (s / 4, -s / 4)), ((3 * s / 4, 5 * s / 4), (5 * s / 4, 3 * s / 4))]
    backward = [((0, 0), (s, s)), ((-s / 4, 3 * s / 4), (s / 4, 5 * s / 4)), ((3 * s / 4, -s / 4), (5 * s / 4, s / 4))]
    segments = {"Horizontal": horizontal, "Vertical": vertical, "Cross": horizontal + vertical, "Forward": forward,
                "Backward": backward, "CrossDiag": forward + backward}[pattern]
    return " ".join(f"M{_num(a[0])},{_num(a[1])} L{_num(b[0])},{_num(b[1])}" for a, b in segments)


def _short(name: str) -> str:
    return name.rsplit(".", 1)[-1]


def _bounds(points) -> tuple:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return (min(xs), min(ys)), (max(xs), max(ys))


def _rectangle(extent, radius: float) -> list:
    (x1, y1), (x2, y2) = extent
    xmin, xmax, ymin, ymax = min(x1, x2), max(x1, x2), min(y1, y2), max(y1, y2)
    r = min(radius, (xmax - xmin) / 2, (ymax - ymin) / 2)
    if r <= 0:
        return [(xmin, ymin), (xmin, ymax), (xmax, ymax), (xmax, ymin)]
    points = []
    for (cx, cy), start in (((xmax - r, ymax - r), 0), ((xmin + r, ymax - r), 90), ((xmin + r, ymin + r), 180),
                            ((xmax - r, ymin + r), 270)):
        points += [(cx + r * math.cos(math.radians(start + 15 * k)), cy + r * math.sin(math.radians(start + 15 * k)))
                   for k in range(7)]
    return points


def _path_parts(reference: str) -> list:
    """``a[1].b`` -> ``["a", "b"]``."""
    return [re.sub(r"\[.*?\]", "", part) for part in re.split(r"\.(?![^\[]*\])", reference)]


def _default_positions(count: int, system: CoordinateSystem, unit: float, below: bool) -> list:
    """Transformations on a grid, 40 units (of a 200-unit extent) apart, 20 units wide: from the
    upper left of the extent, or with ``below`` (where other components are placed) in rows
    under the extent, clear of them."""
    (x1, y1), (x2, y2) = system.extent
    cell, half = 40 * unit, 10 * unit
    columns = max(1, int((x2 - x1) // cell))
    top = y1 - 5 * unit if below else y2
    return [Transformation(((-half, -half), (half, half)),
                           (x1 + cell * (k % columns + 0.5), top - cell * (k // columns + 0.5)))
            for k in range(count)]


def _drawn_unplaced(c: ComponentView) -> bool:
    return c.kind in DRAWN_KINDS and not ({"parameter", "constant"} & set(c.prefixes))


def draw(class_name: str, icon: bool = False, library: Library | None = None) -> Drawing:
    """The diagram layer (or with ``icon`` the icon layer) of ``class_name`` as SVG.

    Parameters
    ----------
    class_name : str
        Full name of a class of the library, e.g. ``Bicycle.Bicycles.Whipple``.
    icon : bool
        Draw the icon layer instead of the diagram layer.
    library : Library, optional
        Default: the library of ``--library`` / ``COSIM_MODELICA_PATH`` (parsed once per process).

    Returns
    -------
    Drawing
        The SVG document and what was drawn.

    Raises
    ------
    UnknownModelError
        If the library has no class ``class_name``.
    ModelicaError
        ``file:line`` of a malformed annotation, or of a file that does not parse.
    """
    library = library or load_library()
    graphics = Graphics(library)
    graphics.require(class_name)
    which = "Icon" if icon else "Diagram"
    layer: Layer = graphics.layer(class_name, which)
    system = layer.coordinate_system
    (x1, y1), (x2, y2) = system.extent
    unit = max(x2 - x1, y2 - y1) / 200.0
    painter = _Painter(graphics, unit)
    painter.include(system.extent)
    painter.add(f'<rect class="extent" x="{_num(x1)}" y="{_num(-y2)}" width="{_num(x2 - x1)}" '
                f'height="{_num(y2 - y1)}" fill="none" stroke="#d8d8d8" stroke-width="{_num(0.3 * unit)}"/>')
    own = _Names(_short(class_name), _short(class_name), graphics.bindings(class_name))
    painter.add(f'<g class="layer" data-layer="{which.lower()}">')
    for item in layer.graphics:
        painter.primitive(item, Affine(), own)
    painter.add("</g>")
    components = graphics.components(class_name)
    if icon:
        drawn, connections = _draw_icon_connectors(painter, components), 0
    else:
        drawn, connections = _draw_diagram(painter, class_name, components, system)
    notes = tuple(_notes(painter.notes))
    title = f"{which} layer of {class_name}" + (": " + "; ".join(notes) if notes else "")
    svg = _document(painter, title, class_name, which.lower())
    return Drawing(class_name, which.lower(), svg, title, notes, drawn, connections)


def _draw_icon_connectors(painter: _Painter, components: list) -> int:
    drawn = 0
    for c in components:
        if c.protected or not c.is_connector:
            continue
        t = c.placement.for_icon() if c.placement is not None else None
        if t is None:
            painter.note("no-icon-placement", c.name)
            continue
        if not (c.placement.visible and c.placement.icon_visible):
            continue
        system = painter.graphics.layer(c.type, "Icon").coordinate_system
        m = placement_matrix(t, system)
        painter.add(f'<g data-component="{_attr(c.name)}" data-class="{_attr(c.type or c.type_text)}">'
                    f'<title>{html.escape(c.name)}: {html.escape(c.type or c.type_text)}</title>')
        inner, _ = painter.icon(c.type, m, _Names(c.name, _short(c.type or c.type_text), painter.values(c)), 1)
        if not inner:
            painter.placeholder(m, system)
            (x1, y1), (x2, y2) = system.extent
            painter.label(c.name, [m(p) for p in ((x1, y1), (x1, y2), (x2, y2), (x2, y1))], inside=True)
        painter.add("</g>")
        drawn += 1
    return drawn


def _draw_diagram(painter: _Painter, class_name: str, components: list, system: CoordinateSystem) -> tuple:
    graphics = painter.graphics
    placed, unplaced = [], []
    for c in components:
        if c.placement is not None and c.placement.transformation is not None:
            if c.placement.visible:
                placed.append((c, c.placement.transformation, False))
        elif (c.placement is None or c.placement.visible) and _drawn_unplaced(c):  # no transformation
            unplaced.append(c)
    positions = _default_positions(len(unplaced), system, painter.unit, below=bool(placed))
    placed += [(c, t, True) for c, t in zip(unplaced, positions)]
    where: dict = {}  # component name -> (matrix, its class, its coordinate system)
    for c, t, default in placed:
        which = "Diagram" if c.is_connector and graphics.layer(c.type, "Diagram").graphics else "Icon"
        own_system = graphics.layer(c.type, which).coordinate_system
        m = placement_matrix(t, own_system)
        where[c.name] = (m, c, own_system)
        type_text = c.type or c.type_text
        painter.add(f'<g data-component="{_attr(c.name)}" data-class="{_attr(type_text)}"'
                    + (' class="unplaced"' if default else "") + f'><title>{html.escape(c.name)}: '
                    f'{html.escape(type_text)}{" (no Placement: default position)" if default else ""}</title>')
        corners = [m(p) for p in (own_system.extent[0], (own_system.extent[0][0], own_system.extent[1][1]),
                                  own_system.extent[1], (own_system.extent[1][0], own_system.extent[0][1]))]
        if default:
            painter.note("unplaced", c.name)
            painter.add(f'<path d="{_polyline(corners, True)}" fill="none" stroke="#909090" '
                        f'stroke-width="{_num(0.25 * painter.unit)}" stroke-dasharray="{_num(painter.unit)}"/>')
        if c.type is None:
            painter.note("unknown-class", f"{c.name} ({c.type_text})")
        drew, named = painter.icon(c.type, m, _Names(c.name, _short(type_text), painter.values(c)), 1, which)
        if not drew:
            painter.placeholder(m, own_system)
            painter.label(c.name, corners, inside=True)
        elif not named:
            painter.label(c.name, corners)
        painter.add("</g>")
    connections = 0
    for conn in graphics.connections(class_name):
        painter.add(f'<g data-connect="{_attr(conn.a)} {_attr(conn.b)}"><title>connect({html.escape(conn.a)}, '
                    f'{html.escape(conn.b)})</title>')
        if conn.line is not None:
            painter.primitive(conn.line, Affine(), _Names("", "", {}))
            connections += 1
        else:
            ends = [_connector_point(graphics, where, ref) for ref in (conn.a, conn.b)]
            if None in ends:
                painter.note("not-drawn", f"{conn.a}, {conn.b}")
            else:
                painter.note("straight", f"{conn.a}, {conn.b}")
                painter.add(f'<path class="default-route" d="{_polyline(ends, False)}" fill="none" stroke="#808080" '
                            f'stroke-width="{_num(0.25 * painter.unit)}"/>')
                connections += 1
        painter.add("</g>")
    return len(placed), connections


def _connector_point(graphics: Graphics, where: dict, reference: str):
    """Where the connector ``reference`` (``a.b`` or ``a``) is drawn: the centre of its
    placement inside its component, else the component's centre; None if not drawn."""
    parts = _path_parts(reference)
    found = where.get(parts[0])
    if found is None:
        return None
    m, c, system = found
    if len(parts) > 1:
        for sub in graphics.components(c.type):
            if sub.name == parts[1] and sub.placement is not None and sub.placement.for_icon() is not None:
                sub_system = graphics.layer(sub.type, "Icon").coordinate_system
                return (m @ placement_matrix(sub.placement.for_icon(), sub_system))(sub_system.center)
    return m(system.center)


_NOTES = {
    "unplaced": "{n} component(s) without a Placement annotation, drawn as labelled boxes at default positions "
                "({items})",
    "straight": "{n} connection(s) without a Line annotation, drawn straight between their connectors",
    "not-drawn": "{n} connection(s) without a Line annotation between connectors not drawn ({items})",
    "unknown-class": "{n} component(s) of classes not in the library, drawn as boxes ({items})",
    "no-icon-placement": "{n} public connector(s) without a Placement annotation, not drawn ({items})",
    "bitmap": "{n} bitmap(s) not found, drawn as outlines ({items})",
}


def _notes(found: dict) -> list:
    return [_NOTES[key].format(n=len(items), items=", ".join(dict.fromkeys(items)))
            for key, items in found.items()]


def _document(painter: _Painter, title: str, class_name: str, layer: str) -> str:
    x1, y1, x2, y2 = painter.box
    margin = 0.03 * max(x2 - x1, y2 - y1)
    x1, y1, x2, y2 = x1 - margin, y1 - margin, x2 + margin, y2 + margin
    width, height = x2 - x1, y2 - y1
    scale = PIXELS / max(width, height)
    view = f"{_num(x1)} {_num(-y2)} {_num(width)} {_num(height)}"
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}" width="{_num(width * scale)}" '
            f'height="{_num(height * scale)}" font-family="sans-serif" data-class="{_attr(class_name)}" '
            f'data-layer="{layer}">\n<title>{html.escape(title)}</title>\n{painter.defs_text()}\n'
            f'<rect class="background" x="{_num(x1)}" y="{_num(-y2)}" width="{_num(width)}" '
            f'height="{_num(height)}" fill="white"/>\n' + "\n".join(painter.body) + "\n</svg>\n")


def default_output(class_name: str, icon: bool = False) -> Path:
    """``<class name with _>.svg`` (``-icon.svg`` for the icon) in the working directory."""
    return Path(class_name.replace(".", "_") + ("-icon.svg" if icon else ".svg"))


def write_diagram(class_name: str, output: str | Path | None = None, icon: bool = False,
                  library: Library | None = None) -> tuple[Path, Drawing]:
    """Draw ``class_name`` (:func:`draw`) and write the SVG to ``output`` atomically.

    Returns
    -------
    (Path, Drawing)
        The file written and the drawing.

    Raises
    ------
    OutputError
        If ``output`` does not end in ``.svg`` or cannot be written (checked before drawing).
    UnknownModelError, ModelicaError
        As :func:`draw`.
    """
    path = Path(output) if output is not None else default_output(class_name, icon)
    if path.suffix.lower() != ".svg":
        raise OutputError(f"output file '{path}': must end in .svg")
    check_output(path, "SVG file")
    drawing = draw(class_name, icon=icon, library=library)
    write_text(path, drawing.svg, "SVG file")
    return path, drawing
