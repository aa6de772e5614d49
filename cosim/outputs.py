"""Writing result files safely: checked before the work, written under a temporary name, renamed.

Every command that writes a file (CSV, NPY, PNG, HTML, JSON, SSP, FMU) goes through here, so that

- an output path that cannot be written (a directory, a read-only folder, a file in the way of a
  folder) is refused with one message *before* any computation starts (:func:`check_output`);
- a file appears under its final name only when it is complete: a kill or an error half-way leaves
  at most a hidden ``.NAME.partial-*`` file, never a complete-looking partial result
  (:func:`atomic_output`).

Input text files (CSV input data, system and matrix spec TOML) are read through
:func:`read_text_file`, so that an unreadable or undecodable file gets the same one message
everywhere.
"""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from cosim.errors import OutputError


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


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike, what: str = "output file"):
    """Yield a temporary path beside ``path``; on success it is renamed to ``path``.

    The temporary name keeps the suffix (matplotlib and numpy choose the format by it). On any
    exception the temporary file is removed and the exception propagates; ``path`` is untouched.

    Examples
    --------
    >>> with atomic_output("result.csv") as tmp:        # doctest: +SKIP
    ...     np.savetxt(tmp, data, delimiter=",")
    """
    path = check_output(path, what)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, partial = tempfile.mkstemp(prefix=f".{path.stem}.partial-", suffix=path.suffix, dir=path.parent)
    except OSError as exc:
        raise OutputError(f"{what} '{path}': {exc.strerror or exc}") from None
    os.close(fd)
    partial = Path(partial)
    try:
        yield partial
        os.chmod(partial, 0o666 & ~_umask())
        os.replace(partial, path)
    except OSError as exc:
        partial.unlink(missing_ok=True)
        raise OutputError(f"{what} '{path}': {exc.strerror or exc}") from None
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


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
