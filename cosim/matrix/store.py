"""Results as JSON Lines, one finished case per line, appended atomically.

Each record is written with a single ``write`` of one complete line to a file opened with
``O_APPEND`` (and fsynced at most once a second and at the end), so a killed supervisor leaves
either the whole line or, at worst (power loss), a torn last line. On ``--resume`` the valid
lines are read back, a torn tail is cut off, and only cases whose key has no record yet are run:
nothing is lost and nothing is run or written twice.
"""
from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

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
    return (json.dumps(_clean(record), sort_keys=True, allow_nan=False) + "\n").encode()


def read_records(path: Path) -> tuple[list[dict], int]:
    """Complete records of a results file and the byte length of the valid prefix."""
    if not path.exists():
        return [], 0
    data = path.read_bytes()
    records, valid = [], 0
    pos = 0
    while pos < len(data):
        end = data.find(b"\n", pos)
        if end < 0:
            break  # torn tail: no newline
        line = data[pos:end]
        try:
            records.append(json.loads(line))
        except json.JSONDecodeError:
            break
        pos = end + 1
        valid = pos
    return records, valid


class ResultStore:
    """The results file of a run directory."""

    def __init__(self, directory: Path, resume: bool):
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.path = self.directory / RESULTS
        self._records: dict[str, dict | bytes] = {}  # bytes: a line written, parsed when asked for
        self.torn = 0
        if resume:
            found, valid = read_records(self.path)
            if self.path.exists() and valid < self.path.stat().st_size:
                self.torn = self.path.stat().st_size - valid
                with open(self.path, "r+b") as f:
                    f.truncate(valid)
            for rec in found:
                self._records[rec["key"]] = rec
        else:
            self.path.unlink(missing_ok=True)
        self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        self._synced = time.monotonic()

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
        """Append one encoded record (a complete line, see :func:`encode`) with a single write."""
        if not line.endswith(b"\n") or b"\n" in line[:-1]:
            raise ValueError("a record must be exactly one line")
        view = memoryview(line)
        while view:
            n = os.write(self._fd, view)
            view = view[n:]
        self._records[key] = line
        if time.monotonic() - self._synced > 1.0:
            os.fsync(self._fd)
            self._synced = time.monotonic()

    def close(self) -> None:
        if self._fd is not None:
            os.fsync(self._fd)
            os.close(self._fd)
            self._fd = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
