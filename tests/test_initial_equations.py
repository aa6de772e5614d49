"""States declared ``fixed = false`` solved from ``initial equation``s by the FMU's Newton solve at
initialization: analytic solutions, parameters, inputs and guesses set before initialization,
non-convergence (fmi2Error naming the unknowns), unbalanced initial equations refused at build."""
from __future__ import annotations

import math
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from cosim.compiler.build import build_model
from cosim.compiler.library import Library
from cosim.errors import ModelicaError

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

PACKAGE = "InitTest"

# A point on a circle of radius L started at height h: theta0 = asin(h/L) near the guess 0.3, or
# pi - asin(h/L) from a guess beyond pi/2. No real solution for |h| > L.
CIRCLE = """within InitTest;
model Circle "a point on a circle of radius L whose initial height is h"
  parameter Real L = 2 "radius [m]";
  parameter Real h = 1 "initial height [m]";
  parameter Real thetaGuess = 0.3 "guess of the initial angle [rad]";
  Real theta(start = thetaGuess, fixed = false) "angle [rad]";
  Real omega(start = 0.5, fixed = true) "angular rate [rad/s]";
  output Real y "height [m]";
initial equation
  y = h;
equation
  y = L*sin(theta);
  der(theta) = omega;
  der(omega) = -sin(theta);
  annotation(__Cosim(export = true));
end Circle;
"""

# Two unknowns of one nonlinear system with the fixed state c (declared between them) in it:
# a^2 + b^2 = c^2, a - b = d gives a = (d + sqrt(2 c^2 - d^2))/2, b = a - d.
PAIR = """within InitTest;
model Pair "two unknowns of a nonlinear initial system that involves the fixed state c"
  parameter Real d = 0.5 "difference of the unknowns";
  Real a(start = 1, fixed = false) "first unknown";
  Real c(start = 2, fixed = true) "radius, a fixed state";
  Real b(start = 1, fixed = false) "second unknown";
initial equation
  a^2 + b^2 = c^2;
  a - b = d;
equation
  der(a) = -a;
  der(c) = 0;
  der(b) = -b;
  annotation(__Cosim(export = true));
end Pair;
"""

# Steady state from an initial equation on a derivative (v0 = F/d, F an input) and an explicit
# initial value x0 = 2 k written as an initial equation.
STEADY = """within InitTest;
model Steady "a damped mass started in steady state"
  input Real F(start = 2) "force [N]";
  parameter Real d = 4 "damping [N.s/m]";
  parameter Real k = 1.5 "position scale [m]";
  Real v(start = 0, fixed = false) "velocity [m/s]";
  Real x(start = 0, fixed = false) "position [m]";
initial equation
  der(v) = 0;
  x = 2*k;
equation
  der(v) = F - d*v;
  der(x) = v;
  annotation(__Cosim(export = true));
end Steady;
"""

# log(x) = 1 from the guess -1: the residual is NaN from the first iteration on (fast_newton itself
# reports success); from a positive guess x0 = e.
LOG = """within InitTest;
model Log "an initial equation whose residual is NaN at a negative guess"
  parameter Real guess = -1 "guess of the initial value";
  Real x(start = guess, fixed = false) "unknown";
initial equation
  log(x) = 1;
equation
  der(x) = 0;
  annotation(__Cosim(export = true));
end Log;
"""
MODELS = {"Circle": CIRCLE, "Pair": PAIR, "Steady": STEADY, "Log": LOG}


def library(tmp_path: Path, classes: dict[str, str]) -> Path:
    """A library folder holding the package InitTest with the given classes (name -> text)."""
    package = tmp_path / "lib" / PACKAGE
    package.mkdir(parents=True)
    (package / "package.mo").write_text(f'within;\npackage {PACKAGE} "initial equation tests"\nend {PACKAGE};\n')
    (package / "package.order").write_text("".join(f"{name}\n" for name in classes))
    for name, text in classes.items():
        (package / f"{name}.mo").write_text(text)
    return tmp_path / "lib"


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> dict[str, Path]:
    """The FMUs of the models above: class name -> FMU."""
    tmp_path = tmp_path_factory.mktemp("initial-equations")
    lib = Library(library(tmp_path, MODELS))
    return {name: build_model(f"{PACKAGE}.{name}", tmp_path / "fmus", lib).fmu for name in MODELS}


def initial(fmu: Path, names: list[str], fmi_type: str = "CoSimulation", **start_values) -> dict[str, float]:
    """The values of ``names`` at the start time after initialization with ``start_values``."""
    from fmpy import simulate_fmu

    result = simulate_fmu(str(fmu), stop_time=0.1, output_interval=0.05, fmi_type=fmi_type,
                          start_values=start_values, output=names)
    return {n: float(result[n][0]) for n in names}


class Messages(list):
    """An FMPy logger that keeps the messages (bytes) of the FMU."""

    def __call__(self, component, instance, status, category, message):
        self.append(message.decode())


# --- solutions -------------------------------------------------------------------------------

@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_angle_is_solved_from_nonlinear_initial_equation(built, fmi_type):
    values = initial(built["Circle"], ["theta", "omega", "y"], fmi_type)
    assert values["theta"] == pytest.approx(math.asin(1 / 2), abs=1e-12)
    assert values["y"] == pytest.approx(1.0, abs=1e-12)
    assert values["omega"] == 0.5  # a fixed state keeps its start value


@pytest.mark.parametrize("h", [0.5, 1.5, -1.9, 0.0], ids=lambda h: f"h={h}")
def test_parameter_set_before_initialization_changes_solved_angle(built, h):
    values = initial(built["Circle"], ["theta"], h=h)
    assert values["theta"] == pytest.approx(math.asin(h / 2), abs=1e-12)


@pytest.mark.parametrize("how", ["start-value-of-unknown", "guess-parameter"])
def test_guess_set_before_initialization_selects_the_other_root(built, how):
    """From a guess beyond pi/2 Newton converges to the other solution pi - asin(h/L)."""
    start = {"theta": 2.5} if how == "start-value-of-unknown" else {"thetaGuess": 2.5}
    values = initial(built["Circle"], ["theta"], **start)
    assert values["theta"] == pytest.approx(math.pi - math.asin(1 / 2), abs=1e-12)


def test_solve_waits_for_parameters_set_in_initialization_mode(built, tmp_path):
    """fmi2SetReal of a parameter in initializationMode (after a getter has solved once) counts:
    the initial equations are solved again with the current parameters."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    fmu = built["Circle"]
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu), unzipdir=str(tmp_path / "x")),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="circle")
    slave.instantiate()
    try:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        first = slave.getReal([vr["theta"]])[0]
        slave.setReal([vr["h"]], [1.5])
        second = slave.getReal([vr["theta"]])[0]
        slave.setReal([vr["L"]], [3.0])
        slave.exitInitializationMode()
        final = slave.getReal([vr["theta"], vr["y"]])
        slave.terminate()
    finally:
        slave.freeInstance()
    assert first == pytest.approx(math.asin(1 / 2), abs=1e-12)
    assert second == pytest.approx(math.asin(1.5 / 2), abs=1e-12)
    assert final[0] == pytest.approx(math.asin(1.5 / 3), abs=1e-12) and final[1] == pytest.approx(1.5, abs=1e-12)


@pytest.mark.parametrize("c", [2.0, 3.0], ids=["c-start", "c-set"])
def test_two_unknowns_with_a_fixed_state_in_the_initial_equations(built, c):
    values = initial(built["Pair"], ["a", "b", "c"], **({} if c == 2.0 else {"c": c}))
    a = (0.5 + math.sqrt(2 * c * c - 0.25)) / 2
    assert values["c"] == c
    assert values["a"] == pytest.approx(a, abs=1e-12) and values["b"] == pytest.approx(a - 0.5, abs=1e-12)


@pytest.mark.parametrize("force", [None, 3.0], ids=["input-start", "input-set"])
def test_steady_state_and_explicit_initial_value(built, force):
    """``der(v) = 0`` (the derivative replaced by the model equation, with an input in it) and
    ``x = 2*k`` as initial equations."""
    values = initial(built["Steady"], ["v", "x", "der(v)"], **({} if force is None else {"F": force}))
    assert values["v"] == pytest.approx((force or 2.0) / 4, abs=1e-12)
    assert values["der(v)"] == pytest.approx(0.0, abs=1e-12)
    assert values["x"] == pytest.approx(3.0, abs=1e-12)


def test_fmu_with_initial_equations_is_valid(built):
    """FMI 2: a solved state has initial = "approx" and its guess (at the default parameters) as
    start; FMPy's and cosim's validation (directional derivatives against differences) pass."""
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    from cosim.fmu.validate import validate_report

    for fmu in (built[name] for name in ("Circle", "Pair", "Steady")):  # Log does not initialize
        assert validate_fmu(str(fmu)) == [], fmu
        report = validate_report(fmu)
        assert (report.problems, report.warnings) == ([], []), fmu
    variables = {v.name: v for v in read_model_description(str(built["Circle"])).modelVariables}
    assert (variables["theta"].initial, float(variables["theta"].start)) == ("approx", 0.3)
    assert variables["omega"].initial == "exact"


# --- failures --------------------------------------------------------------------------------

FAILING = {  # model, start values, unknown, check of the reported |residual|
    "no-real-solution": ("Circle", {"h": 3.0}, "theta", lambda r: r >= 1.0),  # min |2 sin(theta) - 3| = 1
    "nan-residual": ("Log", {}, "x", math.isnan),
}


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
@pytest.mark.parametrize("case", list(FAILING))
def test_initial_equations_that_do_not_converge_are_an_fmi_error_naming_the_unknown(built, case, fmi_type):
    from fmpy import simulate_fmu
    from fmpy.fmi1 import FMICallException

    name, start_values, unknown, plausible = FAILING[case]
    messages = Messages()
    with pytest.raises(FMICallException, match="fmi2ExitInitializationMode"):
        simulate_fmu(str(built[name]), stop_time=0.1, fmi_type=fmi_type, start_values=start_values,
                     logger=messages)
    errors = [m for m in messages if "initialization failed" in m]
    assert len(errors) == 1, messages
    assert errors[0].startswith("fmi2ExitInitializationMode: "), errors[0]
    assert f"initial equations for {unknown} did not converge" in errors[0] and "|residual| = " in errors[0]
    assert plausible(float(errors[0].split("|residual| = ")[1].split(")")[0])), errors[0]


def test_positive_guess_solves_the_logarithm(built):
    assert initial(built["Log"], ["x"], guess=2.0)["x"] == pytest.approx(math.e, abs=1e-12)


def test_initial_equation_without_real_solution_through_cli(built, tmp_path):
    lib = Path(built["Circle"]).parents[1] / "lib"
    result = run_cli("simulate", f"{PACKAGE}.Circle", "--library", str(lib), "--param", "h=3", "--stop-time", "1",
                     "-o", str(tmp_path / "r.csv"), env={"COSIM_FMU_DIR": str(tmp_path / "fmus")})
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("cosim simulate: "), result.stderr
    assert "initial equations for theta did not converge" in lines[0], result.stderr
    assert not (tmp_path / "r.csv").exists()


BODY = "  Real w(start = 1, fixed = true) \"other state\";\n"
UNBALANCED = {
    "no-initial-equation": (BODY + "  Real theta(start = 0.3, fixed = false) \"unknown\";\nequation\n"
                            "  der(w) = -w;\n  der(theta) = w;",
                            ["Bad.mo:4:", "0 initial equation(s) for 1 unknown(s)", "theta"]),
    "no-unknown": (BODY + "initial equation\n  w = 2;\nequation\n  der(w) = -w;",
                   ["Bad.mo:4:", "1 initial equation(s) for 0 unknown(s)", "fixed = false"]),
    "too-many": (BODY + "  Real theta(start = 0.3, fixed = false) \"unknown\";\ninitial equation\n  theta = 1;\n"
                 "  sin(theta) = 0.5;\nequation\n  der(w) = -w;\n  der(theta) = w;",
                 ["Bad.mo:5:", "2 initial equation(s) for 1 unknown(s)", "theta"]),
    "singular": (BODY + "  Real a(start = 0, fixed = false) \"unknown\";\n  Real b(start = 0, fixed = false) \"unknown\";\n"
                 "initial equation\n  a = 1 + w;\n  a^2 = 2*w;\nequation\n  der(w) = -w;\n  der(a) = 0;\n  der(b) = 0;",
                 ["Bad.mo:6:", "do not determine", "undetermined: b"]),
}


@pytest.mark.parametrize("case", list(UNBALANCED))
def test_unbalanced_initial_equations_are_refused_at_build_with_file_and_line(tmp_path, case):
    body, fragments = UNBALANCED[case]
    text = f'within {PACKAGE};\nmodel Bad "unbalanced initialization"\n{body}\nend Bad;\n'
    lib = library(tmp_path, {"Bad": text})
    with pytest.raises(ModelicaError) as info:
        build_model(f"{PACKAGE}.Bad", tmp_path / "out", Library(lib))
    for fragment in fragments:
        assert fragment in str(info.value), str(info.value)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


# --- models without initial equations ---------------------------------------------------------

@pytest.mark.parametrize("name", ["Bicycle.Bicycles.WhippleLinear", "BicycleOracle.WhippleRider"])
def test_models_without_initial_equations_start_exactly_at_their_start_values(name):
    """Models without initial equations (the linear Whipple model, the flat generated oracle with its
    pitch as a calculated parameter) do not use the feature: no Newton solve is generated, no state
    is an iteration variable and every state with a literal start starts exactly there."""
    from fmpy import read_model_description, simulate_fmu

    root = Path(__file__).resolve().parents[1]
    library = Library([root / "modelica", root / "tests" / "oracle"])
    # into the session's FMU folder: tests/test_component_rider.py builds the same oracle there
    fmu = build_model(name, Path(os.environ["COSIM_FMU_DIR"]), library).fmu
    with zipfile.ZipFile(fmu) as archive:
        code = archive.read("sources/model_functions.c").decode()
    assert "cosim_init_newton" not in code and "fast_newton" not in code.lower()
    md = read_model_description(str(fmu))
    states = [v.derivative for v in md.modelVariables if v.derivative is not None]
    assert states and all(v.initial in ("exact", "calculated") for v in states)
    result = simulate_fmu(str(fmu), stop_time=0.1, output_interval=0.05, output=[v.name for v in states])
    assert all(result[v.name][0] == float(v.start) for v in states if v.initial == "exact")
    assert all(np.all(np.isfinite(result[v.name])) for v in states)
