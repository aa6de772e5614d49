"""`cosim linearize` and `cosim compare` on the nonlinear bicycles (Bicycle.Bicycles.Whipple,
WhippleRider) about upright straight running: `--speed V` sets the rear wheel rate u_R0 = -V/rR.

What is checked, with the tolerances used:

* `cosim linearize FMU --params SET --speed V --json`, v = 0 ... 10 m/s, for benchmark, astrom2005,
  astrom2005-riderless and a randomly perturbed benchmark file: the lateral eigenvalues of
  "steady_motion" equal cosim.analytic.whipple's (root_set_error, relative per root, <= 1e-9),
  the full A's eigenvalues are those four plus the seven named zeros (<= 1e-9), and the reported
  speed is V (relative 1e-14);
* `cosim compare MODEL --speeds 0:10:1` passes its default --tol 1e-9 for Whipple (default and
  astrom2005 parameters) and WhippleRider with the hinge locked (Meijaard with the upper body
  merged into the rear frame);
* the hinge lock is exact: the same A, B (relative 1e-12) for any hinge stiffness kU and
  damping cU, and the free-hinge reduction keeps every non-zero eigenvalue of the full A (1e-9);
* merged_rear_frame inverts cosim.analytic.parameters.split_upper_body (relative 1e-14);
* the rider's lean torque removes the right-half-plane zero of steer torque -> lateral position
  on the reduced, named coordinates;
* bad input (--speed on a model without forward speed, negative or NaN speeds, --params file
  without a key, --lock-hinge without a hinge, a start value off upright running): exit 2, one
  `cosim VERB: error:` line naming the problem, no traceback.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from cosim.analytic import whipple as W
from cosim.analytic.compare import root_set_error
from cosim.analytic.parameters import (load_parameters, load_upper_body, split_upper_body, upper_body_for,
                                      validate_parameters)
from cosim.analytic.twins import merged_rear_frame
from cosim.cli import main
from cosim.bicycle.linearize import ZERO_MODES, steady_motion
from cosim.fmu.linearize import linearize
from cosim.nonlinear.model import MODEL, RIDER_MODEL

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

SETS = ("benchmark", "astrom2005", "astrom2005-riderless")
PARAMS = Path(__file__).resolve().parents[1] / "cosim" / "params"
SPEEDS = [float(v) for v in range(11)]
ROOT_TOL = 1e-9  # relative per eigenvalue (cosim.analytic.compare.root_set_error)


@pytest.fixture(scope="module")
def fmu(fmus):
    return fmus[MODEL]


@pytest.fixture(scope="module")
def rider_fmu(fmus):
    return fmus[RIDER_MODEL]


def _perturbed_benchmark(seed: int = 20071955) -> dict[str, float]:
    """The benchmark with every value scaled by a factor in [0.9, 1.1] (seeded), wheel inertias
    scaled together (a thin disc has IRyy = 2 IRxx), redrawn until the set is physically valid."""
    rng = np.random.default_rng(seed)
    base = load_parameters("benchmark")
    for _ in range(100):
        p = {k: v * rng.uniform(0.9, 1.1) for k, v in base.items()}
        for wheel in ("R", "F"):
            p[f"I{wheel}yy"] = 2.0 * p[f"I{wheel}xx"]
        try:
            validate_parameters(p)
        except ValueError:
            continue
        return p
    raise AssertionError("no valid perturbed benchmark drawn")


def _parameter_file(tmp_path, name: str):
    """``name`` as a --params argument: a bundled name, or 'perturbed' written to a TOML file."""
    if name != "perturbed":
        return name, load_parameters(name)
    p = _perturbed_benchmark()
    path = tmp_path / "perturbed.toml"
    path.write_text("".join(f"{k} = {v!r}\n" for k, v in p.items()))
    return str(path), p


def _linearize_json(capsys, *argv) -> dict:
    status = main(["linearize", *argv, "--json"])
    out = capsys.readouterr()
    assert status == 0, out.err
    return json.loads(out.out)


def _complex(pairs) -> np.ndarray:
    return np.array([complex(re, im) for re, im in pairs])


# --------------------------------------------------------------------------- linearize

@pytest.mark.parametrize("name", [*SETS, "perturbed"], ids=[*SETS, "perturbed-benchmark-file"])
def test_linearize_speed_gives_meijaard_eigenvalues(fmu, capsys, tmp_path, name):
    params_arg, p = _parameter_file(tmp_path, name)
    worst_lateral = worst_full = worst_speed = 0.0
    for v in SPEEDS:
        d = _linearize_json(capsys, str(fmu), "--params", params_arg, "--speed", repr(v))
        assert d["parameters"]["u_R0"] == -v / p["rR"]
        s = d["steady_motion"]
        assert s["states"] == ["phi", "delta", "u_phi", "u_delta"] and s["hinge"] is None
        assert [z["state"] for z in s["zero_eigenvalues"]] == list(ZERO_MODES)
        expected = W.eigenvalues(p, v)
        worst_lateral = max(worst_lateral, root_set_error(_complex(s["eigenvalues"]), expected))
        worst_full = max(worst_full, root_set_error(_complex(d["eigenvalues"]),
                                                    np.concatenate([expected, np.zeros(7)])))
        worst_speed = max(worst_speed, abs(s["speed"] - v) / max(1.0, v))
    assert worst_lateral <= ROOT_TOL, worst_lateral
    assert worst_full <= ROOT_TOL, worst_full
    assert worst_speed <= 1e-14


@pytest.mark.parametrize("name, upper_body", [("benchmark", "benchmark"), ("astrom2005", "astrom2005")])
def test_rider_model_takes_a_set_with_the_upper_body_split_off(rider_fmu, capsys, name, upper_body):
    """--params SET on WhippleRider: the set's rear frame holds the whole rider, so the set's upper body
    (cosim/params/rider/SET.toml, else the benchmark's) is split off it; with the hinge locked the
    bicycle is the set's bicycle: Whipple's (Meijaard) eigenvalues, relative 1e-9 per root."""
    assert upper_body_for(name) == upper_body
    p = load_parameters(name)
    for v in (0.0, 3.0, 5.0, 8.0):
        d = _linearize_json(capsys, str(rider_fmu), "--params", name, "--speed", repr(v), "--lock-hinge")
        assert d["parameters"]["mB"] == pytest.approx(p["mB"] - load_upper_body(upper_body)["mU"], rel=1e-15)
        error = root_set_error(_complex(d["steady_motion"]["eigenvalues"]), W.eigenvalues(p, v))
        assert error <= ROOT_TOL, (v, error)


@pytest.mark.parametrize("name, problem", [("astrom2005-riderless", "mU"), ("astrom2005-file", "IBxx")])
def test_rider_model_refuses_a_set_that_cannot_carry_the_upper_body(rider_fmu, capsys, tmp_path, name, problem):
    """The riderless set's 12 kg rear frame, or the paper's rider set given as a file (which carries the
    benchmark's upper body, larger than that rear frame's roll inertia allows): one message naming the
    parameter, exit 2."""
    if name.endswith("-file"):
        path = tmp_path / "astrom2005.toml"
        path.write_text((PARAMS / "astrom2005.toml").read_text(encoding="utf-8"), encoding="utf-8")
        name = str(path)
    status = main(["linearize", str(rider_fmu), "--params", name, "--speed", "5"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and problem in err and "Traceback" not in err, err


def test_linearize_model_name_on_the_command_line(fmu):
    """The real command, model name resolved (built into COSIM_FMU_DIR), default parameters."""
    result = run_cli("linearize", MODEL, "--speed", "5", "--json")
    assert result.returncode == 0, result.stderr
    d = json.loads(result.stdout)
    assert d["parameters"]["u_R0"] == pytest.approx(-5.0 / 0.3, rel=1e-15)
    assert root_set_error(_complex(d["steady_motion"]["eigenvalues"]),
                          W.eigenvalues(load_parameters("benchmark"), 5.0)) <= ROOT_TOL
    text = run_cli("linearize", MODEL, "--speed", "5")
    assert text.returncode == 0, text.stderr
    assert "lateral eigenvalues:" in text.stdout and "theta: pitch" in text.stdout


def test_linearize_help_documents_the_reduction():
    result = run_cli("linearize", "--help")
    assert result.returncode == 0
    flat = " ".join(result.stdout.split())
    for phrase in ("u_R0 = -V/rR", "steady_motion", "zero_eigenvalues", "holonomic constraint",
                   "ignorable (cyclic)", "--lock-hinge"):
        assert phrase in flat, phrase


def test_off_upright_point_is_reported_not_reduced(fmu, capsys):
    d = _linearize_json(capsys, str(fmu), "--speed", "4", "--param", "phi0=0.1")
    assert d["steady_motion"] is None
    assert "not upright straight running" in d["steady_motion_note"] and "phi = 0.1" in d["steady_motion_note"]


# --------------------------------------------------------------------------- the rider's hinge

@pytest.mark.parametrize("hinge", [(300.0, 30.0), (0.0, 0.0), (1e4, 0.0)], ids=["default", "limp", "stiff"])
def test_locked_hinge_is_exact(rider_fmu, hinge):
    """Locked by its reaction torque: independent of kU, cU; defaults merge into the benchmark."""
    kU, cU = hinge
    p = load_parameters("benchmark")
    for v in (0.0, 3.0, 6.0, 9.0):
        lin = linearize(rider_fmu, {"u_R0": -v / p["rR"], "kU": kU, "cU": cU})
        locked = steady_motion(lin, lock_hinge=True)
        ref = steady_motion(linearize(rider_fmu, {"u_R0": -v / p["rR"]}), lock_hinge=True)
        assert locked.hinge == "locked" and locked.system.inputs == ["T_delta", "T_phi"]
        ours, theirs = locked.system, ref.system
        assert np.abs(ours.A - theirs.A).max() <= 1e-12 * np.abs(theirs.A).max()
        assert np.abs(ours.B - theirs.B).max() <= 1e-12 * np.abs(theirs.B).max()
        assert root_set_error(locked.eigenvalues, W.eigenvalues(p, v)) <= ROOT_TOL


def test_stiff_hinge_only_approximates_the_lock(rider_fmu):
    """The old approximation (a stiff spring) converges to the exact lock like 1/kU: the lock is
    not a huge stiffness in disguise."""
    p = load_parameters("benchmark")
    exact = W.eigenvalues(p, 5.0)
    errors = []
    for kU in (1e4, 1e6):
        lin = linearize(rider_fmu, {"u_R0": -5.0 / p["rR"], "kU": kU, "cU": 0.0})
        ev = np.linalg.eigvals(lin.system.A)
        ev = ev[(np.abs(ev) > 1e-6) & (np.abs(ev) < 30.0)]  # drop the zeros and the fast hinge mode
        errors.append(root_set_error(ev, exact))
    assert errors[0] > 1e-6 and errors[1] < errors[0] / 30.0


def test_free_hinge_reduction_keeps_the_spectrum(rider_fmu):
    p = load_parameters("benchmark")
    for v in (0.0, 2.0, 5.0, 8.0):
        lin = linearize(rider_fmu, {"u_R0": -v / p["rR"]})
        free = steady_motion(lin)
        assert free.hinge == "free" and free.system.states == ["phi", "delta", "beta", "u_phi", "u_delta", "u_beta"]
        assert root_set_error(lin.eigenvalues, free.all_eigenvalues()) <= ROOT_TOL


@pytest.mark.parametrize("name", ["benchmark", "astrom2005"])
def test_merged_rear_frame_inverts_the_split(name):
    p = load_parameters(name)
    merged = merged_rear_frame(split_upper_body(p, load_upper_body(upper_body_for(name))))
    assert max(abs(merged[k] - p[k]) / max(1.0, abs(p[k])) for k in p) <= 1e-14


@pytest.mark.parametrize("v", [2.0, 5.0], ids=lambda v: f"v={v:g}")
def test_lean_torque_removes_right_half_plane_zero(rider_fmu, v):
    """On the reduced, named coordinates (free hinge): steer torque -> y has a real zero in the
    right half plane; steer and lean torque together have no invariant zero there."""
    from cosim.nonlinear.rider import invariant_zeros

    sys = steady_motion(linearize(rider_fmu, {"u_R0": -v / 0.3})).to_statespace()
    iy = list(sys.output_labels).index("y")
    cols = [list(sys.input_labels).index(u) for u in ("T_delta", "T_beta")]
    C, D = sys.C[[iy]], sys.D[np.ix_([iy], cols)]
    steer = invariant_zeros(sys.A, sys.B[:, cols[:1]], C, D[:, :1])
    both = invariant_zeros(sys.A, sys.B[:, cols], C, D)
    assert np.any((steer.real > 0.5) & (np.abs(steer.imag) < 1e-9))
    assert not np.any(both.real > 0)


# --------------------------------------------------------------------------- compare

@pytest.mark.parametrize("model,extra", [(MODEL, []), (MODEL, ["--params", "astrom2005"]), (RIDER_MODEL, [])],
                         ids=["Whipple", "Whipple-astrom2005", "WhippleRider-locked"])
def test_compare_nonlinear_bicycle(fmus, model, extra):
    result = run_cli("compare", model, "--speeds", "0:10:1", *extra, "--json")
    assert result.returncode == 0, result.stderr
    d = json.loads(result.stdout)
    assert [c["speed"] for c in d["comparisons"]] == pytest.approx(SPEEDS, rel=1e-14, abs=1e-14)
    assert d["largest_error"] <= 1e-9
    assert all(len(c["eigenvalues"]) == 6 and len(c["pairs"]) == 12 for c in d["comparisons"])


# --------------------------------------------------------------------------- bad input

def _missing_key_file(tmp_path):
    text = "".join(f"{k} = {v!r}\n" for k, v in load_parameters("benchmark").items() if k != "IBxx")
    (tmp_path / "missing.toml").write_text(text)
    return str(tmp_path / "missing.toml")


# "FMU:NAME" is replaced by the FMU file of model NAME (linearize reads it without the Modelica source).
BAD = {
    "no-forward-speed": (["linearize", "FMU:Bicycle.Control.PD", "--speed", "5"], "has no forward speed"),
    "model-without-forward-speed": (["linearize", "Bicycle.Control.PD", "--speed", "5"], "has no forward speed"),
    "negative-speed": (["linearize", f"FMU:{MODEL}", "--speed", "-1"], "forward speed must be >= 0"),
    "model-negative-speed": (["linearize", MODEL, "--speed", "-0.5"], "forward speed must be >= 0"),
    "nan-speed": (["linearize", f"FMU:{MODEL}", "--speed", "nan"], "must be finite"),
    "compare-negative-speed": (["compare", MODEL, "--speeds=-1:1:1"], "forward speed must be >= 0"),
    "compare-nan-speed": (["compare", MODEL, "--speeds", "nan,1"], "must be finite"),
    "missing-key": (["linearize", f"FMU:{MODEL}", "--params", "MISSING", "--speed", "3"], "IBxx"),
    "lock-without-hinge": (["linearize", f"FMU:{MODEL}", "--speed", "3", "--lock-hinge"], "no rider hinge"),
    "compare-off-upright": (["compare", MODEL, "--speeds", "3", "--param", "phi0=0.1"], "phi0"),
}


@pytest.mark.parametrize("case", list(BAD), ids=list(BAD))
def test_bad_input_is_one_message(fmus, tmp_path, case):
    argv, fragment = BAD[case]
    argv = [_missing_key_file(tmp_path) if a == "MISSING" else str(fmus[a[4:]]) if a.startswith("FMU:") else a
            for a in argv]
    result = run_cli(*argv)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    errors = [line for line in result.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1 and errors[0].startswith(f"cosim {argv[0]}: error:"), result.stderr
    assert fragment in errors[0]
    assert result.stdout == ""
