"""Running a foreign FMU's binary where it cannot take the caller down.

An FMU from another tool is C code loaded into the process that calls it: a segmentation fault,
``exit``, ``abort``, an endless loop or a ``kill`` of its parent there would end (or stall) the
command and lose every row computed so far. :func:`run_isolated` runs a function that calls the
binary in a child process instead, behind a guard process:

    caller ── guard (own session: a signal to the FMU's process group stops there) ── worker

* the worker calls the FMU and streams what it computed (rows, progress, the result) back through
  a pipe, so that the caller keeps everything up to a fault;
* the guard only waits for the worker and reports how it ended (exit status or signal): an FMU
  that kills its parent kills the guard, not the caller;
* both die with their parent (:func:`cosim.processes.die_with_parent`), so a killed command leaves
  no worker behind;
* a worker that sends nothing for ``timeout`` seconds is stopped (SIGKILL to its session).

The failure is raised as :class:`FMUProcessError` naming what happened (the signal, the exit
status, the time limit) and the FMI call in progress; the caller decides what the rows it has
mean. FMUs built by this project (:func:`built_here`) may run in-process (their runtime checks
every call), everything else goes through here. Linux and other POSIX systems (``os.fork``).
"""
from __future__ import annotations

import faulthandler
import json
import os
import pickle
import select
import signal
import struct
import sys
import time
import zipfile
from typing import Any, Callable

from cosim.errors import SimulationError
from cosim.processes import die_with_parent

__all__ = ["DEFAULT_TIMEOUT", "FMUProcessError", "Worker", "built_here", "can_isolate", "run_isolated"]

#: Longest time [s] a foreign FMU may go without progress (a completed step, a call returned)
#: before it is stopped: far beyond one communication step of any model that finishes at all.
DEFAULT_TIMEOUT = 60.0

_HEADER = struct.Struct("!I")
_POLL = 0.2  # seconds between checks of ``progress`` while the worker is silent
_GRACE = 5.0  # seconds the guard may take to report how its worker ended


class FMUProcessError(SimulationError):
    """The process running a foreign FMU ended abnormally or stopped answering.

    Attributes
    ----------
    what : str
        What happened, e.g. ``"crashed (SIGSEGV)"``, ``"ended the process with exit status 0 (a call
        of exit?)"``, ``"gave no answer within 60 s and was stopped"``.
    doing : str
        The FMI call (or phase) in progress, as the worker last reported it.
    """

    def __init__(self, message: str, what: str = "", doing: str = ""):
        super().__init__(message)
        self.what, self.doing = what, doing

    def __reduce__(self):
        return type(self), (str(self), self.what, self.doing)


def can_isolate() -> bool:
    """True where child processes can be forked (POSIX)."""
    return hasattr(os, "fork")


def built_here(path: str | os.PathLike) -> bool:
    """True for an FMU this project built: its ``generationTool`` is cosim and it carries the build
    manifest. Anything else (or anything unreadable) is foreign."""
    from cosim.compiler.fmu import MANIFEST  # deferred: `cosim --help` loads this module

    try:
        with zipfile.ZipFile(path) as archive:
            names = set(archive.namelist())
            if MANIFEST not in names or "modelDescription.xml" not in names:
                return False
            head = archive.read("modelDescription.xml")[:4096].decode("utf-8", "replace")
    except (OSError, zipfile.BadZipFile, KeyError, ValueError):
        return False
    return 'generationTool="cosim' in head


class Worker:
    """The worker's end of the pipe: what the function run by :func:`run_isolated` reports."""

    def __init__(self, fd: int):
        self._fd = fd
        self.stderr = sys.stderr  #: where the worker may show progress (the caller's terminal)

    def send(self, kind: str, payload: Any = None) -> None:
        """Send one message (``kind`` other than result/error/doing goes to ``on_message``)."""
        data = pickle.dumps((kind, payload), protocol=pickle.HIGHEST_PROTOCOL)
        view = memoryview(_HEADER.pack(len(data)) + data)
        while view:
            view = view[os.write(self._fd, view):]

    def doing(self, text: str) -> None:
        """Name the call or phase that comes next (the message of a fault names it)."""
        self.send("doing", text)


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def _how_ended(status: int) -> str:
    """Words for a worker's wait status."""
    if os.WIFSIGNALED(status):
        number = os.WTERMSIG(status)
        if number == signal.SIGABRT:
            return "aborted (SIGABRT: the binary called abort?)"
        if number == signal.SIGKILL:
            return "was killed (SIGKILL)"
        return f"crashed ({_signal_name(number)})"
    return f"ended the process with exit status {os.WEXITSTATUS(status)} (a call of exit?)"


def _worker_body(function: Callable[[Worker], Any], fd: int, guard: int) -> None:
    """In the worker: run ``function`` and send its result or exception; never returns."""
    die_with_parent(guard)
    faulthandler.disable()  # a crash is reported by the caller, not as a dump of this stack
    worker = Worker(fd)
    # What the binary (or a library's exit handler) prints is not the command's output: the
    # caller's message says what happened. The worker's own progress output keeps the terminal.
    worker.stderr = os.fdopen(os.dup(2), "w")
    silent = os.open(os.devnull, os.O_WRONLY)
    os.dup2(silent, 1)
    os.dup2(silent, 2)
    os.close(silent)
    try:
        try:
            value = function(worker)
            message = ("result", value)
        except BaseException as exc:  # the caller re-raises it; one that does not pickle as text
            try:
                pickle.loads(pickle.dumps(exc))
                message = ("error", exc)
            except Exception:
                message = ("error", SimulationError(f"{type(exc).__name__}: {exc}"))
        worker.send(*message)
    finally:
        os._exit(0)


def _guard_body(function: Callable[[Worker], Any], data_fd: int, control_fd: int, caller: int) -> None:
    """In the guard: a new session, the worker started and waited for; never returns."""
    try:
        os.setsid()
        die_with_parent(caller)
        worker = os.fork()
        if worker == 0:
            os.close(control_fd)
            _worker_body(function, data_fd, os.getppid())
        os.close(data_fd)
        os.write(control_fd, json.dumps({"worker": worker}).encode() + b"\n")
        _, status = os.waitpid(worker, 0)
        os.write(control_fd, json.dumps({"status": status}).encode() + b"\n")
    finally:
        os._exit(0)


def _read_control(fd: int, wait: float) -> dict:
    """What the guard reported (the worker's pid, then its wait status), read until the guard
    closes the pipe or ``wait`` seconds have passed."""
    chunks, deadline = [], time.monotonic() + wait
    while True:
        ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
        if not ready:
            break
        try:
            chunk = os.read(fd, 4096)
        except OSError:
            break
        if not chunk:
            break
        chunks.append(chunk)
    found = {}
    for line in b"".join(chunks).splitlines():
        try:
            found.update(json.loads(line))
        except ValueError:
            pass
    return found


def _stop(guard: int) -> None:
    """Kill the guard's session (guard and worker) and reap the guard."""
    for kill in (lambda: os.killpg(guard, signal.SIGKILL), lambda: os.kill(guard, signal.SIGKILL)):
        try:
            kill()
        except (ProcessLookupError, PermissionError):
            pass


def run_isolated(function: Callable[[Worker], Any], *, what: str, timeout: float | None = DEFAULT_TIMEOUT,
                 on_message: Callable[[str, Any], None] | None = None,
                 progress: Callable[[], bool] | None = None) -> Any:
    """Run ``function(worker)`` in a guarded child process and return what it returns.

    Parameters
    ----------
    function : callable
        Called in the worker with a :class:`Worker`; it reports through ``worker.send`` and
        ``worker.doing``. Its return value and exceptions must pickle (an exception that does not
        comes back as :class:`SimulationError` with its text).
    what : str
        The FMU, for messages (e.g. its path).
    timeout : float or None
        Longest time [s] without a message from the worker (or progress, see below) before it is
        stopped; None: no limit.
    on_message : callable, optional
        Gets every message ``(kind, payload)`` other than the result, an error and ``doing``.
    progress : callable, optional
        Called every 0.2 s while the worker is silent; True counts as progress (e.g. rows the
        worker wrote to shared memory).

    Raises
    ------
    FMUProcessError
        If the worker ended without a result (crash, ``exit``, ``abort``, killed) or was stopped
        after ``timeout``.
    Exception
        Whatever ``function`` raised, re-raised here.
    """
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()  # no buffered text printed twice (once by each process)
        except (OSError, ValueError):
            pass
    data_read, data_write = os.pipe()
    control_read, control_write = os.pipe()
    caller = os.getpid()
    guard = os.fork()
    if guard == 0:
        os.close(data_read)
        os.close(control_read)
        _guard_body(function, data_write, control_write, caller)
    os.close(data_write)
    os.close(control_write)
    doing, buffer, reply = "loading the binary", b"", None
    limit = float("inf") if timeout is None else float(timeout)
    deadline = time.monotonic() + limit
    ended = timed_out = False
    try:
        while reply is None:
            wait = max(0.0, min(deadline - time.monotonic(), _POLL if progress else limit))
            ready, _, _ = select.select([data_read], [], [], None if wait == float("inf") else wait)
            if not ready:
                if progress is not None and progress():
                    deadline = time.monotonic() + limit
                elif time.monotonic() >= deadline:
                    timed_out = True
                    break
                continue
            chunk = os.read(data_read, 1 << 16)
            if not chunk:
                ended = True
                break
            buffer += chunk
            while len(buffer) >= _HEADER.size:
                (size,) = _HEADER.unpack_from(buffer)
                if len(buffer) < _HEADER.size + size:
                    break
                kind, payload = pickle.loads(buffer[_HEADER.size:_HEADER.size + size])
                buffer = buffer[_HEADER.size + size:]
                deadline = time.monotonic() + limit
                if kind == "doing":
                    doing = payload
                elif kind in ("result", "error"):
                    reply = (kind, payload)
                    break
                elif on_message is not None:
                    on_message(kind, payload)
    finally:
        # After a reply or the end of the worker the guard reports and exits by itself; otherwise
        # (time limit, Ctrl-C, an error here) the guard's session is stopped at once.
        control = _read_control(control_read, _GRACE) if reply is not None or ended else {}
        _stop(guard)
        control.update(_read_control(control_read, _GRACE))
        os.close(control_read)
        os.close(data_read)
        _, guard_status = os.waitpid(guard, 0)
        if "worker" in control and "status" not in control:
            try:  # the guard is gone; its worker must not outlive it (the kernel's signal is not instant)
                os.kill(int(control["worker"]), signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
    if reply is not None:
        kind, payload = reply
        if kind == "error":
            raise payload
        return payload
    if timed_out:
        happened = f"gave no answer within {limit:g} s and was stopped"
    elif "status" in control:
        happened = _how_ended(int(control["status"]))
    elif os.WIFSIGNALED(guard_status):  # the FMU signalled its parent (the guard) or its session
        happened = (f"ended when its parent process was killed ({_signal_name(os.WTERMSIG(guard_status))}; "
                    "did the binary signal its parent?)")
    else:
        happened = "ended without an answer"
    raise FMUProcessError(f"{what}: the FMU {happened} during {doing}", happened, doing)

