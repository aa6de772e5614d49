"""`cosim run` honours stop exactly: steps of [system] step, the last one shorter when step does not
divide the span; a step longer than the run, non-finite or not positive is refused; the message
reports the real end time and step count."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import run_cli

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

BIKE = "Bicycle.Bicycles.SelfStabilizing"


def _system(tmp_path, fmus, settings: str, python_block: bool) -> str:
    """A system file: the bicycle alone (stepped by the C loop) or with a Python block (Python loop)."""
    text = 'connections = ["push.y -> bike.T"]\n' if python_block else "connections = []\n"
    text += f"[system]\n{settings}\n[components.bike]\nfmu = \"{fmus[BIKE]}\"\nparameters = {{ V = 6.0 }}\n"
    if python_block:
        text += '[components.push]\npython = "Pulse"\nparameters = { amplitude = 1.0, start = 0.5, duration = 0.2 }\n'
    path = tmp_path / "system.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("python_block", [False, True], ids=["fast-c-loop", "python-loop"])
def test_run_step_not_dividing_span_ends_on_stop_with_a_short_last_step(fmus, tmp_path, python_block):
    out = tmp_path / "r.csv"
    result = run_cli("run", _system(tmp_path, fmus, "stop = 2.0\nstep = 0.3", python_block), "-o", str(out))
    assert result.returncode == 0, result.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    np.testing.assert_allclose(data["time"], [0, 0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 2.0], rtol=0, atol=1e-12)
    assert data["time"][-1] == 2.0  # exactly, not 2.1 and not 0.3 * 7
    assert "completed at t = 2 s after 7 steps (the last one 0.2 s" in result.stdout
    assert "(7 steps, 8 rows, t = 0 .. 2 s)" in result.stdout


@pytest.mark.parametrize("settings,message", [
    ("stop = 2.0\nstep = 5.0", "[system] step: 5 s is longer than the run from 0 s to 2 s"),
    ("stop = 2.0\nstep = inf", "[system] step: must be finite, got inf"),
    ("stop = 2.0\nstep = nan", "[system] step: must be finite, got nan"),
    ("stop = 2.0\nstep = 0.0", "[system] step: must be > 0, got 0"),
    ("stop = inf", "[system] stop: must be finite, got inf"),
    ("start = 3.0\nstop = 2.0", "[system] stop: must be after start (2 s <= 3 s)"),
    ("stop = 1e9\nstep = 1e-9",
     "[system] step: 1e-09 s from 0 s to 1e+09 s would take 1e+18 steps (at most 10,000,000)"),
], ids=["step-larger-than-stop", "step-inf", "step-nan", "step-zero", "stop-inf", "stop-before-start",
        "too-many-steps"])
def test_run_step_larger_than_stop_or_not_finite_is_refused(fmus, tmp_path, settings, message):
    out = tmp_path / "r.csv"
    system = _system(tmp_path, fmus, settings, python_block=False)
    result = run_cli("run", system, "-o", str(out))
    assert result.returncode == 2, result.stdout
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    assert f"cosim run: error: {system}: {message}" in result.stderr, result.stderr
    assert "completed" not in result.stdout and not out.exists()


def test_step_grid_ends_on_stop_exactly():
    from cosim.cosimulation.master import step_grid

    assert step_grid(0.0, 10.0, 0.01)[-1] == 10.0 and len(step_grid(0.0, 10.0, 0.01)) == 1001  # round-off only
    grid = step_grid(0.5, 2.0, 0.4)
    np.testing.assert_allclose(grid, [0.5, 0.9, 1.3, 1.7, 2.0], rtol=0, atol=1e-15)


def test_export_ssp_refuses_step_not_dividing_span(tmp_path):
    """The OSP fixed-step algorithm of an SSP cannot end on stop with a shorter step."""
    system = tmp_path / "s.toml"
    system.write_text('connections = []\n[system]\nstop = 2.0\nstep = 0.3\n'
                      f'[components.bike]\nmodel = "{BIKE}"\n')
    out = tmp_path / "s.ssp"
    result = run_cli("export-ssp", str(system), "-o", str(out))
    assert result.returncode == 2 and "step 0.3 s does not divide the run" in result.stderr
    assert not out.exists()
