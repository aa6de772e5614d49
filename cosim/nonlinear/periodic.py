"""Periodic orbits of the nonlinear bicycle FMU (Figure 10 of Astrom, Klein & Lennartsson 2005).

The FMU's Model Exchange vector field is integrated with scipy's DOP853 (event location on the
Poincare section); a periodic orbit is a fixed point of the Poincare map on the section
``phi = 0, u_phi > 0`` (roll through upright, rolling right). Coordinates on the section:
``z = (delta, u_phi, u_delta, u_R)`` (the pitch follows from the holonomic constraint, the
ignorable coordinates x, y, yaw and the wheel angles start at 0).

Energy is conserved, so periodic orbits come in a one-parameter family (one per energy level);
the Newton iteration keeps ``u_R`` on the section fixed and solves for
``(delta, u_phi, u_delta)``: equal energy then returns ``u_R`` too. The Floquet multipliers are
the eigenvalues of the 4x4 Jacobian of the map (central differences); one of them is 1 (the
family), the orbit is stable within its energy level when the others lie inside the unit circle.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cosim.nonlinear.model import Bicycle

SECTION = ("delta", "u_phi", "u_delta", "u_R")


@dataclass
class Orbit:
    """A periodic orbit through the section point ``z``."""

    z: np.ndarray
    period: float
    roll_amplitude: float  # max |phi| over the period [rad]
    steer_amplitude: float  # max |delta| [rad]
    mean_speed: float  # time-averaged forward speed of the rear contact point [m/s]
    multipliers: np.ndarray = field(default_factory=lambda: np.zeros(0))
    residual: float = float("nan")  # |P(z) - z| of the returned point
    iterations: int = 0
    trajectory: dict = field(default_factory=dict)  # one period: time and states by name

    @property
    def stable(self) -> bool:
        """All Floquet multipliers but the family's (closest to 1) inside the unit circle."""
        m = np.asarray(self.multipliers)
        if m.size == 0:
            return False
        rest = np.delete(m, np.argmin(np.abs(m - 1.0)))
        return bool(np.all(np.abs(rest) < 1.0))

    def to_dict(self) -> dict:
        return {
            "section_point": dict(zip(SECTION, map(float, self.z))), "period_s": self.period,
            "roll_amplitude_rad": self.roll_amplitude, "steer_amplitude_rad": self.steer_amplitude,
            "mean_speed_m_s": self.mean_speed,
            "floquet_multipliers": [[float(m.real), float(m.imag)] for m in self.multipliers],
            "stable": self.stable, "fixed_point_residual": self.residual, "newton_iterations": self.iterations,
        }


def integrate(bike: Bicycle, x0, t_end: float, *, events=None, t_eval=None, rtol: float = 1e-11,
              atol: float = 1e-12, max_step: float = 0.05):
    """Integrate the FMU's vector field (no inputs) with DOP853 from ``x0``."""
    from scipy.integrate import solve_ivp

    return solve_ivp(lambda t, x: bike.derivatives(x), (0.0, t_end), np.asarray(x0, float), method="DOP853",
                     rtol=rtol, atol=atol, events=events, t_eval=t_eval, dense_output=True, max_step=max_step)


def section_state(bike: Bicycle, z) -> np.ndarray:
    """The full state on the section for ``z = (delta, u_phi, u_delta, u_R)``."""
    return bike.state(phi=0.0, delta=z[0], u_phi=z[1], u_delta=z[2], u_R=z[3])


def _crossing(bike: Bicycle):
    iphi = bike.index["phi"]

    def event(t, x):
        return x[iphi] if t > 1e-9 else 1.0

    event.terminal = True
    event.direction = 1.0
    return event


def poincare(bike: Bicycle, z, t_max: float = 20.0):
    """One return to the section: (z', return time, solution)."""
    x0 = section_state(bike, z)
    sol = integrate(bike, x0, t_max, events=[_crossing(bike)])
    if not sol.t_events[0].size:
        raise RuntimeError(f"no return to the section phi = 0 within {t_max} s from {z}")
    xe = sol.y_events[0][0]
    return np.array([xe[bike.index[n]] for n in SECTION]), float(sol.t_events[0][0]), sol


def settle(bike: Bicycle, x0, t_end: float):
    """Integrate from ``x0`` for ``t_end`` and return the last section crossing's z (or None)."""
    event = _crossing(bike)
    event.terminal = False
    sol = integrate(bike, x0, t_end, events=[event])
    ys = sol.y_events[0]
    if not len(ys):
        return None, sol
    return np.array([ys[-1][bike.index[n]] for n in SECTION]), sol


def periodic_orbit(bike: Bicycle, z0, *, tol: float = 1e-10, max_iter: int = 12, h: float = 1e-6) -> Orbit:
    """Newton on the Poincare map from the section point ``z0`` (u_R held fixed)."""
    z = np.asarray(z0, float).copy()
    residual = np.inf
    k = 0
    for k in range(1, max_iter + 1):
        pz, _, _ = poincare(bike, z)
        g = (pz - z)[:3]
        residual = float(np.abs(g).max())
        if residual <= tol:
            break
        J = np.zeros((3, 3))
        for j in range(3):
            dz = np.zeros(4)
            dz[j] = h
            J[:, j] = ((poincare(bike, z + dz)[0] - (z + dz)) - (poincare(bike, z - dz)[0] - (z - dz)))[:3] / (2 * h)
        z[:3] -= np.linalg.solve(J, g)
    pz, period, sol = poincare(bike, z)
    residual = float(np.abs(pz - z).max())
    # Floquet multipliers of the 4-dimensional map.
    Jm = np.zeros((4, 4))
    for j in range(4):
        dz = np.zeros(4)
        dz[j] = h * max(1.0, abs(z[j]))
        Jm[:, j] = (poincare(bike, z + dz)[0] - poincare(bike, z - dz)[0]) / (2 * dz[j])
    t = np.linspace(0.0, period, 2001)
    xs = sol.sol(t)
    speeds = np.array([bike.get(["v"], xs[:, k])[0] for k in range(0, t.size, 10)])
    trajectory = {"time": t, **{name: xs[k] for name, k in bike.index.items()}}
    return Orbit(z=z, period=period, roll_amplitude=float(np.abs(xs[bike.index["phi"]]).max()),
                 steer_amplitude=float(np.abs(xs[bike.index["delta"]]).max()),
                 mean_speed=float(np.mean(speeds[:-1])), multipliers=np.linalg.eigvals(Jm),
                 residual=residual, iterations=k, trajectory=trajectory)
