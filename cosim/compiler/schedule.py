"""The order of a parallel build: the longest builds first, from the times of the last builds.

With the models in alphabetical order, the two nonlinear bicycles (a third of all the work of a
clean build of the library) started in the middle and one of them ended last, alone on one core
while the other idled. Started first, the small models fill in behind them (longest processing
time first, the classic list-scheduling rule): a clean build of the library on 2 cores ends
when the work is done, not a big model later.

The seconds of each model's last build are kept in ``$XDG_CACHE_HOME/cosim/build-seconds.json``
(a hint, like ninja's log: a missing, unreadable or foreign file only means the given order).
A model without a recorded time counts as long (a new model may well be large): it starts
first, in the given order.
"""
from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path
from cosim.compiler.catalog import cache_folder

LOG_NAME = "build-seconds.json"
MAX_ENTRIES = 2000  # models remembered (the oldest entries are dropped beyond this)


def log_file() -> Path:
    return cache_folder() / LOG_NAME


def recorded_seconds() -> dict[str, float]:
    """Model name -> wall seconds of its last build (empty if there is no usable log)."""
    try:
        data = json.loads(log_file().read_text())
    except (OSError, ValueError):
        return {}
    if not isinstance(data, dict):
        return {}
    return {k: float(v) for k, v in data.items() if isinstance(k, str) and isinstance(v, (int, float))}


def longest_first(names: list[str]) -> list[str]:
    """``names`` in the order to start their builds: unknown ones first (in the given order),
    then by the recorded seconds, longest first."""
    seconds = recorded_seconds()
    unknown = [n for n in names if n not in seconds]
    known = sorted((n for n in names if n in seconds), key=lambda n: -seconds[n])  # stable for ties
    return unknown + known


def record(seconds: dict[str, float]) -> None:
    """Remember the build times of ``seconds`` (model name -> wall seconds) for the next build.

    Written to a temporary file and renamed (a concurrent build may lose its update, never
    corrupt the log); a log that cannot be written is no error: it only orders the next build."""
    if not seconds:
        return
    merged = recorded_seconds()
    for name in seconds:
        merged.pop(name, None)  # re-inserted last: the newest entries survive the trimming
    merged.update({name: round(float(s), 3) for name, s in seconds.items()})
    merged = dict(list(merged.items())[-MAX_ENTRIES:])
    target = log_file()
    with contextlib.suppress(OSError):
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{LOG_NAME}.", dir=target.parent)
        try:
            with os.fdopen(fd, "w") as f:
                json.dump(merged, f, indent=0, sort_keys=False)
            os.replace(tmp, target)
        except OSError:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
