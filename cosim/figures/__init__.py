"""`cosim figures`: the paper's figures, each made by one module of this package.

A figure module defines ``NAME`` (e.g. ``"fig5"``) and ``make(output: Path) -> list[Path]``, which
computes the figure from FMU simulations or linearizations and writes image files. A figure whose
computation falls into independent parts (fig7: two bicycles) also defines ``parts() ->
list[(function, args)]`` and ``make(output, computed=None)``, which draws from the parts' results
(in the order of ``parts()``; computed by ``make`` itself when not given).

:func:`make_figures` runs the figures and parts in a pool of worker processes (``jobs``), the
longest first, forked after the imports; every part and figure is computed as in one process,
so the files do not depend on the number of workers.
"""
from __future__ import annotations

import importlib
import multiprocessing
import os
import pkgutil
import signal
import sys
import threading
from concurrent.futures import FIRST_EXCEPTION, ProcessPoolExecutor, wait
from multiprocessing.util import Finalize
from pathlib import Path

from cosim.errors import ParameterError
from cosim.fmu import access
from cosim.folder_lock import folder_lock
from cosim.outputs import atomic_output, check_output_folder
from cosim.processes import die_with_parent, stop_pool
from cosim.progress import active as progress

#: Figures in the order the workers start them, the longest computations first; figures not
#: listed follow in the registry's order.
LONGEST_FIRST = ("fig7", "fig13", "fig5", "fig10", "fig15", "fig8", "fig9")


def registry() -> dict:
    """Figure name -> module, for every figure module of this package."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        if hasattr(module, "NAME") and hasattr(module, "make"):
            found[module.NAME] = module
    return dict(sorted(found.items(), key=lambda item: (len(item[0]), item[0])))


def make_figures(names: list[str], output: str | Path, jobs: int | None = None) -> list[Path]:
    """Make the named figures (all if ``names`` is empty) into ``output``.

    Parameters
    ----------
    names : list of str
        Figure names (``fig5``, ...); empty: all.
    output : path
        The folder of the files.
    jobs : int, optional
        Worker processes (default: the CPUs this process may use, :func:`default_jobs`); 1
        computes everything in this process. The files are the same for any number.

    Returns
    -------
    list of Path
        The files written, figure by figure in the order of ``names``.

    Raises
    ------
    ParameterError
        For an unknown figure name, or ``jobs`` < 1.
    OutputError
        If ``output`` cannot be a writable folder, or another command is writing it
        (:class:`cosim.folder_lock.FolderBusy`), before any figure is computed.
    """
    figures = registry()
    unknown = [n for n in names if n not in figures]
    if unknown:
        raise ParameterError(f"unknown figure(s) {', '.join(unknown)}; available: {', '.join(figures)}")

    output = check_output_folder(output, "figures folder")  # before any figure is computed
    names = list(dict.fromkeys(names)) or list(figures)
    jobs = default_jobs() if jobs is None else jobs
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ParameterError(f"-j/--jobs must be >= 1, got {jobs!r}")
    with folder_lock(output, "figures folder"):  # one command writes the folder at a time
        if jobs == 1 or (len(names) == 1 and not hasattr(figures[names[0]], "parts")):
            with progress().steps(len(names)):
                return [path for name in names for path in _make_in_turn(name, figures[name], output)]
        return _make_in_pool({name: figures[name] for name in names}, output, jobs)


def _make_in_turn(name: str, module, output: Path) -> list[Path]:
    """One figure in this process, its start reported (with ``-v`` its time and files)."""
    reporter = progress()
    reporter.item(name)
    paths = module.make(output)
    reporter.detail(f"{name}: {', '.join(map(str, paths))} ({reporter.elapsed():.1f} s)")
    return paths


def default_jobs() -> int:
    """The CPUs this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _make_in_pool(modules: dict, output: Path, jobs: int) -> list[Path]:
    """:func:`make_figures` with ``jobs`` worker processes: the parts of the figures that have
    parts, then every other figure, the longest first (:data:`LONGEST_FIRST`); a figure with
    parts is drawn here once its parts are done. The paths come in the order of ``modules``."""
    order = sorted(modules, key=lambda n: LONGEST_FIRST.index(n) if n in LONGEST_FIRST else len(LONGEST_FIRST))
    parted = {name for name in order if hasattr(modules[name], "parts")}
    tasks = [(name, function, args) for name in order if name in parted for function, args in modules[name].parts()]
    tasks += [(name, modules[name].make, (output,)) for name in order if name not in parted]
    pyplot()  # imported before the fork: the workers inherit it
    # fork (the workers start at once with this process's imports) where it is safe: Linux, one thread
    fork = sys.platform.startswith("linux") and threading.active_count() == 1
    context = multiprocessing.get_context("fork" if fork else "spawn")
    pool = ProcessPoolExecutor(max_workers=min(jobs, len(tasks)), mp_context=context,
                               initializer=_init_worker, initargs=(os.getpid(),))
    with progress().steps(len(tasks)):
        return _run_pool(pool, tasks, modules, order, parted, output)


def _run_pool(pool, tasks: list, modules: dict, order: list, parted: set, output: Path) -> list[Path]:
    """The tasks of :func:`_make_in_pool` in ``pool``, each counted when it finishes."""
    try:
        futures = [pool.submit(function, *args) for _, function, args in tasks]
        for (name, _, _), future in zip(tasks, futures):  # counted as they finish, in the pool's thread
            future.add_done_callback(lambda done, name=name: _finished(name, done))
        written: dict[str, list[Path]] = {}
        for name in order:  # the figures with parts first: drawn here while the workers go on
            mine = [future for (n, _, _), future in zip(tasks, futures) if n == name]
            wait(mine, return_when=FIRST_EXCEPTION)
            results = [future.result() for future in mine]  # the first error is raised here
            written[name] = modules[name].make(output, computed=results) if name in parted else results[0]
    except BaseException:
        stop_pool(pool)
        raise
    pool.shutdown(wait=True)
    return [path for name in modules for path in written[name]]


def _finished(name: str, future) -> None:
    """A task of the pool ended: counted unless it was cancelled or failed (the error says that)."""
    if not future.cancelled() and future.exception() is None:
        progress().item(name)
        paths = future.result()
        if isinstance(paths, list):  # a whole figure's files (a part's numbers are drawn here later)
            progress().detail(f"{name}: {', '.join(map(str, paths))}")


def _init_worker(parent: int) -> None:
    """Initializer of a pool worker: Ctrl-C is left to the parent, which stops the workers; a
    worker ends with its parent, removing the FMUs it unpacked (its exit skips atexit)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent(parent, cleanup=_remove_own_extractions)
    Finalize(None, _remove_own_extractions, exitpriority=1)


def _remove_own_extractions() -> None:
    own = access._PROCESS_FOLDER
    if own is not None and own[0] == os.getpid():
        access._remove_extracted(*own)


def save(fig, path: Path) -> Path:
    """Save a matplotlib figure (format by suffix) atomically and close it."""
    import matplotlib.pyplot as plt

    try:
        with atomic_output(path, "figure") as tmp:
            fig.savefig(tmp, dpi=120, bbox_inches="tight")
    finally:
        plt.close(fig)
    return Path(path)


def pyplot():
    """matplotlib.pyplot with a non-interactive backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
