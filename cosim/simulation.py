"""`cosim simulate`: run an FMU (ME with CVode or CS with its own solver) through FMPy."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .errors import ParameterError, SimulationError
from .parameters import split_assignment


def _variables(fmu: Path):
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    return md, {v.name: v for v in md.modelVariables}


def input_signals(fmu: Path, specs: list[str], start_time: float, stop_time: float) -> np.ndarray | None:
    """Build FMPy's structured input array from ``NAME=FILE.csv`` or ``NAME=step:T0:VALUE``.

    A CSV file has a header row and two columns, time (s) and value; values between rows are
    interpolated linearly, a repeated time marks a jump.
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
            raise ParameterError(f"unknown input '{name}'; inputs are: {known}")
        if source.startswith("step:"):
            try:
                _, t0, value = source.split(":")
                t0, value = float(t0), float(value)
            except ValueError:
                raise ParameterError(f"--input {name}: expected step:T0:VALUE, got '{source}'") from None
            base = float(variable.start or 0.0)
            t0 = min(max(t0, start_time), stop_time)
            signals[name] = (np.array([start_time, t0, t0, stop_time]), np.array([base, base, value, value]))
        else:
            path = Path(source)
            if not path.is_file():
                raise ParameterError(f"--input {name}: file '{source}' not found")
            try:
                data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
            except ValueError as exc:
                raise ParameterError(f"--input {name}: cannot read '{source}': {exc}") from None
            if data.shape[1] < 2 or np.any(np.diff(data[:, 0]) < 0):
                raise ParameterError(f"--input {name}: '{source}' needs columns time,value with non-decreasing time")
            signals[name] = (data[:, 0], data[:, 1])
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


class _Progress:
    """A one-line progress bar on stderr for runs that take a while."""

    def __init__(self, start: float, stop: float, enabled: bool):
        self.start, self.stop, self.enabled, self.last = start, stop, enabled, -1

    def __call__(self, time, recorder):
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


def simulate(fmu: str | Path, stop_time: float | None = None, step: float | None = None, fmi_type: str = "cs",
             parameters: dict | None = None, inputs: np.ndarray | None = None, start_time: float | None = None,
             relative_tolerance: float | None = None, outputs: list[str] | None = None,
             progress: bool = False) -> np.ndarray:
    """Simulate an FMU with FMPy and return the result as a structured array (column ``time`` first).

    Parameters
    ----------
    fmu : path
        The FMU file.
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
    """
    from fmpy import simulate_fmu

    if fmi_type not in ("cs", "me"):
        raise ParameterError(f"--fmi-type must be 'cs' or 'me', got '{fmi_type}'")
    if stop_time is not None and not np.isfinite(stop_time):
        raise ParameterError("--stop-time must be finite")
    if step is not None and not step > 0:
        raise ParameterError(f"--step must be positive, got {step}")
    md, _ = _variables(Path(fmu))
    t0 = start_time if start_time is not None else float(md.defaultExperiment.startTime or 0.0) \
        if md.defaultExperiment else 0.0
    t1 = stop_time if stop_time is not None else (float(md.defaultExperiment.stopTime)
                                                   if md.defaultExperiment and md.defaultExperiment.stopTime else 1.0)
    if t1 <= t0:
        raise ParameterError(f"--stop-time ({t1}) must be after the start time ({t0})")
    bar = _Progress(t0, t1, progress)
    try:
        result = simulate_fmu(
            str(fmu), start_time=t0, stop_time=t1, output_interval=step,
            fmi_type="CoSimulation" if fmi_type == "cs" else "ModelExchange",
            start_values=parameters or {}, input=inputs, relative_tolerance=relative_tolerance,
            output=outputs, step_finished=bar, validate=False,
        )
    except Exception as exc:
        raise SimulationError(f"{fmu}: simulation failed: {exc}") from None
    finally:
        bar.close()
    return result


def write_csv(result: np.ndarray, path: str | Path) -> None:
    """Write a result array to CSV with a header row."""
    names = result.dtype.names
    data = np.column_stack([result[n].astype(float) for n in names])
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")


def plot(result: np.ndarray, path: str | Path, title: str = "") -> None:
    """One subplot per signal against time, saved as an image."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [n for n in result.dtype.names if n != "time"]
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(7, 1.8 * max(1, len(names))), squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        ax.plot(result["time"], result[name])
        ax.set_ylabel(name)
        ax.grid(True)
    axes[-1, 0].set_xlabel("time [s]")
    if title:
        axes[0, 0].set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
