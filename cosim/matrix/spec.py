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

Every key is documented in the docstring of :mod:`cosim.matrix`. Every key is checked for its
type and range when the spec is loaded, before any work: a problem is one :class:`SpecError`
naming the file, the study and the key. The number of cases is bounded (:data:`MAX_CASES`, the
``--max-cases`` option): an axis or a product of axes beyond it is refused *before* it is
expanded, with the axis sizes in the message -- unless the caller runs a sample
(``sample=True``): then only each axis is bounded, and :meth:`MatrixSpec.cases` with a ``limit``
makes a stratified sample of the cases (:func:`stratified_indices`) without expanding the rest.
"""
from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import re
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from cosim.cosimulation import algorithms
from cosim.cosimulation.system import system_from_dict, SystemError_, type_name
from cosim.errors import CosimError, ParameterError
from cosim.matrix import expr
from cosim.outputs import check_input_file, read_text_file

SPECS_DIR = Path(__file__).resolve().parent / "specs"

#: Default limit on the number of cases of a spec (``--max-cases`` raises it).
MAX_CASES = 100_000

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
#: Ranges of the settings: (lowest, highest, lowest included); every number must be finite.
RANGES = {
    "stop": (0.0, math.inf, False), "step": (0.0, math.inf, False), "fall_limit": (0.0, math.inf, True),
    "margin": (0.0, math.inf, True), "observed_margin": (0.0, math.inf, True), "extend": (0.0, 100.0, True),
    "pade_order": (1, 20, True), "timeout": (0.0, math.inf, False),
}


def _algorithms() -> tuple[str, ...]:
    """The coupling algorithms a study may use: those the analytic prediction models."""
    return tuple(a.name for a in algorithms.algorithms() if a.predicted)


MATRIX_KEYS = {"name", "description", "imports", *DEFAULTS}
STUDY_KEYS = {"name", "title", "claim", "description", "observe", "connections", "system", "components",
              "variables", "axes", "cases", "tune", "checks", "plots", *DEFAULTS}
COMPONENT_KEYS = {"model", "fmu", "python", "parameters", "step_multiple", "parameter_set", "initial"}
CHECK_KINDS = ("stable-interval", "region", "growth-rate", "agreement")
#: Keys of each check kind (besides kind and title).
CHECK_KEYS = {"stable-interval": {"axis", "expected", "tolerance"}, "region": {"where", "expect"},
              "growth-rate": {"expected", "rtol", "atol", "where"}, "agreement": set()}
REGION_EXPECT = ("stable", "unstable", "not-stable", "marginal")
TUNE_KEYS = {"min", "max", "points", "scale"}
TUNE_MAX_POINTS = 10_000
PLOT_KEYS = {"x", "y", "hlines", "x_unit", "y_unit"}
#: Names that become file names (study.png) and folder names (matrix-NAME).
_SAFE_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.+-]*$")


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
    @property
    def count(self) -> int:
        """Number of cases (the axes' product plus the explicit cases), without expanding them."""
        return (math.prod(len(v) for v in self.axes.values()) if self.axes else 0) + len(self.explicit)

    def first_point(self) -> dict:
        """Coordinates of the first case (the start of every axis, or the first explicit case)."""
        if self.axes:
            return {n: v[0] for n, v in self.axes.items()}
        return dict(self.explicit[0])

    def point(self, k: int) -> dict:
        """Coordinates of the case at position ``k`` (as in :meth:`points`), without expanding the others."""
        grid = self.count - len(self.explicit)
        if k >= grid:
            return dict(self.explicit[k - grid])
        coordinates = {}
        for name in reversed(list(self.axes)):  # the last axis fastest
            k, r = divmod(k, len(self.axes[name]))
            coordinates[name] = self.axes[name][r]
        return {name: coordinates[name] for name in self.axes}

    def sample(self, m: int) -> list[int]:
        """Positions of ``m`` distinct cases spread over the study (all of them when ``m`` >= :attr:`count`).

        The grid of the axes gets a stratified sample (:func:`stratified_indices`: every value of
        every axis when the grid's share is at least the longest axis), the explicit cases an evenly
        spaced share; the same ``m`` give the same positions in every run.
        """
        total = self.count
        if m >= total:
            return list(range(total))
        explicit = len(self.explicit)
        grid_size = total - explicit
        widest = max((len(v) for v in self.axes.values()), default=0)
        grid = _split(m, grid_size, explicit, widest)
        chosen = stratified_indices([len(v) for v in self.axes.values()], grid, self.name) if grid else []
        share = m - grid
        chosen += [grid_size + ((2 * j + 1) * explicit) // (2 * share) for j in range(share)]
        return chosen

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
            try:
                scope[name] = expr.evaluate(text, scope) if isinstance(text, str) else text
            except expr.ExpressionError as exc:
                raise expr.ExpressionError(f"variable '{name}': {exc}") from None
        return scope

    def make_case(self, values: dict, index: int = -1) -> Case:
        """The case at ``values`` (used for the spec's cases and for boundary searches)."""
        where = f"{self.where}: study '{self.name}'"
        try:
            scope = self.variables_at(values)
            system = {"connections": list(self.raw.get("connections", [])),
                      "system": expr.resolve(copy.deepcopy(self.raw.get("system", {})), scope, "system"),
                      "components": {}}
            initial = {}
            for cname, entry in self.raw.get("components", {}).items():
                entry = dict(entry)
                params = {}
                pset = entry.pop("parameter_set", None)
                if pset is not None:
                    params.update(_parameter_set(_resolve_path(pset, self.where), f"{where}: component "
                                                 f"'{cname}': parameter_set"))
                params.update(expr.resolve(entry.pop("parameters", {}), scope, f"component '{cname}' parameters"))
                init = expr.resolve(entry.pop("initial", {}), scope, f"component '{cname}' initial")
                if init:
                    initial[cname] = {k: _start_value(v, f"{where}: component '{cname}': initial '{k}'")
                                      for k, v in init.items()}
                entry = expr.resolve(entry, scope, f"component '{cname}'")
                if isinstance(entry.get("fmu"), str):
                    entry["fmu"] = _resolve_path(entry["fmu"], self.where, always=True)
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

    def cases(self, positions: list[int] | None = None) -> list[Case]:
        """Every case, or those at ``positions`` (of :meth:`sample`), each keeping its position as index."""
        if positions is None:
            return [self.make_case(values, i) for i, values in enumerate(self.points())]
        return [self.make_case(self.point(i), i) for i in positions]


@dataclass
class MatrixSpec:
    name: str
    description: str
    path: Path | None
    settings: dict
    studies: list[Study]
    imports: list[str]
    digest: str

    @property
    def count(self) -> int:
        """Number of cases of all studies (without expanding them)."""
        return sum(s.count for s in self.studies)

    def check_count(self, max_cases: int = MAX_CASES) -> None:
        """Refuse more than ``max_cases`` cases (the message names the studies' sizes)."""
        check_count(self.studies, max_cases, str(self.path or self.name))

    def sample(self, n: int) -> dict[str, list[int]]:
        """Positions of the cases of each study in a sample of ``n`` cases of the spec (every case
        when ``n`` >= :attr:`count`); deterministic, see :func:`allocate` and :meth:`Study.sample`."""
        shares = allocate([s.count for s in self.studies], [_need(s) for s in self.studies], n)
        return {s.name: s.sample(m) for s, m in zip(self.studies, shares)}

    def sample_covers_axes(self, n: int) -> bool:
        """Whether a sample of ``n`` cases shows every value of every axis of every study."""
        for study, positions in zip(self.studies, self.sample(n).values()):
            grid = study.count - len(study.explicit)
            points = [study.point(k) for k in positions if k < grid]
            for name, values in study.axes.items():
                if len({repr(p[name]) for p in points}) < len({repr(v) for v in values}):
                    return False
        return True

    def cases(self, limit: int | None = None) -> list[Case]:
        """Every case, or a stratified sample of ``limit`` cases when the spec has more
        (:meth:`sample`), each system checked against the system-file schema (before any work)."""
        plan = self.sample(limit) if limit is not None and self.count > limit else {}
        found, seen = [], {}
        for study in self.studies:
            checked = set()
            for case in study.cases(plan.get(study.name) if plan else None):
                if case.key in seen:
                    raise SpecError(f"{self.path or self.name}: study '{study.name}': case {case.label} "
                                    f"duplicates {seen[case.key]}")
                seen[case.key] = f"{case.study} {case.label}"
                digest = json.dumps(case.system, sort_keys=True, default=repr)
                if digest not in checked:  # cases differing only in start values share a system
                    checked.add(digest)
                    try:
                        system_from_dict(case.system, None)
                    except SystemError_ as exc:
                        raise SpecError(f"{self.path or self.name}: study '{study.name}': case {case.label}: "
                                        f"{str(exc).removeprefix('system: ')}") from None
                found.append(case)
        return found

    def study(self, name: str) -> Study:
        for s in self.studies:
            if s.name == name:
                return s
        raise KeyError(name)


@lru_cache(maxsize=32)
def _parameter_set_cached(name: str) -> tuple:
    from cosim.analytic.parameters import parameters_for_model  # deferred: `cosim --help` loads this module

    return tuple(parameters_for_model(name).items())


def _parameter_set(name: str, where: str = "parameter_set") -> dict:
    try:
        return dict(_parameter_set_cached(name))
    except CosimError as exc:
        raise SpecError(f"{where}: {exc}") from None
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SpecError(f"{where}: cannot read '{name}': {exc}") from None


def _start_value(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SpecError(f"{where}: expected a finite number, got {type_name(value)}")
    return float(value)


def _short(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _plain(value) -> bool:
    return isinstance(value, (int, float, str, bool)) and not (isinstance(value, float) and not math.isfinite(value))


def _resolve_path(name: str, where: str, always: bool = False) -> str:
    """A parameter-set name stays a name; a relative file is taken relative to the spec."""
    if where != "spec" and (always or name.endswith(".toml") or "/" in name):
        p = Path(name)
        if not p.is_absolute():
            p = Path(where).parent / p
        return str(p)
    return name


# --------------------------------------------------------------------------- samples

def _rank(seed: str, *parts) -> int:
    """A fixed pseudo-random number of ``seed`` and ``parts``: the same in every run and Python version
    (unlike :func:`hash` and :mod:`random`)."""
    text = ":".join(map(str, (seed, *parts)))
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "big")


def stratified_indices(sizes: list[int], m: int, seed: str) -> list[int]:
    """``m`` distinct positions in the grid of axes of ``sizes`` (last axis fastest), sorted.

    A Latin hypercube: each axis is cut into ``m`` strata, its values taken from their middles
    (so every value of an axis appears when ``m`` >= its size, else ``m`` values spread evenly
    over it), and the strata of each axis after the first are shuffled by a fixed permutation of
    ``seed``. Points drawn twice are replaced by points chosen by ``seed`` too: the same
    arguments give the same positions in every run. All positions when ``m`` >= the grid's size.
    """
    total = math.prod(sizes)
    if m >= total:
        return list(range(total))
    columns = []
    for a, n in enumerate(sizes):
        strata = [((2 * j + 1) * n) // (2 * m) for j in range(m)]
        if a:
            strata = [strata[j] for j in sorted(range(m), key=lambda j: _rank(seed, a, j))]
        columns.append(strata)
    chosen: set[int] = set()
    for j in range(m):
        k = 0
        for a, n in enumerate(sizes):
            k = k * n + columns[a][j]
        chosen.add(k)
    if len(chosen) < m and 2 * m >= total:  # a dense sample: choose among the rest, which is small
        rest = sorted((k for k in range(total) if k not in chosen), key=lambda k: _rank(seed, "rest", k))
        chosen.update(rest[:m - len(chosen)])
    draw = 0
    while len(chosen) < m:  # a sparse sample: a random point is new with probability > 1/2
        k = 0
        for a, n in enumerate(sizes):
            k = k * n + _rank(seed, "fill", draw, a) % n
        chosen.add(k)
        draw += 1
    return sorted(chosen)


def allocate(counts: list[int], needs: list[int], n: int) -> list[int]:
    """How many of ``n`` cases each study of ``counts`` cases gets (all when ``n`` >= their sum).

    First each study's need (the cases that show every value of its axes, ``needs``) -- shared in
    proportion to the needs when ``n`` is below their sum, at least one per study while ``n``
    allows --, then the rest in proportion to the cases left (largest remainders; ties to the
    first study).
    """
    if n >= sum(counts):
        return list(counts)
    needs = [min(c, max(1, d)) for c, d in zip(counts, needs)]
    if n <= sum(needs):
        floor = [1 if k < n else 0 for k in range(len(needs))]
        return [f + s for f, s in zip(floor, _proportional([d - f for d, f in zip(needs, floor)], n - sum(floor)))]
    extra = _proportional([c - d for c, d in zip(counts, needs)], n - sum(needs))
    return [d + e for d, e in zip(needs, extra)]


def _proportional(weights: list[int], n: int) -> list[int]:
    """``n`` split in proportion to ``weights`` (largest remainders), none above its weight (``n`` <= their sum)."""
    total = sum(weights)
    if not total or n <= 0:
        return [0] * len(weights)
    shares = [n * w // total for w in weights]
    order = sorted(range(len(weights)), key=lambda k: (-((n * weights[k]) % total), k))
    for k in order[:n - sum(shares)]:
        shares[k] += 1
    return shares


def _need(study: Study) -> int:
    """Cases of a sample that show every value of every axis of ``study`` (and one explicit case)."""
    return max((len(v) for v in study.axes.values()), default=0) + (1 if study.explicit else 0)


def _split(m: int, grid: int, explicit: int, widest: int) -> int:
    """How many of a study's ``m`` sampled cases come from its grid of ``grid`` points (the rest
    from its ``explicit`` cases): in proportion, but first enough for every value of the
    ``widest`` axis, and then at least one explicit case."""
    if not explicit:
        return m
    if not grid:
        return 0
    share = max(round(m * grid / (grid + explicit)), min(m, widest))
    if m > widest:
        share = min(share, m - 1)
    return max(min(share, grid), m - explicit)


# --------------------------------------------------------------------------- checking the schema

def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _expect(value, ok: bool, where: str, what: str):
    if not ok:
        raise SpecError(f"{where}: expected {what}, got {type_name(value)}")
    return value


def _table(value, where: str, what: str = "a table") -> dict:
    return _expect(value, isinstance(value, dict), where, what)


def _text(value, where: str) -> str:
    return _expect(value, isinstance(value, str), where, "a string")


def _texts(value, where: str) -> list:
    return _expect(value, isinstance(value, list) and all(isinstance(v, str) for v in value), where,
                   "an array of strings")


def _finite(value, where: str) -> float:
    _expect(value, _is_number(value), where, "a number")
    if not math.isfinite(value):
        raise SpecError(f"{where}: must be finite, got {value!r}")
    return value


def _scalar(value, where: str):
    """A value of a case or variable: a number, boolean or string (an expression when '=...')."""
    return _expect(value, isinstance(value, (int, float, str, bool)), where, "a number, boolean or string")


def _name(value, where: str, what: str) -> str:
    _text(value, where)
    if not _SAFE_NAME.match(value):
        raise SpecError(f"{where}: {what} '{value}' may only contain letters, digits and _ . + - "
                        "(it names files of the report)")
    return value


def _axis_size(name: str, raw, where: str, max_cases: int) -> int:
    """Number of values of an axis, computed without making them (refused beyond ``max_cases``)."""
    key = f"{where}: axis '{name}'"
    if isinstance(raw, list):
        n = len(raw)
    elif isinstance(raw, dict):
        if "values" in raw:
            n = len(_expect(raw["values"], isinstance(raw["values"], list), f"{key} values", "an array"))
        elif "linspace" in raw:
            ls = raw["linspace"]
            _expect(ls, isinstance(ls, list) and len(ls) == 3 and all(_is_number(v) for v in ls), f"{key} linspace",
                    "an array [a, b, n] of numbers")
            a, b, n = ls
            _finite(a, f"{key} linspace a"), _finite(b, f"{key} linspace b")
            if not (math.isfinite(n) and float(n).is_integer() and n >= 1):
                raise SpecError(f"{key} linspace: n must be a whole number >= 1, got {n!r}")
            n = int(n)
        elif {"from", "to", "step"} <= set(raw):
            a, b, h = (_finite(raw[k], f"{key} {k}") for k in ("from", "to", "step"))
            if not h > 0 or b < a:
                raise SpecError(f"{key}: need step > 0 and to >= from")
            steps = (b - a) / h
            if not math.isfinite(steps):
                raise SpecError(f"{key}: from {a:g} to {b:g} in steps of {h:g} is more than 1e308 values")
            n = int(math.floor(steps + 1e-9)) + 1
        else:
            raise SpecError(f"{key}: give a list, {{values = [...]}}, {{linspace = [a, b, n]}} or {{from, to, step}}")
        unknown = set(raw) - {"values", "linspace", "from", "to", "step"}
        if unknown:
            raise SpecError(f"{key}: unknown keys {', '.join(sorted(unknown))}")
    else:
        raise SpecError(f"{key} must be a list or a table")
    if n > max_cases:
        raise SpecError(f"{key} has {n} values, more than the limit of {max_cases} cases "
                        "(raise it with --max-cases N)")
    if n == 0:
        raise SpecError(f"{key} has no values")
    return n


def _axis_values(name: str, raw, where: str, max_cases: int = MAX_CASES) -> list:
    _axis_size(name, raw, where, max_cases)  # refuses a huge axis before making it
    if isinstance(raw, list):
        values = list(raw)
    elif "values" in raw:
        values = list(raw["values"])
    elif "linspace" in raw:
        a, b, n = raw["linspace"]
        n = int(n)
        values = [a + (b - a) * k / (n - 1) for k in range(n)] if n > 1 else [a]
    else:
        a, b, h = float(raw["from"]), float(raw["to"]), float(raw["step"])
        n = int(math.floor((b - a) / h + 1e-9)) + 1
        values = [round(a + k * h, 12) for k in range(n)]
    for k, v in enumerate(values):
        _scalar(v, f"{where}: axis '{name}' value {k + 1}")
    return values


def check_count(studies: list[Study], max_cases: int, where: str) -> None:
    """Refuse studies with more than ``max_cases`` cases in all (the message names the sizes)."""
    total = 0
    for study in studies:
        n = study.count
        if n > max_cases:
            sizes = " x ".join(f"{a} ({len(v)})" for a, v in study.axes.items())
            extra = f" + {len(study.explicit)} explicit" if study.explicit else ""
            raise SpecError(f"{where}: study '{study.name}': axes {sizes}{extra} = {n} cases, more than the "
                            f"limit of {max_cases} (--max-cases N runs a sample of N of them, or all when N is at "
                            "least their number)")
        total += n
    if total > max_cases:
        parts = " + ".join(f"{s.count} ({s.name})" for s in studies)
        raise SpecError(f"{where}: {parts} = {total} cases, more than the limit of {max_cases} "
                        "(--max-cases N runs a sample of N of them, or all when N is at least their number)")


def _settings(table: dict, base: dict, where: str) -> dict:
    out = dict(base)
    for k in DEFAULTS:
        if k in table:
            want = type(DEFAULTS[k])
            value = table[k]
            if want is float and isinstance(value, int) and not isinstance(value, bool):
                value = float(value)
            if not isinstance(value, want) or (want is int and isinstance(value, bool)):
                raise SpecError(f"{where}: '{k}' must be {'a number' if want is float else want.__name__}, "
                                f"got {type_name(value)}")
            if k in RANGES:
                lo, hi, closed = RANGES[k]
                if not math.isfinite(value) or value > hi or value < lo or (value == lo and not closed):
                    bound = f">= {lo:g}" if closed else f"> {lo:g}"
                    rng = f"{bound} and <= {hi:g}" if math.isfinite(hi) else f"finite and {bound}"
                    raise SpecError(f"{where}: '{k}' must be {rng}, got {value!r}")
            if k == "algorithm" and value.lower() not in _algorithms():
                raise SpecError(f"{where}: 'algorithm' must be one of {', '.join(_algorithms())}, got {value!r}")
            out[k] = value
    if out["step"] > out["stop"]:
        raise SpecError(f"{where}: step {out['step']:g} s is longer than stop {out['stop']:g} s")
    return out


def _check_expression(text, where: str, known: set[str]) -> None:
    """Parse an expression of a check (cost limits included) and refuse names no case has."""
    _text(text, where)
    try:
        unknown = expr.names(text) - known
    except expr.ExpressionError as exc:
        raise SpecError(f"{where}: {exc}") from None
    if unknown:
        raise SpecError(f"{where}: expression '{text}': unknown name(s) {', '.join(sorted(unknown))} "
                        f"(known: {', '.join(sorted(known))})")


def _checks(raw, study_axes: dict, known: set[str], where: str) -> list:
    checks = list(_expect(raw, isinstance(raw, list), f"{where}: checks", "an array of [[study.checks]] tables"))
    for k, c in enumerate(checks):
        cw = f"{where}: check {k + 1}"
        _table(c, cw)
        kind = c.get("kind")
        if not isinstance(kind, str) or kind not in CHECK_KINDS:
            raise SpecError(f"{cw}: check kind must be one of {', '.join(CHECK_KINDS)}, got {kind!r}")
        cw = f"{where}: {kind} check {k + 1}"
        unknown = set(c) - CHECK_KEYS[kind] - {"kind", "title"}
        if unknown:
            raise SpecError(f"{cw}: unknown keys {', '.join(sorted(unknown))} (known: "
                            f"{', '.join(sorted(CHECK_KEYS[kind] | {'kind', 'title'}))})")
        if "title" in c:
            _text(c["title"], f"{cw} title")
        if kind == "stable-interval":
            for key in ("axis", "expected"):
                if key not in c:
                    raise SpecError(f"{cw}: '{key}' is missing")
            _text(c["axis"], f"{cw} axis")
            if c["axis"] not in study_axes:
                raise SpecError(f"{cw}: axis '{c['axis']}' is not an axis of the study "
                                f"(axes: {', '.join(study_axes) or 'none'})")
            e = c["expected"]
            _expect(e, isinstance(e, list) and len(e) == 2 and all(_is_number(v) and math.isfinite(v) for v in e),
                    f"{cw} expected", "an array [low, high] of numbers")
            if not e[0] < e[1]:
                raise SpecError(f"{cw} expected: low {e[0]:g} must be below high {e[1]:g}")
            if "tolerance" in c and not _finite(c["tolerance"], f"{cw} tolerance") > 0:
                raise SpecError(f"{cw} tolerance: must be > 0, got {c['tolerance']!r}")
        if kind == "region":
            if not isinstance(c.get("expect"), str) or c["expect"] not in REGION_EXPECT:
                raise SpecError(f"{cw}: expect must be one of {', '.join(REGION_EXPECT)}, got {c.get('expect')!r}")
        if kind == "growth-rate":
            for key in ("rtol", "atol"):
                if key in c and not _finite(c[key], f"{cw} {key}") >= 0:
                    raise SpecError(f"{cw} {key}: must be >= 0, got {c[key]!r}")
            if "expected" in c and not _is_number(c["expected"]):
                _check_expression(c["expected"], f"{cw} expected", known)
            elif "expected" in c:
                _finite(c["expected"], f"{cw} expected")
        if "where" in c:
            _check_expression(c["where"], f"{cw} where", known)
    return checks


def _tune(raw, components: dict, where: str) -> dict:
    _table(raw, f"{where}: tune", "a table { \"COMPONENT.PARAMETER\" = { min, max, points, scale } }")
    if len(raw) > 1:
        raise SpecError(f"{where}: tune one parameter at a time, got {', '.join(raw)}")
    for target, opts in raw.items():
        tw = f"{where}: tune '{target}'"
        tcomp, _, tpar = target.partition(".")
        if tcomp not in components or not tpar:
            raise SpecError(f"{where}: tune '{target}' is not COMPONENT.PARAMETER of a component")
        _table(opts, tw, "a table { min, max, points, scale }")
        unknown = set(opts) - TUNE_KEYS
        if unknown:
            raise SpecError(f"{tw}: unknown keys {', '.join(sorted(unknown))} (known: {', '.join(sorted(TUNE_KEYS))})")
        lo = _finite(opts.get("min", 1e-3), f"{tw} min")
        hi = _finite(opts.get("max", 1e3), f"{tw} max")
        points = opts.get("points", 32)
        _expect(points, isinstance(points, int) and not isinstance(points, bool), f"{tw} points", "an integer")
        scale = opts.get("scale", "log")
        if scale not in ("log", "linear"):
            raise SpecError(f"{tw} scale: must be 'log' or 'linear', got {type_name(scale)}")
        if not 3 <= points <= TUNE_MAX_POINTS:
            raise SpecError(f"{tw} points: must be 3 to {TUNE_MAX_POINTS}, got {points}")
        if not (hi > lo and (lo > 0 or scale != "log")):
            raise SpecError(f"{tw}: need max > min (and min > 0 on a log scale), got min {lo:g}, max {hi:g}")
    return raw


def _components(raw, where: str) -> dict:
    _table(raw, f"{where}: components", "tables [study.components.NAME]")
    if not raw:
        raise SpecError(f"{where}: no [study.components.NAME] tables")
    for cname, entry in raw.items():
        cw = f"{where}: component '{cname}'"
        _table(entry, cw)
        bad = set(entry) - COMPONENT_KEYS
        if bad:
            raise SpecError(f"{cw}: unknown keys {', '.join(sorted(bad))} (known: {', '.join(sorted(COMPONENT_KEYS))})")
        for key in ("parameters", "initial"):
            if key in entry:
                _table(entry[key], f"{cw} {key}", "a table { NAME = VALUE, ... }")
                for name, value in entry[key].items():
                    _scalar(value, f"{cw} {key} '{name}'")
        if "parameter_set" in entry:
            _text(entry["parameter_set"], f"{cw} parameter_set")
    return raw


def _explicit_cases(raw, axes: dict, variables: dict, where: str) -> list:
    cases = _expect(raw, isinstance(raw, list), f"{where}: cases", "an array of [[study.cases]] tables")
    for k, case in enumerate(cases):
        cw = f"{where}: case {k + 1}"
        _table(case, cw)
        if not case:
            raise SpecError(f"{cw} is empty")
        for name, value in case.items():
            _scalar(value, f"{cw} '{name}'")
        if axes:
            unknown = set(case) - set(axes) - set(variables)
            if unknown:
                raise SpecError(f"{cw}: unknown axis names {', '.join(sorted(unknown))} "
                                f"(axes: {', '.join(axes)}; variables: {', '.join(variables) or 'none'})")
    return list(cases)


def _plots(raw, known: set[str], where: str) -> list:
    plots = _expect(raw, isinstance(raw, list), f"{where}: plots", "an array of [[study.plots]] tables")
    for k, plot in enumerate(plots):
        pw = f"{where}: plot {k + 1}"
        _table(plot, pw)
        unknown = set(plot) - PLOT_KEYS
        if unknown:
            raise SpecError(f"{pw}: unknown keys {', '.join(sorted(unknown))} (known: {', '.join(sorted(PLOT_KEYS))})")
        for key in ("x", "y"):
            if key in plot:
                _text(plot[key], f"{pw} {key}")
                if plot[key] not in known:
                    raise SpecError(f"{pw} {key}: '{plot[key]}' is not a variable of the cases "
                                    f"(variables: {', '.join(sorted(known))})")
        for key in ("x_unit", "y_unit"):
            if key in plot:
                _text(plot[key], f"{pw} {key}")
        if "hlines" in plot:
            _expect(plot["hlines"], isinstance(plot["hlines"], list)
                    and all(_is_number(v) and math.isfinite(v) for v in plot["hlines"]),
                    f"{pw} hlines", "an array of numbers")
    return list(plots)


# --------------------------------------------------------------------------- loading

def load_spec(path_or_name: str | Path, max_cases: int = MAX_CASES, *, sample: bool = False) -> MatrixSpec:
    """Read a spec file, or a bundled spec by name (``cosim/matrix/specs/NAME.toml``).

    ``sample``: the caller runs a sample of ``max_cases`` cases (:meth:`MatrixSpec.cases`), so
    only each axis is bounded (by ``max_cases`` or :data:`MAX_CASES`, the larger), not their product.

    Raises
    ------
    SpecError
        If the file cannot be read or is not a valid spec, or it has more than ``max_cases`` cases
        (without ``sample``).
    """
    path = Path(path_or_name)
    if not os.path.exists(path):  # (False for a name too long to be a file)
        bundled = SPECS_DIR / f"{path_or_name}.toml"
        if not os.path.isfile(bundled):
            names = ", ".join(sorted(p.stem for p in SPECS_DIR.glob("*.toml")))
            raise SpecError(f"{path_or_name}: no such spec file (bundled specs: {names})")
        path = bundled
    check_input_file(path, SpecError, str(path_or_name), "spec file")  # a folder, a FIFO, a device
    text = read_text_file(path, SpecError, str(path))
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{path}: {exc}") from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise SpecError(f"{path}: not valid TOML: nested too deeply") from None
    return spec_from_dict(data, path, max_cases, sample=sample)


def bundled_specs() -> list[str]:
    return sorted(p.stem for p in SPECS_DIR.glob("*.toml"))


def spec_from_dict(data: dict, path: Path | None = None, max_cases: int = MAX_CASES, *,
                   sample: bool = False) -> MatrixSpec:
    """A checked spec from a parsed TOML document (see the module docstring).

    ``sample``: as in :func:`load_spec` (each axis bounded, not the number of cases).

    Raises
    ------
    SpecError
        If a key is unknown or of the wrong type or range, an expression is invalid or too costly,
        or the spec has more than ``max_cases`` cases (an axis more values, with ``sample``).
    """
    # a sample never makes more than one axis whole: bound the axes, not their product
    axis_limit = max(max_cases, MAX_CASES) if sample else max_cases
    where = str(path) if path else "spec"
    _table(data, where, "a TOML document")
    table = _table(data.get("matrix", {}), f"{where}: [matrix]")
    unknown = set(table) - MATRIX_KEYS
    if unknown:
        raise SpecError(f"{where}: unknown [matrix] keys: {', '.join(sorted(unknown))}")
    extra = set(data) - {"matrix", "study"}
    if extra:
        raise SpecError(f"{where}: unknown top-level keys: {', '.join(sorted(extra))} "
                        "(a spec has [matrix] and [[study]] tables)")
    if "name" in table:
        _name(table["name"], f"{where}: [matrix] name", "the name")
    if "description" in table:
        _text(table["description"], f"{where}: [matrix] description")
    settings = _settings(table, DEFAULTS, f"{where}: [matrix]")
    imports = []
    for item in _texts(table.get("imports", []), f"{where}: [matrix] imports"):
        if item.endswith(".py"):
            p = Path(item)
            if not p.is_absolute() and path is not None:
                p = path.parent / p
            check_input_file(p, SpecError, f"{where}: [matrix] imports: '{p}'")
            imports.append(str(p.resolve()))
        else:
            imports.append(item)
    studies, names = [], set()
    raw_studies = data.get("study", [])
    if not isinstance(raw_studies, list) or not raw_studies:
        raise SpecError(f"{where}: no [[study]] tables")
    for k, raw in enumerate(raw_studies):
        _table(raw, f"{where}: study {k + 1}", "a [[study]] table")
        name = _name(raw.get("name") or f"study{k + 1}", f"{where}: study {k + 1} name", "the study name")
        swhere = f"{where}: study '{name}'"
        unknown = set(raw) - STUDY_KEYS
        if unknown:
            raise SpecError(f"{swhere}: unknown keys: {', '.join(sorted(unknown))}")
        if name in names:
            raise SpecError(f"{swhere}: duplicate study name")
        names.add(name)
        for key in ("title", "claim", "description", "observe"):
            if key in raw:
                _text(raw[key], f"{swhere}: {key}")
        _texts(raw.get("connections", []), f"{swhere}: connections")
        _table(raw.get("system", {}), f"{swhere}: system", "a table of [system] keys")
        components = _components(raw.get("components", {}), swhere)
        variables = _table(raw.get("variables", {}), f"{swhere}: variables", "a table { NAME = VALUE or \"EXPR\" }")
        for vname, value in variables.items():
            _scalar(value, f"{swhere}: variable '{vname}'")
        fall = raw.get("system", {}).get("fall", {})
        observe = raw.get("observe") or (fall.get("signal") if isinstance(fall, dict) else None)
        if not observe:
            raise SpecError(f"{swhere}: 'observe' (COMPONENT.OUTPUT to classify) is missing")
        _text(observe, f"{swhere}: observe")
        comp, _, var = observe.partition(".")
        if comp not in components or not var:
            raise SpecError(f"{swhere}: observe = '{observe}' is not COMPONENT.OUTPUT of a component")
        tune = _tune(raw.get("tune", {}), components, swhere)
        raw_axes = _table(raw.get("axes", {}), f"{swhere}: axes", "a table [study.axes]")
        for n in raw_axes:
            if not n.isidentifier():
                raise SpecError(f"{swhere}: axis name '{n}' must be an identifier (use it as '={n}' in values)")
        for n, v in raw_axes.items():
            _axis_size(n, v, swhere, axis_limit)
        product = math.prod(_axis_size(n, v, swhere, axis_limit) for n, v in raw_axes.items()) if raw_axes else 0
        if product > max_cases and not sample:
            sizes = " x ".join(f"{n} ({_axis_size(n, v, swhere, max_cases)})" for n, v in raw_axes.items())
            raise SpecError(f"{swhere}: axes {sizes} = {product} cases, more than the limit of {max_cases} "
                            "(--max-cases N runs a sample of N of them, or all when N is at least their number)")
        axes = {n: _axis_values(n, v, swhere, axis_limit) for n, v in raw_axes.items()}
        explicit = _explicit_cases(raw.get("cases", []), axes, variables, swhere)
        if not axes and not explicit:
            raise SpecError(f"{swhere}: neither [study.axes] nor [[study.cases]]")
        study = Study(name=name, title=raw.get("title", name), claim=raw.get("claim", ""),
                      description=raw.get("description", ""), observe=observe, raw=raw,
                      settings=_settings(raw, settings, swhere), axes=axes, explicit=explicit,
                      checks=[], plots=[], where=where)
        if not sample:
            check_count([*studies, study], max_cases, where)
        first = study.make_case(study.first_point(), 0)
        coordinates = set(first.variables) | set(variables) | set(axes) | {n for c in explicit for n in c}
        known = coordinates | set(expr.CONSTANTS) | {"max_re", "growth_rate"} | {t.replace(".", "_") for t in tune}
        study.checks = _checks(raw.get("checks", []), axes, known, swhere)
        study.plots = _plots(raw.get("plots", []), coordinates, swhere)
        try:
            system_from_dict(first.system, None)
        except SystemError_ as exc:
            raise SpecError(f"{swhere}: {str(exc).removeprefix('system: ')}") from None
        studies.append(study)
    digest = hashlib.sha256(json.dumps(data, sort_keys=True, default=repr).encode()).hexdigest()[:16]
    return MatrixSpec(name=table.get("name", path.stem if path else "matrix"),
                      description=table.get("description", ""), path=path, settings=settings,
                      studies=studies, imports=imports, digest=digest)
