"""`cosim matrix` whatever the input: earlier results, failed cases, unbounded work,
an unreachable scheduler, the verdict of slow modes, orphaned workers, outputs, bad specs.

Tolerances (stated per test): exponents identified by the modal fit vs the exponents of
synthetic signals: absolute 1e-6 1/s; no absolute wall-clock assertion anywhere (subprocesses
get generous timeouts, waits are bounded loops).
"""
from __future__ import annotations

import contextlib
import json
import math
import os
import resource
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, bound_by_permissions, run_cli, toml_value
from cosim.matrix import classify, expr
from cosim.matrix.spec import MAX_CASES, SpecError, load_spec, spec_from_dict
from cosim.matrix.store import read_records

# the quick run (-m 'not slow') leaves this module out: it runs co-simulation matrices with worker processes
pytestmark = pytest.mark.slow

FAST = {"stop": 2.0}


def _write_spec(path: Path, studies: list[dict], matrix: dict | None = None) -> Path:
    lines = ["[matrix]"] + [f"{k} = {toml_value(v)}" for k, v in {"name": path.stem, **(matrix or {})}.items()]
    for study in studies:
        lines.append("[[study]]")
        lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in study.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def _whipple(name="bench", speeds=(3.0, 5.0, 7.0), **extra) -> dict:
    return {"name": name, "observe": "bike.phi", "connections": [],
            "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                    "parameters": {"v": "=v", "phi0": 0.01}}},
            "axes": {"v": list(speeds)}, **extra}


def _matrix(*args: str) -> subprocess.CompletedProcess:
    result = run_cli("matrix", *args, "--no-progress")
    assert "Traceback" not in result.stderr, result.stderr
    return result


def _snapshot(folder: Path) -> dict:
    return {p.relative_to(folder): (p.stat().st_mtime_ns, p.read_bytes()) for p in folder.rglob("*") if p.is_file()}


# --------------------------------------------------------------------------- 1. earlier results

def test_run_into_folder_with_results_without_resume_or_force_is_refused(fmus, tmp_path):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    out = tmp_path / "out"
    first = _matrix(str(spec), "-o", str(out), "--workers", "1")
    assert first.returncode == 0, first.stderr
    before = _snapshot(out)
    again = _matrix(str(spec), "-o", str(out), "--workers", "1")
    assert again.returncode == 2
    lines = again.stderr.strip().splitlines()
    assert len(lines) == 1 and str(out) in lines[0] and "--resume" in lines[0] and "--force" in lines[0], lines
    assert _snapshot(out) == before  # nothing changed
    forced = _matrix(str(spec), "-o", str(out), "--workers", "1", "--force")
    assert forced.returncode == 0 and "3 cases (3 run, 0 resumed)" in forced.stdout, forced.stdout + forced.stderr
    assert len(read_records(out / "results.jsonl")[0]) == 3
    both = _matrix(str(spec), "-o", str(out), "--resume", "--force")
    assert both.returncode == 2 and "not allowed with" in both.stderr


# --------------------------------------------------------------------------- 2. failed cases

CRASH_ONCE = '''
import os, signal
from cosim.cosimulation.controllers import Proportional


class CrashWhileMarked(Proportional):
    """T = -k phi; segfaults the worker at t = 0.5 s while the file 'marker' exists (a flaky FMU)."""

    def __init__(self, name, k=1.0, marker=""):
        super().__init__(name, k)
        self.marker = marker

    def step(self, t, h):
        if t >= 0.5 and self.marker and os.path.exists(self.marker):
            os.kill(os.getpid(), signal.SIGSEGV)


'''


def test_resume_retries_cases_failed_by_a_crashed_worker_unless_keep_failed(fmus, tmp_path):
    (tmp_path / "crash_once.py").write_text(CRASH_ONCE)
    marker = tmp_path / "marker"
    marker.write_text("crash")
    study = {"name": "flaky", "observe": "bike.phi", "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_phi"],
             "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                     "parameters": {"v": 5.0, "phi0": 0.01}},
                            "rider": {"python": "CrashWhileMarked",
                                      "parameters": {"k": "=k", "marker": "=m"}}},
             "cases": [{"k": 1.0, "m": ""}, {"k": 2.0, "m": str(marker)}, {"k": 3.0, "m": ""}]}
    spec = _write_spec(tmp_path / "flaky.toml", [study], {**FAST, "imports": ["crash_once.py"], "timeout": 60.0})
    out = tmp_path / "out"
    first = _matrix(str(spec), "-o", str(out), "--workers", "1")
    assert first.returncode == 1 and "1 failed" in first.stdout, first.stdout + first.stderr
    failed = [r for r in read_records(out / "results.jsonl")[0] if r["agreement"] == "failed"]
    assert len(failed) == 1 and "SIGSEGV" in failed[0]["error"]
    marker.unlink()  # the cause is gone: a retry succeeds
    kept = _matrix(str(spec), "-o", str(out), "--workers", "1", "--resume", "--keep-failed")
    assert kept.returncode == 1 and "(0 run, 3 resumed)" in kept.stdout and "1 failed" in kept.stdout, kept.stdout
    retried = _matrix(str(spec), "-o", str(out), "--workers", "1", "--resume")
    assert retried.returncode == 0, retried.stdout + retried.stderr
    assert "(1 run, 2 resumed, 1 failed run again)" in retried.stdout and "0 failed" in retried.stdout
    records = read_records(out / "results.jsonl")[0]
    assert len(records) == 3 and len({r["key"] for r in records}) == 3  # one line per case
    assert all(r["agreement"] == "agree" for r in records)


def test_resume_keeps_the_records_after_a_corrupted_line(tmp_path):
    """A line edited or corrupted by hand used to end the read: every later record was cut off."""
    from cosim.matrix.store import ResultStore

    with ResultStore(tmp_path, resume=False) as store:
        for k in range(4):
            store.append({"key": f"k{k}", "agreement": "failed" if k == 3 else "agree"})
    lines = (tmp_path / "results.jsonl").read_bytes().splitlines(keepends=True)
    lines[1] = b'{"key": "k1", "agree\n'                      # corrupted in the middle
    (tmp_path / "results.jsonl").write_bytes(b"".join(lines) + b'[1, 2]\n{"key": "k9", "ag')  # not a record; torn
    with ResultStore(tmp_path, resume=True) as store:
        assert sorted(store.records) == ["k0", "k2", "k3"] and store.torn > 0
    assert [r["key"] for r in read_records(tmp_path / "results.jsonl")[0]] == ["k0", "k2", "k3"]
    with ResultStore(tmp_path, resume=True, retry_failed=True) as store:
        assert sorted(store.records) == ["k0", "k2"] and store.retried == {"k3"}
    assert (tmp_path / "results.jsonl").read_bytes().count(b"\n") == 2  # one line per kept case


def test_record_cut_short_by_the_file_system_is_cut_off(tmp_path):
    """A write that stops in the middle of a line (a file size limit reached: the kernel writes
    what fits, then refuses with EFBIG) leaves no torn line: the part written is cut off, the
    error names the file and what is kept."""
    from cosim.errors import ResultNotWritten
    from cosim.matrix.store import ResultStore

    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    with ResultStore(tmp_path, resume=False) as store:
        store.append({"key": "k0", "agreement": "agree"})
        size = (tmp_path / "results.jsonl").stat().st_size
        previous = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of the signal
        resource.setrlimit(resource.RLIMIT_FSIZE, (size + 10, hard))
        try:
            with pytest.raises(ResultNotWritten, match="results.jsonl': File too large; the case recorded before is kept"):
                store.append({"key": "k1", "agreement": "agree", "note": "x" * 100})
        finally:
            resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
            signal.signal(signal.SIGXFSZ, previous)
    assert (tmp_path / "results.jsonl").read_bytes() == b'{"agreement": "agree", "key": "k0"}\n'


def test_keep_failed_without_resume_is_refused(tmp_path):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    result = _matrix(str(spec), "-o", str(tmp_path / "out"), "--keep-failed")
    assert result.returncode == 2 and "--keep-failed applies only with --resume" in result.stderr
    assert not (tmp_path / "out").exists()


# --------------------------------------------------------------------------- 3. unbounded work

def _limited_memory() -> None:
    """2 GB of address space: a regression (expanding 10^9 cases) fails instead of eating the machine."""
    resource.setrlimit(resource.RLIMIT_AS, (2 * 1024 ** 3, 2 * 1024 ** 3))


@pytest.mark.parametrize("axes, sizes", [
    ({"v": {"from": 0.0, "to": 1e9, "step": 1.0}}, "axis 'v' has 1000000001 values"),
    ({"v": {"linspace": [0.0, 1.0, 1e12]}}, "axis 'v' has 1000000000000 values"),
    ({"v": {"from": 0.0, "to": 999.0, "step": 1.0}, "w": {"from": 0.0, "to": 999.0, "step": 1.0}},
     "axes v (1000) x w (1000) = 1000000 cases"),
], ids=["from-to-step-1e9", "linspace-1e12", "product-1e6"])
def test_spec_beyond_case_limit_is_refused_before_expanding(tmp_path, axes, sizes):
    spec = _write_spec(tmp_path / "huge.toml", [_whipple(axes=axes)], FAST)
    result = subprocess.run([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(tmp_path / "out")],
                            capture_output=True, text=True, cwd=ROOT, timeout=300, preexec_fn=_limited_memory)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert str(spec) in result.stderr and sizes in result.stderr, result.stderr
    assert f"limit of {MAX_CASES}" in result.stderr and "--max-cases" in result.stderr
    assert not (tmp_path / "out").exists()


def _grid(name="grid", speeds=(3.0, 5.0, 7.0), rolls=(0.005, 0.01, 0.02, 0.03), **extra) -> dict:
    """A study over two axes: the speed and the initial roll angle."""
    study = _whipple(name, speeds=speeds, **extra)
    study["components"]["bike"]["parameters"]["phi0"] = "=phi0"
    study["axes"]["phi0"] = list(rolls)
    return study


def _axes_study(sizes: tuple, explicit: int = 0, name: str = "s") -> dict:
    """A study whose axes a0, a1, ... take the values 0 .. size-1, each case a distinct initial roll."""
    axes = {f"a{k}": list(range(n)) for k, n in enumerate(sizes)}
    phi0 = "=0.01 + " + " + ".join(f"a{k} * {10.0 ** (-3 - 4 * k):g}" for k in range(len(sizes)))
    cases = [{**{a: 0 for a in axes}, "phi0": 0.05 + 0.001 * j} for j in range(explicit)]
    variables = {"phi0": phi0} if explicit else {}
    return {"name": name, "observe": "bike.phi", "connections": [], "variables": variables,
            "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                    "parameters": {"v": 5.0, "phi0": "=phi0" if explicit else phi0}}},
            "axes": axes, **({"cases": cases} if cases else {})}


@pytest.mark.parametrize("studies, n, covers", [
    ([((3, 4), 0)], 4, True),
    ([((3, 4), 0)], 7, True),
    ([((3, 4), 0)], 2, False),
    ([((6, 6, 6), 0)], 6, True),
    ([((6, 6, 6), 0)], 50, True),
    ([((6, 6, 6), 0)], 215, True),
    ([((3, 4), 2)], 6, True),
    ([((3, 4), 0), ((2,), 0), ((5, 2), 1)], 12, True),
    ([((3, 4), 0), ((2,), 0), ((5, 2), 1)], 3, False),
    ([((40,), 0)], 7, False),
], ids=["grid-4-of-12", "grid-7-of-12", "grid-2-of-12", "cube-6-of-216", "cube-50-of-216", "cube-215-of-216",
        "explicit-6-of-14", "three-studies-12-of-25", "three-studies-3-of-25", "line-7-of-40"])
def test_sample_is_n_distinct_cases_of_the_spec_covering_every_axis_value(studies, n, covers):
    data = {"matrix": {"name": "sampled", **FAST},
            "study": [_axes_study(sizes, explicit, f"s{k}") for k, (sizes, explicit) in enumerate(studies)]}
    spec = spec_from_dict(data, sample=True, max_cases=n)
    every = {c.key: c for c in spec_from_dict(data).cases()}
    sample = spec.cases(n)
    assert len(sample) == min(n, len(every)) and len({c.key for c in sample}) == len(sample)
    assert all(c.key in every and every[c.key].index == c.index for c in sample)  # cases of the spec, in place
    assert [c.key for c in spec_from_dict(data, sample=True, max_cases=n).cases(n)] == [c.key for c in sample]
    assert spec.sample_covers_axes(n) is covers
    if covers:
        for study in spec.studies:
            grid = [c for c in sample if c.study == study.name and c.index < study.count - len(study.explicit)]
            for axis, values in study.axes.items():
                assert {c.values[axis] for c in grid} == set(values), (study.name, axis)
        assert {c.study for c in sample} == {s.name for s in spec.studies}


@pytest.mark.parametrize("n", [400, 3], ids=["every-value-400-of-160000", "3-of-160000"])
def test_sample_of_a_spec_beyond_the_case_limit_expands_only_the_sample(n):
    sizes = (400, 400)
    assert sizes[0] * sizes[1] > MAX_CASES
    spec = spec_from_dict({"matrix": {"name": "huge", **FAST}, "study": [_axes_study(sizes)]}, max_cases=n,
                          sample=True)
    cases = spec.cases(n)
    assert len(cases) == n == len({c.key for c in cases}) and spec.count == sizes[0] * sizes[1]
    for axis, size in zip(("a0", "a1"), sizes):
        assert len({c.values[axis] for c in cases}) == min(n, size), axis


@pytest.mark.parametrize("n, runs", [(5, 5), (12, 12), (40, 12)], ids=["sample-5-of-12", "all-12-of-12", "all-above"])
def test_max_cases_runs_at_most_n_cases(tmp_path, n, runs):
    spec = _write_spec(tmp_path / "grid.toml", [_grid()], FAST)
    out = tmp_path / "out"
    result = _matrix(str(spec), "-o", str(out), "--max-cases", str(n))
    assert result.returncode == 0, result.stderr
    records = read_records(out / "results.jsonl")[0]
    assert len(records) == runs == len({r["key"] for r in records})
    points = [(r["values"]["v"], r["values"]["phi0"]) for r in records]
    assert len(set(points)) == runs
    assert {v for v, _ in points} == {3.0, 5.0, 7.0} and {p for _, p in points} == {0.005, 0.01, 0.02, 0.03}
    notes = [line for line in result.stderr.splitlines() if "cases (--max-cases" in line]
    summary = json.loads((out / "summary.json").read_text())
    report = (out / "report.md").read_text()
    if runs < 12:
        assert notes == [f"cosim matrix: running {runs} of 12 cases (--max-cases {n}): a stratified sample (Latin "
                         "hypercube) across the axes, the same every run; every value of every axis appears"], notes
        assert summary["sample"]["cases"] == runs and summary["sample"]["of"] == 12
        assert f"A sample: running {runs} of 12 cases (--max-cases {n}): a stratified sample" in report
    else:
        assert notes == [] and summary["sample"] is None and "A sample" not in report


def test_max_cases_samples_every_study(tmp_path):
    spec = _write_spec(tmp_path / "small.toml", [_whipple(), _whipple("other", speeds=(4.0, 6.0))], FAST)
    result = _matrix(str(spec), "-o", str(tmp_path / "out"), "--max-cases", "4")
    assert result.returncode == 0, result.stderr
    assert "running 4 of 5 cases (--max-cases 4)" in result.stderr, result.stderr
    assert "of each of the 2 studies" in result.stderr and "too few for every value" in result.stderr
    records = read_records(tmp_path / "out" / "results.jsonl")[0]
    assert len(records) == 4 and {r["study"] for r in records} == {"bench", "other"}
    assert len(load_spec(spec, max_cases=5).cases()) == 5


@pytest.mark.parametrize("text, message", [
    ("9**9**9", "the power 9**387420489 exceeds 4096 bits"),
    ("10**10**10", "exceeds 4096 bits"),
    ("2**100000", "exceeds 4096 bits"),
    ("(2**4000)*(2**4000)", "an integer beyond 4096 bits"),
    ("'a' * 10**9", "a string longer than 10000 characters"),
    ("round(5, -10**9)", "ndigits"),
    ("-" * 500 + "1", "nested more than 100 levels"),
    ("1" + "+1" * 600, "longer than 1000 characters"),
    ("(-8)**0.5", "complex"),
    ("10.0**400", "overflows a float"),
], ids=["9**9**9", "10**10**10", "2**100000", "big-product", "string-repetition", "round-ndigits", "deep-nesting",
        "long", "complex", "float-overflow"])
def test_costly_expression_is_refused(text, message):
    """Each in its own process with a timeout: a regression would hang, not pass."""
    code = ("import sys; from cosim.matrix import expr\n"
            "try:\n    expr.evaluate(sys.argv[1], {})\nexcept expr.ExpressionError as exc:\n    print(exc)\n"
            "else:\n    print('accepted')\n")
    result = subprocess.run([sys.executable, "-c", code, text], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr
    assert result.stdout.startswith("expression '") and message in result.stdout, result.stdout


def test_costly_expression_in_spec_names_file_and_expression(tmp_path):
    study = _whipple()
    study["components"]["bike"]["parameters"]["v"] = "=9**9**9"
    spec = _write_spec(tmp_path / "costly.toml", [study], FAST)
    result = subprocess.run([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(tmp_path / "out")],
                            capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    line = result.stderr.strip()
    assert "\n" not in line and str(spec) in line and "parameters 'v'" in line and "'9**9**9'" in line, line


@pytest.mark.parametrize("text, value", [("2**10", 1024), ("2.0**5000 > 1 if False else 3", 3), ("3**-2", 1 / 9),
                                         ("round(3.14159, 2)", 3.14), ("2**4095 > 0", True)],
                         ids=["small-power", "short-circuit", "negative-exponent", "round", "largest-power"])
def test_reasonable_expressions_still_evaluate(text, value):
    assert expr.evaluate(text, {}) == pytest.approx(value)


# --------------------------------------------------------------------------- 4. scheduler

def _closed_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # closed again when the socket is


def test_unreachable_scheduler_is_one_line_naming_the_address(tmp_path):
    pytest.importorskip("distributed")
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    address = f"tcp://127.0.0.1:{_closed_port()}"
    result = subprocess.run([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(tmp_path / "out"),
                             "--scheduler", address], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and address in lines[0] and "cannot reach the Dask scheduler" in lines[0], lines
    assert "within 5 s" in lines[0]  # the connection timeout (pool.SCHEDULER_TIMEOUT), not 60 s
    assert not (tmp_path / "out" / "results.jsonl").exists()


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:notaport", "ftp://127.0.0.1:8786", "tcp://127.0.0.1"],
                         ids=["port-not-a-number", "unknown-scheme", "no-port"])
def test_malformed_scheduler_address_is_one_line(tmp_path, address):
    pytest.importorskip("distributed")
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    result = subprocess.run([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(tmp_path / "out"),
                             "--scheduler", address], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and repr(address) in lines[0] and "is not a scheduler address" in lines[0], lines


# --------------------------------------------------------------------------- 5. slow modes

def _rear_steered(stop: float | None) -> dict:
    study = {"name": "rear", "observe": "bike.phi",
             "connections": ["bike.phi -> rider.phi", "rider.delta -> bike.delta"],
             "components": {"bike": {"model": "Bicycle.Bicycles.RearSteered",
                                     "parameters": {"V": "=U", "phi0": 0.01}},
                            "rider": {"python": "SteerAngleFeedback", "parameters": {"k2": "=k2"}}},
             "axes": {"U": [10.0], "k2": [0.1]}}
    if stop is not None:
        study["stop"] = stop
    return study


def test_verdict_of_slow_unstable_mode_does_not_depend_on_stop_time(fmus):
    """The paper's rear-steered bicycle at 10 m/s with k2 = 0.1: a slow unstable oscillation
    (0.31 +- 0.29j 1/s, a 22 s period). With an 8 s run the old envelope comparison fell in a zero
    crossing and said 'stable'; the modal fit sees the same mode at 8 s, 10 s (the default) and 20 s."""
    from cosim.matrix.worker import FMUCache, run_case

    paths = {k: str(v) for k, v in fmus.items()}
    cache = FMUCache()
    try:
        records = {stop: run_case(spec_from_dict({"study": [_rear_steered(stop)]}).cases()[0].to_dict(), cache, paths)
                   for stop in (8.0, None, 20.0)}
    finally:
        cache.close()
    for stop, rec in records.items():
        assert rec["prediction"]["class"] == "unstable", stop
        assert rec["observed"]["class"] in classify.UNSTABLE and rec["agreement"] == "agree", (stop, rec["observed"])
        if rec["observed"]["class"] != "fell":
            assert rec["observed"]["growth_method"] == "modal"
            assert rec["observed"]["growth_rate"] == pytest.approx(rec["prediction"]["max_re"], abs=1e-3), stop


@pytest.mark.parametrize("stop", [4.0, 8.0, 10.0, 30.0], ids=lambda s: f"stop={s:g}")
@pytest.mark.parametrize("kind, expected, rate", [
    ("slow-oscillation", "unstable", 0.308),            # rear-steered bicycle, 22 s period
    ("capsize-under-weave", "unstable", 0.03),          # slow capsize hidden by a large decaying weave
    ("weave-over-slow-decay", "stable", -0.05),         # slowly decaying mode under a faster transient
    ("undamped", "marginal", 0.0),                      # crowned rollers with R > h
], ids=lambda v: v if isinstance(v, str) else None)
def test_observed_class_of_slow_modes_does_not_depend_on_stop_time(kind, expected, rate, stop):
    t = np.round(np.arange(0.0, stop + 1e-9, 0.01), 10)
    if kind == "slow-oscillation":
        x = 0.01 * np.exp(0.308 * t) * np.cos(0.29 * t + 0.3)
    elif kind == "capsize-under-weave":
        x = 0.01 * np.exp(-0.5 * t) * np.sin(5 * t) + 1e-4 * np.exp(0.03 * t)
    elif kind == "weave-over-slow-decay":
        x = 0.02 * np.exp(-1.0 * t) * np.cos(6 * t) + 1e-3 * np.exp(-0.05 * t)
    else:
        x = 0.01 * np.cos(3 * t)
    obs = classify.observe(t, x, "completed", 0.01)
    assert obs["class"] == expected and obs["growth_method"] == "modal"
    assert obs["growth_rate"] == pytest.approx(rate, abs=1e-6)


@pytest.mark.parametrize("small", [True, False], ids=["small-pencil-first", "n/3-pencil"])
@pytest.mark.parametrize("v", [2.0, 4.6, 5.0, 6.0, 8.0],
                         ids=["2m/s-unstable", "4.6m/s-stable", "5m/s-stable", "6m/s-near-capsize", "8m/s-capsize"])
def test_modal_fit_recovers_the_exact_growth_rate(v, small):
    """The free roll response of the linear benchmark bicycle, sampled exactly (the matrix
    exponential of A(v) of cosim.analytic, an initial roll of 0.01 rad, 10 s at 0.01 s as the matrix
    runs): the modes the fit finds are eigenvalues of A(v), and its rate is the largest real part of A(v)'s eigenvalues
    to 1e-8 1/s -- also at 6 m/s, 4e-3 1/s from the capsize speed, where a slow mode hides under
    the weave (with 400 samples the fit missed a mode at 6 and 8 m/s: error 3.6e-8 1/s)."""
    from scipy.linalg import expm

    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import state_matrices

    A, _ = state_matrices(load_parameters("benchmark"), v)
    step = expm(A * 0.01)
    states = [np.array([0.01, 0.0, 0.0, 0.0])]
    for _ in range(1000):
        states.append(step @ states[-1])
    t = np.round(np.arange(1001) * 0.01, 10)
    fit = classify.modal_fit(t, np.array(states)[:, 0], small=small)
    exact = np.linalg.eigvals(A)
    assert fit is not None
    # every mode found is one of A(v) (modes whose contribution is below 1e-6 of the peak, such as
    # the fast decaying ones under a growing weave at 2 m/s, are left out by design)
    assert all(np.min(np.abs(exact - mode)) <= 1e-6 for mode in fit.modes), (fit.modes, exact)
    assert fit.rate == pytest.approx(float(np.max(exact.real)), abs=1e-8)


@pytest.mark.parametrize("oscillations", [5, 6, 9], ids=["10-modes", "12-modes", "18-modes"])
def test_signal_with_more_modes_than_the_small_pencil_takes_gets_the_full_one(oscillations):
    """A sum of up to 18 modes: the small pencil (SMALL_ORDER = 10 modes at most) passes what it
    cannot resolve to the n/3 pencil, so the fit finds the same modes and rate either way."""
    t = np.round(np.arange(1001) * 0.01, 10)
    rates = -0.1 - 0.15 * np.arange(oscillations)
    freqs = 1.0 + 0.9 * np.arange(oscillations)
    x = sum(np.exp(r * t) * np.cos(w * t + 0.3 * k) for k, (r, w) in enumerate(zip(rates, freqs)))
    small = classify.modal_fit(t, x, small=True)
    full = classify.modal_fit(t, x, small=False)
    assert small is not None and full is not None
    assert small.order == full.order == 2 * oscillations
    # the same modes bit for bit exactly when both went to the n/3 pencil
    assert (2 * oscillations > classify.SMALL_ORDER) == (small.modes == full.modes)
    assert small.rate == pytest.approx(-0.1, abs=1e-8) and full.rate == pytest.approx(-0.1, abs=1e-8)


def test_a_run_that_fell_is_fitted_with_the_full_pencil():
    """The reported rate of a fall comes from the n/3 pencil (see classify.SMALL_PENCIL)."""
    t = np.round(np.arange(301) * 0.01, 10)
    x = 0.01 * np.exp(1.5 * t) * np.cos(4 * t) + 0.002 * np.exp(-3 * t)
    full, small = classify.modal_fit(t, x, small=False), classify.modal_fit(t, x, small=True)
    assert full.rate != small.rate  # equal to rounding only: which one was used is visible
    assert classify.observe(t, x, "fell", 0.01)["growth_rate"] == full.rate
    assert classify.observe(t, x, "completed", 0.01)["growth_rate"] == small.rate


@pytest.mark.parametrize("kind", ["clipped", "noisy", "switched-on", "rectified"])
def test_signal_that_is_not_a_sum_of_modes_falls_back_to_the_envelope(kind):
    t = np.linspace(0.0, 10.0, 1001)
    if kind == "clipped":
        x = np.clip(0.01 * np.exp(0.2 * t) * np.sin(5 * t), -0.02, 0.02)
    elif kind == "noisy":
        x = 0.01 * np.exp(-0.3 * t) * np.sin(5 * t) + 1e-4 * np.random.default_rng(1).standard_normal(t.size)
    elif kind == "switched-on":  # a pulse response that starts inside the fitted windows
        x = np.where(t < 7.0, 0.0, 0.01 * np.exp(0.2 * (t - 7.0)) * np.sin(5 * (t - 7.0)))
    else:
        x = np.abs(0.01 * np.exp(-0.2 * t) * np.sin(5 * t))
    assert classify.modal_fit(t, x) is None
    assert classify.observe(t, x, "completed", 0.01)["growth_method"] == "envelope"


def test_periodic_signal_is_marginal_whatever_the_method():
    """A sawtooth of period 1 s: sampled at a step that divides the period it *is* a finite sum of
    undamped modes (one per harmonic the samples resolve: 25 at the fit's 0.04 s), which the modal
    fit may identify (rate 0) or refuse (more than MODAL_MAX_ORDER modes at a finer step); either
    way the observation is marginal, neither growing nor decaying."""
    t = np.linspace(0.0, 10.0, 1001)
    x = (t % 1.0) - 0.5
    obs = classify.observe(t, x, "completed", 0.01)
    assert obs["class"] == "marginal"
    assert abs(obs["growth_rate"]) < 1e-3


# --------------------------------------------------------------------------- 6. orphans

def _descendants_alive(procs) -> list:
    import psutil

    alive = []
    for p in procs:
        try:
            if p.status() != psutil.STATUS_ZOMBIE:
                alive.append(p)
        except psutil.NoSuchProcess:
            pass
    return alive


def _wait_gone(procs, seconds: float = 60.0) -> list:
    deadline = time.monotonic() + seconds
    while (alive := _descendants_alive(procs)) and time.monotonic() < deadline:
        time.sleep(0.1)
    return alive


HANG = '''
import os, time
from pathlib import Path
from cosim.cosimulation.controllers import Proportional


class Hang(Proportional):
    """T = -k phi; at t = 0.5 s announces itself in the folder 'flag' and sleeps (a hung FMU)."""

    def __init__(self, name, k=1.0, flag=""):
        super().__init__(name, k)
        self.flag = flag

    def step(self, t, h):
        if t >= 0.5:
            (Path(self.flag) / str(os.getpid())).write_text("running")
            time.sleep(3600)


'''


def test_killed_matrix_leaves_no_worker_behind(fmus, tmp_path):
    """kill -9 of `cosim matrix --workers 2` while both workers are busy in a case (that would
    run for an hour): every process it started is gone within a bounded wait."""
    psutil = pytest.importorskip("psutil")
    (tmp_path / "hang.py").write_text(HANG)
    flags = tmp_path / "running"
    flags.mkdir()
    study = {"name": "hang", "observe": "bike.phi", "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_phi"],
             "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                     "parameters": {"v": 5.0, "phi0": 0.01}},
                            "rider": {"python": "Hang", "parameters": {"k": "=k", "flag": str(flags)}}},
             "axes": {"k": [1.0, 2.0, 3.0, 4.0]}}
    spec = _write_spec(tmp_path / "hang.toml", [study], {**FAST, "imports": ["hang.py"], "timeout": 3600.0})
    proc = subprocess.Popen([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(tmp_path / "out"),
                             "--workers", "2", "--no-progress"], cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + 300
        while len(list(flags.iterdir())) < 2 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.05)
        busy = {int(p.name) for p in flags.iterdir()}
        everyone = parent.children(recursive=True)
        assert len(busy) == 2 and busy <= {p.pid for p in everyone}, "both workers must be running a case"
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        assert _wait_gone(everyone) == [], "processes outlived the killed matrix"
    finally:
        if proc.poll() is None:
            proc.kill()
        for p in _descendants_alive(locals().get("everyone", [])):  # never leave them behind, even on failure
            p.kill()


POOL_PARENT = """
import functools, os, time
from concurrent.futures import ProcessPoolExecutor
from cosim.processes import die_with_parent

init = functools.partial(die_with_parent, pdeathsig={pdeathsig})
pool = ProcessPoolExecutor(2, initializer=init, initargs=(os.getpid(),))
futures = [pool.submit(time.sleep, 600) for _ in range(2)]
while len(pool._processes) < 2:
    time.sleep(0.05)
print(" ".join(str(p) for p in pool._processes), flush=True)
time.sleep(600)
"""


@pytest.mark.parametrize("pdeathsig", [True, False], ids=["pdeathsig-and-watchdog", "watchdog-only"])
def test_pool_workers_die_with_their_parent(pdeathsig):
    """cosim.processes.die_with_parent as a ProcessPoolExecutor initializer (as `cosim build -j`
    can use it): kill -9 of the parent ends its pool workers, by the kernel's parent-death signal
    or by the watchdog thread alone."""
    psutil = pytest.importorskip("psutil")
    proc = subprocess.Popen([sys.executable, "-c", POOL_PARENT.format(pdeathsig=pdeathsig)], cwd=ROOT,
                            stdout=subprocess.PIPE, text=True)
    try:
        pids = [int(p) for p in proc.stdout.readline().split()]
        assert len(pids) == 2
        workers = [psutil.Process(p) for p in pids]
        assert _descendants_alive(workers) == workers
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        assert _wait_gone(workers) == []
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.stdout.close()


def test_worker_whose_parent_died_before_it_started_exits():
    """The race at start: the parent is gone before die_with_parent runs (passed its pid)."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    result = subprocess.run([sys.executable, "-c", f"from cosim.processes import die_with_parent\n"
                             f"die_with_parent({dead.pid})\nimport time; time.sleep(60)\nprint('alive')"],
                            capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == -signal.SIGKILL and "alive" not in result.stdout


# --------------------------------------------------------------------------- 7. outputs

@pytest.mark.parametrize("where", ["file", "under-file"])
def test_unusable_output_folder_is_refused_before_any_work(tmp_path, where):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    blocker = tmp_path / "blocker"
    blocker.write_text("not a folder")
    out = blocker if where == "file" else blocker / "sub"
    result = _matrix(str(spec), "-o", str(out), "--fmu-dir", str(tmp_path / "fmus"))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "is a file" in lines[0] and str(blocker) in lines[0], lines
    assert blocker.read_text() == "not a folder"
    assert not (tmp_path / "fmus").exists()  # nothing was built


def test_fmu_folder_that_is_a_file_is_refused_before_any_work(tmp_path):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    blocker = tmp_path / "fmus"
    blocker.write_text("not a folder")
    result = _matrix(str(spec), "-o", str(tmp_path / "out"), "--fmu-dir", str(blocker))
    assert result.returncode == 2 and "FMU folder" in result.stderr and str(blocker) in result.stderr, result.stderr
    assert not (tmp_path / "out").exists()


def test_read_only_output_folder_is_refused_before_any_work(tmp_path):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:  # in a child that the folder's mode binds, as root too
        result = bound_by_permissions(lambda: _matrix(str(spec), "-o", str(locked / "out")), locked)
        assert result.returncode == 2 and "not writable" in result.stderr and str(locked) in result.stderr
        assert list(locked.iterdir()) == []
    finally:
        locked.chmod(0o700)


def test_report_files_appear_only_when_complete(fmus, tmp_path, monkeypatch):
    """A failure while a heat map is written leaves neither a partial PNG under its final name
    nor a temporary file; report.md, summary.json and matrix.json come through cosim.outputs."""
    import matplotlib.figure

    from cosim.errors import OutputError
    from cosim.matrix.runner import run_matrix

    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    real = matplotlib.figure.Figure.savefig

    def broken(self, fname, **kw):
        Path(fname).write_bytes(b"\x89PNG half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", broken)
    with pytest.raises(OutputError, match="No space left on device"):
        run_matrix(spec, tmp_path / "out", workers=1, progress=False)
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert "bench.png" not in names and not [n for n in names if "partial" in n], names
    assert len(read_records(tmp_path / "out" / "results.jsonl")[0]) == 3  # the results are kept
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", real)
    result = run_matrix(spec, tmp_path / "out", workers=1, progress=False, resume=True)
    assert result.exit_code == 0 and (tmp_path / "out" / "bench.png").read_bytes().startswith(b"\x89PNG\r\n")
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["cases"] == 3


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_disk_full_while_recording_keeps_the_recorded_cases(fmus, tmp_path, monkeypatch):
    """ENOSPC on the results file was an internal error (exit 70) naming no file. After the first
    record the results file's descriptor is pointed at /dev/full (the kernel's ENOSPC, as on a
    full disk): one line naming the file and what is kept, exit 4, the file ends with its last
    complete record; --resume then runs the other cases, one record per case."""
    from conftest import cli_in_process
    from cosim.matrix.store import ResultStore

    real = ResultStore.append_line

    def disk_full_after_the_first(self, key, line):
        real(self, key, line)
        full = os.open("/dev/full", os.O_WRONLY)
        os.dup2(full, self._fd)
        os.close(full)

    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    out = tmp_path / "out"
    argv = ["matrix", str(spec), "-o", str(out), "--workers", "1", "--no-progress"]
    monkeypatch.setattr(ResultStore, "append_line", disk_full_after_the_first)
    status, stdout, err = cli_in_process(argv, tmp_path)
    assert status == 4, stdout + err
    assert err.splitlines() == [f"cosim matrix: error: cannot write results file '{out}/results.jsonl': No space "
                                "left on device; the case recorded before is kept (--resume runs the rest)"]
    assert len(read_records(out / "results.jsonl")[0]) == 1 and not (out / ".cosim-lock").exists()
    monkeypatch.undo()
    status, stdout, err = cli_in_process([*argv, "--resume"], tmp_path)
    assert status == 0 and "3 cases (2 run, 1 resumed)" in stdout, stdout + err
    records = read_records(out / "results.jsonl")[0]
    assert len(records) == 3 and len({r["key"] for r in records}) == 3


# --------------------------------------------------------------------------- 8. bad input

def _study(**changes) -> dict:
    study = _whipple()
    for key, value in changes.items():
        if value is _DELETE:
            study.pop(key, None)
        else:
            study[key] = value
    return study


_DELETE = object()
BIKE = {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
        "parameters": {"v": "=v", "phi0": 0.01}}

BAD_SPECS = {
    # id: (document, words the message must contain)
    "matrix-not-table": ({"matrix": 5, "study": [_study()]}, "[matrix]: expected a table"),
    "name-number": ({"matrix": {"name": 5}, "study": [_study()]}, "[matrix] name: expected a string"),
    "name-path": ({"matrix": {"name": "../x"}, "study": [_study()]}, "may only contain"),
    "imports-number": ({"matrix": {"imports": 5}, "study": [_study()]}, "imports: expected an array of strings"),
    "imports-missing": ({"matrix": {"imports": ["nope.py"]}, "study": [_study()]}, "no such file"),
    "stop-inf": ({"matrix": {"stop": math.inf}, "study": [_study()]}, "'stop' must be finite"),
    "stop-string": ({"matrix": {"stop": "10"}, "study": [_study()]}, "'stop' must be a number"),
    "step-beyond-stop": ({"matrix": {"stop": 1.0, "step": 2.0}, "study": [_study()]}, "longer than stop"),
    "timeout-zero": ({"matrix": {"timeout": 0.0}, "study": [_study()]}, "'timeout' must be"),
    "extend-huge": ({"matrix": {"extend": 1e9}, "study": [_study()]}, "'extend' must be"),
    "pade-order": ({"matrix": {"pade_order": 0}, "study": [_study()]}, "'pade_order' must be"),
    "algorithm": ({"matrix": {"algorithm": "magic"}, "study": [_study()]}, "'algorithm' must be one of"),
    "margin-nan": ({"matrix": {"margin": math.nan}, "study": [_study()]}, "'margin' must be"),
    "study-number": ({"study": 5}, "no [[study]] tables"),
    "study-entry-number": ({"study": [5]}, "study 1: expected a [[study]] table"),
    "study-name-path": ({"study": [_study(name="../../etc/x")]}, "may only contain"),
    "observe-number": ({"study": [_study(observe=5)]}, "observe: expected a string"),
    "connections-string": ({"study": [_study(connections="a -> b")]}, "connections: expected an array of strings"),
    "components-number": ({"study": [_study(components=5)]}, "components: expected tables"),
    "component-number": ({"study": [_study(components={"bike": 5})]}, "component 'bike': expected a table"),
    "parameters-number": ({"study": [_study(components={"bike": {**BIKE, "parameters": 5}})]},
                          "component 'bike' parameters: expected a table"),
    "parameter-list": ({"study": [_study(components={"bike": {**BIKE, "parameters": {"v": [1]}}})]},
                       "parameters 'v': expected a number, boolean or string"),
    "parameter-set-missing": ({"study": [_study(components={"bike": {**BIKE, "parameter_set": "nope"}})]},
                              "parameter_set"),
    "initial-string": ({"study": [_study(components={"bike": {**BIKE, "initial": {"frame.phi": "x"}}})]},
                       "initial 'frame.phi': expected a finite number"),
    "axes-number": ({"study": [_study(axes=5)]}, "axes: expected a table"),
    "axis-string": ({"study": [_study(axes={"v": "fast"})]}, "axis 'v' must be a list or a table"),
    "axis-linspace-short": ({"study": [_study(axes={"v": {"linspace": [1, 2]}})]},
                            "linspace: expected an array [a, b, n]"),
    "axis-linspace-fraction": ({"study": [_study(axes={"v": {"linspace": [1, 2, 2.5]}})]}, "whole number"),
    "axis-step-string": ({"study": [_study(axes={"v": {"from": 1, "to": 2, "step": "x"}})]}, "step: expected a number"),
    "axis-value-table": ({"study": [_study(axes={"v": [1.0, {"a": 1}]})]}, "axis 'v' value 2"),
    "cases-number": ({"study": [_study(cases=5)]}, "cases: expected an array"),
    "case-unknown-axis": ({"study": [_study(cases=[{"speed": 3.0}])]}, "unknown axis names speed"),
    "variables-number": ({"study": [_study(variables=5)]}, "variables: expected a table"),
    "variable-expression": ({"study": [_study(variables={"w": "v +* 2"})]}, "variable 'w'"),
    "tune-number": ({"study": [_study(tune=5)]}, "tune: expected a table"),
    "tune-points": ({"study": [_study(tune={"bike.v": {"points": 10 ** 9}})]}, "points: must be 3 to"),
    "tune-scale": ({"study": [_study(tune={"bike.v": {"scale": "cubic"}})]}, "scale: must be 'log' or 'linear'"),
    "checks-table": ({"study": [_study(checks={"kind": "region"})]}, "checks: expected an array"),
    "check-unknown-axis": ({"study": [_study(checks=[{"kind": "stable-interval", "axis": "speed",
                                                     "expected": [4.0, 6.0]}])]}, "axis 'speed' is not an axis"),
    "check-expected": ({"study": [_study(checks=[{"kind": "stable-interval", "axis": "v", "expected": 5}])]},
                       "expected: expected an array [low, high]"),
    "check-expect": ({"study": [_study(checks=[{"kind": "region", "expect": "wobbly"}])]}, "expect must be one of"),
    "check-where-name": ({"study": [_study(checks=[{"kind": "region", "expect": "stable", "where": "speed > 2"}])]},
                         "unknown name(s) speed"),
    "check-where-costly": ({"study": [_study(checks=[{"kind": "region", "expect": "stable",
                                                      "where": "-" * 150 + "v"}])]}, "nested more than 100"),
    "check-unknown-key": ({"study": [_study(checks=[{"kind": "region", "expect": "stable", "axis": "v"}])]},
                          "unknown keys axis"),
    "plot-unknown-axis": ({"study": [_study(plots=[{"x": "speed"}])]}, "'speed' is not a variable"),
    "system-number": ({"study": [_study(system=5)]}, "system: expected a table"),
    "system-stop-string": ({"study": [_study(system={"stop": "long"})]}, "[system] stop"),
}


@pytest.mark.parametrize("document, message", list(BAD_SPECS.values()), ids=list(BAD_SPECS))
def test_bad_spec_is_one_message_naming_file_and_key(tmp_path, document, message):
    path = tmp_path / "bad.toml"
    with pytest.raises(SpecError) as info:
        spec_from_dict(document, path).cases()
    text = str(info.value)
    assert text.startswith(str(path)) and message in text and "\n" not in text, text


def _writetoml_value(path: Path, document: dict) -> Path:
    """A TOML document from nested dicts (inline tables; inf/nan as TOML floats)."""
    def value(v):
        if isinstance(v, float) and not math.isfinite(v):
            return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
        if isinstance(v, dict):
            return "{" + ", ".join(f"{json.dumps(k)} = {value(x)}" for k, x in v.items()) + "}"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return toml_value(v)
    lines = []
    for key, v in document.items():
        lines.append(f"{json.dumps(key)} = {value(v)}")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("name", ["stop-inf", "initial-string", "case-unknown-axis", "check-unknown-axis",
                                  "study-name-path"])
def test_bad_spec_file_is_one_message_on_the_command_line(tmp_path, name):
    document, message = BAD_SPECS[name]
    path = _writetoml_value(tmp_path / "bad.toml", document)
    result = _matrix(str(path), "-o", str(tmp_path / "out"))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and message in lines[0], lines
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, message", [
    (("--workers", "0"), "--workers: must be at least 1, got 0"),
    (("--workers", "-2"), "--workers: must be at least 1, got -2"),
    (("--workers", "two"), "--workers: expected a whole number"),
    (("--max-cases", "0"), "--max-cases: must be at least 1, got 0"),
    (("--max-cases", "-3"), "--max-cases: must be at least 1, got -3"),
    (("--max-cases", "many"), "--max-cases: expected a whole number >= 1, got 'many'"),
    (("--max-cases", "2.5"), "--max-cases: expected a whole number >= 1, got '2.5'"),
], ids=["workers-0", "workers-negative", "workers-text", "max-cases-0", "max-cases-negative", "max-cases-text",
        "max-cases-fraction"])
def test_bad_option_values_are_refused(tmp_path, args, message):
    spec = _write_spec(tmp_path / "small.toml", [_whipple()], FAST)
    result = _matrix(str(spec), "-o", str(tmp_path / "out"), *args)
    assert result.returncode == 2 and message in result.stderr, result.stderr
    errors = [line for line in result.stderr.splitlines() if line.startswith("cosim matrix: error:")]
    assert len(errors) == 1 and message in errors[0], result.stderr  # (argparse's usage stands above it)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("content, message", [(b"\xff\xfe\x00bad", "not UTF-8 text (byte 0)"),
                                              (b"[matrix\nname = 1", "Expected ']'")],
                         ids=["not-utf8", "toml-syntax"])
def test_unreadable_spec_file_is_one_message(tmp_path, content, message):
    path = tmp_path / "bad.toml"
    path.write_bytes(content)
    result = _matrix(str(path), "-o", str(tmp_path / "out"))
    assert result.returncode == 2 and str(path) in result.stderr and message in result.stderr, result.stderr


def test_failing_plugin_import_is_one_message(tmp_path):
    (tmp_path / "broken.py").write_text("raise RuntimeError('plugin is broken')\n")
    spec = _write_spec(tmp_path / "plug.toml", [_whipple()], {**FAST, "imports": ["broken.py"]})
    result = _matrix(str(spec), "-o", str(tmp_path / "out"))
    assert result.returncode == 2
    assert "imports: " in result.stderr and "broken.py" in result.stderr and "plugin is broken" in result.stderr


# --------------------------------------------------------------------------- 9. one writer per output folder

WAIT_WHILE_MARKED = '''
import os, time
from pathlib import Path
from cosim.cosimulation.controllers import Proportional


class WaitWhileMarked(Proportional):
    """T = -k phi; at t = 0.5 s, while the file 'marker' exists, writes its pid to 'flag' and waits."""

    def __init__(self, name, k=1.0, marker="", flag=""):
        super().__init__(name, k)
        self.marker, self.flag = marker, flag

    def step(self, t, h):
        if t >= 0.5 and self.marker and os.path.exists(self.marker):
            Path(self.flag).write_text(str(os.getpid()))
            while os.path.exists(self.marker):
                time.sleep(0.02)


'''


def _waiting_spec(tmp_path: Path) -> tuple[Path, Path, Path]:
    """A spec of 3 cases whose last one waits while ``marker`` exists (after writing ``flag``);
    with one worker the first two are recorded before it. Returns (spec, marker, flag)."""
    (tmp_path / "wait_marked.py").write_text(WAIT_WHILE_MARKED)
    marker, flag = tmp_path / "marker", tmp_path / "flag"
    marker.write_text("wait")
    study = {"name": "waits", "observe": "bike.phi",
             "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_phi"],
             "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
                                     "parameters": {"v": 5.0, "phi0": 0.01}},
                            "rider": {"python": "WaitWhileMarked",
                                      "parameters": {"k": "=k", "marker": "=m", "flag": str(flag)}}},
             "cases": [{"k": 1.0, "m": ""}, {"k": 2.0, "m": ""}, {"k": 3.0, "m": str(marker)}]}
    spec = _write_spec(tmp_path / "waits.toml", [study], {**FAST, "imports": ["wait_marked.py"], "timeout": 600.0})
    return spec, marker, flag


def _start_matrix(spec: Path, out: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "cosim", "matrix", str(spec), "-o", str(out), "--workers", "1",
                             "--no-progress"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_the_last_case(proc: subprocess.Popen, flag: Path, results: Path) -> None:
    """Until the waiting case runs (its flag exists) and the two cases before it are recorded."""
    deadline = time.monotonic() + 300
    while not (flag.exists() and results.exists() and len(read_records(results)[0]) == 2):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the matrix did not reach its last case"
        time.sleep(0.05)


def test_second_matrix_on_a_folder_being_written_is_refused(fmus, tmp_path):
    """Two runs on one folder used to both print PASS while one wrote to a deleted file
    (--force), or every case ended up twice (--resume): a second run (plain, --resume, --force)
    is refused in one line naming the first (its pid and command), changes nothing, and the
    first completes."""
    spec, marker, flag = _waiting_spec(tmp_path)
    out = tmp_path / "out"
    first = _start_matrix(spec, out)
    try:
        _wait_for_the_last_case(first, flag, out / "results.jsonl")
        before = _snapshot(out)
        for again in ([], ["--resume"], ["--force"]):
            second = _matrix(str(spec), "-o", str(out), "--workers", "1", *again)
            assert second.returncode == 2, (again, second.stdout + second.stderr)
            lines = second.stderr.strip().splitlines()
            assert len(lines) == 1 and lines[0].startswith(f"cosim matrix: error: output folder '{out}' is being "
                                                           f"written by pid {first.pid} (cosim matrix "), (again, lines)
            assert str(spec) in lines[0] and "started " in lines[0], lines
            assert _snapshot(out) == before, f"the refused run {again} changed the folder"
        marker.unlink()  # the last case of the first run ends
        stdout, stderr = first.communicate(timeout=300)
    finally:
        if first.poll() is None:
            first.kill()
            first.communicate()
    assert first.returncode == 0 and "PASS" in stdout and "3 cases (3 run, 0 resumed)" in stdout, stdout + stderr
    records = read_records(out / "results.jsonl")[0]
    assert sorted(r["key"] for r in records) == sorted({r["key"] for r in records}) and len(records) == 3
    assert not (out / ".cosim-lock").exists(), "the lock file is removed at the end"


def test_resume_after_kill_completes_without_duplicates(fmus, tmp_path):
    """kill -9 of a run in its last case (two cases recorded, the lock file left behind), a torn
    line at the end of the results (as a kill in the middle of a write leaves it, appended here by
    hand), then --resume: the killed run's lock is no lock, the torn line is cut off, only the
    missing case runs, and every case has exactly one record."""
    spec, marker, flag = _waiting_spec(tmp_path)
    out = tmp_path / "out"
    first = _start_matrix(spec, out)
    try:
        _wait_for_the_last_case(first, flag, out / "results.jsonl")
        first.send_signal(signal.SIGKILL)
        first.communicate(timeout=60)
    finally:
        if first.poll() is None:
            first.kill()
            first.communicate()
    assert (out / ".cosim-lock").exists() and str(first.pid) in (out / ".cosim-lock").read_text()
    with open(out / "results.jsonl", "ab") as f:
        f.write(b'{"key": "torn by the kill", "agree')
    marker.unlink()
    resumed = _matrix(str(spec), "-o", str(out), "--workers", "1", "--resume")
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert "3 cases (1 run, 2 resumed)" in resumed.stdout and "PASS" in resumed.stdout, resumed.stdout
    data = (out / "results.jsonl").read_bytes()
    records = read_records(out / "results.jsonl")[0]
    assert data.endswith(b"\n") and data.count(b"\n") == 3, data[-200:]
    assert len(records) == 3 and len({r["key"] for r in records}) == 3
    assert all(r["agreement"] == "agree" for r in records)
    assert not (out / ".cosim-lock").exists()


FORKING_HOLDER = """
import os, sys, time
from cosim.folder_lock import folder_lock

with folder_lock(sys.argv[1]):
    if os.fork() == 0:  # a worker that outlives its parent for a while (as one still ending)
        print(os.getpid(), flush=True)  # (after the fork handlers ran)
        time.sleep(600)
        os._exit(0)
    time.sleep(600)
"""


def test_lock_of_a_killed_holder_is_free_while_its_forked_child_lives(tmp_path, monkeypatch):
    """flock belongs to the open file, which a fork shares: a worker forked by the holder would
    keep the folder locked after kill -9 of the holder. Forked children close their copy, so the
    next command takes the folder at once (without the grace given to an ended holder's lock)."""
    from cosim import folder_lock as folder_lock_module
    from cosim.folder_lock import folder_lock

    monkeypatch.setattr(folder_lock_module, "ENDED_HOLDER_GRACE", 0.0)

    out = tmp_path / "out"
    holder = subprocess.Popen([sys.executable, "-c", FORKING_HOLDER, str(out)], cwd=ROOT, stdout=subprocess.PIPE,
                              text=True)
    child = None
    try:
        child = int(holder.stdout.readline())
        holder.send_signal(signal.SIGKILL)
        holder.wait(timeout=60)
        os.kill(child, 0)  # the forked child lives on
        with folder_lock(out):  # FolderBusy if the child still held the lock
            assert (out / ".cosim-lock").exists()
    finally:
        if holder.poll() is None:
            holder.kill()
        holder.stdout.close()
        if child is not None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(child, signal.SIGKILL)
