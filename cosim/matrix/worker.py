"""Running cases: in a worker process (``python -m cosim.matrix.worker``) that keeps its FMUs.

A worker process reads length-prefixed pickled messages on stdin and answers on stdout:
``{"op": "init", "imports": [...], "fmu_paths": {...}}`` (answer ``{"ready": pid}``), then
``{"op": "case", "case": {...}}`` or ``{"op": "cases", "cases": [...]}`` (one answer per case,
``{"key", "agreement", "line"}`` with the record as its JSON line) for as long as it lives. Stray
output of FMUs or Python goes to stderr (the worker's log), never into the protocol.

Each FMU is extracted and instantiated once per worker and component name; every later case
resets the instance (``fmi2Reset``: start values, solver state and time are restored), so a case
gives bit-identical results whichever worker runs it and whatever ran before.

The same loop (:func:`serve`) also runs in a worker *forked* from the supervisor
(:mod:`cosim.matrix.pool`, Linux): it then inherits the supervisor's imports and starts in
milliseconds instead of the time an interpreter and numpy take. Either way a worker computes with
one BLAS thread, as the workers are the parallelism and BLAS threads of several workers spin
against each other (docs/benchmarks.md): a spawned worker gets it from
:data:`BLAS_THREAD_VARIABLES`, a forked one from the supervisor, which sets it before it forks
(:func:`set_blas_threads`), since OpenBLAS rebuilds its thread pool where it is set.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import pickle
import struct
import sys
import time
import traceback
from pathlib import Path

import numpy as np

from cosim.cosimulation.component import FMUComponent
from cosim.errors import SimulationError
from cosim.analytic import whipple  # noqa: F401  (the bicycles' predictions)
from cosim.analytic.parameters import bundled_parameter_sets
from cosim.cosimulation.factory import python_block
from cosim.cosimulation.fastloop import library
from cosim.cosimulation.master import run_components
from cosim.cosimulation.system import system_from_dict
from cosim.fmu.access import ALL_FMI_VERSIONS, FMU, read_fmu, READABLE_FMI_VERSIONS
from cosim.fmu.parameters import check, declarations, START_ROLES
from cosim.matrix import classify
from cosim.matrix.predict import predict_case
from cosim.matrix.spec import Case
from cosim.matrix.store import encode
from cosim.native import loaded_libraries
from cosim.processes import die_with_parent

_HEADER = struct.Struct(">Q")


# --------------------------------------------------------------------------- protocol

def write_message(stream, obj) -> None:
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    payload = _HEADER.pack(len(data)) + data
    view = memoryview(payload)
    while view:
        n = stream.write(view)
        if n is None:  # pragma: no cover - non-blocking stream
            continue
        view = view[n:]
    stream.flush()


def _read_exact(stream, n: int) -> bytes | None:
    chunks, left = [], n
    while left:
        chunk = stream.read(left)
        if not chunk:
            return None
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def read_message(stream):
    """The next message, or None at end of stream (the other side is gone)."""
    head = _read_exact(stream, _HEADER.size)
    if head is None:
        return None
    body = _read_exact(stream, _HEADER.unpack(head)[0])
    if body is None:
        return None
    return pickle.loads(body)


# --------------------------------------------------------------------------- plugins

def import_plugins(imports: list[str]) -> None:
    """Import modules (dotted names) or Python files that register extra blocks."""
    for item in imports:
        if item.endswith(".py"):
            path = Path(item)
            name = f"cosim_matrix_plugin_{path.stem}"
            if name in sys.modules:
                continue
            spec = importlib.util.spec_from_file_location(name, path)
            if spec is None or spec.loader is None:
                raise ImportError(f"cannot import {path}")
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            try:
                spec.loader.exec_module(module)
            except BaseException:
                del sys.modules[name]  # a failed import is not cached as done
                raise
        else:
            importlib.import_module(item)


# --------------------------------------------------------------------------- FMU reuse

class ReusableFMUComponent(FMUComponent):
    """An FMU component whose extraction and instance outlive one run.

    ``close`` (called by the master after every run) only terminates the instance; the next
    ``setup`` resets it. ``dispose`` frees it for good."""

    def __init__(self, name: str, path: str | Path):
        super().__init__(name, path, {})

        self._declared = declarations(str(path))
        self._checked: dict = {}  # (name, type, value) -> the checked value

    def _check(self, parameters: dict) -> dict:
        """:func:`cosim.fmu.parameters.check` of ``parameters``, each value checked once per
        component: the cases of a study repeat most of them (a parameter set of 28 values and the
        swept one), and checking them all again was a fifth of a case's Python time. The same
        values and the same first error as ``check``."""
        checked, memo = {}, self._checked
        for name, raw in parameters.items():
            try:
                key = (name, type(raw), raw)
                value = memo[key]
            except KeyError:
                if len(memo) >= 100_000:  # a sweep of many values: bounded memory
                    memo.clear()
                value = memo[key] = check({name: raw}, self._declared)[name]
            except TypeError:  # unhashable: checked (and refused) every time
                value = check({name: raw}, self._declared)[name]
            checked[name] = value
        return checked

    def configure(self, parameters: dict, initial: dict) -> None:
        values = self._check(parameters)
        for var in initial:
            declared = self._declared.get(var)
            if declared is None or declared.causality not in START_ROLES:
                raise SimulationError(f"{self.name}: '{var}' is not a state start value that can be set "
                                      "(use parameters for parameters)")
        self.parameters = {**values, **{k: float(v) for k, v in initial.items()}}

    def _instantiate(self) -> None:
        """Reuse the instance of the previous case (fmi2Reset) where possible."""
        if self.instance is not None:
            try:
                self.instance.reset()
            except Exception:
                self._free()
        if self.instance is None:
            super()._instantiate()

    def close(self) -> None:
        """Terminate for reuse where FMI allows it: after fmi2Error only fmi2FreeInstance (or
        fmi2Reset) is allowed, after fmi2Fatal nothing; such an instance is not reused."""
        if self.instance is None:
            return
        if self.status >= 4:
            self.instance = None
        elif self.status >= 3:
            self._free()
        else:
            try:
                self.instance.terminate()
            except Exception:
                self._free()

    def _free(self) -> None:
        if self.instance is not None:
            try:
                self.instance.freeInstance()
            except Exception:
                pass
            self.instance = None

    def dispose(self) -> None:
        self._free()
        self.fmu.close()


class FMUCache:
    """Reusable FMU components by (FMU path, component name)."""

    def __init__(self):
        self._components: dict[tuple[str, str], ReusableFMUComponent] = {}

    def component(self, name: str, path: str, parameters: dict, initial: dict) -> ReusableFMUComponent:
        key = (str(path), name)
        comp = self._components.get(key)
        if comp is None:
            comp = self._components[key] = ReusableFMUComponent(name, path)
        comp.configure(parameters, initial)
        return comp

    def close(self) -> None:
        for comp in self._components.values():
            comp.dispose()
        self._components.clear()


# --------------------------------------------------------------------------- one case

def base_record(case: dict) -> dict:
    return {"key": case["key"], "study": case["study"], "index": case["index"], "label": case["label"],
            "values": case["values"], "status": "ok", "error": None, "prediction": None, "outcome": None,
            "observed": None, "agreement": None}


def failed_record(case: dict, message: str) -> dict:
    rec = base_record(case)
    rec.update(status="failed", error=message, agreement="failed")
    return rec


def _with_fmus(system: dict, fmu_paths: dict) -> dict:
    comps = {}
    for name, entry in system["components"].items():
        entry = dict(entry)
        if "model" in entry:
            model = entry.pop("model")
            if model not in fmu_paths:
                raise SimulationError(f"component '{name}': model {model} was not built")
            entry["fmu"] = str(fmu_paths[model])
        comps[name] = entry
    return {**system, "components": comps}


def simulate(system: dict, initial: dict, observe: str, cache: FMUCache, fmu_paths: dict, stop: float | None = None):
    """Co-simulate a system dict; returns (time, observed signal, outcome dict)."""
    system = _with_fmus(system, fmu_paths)
    settings = dict(system.get("system", {}))
    settings["record"] = list(dict.fromkeys([observe, *(settings.get("record") or [])]))
    if stop is not None:
        settings["stop"] = stop
    spec = system_from_dict({**system, "system": settings})
    comps = {}
    try:
        for name, entry in spec.components.items():
            if entry.kind == "python":
                if initial.get(name):
                    raise SimulationError(f"component '{name}': 'initial' applies to FMUs only")
                comps[name] = python_block(name, entry.source, entry.parameters, spec.name)
            else:
                comps[name] = cache.component(name, entry.source, entry.parameters, initial.get(name, {}))
    except BaseException:
        for comp in comps.values():
            comp.close()
        raise
    result = run_components(spec, comps)
    outcome = {"status": result.outcome.status, "time": result.outcome.time, "message": result.outcome.message,
               "steps": result.steps}
    return np.asarray(result.data["time"]), np.asarray(result.data[observe]), outcome


def run_case(case: dict, cache: FMUCache, fmu_paths: dict) -> dict:
    """Prediction, co-simulation, classification and agreement of one case (never raises)."""
    started = time.perf_counter()
    rec = base_record(case)
    try:
        c = Case(**case)
        settings = c.settings
        system = c.system
        predicted = None
        if settings["predict"]:
            system, rec["prediction"] = predict_case(c, fmu_paths)
            predicted = rec["prediction"]["class"]
        stop = float(system["system"]["stop"])
        t, x, outcome = simulate(system, c.initial, c.observe, cache, fmu_paths)
        obs = classify.observe(t, x, outcome["status"], settings["observed_margin"])
        obs["extended"] = False
        if obs["class"] == "marginal" and settings["extend"] > 1 and predicted in ("stable", "unstable"):
            t, x, outcome = simulate(system, c.initial, c.observe, cache, fmu_paths, stop=stop * settings["extend"])
            obs = classify.observe(t, x, outcome["status"], settings["observed_margin"])
            obs["extended"] = True
        rec["outcome"], rec["observed"] = outcome, obs
        if obs["class"] == "unexcited":
            rec.update(status="failed", error=f"'{c.observe}' stayed 0: perturb the case (an initial state "
                                              "value or a pulse)")
        rec["agreement"] = classify.agreement(predicted, obs["class"]) if settings["predict"] else "observed"
        if rec["status"] == "failed":
            rec["agreement"] = "failed"
    except Exception as exc:  # the case fails, the matrix goes on
        rec.update(status="failed", error=f"{type(exc).__name__}: {exc}", agreement="failed")
        print(f"case {case.get('study')} {case.get('label')}:\n{traceback.format_exc()}", file=sys.stderr)
    rec["elapsed"] = time.perf_counter() - started
    rec["worker"] = os.getpid()
    return rec


# --------------------------------------------------------------------------- process main

#: Environment variables that limit the BLAS/OpenMP thread pools of a worker started as a new process.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


#: (set, get) thread-count functions of the BLAS libraries a process may have loaded.
_BLAS_THREAD_FUNCTIONS = (("openblas_set_num_threads", "openblas_get_num_threads"),
                          ("scipy_openblas_set_num_threads64_", "scipy_openblas_get_num_threads64_"),
                          ("scipy_openblas_set_num_threads", "scipy_openblas_get_num_threads"),
                          ("openblas_set_num_threads64_", "openblas_get_num_threads64_"),
                          ("MKL_Set_Num_Threads", "MKL_Get_Max_Threads"))


def set_blas_threads(count: int | dict) -> dict:
    """Set the thread count of the BLAS libraries loaded in this process: ``count`` for all, or a
    dict returned by an earlier call (restores those counts). Returns the counts before, by
    library ({} where none is found: the libraries are looked up in ``/proc/self/maps``, Linux).

    A process whose numpy is imported has its OpenBLAS threads already (the environment variables
    of :data:`BLAS_THREAD_VARIABLES` act only before numpy loads it)."""
    import ctypes

    before, seen = {}, set()
    for lib in loaded_libraries("openblas|blas|mkl_rt"):
        try:
            handle = ctypes.CDLL(lib)
        except OSError:
            continue
        for setter, getter in _BLAS_THREAD_FUNCTIONS:
            set_count, get_count = getattr(handle, setter, None), getattr(handle, getter, None)
            if set_count is None or get_count is None:
                continue
            function = ctypes.cast(set_count, ctypes.c_void_p).value
            if function in seen:  # the same library again (scipy's BLAS modules resolve to its OpenBLAS)
                break
            seen.add(function)
            set_count.argtypes, set_count.restype, get_count.restype = [ctypes.c_int], None, ctypes.c_int
            before[lib] = get_count()
            wanted = count.get(lib) if isinstance(count, dict) else count
            if wanted is not None and wanted != before[lib]:
                set_count(int(wanted))
            break
    return before


def warm_up() -> None:
    """Import what every case needs before reporting ready, and run the classification once.

    A worker's first case otherwise paid 50-100 ms for fmpy's imports, the C loop's library, the
    package data and numpy's first calls -- on 2 workers of a 600-run matrix a sixth of the steady time.
    python-control (0.8 s to import) and scipy are not among them: they are imported by the
    cases that need them (exact delays, tuning), so that a worker of a matrix of FMUs starts fast."""
    import fmpy.fmi2  # noqa: F401
    import fmpy.fmi3  # noqa: F401

    library()
    bundled_parameter_sets()  # importlib.resources' readers, loaded on the first lookup of package data
    t = np.linspace(0.0, 10.0, 1001)
    classify.observe(t, np.exp(-0.5 * t) * np.cos(4.0 * t), "completed", 1e-3)


def warm_fmus(fmu_paths: dict, unzip: bool = False) -> None:
    """Read the model descriptions of the matrix's FMUs and, with ``unzip``, unzip them (each once
    per process, see cosim.fmu.access).

    Reading is XML only, no FMU code runs: safe in the supervisor, whose forked workers inherit the
    descriptions; a worker unzips into its own folder before it reports ready. A broken FMU is
    skipped here: the cases that use it fail with their own message."""
    for path in dict.fromkeys(str(p) for p in fmu_paths.values()):
        try:
            read_fmu(path, READABLE_FMI_VERSIONS)
            if unzip:
                FMU(path, versions=ALL_FMI_VERSIONS)
        except Exception:
            continue


def warm_imports(cases: list[dict]) -> None:
    """Import here what the predictions of ``cases`` will import, so that workers forked
    afterwards inherit it instead of each paying for it in its first case: python-control
    (0.8 s) for the Pade approximations of delays -- exact ``TransportDelay`` blocks and the
    master's lags on connections -- and scipy for tuning.

    Only imports: no case is predicted here, since a prediction may linearize an FMU, and an FMU
    that crashes must take down a worker, never the supervisor."""
    needs_control = needs_scipy = False
    for case in cases:
        if not (case.get("settings") or {}).get("predict", True):
            continue
        system = case.get("system") or {}
        if system.get("connections") or any("python" in e for e in system.get("components", {}).values()):
            needs_control = True
        if case.get("tune"):
            needs_scipy = needs_control = True
        if needs_control and needs_scipy:
            break
    if needs_control:
        import control  # noqa: F401

        from cosim.cosimulation import blocks, controllers  # deferred: imports scipy.linalg  # noqa: F401
    if needs_scipy:
        import scipy.optimize  # noqa: F401


def _parent_pid(argv: list[str]) -> int | None:
    """The supervisor's pid from ``--parent PID`` (the worker dies with it), else None."""
    if "--parent" in argv:
        try:
            return int(argv[argv.index("--parent") + 1])
        except (IndexError, ValueError):
            return None
    return None


def main(argv: list[str] | None = None) -> int:
    # first: a worker must not outlive its supervisor (or Dask worker), even one killed with -9
    die_with_parent(_parent_pid(sys.argv[1:] if argv is None else argv))
    proto_in = sys.stdin.buffer
    proto_out = os.fdopen(os.dup(1), "wb", buffering=0)
    os.dup2(2, 1)               # C-level printf of FMUs goes to the log
    sys.stdout = sys.stderr
    init = read_message(proto_in)
    if init is None:
        return 0
    return serve(proto_in, proto_out, init)


def serve(proto_in, proto_out, init: dict) -> int:
    """The worker loop after the ``init`` message: ready, then one answer per case until ``stop``.

    Messages ``{"op": "cases", "cases": [...]}`` carry several cases (fewer, larger pipe writes);
    each case is still answered on its own, as soon as it is done, so that the supervisor knows
    which case a worker that dies was running."""
    import_plugins(init.get("imports", []))
    fmu_paths = init.get("fmu_paths", {})
    warm_up()
    warm_fmus(fmu_paths, unzip=True)
    cache = FMUCache()
    write_message(proto_out, {"ready": os.getpid()})
    try:
        while True:
            msg = read_message(proto_in)
            if msg is None or msg.get("op") == "stop":
                break
            op = msg.get("op")
            batch = [msg["case"]] if op == "case" else msg.get("cases", []) if op == "cases" else []
            for case in batch:
                rec = run_case(case, cache, fmu_paths)
                # the JSON line is made here, in parallel, so the supervisor only writes it
                write_message(proto_out, {"key": rec["key"], "agreement": rec["agreement"], "line": encode(rec)})
    finally:
        cache.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
