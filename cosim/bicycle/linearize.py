"""The bicycles' linearizations: the nonlinear bicycles' steady motion, and sweeps over speed.

For the nonlinear bicycles (``Bicycle.Bicycles.Whipple``, ``WhippleRider``) :func:`steady_motion`
reduces the linearization (:func:`cosim.fmu.linearize.linearize`) about upright straight running
exactly to its lateral dynamics (see there): the ignorable coordinates, the pitch (fixed by the
holonomic constraint) and the conserved forward speed each contribute an exact zero eigenvalue,
which are named; the hinge of the rider can be locked exactly by its reaction torque.
:func:`linearize_speeds` linearizes a bicycle at many forward speeds and reduces all of them in
one vectorized pass.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cosim.analytic.parameters import MAX_SPEED
from cosim.bicycle.parameters import forward_speed
from cosim.errors import ParameterError
from cosim.fmu.isolation import DEFAULT_TIMEOUT
from cosim.fmu.linearize import Linearization, coordinate_matrix, linearize_sweep, stacked
from cosim.fmu.parameters import declarations, starts
from cosim.statespace import StateSpace

# --------------------------------------------------------------------------- steady motion

#: The quantities of the nonlinear bicycles (outputs of ``Bicycle.Bicycles.Whipple`` and
#: ``WhippleRider``) in the roles they play in upright straight running.
IGNORABLE = ("x", "y", "psi", "thetaR", "thetaF")  # nothing depends on them but the path
PATH = ("psi", "y")  # yaw and lateral position: reported with the lateral dynamics
PITCH = "theta"  # fixed by roll and steer through the holonomic constraint
PITCH_GUESS = "theta_guess"  # the parameter the initial pitch's Newton iteration starts from
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
    return names_of_bicycle() <= set(lin.system.states) | set(lin.system.outputs)


def names_of_bicycle() -> set[str]:
    """The states or outputs a nonlinear bicycle has (see :func:`is_bicycle`)."""
    return {*IGNORABLE, PITCH, FORWARD_SPEED, *LATERAL_COORDINATES, *LATERAL_SPEEDS}


class NotSteadyMotion(ValueError):
    """The linearization is not about upright straight running (or lacks its structure)."""


@dataclass
class SteadyMotion:
    """The exact lateral linearization of a nonlinear bicycle about upright straight running.

    ``system`` is ``x' = A x + B u`` on the lateral states (roll, steer[, lean], their rates),
    every state an output; ``path_A``, ``path_B`` the rows of yaw and lateral position
    (``psi' , y'``) on ``system.states + path``.
    The eigenvalues of the whole model are :attr:`eigenvalues` and one exact zero for each
    entry of :attr:`zero_modes`.
    """

    model: str
    speed: float  # forward speed v [m/s] of the operating point
    hinge: str | None  # "free", "locked" or None (no rider hinge)
    system: StateSpace
    path: list[str]
    path_A: np.ndarray
    path_B: np.ndarray
    zero_modes: dict[str, str]
    method: str

    @property
    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues [1/s] of the lateral dynamics, sorted by real, then imaginary part."""
        ev = np.linalg.eigvals(self.system.A)
        return ev[np.lexsort((ev.imag, ev.real))]

    def all_eigenvalues(self) -> np.ndarray:
        """Eigenvalues of the whole (locked) model: the lateral ones and the exact zeros."""
        return np.concatenate([self.eigenvalues, np.zeros(len(self.zero_modes), complex)])

    def to_statespace(self):
        """python-control StateSpace of the lateral dynamics plus the path (``states + path``),
        every state an output."""
        import control

        s = self.system
        n = len(s.states)
        A = np.zeros((n + len(self.path),) * 2)
        A[:n, :n] = s.A
        A[n:] = self.path_A
        B = np.vstack([s.B, self.path_B])
        names = s.states + self.path
        return control.ss(A, B, np.eye(len(names)), np.zeros((len(names), len(s.inputs))), states=names,
                          inputs=s.inputs, outputs=names, name=self.model.replace(".", "_"))

    def to_dict(self) -> dict:
        return {
            "operating_point": f"upright straight running at forward speed v = {self.speed:.15g} m/s",
            "speed": self.speed, "hinge": self.hinge, "states": self.system.states, "inputs": self.system.inputs,
            "A": self.system.A.tolist(), "B": self.system.B.tolist(),
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

    Works on the named quantities (states or outputs aliasing them, :func:`cosim.fmu.linearize.coordinate_matrix`):

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
    s = lin.system
    (result,) = _steady_motions(lin.model, s.states, s.inputs, s.outputs, s.C, s.D, s.A[None],
                                s.B[None], _point(lin.x0, len(s.states))[None],
                                _point(lin.xdot0, len(s.states))[None], lin.method, lock_hinge)
    if isinstance(result, NotSteadyMotion):
        raise result
    return result


def _point(x, n: int) -> np.ndarray:
    """An operating-point vector, NaN where it is unknown (a Linearization built by hand)."""
    return np.full(n, np.nan) if x is None else np.asarray(x, float)



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
    T = coordinate_matrix(model, states, outputs, C, D, names)
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
    eye, no_feedthrough = np.eye(len(lat)), np.zeros((len(lat), len(inputs)))  # every state an output
    path_A, path_B = A[:, path][:, :, lat + path], B[:, path]
    return [refused[k] if k in refused else
            SteadyMotion(model, float(speed[k]), hinge,
                         StateSpace(lateral_A[k], lateral_B[k], eye, no_feedthrough, list(lateral), inputs,
                                    list(lateral)),
                         list(PATH), path_A[k], path_B[k], dict(zero_modes), method)
            for k in range(n_points)]



# --------------------------------------------------------------------------- speed sweeps

#: Most speeds one sweep (``cosim linearize --speeds``, ``cosim compare --speeds``) takes.
MAX_SPEEDS = 10_000


def parse_speeds(text: str, option: str = "--speeds") -> list[float]:
    """``A:B:STEP`` (B included, as far as it is reached by whole steps) or ``V1,V2,...`` [m/s].

    The grammar of ``--speeds`` for ``cosim linearize`` and ``cosim compare`` (here, not beside
    the comparison, which imports SciPy: ``cosim linearize`` stays light); the largest speed is
    :data:`cosim.analytic.parameters.MAX_SPEED`.

    Raises
    ------
    ParameterError
        Malformed text, non-finite values, ``STEP <= 0``, ``B < A``, an empty list or more
        than :data:`MAX_SPEEDS` speeds.
    """
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

    ``systems`` one :class:`~cosim.statespace.StateSpace` per speed (the same names, the state
    order of :class:`Linearization`), ``x0``, ``xdot0`` (N, nx); ``values`` the speed parameter's value
    per speed (``V``/``v`` [m/s] or ``u_R0`` [rad/s]). For the nonlinear bicycles ``steady``
    holds per speed the :class:`SteadyMotion` or the :class:`NotSteadyMotion` that refuses it
    (None for other models).
    """

    model: str
    parameters: dict
    speed_parameter: str
    speeds: np.ndarray
    values: np.ndarray
    systems: list[StateSpace]
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
        n = len(self.systems[0].states)
        return np.linalg.eigvals(stacked(self.systems, "A")) if n else np.zeros((len(self), 0), complex)

    @property
    def lateral_eigenvalues(self) -> np.ndarray:
        """(N, n_lat) eigenvalues [1/s] of the lateral dynamics (sorted as
        :attr:`SteadyMotion.eigenvalues`), NaN rows where the reduction is refused; ValueError
        for a model that is not a nonlinear bicycle."""
        if self.steady is None:
            raise ValueError(f"{self.model} is not a nonlinear bicycle; it has no steady-motion reduction")
        good = [k for k, s in enumerate(self.steady) if isinstance(s, SteadyMotion)]
        n = len(self.steady[good[0]].system.states) if good else 0
        out = np.full((len(self), n), np.nan + 0j)
        if good:
            ev = np.linalg.eigvals(np.array([self.steady[k].system.A for k in good]))
            for row, k in zip(ev, good):
                out[k] = row[np.lexsort((row.imag, row.real))]
        return out

    def linearization(self, k: int) -> Linearization:
        """The :class:`Linearization` at ``speeds[k]``."""
        s = self.systems[k]
        return Linearization(self.model, {**self.parameters, self.speed_parameter: float(self.values[k])},
                             StateSpace(s.A, s.B, s.C, s.D, list(s.states), list(s.inputs), list(s.outputs)),
                             self.method, self.x0[k], self.xdot0[k])

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
                point.update({name: getattr(self.systems[k], name).tolist() for name in "ABCD"})
            if self.steady is not None:
                s = self.steady[k]
                if isinstance(s, SteadyMotion):
                    point["steady_motion"] = {"A": s.system.A.tolist(), "B": s.system.B.tolist(),
                                              "eigenvalues": lateral[k],
                                              "path": {"A": s.path_A.tolist(), "B": s.path_B.tolist()}}
                else:
                    point["steady_motion"] = None
                    point["steady_motion_note"] = str(s)
            points.append(point)
        report = {"model": self.model, "parameters": self.parameters, "speed_parameter": self.speed_parameter,
                  "speeds": [float(v) for v in self.speeds], "states": self.systems[0].states,
                  "inputs": self.systems[0].inputs, "outputs": self.systems[0].outputs, "method": self.method}
        good = [s for s in self.steady or [] if isinstance(s, SteadyMotion)]
        if good:
            s = good[0]
            report["steady_motion"] = {"hinge": s.hinge, "states": s.system.states, "inputs": s.system.inputs,
                                       "path": {"states": s.path},
                                       "zero_eigenvalues": [{"state": n, "reason": r} for n, r in s.zero_modes.items()],
                                       "method": s.method}
        report["points"] = points
        return report


def linearize_speeds(fmu_path: str | Path, speeds, parameters: dict | None = None, inputs: dict | None = None,
                     lock_hinge: bool = False, isolate: bool | None = None,
                     timeout: float | None = DEFAULT_TIMEOUT, continuation: bool = True) -> SpeedSweep:
    """Linearize an FMU at each forward speed of ``speeds``: one Model Exchange instance,
    initialized per speed (by continuation: only the speed parameter changes, the initial pitch
    is solved from the previous speed's), exact directional derivatives (:func:`cosim.fmu.linearize.linearize_sweep`); the lateral reduction
    (:func:`steady_motion`) of the nonlinear bicycles for all speeds in one vectorized pass.

    Parameters
    ----------
    fmu_path : path
        FMI 2.0 or 3.0 FMU with Model Exchange and directional derivatives (as built here).
    speeds : sequence of float
        Forward speeds [m/s]; set as :class:`cosim.bicycle.parameters.ForwardSpeed` says (``V`` or
        ``v``, or upright straight running ``u_R0 = -V/rR`` with ``V >= 0`` for the nonlinear
        bicycles).
    parameters : dict, optional
        Other parameter values (SI units, checked by the caller as for :func:`cosim.fmu.linearize.linearize`); the
        speed parameter must not be among them.
    inputs : dict, optional
        Operating-point input values [SI] (default: their start values).
    lock_hinge : bool
        WhippleRider: lock the rider's hinge in the reduction (see :func:`steady_motion`).
    isolate, timeout
        As for :func:`cosim.fmu.linearize.linearize` (the FMU's binary is called by
        :func:`cosim.fmu.linearize.linearize_sweep`).
    continuation : bool
        As for :func:`cosim.fmu.linearize.linearize_sweep`: the FMU stays in initialization mode,
        only the speed parameter changes and the initial pitch's guess (:data:`PITCH_GUESS`, if
        the model has it) is the pitch solved at the previous speed (upright straight running:
        the pitch depends on the geometry, not on the speed, so that is the solution); False
        initializes from scratch at every speed. The same numbers either way.

    Returns
    -------
    SpeedSweep
        Per speed the matrices and eigenvalues equal (up to rounding, in practice exactly) to
        :func:`cosim.fmu.linearize.linearize` with the speed parameter set, and :func:`steady_motion` of them.

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
    guessed = PITCH_GUESS in declared and declared[PITCH_GUESS].causality == "parameter"
    swept = linearize_sweep(fmu_path, fs.parameter, values, parameters, inputs, isolate, timeout, continuation,
                            {PITCH: PITCH_GUESS} if guessed else None)
    first = swept.systems[0]
    states, input_names, output_names = first.states, first.inputs, first.outputs
    C, D, x0, xdot0, N = stacked(swept.systems, "C"), stacked(swept.systems, "D"), swept.x0, swept.xdot0, len(speeds)
    sweep = SpeedSweep(swept.model, swept.parameters, fs.parameter, speeds, swept.values, swept.systems, x0, xdot0,
                       swept.method)
    if names_of_bicycle() <= set(states) | set(output_names):
        # the rows of C and D of the outputs that alias the bicycle's states are the same at every
        # speed (checked, else the reduction goes one speed at a time)
        aliases = {*names_of_bicycle(), *HINGE, *(n for pair in further_coordinates(states) for n in pair)}
        rows = [k for k, n in enumerate(output_names) if n in aliases]
        if np.all(C[:, rows] == C[:1, rows]) and np.all(D[:, rows] == D[:1, rows]):
            sweep.steady = _steady_motions(sweep.model, states, input_names, output_names, C[0], D[0],
                                           stacked(sweep.systems, "A"), stacked(sweep.systems, "B"), x0, xdot0,
                                           sweep.method, lock_hinge)
        else:
            sweep.steady = []
            for k in range(N):
                lin = sweep.linearization(k)
                s = lin.system
                sweep.steady += _steady_motions(lin.model, states, input_names, output_names, s.C, s.D,
                                                s.A[None], s.B[None], lin.x0[None], lin.xdot0[None],
                                                lin.method, lock_hinge)
    elif lock_hinge:
        raise NotSteadyMotion(f"{sweep.model} is not a nonlinear bicycle with a rider hinge to lock")
    return sweep
