"""The structure of cosim/compiler/ode.py's explicit model: tearing of linear algebraic loops, declared
states without der() (algebraic variables) and states of components named by their top-level
alias. Each test writes a tiny library into ``tmp_path``, flattens it, makes it explicit and
compares with a hand-computed solution."""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import casadi as ca
import numpy as np
import pytest

from cosim.compiler.codegen import start_function
from cosim.compiler.model_description import model_description_xml
from cosim.compiler.ode import _tear
from cosim.errors import ModelStructureError
from test_pymoca_patches import _explicit, _library


def _values(explicit, x=None, inputs=None, parameters=None) -> dict[str, float]:
    """State derivatives (``der(name)``) and algebraic variables at time 0 for the given states,
    inputs and parameters (by name; states and inputs 0, parameters at their values unless given)."""
    x, inputs, parameters = x or {}, inputs or {}, parameters or {}
    f = ca.Function("f", [explicit.t, explicit.x, explicit.u, explicit.p], [explicit.xdot, explicit.z])
    xdot, z = f(0.0, [x.get(s.name, 0.0) for s in explicit.states], [inputs.get(s.name, 0.0) for s in explicit.inputs],
                [parameters.get(s.name, s.start) for s in explicit.parameters])
    values = {f"der({s.name})": float(v) for s, v in zip(explicit.states, np.asarray(xdot).ravel())}
    values.update({s.name: float(v) for s, v in zip(explicit.algebraics, np.asarray(z).ravel())})
    return values


# -- 1. Tearing of linear loops ---------------------------------------------------------------------

# Kane's method with connectors that pair the generalized accelerations du (potential) with the
# generalized forces including inertia forces F (flow): the root writes du = S*dui + a0 and
# transpose(S)*F = 0, each body F = f - M*du, the connections alias du and sum F. A double pendulum
# (point masses m1, m2 on rods L1, L2 with rotational inertias J1, J2; absolute angles th from the
# downward vertical) with the generalized speeds {w1, w2, v1x, v1y, v2x, v2y}: two independent
# ones (the rates w) and the velocities of the masses as dependent ones.
KANE = {
    "Kane/package.mo": """
        package Kane "Kane-style assemblies"
          connector Frame "Generalized accelerations (potential) and generalized forces with inertia forces (flow)"
            parameter Integer n = 6 "Number of generalized speeds";
            Real du[n] "Generalized accelerations";
            flow Real F[n] "Generalized forces, inertia forces included";
          end Frame;

          model Root "Kinematics du = S*dui + a0 and Kane's equations transpose(S)*F = 0"
            parameter Real L1 = 1.1 "Length of rod 1";
            parameter Real L2 = 0.7 "Length of rod 2";
            Real th[2](each fixed = true, start = {0.3, -0.4}) "Absolute rod angles";
            Real w[2](each fixed = true, start = {0.5, 1.2}) "Angular rates";
            Real dui[2] "Independent accelerations";
            Real S[6, 2] "Partial velocities";
            Real a0[6] "Acceleration remainder";
            Frame frame(n = 6);
          equation
            der(th) = w;
            der(w) = dui;
            S = [1, 0; 0, 1; L1*cos(th[1]), 0; L1*sin(th[1]), 0; L1*cos(th[1]), L2*cos(th[2]);
                 L1*sin(th[1]), L2*sin(th[2])];
            a0 = {0, 0, -L1*sin(th[1])*w[1]^2, L1*cos(th[1])*w[1]^2,
                  -L1*sin(th[1])*w[1]^2 - L2*sin(th[2])*w[2]^2, L1*cos(th[1])*w[1]^2 + L2*cos(th[2])*w[2]^2};
            frame.du = S*dui + a0;
            transpose(S)*frame.F = zeros(2);
          end Root;

          model Body "Generalized inertia and applied forces of a diagonal mass matrix: F = f - diagonal(m)*du"
            parameter Real m[6] = zeros(6) "Diagonal of the generalized mass matrix";
            parameter Real f[6] = zeros(6) "Generalized applied forces";
            Frame frame(n = 6);
          equation
            for i in 1:6 loop
              frame.F[i] = f[i] - m[i]*frame.du[i];
            end for;
          end Body;

          model DoublePendulum "Two point masses with rotational inertias on rods"
            parameter Real m1 = 1.3;
            parameter Real m2 = 0.8;
            parameter Real J1 = 0.05;
            parameter Real J2 = 0.03;
            parameter Real g = 9.81;
            Root root;
            Body mass1(m = {0, 0, m1, m1, 0, 0}, f = {0, 0, 0, -m1*g, 0, 0});
            Body mass2(m = {0, 0, 0, 0, m2, m2}, f = {0, 0, 0, 0, 0, -m2*g});
            Body disk1(m = {J1, 0, 0, 0, 0, 0});
            Body disk2(m = {0, J2, 0, 0, 0, 0});
          equation
            connect(root.frame, mass1.frame);
            connect(mass1.frame, mass2.frame);
            connect(mass2.frame, disk1.frame);
            connect(disk1.frame, disk2.frame);
          end DoublePendulum;
        end Kane;
    """,
}


def _double_pendulum(th1, th2, w1, w2, m1, m2, J1, J2, g, L1, L2):
    """Angular accelerations of the double pendulum from Lagrange's equations."""
    c, s = math.cos(th1 - th2), math.sin(th1 - th2)
    mass = np.array([[(m1 + m2) * L1**2 + J1, m2 * L1 * L2 * c], [m2 * L1 * L2 * c, m2 * L2**2 + J2]])
    force = np.array([-m2 * L1 * L2 * s * w2**2 - (m1 + m2) * g * L1 * math.sin(th1),
                      m2 * L1 * L2 * s * w1**2 - m2 * g * L2 * math.sin(th2)])
    return np.linalg.solve(mass, force)


def test_kane_assembly_tears_to_the_independent_accelerations(tmp_path):
    """The loop of all generalized accelerations and forces (tens of unknowns) is solved as a 2x2
    system in the two independent accelerations; the accelerations are those of Lagrange's
    equations."""
    _, explicit, _ = _explicit(_library(tmp_path, KANE), "Kane.DoublePendulum")
    assert [s.name for s in explicit.states] == ["root.th[1]", "root.th[2]", "root.w[1]", "root.w[2]"]
    assert len(explicit.loops) == 1
    unknowns, tears = explicit.loops[0]
    assert unknowns > 20 and tears == 2
    parameters = {"m1": 1.3, "m2": 0.8, "J1": 0.05, "J2": 0.03, "g": 9.81, "root.L1": 1.1, "root.L2": 0.7}
    rng = np.random.default_rng(3)
    for th1, th2, w1, w2 in rng.uniform(-2.0, 2.0, (4, 4)):
        values = _values(explicit, {"root.th[1]": th1, "root.th[2]": th2, "root.w[1]": w1, "root.w[2]": w2})
        expected = _double_pendulum(th1, th2, w1, w2, *parameters.values())
        assert values["der(root.th[1])"] == w1 and values["der(root.th[2])"] == w2
        assert values["der(root.w[1])"] == pytest.approx(expected[0], abs=1e-12)
        assert values["der(root.w[2])"] == pytest.approx(expected[1], abs=1e-12)
        # the first of Kane's equations: the root's generalized forces along the partial velocities of w1
        F = [values[f"root.frame.F[{k}]"] for k in range(1, 7)]
        kane = F[0] + 1.1 * (math.cos(th1) * (F[2] + F[4]) + math.sin(th1) * (F[3] + F[5]))
        assert kane == pytest.approx(0, abs=1e-12)


def _kane_structure(n: int, independent: tuple[int, ...], bodies: int, identity_rows: bool):
    """The structure of the loop of a Kane assembly as :func:`_tear` takes it (unknown -> whether it
    can be assigned from the equation) and the names of the unknowns: a root ``du = S*dui + D*ad0``
    (``S`` symbolic; with unit rows for the independent accelerations when ``identity_rows``) and
    ``transpose(S)*F = 0``; bodies ``F = f - M*du`` with a full symbolic ``M``; the frames
    connected in a chain (aliases of ``du``) and one sum of ``F``."""
    names = []

    def unknown(name):
        names.append(name)
        return len(names) - 1

    dui = [unknown(f"dui[{j + 1}]") for j in range(len(independent))]
    du = [[unknown(f"body{b}.du[{k + 1}]") for k in range(n)] for b in range(bodies + 1)]  # body0: the root
    F = [[unknown(f"body{b}.F[{k + 1}]") for k in range(n)] for b in range(bodies + 1)]
    equations = []
    for k in range(n):  # du[k] - S[k, :]*dui - D[k]*ad0
        row = {du[0][k]: True}
        for j, i in enumerate(independent):
            if not identity_rows or k not in independent:
                row[dui[j]] = False
            elif k == i:
                row[dui[j]] = True
        equations.append(row)
    for i in independent:  # transpose(S)*F: the unit rows of S give numeric coefficients
        equations.append({F[0][k]: identity_rows and k == i for k in range(n)
                          if not identity_rows or k == i or k not in independent})
    for b in range(1, bodies + 1):
        for k in range(n):
            equations.append({F[b][k]: True, **{du[b][c]: False for c in range(n)}})  # F - f + M*du
            equations.append({du[b - 1][k]: True, du[b][k]: True})  # connection: alias
    for k in range(n):
        equations.append({F[b][k]: True for b in range(bodies + 1)})  # connection: sum of flows
    return equations, names


@pytest.mark.parametrize("identity_rows", [True, False], ids=["unit-rows", "symbolic-rows"])
@pytest.mark.parametrize("n, bodies", [(8, 4), (12, 20)])
def test_tearing_of_a_bicycle_sized_kane_structure(identity_rows, n, bodies):
    """Three independent accelerations among n generalized accelerations, bodies with full mass
    matrices: three tear variables (the independent accelerations or their aliases), every other
    unknown assigned from an equation in which it has a numeric coefficient once the unknowns
    assigned before are known."""
    equations, names = _kane_structure(n, (2, 4, 7), bodies, identity_rows)
    assert len(equations) == len(names)
    assignments, tears, residual_rows = _tear(equations, len(names))
    assert len(tears) == 3 and len(residual_rows) == 3
    assert sorted([v for v, _ in assignments] + tears) == list(range(len(names)))
    assert sorted([e for _, e in assignments] + residual_rows) == list(range(len(equations)))
    known = set(tears)
    for v, e in assignments:
        assert equations[e][v] and set(equations[e]) - {v} <= known
        known.add(v)
    # each tear variable is an independent acceleration or an alias of one, one for each
    coordinate = {f"dui[{j + 1}]": i for j, i in enumerate((2, 4, 7))}
    coordinate.update({f"body{b}.du[{i + 1}]": i for b in range(bodies + 1) for i in (2, 4, 7)})
    assert sorted(coordinate[names[t]] for t in tears) == [2, 4, 7]


LOOPS = {
    "Loops/package.mo": """
        package Loops "Linear loops"
          model Mixed "A loop of four unknowns whose only numeric coefficients do not involve k"
            parameter Real k = 0 "Coefficient of a in the first equation";
            input Real u1;
            input Real u2;
            input Real u3;
            Real a;
            Real b;
            Real c;
            Real d;
          equation
            k*a + b = u1;
            b = c;
            c + d = u2;
            a - d = u3;
          end Mixed;

          model Symbolic "A loop of four unknowns in which every coefficient is a parameter"
            parameter Real p[4] = {2, 3, 5, 7};
            parameter Real q[4] = {1, -1, 2, 0.5};
            input Real u[4];
            Real a;
            Real b;
            Real c;
            Real d;
          equation
            p[1]*a + q[1]*b = u[1];
            p[2]*b + q[2]*c = u[2];
            p[3]*c + q[3]*d = u[3];
            p[4]*d + q[4]*a = u[4];
          end Symbolic;

          model Small "A loop of three unknowns: solved as one linear system, as before tearing"
            input Real u1;
            input Real u2;
            Real a;
            Real b;
            Real c;
          equation
            a = b;
            b + c = u1;
            c - 2*a = u2;
          end Small;
        end Loops;
    """,
}


@pytest.mark.parametrize("k", [0.0, 2.0, -0.5])
def test_tearing_never_divides_by_a_symbolic_coefficient(tmp_path, k):
    """The loop is torn to one unknown (one residual equation) without dividing by k: the solution
    at k = 0 is finite and exact."""
    _, explicit, _ = _explicit(_library(tmp_path, LOOPS), "Loops.Mixed")
    assert explicit.loops == [(4, 1)]
    inputs = {"u1": 0.7, "u2": -1.3, "u3": 2.1}
    values = _values(explicit, inputs=inputs, parameters={"k": k})
    A = np.array([[k, 1, 0, 0], [0, 1, -1, 0], [0, 0, 1, 1], [1, 0, 0, -1]])
    expected = np.linalg.solve(A, [0.7, 0.0, -1.3, 2.1])
    assert [values[n] for n in "abcd"] == pytest.approx(expected, abs=1e-13)


def test_loop_of_symbolic_coefficients_is_solved_as_one_system(tmp_path):
    """No unknown can be assigned without dividing by a parameter: the loop is solved as one
    linear system, also where a parameter is zero."""
    _, explicit, _ = _explicit(_library(tmp_path, LOOPS), "Loops.Symbolic")
    assert explicit.loops == [(4, 4)]
    u = [0.3, -1.1, 0.8, 2.5]
    for p, q in (([2, 3, 5, 7], [1, -1, 2, 0.5]), ([0, 3, 5, 7], [1, -1, 2, 0.5]), ([2, 0, 0, 7], [1, -1, 2, 3])):
        parameters = {f"p[{i + 1}]": v for i, v in enumerate(p)} | {f"q[{i + 1}]": v for i, v in enumerate(q)}
        values = _values(explicit, inputs={f"u[{i + 1}]": v for i, v in enumerate(u)}, parameters=parameters)
        A = np.array([[p[0], q[0], 0, 0], [0, p[1], q[1], 0], [0, 0, p[2], q[2]], [q[3], 0, 0, p[3]]])
        assert [values[n] for n in "abcd"] == pytest.approx(np.linalg.solve(A, u), abs=1e-13)


def test_small_loop_is_not_torn(tmp_path):
    _, explicit, _ = _explicit(_library(tmp_path, LOOPS), "Loops.Small")
    assert explicit.loops == [(3, 3)]
    values = _values(explicit, inputs={"u1": 1.0, "u2": 4.0})
    assert [values[n] for n in "abc"] == pytest.approx([-1.0, -1.0, 2.0], abs=1e-14)


# -- 2. A declared state without der() is algebraic ---------------------------------------------------

DEPENDENT = {
    "Dep/package.mo": """
        package Dep "Coordinates that are states or given"
          model Coordinate "Integrated, or equal to the input ud when dep"
            constant Boolean dep = false "Given by ud instead of integrated";
            parameter Real a = 2 "Rate when integrated";
            input Real ud "The coordinate when dep";
            Real s(start = 1) "Coordinate";
          equation
            if dep then
              s = ud;
            else
              der(s) = -a;
            end if;
          end Coordinate;

          model Pair "A given and an integrated coordinate"
            input Real ud(start = 0.5) "Given coordinate";
            Coordinate given(dep = true, ud = ud) "Equal to ud";
            Coordinate free(ud = ud, a = 3) "Integrated";
            Real y(start = 0, fixed = true) "Integral of the given coordinate";
          equation
            der(y) = given.s;
          end Pair;

          model Fixed "fixed = true on a coordinate that is given"
            input Real ud;
            Coordinate given(dep = true, ud = ud, s(fixed = true));
          end Fixed;
        end Dep;
    """,
}


def test_state_whose_der_is_in_a_dropped_branch_is_algebraic(tmp_path):
    _, explicit, info = _explicit(_library(tmp_path, DEPENDENT), "Dep.Pair")
    assert [s.name for s in explicit.states] == ["y", "free.s"]
    assert "given.s" in [s.name for s in explicit.algebraics]
    assert info.variable("given.s").role == "algebraic"
    values = _values(explicit, inputs={"ud": 0.25})
    assert values["given.s"] == 0.25 and values["der(y)"] == 0.25 and values["der(free.s)"] == -3.0


def test_fixed_on_a_state_without_der_is_refused(tmp_path):
    """``fixed = true`` on a variable that is not a state would be the initial equation s = start."""
    with pytest.raises(ModelStructureError, match=r"'given\.s' is not a state but has fixed = true"):
        _explicit(_library(tmp_path, DEPENDENT), "Dep.Fixed")


# -- 3. States of components named by their top-level alias -------------------------------------------

ALIAS = {
    "Alias/package.mo": """
        package Alias "Joints that own their coordinates"
          type Angle = Real(final quantity = "Angle", final unit = "rad");

          model Joint "A joint whose angle is a state that starts at angle0"
            parameter Real angle0 = 0.1 "Initial angle";
            parameter Real k = 4 "Stiffness";
            Angle angle(start = angle0, fixed = true) "Joint angle";
            Real omega(start = 0.5, fixed = true) "Joint rate";
          equation
            der(angle) = omega;
            der(omega) = -k*angle;
          end Joint;

          model FreeJoint "A joint whose angle is solved from initial equations"
            Angle angle(start = 0.3, fixed = false) "Joint angle (start: the guess)";
            Real omega(start = 0, fixed = true) "Joint rate";
            Angle link "The angle, passed on";
          equation
            link = angle;
            der(angle) = omega;
            der(omega) = -sin(angle);
          end FreeJoint;

          model Assembly "Joint coordinates named for the FMU by top-level declarations"
            parameter Real L = 2 "Radius";
            parameter Real h = 1 "Initial height";
            Alias.Joint steer(angle0 = 0.2) "Steering joint";
            Alias.FreeJoint lean "Lean joint";
            output Angle delta = steer.angle "Steer angle, positive to the left";
            output Angle phi = lean.link "Lean angle";
            Real steer2 = steer.angle "A second name of the steer angle";
            output Real height "Height at radius L";
            Real rate "The steer rate, equated in the equation section";
          initial equation
            height = h;
          equation
            height = L*sin(phi);
            rate = steer.omega;
            annotation(__Cosim(export = true));
          end Assembly;
        end Alias;
    """,
}


def test_component_state_is_named_by_its_top_level_alias(tmp_path):
    library = _library(tmp_path, ALIAS)
    _, explicit, info = _explicit(library, "Alias.Assembly")
    # renamed states in the order of the top-level declarations, then the states that keep their names
    assert [s.name for s in explicit.states] == ["delta", "phi", "steer.omega", "lean.omega"]
    delta, der_delta = info.variable("delta"), info.variable("der(delta)")
    assert (delta.role, delta.causality, delta.description, delta.unit) == (
        "state", "output", "Steer angle, positive to the left", "rad")
    assert der_delta.role == "derivative" and der_delta.derivative_of == delta.position and der_delta.unit == "rad/s"
    assert info.variable("phi").initial == "approx"
    for name in ("steer.angle", "steer2", "lean.angle", "lean.link", "rate"):
        assert info.variable(name).role == "algebraic" and info.variable(name).causality == "local"
    assert not any(v.name in ("der(steer.angle)", "der(lean.angle)") for v in info.variables)

    # start values: delta from steer(angle0 = 0.2), phi (fixed = false) solved from height = h
    parameters = [s.start for s in explicit.parameters]
    assert explicit.init_unknowns == [1]
    start = start_function(explicit)
    x0, residual = start(0.0, ca.DM.zeros(0), parameters, ca.DM.zeros(4), ca.DM.zeros(4))
    x0 = np.asarray(x0).ravel()
    assert x0 == pytest.approx([0.2, math.asin(1 / 2), 0.5, 0.0], abs=1e-12)
    assert float(residual) == pytest.approx(0.0, abs=1e-12)
    angle0 = [s.name for s in explicit.parameters].index("steer.angle0")
    assert float(ca.Function("x0", [explicit.p], [explicit.x0])(
        [7.0 if k == angle0 else v for k, v in enumerate(parameters)])[0]) == 7.0

    # the component's names are local aliases of the states; der(delta) is the joint's equation
    values = _values(explicit, dict(zip(["delta", "phi", "steer.omega", "lean.omega"], [0.3, -0.2, 1.5, 0.1])))
    assert values["steer.angle"] == 0.3 and values["steer2"] == 0.3 and values["lean.angle"] == -0.2
    assert values["lean.link"] == -0.2 and values["rate"] == 1.5
    assert values["der(delta)"] == 1.5 and values["der(steer.omega)"] == pytest.approx(-4 * 0.3, abs=1e-15)
    assert values["der(phi)"] == 0.1 and values["height"] == pytest.approx(2 * math.sin(-0.2), abs=1e-15)

    # modelDescription.xml: der(delta) is the derivative of delta in ModelStructure
    root = ET.fromstring(model_description_xml(info, "test"))
    variables = root.find("ModelVariables").findall("ScalarVariable")
    index = {v.get("name"): k + 1 for k, v in enumerate(variables)}
    real = variables[index["der(delta)"] - 1].find("Real")
    assert real.get("derivative") == str(index["delta"])
    derivatives = [int(u.get("index")) for u in root.find("ModelStructure").find("Derivatives")]
    assert index["der(delta)"] in derivatives


def test_built_fmu_has_the_state_under_its_top_level_name(tmp_path):
    from fmpy import read_model_description, simulate_fmu

    from cosim.compiler.build import build_model

    library = _library(tmp_path / "lib", ALIAS)
    fmu = build_model("Alias.Assembly", tmp_path / "fmus", library).fmu
    md = read_model_description(str(fmu))
    assert [d.variable.derivative.name for d in md.derivatives] == ["delta", "phi", "steer.omega", "lean.omega"]
    assert md.derivatives[0].variable.name == "der(delta)"
    delta = next(v for v in md.modelVariables if v.name == "delta")
    assert (delta.causality, delta.unit, delta.description) == ("output", "rad", "Steer angle, positive to the left")
    result = simulate_fmu(str(fmu), stop_time=0.5, output_interval=0.25,
                          output=["delta", "steer.angle", "phi", "lean.angle", "height"])
    assert result["delta"][0] == pytest.approx(0.2, abs=1e-12)
    assert result["phi"][0] == pytest.approx(math.asin(1 / 2), abs=1e-12)
    assert result["height"][0] == pytest.approx(1.0, abs=1e-12)
    assert list(result["steer.angle"]) == list(result["delta"]) and list(result["lean.angle"]) == list(result["phi"])
    # der(delta) = steer.omega, der(steer.omega) = -4 delta: delta = 0.2 cos(2t) + 0.25 sin(2t)
    assert result["delta"][-1] == pytest.approx(0.2 * math.cos(1.0) + 0.25 * math.sin(1.0), abs=1e-6)
