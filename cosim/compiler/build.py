"""`cosim build`: Modelica model -> FMU (FMI 2.0 and/or 3.0), incremental and in parallel.

An FMI 2.0 FMU goes to ``OUTPUT/NAME.fmu``, an FMI 3.0 FMU to ``OUTPUT/fmi3/NAME.fmu``: the two
versions of one model are built from one flattening and one symbolic differentiation and never
invalidate each other.

Safe to run concurrently and to kill:

- a build of one model into one folder holds an exclusive lock (``OUTPUT/.NAME.fmu.lock``,
  :mod:`cosim.folder_lock`): a second build of the same model into the same folder waits, then
  finds the FMU up to date; builds of other models into the folder run side by side; the FMU
  itself is written to a temporary name and renamed when complete;
- the pool workers of a parallel build die with their parent (``kill -9`` of `cosim build`
  included): they stop their compilers, remove their temporary files and exit, and never
  write an FMU after the command is gone.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import signal
import tempfile
import time
import uuid
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path

from cosim.errors import BuildError, CosimError, ModelicaError, OutputError, ParameterError
from cosim.folder_lock import held_lock_files, lock_file, unlock_file
from cosim.outputs import (check_output_folder, make_temporary_folder, name_max, os_error_message,
                           temporary_folder)
from cosim.processes import die_with_parent, stop_pool
from cosim.progress import active as progress
from cosim.compiler import fmu as fmu_files
from cosim.compiler import schedule
from cosim.compiler.library import compiler_digest  # noqa: F401 (cosim.compiler.build.compiler_digest)
from cosim.compiler.library import tool_versions as _tool_versions
from cosim.compiler.codegen import (FMI_VERSIONS, casadi_functions, generated_sources, unoptimized_sources,
                                    write_sources)
from cosim.compiler.description import describe
from cosim.compiler.flatten import fewer_collections, flatten
from cosim.compiler.fmu import MANIFEST, compile_binary, pack, platform_folder, read_manifest
from cosim.compiler.library import Library, load_library
from cosim.compiler.model_description import build_description_xml, model_description_xml
from cosim.compiler.ode import make_explicit
from cosim.compiler.catalog import cache_folder

# Where `cosim build` and every command that builds on demand put FMUs: fmus/ of the working
# directory (never the installed package), or the folder named by COSIM_FMU_DIR (the tests point
# it to a temporary folder).
DEFAULT_OUTPUT = Path(os.environ.get("COSIM_FMU_DIR") or Path.cwd() / "fmus").absolute()


def runtime_cache() -> Path:
    """``$XDG_CACHE_HOME/cosim/runtime``: the compiled runtime, one object per runtime source,
    compiler and flags (:func:`cosim.compiler.fmu.load_runtime_object`), compiled once per
    machine, not per FMU nor per output folder (a clean build of the library does not compile it
    again; like ccache, the object is keyed by everything it is made from)."""
    return cache_folder() / "runtime"


@dataclass
class BuildResult:
    """What `cosim build` did for one model."""

    model: str
    fmu: Path
    rebuilt: bool
    seconds: float = 0.0
    fmi_version: str = "2"  # "2": FMI 2.0, "3": FMI 3.0


def _fingerprint(flat, entry) -> str:
    """Hash of everything the FMU is made from: the flat equations, declarations, parameter
    values, annotations and the compiler itself."""
    m = flat.casadi
    h = hashlib.sha256(compiler_digest().encode())
    parts = [flat.name, entry.description, repr(entry.annotation), repr(sorted(flat.declarations.items()))]
    parts += [str(e) for e in m.equations] + [str(e) for e in m.initial_equations]
    for group in (m.states, m.der_states, m.alg_states, m.inputs, m.outputs, m.parameters, m.constants):
        parts += [f"{getattr(v, 'symbol', v)}={getattr(v, 'value', '')}|{getattr(v, 'start', '')}" for v in group]
    for part in parts:
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


# Subfolder of the output folder for FMI 3.0 FMUs (FMI 2.0 FMUs keep the output folder itself).
FMI3_FOLDER = "fmi3"


def fmu_path(model_name: str, output: Path, fmi_version: str = "2") -> Path:
    """Where `cosim build` puts the FMU of ``model_name``: ``OUTPUT/NAME.fmu`` for FMI 2.0,
    ``OUTPUT/fmi3/NAME.fmu`` for FMI 3.0 (``fmi_version`` "2" or "3")."""
    folder = Path(output) / FMI3_FOLDER if _fmi_version(fmi_version) == "3" else Path(output)
    return folder / f"{model_name.replace('.', '_')}.fmu"


def _fmi_version(value) -> str:
    """``value`` ("2", "3", 2, 3, "2.0", "3.0") as "2" or "3"; ParameterError otherwise."""
    version = str(value).strip().removesuffix(".0")
    if version not in FMI_VERSIONS:
        raise ParameterError(f"FMI version must be 2 or 3, got {value!r}")
    return version


def _fmi_versions(values) -> tuple[str, ...]:
    """The FMI versions to build, without repeats, in the order 2, 3."""
    if isinstance(values, (str, int)):
        values = (values,)
    versions = {_fmi_version(v) for v in values}
    if not versions:
        raise ParameterError("no FMI version to build (choose 2, 3 or both)")
    return tuple(v for v in FMI_VERSIONS if v in versions)


# --- one build of a model into a folder at a time ---------------------------------------------

@contextlib.contextmanager
def _build_lock(target: Path):
    """Hold the exclusive lock of building ``target`` (``.NAME.fmu.lock`` beside it), waiting
    while another build of it runs (:func:`cosim.folder_lock.lock_file`). The lock file is
    removed when the lock is released, so none is left behind."""
    lock = target.parent / f".{target.name}.lock"
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"output folder '{target.parent}': cannot lock {lock.name}: "
                          f"{exc.strerror or exc}") from None
    fd = lock_file(lock, wait=True, what=f"output folder '{target.parent}'")
    try:
        yield
    finally:
        unlock_file(fd)


def _remove_stale_lock(target: Path) -> None:
    """Remove the lock file a killed build left, unless a live build holds it."""
    import fcntl

    lock = target.parent / f".{target.name}.lock"
    try:
        fd = os.open(lock, os.O_RDWR)
    except OSError:
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        if os.path.samestat(os.fstat(fd), os.stat(lock)):
            os.unlink(lock)
    except OSError:
        pass  # held by a live build (or already gone): not stale
    finally:
        os.close(fd)


def build_model(model_name: str, output: str | Path = DEFAULT_OUTPUT, library: Library | None = None,
                force: bool = False, fmi_version: str = "2") -> BuildResult:
    """Compile one Modelica model to an FMU (ME + CS), unless up to date.

    A concurrent build of the same model into the same folder is waited for (then the FMU is
    usually up to date); the FMU appears under its name only when complete.

    Parameters
    ----------
    model_name : str
        Full Modelica name, e.g. ``"Bicycle.Bicycles.SelfStabilizing"``.
    output : path, optional
        Folder of the FMU (default: ``$COSIM_FMU_DIR``, else ``./fmus`` of the working directory).
    library : Library, optional
        Default: ``load_library()`` (the folders of ``$COSIM_MODELICA_PATH`` and the shipped library).
    force : bool
        Rebuild even if up to date.
    fmi_version : {"2", "3"}
        FMI 2.0 (``OUTPUT/<identifier>.fmu``) or FMI 3.0 (``OUTPUT/fmi3/<identifier>.fmu``).

    Returns
    -------
    BuildResult
        ``fmu`` (path), ``rebuilt`` (False if it was up to date), ``seconds`` [s] spent.

    Raises
    ------
    UnknownModelError, ModelicaError, ModelStructureError, BuildError
    ParameterError
        If ``fmi_version`` is not 2 or 3 (or a parameter of the model is invalid).
    OutputError
        If the output folder cannot be written (before any work) or the FMU cannot be stored.
    """
    return build_versions(model_name, output, library, force, (fmi_version,))[0]


def build_versions(model_name: str, output: str | Path = DEFAULT_OUTPUT, library: Library | None = None,
                   force: bool = False, fmi_versions=("2",)) -> list[BuildResult]:
    """:func:`build_model` for several FMI versions at once: the model is flattened and
    differentiated once for all of them. Returns one result per version, in the order 2, 3."""
    started = time.perf_counter()
    versions = _fmi_versions(fmi_versions)
    output = check_output_folder(output)
    library = library or load_library()
    entry = library.entry(model_name)
    targets = {v: fmu_path(model_name, output, v) for v in versions}
    _check_file_name(model_name, targets[versions[0]])  # (FMI 3's has the same name, in fmi3/)
    for target in targets.values():
        try:
            in_the_way = target.is_dir()
        except OSError as exc:  # e.g. a model name longer than a file name may be
            raise OutputError(f"cannot write the FMU '{target}': {exc.strerror or exc}") from None
        if in_the_way:
            raise OutputError(f"cannot write the FMU '{target}': a folder of that name is in the way")
    with contextlib.ExitStack() as locks:
        for version in versions:  # always in the order 2, 3: two builds cannot wait on each other
            locks.enter_context(_build_lock(targets[version]))
        locks.enter_context(fewer_collections())
        try:
            return _build_locked(model_name, targets, library, entry, force, started)
        except OutputError:
            raise
        except OSError as exc:  # the temporary build files: a full disk, a quota
            message = os_error_message(exc) if exc.filename else f"cannot write its build files: {exc.strerror or exc}"
            raise OutputError(f"{model_name}: {message}") from None


#: More than the characters the files written beside an FMU add to its name: the lock
#: ``.NAME.fmu.lock`` adds 6 (the partial file of :func:`cosim.outputs.atomic_output` keeps at most
#: 64 characters of the name, so it is never the longest).
_NAME_MARGIN = 18


def _check_file_name(model_name: str, target: Path) -> None:
    """Refuse a model whose FMU file name (the model name with ``_`` for ``.``, see
    :func:`fmu_path`) is longer than the output folder's file system allows, before any work.

    Raises
    ------
    BuildError
        Naming the model, the length and the limit.
    """
    folder = next((f for f in [target.parent, *target.parents] if f.is_dir()), Path("/"))
    limit = name_max(folder)
    length = len(os.fsencode(target.name))
    if length + _NAME_MARGIN > limit:
        raise BuildError(f"model name '{model_name}' is too long for an FMU file: its name '{target.name}' has "
                         f"{length} bytes, at most {limit - _NAME_MARGIN} fit in {folder} (with the temporary "
                         "and lock files beside it); give the model or its packages shorter names")


def _up_to_date(manifest: dict | None, version: str, key: str, value: str) -> bool:
    return bool(manifest) and manifest.get("fmi_version", "2") == version and manifest.get(key) == value


def _build_locked(model_name, targets, library, entry, force, started) -> list[BuildResult]:
    manifests = {v: read_manifest(target) if target.exists() else None for v, target in targets.items()}
    results = {}

    def up_to_date(key, value):
        for version, manifest in manifests.items():
            if version not in results and not force and _up_to_date(manifest, version, key, value):
                results[version] = BuildResult(model_name, targets[version], False, time.perf_counter() - started,
                                               version)
        return len(results) == len(targets)

    # Fast path: no source file and no part of the compiler changed since the FMU was built.
    sources_digest = hashlib.sha256((library.digest() + compiler_digest()).encode()).hexdigest()
    if up_to_date("sources_digest", sources_digest):
        return [results[v] for v in targets]
    flat = flatten(library, model_name)
    fingerprint = _fingerprint(flat, entry)
    if up_to_date("fingerprint", fingerprint):
        return [results[v] for v in targets]

    model = make_explicit(flat)
    info = describe(entry, flat, model)
    functions = casadi_functions(model)
    # The GUID (FMI 3: instantiationToken) identifies the model, the same in both FMI versions.
    guid_source = hashlib.sha256(fingerprint.encode())
    for f in functions:
        guid_source.update(f.serialize().encode())
    info.guid = "{" + str(uuid.UUID(guid_source.hexdigest()[:32])) + "}"
    versions = _tool_versions()
    tool = f"cosim {versions['cosim']} (pymoca {versions['pymoca']}, CasADi {versions['casadi']})"

    for version, target in targets.items():
        if version in results:
            continue
        with _scratch_folder() as tmp:
            staging = Path(tmp) / "fmu"
            sources = staging / "sources"
            files = write_sources(info, model, sources, functions, version)
            if version == "3":
                (sources / "buildDescription.xml").write_bytes(build_description_xml(info))
                files = sorted(files + ["buildDescription.xml"])
            (staging / "modelDescription.xml").write_bytes(model_description_xml(info, tool, version))
            binaries = staging / "binaries" / platform_folder(version)
            binaries.mkdir(parents=True)
            compile_binary(sources, info.identifier, binaries / f"{info.identifier}.so",
                           generated=tuple(generated_sources(info, version)),
                           unoptimized=tuple(unoptimized_sources(info, version)),
                           objects=Path(tmp) / "objects", cache=runtime_cache())
            source_hashes = {name: hashlib.sha256((sources / name).read_bytes()).hexdigest() for name in files}
            (staging / MANIFEST).parent.mkdir(parents=True, exist_ok=True)
            (staging / MANIFEST).write_text(json.dumps({
                "model": model_name,
                "fmi_version": version,
                "fingerprint": fingerprint,
                "sources_digest": sources_digest,
                "guid": info.guid,
                "modelica_files": [library.relative_name(p) for p in library.files],
                "tools": versions,
                "sources": source_hashes,
            }, indent=2, sort_keys=True) + "\n")
            pack(staging, target)
        results[version] = BuildResult(model_name, target, True, time.perf_counter() - started, version)
    return [results[v] for v in targets]


# --- pool workers die with their parent (cosim.processes), leaving nothing behind ------------

_scratch: set[Path] = set()  # temporary build folders of this process (removed if it is abandoned)
_scratch_root: Path | None = None  # in a pool worker: the parallel build's folder for temporary files
_PARENT_POLL = 0.2  # s between two looks of the watchdog at the parent


@contextlib.contextmanager
def _scratch_folder():
    """A temporary folder, registered so that an abandoned worker removes it: in the parallel
    build's folder, else ``TMPDIR/cosim-build-PID-*`` (one a killed build left is removed by
    the next build: :func:`cosim.outputs.temporary_folder`)."""
    with (tempfile.TemporaryDirectory(prefix="cosim-build-", dir=_scratch_root) if _scratch_root
          else temporary_folder("build")) as tmp:
        _scratch.add(Path(tmp))
        try:
            yield tmp
        finally:
            _scratch.discard(Path(tmp))


def _stop_children(timeout: float = 2.0) -> None:
    """SIGTERM to every descendant (gcc removes its temporary files on it), SIGKILL after
    ``timeout`` seconds to any that is left."""
    try:
        import psutil  # a core dependency: without it gcc would silently go on
    except ImportError as exc:  # a broken install: say so rather than leave compilers running
        raise BuildError(f"cannot stop the compiler processes: {exc}") from None
    try:
        children = psutil.Process().children(recursive=True)
    except psutil.Error:
        return
    for child in children:
        with contextlib.suppress(psutil.Error):
            child.terminate()
    _, alive = psutil.wait_procs(children, timeout=timeout)
    for child in alive:
        with contextlib.suppress(psutil.Error):
            child.kill()


def _clean_up_worker() -> None:
    """Leave nothing behind: stop the compiler, remove the temporary folder, the partial FMU
    and the lock. Run by :func:`cosim.processes.die_with_parent` when the parent has died."""
    _stop_children()
    for folder in list(_scratch):
        shutil.rmtree(folder, ignore_errors=True)
    if _scratch_root is not None:
        with contextlib.suppress(OSError):
            _scratch_root.rmdir()  # the last worker to go removes the build's folder
    for path in list(fmu_files.PARTIALS) + held_lock_files():
        with contextlib.suppress(OSError):
            os.unlink(path)


def _init_worker(parent: int, scratch_root: str | None = None) -> None:
    """Initializer of a pool worker: end (cleanly) as soon as ``parent`` is gone.

    Temporary build folders go into ``scratch_root``, which the parent removes when the build
    ends: so even a worker killed with SIGKILL leaves nothing behind. The parent-death signal is
    SIGTERM with a cleanup handler, and a watchdog covers a parent that died before this ran and
    a main thread busy in C. Ctrl-C is left to the parent, which stops the workers with SIGTERM.
    """
    global _scratch_root
    _scratch_root = Path(scratch_root) if scratch_root else None
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent(parent, poll=_PARENT_POLL, cleanup=_clean_up_worker)


def _build_one(args):
    """One task: the FMUs of one model in the FMI versions asked for (a list of results), or the error."""
    model_name, output, library_path, force, versions = args
    try:
        return build_versions(model_name, output, load_library(library_path), force, versions)
    except CosimError as exc:
        return exc


def _build_in_turn(task):
    """:func:`_build_one` in this process, its start and end reported."""
    progress().item(task[0])
    outcome = _build_one(task)
    _report(task[0], outcome, started=False)
    return outcome


def _report(model_name: str, outcome, started: bool = True) -> None:
    """The progress of a finished build task (``started``: its item is not shown yet, as for a
    task of the pool, which is reported when it ends); with ``-v`` a failure at once (the
    command's error lists every failure after the other builds)."""
    if started:
        progress().item(model_name)
    if isinstance(outcome, Exception):
        progress().detail(f"{model_name} failed: {str(outcome).splitlines()[0]}")


def _remove_stale_locks(task) -> None:
    model_name, output, _, _, versions = task
    for version in versions:
        _remove_stale_lock(fmu_path(model_name, Path(output), version))


def _run_parallel(tasks: list[tuple], jobs: int) -> list:
    scratch_root = str(make_temporary_folder("build"))  # TMPDIR/cosim-build-PID-*
    try:
        return _run_pool(tasks, jobs, scratch_root)
    finally:
        shutil.rmtree(scratch_root, ignore_errors=True)


def _run_pool(tasks: list[tuple], jobs: int, scratch_root: str) -> list:
    pool = ProcessPoolExecutor(max_workers=min(jobs, len(tasks)), initializer=_init_worker,
                               initargs=(os.getpid(), scratch_root))
    try:
        futures = {pool.submit(_build_one, task): k for k, task in enumerate(tasks)}
        results: list = [None] * len(tasks)
        for future in as_completed(futures):  # reported as they finish, kept in the order of the tasks
            task = tasks[futures[future]]
            try:
                results[futures[future]] = future.result()
            except BrokenProcessPool:
                _remove_stale_locks(task)
                results[futures[future]] = BuildError(f"{task[0]}: a build worker died unexpectedly (killed, or "
                                                      "out of memory?) while this model was built or waiting; "
                                                      "nothing was written for it")
            _report(task[0], results[futures[future]])
    except BaseException:
        stop_pool(pool)
        # A worker killed before its cleanup ran (e.g. SIGKILL after the grace period of a
        # loaded machine) leaves its lock file: the workers are gone now, so remove the stale ones.
        for task in tasks:
            _remove_stale_locks(task)
        raise
    pool.shutdown(wait=True)
    return results


def _combined(errors: list[Exception]) -> Exception:
    """The first error; with more than one, its message lists the others too."""
    first = errors[0]
    if len(errors) == 1:
        return first
    others = "\n  ".join(str(e).splitlines()[0] for e in errors[1:])
    text = f"{first}\n{len(errors) - 1} more failed:\n  {others}"
    try:
        combined = type(first)(text)
    except Exception:
        combined = BuildError(text)
    return combined


def build(models: list[str] | None = None, output: str | Path = DEFAULT_OUTPUT, jobs: int = 1,
          library_path: str | None = None, force: bool = False, fmi_versions=("2",)) -> list[BuildResult]:
    """Build several models (default: every exported model), ``jobs`` at a time, as FMI 2.0
    and/or FMI 3.0 FMUs.

    All models are attempted; if any fails, the first error is raised after the others finished
    (their FMUs are complete, the failed one leaves nothing behind; the error's ``results``
    attribute holds what was built). A model of a Modelica file that did not parse fails with
    that file's error; without a list of models, every such file counts as a failure.

    Parameters
    ----------
    models : list of str, optional
        Full Modelica names (default: every model with ``annotation(__Cosim(export = true))``).
    output : path, optional
        Folder of the FMUs (default: ``$COSIM_FMU_DIR``, else ``./fmus`` of the working directory).
    jobs : int
        Parallel builds (>= 1); worker processes die with the calling process. They start the
        models whose last builds took longest first (:mod:`cosim.compiler.schedule`).
    library_path : path, optional
        Modelica library folder(s), searched before the shipped library (default:
        ``$COSIM_MODELICA_PATH``).
    force : bool
        Rebuild even if up to date.
    fmi_versions : sequence of {"2", "3"}
        The FMI versions to build (default: FMI 2.0 only): FMI 2.0 FMUs go to ``output``, FMI 3.0
        FMUs to ``output/fmi3``. Both versions of a model are built by one task from one
        flattening and differentiation.

    Returns
    -------
    list of BuildResult
        One per model and FMI version, in the order given (FMI 2 before FMI 3); ``seconds`` [s] each.

    Raises
    ------
    ParameterError
        If ``jobs`` < 1 or an FMI version is not 2 or 3.
    OutputError
        If ``output`` cannot be a writable folder (before any work).
    UnknownModelError
        If a name is not a model of the library (before any work).
    """
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ParameterError(f"-j/--jobs must be >= 1, got {jobs!r}")
    versions = _fmi_versions(fmi_versions)
    output = check_output_folder(output)
    library = load_library(library_path)
    names = list(dict.fromkeys(models)) if models else [e.name for e in library.models(exported_only=True)]
    for name in names:
        try:
            library.entry(name)  # unknown names fail before any work starts
        except ModelicaError:
            pass  # a model of a file that did not parse fails in its turn; the others are built
    parallel = jobs > 1 and len(names) > 1
    started = schedule.longest_first(names) if parallel else names
    tasks = [(name, str(output), library_path, force, versions) for name in started]
    with progress().steps(len(tasks)):
        done = dict(zip(started, _run_parallel(tasks, jobs) if parallel else map(_build_in_turn, tasks)))
    outcomes = [done[name] for name in names]
    schedule.record({outcome[0].model: max(r.seconds for r in outcome) for outcome in outcomes
                     if isinstance(outcome, list) and outcome and any(r.rebuilt for r in outcome)})
    results = [r for outcome in outcomes for r in (outcome if isinstance(outcome, list) else [outcome])]
    errors = [r for r in results if isinstance(r, Exception)]
    if not models:  # "everything" includes the files that did not parse (once each)
        errors += [e for e in library.errors.values() if not any(str(e) in str(r) for r in errors)]
    if errors:
        error = _combined(errors)
        error.results = [r for r in results if isinstance(r, BuildResult)]
        raise error
    return results
