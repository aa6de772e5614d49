"""FMI 3.0 export: every exported model built by `cosim build --fmi-version 3` is a valid
FMI 3.0 FMU (FMPy's validator, `fmutool -check` for both FMI versions, the build description's
schema), runs in FMPy as Model Exchange (CVode) and Co-Simulation with the results of its FMI 2.0
twin, has directional and adjoint derivatives that agree with each other and with central
differences, and FMU states that round-trip (a state of another model is refused).

The FMI 3 FMUs are built once per module, by the command line, into the session's FMU folder
(``COSIM_FMU_DIR/fmi3``), beside the FMI 2 FMUs of the ``fmus`` fixture.
"""
from __future__ import annotations

import ctypes
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli, shipped_models
from registered_engines import engine_params

from cosim.compiler.build import fmu_path

# the quick run (-m 'not slow') leaves this module out: it builds FMI 3 FMUs and the Reference FMUs
pytestmark = pytest.mark.slow

EXPORTED = shipped_models(exported_only=True)
STOP, STEP = 2.0, 0.01  # s
CS_EQUAL = 1e-12  # FMI 3 CS against FMI 2 CS: the same core and integrator, only the API differs
ME_RTOL = 1e-6  # CVode's relative tolerance in both ME runs
ME_AGREEMENT = 10 * ME_RTOL  # relative to the largest magnitude of a signal
ADJOINT_TOL = 1e-12  # v^T (J u) against (J^T v)^T u, relative to |v| |J| |u|
FD_RTOL = 1e-6  # AD against central differences
FD_STEP = 1e-6  # relative step of the central differences


def _folder() -> Path:
    return Path(os.environ["COSIM_FMU_DIR"])


@pytest.fixture(scope="module")
def build_output(fmus) -> str:
    """`cosim build --fmi-version 2 3` of every exported model into the session's FMU folder, after
    the ``fmus`` fixture built the FMI 2 FMUs there: its standard output."""
    result = run_cli("build", "--fmi-version", "2", "3", "-o", str(_folder()), "-j", "2")
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.fixture(scope="module")
def fmi3(build_output) -> dict[str, Path]:
    return {model: fmu_path(model, _folder(), "3") for model in EXPORTED}


@pytest.fixture(scope="module")
def unzipped(fmi3, fmus, tmp_path_factory):
    """Extraction folders of the FMUs: (model, "2" | "3") -> folder (extracted on first use)."""
    from fmpy import extract

    root, cache = tmp_path_factory.mktemp("unzipped"), {}

    def get(model: str, version: str) -> str:
        if (model, version) not in cache:
            fmu = fmi3[model] if version == "3" else fmus[model]
            cache[model, version] = extract(str(fmu), str(root / f"{version}-{model}"))
        return cache[model, version]

    return get


def test_one_command_builds_both_versions(build_output, fmus, fmi3):
    """FMI 2 FMUs of the ``fmus`` fixture are up to date for a build of both versions: an FMI 3
    build does not invalidate them; the FMI 3 FMUs go to OUTPUT/fmi3/NAME.fmu."""
    lines = build_output.splitlines()
    for model in EXPORTED:
        assert any(line.startswith("up to date") and line.split()[-3] == str(fmus[model]) for line in lines), model
        assert any(line.split()[-3] == str(fmi3[model]) for line in lines), model
        assert fmi3[model].parent == _folder() / "fmi3" and fmi3[model].is_file()


@pytest.mark.parametrize("model", EXPORTED)
def test_fmu_layout(fmi3, fmus, model):
    """binaries/x86_64-linux/<id>.so, sources/ with every C file of buildDescription.xml (which
    is valid against the FMI 3 schema), the FMI 3 headers, a manifest naming FMI 3; the model's
    own C files are those of its FMI 2 FMU plus the adjoint derivatives; the same GUID."""
    from fmpy import platform_tuple
    from lxml import etree

    identifier = model.replace(".", "_")
    with zipfile.ZipFile(fmi3[model]) as archive:
        names = set(archive.namelist())
        description = ET.fromstring(archive.read("modelDescription.xml"))
        build_text = archive.read("sources/buildDescription.xml")
        manifest = json.loads(archive.read("documentation/build.json"))
    with zipfile.ZipFile(fmus[model]) as archive:
        fmi2_description = ET.fromstring(archive.read("modelDescription.xml"))
    assert description.get("fmiVersion") == "3.0"
    assert f"binaries/{platform_tuple}/{identifier}.so" in names
    assert not any(n.startswith("binaries/") and platform_tuple not in n for n in names)
    schema = etree.XMLSchema(etree.parse(str(Path(__import__("fmpy").__file__).parent
                                              / "schema" / "fmi3" / "fmi3BuildDescription.xsd")))
    build = etree.fromstring(build_text)
    assert schema.validate(build), schema.error_log
    [configuration] = build.findall("BuildConfiguration")
    assert configuration.get("modelIdentifier") == identifier
    [file_set] = configuration.findall("SourceFileSet")
    assert file_set.get("language") == "C99"
    listed = [f.get("name") for f in file_set.findall("SourceFile")]
    assert sorted(listed) == sorted(n[len("sources/"):] for n in names if n.startswith("sources/") and n.endswith(".c"))
    fmi2_listed = [f.get("name") for f in fmi2_description.find("ModelExchange").iter("File")]
    runtime = {"cosim_runtime.c", "fmi2_api.c", "fmi3_api.c"}
    assert [n for n in listed if n not in runtime and n != "model_vjp.c"] == [n for n in fmi2_listed if n not in runtime]
    assert "model_vjp.c" in listed and {"cosim_runtime.c", "fmi3_api.c"} <= set(listed)
    assert {f"sources/{h}" for h in ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h",
                                     "cosim_model.h", "cosim_runtime.h")} <= names
    assert manifest["fmi_version"] == "3" and manifest["model"] == model
    assert description.get("instantiationToken") == fmi2_description.get("guid") == manifest["guid"]


# FMPy's validator parses every variable name with a grammar: 20 s for the 4000 variables of the
# component bicycle with a rider on a 2-core machine
VALIDATE_SLOW = {"Bicycle.Bicycles.Whipple", "Bicycle.Bicycles.WhippleRider"}


@pytest.mark.parametrize("model", [pytest.param(m, marks=pytest.mark.slow) if m in VALIDATE_SLOW else m
                                   for m in EXPORTED])
def test_fmpy_validate_reports_nothing(fmi3, model):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmi3[model])) == []


# `fmutool -input FMU -check` for many FMUs in one interpreter: the command's own entry point (the
# console script `fmutool` calls it), with its arguments and output per FMU; one Python start-up
# (1 s, most of a check) instead of one per FMU.
FMUTOOL_RUNNER = """
import contextlib, io, json, sys
from fmu_manipulation_toolbox.cli.fmutool import fmutool
results = {}
for path in json.loads(sys.stdin.read()):
    sys.argv = ["fmutool", "-input", path, "-check"]
    out = io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        try:
            fmutool()
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 1
    results[path] = [code, out.getvalue()]
print(json.dumps(results))
"""


@pytest.fixture(scope="module")
def fmutool_results(fmi3, fmus) -> dict[tuple[str, str], tuple[int, str]]:
    """(model, version) -> exit status and output of `fmutool -input FMU -check`."""
    pytest.importorskip("fmu_manipulation_toolbox", reason="fmu-manipulation-toolbox (the test extra) missing")
    paths = {(m, v): str(fmi3[m] if v == "3" else fmus[m]) for m in EXPORTED for v in ("2", "3")}
    run = subprocess.run([sys.executable, "-c", FMUTOOL_RUNNER], input=json.dumps(list(paths.values())),
                         capture_output=True, text=True, timeout=600, check=False)
    assert run.returncode == 0, run.stderr
    results = json.loads(run.stdout)
    return {key: tuple(results[path]) for key, path in paths.items()}


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
@pytest.mark.parametrize("model", EXPORTED)
def test_fmutool_check_passes(fmutool_results, model, version):
    status, text = fmutool_results[model, version]
    assert status == 0, text
    assert f"compliant with FMI-{version}.0" in text and f"No semantic error against the FMI-{version}" in text, text


def _input_signals(unzipdir: str):
    """A different sine on every Float64 input over [0, STOP] (None without inputs)."""
    from fmpy import read_model_description

    md = read_model_description(unzipdir)
    names = [v.name for v in md.modelVariables if v.causality == "input" and v.type in ("Real", "Float64")]
    if not names:
        return None
    t = np.arange(0.0, STOP + STEP / 2, STEP)
    signals = np.zeros(t.size, dtype=[("time", float)] + [(n, float) for n in names])
    signals["time"] = t
    for k, name in enumerate(names):
        signals[name] = 0.1 * np.sin((k + 1) * 2.0 * t + 0.3)
    return signals


def _simulate(unzipdir: str, fmi_type: str) -> np.ndarray:
    from fmpy import simulate_fmu

    options = {"solver": "CVode", "relative_tolerance": ME_RTOL} if fmi_type == "ModelExchange" else {}
    return simulate_fmu(unzipdir, fmi_type=fmi_type, start_time=0.0, stop_time=STOP, output_interval=STEP,
                        input=_input_signals(unzipdir), **options)


def _signals(result: np.ndarray) -> dict[str, np.ndarray]:
    return {name: np.asarray(result[name], float) for name in result.dtype.names if name != "time"}


@pytest.mark.parametrize("model", EXPORTED)
def test_co_simulation_equals_fmi2(unzipped, model):
    fmi2, fmi3_result = (_simulate(unzipped(model, v), "CoSimulation") for v in ("2", "3"))
    np.testing.assert_array_equal(fmi3_result["time"], fmi2["time"])
    a, b = _signals(fmi2), _signals(fmi3_result)
    assert a and a.keys() == b.keys()
    for name in a:
        assert np.isfinite(b[name]).all(), name
        scale = max(1.0, float(np.max(np.abs(a[name]))))
        assert np.max(np.abs(b[name] - a[name])) <= CS_EQUAL * scale, name


@pytest.mark.parametrize("model", EXPORTED)
def test_model_exchange_matches_fmi2(unzipped, model):
    fmi2, fmi3_result = (_simulate(unzipped(model, v), "ModelExchange") for v in ("2", "3"))
    a, b = _signals(fmi2), _signals(fmi3_result)
    assert a and a.keys() == b.keys()
    for name in a:
        scale = max(1.0, float(np.max(np.abs(a[name]))))
        assert np.max(np.abs(np.interp(fmi2["time"], fmi3_result["time"], b[name]) - a[name])) <= ME_AGREEMENT * scale, name


@pytest.mark.parametrize("engine", engine_params("fmu", "3.0", independent=True, reference=False))
@pytest.mark.parametrize("model", EXPORTED)
def test_co_simulation_in_ecos_equals_fmpy(fmi3, model, engine):
    """Each independent FMI 3 co-simulation engine (Ecos) runs the FMI 3 FMU to FMPy's CS result
    (constant 0.1 on every input, fixed communication step), to 1e-9."""
    from fmpy import read_model_description, simulate_fmu

    fmu = str(fmi3[model])
    md = read_model_description(fmu)
    start = {v.name: 0.1 for v in md.modelVariables if v.causality == "input" and v.type == "Float64"}
    reference = simulate_fmu(fmu, fmi_type="CoSimulation", stop_time=STOP, output_interval=STEP, start_values=start)
    outputs = [n for n in reference.dtype.names if n != "time"]
    other = engine.run_fmu(fmu, STOP, STEP, start, outputs)
    for name in outputs:
        scale = np.maximum(1.0, np.abs(reference[name][1:]))  # engines record after each step, FMPy also at t = 0
        assert np.max(np.abs(other[name] - reference[name][1:]) / scale) <= 1e-9, name


def _instantiate(unzipdir: str, fmi_type: str):
    from fmpy import instantiate_fmu, read_model_description

    md = read_model_description(unzipdir)
    return md, instantiate_fmu(unzipdir, md, fmi_type=fmi_type)


def _size(variable) -> int:
    """Number of values of an FMI 3 variable (an array: the product of its dimensions)."""
    return int(np.prod([int(d.start) for d in variable.dimensions])) if variable.dimensions else 1


def _doubles(values):
    """A ctypes array of doubles (what FMPy's FMU3Model passes on to the C functions)."""
    return (ctypes.c_double * len(values))(*values)


class _Point:
    """An FMI 3 ME instance in continuous-time mode at a random state and input; the unknowns
    (derivatives, outputs) and knowns (states, Float64 inputs) of its Jacobian as variables, an
    array variable (the Pade delay's states) with all its values."""

    def __init__(self, unzipdir: str):
        md, self.me = _instantiate(unzipdir, "ModelExchange")
        self.me.enterInitializationMode(startTime=0.0)
        self.me.exitInitializationMode()
        self.me.updateDiscreteStates()
        self.me.enterContinuousTimeMode()
        states = [d.variable.derivative for d in md.derivatives]
        self.inputs = [v for v in md.modelVariables if v.causality == "input" and v.type == "Float64"]
        self.outputs = [o.variable for o in md.outputs]
        self.nx, self.nu = sum(map(_size, states)), sum(map(_size, self.inputs))
        self.unknowns = [d.variable.valueReference for d in md.derivatives] + [v.valueReference for v in self.outputs]
        self.knowns = [v.valueReference for v in states + self.inputs]
        self.n, self.m = self.nx + sum(map(_size, self.outputs)), self.nx + self.nu
        rng = np.random.default_rng(15)
        self.values = np.concatenate([rng.uniform(-0.3, 0.3, self.nx), rng.uniform(-0.5, 0.5, self.nu)])
        self.set(self.values)

    def set(self, values: np.ndarray) -> None:
        if self.nx:
            self.me.setContinuousStates(_doubles(values[:self.nx]), self.nx)
        if self.nu:
            self.me.setFloat64([v.valueReference for v in self.inputs], list(values[self.nx:]))

    def evaluate(self) -> np.ndarray:
        """der(x) and the outputs."""
        derivatives = _doubles([0.0] * self.nx)
        if self.nx:
            self.me.getContinuousStateDerivatives(derivatives, self.nx)
        outputs = (self.me.getFloat64([v.valueReference for v in self.outputs], self.n - self.nx)
                   if self.outputs else [])
        return np.concatenate([np.array(derivatives[:], float), outputs])

    def directional(self, seed) -> np.ndarray:
        return np.array(self.me.getDirectionalDerivative(self.unknowns, self.knowns, list(seed), nSensitivity=self.n))

    def adjoint(self, seed) -> np.ndarray:
        return np.array(self.me.getAdjointDerivative(self.unknowns, self.knowns, list(seed), nSensitivity=self.m))


@pytest.mark.parametrize("model", EXPORTED)
def test_directional_adjoint_and_central_differences_agree(unzipped, model):
    """The Jacobian of (der(x), outputs) with respect to (x, u): column by column from
    fmi3GetDirectionalDerivative, row by row from fmi3GetAdjointDerivative, equal; v^T (J u) =
    (J^T v)^T u for random seeds; both equal central differences."""
    point = _Point(unzipped(model, "3"))
    n, m = point.n, point.m
    if not n or not m:
        pytest.skip(f"{model} has no states or inputs (nothing to differentiate)")
    jacobian = np.column_stack([point.directional(e) for e in np.eye(m)])
    transposed = np.column_stack([point.adjoint(e) for e in np.eye(n)])
    scale = max(1.0, float(np.max(np.abs(jacobian))))
    assert jacobian.shape == (n, m) and np.isfinite(jacobian).all()
    np.testing.assert_allclose(transposed.T, jacobian, rtol=0, atol=ADJOINT_TOL * scale)
    rng = np.random.default_rng(3)
    for _ in range(3):
        u, v = rng.standard_normal(m), rng.standard_normal(n)
        assert abs(v @ point.directional(u) - point.adjoint(v) @ u) <= (ADJOINT_TOL * scale * np.linalg.norm(u)
                                                                        * np.linalg.norm(v))
    central = np.zeros((n, m))
    for k in range(m):
        h = FD_STEP * max(1.0, abs(point.values[k]))
        sides = []
        for sign in (1.0, -1.0):
            shifted = point.values.copy()
            shifted[k] += sign * h
            point.set(shifted)
            sides.append(point.evaluate())
        central[:, k] = (sides[0] - sides[1]) / (2.0 * h)
    point.set(point.values)
    np.testing.assert_allclose(jacobian, central, rtol=FD_RTOL, atol=FD_RTOL * scale)
    point.me.terminate()
    point.me.freeInstance()


def test_pade_delay_states_are_one_array(fmi3, unzipped):
    """The Pade delay's states x[1..n] are one FMI 3 array ``x`` (``<Dimension start="n"/>``, its
    derivative ``der(x)`` too): one fmi3GetFloat64 with nValues = n reads what the FMI 2 FMU
    has in x[1], ..., x[n] after the same co-simulation steps."""
    from fmpy import instantiate_fmu, read_model_description

    model = "Bicycle.Rider.PadeDelay"
    md3 = read_model_description(unzipped(model, "3"))
    md2 = read_model_description(unzipped(model, "2"))
    order = next(int(v.start) for v in md3.modelVariables if v.name == "n")
    x = next(v for v in md3.modelVariables if v.name == "x")
    der = next(v for v in md3.modelVariables if v.name == "der(x)")
    assert order >= 2 and _size(x) == _size(der) == order and der.derivative is x
    assert not any(v.name.startswith("x[") for v in md3.modelVariables)
    elements = [next(v for v in md2.modelVariables if v.name == f"x[{k}]") for k in range(1, order + 1)]
    assert [v.valueReference for v in elements] == list(range(x.valueReference, x.valueReference + order))
    u2 = next(v.valueReference for v in md2.modelVariables if v.name == "u")
    seen = []
    for version, md in (("2", md2), ("3", md3)):
        cs = instantiate_fmu(unzipped(model, version), md, fmi_type="CoSimulation")
        if version == "2":
            cs.setupExperiment(startTime=0.0)
            cs.enterInitializationMode()
        else:
            cs.enterInitializationMode(startTime=0.0)
        cs.exitInitializationMode()
        (cs.setReal if version == "2" else cs.setFloat64)([u2], [1.0])
        for k in range(20):
            cs.doStep(0.01 * k, 0.01)
        seen.append(cs.getReal([v.valueReference for v in elements]) if version == "2"
                    else cs.getFloat64([x.valueReference], order))
        cs.terminate()
        cs.freeInstance()
    assert seen[1] == seen[0] and max(map(abs, seen[0])) > 1e-5  # the same, and the delay moved


def _co_simulation(unzipdir: str):
    """An FMI 3 CS instance stepped to 0.1 s with a constant 0.1 on every Float64 input."""
    md, cs = _instantiate(unzipdir, "CoSimulation")
    cs.enterInitializationMode(startTime=0.0)
    cs.exitInitializationMode()
    inputs = [v.valueReference for v in md.modelVariables if v.causality == "input" and v.type == "Float64"]
    if inputs:
        cs.setFloat64(inputs, [0.1] * len(inputs))
    t = 0.0
    for _ in range(10):
        cs.doStep(t, 0.01)
        t += 0.01
    return md, cs, t


def _steps(md, cs, t: float, n: int = 5) -> list[tuple]:
    outputs = [o.variable.valueReference for o in md.outputs]
    seen = []
    for k in range(n):
        cs.doStep(t + 0.05 * k, 0.05)
        seen.append(tuple(cs.getFloat64(outputs)))
    return seen


@pytest.mark.parametrize("model", EXPORTED)
def test_fmu_state_round_trip_and_foreign_state_refused(unzipped, model):
    """Save, step, restore, step: identical outputs (directly and through serialization); the
    serialized state of another model is refused with an error, and the instance stays usable."""
    from fmpy.fmi1 import FMICallException

    md, cs, t = _co_simulation(unzipped(model, "3"))
    state = cs.getFMUState()
    first = _steps(md, cs, t)
    cs.setFMUState(state)
    assert _steps(md, cs, t) == first
    restored = cs.deserializeFMUState(cs.serializeFMUState(state))
    cs.setFMUState(restored)
    assert _steps(md, cs, t) == first
    other = EXPORTED[(EXPORTED.index(model) + 1) % len(EXPORTED)]
    _, other_cs, _ = _co_simulation(unzipped(other, "3"))
    foreign = other_cs.serializeFMUState(other_cs.getFMUState())
    with pytest.raises(FMICallException):
        cs.deserializeFMUState(foreign)
    cs.setFMUState(state)
    assert _steps(md, cs, t) == first, "the refused state must leave the instance as it was"
    for instance in (cs, other_cs):
        instance.terminate()
        instance.freeInstance()


def test_rebuilds_from_its_sources(fmi3, unzipped, tmp_path):
    """gcc on the files of sources/buildDescription.xml (nothing else) gives a binary that runs the
    model as the shipped one does (CS, to 1e-12)."""
    model = "Bicycle.Rider.PadeDelay"
    original = unzipped(model, "3")
    copy = tmp_path / "fmu"
    shutil.copytree(original, copy)
    build = ET.parse(copy / "sources" / "buildDescription.xml").getroot()
    files = [f.get("name") for f in build.iter("SourceFile")]
    [binary] = (copy / "binaries").rglob("*.so")
    binary.unlink()
    compiler = shutil.which(os.environ.get("CC", "gcc")) or pytest.fail("no C compiler")
    result = subprocess.run([compiler, "-std=c99", "-shared", "-fPIC", "-O1", "-I.", *files, "-o", str(binary), "-lm"],
                            cwd=copy / "sources", capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    a, b = _simulate(original, "CoSimulation"), _simulate(str(copy), "CoSimulation")
    for name, values in _signals(a).items():
        assert np.max(np.abs(_signals(b)[name] - values)) <= CS_EQUAL * max(1.0, float(np.max(np.abs(values)))), name


def test_unknown_fmi_version_refused():
    result = run_cli("build", "Bicycle.Control.PD", "--fmi-version", "4")
    assert result.returncode != 0 and "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines()[-1] == ("cosim build: error: argument --fmi-version: invalid FMI "
                                                      "version '4' (choose 2, 3 or both)")
