"""Bad system files: one clear error naming the offending connection or entry."""
from __future__ import annotations

import pytest

from conftest import run_cli
from cosim.cosimulation.factory import run_system
from cosim.cosimulation.system import SystemError_, system_from_dict

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


def test_type_mismatch(fmus):
    """An Integer variable cannot take a Real signal (the Pade delay's order n is an Integer)."""
    from cosim.compiler.build import build_model

    pade = build_model("Bicycle.Rider.PadeDelay", fmus[BIKE].parent).fmu
    with pytest.raises(SystemError_) as info:
        run_system(spec(fmus, ["bike.phi -> delay.n"], extra={"delay": {"fmu": str(pade)}}))
    assert "'delay.n' is an parameter" not in str(info.value)
    assert "delay.n" in str(info.value) and ("type mismatch" in str(info.value) or "causality" in str(info.value))


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
    ('[system]\nstep = -1\n[components.a]\npython = "Step"\n', "step must be positive"),
    ('[system]\nalgorithm = "rk4"\n[components.a]\npython = "Step"\n', "algorithm must be one of"),
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
