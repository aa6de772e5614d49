"""`cosim simulate`: run an FMU (ME with CVode or CS with its own solver) through FMPy.

What the command promises (see ``cosim simulate --help``):

- the FMU is opened through :func:`cosim.fmu.access.read_fmu` (one message for a damaged file);
- inputs from CSV files are checked cell by cell (file, line and column named for a cell that is
  not a finite number);
- results are written under a temporary name and renamed (:mod:`cosim.outputs`): ``.csv`` (a
  header row, then one row per output time) or ``.npy`` (a NumPy structured array);
- when the solver fails part-way, the rows computed up to the failure are kept: they are written
  to ``NAME.incomplete.csv`` (``.npy``) beside the requested ``NAME.csv`` and the message names
  the physical cause where the model's outputs show one: a singular configuration the model
  declares in its ``__Cosim(singular(...))`` annotation (the nonlinear Whipple bicycles: steer
  or roll angle at ±π/2, see :func:`cosim.compiler.catalog.singular_configurations`), or the
  constraint residual growing; see :func:`physical_cause`.
"""
from __future__ import annotations

import csv
import io
import math
import re
import sys
from pathlib import Path

import numpy as np

from cosim.errors import InputDataError, ParameterError, SimulationError
from cosim.outputs import check_input_file, read_text_file
from cosim.fmu.parameters import split_assignment

#: Result formats by file suffix (``-o``).
RESULT_FORMATS = {".csv": "CSV text with a header row", ".npy": "a NumPy structured array for numpy.load"}
#: Most output rows one command records (a guard against ``--stop-time 1e9 --step 1e-6``).
MAX_ROWS = 10_000_000
#: Where a result that stopped early goes: ``out.csv`` -> ``out.incomplete.csv``.
INCOMPLETE_TAG = "incomplete"

RESIDUAL_LIMIT = 1e-6  # m: holonomic constraint residual of the nonlinear Whipple models


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


def _variables(fmu: Path):
    from cosim.fmu.access import ALL_FMI_VERSIONS, read_fmu

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


def read_input_csv(path: Path, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Time [s] and value columns of an input CSV file, every cell checked.

    The file has a header row, then one row per time stamp. The value column is the column
    named ``name`` if the header has one (e.g. a result CSV of an earlier run), else the second
    of exactly two columns. Blank lines and lines starting with ``#`` are skipped. Times must
    not decrease; a repeated time stamp marks a jump.

    Raises
    ------
    InputDataError
        Naming the file, the line (1-based, as an editor shows it) and the column of the first
        cell that is not a finite number, of a row with the wrong number of columns, or of a
        time that decreases; also for an empty file or one without data rows.
    """
    label = f"--input {name}: {path}"
    text = read_text_file(path, InputDataError, label, encoding="utf-8-sig")
    reader = csv.reader(io.StringIO(text))
    header: list[str] | None = None
    column = 1
    times: list[float] = []
    values: list[float] = []
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
            value = finite_number(cells[column], f"{label}:{line}: column {column + 1} ({header[column]})")
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
    return np.array(times), np.array(values)


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


def _step_signal(name: str, source: str, base: float, start_time: float, stop_time: float):
    parts = source.split(":")
    if len(parts) != 3:
        raise ParameterError(f"--input {name}: expected step:T0:VALUE, got '{source}'")
    t0 = finite_number(parts[1], f"--input {name}: step time T0")
    value = finite_number(parts[2], f"--input {name}: step value")
    t0 = min(max(t0, start_time), stop_time)
    return np.array([start_time, t0, t0, stop_time]), np.array([base, base, value, value])


def input_signals(fmu: Path, specs: list[str], start_time: float, stop_time: float) -> np.ndarray | None:
    """Build FMPy's structured input array from ``NAME=FILE.csv`` or ``NAME=step:T0:VALUE``.

    A CSV file is read by :func:`read_input_csv`; values between rows are interpolated
    linearly, a repeated time marks a jump.

    Raises
    ------
    ParameterError
        For an unknown input, an input given twice or a malformed step.
    InputDataError
        For a CSV file that is missing or has a bad cell (file, line and column named).
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
        if source.startswith("step:"):
            base = float(variable.start) if variable.start not in (None, "") else 0.0
            signals[name] = _step_signal(name, source, base, start_time, stop_time)
        else:
            path = check_input_file(source, InputDataError, f"--input {name}: '{source}'")
            signals[name] = read_input_csv(path, name)
    times = np.unique(np.concatenate([t for t, _ in signals.values()]))
    rows = []
    for t in times:
        # At a time where a signal jumps (repeated time stamp) emit its left and its right value.
        def value(ts, vs, side):
            if np.any(ts == t):
                return vs[np.searchsorted(ts, t, side="left") if side == "left" else
                          np.searchsorted(ts, t, side="right") - 1]
            return np.interp(t, ts, vs)

        left = [value(ts, vs, "left") for ts, vs in signals.values()]
        right = [value(ts, vs, "right") for ts, vs in signals.values()]
        rows.append((t, *left))
        if left != right:
            rows.append((t, *right))
    dtype = [("time", np.float64)] + [(n, np.float64) for n in signals]
    return np.array(rows, dtype=dtype)


# --------------------------------------------------------------------------- running

class _Progress:
    """A one-line progress bar on stderr for runs that take a while; keeps FMPy's recorder so
    that the rows computed before a solver failure can be recovered."""

    def __init__(self, start: float, stop: float, enabled: bool):
        self.start, self.stop, self.enabled, self.last = start, stop, enabled, -1
        self.recorder = None

    def __call__(self, time, recorder):
        self.recorder = recorder
        if self.enabled and self.stop > self.start:
            percent = int(100 * (time - self.start) / (self.stop - self.start))
            if percent != self.last:
                self.last = percent
                bar = "#" * (percent // 4)
                print(f"\r[{bar:<25}] {percent:3d}%  t = {time:.3g} s", end="", file=sys.stderr, flush=True)
        return True

    def close(self):
        if self.enabled and self.last >= 0:
            print(file=sys.stderr)

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


def check_run(md, stop_time: float | None, step: float | None, fmi_type: str, start_time: float | None = None,
              parameters: dict | None = None) -> tuple[float, float]:
    """Refuse settings that cannot give a meaningful run (before anything runs); returns (t0, t1).

    With ``md`` None only the checks that need no model description are made (returns NaNs).

    Raises
    ------
    ParameterError
        A non-finite or non-positive step, a stop time that is not after the start, a run of
        more than :data:`MAX_ROWS` output rows, or ``solver.fixedStepSize`` with Model Exchange.
    """
    from cosim.fmu.parameters import FIXED_STEP_PARAMETER

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
    return t0, t1


def simulate(fmu: str | Path, stop_time: float | None = None, step: float | None = None, fmi_type: str = "cs",
             parameters: dict | None = None, inputs: np.ndarray | None = None, start_time: float | None = None,
             relative_tolerance: float | None = None, outputs: list[str] | None = None,
             progress: bool = False) -> np.ndarray:
    """Simulate an FMU with FMPy and return the result as a structured array (column ``time`` first).

    Parameters
    ----------
    fmu : path
        The FMU file (FMI 2.0 or 3.0).
    stop_time, start_time : float, optional
        Simulation interval in s (default: the FMU's DefaultExperiment).
    step : float, optional
        Output interval / communication step in s.
    fmi_type : {'cs', 'me'}
        Co-Simulation (the FMU's own integrator) or Model Exchange (FMPy's CVode).
    parameters : dict, optional
        Start values by variable name.
    inputs : structured array, optional
        Input signals as built by :func:`input_signals`.

    Raises
    ------
    FMUError
        The file is not a usable FMU (see :func:`cosim.fmu.access.read_fmu`).
    ParameterError
        Settings refused by :func:`check_run`.
    IncompleteResult
        The solver failed part-way (or the FMU ended the run early); carries the rows up to the
        failure and the cause.
    SimulationError
        The FMU failed before the first step (nothing computed).
    """
    from fmpy import simulate_fmu

    from cosim.fmu.access import ALL_FMI_VERSIONS, FMU, FMULog

    fmu = Path(fmu)
    handle = FMU(fmu, versions=ALL_FMI_VERSIONS)  # FMPy's simulate_fmu runs FMI 2 and FMI 3 alike
    md = handle.description
    t0, t1 = check_run(md, stop_time, step, fmi_type, start_time, parameters)
    kind = "cs" if fmi_type == "cs" else "me"
    if kind == "me":
        _guard_cvode_cleanup()
    log = FMULog()
    instance = handle.instantiate(kind, name=md.modelName, log=log)
    bar = _Progress(t0, t1, progress)
    # The worst FMI status seen decides which calls the clean-up may still make; FMPy itself
    # calls fmi2Terminate at the end of a run that succeeds.
    state = {"status": 0, "terminated": False}
    try:
        result = simulate_fmu(
            handle.unzipdir, start_time=t0, stop_time=t1, output_interval=step,
            fmi_type="CoSimulation" if kind == "cs" else "ModelExchange",
            start_values=dict(parameters or {}), input=inputs, relative_tolerance=relative_tolerance,
            output=outputs, step_finished=bar, validate=False, model_description=md, fmu_instance=instance,
        )
        state["terminated"] = True
    except Exception as exc:  # FMPy raises FMICallException, RuntimeError (CVode), bare Exception
        state["status"] = int(getattr(exc, "status", 0) or 0)
        raise _failure(fmu, md, exc, log, bar.rows(), t1) from None
    finally:
        bar.close()
        _release(instance, state["status"], state["terminated"])
    result = np.asarray(result)
    if result.size and result["time"][-1] < t1 - 1e-9 * max(1.0, abs(t1)):
        # The FMU ended the run itself (fmi2Discard + fmi2Terminated): FMPy returns what it has.
        said = log.last_error()
        cause = _cause(md, result)
        text = f"{cause} (solver: {_first_clause(said)})" if cause and said else \
            cause or said or "the FMU ended the run early"
        raise IncompleteResult(f"{fmu}: the simulation stopped at t = {result['time'][-1]:.6g} s of "
                               f"{t1:g} s: {text}", result, float(result["time"][-1]), cause or text)
    return result


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
    cause = _cause(md, rows)
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
    from cosim.compiler.catalog import singular_configurations
    from cosim.errors import CosimError

    try:
        return singular_configurations(model_name)
    except CosimError:
        return ()


def _cause(md, rows) -> str | None:
    """:func:`physical_cause` of a failed run of the FMU described by ``md``, with the singular
    configurations its model declares."""
    return physical_cause(_last_values(rows), model_singularities(md.modelName))


def _last_values(rows) -> dict[str, float]:
    if rows is None or len(rows) == 0:
        return {}
    return {n: float(rows[n][-1]) for n in rows.dtype.names if n != "time"}


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
    from cosim.compiler.library import load_library
    from cosim.errors import CosimError

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
    from cosim.outputs import check_output

    path = check_output(path, "result file")
    if path.suffix.lower() not in RESULT_FORMATS:
        known = " or ".join(f"{s} ({d})" for s, d in RESULT_FORMATS.items())
        raise ParameterError(f"{option} {path}: unknown result format '{path.suffix or '(no suffix)'}'; "
                             f"use {known}")
    check_output(incomplete_path(path), "result file")
    return path


def check_plot_output(path: str | Path, option: str = "--plot") -> Path:
    """Refuse a plot path whose format matplotlib does not write, or that cannot be written."""
    from cosim.outputs import check_output

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
    """Write a result array as CSV or NPY (by suffix), atomically."""
    path = Path(path)
    if path.suffix.lower() == ".npy":
        from cosim.outputs import atomic_output

        with atomic_output(path, "result file") as tmp:
            np.save(tmp, np.asarray(result), allow_pickle=False)
        return path
    return write_csv(result, path)


def write_csv(result: np.ndarray, path: str | Path) -> Path:
    """Write a result array to CSV with a header row (atomically: complete or absent)."""
    from cosim.outputs import atomic_output

    names = result.dtype.names
    data = np.column_stack([result[n].astype(float) for n in names]) if len(result) else \
        np.zeros((0, len(names)))
    with atomic_output(path, "result file") as tmp:
        np.savetxt(tmp, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    return Path(path)


def plot(result: np.ndarray, path: str | Path, title: str = "") -> Path:
    """One subplot per signal against time, saved as an image (atomically)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from cosim.outputs import atomic_output

    names = [n for n in result.dtype.names if n != "time"]
    fig, axes = plt.subplots(len(names) or 1, 1, sharex=True, figsize=(7, 1.8 * max(1, len(names))), squeeze=False)
    try:
        for ax, name in zip(axes[:, 0], names):
            ax.plot(result["time"], result[name])
            ax.set_ylabel(name)
            ax.grid(True)
        axes[-1, 0].set_xlabel("time [s]")
        if title:
            axes[0, 0].set_title(title)
        fig.tight_layout()
        with atomic_output(path, "plot file") as tmp:
            fig.savefig(tmp, dpi=120)
    finally:
        plt.close(fig)
    return Path(path)
