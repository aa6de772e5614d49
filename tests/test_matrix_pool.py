"""The fast path of `cosim matrix`: forked workers, batched messages, one BLAS thread,
the pencil's SVD without U -- each giving the same records as the per-case path.

Tolerances: none where the claim is bit-for-bit identity (records compared field by field, the
SVD compared with ``np.array_equal``). No wall-clock assertion anywhere: the speed is measured by
``python benchmarks/matrix.py``.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT
from cosim.matrix import classify, pool
from cosim.matrix.spec import spec_from_dict

# the quick run (-m 'not slow') leaves this module out: it runs co-simulation matrices with worker processes
pytestmark = pytest.mark.slow

VOLATILE = {"elapsed", "worker"}
STOP = {"stop": 2.0, "step": 0.01}


def _bike(v="=v") -> dict:
    return {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
            "parameters": {"v": v, "phi0": 0.01}}


def _spec(name: str, matrix: dict | None = None, extra_studies: tuple = ()) -> dict:
    """FMU-only cases (the C stepping loop) and rider + exact delay cases (Python blocks)."""
    studies = [
        {"name": "fmu", "observe": "bike.phi", "connections": [], "components": {"bike": _bike()},
         "axes": {"v": [2.0, 4.6, 5.3, 7.0]}},
        {"name": "rider", "observe": "bike.phi",
         "connections": ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"],
         "components": {"bike": _bike(), "rider": {"python": "Proportional", "parameters": {"k": 0.5}},
                        "delay": {"python": "TransportDelay", "parameters": {"tau": 0.1}}},
         "axes": {"v": [4.6, 5.5]}},
        *extra_studies,
    ]
    return {"matrix": {"name": name, **STOP, **(matrix or {})}, "study": studies}


def _strip(records: list[dict]) -> dict:
    return {r["key"]: {k: v for k, v in r.items() if k not in VOLATILE} for r in records}


def _per_case(spec) -> dict:
    """The reference: every case run in this process, one after the other (run_case, then the
    record as written to results.jsonl and read back)."""
    import json

    from cosim.matrix.runner import build_fmus
    from cosim.matrix.store import encode
    from cosim.matrix.worker import FMUCache, run_case

    cases = spec.cases()
    paths = build_fmus(cases, None)
    cache = FMUCache()
    try:
        return _strip([json.loads(encode(run_case(c.to_dict(), cache, paths))) for c in cases])
    finally:
        cache.close()


@pytest.fixture(scope="module")
def reference():
    spec = spec_from_dict(_spec("pool"))
    return spec, _per_case(spec)


# --------------------------------------------------------------------------- records

# The matrix run in a process of its own, as `cosim matrix` runs it: this test process has threads
# left by other tests (Dask's, pools'), from which the supervisor rightly never forks.
MATRIX_PROCESS = """
import json, sys
from cosim.matrix.runner import run_matrix
from cosim.matrix.spec import spec_from_dict
from cosim.matrix.store import encode
result = run_matrix(spec_from_dict(json.loads(sys.argv[1])), sys.argv[2], workers=int(sys.argv[3]),
                    progress=False, report=False)
print(json.dumps({"start": result.timing["start"], "counts": result.counts,
                  "records": [json.loads(encode(r)) for r in result.records]}))
"""


@pytest.mark.parametrize("start, workers", [("fork", 2), ("fork", 1), ("spawn", 2)],
                         ids=["fork-2-workers", "fork-1-worker", "spawn-2-workers"])
def test_pool_records_equal_the_per_case_path_field_by_field(reference, tmp_path, start, workers):
    import json

    spec, expected = reference
    run = subprocess.run([sys.executable, "-c", MATRIX_PROCESS, json.dumps(_spec("pool")), str(tmp_path / "out"),
                          str(workers)], capture_output=True, text=True, timeout=600,
                         env={**os.environ, "COSIM_MATRIX_START": start})
    assert run.returncode == 0, run.stderr[-2000:]
    result = json.loads(run.stdout.strip().splitlines()[-1])
    assert result["start"] == start  # the path under test was taken
    got = _strip(result["records"])
    assert list(got) == list(expected)  # every case, in spec order
    for key, record in expected.items():
        for field, value in record.items():
            assert got[key][field] == value, f"{key}: field {field!r} differs"
        assert set(got[key]) == set(record), key
    assert result["counts"]["failed"] == 0 and result["counts"]["disagree"] == 0
    assert len({r["worker"] for r in result["records"]}) == workers  # the cases were shared out
    for pid in {r["worker"] for r in result["records"]}:  # each worker removed the FMUs it unzipped
        assert not list(Path(tempfile.gettempdir()).glob(f"cosim-fmu-{pid}-*")), pid


# --------------------------------------------------------------------------- failures

CRASH = '''
import os, signal
from cosim.cosimulation.controllers import Proportional


class SegfaultAt(Proportional):
    """T = -k phi; segfaults the process at t = 0.5 s when 'crash' is 1 (a broken FMU)."""

    def __init__(self, name, k=1.0, crash=0.0):
        super().__init__(name, k)
        self.crash = crash

    def step(self, t, h):
        if t >= 0.5 and self.crash:
            os.kill(os.getpid(), signal.SIGSEGV)
'''


@pytest.mark.parametrize("start", ["fork", "spawn"])
def test_crashing_worker_fails_its_case_only_and_keeps_the_rest(reference, tmp_path, monkeypatch, start):
    """A worker that segfaults in the middle of a batch: that case fails with one message naming
    the signal, the cases queued behind it run on a fresh worker, every other record equals the
    per-case path."""
    from cosim.matrix.runner import run_matrix

    _, expected = reference
    (tmp_path / "segfault.py").write_text(CRASH)
    crashing = {"name": "crash", "observe": "bike.phi", "connections": ["bike.phi -> rider.phi",
                                                                        "rider.T -> bike.T_phi"],
                "components": {"bike": _bike(5.0), "rider": {"python": "SegfaultAt",
                                                             "parameters": {"k": "=k", "crash": "=crash"}}},
                "cases": [{"k": 1.0, "crash": 0.0}, {"k": 2.0, "crash": 1.0}, {"k": 3.0, "crash": 0.0}]}
    data = _spec("pool", {"imports": [str(tmp_path / "segfault.py")]}, (crashing,))
    spec = spec_from_dict(data)
    monkeypatch.setenv("COSIM_MATRIX_START", start)
    result = run_matrix(spec, tmp_path / "out", workers=2, progress=False, report=False)
    failed = [r for r in result.records if r["agreement"] == "failed"]
    assert len(failed) == 1 and failed[0]["values"]["crash"] == 1.0, [r["error"] for r in failed]
    assert failed[0]["error"].startswith("worker process died (SIGSEGV (signal 11)) while running this case")
    assert "Traceback" not in failed[0]["error"]
    got = _strip(result.records)
    for key, record in expected.items():
        assert got[key] == record, key
    assert len(result.records) == len(spec.cases())


def test_bad_case_gives_one_message_and_the_others_run(reference, tmp_path, monkeypatch):
    """A case with a value the FMU refuses (a wheel radius below its declared minimum): that case
    fails with one message naming the parameter. (A name the FMU does not have is refused for the
    whole spec before anything is built: tests/test_declarations.py.)"""
    from cosim.matrix.runner import run_matrix

    _, expected = reference
    bad = {"name": "bad", "observe": "bike.phi", "connections": [],
           "components": {"bike": {**_bike(5.0), "parameters": {"v": 5.0, "phi0": 0.01, "rR": "=-x"}}},
           "axes": {"x": [1.0]}}
    spec = spec_from_dict(_spec("pool", None, (bad,)))
    monkeypatch.setenv("COSIM_MATRIX_START", "fork")
    result = run_matrix(spec, tmp_path / "out", workers=2, progress=False, report=False)
    failed = [r for r in result.records if r["agreement"] == "failed"]
    assert len(failed) == 1 and "rR" in failed[0]["error"] and "\n" not in failed[0]["error"]
    got = _strip(result.records)
    assert all(got[key] == record for key, record in expected.items())


# --------------------------------------------------------------------------- start method

@pytest.mark.parametrize("value", ["forkserver", "threads"], ids=["forkserver", "threads"])
def test_unknown_start_method_is_refused_with_the_choices(monkeypatch, value):
    monkeypatch.setenv("COSIM_MATRIX_START", value)
    with pytest.raises(ValueError, match=r"COSIM_MATRIX_START must be one of auto, fork, spawn, got"):
        pool.start_method()


@pytest.mark.parametrize("requested, threads, expected", [
    ("auto", 1, "fork"), ("fork", 1, "fork"), ("spawn", 1, "spawn"),
    ("auto", 2, "spawn"), ("fork", 2, "spawn"),
], ids=["auto", "fork", "spawn", "auto-from-threads", "fork-from-threads"])
def test_fork_only_from_a_single_threaded_process(monkeypatch, requested, threads, expected):
    """A fork copies only the calling thread: with another thread alive (Dask's) workers are spawned."""
    if not sys.platform.startswith("linux"):
        pytest.skip("fork is used on Linux only")
    monkeypatch.delenv("COSIM_MATRIX_START", raising=False)
    monkeypatch.setattr(threading, "active_count", lambda: threads)
    assert pool.start_method(requested) == expected


def test_forked_worker_computes_with_one_blas_thread(tmp_path):
    """set_blas_threads(1) in a process whose numpy already runs OpenBLAS with 2 threads."""
    code = ("import ctypes, re, numpy\n"
            "from cosim.matrix.worker import set_blas_threads\n"
            "libs = sorted(set(re.findall(r'(/\\S*openblas\\S*\\.so\\S*)', open('/proc/self/maps').read())))\n"
            "get = [getattr(ctypes.CDLL(p), n) for p in libs for n in ('openblas_get_num_threads',\n"
            "       'scipy_openblas_get_num_threads64_') if hasattr(ctypes.CDLL(p), n)][0]\n"
            "before = get()\n"
            "print(before, bool(set_blas_threads(1)), get())\n")
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
    env["OPENBLAS_NUM_THREADS"] = "2"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                         timeout=120)
    if out.returncode and "IndexError" in out.stderr:
        pytest.skip("numpy is not linked with OpenBLAS here")
    assert out.returncode == 0, out.stderr
    before, found, after = out.stdout.split()
    assert (before, found, after) == ("2", "True", "1")


FORKED_THREADS = """
import json, os, sys
from cosim.matrix import worker
from cosim.matrix.runner import run_matrix
from cosim.matrix.spec import spec_from_dict
serve = worker.serve

def recording_serve(*args, **kwargs):  # what a forked worker has when it stops
    try:
        return serve(*args, **kwargs)
    finally:
        with open(os.path.join(sys.argv[2], f"worker-{os.getpid()}.json"), "w") as f:
            json.dump({"threads": len(os.listdir("/proc/self/task")),
                       "blas": list(worker.set_blas_threads({}).values())}, f)

worker.serve = recording_serve
before = list(worker.set_blas_threads({}).values())
result = run_matrix(spec_from_dict(json.loads(sys.argv[1])), os.path.join(sys.argv[2], "out"), workers=2,
                    progress=False, report=False)
print(json.dumps({"before": before, "after": list(worker.set_blas_threads({}).values()),
                  "start": result.timing["start"]}))
"""


def test_forked_workers_inherit_one_blas_thread_and_start_no_blas_pool(reference, tmp_path):
    """The supervisor sets one BLAS thread before it forks and restores its own count after the
    run; a forked worker keeps the inherited count, so OpenBLAS builds no thread pool in it (its
    thread spun for ~0.1 s of CPU at every worker's start): a worker has its main thread and the
    die-with-parent watchdog, nothing else."""
    import json

    spec, _ = reference
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
    env["OPENBLAS_NUM_THREADS"] = "2"
    data = _spec("threads")
    out = subprocess.run([sys.executable, "-c", FORKED_THREADS, json.dumps(data), str(tmp_path)],
                         capture_output=True, text=True, cwd=ROOT, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout.strip().splitlines()[-1])
    if not result["before"]:
        pytest.skip("no OpenBLAS found in the process")
    assert result["start"] == "fork"
    # the supervisor's numpy (and scipy, loaded during the run for the rider's prediction) as before
    assert result["before"] == [2] and set(result["after"]) == {2}
    workers = [json.loads(p.read_text()) for p in tmp_path.glob("worker-*.json")]
    assert len(workers) == 2
    assert all(w["threads"] == 2 and set(w["blas"]) == {1} for w in workers), workers


# --------------------------------------------------------------------------- classification

def _signal(kind: str, n: int) -> np.ndarray:
    rng = np.random.default_rng(n)
    t = np.arange(n) * 0.03
    if kind == "modes":
        x = sum(rng.normal() * np.exp(0.3 * rng.normal() * t) * np.cos(rng.uniform(0, 5) * t + rng.uniform(0, 3))
                for _ in range(4))
    elif kind == "noisy":
        x = np.exp(-0.2 * t) * np.cos(2 * t) + 1e-9 * rng.normal(size=n)
    else:  # a signal that is no sum of a few modes (clipped)
        x = np.clip(np.exp(0.4 * t) * np.sin(3 * t), -2.0, 2.0)
    return x / np.abs(x).max()


@pytest.mark.parametrize("n", [30, 31, 100, 334, 400, 1001])
@pytest.mark.parametrize("kind", ["modes", "noisy", "clipped"])
def test_pencil_svd_equals_numpy_svd_bit_for_bit(kind, n):
    """The SVD of R (Y = QR) gives the singular values and right vectors numpy's SVD of Y gives."""
    from scipy.linalg import hankel

    x = _signal(kind, n)
    pencil = n // 3
    Y = hankel(x[:n - pencil], x[n - pencil - 1:])
    assert np.array_equal(classify.hankel(x, pencil), Y)
    _, s, vh = np.linalg.svd(Y, full_matrices=False)
    s2, vh2 = classify.singular_values_right(classify.hankel(x, pencil))
    assert np.array_equal(s, s2) and np.array_equal(vh, vh2)


def test_worker_start_imports_neither_control_nor_scipy():
    """What a worker imports before it is ready (python-control alone takes ~0.8 s)."""
    code = ("import sys\nfrom cosim.matrix.worker import warm_up\nwarm_up()\n"
            "print(sorted(m for m in ('control', 'scipy', 'matplotlib', 'casadi', 'pymoca') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


# --------------------------------------------------------------------------- prediction caches

@pytest.mark.parametrize("v", [0.0, 2.5, 4.6, 5.99, -3.0, 12.0], ids=lambda v: f"v={v}")
@pytest.mark.parametrize("change", [{}, {"mB": 90.0, "c": 0.1}], ids=["benchmark", "heavier-rider"])
def test_cached_whipple_matrices_equal_state_matrices_bit_for_bit(v, change):
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import state_matrices
    from cosim.matrix.predict import whipple_state_matrices

    p = {**load_parameters("benchmark"), **change}
    A, B = state_matrices(p, v)
    for _ in range(2):  # computed, then from the cache
        A2, B2 = whipple_state_matrices(p, v)
        assert np.array_equal(A, A2) and np.array_equal(B, B2)
        A2[0, 0] = 99.0  # the result is the caller's own: the cache is not changed
    assert np.array_equal(whipple_state_matrices(p, v)[0], A)


def test_predictions_with_warm_caches_equal_cold_ones(reference):
    """Every case's prediction record: with the block and bicycle caches cleared before each
    case (the per-case path before the caches) and warm (the matrix's path)."""
    from cosim.matrix import predict
    from cosim.matrix.runner import build_fmus

    spec, _ = reference
    cases = spec.cases()
    paths = build_fmus(cases, None)
    cold = []
    for case in cases:
        predict._BLOCK_MODELS.clear()
        predict._whipple_matrices.cache_clear()
        cold.append(predict.predict_case(case, paths))
    warm = [predict.predict_case(case, paths) for case in cases]
    assert predict._BLOCK_MODELS  # the delay's and the rider's models were cached
    assert warm == cold


def test_unconnected_loop_predicts_what_the_closed_loop_formula_gives(reference):
    """A system without connections (K = 0) skips solve(I - D K, C) and A + B K Cy: the same
    eigenvalues, bit for bit, as with them."""
    from cosim.matrix import predict
    from cosim.matrix.runner import build_fmus

    spec, _ = reference
    cases = [c for c in spec.cases() if not c.system.get("connections")]
    assert cases
    paths = build_fmus(cases, None)
    for case in cases:
        loop = predict.Loop(case.system, case.observe, paths, case.settings)
        assert not loop.connected and not loop.K.any()
        fast = loop.prediction()
        loop.connected = True  # the general formula
        assert loop.prediction() == fast


@pytest.mark.parametrize("n", [1, 2, 6, 12, 32])
def test_influence_search_in_python_equals_the_array_iteration(n, monkeypatch):
    """The states that influence the observed output: the plain-Python search of small graphs and
    the whole-array iteration of large ones give the same set (random sparse graphs, chains)."""
    from cosim.matrix import predict

    rng = np.random.default_rng(n)
    graphs = [rng.normal(size=(n, n)) * (rng.uniform(size=(n, n)) < density) for density in (0.0, 0.1, 0.3, 1.0)]
    graphs.append(np.diag(np.ones(n - 1), -1) if n > 1 else np.ones((1, 1)))  # a chain: x_k drives x_k+1
    for A in graphs:
        for row in (np.eye(n)[-1], np.eye(n)[0], rng.normal(size=n) * (rng.uniform(size=n) < 0.3)):
            small = predict._influencing(A, row)
            monkeypatch.setattr(predict, "SMALL_GRAPH", 0)
            large = predict._influencing(A, row)
            monkeypatch.setattr(predict, "SMALL_GRAPH", 32)
            assert small.tolist() == large.tolist()


@pytest.mark.parametrize("tau, k", [(0.1, 0.5), (0.2, 0.5), (0.1, 2.0)], ids=["base", "other-tau", "other-k"])
def test_block_model_cache_tells_parameters_apart(tau, k):
    from cosim.matrix.predict import block_lti

    settings = {"pade_order": 6, "master_lag": True}
    base = block_lti("delay", "TransportDelay", {"tau": 0.1}, settings)
    model = block_lti("delay", "TransportDelay", {"tau": tau}, settings)
    rider = block_lti("rider", "Proportional", {"k": k}, settings)
    assert (model is base) == (tau == 0.1)
    assert not model.system.A.flags.writeable  # shared between cases: nobody may change it
    assert float(rider.system.D[0, 0]) == -k  # T = -k phi: a different k is a different cached model


@pytest.mark.parametrize("study, imported", [("fmu", "[]"), ("rider", "['control']")], ids=["fmu-only", "rider"])
def test_supervisor_imports_python_control_only_for_cases_that_need_it(study, imported):
    """Before forking, the supervisor imports python-control once for delays and connected
    blocks (else every worker would import it in its first case), never for FMU-only cases."""
    code = ("import sys, json\nfrom cosim.matrix.spec import spec_from_dict\n"
            "from cosim.matrix.worker import warm_imports\n"
            f"spec = spec_from_dict(json.loads(sys.argv[1]))\n"
            f"warm_imports([c.to_dict() for c in spec.cases() if c.study == {study!r}])\n"
            "print(sorted(m for m in ('control',) if m in sys.modules))")
    import json

    out = subprocess.run([sys.executable, "-c", code, json.dumps(_spec("warm"))], capture_output=True, text=True,
                         cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == imported


# --------------------------------------------------------------------------- a worker's first case

FIRST_CASE = """
import json, sys
import fmpy.model_description as fmd
from cosim.matrix import worker
paths, case = json.loads(sys.argv[1]), json.loads(sys.argv[2])
worker.warm_up()
worker.warm_imports([case])  # the supervisor's, before it forks
worker.warm_fmus(paths, unzip=True)
cache = worker.FMUCache()
before, reads = set(sys.modules), []
original = fmd.read_model_description
fmd.read_model_description = lambda *a, **k: reads.append(a) or original(*a, **k)
record = worker.run_case(case, cache, paths)
print(json.dumps({"new": sorted(set(sys.modules) - before), "reads": len(reads), "status": record["status"],
                  "agreement": record["agreement"]}))
"""


@pytest.mark.parametrize("study", ["fmu", "rider"], ids=["fmu-only", "rider"])
def test_first_case_after_the_warm_up_imports_and_reads_nothing(reference, study):
    """What a worker does before it reports ready (warm_up, warm_fmus with unzip) leaves its
    first case nothing to import and no model description to read: that first case cost 50-100 ms,
    a sixth of the steady time of a 600-run matrix on 2 workers. (python-control and the blocks,
    which the rider's case needs, are imported by the supervisor before it forks: warm_imports.)"""
    import json

    from cosim.matrix.runner import build_fmus

    spec, _ = reference
    cases = [c for c in spec.cases() if c.study == study]
    paths = {k: str(v) for k, v in build_fmus(cases, None).items()}
    out = subprocess.run([sys.executable, "-c", FIRST_CASE, json.dumps(paths),
                          json.dumps(cases[0].to_dict())], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["status"] == "ok" and result["agreement"] in ("agree", "marginal"), result
    assert result["reads"] == 0
    assert result["new"] == [], result["new"]


def test_window_maximum_by_slices_equals_the_masked_one():
    """On an increasing time grid the windows of observe are slices (found by bisection): the same
    maxima as the masks over the whole run, also for windows outside the run or between samples."""
    rng = np.random.default_rng(3)
    for _ in range(500):
        t = np.unique(np.round(np.cumsum(rng.uniform(0.0, 1.0, int(rng.integers(1, 200)))), int(rng.integers(0, 4))))
        ax = rng.uniform(size=t.size)
        a, b = np.sort(rng.uniform(t[0] - 1.0, t[-1] + 1.0, 2))
        for lo, hi in ((a, b), (t[0], t[-1]), (t[-1] / 3, 2 * t[-1] / 3), (b, a)):
            assert classify._window_max(t, ax, lo, hi, True) == classify._window_max(t, ax, lo, hi)


@pytest.mark.parametrize("n", [1, 2, 3, 10, 11, 500, 1001])
def test_median_equals_numpy_median_bit_for_bit(n):
    rng = np.random.default_rng(n)
    for a in (rng.normal(size=n), np.round(rng.normal(size=n), 2), np.full(n, 0.01), rng.normal(size=n) * 1e-300):
        assert classify._median(a) == float(np.median(a))


def test_warming_skips_a_broken_fmu_and_warms_the_others(reference, tmp_path):
    """A damaged FMU is left to the cases that use it (they fail with its message); the others are
    read and unzipped all the same."""
    from cosim.fmu import access
    from cosim.matrix.runner import build_fmus
    from cosim.matrix.worker import warm_fmus

    spec, _ = reference
    good = str(next(iter(build_fmus(spec.cases(), None).values())))
    bad = tmp_path / "broken.fmu"
    bad.write_bytes(b"not a zip archive")
    access._DESCRIPTIONS.pop(access._key(Path(good)), None)
    warm_fmus({"Broken": str(bad), "Good": good}, unzip=True)
    assert access._key(Path(good)) in access._DESCRIPTIONS


def test_checked_parameters_of_a_reused_component_equal_a_fresh_check(reference):
    """A worker's component checks each (name, value) once (the cases of a study repeat most of
    them): the values are those of cosim.fmu.parameters.check, and a bad value is refused by name
    every time it comes, never remembered as checked."""
    from cosim.analytic.parameters import PARAMETER_NAMES, load_parameters
    from cosim.fmu.parameters import ParameterError, check
    from cosim.matrix.runner import build_fmus
    from cosim.matrix.worker import ReusableFMUComponent

    spec, _ = reference
    path = next(iter(build_fmus(spec.cases(), None).values()))
    comp = ReusableFMUComponent("bike", path)
    try:
        base = {k: v for k, v in load_parameters("benchmark").items() if k in PARAMETER_NAMES}
        for v in (4.0, 5.0, 4.0, "6.5", 5):
            values = {**base, "v": v, "phi0": 0.01}
            assert comp._check(values) == check(values, comp._declared)
            assert type(comp._check(values)["v"]) is float
        for _ in range(2):
            with pytest.raises(ParameterError, match="'v'"):
                comp._check({**base, "v": "fast"})
            with pytest.raises(ParameterError, match="unknown parameter 'nonsense'"):
                comp._check({"v": 5.0, "nonsense": 1.0})
            with pytest.raises(ParameterError, match="'v': expected a number"):
                comp._check({"v": [5.0]})  # unhashable: checked (and refused) every time
    finally:
        comp.dispose()


@pytest.mark.parametrize("value", [1.5, float("nan"), float("inf"), np.float64(2.5), np.int64(3), np.bool_(True),
                                   1 + 2j, (1.0, 2.0), {"x": [np.float32(0.5), None]}],
                         ids=["float", "nan", "inf", "numpy-float", "numpy-int", "numpy-bool", "complex", "tuple",
                              "nested"])
def test_encoded_record_is_the_cleaned_record(value):
    """store.encode tries json's C encoder on the record as it is and walks it with _clean only
    where that fails: the line is the same either way."""
    import json

    from cosim.matrix.store import _clean, encode

    record = {"key": "k", "value": value, "observed": {"modes": [[0.1, -2.0]]}}
    assert encode(record) == (json.dumps(_clean(record), sort_keys=True, allow_nan=False) + "\n").encode()
