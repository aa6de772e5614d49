"""Writing result files safely: checked before the work, written under a temporary name, renamed.

Every command that writes a file (CSV, NPY, PNG, HTML, JSON, SSP, FMU) goes through here, so that

- an output path that cannot be written (a directory, a read-only folder, a file in the way of a
  folder) is refused with one message *before* any computation starts (:func:`check_output`);
- a file appears under its final name only when it is complete: a kill or an error half-way leaves
  at most a hidden ``.NAME.partial-PID-HOST-*`` file, never a complete-looking partial result
  (:func:`atomic_output`); the next command that writes into that folder removes the partial
  files whose writer (PID on this HOST) has ended (:func:`remove_leftovers`).

Temporary folders (extracted FMUs, the served app, build files) are ``TMPDIR/cosim-KIND-PID-*``
(:func:`temporary_folder`): the next command that makes one of that kind removes those of ended
processes, so a ``kill -9`` leaves its folder only until then.

Input text files (CSV input data, system and matrix spec TOML) are read through
:func:`read_text_file`, so that an unreadable or undecodable file gets the same one message
everywhere.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import socket
import tempfile
from pathlib import Path

from cosim.errors import OutputError
from cosim.processes import alive


def _existing_ancestor(path: Path) -> Path:
    for parent in [path, *path.parents]:
        if parent.exists():
            return parent
    return Path("/")


def check_output(path: str | os.PathLike, what: str = "output file") -> Path:
    """Refuse ``path`` as an output file unless it can be written; returns it as a Path.

    Raises
    ------
    OutputError
        If ``path`` is a directory, or a component of its folder is a file, or the folder is
        not writable (or cannot be created).
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"{what} '{path}' is a directory")
    folder = _existing_ancestor(path.parent if str(path.parent) else Path("."))
    if not folder.is_dir():
        raise OutputError(f"{what} '{path}': '{folder}' is a file, not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{what} '{path}': folder '{folder}' is not writable")
    if path.exists() and not os.access(path, os.W_OK):
        raise OutputError(f"{what} '{path}' exists and is not writable")
    return path


def check_output_folder(path: str | os.PathLike, what: str = "output folder") -> Path:
    """Refuse ``path`` as an output folder unless it is (or can be made) a writable folder."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{what} '{path}' is a file, not a folder")
    folder = _existing_ancestor(path)
    if not folder.is_dir():
        raise OutputError(f"{what} '{path}': '{folder}' is a file, not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{what} '{path}': folder '{folder}' is not writable")
    return path


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


def read_text_file(path: Path, error: type[Exception], label: str, encoding: str = "utf-8") -> str:
    """The text of the input file ``path``.

    Raises
    ------
    error
        ``"LABEL: not UTF-8 text (byte N)"`` for undecodable bytes, ``"LABEL: cannot read the file:
        REASON"`` if it cannot be read (missing, a folder, no permission).
    """
    try:
        return path.read_text(encoding=encoding)
    except UnicodeDecodeError as exc:
        raise error(f"{label}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise error(f"{label}: cannot read the file: {exc.strerror or exc}") from None


def write_text(path: str | os.PathLike, text: str, what: str = "output file") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_output`)."""
    with atomic_output(path, what) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)
