"""Linearize an FMU about its initial point: A, B, C, D from directional derivatives.

``fmi2GetDirectionalDerivative`` gives exact Jacobians for FMUs built here; for foreign FMUs
without it, central finite differences are used.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import FMUError, ParameterError, SimulationError
from cosim.fmu.access import FMU, get_continuous_states, set_continuous_states

FD_STEP = 1e-6  # relative step of the central differences


@dataclass
class Linearization:
    """x' = A x + B u, y = C x + D u about an operating point (deviations)."""

    model: str
    parameters: dict
    states: list[str]
    inputs: list[str]
    outputs: list[str]
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    method: str

    @property
    def eigenvalues(self) -> np.ndarray:
        return np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, complex)

    def to_statespace(self):
        """A python-control StateSpace with named states, inputs and outputs."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, states=self.states, inputs=self.inputs,
                          outputs=self.outputs, name=self.model.replace(".", "_"))

    def to_dict(self) -> dict:
        return {
            "model": self.model, "parameters": self.parameters, "states": self.states,
            "inputs": self.inputs, "outputs": self.outputs,
            "A": self.A.tolist(), "B": self.B.tolist(), "C": self.C.tolist(), "D": self.D.tolist(),
            "eigenvalues": [[float(e.real), float(e.imag)] for e in self.eigenvalues],
            "method": self.method,
        }

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2)


class _Point:
    """An ME instance held at (t, x, u) that evaluates derivatives and outputs."""

    def __init__(self, fmu: FMU, parameters: dict):
        self.fmu = fmu
        self.me = fmu.instantiate("me")
        self.status = 0  # worst FMI status seen (decides the clean-up, see close)
        try:
            fmu.set(self.me, parameters)
            self.me.setupExperiment(startTime=0.0)
            self.me.enterInitializationMode()
            self.me.exitInitializationMode()
            self.me.enterContinuousTimeMode()
        except FMICallException as exc:  # the FMU refused the parameters or the initialization
            self.fail(exc)
            self.close()
            raise SimulationError(f"{fmu.path}: initialization failed: {self.said(exc)}") from None
        self.nx = len(fmu.states)
        self.x0 = self.get_states()

    def fail(self, exc: Exception) -> None:
        self.status = max(self.status, int(getattr(exc, "status", 3) or 3))

    def said(self, exc: Exception) -> str:
        """What the FMU logged about a failed call, else the call's exception text."""
        return self.me.log.last_error() or str(exc)

    def get_states(self) -> np.ndarray:
        return get_continuous_states(self.me, self.nx)

    def set_states(self, x) -> None:
        set_continuous_states(self.me, x)

    def close(self):
        """fmi2Terminate where FMI allows it (not after fmi2Error), then fmi2FreeInstance."""
        if self.status >= 4:
            return
        if self.status < 3:
            try:
                self.me.terminate()
            except Exception:  # freeing is still allowed
                pass
        try:
            self.me.freeInstance()
        except Exception:
            pass


def linearize(fmu_path: str | Path, parameters: dict | None = None, inputs: dict | None = None,
              method: str = "auto") -> Linearization:
    """Linearize an FMU at its initial state (after initialization) and the given inputs.

    Parameters
    ----------
    fmu_path : path
        FMI 2.0 FMU with Model Exchange.
    parameters : dict, optional
        Start values of parameters (name -> value), in the SI units the FMU declares
        (e.g. ``V`` [m/s], ``m`` [kg]).
    inputs : dict, optional
        Operating-point input values in SI units (e.g. ``T`` [N m]; default: the inputs' start
        values).
    method : {'auto', 'directional', 'finite-differences'}
        'auto' uses directional derivatives where the FMU provides them.

    Returns
    -------
    Linearization
        Matrices with states ordered as the FMU's ModelStructure/Derivatives, inputs and outputs
        in modelDescription order.
    """
    parameters = dict(parameters or {})
    with FMU(fmu_path) as fmu:
        md = fmu.description
        if md.modelExchange is None:
            raise FMUError(f"{fmu_path}: linearization needs Model Exchange, which the FMU does not offer")
        if method not in ("auto", "directional", "finite-differences"):
            raise ParameterError(f"method must be 'auto', 'directional' or 'finite-differences', got '{method}'")
        use_dd = method == "directional" or (method == "auto" and md.modelExchange.providesDirectionalDerivative)
        states, derivatives = fmu.states, fmu.derivatives
        input_names, output_names = fmu.names("input"), fmu.names("output")
        point = _Point(fmu, {**parameters, **(inputs or {})})
        try:
            return _jacobians(fmu, md, point, use_dd, parameters, states, derivatives, input_names, output_names)
        except FMICallException as exc:  # an FMI call refused at the operating point
            point.fail(exc)
            raise SimulationError(f"{fmu_path}: linearization failed: {point.said(exc)}") from None
        finally:
            point.close()


def _jacobians(fmu, md, point, use_dd, parameters, states, derivatives, input_names, output_names):
    """The matrices at the point (see :func:`linearize`)."""
    x0 = point.x0
    u0 = fmu.get_real(point.me, input_names)
    state_index = {n: k for k, n in enumerate(states)}
    # Outputs that are states have an identity row; the others are unknowns to differentiate.
    computed = [n for n in output_names if n not in state_index]
    unknowns = derivatives + computed
    unknown_vrs = [fmu.vr[n] for n in unknowns]
    knowns = states + input_names
    known_vrs = [fmu.vr[n] for n in knowns]
    nx, nu = len(states), len(input_names)
    J = np.zeros((len(unknowns), nx + nu))
    if use_dd:
        for k in range(nx + nu):
            seed = [0.0] * (nx + nu)
            seed[k] = 1.0
            J[:, k] = point.me.getDirectionalDerivative(unknown_vrs, known_vrs, seed)
    else:
        def evaluate(x, u):
            point.set_states(x)
            fmu.set(point.me, dict(zip(input_names, u)))
            return np.array(point.me.getReal(unknown_vrs))

        for k in range(nx + nu):
            x, u = x0.copy(), u0.copy()
            base = x0[k] if k < nx else u0[k - nx]
            h = FD_STEP * max(1.0, abs(base))
            values = []
            for sign in (1, -1):
                x, u = x0.copy(), u0.copy()
                if k < nx:
                    x[k] += sign * h
                else:
                    u[k - nx] += sign * h
                values.append(evaluate(x, u))
            J[:, k] = (values[0] - values[1]) / (2 * h)
        evaluate(x0, u0)
    A, B = J[:nx, :nx], J[:nx, nx:]
    C = np.zeros((len(output_names), nx))
    D = np.zeros((len(output_names), nu))
    for row, name in enumerate(output_names):
        if name in state_index:
            C[row, state_index[name]] = 1.0
        else:
            k = nx + computed.index(name)
            C[row], D[row] = J[k, :nx], J[k, nx:]
    return Linearization(md.modelName, parameters, states, input_names, output_names, A, B, C, D,
                         "directional derivatives" if use_dd else "central finite differences")
