"""Writing result files safely: checked before the work, written under a temporary name, renamed.

Every command that writes a file (CSV, NPY, PNG, HTML, JSON, SSP, FMU) goes through here, so that

- an output path that cannot be written (a directory, a device or FIFO, a read-only folder, a
  file in the way of a folder, a name too long) is refused with one message *before* any
  computation starts (:func:`check_output`);
- a file appears under its final name only when it is complete: a kill or an error half-way leaves
  at most a hidden ``.NAME.partial-PID-HOST-*`` file, never a complete-looking partial result
  (:func:`atomic_output`); the next command that writes into that folder removes the partial
  files whose writer (PID on this HOST) has ended (:func:`remove_leftovers`).

Temporary folders (extracted FMUs, the served app, build files) are ``TMPDIR/cosim-KIND-PID-*``
(:func:`temporary_folder`): the next command that makes one of that kind removes those of ended
processes, so a ``kill -9`` leaves its folder only until then.

Input files the user names (FMUs, CSV and NPY data, system, spec and parameter TOML) are refused
unless they are regular files, before they are opened (:func:`check_input_file`: a FIFO would
block, ``/dev/zero`` never end); text files are read through :func:`read_text_file`, so that an
unreadable or undecodable file gets the same one message everywhere. An OS error while writing
(disk full, quota, read-only file system, a name too long) is one line naming the path
(``cannot write result file 'r.csv': No space left on device``; :func:`os_error_message` for the
ones no caller named).
"""
from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import socket
import stat
import tempfile
from pathlib import Path

from cosim.errors import OutputError
from cosim.processes import alive


def _existing_ancestor(path: Path) -> Path:
    for parent in [path, *path.parents]:
        if parent.exists():
            return parent
    return Path("/")


def _status(path: Path) -> os.stat_result | None:
    """``os.stat`` of ``path``; None if there is nothing (a component that is a file is found by
    the caller's look at the folder); other OS errors (a name too long) propagate."""
    try:
        return os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None


def _os_refusal(what: str, path: Path, exc: Exception) -> OutputError:
    reason = getattr(exc, "strerror", None) or ("the name contains a NUL character" if isinstance(exc, ValueError)
                                                 else str(exc))
    return OutputError(f"cannot write {what} '{path}': {reason}")


def check_output(path: str | os.PathLike, what: str = "output file") -> Path:
    """Refuse ``path`` as an output file unless it can be written; returns it as a Path.

    Raises
    ------
    OutputError
        If ``path`` is a directory, a FIFO or a device (it would be replaced by a file), or a
        component of its folder is a file, or the folder is not writable (or cannot be created),
        or the name is too long.
    """
    path = Path(path)
    try:
        status = _status(path)
        if status is not None and stat.S_ISDIR(status.st_mode):
            raise OutputError(f"{what} '{path}' is a directory")
        if status is not None and not stat.S_ISREG(status.st_mode):
            raise OutputError(f"{what} '{path}' is {file_kind(status.st_mode)}, not a regular file")
        folder = _existing_ancestor(path.parent if str(path.parent) else Path("."))
        if not folder.is_dir():
            raise OutputError(f"{what} '{path}': '{folder}' is a file, not a folder")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise OutputError(f"{what} '{path}': folder '{folder}' is not writable")
        if status is not None and not os.access(path, os.W_OK):
            raise OutputError(f"{what} '{path}' exists and is not writable")
        _probe(folder)
    except OutputError:
        raise
    except (OSError, ValueError) as exc:  # a name too long, a loop of symbolic links, a NUL character
        raise _os_refusal(what, path, exc) from None
    return path


def name_max(folder: str | os.PathLike) -> int:
    """The longest file name [bytes] the file system of ``folder`` (or of its nearest existing
    ancestor) allows; 255 where it does not say."""
    try:
        return int(os.pathconf(_existing_ancestor(Path(folder)), "PC_NAME_MAX"))
    except (OSError, ValueError):
        return 255


def check_output_folder(path: str | os.PathLike, what: str = "output folder") -> Path:
    """Refuse ``path`` as an output folder unless it is (or can be made) a writable folder."""
    path = Path(path)
    try:
        status = _status(path)
        if status is not None and not stat.S_ISDIR(status.st_mode):
            raise OutputError(f"{what} '{path}' is a file, not a folder" if stat.S_ISREG(status.st_mode) else
                              f"{what} '{path}' is {file_kind(status.st_mode)}, not a folder")
        folder = _existing_ancestor(path)
        if not folder.is_dir():
            raise OutputError(f"{what} '{path}': '{folder}' is a file, not a folder")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise OutputError(f"{what} '{path}': folder '{folder}' is not writable")
        _probe(folder)
    except OutputError:
        raise
    except (OSError, ValueError) as exc:
        raise _os_refusal(what, path, exc) from None
    return path


def _probe(folder: Path) -> None:
    """Create and remove a hidden file in ``folder``: what the permission bits cannot tell (a
    read-only file system, /proc and /sys, which refuse new files also to root) shows here,
    before any work, not when the result is written."""
    handle, name = tempfile.mkstemp(dir=folder, prefix=".cosim-probe-")
    os.close(handle)
    os.unlink(name)


def host_tag() -> str:
    """Six hex digits naming this host in temporary names (a folder may be shared over NFS)."""
    return hashlib.sha256(socket.gethostname().encode()).hexdigest()[:6]


#: The partial files of :func:`atomic_output`: ``.STEM.partial-PID-HOST-XXXXXXXX.SUFFIX``.
PARTIAL_NAME = re.compile(r"^\..*\.partial-(?P<pid>\d+)-(?P<host>[0-9a-f]{6})-[a-z0-9_]{8}(\.[^.]*)?$")


def remove_leftovers(folder: str | os.PathLike, pattern: re.Pattern) -> list[Path]:
    """Remove what ended processes left in ``folder``: the files and folders whose names match
    ``pattern``, owned by this user, whose writer has ended.

    ``pattern``'s group ``pid`` is the writer's pid; its optional group ``host`` the
    :func:`host_tag` of the writer's host (an entry of another host is kept: its pid means
    nothing here). An entry whose pid is alive is kept (also one of a recycled pid: the entry
    then stays until that process ends too). Entries that cannot be read or removed are skipped.

    Returns
    -------
    list of Path
        What was removed.
    """
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        match = pattern.search(entry.name)
        if match is None or match.groupdict().get("host") not in (None, host_tag()):
            continue
        try:
            if entry.stat(follow_symlinks=False).st_uid != os.getuid() or alive(int(match["pid"])):
                continue
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
        except OSError:  # gone meanwhile, or not ours to remove
            continue
        removed.append(Path(entry.path))
    return removed


def _make_partial(folder: Path, stem: str, suffix: str) -> Path:
    """A new empty partial file in ``folder`` named after this process (see :data:`PARTIAL_NAME`)."""
    fd, partial = tempfile.mkstemp(prefix=f".{stem[:64]}.partial-{os.getpid()}-{host_tag()}-",
                                   suffix=suffix if re.fullmatch(r"(\.[^.]*)?", suffix) else "", dir=folder)
    os.close(fd)
    return Path(partial)


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike, what: str = "output file"):
    """Yield a temporary path beside ``path``; on success it is renamed to ``path``.

    The temporary name keeps the suffix (matplotlib and numpy choose the format by it) and names
    this process, so that the next command writing into the folder removes it if this one is
    killed (:func:`remove_leftovers`). On any exception the temporary file is removed and the
    exception propagates; ``path`` is untouched.

    Raises
    ------
    OutputError
        ``cannot write WHAT 'PATH': REASON`` if the file cannot be created, written (disk full,
        quota, read-only file system, ...) or renamed.

    Examples
    --------
    >>> with atomic_output("result.csv") as tmp:        # doctest: +SKIP
    ...     np.savetxt(tmp, data, delimiter=",")
    """
    path = check_output(path, what)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_leftovers(path.parent, PARTIAL_NAME)
        partial = _make_partial(path.parent, path.stem, path.suffix)
    except OSError as exc:
        raise OutputError(f"cannot write {what} '{path}': {exc.strerror or exc}") from None
    try:
        yield partial
        os.chmod(partial, 0o666 & ~_umask())
        os.replace(partial, path)
    except OSError as exc:
        partial.unlink(missing_ok=True)
        if isinstance(exc, OutputError):
            raise
        raise OutputError(f"cannot write {what} '{path}': {exc.strerror or exc}") from None
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


def make_temporary_folder(kind: str) -> Path:
    """A new folder ``TMPDIR/cosim-KIND-PID-XXXXXXXX`` of this process; the caller removes it.

    The folders of this kind that ended processes left (``kill -9``) are removed first."""
    base = Path(tempfile.gettempdir())
    remove_leftovers(base, re.compile(rf"^cosim-{re.escape(kind)}-(?P<pid>\d+)-"))
    return Path(tempfile.mkdtemp(prefix=f"cosim-{kind}-{os.getpid()}-", dir=base))


@contextlib.contextmanager
def temporary_folder(kind: str):
    """:func:`make_temporary_folder` removed (with everything in it) when the block ends."""
    folder = make_temporary_folder(kind)
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Errors of writing (rather than of finding or opening) a file.
WRITE_ERRORS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG, errno.EIO})


def os_error_message(exc: OSError) -> str:
    """One line for an OS error: ``cannot write 'PATH': No space left on device`` (for errors of
    writing), else ``cannot access 'PATH': REASON``; a second path is named too."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    operation = "write" if exc.errno in WRITE_ERRORS else "access"
    if exc.filename is None:
        return f"cannot {operation}: {reason}" if exc.errno in WRITE_ERRORS else reason
    other = f" or '{_text(exc.filename2)}'" if exc.filename2 is not None else ""
    return f"cannot {operation} '{_text(exc.filename)}'{other}: {reason}"


def _text(name) -> str:
    return os.fsdecode(name) if isinstance(name, (str, bytes, os.PathLike)) else str(name)


#: What a file that is not a regular file is, by the type bits of its mode.
_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def file_kind(mode: int) -> str:
    """``a directory``, ``a FIFO (named pipe)``, ... for the ``st_mode`` of what is not a regular file."""
    return next((name for test, name in _KINDS if test(mode)), "of an unknown type")


def check_input_file(path: str | os.PathLike, error: type[Exception], label: str | None = None,
                     what: str = "file", article: str = "a") -> Path:
    """Refuse ``path`` as an input file unless it is a regular file (after symbolic links),
    before it is opened: a FIFO would block the command forever, a device (``/dev/zero``) feed
    it without end. Returns it as a Path.

    Raises
    ------
    error
        ``"LABEL: no such WHAT"``, ``"LABEL: is a FIFO (named pipe), not ARTICLE WHAT"`` (a directory,
        a character device, ...) or ``"LABEL: cannot read the WHAT: REASON"`` (a name too long,
        a folder that may not be searched, a loop of symbolic links). ``LABEL`` defaults to the
        path.
    """
    path = Path(path)
    label = str(path) if label is None else label
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise error(f"{label}: no such {what}") from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL character in the name
        raise error(f"{label}: cannot read the {what}: {getattr(exc, 'strerror', None) or exc}") from None
    if not stat.S_ISREG(mode):
        raise error(f"{label}: is {file_kind(mode)}, not {article} {what}")
    return path


def read_text_file(path: Path, error: type[Exception], label: str, encoding: str = "utf-8") -> str:
    """The text of the input file ``path``.

    Raises
    ------
    error
        ``"LABEL: not UTF-8 text (byte N)"`` for undecodable bytes, ``"LABEL: no such file"``,
        ``"LABEL: is a directory, not a file"`` (a FIFO, a device: :func:`check_input_file`),
        ``"LABEL: cannot read the file: REASON"`` if it cannot be read (no permission, a name
        too long).
    """
    check_input_file(path, error, label)
    try:
        return Path(path).read_text(encoding=encoding)
    except UnicodeDecodeError as exc:
        raise error(f"{label}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise error(f"{label}: cannot read the file: {exc.strerror or exc}") from None


def write_text(path: str | os.PathLike, text: str, what: str = "output file") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_output`)."""
    with atomic_output(path, what) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)
