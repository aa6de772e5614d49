"""The co-simulation test matrix (`cosim matrix`, package cosim.matrix).

Tolerances (stated per test):
* predicted max Re of the uncontrolled Whipple bicycle vs cosim.analytic.whipple.eigenvalues:
  relative 1e-10; the crowned-roller pole vs (27): relative 1e-12;
* predicted closed loop with a Pade delay (master lags off) vs python-control's feedback of the
  same transfer functions: max Re within 1e-8 (absolute, 1/s);
* the stable-interval check's predicted boundaries vs cosim.analytic.whipple.self_stable_interval:
  1e-6 m/s;
* growth rate fitted to an exact exponential: relative 1e-9; classification of synthetic signals
  uses the default observed margin 0.01 1/s; co-simulated growth rates vs predicted max Re:
  0.03 1/s + 5 %;
* resumed / Dask / reused-FMU runs vs an uninterrupted local run: records identical (bit for bit)
  except the wall time and worker pid.
"""
from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import toml_value
from reference import SELF_STABILIZING_DEFAULTS as PAPER
from cosim.matrix import classify, expr
from cosim.matrix.spec import SpecError, load_spec, spec_from_dict
from cosim.matrix.store import ResultStore, read_records

# the quick run (-m 'not slow') leaves this module out: it runs co-simulation matrices with worker processes
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
VOLATILE = ("elapsed", "worker")


def _strip(records):
    return {r["key"]: {k: v for k, v in r.items() if k not in VOLATILE} for r in records}


def _whipple_study(name="bench", speeds=(3.0, 5.0, 7.0), **extra):
    return {"name": name, "observe": "bike.phi", "connections": [],
            "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                    "parameters": {"v": "=v", "phi0": 0.01}}},
            "axes": {"v": list(speeds)}, **extra}


def _rider_study(name="rider", speeds=(1.0, 3.0), taus=(0.05, 0.1, 0.6)):
    """The bicycle (1) steered by a delayed rider with the best gain: Python blocks, Python loop."""
    return {"name": name, "observe": "bike.phi",
            "connections": ["bike.phi -> rider.phi", "rider.delta -> delay.u", "delay.y -> bike.delta"],
            "components": {"bike": {"model": "Bicycle.Bicycles.InvertedPendulum", "parameters": {"V": "=V"},
                                    "initial": {"frame.phi": 0.01}},
                           "rider": {"python": "SteerAngleFeedback", "parameters": {"k2": 1.0}},
                           "delay": {"python": "TransportDelay", "parameters": {"tau": "=tau"}}},
            "tune": {"rider.k2": {"min": 0.01, "max": 1000.0, "points": 32}},
            "axes": {"V": list(speeds), "tau": list(taus)}}


def _write_spec(path: Path, studies: list[dict], matrix: dict | None = None) -> Path:
    """A spec file (TOML written from dicts through json-compatible inline tables)."""
    lines = ["[matrix]"]
    for k, v in {"name": path.stem, **(matrix or {})}.items():
        lines.append(f"{k} = {toml_value(v)}")
    for study in studies:
        lines.append("[[study]]")
        for k, v in study.items():
            lines.append(f"{json.dumps(k)} = {toml_value(v)}")
    path.write_text("\n".join(lines) + "\n")
    return path


# --------------------------------------------------------------------------- expressions

@pytest.mark.parametrize("text, variables, value", [
    ("p * tau", {"p": 3.0, "tau": 0.1}, 0.30000000000000004),
    ("sqrt(90*9.8*(1.0 - R)/95.5)", {"R": 0.0}, math.sqrt(90 * 9.8 / 95.5)),
    ("1 if case == 3 else 0", {"case": 3}, 1),
    ("ptau > 2 and V < 5", {"ptau": 2.4, "V": 3}, True),
    ("-U", {"U": 4.0}, -4.0),
    ("0.2 < ptau <= 2", {"ptau": 2.0}, True),
], ids=["product", "roller-pole", "conditional", "boolean", "negation", "chained-compare"])
def test_expression_values(text, variables, value):
    assert expr.evaluate(text, variables) == value


@pytest.mark.parametrize("text", ["__import__('os')", "p.real", "[1, 2]", "lambda: 1", "open('x')", "q + 1"],
                         ids=["import", "attribute", "list", "lambda", "open", "unknown-name"])
def test_expression_refused(text):
    with pytest.raises(expr.ExpressionError, match="expression"):
        expr.evaluate(text, {"p": 1.0})


def test_resolve_nested_values():
    assert expr.resolve({"a": "=x + 1", "b": ["=x", 2], "c": "plain"}, {"x": 1}) == {"a": 2, "b": [1, 2], "c": "plain"}


# --------------------------------------------------------------------------- specs

def test_axes_product_and_explicit_cases():
    spec = spec_from_dict({"study": [{**_rider_study(speeds=(1.0, 2.0), taus=(0.1, 0.2, 0.3)),
                                      "cases": [{"V": 9.0, "tau": 0.5}]}]})
    cases = spec.cases()
    assert [c.values for c in cases[:3]] == [{"V": 1.0, "tau": 0.1}, {"V": 1.0, "tau": 0.2}, {"V": 1.0, "tau": 0.3}]
    assert cases[-1].values == {"V": 9.0, "tau": 0.5} and len(cases) == 7
    assert len({c.key for c in cases}) == 7
    assert cases[0].system["components"]["delay"]["parameters"]["tau"] == 0.1
    assert cases[0].system["system"]["fall"] == {"signal": "bike.phi", "limit": 1.0}
    # the key is a content hash: the same case has the same key in another expansion
    assert spec_from_dict({"study": [_rider_study(speeds=(1.0,), taus=(0.1,))]}).cases()[0].key == cases[0].key


def test_parameter_set_and_variables():
    spec = spec_from_dict({"study": [{**_whipple_study(speeds=(4.0,)), "variables": {"double": "2*v"}}]})
    case = spec.cases()[0]
    params = case.system["components"]["bike"]["parameters"]
    assert params["v"] == 4.0 and params["mB"] == 85.0 and case.variables["double"] == 8.0


@pytest.mark.parametrize("study, message", [
    ({**_whipple_study(), "observe": "nobody.phi"}, "observe"),
    ({**_whipple_study(), "bogus": 1}, "unknown keys: bogus"),
    ({**_whipple_study(), "axes": {}}, "neither"),
    ({**_whipple_study(), "axes": {"v": {"from": 1}}}, "axis 'v'"),
    ({**_whipple_study(), "checks": [{"kind": "vibes"}]}, "check kind"),
    ({**_whipple_study(), "tune": {"bike": {}}}, "tune"),
    ({**_whipple_study(), "components": {"bike": {"model": "X", "python": "PD"}}}, "exactly one"),
    ({**_whipple_study(), "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear",
                                                  "parameters": {"v": "=speed"}}}}, "unknown name 'speed'"),
], ids=["bad-observe", "unknown-key", "no-cases", "bad-axis", "bad-check", "bad-tune", "two-kinds", "bad-expression"])
def test_spec_errors(study, message):
    with pytest.raises(SpecError, match=message):
        spec_from_dict({"study": [study]}).cases()


def test_bundled_spec_loads():
    spec = load_spec("paper")
    names = [s.name for s in spec.studies]
    assert names == ["astrom2005-self-stable", "benchmark-self-stable", "rear-steered-p-control", "delayed-rider",
                     "crowned-rollers", "rollers-delayed-rider"]
    assert len(spec.cases()) > 200


# --------------------------------------------------------------------------- classification

def _signal(kind: str):
    t = np.linspace(0.0, 10.0, 1001)
    if kind == "decaying-weave":
        return t, 0.01 * np.exp(-0.3 * t) * np.sin(5 * t), "completed"
    if kind == "growing-weave":
        return t, 0.01 * np.exp(0.2 * t) * np.sin(5 * t), "completed"
    if kind == "undamped":
        return t, 0.01 * np.cos(3 * t), "completed"
    if kind == "slow-capsize":
        return t, 1e-3 * np.exp(0.05 * t), "completed"
    if kind == "decayed-to-zero":
        return t, np.where(t < 2, 0.01 * (1 - t / 2), 0.0), "completed"
    if kind == "never-excited":
        return t, np.zeros_like(t), "completed"
    if kind == "fell":
        return t[:300], 1e-3 * np.exp(2.5 * t[:300]), "fell"
    raise KeyError(kind)


@pytest.mark.parametrize("kind, expected", [
    ("decaying-weave", "stable"), ("growing-weave", "unstable"), ("undamped", "marginal"),
    ("slow-capsize", "unstable"), ("decayed-to-zero", "stable"), ("never-excited", "unexcited"), ("fell", "fell"),
], ids=lambda v: v if isinstance(v, str) else None)
def test_observed_class(kind, expected):
    t, x, status = _signal(kind)
    assert classify.observe(t, x, status, 0.01)["class"] == expected


@pytest.mark.parametrize("rate", [-0.7, -0.05, 0.05, 1.3], ids=["fast-decay", "slow-decay", "slow-growth", "fast-growth"])
def test_growth_rate_of_exponential(rate):
    t = np.linspace(0.0, 10.0, 1001)
    assert classify.growth_rate(t, 0.01 * np.exp(rate * t)) == pytest.approx(rate, rel=1e-9)


def test_settling_time_and_max_roll():
    t, x, status = _signal("decaying-weave")
    obs = classify.observe(t, x, status, 0.01)
    assert obs["max_roll"] == pytest.approx(np.abs(x).max())
    last = t[np.flatnonzero(np.abs(x) > 0.02 * np.abs(x).max())[-1] + 1]
    assert obs["settling_time"] == pytest.approx(last)


@pytest.mark.parametrize("predicted, observed, expected", [
    ("stable", "stable", "agree"), ("stable", "unstable", "disagree"), ("stable", "fell", "disagree"),
    ("unstable", "fell", "agree"), ("unstable", "diverged", "agree"), ("unstable", "stable", "disagree"),
    ("marginal", "stable", "marginal"), ("marginal", "fell", "marginal"), ("stable", "marginal", "disagree"),
    ("stable", "unexcited", "failed"), (None, "stable", "failed"),
], ids=lambda v: str(v))
def test_agreement_table(predicted, observed, expected):
    assert classify.agreement(predicted, observed) == expected


# --------------------------------------------------------------------------- predictions

@pytest.mark.parametrize("parameter_set, v", [("benchmark", 3.0), ("benchmark", 5.0), ("astrom2005", 8.0),
                                              ("astrom2005", 12.0)], ids=lambda v: str(v))
def test_uncontrolled_whipple_prediction(parameter_set, v):
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import eigenvalues
    from cosim.matrix.predict import predict_case

    study = _whipple_study(speeds=(v,))
    study["components"]["bike"]["parameter_set"] = parameter_set
    case = spec_from_dict({"study": [study]}).cases()[0]
    _, pred = predict_case(case, {})
    expected = eigenvalues(load_parameters(parameter_set), v).real.max()
    assert pred["states"] == 4  # heading and lateral position do not influence phi
    assert pred["max_re"] == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("R", [0.0, 0.5, 0.9], ids=lambda r: f"R={r}")
def test_crowned_roller_pole(R):
    from cosim.matrix.predict import predict_case

    study = {"name": "rollers", "observe": "bike.phi", "connections": [], "axes": {"R": [R]},
             "components": {"bike": {"model": "Bicycle.Bicycles.CrownedRoller", "parameters": {"R": "=R"}}}}
    _, pred = predict_case(spec_from_dict({"study": [study]}).cases()[0], {})
    m, g, h, J = (PAPER[k] for k in ("m", "g", "h", "J"))
    assert pred["max_re"] == pytest.approx(math.sqrt(m * g * (h - R) / J), rel=1e-12)


@pytest.mark.parametrize("V, tau, k2", [(2.0, 0.1, 5.0), (4.0, 0.05, 3.0), (1.0, 0.3, 10.0)], ids=lambda v: str(v))
def test_delayed_loop_matches_python_control(V, tau, k2):
    import control

    from cosim.matrix.predict import predict_case

    study = _rider_study(speeds=(V,), taus=(tau,))
    del study["tune"]
    study["components"]["rider"]["parameters"]["k2"] = k2
    spec = spec_from_dict({"matrix": {"master_lag": False, "pade_order": 6}, "study": [study]})
    _, pred = predict_case(spec.cases()[0], {})
    m, h, b, J, D, g = (PAPER[k] for k in ("m", "h", "b", "J", "D", "g"))
    G = control.tf([V * D / b, m * V * V * h / b], [J, 0, -m * g * h])      # (4)
    P = control.tf(*control.pade(tau, 6))
    loop = control.feedback(G, k2 * P)
    assert pred["max_re"] == pytest.approx(max(loop.poles().real), abs=1e-8)


def test_master_lag_is_modelled():
    """With the master's lags (Jacobi: one step for the static rider, h/2 hold at the bicycle) the
    predicted loop equals the same loop with the delay lengthened by 1.5 h (to Pade accuracy)."""
    from cosim.matrix.predict import predict_case

    study = _rider_study(speeds=(2.0,), taus=(0.2,))
    del study["tune"]
    study["components"]["rider"]["parameters"]["k2"] = 2.5
    with_lag = predict_case(spec_from_dict({"study": [study]}).cases()[0], {})[1]["max_re"]
    study["axes"]["tau"] = [0.2 + 1.5 * 0.01]
    longer = predict_case(spec_from_dict({"matrix": {"master_lag": False}, "study": [study]}).cases()[0], {})[1]
    assert with_lag == pytest.approx(longer["max_re"], abs=2e-3)


def test_tuning_finds_the_best_gain():
    from cosim.matrix.predict import closed_loop, predict_case

    case = spec_from_dict({"study": [_rider_study(speeds=(3.0,), taus=(0.1,))]}).cases()[0]
    system, pred = predict_case(case, {})
    k = pred["tuned"]["rider.k2"]
    for factor in (0.9, 1.1):
        other = json.loads(json.dumps(system))
        other["components"]["rider"]["parameters"]["k2"] = k * factor
        assert closed_loop(other, "bike.phi", {}, case.settings).max_re > pred["max_re"]


# --------------------------------------------------------------------------- results file

def test_store_drops_a_torn_tail_and_skips_nothing(tmp_path):
    with ResultStore(tmp_path, resume=False) as store:
        for k in range(3):
            store.append({"key": f"k{k}", "value": float(k), "bad": math.nan})
    with open(tmp_path / "results.jsonl", "ab") as f:
        f.write(b'{"key": "k3", "val')  # a write cut short
    with ResultStore(tmp_path, resume=True) as store:
        assert sorted(store.records) == ["k0", "k1", "k2"] and store.torn > 0
        assert store.records["k1"]["bad"] is None
        store.append({"key": "k3", "value": 3.0})
    records, valid = read_records(tmp_path / "results.jsonl")
    assert [r["key"] for r in records] == ["k0", "k1", "k2", "k3"]
    assert valid == (tmp_path / "results.jsonl").stat().st_size


def test_store_without_resume_starts_afresh(tmp_path):
    with ResultStore(tmp_path, resume=False) as store:
        store.append({"key": "a"})
    with ResultStore(tmp_path, resume=False) as store:
        assert store.records == {}
    assert read_records(tmp_path / "results.jsonl")[0] == []


# --------------------------------------------------------------------------- running matrices

@pytest.fixture(scope="module")
def small_spec(tmp_path_factory) -> Path:
    """FMU-only cases (C stepping loop) and delayed-rider cases (Python loop): 3 + 6 cases."""
    d = tmp_path_factory.mktemp("spec")
    return _write_spec(d / "small.toml", [_whipple_study(), _rider_study()])


@pytest.fixture(scope="module")
def small_run(fmus, small_spec, tmp_path_factory):
    from cosim.matrix.runner import run_matrix

    out = tmp_path_factory.mktemp("small-run")
    return run_matrix(small_spec, out, workers=2, progress=False)


def test_small_matrix_agrees_and_reports(small_run):
    result = small_run
    assert result.exit_code == 0, [c.details for c in result.checks if not c.passed]
    assert result.counts["cases"] == 9 and result.counts["failed"] == 0 and result.counts["disagree"] == 0
    for name in ("report.md", "report.html", "summary.json", "bench.png", "rider.png", "results.jsonl"):
        assert (result.directory / name).is_file(), name
    by_label = {(r["study"], r["label"]): r for r in result.records}
    # benchmark bicycle: unstable at 3 m/s (falls), self-stable at 5 m/s, unstable (capsize) at 7 m/s
    assert by_label[("bench", "v=3")]["observed"]["class"] == "fell"
    assert by_label[("bench", "v=5")]["observed"]["class"] == "stable"
    assert by_label[("bench", "v=7")]["observed"]["class"] == "unstable"
    # the rider copes with tau = 0.05 s but not with 0.6 s
    assert by_label[("rider", "V=1, tau=0.05")]["agreement"] == "agree"
    assert by_label[("rider", "V=1, tau=0.6")]["prediction"]["class"] == "unstable"
    md = (result.directory / "report.md").read_text()
    assert "**PASS**" in md and "| case |" in md


def test_observed_growth_equals_prediction(small_run):
    """Decisive cases that did not fall: the fitted growth rate is the predicted max Re within
    0.03 1/s + 5 % (the window maxima of a fast-decaying oscillation lag its envelope a little)."""
    for r in small_run.records:
        pred, obs = r["prediction"], r["observed"]
        if pred["class"] != "marginal" and obs["class"] in ("stable", "unstable") and obs["growth_rate"] is not None:
            assert abs(obs["growth_rate"] - pred["max_re"]) <= 0.03 + 0.05 * abs(pred["max_re"]), r["label"]


def test_reused_fmus_give_identical_results(small_run, fmus):
    """A case run in a fresh worker and again after other cases (FMU instance reset) gives the
    same record as in the matrix."""
    from cosim.matrix.spec import load_spec
    from cosim.matrix.worker import FMUCache, run_case

    spec = load_spec(small_run.spec.path)
    cases = spec.cases()
    paths = {k: str(v) for k, v in fmus.items()}
    expected = _strip(small_run.records)
    cache = FMUCache()
    try:
        for case in cases + cases[::-1]:
            rec = run_case(case.to_dict(), cache, paths)
            assert _strip([rec])[case.key] == expected[case.key], case.label
    finally:
        cache.close()


CRASH_PLUGIN = '''
import os, signal, time
from cosim.cosimulation.controllers import Proportional


class Misbehaving(Proportional):
    """T = -k phi; 'crash' = 1 segfaults the process at t = 0.5 s (as a broken FMU would), 'hang' = 1 sleeps."""

    def __init__(self, name, k=1.0, crash=0.0, hang=0.0):
        super().__init__(name, k)
        self.crash, self.hang = crash, hang

    def step(self, t, h):
        if t >= 0.5 and self.crash:
            os.kill(os.getpid(), signal.SIGSEGV)
        if t >= 0.5 and self.hang:
            time.sleep(3600)


'''


def _misbehaving_spec(directory: Path, flags: list[dict]) -> Path:
    (directory / "misbehaving.py").write_text(CRASH_PLUGIN)
    study = {"name": "crash", "observe": "bike.phi", "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_phi"],
             "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                     "parameters": {"v": 5.0, "phi0": 0.01}},
                            "rider": {"python": "Misbehaving", "parameters": {"k": "=k", "crash": "=crash",
                                                                               "hang": "=hang"}}},
             "cases": flags}
    return _write_spec(directory / "crash.toml", [study], {"imports": ["misbehaving.py"], "timeout": 20.0})


@pytest.mark.parametrize("workers", [1, 2], ids=["1-worker", "2-workers"])
def test_crashing_case_fails_alone(fmus, tmp_path, workers):
    from cosim.matrix.runner import run_matrix

    flags = [{"k": k, "crash": float(k == 3.0), "hang": 0.0} for k in (1.0, 2.0, 3.0, 4.0, 5.0)]
    result = run_matrix(_misbehaving_spec(tmp_path, flags), tmp_path / "out", workers=workers, progress=False)
    failed = [r for r in result.records if r["agreement"] == "failed"]
    assert len(result.records) == 5 and len(failed) == 1
    assert failed[0]["values"]["k"] == 3.0 and "SIGSEGV" in failed[0]["error"]
    assert all(r["agreement"] == "agree" for r in result.records if r is not failed[0])
    assert result.exit_code == 1
    md = (tmp_path / "out" / "report.md").read_text()
    table = md[md.index("| case |"):]
    assert table.splitlines()[2].startswith("| k=3, crash=1, hang=0 |")  # failures first
    assert "SIGSEGV" in table


def test_hanging_case_times_out(fmus, tmp_path):
    from cosim.matrix.runner import run_matrix

    flags = [{"k": 1.0, "crash": 0.0, "hang": 1.0}, {"k": 2.0, "crash": 0.0, "hang": 0.0}]
    spec = _misbehaving_spec(tmp_path, flags)
    spec.write_text(spec.read_text().replace("timeout = 20.0", "timeout = 3.0"))
    result = run_matrix(spec, tmp_path / "out", workers=1, progress=False)
    assert [r["agreement"] for r in result.records] == ["failed", "agree"]
    assert "timeout" in result.records[0]["error"]


def _matrix_cli(*args, **kw) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen([sys.executable, "-m", "cosim", "matrix", *args], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


@pytest.mark.slow
def test_killed_matrix_resumes_to_the_same_results(fmus, tmp_path):
    spec = _write_spec(tmp_path / "resume.toml", [_rider_study(speeds=(1.0, 2.0, 3.0, 4.0, 5.0),
                                                               taus=(0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8))])
    n = 40
    killed = tmp_path / "killed"
    proc = _matrix_cli(str(spec), "-o", str(killed), "--workers", "1", "--no-progress")
    results = killed / "results.jsonl"
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline:
        if results.exists() and len(read_records(results)[0]) >= 3:
            break
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    partial = read_records(results)[0]
    assert 3 <= len(partial) < n, "the matrix must be killed mid-way"
    resumed = _matrix_cli(str(spec), "-o", str(killed), "--workers", "2", "--resume", "--no-progress")
    out, err = resumed.communicate(timeout=600)
    assert resumed.returncode == 0, out + err
    assert f"{n} cases ({n - len(partial)} run, {len(partial)} resumed)" in out
    full = tmp_path / "full"
    straight = _matrix_cli(str(spec), "-o", str(full), "--workers", "2", "--no-progress")
    out2, err2 = straight.communicate(timeout=600)
    assert straight.returncode == 0, out2 + err2
    after, _ = read_records(results)
    keys = [r["key"] for r in after]
    assert len(keys) == n and len(set(keys)) == n  # no loss, no duplicates
    assert _strip(after) == _strip(read_records(full / "results.jsonl")[0])


def test_dask_gives_the_same_results_as_the_local_pool(small_run, small_spec, tmp_path):
    pytest.importorskip("distributed")
    from distributed import LocalCluster

    from cosim.matrix.runner import run_matrix

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        result = run_matrix(small_spec, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert result.exit_code == 0
    assert _strip(result.records) == _strip(small_run.records)


def test_cli_parser_and_errors(tmp_path):
    import argparse

    from cosim.matrix import cli

    parser = argparse.ArgumentParser()
    cli.add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["matrix", "spec.toml", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1",
                              "-o", "out", "--resume"])
    assert (args.command, args.spec, args.workers, args.scheduler, args.output, args.resume) == \
        ("matrix", "spec.toml", 2, "tcp://127.0.0.1:1", "out", True)
    assert args.func is cli.run
    bad = tmp_path / "bad.toml"
    bad.write_text("[matrix]\nname = 'x'\n")
    proc = _matrix_cli(str(bad), "-o", str(tmp_path / "o"))
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and "no [[study]] tables" in err


def test_bundled_paper_spec_is_green(fmus, tmp_path):
    """The paper's claims, on 2 workers (about 20 s)."""
    from cosim.matrix.runner import run_matrix

    result = run_matrix("paper", tmp_path / "paper", workers=2, progress=False)
    failing = [f"{c.study}: {c.title}: {c.details}" for c in result.checks if not c.passed]
    assert result.exit_code == 0, failing
    interval = next(c for c in result.checks if c.study == "astrom2005-self-stable" and c.kind == "stable-interval")
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import self_stable_interval

    lo, hi = self_stable_interval(load_parameters("astrom2005"))
    assert interval.data["predicted"] == pytest.approx((lo, hi), abs=1e-6)
    assert round(lo, 4) == 5.9548 and round(hi, 4) == 10.3682
    assert result.counts["marginal"] <= 15 and result.counts["agree"] >= 220
    for study in result.spec.studies:
        assert (tmp_path / "paper" / f"{study.name}.png").is_file()
