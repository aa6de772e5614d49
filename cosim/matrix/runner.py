"""Running a matrix: build the FMUs once, dispatch the cases, persist, check, report.

Everything the user can get wrong is refused before any work, each with one message: the spec
(types, ranges, expressions, the number of cases, the names of parameters and start values that
its model and FMU components do not declare), the output folder (not writable, a file in the way,
being written by another run, or already holding results without ``resume``/``force``) and an
unreachable scheduler.

One run writes a folder at a time: a run holds the folder's lock (:mod:`cosim.folder_lock`) from
the build of its FMUs to its report, and a second run on the folder is refused naming the first.
"""
from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from cosim.errors import OutputError, ParameterError, ResultNotWritten
from cosim.folder_lock import check_not_busy, folder_lock
from cosim.matrix.spec import MAX_CASES, Case, MatrixSpec, SpecError, load_spec
from cosim.matrix.store import RESULTS, ResultStore, has_results
from cosim.matrix.progress import Progress
from cosim.matrix.report import write_report
from cosim.outputs import check_output_folder, write_text


@dataclass
class MatrixResult:
    spec: MatrixSpec
    directory: Path
    cases: list[Case]
    records: list[dict]          # one per case, in spec order
    checks: list = field(default_factory=list)
    ran: int = 0                 # cases run in this invocation
    resumed: int = 0             # cases taken from an earlier run
    retried: int = 0             # failed cases of an earlier run run again
    seconds: float = 0.0
    timing: dict = field(default_factory=dict)   # startup (workers ready) and run (dispatch) seconds
    report: dict = field(default_factory=dict)
    total: int = 0               # cases of the spec (more than ``cases`` when they are a sample)
    sample: str = ""             # how a sample was chosen ("" when every case runs)

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


def check_names(cases: list[Case], where: str) -> None:
    """Every parameter, ``initial`` state and tuned parameter that a case names for a model or
    FMU component is one its FMU declares (:func:`cosim.fmu.parameters.declarations`: for a
    model, the FMU it is built as, read without building it), before anything is built. The
    values are checked when each case runs (a case with a value outside its declared range
    fails, the others run).

    Raises
    ------
    SpecError
        Naming the spec, the study, the component and the name: unknown, an input, a calculated
        parameter, or an ``initial`` entry that is not a state's start value.
    """
    # deferred: loads numpy, which importing this module does not
    from cosim.fmu.parameters import START_ROLES, declarations, settable

    declared: dict[str, dict] = {}
    seen: set[tuple] = set()
    hint = "connect it, e.g. to a Step or Pulse block"
    for case in cases:
        components = case.system.get("components", {})
        names = {c: [("parameters", n) for n in e.get("parameters", {})] for c, e in components.items()}
        for c, states in case.initial.items():
            names.setdefault(c, []).extend(("initial", n) for n in states)
        for target in case.tune:
            c, _, n = target.partition(".")
            names.setdefault(c, []).append(("tune", n))
        for c, items in names.items():
            entry = components.get(c, {})
            source = entry.get("model") or entry.get("fmu")
            if source is None:
                continue  # a Python block checks its own parameters
            for key, name in items:
                if (source, key, name) in seen:
                    continue
                seen.add((source, key, name))
                if source not in declared:
                    declared[source] = declarations(str(source))
                try:
                    d = settable(name, declared[source], hint)
                    if key == "initial" and d.causality not in START_ROLES:
                        raise ParameterError(f"'{name}' is not a state start value that can be set (use "
                                             "parameters for parameters)")
                except ParameterError as exc:
                    raise SpecError(f"{where}: study '{case.study}': component '{c}' {key}: {exc}") from None


def build_fmus(cases: list[Case], fmu_dir: str | Path | None, jobs: int = 1) -> dict:
    """Every model the cases use, built (incrementally) once: model name -> FMU path."""
    # deferred: loads casadi, numpy, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build

    models = sorted({e["model"] for c in cases for e in c.system["components"].values() if "model" in e})
    if not models:
        return {}
    results = build(models, output=fmu_dir or DEFAULT_OUTPUT, jobs=max(1, min(jobs, len(models))))
    return {r.model: str(r.fmu) for r in results}


def prepare_directory(directory: Path, resume: bool = False, force: bool = False) -> Path:
    """Refuse an output folder that cannot be written, or that holds results unless told what to do.

    Nothing is changed here: with ``force`` the earlier results are discarded only when the run
    starts (after the FMUs are built), with ``resume`` they are kept.

    Raises
    ------
    OutputError
        If ``directory`` is a file, lies under a file or in a folder that is not writable, is
        being written by another run (:class:`cosim.folder_lock.FolderBusy`), or already holds
        results of an earlier run and neither ``resume`` nor ``force`` is given.
    """
    if resume and force:
        raise OutputError("give either --resume (keep the results) or --force (discard them), not both")
    directory = check_output_folder(directory)
    check_not_busy(directory)  # another run writing it: named, rather than its results
    found = has_results(directory)
    if found and not (resume or force):
        raise OutputError(f"output folder '{directory}' already holds the results of an earlier run "
                          f"({found} cases in {RESULTS}): give --resume to keep them and run only the "
                          "missing and failed cases, or --force to discard them")
    return directory


def _write_json(path: Path, data: dict) -> None:
    write_text(path, json.dumps(data, indent=2) + "\n")


def sample_note(spec: MatrixSpec, n: int) -> str:
    """How a sample of ``n`` cases of ``spec`` is chosen, in words (one line)."""
    studies = f" of each of the {len(spec.studies)} studies" if len(spec.studies) > 1 else ""
    if spec.sample_covers_axes(n):
        shown = "every value of every axis appears"
    else:
        shown = "too few for every value of every axis: each axis's values spread evenly"
    return (f"a stratified sample (Latin hypercube) across the axes{studies}, the same every run; {shown}")


def run_matrix(spec: MatrixSpec | str | Path, directory: str | Path | None = None, *, workers: int | None = None,
               scheduler: str | None = None, resume: bool = False, force: bool = False, keep_failed: bool = False,
               max_cases: int | None = None, fmu_dir: str | Path | None = None, progress: bool = True,
               report: bool = True, stream=None) -> MatrixResult:
    """Run every case of a spec not yet in ``directory/results.jsonl`` (with ``resume``), then check and report.

    Parameters
    ----------
    spec : MatrixSpec or path or bundled name
    directory : output folder (default ``matrix-<name>``)
    workers : local worker processes (>= 1; default: the number of CPUs); ignored with ``scheduler``
    scheduler : address of a Dask scheduler (``tcp://HOST:PORT``), contacted before any work
    resume : keep the results of an earlier (interrupted) run and run only the missing cases and,
        unless ``keep_failed``, the failed ones again
    force : discard the results of an earlier run in ``directory`` (without ``resume`` or
        ``force``, a folder with results is refused)
    keep_failed : with ``resume``, keep failed cases as they are instead of running them again
    max_cases : run at most this many cases: a spec with more runs a stratified sample of them
        (:meth:`MatrixSpec.cases`; one line on stderr says how many and how they were chosen), its
        other cases never expanded. ``None``: every case, a spec of more than
        :data:`~cosim.matrix.spec.MAX_CASES` refused before its axes are expanded
    fmu_dir : where models are built (default: the project's ``fmus/``)

    Raises
    ------
    SpecError, OutputError, SchedulerError, BuildError
        Before any case is run, each with one message (see the module docstring).
    """
    # deferred: loads fmpy, numpy, which importing this module does not
    from cosim.matrix.pool import connect

    started = time.perf_counter()
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise SpecError(f"workers must be a whole number >= 1, got {workers!r}")
    if max_cases is not None and (isinstance(max_cases, bool) or not isinstance(max_cases, int) or max_cases < 1):
        raise SpecError(f"max_cases must be a whole number >= 1, got {max_cases!r}")
    if keep_failed and not resume:
        raise SpecError("--keep-failed applies only with --resume")
    sample = max_cases is not None
    if not isinstance(spec, MatrixSpec):
        spec = load_spec(spec, max_cases or MAX_CASES, sample=sample)
    if not sample:
        spec.check_count(MAX_CASES)
    total = spec.count
    note = sample_note(spec, max_cases) if sample and total > max_cases else ""
    directory = prepare_directory(Path(directory or f"matrix-{spec.name}"), resume, force)
    if fmu_dir is not None:
        check_output_folder(fmu_dir, "FMU folder")
    workers = workers or os.cpu_count() or 1
    client = connect(scheduler) if scheduler else None  # an unreachable scheduler: one message, now
    try:
        _import_plugins(spec)
        cases = spec.cases(max_cases)
        if note:
            note = f"running {len(cases)} of {total} cases (--max-cases {max_cases}): {note}"
        check_names(cases, str(spec.path or spec.name))  # before anything is built
        # one run writes a folder at a time: a second one is refused here, naming the first
        with folder_lock(directory):
            prepare_directory(directory, resume, force)  # again: a run that ended meanwhile left results
            result = _run_locked(spec, cases, directory, client, scheduler, workers, resume, keep_failed,
                                 fmu_dir, progress, stream, started, note)
            if report:
                result.report = _write_report(result)
    finally:
        if client is not None:
            client.close()
    return result


def _run_locked(spec, cases, directory, client, scheduler, workers, resume, keep_failed, fmu_dir, progress,
                stream, started, note="") -> MatrixResult:
    """:func:`run_matrix` holding the output folder's lock: build, dispatch, store, check."""
    # deferred: loads numpy, which importing this module does not
    from cosim.matrix import checks as checks_mod

    fmu_paths = build_fmus(cases, fmu_dir, workers)
    if note:  # after the last check of the input: a refusal stays one line
        print(f"cosim matrix: {note}", file=sys.stderr, flush=True)
    with ResultStore(directory, resume, retry_failed=resume and not keep_failed) as store:
        _write_json(directory / "matrix.json", {
            "spec": str(spec.path) if spec.path else spec.name, "name": spec.name, "digest": spec.digest,
            "cases": len(cases), "spec_cases": spec.count, "sample": note or None, "fmus": fmu_paths,
            "scheduler": scheduler,
            "workers": None if scheduler else workers})
        done = {k for k in store.keys()} & {c.key for c in cases}
        todo = [c for c in cases if c.key not in done]
        timing = _dispatch(todo, spec, fmu_paths, directory, client, workers, store,
                           Progress(len(cases), len(done), stream=stream, enabled=progress))
    stored = store.records
    records = [stored[c.key] for c in cases if c.key in stored]
    retried = len(store.retried & {c.key for c in cases})
    result = MatrixResult(spec=spec, directory=directory, cases=cases, records=records, ran=len(todo),
                          resumed=len(done), retried=retried, timing=timing, total=spec.count, sample=note)
    result.checks = checks_mod.evaluate(spec, cases, records, fmu_paths)
    result.seconds = time.perf_counter() - started
    return result


def _write_report(result: MatrixResult) -> dict:
    """The report files; one that cannot be written says that the results are kept."""
    try:
        return write_report(result)
    except OutputError as exc:
        raise ResultNotWritten(f"{exc}; the {len(result.records)} case results are kept in "
                               f"'{result.directory / RESULTS}' (--resume writes the report)") from None


def _import_plugins(spec: MatrixSpec) -> None:
    """The spec's imports (blocks and their linear models), a failing one named in one message."""
    # deferred: loads fmpy, numpy, which importing this module does not
    from cosim.matrix.worker import import_plugins

    for item in spec.imports:
        try:
            import_plugins([item])
        except Exception as exc:  # the user's module: any error it raises is a spec error
            raise SpecError(f"{spec.path or spec.name}: [matrix] imports: '{item}' cannot be imported: "
                            f"{type(exc).__name__}: {exc}") from None


def _dispatch(todo: list[Case], spec: MatrixSpec, fmu_paths: dict, directory: Path, client, workers: int,
              store: ResultStore, bar) -> dict:
    """Run ``todo`` on the Dask ``client`` or local workers, each record stored as it arrives."""
    # deferred: loads fmpy, numpy, which importing this module does not
    from cosim.matrix.pool import run_dask, run_local

    init = {"imports": spec.imports, "fmu_paths": fmu_paths}
    timeout = max((float(c.settings["timeout"]) for c in todo), default=1.0)

    def on_record(record: dict) -> None:
        if "line" in record:
            store.append_line(record["key"], record["line"])
        else:
            store.append(record)
        bar.update(record)

    try:
        payload = [c.to_dict() for c in todo]
        if client is not None:
            t0 = time.perf_counter()
            run_dask(payload, init, client, on_record, timeout)
            return {"startup": 0.0, "run": time.perf_counter() - t0}
        logs = directory / "logs"
        try:
            logs.mkdir(exist_ok=True)
        except OSError as exc:
            raise OutputError(f"log folder '{logs}': {exc.strerror or exc}") from None
        cpu = time.process_time()
        timing = run_local(payload, init, workers, on_record, timeout, logs)
        timing["supervisor_cpu"] = time.process_time() - cpu
        return timing
    finally:
        bar.close()
