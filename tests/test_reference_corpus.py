"""The Reference FMUs 0.0.41 as the importer corpus: every verb on every model, FMI 2 and FMI 3.

Each FMU (tests/reference_fmus.py, built once per session) goes through ``cosim info``, ``validate``
(exit 0), ``simulate`` as Co-Simulation and as Model Exchange, compared with the reference result
the FMU ships (``extra/org.fmi-standard.fmi-ls-ref/NAME_out.csv``) by FMPy's cross-check measure
``fmpy.util.validate_result`` (the fraction of result samples outside a band around the reference),
and ``linearize`` where the model has continuous states (against the Jacobian of its model.c).
The Scheduled Execution model ``Clocks`` is described by ``info`` and refused by the others with one
line.

Two reference results are not results of their model, and these models are compared with FMPy's own
``simulate_fmu`` on the same FMU instead: ``Roberts/Roberts_out.csv`` is a copy of BouncingBall's
(and its fmi-ls-ref manifest names ``BouncingBall_out.csv``), and ``Feedthrough_out.csv`` is the
run without inputs (every output at its start value), so the run with ``Feedthrough_in.csv`` is
compared with FMPy given the same input.
"""
from __future__ import annotations

import csv
import json
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.util import validate_result
from lxml import etree

from conftest import cli_in_process
from reference_fmus import (ALL_MODELS_FMI2, ALL_MODELS_FMI3, SCHEDULED_MODELS, SOURCES, model_description,
                            reference_fmu, reference_fmu2, reference_output)

#: validate_result's measure: the fraction of result samples outside the band around the reference.
#: The FMI cross-check accepts a result at 0, the strictest value: every sample inside the band.
OUTLIERS = 0.0
#: Jacobian of linearize (central differences, or the FMU's directional derivatives) against model.c.
JACOBIAN_TOLERANCE = 1e-8
#: Roberts (stiff; no reference of its own) is compared with FMPy over this interval and output step [s].
ROBERTS_STOP, ROBERTS_STEP = 4.0, 0.04

MODELS = [(3, m) for m in ALL_MODELS_FMI3 if m not in SCHEDULED_MODELS] + [(2, m) for m in ALL_MODELS_FMI2]
#: Whose shipped reference result is not a result of the model (see the module docstring).
NO_REFERENCE = {"Roberts"}

#: d der(x) / d x of model.c at the start values.
JACOBIANS = {
    "BouncingBall": [[0.0, 1.0], [0.0, 0.0]],  # h' = v, v' = g
    "Dahlquist": [[-1.0]],  # x' = -k x, k = 1
    "VanDerPol": [[0.0, 1.0], [-1.0, -3.0]],  # x0' = x1, x1' = mu (1 - x0^2) x1 - x0 at (2, 0), mu = 1
    "StateSpace": np.eye(3).tolist(),  # x' = A x + B u, A = I
    # y1' = -0.04 y1 + 1e4 y2 y3, y2' = 0.04 y1 - 1e4 y2 y3 - 3e7 y2^2, y3 = 1 - y1 - y2 at (1, 0, 0)
    "Roberts": [[-0.04, 0.0], [0.04, 0.0]],
}


def model_id(version: int, name: str) -> str:
    return f"fmi{version}-{name}"


@pytest.fixture(scope="session")
def corpus(tmp_path_factory) -> dict[str, Path]:
    """Every Reference FMU (``fmi3-BouncingBall``, ..., ``fmi3-Clocks``, ``fmi2-BouncingBall``, ...),
    compiled once per session, two at a time."""
    folder = tmp_path_factory.mktemp("reference-corpus")
    jobs = {model_id(3, m): (reference_fmu, m, folder / "fmi3") for m in ALL_MODELS_FMI3}
    jobs.update({model_id(2, m): (reference_fmu2, m, folder / "fmi2") for m in ALL_MODELS_FMI2})
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = {key: pool.submit(build, name, where) for key, (build, name, where) in jobs.items()}
        return {key: future.result() for key, future in futures.items()}


def cosim(*argv, cwd: Path) -> tuple[int, str, str]:
    return cli_in_process([str(a) for a in argv], cwd)


def experiment(version: int, name: str) -> dict[str, float]:
    """The DefaultExperiment attributes of the model as numbers."""
    element = etree.parse(str(model_description(name, version))).getroot().find("DefaultExperiment")
    return {key: float(value) for key, value in element.attrib.items()}


def read_table(path: Path) -> tuple[np.ndarray, dict[str, list[str]]]:
    """A result or reference CSV as (numbers, texts): the columns of numbers (true/false as 1/0, a
    cell of several numbers separated by blanks as the elements ``NAME[1]``, ``NAME[2]``, ... of an
    array, as ``fmpy.read_csv`` reads them) as a structured float array, the others as lists of
    cells. For the files that ``fmpy.read_csv`` cannot read: Booleans and String or Binary texts."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    numbers, texts = {}, {}
    for k, name in enumerate(header):
        cells = [row[k] for row in rows]
        words = [c.strip().lower() for c in cells]
        if all(w in ("true", "false") for w in words):
            numbers[name] = np.array([w == "true" for w in words], dtype=float)
            continue
        try:
            values = np.array([[float(x) for x in c.split()] for c in cells])
        except ValueError:
            texts[name] = cells
            continue
        if values.shape[1] == 1 or name == "time":
            numbers[name] = values[:, 0]
        else:
            numbers.update({f"{name}[{i + 1}]": values[:, i] for i in range(values.shape[1])})
    table = np.empty(len(rows), dtype=[(n, float) for n in numbers])
    for name, values in numbers.items():
        table[name] = values
    return table, texts


def read_result(path: Path, texts: bool) -> tuple[np.ndarray, dict[str, list[str]]]:
    """cosim's result CSV: by ``fmpy.read_csv`` (its columns ``y[1]``, ... of an array are columns of
    their own there), or by :func:`read_table` if it has String columns (``texts``), which
    ``fmpy.read_csv`` cannot read."""
    return read_table(path) if texts else (fmpy.read_csv(path), {})


def assert_within_band(result: np.ndarray, reference: np.ndarray, what: str) -> None:
    """validate_result of ``result`` against ``reference`` on every numeric reference column, all of
    which the result must have (so that no column is left out of the comparison)."""
    columns = [n for n in reference.dtype.names if n != "time"]
    missing = set(columns) - set(result.dtype.names)
    assert not missing, f"{what}: the result lacks {sorted(missing)}"
    assert columns, what
    outliers = validate_result(result[["time", *columns]], reference.copy())
    assert outliers <= OUTLIERS, f"{what}: {outliers:.3f} of the samples outside the band"


SIMULATIONS = [(v, m, kind) for v, m in MODELS for kind in ("cs", "me")]


@pytest.mark.parametrize("version, name, kind", SIMULATIONS,
                         ids=[f"{model_id(v, m)}-{kind}" for v, m, kind in SIMULATIONS])
def test_simulate_within_the_reference_band(corpus, tmp_path, version, name, kind):
    """`cosim simulate` over the default experiment (stop time of the model description, cosim's
    default output step) lies within the cross-check band of the shipped reference result."""
    fmu = corpus[model_id(version, name)]
    stop = ROBERTS_STOP if name in NO_REFERENCE else experiment(version, name)["stopTime"]
    argv = ["simulate", fmu, "--stop-time", stop, "--fmi-type", kind, "-o", "out.csv"]
    if name in NO_REFERENCE:
        argv += ["--step", ROBERTS_STEP]
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    has_text = name == "Feedthrough"
    result, texts = read_result(tmp_path / "out.csv", has_text)
    if name == "Stair":  # terminateSimulation at t = 9 s: a normal end, one note
        assert err.strip().splitlines() == ["cosim simulate: note: the FMU ended the simulation at t = 9 s "
                                            "(terminateSimulation)"], err
        assert result["time"][-1] == 9.0
    else:
        assert err == "", err
        assert result["time"][-1] == pytest.approx(stop, abs=1e-9)
    if name in NO_REFERENCE:
        theirs = fmpy.simulate_fmu(str(fmu), fmi_type="ModelExchange", start_time=experiment(3, name)["startTime"],
                                   stop_time=stop, output_interval=ROBERTS_STEP)
        assert_within_band(result, theirs, f"{name} {kind} against FMPy")
        # the ODE form keeps y1 + y2 + y3 = 1
        np.testing.assert_allclose(result["y1"] + result["y2"] + result["y3"], 1.0, rtol=0, atol=1e-12)
        return
    reference, reference_texts = read_table(reference_output(name))
    outputs = output_names(version, name)
    kept = ["time"] + [n for n in reference.dtype.names[1:] if n.split("[")[0] in outputs]
    if version == 3:  # the reference is the FMI 3 model's: every column is compared
        assert kept == list(reference.dtype.names)
    assert_within_band(result, reference[kept], f"{model_id(version, name)} {kind}")
    # String outputs exactly at the reference times (cosim writes no Binary outputs)
    for column in sorted(set(reference_texts) & outputs - {"Binary_output"}):
        ours = dict(zip(np.round(result["time"], 9), texts[column]))
        assert [ours[round(t, 9)] for t in reference["time"]] == reference_texts[column], column


def output_names(version: int, name: str) -> set[str]:
    """The outputs of the model's FMI ``version`` description."""
    root = etree.parse(str(model_description(name, version))).getroot()
    return {v.get("name") for v in root.find("ModelVariables") if v.get("causality") == "output"}


INPUT_FILE = SOURCES / "Feedthrough" / "Feedthrough_in.csv"
INTEGER_TYPES = {"Int8": np.int8, "UInt8": np.uint8, "Int16": np.int16, "UInt16": np.uint16, "Int32": np.int32,
                 "UInt32": np.uint32, "Int64": np.int64, "UInt64": np.uint64, "Integer": np.int32}
INPUT_RUNS = [(v, kind) for v in (3, 2) for kind in ("cs", "me")]


@pytest.mark.parametrize("version, kind", INPUT_RUNS, ids=[f"fmi{v}-Feedthrough-{k}" for v, k in INPUT_RUNS])
def test_feedthrough_with_its_input_file_equals_fmpy(corpus, tmp_path, version, kind):
    """Feedthrough with ``Feedthrough_in.csv`` (integer inputs from their minimum to their maximum at
    t = 1 s, the 64-bit extremes too): every input given by ``--input NAME=Feedthrough_in.csv`` holds
    its value from one row to the next (a discrete signal), the outputs follow them exactly, as in
    FMPy's simulate_fmu given the same input as integers of the variables' types."""
    fmu = corpus[model_id(version, "Feedthrough")]
    md = fmpy.read_model_description(str(fmu))
    types = {v.name: v.type for v in md.modelVariables if v.causality == "input"}
    with open(INPUT_FILE, newline="") as f:
        rows = list(csv.reader(f))
    names = [n for n in rows[0][1:] if n in types]
    assert len(names) == (8 if version == 3 else 1)
    argv = ["simulate", fmu, "--stop-time", 2, "--fmi-type", kind, "-o", "out.csv"]
    argv += [a for n in names for a in ("--input", f"{n}={INPUT_FILE}")]
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    columns = [rows[0].index(n) for n in names]
    signals = np.array([tuple([float(r[0])] + [int(r[k]) for k in columns]) for r in rows[1:]],
                       dtype=[("time", float)] + [(n, INTEGER_TYPES[types[n]]) for n in names])
    theirs = fmpy.simulate_fmu(str(fmu), fmi_type="CoSimulation" if kind == "cs" else "ModelExchange",
                               stop_time=2.0, output_interval=0.01, input=signals)
    with open(tmp_path / "out.csv", newline="") as f:
        ours = list(csv.reader(f))
    header, ours = ours[0], ours[1:]
    assert len(ours) == len(theirs)
    np.testing.assert_allclose([float(r[0]) for r in ours], theirs["time"], rtol=0, atol=1e-12)
    for name in names:
        output = name.replace("_input", "_output")
        k = header.index(output)
        assert [int(r[k]) for r in ours] == [int(v) for v in theirs[output]], output
        # the value of each input row holds up to the next one (FMPy's Model Exchange records t = 1 s
        # before and after the input event)
        low, high = (int(rows[1][rows[0].index(name)]), int(rows[2][rows[0].index(name)]))
        assert {int(r[k]) for r in ours if float(r[0]) < 1.0} == {low}
        assert {int(r[k]) for r in ours if float(r[0]) > 1.0} == {high}


@pytest.mark.parametrize("version, kind", INPUT_RUNS, ids=[f"fmi{v}-Feedthrough-{k}" for v, k in INPUT_RUNS])
def test_feedthrough_real_boolean_and_enumeration_inputs(corpus, tmp_path, version, kind):
    """A real input of variability continuous is interpolated linearly between the rows of its file,
    one of variability discrete holds each row's value up to the next; Boolean and enumeration
    inputs step (``--input NAME=step:T0:VALUE``); the outputs of every type follow, the String
    output keeps its start value."""
    ramp = tmp_path / "ramp.csv"
    ramp.write_text("time,u\n0,0\n2,4\n")
    argv = ["simulate", corpus[model_id(version, "Feedthrough")], "--stop-time", 2, "--step", 0.1, "--fmi-type", kind,
            "-o", "out.csv", "--input", f"Float64_continuous_input={ramp}", "--input", f"Float64_discrete_input={ramp}",
            "--input", "Boolean_input=step:0.5:true", "--input", "Enumeration_input=step:1.5:2"]
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    result, texts = read_table(tmp_path / "out.csv")
    # The time of the inputs each row shows: Model Exchange records the outputs at the inputs of the
    # row's time; Co-Simulation those at the end of the step to it, over which the inputs held the
    # values of its start (as FMPy's simulate_fmu does).
    t = np.maximum(result["time"] - (0.1 if kind == "cs" else 0.0), 0.0)
    np.testing.assert_allclose(result["Float64_continuous_output"], 2 * t, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(result["Float64_discrete_output"][t < 2 - 1e-9], 0.0)
    if kind == "me":
        assert result["Float64_discrete_output"][-1] == 4.0
    # (at an input's step time itself the value before or after it)
    np.testing.assert_array_equal(result["Boolean_output"][t < 0.5 - 1e-9], 0.0)
    np.testing.assert_array_equal(result["Boolean_output"][t > 0.5 + 1e-9], 1.0)
    np.testing.assert_array_equal(result["Enumeration_output"][t < 1.5 - 1e-9], 1.0)
    np.testing.assert_array_equal(result["Enumeration_output"][t > 1.5 + 1e-9], 2.0)
    assert set(texts["String_output"]) == {"Set me!"}


BAD_INPUTS = [  # (id, input, file text or None for a step, what the one line says)
    ("int8-out-of-range", "Int8_input", "time,v\n0,1\n1,128\n", "in.csv:3: column 2 (v): 128 is outside the range of "
                                                                 "int8 (-128 .. 127)"),
    ("uint64-negative", "UInt64_input", "time,v\n0,-1\n", "in.csv:2: column 2 (v): -1 is outside the range of uint64"),
    ("int32-fraction", "Int32_input", "time,v\n0,1.5\n", "in.csv:2: column 2 (v): '1.5' is not a whole number"),
    ("boolean-word", "Boolean_input", "time,v\n0,maybe\n", "in.csv:2: column 2 (v): 'maybe' is not a Boolean"),
    ("string-input", "String_input", None, "--input String_input: String inputs are not supported"),
]


@pytest.mark.parametrize("case", BAD_INPUTS, ids=[c[0] for c in BAD_INPUTS])
def test_bad_typed_input_is_one_line(corpus, tmp_path, case):
    """A value an integer or Boolean input cannot take, or an input of a type cosim cannot set, is
    refused in one line naming the file, line and column (exit 2), before anything runs."""
    _, name, text, expected = case
    if text is None:
        source = "step:1:foo"
    else:
        (tmp_path / "in.csv").write_text(text)
        source = "in.csv"
    status, out, err = cosim("simulate", corpus["fmi3-Feedthrough"], "--stop-time", 1, "--input", f"{name}={source}",
                             "-o", "out.csv", cwd=tmp_path)
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cosim simulate: error: "), err
    assert expected in lines[0], lines[0]
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize("version, name", MODELS, ids=[model_id(v, m) for v, m in MODELS])
def test_validate_and_info(corpus, tmp_path, version, name):
    """`cosim validate` passes every Reference FMU (exit 0; warnings allowed) and `cosim info`
    describes it."""
    fmu = corpus[model_id(version, name)]
    status, out, err = cosim("validate", fmu, cwd=tmp_path)
    assert status == 0, out + err
    assert out.splitlines()[0].startswith(f"{fmu}: valid"), out
    status, out, err = cosim("info", fmu, "--json", cwd=tmp_path)
    assert status == 0, err
    info = json.loads(out)
    assert info["fmiVersion"] == f"{version}.0"
    assert info["interfaces"] == ["ModelExchange", "CoSimulation"]


#: `run` against `simulate` of the same FMU on the same communication grid: the same calls of the
#: same binary, so the same numbers but for the last bits of the time grid's sums.
RUN_EQUALS_SIMULATE = 1e-12


def system_file(folder: Path, fmu: Path, start: float, stop: float, step: float) -> Path:
    """A system of the one FMU ``fmu`` as component ``m``, every output recorded."""
    path = folder / "one.toml"
    path.write_text(f'[system]\nname = "one"\nstart = {start!r}\nstop = {stop!r}\nstep = {step!r}\n'
                    f'[components.m]\nfmu = "{fmu}"\n')
    return path


@pytest.mark.parametrize("version, name", MODELS, ids=[model_id(v, m) for v, m in MODELS])
def test_run_as_a_component(corpus, tmp_path, version, name):
    """`cosim run` of a system with the Reference FMU as its one component records every numeric and
    Boolean output (arrays element by element, ``m.y[1]``, ...) equal to `cosim simulate` of the FMU
    on the same grid, and within the band of the reference result; Stair ends the run at 9 s with
    exit 0 and a note."""
    fmu = corpus[model_id(version, name)]
    stop = ROBERTS_STOP if name in NO_REFERENCE else experiment(version, name)["stopTime"]
    step = ROBERTS_STEP if name in NO_REFERENCE else 0.01
    start = experiment(version, name).get("startTime", 0.0)
    status, out, err = cosim("run", system_file(tmp_path, fmu, start, stop, step), "-o", "run.csv", cwd=tmp_path)
    assert status == 0, err
    if name == "Stair":
        assert err.strip().splitlines() == ["cosim run: note: component 'm' ended the run at t = 9 s "
                                            "(terminateSimulation)"], err
    else:
        assert err == "", err
    ran = fmpy.read_csv(tmp_path / "run.csv")
    status, _, err = cosim("simulate", fmu, "--fmi-type", "cs", "--stop-time", stop, "--step", step,
                           "-o", "simulate.csv", cwd=tmp_path)
    assert status == 0, err
    simulated, _ = read_result(tmp_path / "simulate.csv", name == "Feedthrough")
    recorded = [n for n in ran.dtype.names[1:]]
    assert recorded, "nothing recorded"
    numeric = [n for n in simulated.dtype.names[1:] if f"m.{n}" in recorded]
    assert {f"m.{n}" for n in numeric} == {n for n in recorded if n != "m.h_ft"}, (recorded, numeric)
    np.testing.assert_allclose(ran["time"], simulated["time"], rtol=0, atol=RUN_EQUALS_SIMULATE)
    for n in numeric:
        np.testing.assert_allclose(ran[f"m.{n}"], simulated[n], rtol=0, atol=RUN_EQUALS_SIMULATE, err_msg=n)
    if name in NO_REFERENCE:
        return
    reference, _ = read_table(reference_output(name))
    as_result = np.empty(len(ran), dtype=[("time", float)] + [(n, float) for n in numeric])
    as_result["time"] = ran["time"]
    for n in numeric:
        as_result[n] = ran[f"m.{n}"]
    kept = ["time"] + [n for n in reference.dtype.names[1:] if n in numeric]
    assert len(kept) > 1, reference.dtype.names
    assert_within_band(as_result, reference[kept], f"{model_id(version, name)} run")


def test_run_refuses_scheduled_execution(corpus, tmp_path):
    """A Scheduled Execution FMU as a component of a system: one line, exit 2, nothing written."""
    status, out, err = cosim("run", system_file(tmp_path, corpus["fmi3-Clocks"], 0.0, 1.0, 0.1), "-o", "run.csv",
                             cwd=tmp_path)
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cosim run: error: ") and "Traceback" not in err, err
    assert "Clocks" in lines[0], lines[0]
    assert not (tmp_path / "run.csv").exists()


LINEARIZED = [(v, m) for v, m in MODELS if m in JACOBIANS]


@pytest.mark.parametrize("version, name", LINEARIZED, ids=[model_id(v, m) for v, m in LINEARIZED])
def test_linearize_gives_the_jacobian(corpus, tmp_path, version, name):
    """`cosim linearize` of a Reference FMU with continuous states at its start values gives the
    Jacobian of its model.c."""
    status, out, err = cosim("linearize", corpus[model_id(version, name)], "--json", cwd=tmp_path)
    assert status == 0, err
    report = json.loads(out)
    np.testing.assert_allclose(report["A"], JACOBIANS[name], rtol=0, atol=JACOBIAN_TOLERANCE)
    if name == "StateSpace":  # y = C x + D u, x' = A x + B u with identities
        for matrix in ("B", "C", "D"):
            np.testing.assert_allclose(report[matrix], np.eye(3), rtol=0, atol=JACOBIAN_TOLERANCE, err_msg=matrix)


REFUSALS = {"simulate-cs": ["simulate", "--stop-time", "1", "--fmi-type", "cs"],
            "simulate-me": ["simulate", "--stop-time", "1", "--fmi-type", "me"],
            "linearize": ["linearize"], "validate": ["validate"]}


@pytest.mark.parametrize("verb", REFUSALS)
def test_scheduled_execution_is_refused_in_one_line(corpus, tmp_path, verb):
    """Clocks (FMI 3 Scheduled Execution only) is refused with one line naming it (exit 2)."""
    argv = REFUSALS[verb]
    status, out, err = cosim(argv[0], corpus["fmi3-Clocks"], *argv[1:], cwd=tmp_path)
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith(f"cosim {argv[0]}: error: ")
    assert "Clocks is an FMI 3 Scheduled Execution FMU" in lines[0] and "not supported" in lines[0], lines[0]
    assert list(tmp_path.iterdir()) == []


def test_scheduled_execution_is_described(corpus, tmp_path):
    """`cosim info` describes Clocks: its one interface and its clocks."""
    status, out, err = cosim("info", corpus["fmi3-Clocks"], "--json", cwd=tmp_path)
    assert status == 0, err
    info = json.loads(out)
    assert info["interfaces"] == ["ScheduledExecution"]
    assert {v["name"] for v in info["variables"]["input"] if v["type"] == "Clock"} == {"inClock1", "inClock2",
                                                                                        "inClock3"}
