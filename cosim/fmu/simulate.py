"""`cosim simulate`: run an FMU (ME with CVode or CS with its own solver) through FMPy.

What the command promises (see ``cosim simulate --help``):

- the FMU is opened through :func:`cosim.fmu.access.read_fmu` (one message for a damaged file);
- inputs from CSV and NPY files are checked value by value (file, row and column named for a
  value that is not a finite number), in time and memory linear in the rows; a jump or step at
  the start time acts from the start (:func:`merge_signals`);
- without ``--step`` the communication step is :func:`default_step`, whatever the stop time;
- results are written under a temporary name and renamed (:mod:`cosim.outputs`): ``.csv`` (a
  header row, then one row per output time; an FMI 3 array variable as one column per value,
  ``y[1]``, ``y[2]``, ...) or ``.npy`` (a NumPy structured array);
- an FMU that ends the run itself without an error (``terminateSimulation``) ends it normally:
  the rows up to that time are the result (:class:`SimulationTerminated` is warned);
- when the solver fails part-way, the rows computed up to the failure are kept: they are written
  to ``NAME.incomplete.csv`` (``.npy``) beside the requested ``NAME.csv`` and the message names
  the physical cause where the model's outputs show one: a singular configuration the model
  declares in its ``__Cosim(singular(...))`` annotation (the nonlinear Whipple bicycles: steer
  or roll angle at ±π/2, see :func:`cosim.compiler.catalog.singular_configurations`), or the
  constraint residual growing; see :func:`physical_cause`.
"""
from __future__ import annotations

import contextlib
import csv
import io
import math
import os
import re
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from cosim.errors import CosimError, InputDataError, ParameterError, SimulationError
from cosim.fmu.isolation import DEFAULT_TIMEOUT, FMUProcessError, built_here, can_isolate, run_isolated
from cosim import outputs as output_files  # atomic_output looked up when used: a replacement is seen
from cosim.outputs import check_input_file, check_output, read_text_file
from cosim.fmu.parameters import FIXED_STEP_PARAMETER, split_assignment
from cosim.compiler.catalog import singular_configurations
from cosim.compiler.library import load_library
from cosim.fmu.access import ALL_FMI_VERSIONS, FMU, FMULog, read_fmu

#: Result formats by file suffix (``-o``).
RESULT_FORMATS = {".csv": "CSV text with a header row", ".npy": "a NumPy structured array for numpy.load"}
#: Most output rows one command records (a guard against ``--stop-time 1e9 --step 1e-6``).
MAX_ROWS = 10_000_000
#: Communication step [s] of a run without ``--step`` whose FMU declares no DefaultExperiment
#: stepSize (see :func:`default_step`): 100 rows per second of model time, the ``Interval`` every
#: bicycle of the library declares. It resolves the bicycles' fastest mode, the castering of the
#: front wheel (time constant 0.07 s at 5 m/s, 0.04 s at 10 m/s for the benchmark bicycle of
#: Meijaard et al. 2007), and the weave (period 1.4 s at 5 m/s, 0.6 s at 10 m/s); a step that
#: does not grow with the stop time keeps the rows of a long run as close as those of a short one.
DEFAULT_STEP = 0.01
#: Where a result that stopped early goes: ``out.csv`` -> ``out.incomplete.csv``.
INCOMPLETE_TAG = "incomplete"

RESIDUAL_LIMIT = 1e-6  # m: holonomic constraint residual of the nonlinear Whipple models


class SimulationTerminated(UserWarning):
    """The FMU ended the run itself before the stop time, without an error (``terminateSimulation``
    of fmi2NewDiscreteStates / fmi3UpdateDiscreteStates / fmi3DoStep, or fmi2DoStep returning
    fmi2Discard with fmi2Terminated): a normal end of the model, whose rows :func:`simulate`
    returns (the last row is the time of the end). ``time`` is that time [s]."""

    def __init__(self, time: float):
        super().__init__(f"the FMU ended the simulation at t = {time:g} s (terminateSimulation)")
        self.time = time


class IncompleteResult(SimulationError):
    """The solver failed part-way; ``result`` holds the rows up to the failure (may be empty).

    Attributes
    ----------
    result : numpy structured array or None
        Rows computed before the failure (``time`` first).
    time : float or None
        Time of the failure [s] where the solver reports it, else the last row's time.
    cause : str
        The physical cause (see :func:`physical_cause`) or the solver's own message.
    """

    def __init__(self, message: str, result, time: float | None, cause: str):
        super().__init__(message)
        self.result, self.time, self.cause = result, time, cause

    def __reduce__(self):  # pickled from an isolated worker with its rows
        return type(self), (str(self), self.result, self.time, self.cause)


def _variables(fmu: Path):
    md = read_fmu(fmu, ALL_FMI_VERSIONS)
    return md, {v.name: v for v in md.modelVariables}


# --------------------------------------------------------------------------- input signals

def finite_number(text: str, where: str) -> float:
    """``text`` as a finite float; :class:`InputDataError` naming ``where`` otherwise (the one
    parser of input values: CSV cells, ``--input NAME=step:T0:VALUE``, ``linearize --input``)."""
    try:
        value = float(text)
    except ValueError:
        raise InputDataError(f"{where}: '{text}' is not a number") from None
    if not math.isfinite(value):
        raise InputDataError(f"{where}: '{text}' is not a finite number (NaN and infinity are not accepted)")
    return value


INTEGER_TYPES = {"Integer": np.int32, "Enumeration": np.int64, "Int8": np.int8, "UInt8": np.uint8,
                 "Int16": np.int16, "UInt16": np.uint16, "Int32": np.int32, "UInt32": np.uint32,
                 "Int64": np.int64, "UInt64": np.uint64}
"""FMI 2 and FMI 3 integer variable types and the NumPy type of their values (FMI 2's Integer is a
32-bit fmi2Integer; an Enumeration is set as fmi3Int64 in FMI 3, as fmi2Integer in FMI 2)."""


def whole_number(text: str, where: str, kind=np.int64) -> int:
    """``text`` as an integer within the range of the NumPy integer type ``kind``, exactly (also the
    64-bit extremes, which a float cannot hold); :class:`InputDataError` naming ``where`` otherwise.
    A number with a zero fraction (``3.0``) is accepted."""
    try:
        value = int(text)
    except ValueError:
        number = finite_number(text, where)
        if not number.is_integer():
            raise InputDataError(f"{where}: '{text}' is not a whole number (the input is an integer)") from None
        value = int(number)
    info = np.iinfo(kind)
    if not info.min <= value <= info.max:
        raise InputDataError(f"{where}: {value} is outside the range of {np.dtype(kind).name} "
                             f"({info.min} .. {info.max})")
    return value


def truth_value(text: str, where: str) -> bool:
    """``text`` (true/false or 1/0, any case) as a bool; :class:`InputDataError` naming ``where``
    otherwise."""
    word = text.strip().lower()
    if word in ("true", "1", "1.0"):
        return True
    if word in ("false", "0", "0.0"):
        return False
    raise InputDataError(f"{where}: '{text}' is not a Boolean (true, false, 1 or 0)")


def value_parser(variable):
    """How the values of an input ``variable`` are read: (parser of one cell, NumPy type), the
    parser called as ``parser(text, where)``; None for a real-valued variable (:func:`finite_number`)."""
    if variable is None:
        return None
    if variable.type in INTEGER_TYPES:
        kind = INTEGER_TYPES[variable.type]
        return (lambda text, where: whole_number(text, where, kind)), kind
    if variable.type == "Boolean":
        return truth_value, np.bool_
    return None


def read_input(path: Path, name: str, parser=None) -> tuple[np.ndarray, np.ndarray]:
    """Time [s] and value columns of the input file of ``--input NAME=FILE``: ``.npy`` by
    :func:`read_input_npy`, any other suffix as CSV by :func:`read_input_csv` (``parser``: see
    :func:`value_parser`; None: real values)."""
    path = Path(path)
    if path.suffix.lower() == ".npy":
        times, values = read_input_npy(path, name)
        if parser is not None:
            values = _parsed(values, parser, f"--input {name}: {path}")
        return times, values
    return read_input_csv(path, name, parser)


def _parsed(values: np.ndarray, parser, label: str) -> np.ndarray:
    """Real ``values`` of an ``.npy`` input converted by ``parser`` (rows counted from 1)."""
    parse, kind = parser
    return np.array([parse(repr(v), f"{label}: row {i + 1}") for i, v in enumerate(values.tolist())], dtype=kind)


def read_input_csv(path: Path, name: str, parser=None) -> tuple[np.ndarray, np.ndarray]:
    """Time [s] and value columns of an input CSV file, every cell checked.

    The file has a header row, then one row per time stamp. The value column is the column
    named ``name`` if the header has one (e.g. a result CSV of an earlier run), else the second
    of exactly two columns. Blank lines and lines starting with ``#`` are skipped. Times must
    not decrease; a repeated time stamp marks a jump.

    Time and memory grow linearly with the file: numpy's parser reads a file of plain numbers;
    a file it refuses, or whose numbers break a rule, is read again row by row by the checked
    reader, which names the first problem (or accepts what only numpy's parser refused, such as
    comment lines between the rows).

    Raises
    ------
    InputDataError
        Naming the file, the line (1-based, as an editor shows it) and the column of the first
        cell that is not a finite number, of a row with the wrong number of columns, or of a
        time that decreases; also for an empty file or one without data rows.
    """
    label = f"--input {name}: {path}"
    text = read_text_file(path, InputDataError, label, encoding="utf-8-sig")
    if parser is not None:  # integers and Booleans exactly, cell by cell
        return _read_csv_checked(text, name, label, parser)
    columns = _parse_plain_csv(text, name, label)
    return columns if columns is not None else _read_csv_checked(text, name, label)


def _parse_plain_csv(text: str, name: str, label: str) -> tuple[np.ndarray, np.ndarray] | None:
    """The time and value columns by numpy's parser, or None where the checked reader must decide:
    comments or quotes after the header, a cell numpy does not parse, a row of another length,
    a value that is not finite, a time that decreases, no data rows."""
    buffer = io.StringIO(text)
    reader = csv.reader(buffer)
    try:
        for row in reader:
            cells = [c.strip() for c in row]
            if any(cells) and not cells[0].startswith("#"):
                header, column = _input_header(cells, name, f"{label}:{reader.line_num}")
                break
        else:
            return None
    except csv.Error:
        return None
    # The csv reader takes the text line by line: the buffer stands at the line after the header.
    rest = buffer.tell()
    if text.find("#", rest) >= 0 or text.find('"', rest) >= 0 or not text[rest:].strip():
        return None
    try:
        data = np.loadtxt(buffer, delimiter=",", comments=None, dtype=np.float64, ndmin=2)
    except ValueError:
        return None
    if data.shape[1] != len(header):
        return None
    times, values = data[:, 0], data[:, column]
    if not (np.isfinite(times).all() and np.isfinite(values).all() and (np.diff(times) >= 0).all()):
        return None
    return np.ascontiguousarray(times), np.ascontiguousarray(values)


def _read_csv_checked(text: str, name: str, label: str, parser=None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`read_input_csv` row by row, every cell checked (one pass)."""
    parse, kind = parser if parser is not None else (finite_number, np.float64)
    reader = csv.reader(io.StringIO(text))
    header: list[str] | None = None
    column = 1
    times: list[float] = []
    values: list = []
    try:
        for row in reader:
            line = reader.line_num
            cells = [c.strip() for c in row]
            if not any(cells) or cells[0].startswith("#"):
                continue
            if header is None:
                header, column = _input_header(cells, name, f"{label}:{line}")
                continue
            if len(cells) != len(header):
                raise InputDataError(f"{label}:{line}: {len(cells)} column(s), but the header has "
                                     f"{len(header)} ({','.join(header)})")
            t = finite_number(cells[0], f"{label}:{line}: column 1 ({header[0]})")
            value = parse(cells[column], f"{label}:{line}: column {column + 1} ({header[column]})")
            if times and t < times[-1]:
                raise InputDataError(f"{label}:{line}: column 1 ({header[0]}): time {t:g} s is before the "
                                     f"previous row's {times[-1]:g} s (times must not decrease)")
            times.append(t)
            values.append(value)
    except csv.Error as exc:
        raise InputDataError(f"{label}:{reader.line_num}: malformed CSV: {exc}") from None
    if header is None:
        raise InputDataError(f"{label}: the file is empty (expected a header row such as 'time,{name}' "
                             "and rows of time,value)")
    if not times:
        raise InputDataError(f"{label}: no data rows after the header")
    return np.array(times), np.array(values, dtype=kind)


def _input_header(cells: list[str], name: str, where: str) -> tuple[list[str], int]:
    """The header row and the index of the value column."""
    numeric = True
    for cell in cells:
        try:
            float(cell)
        except ValueError:
            numeric = False
    if numeric:
        raise InputDataError(f"{where}: expected a header row (e.g. 'time,{name}'), got numbers")
    if name in cells[1:]:
        return cells, cells.index(name, 1)
    if len(cells) == 2:
        return cells, 1
    raise InputDataError(f"{where}: the header has {len(cells)} column(s) ({','.join(cells)}); expected "
                         f"two (time,value) or a column named '{name}'")


def read_input_npy(path: Path, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Time [s] and value columns of an input ``.npy`` file (:func:`numpy.save`), every value checked.

    The file holds either a structured one-dimensional array with a field ``time`` [s] and a
    field named ``name`` (e.g. a ``.npy`` result of an earlier run) -- or, if ``time`` and one
    other field are all it has, that field --, or a two-dimensional float array of two columns,
    time [s] and value. Times must not decrease; a repeated time stamp marks a jump.

    Raises
    ------
    InputDataError
        Naming the file for one that is not a ``.npy`` file or holds another kind of array, and
        the row (counted from 1) and the field or column of the first value that is not a finite
        number or of a time that decreases.
    """
    label = f"--input {name}: {path}"
    try:
        with open(path, "rb") as f:
            magic = f.read(6)
            f.seek(0)
            array = np.load(f, allow_pickle=False) if magic == b"\x93NUMPY" else None
    except OSError as exc:
        raise InputDataError(f"{label}: cannot read the file: {exc.strerror or exc}") from None
    except (ValueError, EOFError) as exc:  # a damaged header, truncated data, an object array
        raise InputDataError(f"{label}: not a readable .npy file: {' '.join(str(exc).split())}") from None
    if array is None:
        raise InputDataError(f"{label}: not a NumPy .npy file (it does not start with the .npy magic "
                             "string; numpy.save writes one)")
    expected = (f"expected a structured array with fields 'time' and '{name}' or a two-column float array "
                "of time [s] and value")
    if array.dtype.names is not None and array.ndim == 1:
        fields = array.dtype.names
        others = [f for f in fields if f != "time"]
        if "time" not in fields or (name not in fields and len(others) != 1):
            raise InputDataError(f"{label}: the array has the fields {', '.join(fields)}; {expected}")
        value_field = name if name in fields else others[0]
        columns = [(array["time"], "field 'time'"), (array[value_field], f"field '{value_field}'")]
    elif array.dtype.names is None and array.ndim == 2 and array.shape[1] == 2:
        columns = [(array[:, 0], "column 1 (time)"), (array[:, 1], f"column 2 ({name})")]
    else:
        raise InputDataError(f"{label}: an array of shape {array.shape} and type {array.dtype}; {expected}")
    if len(array) == 0:
        raise InputDataError(f"{label}: the array has no rows")
    checked = []
    for values, what in columns:
        if values.ndim != 1:
            raise InputDataError(f"{label}: {what} holds an array of shape {values.shape[1:]} per row, "
                                 "not one number")
        if values.dtype.kind not in "biuf":
            raise InputDataError(f"{label}: {what} holds {values.dtype} values, not real numbers")
        values = np.asarray(values, dtype=np.float64)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputDataError(f"{label}: row {bad[0] + 1}, {what}: {values[bad[0]]} is not a finite number "
                                 "(NaN and infinity are not accepted; rows counted from 1)")
        checked.append(np.ascontiguousarray(values))
    times, values = checked
    back = np.flatnonzero(np.diff(times) < 0)
    if back.size:
        i = back[0] + 1
        raise InputDataError(f"{label}: row {i + 1}, {columns[0][1]}: time {times[i]:g} s is before the "
                             f"previous row's {times[i - 1]:g} s (times must not decrease; rows counted from 1)")
    return times, values


def _step_signal(name: str, source: str, base, start_time: float, stop_time: float, parser=None):
    parse, kind = parser if parser is not None else (finite_number, np.float64)
    parts = source.split(":")
    if len(parts) != 3:
        raise ParameterError(f"--input {name}: expected step:T0:VALUE, got '{source}'")
    t0 = finite_number(parts[1], f"--input {name}: step time T0")
    value = parse(parts[2], f"--input {name}: step value")
    t0 = min(max(t0, start_time), stop_time)
    return np.array([start_time, t0, t0, stop_time]), np.array([base, base, value, value], dtype=kind)


def input_signals(fmu: Path, specs: list[str], start_time: float, stop_time: float) -> np.ndarray | None:
    """Build FMPy's structured input array from ``NAME=FILE.csv``, ``NAME=FILE.npy`` or
    ``NAME=step:T0:VALUE``.

    A file is read by :func:`read_input`; values of a continuous real input between rows are
    interpolated linearly, those of a discrete input (an integer, Boolean or enumeration, or a real
    of variability discrete) hold from their row to the next, as FMI defines a discrete signal
    (integers exactly, also beyond a float's 53 bits); a repeated time marks a jump (the value
    before and the value after it), and before the first and after the last row the first and
    the last value hold. The array starts at
    ``start_time`` with the value each signal has right after it: a jump at the start time (a
    step at T0 = the start time, or a file whose value jumps there) acts from the start, as a
    file holding the new value from the start would. Time and memory grow linearly with the
    rows of the files.

    Raises
    ------
    ParameterError
        For an unknown input, an input given twice, a malformed step or a String or Binary
        input (FMPy sets real, integer, Boolean and enumeration inputs only).
    InputDataError
        For a file that is missing or has a bad value (file, row and column named).
    """
    if not specs:
        return None
    _, variables = _variables(fmu)
    signals = {}
    for text in specs:
        name, source = split_assignment(text, "--input")
        variable = variables.get(name)
        if variable is None or variable.causality != "input":
            known = ", ".join(v.name for v in variables.values() if v.causality == "input") or "(none)"
            what = f"'{name}' is a {variable.causality}, not an input" if variable is not None \
                else f"unknown input '{name}'"
            raise ParameterError(f"--input: {what}; inputs are: {known}")
        if name in signals:
            raise ParameterError(f"--input {name} is given twice")
        if variable.type in ("String", "Binary"):
            raise ParameterError(f"--input {name}: {variable.type} inputs are not supported (real, integer, "
                                 "Boolean and enumeration inputs are)")
        parser = value_parser(variable)
        if source.startswith("step:"):
            start = variable.start if variable.start not in (None, "") else "0"
            base = (parser[0] if parser else finite_number)(str(start), f"--input {name}: start value")
            signals[name] = _step_signal(name, source, base, start_time, stop_time, parser)
        else:
            path = check_input_file(source, InputDataError, f"--input {name}: '{source}'")
            signals[name] = read_input(path, name, parser)
    discrete = {name for name in signals if variables[name].type not in ("Real", "Float32", "Float64")
                or variables[name].variability == "discrete"}
    return merge_signals(signals, start_time, discrete)


def merge_signals(signals: dict[str, tuple[np.ndarray, np.ndarray]], start_time: float,
                  discrete: set[str] | frozenset[str] = frozenset()) -> np.ndarray:
    """FMPy's structured input array (``time`` first) of signals given as (times [s], values).

    Between its own time stamps a signal is interpolated linearly, one named in ``discrete`` holds
    its value from one stamp to the next (and keeps its NumPy type: integers stay exact).

    The rows are the start time and every time stamp of any signal after it; where a signal
    jumps (a repeated time stamp) two rows of that time carry the values before and after the
    jump. At the start time each signal has the value right after it (a jump there acts from
    the start: FMPy applies the first row's values at the start, also in Model Exchange's
    initialization, and handles no input event at the start time itself). Vectorized: time and
    memory grow linearly with the rows (and a sort of the time stamps).
    """
    stamps, where = np.unique(np.concatenate([t for t, _ in signals.values()]), return_inverse=True)
    later = stamps > start_time
    grid = np.concatenate([[start_time], stamps[later]])
    before, after = [], []
    offset = 0
    for name, (times, values) in signals.items():
        # rows of this signal at or before each grid time (counted, not searched: linear in the rows)
        count = np.bincount(where.ravel()[offset:offset + len(times)], minlength=len(stamps))
        offset += len(times)
        upto = np.cumsum(count)
        at_start = np.searchsorted(times, start_time, side="left"), np.searchsorted(times, start_time, side="right")
        first = np.concatenate([[at_start[0]], (upto - count)[later]])  # rows before the time
        last = np.concatenate([[at_start[1]], upto[later]]) - 1  # the last row at or before it
        stamped = last >= first  # the signal has a row at this time: its first and last value there
        if name in discrete:  # the value of the last row at or before the time (the first one before it)
            between = values[np.maximum(last, 0)]
        else:  # holds the end values outside the signal's times
            between = np.interp(grid, times, np.asarray(values, dtype=np.float64))
        before.append(np.where(stamped, values[np.minimum(first, len(times) - 1)], between))
        after.append(np.where(stamped, values[np.maximum(last, 0)], between))
        before[-1][0] = after[-1][0]  # the start row: the values right after the start time
    jump = np.any([b != a for b, a in zip(before, after)], axis=0)
    index = np.repeat(np.arange(len(grid)), 1 + jump)
    right = np.zeros(len(index), dtype=bool)
    right[np.cumsum(1 + jump) - 1] = jump  # the second of the two rows of a jump
    dtype = [("time", np.float64)] + [(n, v.dtype if n in discrete else np.float64)
                                      for n, (_, v) in signals.items()]
    rows = np.empty(len(index), dtype=dtype)
    rows["time"] = grid[index]
    for k, name in enumerate(signals):
        rows[name] = np.where(right, after[k][index], before[k][index])
    return rows


# --------------------------------------------------------------------------- running

class _Progress:
    """A one-line progress bar on stderr for runs that take a while; keeps FMPy's recorder so
    that the rows computed before a solver failure can be recovered, and in an isolated worker
    sends each new row to the caller before the next step."""

    def __init__(self, start: float, stop: float, enabled: bool, worker=None):
        self.start, self.stop, self.enabled, self.last = start, stop, enabled, -1
        self.recorder = None
        self.worker, self.sent = worker, 0
        self.stream = sys.stderr

    def __call__(self, time, recorder):
        self.recorder = recorder
        if self.worker is not None:
            if self.sent == 0:
                self.worker.send("dtype", recorder.cols)
            rows = recorder.rows
            if len(rows) > self.sent:
                self.worker.send("rows", rows[self.sent:])
                self.sent = len(rows)
        if self.enabled and self.stop > self.start:
            percent = int(100 * (time - self.start) / (self.stop - self.start))
            if percent != self.last:
                self.last = percent
                bar = "#" * (percent // 4)
                print(f"\r[{bar:<25}] {percent:3d}%  t = {time:.3g} s", end="", file=self.stream, flush=True)
        return True

    def close(self):
        if self.enabled and self.last >= 0:
            print(file=self.stream)

    def rows(self):
        """What the recorder holds (None if no step finished)."""
        return None if self.recorder is None else np.asarray(self.recorder.result())


def _interval(md, start_time: float | None, stop_time: float | None) -> tuple[float, float]:
    experiment = md.defaultExperiment
    t0 = start_time if start_time is not None else (
        float(experiment.startTime) if experiment and experiment.startTime not in (None, "") else 0.0)
    t1 = stop_time if stop_time is not None else (
        float(experiment.stopTime) if experiment and experiment.stopTime not in (None, "") else t0 + 1.0)
    return t0, t1


def default_step(md) -> tuple[float, str]:
    """The communication step [s] of a run without ``--step``, and where it comes from.

    The FMU's DefaultExperiment stepSize (the model's ``experiment(Interval=...)``) if it
    declares a positive one, else :data:`DEFAULT_STEP`. It does not depend on the stop time:
    a longer run has more rows, never coarser ones (:func:`check_run` refuses more than
    :data:`MAX_ROWS`).
    """
    experiment = md.defaultExperiment
    try:
        declared = float(experiment.stepSize) if experiment and experiment.stepSize not in (None, "") else None
    except (TypeError, ValueError):
        declared = None
    if declared is not None and math.isfinite(declared) and declared > 0:
        return declared, "the FMU's DefaultExperiment stepSize"
    return DEFAULT_STEP, "the default for an FMU without a DefaultExperiment stepSize"


def check_run(md, stop_time: float | None, step: float | None, fmi_type: str, start_time: float | None = None,
              parameters: dict | None = None) -> tuple[float, float]:
    """Refuse settings that cannot give a meaningful run (before anything runs); returns (t0, t1).

    With ``md`` None only the checks that need no model description are made (returns NaNs).
    Without ``step`` the run's rows are counted at :func:`default_step`.

    Raises
    ------
    ParameterError
        A non-finite or non-positive step, a stop time that is not after the start, a run of
        more than :data:`MAX_ROWS` output rows (also at the default step: one message naming the
        step and the rows, never a silently coarser step), or ``solver.fixedStepSize`` with
        Model Exchange.
    """
    if fmi_type not in ("cs", "me"):
        raise ParameterError(f"--fmi-type must be 'cs' or 'me', got '{fmi_type}'")
    if stop_time is not None and not math.isfinite(stop_time):
        raise ParameterError(f"--stop-time must be finite, got {stop_time}")
    if step is not None and not (math.isfinite(step) and step > 0):
        raise ParameterError(f"--step must be a finite number > 0 s, got {step}")
    if fmi_type == "me" and (parameters or {}).get(FIXED_STEP_PARAMETER):
        raise ParameterError(f"{FIXED_STEP_PARAMETER} sets the FMU's own Co-Simulation solver; with "
                             "--fmi-type me FMPy's CVode integrates (drop the parameter or use --fmi-type cs)")
    if md is None:  # the checks that need no model description, before a model is built
        return math.nan, math.nan
    t0, t1 = _interval(md, start_time, stop_time)
    if not t1 > t0:
        raise ParameterError(f"--stop-time ({t1:g} s) must be after the start time ({t0:g} s)")
    if step is not None and (t1 - t0) / step > MAX_ROWS:
        raise ParameterError(f"--step {step:g} s over {t1 - t0:g} s would record {(t1 - t0) / step:.3g} rows "
                             f"(at most {MAX_ROWS:,}); use a larger --step")
    if step is None:
        h, source = default_step(md)
        if (t1 - t0) / h > MAX_ROWS:
            raise ParameterError(f"--stop-time {t1:g} s with the default step of {h:g} s ({source}) would "
                                 f"record {(t1 - t0) / h:.3g} rows (at most {MAX_ROWS:,}); give a --step of at "
                                 f"least {(t1 - t0) / MAX_ROWS:.3g} s or a shorter --stop-time")
    return t0, t1


def simulate(fmu: str | Path, stop_time: float | None = None, step: float | None = None, fmi_type: str = "cs",
             parameters: dict | None = None, inputs: np.ndarray | None = None, start_time: float | None = None,
             relative_tolerance: float | None = None, outputs: list[str] | None = None,
             progress: bool = False, isolate: bool | None = None, timeout: float | None = DEFAULT_TIMEOUT,
             lenient: bool = False) -> np.ndarray:
    """Simulate an FMU with FMPy and return the result as a structured array (column ``time`` first).

    Parameters
    ----------
    fmu : path
        The FMU file (FMI 2.0 or 3.0).
    stop_time, start_time : float, optional
        Simulation interval in s (default: the FMU's DefaultExperiment).
    step : float, optional
        Output interval / communication step in s (default: :func:`default_step`, the FMU's
        DefaultExperiment stepSize or :data:`DEFAULT_STEP`, whatever the stop time).
    fmi_type : {'cs', 'me'}
        Co-Simulation (the FMU's own integrator) or Model Exchange (FMPy's CVode).
    parameters : dict, optional
        Start values by variable name.
    inputs : structured array, optional
        Input signals as built by :func:`input_signals`.
    isolate : bool, optional
        Run the FMU's binary in a guarded child process (:mod:`cosim.fmu.isolation`), so that a
        crash, ``exit`` or hang of the binary ends the run with the rows computed so far instead
        of ending this process. Default: for every FMU not built by this project.
    timeout : float or None
        With ``isolate``: longest time [s] the FMU may go without completing a step (default
        :data:`~cosim.fmu.isolation.DEFAULT_TIMEOUT`); None: no limit.
    lenient : bool
        Open the FMU even if its model description fails FMPy's checks, each finding a warning
        (see :func:`cosim.fmu.access.read_fmu`).

    Raises
    ------
    FMUError
        The file is not a usable FMU (see :func:`cosim.fmu.access.read_fmu`).
    ParameterError
        Settings refused by :func:`check_run`.
    IncompleteResult
        The solver failed part-way, the FMU ended the run early with an error message (or at a
        singular configuration of the model), its process ended abnormally or stopped answering,
        or an output turned non-finite; carries the rows up to the failure and the cause.

    Warns
    -----
    SimulationTerminated
        The FMU ended the run itself before the stop time without an error
        (``terminateSimulation``): a normal end; the rows up to that time are returned.
    SimulationError
        The FMU failed before the first step (nothing computed).
    """
    fmu = Path(fmu)
    # FMPy's simulate_fmu runs FMI 2 and FMI 3 alike
    handle = FMU(fmu, versions=ALL_FMI_VERSIONS, lenient=lenient)
    md = handle.description
    t0, t1 = check_run(md, stop_time, step, fmi_type, start_time, parameters)
    step = step if step is not None else default_step(md)[0]
    run = _Run(handle, t0, t1, step, "cs" if fmi_type == "cs" else "me", dict(parameters or {}), inputs,
               relative_tolerance, outputs, progress)
    if isolate is None:
        isolate = can_isolate() and not built_here(fmu)
    result = _finite(fmu, md, text_as_str(_run_isolated(run, timeout) if isolate else run(None)), t1)
    if _ended_early(result, t1):
        warnings.warn(SimulationTerminated(float(result["time"][-1])), stacklevel=2)
    return result


def _ended_early(result: np.ndarray, t1: float) -> bool:
    """Whether the last row of ``result`` lies before the stop time ``t1`` [s]."""
    return bool(result.size) and result["time"][-1] < t1 - 1e-9 * max(1.0, abs(t1))


class _Run:
    """One simulation with FMPy, run here or in an isolated worker (``worker`` not None: rows and
    the FMI call in progress are reported to the caller as they come)."""

    def __init__(self, handle, t0, t1, step, kind, parameters, inputs, relative_tolerance, outputs, progress):
        self.handle, self.t0, self.t1, self.step, self.kind = handle, t0, t1, step, kind
        self.parameters, self.inputs, self.relative_tolerance = parameters, inputs, relative_tolerance
        self.outputs, self.progress = outputs, progress
        self.prefix = "fmi3" if handle.is_fmi3 else "fmi2"

    def stepping(self) -> str:
        """The calls between two rows."""
        return f"{self.prefix}DoStep" if self.kind == "cs" else \
            f"the integration ({self.prefix}GetDerivatives and the other calls of CVode)"

    def __call__(self, worker) -> np.ndarray:
        from fmpy import simulate_fmu

        handle, md, fmu, t1 = self.handle, self.handle.description, self.handle.path, self.t1
        if self.kind == "me":
            _guard_cvode_cleanup()
        log = FMULog()
        if worker is not None:
            worker.doing(f"{self.prefix}Instantiate")
        instance = handle.instantiate(self.kind, name=md.modelName, log=log)
        bar = _Progress(self.t0, t1, self.progress, worker)
        if worker is not None:
            bar.stream = worker.stderr
        if worker is not None:
            worker.doing(f"the initialization ({self.prefix}EnterInitializationMode .. ExitInitializationMode)")
            _report_after(instance, "exitInitializationMode", lambda: worker.doing(self.stepping()))
        # The worst FMI status seen decides which calls the clean-up may still make; FMPy itself
        # calls fmi2Terminate at the end of a run that succeeds.
        state = {"status": 0, "terminated": False}
        quiet = _solver_output_hidden(bar) if self.kind == "me" else contextlib.nullcontext()
        try:
            with quiet, _strings_recorded():
                result = simulate_fmu(
                    handle.unzipdir, start_time=self.t0, stop_time=t1, output_interval=self.step,
                    fmi_type="CoSimulation" if self.kind == "cs" else "ModelExchange",
                    start_values=self.parameters, input=self.inputs, relative_tolerance=self.relative_tolerance,
                    output=self.outputs, step_finished=bar, validate=False, model_description=md,
                    fmu_instance=instance,
                )
            state["terminated"] = True
        except Exception as exc:  # FMPy raises FMICallException, RuntimeError (CVode), bare Exception
            state["status"] = int(getattr(exc, "status", 0) or 0)
            raise _failure(fmu, md, exc, log, bar.rows(), t1) from None
        finally:
            bar.close()
            if worker is not None:
                worker.doing(f"the clean-up ({self.prefix}Terminate, {self.prefix}FreeInstance)")
            _release(instance, state["status"], state["terminated"])
        result = np.asarray(result)
        if _ended_early(result, t1):
            # The FMU ended the run itself (terminateSimulation; in FMI 2 CS fmi2Discard +
            # fmi2Terminated): FMPy returns what it has. Without an error message or a physical
            # cause that is the model's own end (see simulate); with one it is a failure.
            said = log.last_error()
            cause = _cause(md, result, fmu)
            if not said and not cause:
                return result
            text = f"{cause} (solver: {_first_clause(said)})" if cause and said else \
                cause or said or "the FMU ended the run early"
            raise IncompleteResult(f"{fmu}: the simulation stopped at t = {result['time'][-1]:.6g} s of "
                                   f"{t1:g} s: {text}", result, float(result["time"][-1]), cause or text)
        return result


@contextlib.contextmanager
def _strings_recorded():
    """FMPy's recorder samples numbers only: within this context it also records the scalar String
    outputs it is asked for (one column each, the text at every sample, after the numbers)."""
    import fmpy.simulation

    original = fmpy.simulation.Recorder

    class Recorder(original):
        def __init__(self, fmu, modelDescription, variableNames=None, interval=None):
            super().__init__(fmu, modelDescription, variableNames=variableNames, interval=interval)
            wanted = set(variableNames) if variableNames is not None else \
                {v.name for v in modelDescription.modelVariables if v.causality == "output"}
            self.text = [v for v in modelDescription.modelVariables
                         if v.name in wanted and v.type == "String" and not getattr(v, "dimensions", None)]
            self.cols += [(v.name, object) for v in self.text]

        def sample(self, time, force=False):
            super().sample(time, force=force)
            if self.text:
                values = self.fmu.getString([v.valueReference for v in self.text])
                self.rows[-1] += tuple(_text(v) for v in values)

    fmpy.simulation.Recorder = Recorder
    try:
        yield
    finally:
        fmpy.simulation.Recorder = original


def _text(value) -> str:
    """A String value as FMPy returns it (FMI 2: bytes or None, FMI 3: str) as str."""
    if value is None:
        return ""
    return value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)


def numeric_names(result: np.ndarray) -> list[str]:
    """The columns of ``result`` other than ``time`` that hold numbers (not String outputs)."""
    return [n for n in result.dtype.names if n != "time" and result.dtype[n].base.kind in "biuf"]


def text_as_str(result: np.ndarray) -> np.ndarray:
    """``result`` with its String columns (Python objects as recorded) as NumPy str fields, which
    ``numpy.save`` stores without pickling."""
    result = np.asarray(result)
    if result.dtype.names is None or not any(result.dtype[n].kind == "O" for n in result.dtype.names):
        return result
    fields = []
    for n in result.dtype.names:
        if result.dtype[n].kind == "O":
            width = max([len(_text(v)) for v in result[n]] + [1])
            fields.append((n, f"<U{width}"))
        else:
            fields.append((n, result.dtype[n]))
    converted = np.empty(result.shape, dtype=fields)
    for n in result.dtype.names:
        converted[n] = [_text(v) for v in result[n]] if result.dtype[n].kind == "O" else result[n]
    return converted


@contextlib.contextmanager
def _solver_output_hidden(bar: "_Progress"):
    """Keep CVode's own printing off the terminal while it integrates: SUNDIALS writes warnings to
    the C stdout and errors to the C stderr, and an FMU call refused inside FMPy's right-hand-side
    callback raises in a ctypes callback, which Python prints as a traceback each time CVode
    retries. The failure still ends the run with one message (CVode's error is in the exception
    FMPy raises). The progress bar keeps the real stderr."""
    for stream in (sys.stdout, sys.stderr):
        stream.flush()
    saved = {fd: os.dup(fd) for fd in (1, 2)}
    previous_hook = sys.unraisablehook
    stream = bar.stream
    try:
        with tempfile.TemporaryFile() as sink:
            for fd in saved:
                os.dup2(sink.fileno(), fd)
            sys.unraisablehook = lambda unraisable: None
            bar.stream = os.fdopen(os.dup(saved[2]), "w")
            try:
                yield
            finally:
                bar.stream.close()
                bar.stream = stream
    finally:
        sys.unraisablehook = previous_hook
        for fd, copy in saved.items():
            os.dup2(copy, fd)
            os.close(copy)


def _report_after(instance, method: str, report) -> None:
    """Call ``report()`` after each return of ``instance.method`` (FMPy calls it by attribute)."""
    call = getattr(instance, method)

    def reported(*args, **kwargs):
        value = call(*args, **kwargs)
        report()
        return value

    setattr(instance, method, reported)


def _run_isolated(run: _Run, timeout: float | None) -> np.ndarray:
    """``run`` in a guarded worker process; a fault of the binary keeps the rows it streamed."""
    received: dict = {"dtype": None, "rows": []}

    def on_message(kind, payload):
        if kind == "dtype":
            received["dtype"] = payload
        elif kind == "rows":
            received["rows"].extend(payload)

    fmu = run.handle.path
    try:
        return run_isolated(run, what=str(fmu), timeout=timeout, on_message=on_message)
    except FMUProcessError as exc:
        rows = np.array(received["rows"], dtype=np.dtype(received["dtype"])) if received["dtype"] else None
        stepping = exc.doing == run.stepping()
        if rows is None or len(rows) == 0:
            raise SimulationError(f"{fmu}: simulation failed before the first step: the FMU {exc.what} "
                                  f"during {exc.doing}") from None
        last = float(rows["time"][-1])
        during = f"{exc.doing} from t = {last:.6g} s" if stepping else exc.doing
        cause = f"the FMU {exc.what} during {during}"
        raise IncompleteResult(f"{fmu}: {cause}", rows, last, cause) from None


def _finite(fmu: Path, md, result: np.ndarray, t1: float) -> np.ndarray:
    """``result`` if every recorded value is finite; else the rows before the first non-finite one
    as an IncompleteResult naming the variable and the time."""
    names = numeric_names(result)
    if not names or not len(result):
        return result
    table = np.column_stack([result[n] for n in names])
    bad = ~np.isfinite(table)
    if not bad.any():
        return result
    row, column = np.argwhere(bad)[0]
    when = float(result["time"][row])
    cause = f"output {names[column]} is {table[row, column]} at t = {when:.6g} s"
    rows = result[:row]
    raise IncompleteResult(f"{fmu}: the simulation stopped at t = {when:.6g} s of {t1:g} s: {cause}", rows,
                           when, cause)


def _guard_cvode_cleanup() -> None:
    """Keep FMPy's CVode wrapper from printing a traceback after a failed start.

    ``fmpy.sundials.CVodeSolver.__del__`` frees ``self.cvode_mem``, which ``__init__`` sets only
    after its first calls into the FMU (``GetContinuousStates``, ``GetNominalsOfContinuousStates``).
    An FMU that refuses one of them (e.g. a model description whose number of states differs from
    the binary's) leaves a half-made solver whose ``__del__`` raises AttributeError, which Python
    prints as "Exception ignored in ... Traceback" after our one-line message. A class-level
    ``None`` makes that clean-up ``CVodeFree(NULL)``, which SUNDIALS ignores; a solver that was
    made has its own attribute and is freed as before."""
    from fmpy.sundials import CVodeSolver

    if not hasattr(CVodeSolver, "cvode_mem"):
        CVodeSolver.cvode_mem = None


def _release(instance, status: int, terminated: bool = False) -> None:
    """Terminate and free an instance as far as FMI allows after ``status`` (the same rule in FMI
    2.0 and 3.0): Terminate is not allowed after Error, nothing at all after Fatal."""
    if status >= 4:
        return
    if status < 3 and not terminated:
        try:
            instance.terminate()
        except Exception:  # already terminated by FMPy, or refused: freeing is still allowed
            pass
    try:
        instance.freeInstance()
    except Exception:
        pass


def _solver_message(exc: Exception, log) -> tuple[str, float | None]:
    """The solver's own words and the failure time where it states one."""
    said = log.last_error()
    text = str(exc)
    cvode = re.search(r"CVode error \(code (-?\d+)\).*?:\s*(At t = .*)$", text)
    if cvode:
        text = f"CVode: {cvode.group(2)}"
    elif said:
        text = said
    when = re.search(r"at t = ([-+0-9.eE]+)", text, re.IGNORECASE)
    try:
        return text, float(when.group(1).rstrip(".,")) if when else None
    except ValueError:
        return text, None


def _failure(fmu: Path, md, exc: Exception, log, rows, t1: float) -> SimulationError:
    """The exception for a run that failed: IncompleteResult if any step was completed."""
    text, when = _solver_message(exc, log)
    if rows is None or len(rows) == 0:
        return SimulationError(f"{fmu}: simulation failed before the first step: {text}")
    cause = _cause(md, rows, fmu)
    when = when if when is not None else float(rows["time"][-1])
    message = f"{fmu}: the solver failed at t = {when:.6g} s of {t1:g} s"
    message += f": {cause} (solver: {_first_clause(text)})" if cause else f": {text}"
    return IncompleteResult(message, rows, when, cause or text)


def _first_clause(text: str) -> str:
    """The solver's message up to its first ``;`` (the rest repeats what the cause says)."""
    return text.split(";", 1)[0].strip()


def model_singularities(model_name: str):
    """The singular configurations ``model_name`` declares (:func:`cosim.compiler.catalog.
    singular_configurations`); empty for a model the library does not have (an FMU from
    elsewhere) or whose annotation cannot be read (the failure is reported without it)."""
    try:
        return singular_configurations(model_name)
    except CosimError:
        return ()


def _cause(md, rows, fmu: Path) -> str | None:
    """:func:`physical_cause` of a failed run of the FMU ``fmu`` described by ``md``, with the
    singular configurations its model declares; none for an FMU from elsewhere, whose model name
    says nothing about this library's models (and needs no reading of the library)."""
    singular = model_singularities(md.modelName) if built_here(fmu) else ()
    return physical_cause(_last_values(rows), singular)


def _last_values(rows) -> dict[str, float]:
    if rows is None or len(rows) == 0:
        return {}
    return {n: float(rows[n][-1]) for n in numeric_names(rows) if not rows.dtype[n].shape}


def physical_cause(values: dict[str, float], singular=None) -> str | None:
    """The physical reason a bicycle run broke down, read from its last output values.

    Parameters
    ----------
    values : dict
        Output name -> last value; names may carry a component prefix (``bike.delta``).
    singular : sequence of Singularity, optional
        The singular configurations of the model that ran
        (:func:`cosim.compiler.catalog.singular_configurations`, read from its
        ``__Cosim(singular(...))`` annotation); an output whose name (without prefix) is a
        declared variable and whose value lies in the declared band is named. None (the model is
        not known, e.g. a component of a system) takes those of every model of the library that
        declares any, matched by variable name.

    Also recognized: ``residual`` (holonomic constraint residual of the nonlinear Whipple models,
    m) above :data:`RESIDUAL_LIMIT`.

    Returns
    -------
    str or None
        E.g. "steer angle delta = 1.607 rad (92.1 deg) reached +-pi/2 (+-90 deg), a singular
        configuration of Bicycle.Bicycles.Whipple: the front wheel ..."; None if no output shows a
        known limit.
    """
    declared = _library_singularities() if singular is None else tuple(singular)
    found = []
    for name, value in values.items():
        short = name.rpartition(".")[2]
        for s in declared:
            if s.variable == short and s.reached(value):
                degrees = math.degrees(s.angle)
                at = "+-pi/2 (+-90 deg)" if abs(degrees - 90.0) < 1e-9 else f"+-{degrees:g} deg"
                what = f"{s.quantity} {name}" if s.quantity else name
                found.append((s.distance(value) / s.tolerance,
                              f"{what} = {value:.4g} rad ({math.degrees(value):.1f} deg) reached {at}, "
                              f"a singular configuration of {s.model}: {s.description}"))
                break
        if short == "residual" and (not math.isfinite(value) or abs(value) > RESIDUAL_LIMIT):
            found.append((-math.inf, f"the constraint residual {name} grew to {value:.3g} m "
                                     f"(more than {RESIDUAL_LIMIT:g} m): the solution left the constraint"))
    return "; ".join(text for _, text in sorted(found)) if found else None


def _library_singularities():
    """Every singular configuration declared in the library, for :func:`physical_cause` without a
    model (one per model and variable; the first model that declares a variable names it)."""
    try:
        library = load_library()
    except CosimError:
        return ()
    found = {}
    for name, entry in library.entries.items():
        cosim = entry.annotation.get("__Cosim")
        if isinstance(cosim, dict) and cosim.get("singular") is not None:
            for s in model_singularities(name):
                found.setdefault(s.variable, s)
    return tuple(found.values())


# --------------------------------------------------------------------------- writing results

def check_result_output(path: str | Path, option: str = "-o") -> Path:
    """Refuse a result path with an unknown suffix or that cannot be written (before any work)."""
    path = check_output(path, "result file")
    if path.suffix.lower() not in RESULT_FORMATS:
        known = " or ".join(f"{s} ({d})" for s, d in RESULT_FORMATS.items())
        raise ParameterError(f"{option} {path}: unknown result format '{path.suffix or '(no suffix)'}'; "
                             f"use {known}")
    check_output(incomplete_path(path), "result file")
    return path


def check_plot_output(path: str | Path, option: str = "--plot") -> Path:
    """Refuse a plot path whose format matplotlib does not write, or that cannot be written."""
    path = check_output(path, "plot file")
    formats = _plot_formats()
    if path.suffix.lower().lstrip(".") not in formats:
        raise ParameterError(f"{option} {path}: unknown image format '{path.suffix or '(no suffix)'}'; "
                             f"use one of {', '.join('.' + f for f in sorted(formats))}")
    check_output(incomplete_path(path), "plot file")
    return path


def _plot_formats() -> set[str]:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    return set(Figure().canvas.get_supported_filetypes())


def incomplete_path(path: str | Path) -> Path:
    """Where a result that stopped early goes: ``out.csv`` -> ``out.incomplete.csv``."""
    path = Path(path)
    return path.with_name(f"{path.stem}.{INCOMPLETE_TAG}{path.suffix}")


def write_result(result: np.ndarray, path: str | Path) -> Path:
    """Write a result array as CSV (:func:`write_csv`: arrays flattened to one column per value) or
    NPY (by suffix), atomically. NPY keeps the structured array as it is: an array variable stays
    one field of its shape (``numpy.load(path)["y"]`` has the shape ``(rows, n)``)."""
    path = Path(path)
    if path.suffix.lower() == ".npy":
        with output_files.atomic_output(path, "result file") as tmp:
            np.save(tmp, text_as_str(result), allow_pickle=False)
        return path
    return write_csv(result, path)


def write_csv(result: np.ndarray, path: str | Path) -> Path:
    """Write a result array to CSV with a header row (atomically: complete or absent).

    One column per value: an array variable (an FMI 3 variable with dimensions, a field of shape
    ``(n,)`` or ``(n, m, ...)``) is flattened row-major to the columns ``name[1]``, ``name[2]``, ...
    or ``name[1,1]``, ``name[1,2]``, ... (1-based, as Modelica and FMI index arrays), so that every
    column has its own unique name. A name holding a comma is quoted (RFC 4180)."""
    # 64-bit integers (FMI 3 Int64, UInt64) are written exactly, which a float cannot hold; the text
    # of a String output as it is (quoted where RFC 4180 asks for it)
    wide = any((result.dtype[n].base.kind in "iu" and result.dtype[n].base.itemsize == 8)
               or result.dtype[n].base.kind in "OUS" for n in result.dtype.names)
    names, columns, formats = [], [], []
    for name in result.dtype.names:
        base = result.dtype[name].base
        exact = wide and base.kind in "iub"
        text = base.kind in "OUS"
        values = np.asarray(result[name], dtype=object if exact or text else float)
        if exact:
            values = np.vectorize(int, otypes=[object])(values) if values.size else values
        if text:
            values = np.array([_csv_cell(_text(v)) for v in values.ravel()], dtype=object).reshape(values.shape)
        shape = result.dtype[name].shape
        count = int(np.prod(shape)) if shape else 1
        formats += ["%s" if text else "%d" if exact else "%.17g"] * count
        if not shape:
            names.append(name)
            columns.append(values.reshape(len(result), 1))
            continue
        names += [f"{name}[{','.join(str(i + 1) for i in index)}]" for index in np.ndindex(*shape)]
        columns.append(values.reshape(len(result), count))  # C order: last index fastest
    data = np.hstack(columns) if columns else np.zeros((len(result), 0))
    header = io.StringIO()
    csv.writer(header, lineterminator="").writerow(names)
    with output_files.atomic_output(path, "result file") as tmp:
        np.savetxt(tmp, data, delimiter=",", header=header.getvalue(), comments="",
                   fmt=formats if wide else "%.17g")
    return Path(path)


def _csv_cell(text: str) -> str:
    """``text`` as one CSV cell: quoted (quotes doubled) if it holds a comma, a quote or a line break."""
    if any(c in text for c in ',"\r\n'):
        return '"' + text.replace('"', '""') + '"'
    return text


#: At most this many panels in a plot whose signals are not chosen (``--signals``).
PLOT_PANELS = 4
#: The signals a plot shows when it chooses (matched on the name after the last ``.``, so
#: ``bike.phi`` is ``phi``): the roll and steer angles first, then the model's inputs, then the
#: torques, the forward speed and the lateral position, then the others in the result's order,
#: :data:`PLOT_PANELS` in all.
PLOT_FIRST = ("phi", "delta")
PLOT_THEN = ("T_delta", "T", "T_phi", "v", "V", "y", "eta")


def plot_signals(result: np.ndarray, signals: list[str] | None = None, inputs=()) -> list[str]:
    """The columns of ``result`` that :func:`plot` draws, one panel each.

    Parameters
    ----------
    result : numpy structured array
        A result with a ``time`` column [s].
    signals : list of str, optional
        The columns to draw, in this order; default: at most :data:`PLOT_PANELS`, chosen as
        :data:`PLOT_FIRST` describes.
    inputs : sequence of str
        The model's input names, preferred after the roll and steer angles.

    Raises
    ------
    ParameterError
        If a name of ``signals`` is not a numeric column of ``result``; the message lists them.
    """
    names = numeric_names(result)
    if signals is not None:
        check_signals(signals, names)
        return list(dict.fromkeys(signals))
    if len(names) <= PLOT_PANELS:
        return names
    base = {n: n.rsplit(".", 1)[-1] for n in names}
    ranked = [*PLOT_FIRST, *inputs, *PLOT_THEN]
    order = sorted(names, key=lambda n: (ranked.index(base[n]) if base[n] in ranked else len(ranked),
                                         names.index(n)))
    return order[:PLOT_PANELS]


def variable_units(md, prefix: str = "") -> dict:
    """Variable name (with ``prefix`` before it) -> unit, as the model description ``md`` declares
    it (on the variable or on its declared type); variables without a unit are left out."""
    units = {}
    for v in md.modelVariables:
        unit = getattr(v, "unit", None) or getattr(getattr(v, "declaredType", None), "unit", None)
        if unit:
            units[prefix + v.name] = unit
    return units


def check_signals(signals: list[str], available: list[str], option: str = "--signals") -> None:
    """Refuse names that are not among ``available`` (one message listing those available)."""
    unknown = [s for s in signals if s not in available]
    if unknown:
        raise ParameterError(f"{option}: unknown signal(s) {', '.join(unknown)}; available: {', '.join(available)}")
    if not signals:
        raise ParameterError(f"{option}: no signal named; available: {', '.join(available)}")


def plot(result: np.ndarray, path: str | Path, title: str = "", units: dict | None = None,
         signals: list[str] | None = None, inputs=()) -> Path:
    """One subplot per signal against time, saved as an image (atomically).

    Parameters
    ----------
    result : numpy structured array
        A result with a ``time`` column [s].
    path : path
        The image file; its suffix gives the format.
    title : str
        The title above the first panel.
    units : dict, optional
        Signal name -> unit (the model description's); a signal in ``rad`` is drawn in degrees,
        for display only. A signal without a unit is labelled "no unit declared".
    signals, inputs
        Which signals, as :func:`plot_signals` chooses them.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    names = plot_signals(result, signals, inputs)
    fig, axes = plt.subplots(len(names) or 1, 1, sharex=True, figsize=(7, 1.8 * max(1, len(names))), squeeze=False)
    try:
        for ax, name in zip(axes[:, 0], names):
            values, unit = np.asarray(result[name], dtype=float), units.get(name)
            if unit == "rad":  # angles are read in degrees
                values, unit = np.degrees(values), "deg"
            ax.plot(result["time"], values)
            ax.set_ylabel(f"{name} [{unit}]" if unit else f"{name}\n(no unit declared)")
            ax.grid(True)
        axes[-1, 0].set_xlabel("time [s]")
        if title:
            axes[0, 0].set_title(title)
        fig.tight_layout()
        with output_files.atomic_output(path, "plot file") as tmp:
            fig.savefig(tmp, dpi=120)
    finally:
        plt.close(fig)
    return Path(path)
