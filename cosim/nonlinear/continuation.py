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
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cosim.nonlinear.model import Bicycle, reduced_jacobian

#: Scale of the continuation variables (phi [rad], delta [rad], speed -u_R rR [m/s]).
SPEED_SCALE = 10.0


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

    # z = (phi, delta, s) with s = -u_R rR / SPEED_SCALE
    def _start(self, z):
        return {"phi0": z[0], "delta0": z[1], "u_R0": -z[2] * SPEED_SCALE / self.rR}

    def residual(self, z) -> np.ndarray:
        self.bike.initialize(self._start(z))
        return self.bike.derivatives()[self.rows]

    def linearization(self, z):
        """G(z), dG/dz (2x3) and the reduced Jacobian (5x5, its names)."""
        x = self.bike.initialize(self._start(z))
        G = self.bike.derivatives(x)[self.rows]
        R, names = reduced_jacobian(self.bike.jacobian(x), self.bike.states)
        r = [names.index("u_phi"), names.index("u_delta")]
        cols = [names.index("phi"), names.index("delta"), names.index("u_R")]
        DG = R[np.ix_(r, cols)] * np.array([1.0, 1.0, -SPEED_SCALE / self.rR])
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
            G, DG, _, _ = self.linearization(z)
            if tangent is None:
                # minimum-norm step in (phi, delta) with fixed speed
                step = np.linalg.lstsq(DG[:, :2], -G, rcond=None)[0]
                z[:2] += step
            else:
                F = np.concatenate([G, [tangent @ (z - z_pred)]])
                Jf = np.vstack([DG, tangent])
                step = np.linalg.solve(Jf, -F)
                z += step
            if np.abs(step).max() < tol and np.abs(G).max() < 1e-7:
                return z, k + 1
        G = self.residual(z)
        if np.abs(G).max() < 1e-8:
            return z, max_iter
        return None, max_iter

    def trace(self, z0, direction: float = 1.0, *, ds: float = 0.02, ds_max: float = 0.05,
              ds_min: float = 1e-5, max_points: int = 2000, v_max: float = 15.0, phi_max: float = 1.45,
              delta_max: float = 1.45) -> Branch:
        """Continue the curve through ``z0`` in one direction until it leaves the domain
        ``0 < phi < phi_max``, ``|delta| < delta_max``, ``0 < v < v_max``."""
        z, _ = self.correct(z0)
        if z is None:
            raise RuntimeError(f"no steady turn near {z0}")
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
            if not (0.0 < z[0] < phi_max and abs(z[1]) < delta_max and 0.0 < z[2] * SPEED_SCALE < v_max):
                break
            branch.points.append(point)
            if iters <= 3:
                ds = min(ds * 1.3, ds_max)
        return branch

    def upright(self, speeds) -> Branch:
        """The upright straight-running branch phi = delta = 0."""
        return Branch([self.equilibrium(np.array([0.0, 0.0, v / SPEED_SCALE]), np.array([0.0, 0.0, 1.0]))
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

    def find_turns(self, phis, deltas, speeds) -> list[np.ndarray]:
        """Steady turns at fixed roll angles: sign changes of both components of G on a
        (speed, steer) grid, polished by Newton in (delta, s) at fixed phi."""
        found = []
        for phi in phis:
            G = np.array([[self.residual(np.array([phi, d, v / SPEED_SCALE])) for d in deltas] for v in speeds])
            for i in range(len(speeds) - 1):
                for j in range(len(deltas) - 1):
                    cell = G[i:i + 2, j:j + 2]
                    if all(cell[..., k].min() < 0.0 < cell[..., k].max() for k in range(2)):
                        z = self._polish_fixed_phi(np.array([phi, deltas[j], speeds[i] / SPEED_SCALE]))
                        if z is not None and not any(np.linalg.norm(z - f) < 1e-6 for f in found):
                            found.append(z)
        return found

    def _polish_fixed_phi(self, z, max_iter: int = 20):
        z = z.copy()
        for _ in range(max_iter):
            G, DG, _, _ = self.linearization(z)
            J = DG[:, 1:]
            try:
                step = np.linalg.solve(J, -G)
            except np.linalg.LinAlgError:
                return None
            scale = min(1.0, 0.2 / max(1e-12, np.abs(step).max()))
            z[1:] += scale * step
            if np.abs(step).max() < 1e-12 or np.abs(G).max() < 1e-11:
                break
        return z if np.abs(self.residual(z)).max() < 1e-9 and z[2] > 0 else None


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
