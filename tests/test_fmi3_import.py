"""Foreign FMI 3.0 FMUs through the import verbs: `cosim info`, `simulate` (ME and CS) and
`linearize` (directional derivatives with the adjoint cross-check, finite differences without them).

The foreign FMUs are the Modelica Association's Reference FMUs, compiled from the vendored sources
(tests/reference_fmus.py, no network), and FMI 3 Co-Simulation containers of our FMI 2 FMUs made by
fmu-manipulation-toolbox's ``fmucontainer -fmi 3``. Broken FMI 3 FMUs (bad XML, missing binary,
wrong instantiationToken, traversal members, a missing fmi3 function) are made from good ones.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from conftest import cli_in_process, run_cli
from cosim.fmu.simulate import default_step
from reference_fmus import REFERENCE_MODELS, model_description, reference_fmu

# the quick run (-m 'not slow') leaves this module out: it builds FMI 3 FMUs and the Reference FMUs
pytestmark = pytest.mark.slow

#: cosim simulate against FMPy's own simulate_fmu on the same FMU: the same integrator, so 1e-9.
SIMULATE_TOLERANCE = 1e-9
#: An analytic Jacobian against directional derivatives (exact in the model's C code).
JACOBIAN_TOLERANCE = 1e-12
#: Central finite differences (relative step 1e-6) of a linear model: rounding only.
FINITE_DIFFERENCE_TOLERANCE = 1e-8
#: An FMI 3 container of an FMI 2 FMU against that FMU (both take the same 0.01 s steps).
CONTAINER_TOLERANCE = 1e-12


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> dict[str, Path]:
    """Every vendored Reference FMU, compiled once for this module."""
    folder = tmp_path_factory.mktemp("reference-fmus")
    return {name: reference_fmu(name, folder) for name in REFERENCE_MODELS}


def cosim(*argv: str, cwd: Path) -> tuple[int, str, str]:
    """``cosim ARGV`` in-process in ``cwd``: (exit status, stdout, stderr)."""
    return cli_in_process(list(argv), cwd)


def read_csv(path: Path) -> np.ndarray:
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="", ndmin=1)


def outputs_of(name: str) -> list[str]:
    """The output names of a vendored Reference FMU, read from its modelDescription.xml here."""
    root = etree.parse(str(model_description(name))).getroot()
    return [v.get("name") for v in root.find("ModelVariables") if v.get("causality") == "output"]


def strings_of(name: str) -> set[str]:
    """The names of the String variables of a vendored Reference FMU."""
    root = etree.parse(str(model_description(name))).getroot()
    return {v.get("name") for v in root.find("ModelVariables") if v.tag == "String"}


# --------------------------------------------------------------------------- simulate

STOP = {"VanDerPol": 5.0, "BouncingBall": 3.0, "Dahlquist": 4.0, "Feedthrough": 2.0, "Stair": 6.0}
STEP_INPUT = ("Float64_continuous_input", 0.5, 2.0)  # Feedthrough: the input steps to 2 at t = 0.5 s
CASES = [(name, kind, (), None) for name in REFERENCE_MODELS for kind in ("cs", "me")] + [
    ("VanDerPol", "cs", ("mu=3",), None), ("VanDerPol", "me", ("mu=3",), None),
    ("Feedthrough", "cs", (), STEP_INPUT), ("Feedthrough", "me", (), STEP_INPUT),
]


def case_id(case) -> str:
    name, kind, params, step_input = case
    return "-".join([name, kind, *params, *(["step-input"] if step_input else [])])


@pytest.mark.parametrize("case", CASES, ids=[case_id(c) for c in CASES])
def test_simulate_equals_fmpy(reference, tmp_path, case):
    """`cosim simulate` of a Reference FMU gives FMPy's own simulate_fmu result on it (same
    interface, interval, output step, parameters and input), every output at every time to 1e-9.
    The output step is cosim's default (the FMU's DefaultExperiment stepSize), given to FMPy,
    whose own default grows with the stop time and prefers an FMI 3 fixedInternalStepSize."""
    from fmpy import read_model_description, simulate_fmu

    name, kind, params, step_input = case
    fmu, stop = reference[name], STOP[name]
    argv = ["simulate", str(fmu), "--stop-time", str(stop), "--fmi-type", kind, "-o", "out.csv"]
    argv += [a for p in params for a in ("--param", p)]
    signals = None
    if step_input:
        variable, t0, value = step_input
        argv += ["--input", f"{variable}=step:{t0}:{value}"]
        signals = np.array([(0.0, 0.0), (t0, 0.0), (t0, value), (stop, value)],
                           dtype=[("time", float), (variable, float)])
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    ours = read_csv(tmp_path / "out.csv")
    theirs = simulate_fmu(str(fmu), fmi_type="CoSimulation" if kind == "cs" else "ModelExchange",
                          stop_time=stop, start_values={k: float(v) for k, v in (p.split("=") for p in params)},
                          input=signals, output=outputs_of(name),
                          output_interval=default_step(read_model_description(str(fmu)))[0])
    # every output FMPy records, in FMPy's order (its recorder groups them by type), then the String
    # outputs, which FMPy does not record (not Binary ones)
    strings = tuple(v for v in outputs_of(name) if v in strings_of(name))
    assert ours.dtype.names == theirs.dtype.names + strings
    assert set(ours.dtype.names) == {"time", *outputs_of(name)} - {"Binary_output"}
    assert len(ours) == len(theirs) > 10
    for column in theirs.dtype.names:
        np.testing.assert_allclose(ours[column], theirs[column].astype(float), rtol=0, atol=SIMULATE_TOLERANCE,
                                   err_msg=f"{name} {kind}: {column}")
    if params:  # the parameter took effect: the result differs from the default run
        status, _, err = cosim("simulate", str(fmu), "--stop-time", str(stop), "--fmi-type", kind, "-o", "d.csv",
                               cwd=tmp_path)
        assert status == 0, err
        assert np.max(np.abs(read_csv(tmp_path / "d.csv")["x1"] - ours["x1"])) > 0.1


# --------------------------------------------------------------------------- linearize

def vanderpol_jacobian(mu: float, x0: float, x1: float) -> np.ndarray:
    """d(der(x0), der(x1))/d(x0, x1) of x0' = x1, x1' = mu (1 - x0^2) x1 - x0."""
    return np.array([[0.0, 1.0], [-1.0 - 2.0 * mu * x0 * x1, mu * (1.0 - x0 ** 2)]])


@pytest.mark.parametrize("mu, x0, x1", [(1.0, 2.0, 0.0), (2.5, 2.0, 0.0), (0.7, -1.3, 0.9)],
                         ids=["default", "mu-2.5", "moved-start"])
def test_linearize_vanderpol_equals_its_analytic_jacobian(reference, tmp_path, mu, x0, x1):
    argv = ["linearize", str(reference["VanDerPol"]), "--json", "--param", f"mu={mu}"]
    if (x0, x1) != (2.0, 0.0):  # the start values are settable (initial = exact)
        argv += ["--param", f"x0={x0}", "--param", f"x1={x1}"]
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    report = json.loads(out)
    assert report["states"] == ["x0", "x1"] and report["outputs"] == ["x0", "x1"]
    np.testing.assert_allclose(report["A"], vanderpol_jacobian(mu, x0, x1), rtol=0, atol=JACOBIAN_TOLERANCE)
    np.testing.assert_array_equal(report["C"], np.eye(2))
    # the Reference VanDerPol provides both: the directional Jacobian was checked against the adjoint one
    assert report["method"].startswith("directional derivatives (adjoint derivatives agree")
    assert report["adjoint_difference"] is not None and report["adjoint_difference"] <= JACOBIAN_TOLERANCE


@pytest.mark.parametrize("k", [1.0, 2.5], ids=["default", "k-2.5"])
def test_linearize_without_directional_derivatives_takes_finite_differences(reference, tmp_path, k):
    """Dahlquist (x' = -k x) declares no directional derivatives: central finite differences."""
    status, out, err = cosim("linearize", str(reference["Dahlquist"]), "--json", "--param", f"k={k}", cwd=tmp_path)
    assert status == 0, err
    report = json.loads(out)
    assert report["method"] == "central finite differences" and report["adjoint_difference"] is None
    np.testing.assert_allclose(report["A"], [[-k]], rtol=0, atol=FINITE_DIFFERENCE_TOLERANCE)


@pytest.fixture(scope="module")
def speed_vanderpol(tmp_path_factory) -> Path:
    """The Reference VanDerPol with its parameter mu named V (only the name in modelDescription.xml):
    a model with a 'forward speed', so that `cosim linearize --speeds` takes the sweep's fast path
    through the raw fmi3 functions."""
    return reference_fmu("VanDerPol", tmp_path_factory.mktemp("speed"), fmu_name="SpeedVanDerPol",
                         edits={"modelDescription.xml": [('name="mu"', 'name="V"')]})


def test_linearize_speed_sweep_of_an_fmi3_fmu(speed_vanderpol, tmp_path):
    status, out, err = cosim("linearize", str(speed_vanderpol), "--speeds", "0:2:0.5", "--json", "--matrices",
                             cwd=tmp_path)
    assert status == 0, err
    report = json.loads(out)
    assert report["speeds"] == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert report["method"].startswith("directional derivatives (adjoint derivatives agree")
    for point in report["points"]:
        np.testing.assert_allclose(point["A"], vanderpol_jacobian(point["speed"], 2.0, 0.0), rtol=0,
                                   atol=JACOBIAN_TOLERANCE, err_msg=f"V = {point['speed']}")
    # one speed through the single-point path gives the same matrix
    status, out, err = cosim("linearize", str(speed_vanderpol), "--json", "--param", "V=1.5", cwd=tmp_path)
    assert status == 0, err
    np.testing.assert_array_equal(json.loads(out)["A"], report["points"][3]["A"])


@pytest.fixture(scope="module")
def wrong_adjoint(tmp_path_factory) -> Path:
    """A VanDerPol whose fmi3GetAdjointDerivative scales every partial derivative by 1.5 (the
    directional derivatives stay right), with mu named V for the sweep."""
    call = ("CALL(getPartialDerivative(S, (ValueReference)unknowns[j], (ValueReference)knowns[i], "
            "&partialDerivative));")
    return reference_fmu("VanDerPol", tmp_path_factory.mktemp("wrong-adjoint"), fmu_name="WrongAdjoint",
                         edits={"fmi3Functions.c": [(call, call + " partialDerivative *= 1.5;")],
                                "modelDescription.xml": [('name="mu"', 'name="V"')]})


@pytest.mark.parametrize("sweep", [False, True], ids=["single", "speeds"])
def test_directional_and_adjoint_derivatives_that_disagree_are_refused(wrong_adjoint, tmp_path, sweep):
    argv = ["linearize", str(wrong_adjoint)] + (["--speeds", "0.5,1"] if sweep else [])
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, lines
    assert "directional and adjoint derivatives disagree" in lines[0]
    # the worst entry is d der(x1)/d x1 = mu (1 - x0^2) = -3 mu (x0 = 2), the adjoint one 1.5 times that;
    # the sweep stops at its first speed, V = mu = 0.5
    mu = 0.5 if sweep else 1.0
    assert (f"d der(x1) / d x1 = {-3 * mu:g} (fmi3GetDirectionalDerivative) but {-4.5 * mu:g} "
            "(fmi3GetAdjointDerivative)") in lines[0], lines[0]
    assert ("at V = 0.5:" in lines[0]) == sweep


# --------------------------------------------------------------------------- info

@pytest.mark.parametrize("name", REFERENCE_MODELS)
def test_info_shows_the_fmi3_specifics(reference, tmp_path, name):
    root = etree.parse(str(model_description(name))).getroot()
    status, out, err = cosim("info", str(reference[name]), "--json", cwd=tmp_path)
    assert status == 0, err
    info = json.loads(out)
    assert (info["fmiVersion"], info["guid"]) == ("3.0", root.get("instantiationToken"))
    assert info["interfaces"] == ["ModelExchange", "CoSimulation"]
    for interface in info["interfaces"]:
        element = root.find(interface)
        for attribute in ("providesDirectionalDerivatives", "providesAdjointDerivatives", "canGetAndSetFMUState"):
            assert info["capabilities"][interface][attribute] == (element.get(attribute) == "true"), attribute
    cs = root.find("CoSimulation")
    assert info["capabilities"]["CoSimulation"]["fixedInternalStepSize"] == float(cs.get("fixedInternalStepSize"))
    types = {v.get("name"): v.tag for v in root.find("ModelVariables")}
    shown = {v["name"]: v["type"] for group in info["variables"].values() for v in group}
    assert shown == types
    status, text, err = cosim("info", str(reference[name]), cwd=tmp_path)
    assert status == 0, err
    assert "independent variable: time" in text
    assert ("adjoint derivatives" in text) == (root.find("ModelExchange").get("providesAdjointDerivatives") == "true")
    for variable, kind in types.items():  # FMI 3's sized types are named (Float64, the default, is not)
        if root.find(f"ModelVariables/*[@name='{variable}']").get("causality") in ("input", "output", "parameter"):
            assert (f" {kind}  " in text.split(f"    {variable}", 1)[1].splitlines()[0]) == (kind != "Float64")


# --------------------------------------------------------------------------- FMI 3 containers

@pytest.fixture(scope="module")
def container(tmp_path_factory):
    """An FMI 3.0 CS container (fmucontainer -fmi 3, step 0.01 s) of our FMI 2 WhippleLinear."""
    if shutil.which("fmucontainer") is None:
        pytest.skip("fmucontainer (fmu-manipulation-toolbox, the test extra) is not installed")
    from cosim.fmu.target import resolve_fmu

    fmi2 = resolve_fmu("Bicycle.Bicycles.WhippleLinear")  # built into the session's COSIM_FMU_DIR
    folder = tmp_path_factory.mktemp("container")
    shutil.copy2(fmi2, folder / fmi2.name)
    (folder / "bike.csv").write_text(f"rule;from_fmu;from_port;to_fmu;to_port\nFMU;{fmi2.name};;;\n")
    made = subprocess.run(["fmucontainer", "-container", "bike.csv:0.01", "-fmi", "3"], cwd=folder,
                          capture_output=True, text=True, timeout=120)
    assert made.returncode == 0 and (folder / "bike.fmu").is_file(), made.stdout + made.stderr
    return folder / "bike.fmu", fmi2


@pytest.mark.parametrize("inputs", [("T_delta=step:0.5:0.1",), ("T_phi=step:0.2:-0.3", "T_delta=step:1:0.05")],
                         ids=["steer-torque", "both-torques"])
def test_fmi3_container_simulates_as_its_fmi2_fmu(container, tmp_path, inputs):
    bike, fmi2 = container
    results = []
    for fmu, name in ((bike, "fmi3.csv"), (fmi2, "fmi2.csv")):
        argv = ["simulate", str(fmu), "--stop-time", "2", "--step", "0.01", "-o", name]
        status, _, err = cosim(*argv, *[a for i in inputs for a in ("--input", i)], cwd=tmp_path)
        assert status == 0, err
        results.append(read_csv(tmp_path / name))
    fmi3, reference_result = results
    assert fmi3.dtype.names == reference_result.dtype.names and len(fmi3) == len(reference_result) == 201
    assert np.max(np.abs(reference_result["phi"])) > 1e-3  # the torques moved the bicycle
    for column in fmi3.dtype.names:
        np.testing.assert_allclose(fmi3[column], reference_result[column], rtol=0, atol=CONTAINER_TOLERANCE,
                                   err_msg=column)


def test_fmi3_container_without_model_exchange_is_refused_for_me(container, tmp_path):
    status, _, err = cosim("simulate", str(container[0]), "--stop-time", "1", "--fmi-type", "me", "-o", "x.csv",
                           cwd=tmp_path)
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "does not support Model Exchange" in err and not (tmp_path / "x.csv").exists()


# --------------------------------------------------------------------------- broken FMI 3 FMUs

def rewrite(source: Path, target: Path, change) -> Path:
    """A copy of the FMU ``source`` whose members ``change(members)`` edits (a dict name -> bytes)."""
    with zipfile.ZipFile(source) as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    change(members)
    with zipfile.ZipFile(target, "w") as archive:
        for name, data in members.items():
            archive.writestr(zipfile.ZipInfo(name), data)
    return target


def _bad_xml(m):
    m["modelDescription.xml"] = m["modelDescription.xml"][:-40]


def _no_binary(m):
    for name in [n for n in m if n.startswith("binaries/")]:
        del m[name]


def _wrong_token(m):
    m["modelDescription.xml"] = m["modelDescription.xml"].replace(b'instantiationToken="{BD4', b'instantiationToken="{0D4')


def _traversal(m):
    m["../escaped.txt"] = b"outside"


BROKEN = {  # case -> (how, what the message says, whether `cosim info` still reads the description)
    "bad-xml": (_bad_xml, "modelDescription.xml is not well-formed XML", False),
    "missing-binary": (_no_binary, "no binary for this platform (binaries/x86_64-linux/VanDerPol.so is missing", True),
    "wrong-token": (_wrong_token, "cannot instantiate VanDerPol.so: Failed to instantiate FMU (the FMU says: "
                                  "Wrong instantiationToken.)", True),
    "traversal": (_traversal, "unsafe member name '../escaped.txt' in the archive (points outside the FMU ('..'))",
                  False),
    "missing-function": (None, "VanDerPol.so does not export fmi3GetFloat64, a function every FMI 3.0 binary must have",
                         True),
}
VERBS = {"info": ["info"], "simulate-cs": ["simulate", "--stop-time", "1", "-o", "{out}"],
         "simulate-me": ["simulate", "--stop-time", "1", "--fmi-type", "me", "-o", "{out}"],
         "linearize": ["linearize"]}


@pytest.fixture(scope="module")
def broken(reference, tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("broken")
    found = {case: rewrite(reference["VanDerPol"], folder / f"{case}.fmu", how)
             for case, (how, _, _) in BROKEN.items() if how is not None}
    found["missing-function"] = reference_fmu(  # fmi3GetFloat64 renamed: hidden, the binary does not export it
        "VanDerPol", folder, fmu_name="missing-function",
        edits={"fmi3Functions.c": [("fmi3Status fmi3GetFloat64(", "fmi3Status hidden_GetFloat64(")]})
    return found


@pytest.mark.parametrize("verb", VERBS)
@pytest.mark.parametrize("case", BROKEN)
def test_broken_fmi3_fmu_gets_one_message(broken, tmp_path, case, verb):
    """A broken FMI 3 FMU: one `cosim VERB: error:` line naming the file and the problem, exit 2,
    no traceback, nothing written (a subprocess, as a user runs it)."""
    _, message, readable = BROKEN[case]
    fmu = broken[case]
    command, *options = VERBS[verb]
    result = run_cli(command, str(fmu), *(o.format(out=tmp_path / "out.csv") for o in options))
    if verb == "info" and readable:  # only the description is read: the defect is not its business
        assert result.returncode == 0, result.stderr
        assert "FMI 3.0 ModelExchange + CoSimulation" in result.stdout
        return
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"cosim {command}: error: {fmu}: ") and message in lines[0], lines[0]
    assert not (tmp_path / "out.csv").exists() and not (tmp_path.parent / "escaped.txt").exists()


# --------------------------------------------------------------------------- our own FMI 3 FMUs

#: FMI 3 and FMI 2 builds of one model run the same generated C code and runtime core: CS (our
#: integrator) and the Jacobians agree to rounding.
OWN_TOLERANCE = 1e-12
#: Model Exchange: FMPy's CVode on the same derivatives; the FMI 3 call sequence (initial event
#: iteration, typed getters) must not change the integration beyond rounding.
OWN_ME_TOLERANCE = 1e-10
OWN_MODELS = {  # model -> (parameters, inputs) of the runs
    "Bicycle.Bicycles.WhippleLinear": (("v=4", "phi0=0.05"), ("T_delta=step:0.5:0.1",)),
    "Bicycle.Bicycles.SelfStabilizing": (("V=3",), ("T=step:0.2:0.5",)),
    "Bicycle.Rider.PadeDelay": (("tau=0.2",), ("u=step:0.1:1",)),  # FMI 3: its states are one array x
}
#: Models linearized (options of `cosim linearize`): also the nonlinear Whipple bicycle, whose
#: CasADi reverse mode (its adjoint derivatives) is the largest of the library.
OWN_LINEARIZED = {"Bicycle.Bicycles.WhippleLinear": ("--param", "v=4"),
                  "Bicycle.Bicycles.SelfStabilizing": ("--param", "V=3"),
                  "Bicycle.Bicycles.Whipple": ("--speed", "4"),
                  "Bicycle.Rider.PadeDelay": ("--param", "tau=0.2")}
OWN_SWEPT = ("Bicycle.Bicycles.WhippleLinear", "Bicycle.Bicycles.SelfStabilizing", "Bicycle.Bicycles.Whipple")


@pytest.fixture(scope="module")
def own(request) -> dict[str, tuple[Path, Path]]:
    """Model -> (FMI 2 FMU, FMI 3 FMU), both built from one compilation into the session's
    COSIM_FMU_DIR (cosim build --fmi-version 2 3)."""
    from cosim.compiler.build import build_versions

    found = {}
    for model in OWN_LINEARIZED:
        fmi2, fmi3 = build_versions(model, os.environ["COSIM_FMU_DIR"], fmi_versions=("2", "3"))
        found[model] = (fmi2.fmu, fmi3.fmu)
    return found


@pytest.mark.parametrize("kind", ["cs", "me"])
@pytest.mark.parametrize("model", OWN_MODELS)
def test_own_fmi3_fmu_simulates_as_its_fmi2_fmu(own, tmp_path, model, kind):
    parameters, inputs = OWN_MODELS[model]
    options = [a for p in parameters for a in ("--param", p)] + [a for i in inputs for a in ("--input", i)]
    results = []
    for fmu, name in zip(own[model], ("fmi2.csv", "fmi3.csv")):
        status, _, err = cosim("simulate", str(fmu), "--stop-time", "3", "--step", "0.01", "--fmi-type", kind,
                               "-o", name, *options, cwd=tmp_path)
        assert status == 0, err
        results.append(read_csv(tmp_path / name))
    fmi2, fmi3 = results
    # 301 output times; ME adds a row at the input's step (FMPy records both sides of the event)
    assert fmi3.dtype.names == fmi2.dtype.names and len(fmi3) == len(fmi2) == (301 if kind == "cs" else 302)
    moving = [n for n in fmi2.dtype.names if n != "time" and np.ptp(fmi2[n]) > 1e-3]
    assert moving, "the run must move something, else equal results say nothing"
    tolerance = OWN_TOLERANCE if kind == "cs" else OWN_ME_TOLERANCE
    for column in fmi2.dtype.names:
        np.testing.assert_allclose(fmi3[column], fmi2[column], rtol=0, atol=tolerance, err_msg=column)


@pytest.mark.parametrize("model", OWN_LINEARIZED)
def test_own_fmi3_fmu_linearizes_as_its_fmi2_fmu(own, tmp_path, model):
    reports = []
    for fmu in own[model]:
        status, out, err = cosim("linearize", str(fmu), "--json", *OWN_LINEARIZED[model], cwd=tmp_path)
        assert status == 0, err
        reports.append(json.loads(out))
    fmi2, fmi3 = reports
    assert fmi2["method"] == "directional derivatives" and fmi2["adjoint_difference"] is None
    # FMI 3: CasADi's reverse mode (fmi3GetAdjointDerivative) checked the forward mode's Jacobian
    assert fmi3["method"].startswith("directional derivatives (adjoint derivatives agree")
    assert fmi3["adjoint_difference"] <= OWN_TOLERANCE
    for key in ("states", "inputs", "outputs"):
        assert fmi3[key] == fmi2[key], key
    assert np.max(np.abs(fmi2["A"])) > 1.0
    for name in "ABCD":
        np.testing.assert_allclose(np.array(fmi3[name]), np.array(fmi2[name]), rtol=0, atol=OWN_TOLERANCE,
                                   err_msg=name)
    if "steady_motion" in fmi2:  # the nonlinear bicycle: its lateral reduction from the same matrices
        np.testing.assert_allclose(fmi3["steady_motion"]["eigenvalues"], fmi2["steady_motion"]["eigenvalues"],
                                   rtol=0, atol=OWN_TOLERANCE)


@pytest.mark.parametrize("model", OWN_SWEPT)
def test_own_fmi3_fmu_speed_sweep_as_its_fmi2_fmu(own, tmp_path, model):
    """The sweep's fast path (raw fmi3 functions, adjoint check at every speed) against FMI 2's."""
    reports = []
    for fmu in own[model]:
        status, out, err = cosim("linearize", str(fmu), "--speeds", "1:6:1", "--json", "--matrices", cwd=tmp_path)
        assert status == 0, err
        reports.append(json.loads(out))
    fmi2, fmi3 = reports
    assert fmi3["method"].startswith("directional derivatives (adjoint derivatives agree")
    assert fmi3["speeds"] == fmi2["speeds"] == [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    for p2, p3 in zip(fmi2["points"], fmi3["points"]):
        for name in "ABCD":
            np.testing.assert_allclose(np.array(p3[name]), np.array(p2[name]), rtol=0, atol=OWN_TOLERANCE,
                                       err_msg=f"{name} at {p2['speed']} m/s")


def test_fmi3_array_states_are_linearized_value_by_value(own):
    """The Pade delay's FMI 3 FMU exports its states as one array x (one value reference, n values):
    the linearization names the values x[1], x[2] as the FMI 2 FMU (scalarized) does, and central
    finite differences through fmi3Get/SetFloat64 with nValues agree with the directional derivatives."""
    from cosim.fmu.access import ALL_FMI_VERSIONS, FMU
    from cosim.fmu.linearize import linearize

    fmi2, fmi3 = own["Bicycle.Rider.PadeDelay"]
    with FMU(fmi3, versions=ALL_FMI_VERSIONS) as fmu:
        assert fmu.states == ["x"] and fmu.n_states == 2 and fmu.elements(["x"]) == ["x[1]", "x[2]"]
    exact = linearize(fmi3, {"tau": 0.2})
    differences = linearize(fmi3, {"tau": 0.2}, method="finite-differences")
    assert (exact.system.states == differences.system.states == linearize(fmi2, {"tau": 0.2}).system.states
            == ["x[1]", "x[2]"])
    assert differences.method == "central finite differences"
    for name in "ABCD":
        a, b = getattr(exact.system, name), getattr(differences.system, name)
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-6 * max(1.0, np.max(np.abs(a))), err_msg=name)
    # x'' + (6/tau) x' + (12/tau^2) x = u: the second-order Pade denominator at tau = 0.2 s
    np.testing.assert_allclose(exact.system.A, [[0.0, 1.0], [-12 / 0.2 ** 2, -6 / 0.2]], rtol=1e-12, atol=0)


def test_fmi3_variable_types_are_checked_as_their_values(reference):
    """--param/--input checks of FMI 3's sized types: Float32/Float64 as numbers, Int8..UInt64 as
    whole numbers in their own range (not FMI 2's 32 bit)."""
    from cosim.errors import ParameterError
    from cosim.fmu.parameters import check, declarations

    declared = declarations(str(reference["Feedthrough"]))
    assert (declared["Float32_continuous_input"].type, declared["Int8_input"].type) == ("Real", "Integer")
    assert declared["UInt8_input"].range == (0, 255) and declared["Int64_input"].range == (-2 ** 63, 2 ** 63 - 1)
    as_parameter = {n: d.__class__(**{**vars(d), "causality": "parameter"}) for n, d in declared.items()}
    assert check({"UInt8_input": "255", "Int16_input": "-32768"}, as_parameter) == \
        {"UInt8_input": 255, "Int16_input": -32768}
    with pytest.raises(ParameterError, match=r"'UInt8_input' is an Integer; 256 is out of range \(0 \.\. 255\)"):
        check({"UInt8_input": "256"}, as_parameter)
    with pytest.raises(ParameterError, match=r"'Int8_input' is an Integer; 1.5 is not a whole number"):
        check({"Int8_input": "1.5"}, as_parameter)


def test_info_of_own_fmi3_fmu(own, tmp_path):
    """`cosim info` of our FMI 3 Pade delay: adjoint derivatives offered, the state array's size."""
    fmi3 = own["Bicycle.Rider.PadeDelay"][1]
    status, out, err = cosim("info", str(fmi3), "--json", cwd=tmp_path)
    assert status == 0, err
    info = json.loads(out)
    assert info["fmiVersion"] == "3.0" and info["states"] == ["x"]
    assert info["capabilities"]["ModelExchange"]["providesAdjointDerivatives"] is True
    assert info["capabilities"]["CoSimulation"]["providesIntermediateUpdate"] is False
    (x,) = [v for v in info["variables"]["local"] if v["name"] == "x"]
    assert x["dimensions"] == [2] and x["type"] == "Float64"
    status, text, err = cosim("info", str(fmi3), cwd=tmp_path)
    assert status == 0, err
    assert "ModelExchange: directional derivatives, adjoint derivatives" in text
    assert "independent variable: time [s]" in text
