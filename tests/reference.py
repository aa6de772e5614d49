"""Independent Python implementations of the paper's equations, to check the FMUs against."""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

# Published values the tests check against (the code under test reads cosim/params/ instead).
#: The paper's Table 1 bicycle of the second-order models (Astrom et al. 2005).
SELF_STABILIZING_DEFAULTS = dict(m=92.0, a=0.5, h=1.0, b=1.0, c=0.08, lam=math.radians(70.0),
                                 J=96.7, D=46.3, V=5.0, g=9.81)
#: The benchmark bicycle of Meijaard et al. (2007), Table 1.
MEIJAARD_BENCHMARK = {
    "w": 1.02, "c": 0.08, "lam": math.pi / 10, "g": 9.81,
    "rR": 0.3, "mR": 2.0, "IRxx": 0.0603, "IRyy": 0.12,
    "xB": 0.3, "zB": -0.9, "mB": 85.0, "IBxx": 9.2, "IBxz": 2.4, "IByy": 11.0, "IBzz": 2.8,
    "xH": 0.9, "zH": -0.7, "mH": 4.0, "IHxx": 0.05892, "IHxz": -0.00756, "IHyy": 0.06, "IHzz": 0.00708,
    "rF": 0.35, "mF": 3.0, "IFxx": 0.1405, "IFyy": 0.28,
}


def self_stabilizing_rhs(p: dict, torque):
    """Eqs (14) and (11) in momentum form: states phi and L = J phi' - D V sin(lam) delta / b."""
    m, a, h, b, c, lam, J, D, V, g = (p[k] for k in ("m", "a", "h", "b", "c", "lam", "J", "D", "V", "g"))
    den = V**2 * math.sin(lam) - b * g * math.cos(lam)
    k1 = b**2 / (den * m * a * c * math.sin(lam))
    k2 = b * g / den

    def steer(t, phi):
        return k1 * torque(t) - k2 * phi

    def rhs(t, y):
        phi, L = y
        delta = steer(t, phi)
        return [(L + D * V * math.sin(lam) * delta / b) / J,
                m * g * h * phi + m * (V**2 * h - a * c * g) * math.sin(lam) / b * delta]

    return rhs, steer


def simulate_self_stabilizing(times: np.ndarray, torque, params: dict | None = None, rtol: float = 1e-11):
    """phi(t) and delta(t) of the self-stabilizing bicycle from rest, by scipy's DOP853."""
    p = {**SELF_STABILIZING_DEFAULTS, **(params or {})}
    rhs, steer = self_stabilizing_rhs(p, torque)
    sol = solve_ivp(rhs, (times[0], times[-1]), [0.0, 0.0], method="DOP853", t_eval=times,
                    rtol=rtol, atol=1e-13, max_step=0.01)
    phi = sol.y[0]
    delta = np.array([steer(t, x) for t, x in zip(sol.t, phi)])
    return phi, delta
