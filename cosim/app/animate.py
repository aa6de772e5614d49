"""`cosim animate RESULT [-o ride.html]`: a self-contained 3-D animation of a bicycle result.

RESULT is a result of `cosim simulate` or `cosim run` (``.csv`` with a header row, or a structured
``.npy``) that carries the bicycle's configuration signals, found by name with or without one
component prefix (``phi`` or ``bike.phi``; the prefix of the one component that has both ``phi``
and ``delta``, so that another block's ``push.y`` is not taken for ``bike.y``):

============  ========  =============================================================================
signal        unit      when the result has none
============  ========  =============================================================================
``time``      s         required
``phi``       rad       required: roll, positive leaning right
``delta``     rad       required: steer, positive to the right
``x``         m         ``--speed V`` gives ``x = V t`` (the linear models have no x); else an error
``y``         m         0 (rear contact point, right)
``psi``       rad       0 (yaw, positive turning right)
``theta``     rad       0 (pitch; 0 is the linear models' value)
``thetaR``    rad       rolled along the path: ``-s / rR``, s the distance travelled along the heading
``thetaF``    rad       ``-s / rF``
============  ========  =============================================================================

Sign conventions (``--signs``): the page draws in Meijaard's axes (x forward, y right, z down:
roll, steer, yaw and ``y`` positive to the right), the convention of the Whipple models. The
paper's second-order models (SelfStabilizing, InvertedPendulum, LeaningRider, ...) use its ISO 8855
axes (x forward, y left, z up): roll positive leaning right as in Meijaard's, but steer ``delta``,
yaw ``psi`` and the path deviation ``eta`` positive to the left. ``--signs paper`` converts them
(``delta``, ``psi`` negated, ``y = -eta``); ``auto`` (the default) takes the paper's signs for a
result that has ``eta`` and no ``y`` (only those models write ``eta``), Meijaard's otherwise, and
says which in a note. The rear-steered models (RearSteered and its examples) are drawn as a
front-steered bicycle: the page has no rear-steered geometry.

The page is one HTML file: the vendored three.js, ``static/ride3d.js`` (the view and the player)
and ``static/animate.js`` (the controls and the roll/steer plots) inlined with
:meth:`cosim.app.export.Script.inline`, and the trajectory as JSON; it opens from ``file://`` with
no network. The geometry (w, c, lam, rR, rF; tR, tF crown radii) is that of a parameter set of
``cosim/params`` (:func:`cosim.analytic.parameters.load_parameters`, default ``benchmark``),
values overridden by ``--param NAME=VALUE``.
"""
from __future__ import annotations

import html
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cosim.errors import InputDataError, ParameterError
from cosim.outputs import check_input_file, check_output, read_text_file, write_text

from cosim.app.export import STATIC, VENDOR, Script
from cosim.analytic.parameters import load_parameters
from cosim.fmu.parameters import split_assignment
from cosim.fmu.simulate import finite_number

REQUIRED = ("phi", "delta")
OPTIONAL = ("x", "y", "psi", "theta", "thetaR", "thetaF")
#: Sign conventions of a result: Meijaard's (the Whipple models) and the paper's ISO 8855 axes of
#: the second-order models (steer, yaw and the path deviation ``eta`` positive to the left).
SIGNS = ("auto", "meijaard", "paper")
PAPER_PATH = "eta"  # [m] the paper's path deviation of the rear contact point, positive to the left
GEOMETRY = ("w", "c", "lam", "rR", "rF", "tR", "tF")  # [m, rad]
TEMPLATE = STATIC / "animate.html"
MARKER = "<!-- COSIM:SCRIPTS -->"


def _scripts() -> tuple[Script, ...]:
    """The scripts of the page, in their order: three.js, the 3-D view, the page's controls."""
    return (Script(VENDOR / "three.min.js"), Script(STATIC / "ride3d.js"), Script(STATIC / "animate.js"))


@dataclass
class AnimationResult:
    """What :func:`animate` wrote."""

    path: Path
    rows: int
    duration: float  # [s]
    signals: dict  # configuration signal -> the result's column it came from (or how it was made)
    notes: list  # what was filled in or ignored, one sentence each
    bytes: int


def read_result(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """The columns of a result file (``.csv`` with a header row, or a structured ``.npy``).

    Parameters
    ----------
    path : path
        A result of `cosim simulate` / `cosim run`.

    Returns
    -------
    dict of str to numpy.ndarray
        Column name -> values (float), in the file's order.

    Raises
    ------
    InputDataError
        If the file is missing or unreadable, is not a result (no header, a row with another
        number of cells than the header, an empty result), or has a cell that is not a finite
        number: ``"FILE: row R, column C (NAME): ..."``, R counting the file's lines (the header
        is row 1), C its columns from 1.
    """
    path = check_input_file(path, InputDataError)  # a folder, a FIFO, a device: refused before opening
    if path.suffix.lower() == ".npy":
        return _read_npy(path)

    lines = read_text_file(path, InputDataError, str(path)).splitlines()
    header_row = next((i for i, line in enumerate(lines) if line.strip()), None)
    if header_row is None:
        raise InputDataError(f"{path}: not a result (the file is empty)")
    names = [cell.strip() for cell in lines[header_row].split(",")]
    for k, name in enumerate(names):
        if not name:
            raise InputDataError(f"{path}: row {header_row + 1}, column {k + 1}: empty column name in the header")
        try:
            float(name)
        except ValueError:
            continue
        raise InputDataError(f"{path}: not a result: row {header_row + 1} (the header) has a number, '{name}', "
                             f"in column {k + 1}, not a column name")
    if len(set(names)) != len(names):
        twice = sorted({n for n in names if names.count(n) > 1})
        raise InputDataError(f"{path}: row {header_row + 1}: column(s) {', '.join(twice)} appear twice in the header")
    rows = []
    for i in range(header_row + 1, len(lines)):
        line = lines[i]
        if not line.strip():
            continue
        cells = line.split(",")
        if len(cells) != len(names):
            raise InputDataError(f"{path}: row {i + 1}: {len(cells)} cell(s), but the header has {len(names)}")
        rows.append([finite_number(cell.strip(), f"{path}: row {i + 1}, column {k + 1} ({names[k]})")
                     for k, cell in enumerate(cells)])
    if not rows:
        raise InputDataError(f"{path}: not a result (a header and no rows)")
    data = np.array(rows, dtype=float)
    return {name: data[:, k] for k, name in enumerate(names)}


def _read_npy(path: Path) -> dict[str, np.ndarray]:
    try:
        array = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise InputDataError(f"{path}: not a result (not a NumPy .npy file: {' '.join(str(exc).split())})") from None
    if array.dtype.names is None or array.ndim != 1:
        raise InputDataError(f"{path}: not a result (a structured one-dimensional array with named fields "
                             f"is expected, got shape {array.shape} of {array.dtype})")
    if len(array) == 0:
        raise InputDataError(f"{path}: not a result (no rows)")
    columns = {}
    for k, name in enumerate(array.dtype.names):
        try:
            values = np.asarray(array[name], dtype=float)
        except (TypeError, ValueError):
            raise InputDataError(f"{path}: column {k + 1} ({name}) is not numeric ({array.dtype[name]})") from None
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InputDataError(f"{path}: row {bad[0] + 1}, column {k + 1} ({name}): {values[bad[0]]} is not a "
                                 "finite number (rows counted from 1)")
        columns[name] = values
    return columns


def bicycle_prefix(columns: dict, path: Path) -> str:
    """The prefix of the bicycle's signals: ``""`` (``phi``, ``delta`` without a prefix) or
    ``"COMPONENT."``, the one component with both ``COMPONENT.phi`` and ``COMPONENT.delta`` (the
    other signals are looked up with the same prefix, so that e.g. a pulse block's ``push.y``
    is not taken for the bicycle's ``bike.y``).

    Raises
    ------
    InputDataError
        If no source has both phi and delta (the message names what is missing and what was
        found), or more than one has (the result of a system of two bicycles).
    """
    prefixes = [""] if all(name in columns for name in REQUIRED) else []
    components = {c.split(".")[0] for c in columns if c.count(".") == 1}
    prefixes += sorted(f"{c}." for c in components if all(f"{c}.{name}" in columns for name in REQUIRED))
    if len(prefixes) > 1:
        raise InputDataError(f"{path}: more than one bicycle: {', '.join(p + 'phi' for p in prefixes)} "
                             "(animate a result of one bicycle)")
    if not prefixes:
        missing = [name for name in REQUIRED
                   if name not in columns and not any(c.count(".") == 1 and c.split(".")[1] == name for c in columns)]
        what = " or ".join(missing) if missing else " and ".join(REQUIRED) + " of one component"
        raise InputDataError(f"{path}: no configuration signal {what} (nor COMPONENT.{(missing or REQUIRED)[0]}); "
                             f"found: {', '.join(columns)}")
    return prefixes[0]


def geometry(params: str | None = None, overrides: list[str] = ()) -> dict[str, float]:
    """The bicycle's drawn geometry {w, c, lam, rR, rF, tR, tF} [m, rad].

    Parameters
    ----------
    params : str, optional
        A bundled parameter set (``benchmark``, ``astrom2005``, ...) or a TOML file (default
        ``benchmark``); its tR, tF (crown radii) are 0 unless it has them.
    overrides : list of str
        ``NAME=VALUE`` assignments of the names of :data:`GEOMETRY`.

    Raises
    ------
    ParameterError
        For an unknown or unreadable set, an assignment of another name, a value that is not a
        finite number or is out of range (w, rR, rF > 0; 0 <= tR <= rR, 0 <= tF <= rF).
    """
    try:
        values = load_parameters(params or "benchmark")
    except (ValueError, OSError) as exc:
        raise ParameterError(f"--params {params}: {exc}") from None
    g = {name: float(values.get(name, 0.0)) for name in GEOMETRY}
    for text in overrides:
        name, raw = split_assignment(text, "--param")
        if name not in GEOMETRY:
            raise ParameterError(f"--param: '{name}' is not a geometry value; those are: {', '.join(GEOMETRY)}")
        try:
            g[name] = float(raw)
        except ValueError:
            raise ParameterError(f"--param {name}: '{raw}' is not a number") from None
        if not math.isfinite(g[name]):
            raise ParameterError(f"--param {name}: '{raw}' is not a finite number")
    for name in ("w", "rR", "rF"):
        if g[name] <= 0:
            raise ParameterError(f"geometry: {name} = {g[name]:g} m must be positive")
    if not (0 <= g["tR"] <= g["rR"] and 0 <= g["tF"] <= g["rF"]):
        raise ParameterError(f"geometry: the crown radii need 0 <= tR <= rR and 0 <= tF <= rF "
                             f"(tR = {g['tR']:g}, tF = {g['tF']:g} m)")
    return g


def result_signs(columns: dict, prefix: str, signs: str = "auto") -> str:
    """The sign convention of a result: ``"meijaard"`` or ``"paper"`` (see the module docstring).

    Parameters
    ----------
    columns : dict
        The result's columns.
    prefix : str
        The bicycle's prefix (:func:`bicycle_prefix`).
    signs : {"auto", "meijaard", "paper"}
        ``auto``: the paper's for a result with ``eta`` and no ``y``, else Meijaard's.
    """
    if signs not in SIGNS:
        raise ParameterError(f"--signs: '{signs}' is not one of {', '.join(SIGNS)}")
    if signs != "auto":
        return signs
    return "paper" if prefix + PAPER_PATH in columns and prefix + "y" not in columns else "meijaard"


def trajectory(columns: dict, path: Path, geometry_: dict, speed: float | None = None, signs: str = "auto"):
    """The configuration signals of a result: ``(trajectory, signals, notes)``.

    ``signs`` is the result's sign convention (:func:`result_signs`); the trajectory is always in
    Meijaard's (roll, steer, yaw and y positive to the right).

    Returns
    -------
    trajectory : dict of str to list of float
        ``t`` [s] and ``x, y, psi, phi, theta, delta, thetaR, thetaF`` [m, rad] (the player's input).
    signals : dict of str to str
        Where each signal came from (a column name, or how it was made).
    notes : list of str
        What was filled in (e.g. ``x = V t``) or ignored.

    Raises
    ------
    InputDataError
        If ``time``, ``phi`` or ``delta`` is missing (the message names what was found), ``x`` is
        missing and no ``speed`` is given, or the time decreases.
    """
    found = ", ".join(columns)
    if "time" not in columns:
        raise InputDataError(f"{path}: no column 'time'; found: {found}")
    t = columns["time"]
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        i = back[0] + 1
        raise InputDataError(f"{path}: the time decreases at sample {i + 1} ({t[i - 1]:g} -> {t[i]:g} s): "
                             "not one result")
    signals = {"t": "time"}
    prefix = bicycle_prefix(columns, path)
    out = {"t": t}
    for name in (*REQUIRED, *OPTIONAL):
        if prefix + name in columns:
            out[name] = columns[prefix + name]
            signals[name] = prefix + name
    notes = []
    convention = result_signs(columns, prefix, signs)
    if convention == "paper":
        if "y" not in out and prefix + PAPER_PATH in columns:
            out["y"] = -columns[prefix + PAPER_PATH]
            signals["y"] = f"-{prefix}{PAPER_PATH}"
        flipped = [name for name in ("delta", "psi") if name in out]
        for name in flipped:
            out[name] = -out[name]
            signals[name] = f"-{signals[name]}"
        notes.append("the paper's signs (ISO 8855: steer, yaw and path positive to the left) drawn in "
                     f"Meijaard's (to the right): {', '.join(f'{n} = -{prefix}{n}' for n in flipped)}"
                     + (f", y = -{prefix}{PAPER_PATH}" if signals.get("y", "").startswith("-") else ""))
    elif prefix + PAPER_PATH in columns:
        notes.append(f"{prefix}{PAPER_PATH} ignored: Meijaard's signs were chosen (--signs paper draws it as the path)")
    if "x" not in out:
        if speed is None:
            raise InputDataError(f"{path}: no signal {prefix}x, the forward position of the rear "
                                 "contact point (results of the linear models have none): give --speed V "
                                 f"[m/s] to draw x = V t; found: {found}")
        out["x"] = speed * (t - t[0])
        signals["x"] = f"--speed {speed:g} m/s: x = V t"
        notes.append(f"x = V t with V = {speed:g} m/s (the result has no x)")
    elif speed is not None:
        notes.append(f"--speed ignored: the result has x ({signals['x']})")
    zero = [name for name in ("y", "psi", "theta") if name not in out]
    for name in zero:
        out[name] = np.zeros_like(t)
        signals[name] = "0 (not in the result)"
    if zero:
        notes.append(f"{', '.join(zero)} = 0 (not in the result)")
    if "thetaR" not in out or "thetaF" not in out:
        # rolled along the path, so that the spokes turn at the right rate and direction: the
        # distance travelled along the heading (negative riding backwards, as the rear-steered
        # bicycle of WhippleLinear with v < 0), the heading of each step its mean yaw
        psi = 0.5 * (out["psi"][1:] + out["psi"][:-1])
        step = np.diff(out["x"]) * np.cos(psi) + np.diff(out["y"]) * np.sin(psi)
        s = np.concatenate([[0.0], np.cumsum(step)])
        for name, radius in (("thetaR", geometry_["rR"]), ("thetaF", geometry_["rF"])):
            if name not in out:
                out[name] = -s / radius
                signals[name] = f"-s/r{name[-1]} (rolled along the path)"
        notes.append("wheel angles rolled along the path (the result has none)")
    order = ("t", "x", "y", "psi", "phi", "theta", "delta", "thetaR", "thetaF")
    return {k: [float(v) for v in out[k]] for k in order}, signals, notes


def page(trajectory_: dict, geometry_: dict, title: str, signals: dict, notes: list) -> str:
    """The self-contained HTML page: the template with the scripts and the data inlined."""
    data = {"title": title, "geometry": geometry_, "trajectory": trajectory_, "signals": signals, "notes": notes}
    blocks = ["<script>window.COSIM_ANIMATION = " + _script_safe(json.dumps(data, separators=(",", ":")))
              + ";</script>"]
    for script in _scripts():
        blocks.append("<script>\n" + _script_safe(script.inline()) + "\n</script>")
    template = TEMPLATE.read_text(encoding="utf-8")
    if template.count(MARKER) != 1:
        raise ValueError(f"{TEMPLATE} must hold {MARKER} once")
    return template.replace("COSIM:TITLE", html.escape(title)).replace(MARKER, "\n".join(blocks))


def _script_safe(text: str) -> str:
    """``text`` safe inside ``<script>...</script>``: a ``</script`` in it (in a string, a regular
    expression or a comment: nowhere else in valid JavaScript or JSON) becomes ``<\\/script``,
    which means the same there."""
    return re.sub(r"</(script)", r"<\\/\1", text, flags=re.IGNORECASE)


def animate(result: str | os.PathLike, output: str | os.PathLike | None = None, *, params: str | None = None,
            param: list[str] = (), speed: float | None = None, signs: str = "auto") -> AnimationResult:
    """Write the 3-D animation of a result as one HTML file.

    Parameters
    ----------
    result : path
        A ``.csv`` or ``.npy`` result of `cosim simulate` / `cosim run`.
    output : path, optional
        The HTML file (default: ``RESULT`` with the suffix ``.html`` in the working directory).
    params : str, optional
        Parameter set of the drawn geometry (default ``benchmark``).
    param : list of str
        ``NAME=VALUE`` geometry overrides (w, c, lam, rR, rF, tR, tF) [m, rad].
    speed : float, optional
        Forward speed V [m/s] for results without x (x = V t).
    signs : {"auto", "meijaard", "paper"}
        The result's sign convention (:func:`result_signs`; the notes say which was used).

    Returns
    -------
    AnimationResult

    Raises
    ------
    OutputError
        If ``output`` cannot be written (checked before the result is read); nothing is
        written under its name unless complete.
    InputDataError, ParameterError
        For a missing file, a file that is not a result, missing signals, bad geometry or speed.
    """
    result = Path(result)
    output = Path(output) if output is not None else Path(result.stem + ".html")
    check_output(output, "animation file")
    if speed is not None and not math.isfinite(speed):
        raise ParameterError(f"--speed: {speed} is not a finite number")
    if signs not in SIGNS:
        raise ParameterError(f"--signs: '{signs}' is not one of {', '.join(SIGNS)}")
    g = geometry(params, list(param))
    columns = read_result(result)
    traj, signals, notes = trajectory(columns, result, g, speed, signs)
    text = page(traj, g, f"{result.name}: 3-D ride", signals, notes)
    write_text(output, text, "animation file")
    t = traj["t"]
    return AnimationResult(output, len(t), t[-1] - t[0], signals, notes, len(text.encode("utf-8")))
