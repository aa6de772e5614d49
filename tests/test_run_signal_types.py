"""Signals of other types than Real between foreign FMUs under `cosim run`, with the Reference FMU
``Feedthrough`` (each output equals the input of its type).

- Integer, Boolean and Enumeration signals (FMI 3: every integer width, Float32) connect to
  variables of the same type (an enumeration of the same declared type; FMI 2 Integer is FMI 3
  Int32, Real is Float64) and are recorded (as numbers: Booleans 0 and 1).
- Any other pairing, and String or Binary variables, are refused with one line naming the
  connection; a discrete input under algorithm = "model-exchange" too (FMI sets those in Event
  Mode only).
- Parameters of other types are set from the system file as `simulate --param` sets them (the
  String parameter of Feedthrough), a value of the wrong type refused naming it.

The variant ``FeedthroughStarts`` starts its Int32, Boolean and Enumeration inputs at 7, true and
2, so that the values passed on are not the defaults.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import cli_in_process
from reference_fmus import reference_fmu, reference_fmu2

STARTS = {"model.c": [("M(Int32_input)   = 0;", "M(Int32_input)   = 7;"),
                      ("M(Boolean_input)  = false;", "M(Boolean_input)  = true;"),
                      ("M(Enumeration_input)  = Option1;", "M(Enumeration_input)  = Option2;")]}
PASSED = {"Int32": 7.0, "Boolean": 1.0, "Enumeration": 2.0}  # the started inputs, through two FMUs
STEP_AMPLITUDE = 2.0  # the Step block on the Float64 path, from t = 0.5 s


@pytest.fixture(scope="module")
def feedthrough(tmp_path_factory):
    folder = tmp_path_factory.mktemp("feedthrough")
    return {"2": reference_fmu2("Feedthrough", folder / "fmi2", edits=STARTS, fmu_name="FeedthroughStarts"),
            "3": reference_fmu("Feedthrough", folder / "fmi3", edits=STARTS, fmu_name="FeedthroughStarts")}


def _system(folder, fmus: tuple, connections: list[str], algorithm: str = "jacobi", record=None,
            parameters: str = "") -> str:
    text = f"connections = {connections!r}\n".replace("'", '"')
    text += f'[system]\nname = "types"\nstop = 1.0\nstep = 0.1\nalgorithm = "{algorithm}"\n'
    if record:
        text += f"record = {record!r}\n".replace("'", '"')
    for name, fmu in zip("ab", fmus):
        text += f'[components.{name}]\nfmu = "{fmu}"\n'
        if name == "a" and parameters:
            text += f"parameters = {{ {parameters} }}\n"
    text += '[components.src]\npython = "Step"\n' + f"parameters = {{ amplitude = {STEP_AMPLITUDE}, start = 0.5 }}\n"
    path = folder / "types.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
@pytest.mark.parametrize("versions", [("2", "2"), ("3", "3"), ("2", "3")], ids=["fmi2", "fmi3", "fmi2-to-fmi3"])
def test_signals_of_one_type_connect(feedthrough, tmp_path, versions, algorithm):
    a, b = (feedthrough[v] for v in versions)
    enumeration = "Enumeration_output -> b.Enumeration_input"
    connections = ["a.Int32_output -> b.Int32_input", "a.Boolean_output -> b.Boolean_input", f"a.{enumeration}",
                   "src.y -> a.Float64_continuous_input", "a.Float64_continuous_output -> b.Float64_continuous_input"]
    record = [f"b.{t}_output" for t in PASSED] + ["a.Float64_continuous_output", "b.Float64_continuous_output"]
    system = _system(tmp_path, (a, b), connections, algorithm, record, 'String_parameter = "set from the system"')
    code, stdout, stderr = cli_in_process(["run", system, "-o", "types.csv"], tmp_path)
    assert code == 0 and not stderr, stdout + stderr
    rows = np.genfromtxt(tmp_path / "types.csv", delimiter=",", names=True, deletechars="")
    for type_, value in PASSED.items():
        np.testing.assert_array_equal(rows[f"b.{type_}_output"], value)
    # The Real path beside them: b takes a's output of the step before under Jacobi, of the same
    # step under Gauss-Seidel (a before b)
    a_out, b_out = rows["a.Float64_continuous_output"], rows["b.Float64_continuous_output"]
    assert a_out[-1] == STEP_AMPLITUDE
    if algorithm == "jacobi":
        np.testing.assert_array_equal(b_out[1:], a_out[:-1])
    else:
        np.testing.assert_array_equal(b_out[1:], a_out[1:])


@pytest.mark.parametrize("version, connection, message", [
    ("2", "a.Int32_output -> b.Float64_continuous_input",
     "'a.Int32_output' is Integer and 'b.Float64_continuous_input' is Real; a connection joins variables of one type"),
    ("2", "a.Boolean_output -> b.Int32_input", "'a.Boolean_output' is Boolean and 'b.Int32_input' is Integer"),
    ("3", "a.Int8_output -> b.Int16_input", "'a.Int8_output' is Int8 and 'b.Int16_input' is Int16"),
    ("3", "a.Float64_continuous_output -> b.Float32_continuous_input",
     "'a.Float64_continuous_output' is Float64 and 'b.Float32_continuous_input' is Float32"),
    ("3", "a.Binary_output -> b.Binary_input", "'a.Binary_output' is Binary; connections carry numbers and Booleans"),
    ("3", "src.y -> a.Int32_input", "'src.y' is Real and 'a.Int32_input' is Int32"),
], ids=["integer-to-real", "boolean-to-integer", "int8-to-int16", "float64-to-float32", "binary", "block-to-int32"])
def test_other_connections_are_refused(feedthrough, tmp_path, version, connection, message):
    system = _system(tmp_path, (feedthrough[version],) * 2, [connection])
    code, stdout, stderr = cli_in_process(["run", system, "-o", "types.csv"], tmp_path)
    assert code == 2, stdout + stderr
    assert stderr.count("\n") == 1 and stderr.startswith("cosim run: error: ")
    assert f"connection '{connection}': type mismatch: {message}" in stderr
    assert not (tmp_path / "types.csv").exists()


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_discrete_inputs_under_model_exchange(feedthrough, tmp_path, version):
    fmus = (feedthrough[version],) * 2
    # recorded, not connected: read in continuous time
    system = _system(tmp_path, fmus, [], "model-exchange", ["a.Int32_output", "a.Boolean_output"])
    code, stdout, stderr = cli_in_process(["run", system, "-o", "types.csv"], tmp_path)
    assert code == 0 and not stderr, stdout + stderr
    rows = np.genfromtxt(tmp_path / "types.csv", delimiter=",", names=True, deletechars="")
    np.testing.assert_array_equal(rows["a.Int32_output"], PASSED["Int32"])
    np.testing.assert_array_equal(rows["a.Boolean_output"], PASSED["Boolean"])
    # connected: refused before anything runs
    system = _system(tmp_path, fmus, ["a.Int32_output -> b.Int32_input"], "model-exchange")
    code, stdout, stderr = cli_in_process(["run", system, "-o", "types.csv"], tmp_path)
    assert code == 2 and stderr.count("\n") == 1, stdout + stderr
    assert "connection 'a.Int32_output -> b.Int32_input': 'b.Int32_input' is a discrete input" in stderr


@pytest.mark.parametrize("value, message", [
    ("3", "parameter 'String_parameter' is a String; got 3"),
    ("true", "parameter 'String_parameter' is a String; got True"),
    ('"x", unknown = 1', "unknown parameter 'unknown'"),
], ids=["number-for-string", "boolean-for-string", "unknown"])
def test_parameters_of_other_types_are_checked(feedthrough, tmp_path, value, message):
    system = _system(tmp_path, (feedthrough["3"],) * 2, [], parameters=f"String_parameter = {value}")
    code, stdout, stderr = cli_in_process(["run", system, "-o", "types.csv"], tmp_path)
    assert code == 2 and stderr.count("\n") == 1, stdout + stderr
    assert "component 'a': " in stderr and message in stderr
