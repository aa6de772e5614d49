"""The FMUs of ``Bicycle.Bicycles.Whipple`` / ``WhippleRider`` as vector fields.

Everything here evaluates the FMU (Model Exchange, exact directional derivatives), never the
sympy derivation: :class:`Bicycle` sets a parameter set and an initial state (the FMU makes the
pitch consistent with the holonomic constraint by its generated Newton steps), reads the state
vector and the derivatives, and linearizes.

States (FMU order): ``x, y, psi, phi, theta, delta, thetaR, thetaF, [beta,] u_phi, u_delta, u_R
[, u_beta]``. Speed: the rear wheel rate ``u_R = -v/rR`` (upright, straight running).
"""
from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from cosim.errors import FMUError
from cosim.fmu.access import FMU, DirectCalls
from cosim.analytic.parameters import load_parameters
from cosim.compiler.library import load_library

MODEL = "Bicycle.Bicycles.Whipple"
RIDER_MODEL = "Bicycle.Bicycles.WhippleRider"
#: Initial-state parameters of the FMU by state name.
START = {"x": "x0", "y": "y0", "psi": "psi0", "phi": "phi0", "delta": "delta0", "thetaR": "thetaR0",
         "thetaF": "thetaF0", "beta": "beta0", "u_phi": "u_phi0", "u_delta": "u_delta0", "u_R": "u_R0",
         "u_beta": "u_beta0"}


def build(model: str = MODEL, output: str | Path | None = None) -> Path:
    """The FMU of ``model`` built (incrementally) into ``output`` (default: the project's ``fmus/``)."""
    # deferred: loads casadi, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model

    return build_model(model, output or DEFAULT_OUTPUT, load_library()).fmu


def parameters(name_or_path: str = "benchmark", **extra: float) -> dict[str, float]:
    """FMU parameters of a Meijaard parameter set (bundled name or TOML file; the FMU's names are
    Meijaard's symbols), plus ``extra`` (e.g. crown radii ``tR``, ``tF``)."""
    return {**load_parameters(name_or_path), **extra}


def defaults(fmu: str | Path, names) -> dict[str, float]:
    """Default (start) values of FMU variables."""
    with FMU(fmu) as f:
        return {n: float(f.variables[n].start) for n in names}


def speed_parameters(params: dict, v: float, **state: float) -> dict[str, float]:
    """``params`` plus the initial rear wheel rate for forward speed ``v`` (upright: ``-v/rR``) and
    other initial values by state name (``phi=0.1`` -> ``phi0 = 0.1``)."""
    out = dict(params)
    out["u_R0"] = -float(v) / float(params["rR"])
    for name, value in state.items():
        out[START.get(name, name)] = float(value)
    return out


class Bicycle:
    """A Model Exchange instance of the nonlinear bicycle FMU held for repeated evaluation.

    Parameters
    ----------
    fmu : path
        The FMU of ``Bicycle.Bicycles.Whipple`` or ``WhippleRider``.
    params : dict
        Parameter values (names as in the FMU).
    """

    def __init__(self, fmu: str | Path, params: dict | None = None):
        self.fmu = FMU(fmu)
        self.params = dict(params or {})
        self.states = self.fmu.states
        self.index = {n: k for k, n in enumerate(self.states)}
        self.nx = len(self.states)
        self.inputs = self.fmu.names("input")
        self.me = self.fmu.instantiate("me")
        # the instance is re-initialized some 10^5 times by an equilibrium search: direct calls
        self.calls = DirectCalls(self.fmu, self.me)
        self._starts: dict[tuple, tuple] = {}  # names of a start dict -> (setter, its slots)
        self._initialized = False
        self.initialize({})

    def close(self):
        if self.me is not None:
            self.me.terminate()
            self.me.freeInstance()
            self.me = None
        self.fmu.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _start_setter(self, names: tuple) -> tuple:
        """The prepared ``fmi2SetReal`` of the parameters followed by the start values ``names``
        (one call, in the order of ``{**params, **start}``), the parameter values filled in once,
        and the slots of ``names`` in it."""
        found = self._starts.get(names)
        if found is None:
            order = list({**self.params, **dict.fromkeys(names)})
            setter = self.calls.real_setter(order)
            for k, name in enumerate(order):
                if name in self.params:
                    setter[1][k] = float(self.params[name])
            found = self._starts[names] = (setter, [order.index(n) for n in names])
        return found

    def initialize(self, start: dict) -> np.ndarray:
        """Re-initialize with the parameters and ``start`` (FMU parameter names, e.g. ``phi0``);
        returns the initial state vector (pitch from the generated Newton steps)."""
        self.reinitialize(start)
        return self.get_states()

    def reinitialize(self, start: dict) -> None:
        """:meth:`initialize` without reading the states back."""
        if self._initialized:
            self.calls.reset()
        try:
            setter, slots = self._start_setter(tuple(start))
        except FMUError:  # a variable that is not Real: the setter of every type
            self.fmu.set(self.me, {**self.params, **start})
        else:
            values = setter[1]
            for slot, value in zip(slots, start.values()):
                values[slot] = float(value)
            self.calls.set_reals(setter)
        self.calls.initialize(0.0)
        self._initialized = True

    def get_states(self) -> np.ndarray:
        return self.calls.get_states()

    def set_states(self, x) -> None:
        self.calls.set_states(x)

    def set_inputs(self, values: dict) -> None:
        self.fmu.set(self.me, values)

    def derivatives(self, x=None) -> np.ndarray:
        if x is not None:
            self.set_states(x)
        return self.calls.derivatives()

    def get(self, names, x=None) -> np.ndarray:
        if x is not None:
            self.set_states(x)
        return np.array(self.fmu.get_real(self.me, list(names)))

    def jacobian(self, x=None) -> np.ndarray:
        """d(xdot)/dx at ``x`` from the FMU's directional derivatives."""
        if x is not None:
            self.set_states(x)
        return self.calls.state_jacobian()

    def state(self, **values: float) -> np.ndarray:
        """Initial state from values by state name (pitch made consistent)."""
        return self.initialize({START[k]: v for k, v in values.items()})


def reduced_jacobian(J: np.ndarray, states: list[str]) -> tuple[np.ndarray, list[str]]:
    """The Jacobian on the constraint manifold in the coordinates (roll, steer, [lean,] and the
    independent speeds): pitch is eliminated with ``d theta = A_theta,phi d phi + A_theta,delta
    d delta`` (its rates ``J[theta, u_phi]``, ``J[theta, u_delta]`` are exactly these
    coefficients), and the ignorable coordinates x, y, psi and the wheel angles are dropped
    (nothing depends on them). ``J`` is the full Jacobian at a point with ``u_phi = u_delta = 0``."""
    keep, rows, th, pitch = _reduction(tuple(states))
    R = J[rows[:, None], rows]
    for col, rate in pitch:
        R[:, col] += J[rows, th] * J[th, rate]
    return R, list(keep)


@functools.lru_cache(maxsize=8)
def _reduction(states: tuple) -> tuple:
    """What :func:`reduced_jacobian` keeps of ``states``: the names, their rows, the row of the
    pitch and, per column of roll and steer, the state whose rate gives the pitch's part."""
    ix = {n: k for k, n in enumerate(states)}
    keep = tuple(n for n in states if n not in ("x", "y", "psi", "theta", "thetaR", "thetaF"))
    pitch = tuple((col, ix[rate]) for col, name in enumerate(keep)
                  for coordinate, rate in (("phi", "u_phi"), ("delta", "u_delta")) if name == coordinate)
    return keep, np.array([ix[n] for n in keep]), ix["theta"], pitch
