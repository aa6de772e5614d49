"""Linearize an FMU about its initial point: A, B, C, D from directional derivatives.

FMI 2.0 and 3.0 FMUs with Model Exchange. ``fmi2GetDirectionalDerivative`` /
``fmi3GetDirectionalDerivative`` give exact Jacobians for FMUs built here; for foreign FMUs
without them, central finite differences are used. Where an FMI 3 FMU also provides
``fmi3GetAdjointDerivative``, the whole Jacobian is computed a second time from it (one adjoint
seed per unknown: ``(J^T v)^T u = v^T (J u)`` for unit vectors ``u``, ``v``, entry by entry) and a
disagreement beyond :data:`ADJOINT_TOLERANCE` is refused with the entry named.

For the nonlinear bicycles (``Bicycle.Bicycles.Whipple``, ``WhippleRider``) :func:`steady_motion`
reduces the linearization about upright straight running exactly to its lateral dynamics (see
there): the ignorable coordinates, the pitch (fixed by the holonomic constraint) and the
conserved forward speed each contribute an exact zero eigenvalue, which are named; the hinge of
the rider can be locked exactly by its reaction torque.
"""
from __future__ import annotations

from ctypes import c_double
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import FMUError, ParameterError, SimulationError
from cosim.fmu.isolation import DEFAULT_TIMEOUT, built_here, can_isolate, run_isolated
from cosim.fmu.access import (ALL_FMI_VERSIONS, FMU, get_continuous_states, get_state_derivatives, lenient_reading,
                              read_fmu, set_continuous_states)

FD_STEP = 1e-6  # relative step of the central differences
#: Largest difference between the Jacobian from directional and the one from adjoint derivatives,
#: relative to the largest entry (at least 1): the two are exact derivatives of the same function,
#: so they differ by rounding only (CasADi's forward and reverse modes sum in other orders).
ADJOINT_TOLERANCE = 1e-12


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
    #: Largest difference between the directional and the adjoint Jacobian relative to the largest
    #: entry (at least 1); None where the FMU has no adjoint derivatives (FMI 2, most foreign FMUs).
    adjoint_difference: float | None = None

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
            "method": self.method, "adjoint_difference": self.adjoint_difference,
        }


class _Point:
    """An ME instance held at (t, x, u) that evaluates derivatives and outputs."""

    def __init__(self, fmu: FMU, parameters: dict):
        self.fmu = fmu
        self.me = fmu.instantiate("me")
        self.status = 0  # worst FMI status seen (decides the clean-up, see close)
        self.nx = fmu.n_states
        try:
            fmu.set(self.me, parameters)
            fmu.initialize_me(self.me, start_time=0.0)
            self.x0 = self.get_states()  # refused by an FMU whose binary has another number of states
        except (FMICallException, FMUError) as exc:  # the FMU refused the parameters or the initialization
            self.fail(exc)
            self.close()
            raise SimulationError(f"{fmu.path}: initialization failed: {self.said(exc)}") from None

    def fail(self, exc: Exception) -> None:
        self.status = max(self.status, int(getattr(exc, "status", 3) or 3))

    def said(self, exc: Exception) -> str:
        """What the FMU logged about a failed call, else the call's exception text."""
        return self.me.log.last_error() or str(exc)

    def get_states(self) -> np.ndarray:
        return get_continuous_states(self.me, self.nx)

    def set_states(self, x) -> None:
        set_continuous_states(self.me, x)

    def get_reals(self, vrs, n: int | None = None) -> np.ndarray:
        """Real (FMI 3: Float64) values by value reference; ``n`` values in all (FMI 3 arrays: more
        than one per value reference; default one each)."""
        if not vrs:
            return np.zeros(0)
        return np.array(self.me.getFloat64(vrs, n) if self.fmu.is_fmi3 else self.me.getReal(vrs))

    def set_reals(self, names, vrs, values) -> None:
        """Set real inputs: FMI 3 one fmi3SetFloat64 of every value (arrays included), FMI 2 by name."""
        if self.fmu.is_fmi3:
            if vrs:
                self.me.setFloat64(vrs, [float(v) for v in values])
        else:
            self.fmu.set(self.me, dict(zip(names, values)))

    def close(self):
        """Terminate where FMI allows it (not after Error), then free the instance (FMI 2 and 3)."""
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
              method: str = "auto", isolate: bool | None = None, timeout: float | None = DEFAULT_TIMEOUT,
              lenient: bool = False
              ) -> Linearization:
    """Linearize an FMU at its initial state (after initialization) and the given inputs.

    Parameters
    ----------
    fmu_path : path
        FMI 2.0 or 3.0 FMU with Model Exchange.
    parameters : dict, optional
        Start values of parameters (name -> value), in the SI units the FMU declares
        (e.g. ``V`` [m/s], ``m`` [kg]).
    inputs : dict, optional
        Operating-point input values in SI units (e.g. ``T`` [N m]; default: the inputs' start
        values).
    method : {'auto', 'directional', 'finite-differences'}
        'auto' uses directional derivatives where the FMU provides them.
    isolate : bool, optional
        Call the FMU's binary in a guarded child process (:mod:`cosim.fmu.isolation`): a crash,
        ``exit`` or hang of the binary becomes an error instead of ending this process. Default:
        for every FMU not built by this project.
    timeout : float or None
        With ``isolate``: longest time [s] the linearization may take; None: no limit.
    lenient : bool
        Open the FMU even if its model description fails FMPy's checks, each finding a warning
        (see :func:`cosim.fmu.access.read_fmu`).

    Returns
    -------
    Linearization
        Matrices with states ordered as the FMU's ModelStructure/Derivatives, inputs and outputs
        (those of type Real, FMI 3 Float64: :data:`REAL_TYPES`) in modelDescription order; the operating point's states ``x0`` and derivatives ``xdot0``;
        ``adjoint_difference`` where the FMU has adjoint derivatives (see the module docstring).

    Raises
    ------
    FMUError
        The FMU cannot be opened, has no Model Exchange, or (``method='directional'``) no
        directional derivatives.
    SimulationError
        The FMU refuses the initialization or a call at the operating point, its directional and
        adjoint derivatives disagree (the entry named), an entry of A, B, C or D is not finite, or
        (isolated) the FMU's process ended abnormally or stopped answering.

    See Also
    --------
    steady_motion : the exact lateral dynamics of a nonlinear bicycle about upright straight running.
    """
    with lenient_reading(lenient):
        read_fmu(fmu_path, ALL_FMI_VERSIONS)  # here, not in the worker: refused or warned once, in this process
        if isolate is None:
            isolate = can_isolate() and not built_here(fmu_path)
        if isolate:
            return run_isolated(lambda worker: _linearize(fmu_path, parameters, inputs, method, worker.doing),
                                what=str(fmu_path), timeout=timeout)
        return _linearize(fmu_path, parameters, inputs, method)


def _linearize(fmu_path, parameters, inputs, method, doing=lambda text: None) -> Linearization:
    """:func:`linearize` in this process; ``doing`` is told each phase (for the isolated worker)."""
    parameters = dict(parameters or {})
    with FMU(fmu_path, versions=ALL_FMI_VERSIONS) as fmu:
        md = fmu.description
        if md.modelExchange is None:
            raise FMUError(f"{fmu_path}: linearization needs Model Exchange, which the FMU does not offer")
        if method not in ("auto", "directional", "finite-differences"):
            raise ParameterError(f"method must be 'auto', 'directional' or 'finite-differences', got '{method}'")
        provided = md.modelExchange.providesDirectionalDerivative
        if method == "directional" and not provided:
            raise FMUError(f"{fmu_path}: the FMU does not provide directional derivatives; use central finite "
                           "differences (method 'auto' or 'finite-differences')")
        use_dd = method == "directional" or (method == "auto" and provided)
        structure = _Structure.of(fmu)
        prefix = fmu.fmi_version[:1]
        doing(f"fmi{prefix}Instantiate and the initialization")
        point = _Point(fmu, {**parameters, **(inputs or {})})
        try:
            doing("the Jacobians (" + ("directional derivatives" if use_dd else "finite differences of "
                                       f"fmi{prefix}GetDerivatives") + ")")
            return _finite_matrices(fmu_path, _jacobians(fmu, md, point, use_dd, parameters, structure))
        except FMICallException as exc:  # an FMI call refused at the operating point
            point.fail(exc)
            raise SimulationError(f"{fmu_path}: linearization failed: {point.said(exc)}") from None
        finally:
            point.close()


def _finite_matrices(fmu_path, lin: Linearization) -> Linearization:
    """``lin`` if A, B, C and D are finite, else the first non-finite entry named."""
    rows = {"A": lin.states, "B": lin.states, "C": lin.outputs, "D": lin.outputs}
    columns = {"A": lin.states, "B": lin.inputs, "C": lin.states, "D": lin.inputs}
    for name in "ABCD":
        matrix = np.asarray(getattr(lin, name), float)
        bad = np.argwhere(~np.isfinite(matrix))
        if len(bad):
            i, j = bad[0]
            raise SimulationError(f"{fmu_path}: linearization failed: {name}[{i}, {j}] (d {rows[name][i]} / "
                                  f"d {columns[name][j]}) is {matrix[i, j]} at the operating point")
    return lin


#: The variable types that are linearized (FMI 2 ``Real``, FMI 3 ``Float64``); inputs and outputs
#: of other types (integers, Booleans, strings, FMI 3 ``Float32``) or with discrete variability
#: (changed in Event Mode only, so they have no derivative in Continuous-Time Mode) are left out
#: of B, C, D.
REAL_TYPES = ("Real", "Float64")


def real_names(fmu: FMU, causality: str) -> list[str]:
    """Names of the continuous variables of ``causality`` with a type of :data:`REAL_TYPES`, in
    modelDescription order."""
    return [n for n in fmu.names(causality)
            if fmu.variables[n].type in REAL_TYPES and fmu.variables[n].variability in (None, "continuous")]


@dataclass
class _Structure:
    """What is differentiated, value by value (an FMI 3 array ``x`` has the values ``x[1]``,
    ``x[2]``, ... at one value reference): the unknowns are the state derivatives and the outputs
    that are not states, the knowns the states and the inputs."""

    states: list[str]  # names of the state values, in the FMU's order
    inputs: list[str]
    outputs: list[str]
    unknowns: list[str]  # derivative values, then the values of the computed outputs
    knowns: list[str]  # state values, then input values
    unknown_vrs: list[int]  # one per variable (an array once)
    known_vrs: list[int]
    input_names: list[str]  # variables
    input_vrs: list[int]
    state_index: dict[str, int]  # state value name -> column
    computed: list[str]  # values of the outputs that are not states

    @classmethod
    def of(cls, fmu: FMU) -> "_Structure":
        states, derivatives = fmu.states, fmu.derivatives
        input_names, output_names = real_names(fmu, "input"), real_names(fmu, "output")
        # Outputs that are states have an identity row; the others are unknowns to differentiate.
        computed = [n for n in output_names if n not in set(states)]
        x = fmu.elements(states)
        return cls(x, fmu.elements(input_names), fmu.elements(output_names),
                   fmu.elements(derivatives) + fmu.elements(computed), x + fmu.elements(input_names),
                   [fmu.vr[n] for n in derivatives + computed], [fmu.vr[n] for n in states + input_names],
                   input_names, [fmu.vr[n] for n in input_names], {n: k for k, n in enumerate(x)},
                   fmu.elements(computed))

    def output_matrices(self, J: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """C and D from the Jacobian ``J`` (unknowns x knowns, or a stack of them)."""
        nx, nu, stack = len(self.states), len(self.inputs), J.shape[:-2]
        C, D = np.zeros((*stack, len(self.outputs), nx)), np.zeros((*stack, len(self.outputs), nu))
        for row, name in enumerate(self.outputs):
            if name in self.state_index:
                C[..., row, self.state_index[name]] = 1.0
            else:
                k = nx + self.computed.index(name)
                C[..., row, :], D[..., row, :] = J[..., k, :nx], J[..., k, nx:]
        return C, D


def _jacobians(fmu, md, point, use_dd, parameters, st: _Structure):
    """The matrices at the point (see :func:`linearize`)."""
    x0 = point.x0
    nx, nu, n_unknown = len(st.states), len(st.inputs), len(st.unknowns)
    u0 = point.get_reals(st.input_vrs, nu)
    J = np.zeros((n_unknown, nx + nu))
    adjoint = None
    if use_dd:
        # FMI 3 sizes the sensitivity by values (arrays); FMPy's FMI 2 wrapper has no such argument
        size = {"nSensitivity": n_unknown} if fmu.is_fmi3 else {}
        for k in range(nx + nu):
            seed = [0.0] * (nx + nu)
            seed[k] = 1.0
            J[:, k] = point.me.getDirectionalDerivative(st.unknown_vrs, st.known_vrs, seed, **size)
        if fmu.provides_adjoint_derivatives("me") and st.unknowns and st.knowns:
            rows = adjoint_jacobian(point.me, st.unknown_vrs, st.known_vrs, n_unknown, nx + nu)
            adjoint = check_adjoint(fmu, J, rows, st.unknowns, st.knowns)
    else:
        def evaluate(x, u):
            point.set_states(x)
            point.set_reals(st.input_names, st.input_vrs, u)
            return point.get_reals(st.unknown_vrs, n_unknown)

        for k in range(nx + nu):
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
    C, D = st.output_matrices(J)
    point.set_states(x0)
    xdot0 = get_state_derivatives(point.me, nx)
    method = "directional derivatives" if use_dd else "central finite differences"
    if adjoint is not None:
        method += f" (adjoint derivatives agree to {adjoint:.1e})"
    return Linearization(md.modelName, parameters, st.states, st.inputs, st.outputs, A, B, C, D,
                         method, x0.copy(), xdot0, adjoint)


def adjoint_jacobian(instance, unknown_vrs, known_vrs, n_unknown: int | None = None,
                     n_known: int | None = None) -> np.ndarray:
    """The Jacobian d(unknowns)/d(knowns) row by row from ``fmi3GetAdjointDerivative``: the seed
    ``e_i`` (one per unknown value) gives ``J^T e_i``, the row ``i``. ``n_unknown``, ``n_known``:
    the numbers of values (default: one per value reference; FMI 3 arrays have more)."""
    n_unknown = len(unknown_vrs) if n_unknown is None else n_unknown
    n_known = len(known_vrs) if n_known is None else n_known
    rows = np.zeros((n_unknown, n_known))
    for i in range(n_unknown):
        seed = [0.0] * n_unknown
        seed[i] = 1.0
        # FMPy sizes the sensitivity by the unknowns unless told: the adjoint one has one per known
        rows[i] = instance.getAdjointDerivative(unknown_vrs, known_vrs, seed, nSensitivity=n_known)
    return rows


def check_adjoint(fmu, J: np.ndarray, J_adjoint: np.ndarray, unknowns, knowns, where: str = "") -> float:
    """The largest difference of the two Jacobians relative to the largest entry (at least 1);
    :class:`SimulationError` naming the worst entry if it exceeds :data:`ADJOINT_TOLERANCE`."""
    scale = max(1.0, float(np.max(np.abs(J))) if J.size else 1.0)
    difference = np.abs(J - J_adjoint) / scale
    worst = float(np.max(difference)) if difference.size else 0.0
    if not worst <= ADJOINT_TOLERANCE:  # NaN fails too
        i, k = np.unravel_index(np.nanargmax(difference) if np.isfinite(difference).any() else 0, J.shape)
        raise SimulationError(
            f"{fmu.path}: the FMU's directional and adjoint derivatives disagree{where}: "
            f"d {unknowns[i]} / d {knowns[k]} = {J[i, k]:.17g} (fmi3GetDirectionalDerivative) but "
            f"{J_adjoint[i, k]:.17g} (fmi3GetAdjointDerivative); relative difference {worst:.2e} > "
            f"{ADJOINT_TOLERANCE:g} (one of them is wrong: the linearization is not trusted)")
    return worst


# --------------------------------------------------------------------------- steady motion

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


def further_coordinates(states) -> list[tuple[str, str]]:
    """The coordinates a nonlinear bicycle has beyond its own, with their rates: every state ``q``
    that is not one of the bicycle's and whose rate ``u_q`` is a state too (the rider's lean
    ``beta, u_beta``, a twist ``twist, u_twist``, ...). They join the lateral coordinates."""
    known = names_of_bicycle()
    return [(q, f"u_{q}") for q in states if q not in known and not q.startswith("u_") and f"u_{q}" in states]


def is_bicycle(lin: Linearization) -> bool:
    """Whether the FMU has the quantities of the nonlinear bicycles (:data:`IGNORABLE` etc.) as
    states or outputs, so that :func:`steady_motion` applies."""
    return names_of_bicycle() <= set(lin.states) | set(lin.outputs)


def names_of_bicycle() -> set[str]:
    """The states or outputs a nonlinear bicycle has (see :func:`is_bicycle`)."""
    return {*IGNORABLE, PITCH, FORWARD_SPEED, *LATERAL_COORDINATES, *LATERAL_SPEEDS}


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


def _eliminate(A, B, names, gone: str, coefficients: dict):
    """Substitute ``gone = sum coefficients[n] * n`` and drop the state ``gone``, on stacks
    ``A`` (N, n, n), ``B`` (N, n, m) with one coefficient per matrix (arrays of shape (N,))."""
    k = names.index(gone)
    A = A.copy()
    for name, a in coefficients.items():
        A[..., names.index(name)] += A[..., k] * np.asarray(a, float).reshape(-1, 1)
    keep = [j for j in range(len(names)) if j != k]
    return A[:, keep][:, :, keep], B[:, keep], [names[j] for j in keep]


def steady_motion(lin: Linearization, lock_hinge: bool = False) -> SteadyMotion:
    """Reduce a nonlinear bicycle's linearization about upright straight running exactly.

    Works on the named quantities (states or outputs aliasing them, :func:`_coordinates`):

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
    (result,) = _steady_motions(lin.model, lin.states, lin.inputs, lin.outputs, lin.C, lin.D, lin.A[None],
                                lin.B[None], _point(lin.x0, len(lin.states))[None],
                                _point(lin.xdot0, len(lin.states))[None], lin.method, lock_hinge)
    if isinstance(result, NotSteadyMotion):
        raise result
    return result


def _point(x, n: int) -> np.ndarray:
    """An operating-point vector, NaN where it is unknown (a Linearization built by hand)."""
    return np.full(n, np.nan) if x is None else np.asarray(x, float)


def _coordinates(model: str, states, outputs, C, D, names) -> np.ndarray:
    """The matrix ``T`` of the coordinates ``z = T x`` named by ``names``: each name is a state or
    an output that is a linear function of the states only (a row of ``C`` with a zero row of
    ``D``), so state names of the implementation do not matter. For aliases of the states ``T`` is
    a permutation.

    Raises
    ------
    ValueError
        A name that is neither, an output that depends on the inputs, or names that are not
        coordinates of the whole state (wrong number, linearly dependent).
    """
    index = {n: k for k, n in enumerate(states)}
    rows = []
    for name in names:
        if name in index:
            row = np.zeros(len(states))
            row[index[name]] = 1.0
        elif name in outputs:
            k = outputs.index(name)
            if np.any(D[k] != 0.0):
                raise ValueError(f"{model}: output {name} depends on the inputs; it is not a state coordinate")
            row = C[k]
        else:
            raise ValueError(f"{model}: no state or output named {name}")
        rows.append(row)
    T = np.array(rows, float).reshape(len(rows), len(states))
    if T.shape[0] != T.shape[1] or np.linalg.matrix_rank(T) < T.shape[0]:
        raise ValueError(f"{model}: {', '.join(names)} are not coordinates of its {len(states)} states "
                         f"({', '.join(states)})")
    return T


def _steady_motions(model, states, inputs, outputs, C, D, A, B, x0, xdot0, method, lock_hinge=False):
    """:func:`steady_motion` of N linearizations of one model at once (stacks ``A`` (N, nx, nx),
    ``B`` (N, nx, nu), ``x0``, ``xdot0`` (N, nx); ``C``, ``D`` the same for all, as the outputs
    that alias states do not depend on the operating point): one vectorized pass, the same
    arithmetic for one and for many. Returns per linearization a :class:`SteadyMotion` or the
    :class:`NotSteadyMotion` that refuses it; raises what applies to all (no hinge to lock,
    ValueError for a model without the bicycle's quantities)."""
    n_points = A.shape[0]
    free_hinge = all(n in states or n in outputs for n in HINGE[:2]) and HINGE[2] in inputs
    if lock_hinge and not free_hinge:
        raise NotSteadyMotion(f"{model} has no rider hinge ({HINGE[0]}, {HINGE[1]}, input {HINGE[2]}) to lock")
    further = further_coordinates(states)
    if free_hinge and (HINGE[0], HINGE[1]) not in further:  # the hinge's quantities as outputs only
        further.insert(0, (HINGE[0], HINGE[1]))
    conf = list(LATERAL_COORDINATES) + [q for q, _ in further]
    rates = list(LATERAL_SPEEDS) + [u for _, u in further]
    names = [*IGNORABLE, PITCH, *conf, *rates, FORWARD_SPEED]
    T = _coordinates(model, states, outputs, C, D, names)
    A = np.swapaxes(np.linalg.solve(T.T, np.swapaxes(T @ A, 1, 2)), 1, 2)  # T A T^-1
    B = T @ B
    z0, zdot0 = x0 @ T.T, xdot0 @ T.T
    inputs = list(inputs)
    scale = np.maximum(1.0, np.abs(np.concatenate([A, B], axis=2)).max(axis=(1, 2), initial=0.0))
    tol = STRUCTURE_TOL * scale
    refused: dict[int, NotSteadyMotion] = {}  # the first reason per operating point

    def refuse(bad, message) -> None:
        for k in np.flatnonzero(bad):
            refused.setdefault(int(k), NotSteadyMotion(message(int(k))))

    ix = {n: k for k, n in enumerate(names)}
    lateral = conf + rates
    off = [(n, z0[:, ix[n]]) for n in lateral] + [(f"d{n}/dt", zdot0[:, ix[n]]) for n in lateral + [FORWARD_SPEED]]
    bad_point = np.zeros(n_points, bool)
    for _, values in off:
        bad_point |= ~(np.abs(values) <= tol)
    refuse(bad_point, lambda k: (f"{model}: the operating point is not upright straight running ("
                                 + ", ".join(f"{n} = {v[k]:.3g}" for n, v in off if not abs(v[k]) <= tol[k])
                                 + "); linearize with zero roll, steer and rates and zero inputs"))
    speed = zdot0[:, ix["x"]] * np.cos(z0[:, ix["psi"]]) + zdot0[:, ix["y"]] * np.sin(z0[:, ix["psi"]])
    hinge = "free" if free_hinge else None
    if lock_hinge:
        beta, u_beta, torque = HINGE
        j = inputs.index(torque)
        b, r = B[:, :, j], A[:, ix[beta]]
        gain = np.einsum("ki,ki->k", r, b)
        refuse(~(np.abs(gain) > tol), lambda k: f"{model}: the lean torque {torque} does not reach the hinge "
                                                "acceleration; the hinge cannot be locked by it")
        gain = np.where(np.abs(gain) > tol, gain, 1.0)  # refused points: any finite value
        others = [k for k in range(len(inputs)) if k != j]
        A = A - b[:, :, None] * (r[:, None, :] @ A) / gain[:, None, None]
        B = B[:, :, others] - b[:, :, None] * (r[:, None, :] @ B[:, :, others]) / gain[:, None, None]
        inputs = [inputs[k] for k in others]
        # restrict to beta = 0 and r x = 0 (solved for the state with the largest coefficient in r,
        # which must be the hinge rate)
        A, B, names = _eliminate(A, B, names, beta, {})
        r = np.delete(r, ix[beta], axis=1)
        largest = np.argmax(np.abs(r), axis=1)
        k_rate = names.index(u_beta)
        refuse(largest != k_rate, lambda k: f"{model}: the hinge rate is not {u_beta} ({beta}' depends most on "
                                            f"{names[largest[k]]})")
        pivot = np.where(r[:, k_rate] != 0.0, r[:, k_rate], 1.0)
        A, B, names = _eliminate(A, B, names, u_beta, {n: -r[:, i] / pivot for i, n in enumerate(names)
                                                       if i != k_rate})
        conf.remove(beta)
        rates.remove(u_beta)
        hinge = "locked"
        lateral = conf + rates
        ix = {n: k for k, n in enumerate(names)}
    # the pitch: theta' = a . q' for the configuration coordinates q (holonomic constraint)
    M = np.concatenate([A, B], axis=2)
    Q = M[:, [ix[n] for n in conf]]  # (N, len(conf), columns)
    t = M[:, ix[PITCH]]
    a = np.einsum("kij,kj->ki", np.linalg.pinv(np.swapaxes(Q, 1, 2)), t)  # least squares
    residual = np.abs(np.einsum("kij,ki->kj", Q, a) - t).max(axis=1, initial=0.0)
    refuse(~(residual <= tol), lambda k: f"{model}: the pitch rate is not a combination of the roll and steer "
                                         f"rates (residual {residual[k]:.3g}); no holonomic constraint fixes {PITCH}")
    A, B, names = _eliminate(A, B, names, PITCH, {n: a[:, i] for i, n in enumerate(conf)})
    ix = {n: k for k, n in enumerate(names)}
    rest = [ix[n] for n in names if n not in IGNORABLE]
    ign = [ix[n] for n in IGNORABLE]
    feed = np.abs(A[:, rest][:, :, ign]).max(axis=(1, 2), initial=0.0)
    block = np.abs(np.linalg.matrix_power(A[:, ign][:, :, ign], len(ign))).max(axis=(1, 2), initial=0.0)
    refuse(~((feed <= tol) & (block <= tol * scale ** (len(ign) - 1))),
           lambda k: f"{model}: the coordinates {', '.join(IGNORABLE)} are not ignorable at this operating point "
                     "(they feed back into the lateral dynamics)")
    u_R = ix[FORWARD_SPEED]
    row = np.abs(np.concatenate([A[:, u_R, rest], B[:, u_R]], axis=1)).max(axis=1, initial=0.0)
    refuse(~(row <= tol), lambda k: f"{model}: the forward speed {FORWARD_SPEED} is not conserved at first order "
                                    f"(largest coupling {row[k]:.3g})")
    lat = [ix[n] for n in lateral]
    path = [ix[n] for n in PATH]
    zero_modes = {n: ZERO_MODES[n] for n in [PITCH, FORWARD_SPEED, *IGNORABLE]}
    method = method + ("; hinge locked by its reaction torque" if hinge == "locked" else "")
    lateral_A, lateral_B = A[:, lat][:, :, lat], B[:, lat]
    path_A, path_B = A[:, path][:, :, lat + path], B[:, path]
    return [refused[k] if k in refused else
            SteadyMotion(model, float(speed[k]), hinge, list(lateral), inputs, lateral_A[k], lateral_B[k], list(PATH),
                         path_A[k], path_B[k], dict(zero_modes), method)
            for k in range(n_points)]


# --------------------------------------------------------------------------- speed sweeps

#: Most speeds one sweep (``cosim linearize --speeds``, ``cosim compare --speeds``) takes.
MAX_SPEEDS = 10_000
#: Largest forward speed [m/s] in magnitude that --speed/--speeds accept (beyond it the squares of
#: the speed in the equations of motion lose every digit of the other terms, then overflow).
MAX_SPEED = 1e4


def parse_speeds(text: str, option: str = "--speeds") -> list[float]:
    """``A:B:STEP`` (B included, as far as it is reached by whole steps) or ``V1,V2,...`` [m/s].

    The grammar of ``--speeds`` for ``cosim linearize`` and ``cosim compare`` (here, not beside
    the comparison, which imports SciPy: ``cosim linearize`` stays light).

    Raises
    ------
    ParameterError
        Malformed text, non-finite values, ``STEP <= 0``, ``B < A``, an empty list or more
        than :data:`MAX_SPEEDS` speeds.
    """
    import math

    def numbers(parts):
        try:
            values = [float(v) for v in parts]
        except ValueError:
            raise ParameterError(f"{option} expects A:B:STEP or V1,V2,... [m/s], got '{text}'") from None
        if not all(math.isfinite(v) for v in values):
            raise ParameterError(f"{option} {text}: the speeds must be finite")
        if not all(abs(v) <= MAX_SPEED for v in values):
            raise ParameterError(f"{option} {text}: the speeds must be at most {MAX_SPEED:g} m/s in magnitude")
        return values

    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ParameterError(f"{option} expects A:B:STEP, got '{text}'")
        start, stop, step = numbers(parts)
        if step <= 0 or stop < start:
            raise ParameterError(f"{option} {text}: need STEP > 0 and B >= A")
        count = np.floor((stop - start) / step + 1e-9) + 1  # inf where B - A overflows
        if not count <= MAX_SPEEDS:
            raise ParameterError(f"{option} {text}: {count:.3g} speeds (at most {MAX_SPEEDS}); use a larger STEP")
        n = int(count)
        if n > MAX_SPEEDS:
            raise ParameterError(f"{option} {text}: {n} speeds (at most {MAX_SPEEDS}); use a larger STEP")
        return [round(start + k * step, 12) for k in range(n)]
    values = numbers(text.split(","))
    if len(values) > MAX_SPEEDS:
        raise ParameterError(f"{option}: {len(values)} speeds (at most {MAX_SPEEDS})")
    return values

@dataclass
class SpeedSweep:
    """Linearizations of one model at N forward speeds (:func:`linearize_speeds`).

    ``A`` (N, nx, nx), ``B`` (N, nx, nu), ``C`` (N, ny, nx), ``D`` (N, ny, nu), ``x0``, ``xdot0``
    (N, nx) in the state order of :class:`Linearization`; ``values`` the speed parameter's value
    per speed (``V``/``v`` [m/s] or ``u_R0`` [rad/s]). For the nonlinear bicycles ``steady``
    holds per speed the :class:`SteadyMotion` or the :class:`NotSteadyMotion` that refuses it
    (None for other models).
    """

    model: str
    parameters: dict
    speed_parameter: str
    speeds: np.ndarray
    values: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    x0: np.ndarray
    xdot0: np.ndarray
    method: str
    steady: list | None = None

    def __len__(self) -> int:
        return len(self.speeds)

    @property
    def eigenvalues(self) -> np.ndarray:
        """(N, nx) eigenvalues [1/s] of ``A`` per speed (one batched LAPACK call, each row the
        same numbers as :attr:`Linearization.eigenvalues`)."""
        n = len(self.states)
        return np.linalg.eigvals(self.A) if n else np.zeros((len(self), 0), complex)

    @property
    def lateral_eigenvalues(self) -> np.ndarray:
        """(N, n_lat) eigenvalues [1/s] of the lateral dynamics (sorted as
        :attr:`SteadyMotion.eigenvalues`), NaN rows where the reduction is refused; ValueError
        for a model that is not a nonlinear bicycle."""
        if self.steady is None:
            raise ValueError(f"{self.model} is not a nonlinear bicycle; it has no steady-motion reduction")
        good = [k for k, s in enumerate(self.steady) if isinstance(s, SteadyMotion)]
        n = len(self.steady[good[0]].states) if good else 0
        out = np.full((len(self), n), np.nan + 0j)
        if good:
            ev = np.linalg.eigvals(np.array([self.steady[k].A for k in good]))
            for row, k in zip(ev, good):
                out[k] = row[np.lexsort((row.imag, row.real))]
        return out

    def linearization(self, k: int) -> Linearization:
        """The :class:`Linearization` at ``speeds[k]``."""
        return Linearization(self.model, {**self.parameters, self.speed_parameter: float(self.values[k])},
                             list(self.states), list(self.inputs), list(self.outputs), self.A[k], self.B[k],
                             self.C[k], self.D[k], self.method, self.x0[k], self.xdot0[k])

    def to_dict(self, matrices: bool = False) -> dict:
        """JSON-ready: the common fields once, per speed the eigenvalues (and the lateral
        reduction of the nonlinear bicycles); ``matrices`` adds A, B, C, D per speed."""
        def pairs(ev):  # (N, n) complex -> per speed [[re, im], ...] (vectorized: 1000s of speeds)
            return np.stack([ev.real, ev.imag], axis=-1).tolist()

        full = pairs(self.eigenvalues)
        lateral = pairs(self.lateral_eigenvalues) if self.steady is not None else None
        points = []
        for k, v in enumerate(self.speeds):
            point = {"speed": float(v), self.speed_parameter: float(self.values[k]), "eigenvalues": full[k]}
            if matrices:
                point.update({name: getattr(self, name)[k].tolist() for name in "ABCD"})
            if self.steady is not None:
                s = self.steady[k]
                if isinstance(s, SteadyMotion):
                    point["steady_motion"] = {"A": s.A.tolist(), "B": s.B.tolist(), "eigenvalues": lateral[k],
                                              "path": {"A": s.path_A.tolist(), "B": s.path_B.tolist()}}
                else:
                    point["steady_motion"] = None
                    point["steady_motion_note"] = str(s)
            points.append(point)
        report = {"model": self.model, "parameters": self.parameters, "speed_parameter": self.speed_parameter,
                  "speeds": [float(v) for v in self.speeds], "states": self.states, "inputs": self.inputs,
                  "outputs": self.outputs, "method": self.method}
        good = [s for s in self.steady or [] if isinstance(s, SteadyMotion)]
        if good:
            s = good[0]
            report["steady_motion"] = {"hinge": s.hinge, "states": s.states, "inputs": s.inputs,
                                       "path": {"states": s.path},
                                       "zero_eigenvalues": [{"state": n, "reason": r} for n, r in s.zero_modes.items()],
                                       "method": s.method}
        report["points"] = points
        return report


class _FastPoint:
    """One ME instance re-initialized per operating point through the raw FMI functions.

    FMPy's wrappers convert and check every argument in Python on each call; here the C
    functions (argument types already declared by FMPy) are called with preallocated buffers,
    and ``fmi2Reset``/``fmi3Reset`` replaces a new instance (no library load, no FMPy set-up) per
    point. Each point is initialized from scratch exactly as :func:`linearize` does, so the
    results are the same numbers. FMI 3 takes the same path with the FMI 3 functions (the
    ``nValues``/``nSeed``/``nSensitivity`` arguments, the initial event iteration) and, where the
    FMU provides adjoint derivatives, checks the Jacobian against them at every point."""

    def __init__(self, fmu: FMU, fixed: dict, varying: str, st: _Structure):
        from ctypes import POINTER, c_uint

        self.fmu, self.me, self.varying = fmu, fmu.instantiate("me"), varying
        self.status = 0
        self.fmi3 = fmu.is_fmi3
        f = self.me._functions
        self.c = self.me.component
        fmi = "fmi3" if self.fmi3 else "fmi2"
        self._reset = f[f"{fmi}Reset"]
        self._set_real = f["fmi3SetFloat64" if self.fmi3 else "fmi2SetReal"]
        self._setup = None if self.fmi3 else f["fmi2SetupExperiment"]
        self._enter, self._exit = f[f"{fmi}EnterInitializationMode"], f[f"{fmi}ExitInitializationMode"]
        self._ct, self._get_x = f[f"{fmi}EnterContinuousTimeMode"], f[f"{fmi}GetContinuousStates"]
        self._get_dx = f["fmi3GetContinuousStateDerivatives" if self.fmi3 else "fmi2GetDerivatives"]
        self._dd = f[f"{fmi}GetDirectionalDerivative"]
        self._adjoint = f["fmi3GetAdjointDerivative"] if fmu.provides_adjoint_derivatives("me") else None
        self.unknowns, self.knowns = list(st.unknowns), list(st.knowns)
        self.adjoint_difference = 0.0 if self._adjoint is not None else None
        # Real parameters through one fmi2SetReal/fmi3SetFloat64; other types (rare) through the wrappers.
        real = "Float64" if self.fmi3 else "Real"
        reals = {n: float(v) for n, v in fixed.items() if fmu.variables[n].type == real}
        self.other = {n: v for n, v in fixed.items() if n not in reals}
        names = list(reals) + [varying]
        self.set_vr = (c_uint * len(names))(*[fmu.vr[n] for n in names])
        self.set_values = (c_double * len(names))(*reals.values(), 0.0)
        self.n_set = len(names)
        self.nx = len(st.states)
        self.x = (c_double * max(self.nx, 1))()
        self.dx = (c_double * max(self.nx, 1))()
        self.u_vr = (c_uint * len(st.unknown_vrs))(*st.unknown_vrs)
        self.k_vr = (c_uint * len(st.known_vrs))(*st.known_vrs)
        # numbers of values (seeds, sensitivities) and of value references (equal unless FMI 3 arrays)
        self.nu, self.nk = len(st.unknowns), len(st.knowns)
        self.n_uvr, self.n_kvr = len(st.unknown_vrs), len(st.known_vrs)
        self.seeds = np.eye(max(self.nk, 1))
        self.column = np.zeros(max(self.nu, 1))
        P = POINTER(c_double)
        self.seed_ptrs = [self.seeds[k].ctypes.data_as(P) for k in range(self.nk)]
        self.column_ptr = self.column.ctypes.data_as(P)
        if self._adjoint is not None:  # the rows of J from the adjoint seeds e_i, one per unknown
            self.adjoint_seeds = np.eye(max(self.nu, 1))
            self.adjoint_seed_ptrs = [self.adjoint_seeds[i].ctypes.data_as(P) for i in range(self.nu)]
            self.row = np.zeros(max(self.nk, 1))
            self.row_ptr = self.row.ctypes.data_as(P)

    def check(self, status: int, what: str, value: float) -> None:
        if status > 1:  # Discard, Error, Fatal (the same codes in FMI 2 and 3)
            self.status = max(self.status, status)
            said = self.me.log.last_error()
            raise SimulationError(f"{self.fmu.path}: {what} failed at {self.varying} = {value:.15g}"
                                  + (f": {said}" if said else f" (FMI status {status})"))

    def evaluate(self, value: float, J: np.ndarray, x0: np.ndarray, xdot0: np.ndarray) -> None:
        """Initialize with the speed parameter = ``value``; fill the Jacobian ``J`` (unknowns x
        knowns), the states ``x0`` and their derivatives ``xdot0``."""
        if self.fmi3:
            return self._evaluate_fmi3(value, J, x0, xdot0)
        c = self.c
        self.check(self._reset(c), "fmi2Reset", value)
        if self.other:
            self.fmu.set(self.me, self.other)
        self.set_values[self.n_set - 1] = value
        self.check(self._set_real(c, self.set_vr, self.n_set, self.set_values), "fmi2SetReal", value)
        self.check(self._setup(c, 0, 0.0, 0.0, 0, 0.0), "fmi2SetupExperiment", value)
        self.check(self._enter(c), "initialization", value)
        self.check(self._exit(c), "initialization", value)
        self._initial_event_iteration(value)
        self.check(self._ct(c), "fmi2EnterContinuousTimeMode", value)
        if self.nx:
            self.check(self._get_x(c, self.x, self.nx), "fmi2GetContinuousStates", value)
            self.check(self._get_dx(c, self.dx, self.nx), "fmi2GetDerivatives", value)
            x0[:] = self.x[:self.nx]
            xdot0[:] = self.dx[:self.nx]
        for k in range(self.nk):
            self.check(self._dd(c, self.u_vr, self.nu, self.k_vr, self.nk, self.seed_ptrs[k], self.column_ptr),
                       "fmi2GetDirectionalDerivative", value)
            J[:, k] = self.column[:self.nu]

    def _initial_event_iteration(self, value: float) -> None:
        """Leave the Event Mode after initialization as the standard requires (FMPy's wrappers:
        several out-arguments, rarely more than one call)."""
        try:
            self.fmu.initial_event_iteration(self.me)
        except (FMICallException, FMUError) as exc:
            self.check(int(getattr(exc, "status", 3) or 3), f"the initial event iteration ({exc})", value)

    def _evaluate_fmi3(self, value: float, J: np.ndarray, x0: np.ndarray, xdot0: np.ndarray) -> None:
        """:meth:`evaluate` through the FMI 3 functions, with the adjoint cross-check."""
        c = self.c
        self.check(self._reset(c), "fmi3Reset", value)
        if self.other:
            self.fmu.set(self.me, self.other)
        self.set_values[self.n_set - 1] = value
        self.check(self._set_real(c, self.set_vr, self.n_set, self.set_values, self.n_set), "fmi3SetFloat64", value)
        self.check(self._enter(c, False, 0.0, 0.0, False, 0.0), "initialization", value)
        self.check(self._exit(c), "initialization", value)
        self._initial_event_iteration(value)
        self.check(self._ct(c), "fmi3EnterContinuousTimeMode", value)
        if self.nx:
            self.check(self._get_x(c, self.x, self.nx), "fmi3GetContinuousStates", value)
            self.check(self._get_dx(c, self.dx, self.nx), "fmi3GetContinuousStateDerivatives", value)
            x0[:] = self.x[:self.nx]
            xdot0[:] = self.dx[:self.nx]
        for k in range(self.nk):
            self.check(self._dd(c, self.u_vr, self.n_uvr, self.k_vr, self.n_kvr, self.seed_ptrs[k], self.nk,
                                self.column_ptr, self.nu), "fmi3GetDirectionalDerivative", value)
            J[:, k] = self.column[:self.nu]
        if self._adjoint is not None and self.nu and self.nk:
            rows = np.zeros((self.nu, self.nk))
            for i in range(self.nu):
                self.check(self._adjoint(c, self.u_vr, self.n_uvr, self.k_vr, self.n_kvr, self.adjoint_seed_ptrs[i],
                                         self.nu, self.row_ptr, self.nk), "fmi3GetAdjointDerivative", value)
                rows[i] = self.row[:self.nk]
            difference = check_adjoint(self.fmu, J, rows, self.unknowns, self.knowns,
                                       f" at {self.varying} = {value:.15g}")
            self.adjoint_difference = max(self.adjoint_difference, difference)

    def close(self) -> None:
        _Point.close(self)


def linearize_speeds(fmu_path: str | Path, speeds, parameters: dict | None = None, inputs: dict | None = None,
                     lock_hinge: bool = False, isolate: bool | None = None,
                     timeout: float | None = DEFAULT_TIMEOUT) -> SpeedSweep:
    """Linearize an FMU at each forward speed of ``speeds``: one Model Exchange instance,
    re-initialized per speed, exact directional derivatives; the lateral reduction
    (:func:`steady_motion`) of the nonlinear bicycles for all speeds in one vectorized pass.

    Parameters
    ----------
    fmu_path : path
        FMI 2.0 or 3.0 FMU with Model Exchange and directional derivatives (as built here).
    speeds : sequence of float
        Forward speeds [m/s]; set as :class:`cosim.fmu.parameters.ForwardSpeed` says (``V`` or
        ``v``, or upright straight running ``u_R0 = -V/rR`` with ``V >= 0`` for the nonlinear
        bicycles).
    parameters : dict, optional
        Other parameter values (SI units, checked by the caller as for :func:`linearize`); the
        speed parameter must not be among them.
    inputs : dict, optional
        Operating-point input values [SI] (default: their start values).
    lock_hinge : bool
        WhippleRider: lock the rider's hinge in the reduction (see :func:`steady_motion`).
    isolate, timeout
        As for :func:`linearize`.

    Returns
    -------
    SpeedSweep
        Per speed the matrices and eigenvalues equal (up to rounding, in practice exactly) to
        :func:`linearize` with the speed parameter set, and :func:`steady_motion` of them.

    Raises
    ------
    ParameterError
        No speeds, a speed the model refuses (:meth:`ForwardSpeed.check`), the speed parameter
        also in ``parameters``.
    FMUError
        No Model Exchange or no directional derivatives.
    SimulationError
        The FMU refuses the initialization at a speed (named).
    NotSteadyMotion
        ``lock_hinge`` for a model without the rider hinge.
    """
    if isolate is None:
        isolate = can_isolate() and not built_here(fmu_path)
    if isolate:
        return run_isolated(lambda worker: linearize_speeds(fmu_path, speeds, parameters, inputs, lock_hinge, False),
                            what=str(fmu_path), timeout=timeout)
    from cosim.fmu.parameters import declarations, forward_speed, starts

    parameters = dict(parameters or {})
    declared = declarations(str(fmu_path))
    fs = forward_speed(str(fmu_path), declared)
    if fs.parameter in parameters:
        raise ParameterError(f"the speed parameter {fs.parameter} is set by the speeds; do not give it as a parameter")
    speeds = np.array([fs.check(v) for v in speeds], float)
    if speeds.size == 0:
        raise ParameterError("no speeds to linearize at")
    known = {**starts(declared), **parameters}
    values = np.array([fs.values(float(v), known)[fs.parameter] for v in speeds])
    with FMU(fmu_path, versions=ALL_FMI_VERSIONS) as fmu:
        md = fmu.description
        if md.modelExchange is None:
            raise FMUError(f"{fmu_path}: linearization needs Model Exchange, which the FMU does not offer")
        if not md.modelExchange.providesDirectionalDerivative:
            raise FMUError(f"{fmu_path}: a speed sweep needs directional derivatives, which the FMU does not "
                           "provide; use linearize() per speed (central finite differences)")
        st = _Structure.of(fmu)
        states, input_names, output_names = st.states, st.inputs, st.outputs
        nx, nu, N = len(states), len(input_names), len(speeds)
        J = np.zeros((N, len(st.unknowns), nx + nu))
        x0, xdot0 = np.zeros((N, nx)), np.zeros((N, nx))
        point = _FastPoint(fmu, {**parameters, **(inputs or {})}, fs.parameter, st)
        try:
            for k in range(N):
                point.evaluate(float(values[k]), J[k], x0[k], xdot0[k])
        finally:
            point.close()
    method = "directional derivatives"
    if point.adjoint_difference is not None:
        method += f" (adjoint derivatives agree to {point.adjoint_difference:.1e})"
    A, B = J[:, :nx, :nx], J[:, :nx, nx:]
    C, D = st.output_matrices(J)
    sweep = SpeedSweep(md.modelName, parameters, fs.parameter, speeds, values, states, input_names, output_names,
                       np.ascontiguousarray(A), np.ascontiguousarray(B), C, D, x0, xdot0, method)
    if names_of_bicycle() <= set(states) | set(output_names):
        # the rows of C and D of the outputs that alias the bicycle's states are the same at every
        # speed (checked, else the reduction goes one speed at a time)
        aliases = {*names_of_bicycle(), *HINGE, *(n for pair in further_coordinates(states) for n in pair)}
        rows = [k for k, n in enumerate(output_names) if n in aliases]
        if np.all(C[:, rows] == C[:1, rows]) and np.all(D[:, rows] == D[:1, rows]):
            sweep.steady = _steady_motions(sweep.model, states, input_names, output_names, C[0], D[0], sweep.A,
                                           sweep.B, x0, xdot0, sweep.method, lock_hinge)
        else:
            sweep.steady = []
            for k in range(N):
                lin = sweep.linearization(k)
                sweep.steady += _steady_motions(lin.model, states, input_names, output_names, lin.C, lin.D,
                                                lin.A[None], lin.B[None], lin.x0[None], lin.xdot0[None],
                                                lin.method, lock_hinge)
    elif lock_hinge:
        raise NotSteadyMotion(f"{md.modelName} is not a nonlinear bicycle with a rider hinge to lock")
    return sweep
