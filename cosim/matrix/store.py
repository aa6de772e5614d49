"""Results as JSON Lines, one finished case per line, appended atomically.

Each record is written with a single ``write`` of one complete line to a file opened with
``O_APPEND`` (and fsynced at most once a second and at the end), so a killed supervisor leaves
either the whole line or, at worst (power loss), a torn last line. On ``--resume`` the valid
lines are read back, a torn tail is cut off, and only cases whose key has no record yet are run:
nothing is lost and nothing is run or written twice. Failed cases (a crashed or killed worker, a
timeout) are retried on ``--resume`` unless ``--keep-failed``: their records are dropped from the
file first (rewritten under a temporary name and renamed), so the file keeps one line per case.
A line that cannot be written whole (a full disk) is cut off again at once. One run writes a
folder at a time (:mod:`cosim.folder_lock`), so the appends of two runs never mix.
"""
from __future__ import annotations

import contextlib
import json
import math
import os
import time
from pathlib import Path
from cosim.errors import OutputError, ResultNotWritten
from cosim.outputs import atomic_output

RESULTS = "results.jsonl"


def _clean(value):
    """JSON-safe: non-finite floats become null, numpy scalars plain numbers, tuples lists."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, complex):
        return [_clean(value.real), _clean(value.imag)]
    return value


def encode(record: dict) -> bytes:
    """One JSON line of ``record`` (see :func:`_clean` for what is converted)."""
    try:  # plain values (nearly every record): json's C encoder alone, without the walk of _clean
        text = json.dumps(record, sort_keys=True, allow_nan=False)
    except (TypeError, ValueError):  # a numpy scalar, a complex, a non-finite float
        text = json.dumps(_clean(record), sort_keys=True, allow_nan=False)
    return (text + "\n").encode()


def read_records(path: Path) -> tuple[list[dict], int]:
    """Complete records of a results file and the byte length up to the last complete line.

    A torn last line (no newline: the writer was killed mid-write) is not a record; a complete
    line that is not a record (edited or corrupted by hand) is skipped, and the records after it
    are kept."""
    if not path.exists():
        return [], 0
    data = path.read_bytes()
    records, valid = [], 0
    pos = 0
    while pos < len(data):
        end = data.find(b"\n", pos)
        if end < 0:
            break  # torn tail: no newline
        try:
            rec = json.loads(data[pos:end])
        except (json.JSONDecodeError, UnicodeDecodeError):
            rec = None
        if isinstance(rec, dict) and isinstance(rec.get("key"), str):
            records.append(rec)
        pos = valid = end + 1
    return records, valid


def data_lines(path: Path) -> int:
    """Number of complete lines of a file."""
    return Path(path).read_bytes().count(b"\n")


def has_results(directory: Path) -> int:
    """Number of complete records in ``directory``'s results file (0: none, or no file)."""
    path = Path(directory) / RESULTS
    try:
        if not path.is_file() or path.stat().st_size == 0:
            return 0
    except OSError:
        return 0
    return len(read_records(path)[0]) or 1  # a file with only a torn line still holds a result


class ResultStore:
    """The results file of a run directory.

    Parameters
    ----------
    directory : the run directory (created if missing)
    resume : keep the records of an earlier run (else the file is started afresh)
    retry_failed : with ``resume``, drop the records of failed cases so that they are run again
    """

    def __init__(self, directory: Path, resume: bool, retry_failed: bool = False):
        self.directory = Path(directory)
        self.path = self.directory / RESULTS
        self._records: dict[str, dict | bytes] = {}  # bytes: a line written, parsed when asked for
        self.torn = 0
        self.retried: set[str] = set()   # keys of failed records dropped to be run again
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            if resume:
                self._read_back(retry_failed)
            else:
                self.path.unlink(missing_ok=True)
            self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        except OutputError:
            raise
        except OSError as exc:
            raise OutputError(f"results file '{self.path}': {exc.strerror or exc}") from None
        self._synced = time.monotonic()

    def _read_back(self, retry_failed: bool) -> None:
        found, valid = read_records(self.path)
        if self.path.exists() and valid < self.path.stat().st_size:
            self.torn = self.path.stat().st_size - valid
            with open(self.path, "r+b") as f:
                f.truncate(valid)
        for rec in found:
            self._records[rec["key"]] = rec   # a later record of a key replaces an earlier one
        if retry_failed:
            failed = [k for k, rec in self._records.items() if rec.get("agreement") == "failed"]
            for k in failed:
                del self._records[k]
            self.retried = set(failed)
        lines = data_lines(self.path) if self.path.exists() else 0
        if self.retried or len(self._records) < lines:  # dropped, replaced or unreadable lines
            self._rewrite()

    def _rewrite(self) -> None:
        """Replace the file by one line per kept record, atomically (a kill leaves the old file)."""
        with atomic_output(self.path, "results file") as tmp:
            with open(tmp, "wb") as f:
                for rec in self._records.values():
                    f.write(encode(rec))
                f.flush()
                os.fsync(f.fileno())

    @property
    def records(self) -> dict[str, dict]:
        """Every record by key (as read back from JSON)."""
        for key, value in self._records.items():
            if isinstance(value, bytes):
                self._records[key] = json.loads(value)
        return self._records  # type: ignore[return-value]

    def keys(self) -> set[str]:
        return set(self._records)

    def append(self, record: dict) -> None:
        self.append_line(record["key"], encode(record))

    def append_line(self, key: str, line: bytes) -> None:
        """Append one encoded record (a complete line, see :func:`encode`) with a single write.

        Raises
        ------
        ResultNotWritten
            If the line cannot be written (disk full, quota, ...): the part of it that was
            written is cut off again, so the file ends with the last complete record, and the
            message says how many records are kept.
        """
        if not line.endswith(b"\n") or b"\n" in line[:-1]:
            raise ValueError("a record must be exactly one line")
        start = None
        try:
            view = memoryview(line)
            while view:
                n = os.write(self._fd, view)
                if start is None and n < len(view):  # a short write: where the line began, to cut it off
                    start = os.fstat(self._fd).st_size - n
                view = view[n:]
            if time.monotonic() - self._synced > 1.0:
                os.fsync(self._fd)
                self._synced = time.monotonic()
        except OSError as exc:
            if start is not None:  # a part of the line went out: cut it off (read_records would skip it)
                with contextlib.suppress(OSError):
                    os.ftruncate(self._fd, start)
            raise self._lost(exc) from None
        self._records[key] = line

    def _lost(self, exc: OSError):
        n = len(self._records)
        kept = f"the {n} cases recorded before are kept" if n != 1 else "the case recorded before is kept"
        return ResultNotWritten(f"cannot write results file '{self.path}': {exc.strerror or exc}; {kept} "
                                "(--resume runs the rest)")

    def close(self, check: bool = True) -> None:
        """Sync and close the file; a failing sync raises :class:`ResultNotWritten` if ``check``."""
        if self._fd is None:
            return
        try:
            os.fsync(self._fd)
        except OSError as exc:
            if check:
                raise self._lost(exc) from None
        finally:
            os.close(self._fd)
            self._fd = None

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *_):
        self.close(check=exc_type is None)  # an error on the way out is not hidden by one of the sync
