"""The guided demos of `cosim app`: one TOML file per demo in ``cosim/app/demos/``.

A demo is a ride of the nonlinear bicycle in the page (``static/ride.js``), optionally a second
ride to compare with, a short text with the paper's equation and figure numbers, and a
machine-checkable expectation that the page (and tests/test_app_ride.py) verifies on the
recorded ride. A new demo is one new file; :func:`load_demos` reads and checks every file at
export time and refuses a bad one with one message naming the file and the key.

File format (every key is checked; unknown keys are refused)::

    title = "..."                 # required
    order = 1                     # position in the page's list (required, integer)
    text = "..."                  # the explanation (plain text; blank lines separate paragraphs)
    references = ["Figure 5"]     # the paper's equation/figure numbers (required, non-empty)
    duration = 10.0               # [s] simulated time of each ride (0 < duration <= 60)
    step = 0.01                   # [s] communication step (optional, default 0.01)

    [ride]                        # the ride played in the 3-D view (required)
    label = "..."
    model = "Bicycle.Bicycles.Whipple"
    params = "benchmark"          # a parameter set of cosim/params (load_parameters)
    speed = 5.0                   # [m/s] forward speed; negative: ridden backwards (rear-steered)
    parameters = { tR = 0.3 }     # optional: other parameter values of the model
    initial = { u_phi0 = 0.5 }    # optional: start values (parameters of the model)
    [ride.inputs.T_phi]           # optional: a source per input of the bicycle (summed with the controller)
    source = "pulse"              # "pulse" (amplitude, start, duration) or "step" (amplitude, start)
    [ride.controller]             # optional: a controller FMU of the library in the loop
    model = "Bicycle.Control.PD"
    parameters = { kp = 10.0 }
    connect = { phi = "phi", phi_dot = "u_phi" }   # controller input <- bicycle output
    output = "T"
    drives = "T_delta"            # the bicycle input it adds to
    delay = 0.1                   # [s] the rider's exact transport delay (optional, default 0)

    [compare]                     # optional: a second ride, the keys of [ride] that differ

    [[expect]]                    # one or more checks on the recorded rides
    check = "max_abs"             # see CHECKS
    ride = "main"                 # or "compare"

The keys a check takes are listed in :data:`CHECKS`; :func:`check_expectation` evaluates them on
recorded rides (tests use it; ride.js has the same definitions for the page's verdict).
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

from cosim.errors import CosimError
from cosim.analytic.parameters import load_parameters

DEMOS = Path(__file__).resolve().parent / "demos"
DEFAULT_STEP = 0.01  # [s]
MAX_DURATION = 60.0  # [s] a page precomputes the ride: keep it short
TOP_KEYS = {"title": str, "order": int, "text": str, "references": list, "duration": float, "step": float,
            "ride": dict, "compare": dict, "expect": list}
REQUIRED_TOP = ("title", "order", "text", "references", "duration", "ride", "expect")
RIDE_KEYS = {"label": str, "model": str, "params": str, "speed": float, "parameters": dict, "initial": dict,
             "inputs": dict, "controller": dict}
REQUIRED_RIDE = ("label", "model", "params", "speed")
SOURCES = {"pulse": ("amplitude", "start", "duration"), "step": ("amplitude", "start")}
CONTROLLER_KEYS = {"model": str, "parameters": dict, "connect": dict, "output": str, "drives": str, "delay": float}
REQUIRED_CONTROLLER = ("model", "connect", "output", "drives")
# check -> (required keys, optional keys); every check also takes "ride" ("main" or "compare").
CHECKS = {
    # the ride ended by a fall (|phi| > 1 rad, or the FMU stopped the step) before its duration
    "falls": (("value",), ("before",)),
    # max |signal| over [from, to] (default: the whole ride) below and/or above a bound
    "max_abs": (("signal",), ("from", "to", "below", "above")),
    # max |signal| over `late` >= ratio * max |signal| over `early` (each [t0, t1] in s)
    "grows": (("signal", "early", "late", "ratio"), ()),
    # the first sample with |signal| > threshold has this sign (+1 or -1)
    "first_excursion": (("signal", "threshold", "sign"), ()),
    # the last sample of the signal has this sign (+1 or -1) and |value| >= at_least (default 0)
    "final_sign": (("signal", "sign"), ("at_least",)),
    # the main ride lasts at least `ratio` times as long as the compare ride, which falls
    "outlasts": (("ratio",), ()),
    # the exponential growth rate [1/s] of |signal| (least-squares slope of log|signal| over the
    # samples with between[0] < |signal| < between[1] before |signal| first exceeds between[1]),
    # below and/or above bounds, or at most than_compare times the compare ride's rate
    "growth_rate": (("signal", "between"), ("below", "above", "than_compare")),
}
FALL_ROLL = 1.0  # [rad] |phi| beyond this is a fall (as the bundled systems' `fall`)


class DemoError(CosimError, ValueError):
    """A demo file that cannot be used: the message names the file and the key."""


def _where(path: Path) -> str:
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def _typed(path: Path, key: str, value, kind):
    """``value`` as ``kind`` (int accepted for float), or DemoError naming the file and key."""
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
        raise DemoError(f"{_where(path)}: key '{key}' must be {_KIND_NAMES[kind]}, got {value!r}")
    if kind is float and not math.isfinite(value):
        raise DemoError(f"{_where(path)}: key '{key}' must be a finite number, got {value!r}")
    return value


_KIND_NAMES = {str: "a string", int: "an integer", float: "a number", list: "an array", dict: "a table",
               bool: "true or false"}


def _table(path: Path, key: str, table: dict, spec: dict, required) -> dict:
    unknown = sorted(set(table) - set(spec))
    if unknown:
        raise DemoError(f"{_where(path)}: unknown key '{key}.{unknown[0]}' (known: {', '.join(sorted(spec))})"
                        if key else f"{_where(path)}: unknown key '{unknown[0]}' (known: {', '.join(sorted(spec))})")
    prefix = f"{key}." if key else ""
    for name in required:
        if name not in table:
            raise DemoError(f"{_where(path)}: missing key '{prefix}{name}'")
    return {name: _typed(path, prefix + name, value, spec[name]) for name, value in table.items()}


def _numbers(path: Path, key: str, table: dict) -> dict:
    return {name: _typed(path, f"{key}.{name}", value, float) for name, value in table.items()}


def _ride(path: Path, key: str, table: dict, required) -> dict:
    ride = _table(path, key, table, RIDE_KEYS, required)
    for name in ("parameters", "initial"):
        if name in ride:
            ride[name] = _numbers(path, f"{key}.{name}", ride[name])
    if "inputs" in ride:
        inputs = {}
        for name, source in ride["inputs"].items():
            where = f"{key}.inputs.{name}"
            if not isinstance(source, dict):
                raise DemoError(f"{_where(path)}: key '{where}' must be a table, got {source!r}")
            kind = source.get("source")
            if kind not in SOURCES:
                raise DemoError(f"{_where(path)}: key '{where}.source' must be one of {', '.join(SOURCES)}, "
                                f"got {kind!r}")
            spec = {"source": str, **{k: float for k in SOURCES[kind]}}
            inputs[name] = _table(path, where, source, spec, tuple(spec))
            if kind == "pulse" and inputs[name]["duration"] <= 0:
                raise DemoError(f"{_where(path)}: key '{where}.duration' must be > 0")
        ride["inputs"] = inputs
    if "controller" in ride:
        where = f"{key}.controller"
        c = _table(path, where, ride["controller"], CONTROLLER_KEYS, REQUIRED_CONTROLLER)
        c["parameters"] = _numbers(path, f"{where}.parameters", c.get("parameters", {}))
        for name, value in c["connect"].items():
            _typed(path, f"{where}.connect.{name}", value, str)
        c.setdefault("delay", 0.0)
        if c["delay"] < 0:
            raise DemoError(f"{_where(path)}: key '{where}.delay' must not be negative, got {c['delay']}")
        ride["controller"] = c
    return ride


def _expectation(path: Path, index: int, table, has_compare: bool) -> dict:
    key = f"expect[{index}]"
    if not isinstance(table, dict):
        raise DemoError(f"{_where(path)}: key '{key}' must be a table, got {table!r}")
    check = table.get("check")
    if check not in CHECKS:
        raise DemoError(f"{_where(path)}: key '{key}.check' must be one of {', '.join(CHECKS)}, got {check!r}")
    required, optional = CHECKS[check]
    spec = {"check": str, "ride": str}
    for name in (*required, *optional):
        spec[name] = {"signal": str, "value": bool, "early": list, "late": list, "between": list}.get(name, float)
    out = _table(path, key, table, spec, required)
    out.setdefault("ride", "main")
    if out["ride"] not in ("main", "compare"):
        raise DemoError(f"{_where(path)}: key '{key}.ride' must be \"main\" or \"compare\", got {out['ride']!r}")
    if (out["ride"] == "compare" or check == "outlasts") and not has_compare:
        raise DemoError(f"{_where(path)}: key '{key}' needs a [compare] ride, the file has none")
    for name in ("early", "late", "between"):
        if name in out:
            window = out[name]
            if len(window) != 2 or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in window) \
                    or not window[0] < window[1]:
                raise DemoError(f"{_where(path)}: key '{key}.{name}' must be [t0, t1] with t0 < t1, got {window!r}")
            out[name] = [float(x) for x in window]
    if "sign" in out and out["sign"] not in (1.0, -1.0):
        raise DemoError(f"{_where(path)}: key '{key}.sign' must be 1 or -1, got {out['sign']!r}")
    if check in ("max_abs", "growth_rate") and not {"below", "above", "than_compare"} & set(out):
        raise DemoError(f"{_where(path)}: key '{key}' needs 'below' or 'above'")
    if "than_compare" in out and not has_compare:
        raise DemoError(f"{_where(path)}: key '{key}.than_compare' needs a [compare] ride, the file has none")
    return out


def read_demo(path: str | Path) -> dict:
    """One demo file, its structure checked (names of models and parameters: :func:`resolve`).

    Raises
    ------
    DemoError
        If the file cannot be read or parsed, or a key is unknown, missing or of the wrong type
        (the message names the file and the key).
    """
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise DemoError(f"{_where(path)}: cannot read the demo: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise DemoError(f"{_where(path)}: not valid TOML: {exc}") from None
    demo = _table(path, "", data, TOP_KEYS, REQUIRED_TOP)
    if not 0 < demo["duration"] <= MAX_DURATION:
        raise DemoError(f"{_where(path)}: key 'duration' must be in (0, {MAX_DURATION:g}] s, got {demo['duration']}")
    demo.setdefault("step", DEFAULT_STEP)
    if not 0 < demo["step"] <= demo["duration"]:
        raise DemoError(f"{_where(path)}: key 'step' must be in (0, duration], got {demo['step']}")
    if not demo["references"] or not all(isinstance(r, str) and r for r in demo["references"]):
        raise DemoError(f"{_where(path)}: key 'references' must be a non-empty array of strings")
    demo["ride"] = _ride(path, "ride", demo["ride"], REQUIRED_RIDE)
    if "compare" in demo:
        # a compare ride is the main ride with the keys it gives replaced
        demo["compare"] = {**demo["ride"], **_ride(path, "compare", demo["compare"], ("label",))}
    if not demo["expect"]:
        raise DemoError(f"{_where(path)}: key 'expect' must have at least one check")
    demo["expect"] = [_expectation(path, i, e, "compare" in demo) for i, e in enumerate(demo["expect"])]
    demo["name"] = path.stem
    return demo


def resolve(demo: dict, descriptions: dict, path: str | Path | None = None) -> dict:
    """The demo with its parameter sets read (``ride.values``: every parameter and start value
    of the bicycle for the page) and every name checked against the models' descriptions.

    Parameters
    ----------
    demo : dict
        From :func:`read_demo`.
    descriptions : dict
        Model name -> NAME.json of its WebAssembly module (the models the page carries).

    Raises
    ------
    DemoError
        If a model is not one the page carries, a parameter set does not exist, or a parameter,
        input, output or signal name is not one of the model's.
    """
    where = _where(Path(path)) if path else f"demo '{demo['name']}'"
    out = dict(demo)
    signals = set()
    for key in ("ride", "compare"):
        if key not in demo:
            continue
        ride = dict(demo[key])
        if ride["model"] not in descriptions:
            raise DemoError(f"{where}: key '{key}.model': {ride['model']} is not a model of the page "
                            f"({', '.join(sorted(descriptions))})")
        variables = {v["name"]: v for v in descriptions[ride["model"]]["variables"]}

        def by(causality, vs=variables):
            return {n for n, v in vs.items() if v["causality"] == causality}

        try:
            values = dict(load_parameters(ride["params"]))
        except (CosimError, OSError, ValueError) as exc:
            raise DemoError(f"{where}: key '{key}.params': {exc}") from None
        for group in ("parameters", "initial"):
            for name in ride.get(group, {}):
                if name not in by("parameter"):
                    raise DemoError(f"{where}: key '{key}.{group}.{name}': not a parameter of {ride['model']}")
        unknown = sorted(set(values) - by("parameter"))
        if unknown:
            raise DemoError(f"{where}: key '{key}.params': {', '.join(unknown)} are not parameters of {ride['model']}")
        values.update(ride.get("parameters", {}))
        values.update(ride.get("initial", {}))
        if "u_R0" in values or "rR" not in values:
            raise DemoError(f"{where}: key '{key}.speed': the speed sets u_R0 = -speed/rR; give no u_R0 "
                            "and a parameter set with rR")
        values["u_R0"] = -ride["speed"] / values["rR"]  # the rear wheel rate: negative rolling forward
        ride["values"] = values
        for name in ride.get("inputs", {}):
            if name not in by("input"):
                raise DemoError(f"{where}: key '{key}.inputs.{name}': not an input of {ride['model']}")
        c = ride.get("controller")
        if c:
            if c["model"] not in descriptions:
                raise DemoError(f"{where}: key '{key}.controller.model': {c['model']} is not a model of the page "
                                f"({', '.join(sorted(descriptions))})")
            cvars = {v["name"]: v["causality"] for v in descriptions[c["model"]]["variables"]}
            for name in c["parameters"]:
                if cvars.get(name) != "parameter":
                    raise DemoError(f"{where}: key '{key}.controller.parameters.{name}': not a parameter of "
                                    f"{c['model']}")
            for name, source in c["connect"].items():
                if cvars.get(name) != "input":
                    raise DemoError(f"{where}: key '{key}.controller.connect.{name}': not an input of {c['model']}")
                if source not in by("output"):
                    raise DemoError(f"{where}: key '{key}.controller.connect.{name}': {source!r} is not an output "
                                    f"of {ride['model']}")
            missing = sorted(n for n, cz in cvars.items() if cz == "input" and n not in c["connect"])
            if missing:
                raise DemoError(f"{where}: key '{key}.controller.connect': inputs {', '.join(missing)} of "
                                f"{c['model']} are not connected")
            if cvars.get(c["output"]) != "output":
                raise DemoError(f"{where}: key '{key}.controller.output': {c['output']!r} is not an output of "
                                f"{c['model']}")
            if c["drives"] not in by("input"):
                raise DemoError(f"{where}: key '{key}.controller.drives': {c['drives']!r} is not an input of "
                                f"{ride['model']}")
        signals |= by("output") | by("input")
        out[key] = ride
    for i, e in enumerate(demo["expect"]):
        if "signal" in e and e["signal"] not in signals:
            raise DemoError(f"{where}: key 'expect[{i}].signal': {e['signal']!r} is not an output or input of "
                            "the bicycle")
    return out


def load_demos(folder: str | Path = DEMOS, descriptions: dict | None = None) -> list[dict]:
    """Every ``*.toml`` of ``folder``, read and checked, in their ``order`` (then file name).

    With ``descriptions`` (model name -> NAME.json) the names are checked too (:func:`resolve`).

    Raises
    ------
    DemoError
        For the first bad file (its name and the key), or two demos with the same order.
    """
    folder = Path(folder)
    files = sorted(folder.glob("*.toml"))
    if not files:
        raise DemoError(f"{_where(folder)}: no demo files (*.toml)")
    demos, orders = [], {}
    for path in files:
        demo = read_demo(path)
        if demo["order"] in orders:
            raise DemoError(f"{_where(path)}: key 'order': {demo['order']} is also the order of "
                            f"{orders[demo['order']]}")
        orders[demo["order"]] = path.name
        demos.append(resolve(demo, descriptions, path) if descriptions is not None else demo)
    return sorted(demos, key=lambda d: (d["order"], d["name"]))


# --- the expectation, evaluated on recorded rides (the test's independent check of the page) -----

def _window(t, s, t0=None, t1=None):
    return [abs(v) for tt, v in zip(t, s) if (t0 is None or tt >= t0 - 1e-12) and (t1 is None or tt <= t1 + 1e-12)]


def growth_rate(t, s, low: float, high: float) -> float:
    """Least-squares slope [1/s] of log|s| over the samples with low < |s| < high before |s|
    first exceeds ``high`` (NaN with fewer than 3 such samples)."""
    ts, ls = [], []
    for tt, v in zip(t, s):
        if abs(v) >= high:
            break
        if abs(v) > low:
            ts.append(tt)
            ls.append(math.log(abs(v)))
    if len(ts) < 3:
        return float("nan")
    mt, ml = sum(ts) / len(ts), sum(ls) / len(ls)
    return sum((a - mt) * (b - ml) for a, b in zip(ts, ls)) / sum((a - mt) ** 2 for a in ts)


def check_expectation(check: dict, rides: dict, duration: float) -> tuple[bool, str]:
    """One check of a demo's ``expect`` on recorded rides.

    Parameters
    ----------
    check : dict
        One entry of ``demo["expect"]``.
    rides : dict
        ``"main"`` (and ``"compare"``) -> ``{"t": [...], "fell": bool, signal: [...]}``.
    duration : float
        The demo's duration [s].

    Returns
    -------
    (bool, str)
        Whether it holds, and what was measured (for the test's output).
    """
    ride = rides[check["ride"]]
    t, kind = ride["t"], check["check"]
    if kind == "falls":
        end = t[-1]
        ok = ride["fell"] == check["value"] and (not check["value"] or end <= check.get("before", duration))
        return ok, f"fell={ride['fell']} at t={end:.2f} s"
    if kind == "outlasts":
        other = rides["compare"]
        ok = other["fell"] and t[-1] >= check["ratio"] * other["t"][-1]
        return ok, f"main ends at {t[-1]:.2f} s, compare at {other['t'][-1]:.2f} s (fell={other['fell']})"
    s = ride[check["signal"]]
    if kind == "max_abs":
        values = _window(t, s, check.get("from"), check.get("to"))
        m = max(values) if values else float("nan")
        ok = bool(values) and ("below" not in check or m < check["below"]) and \
            ("above" not in check or m > check["above"])
        return ok, f"max |{check['signal']}| = {m:.4g}"
    if kind == "grows":
        early, late = _window(t, s, *check["early"]), _window(t, s, *check["late"])
        a, b = (max(early) if early else float("nan")), (max(late) if late else float("nan"))
        return bool(early and late) and b >= check["ratio"] * a, f"max |{check['signal']}| {a:.4g} -> {b:.4g}"
    if kind == "first_excursion":
        first = next((v for v in s if abs(v) > check["threshold"]), None)
        return first is not None and math.copysign(1, first) == check["sign"], f"first excursion {first}"
    if kind == "final_sign":
        last = s[-1]
        ok = math.copysign(1, last) == check["sign"] and abs(last) >= check.get("at_least", 0.0)
        return ok, f"final {check['signal']} = {last:.4g}"
    if kind == "growth_rate":
        rate = growth_rate(t, s, *check["between"])
        ok = math.isfinite(rate) and ("below" not in check or rate < check["below"]) and \
            ("above" not in check or rate > check["above"])
        text = f"growth rate of |{check['signal']}| {rate:.4g} 1/s"
        if "than_compare" in check:
            other = growth_rate(rides["compare"]["t"], rides["compare"][check["signal"]], *check["between"])
            ok = ok and math.isfinite(other) and rate <= check["than_compare"] * other
            text += f", compare {other:.4g} 1/s"
        return ok, text
    raise ValueError(f"unknown check {kind!r}")
