"""The analytic prediction of a case: closed-loop eigenvalues of the linear models of its components.

Every component gets a linear model (:class:`ComponentModel`: a :class:`~cosim.statespace.StateSpace`
and how the master treats its inputs):

* bicycles: the analytic twins of :mod:`cosim.analytic.twins` (the paper's equations) and, for
  ``Bicycle.Bicycles.WhippleLinear``, :func:`cosim.analytic.whipple.state_matrices` (Meijaard et al.
  2007) with the heading and lateral position added;
* Python blocks and the FMUs of their Modelica twins: the linear model each block declares
  (:meth:`cosim.cosimulation.registry.Block.linear`, read from the block registry); an exact
  ``TransportDelay`` declares python-control's Pade approximation of order ``pade_order``;
* any other FMU: its numerical linearization (:func:`cosim.fmu.linearize.linearize`).

The components are connected as in the system. With ``master_lag`` the co-simulation master's own
delays are modelled too (outputs sampled after the step), as the coupling algorithm states them
(:meth:`~cosim.cosimulation.algorithms.CouplingAlgorithm.output_lag`,
:meth:`~cosim.cosimulation.algorithms.CouplingAlgorithm.hold_lag`): under Jacobi an input held
over a communication step h by a component with states lags by h/2 (zero-order hold), and a
component without states (a static gain) answers one step late, a lag of h; each lag is a
second-order Pade approximation. Only the states that influence the observed signal are kept (the
heading and path integrators, which never feed back, would otherwise add eigenvalues at 0).

The prediction is the largest real part of the closed-loop eigenvalues, ``max_re`` [1/s]:
stable below ``-margin``, unstable above ``+margin``, marginal in between.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from cosim.cosimulation import algorithms
from cosim.errors import CosimError
from cosim.statespace import StateSpace
from cosim.analytic.parameters import load_parameters, PARAMETER_NAMES
from cosim.analytic.whipple import assembled_state_matrices, matrices
from cosim.cosimulation.system import parse_connection
from cosim.fmu.access import read_fmu, READABLE_FMI_VERSIONS


class PredictionError(CosimError, ValueError):
    """No analytic prediction can be made for a case; the message says why."""


@dataclass
class ComponentModel:
    """The linear model of one component: its ``system`` and how the master treats its inputs.

    ``kind`` is ``dynamic`` (inputs held by the master), ``static`` (no states) or ``delay``
    (interpolating); ``source`` says where the model comes from."""

    system: StateSpace
    kind: str = "dynamic"
    source: str = ""


def _lti(A, B, C, D, inputs, outputs, kind=None, source="", states=None) -> ComponentModel:
    system = StateSpace.of(A, B, C, D, inputs, outputs, states)
    if kind is None:
        kind = "static" if system.n == 0 else "dynamic"
    return ComponentModel(system, kind, source)


def static(D, inputs, outputs, source="") -> ComponentModel:
    return _lti(np.zeros((0, 0)), np.zeros((0, len(inputs))), np.zeros((len(outputs), 0)),
                np.asarray(D, float).reshape(len(outputs), len(inputs)), inputs, outputs, "static", source)


def tf_to_lti(num, den, inputs=("u",), outputs=("y",), kind=None, source="") -> ComponentModel:
    """Controllable canonical form of a proper SISO transfer function."""
    num = np.atleast_1d(np.asarray(num, float))
    den = np.atleast_1d(np.asarray(den, float))
    num, den = num / den[0], den / den[0]
    n = len(den) - 1
    if n == 0:
        return static([[num[-1]]], inputs, outputs, source)
    num = np.concatenate([np.zeros(n + 1 - len(num)), num])
    d = num[0]
    rest = num[1:] - d * den[1:]          # strictly proper part: coefficients of s^(n-1) ... s^0
    A = np.zeros((n, n))
    A[0, :] = -den[1:]
    A[1:, :-1] = np.eye(n - 1)
    B = np.zeros((n, 1))
    B[0, 0] = 1.0
    return _lti(A, B, rest.reshape(1, n), [[d]], inputs, outputs, kind, source)


@lru_cache(maxsize=4096)
def _pade(tau: float, n: int):
    import control

    num, den = control.pade(tau, n)
    return tuple(num), tuple(den)


def delay_lti(tau: float, order: int, inputs=("u",), outputs=("y",), kind="delay", source="") -> ComponentModel:
    """exp(-s tau) as the [order/order] Pade approximation (python-control's ``pade``)."""
    if tau <= 0:
        return static([[1.0]], inputs, outputs, source)
    num, den = _pade(float(tau), int(order))
    return tf_to_lti(num, den, inputs, outputs, kind, source)


# --------------------------------------------------------------------------- models of blocks

def _frozen(value):
    """A hashable form of a JSON-like value (dicts by sorted key); TypeError for anything else."""
    if isinstance(value, dict):
        return ("dict", tuple(sorted((str(k), _frozen(v)) for k, v in value.items())))
    if isinstance(value, (list, tuple)):
        return ("list", tuple(_frozen(v) for v in value))
    if value is None or isinstance(value, (bool, int, float, str)):
        return (type(value).__name__, value)
    raise TypeError(f"no cache key for {type(value).__name__}")


def _read_only(model: ComponentModel) -> ComponentModel:
    s = model.system
    for array in (s.A, s.B, s.C, s.D):
        array.setflags(write=False)
    return model


#: Linear models of blocks by (name, block class, parameters, settings): the cases of a study
#: usually share a block's parameters (python-control's Pade approximation of a delay costs
#: ~0.4 ms a case).
_BLOCK_MODELS: dict = {}
_BLOCK_MODELS_MAX = 4096


def block_lti(name: str, block: str, parameters: dict, settings: dict) -> ComponentModel:
    """The linear model a registered Python block declares, for the parameters given (its
    defaults for the others); a block that interpolates its inputs is of kind ``delay``.

    Models are cached by their arguments and the block's class (a block's linear model is a
    function of its parameters and the settings); the cached arrays are read-only."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.cosimulation import registry

    try:
        key = (registry.lookup(block), _frozen([name, parameters, settings]))
    except (CosimError, TypeError):  # an unknown block (the error comes below) or an odd value
        key = None
    model = _BLOCK_MODELS.get(key) if key is not None else None
    if model is None:
        model = _block_lti(name, block, parameters, settings)
        if key is not None:
            if len(_BLOCK_MODELS) >= _BLOCK_MODELS_MAX:
                _BLOCK_MODELS.clear()
            _BLOCK_MODELS[key] = _read_only(model)
    return model


def _block_lti(name: str, block: str, parameters: dict, settings: dict) -> ComponentModel:
    # deferred: loads fmpy, which importing this module does not
    from cosim.cosimulation import registry

    try:
        instance = registry.lookup(block).create(name, parameters)
        model = instance.linear(settings)
    except (CosimError, NotImplementedError) as exc:  # unknown block or parameter, no linear model
        raise PredictionError(f"component '{name}': {exc}") from None
    kind = "delay" if instance.interpolates else None
    return _lti(model.A, model.B, model.C, model.D, model.inputs, model.outputs, kind,
                f"{block}: {type(instance).summary()}")


WHIPPLE = "Bicycle.Bicycles.WhippleLinear"


@lru_cache(maxsize=1)
def _benchmark() -> dict:
    return load_parameters("benchmark")


@lru_cache(maxsize=256)
def _whipple_matrices(items: tuple) -> tuple:
    """M, C1, K0, K2 (read-only), M^-1 and g of a parameter set (given as sorted items): the
    part of :func:`cosim.analytic.whipple.state_matrices` that does not depend on the speed,
    computed (and the parameters validated) once per parameter set instead of once per case."""
    p = dict(items)
    M, C1, K0, K2 = matrices(p)
    Minv = np.linalg.inv(M)
    for array in (M, C1, K0, K2, Minv):
        array.setflags(write=False)
    return M, C1, K0, K2, Minv, float(p["g"])


def whipple_state_matrices(p: dict, v: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cosim.analytic.whipple.state_matrices` with the speed-independent part cached:
    the same operations in the same order, so the same bits (tests/test_matrix_pool.py)."""
    M, C1, K0, K2, Minv, g = _whipple_matrices(tuple(sorted(p.items())))
    return assembled_state_matrices(Minv, C1, K0, K2, g, float(v))


def _whipple(params: dict) -> ComponentModel:
    base = _benchmark()
    p = {k: float(params.get(k, base[k])) for k in PARAMETER_NAMES}
    v = float(params.get("v", 5.0))
    A4, B4 = whipple_state_matrices(p, v)
    A = np.zeros((6, 6))
    A[:4, :4] = A4
    k = math.cos(p["lam"]) / p["w"]
    A[4, 1], A[4, 3] = v * k, p["c"] * k       # der(psi) = (v delta + c delta_dot) cos(lam) / w
    A[5, 4] = v                                 # der(y) = v psi
    B = np.zeros((6, 2))
    B[:4] = B4
    names = ["phi", "delta", "phi_dot", "delta_dot", "psi", "y"]
    return _lti(A, B, np.eye(6), np.zeros((6, 2)), ["T_phi", "T_delta"], names, "dynamic",
                "linear Whipple model (Meijaard et al. 2007)", names)


def _twin(model: str, params: dict) -> ComponentModel | None:
    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic.twins import TWINS

    twin = TWINS.get(model)
    if twin is None:
        return None
    plain = {k: v for k, v in params.items() if "." not in k}
    try:
        sys = twin.system(plain)
    except ValueError as exc:
        raise PredictionError(f"analytic twin of {model}: {exc}") from None
    return _lti(sys.A, sys.B, sys.C, sys.D, list(sys.input_labels), list(sys.output_labels), "dynamic",
                f"analytic twin: {twin.equations}", list(sys.state_labels))


@lru_cache(maxsize=64)
def _fmu_info(path: str):
    md = read_fmu(path, READABLE_FMI_VERSIONS)  # the one cached reading per process (cosim.fmu.access)
    starts = {}
    for v in md.modelVariables:
        if v.causality == "parameter" and v.start is not None:
            try:
                starts[v.name] = float(v.start)
            except (TypeError, ValueError):
                pass
    return md.modelName, starts


def component_lti(name: str, entry: dict, fmu_paths: dict, settings: dict) -> ComponentModel:
    """The linear model of one component of a system dict."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.cosimulation import registry

    params = dict(entry.get("parameters", {}))
    if "python" in entry:
        return block_lti(name, entry["python"], params, settings)
    path = entry.get("fmu") or fmu_paths.get(entry.get("model"))
    model_name = entry.get("model")
    starts = {}
    if path:
        md_name, starts = _fmu_info(str(path))
        model_name = model_name or md_name
    if model_name == WHIPPLE:
        return _whipple(params)
    twin = _twin(model_name, params)
    if twin is not None:
        return twin
    block = registry.for_twin(model_name)
    if block is not None:  # the FMU of a block's twin: the block's linear model, the FMU's defaults
        accepted = block.parameters()
        return block_lti(name, block.__name__, {k: v for k, v in {**starts, **params}.items() if k in accepted},
                         settings)
    if path:
        # deferred: loads fmpy, which importing this module does not
        from cosim.fmu.linearize import linearize

        s = linearize(path, dict(params)).system
        return _lti(s.A, s.B, s.C, s.D, s.inputs, s.outputs, None, "FMU linearization", s.states)
    raise PredictionError(f"component '{name}': no analytic model for '{model_name}'")


# --------------------------------------------------------------------------- closed loop

@dataclass
class Prediction:
    max_re: float
    dominant: complex
    eigenvalues: list = field(default_factory=list)
    states: int = 0
    sources: dict = field(default_factory=dict)

    def classify(self, margin: float) -> str:
        if self.max_re < -margin:
            return "stable"
        if self.max_re > margin:
            return "unstable"
        return "marginal"


def _split(signal: str) -> tuple[str, str]:
    comp, _, var = signal.partition(".")
    return comp, var


class Loop:
    """The closed loop of a system dict, assembled once; blocks of the same shape can be swapped
    (tuning) before :meth:`prediction` is evaluated again."""

    def __init__(self, system: dict, observe: str, fmu_paths: dict, settings: dict, models: dict | None = None):
        comps = system["components"]
        self.models = models or {n: component_lti(n, e, fmu_paths, settings) for n, e in comps.items()}
        sysset = system.get("system", {})
        h = float(sysset.get("step", 0.01))
        try:
            coupling = algorithms.algorithm(str(sysset.get("algorithm", "jacobi")))
        except algorithms.UnknownAlgorithm as exc:
            raise PredictionError(str(exc)) from None
        if not coupling.predicted:
            raise PredictionError(f"the prediction does not model algorithm = \"{coupling.name}\"")
        blocks = dict(self.models)
        wiring = []  # (source, output, target, input)
        for text in system.get("connections", []):
            c = parse_connection(text, "system")
            for comp, var, attr in ((c.source, c.output, "outputs"), (c.target, c.input, "inputs")):
                if comp not in blocks or var not in getattr(blocks[comp].system, attr):
                    listed = ", ".join(getattr(blocks[comp].system, attr)) if comp in blocks else "no such component"
                    raise PredictionError(f"connection '{c}': the linear model of '{comp}' has no "
                                          f"{attr[:-1]} '{var}' ({listed})")
            lag = 0.0
            if settings.get("master_lag", True):
                src, dst = blocks[c.source], blocks[c.target]
                m_src = int(comps[c.source].get("step_multiple", 1))
                m_dst = int(comps[c.target].get("step_multiple", 1))
                if src.kind == "static" and src.system.D.size:
                    lag += coupling.output_lag(h * m_src)
                if dst.kind == "dynamic" and dst.system.n > 0:
                    lag += coupling.hold_lag(h * m_dst)
            if lag > 0:
                lname = f"lag:{c}"
                blocks[lname] = delay_lti(lag, 2, kind="delay", source=f"master lag {lag:g} s")
                wiring += [(c.source, c.output, lname, "u"), (lname, "y", c.target, c.input)]
            else:
                wiring.append((c.source, c.output, c.target, c.input))
        self.blocks = blocks
        self.slices = {}
        nx = nu = ny = 0
        for n, b in blocks.items():
            b = b.system
            self.slices[n] = (slice(nx, nx + b.n), slice(nu, nu + len(b.inputs)), slice(ny, ny + len(b.outputs)))
            nx, nu, ny = nx + b.n, nu + len(b.inputs), ny + len(b.outputs)
        self.A, self.B = np.zeros((nx, nx)), np.zeros((nx, nu))
        self.C, self.D = np.zeros((ny, nx)), np.zeros((ny, nu))
        for n, b in blocks.items():
            self._write(n, b)
        self.K = np.zeros((nu, ny))
        for s, out, t, inp in wiring:
            self.K[self.slices[t][1].start + blocks[t].system.inputs.index(inp),
                   self.slices[s][2].start + blocks[s].system.outputs.index(out)] = 1.0
        ocomp, ovar = _split(observe)
        if ocomp not in blocks or ovar not in blocks[ocomp].system.outputs:
            raise PredictionError(f"observed signal '{observe}' is not an output of the linear model of '{ocomp}'")
        self.observed = self.slices[ocomp][2].start + blocks[ocomp].system.outputs.index(ovar)
        self.connected = bool(wiring)
        self.eye = np.eye(ny)
        self.keep = None  # states kept: fixed while tuning (the structure does not change)

    def _write(self, name: str, b: ComponentModel) -> None:
        xs, us, ys = self.slices[name]
        s = b.system
        self.A[xs, xs], self.B[xs, us], self.C[ys, xs], self.D[ys, us] = s.A, s.B, s.C, s.D

    def replace(self, name: str, b: ComponentModel) -> None:
        old, new = self.blocks[name].system, b.system
        if (old.A.shape, old.D.shape) != (new.A.shape, new.D.shape):
            raise PredictionError(f"component '{name}': the tuned model changed its size")
        self.blocks[name] = self.models[name] = b
        self._write(name, b)

    def prediction(self) -> Prediction:
        if self.connected:
            try:
                Cy = np.linalg.solve(self.eye - self.D @ self.K, self.C)
            except np.linalg.LinAlgError:
                raise PredictionError("algebraic loop without a solution (I - D K is singular)") from None
            Acl = self.A + self.B @ self.K @ Cy
        else:  # K = 0: what the two lines above give, without their cost (a case of one FMU)
            Cy, Acl = self.C, self.A
        keep = self.keep if self.keep is not None else _influencing(Acl, Cy[self.observed])
        if not keep.size:
            raise PredictionError("no state influences the observed signal")
        self.last_keep = keep
        ev = np.linalg.eigvals(Acl[keep[:, None], keep])  # (= Acl[np.ix_(keep, keep)])
        ev = ev[np.lexsort((-ev.imag, -ev.real))]
        dom = complex(ev[0])
        if dom.imag < 0:
            dom = dom.conjugate()
        return Prediction(max_re=float(ev[0].real), dominant=dom, eigenvalues=[complex(e) for e in ev],
                          states=int(keep.size), sources={n: m.source for n, m in self.models.items()})


def closed_loop(system: dict, observe: str, fmu_paths: dict, settings: dict,
                models: dict | None = None) -> Prediction:
    """Closed-loop eigenvalues of a system dict (see the module docstring)."""
    return Loop(system, observe, fmu_paths, settings, models).prediction()


#: Largest number of states whose influence graph :func:`_influencing` searches in plain Python (a
#: matrix case's bicycle has 6, where the dozen small array operations of the iteration below cost
#: three times as much); larger graphs grow the set with whole-array operations.
SMALL_GRAPH = 32


def _influencing(A: np.ndarray, row: np.ndarray) -> np.ndarray:
    """States with a path in the graph of A to a state the observed output reads."""
    if not A.size:
        return np.zeros(0, dtype=int)
    magnitude, reads = np.abs(A), np.abs(row)
    nz = magnitude > 1e-14 * max(1.0, float(magnitude.max()))
    keep = reads > 1e-14 * max(1.0, float(reads.max()))
    if A.shape[0] <= SMALL_GRAPH:
        edges, kept = nz.tolist(), keep.tolist()
        todo = [i for i, k in enumerate(kept) if k]
        while todo:  # x_j influences x_i where A[i, j] != 0
            for j, edge in enumerate(edges[todo.pop()]):
                if edge and not kept[j]:
                    kept[j] = True
                    todo.append(j)
        return np.flatnonzero(kept)
    count = int(keep.sum())
    while True:  # grows only: done when the count stays
        keep = keep | nz[keep].any(axis=0)
        grown = int(keep.sum())
        if grown == count:
            break
        count = grown
    return np.flatnonzero(keep)


# --------------------------------------------------------------------------- cases

def _set_parameter(system: dict, target: str, value: float) -> dict:
    comp, par = _split(target)
    out = {**system, "components": dict(system["components"])}
    entry = dict(out["components"][comp])
    entry["parameters"] = {**entry.get("parameters", {}), par: float(value)}
    out["components"][comp] = entry
    return out


def tune(system: dict, observe: str, tune_spec: dict, fmu_paths: dict, settings: dict):
    """The parameter value minimizing the predicted max Re (the best rider): a grid, then Brent.

    Returns (system with the tuned value, {target: value}, prediction there)."""
    from scipy.optimize import minimize_scalar

    if len(tune_spec) != 1:
        raise PredictionError(f"tune one parameter at a time, got {', '.join(tune_spec)}")
    (target, opts), = tune_spec.items()
    lo, hi = float(opts.get("min", 1e-3)), float(opts.get("max", 1e3))
    points = int(opts.get("points", 32))
    log = opts.get("scale", "log") == "log"
    if not (hi > lo and points >= 3 and (lo > 0 or not log)):
        raise PredictionError(f"tune '{target}': need max > min (> 0 on a log scale) and points >= 3")
    comp, _ = _split(target)
    loop = Loop(system, observe, fmu_paths, settings)
    loop.prediction()
    loop.keep = loop.last_keep

    def objective(u):
        sys = _set_parameter(system, target, math.exp(u) if log else u)
        loop.replace(comp, component_lti(comp, sys["components"][comp], fmu_paths, settings))
        return loop.prediction().max_re

    grid = np.linspace(math.log(lo), math.log(hi), points) if log else np.linspace(lo, hi, points)
    values = [objective(u) for u in grid]
    k = int(np.argmin(values))
    best_u, best = float(grid[k]), values[k]
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, points - 1)]
    if b > a:
        res = minimize_scalar(objective, bounds=(a, b), method="bounded",
                              options={"xatol": 1e-3})
        if res.fun < best:
            best_u, best = float(res.x), float(res.fun)
    value = float(math.exp(best_u) if log else best_u)
    tuned = _set_parameter(system, target, value)
    return tuned, {target: value}, closed_loop(tuned, observe, fmu_paths, settings)


def predict_case(case, fmu_paths: dict) -> tuple[dict, dict]:
    """(system to simulate, prediction record) of a case; tuned parameters are applied."""
    system, tuned = case.system, {}
    if case.tune:
        system, tuned, pred = tune(case.system, case.observe, case.tune, fmu_paths, case.settings)
    else:
        pred = closed_loop(system, case.observe, fmu_paths, case.settings)
    margin = float(case.settings["margin"])
    record = {
        "max_re": pred.max_re,
        "dominant": [pred.dominant.real, pred.dominant.imag],
        "eigenvalues": [[e.real, e.imag] for e in pred.eigenvalues[:8]],
        "states": pred.states,
        "class": pred.classify(margin),
        "margin": margin,
        "tuned": tuned,
    }
    return system, record


def max_re_at(study, values: dict, fmu_paths: dict) -> float:
    """Predicted max Re of a study at arbitrary coordinates (for boundary searches)."""
    _, record = predict_case(study.make_case(values), fmu_paths)
    return record["max_re"]
