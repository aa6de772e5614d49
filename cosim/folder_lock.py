"""One writer per output: a lock file that names the command holding it.

Every command that writes a folder of results holds that folder's lock while it writes:
``cosim matrix -o DIR``, ``cosim figures -o DIR``, ``cosim demo -o DIR`` and ``cosim app --export
DIR`` hold ``DIR/.cosim-lock`` (:func:`folder_lock`); a second command on the same folder is
refused at once with one message naming the holder::

    output folder 'DIR' is being written by pid 4242 (cosim matrix spec.toml -o DIR, started 2025-01-31 12:00:00)

``cosim build`` (and every command that builds a model on demand) holds the lock of each FMU it
writes (``OUTPUT/.NAME.fmu.lock``, :func:`lock_file` with ``wait=True``): builds of other models
into the same folder run side by side, and a second build of the same model waits, then finds
the FMU up to date.

The lock is ``flock(2)`` on the open lock file, so the kernel releases it when its holder ends in
whatever way (``kill -9`` included): a lock file left by a killed command locks nothing, and the
next command takes it over without being told. The holder writes its pid, host, command line and
start time into the file (for the message of the refused command) and removes the file when it
releases the lock. Processes forked while a lock is held (worker pools) close their inherited
copy at once, so a lock never outlives its holder in a child that is still ending.
"""
from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shlex
import socket
import sys
import time
from pathlib import Path

from cosim.errors import OutputError
from cosim.processes import alive

__all__ = ["LOCK_NAME", "FolderBusy", "check_not_busy", "folder_lock", "lock_file", "unlock_file"]

#: The lock file of an output folder (hidden; removed when the writing command ends).
LOCK_NAME = ".cosim-lock"
#: Seconds to wait for the lock of a holder that has ended (its lock file is still being
#: released by the kernel) before calling the folder busy.
ENDED_HOLDER_GRACE = 10.0

_held: dict[int, Path] = {}  # file descriptor -> lock file, of the locks this process holds


class FolderBusy(OutputError):
    """Another command is writing the output; the message names it (pid, command, start)."""


def _close_inherited() -> None:
    """In a forked child: close the copies of the parent's lock files (the parent holds them)."""
    for fd in list(_held):
        with contextlib.suppress(OSError):
            os.close(fd)  # flock: closing one copy does not release the parent's lock
    _held.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_close_inherited)


def _command_line() -> str:
    """The command line of this process as a user would type it (``cosim matrix spec.toml ...``)."""
    argv = list(sys.argv) or [sys.executable]
    first = Path(argv[0])
    if first.name == "__main__.py":  # python -m cosim
        program = "cosim"
    elif argv[0] == "-c":
        program = "python -c"
    else:
        program = first.name or "python"
    text = " ".join([program, *(shlex.quote(a) for a in argv[1:])])
    return text if len(text) <= 200 else text[:197] + "..."


def _holder_record() -> bytes:
    return json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "command": _command_line(),
                       "started": time.strftime("%Y-%m-%d %H:%M:%S")}).encode()


def _read_holder(fd: int) -> dict:
    """What the holder of the lock wrote into its lock file ({} if nothing readable yet)."""
    try:
        data = os.pread(fd, 4096, 0)
        record = json.loads(data)
    except (OSError, ValueError):
        return {}
    return record if isinstance(record, dict) else {}


def describe_holder(record: dict) -> str:
    """``pid N (COMMAND, started TIME)`` of a holder record; ``another process`` if it is empty."""
    if not isinstance(record.get("pid"), int):
        return "another process"
    where = f" on {record['host']}" if record.get("host") not in (None, socket.gethostname()) else ""
    details = [str(record["command"])] if record.get("command") else []
    if record.get("started"):
        details.append(f"started {record['started']}")
    return f"pid {record['pid']}{where}" + (f" ({', '.join(details)})" if details else "")


def _try_lock(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _busy(fd: int, what: str) -> None:
    """Wait for a holder that has ended, else raise :class:`FolderBusy` naming the holder.

    The holder writes its record just after it took the lock: an empty one is read again for a
    moment. A holder on this host whose pid has ended (the kernel is still closing the file in
    one of its children) releases the lock within :data:`ENDED_HOLDER_GRACE` seconds."""
    deadline = time.monotonic() + 1.0
    record = _read_holder(fd)
    while not record and time.monotonic() < deadline:
        time.sleep(0.02)
        if _try_lock(fd):
            return
        record = _read_holder(fd)
    pid = record.get("pid")
    if record.get("host") == socket.gethostname() and isinstance(pid, int) and not alive(pid):
        deadline = time.monotonic() + ENDED_HOLDER_GRACE
        while time.monotonic() < deadline:
            if _try_lock(fd):
                return
            time.sleep(0.05)
    raise FolderBusy(f"{what} is being written by {describe_holder(record)}")


def lock_file(path: str | os.PathLike, wait: bool = False, what: str | None = None) -> int:
    """Take the exclusive lock of ``path`` (created if missing); returns its file descriptor.

    Only the file currently under the name counts: a command that waited on a file its holder
    removed meanwhile tries again with the new one.

    Parameters
    ----------
    path : path
        The lock file; its folder must exist.
    wait : bool
        Wait while another process holds the lock (else raise :class:`FolderBusy` at once).
    what : str, optional
        What the lock protects, for the message (default: the lock file's folder).

    Raises
    ------
    FolderBusy
        If another process holds the lock and ``wait`` is false; the message names it.
    OutputError
        If the lock file cannot be created or locked (a read-only folder, disk full).
    """
    path = Path(path)
    what = what or f"folder '{path.parent}'"
    try:
        while True:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
            try:
                if not _try_lock(fd):
                    if wait:
                        fcntl.flock(fd, fcntl.LOCK_EX)
                    else:
                        _busy(fd, what)
                if os.path.samestat(os.fstat(fd), os.stat(path)):
                    break
            except FileNotFoundError:
                pass  # removed by its holder while we waited: lock the new one
            except BaseException:
                os.close(fd)
                raise
            os.close(fd)
    except OSError as exc:
        if isinstance(exc, OutputError):
            raise
        raise OutputError(f"{what}: cannot lock '{path}': {exc.strerror or exc}") from None
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, _holder_record(), 0)
    except OSError:
        pass  # a full disk: the lock holds all the same, the message of a refused command is shorter
    _held[fd] = path
    return fd


def unlock_file(fd: int) -> None:
    """Release a lock of :func:`lock_file` and remove its file (if it is still the locked one)."""
    path = _held.pop(fd, None)
    try:
        if path is not None and os.path.samestat(os.fstat(fd), os.stat(path)):
            os.unlink(path)
    except OSError:
        pass
    finally:
        os.close(fd)


def check_not_busy(folder: str | os.PathLike, what: str = "output folder") -> None:
    """Refuse the output folder ``folder`` if another command is writing it; creates nothing.

    For the checks before any work: a folder being written is named as such, before other
    complaints about its contents (which the writer is still changing).

    Raises
    ------
    FolderBusy
        As :func:`folder_lock`.
    """
    try:
        fd = os.open(Path(folder) / LOCK_NAME, os.O_RDONLY | os.O_CLOEXEC)
    except OSError:
        return  # no lock file: nobody is writing (an unreadable folder is refused by the lock itself)
    try:
        ours = any(os.path.samestat(os.fstat(fd), os.fstat(held)) for held in _held)
        if not ours and not _try_lock(fd):
            _busy(fd, f"{what} '{folder}'")
    finally:
        os.close(fd)  # (a lock taken by the probe ends with it)


def held_lock_files() -> list[Path]:
    """The lock files this process holds (removed by a process that is being abandoned)."""
    return list(_held.values())


@contextlib.contextmanager
def folder_lock(folder: str | os.PathLike, what: str = "output folder", wait: bool = False):
    """Hold the lock of the output folder ``folder`` (created if missing) while the block runs.

    A folder this call created is removed again if it is still empty at the end (a command
    refused or failed before writing anything leaves nothing behind).

    Raises
    ------
    FolderBusy
        If another command is writing the folder (unless ``wait``): ``WHAT 'FOLDER' is being
        written by pid N (COMMAND, started TIME)``.
    OutputError
        If the folder cannot be created or locked.
    """
    folder = Path(folder)
    created = not folder.exists()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{what} '{folder}': cannot create it: {exc.strerror or exc}") from None
    try:
        fd = lock_file(folder / LOCK_NAME, wait, f"{what} '{folder}'")
    except BaseException:
        if created:
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    try:
        yield folder
    finally:
        unlock_file(fd)
        if created:
            with contextlib.suppress(OSError):
                folder.rmdir()  # only if empty
