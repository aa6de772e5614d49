"""Running a matrix: build the FMUs once, dispatch the cases, persist, check, report."""
from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

from .spec import Case, MatrixSpec, load_spec
from .store import ResultStore


@dataclass
class MatrixResult:
    spec: MatrixSpec
    directory: Path
    cases: list[Case]
    records: list[dict]          # one per case, in spec order
    checks: list = field(default_factory=list)
    ran: int = 0                 # cases run in this invocation
    resumed: int = 0             # cases taken from an earlier run
    seconds: float = 0.0
    timing: dict = field(default_factory=dict)   # startup (workers ready) and run (dispatch) seconds
    report: dict = field(default_factory=dict)

    @property
    def counts(self) -> dict:
        out = {"cases": len(self.records)}
        for key in ("agree", "disagree", "marginal", "failed", "observed"):
            out[key] = sum(1 for r in self.records if r.get("agreement") == key)
        return out

    @property
    def passed(self) -> bool:
        c = self.counts
        return c["disagree"] == 0 and c["failed"] == 0 and all(ch.passed for ch in self.checks)

    @property
    def exit_code(self) -> int:
        return 0 if self.passed else 1


def build_fmus(cases: list[Case], fmu_dir: str | Path | None, jobs: int = 1) -> dict:
    """Every model the cases use, built (incrementally) once: model name -> FMU path."""
    from ..compiler.build import DEFAULT_OUTPUT, build

    models = sorted({e["model"] for c in cases for e in c.system["components"].values() if "model" in e})
    if not models:
        return {}
    results = build(models, output=fmu_dir or DEFAULT_OUTPUT, jobs=max(1, min(jobs, len(models))))
    return {r.model: str(r.fmu) for r in results}


def run_matrix(spec: MatrixSpec | str | Path, directory: str | Path | None = None, *, workers: int | None = None,
               scheduler: str | None = None, resume: bool = False, fmu_dir: str | Path | None = None,
               progress: bool = True, report: bool = True, stream=None) -> MatrixResult:
    """Run every case of a spec not yet in ``directory/results.jsonl`` (with ``resume``), then check and report.

    Parameters
    ----------
    spec : MatrixSpec or path or bundled name
    directory : output folder (default ``matrix-<name>``)
    workers : local worker processes (default: the number of CPUs); ignored with ``scheduler``
    scheduler : address of a Dask scheduler (``tcp://HOST:PORT``)
    resume : keep the results of an earlier (interrupted) run and run only the missing cases
    fmu_dir : where models are built (default: the project's ``fmus/``)
    """
    from . import checks as checks_mod
    from .pool import run_dask, run_local
    from .progress import Progress
    from .worker import import_plugins

    started = time.perf_counter()
    spec = spec if isinstance(spec, MatrixSpec) else load_spec(spec)
    directory = Path(directory or f"matrix-{spec.name}")
    workers = workers or os.cpu_count() or 1
    import_plugins(spec.imports)
    cases = spec.cases()
    fmu_paths = build_fmus(cases, fmu_dir, workers)
    store = ResultStore(directory, resume)
    (directory / "matrix.json").write_text(json.dumps({
        "spec": str(spec.path) if spec.path else spec.name, "name": spec.name, "digest": spec.digest,
        "cases": len(cases), "fmus": fmu_paths, "scheduler": scheduler, "workers": None if scheduler else workers,
    }, indent=2) + "\n")
    keys = {c.key for c in cases}
    done = {k for k in store.keys() if k in keys}
    todo = [c for c in cases if c.key not in done]
    init = {"imports": spec.imports, "fmu_paths": fmu_paths}
    bar = Progress(len(cases), len(done), stream=stream, enabled=progress)
    timeout = max(float(c.settings["timeout"]) for c in cases)

    def on_record(record: dict) -> None:
        if "line" in record:
            store.append_line(record["key"], record["line"])
        else:
            store.append(record)
        bar.update(record)

    try:
        payload = [c.to_dict() for c in todo]
        if scheduler:
            t0 = time.perf_counter()
            run_dask(payload, init, scheduler, on_record, timeout)
            timing = {"startup": 0.0, "run": time.perf_counter() - t0}
        else:
            logs = directory / "logs"
            logs.mkdir(exist_ok=True)
            cpu = time.process_time()
            timing = run_local(payload, init, workers, on_record, timeout, logs)
            timing["supervisor_cpu"] = time.process_time() - cpu
    finally:
        bar.close()
        store.close()
    stored = store.records
    records = [stored[c.key] for c in cases if c.key in stored]
    result = MatrixResult(spec=spec, directory=directory, cases=cases, records=records, ran=len(todo),
                          resumed=len(done), timing=timing)
    result.checks = checks_mod.evaluate(spec, cases, records, fmu_paths)
    result.seconds = time.perf_counter() - started
    if report:
        from .report import write_report

        result.report = write_report(result)
    return result
