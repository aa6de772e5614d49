"""Executing cases: a local pool of worker processes, or a Dask cluster.

Process isolation: every case runs in a worker *process* of our own -- forked from the
supervisor on Linux (it inherits the imports: start-up in milliseconds), else ``python -m
cosim.matrix.worker`` -- that the supervisor talks to over pipes. When a worker dies (an FMU
segfaults, it is killed, it runs out of time) the supervisor sees the end of its pipe, records
that one case as failed with the signal and the tail of the worker's log, starts a fresh worker and
goes on. Unlike ``ProcessPoolExecutor``, nothing else breaks.

With Dask (``--scheduler tcp://HOST:PORT``) cases are sent in chunks as tasks; each Dask worker
thread keeps one such worker process of its own, so a crash fails one case and the Dask worker
lives on. The scheduler is contacted before any work (:func:`connect`): one that cannot be
reached within :data:`SCHEDULER_TIMEOUT` seconds is one message naming its address.

Workers die with their parent (:func:`cosim.processes.die_with_parent`, given the parent's pid on
the command line): ``kill -9`` of the supervisor (or of the Dask worker) leaves no process behind.
"""
from __future__ import annotations

import json
import math
import os
import selectors
import signal
import subprocess
import sys
import threading
import time
import uuid
from collections import deque
from pathlib import Path

from cosim.errors import CosimError, MissingExtraError
from cosim.matrix.worker import (BLAS_THREAD_VARIABLES, failed_record, import_plugins, read_message, serve,
                                 set_blas_threads, warm_fmus, warm_imports, warm_up, write_message)
from cosim.fmu import access
from cosim.processes import die_with_parent

_PACKAGE_ROOT = str(Path(__file__).resolve().parents[2])

#: Seconds to wait for the Dask scheduler to answer before giving up.
SCHEDULER_TIMEOUT = 5.0


class WorkerDied(Exception):
    pass


class SchedulerError(CosimError, ConnectionError):
    """The Dask scheduler cannot be reached, or was lost during the run; the message names it."""


def _signal_name(returncode: int | None) -> str:
    if returncode is None:
        return "still running"
    if returncode < 0:
        try:
            return f"{signal.Signals(-returncode).name} (signal {-returncode})"
        except ValueError:
            return f"signal {-returncode}"
    return f"exit status {returncode}"


#: How local workers are started: ``fork`` (Linux, from a single-threaded supervisor: the worker
#: inherits the imports and starts in milliseconds) or ``spawn`` (a new ``python -m
#: cosim.matrix.worker``: 0.2 s or more per worker; always from threads, e.g. Dask's). ``auto``
#: picks fork where it is safe. The environment variable ``COSIM_MATRIX_START`` overrides it.
START_METHODS = ("auto", "fork", "spawn")

_forked_fds: set[int] = set()   # the supervisor's ends of the pipes of forked workers


def start_method(requested: str | None = None) -> str:
    """``fork`` or ``spawn`` for a worker started now (see :data:`START_METHODS`).

    Fork is used only where it is safe: on Linux, and from a process with a single thread (a
    fork copies only the calling thread; a lock another thread held stays locked in the child)."""
    method = (requested or os.environ.get("COSIM_MATRIX_START") or "auto").strip().lower()
    if method not in START_METHODS:
        raise ValueError(f"COSIM_MATRIX_START must be one of {', '.join(START_METHODS)}, got {method!r}")
    if method == "spawn":
        return "spawn"
    safe = sys.platform.startswith("linux") and threading.active_count() == 1 and hasattr(os, "fork")
    return "fork" if safe else "spawn"


def _remove_own_extractions() -> None:
    """Remove the FMU extraction folder of this (forked) process: ``os._exit`` skips the atexit
    hook that removes it -- and must, since the inherited hooks are the supervisor's."""
    try:
        own = access._PROCESS_FOLDER
        if own is not None and own[0] == os.getpid():
            access._remove_extracted(*own)
    except BaseException:  # never keep a dying worker from exiting
        pass


class _Forked:
    """A worker forked from the supervisor, with the part of the :class:`subprocess.Popen`
    interface :class:`Child` uses (``stdin``, ``stdout``, ``pid``, ``poll``, ``wait``, ``kill``,
    ``returncode``)."""

    def __init__(self, init: dict, log_path: Path | None):
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        parent = os.getpid()
        log_fd = os.open(log_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644) if log_path else \
            os.open(os.devnull, os.O_WRONLY)
        for stream in (sys.stdout, sys.stderr):  # else the child would write their buffers again
            try:
                stream.flush()
            except (AttributeError, OSError, ValueError):  # None (no console), closed
                pass

        set_blas_threads(1)  # the child inherits it (run_local restores the supervisor's count)
        pid = os.fork()
        if pid == 0:  # the worker: never returns into the supervisor's code
            code = 1
            try:
                os.setsid()  # as start_new_session: Ctrl-C at the terminal goes to the supervisor only
                # the other workers' pipes (their EOF must not depend on this one) and the parent's ends
                for fd in (_forked_fds - {to_child_r, from_child_w, log_fd}) | {to_child_w, from_child_r}:
                    try:
                        os.close(fd)
                    except OSError:
                        pass
                os.dup2(log_fd, 1)  # stray output (C printf of FMUs, print) goes to the log
                os.dup2(log_fd, 2)
                os.close(log_fd)
                devnull = os.open(os.devnull, os.O_RDONLY)
                os.dup2(devnull, 0)
                os.close(devnull)
                sys.stdout = sys.stderr = open(2, "w", buffering=1, closefd=False)
                sys.stdin = None
                import faulthandler

                # as in a spawned worker: a crash is reported by the supervisor (signal and log
                # tail), not by a dump the supervisor's faulthandler (pytest's) writes to its stderr
                faulthandler.disable()

                die_with_parent(parent)

                # one BLAS thread, inherited (set before the fork: see cosim.matrix.worker)
                code = serve(os.fdopen(to_child_r, "rb", buffering=0), os.fdopen(from_child_w, "wb", buffering=0),
                             init)
            except BaseException:
                try:
                    import traceback

                    traceback.print_exc()
                    sys.stderr.flush()
                except BaseException:
                    pass
            finally:
                _remove_own_extractions()
                os._exit(code)
        os.close(log_fd)
        os.close(to_child_r)
        os.close(from_child_w)
        self.pid = pid
        self.returncode: int | None = None
        self.stdin = os.fdopen(to_child_w, "wb", buffering=0)
        self.stdout = os.fdopen(from_child_r, "rb", buffering=0)
        self._fds = {to_child_w, from_child_r}
        _forked_fds.update(self._fds)

    def poll(self) -> int | None:
        if self.returncode is None:
            try:
                pid, status = os.waitpid(self.pid, os.WNOHANG)
            except ChildProcessError:  # reaped elsewhere (SIGCHLD ignored): the status is lost
                self.returncode = -signal.SIGKILL
            else:
                if pid:
                    self.returncode = os.waitstatus_to_exitcode(status)
                    _forked_fds.difference_update(self._fds)
        return self.returncode

    def wait(self, timeout: float | None = None) -> int:
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.poll() is None:
            if deadline is not None and time.monotonic() > deadline:
                raise subprocess.TimeoutExpired(f"worker {self.pid}", timeout)
            time.sleep(0.001)
        return self.returncode

    def kill(self) -> None:
        if self.poll() is None:
            os.kill(self.pid, signal.SIGKILL)


class Child:
    """One worker process; ``init`` = {"imports": [...], "fmu_paths": {...}}; ``start`` one of
    :data:`START_METHODS` (default: ``COSIM_MATRIX_START``, else ``auto``)."""

    START_TIMEOUT = 300.0

    def __init__(self, init: dict, log_path: Path | None = None, wait: bool = True, start: str | None = None):
        self.init = init
        self.log_path = log_path
        self.method = start_method(start)
        if self.method == "fork":
            self.proc = _Forked(init, log_path)
        else:
            env = dict(os.environ)
            env["PYTHONPATH"] = _PACKAGE_ROOT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
            env.update({name: "1" for name in BLAS_THREAD_VARIABLES})  # the workers are the parallelism
            log = open(log_path, "ab") if log_path else subprocess.DEVNULL
            try:
                # the pid of the parent as it sees itself: the worker dies with it (cosim.processes)
                self.proc = subprocess.Popen([sys.executable, "-m", "cosim.matrix.worker",
                                              "--parent", str(os.getpid())],
                                             stdin=subprocess.PIPE,
                                             stdout=subprocess.PIPE, stderr=log, bufsize=0, env=env,
                                             start_new_session=True)
            finally:
                if log_path:
                    log.close()
        self.case: dict | None = None
        self.started = 0.0
        self.pid = None
        if self.method == "spawn":  # a forked worker has its init already
            write_message(self.proc.stdin, {"op": "init", **init})
        if wait:
            self.wait_ready()

    def wait_ready(self) -> None:
        """Wait for the worker's imports and warm-up (started in parallel for several workers)."""
        ready = self._receive(self.START_TIMEOUT)
        if ready is None or "ready" not in ready:
            self.kill()
            raise WorkerDied(f"worker did not start: {_signal_name(self.proc.poll())}{self.log_tail()}")
        self.pid = ready["ready"]

    def fileno(self) -> int:
        return self.proc.stdout.fileno()

    def alive(self) -> bool:
        return self.proc.poll() is None

    def send(self, case: dict) -> None:
        self.case, self.started = case, time.monotonic()
        write_message(self.proc.stdin, {"op": "case", "case": case})

    def _receive(self, timeout: float | None):
        if timeout is not None:
            sel = selectors.DefaultSelector()
            sel.register(self.proc.stdout, selectors.EVENT_READ)
            try:
                if not sel.select(timeout):
                    return None
            finally:
                sel.close()
        try:
            return read_message(self.proc.stdout)
        except Exception:  # a torn message: the worker died while writing
            return None

    def receive(self) -> dict:
        """The record of the case in flight (the pipe is readable), or a failed record if the worker died."""
        msg = self._receive(None)
        case, self.case = self.case, None
        if msg is None or "line" not in msg:
            self.kill()
            return failed_record(case, f"worker process died ({_signal_name(self.proc.returncode)}) "
                                       f"while running this case{self.log_tail()}")
        return json.loads(msg["line"])

    def run(self, case: dict, timeout: float) -> dict:
        """Blocking: send, wait at most ``timeout`` s, return the record."""
        try:
            self.send(case)
        except (BrokenPipeError, OSError):
            self.kill()
            return failed_record(case, f"worker process died ({_signal_name(self.proc.returncode)}){self.log_tail()}")
        sel = selectors.DefaultSelector()
        sel.register(self.proc.stdout, selectors.EVENT_READ)
        try:
            ready = sel.select(timeout)
        finally:
            sel.close()
        if not ready:
            self.case = None
            self.kill()
            return failed_record(case, f"timeout: no result after {timeout:g} s (worker killed)")
        return self.receive()

    def timed_out(self, timeout: float) -> bool:
        return self.case is not None and time.monotonic() - self.started > timeout

    def kill(self) -> None:
        if self.proc.poll() is None:
            try:
                self.proc.kill()
            except ProcessLookupError:
                pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:  # pragma: no cover
            pass
        for stream in (self.proc.stdin, self.proc.stdout):
            try:
                stream.close()
            except Exception:
                pass

    def stop(self) -> None:
        try:
            write_message(self.proc.stdin, {"op": "stop"})
            self.proc.stdin.close()
            self.proc.wait(timeout=10)
        except Exception:
            pass
        self.kill()

    def log_tail(self, chars: int = 600) -> str:
        if not self.log_path or not Path(self.log_path).exists():
            return ""
        with open(self.log_path, "rb") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - chars))
            text = f.read().decode(errors="replace").strip()
        return f"; worker log: ...{text[-chars:]}" if text else ""


# --------------------------------------------------------------------------- local pool

def run_local(cases: list[dict], init: dict, workers: int, on_record, timeout: float,
              log_dir: Path | None = None, depth: int = 2) -> dict:
    """Run ``cases`` on ``workers`` worker processes; ``on_record(record)`` in the calling thread,
    with a record dict or ``{"key", "agreement", "line"}`` (the record encoded by the worker).

    Workers are forked from this process where that is safe (:func:`start_method`; the modules
    a worker needs are imported here first, once), else spawned. Each worker has up to ``depth``
    cases queued, sent in one message whenever places are free (it starts the next one while
    the supervisor records the last); it answers every case on its own. A worker that dies fails
    the case it was running (the first unanswered one); the cases queued behind it go back to
    the pending list. Returns timings: ``startup`` (s until every worker was ready), ``run`` (s
    from then on) and ``start`` (``fork`` or ``spawn``)."""
    t0 = time.perf_counter()
    if not cases:
        return {"startup": 0.0, "run": 0.0, "start": None}
    workers = max(1, min(workers, len(cases)))
    depth = max(1, depth)
    pending = deque(cases)
    counter = iter(range(1_000_000))
    queued: dict[Child, deque] = {}
    head_start: dict[Child, float] = {}
    sel = selectors.DefaultSelector()

    method = start_method()
    blas_threads = {}
    if method == "fork":  # imported once here, inherited by every forked worker

        import_plugins(init.get("imports", []))
        warm_up()
        warm_imports(cases)
        warm_fmus(init.get("fmu_paths", {}))
        # the workers inherit one BLAS thread; every library loaded by now is restored below
        blas_threads = set_blas_threads(1)

    def new_child(wait: bool = True) -> Child:
        log = log_dir / f"worker-{next(counter)}.log" if log_dir else None
        return Child(init, log, wait=wait)

    def attach(child: Child) -> None:
        queued[child] = deque()
        sel.register(child.proc.stdout, selectors.EVENT_READ, child)

    def detach(child: Child, reason: str) -> None:
        """The worker is gone: fail its running case, requeue the ones behind it, replace it."""
        sel.unregister(child.proc.stdout)
        child.kill()
        lost = queued.pop(child)
        head_start.pop(child, None)
        if lost:
            on_record(failed_record(lost.popleft(), reason(child) if callable(reason) else reason))
        pending.extendleft(reversed(lost))
        if pending:
            attach(new_child())

    def died(child: Child) -> str:
        return (f"worker process died ({_signal_name(child.proc.returncode)}) while running this case"
                f"{child.log_tail()}")

    finished = False
    started: list[Child] = []
    try:
        started = [new_child(wait=False) for _ in range(workers)]
        for child in started:
            child.wait_ready()
            attach(child)
        t1 = time.perf_counter()
        while pending or any(queued.values()):
            # the free places of the workers' queues, dealt out in turn (4 cases on 2 workers: 2
            # each, never 4 to the first), each worker's share sent in one message
            batches: dict[Child, list] = {child: [] for child in queued}
            while pending:
                room = [c for c in batches if len(queued[c]) + len(batches[c]) < depth]
                if not room:
                    break
                for child in room:
                    if pending:
                        batches[child].append(pending.popleft())
            for child, batch in batches.items():
                if not batch:
                    continue
                try:
                    write_message(child.proc.stdin, {"op": "cases", "cases": batch})
                except (BrokenPipeError, OSError):
                    pending.extendleft(reversed(batch))
                    continue
                if not queued[child]:
                    head_start[child] = time.monotonic()
                queued[child].extend(batch)
            for key, _ in sel.select(timeout=0.5):
                child: Child = key.data
                if child not in queued:
                    continue
                msg = child._receive(None)
                if msg is None or "line" not in msg:
                    detach(child, died)
                    continue
                queued[child].popleft()
                head_start[child] = time.monotonic()
                on_record(msg)  # {"key", "agreement", "line"}: the record as a JSON line
            now = time.monotonic()
            for child in [c for c, q in queued.items() if q and now - head_start.get(c, now) > timeout]:
                detach(child, f"timeout: no result after {timeout:g} s (worker killed)")
        finished = True
        t2 = time.perf_counter()  # the last result (stopping the workers is not part of the run)
    finally:
        sel.close()
        for child in set(queued) | set(started):
            if finished:
                child.stop()
            else:  # interrupted (Ctrl-C, an error): do not wait for running cases
                child.kill()
        if blas_threads:
            set_blas_threads(blas_threads)
    return {"startup": t1 - t0, "run": t2 - t1, "start": method}


# --------------------------------------------------------------------------- Dask

_local = threading.local()


def dask_chunk(init: dict, cases: list[dict], timeout: float) -> list[dict]:
    """A Dask task: run cases in this Dask worker thread's own worker process."""
    child = getattr(_local, "child", None)
    if child is None or child.init != init or not child.alive():
        if child is not None:
            child.kill()
        child = _local.child = Child(init)
    records = []
    for case in cases:
        if not child.alive():
            child = _local.child = Child(init)
        records.append(child.run(case, timeout))
    return records


SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")


def _check_address(address) -> None:
    """Refuse a scheduler address that is not [SCHEME://]HOST:PORT (no connection is tried)."""
    from urllib.parse import urlsplit

    text = address if isinstance(address, str) else ""
    if text and "://" not in text:
        text = "tcp://" + text  # Dask's default scheme
    try:
        parts = urlsplit(text)
        port = parts.port
    except ValueError:
        port = None
    else:
        if parts.scheme not in SCHEMES or not parts.hostname or parts.path not in ("", "/"):
            port = None
    if port is None:
        raise SchedulerError(f"--scheduler {address!r} is not a scheduler address "
                             f"([{'|'.join(SCHEMES)}://]HOST:PORT, e.g. tcp://127.0.0.1:8786)")


def connect(address: str, timeout: float = SCHEDULER_TIMEOUT):
    """A Dask client of the scheduler at ``address``, or one :class:`SchedulerError` within ``timeout`` s.

    Raises
    ------
    SchedulerError
        If the address is malformed, or the scheduler does not
        answer within ``timeout`` seconds (closed port, unknown host, firewall).
    MissingExtraError
        If dask.distributed (the optional extra ``cluster``) is not installed.
    """
    import logging

    try:
        from distributed import Client
    except ImportError:  # the optional extra `cluster`

        raise MissingExtraError("--scheduler", "dask.distributed", "cluster") from None
    _check_address(address)  # a malformed one would leave a half-made Client that hangs at exit
    # distributed logs every failed connection attempt; the one message below says it all
    quiet = [logging.getLogger(n) for n in ("distributed", "distributed.client", "distributed.comm",
                                            "distributed.core", "tornado", "asyncio")]
    levels = [lg.level for lg in quiet]
    for lg in quiet:
        lg.setLevel(logging.CRITICAL)
    try:
        return Client(address, timeout=timeout)
    except (OSError, TimeoutError) as exc:  # refused, timed out, unknown host
        reason = str(exc).split("\n")[0] or type(exc).__name__
        raise SchedulerError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s ({reason})") from None
    except (ValueError, TypeError) as exc:
        raise SchedulerError(f"--scheduler {address!r} is not a scheduler address (tcp://HOST:PORT): {exc}") from None
    finally:
        for lg, level in zip(quiet, levels):
            lg.setLevel(level)


def run_dask(cases: list[dict], init: dict, client, on_record, timeout: float,
             chunk_size: int | None = None) -> None:
    """Run ``cases`` as tasks on the Dask cluster of ``client`` (a Client or a scheduler address).

    Raises
    ------
    SchedulerError
        If the connection to the scheduler is lost: the records received so far are kept
        (``--resume`` runs the rest).
    """
    from distributed import as_completed

    if not cases:
        return
    if isinstance(client, str):
        with connect(client) as own:
            return run_dask(cases, init, own, on_record, timeout, chunk_size)
    done = 0
    try:
        n_workers = max(1, sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values()))
        size = chunk_size or max(1, min(32, math.ceil(len(cases) / (4 * n_workers))))
        chunks = [cases[i:i + size] for i in range(0, len(cases), size)]
        tag = uuid.uuid4().hex[:8]
        futures = {}
        for k, chunk in enumerate(chunks):
            fut = client.submit(dask_chunk, init, chunk, timeout, key=f"cosim-matrix-{tag}-{k}", pure=False,
                                retries=0)
            futures[fut] = chunk
        for fut in as_completed(list(futures)):
            chunk = futures.pop(fut)
            try:
                records = fut.result()
            except (OSError, TimeoutError):
                raise
            except Exception as exc:
                records = [failed_record(c, f"Dask task failed: {type(exc).__name__}: {exc}") for c in chunk]
            for rec in records:
                on_record(rec)
                done += 1
    except (OSError, TimeoutError) as exc:
        address = getattr(getattr(client, "scheduler", None), "address", None) or "its address"
        raise SchedulerError(f"lost the Dask scheduler at {address} after {done} of "
                             f"{len(cases)} cases ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__}); "
                             "the results so far are kept: --resume runs the rest") from None
