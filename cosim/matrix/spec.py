"""Matrix specs (TOML): studies of co-simulation cases, each with axes or explicit cases and checks.

A spec holds one ``[matrix]`` table of defaults and any number of ``[[study]]`` tables. A study
is a system (components, connections, ``[system]`` settings, as in a system file) whose values
may be expressions (strings starting with ``=``) of the study's variables; the axes span the
cases (their cartesian product, last axis fastest), ``[[study.cases]]`` add explicit ones::

    [matrix]
    name = "example"
    stop = 10.0            # co-simulated time [s] of every case
    step = 0.01            # communication step [s]
    margin = 0.05          # |max Re| [1/s] below which a prediction is 'marginal'

    [[study]]
    name = "self-stability"
    claim = "benchmark bicycle self-stable on 4.29-6.02 m/s"
    observe = "bike.phi"
    connections = []
    [study.components.bike]
    model = "Bicycle.Bicycles.WhippleLinear"
    parameter_set = "benchmark"
    parameters = { v = "=v", phi0 = 0.01 }
    [study.axes]
    v = { from = 2.0, to = 8.0, step = 0.5 }
    [[study.checks]]
    kind = "stable-interval"
    axis = "v"
    expected = [4.29, 6.02]
    tolerance = 0.01

Every key is documented in the docstring of :mod:`cosim.matrix`.
"""
from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from ..errors import ParameterError
from . import expr

SPECS_DIR = Path(__file__).resolve().parent / "specs"

#: Settings of ``[matrix]`` that a ``[[study]]`` may override, with their defaults.
DEFAULTS = {
    "stop": 10.0,             # co-simulated time of a case [s]
    "step": 0.01,             # communication step [s]
    "algorithm": "jacobi",    # master algorithm
    "fall_limit": 1.0,        # |observed signal| beyond which the bicycle fell (unless [system] fall is set)
    "margin": 0.05,           # predicted |max Re| [1/s] below which a case is 'marginal'
    "observed_margin": 0.01,  # observed growth rate [1/s] below which an observation is inconclusive
    "extend": 3.0,            # inconclusive observations are re-run this many times longer (<= 1: never)
    "pade_order": 6,          # order of the Pade approximation of exact transport delays in predictions
    "master_lag": True,       # predictions include the master's sample-and-hold and Jacobi lags
    "timeout": 120.0,         # seconds a case may take before its worker is killed
    "predict": True,          # compute the analytic prediction (false: observations only)
}
MATRIX_KEYS = {"name", "description", "imports", *DEFAULTS}
STUDY_KEYS = {"name", "title", "claim", "description", "observe", "connections", "system", "components",
              "variables", "axes", "cases", "tune", "checks", "plots", *DEFAULTS}
COMPONENT_KEYS = {"model", "fmu", "python", "parameters", "step_multiple", "parameter_set", "initial"}
CHECK_KINDS = ("stable-interval", "region", "growth-rate", "agreement")


class SpecError(ParameterError):
    """A matrix spec that cannot be run; the message names the file and the entry."""


@dataclass
class Case:
    """One co-simulation of a study at one point of its axes."""

    key: str                 # content hash: the same case has the same key in every run
    study: str
    index: int               # position in the study
    label: str               # "v=6, tau=0.1"
    values: dict             # the case's coordinates (axis or explicit values)
    variables: dict          # every variable of the case (coordinates and derived)
    system: dict             # a system-file dict (components by model name, FMU path or Python block)
    initial: dict            # component -> {state variable: start value}
    observe: str             # COMPONENT.OUTPUT classified as stable / unstable
    tune: dict               # COMPONENT.PARAMETER -> {min, max, points, scale}
    settings: dict           # margin, observed_margin, extend, pade_order, master_lag, timeout, predict

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass
class Study:
    name: str
    title: str
    claim: str
    description: str
    observe: str
    raw: dict                # the [[study]] table
    settings: dict
    axes: dict = field(default_factory=dict)    # name -> list of values
    explicit: list = field(default_factory=list)
    checks: list = field(default_factory=list)
    plots: list = field(default_factory=list)
    where: str = "spec"

    # ------------------------------------------------------------------ cases
    def points(self) -> list[dict]:
        """Coordinates of every case: the axes' product, then the explicit cases."""
        found = []
        if self.axes:
            names = list(self.axes)
            for combo in itertools.product(*(self.axes[n] for n in names)):
                found.append(dict(zip(names, combo)))
        found += [dict(c) for c in self.explicit]
        return found

    def variables_at(self, values: dict) -> dict:
        scope = dict(values)
        for name, raw in self.raw.get("variables", {}).items():
            if name in values:
                continue  # an axis or explicit value overrides the definition
            text = raw[1:] if isinstance(raw, str) and raw.startswith("=") else raw
            scope[name] = expr.evaluate(text, scope) if isinstance(text, str) else text
        return scope

    def make_case(self, values: dict, index: int = -1) -> Case:
        """The case at ``values`` (used for the spec's cases and for boundary searches)."""
        where = f"{self.where}: study '{self.name}'"
        try:
            scope = self.variables_at(values)
            system = {"connections": list(self.raw.get("connections", [])),
                      "system": expr.resolve(copy.deepcopy(self.raw.get("system", {})), scope),
                      "components": {}}
            initial = {}
            for cname, entry in self.raw.get("components", {}).items():
                entry = dict(entry)
                params = {}
                pset = entry.pop("parameter_set", None)
                if pset is not None:
                    params.update(_parameter_set(_resolve_path(pset, self.where)))
                params.update(expr.resolve(entry.pop("parameters", {}), scope))
                init = expr.resolve(entry.pop("initial", {}), scope)
                if init:
                    initial[cname] = {k: float(v) for k, v in init.items()}
                entry = expr.resolve(entry, scope)
                if params:
                    entry["parameters"] = params
                system["components"][cname] = entry
        except expr.ExpressionError as exc:
            raise SpecError(f"{where}: {exc}") from None
        settings = {k: self.settings[k] for k in DEFAULTS}
        sysset = system["system"]
        sysset.setdefault("stop", settings["stop"])
        sysset.setdefault("step", settings["step"])
        sysset.setdefault("algorithm", settings["algorithm"])
        sysset.setdefault("name", self.name)
        if "fall" not in sysset and settings["fall_limit"]:
            sysset["fall"] = {"signal": self.observe, "limit": float(settings["fall_limit"])}
        tune = {k: dict(v) for k, v in self.raw.get("tune", {}).items()}
        label = ", ".join(f"{k}={_short(v)}" for k, v in values.items())
        # what determines the result (not the timeout, which only bounds the wall time)
        body = {"study": self.name, "system": system, "initial": initial, "observe": self.observe,
                "tune": tune, "settings": {k: v for k, v in settings.items() if k != "timeout"}}
        key = hashlib.sha256(json.dumps(body, sort_keys=True, default=repr).encode()).hexdigest()[:16]
        return Case(key=key, study=self.name, index=index, label=label or f"case {index}",
                    values=dict(values), variables={k: v for k, v in scope.items() if _plain(v)},
                    system=system, initial=initial, observe=self.observe, tune=tune, settings=settings)

    def cases(self) -> list[Case]:
        return [self.make_case(values, i) for i, values in enumerate(self.points())]


@dataclass
class MatrixSpec:
    name: str
    description: str
    path: Path | None
    settings: dict
    studies: list[Study]
    imports: list[str]
    digest: str

    def cases(self) -> list[Case]:
        found, seen = [], {}
        for study in self.studies:
            for case in study.cases():
                if case.key in seen:
                    raise SpecError(f"{self.path or self.name}: study '{study.name}': case {case.label} "
                                    f"duplicates {seen[case.key]}")
                seen[case.key] = f"{case.study} {case.label}"
                found.append(case)
        return found

    def study(self, name: str) -> Study:
        for s in self.studies:
            if s.name == name:
                return s
        raise KeyError(name)


@lru_cache(maxsize=32)
def _parameter_set_cached(name: str) -> tuple:
    from ..whipple_params import parameters_for_model

    return tuple(parameters_for_model(name).items())


def _parameter_set(name: str) -> dict:
    return dict(_parameter_set_cached(name))


def _short(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _plain(value) -> bool:
    return isinstance(value, (int, float, str, bool)) and not (isinstance(value, float) and not math.isfinite(value))


def _resolve_path(name: str, where: str) -> str:
    """A parameter-set name stays a name; a relative file is taken relative to the spec."""
    if where != "spec" and (name.endswith(".toml") or "/" in name):
        p = Path(name)
        if not p.is_absolute():
            p = Path(where).parent / p
        return str(p)
    return name


def _axis_values(name: str, raw, where: str) -> list:
    if isinstance(raw, list):
        values = raw
    elif isinstance(raw, dict):
        if "values" in raw:
            values = list(raw["values"])
        elif "linspace" in raw:
            a, b, n = raw["linspace"]
            n = int(n)
            values = [a + (b - a) * k / (n - 1) for k in range(n)] if n > 1 else [a]
        elif {"from", "to", "step"} <= set(raw):
            a, b, h = float(raw["from"]), float(raw["to"]), float(raw["step"])
            if not h > 0 or b < a:
                raise SpecError(f"{where}: axis '{name}': need step > 0 and to >= from")
            n = int(math.floor((b - a) / h + 1e-9)) + 1
            values = [round(a + k * h, 12) for k in range(n)]
        else:
            raise SpecError(f"{where}: axis '{name}': give a list, {{values = [...]}}, "
                            "{linspace = [a, b, n]} or {from, to, step}")
    else:
        raise SpecError(f"{where}: axis '{name}' must be a list or a table")
    if not values:
        raise SpecError(f"{where}: axis '{name}' has no values")
    return values


def _settings(table: dict, base: dict, where: str) -> dict:
    out = dict(base)
    for k in DEFAULTS:
        if k in table:
            want = type(DEFAULTS[k])
            value = table[k]
            if want is float and isinstance(value, int) and not isinstance(value, bool):
                value = float(value)
            if not isinstance(value, want) or (want is int and isinstance(value, bool)):
                raise SpecError(f"{where}: '{k}' must be {want.__name__}, got {value!r}")
            out[k] = value
    if not out["step"] > 0 or not out["stop"] > 0:
        raise SpecError(f"{where}: step and stop must be positive")
    if out["margin"] < 0 or out["observed_margin"] < 0:
        raise SpecError(f"{where}: margins must not be negative")
    return out


def load_spec(path_or_name: str | Path) -> MatrixSpec:
    """Read a spec file, or a bundled spec by name (``cosim/matrix/specs/NAME.toml``)."""
    path = Path(path_or_name)
    if not path.is_file():
        bundled = SPECS_DIR / f"{path_or_name}.toml"
        if bundled.is_file():
            path = bundled
        else:
            names = ", ".join(sorted(p.stem for p in SPECS_DIR.glob("*.toml")))
            raise SpecError(f"{path_or_name}: no such spec file (bundled specs: {names})")
    text = path.read_text()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: {exc}") from None
    return spec_from_dict(data, path)


def bundled_specs() -> list[str]:
    return sorted(p.stem for p in SPECS_DIR.glob("*.toml"))


def spec_from_dict(data: dict, path: Path | None = None) -> MatrixSpec:
    from ..cosimulation.system import SystemError_, system_from_dict

    where = str(path) if path else "spec"
    table = data.get("matrix", {})
    unknown = set(table) - MATRIX_KEYS
    if unknown:
        raise SpecError(f"{where}: unknown [matrix] keys: {', '.join(sorted(unknown))}")
    extra = set(data) - {"matrix", "study"}
    if extra:
        raise SpecError(f"{where}: unknown top-level keys: {', '.join(sorted(extra))} "
                        "(a spec has [matrix] and [[study]] tables)")
    settings = _settings(table, DEFAULTS, f"{where}: [matrix]")
    imports = []
    for item in table.get("imports", []):
        if item.endswith(".py"):
            p = Path(item)
            if not p.is_absolute() and path is not None:
                p = path.parent / p
            imports.append(str(p.resolve()))
        else:
            imports.append(item)
    studies, names = [], set()
    raw_studies = data.get("study", [])
    if not isinstance(raw_studies, list) or not raw_studies:
        raise SpecError(f"{where}: no [[study]] tables")
    for k, raw in enumerate(raw_studies):
        name = raw.get("name") or f"study{k + 1}"
        swhere = f"{where}: study '{name}'"
        unknown = set(raw) - STUDY_KEYS
        if unknown:
            raise SpecError(f"{swhere}: unknown keys: {', '.join(sorted(unknown))}")
        if name in names:
            raise SpecError(f"{swhere}: duplicate study name")
        names.add(name)
        for cname, entry in raw.get("components", {}).items():
            bad = set(entry) - COMPONENT_KEYS
            if bad:
                raise SpecError(f"{swhere}: component '{cname}': unknown keys {', '.join(sorted(bad))}")
        observe = raw.get("observe") or raw.get("system", {}).get("fall", {}).get("signal")
        if not observe:
            raise SpecError(f"{swhere}: 'observe' (COMPONENT.OUTPUT to classify) is missing")
        comp, _, var = observe.partition(".")
        if comp not in raw.get("components", {}) or not var:
            raise SpecError(f"{swhere}: observe = '{observe}' is not COMPONENT.OUTPUT of a component")
        for target in raw.get("tune", {}):
            tcomp, _, tpar = target.partition(".")
            if tcomp not in raw.get("components", {}) or not tpar:
                raise SpecError(f"{swhere}: tune '{target}' is not COMPONENT.PARAMETER of a component")
        axes = {n: _axis_values(n, v, swhere) for n, v in raw.get("axes", {}).items()}
        for n in axes:
            if not n.isidentifier():
                raise SpecError(f"{swhere}: axis name '{n}' must be an identifier (use it as '={n}' in values)")
        explicit = list(raw.get("cases", []))
        if not axes and not explicit:
            raise SpecError(f"{swhere}: neither [study.axes] nor [[study.cases]]")
        checks = list(raw.get("checks", []))
        for c in checks:
            if c.get("kind") not in CHECK_KINDS:
                raise SpecError(f"{swhere}: check kind must be one of {', '.join(CHECK_KINDS)}, got {c.get('kind')!r}")
        study = Study(name=name, title=raw.get("title", name), claim=raw.get("claim", ""),
                      description=raw.get("description", ""), observe=observe, raw=raw,
                      settings=_settings(raw, settings, swhere), axes=axes, explicit=explicit,
                      checks=checks, plots=list(raw.get("plots", [])), where=where)
        first = study.make_case(study.points()[0], 0)
        try:
            system_from_dict(first.system, None)
        except SystemError_ as exc:
            raise SpecError(f"{swhere}: {str(exc).removeprefix('system: ')}") from None
        studies.append(study)
    digest = hashlib.sha256(json.dumps(data, sort_keys=True, default=repr).encode()).hexdigest()[:16]
    return MatrixSpec(name=table.get("name", path.stem if path else "matrix"),
                      description=table.get("description", ""), path=path, settings=settings,
                      studies=studies, imports=imports, digest=digest)
