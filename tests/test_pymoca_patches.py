"""cosim's patches of pymoca 0.12 (cosim/compiler/pymoca_patches.py) and the checks in
cosim/compiler/flatten.py: each test writes a tiny library into ``tmp_path``, flattens it and
compares the flat model (or the refusal) with what the Modelica specification prescribes."""
from __future__ import annotations

import math
import re
import textwrap
from pathlib import Path

import casadi as ca
import pytest

from cosim.compiler.description import describe
from cosim.compiler.flatten import flatten
from cosim.compiler.library import DEFAULT_LIBRARY, Library
from cosim.compiler.ode import make_explicit
from cosim.errors import ModelicaError


def _library(root: Path, files: dict[str, str]) -> Library:
    """Write ``files`` (path relative to ``root`` -> Modelica text) and parse the library."""
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return Library(root)


def _explicit(library: Library, model: str):
    flat = flatten(library, model)
    explicit = make_explicit(flat)
    return flat, explicit, describe(library.entry(model), flat, explicit)


def _evaluate(explicit, inputs: dict[str, float], parameters: dict[str, float] | None = None) -> dict[str, float]:
    """The algebraic variables for given input values (states and time 0, parameters at their
    start values unless given)."""
    parameters = parameters or {}
    u = [inputs[s.name] for s in explicit.inputs]
    p = [parameters.get(s.name, s.start) for s in explicit.parameters]
    z = ca.Function("z", [explicit.t, explicit.x, explicit.u, explicit.p], [explicit.z])
    values = z(0.0, ca.DM.zeros(explicit.x.shape[0]), ca.DM(u), ca.DM(p)).full().ravel()
    return {s.name: float(v) for s, v in zip(explicit.algebraics, values)}


# -- 1. Short connector classes ``connector RealInput = input Real`` ---------------------------------

SIGNALS = {
    "Sig/package.mo": """
        package Sig "Signal blocks"
        end Sig;
    """,
    "Sig/package.order": "Units\nInterfaces\nGain\nChain\n",
    "Sig/Units.mo": """
        within Sig;
        package Units "SI types"
          type Angle = Real(final quantity = "Angle", final unit = "rad") "Angle";
        end Units;
    """,
    "Sig/Interfaces/package.mo": """
        within Sig;
        package Interfaces "Connectors"
        end Interfaces;
    """,
    "Sig/Interfaces/package.order": "RealInput\nRealOutput\n",
    "Sig/Interfaces/RealInput.mo": """
        within Sig.Interfaces;
        connector RealInput = input Real "Connector of a Real input signal";
    """,
    "Sig/Interfaces/RealOutput.mo": """
        within Sig.Interfaces;
        connector RealOutput = output Real "Connector of a Real output signal";
    """,
    "Sig/Gain.mo": """
        within Sig;
        block Gain "y = k*u"
          parameter Real k = 2 "Gain";
          Sig.Interfaces.RealInput u(final unit = "rad") "Input signal";
          Sig.Interfaces.RealOutput y(unit = "rad") "Output signal";
        equation
          y = k*u;
        end Gain;
    """,
    "Sig/Chain.mo": """
        within Sig;
        model Chain "Two gains in series between a top-level input and output"
          Sig.Interfaces.RealInput phi(unit = "rad") "Lean angle command";
          Sig.Interfaces.RealOutput out "Twice amplified signal";
          Sig.Gain first(k = 3) "First gain";
          Sig.Gain second "Second gain";
        equation
          connect(phi, first.u);
          connect(first.y, second.u);
          connect(second.y, out);
          annotation(__Cosim(export = true));
        end Chain;
    """,
}


def test_short_connectors_are_plain_variables_with_causality(tmp_path):
    library = _library(tmp_path, SIGNALS)
    _, explicit, info = _explicit(library, "Sig.Chain")
    variables = {v.name: v for v in info.variables}
    assert variables["phi"].causality == "input"
    assert variables["out"].causality == "output"
    assert variables["first.u"].causality == "local"
    assert not any(name.endswith("Real") for name in variables)
    assert variables["phi"].unit == "rad" and variables["first.u"].unit == "rad"
    assert variables["phi"].description == "Lean angle command"
    assert variables["first.u"].description == "Input signal"
    values = _evaluate(explicit, {"phi": 0.25})
    # connect(first.y, second.u) is first.y = second.u; both gains act: out = 2*3*phi
    assert values["out"] == pytest.approx(6 * 0.25, rel=1e-12)
    assert values["second.u"] == pytest.approx(values["first.y"], rel=1e-12)
    assert _evaluate(explicit, {"phi": 0.25}, {"second.k": 5.0})["out"] == pytest.approx(15 * 0.25, rel=1e-12)


def test_short_connector_derived_from_si_type(tmp_path):
    """``connector AngleInput = input Sig.Units.Angle`` carries the type's unit and quantity."""
    files = dict(SIGNALS)
    files["Sig/Interfaces/package.order"] = "RealInput\nRealOutput\nAngleInput\n"
    files["Sig/Interfaces/AngleInput.mo"] = """
        within Sig.Interfaces;
        connector AngleInput = input Sig.Units.Angle "Angle input signal";
    """
    files["Sig/package.order"] = "Units\nInterfaces\nGain\nChain\nAngleChain\n"
    files["Sig/AngleChain.mo"] = """
        within Sig;
        model AngleChain "A gain fed by an angle input"
          Sig.Interfaces.AngleInput delta "Steer angle";
          Sig.Interfaces.RealOutput y "Output";
          Sig.Gain g "Gain";
        equation
          connect(delta, g.u);
          connect(g.y, y);
        end AngleChain;
    """
    library = _library(tmp_path, files)
    _, explicit, info = _explicit(library, "Sig.AngleChain")
    delta = next(v for v in info.variables if v.name == "delta")
    assert (delta.causality, delta.unit, delta.quantity) == ("input", "rad", "Angle")
    assert _evaluate(explicit, {"delta": -0.5})["y"] == pytest.approx(-1.0, rel=1e-12)


# -- 2. Constants of SI types in a replaceable package ---------------------------------------------

DATA = {
    "Lib/package.mo": """
        package Lib "Parameter sets as packages of constants"
          package Units "SI types"
            type Length = Real(final quantity = "Length", final unit = "m") "Length";
          end Units;
        end Lib;
    """,
    "Lib/package.order": "Units\nRecords\nM\nRedeclared\n",
    "Lib/Records/package.mo": """
        within Lib;
        package Records "Parameter sets"
        end Records;
    """,
    "Lib/Records/package.order": "PartialSet\nA\nB\n",
    "Lib/Records/PartialSet.mo": """
        within Lib.Records;
        partial package PartialSet "The constants every set defines"
          constant Lib.Units.Length w "Wheelbase";
          constant Lib.Units.Length z "Height (down)";
          constant Real c(final unit = "m") "Trail";
        end PartialSet;
    """,
    "Lib/Records/A.mo": """
        within Lib.Records;
        package A "Set A"
          extends Lib.Records.PartialSet;
          redeclare constant Lib.Units.Length w = 1.02 "Wheelbase";
          redeclare constant Lib.Units.Length z = -0.9 "Height (down)";
          redeclare constant Real c(final unit = "m") = 0.08 "Trail";
        end A;
    """,
    "Lib/Records/B.mo": """
        within Lib.Records;
        package B "Set B"
          constant Lib.Units.Length w = 2.5 "Wheelbase";
          constant Lib.Units.Length z = -0.3 "Height (down)";
          constant Real c(final unit = "m") = 0.1 "Trail";
        end B;
    """,
    "Lib/M.mo": """
        within Lib;
        model M "Parameters bound to, and equations using, constants of a replaceable package"
          replaceable package Data = Lib.Records.A constrainedby Lib.Records.PartialSet "Parameter set";
          parameter Lib.Units.Length w = Data.w "Wheelbase";
          parameter Real c = Data.c "Trail";
          Real y "Output";
        equation
          y = w + 10*c + 100*Data.z + 1000*Data.w;
        end M;
    """,
    "Lib/Redeclared.mo": """
        within Lib;
        model Redeclared "M with the other set"
          extends Lib.M(redeclare package Data = Lib.Records.B);
        end Redeclared;
    """,
}


@pytest.mark.parametrize("model, w, c, z", [("Lib.M", 1.02, 0.08, -0.9), ("Lib.Redeclared", 2.5, 0.1, -0.3)],
                         ids=["default-set", "redeclared-set"])
def test_typed_constants_of_replaceable_package(tmp_path, model, w, c, z):
    library = _library(tmp_path, DATA)
    flat, explicit, _ = _explicit(library, model)
    parameters = {s.name: s.start for s in explicit.parameters}
    assert parameters == pytest.approx({"w": w, "c": c}, rel=1e-12)
    assert flat.declarations["w"].unit == "m"
    y = _evaluate(explicit, {})["y"]
    assert y == pytest.approx(w + 10 * c + 100 * z + 1000 * w, rel=1e-12)


def test_constant_values_given_as_modifiers_of_extends(tmp_path):
    """``package A extends PartialSet(w = 1.02, ...)``: pymoca lost the modifiers when the constant
    was referred to from a model (the name stayed undeclared); the values must be A's."""
    files = dict(DATA)
    files["Lib/Records/A.mo"] = """
        within Lib.Records;
        package A "Set A, values as modifiers of extends"
          extends Lib.Records.PartialSet(w = 1.5, z = -0.7, c = 0.25);
        end A;
    """
    library = _library(tmp_path, files)
    _, explicit, _ = _explicit(library, "Lib.M")
    assert {s.name: s.start for s in explicit.parameters} == pytest.approx({"w": 1.5, "c": 0.25}, rel=1e-12)
    assert _evaluate(explicit, {})["y"] == pytest.approx(1.5 + 2.5 - 70 + 1500, rel=1e-12)


# -- 3. Record bindings ``Mass body(b = rb)`` --------------------------------------------------------

RECORDS = {
    "Rec/package.mo": """
        package Rec "Record bindings"
          record Body "Mass properties"
            parameter Real m = 1 "Mass";
            parameter Real I = 2 "Inertia";
          end Body;
          record Pair "Two bodies and a length"
            parameter Body front "Front body";
            parameter Body rear(m = 7) "Rear body";
            parameter Real l = 0.5 "Length";
          end Pair;
          record Other "A record of other elements"
            parameter Real m = 1 "Mass";
            parameter Real k = 2 "Stiffness";
          end Other;
          model Mass "A mass with its data as a record"
            parameter Body b "Body data";
            Real y "Output";
          equation
            y = b.m + 10*b.I;
          end Mass;
          model Bound "Record components bound to records"
            parameter Body rb(m = 3, I = 4) "Data";
            parameter Pair pair(front(m = 5, I = 6), l = 0.9) "Pair";
            parameter Pair copy = pair "Bound record with records inside";
            Mass body(b = rb) "Bound in a modifier";
            Mass front(b = copy.front) "Bound to an element of a bound record";
            Mass rear(b(m = 11) = copy.rear) "The binding wins over element modifiers";
          end Bound;
          model Extended "A binding in an extends modifier"
            parameter Body rb(m = 8, I = 9) "Data";
            extends Mass(b = rb);
          end Extended;
          model Constructor "A record constructor"
            Mass body(b = Body(m = 3, I = 4)) "Bound to a constructor call";
          end Constructor;
          model Mismatch "A record bound to a record of another type"
            parameter Other o "Other data";
            Mass body(b = o) "Bound to the wrong record";
          end Mismatch;
        end Rec;
    """,
}


def test_record_bindings_are_applied_element_wise(tmp_path):
    library = _library(tmp_path, RECORDS)
    _, explicit, _ = _explicit(library, "Rec.Bound")
    values = _evaluate(explicit, {})
    assert values["body.y"] == pytest.approx(3 + 10 * 4, rel=1e-12)  # rb, not the defaults 1 + 10*2
    assert values["front.y"] == pytest.approx(5 + 10 * 6, rel=1e-12)  # pair.front through copy
    assert values["rear.y"] == pytest.approx(7 + 10 * 2, rel=1e-12)  # pair.rear through copy
    # a change of the bound-to parameter reaches the bound record
    parameters = {"rb.m": 30.0, "pair.front.I": -1.0}
    changed = _evaluate(explicit, {}, parameters)
    assert changed["body.y"] == pytest.approx(30 + 10 * 4, rel=1e-12)
    assert changed["front.y"] == pytest.approx(5 - 10, rel=1e-12)


def test_record_binding_in_extends_modifier(tmp_path):
    library = _library(tmp_path, RECORDS)
    _, explicit, _ = _explicit(library, "Rec.Extended")
    assert _evaluate(explicit, {})["y"] == pytest.approx(8 + 10 * 9, rel=1e-12)


def _line(text: str, fragment: str) -> int:
    """1-based line of ``fragment`` in the (dedented) library text."""
    lines = textwrap.dedent(text).lstrip().splitlines()
    return next(i for i, line in enumerate(lines, 1) if fragment in line)


def _assert_refused_at(tmp_path, files: dict[str, str], file: str, model: str, fragment: str, message: str):
    """Flattening ``model`` fails with ``FILE:LINE: message``, LINE being the line of ``fragment``."""
    library = _library(tmp_path, files)
    line = _line(files[file], fragment)
    with pytest.raises(ModelicaError, match=rf"{re.escape(Path(file).name)}:{line}: {message}"):
        flatten(library, model)


@pytest.mark.parametrize("model, fragment, message", [
    ("Rec.Constructor", "b = Body(m = 3", r"record binding 'b = Body\(\.\.\.\)' is not supported"),
    ("Rec.Mismatch", "b = o", r"record binding 'b = o' is not supported \('o' has no element 'I'\)"),
], ids=["constructor", "other-record-type"])
def test_unsupported_record_binding_is_refused_with_line(tmp_path, model, fragment, message):
    _assert_refused_at(tmp_path, RECORDS, "Rec/package.mo", model, fragment, rf"{re.escape(model)}: {message}")


# -- 4. Component redeclarations and constraining clauses ------------------------------------------

WHEELS = {
    "Wh/package.mo": """
        package Wh "Replaceable wheels"
          partial model PartialWheel "A wheel: radius and height of its centre"
            parameter Real r = 0.3 "Radius";
            Real y "Height of the centre";
          end PartialWheel;
          model Knife "Knife-edge wheel"
            extends PartialWheel;
            parameter Real k = 1 "Factor";
          equation
            y = k*r;
          end Knife;
          model Torus "Toroidal wheel"
            extends PartialWheel;
            parameter Real rc = 0.1 "Crown radius";
          equation
            y = r + rc;
          end Torus;
          model Plain "A replaceable wheel without constraining clause"
            replaceable Knife w(r = 0.4, k = 2) "Wheel";
          end Plain;
          model Constrained "A replaceable wheel with constraining clause"
            replaceable Knife w(r = 0.4) constrainedby PartialWheel "Wheel";
          end Constrained;
          model ConstrainedModified "Modifiers in the constraining clause"
            replaceable Knife w constrainedby PartialWheel(r = 0.5) "Wheel";
          end ConstrainedModified;
          model ClassModified "A replaceable class with modifiers and constraining clause"
            replaceable model W = Knife(r = 0.4) constrainedby PartialWheel "Wheel model";
            W w "Wheel";
          end ClassModified;
          model ClassConstraintModified "A replaceable class with a modified constraining clause"
            replaceable model W = Knife constrainedby PartialWheel(r = 0.5) "Wheel model";
            W w "Wheel";
          end ClassConstraintModified;
          model Use "Every case"
            Constrained torus(redeclare Torus w(rc = 0.2)) "Redeclared: Knife's equation and r = 0.4 dropped";
            Constrained knife "Not redeclared";
            Plain plain(redeclare Knife w(k = 3)) "Redeclared without constraining clause: r = 0.4 kept";
            ConstrainedModified cmTorus(redeclare Torus w) "r = 0.5 of the constraining clause kept";
            ConstrainedModified cmKnife "r = 0.5 of the constraining clause";
          end Use;
          model Extended "Redeclared in an extends modifier"
            extends Constrained(redeclare Torus w);
          end Extended;
          model UseClassModified "Refused: pymoca would keep r = 0.4"
            ClassModified c(redeclare model W = Torus) "Redeclared";
          end UseClassModified;
          model UseClassConstraintModified "Refused: pymoca would ignore r = 0.5"
            ClassConstraintModified c "Not redeclared";
          end UseClassConstraintModified;
          model Two "Two replaceable wheels of the same class"
            replaceable Knife a(k = 2) constrainedby PartialWheel(r = 0.4) "Wheel a";
            replaceable Knife b(k = 3) constrainedby PartialWheel(r = 0.5) "Wheel b";
          end Two;
          model ExtendedTwo "Both wheels redeclared in one extends"
            extends Two(redeclare Torus a, redeclare Torus b(rc = 0.2));
          end ExtendedTwo;
        end Wh;
    """,
}


def test_component_redeclare_replaces_the_class(tmp_path):
    library = _library(tmp_path, WHEELS)
    flat, explicit, _ = _explicit(library, "Wh.Use")
    assert len(flat.casadi.equations) == 5  # one per wheel: nothing of the replaced classes is left
    parameters = {s.name: s.start for s in explicit.parameters}
    assert "torus.w.k" not in parameters and "cmTorus.w.k" not in parameters
    expected = {"torus.w.y": 0.3 + 0.2, "knife.w.y": 1 * 0.4, "plain.w.y": 3 * 0.4,
                "cmTorus.w.y": 0.5 + 0.1, "cmKnife.w.y": 1 * 0.5}
    assert _evaluate(explicit, {}) == pytest.approx(expected, rel=1e-12)


def test_component_redeclare_in_extends_modifier(tmp_path):
    library = _library(tmp_path, WHEELS)
    _, explicit, _ = _explicit(library, "Wh.Extended")
    assert _evaluate(explicit, {}) == pytest.approx({"w.y": 0.3 + 0.1}, rel=1e-12)


def test_two_component_redeclares_in_one_extends_modifier(tmp_path):
    # pymoca registered the first redeclared component's class in the parent, where the second
    # component found it and got both redeclared classes (3 equations for 2 unknowns)
    library = _library(tmp_path, WHEELS)
    flat, explicit, _ = _explicit(library, "Wh.ExtendedTwo")
    assert len(flat.casadi.equations) == 2
    assert _evaluate(explicit, {}) == pytest.approx({"a.y": 0.4 + 0.1, "b.y": 0.5 + 0.2}, rel=1e-12)


@pytest.mark.parametrize("model, fragment, message", [
    ("Wh.UseClassModified", "replaceable model W = Knife(r = 0.4)",
     (r"Wh\.ClassModified: replaceable 'W': with 'constrainedby PartialWheel' the modifiers of the replaced "
      r"class are dropped by a redeclaration")),
    ("Wh.UseClassConstraintModified", "constrainedby PartialWheel(r = 0.5) \"Wheel model\"",
     (r"Wh\.ClassConstraintModified: replaceable 'W': modifiers of 'constrainedby PartialWheel\(\.\.\.\)' "
      r"are ignored by pymoca")),
], ids=["class-modifiers-redeclared", "constraining-clause-modifiers"])
def test_replaceable_class_modifiers_pymoca_gets_wrong_are_refused(tmp_path, model, fragment, message):
    _assert_refused_at(tmp_path, WHEELS, "Wh/package.mo", model, fragment, message)


# -- 5. Several top-level packages, several library folders ------------------------------------------

DECAY = {
    "P/package.mo": """
        package P "A package"
          model M "Decay"
            parameter Real k = 2 "Rate";
            Real x(start = 1, fixed = true) "State";
          equation
            der(x) = -k*x;
          end M;
        end P;
    """,
    "Disc/package.mo": """
        within;
        package Disc "A second top-level package"
          model D "Decay at rate 5"
            extends P.M(k = 5);
          end D;
        end Disc;
    """,
}
ORACLE = {
    "Oracle/package.mo": """
        package Oracle "Reference models that use the library in another folder"
          model N "Decay at rate 3"
            extends P.M(k = 3);
          end N;
        end Oracle;
    """,
}


def _own(library: Library) -> list[str]:
    """The models of ``library`` without those of the shipped library (searched after the folders)."""
    return [e.name for e in library.models() if not e.name.startswith("Bicycle.")]


def test_two_top_level_packages_in_one_folder(tmp_path):
    library = _library(tmp_path, DECAY)
    assert library.errors == {}
    assert _own(library) == ["Disc.D", "P.M"]
    flat = flatten(library, "Disc.D")
    assert [(p.symbol.name(), p.value) for p in flat.casadi.parameters] == [("k", 5.0)]


@pytest.mark.parametrize("joined", [False, True], ids=["list", "os-pathsep"])
def test_library_of_several_folders(tmp_path, monkeypatch, joined):
    import os

    from cosim.compiler.library import load_library

    _library(tmp_path / "lib", DECAY)
    _library(tmp_path / "oracle", ORACLE)
    folders = [tmp_path / "lib", tmp_path / "oracle"]
    if joined:
        monkeypatch.setenv("COSIM_MODELICA_PATH", os.pathsep.join(map(str, folders)))
        load_library.cache_clear()
        library = load_library()
        load_library.cache_clear()
    else:
        library = Library(folders)
    assert library.errors == {} and library.paths == [f.resolve() for f in folders] + [DEFAULT_LIBRARY.resolve()]
    assert _own(library) == ["Disc.D", "P.M", "Oracle.N"]
    assert library.entry("Oracle.N").file == (tmp_path / "oracle" / "Oracle" / "package.mo").resolve()
    assert library.relative_name(library.entry("Oracle.N").file) == "1:Oracle/package.mo"
    flat = flatten(library, "Oracle.N")
    assert [(p.symbol.name(), p.value) for p in flat.casadi.parameters] == [("k", 3.0)]


def test_package_in_two_folders_comes_from_the_first(tmp_path):
    """MODELICAPATH: a top-level package is taken from the first folder that holds it; the later
    folder's copy is not parsed (its other packages are)."""
    _library(tmp_path / "lib", DECAY)
    _library(tmp_path / "copy", {"P/package.mo": DECAY["P/package.mo"].replace("M ", "Other ").replace("M;", "Other;"),
                                 "Q/package.mo": 'package Q "only here"\nend Q;\n'})
    library = Library([tmp_path / "lib", tmp_path / "copy"])
    copy = (tmp_path / "copy" / "P" / "package.mo").resolve()
    assert library.errors == {} and copy not in library.files
    assert (tmp_path / "copy" / "Q" / "package.mo").resolve() in library.files
    assert _own(library) == ["Disc.D", "P.M"]
    assert library.entry("P.M").file == (tmp_path / "lib" / "P" / "package.mo").resolve()


# -- 6. Array constructors with variables ----------------------------------------------------------

def _array_model(name: str, equations: str) -> dict[str, str]:
    return {"Arr/package.mo": f"""
        package Arr "Array constructors"
          model {name} "der(x) from an array expression"
            parameter Real m = 2 "Factor";
            Real x[2](each start = 1, each fixed = true) "State";
            Real A[2, 2] "Matrix";
          equation
            {equations}
          end {name};
        end Arr;
    """}


X = (0.5, 1.0)
M = 2.0


@pytest.mark.parametrize("equations, expected", [
    ("A = identity(2); der(x) = {1, m*x[1]};", (1.0, M * X[0])),
    ("A = identity(2); der(x) = -m*identity(2)*x;", (-M * X[0], -M * X[1])),
    ("A = identity(2); der(x) = -{1, 2};", (-1.0, -2.0)),
    ("A = identity(2); der(x) = {{1, 0}, {0, 3}}*x*m;", (M * X[0], 3 * M * X[1])),
    ("A = [cos(x[1]), 0; 0, 1]; der(x) = A*x;", (math.cos(X[0]) * X[0], X[1])),
    ("A = {{cos(x[1]), m}, {0, x[2]}}; der(x) = A*x;", (math.cos(X[0]) * X[0] + M * X[1], X[1] * X[1])),
], ids=["vector-with-variable", "minus-m-identity", "minus-literal-vector", "literal-matrix-times-vector",
        "matrix-syntax", "nested-braces-with-variables"])
def test_array_constructors_with_variables(tmp_path, equations, expected):
    library = _library(tmp_path, _array_model("Arr", equations))
    _, explicit, _ = _explicit(library, "Arr.Arr")
    f = ca.Function("f", [explicit.x, explicit.p], [explicit.xdot])
    assert [s.name for s in explicit.states] == ["x[1]", "x[2]"]
    parameters = [s.start for s in explicit.parameters]
    assert f(ca.DM(X), ca.DM(parameters)).full().ravel() == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("declaration, equation, calculated, expected", [
    ("parameter Real v[2] = {1, k} \"Rates\";", "der(x) = v;", ["v[1]", "v[2]"], [1.0, 5.0]),
    ("parameter Real K[2, 2] = -k*identity(2) \"Rate matrix\";", "der(x) = K*x;",
     ["K[1,1]", "K[2,1]", "K[1,2]", "K[2,2]"], [-5.0 * X[0], -5.0 * X[1]]),
], ids=["vector-of-parameters", "minus-k-identity"])
def test_array_parameter_bound_to_expression_of_parameters(tmp_path, declaration, equation, calculated, expected):
    files = {"Arr/package.mo": f"""
        package Arr "Array constructors"
          model Bound "An array parameter whose value uses another parameter"
            parameter Real k = 2 "Factor";
            {declaration}
            Real x[2](each start = 1, each fixed = true) "State";
          equation
            {equation}
          end Bound;
        end Arr;
    """}
    library = _library(tmp_path, files)
    _, explicit, info = _explicit(library, "Arr.Bound")
    assert [s.name for s in explicit.parameters] == ["k"]
    assert sorted(v.name for v in info.variables if v.causality == "calculatedParameter") == sorted(calculated)
    f = ca.Function("f", [explicit.x, explicit.p], [explicit.xdot])
    assert f(ca.DM(X), ca.DM([5.0])).full().ravel() == pytest.approx(expected, rel=1e-12)


# -- 7. Modified constants through several levels (MLS 7.2) -----------------------------------------

NESTED = {
    "Nest/package.mo": """
        package Nest "Constants modified through several levels of components, each with a default"
          connector C "A connector sized by n"
            constant Integer n = 2 "Size";
            Real du[n] "Potential";
            flow Real F[n] "Flow";
          end C;
          model J "Sized by n: states, a connector, the unit vector of column k, ni = n - 1 elements"
            constant Integer n = 2 "Size";
            constant Integer ni = n - 1 "Depends on n";
            constant Integer k = 1 "Column";
            C c(n = n) "Connector";
            Real x[n](each start = 1, each fixed = true) "States";
            Real e[n] "Unit vector of column k";
            Real s[ni] "ni elements";
          equation
            der(x) = -x;
            c.du = x;
            for j in 1:n loop
              e[j] = if j == k then 1 else 0;
            end for;
            for j in 1:ni loop
              s[j] = j*n + k;
            end for;
          end J;
          model B "J one level down"
            constant Integer n = 2 "Size";
            constant Integer k = 1 "Column";
            J j(n = n, k = k) "Component";
          end B;
          model Sys "b at depth 1, b.j at depth 2, b.j.c at depth 3"
            constant Integer n = 3 "Size";
            B b(n = n, k = 3) "Component";
          end Sys;
          model D "B one level down"
            constant Integer n = 2 "Size";
            constant Integer k = 1 "Column";
            B b(n = n, k = k) "Component";
          end D;
          model Sys4 "Four levels: d, d.b, d.b.j, d.b.j.c"
            D d(n = 5, k = 2) "Component";
          end Sys4;
          model Explicit "The nested modifiers written out"
            constant Integer n = 3 "Size";
            B b(n = n, k = 2, j(n = n, k = 2, c(n = n))) "Component";
          end Explicit;
          model Inherited "J as a base class"
            extends J;
          end Inherited;
          model SysInherited "Inherited constants modified from outside"
            Inherited a(n = 4, k = 2) "Component";
          end SysInherited;
          model Ext "B as a base class, its constants given by the modifiers of extends"
            constant Integer m = 2 "Size";
            extends B(n = m, k = 2);
          end Ext;
          model SysExt "The constant of the modifier of extends modified from outside"
            Ext a(m = 3) "Component";
          end SysExt;
          partial model PartialWheel "A wheel: J's contents"
            extends J;
          end PartialWheel;
          model Knife "A wheel"
            extends PartialWheel;
            Real r "Radius";
          equation
            r = 1;
          end Knife;
          model Torus "Another wheel, with ni more variables"
            extends PartialWheel;
            Real r "Radius";
            Real t[ni] "Sized by ni";
          equation
            r = 2;
            t = 2*s;
          end Torus;
          model Bike "A replaceable wheel, the constants given in its constraining clause"
            constant Integer n = 2 "Size";
            replaceable Torus w constrainedby PartialWheel(n = n, k = 2) "Wheel";
          end Bike;
          model SysBike "The bike's n modified: w at depth 2, w.c at depth 3"
            Bike bike(n = 4) "Bike";
          end SysBike;
          model SysKnife "The wheel redeclared"
            Bike bike(n = 5, redeclare Knife w) "Bike";
          end SysKnife;
        end Nest;
    """,
}


def _without_defaults() -> dict[str, str]:
    """NESTED with the modified constants declared without a value (``constant Integer n;``)."""
    text = NESTED["Nest/package.mo"]
    for default in ("n = 2", "k = 1", "m = 2"):
        text = text.replace(f"constant Integer {default} ", f"constant Integer {default[0]} ")
    assert "constant Integer n = 3 " in text and "constant Integer n = 2" not in text
    return {"Nest/package.mo": text}


def _constants(flat) -> dict:
    """The flat model's constants: a value, or the text of what stands for it (a reference, nan)."""
    return {str(c.symbol.name()): c.value if isinstance(c.value, int) else str(c.value) for c in flat.casadi.constants}


def _assert_sized_by(flat, explicit, j: str, n: int, k: int, extra: dict[str, int] | None = None):
    """The instance ``j`` of Nest.J (prefix of its flat names) has the constants n, ni = n - 1, k;
    its arrays, its connector's and the for loops have n and ni elements; e is the unit vector of
    column k and s[i] = i*n + k."""
    constants = _constants(flat)
    assert {name: constants[f"{j}.{name}"] for name in ("n", "ni", "k", "c.n")} == {"n": n, "ni": n - 1, "k": k,
                                                                                    "c.n": n}
    # every constant of the flat model has a value (no stray name of a lost prefix, no reference left)
    assert all(isinstance(v, int) for v in constants.values()), constants
    sizes = {str(v.symbol.name()): v.symbol.numel() for v in flat.casadi.states + flat.casadi.alg_states}
    expected = {f"{j}.x": n, f"{j}.c.du": n, f"{j}.c.F": n, f"{j}.e": n, f"{j}.s": n - 1}
    expected.update(extra or {})
    assert sizes == expected
    assert [s.name for s in explicit.states] == [f"{j}.x[{i}]" for i in range(1, n + 1)]
    values = _evaluate(explicit, {})
    assert [values[f"{j}.e[{i}]"] for i in range(1, n + 1)] == [1.0 if i == k else 0.0 for i in range(1, n + 1)]
    assert [values[f"{j}.s[{i}]"] for i in range(1, n)] == [float(i * n + k) for i in range(1, n)]
    assert [values[f"{j}.c.F[{i}]"] for i in range(1, n + 1)] == [0.0] * n  # unconnected flows
    return values


@pytest.mark.parametrize("defaults", [True, False], ids=["with-defaults", "without-defaults"])
@pytest.mark.parametrize("model, j, n, k", [
    ("Nest.Sys", "b.j", 3, 3),
    ("Nest.Sys4", "d.b.j", 5, 2),
    ("Nest.Explicit", "b.j", 3, 2),
], ids=["three-levels", "four-levels", "nested-modifiers-written-out"])
def test_modified_constants_reach_every_level(tmp_path, model, j, n, k, defaults):
    """MLS 7.2: in ``j(n = n)`` the right-hand ``n`` is the one of the enclosing instance, whose
    value is its own modifier's (``b(n = 3)``), not the default of its class: pymoca took the first
    value of the chain (the default 2) from the second level down."""
    library = _library(tmp_path, NESTED if defaults else _without_defaults())
    flat, explicit, _ = _explicit(library, model)
    _assert_sized_by(flat, explicit, j, n, k)


@pytest.mark.parametrize("model, j, n", [("Nest.SysInherited", "a", 4), ("Nest.SysExt", "a.j", 3)],
                         ids=["inherited-constants-modified", "constants-in-modifiers-of-extends"])
def test_modified_constants_through_extends(tmp_path, model, j, n):
    """Names in an inherited class (``c(n = n)`` of J in ``Inherited a(n = 4)``, ``j(n = n)`` of B in
    ``extends B(n = m)``) are those of the instance, modifiers of extends and of the component
    included: pymoca looked them up in a copy of the base class made anew with its defaults."""
    library = _library(tmp_path, NESTED)
    flat, explicit, _ = _explicit(library, model)
    _assert_sized_by(flat, explicit, j, n, 2)
    if model == "Nest.SysExt":
        constants = _constants(flat)
        assert (constants["a.m"], constants["a.n"]) == (3, 3)


@pytest.mark.parametrize("model, n, extra, r", [
    ("Nest.SysBike", 4, {"t": 3, "r": 1}, 2.0),
    ("Nest.SysKnife", 5, {"r": 1}, 1.0),
], ids=["default-wheel", "redeclared-wheel"])
def test_modified_constants_in_a_constraining_clause(tmp_path, model, n, extra, r):
    """``replaceable Torus w constrainedby PartialWheel(n = n, k = 2)`` with ``bike(n = 4)``: the
    wheel and its connector have n = 4, also when the wheel is redeclared (pymoca's instance of the
    redeclared class lost the component's name: its connector's constant became ``bike.c.n``)."""
    library = _library(tmp_path, NESTED)
    flat, explicit, _ = _explicit(library, model)
    values = _assert_sized_by(flat, explicit, "bike.w", n, 2, {f"bike.w.{v}": size for v, size in extra.items()})
    assert values["bike.w.r"] == r
    if "t" in extra:
        assert [values[f"bike.w.t[{i}]"] for i in range(1, n)] == [2.0 * (i * n + 2) for i in range(1, n)]
