"""Linearize an FMU about its initial point: A, B, C, D from directional derivatives.

``fmi2GetDirectionalDerivative`` gives exact Jacobians for FMUs built here; for foreign FMUs
without it, central finite differences are used.

For the nonlinear bicycles (``Bicycle.Bicycles.Whipple``, ``WhippleRider``) :func:`steady_motion`
reduces the linearization about upright straight running exactly to its lateral dynamics (see
there): the ignorable coordinates, the pitch (fixed by the holonomic constraint) and the
conserved forward speed each contribute an exact zero eigenvalue, which are named; the hinge of
the rider can be locked exactly by its reaction torque.
"""
from __future__ import annotations

import json
from ctypes import c_double
from dataclasses import dataclass, field
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
    #: The operating point: state values and their time derivatives (FMU state order; SI units).
    x0: np.ndarray | None = field(default=None, repr=False)
    xdot0: np.ndarray | None = field(default=None, repr=False)

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
        in modelDescription order; the operating point's states ``x0`` and derivatives ``xdot0``.

    See Also
    --------
    steady_motion : the exact lateral dynamics of a nonlinear bicycle about upright straight running.
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
    point.set_states(x0)
    xdot0 = (c_double * nx)()
    if nx:
        point.me.getDerivatives(xdot0, nx)
    return Linearization(md.modelName, parameters, states, input_names, output_names, A, B, C, D,
                         "directional derivatives" if use_dd else "central finite differences",
                         x0.copy(), np.array(xdot0[:], float))


# --------------------------------------------------------------------------- steady motion

def in_coordinates(lin: Linearization, names) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``A``, ``B``, operating point and its derivative in the coordinates ``z = T x`` named by
    ``names``: each name is a state or an output that is a linear function of the states only
    (a row of ``C`` with a zero row of ``D``), so state names of the implementation do not matter.

    Returns ``(A_z, B_z, z0, zdot0)``; ``T`` must be square and invertible (for aliases of the
    states it is a permutation, and the transformation is exact).

    Raises
    ------
    ValueError
        A name that is neither, an output that depends on the inputs, or names that are not
        coordinates of the whole state (wrong number, linearly dependent).
    """
    index = {n: k for k, n in enumerate(lin.states)}
    rows = []
    for name in names:
        if name in index:
            row = np.zeros(len(lin.states))
            row[index[name]] = 1.0
        elif name in lin.outputs:
            k = lin.outputs.index(name)
            if np.any(lin.D[k] != 0.0):
                raise ValueError(f"{lin.model}: output {name} depends on the inputs; it is not a state coordinate")
            row = lin.C[k]
        else:
            raise ValueError(f"{lin.model}: no state or output named {name}")
        rows.append(row)
    T = np.array(rows, float).reshape(len(rows), len(lin.states))
    if T.shape[0] != T.shape[1] or np.linalg.matrix_rank(T) < T.shape[0]:
        raise ValueError(f"{lin.model}: {', '.join(names)} are not coordinates of its {len(lin.states)} states "
                         f"({', '.join(lin.states)})")
    A = np.linalg.solve(T.T, (T @ lin.A).T).T  # T A T^-1
    z0 = T @ lin.x0 if lin.x0 is not None else np.full(len(names), np.nan)
    zdot0 = T @ lin.xdot0 if lin.xdot0 is not None else np.full(len(names), np.nan)
    return A, T @ lin.B, z0, zdot0


#: The quantities of the nonlinear bicycles (outputs of ``Bicycle.Bicycles.Whipple`` and
#: ``WhippleRider``) in the roles they play in upright straight running.
IGNORABLE = ("x", "y", "psi", "thetaR", "thetaF")  # nothing depends on them but the path
PATH = ("psi", "y")  # yaw and lateral position: reported with the lateral dynamics
PITCH = "theta"  # fixed by roll and steer through the holonomic constraint
FORWARD_SPEED = "u_R"  # rear wheel rate: the conserved speed, u_R = -v/rR
LATERAL_COORDINATES = ("phi", "delta")
LATERAL_SPEEDS = ("u_phi", "u_delta")
HINGE = ("beta", "u_beta", "T_beta")  # rider's lean angle, lean rate and lean torque
ZERO_MODES = {
    PITCH: "pitch: fixed by roll and steer through the holonomic constraint (front contact on the ground)",
    FORWARD_SPEED: "rear wheel rate: the conserved forward speed (does not couple to the lateral motion "
                   "at first order)",
    "x": "ignorable (cyclic) coordinate: longitudinal position of the rear contact",
    "y": "ignorable (cyclic) coordinate: lateral position of the rear contact (integrates yaw)",
    "psi": "ignorable (cyclic) coordinate: yaw (integrates steer)",
    "thetaR": "ignorable (cyclic) coordinate: rear wheel rotation angle",
    "thetaF": "ignorable (cyclic) coordinate: front wheel rotation angle",
}
#: Relative size (to the largest entry of [A B]) below which an entry counts as structurally zero.
STRUCTURE_TOL = 1e-12


def is_bicycle(lin: Linearization) -> bool:
    """Whether the FMU has the quantities of the nonlinear bicycles (:data:`IGNORABLE` etc.) as
    states or outputs, so that :func:`steady_motion` applies."""
    have = set(lin.states) | set(lin.outputs)
    return {*IGNORABLE, PITCH, FORWARD_SPEED, *LATERAL_COORDINATES, *LATERAL_SPEEDS} <= have


class NotSteadyMotion(ValueError):
    """The linearization is not about upright straight running (or lacks its structure)."""


@dataclass
class SteadyMotion:
    """The exact lateral linearization of a nonlinear bicycle about upright straight running.

    ``x' = A x + B u`` on the lateral states (roll, steer[, lean], their rates), ``path_A``,
    ``path_B`` the rows of yaw and lateral position (``psi' , y'``) on ``states + path``.
    The eigenvalues of the whole model are :attr:`eigenvalues` and one exact zero for each
    entry of :attr:`zero_modes`.
    """

    model: str
    speed: float  # forward speed v [m/s] of the operating point
    hinge: str | None  # "free", "locked" or None (no rider hinge)
    states: list[str]
    inputs: list[str]
    A: np.ndarray
    B: np.ndarray
    path: list[str]
    path_A: np.ndarray
    path_B: np.ndarray
    zero_modes: dict[str, str]
    method: str

    @property
    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues [1/s] of the lateral dynamics, sorted by real, then imaginary part."""
        ev = np.linalg.eigvals(self.A)
        return ev[np.lexsort((ev.imag, ev.real))]

    def all_eigenvalues(self) -> np.ndarray:
        """Eigenvalues of the whole (locked) model: the lateral ones and the exact zeros."""
        return np.concatenate([self.eigenvalues, np.zeros(len(self.zero_modes), complex)])

    def to_statespace(self):
        """python-control StateSpace of the lateral dynamics plus the path (``states + path``),
        every state an output."""
        import control

        n = len(self.states)
        A = np.zeros((n + len(self.path),) * 2)
        A[:n, :n] = self.A
        A[n:] = self.path_A
        B = np.vstack([self.B, self.path_B])
        names = self.states + self.path
        return control.ss(A, B, np.eye(len(names)), np.zeros((len(names), len(self.inputs))), states=names,
                          inputs=self.inputs, outputs=names, name=self.model.replace(".", "_"))

    def to_dict(self) -> dict:
        return {
            "operating_point": f"upright straight running at forward speed v = {self.speed:.15g} m/s",
            "speed": self.speed, "hinge": self.hinge, "states": self.states, "inputs": self.inputs,
            "A": self.A.tolist(), "B": self.B.tolist(),
            "eigenvalues": [[float(e.real), float(e.imag)] for e in self.eigenvalues],
            "path": {"states": self.path, "A": self.path_A.tolist(), "B": self.path_B.tolist()},
            "zero_eigenvalues": [{"state": k, "reason": r} for k, r in self.zero_modes.items()],
            "method": self.method,
        }


def _eliminate(A, B, names, gone: str, coefficients: dict[str, float]):
    """Substitute ``gone = sum coefficients[n] * n`` and drop the state ``gone``."""
    k = names.index(gone)
    A = A.copy()
    for name, a in coefficients.items():
        A[:, names.index(name)] += A[:, k] * a
    keep = [j for j in range(len(names)) if j != k]
    return A[np.ix_(keep, keep)], B[keep], [names[j] for j in keep]


def steady_motion(lin: Linearization, lock_hinge: bool = False) -> SteadyMotion:
    """Reduce a nonlinear bicycle's linearization about upright straight running exactly.

    Works on the named quantities (states or outputs aliasing them, :func:`in_coordinates`):

    1. ``lock_hinge`` (models with the rider hinge ``beta``): the hinge is held at ``beta = 0``
       by its reaction torque, which acts exactly like the lean torque ``T_beta`` (a torque
       about the hinge axis between rear frame and upper body). Its value is the one that keeps
       ``beta'' = 0``: ``lambda = -(r A x + r B u) / (r b)`` with ``r`` the row of ``beta'`` and
       ``b`` the column of ``T_beta``; the state is then restricted to ``beta = 0``,
       ``r x = 0``. This is the linearization of the locked bicycle (the Lagrange multiplier
       of the constraint, no stiffness), independent of the hinge's ``kU``, ``cU``; exact up to
       rounding because the hinge torque is zero at the symmetric operating point.
    2. The pitch ``theta`` is eliminated with the holonomic constraint: its rate row is a
       combination ``a`` of the rows of roll and steer (``theta' = a . q'``), found by least
       squares and checked; ``theta - a . q`` is constant, an exact zero eigenvalue.
    3. ``x``, ``y``, ``psi``, ``thetaR``, ``thetaF`` do not feed back (their columns vanish in
       the other rows, their own block is nilpotent) and the forward speed ``u_R`` has a zero row
       (conserved): exact zeros. ``psi`` and ``y`` are kept as the path.

    Raises
    ------
    NotSteadyMotion
        The operating point is not upright straight running (lateral states or their rates not
        zero) or the linearization lacks the structure above (naming what fails).
    ValueError
        The FMU lacks the bicycle's quantities.
    """
    free_hinge = all(n in lin.states or n in lin.outputs for n in HINGE[:2]) and HINGE[2] in lin.inputs
    if lock_hinge and not free_hinge:
        raise NotSteadyMotion(f"{lin.model} has no rider hinge ({HINGE[0]}, {HINGE[1]}, input {HINGE[2]}) to lock")
    conf = list(LATERAL_COORDINATES) + ([HINGE[0]] if free_hinge else [])
    rates = list(LATERAL_SPEEDS) + ([HINGE[1]] if free_hinge else [])
    names = [*IGNORABLE, PITCH, *conf, *rates, FORWARD_SPEED]
    A, B, z0, zdot0 = in_coordinates(lin, names)
    inputs = list(lin.inputs)
    scale = max(1.0, float(np.abs(np.hstack([A, B])).max(initial=0.0)))
    tol = STRUCTURE_TOL * scale
    ix = {n: k for k, n in enumerate(names)}
    lateral = conf + rates
    off = {n: z0[ix[n]] for n in lateral if not abs(z0[ix[n]]) <= tol}
    off.update({f"d{n}/dt": zdot0[ix[n]] for n in lateral + [FORWARD_SPEED] if not abs(zdot0[ix[n]]) <= tol})
    if off:
        raise NotSteadyMotion(f"{lin.model}: the operating point is not upright straight running ("
                              + ", ".join(f"{k} = {v:.3g}" for k, v in off.items())
                              + "); linearize with zero roll, steer and rates and zero inputs")
    speed = float(zdot0[ix["x"]] * np.cos(z0[ix["psi"]]) + zdot0[ix["y"]] * np.sin(z0[ix["psi"]]))
    hinge = None
    if free_hinge:
        hinge = "free"
    if lock_hinge:
        beta, u_beta, torque = HINGE
        j = inputs.index(torque)
        b, r = B[:, j], A[ix[beta]]
        gain = float(r @ b)
        if not abs(gain) > tol:
            raise NotSteadyMotion(f"{lin.model}: the lean torque {torque} does not reach the hinge acceleration; "
                                  "the hinge cannot be locked by it")
        others = [k for k in range(len(inputs)) if k != j]
        A = A - np.outer(b, r @ A) / gain
        B = B[:, others] - np.outer(b, r @ B[:, others]) / gain
        inputs = [inputs[k] for k in others]
        # restrict to beta = 0 and r x = 0 (solved for the state with the largest coefficient in r)
        A, B, names = _eliminate(A, B, names, beta, {})
        r = np.delete(r, ix[beta])
        k = int(np.argmax(np.abs(r)))
        solved = names[k]
        A, B, names = _eliminate(A, B, names, solved, {n: -r[i] / r[k] for i, n in enumerate(names) if i != k})
        conf.remove(beta)
        rates = [n for n in rates if n != solved] if solved in rates else rates
        if solved != u_beta:
            raise NotSteadyMotion(f"{lin.model}: the hinge rate is not {u_beta} ({beta}' depends most on {solved})")
        hinge = "locked"
        lateral = conf + rates
        ix = {n: k for k, n in enumerate(names)}
    # the pitch: theta' = a . q' for the configuration coordinates q (holonomic constraint)
    M = np.hstack([A, B])
    Q = M[[ix[n] for n in conf]]
    t = M[ix[PITCH]]
    a = np.linalg.lstsq(Q.T, t, rcond=None)[0]
    residual = float(np.abs(Q.T @ a - t).max(initial=0.0))
    if not residual <= tol:
        raise NotSteadyMotion(f"{lin.model}: the pitch rate is not a combination of the roll and steer rates "
                              f"(residual {residual:.3g}); no holonomic constraint fixes {PITCH}")
    A, B, names = _eliminate(A, B, names, PITCH, dict(zip(conf, a)))
    ix = {n: k for k, n in enumerate(names)}
    rest = [n for n in names if n not in IGNORABLE]
    ign = [ix[n] for n in IGNORABLE]
    feed = np.abs(A[np.ix_([ix[n] for n in rest], ign)]).max(initial=0.0)
    block = np.linalg.matrix_power(A[np.ix_(ign, ign)], len(ign))
    if not (feed <= tol and np.abs(block).max(initial=0.0) <= tol * scale ** (len(ign) - 1)):
        raise NotSteadyMotion(f"{lin.model}: the coordinates {', '.join(IGNORABLE)} are not ignorable at this "
                              f"operating point (they feed back into the lateral dynamics)")
    row = np.abs(np.hstack([A[ix[FORWARD_SPEED], [ix[n] for n in rest]], B[ix[FORWARD_SPEED]]])).max(initial=0.0)
    if not row <= tol:
        raise NotSteadyMotion(f"{lin.model}: the forward speed {FORWARD_SPEED} is not conserved at first order "
                              f"(largest coupling {row:.3g})")
    lat = [ix[n] for n in lateral]
    path = [ix[n] for n in PATH]
    return SteadyMotion(lin.model, speed, hinge, lateral, inputs, A[np.ix_(lat, lat)], B[lat], list(PATH),
                        A[np.ix_(path, lat + path)], B[path], {n: ZERO_MODES[n] for n in [PITCH, FORWARD_SPEED,
                                                                                        *IGNORABLE]},
                        lin.method + ("; hinge locked by its reaction torque" if hinge == "locked" else ""))
