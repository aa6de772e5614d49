"""Speed sweeps of the linearization: `cosim linearize MODEL --speeds A:B:STEP|V1,V2,...` and
:func:`cosim.bicycle.linearize.linearize_speeds` (one FMU instance re-initialized per speed).

What is checked, with the tolerances used:

* the sweep equals single-speed :func:`linearize` calls (fresh instance per speed, FMPy wrappers)
  at several speeds for Whipple, WhippleRider (hinge free and locked), WhippleLinear and the
  simple SelfStabilizing model: A, B, C, D, x0, xdot0 and the eigenvalues (matched as sets)
  to <= 1e-12 (absolute, relative to max(1, |value|)), the lateral eigenvalues of
  :func:`steady_motion` the same, in the same sorted order; the speeds in the sweep's order
  (not monotonic, repeated) so that nothing carries over from one speed to the next;
* `cosim linearize ... --speeds ... --json`: the JSON shape (speeds, common fields, per point
  speed, speed parameter, eigenvalues, steady_motion), its eigenvalues equal those of
  `--speed V --json` to 1e-12; `--matrices` adds A, B, C, D; the text table has one line per speed;
* the continuation (the instance stays in initialization mode, only the speed changes, the
  pitch solved from the previous speed's) gives what initialization from scratch at every speed
  gives: A, B, C, D, x0, xdot0 and the lateral eigenvalues to <= 1e-12 (as above), also off upright
  running where the pitch is not zero, and it is used for the FMUs built here;
* the one speed parser (also `cosim compare`'s) on valid and
  invalid input;
* bad input (empty range, STEP <= 0, NaN, negative speeds for the nonlinear bicycles, --speed with
  --speeds, the speed parameter also as --param, --matrices without --speeds, --lock-hinge
  without a hinge): exit 2 and one `cosim linearize: error:` line, no traceback.
"""
from __future__ import annotations

import re

import json
import os

import numpy as np
import pytest

from conftest import run_cli
from cosim.errors import ParameterError
from cosim.bicycle.linearize import linearize_speeds, parse_speeds, steady_motion
from cosim.fmu.linearize import linearize

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

WHIPPLE = "Bicycle.Bicycles.Whipple"
RIDER = "Bicycle.Bicycles.WhippleRider"
LINEAR = "Bicycle.Bicycles.WhippleLinear"
SIMPLE = "Bicycle.Bicycles.SelfStabilizing"
TOL = 1e-12
#: Not monotonic and with a repeat: a sweep must not depend on the previous speed.
SPEEDS = [4.3, 0.0, 10.0, 1.0, 4.3, 0.5, 6.25]


@pytest.fixture(scope="module")
def built():
    """The four models built (incrementally) into the test FMU folder."""
    from cosim.compiler.build import build_model
    from cosim.compiler.library import load_library

    library = load_library()
    return {m: build_model(m, os.environ["COSIM_FMU_DIR"], library).fmu for m in (WHIPPLE, RIDER, LINEAR, SIMPLE)}


def _speed_values(model: str, v: float) -> dict:
    """The single-speed parameters as `--speed` sets them (rR = 0.3 m in the nonlinear defaults)."""
    return {"u_R0": -v / 0.3} if model in (WHIPPLE, RIDER) else {("v" if model == LINEAR else "V"): v}


def _close(a, b, tol=TOL) -> float:
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    return float((np.abs(a - b) / np.maximum(1.0, np.abs(b))).max(initial=0.0))


def _set_error(a, b) -> float:
    """Largest distance between two eigenvalue sets matched greedily, relative to max(1, |b|)."""
    a, b = list(np.asarray(a, complex)), list(np.asarray(b, complex))
    assert len(a) == len(b)
    worst = 0.0
    for e in b:
        k = int(np.argmin([abs(x - e) for x in a]))
        worst = max(worst, abs(a.pop(k) - e) / max(1.0, abs(e)))
    return worst


@pytest.mark.parametrize("model, lock", [pytest.param(WHIPPLE, False, id="Whipple"),
                                         pytest.param(RIDER, False, id="WhippleRider-free"),
                                         pytest.param(RIDER, True, id="WhippleRider-locked"),
                                         pytest.param(LINEAR, False, id="WhippleLinear"),
                                         pytest.param(SIMPLE, False, id="SelfStabilizing")])
def test_sweep_equals_single_speed_calls(built, model, lock):
    sweep = linearize_speeds(built[model], SPEEDS, lock_hinge=lock)
    assert len(sweep) == len(SPEEDS) and list(sweep.speeds) == SPEEDS
    eigenvalues = sweep.eigenvalues
    lateral = sweep.lateral_eigenvalues if model in (WHIPPLE, RIDER) else None
    for k, v in enumerate(SPEEDS):
        single = linearize(built[model], _speed_values(model, v))
        swept = sweep.systems[k]
        assert single.system.states == swept.states and single.system.outputs == swept.outputs
        for name in ("A", "B", "C", "D"):
            assert _close(getattr(swept, name), getattr(single.system, name)) <= TOL, (name, v)
        for name in ("x0", "xdot0"):
            assert _close(getattr(sweep, name)[k], getattr(single, name)) <= TOL, (name, v)
        assert _set_error(eigenvalues[k], single.eigenvalues) <= TOL, v
        if lateral is not None:
            reference = steady_motion(single, lock_hinge=lock)
            assert _close(lateral[k], reference.eigenvalues) <= TOL, v
            assert sweep.steady[k].speed == pytest.approx(v, rel=1e-14, abs=1e-14)
            assert sweep.steady[k].system.states == reference.system.states
    if lateral is None:
        assert sweep.steady is None
        with pytest.raises(ValueError, match="not a nonlinear bicycle"):
            sweep.lateral_eigenvalues


def test_sweep_with_parameters_and_refused_reduction(built):
    """Other parameters apply at every speed; a start value off upright running refuses the
    reduction per speed (note), as `--speed` does, while the full eigenvalues are still given."""
    sweep = linearize_speeds(built[WHIPPLE], [1.0, 5.0], {"phi0": 0.1, "mB": 80.0})
    for k, v in enumerate([1.0, 5.0]):
        single = linearize(built[WHIPPLE], {"phi0": 0.1, "mB": 80.0, **_speed_values(WHIPPLE, v)})
        assert _close(sweep.systems[k].A, single.system.A) <= TOL
        assert "not upright straight running" in str(sweep.steady[k]) and "phi = 0.1" in str(sweep.steady[k])
    assert np.all(np.isnan(sweep.lateral_eigenvalues))


CONTINUED = [
    # model, parameters, whether the pitch theta is 0 at the start (upright straight running)
    pytest.param(WHIPPLE, {"tR": 0.3}, True, id="Whipple-crowned-roller"),
    pytest.param(WHIPPLE, {"phi0": 0.1, "delta0": 0.2, "tR": 0.3}, False, id="Whipple-leaning-pitch"),
    pytest.param(RIDER, {}, True, id="WhippleRider"),
    pytest.param(LINEAR, {"c": 0.1}, True, id="WhippleLinear"),
]


@pytest.mark.parametrize("model, parameters, upright", CONTINUED)
def test_continuation_equals_initialization_from_scratch(built, model, parameters, upright):
    from cosim.fmu.access import FMU
    from cosim.fmu.linearize import _continuable

    with FMU(built[model]) as fmu:
        assert _continuable(fmu)  # else both sweeps below would be from scratch
    speeds = [0.0, 0.5, 3.0, 4.3, 4.3, 9.5, 1.0]
    on = linearize_speeds(built[model], speeds, parameters)
    off = linearize_speeds(built[model], speeds, parameters, continuation=False)
    for k, v in enumerate(speeds):
        for name in ("A", "B", "C", "D"):
            assert _close(getattr(on.systems[k], name), getattr(off.systems[k], name)) <= TOL, (name, v)
    assert _close(on.x0, off.x0) <= TOL and _close(on.xdot0, off.xdot0) <= TOL
    if model != LINEAR:
        pitch = on.systems[0].states.index("theta")
        assert (np.all(off.x0[:, pitch] == 0.0)) == upright  # off upright running the pitch is solved anew
        assert _close(np.nan_to_num(on.lateral_eigenvalues), np.nan_to_num(off.lateral_eigenvalues)) <= TOL


@pytest.mark.parametrize("speeds, match", [pytest.param([], "no speeds", id="empty"),
                                           pytest.param([1.0, float("nan")], "finite", id="nan"),
                                           pytest.param([-1.0], ">= 0 m/s", id="negative")])
def test_sweep_api_refuses(built, speeds, match):
    with pytest.raises(ParameterError, match=match):
        linearize_speeds(built[WHIPPLE], speeds)


def test_sweep_api_refuses_the_speed_parameter(built):
    with pytest.raises(ParameterError, match="u_R0"):
        linearize_speeds(built[WHIPPLE], [1.0], {"u_R0": -1.0})


def _json(*args):
    r = run_cli("linearize", *args, "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


@pytest.mark.parametrize("model", [pytest.param(WHIPPLE, id="Whipple"), pytest.param(LINEAR, id="WhippleLinear")])
def test_cli_json_shape_and_single_speed_equality(built, model):
    d = _json(str(built[model]), "--speeds", "0:10:2.5")
    assert d["speeds"] == [0.0, 2.5, 5.0, 7.5, 10.0]
    for key in ("model", "parameters", "states", "inputs", "outputs", "method", "speed_parameter", "points"):
        assert key in d, key
    assert len(d["points"]) == 5 and "A" not in d["points"][0]
    for point in (d["points"][1], d["points"][4]):
        single = _json(str(built[model]), "--speed", str(point["speed"]))
        assert point[d["speed_parameter"]] == single["parameters"][d["speed_parameter"]]
        ev = [complex(*e) for e in point["eigenvalues"]]
        assert _set_error(ev, [complex(*e) for e in single["eigenvalues"]]) <= TOL
        if model == WHIPPLE:
            lateral = [complex(*e) for e in point["steady_motion"]["eigenvalues"]]
            assert _close(lateral, [complex(*e) for e in single["steady_motion"]["eigenvalues"]]) <= TOL
            assert _close(point["steady_motion"]["A"], single["steady_motion"]["A"]) <= TOL
        else:
            assert "steady_motion" not in point
    if model == WHIPPLE:
        common = d["steady_motion"]
        assert common["states"] == ["phi", "delta", "u_phi", "u_delta"]
        assert {z["state"] for z in common["zero_eigenvalues"]} == {"theta", "u_R", "x", "y", "psi", "thetaR",
                                                                      "thetaF"}


def test_cli_matrices_and_text(built):
    d = _json(str(built[LINEAR]), "--speeds", "1,3", "--matrices")
    single = _json(str(built[LINEAR]), "--speed", "3")
    for name in "ABCD":
        assert _close(d["points"][1][name], single[name]) <= TOL
    r = run_cli("linearize", str(built[WHIPPLE]), "--speeds", "0:1:0.25")
    assert r.returncode == 0, r.stderr
    rows = [line.split() for line in r.stdout.splitlines() if line.split() and line.split()[0][0].isdigit()]
    assert [float(row[0]) for row in rows] == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert all(len(row) == 5 for row in rows)  # speed and the four lateral eigenvalues


@pytest.mark.parametrize("text, expected", [
    ("0:1:0.25", [0.0, 0.25, 0.5, 0.75, 1.0]), ("0:0.3:0.1", [0.0, 0.1, 0.2, 0.3]), ("1,2.5,7", [1.0, 2.5, 7.0]),
    ("3", [3.0]), ("0:0:1", [0.0]), ("0:10:0", "STEP > 0"), ("1:0:1", "B >= A"), ("nan", "finite"),
    ("1,,2", "expects"), ("1:2", "expects A:B:STEP"), ("", "expects"), ("0:100000:1", "at most 10000"),
    ("inf:1:1", "finite")], ids=lambda v: repr(v) if isinstance(v, str) else None)
def test_speed_grammar(text, expected):
    """The one --speeds parser (linearize and compare): inclusive ranges without rounding drift,
    lists, and one message per malformed text."""
    from cosim.bicycle import compare

    assert compare.parse_speeds is parse_speeds
    if isinstance(expected, list):
        assert parse_speeds(text) == expected
    else:
        with pytest.raises(ParameterError, match=re.escape(expected)):
            parse_speeds(text)


@pytest.mark.parametrize("args, message", [
    pytest.param(["--speeds", "0:-1:1"], "need STEP > 0 and B >= A", id="empty-range"),
    pytest.param(["--speeds", "0:10:0"], "need STEP > 0", id="zero-step"),
    pytest.param(["--speeds", "0:10:-0.5"], "need STEP > 0", id="negative-step"),
    pytest.param(["--speeds", "1,nan"], "must be finite", id="nan"),
    pytest.param(["--speeds", ""], "expects A:B:STEP or V1,V2", id="empty-text"),
    pytest.param(["--speeds=-1,2"], "forward speed must be >= 0", id="negative-speed"),
    pytest.param(["--speeds", "1,2", "--speed", "1"], "not both", id="speed-and-speeds"),
    pytest.param(["--speeds", "1", "--param", "u_R0=-1"], "u_R0", id="speed-parameter"),
    pytest.param(["--speed", "1", "--matrices"], "--matrices applies to a sweep", id="matrices-without-sweep"),
    pytest.param(["--speeds", "1", "--lock-hinge"], "no rider hinge", id="lock-without-hinge"),
])
def test_cli_bad_input(built, args, message):
    r = run_cli("linearize", str(built[WHIPPLE]), *args)
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cosim linearize: error:") and message in lines[0], r.stderr
    assert "Traceback" not in r.stderr
