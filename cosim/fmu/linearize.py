"""Linearize an FMU about its initial point: A, B, C, D from directional derivatives.

FMI 2.0 and 3.0 FMUs with Model Exchange. ``fmi2GetDirectionalDerivative`` /
``fmi3GetDirectionalDerivative`` give exact Jacobians for FMUs built here; for foreign FMUs
without them, central finite differences are used. Where an FMI 3 FMU also provides
``fmi3GetAdjointDerivative``, the whole Jacobian is computed a second time from it (one adjoint
seed per unknown: ``(J^T v)^T u = v^T (J u)`` for unit vectors ``u``, ``v``, entry by entry) and a
disagreement beyond :data:`ADJOINT_TOLERANCE` is refused with the entry named.

:func:`linearize_sweep` linearizes at many values of one parameter through one instance. What a
linearization means for a bicycle (the steady-motion reduction, speed sweeps) is
:mod:`cosim.bicycle.linearize`.
"""
from __future__ import annotations

from ctypes import POINTER, c_double, c_uint
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import FMUError, ParameterError, SimulationError
from cosim.fmu.isolation import DEFAULT_TIMEOUT, built_here, can_isolate, run_isolated
from cosim.fmu.access import (ALL_FMI_VERSIONS, FMU, get_continuous_states, get_state_derivatives, lenient_reading,
                              read_fmu, set_continuous_states)
from cosim.statespace import StateSpace

FD_STEP = 1e-6  # relative step of the central differences
#: Largest difference between the Jacobian from directional and the one from adjoint derivatives,
#: relative to the largest entry (at least 1): the two are exact derivatives of the same function,
#: so they differ by rounding only (CasADi's forward and reverse modes sum in other orders).
ADJOINT_TOLERANCE = 1e-12


@dataclass
class Linearization:
    """x' = A x + B u, y = C x + D u about an operating point (deviations): the FMU's
    :class:`~cosim.statespace.StateSpace` and where and how it was found."""

    model: str
    parameters: dict
    system: StateSpace
    method: str
    #: The operating point: state values and their time derivatives (FMU state order; SI units).
    x0: np.ndarray | None = field(default=None, repr=False)
    xdot0: np.ndarray | None = field(default=None, repr=False)
    #: Largest difference between the directional and the adjoint Jacobian relative to the largest
    #: entry (at least 1); None where the FMU has no adjoint derivatives (FMI 2, most foreign FMUs).
    adjoint_difference: float | None = None

    @property
    def eigenvalues(self) -> np.ndarray:
        return self.system.eigenvalues

    def to_statespace(self):
        """A python-control StateSpace with named states, inputs and outputs."""
        return self.system.to_control(self.model.replace(".", "_"))

    def to_dict(self) -> dict:
        s = self.system
        return {
            "model": self.model, "parameters": self.parameters, "states": s.states,
            "inputs": s.inputs, "outputs": s.outputs,
            "A": s.A.tolist(), "B": s.B.tolist(), "C": s.C.tolist(), "D": s.D.tolist(),
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
    s = lin.system
    _check_finite(fmu_path, "at the operating point", A=(s.A, s.states, s.states), B=(s.B, s.states, s.inputs),
                  C=(s.C, s.outputs, s.states), D=(s.D, s.outputs, s.inputs))
    return lin


def _check_finite(fmu_path, where: str, **matrices) -> None:
    """Raise :class:`SimulationError` naming the first non-finite entry of ``matrices`` (name ->
    ``(matrix, row names, column names)``, checked in this order) and ``where`` it was computed."""
    for name, (matrix, rows, columns) in matrices.items():
        matrix = np.asarray(matrix, float)
        bad = np.argwhere(~np.isfinite(matrix))
        if len(bad):
            i, j = bad[0]
            raise SimulationError(f"{fmu_path}: linearization failed: {name}[{i}, {j}] (d {rows[i]} / "
                                  f"d {columns[j]}) is {matrix[i, j]} {where}")


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
    return Linearization(md.modelName, parameters, StateSpace(A, B, C, D, st.states, st.inputs, st.outputs),
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


# --------------------------------------------------------------------------- coordinates

def coordinate_matrix(model: str, states, outputs, C, D, names) -> np.ndarray:
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



# --------------------------------------------------------------------------- parameter sweeps

class _FastPoint:
    """One ME instance re-initialized per operating point through the raw FMI functions.

    FMPy's wrappers convert and check every argument in Python on each call; here the C
    functions (argument types already declared by FMPy) are called with preallocated buffers,
    and ``fmi2Reset``/``fmi3Reset`` replaces a new instance (no library load, no FMPy set-up) per
    point. Each point is initialized from scratch exactly as :func:`linearize` does, so the
    results are the same numbers. FMI 3 takes the same path with the FMI 3 functions (the
    ``nValues``/``nSeed``/``nSensitivity`` arguments, the initial event iteration) and, where the
    FMU provides adjoint derivatives, checks the Jacobian against them at every point.

    With ``continuation`` (only where :func:`_continuable` allows it, else ignored) the instance
    is initialized once: it stays in initialization mode and each further point sets only the
    varying parameter and, for each state of ``guesses`` (state name -> the parameter its initial
    equations start from, e.g. a bicycle's pitch and ``theta_guess``), the guess to the state's
    value solved at the previous point. The states, their derivatives and the directional
    derivatives are read in initialization mode, where they are those of the initialized point:
    the same numbers as from scratch when the solution does not depend on the varying parameter
    (then the previous solution is the solution) or is the one nearest the previous point's."""

    def __init__(self, fmu: FMU, fixed: dict, varying: str, st: _Structure, continuation: bool = False,
                 guesses: dict | None = None):
        self.fmu, self.me, self.varying = fmu, fmu.instantiate("me"), varying
        self.status = 0
        self.fmi3 = fmu.is_fmi3
        self.continuation = continuation and _continuable(fmu)
        self.initialized = False  # in initialization mode with the fixed values (continuation)
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
        # the varying parameter, then the guesses (continuation)
        guesses = (guesses or {}) if self.continuation else {}
        self.guessed = [st.states.index(state) for state in guesses]
        self.varying_vr = (c_uint * (1 + len(guesses)))(fmu.vr[varying], *[fmu.vr[g] for g in guesses.values()])
        self.varying_value = (c_double * (1 + len(guesses)))()
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
        """Initialize with the swept parameter = ``value``; fill the Jacobian ``J`` (unknowns x
        knowns), the states ``x0`` and their derivatives ``xdot0``."""
        if self.fmi3:
            return self._evaluate_fmi3(value, J, x0, xdot0)
        c = self.c
        continued, self.initialized = self.initialized, False  # until this point has succeeded
        if continued:
            self.varying_value[0] = value
            for k, i in enumerate(self.guessed):
                self.varying_value[1 + k] = self.x[i]  # the previous point's solution
            self.check(self._set_real(c, self.varying_vr, 1 + len(self.guessed), self.varying_value), "fmi2SetReal",
                       value)
        else:
            self.check(self._reset(c), "fmi2Reset", value)
            if self.other:
                self.fmu.set(self.me, self.other)
            self.set_values[self.n_set - 1] = value
            self.check(self._set_real(c, self.set_vr, self.n_set, self.set_values), "fmi2SetReal", value)
            self.check(self._setup(c, 0, 0.0, 0.0, 0, 0.0), "fmi2SetupExperiment", value)
            self.check(self._enter(c), "initialization", value)
        if not self.continuation:
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
        self.initialized = self.continuation

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


def _continuable(fmu: FMU) -> bool:
    """Whether :class:`_FastPoint` may continue from one point to the next in initialization
    mode: an FMI 2 FMU built here (whose runtime computes the initial equations, the states and
    their derivatives when they are read in initialization mode, and allows setting parameters
    there) without events (no initial event iteration that could change the point after the
    exit of initialization mode) or discrete-time variables."""
    md = fmu.description
    return (not fmu.is_fmi3 and built_here(fmu.path) and not md.numberOfEventIndicators
            and all(v.variability != "discrete" for v in md.modelVariables))


@dataclass
class Sweep:
    """Linearizations of one FMU at N values of one parameter (:func:`linearize_sweep`).

    ``systems`` one :class:`~cosim.statespace.StateSpace` per point (the same names, the state
    order of :class:`Linearization`), ``x0``, ``xdot0`` (N, nx); ``values`` the swept parameter's
    value per point (in its unit), ``parameters`` the other parameter values.
    """

    model: str
    parameters: dict
    parameter: str
    values: np.ndarray
    systems: list[StateSpace]
    x0: np.ndarray
    xdot0: np.ndarray
    method: str


def systems_of(A, B, C, D, states, inputs, outputs) -> list[StateSpace]:
    """One :class:`~cosim.statespace.StateSpace` per matrix of the stacks ``A`` (N, nx, nx),
    ``B`` (N, nx, nu), ``C`` (N, ny, nx), ``D`` (N, ny, nu) (views: nothing is copied)."""
    return [StateSpace(A[k], B[k], C[k], D[k], states, inputs, outputs) for k in range(len(A))]


def stacked(systems: list[StateSpace], name: str) -> np.ndarray:
    """The matrix ``name`` ("A", "B", "C" or "D") of every system, stacked on a first axis."""
    return np.array([getattr(s, name) for s in systems])


class ParameterLinearizer:
    """:func:`linearize` at values of one parameter given one at a time (a root finder's), on one
    Model Exchange instance re-initialized per value: :func:`linearize_sweep` for values not known
    in advance. Only for an FMU built here with directional derivatives (:meth:`usable`): it runs
    in this process, as :func:`linearize` runs such FMUs.

    Parameters
    ----------
    fmu_path : path
        The FMU.
    parameter : str
        The parameter set per call (a Real, set before the initialization).
    parameters : dict, optional
        Other parameter values (SI units).
    """

    def __init__(self, fmu_path: str | Path, parameter: str, parameters: dict | None = None):
        self.fmu = FMU(fmu_path, versions=ALL_FMI_VERSIONS)
        self.structure = _Structure.of(self.fmu)
        self.point = _FastPoint(self.fmu, dict(parameters or {}), parameter, self.structure)
        nx = len(self.structure.states)
        self.J = np.zeros((len(self.structure.unknowns), nx + len(self.structure.inputs)))
        self.x0, self.xdot0 = np.zeros(nx), np.zeros(nx)

    @staticmethod
    def usable(fmu_path: str | Path) -> bool:
        """Whether :func:`linearize` would run the FMU in this process with directional
        derivatives (built here, Model Exchange with them)."""
        if not built_here(fmu_path):
            return False
        me = read_fmu(fmu_path, ALL_FMI_VERSIONS).modelExchange
        return me is not None and bool(me.providesDirectionalDerivative)

    def state_space(self, value: float) -> tuple[np.ndarray, np.ndarray]:
        """``A`` and ``B`` (states and inputs in the order of :func:`linearize`) at ``value``.

        Raises
        ------
        SimulationError
            The FMU refuses the initialization or a call at ``value``, or an entry is not finite.
        """
        self.point.evaluate(float(value), self.J, self.x0, self.xdot0)
        nx = len(self.structure.states)
        A, B = self.J[:nx, :nx].copy(), self.J[:nx, nx:].copy()
        st = self.structure
        _check_finite(self.fmu.path, f"at {self.point.varying} = {value:.15g}", A=(A, st.states, st.states),
                      B=(B, st.states, st.inputs))
        return A, B

    def close(self) -> None:
        self.point.close()


def linearize_sweep(fmu_path: str | Path, parameter: str, values, parameters: dict | None = None,
                    inputs: dict | None = None, isolate: bool | None = None,
                    timeout: float | None = DEFAULT_TIMEOUT, continuation: bool = True,
                    guesses: dict | None = None) -> Sweep:
    """Linearize an FMU at each value of one parameter: one Model Exchange instance, initialized
    per value (by continuation, or from scratch), exact directional derivatives.

    Parameters
    ----------
    fmu_path : path
        FMI 2.0 or 3.0 FMU with Model Exchange and directional derivatives (as built here).
    parameter : str
        The parameter swept (a Real, set before the initialization).
    values : sequence of float
        Its values (in its unit), checked by the caller.
    parameters : dict, optional
        Other parameter values (SI units, checked by the caller as for :func:`linearize`).
    inputs : dict, optional
        Operating-point input values [SI] (default: their start values).
    isolate, timeout
        As for :func:`linearize`.
    continuation : bool
        Initialize once and then change only the parameter (and the guesses), in initialization
        mode (an FMI 2 FMU built here without events; others are initialized from scratch at
        every value, as with False).
    guesses : dict, optional
        With continuation: state name -> the parameter its initial equations start from (its
        guess), set to the state's value at the previous value (e.g. ``{"theta": "theta_guess"}``).

    Returns
    -------
    Sweep
        Per value the matrices equal (up to rounding, in practice exactly) to :func:`linearize`
        with the parameter set to it.

    Raises
    ------
    FMUError
        No Model Exchange or no directional derivatives.
    SimulationError
        The FMU refuses the initialization at a value (named).
    """
    if isolate is None:
        isolate = can_isolate() and not built_here(fmu_path)
    if isolate:
        return run_isolated(lambda worker: linearize_sweep(fmu_path, parameter, values, parameters, inputs, False,
                                                           continuation=continuation, guesses=guesses),
                            what=str(fmu_path), timeout=timeout)
    parameters = dict(parameters or {})
    values = np.asarray(values, float)
    with FMU(fmu_path, versions=ALL_FMI_VERSIONS) as fmu:
        md = fmu.description
        if md.modelExchange is None:
            raise FMUError(f"{fmu_path}: linearization needs Model Exchange, which the FMU does not offer")
        if not md.modelExchange.providesDirectionalDerivative:
            raise FMUError(f"{fmu_path}: a speed sweep needs directional derivatives, which the FMU does not "
                           "provide; use linearize() per speed (central finite differences)")
        st = _Structure.of(fmu)
        states, input_names, output_names = st.states, st.inputs, st.outputs
        nx, nu, N = len(states), len(input_names), len(values)
        J = np.zeros((N, len(st.unknowns), nx + nu))
        x0, xdot0 = np.zeros((N, nx)), np.zeros((N, nx))
        point = _FastPoint(fmu, {**parameters, **(inputs or {})}, parameter, st, continuation, guesses)
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
    return Sweep(md.modelName, parameters, parameter, values,
                 systems_of(np.ascontiguousarray(A), np.ascontiguousarray(B), C, D, states, input_names, output_names),
                 x0, xdot0, method)
