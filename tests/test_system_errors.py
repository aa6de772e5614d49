"""Bad system files: one clear error naming the offending connection or entry."""
from __future__ import annotations

import zipfile

import pytest

from conftest import run_cli
from cosim.cosimulation.factory import run_system
from cosim.cosimulation.system import SystemError_, system_from_dict

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

BIKE = "Bicycle.Bicycles.SelfStabilizing"


def spec(fmus, connections, algorithm="jacobi", extra=None):
    components = {
        "bike": {"fmu": str(fmus[BIKE]), "parameters": {"V": 6.0}},
        "rider": {"python": "Proportional", "parameters": {"k": 20.0}},
        "gain": {"python": "SteerAngleFeedback", "parameters": {"k2": 1.0}},
        **(extra or {}),
    }
    return system_from_dict({"system": {"stop": 0.1, "step": 0.01, "algorithm": algorithm},
                             "components": components, "connections": connections})


CASES = [
    ("unknown-component", ["bike.phi -> nobody.phi"], "unknown component 'nobody'"),
    ("unknown-signal", ["bike.psi_dot -> rider.phi"], "'bike' has no output 'psi_dot'"),
    ("causality", ["bike.T -> rider.phi"], "causality mismatch: 'bike.T' is an input, not an output"),
    ("connected-twice", ["bike.phi -> rider.phi", "bike.delta -> rider.phi"],
     "input rider.phi is connected twice: 'bike.phi -> rider.phi' and 'bike.delta -> rider.phi'"),
    ("malformed", ["bike.phi => rider.phi"], "must read 'COMPONENT.OUTPUT -> COMPONENT.INPUT'"),
]


@pytest.mark.parametrize("case,connections,message", CASES, ids=[c[0] for c in CASES])
def test_bad_connection(fmus, case, connections, message):
    with pytest.raises(SystemError_) as info:
        run_system(spec(fmus, connections))
    assert message in str(info.value)


def test_type_mismatch_is_named(fmus, tmp_path):
    """An Integer input cannot take a Real signal: a copy of the PD rider FMU whose roll input
    is declared Integer (the check reads the FMU's model description)."""
    real = ('<ScalarVariable name="phi" valueReference="1" description="Roll angle" causality="input" '
            'variability="continuous">\n      <Real unit="rad" displayUnit="deg" start="0.0" />')
    integer = ('<ScalarVariable name="phi" valueReference="1" description="Roll angle" causality="input" '
               'variability="discrete">\n      <Integer start="0" />')
    integer_input = tmp_path / "pd_integer_input.fmu"
    with zipfile.ZipFile(fmus["Bicycle.Control.PD"]) as original, zipfile.ZipFile(integer_input, "w") as copy:
        for item in original.infolist():
            data = original.read(item)
            if item.filename == "modelDescription.xml":
                assert real.encode() in data, "the PD FMU's roll input changed: update this test"
                data = data.replace(real.encode(), integer.encode())
            copy.writestr(item, data)
    with pytest.raises(SystemError_) as info:
        run_system(spec(fmus, ["bike.phi -> pd.phi"], extra={"pd": {"fmu": str(integer_input)}}))
    assert ("connection 'bike.phi -> pd.phi': type mismatch: 'bike.phi' is Real and 'pd.phi' is Integer; "
            "a connection joins variables of one type") in str(info.value)


def test_gauss_seidel_algebraic_loop_is_named(fmus):
    """Two direct-feedthrough blocks in a loop cannot be ordered under Gauss-Seidel."""
    connections = ["rider.T -> gain.phi", "gain.delta -> rider.phi"]
    with pytest.raises(SystemError_) as info:
        run_system(spec(fmus, connections, algorithm="gauss-seidel"))
    text = str(info.value)
    assert "cycle without delay under Gauss-Seidel" in text
    assert "'rider.T -> gain.phi'" in text and "'gain.delta -> rider.phi'" in text


def test_gauss_seidel_loop_through_a_state_is_fine(fmus):
    """bike.phi does not depend on bike.T without delay, so the rider loop can be ordered."""
    result = run_system(spec(fmus, ["bike.phi -> rider.phi", "rider.T -> bike.T"], algorithm="gauss-seidel"))
    assert result.outcome.status == "completed"


def test_gauss_seidel_loop_through_transport_delay_is_fine(fmus):
    extra = {"delay": {"python": "TransportDelay", "parameters": {"tau": 0.1}}}
    connections = ["rider.T -> delay.u", "delay.y -> gain.phi", "gain.delta -> rider.phi"]
    result = run_system(spec(fmus, connections, algorithm="gauss-seidel", extra=extra))
    assert result.outcome.status == "completed"


@pytest.mark.parametrize("text,message", [
    ('[system]\nstep = -1\n[components.a]\npython = "Step"\n', "[system] step: must be > 0, got -1"),
    ('[system]\nalgorithm = "rk4"\n[components.a]\npython = "Step"\n',
     "[system] algorithm: must be one of jacobi, gauss-seidel, model-exchange, got 'rk4'"),
    ('[components.a]\npython = "Nope"\n', "unknown Python block 'Nope'"),
    ('[components.a]\npython = "Step"\nparameters = { amplitud = 1 }\n', "unknown parameter(s) amplitud"),
    ('[components.a]\npython = "Step"\nconnections = ["a.y -> a.y"]\n', "'connections' ended up inside"),
], ids=["negative-step", "algorithm", "unknown-block", "unknown-parameter", "misplaced-connections"])
def test_cli_run_reports_bad_file(tmp_path, text, message):
    path = tmp_path / "system.toml"
    path.write_text(text)
    out = tmp_path / "out.csv"
    result = run_cli("run", str(path), "-o", str(out))
    assert result.returncode != 0
    assert message in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()


STEP = '[components.a]\npython = "Step"\n'
# (TOML text, the one problem it has: key and expected type)
WRONG_TYPES = {
    "algorithm-integer": (f"[system]\nalgorithm = 5\n{STEP}",
                          "[system] algorithm: expected a string ('jacobi' or 'gauss-seidel' or 'model-exchange'), got an integer (5)"),
    "fall-integer": (f"[system]\nfall = 3\n{STEP}", "[system] fall: expected a table { signal = "),
    "fall-limit-string": (f'[system]\nfall = {{ signal = "a.y", limit = "1" }}\n{STEP}',
                          "[system] fall.limit: expected a number, got a string ('1')"),
    "stop-string": (f'[system]\nstop = "2"\n{STEP}', "[system] stop: expected a number, got a string ('2')"),
    "step-boolean": (f"[system]\nstep = true\n{STEP}", "[system] step: expected a number, got a boolean (true)"),
    "stop-inf": (f"[system]\nstop = inf\n{STEP}", "[system] stop: must be finite, got inf"),
    "initialize-integer": (f"[system]\ninitialize = 1\n{STEP}",
                           "[system] initialize: expected a boolean (true or false), got an integer (1)"),
    "record-string": (f'[system]\nrecord = "a.y"\n{STEP}',
                      "[system] record: expected an array of strings, got a string ('a.y')"),
    "sampling-integer": (f"[system]\nsampling = 2\n{STEP}", "[system] sampling: expected a string"),
    "system-integer": (f"system = 5\n{STEP}", "[system]: expected a table, got an integer (5)"),
    "params-integer": ('[components.bike]\nmodel = "Bicycle.Bicycles.WhippleLinear"\nparams = 5\n',
                       "[components.bike] params: expected a string, got an integer (5)"),
    "parameters-integer": ('[components.a]\npython = "Step"\nparameters = 5\n',
                           "[components.a] parameters: expected a table { NAME = VALUE, ... }, got an integer (5)"),
    "parameter-array": ('[components.a]\npython = "Step"\nparameters = { amplitude = [1, 2] }\n',
                        "[components.a] parameters amplitude: expected a number, boolean or string, got an array"),
    "block-parameter-string": ('[components.a]\npython = "Step"\nparameters = { amplitude = "big" }\n',
                               "component 'a' (Step): parameter 'amplitude': expected a number, got 'big'"),
    "step-multiple-float": ('[components.a]\npython = "Step"\nstep_multiple = 1.5\n',
                            "[components.a] step_multiple: must be a positive integer, got a number (1.5)"),
    "component-integer": ("[components]\na = 5\n", "[components.a]: expected a table, got an integer (5)"),
    "model-integer": ("[components.a]\nmodel = 5\n", "[components.a] model: expected a string, got an integer (5)"),
    "connections-string": (f'connections = "a.y -> b.u"\n{STEP}',
                           "connections: expected an array of strings, got a string"),
    "unknown-top-level-key": (f"[component.a]\npython = 'Step'\n{STEP}", "unknown top-level keys: component"),
}


@pytest.mark.parametrize("case", list(WRONG_TYPES))
def test_wrong_toml_type_in_system_file_names_file_key_and_type(tmp_path, case):
    text, message = WRONG_TYPES[case]
    path = tmp_path / "system.toml"
    path.write_text(text)
    out = tmp_path / "out.csv"
    result = run_cli("run", str(path), "-o", str(out))
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    assert f"cosim run: error: {path}: {message}" in result.stderr, result.stderr
    assert not out.exists()


def test_system_file_problems_are_all_listed_in_one_message(tmp_path):
    """As FMPy's validation does: every problem of the file, not only the first."""
    from cosim.cosimulation.system import SystemError_, load_system

    path = tmp_path / "system.toml"
    path.write_text('[system]\nalgorithm = 5\nfall = 3\nstop = inf\n[components.bike]\n'
                    'model = "Bicycle.Bicycles.WhippleLinear"\nparams = 5\n')
    with pytest.raises(SystemError_) as info:
        load_system(path)
    text = str(info.value)
    assert text.startswith(f"{path}: 4 problems: ")
    for key in ("[system] algorithm", "[system] fall", "[system] stop", "[components.bike] params"):
        assert f"{key}: " in text
    assert "\n" not in text


@pytest.mark.parametrize("content,message", [
    (b"\xff\xfe[system]\n", "not UTF-8 text (byte 0)"),
    (b"[system\n", "Expected ']'"),
], ids=["not-utf8", "toml-syntax"])
def test_unreadable_system_file_names_the_file(tmp_path, content, message):
    path = tmp_path / "system.toml"
    path.write_bytes(content)
    result = run_cli("run", str(path), "-o", str(tmp_path / "out.csv"))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert f"cosim run: error: {path}: " in result.stderr and message in result.stderr, result.stderr
