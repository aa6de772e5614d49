"""Steady turns of the nonlinear bicycle FMU and their stability (Figure 7 of Astrom, Klein &
Lennartsson 2005).

A steady turn (hands free, no input) is an equilibrium of the reduced dynamics: constant roll
``phi``, steer ``delta`` and rear wheel rate ``u_R`` with ``u_phi = u_delta = 0`` and
``du_phi/dt = du_delta/dt = 0`` (``du_R/dt = 0`` follows from energy conservation); the yaw,
the position and the wheel angles grow uniformly. The two equations
``G(phi, delta, u_R) = (du_phi/dt, du_delta/dt) = 0`` in three unknowns give curves, traced by
pseudo-arclength continuation (tangent predictor, Newton corrector on ``G`` plus the
arclength condition). ``G`` and its Jacobian come from the FMU (derivatives and exact
directional derivatives; the pitch is eliminated with the holonomic constraint, see
:func:`cosim.nonlinear.model.reduced_jacobian`).

Stability of an equilibrium: the eigenvalues of the FMU's Jacobian on the constraint manifold in
``(phi, delta, u_phi, u_delta, u_R)``. One of them is 0 with the curve's tangent as eigenvector
(the family of turns); the other four decide: stable when all have negative real part.
The upright branch ``phi = delta = 0`` is treated the same way (there the family is the speed).

Search window: the turns are looked for in ``|phi| < pi/2``, ``-pi < delta <= pi`` (the steer
may exceed 90 degrees), ``0 < v < v_max`` (:class:`Window`). Start points come from grids in
``(phi, delta)`` at fixed speeds (:meth:`SteadyTurns.find_turns_at_speeds`): every curve that
crosses one of these speeds is found. Where the FMU cannot make the pitch consistent (the
bicycle nearly flat on the ground), its initialization fails; such points count as outside.

Saddle-node folds: points where the speed ``v`` (the FMU's output, the rear contact point's
forward speed) is extremal along a curve, so that two turns at speeds on one side merge and
vanish. There the Jacobian of ``G = 0, v(z) = v`` in ``z`` is singular;
:meth:`SteadyTurns.refine_fold` solves ``G = 0`` and ``det [dG/dz; dv/dz] = 0`` by Newton.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import SimulationError
from cosim.nonlinear.model import Bicycle, reduced_jacobian

#: Scale of the continuation variables (phi [rad], delta [rad], speed -u_R rR [m/s]).
SPEED_SCALE = 10.0


@dataclass(frozen=True)
class Window:
    """The region searched for steady turns: ``0 < phi < phi_max`` (the mirror turns
    ``(-phi, -delta)`` cover negative roll), ``-delta_max < delta <= delta_max`` and
    ``v_min < -u_R rR < v_max`` (the rear rim speed: the contact point's speed for a knife-edge
    wheel, slightly more than it for a crowned wheel leaning).

    Attributes
    ----------
    phi_max : float
        Largest roll angle [rad]; pi/2 is the bicycle lying on the ground.
    delta_max : float
        Largest steer angle magnitude [rad]; pi is the front wheel turned backwards.
    v_min, v_max : float
        Speed range of the rear contact point [m/s].
    """

    phi_max: float = np.pi / 2
    delta_max: float = np.pi
    v_min: float = 0.0
    v_max: float = 15.0

    def contains(self, z) -> bool:
        """Whether the continuation point ``z = (phi, delta, -u_R rR / SPEED_SCALE)`` is inside."""
        return bool(0.0 < z[0] < self.phi_max and -self.delta_max < z[1] <= self.delta_max
                    and self.v_min < z[2] * SPEED_SCALE < self.v_max)

    def describe(self) -> str:
        return (f"0 < phi < {self.phi_max:.4g} rad (and mirror), |delta| <= {self.delta_max:.4g} rad, "
                f"{self.v_min:g} < v < {self.v_max:g} m/s")


@dataclass
class Fold:
    """A saddle-node (fold) point of a curve of steady turns: the speed is extremal along the
    curve and ``dG/d(phi, delta)`` is singular.

    Attributes
    ----------
    v : float
        Speed of the rear contact point [m/s].
    phi, delta : float
        Roll and steer angle [rad].
    kind : str
        ``"min"`` (turns exist only above ``v`` near the fold) or ``"max"`` (only below).
    residual : float
        Largest component of ``G`` at the refined point [rad/s^2].
    """

    v: float
    phi: float
    delta: float
    kind: str
    residual: float


@dataclass
class Equilibrium:
    phi: float  # roll [rad]
    delta: float  # steer [rad]
    u_R: float  # rear wheel rate [rad/s]
    v: float  # forward speed of the rear contact point [m/s]
    eigenvalues: np.ndarray  # the four that decide stability [1/s]
    yaw_rate: float = 0.0  # [rad/s]

    @property
    def stable(self) -> bool:
        return bool(np.all(self.eigenvalues.real < 0.0))

    @property
    def max_real(self) -> float:
        return float(self.eigenvalues.real.max())


@dataclass
class Branch:
    points: list[Equilibrium] = field(default_factory=list)

    def array(self, name: str) -> np.ndarray:
        return np.array([getattr(p, name) for p in self.points])


class SteadyTurns:
    """Steady turns of a bicycle FMU for one parameter set."""

    def __init__(self, bike: Bicycle):
        self.bike = bike
        self.rR = float(bike.params["rR"])
        ix = bike.index
        self.rows = [ix["u_phi"], ix["u_delta"]]
        self._dg = None  # indices of dG/dz in the reduced Jacobian (see linearization)

    # z = (phi, delta, s) with s = -u_R rR / SPEED_SCALE
    def _start(self, z):
        return {"phi0": z[0], "delta0": z[1], "u_R0": -z[2] * SPEED_SCALE / self.rR}

    def residual(self, z) -> np.ndarray:
        """``G(z) = (du_phi/dt, du_delta/dt)`` [rad/s^2]; raises ``FMICallException`` where the
        FMU cannot make the pitch consistent."""
        self.bike.reinitialize(self._start(z))
        return self.bike.derivatives()[self.rows]

    def _residual_or_nan(self, z) -> np.ndarray:
        try:
            return self.residual(z)
        except FMICallException:
            return np.full(2, np.nan)

    def linearization(self, z):
        """G(z), dG/dz (2x3) and the reduced Jacobian (5x5, its names)."""
        x = self.bike.initialize(self._start(z))
        G = self.bike.derivatives(x)[self.rows]
        R, names = reduced_jacobian(self.bike.jacobian(x), self.bike.states)
        if self._dg is None:  # rows (u_phi, u_delta) and columns (phi, delta, u_R) of R in dG/dz
            self._dg = (np.array([[names.index("u_phi")], [names.index("u_delta")]]),
                        np.array([names.index("phi"), names.index("delta"), names.index("u_R")]),
                        np.array([1.0, 1.0, -SPEED_SCALE / self.rR]))
        r, cols, scale = self._dg
        DG = R[r, cols] * scale
        return G, DG, R, names

    def equilibrium(self, z, tangent=None) -> Equilibrium:
        G, DG, R, names = self.linearization(z)
        ev, vec = np.linalg.eig(R)
        if tangent is None:
            tangent = _null(DG)
        t5 = np.zeros(len(names))
        t5[names.index("phi")], t5[names.index("delta")] = tangent[0], tangent[1]
        t5[names.index("u_R")] = -tangent[2] * SPEED_SCALE / self.rR
        t5 /= np.linalg.norm(t5)
        align = np.abs(t5 @ (vec / np.linalg.norm(vec, axis=0)))
        # The family's eigenvalue is 0 with the tangent as eigenvector.
        drop = int(np.argmax(align - 1e3 * np.abs(ev) * (align < 0.999)))
        rest = np.delete(ev, drop)
        v, yaw = self.bike.get(["v", "u_psi"])
        return Equilibrium(float(z[0]), float(z[1]), -float(z[2]) * SPEED_SCALE / self.rR, float(v),
                           rest, float(yaw))

    def correct(self, z, tangent=None, z_pred=None, tol: float = 1e-10, max_iter: int = 10):
        """Newton on G = 0 (plus the arclength condition when ``tangent`` is given)."""
        z = np.asarray(z, float).copy()
        for k in range(max_iter):
            try:
                G, DG, _, _ = self.linearization(z)
            except FMICallException:  # outside the configurations the FMU can assemble
                return None, k
            if tangent is None:
                # minimum-norm step in (phi, delta) with fixed speed
                step = np.linalg.lstsq(DG[:, :2], -G, rcond=None)[0]
                z[:2] += step
            else:
                F = np.concatenate([G, [tangent @ (z - z_pred)]])
                Jf = np.vstack([DG, tangent])
                try:
                    step = np.linalg.solve(Jf, -F)
                except np.linalg.LinAlgError:
                    return None, k
                z += step
            if not np.all(np.isfinite(z)):
                return None, k
            if np.abs(step).max() < tol and np.abs(G).max() < 1e-7:
                return z, k + 1
        G = self._residual_or_nan(z)
        if np.abs(G).max() < 1e-8:
            return z, max_iter
        return None, max_iter

    def trace(self, z0, direction: float = 1.0, *, ds: float = 0.02, ds_max: float = 0.05,
              ds_min: float = 1e-5, max_points: int = 2000, window: Window = Window()) -> Branch:
        """Continue the curve through ``z0`` in one direction (+1: growing speed at ``z0``) until
        it leaves ``window``, the FMU cannot assemble the bicycle, or the step falls below
        ``ds_min``."""
        z, _ = self.correct(z0)
        if z is None:
            raise SimulationError(f"no steady turn near {z0}")
        _, DG, _, _ = self.linearization(z)
        t = _null(DG) * direction
        branch = Branch([self.equilibrium(z, t)])
        while len(branch.points) < max_points:
            z_pred = z + ds * t
            zn, iters = self.correct(z_pred, t, z_pred)
            if zn is None or np.linalg.norm(zn - z) > 3 * ds:
                ds /= 2
                if ds < ds_min:
                    break
                continue
            _, DG, _, _ = self.linearization(zn)
            tn = _null(DG)
            if tn @ t < 0:
                tn = -tn
            z, t = zn, tn
            point = self.equilibrium(z, t)
            if not window.contains(z):
                break
            branch.points.append(point)
            if iters <= 3:
                ds = min(ds * 1.3, ds_max)
        return branch

    def upright(self, speeds, delta: float = 0.0) -> Branch:
        """The upright straight-running branch ``phi = 0, delta = 0`` (or ``delta = pi``: the front
        wheel turned backwards) at ``speeds`` [m/s]."""
        return Branch([self.equilibrium(np.array([0.0, delta, v / SPEED_SCALE]), np.array([0.0, 0.0, 1.0]))
                       for v in speeds])

    def upright_stable_interval(self, v_lo: float = 0.0, v_hi: float = 15.0, num: int = 301):
        """(v_low, v_high) of the first stable speed range of the upright branch, by bisection
        (brentq) on the largest real part of the FMU linearization's eigenvalues."""
        from scipy.optimize import brentq

        def max_real(v):
            return self.equilibrium(np.array([0.0, 0.0, v / SPEED_SCALE]), np.array([0.0, 0.0, 1.0])).max_real

        speeds = np.linspace(v_lo, v_hi, num)
        values = np.array([max_real(v) for v in speeds])
        stable = np.flatnonzero(values < 0.0)
        if not stable.size:
            return None
        i = stable[0]
        j = i
        while j + 1 < len(speeds) and values[j + 1] < 0.0:
            j += 1
        low = brentq(max_real, speeds[i - 1], speeds[i], xtol=1e-13) if i > 0 else speeds[0]
        high = brentq(max_real, speeds[j], speeds[j + 1], xtol=1e-13) if j + 1 < len(speeds) else np.inf
        return float(low), float(high)

    def find_turns_at_speeds(self, speeds, phis, deltas, window: Window = Window()) -> list[np.ndarray]:
        """Steady turns at fixed speeds: cells of a ``(phi, delta)`` grid where both components of
        ``G`` change sign, polished by damped Newton in ``(phi, delta)`` at the cell's speed.

        Parameters
        ----------
        speeds : array_like
            Speeds of the rear contact point [m/s].
        phis, deltas : array_like
            Grid of roll and steer angles [rad]; points the FMU cannot assemble are skipped.
        window : Window
            Only turns inside are returned.

        Returns
        -------
        list of ndarray
            Continuation points ``(phi, delta, v / SPEED_SCALE)``, distinct to 1e-6.
        """
        found = []
        for v in speeds:
            for z in self.turn_candidates(v, phis, deltas):
                # phi = 0 with delta = 0 or pi (straight running) solves G = 0 at every
                # speed: those branches are not turns (see upright()).
                if (z is not None and window.contains(z) and z[0] > 1e-8
                        and not any(np.linalg.norm(z - f) < 1e-6 for f in found)):
                    found.append(z)
        return found

    def turn_candidates(self, v: float, phis, deltas) -> list:
        """The polished start points of one speed of :meth:`find_turns_at_speeds` (None where
        Newton failed), cell by cell (rows of ``phis``, then ``deltas``), before the window and
        the distinctness are checked: the speeds are independent of each other."""
        phis, deltas = np.asarray(phis, float), np.asarray(deltas, float)
        s = v / SPEED_SCALE
        G = np.array([[self._residual_or_nan(np.array([a, d, s])) for d in deltas] for a in phis])
        # a cell is a candidate where both components of G change sign over its four corners
        # (none of them NaN: the FMU could not assemble the bicycle there)
        corners = np.stack([G[:-1, :-1], G[1:, :-1], G[:-1, 1:], G[1:, 1:]])
        with np.errstate(invalid="ignore"):
            change = ((corners.min(axis=0) < 0.0) & (corners.max(axis=0) > 0.0)).all(axis=-1)
        change &= ~np.isnan(corners).any(axis=(0, 3))
        mids = [np.array([0.5 * (phis[i] + phis[i + 1]), 0.5 * (deltas[j] + deltas[j + 1]), s])
                for i, j in zip(*np.nonzero(change))]
        return [self._polish_fixed_speed(mid) for mid in mids]

    def _polish_fixed_speed(self, z, max_iter: int = 30):
        z = z.copy()
        for _ in range(max_iter):
            try:
                G, DG, _, _ = self.linearization(z)
                step = np.linalg.solve(DG[:, :2], -G)
            except (FMICallException, np.linalg.LinAlgError):
                return None
            # damped: a cell is small, a long step would jump to another turn
            z[:2] += min(1.0, 0.1 / max(1e-12, np.abs(step).max())) * step
            if np.abs(step).max() < 1e-12:
                break
        G = self._residual_or_nan(z)
        return z if np.abs(G).max() < 1e-9 else None

    def speed(self, z) -> float:
        """The FMU's forward speed ``v`` of the rear contact point [m/s] at ``z``; it differs from
        ``-u_R rR`` for a crowned rear wheel leaning (the contact point moves round the crown)."""
        self.bike.reinitialize(self._start(z))
        return float(self.bike.get(["v"])[0])

    def fold_function(self, z, h: float = 1e-7) -> tuple[np.ndarray, float, np.ndarray]:
        """``G(z)``, the fold function ``det [dG/dz; dv/dz]`` and ``dG/dz``.

        The steady turns at a prescribed speed ``v`` solve ``G = 0, v(z) = v``; where the Jacobian
        of these three equations in ``z`` is singular, the speed is extremal along the curve (its
        tangent ``dG[0] x dG[1]`` is orthogonal to ``dv/dz``). ``dv/dz`` by central differences
        (``v`` is a smooth output of the FMU); for knife-edge wheels it is ``(0, 0, SPEED_SCALE)``.
        """
        G, DG, _, _ = self.linearization(z)
        grad_v = np.array([(self.speed(z + h * e) - self.speed(z - h * e)) / (2 * h) for e in np.eye(3)])
        return G, float(np.linalg.det(np.vstack([DG, grad_v]))), DG

    def refine_fold(self, z, tol: float = 1e-9, max_iter: int = 30, h: float = 1e-6) -> Fold:
        """The fold near ``z``: Newton on ``(G, fold function) = 0`` in ``z`` (the fold function's
        gradient by central differences), until the step is below ``tol`` (the differences of
        the speed make the fold function noisy at about 1e-11 in ``z``).

        Raises
        ------
        SimulationError
            If Newton does not converge (no fold near ``z``).
        """
        z = np.asarray(z, float).copy()
        for _ in range(max_iter):
            G, f, DG = self.fold_function(z)
            grad = np.array([(self.fold_function(z + h * e)[1] - self.fold_function(z - h * e)[1]) / (2 * h)
                             for e in np.eye(3)])
            step = np.linalg.solve(np.vstack([DG, grad]), -np.concatenate([G, [f]]))
            z += step
            if np.abs(step).max() < tol:
                break
        else:
            raise SimulationError(f"no fold near phi = {z[0]:.6g}, delta = {z[1]:.6g}, u_R = {self._start(z)['u_R0']:.6g}")
        G = self.residual(z)
        v = self.speed(z)
        # kind: on which side of the fold speed the pair of turns lies
        _, _, DG = self.fold_function(z)
        t = _null(DG)
        z_side, _ = self.correct(z + 1e-3 * t, t, z + 1e-3 * t)
        kind = "min" if z_side is not None and self.speed(z_side) > v else "max"
        return Fold(v, float(z[0]), float(z[1]), kind, float(np.abs(G).max()))

    def folds(self, branch: Branch) -> list[Fold]:
        """The folds of a traced curve: every interior local extremum of the speed, refined."""
        v = branch.array("v")
        out = []
        for k in range(1, len(v) - 1):
            if (v[k] - v[k - 1]) * (v[k + 1] - v[k]) < 0:
                p = branch.points[k]
                out.append(self.refine_fold(np.array([p.phi, p.delta, -p.u_R * self.rR / SPEED_SCALE])))
        return out


def _null(DG: np.ndarray) -> np.ndarray:
    """Unit null vector of a 2x3 matrix (the curve's tangent), oriented towards growing speed."""
    t = np.cross(DG[0], DG[1])
    n = np.linalg.norm(t)
    if n == 0.0:
        _, _, vt = np.linalg.svd(DG)
        t = vt[-1]
        n = np.linalg.norm(t)
    t = t / n
    return t if t[2] >= 0 else -t
