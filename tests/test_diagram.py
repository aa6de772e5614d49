"""`cosim diagram`: the annotation parser (cosim/diagram/annotations.py), the chapter-18 objects
with inheritance (cosim/diagram/graphics.py) and the SVG (cosim/diagram/svg.py), on small
libraries written into ``tmp_path`` and on the real library."""
from __future__ import annotations

import functools
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from pymoca import parser

from conftest import run_cli
from test_pymoca_patches import _library
from cosim.compiler.library import Library
from cosim.diagram.annotations import Expression, Name, Record, parse_expression, parse_text, Source
from cosim.diagram.graphics import Graphics, Line, Polygon, Text
from cosim.diagram.svg import Affine, draw, placement_matrix
from cosim.errors import ModelicaError, UnknownModelError

SVG = "{http://www.w3.org/2000/svg}"
ROOT = Path(__file__).resolve().parents[1]


# A library that uses every primitive, inheritance, %name / %par, flipped and rotated placements,
# connectors on icons and connection lines.
GFX = {
    "Gfx/package.mo": """
        package Gfx "graphics test library"
        end Gfx;
    """,
    "Gfx/package.order": "Interfaces\nPartialBlock\nGain\nShapes\nSystem\nPlain\n",
    "Gfx/Interfaces/package.mo": """
        within Gfx;
        package Interfaces "connectors"
          connector RealInput = input Real "input signal"
            annotation(Icon(coordinateSystem(extent = {{-100, -100}, {100, 100}}, preserveAspectRatio = true),
              graphics = {Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}}, lineColor = {0, 0, 127},
                                  fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid)}));
          connector RealOutput = output Real "output signal"
            annotation(Icon(graphics = {Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}},
                                                lineColor = {0, 0, 127}, fillColor = {255, 255, 255},
                                                fillPattern = FillPattern.Solid)}));
        end Interfaces;
    """,
    "Gfx/PartialBlock.mo": """
        within Gfx;
        partial block PartialBlock "one input, one output"
          Interfaces.RealInput u "input" annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
          Interfaces.RealOutput y "output" annotation(Placement(transformation(extent = {{100, -20}, {140, 20}}),
                                                                iconTransformation(extent = {{100, -10}, {120, 10}})));
          annotation(Icon(coordinateSystem(extent = {{-100, -100}, {100, 100}}), graphics = {
            Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255},
                      fillPattern = FillPattern.Solid),
            Text(extent = {{-150, 150}, {150, 110}}, textString = "%name", textColor = {0, 0, 255})}));
        end PartialBlock;
    """,
    "Gfx/Gain.mo": """
        within Gfx;
        block Gain "y = k*u"
          extends PartialBlock;
          parameter Real k = 2 "gain";
        equation
          y = k*u;
          annotation(Icon(graphics = {
            Polygon(points = {{-100, -100}, {-100, 100}, {100, 0}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127},
                    fillPattern = FillPattern.None),
            Text(extent = {{-150, -140}, {150, -100}}, textString = "k=%k")}));
        end Gain;
    """,
    "Gfx/Shapes.mo": """
        within Gfx;
        model Shapes "every primitive"
          annotation(Diagram(coordinateSystem(extent = {{-200, -100}, {200, 100}}, preserveAspectRatio = false),
            graphics = {
              Line(points = {{-180, 80}, {-120, 80}}, color = {255, 0, 0}, thickness = 0.5,
                   arrow = {Arrow.None, Arrow.Filled}),
              Line(points = {{-180, 60}, {-150, 40}, {-120, 60}}, pattern = LinePattern.Dash, smooth = Smooth.Bezier),
              Rectangle(extent = {{-100, 90}, {-40, 40}}, radius = 10, lineColor = {0, 128, 0},
                        fillColor = {200, 255, 200}, fillPattern = FillPattern.Solid, pattern = LinePattern.Dot),
              Rectangle(extent = {{-30, 90}, {30, 40}}, fillColor = {0, 0, 255}, fillPattern = FillPattern.Forward),
              Rectangle(extent = {{40, 90}, {100, 40}}, lineColor = {80, 80, 80}, fillColor = {220, 220, 220},
                        fillPattern = FillPattern.HorizontalCylinder),
              Ellipse(extent = {{110, 90}, {170, 40}}, fillColor = {255, 255, 0}, fillPattern = FillPattern.Sphere),
              Ellipse(extent = {{-180, 20}, {-120, -40}}, startAngle = 0, endAngle = 90, fillColor = {255, 0, 255},
                      fillPattern = FillPattern.Solid),
              Polygon(points = {{-100, 20}, {-40, 20}, {-70, -40}}, fillColor = {0, 255, 255},
                      fillPattern = FillPattern.Solid, origin = {0, 0}, rotation = 0),
              Text(extent = {{-20, 20}, {100, -20}}, textString = "left aligned",
                   horizontalAlignment = TextAlignment.Left, textStyle = {TextStyle.Bold}),
              Text(extent = {{-30, -10}, {30, 10}}, textString = "turned", origin = {150, -10}, rotation = 90),
              Line(points = {{0, 0}, {40, 0}}, origin = {-20, -80}, rotation = 90, visible = true),
              Line(points = {{0, 0}, {40, 0}}, origin = {60, -80}, visible = false)}));
        end Shapes;
    """,
    "Gfx/System.mo": """
        within Gfx;
        model System "placed, flipped, rotated components"
          Gain gain1 annotation(Placement(transformation(extent = {{-70, -10}, {-50, 10}})));
          Gfx.Gain gain2(k = 5) "flipped" annotation(Placement(transformation(extent = {{40, -10}, {20, 10}})));
          Gain gain3 annotation(Placement(transformation(extent = {{-10, -10}, {10, 10}}, rotation = 90,
                                                            origin = {0, 50})));
          Plain plain annotation(Placement(transformation(extent = {{60, -50}, {80, -30}})));
          Gain hidden annotation(Placement(visible = false, transformation(extent = {{60, 60}, {80, 80}})));
          Gain loose "no placement";
          parameter Real p = 1 "not drawn";
        equation
          connect(gain1.y, gain2.u) annotation(Line(points = {{-49, 0}, {0, 0}, {44, 0}}, color = {0, 0, 127}));
          connect(gain2.y, gain3.u);
          connect(loose.y, plain.u);
          annotation(Diagram(graphics = {Text(extent = {{-100, 100}, {100, 80}}, textString = "Top title"),
                                         Rectangle(extent = {{-100, -100}, {-80, -80}}, fillColor = {255, 0, 0},
                                                   fillPattern = FillPattern.Solid)}));
        end System;
    """,
    "Gfx/Plain.mo": """
        within Gfx;
        block Plain "no icon at all"
          Interfaces.RealInput u;
        end Plain;
    """,
}


@pytest.fixture(scope="module")
def gfx(tmp_path_factory) -> Library:
    return _library(tmp_path_factory.mktemp("gfx"), GFX)


def _svg(drawing) -> ET.Element:
    return ET.fromstring(drawing.svg.encode())  # well-formed XML, or this raises


def _group(root: ET.Element, **attributes) -> ET.Element:
    key, value = next(iter(attributes.items()))
    key = key.replace("_", "-")
    found = [g for g in root.iter(f"{SVG}g") if g.get(key) == value]
    assert len(found) == 1, f"{len(found)} groups with {key}={value}"
    return found[0]


def _points(path: ET.Element) -> list[tuple[float, float]]:
    """The points of a path's d (M/L/Q coordinates), back in Modelica coordinates (y up)."""
    numbers = [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?(?:e-?\d+)?", path.get("d"))]
    return [(numbers[k], -numbers[k + 1]) for k in range(0, len(numbers), 2)]


def _fills(group: ET.Element, fill: str) -> list[ET.Element]:
    return [p for p in group.iter(f"{SVG}path") if p.get("fill") == fill]


# --------------------------------------------------------------------------- annotation expressions

def _value(text: str):
    source = Source(Path("t.mo"), text)
    return parse_expression(source, 0, len(source.tokens))


@pytest.mark.parametrize("text, expected", [
    ("12", 12), ("-100", -100), ("+3.5", 3.5), ("1e2", 100.0), ("-1.5E-3", -0.0015), (".5", 0.5),
    ("2*10", 20), ("-2*10 + 1", -19), ("2^3", 8.0), ("10/4", 2.5), ("(1 + 2)*3", 9),
    ('"a \\"quoted\\" \\\\ text\\n"', 'a "quoted" \\ text\n'), ('"a" + "b"', "ab"),
    ("true", True), ("false", False),
    ("{1, -2}", [1, -2]), ("{{-100, -100}, {100, 100}}", [[-100, -100], [100, 100]]), ("{}", []),
    ("{{1, 2}, {3, 4}} * 2", [[2, 4], [6, 8]]), ("-{1, 2}", [-1, -2]), ("[1, 2; 3, 4]", [[1, 2], [3, 4]]),
    ("FillPattern.Solid", Name("FillPattern.Solid")), ("DynamicSelect(3, x)", 3),
    ("Line(points = {{0, 0}, {1, 1}}, color = {0, 0, 255})",
     Record("Line", {"points": [[0, 0], [1, 1]], "color": [0, 0, 255]}, (), 1)),
    ("{Rectangle(extent = {{0, 0}, {1, 1}}), Text(textString = \"%name\")}",
     [Record("Rectangle", {"extent": [[0, 0], [1, 1]]}, (), 1), Record("Text", {"textString": "%name"}, (), 1)]),
    ("k*2", Expression("k*2")), ("if a then 1 else 2", Expression("if a then 1 else 2")),
    ("x[1]", Expression("x[1]")), ("a > 1", Expression("a > 1")),
], ids=["int", "negative", "plus-sign", "exponent", "signed-exponent", "leading-dot", "product", "precedence",
        "power", "quotient", "parentheses", "string-escapes", "string-concatenation", "true", "false", "array",
        "nested-array", "empty-array", "array-scaled", "array-negated", "matrix", "enumeration",
        "dynamic-select", "record", "array-of-records", "variable", "if-expression", "subscript", "comparison"])
def test_annotation_expressions(text, expected):
    assert _value(text) == expected


@pytest.mark.parametrize("text, message", [
    ("{1, 2", "t.mo:1:1: '{' is not closed"),
    ("{1, 2)", "t.mo:1:6: ')' does not close '{' of line 1"),
    ("1 2", "t.mo:1:3: annotation: unexpected '2' after an expression"),
    ('"open', "t.mo:1:1: unterminated string"),
    ("Line(points = )", "t.mo:1:15: annotation: a value is missing before ')'"),
    ("{1, }", "t.mo:1:5: annotation: a value is missing before '}'"),
    ("1 +", "t.mo:1:4: annotation: a value is missing at the end"),
], ids=["unclosed", "wrong-bracket", "two-values", "unterminated-string", "missing-value", "missing-item",
                                    "missing-operand"])
def test_malformed_expressions_name_file_line_col(text, message):
    with pytest.raises(ModelicaError, match=re.escape(message)):
        _value(text)


def test_deeply_nested_annotation_is_an_error_not_a_crash():
    depth = 5000
    text = f"model M\n  annotation(Icon(graphics = {'{' * depth}{'}' * depth}));\nend M;\n"
    annotation = parse_text(text, "M.mo").classes["M"].annotation
    with pytest.raises(ModelicaError, match=re.escape("M.mo:2:14: annotation: Icon(...) is nested too deeply")):
        annotation.get("Icon")


# --------------------------------------------------------------------------- the source extractor

EXTRACT = """within P;
model M "a model"
  parameter Real k = 2 "gain" annotation(Dialog(group = "a"));
  Real a, b(start = 1) annotation(Placement(transformation(extent = {{0, 0}, {10, 10}})));
  replaceable C c(x = 1, y = {1, 2}) constrainedby D(x = 1) "replaceable"
    annotation(Placement(transformation(extent = {{-10, -10}, {10, 10}}, rotation = 90)));
  C cond if k > 1 "conditional" annotation(Placement(transformation(extent = {{1, 1}, {2, 2}})));
  parameter String s = "connect(x, y) annotation(" "a string that looks like code";
  // connect(commented, out) annotation(Line(points = {{0, 0}, {1, 1}}));
  model Inner "nested"
    Real z annotation(Placement(transformation(extent = {{0, 0}, {1, 1}})));
  end Inner;
protected
  C hidden;
equation
  connect(c.p, cond.n) annotation(Line(points = {{0, 0}, {5, 5}}, color = {255, 0, 0}));
  for i in 1:3 loop
    connect(arr[i].p, c.n) "in a loop";
  end for;
  if k > 1 then
    connect(a1.p, a2.p);
  else
    x = if k > 2 then 1 else 2;
  end if;
  annotation(Icon(graphics = {Line(points = {{0, 0}, {1, 1}})}), Diagram(graphics = {}));
end M;
"""


def test_extractor_finds_components_connections_and_class_annotation():
    cls = parse_text(EXTRACT, "P/M.mo").classes["M"]
    names = [(c.name, c.type, c.protected) for c in cls.components]
    assert names == [("k", "Real", False), ("a", "Real", False), ("b", "Real", False), ("c", "C", False),
                     ("cond", "C", False), ("s", "String", False), ("hidden", "C", True)]
    k, a, b, c, cond, s, hidden = cls.components
    assert k.binding == "2" and "parameter" in k.prefixes and k.annotation.get("Dialog").get("group") == "a"
    assert a.annotation is None and b.annotation.get("Placement").name == "Placement"  # per declaration
    assert c.modifiers == {"x": "1", "y": "{1, 2}"} and "replaceable" in c.prefixes
    assert c.annotation.get("Placement").get("transformation").get("rotation") == 90
    assert cond.annotation is not None and cond.line == 7
    assert s.binding == '"connect(x, y) annotation("'
    assert [(x.a, x.b) for x in cls.connections] == [("c.p", "cond.n"), ("arr[i].p", "c.n"), ("a1.p", "a2.p")]
    assert cls.connections[0].annotation.get("Line").get("color") == [255, 0, 0]
    assert cls.connections[0].line == 16 and cls.connections[1].annotation is None
    assert set(cls.annotation.spans) == {"Icon", "Diagram"}
    assert list(cls.classes) == ["Inner"] and cls.classes["Inner"].components[0].name == "z"


def test_extractor_reads_short_classes_extends_and_redeclares():
    parsed = parse_text("""
        within P;
        package Q
          connector In = input Real "in" annotation(Icon(graphics = {Rectangle(extent = {{0, 0}, {1, 1}})}));
          model R
            extends Base(k = 3, redeclare Other part(m = 1), redeclare package Data = D)
              annotation(IconMap(primitivesVisible = false));
          end R;
        end Q;
    """, "P/Q/package.mo")
    q = parsed.classes["Q"]
    assert q.classes["In"].base == "Real" and q.classes["In"].kind == "connector"
    assert "Icon" in q.classes["In"].annotation
    (extends,) = q.classes["R"].extends
    assert (extends.name, extends.modifiers, extends.redeclares) == ("Base", {"k": "3"}, {"part": "Other"})
    assert extends.annotation.get("IconMap").get("primitivesVisible") is False


@pytest.mark.parametrize("text, message", [
    ("model M\n  Real x annotation(Placement(transformation(extent = {{0, 0}, {1, 1}})));\nend N;",
     "M.mo:3:5: 'end N' closes class 'M' of line 1"),
    ("model M\n  Real x\nend M;", "M.mo:3:1: expected ';' after the declaration, found 'end'"),
    ("model M\n  Real x annotation(Placement(;\nend M;", "M.mo:2:30: '(' is not closed"),
    ("model M\n  Real x;\n", "has no 'end M;'"),
], ids=["end-name", "missing-semicolon", "unclosed-annotation", "no-end"])
def test_extractor_errors_name_file_line_col(text, message):
    with pytest.raises(ModelicaError, match=re.escape(message)):
        parse_text(text, "M.mo")


def _pymoca_connects(equations) -> list[tuple[str, str]]:
    """The connect clauses of pymoca's equations, ``for``/``if``/``when`` bodies included."""
    from pymoca import ast

    found = []
    for e in equations:
        if isinstance(e, ast.ConnectClause):
            found.append(tuple(".".join(e_side.to_tuple()) for e_side in (e.left, e.right)))
        elif isinstance(e, ast.ForEquation):
            found += _pymoca_connects(e.equations)
        elif isinstance(e, (ast.IfEquation, ast.WhenEquation)):
            for block in e.blocks:
                found += _pymoca_connects(block)
    return found


def test_extractor_agrees_with_pymoca_on_the_real_library():
    """Every class of every file: the same components, base classes and connect equations as
    pymoca's parse of that file (which has no component or connect annotations). Each file is
    parsed on its own: pymoca's merged tree of the library keeps only the nested classes of a
    package.mo read after another file of its package, not its own extends."""
    parse = functools.lru_cache(maxsize=None)(lambda file: parser.parse(file.read_text(encoding="utf-8")))
    library = _real_library()
    graphics = Graphics(library)
    checked = 0
    for name, entry in library.entries.items():
        if entry.file.suffix != ".mo":
            continue  # a built-in type
        node = parse(entry.file)
        for part in name.split("."):
            node = node.classes[part]
        cls = graphics.definition(name)
        assert [c.name for c in cls.components] == list(node.symbols), name
        bases = [e.name for e in cls.extends] + ([cls.base] if cls.base else [])
        assert bases == [".".join(e.component.to_tuple()) for e in node.extends], name
        mine = [tuple(re.sub(r"\[.*?\]", "", ref) for ref in (c.a, c.b)) for c in cls.connections]
        assert mine == _pymoca_connects(node.equations), name
        checked += 1
    assert checked == len([e for e in library.entries.values() if e.file.suffix == ".mo"]) > 100


# --------------------------------------------------------------------------- chapter-18 objects

def test_icon_is_inherited_bases_first(gfx):
    layer = Graphics(gfx).layer("Gfx.Gain", "Icon")
    kinds = [type(g).__name__ for g in layer.graphics]
    assert kinds == ["Rectangle", "Text", "Polygon", "Text"]  # PartialBlock's, then Gain's own
    assert layer.coordinate_system.extent == ((-100, -100), (100, 100)) and layer.coordinate_system.given


def test_components_are_inherited_with_their_placements(gfx):
    components = {c.name: c for c in Graphics(gfx).components("Gfx.Gain")}
    assert list(components) == ["u", "y", "k"]
    assert components["u"].type == "Gfx.Interfaces.RealInput" and components["u"].is_connector
    assert components["y"].placement.for_icon().extent == ((100, -10), (120, 10))
    assert components["u"].placement.for_icon().extent == ((-140, -20), (-100, 20))


def test_connections_carry_their_lines(gfx):
    lines = [(c.a, c.b, c.line) for c in Graphics(gfx).connections("Gfx.System")]
    assert lines[0][:2] == ("gain1.y", "gain2.u") and isinstance(lines[0][2], Line)
    assert lines[0][2].points == ((-49, 0), (0, 0), (44, 0)) and lines[0][2].color == (0, 0, 127)
    assert [x[2] for x in lines[1:]] == [None, None]


def test_primitives_get_the_defaults_of_the_specification(gfx):
    graphics = Graphics(gfx).layer("Gfx.Shapes", "Diagram").graphics
    polygon = next(g for g in graphics if isinstance(g, Polygon))
    assert (polygon.line_color, polygon.pattern, polygon.line_thickness) == ((0, 0, 0), "Solid", 0.25)
    assert polygon.smooth == "None" and polygon.fill_color == (0, 255, 255)
    text = next(g for g in graphics if isinstance(g, Text))
    assert text.text_color == (0, 0, 0) and text.font_size == 0 and text.text_style == ("Bold",)
    arc = next(g for g in graphics if type(g).__name__ == "Ellipse" and g.end_angle == 90)
    assert arc.closure == "Radial"


@pytest.mark.parametrize("graphic, message", [
    ("Rectangle(extent = {{0, 0}, {1}})", "Icon: Rectangle(extent = {{0, 0}, {1}}): must be a point {x, y}"),
    ("Line(points = {{0, 0}, {1, 1}}, color = {0, 0, 256})", "must be a colour {r, g, b} of integers 0..255"),
    ("Circle(extent = {{0, 0}, {1, 1}})", "Icon: graphics: unknown primitive 'Circle'"),
    ("Line(points = {{0, 0}, {1, 1}}, lineColor = {0, 0, 0})", "Icon: Line: unknown attribute 'lineColor'"),
    ("Rectangle(extent = {{0, 0}, {1, 1}}, fillPattern = FillPattern.Dotted)",
     "must be one of FillPattern.None, Solid"),
    ("Rectangle(extent = {{0, 0}, {w, 1}})", "must be a point {x, y} of literal numbers"),
    ("Line(points = {{0, 0}})", "needs at least 2 points"),
    ("Text(textString = \"x\")", "Icon: Text: 'extent' is missing"),
    ("Polygon(points = {{0, 0}, {1, 0}, {1, 1}}, smooth = true)", "must be one of Smooth.None, Bezier"),
], ids=["short-point", "colour", "unknown-primitive", "unknown-attribute", "enumeration", "not-literal",
        "too-few-points", "missing-extent", "smooth-bool"])
def test_malformed_graphics_name_file_and_line(graphic, message, tmp_path):
    library = _library(tmp_path, {"B/package.mo": f"""
        package B
          model M
            annotation(Icon(graphics = {{
              {graphic}}}));
          end M;
        end B;
    """})
    with pytest.raises(ModelicaError) as info:
        Graphics(library).layer("B.M", "Icon")
    assert str(info.value).startswith(f"{tmp_path / 'B' / 'package.mo'}:4: ") and message in str(info.value)


def test_malformed_placement_names_file_and_line(tmp_path):
    library = _library(tmp_path, {"B/package.mo": """
        package B
          model C
          end C;
          model M
            C c annotation(Placement(transformation(extent = {{0, 0}, {0, 10}})));
          end M;
        end B;
    """})
    with pytest.raises(ModelicaError, match=re.escape(f"{tmp_path / 'B' / 'package.mo'}:5: Placement.transformation: "
                                                      "transformation(extent = {{0, 0}, {0, 10}}): must have a width")):
        draw("B.M", library=library)


def test_a_class_that_extends_itself_is_an_error(tmp_path):
    library = _library(tmp_path, {"B/package.mo": """
        package B
          model M
            extends N;
          end M;
          model N
            extends M;
          end N;
        end B;
    """})
    with pytest.raises(ModelicaError, match="extends itself"):
        Graphics(library).layer("B.M", "Icon")


def test_a_broken_file_fails_the_diagrams_that_use_it(tmp_path):
    library = _library(tmp_path, {
        "B/package.mo": "package B\nend B;\n",
        "B/Bad.mo": "within B;\nmodel Bad\n  Real x\nend Bad;\n",
        "B/User.mo": "within B;\nmodel User\n  Bad bad;\n  Good good;\nend User;\n",
        "B/Good.mo": "within B;\nmodel Good\nend Good;\n",
    })
    bad = tmp_path / "B" / "Bad.mo"
    with pytest.raises(ModelicaError, match=re.escape(f"{bad}:4:1: syntax error")) as info:
        draw("B.User", library=library)
    assert "B.User uses B.Bad" in str(info.value)
    with pytest.raises(ModelicaError, match=re.escape(f"{bad}:4:1: syntax error")):
        draw("B.Bad", library=library)
    assert draw("B.Good", library=library).components == 0


# --------------------------------------------------------------------------- placement geometry

@pytest.mark.parametrize("extent, rotation, origin, point, expected", [
    (((-10, -10), (10, 10)), 0, (0, 0), (100, 0), (10, 0)),
    (((40, -10), (20, 10)), 0, (0, 0), (100, 0), (20, 0)),            # flipped horizontally
    (((-10, 10), (10, -10)), 0, (0, 0), (0, 100), (0, -10)),          # flipped vertically
    (((-10, -10), (10, 10)), 90, (0, 50), (100, 0), (0, 60)),         # rotated about the origin
    (((-10, -10), (10, 10)), -90, (5, 5), (100, 0), (5, -5)),
    (((-20, -10), (20, 10)), 0, (0, 0), (100, 100), (10, 10)),        # aspect ratio preserved
], ids=["plain", "flip-x", "flip-y", "rotate-90", "rotate-minus-90", "aspect"])
def test_placement_matrix_maps_the_icon_into_the_extent(extent, rotation, origin, point, expected):
    from cosim.diagram.graphics import CoordinateSystem, Transformation

    m = placement_matrix(Transformation(extent, origin, rotation), CoordinateSystem())
    assert m(point) == pytest.approx(expected)


def test_placement_without_preserved_aspect_ratio_stretches():
    from cosim.diagram.graphics import CoordinateSystem, Transformation

    m = placement_matrix(Transformation(((-20, -10), (20, 10))), CoordinateSystem(preserve_aspect_ratio=False))
    assert m((100, 100)) == pytest.approx((20, 10))
    assert (Affine.rotate(90) @ Affine.translate(1, 0))((0, 0)) == (0, 1)


# --------------------------------------------------------------------------- SVG

def test_diagram_svg_groups_components_and_connections(gfx):
    drawing = draw("Gfx.System", library=gfx)
    root = _svg(drawing)
    names = [g.get("data-component") for g in root.iter(f"{SVG}g") if g.get("data-component")]
    assert names == ["gain1", "gain2", "gain3", "plain", "loose"]  # hidden: visible=false; p: a parameter
    connects = [g.get("data-connect") for g in root.iter(f"{SVG}g") if g.get("data-connect")]
    assert connects == ["gain1.y gain2.u", "gain2.y gain3.u", "loose.y plain.u"]
    assert drawing.components == 5 and drawing.connections == 3
    x, y, w, h = map(float, root.get("viewBox").split())
    assert x <= -100 and y <= -100 and x + w >= 100 and y + h >= 100  # covers the coordinate system
    assert "1 component(s) without a Placement annotation" in root.find(f"{SVG}title").text


def test_y_points_up(gfx):
    root = _svg(draw("Gfx.System", library=gfx))
    title = next(t for t in root.iter(f"{SVG}text") if t.text == "Top title")
    assert float(title.get("y")) == pytest.approx(-90)  # Modelica y = 90 is near the top of the SVG
    red = next(p for p in root.iter(f"{SVG}path") if p.get("fill") == "rgb(255,0,0)")
    assert sorted({p for p in _points(red)}) == [(-100, -100), (-100, -80), (-80, -100), (-80, -80)]


def test_component_name_and_parameter_substitution(gfx):
    root = _svg(draw("Gfx.System", library=gfx))
    texts = {g: [t.text for t in _group(root, data_component=g).iter(f"{SVG}text")] for g in ("gain1", "gain2")}
    assert "gain1" in texts["gain1"] and "k=2" in texts["gain1"]  # %name; %k from the class's value
    assert "gain2" in texts["gain2"] and "k=5" in texts["gain2"]  # %k from the component's modifier
    plain = [t.text for t in _group(root, data_component="plain").iter(f"{SVG}text")]
    assert plain == ["plain"]  # a class without graphics: a box with its name


def _tip(group: ET.Element) -> tuple[float, float]:
    """The tip of the gain's triangle (the third point of its unfilled polygon)."""
    (triangle,) = [p for p in group.findall(f"{SVG}path")
                   if p.get("fill") == "none" and p.get("stroke") == "rgb(0,0,127)" and len(_points(p)) == 3]
    return _points(triangle)[2]


@pytest.mark.parametrize("component, expected_tip", [
    ("gain1", (-50, 0)), ("gain2", (20, 0)), ("gain3", (0, 60)),
], ids=["plain", "flipped", "rotated"])
def test_rotation_and_flip_of_icons(gfx, component, expected_tip):
    root = _svg(draw("Gfx.System", library=gfx))
    assert _tip(_group(root, data_component=component)) == pytest.approx(expected_tip)


def test_connectors_are_drawn_at_their_own_placements(gfx):
    root = _svg(draw("Gfx.System", library=gfx))
    gain1 = _group(root, data_component="gain1")
    connectors = {g.get("data-connector"): g for g in gain1.iter(f"{SVG}g") if g.get("data-connector")}
    assert set(connectors) == {"u", "y"}
    xs = [p[0] for p in _points(connectors["u"].find(f"{SVG}path"))]
    assert (min(xs), max(xs)) == pytest.approx((-74, -70))  # extent {{-140,-20},{-100,20}} in gain1's 20 units
    xs = [p[0] for p in _points(connectors["y"].find(f"{SVG}path"))]
    assert (min(xs), max(xs)) == pytest.approx((-50, -48))  # its iconTransformation, not its transformation


def test_connection_lines(gfx):
    root = _svg(draw("Gfx.System", library=gfx))
    line = _group(root, data_connect="gain1.y gain2.u").find(f"{SVG}path")
    assert _points(line) == [(-49, 0), (0, 0), (44, 0)] and line.get("stroke") == "rgb(0,0,127)"
    default = _group(root, data_connect="gain2.y gain3.u").find(f"{SVG}path")
    assert default.get("class") == "default-route"
    assert _points(default) == [pytest.approx((19, 0)), pytest.approx((0, 38))]  # gain2.y (flipped) to gain3.u
    # gain3.u: the left end of the icon, turned by 90 degrees counterclockwise to its bottom


def test_every_primitive_is_drawn(gfx):
    root = _svg(draw("Gfx.Shapes", library=gfx))
    layer = _group(root, data_layer="diagram")
    paths = layer.findall(f"{SVG}path")
    fills = [p.get("fill") for p in paths]
    assert "rgb(200,255,200)" in fills and "rgb(255,0,255)" in fills and "rgb(0,255,255)" in fills
    assert any(f.startswith("url(#") for f in fills)  # hatch, cylinder and sphere
    assert {e.tag.replace(SVG, "") for e in root.find(f"{SVG}defs")} == {"pattern", "linearGradient", "radialGradient"}
    dashed = [p for p in paths if p.get("stroke-dasharray")]
    assert len(dashed) == 2 and any(" Q" in p.get("d") for p in dashed)  # the dashed Bezier, the dotted rectangle
    arrow = next(p for p in paths if p.get("fill") == "rgb(255,0,0)")
    assert max(x for x, _ in _points(arrow)) == pytest.approx(-120)  # the filled arrow's tip at the line's end
    texts = {t.text: t for t in layer.iter(f"{SVG}text")}
    assert texts["left aligned"].get("text-anchor") == "start" and texts["left aligned"].get("x") == "-20"
    assert texts["left aligned"].get("font-weight") == "bold"
    assert texts["turned"].get("transform").startswith("rotate(-90 150 10")
    vertical = [p for p in paths if _points(p) == [(-20, -80), (-20, -40)]]
    assert len(vertical) == 1  # rotated by 90 about its origin; the invisible line is not drawn
    assert not [p for p in paths if _points(p) == [(60, -80), (100, -80)]]
    arc = next(p for p in paths if p.get("fill") == "rgb(255,0,255)")
    assert (-150, -10) in [tuple(round(v, 6) for v in p) for p in _points(arc)]  # closed to the centre (Radial)


def test_icon_layer_draws_the_connectors(gfx):
    drawing = draw("Gfx.Gain", icon=True, library=gfx)
    root = _svg(drawing)
    assert drawing.layer == "icon" and [g.get("data-component") for g in root.iter(f"{SVG}g")
                                        if g.get("data-component")] == ["u", "y"]
    texts = [t.text for t in root.iter(f"{SVG}text")]
    assert "Gain" in texts and "k=2" in texts  # %name is the class's name in its own icon


def test_unplaced_components_get_labelled_boxes_at_default_positions(tmp_path):
    library = _library(tmp_path, {"B/package.mo": """
        package B
          connector C = input Real;
          block A
            C u;
          end A;
          model M
            A first;
            A second;
            C inlet;
          equation
            connect(inlet, first.u);
          end M;
        end B;
    """})
    drawing = draw("B.M", library=library)
    root = _svg(drawing)
    groups = {g.get("data-component"): g for g in root.iter(f"{SVG}g") if g.get("data-component")}
    assert list(groups) == ["first", "second", "inlet"]
    for name, group in groups.items():
        assert group.get("class") == "unplaced" and name in [t.text for t in group.iter(f"{SVG}text")]
    assert ("3 component(s) without a Placement annotation, drawn as labelled boxes at default positions"
            in drawing.title)
    assert "1 connection(s) without a Line annotation, drawn straight" in drawing.title
    centres = [_points(g.find(f"{SVG}path")) for g in groups.values()]
    assert len({tuple(map(tuple, c)) for c in centres}) == 3  # three different places


ODD_VALUES = ["5", '"s"', "{1}", "{{1, 2}, {3}}", "true", "x", "{}", "-{1, 2}", "{1, 2, 3, 4}",
              "Line(points = {{0, 0}, {1, 1}})", "{{1, 2}, {3, 4}, {5, 6}}", "1e400", "FillPattern.Solid"]


def test_odd_annotation_values_give_a_drawing_or_one_message(tmp_path):
    """Every literal value of the annotations of Gfx.System and Gfx.Shapes replaced by each of
    ODD_VALUES: a drawing, or a ModelicaError of one line that names the file and line."""
    library = _library(tmp_path, GFX)
    value = re.compile(r"(?<=\w = )(\{\{[^;]*?\}\}|\{[^{}]*\}|-?[\w.]+|\"[^\"]*\")")
    outcomes = {"drawn": 0, "refused": 0}
    for model in ("System", "Shapes"):
        file = tmp_path / "Gfx" / f"{model}.mo"
        original = file.read_text()
        body = original.index("annotation(")  # the values of the annotations, not of declarations
        stamp = file.stat().st_mtime_ns
        for match in [m for m in value.finditer(original) if m.start() > body]:
            for odd in ODD_VALUES:
                file.write_text(original[:match.start()] + odd + original[match.end():])
                stamp += 1000
                os.utime(file, ns=(stamp, stamp))
                try:
                    drawing = draw(f"Gfx.{model}", library=library)
                except ModelicaError as exc:
                    message = str(exc)
                    assert "\n" not in message and message.startswith(f"{file}:"), message
                    outcomes["refused"] += 1
                else:
                    _svg(drawing)
                    outcomes["drawn"] += 1
        file.write_text(original)
    assert outcomes["drawn"] > 50 and outcomes["refused"] > 300, outcomes


def test_unknown_class_is_one_line_with_close_names(gfx):
    with pytest.raises(UnknownModelError) as info:
        draw("Gfx.Gian", library=gfx)
    assert "\n" not in str(info.value) and "unknown class 'Gfx.Gian'" in str(info.value)
    assert "did you mean Gfx.Gain" in str(info.value)


# --------------------------------------------------------------------------- the command line

@pytest.fixture(scope="module")
def gfx_folder(gfx) -> Path:
    return gfx.path


def test_cli_writes_the_svg(gfx_folder, tmp_path):
    out = tmp_path / "system.svg"
    result = run_cli("diagram", "Gfx.System", "-o", str(out), "--library", str(gfx_folder), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"wrote {out} (diagram layer of Gfx.System: 5 components, 3 connections)")
    root = ET.parse(out).getroot()
    assert root.tag == f"{SVG}svg" and [p.name for p in tmp_path.iterdir()] == ["system.svg"]


def test_cli_icon_and_default_name(gfx_folder, tmp_path):
    result = run_cli("diagram", "Gfx.Gain", "--icon", "--library", str(gfx_folder), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert ET.parse(tmp_path / "Gfx_Gain-icon.svg").getroot().get("data-layer") == "icon"


@pytest.mark.parametrize("args, message", [
    (["Gfx.Nope"], "cosim diagram: error: unknown class 'Gfx.Nope' in the Modelica library at "),
    (["Gfx.System", "-o", "x.png"], "cosim diagram: error: output file 'x.png': must end in .svg"),
    (["Gfx.System", "-o", "."], "cosim diagram: error: output file '.': must end in .svg"),
], ids=["unknown-model", "not-svg", "folder"])
def test_cli_refuses_bad_input_in_one_line(gfx_folder, tmp_path, args, message):
    result = run_cli("diagram", *args, "--library", str(gfx_folder), cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), result.stderr
    assert list(tmp_path.iterdir()) == []


def test_cli_malformed_annotation_names_file_and_line(tmp_path):
    library = tmp_path / "lib"
    _library(library, {"B/package.mo": """
        package B
          model M
            annotation(Diagram(graphics = {Line(points = {{0, 0}, {1, 1}}, color = {0, 0})}));
          end M;
        end B;
    """})
    result = run_cli("diagram", "B.M", "-o", str(tmp_path / "m.svg"), "--library", str(library), cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.strip() == (f"cosim diagram: error: {library / 'B' / 'package.mo'}:3: Diagram: "
                                     "Line(color = {0, 0}): must be a colour {r, g, b} of integers 0..255")
    assert not (tmp_path / "m.svg").exists()


# --------------------------------------------------------------------------- the real library

@functools.lru_cache(maxsize=1)
def _real_library() -> Library:
    return Library(ROOT / "modelica")


def _connected_models() -> list[str]:
    """The models and blocks of the real library with connect equations (their own or
    inherited)."""
    graphics = Graphics(_real_library())
    return [e.name for e in _real_library().models() if graphics.connections(e.name)]


CONNECTED = _connected_models()


def test_the_real_library_has_connected_models():
    assert len(CONNECTED) >= 10 and "Bicycle.Bicycles.Whipple" in CONNECTED


@pytest.mark.parametrize("model", CONNECTED)
def test_every_connected_model_of_the_library_renders(model):
    library = _real_library()
    drawing = draw(model, library=library)
    root = _svg(drawing)
    graphics = Graphics(library)
    drawn = {g.get("data-component") for g in root.iter(f"{SVG}g") if g.get("data-component")}
    connected = {ref.split(".")[0].split("[")[0] for c in graphics.connections(model) for ref in (c.a, c.b)}
    assert connected <= drawn  # every connected component is drawn, placed or at a default position
    assert len([g for g in root.iter(f"{SVG}g") if g.get("data-connect")]) == len(graphics.connections(model))
    texts = " ".join(t.text or "" for t in root.iter(f"{SVG}text")) + " ".join(
        s.text or "" for s in root.iter(f"{SVG}tspan"))
    assert all(name in texts for name in drawn)  # every component's name is visible
    unplaced = [g for g in root.iter(f"{SVG}g") if g.get("class") == "unplaced"]
    assert bool(unplaced) == ("without a Placement annotation" in root.find(f"{SVG}title").text)
    icon = _svg(draw(model, icon=True, library=library))
    assert icon.get("data-layer") == "icon"
