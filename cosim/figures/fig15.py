"""Figure 15 of Astrom, Klein & Lennartsson (2005): poles of an adapted bicycle with a crowned roller.

The paper's adapted bicycle has a rider, a heavy front wheel, a centre of mass 0.4 m above
the ground and a rear wheel replaced by a crowned roller of lateral (rocking) radius R (caption:
0.3 m; text: 0.4 m, "the weave mode becomes stable at 3.9 m/s, and the capsize mode remains
stable for all velocities"). The paper computed it with a nonlinear multibody model with
toroidal wheels. Both radii are shown, next to each other.

Roller model used here, and why it is exact
-------------------------------------------
A toroidal rear wheel (crown radius R) that rolls by phi shifts its ground contact point
sideways by R*phi relative to the frame, towards the side the bicycle leans to. The rear normal
force N_R = g*mT*(1 - xT/w) (static load of the rear wheel; mT total mass, xT its distance in
front of the rear contact) then acts with a lever R*phi about the roll axis: a restoring roll
moment -N_R*R*phi. In the linear model this is a roll-torque feedback

    T_phi = -k*phi,   k = g*mT*(1 - xT/w)*R,   i.e.  K0[0,0] -> mT*zT + mT*(1 - xT/w)*R,

applied through the roll-torque input ``T_phi`` of the linear Whipple FMU
(``A_cl = A - k*B[:, T_phi]*e_phi'``, :func:`cosim.bicycle.stability.closed_loop`). It is the
paper's eq (27) argument (the gravity term m*g*h of the inverted pendulum becomes m*g*(h - R))
for a roller on the rear wheel only: with rollers on both wheels, N_R + N_F = m*g and the
correction is exactly eq (27)'s.

For the linearization about upright straight running this is not an approximation: the
nonlinear Whipple FMU (``Bicycle.Bicycles.Whipple``) with an exact toroidal rear wheel of crown
radius tR = R (and a knife-edge front wheel, tF = 0) has the same lateral state matrix to
rounding (relative 1e-15) and so the same weave speeds, 4.5944 m/s (R = 0.3 m) and 4.8708 m/s
(R = 0.4 m). The other differences of a torus from a knife edge (the roll axis through the
crown centre, the moving contact point in the rolling constraint and in the steering geometry)
leave the linearized equations unchanged: only K0[0,0] changes, by exactly the term above
(``tests/test_fig5_fig15.py`` checks the matrices at several speeds and the weave speeds by root
finding on the torus FMU). The difference from the paper's 3.9 m/s therefore comes from the
adapted bicycle's data, which the paper does not give (below: our choice), not from the roller
model.

Adapted bicycle (the paper gives no numbers; our choice):
Table 1 with rider, the rear frame's centre of mass lowered so that the whole bicycle's centre
of mass is 0.4 m above the ground, and a heavy front wheel: twice Table 1's mass (3 kg) with
all of it in the rim (IFyy = mF*rF^2, IFxx = IFyy/2); see :func:`adapted_parameters`. Every eigenvalue comes from an FMU
linearization of ``Bicycle.Bicycles.WhippleLinear``; plotted as in Fig 9 (dot real, o complex,
red unstable, blue stable).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend
from cosim.analytic.parameters import load_parameter_set, parameters_for_model, validate_parameters
from cosim.figures.fig9 import plot_real_parts

NAME = "fig15"
BASE = "astrom2005"
CENTRE_OF_MASS_HEIGHT = 0.4  # m, whole bicycle with rider
FRONT_WHEEL_MASS = 3.0  # kg, twice Table 1
ROLLER_RADII = (0.3, 0.4)  # m: caption, text
SPEEDS = np.linspace(-10.0, 15.0, 201)


def adapted_parameters() -> dict:
    """The adapted bicycle (Meijaard symbols, validated)."""
    p = parameters_for_model(BASE)
    p["mF"] = FRONT_WHEEL_MASS
    p["IFyy"] = FRONT_WHEEL_MASS * p["rF"] ** 2
    p["IFxx"] = p["IFyy"] / 2.0
    mT = p["mR"] + p["mB"] + p["mH"] + p["mF"]
    # zT = (-rR mR + zB mB + zH mH - rF mF)/mT = -h  ->  zB
    p["zB"] = (-CENTRE_OF_MASS_HEIGHT * mT + p["rR"] * p["mR"] - p["zH"] * p["mH"] + p["rF"] * p["mF"]) / p["mB"]
    return validate_parameters(p, waive=set(load_parameter_set(BASE).waiver.checks))


def roller_stiffness(params: dict, radius: float) -> float:
    """k = g mT (1 - xT/w) R [N m/rad]: rear normal force times the contact's lateral shift per roll angle.

    The roll-torque feedback ``T_phi = -k phi`` on the linear Whipple FMU is the linearization of a
    toroidal rear wheel of crown radius ``radius`` [m] (see the module docstring)."""
    mT = params["mR"] + params["mB"] + params["mH"] + params["mF"]
    xT = (params["xB"] * params["mB"] + params["xH"] * params["mH"] + params["w"] * params["mF"]) / mT
    return params["g"] * mT * (1.0 - xT / params["w"]) * radius


def critical_speeds(fmu, params: dict, radius: float) -> tuple[float | None, float | None]:
    """Weave and capsize speed [m/s] of the bicycle ``params`` on a rear roller of radius
    ``radius`` [m] (0: knife edge), from linearizations of the linear Whipple FMU ``fmu`` with
    the roll-torque feedback of :func:`roller_stiffness`; None where the mode does not change
    stability below 200 m/s."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    k = roller_stiffness(params, radius)
    vw = WP.weave_speed(fmu, params, roll_stiffness=k, xtol=1e-9)
    vc = WP.capsize_speed(fmu, params, v_start=vw, roll_stiffness=k, xtol=1e-9)
    return vw, vc


def compute(fmu=None):
    """Per roller radius: eigenvalues over SPEEDS, weave speed, capsize speed (None: none below 200 m/s)."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    fmu = fmu or WP.whipple_fmu()
    params = adapted_parameters()
    systems = WP.state_spaces(fmu, params, SPEEDS)  # one FMU linearization per speed (one sweep)
    out = {}
    for R in (0.0,) + ROLLER_RADII:
        k = roller_stiffness(params, R)
        ev = np.array([WP.sorted_eigenvalues(WP.closed_loop(A, B, k)) for A, B in systems])
        out[R] = (ev, *critical_speeds(fmu, params, R))
    return params, out


def make(output: Path) -> list[Path]:
    plt = pyplot()
    _, results = compute()
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.8), sharey=True)
    for ax, R in zip(axes, ROLLER_RADII):
        ev, vw, vc = results[R]
        plot_real_parts(ax, SPEEDS, ev, vw, vc, no_capsize_note="capsize mode stable at all speeds up to 200 m/s")
        ev0, vw0, vc0 = results[0.0]
        ax.plot(SPEEDS, ev0.real.max(axis=1), color="0.5", lw=0.8, ls="--",
                label=f"max Re, knife-edge rear wheel (R = 0): stable {vw0:.2f}..{vc0:.2f} m/s")
        ax.set_title(f"crowned rear roller R = {R:g} m ({'caption' if R == 0.3 else 'text'})", fontsize=9)
        ax.set_ylim(-16, 16)
    axes[1].set_ylabel("")
    fig.suptitle("Fig. 15: adapted bicycle with rider (CoM height 0.4 m, front wheel 3 kg in the rim), crowned rear "
                 "roller\nroller modelled as restoring roll torque T_phi = -g mT (1 - xT/w) R phi "
                 "(eq (27) for a rear roller) on the linear Whipple FMU; identical to the linearization of an exact\n"
                 "toroidal rear wheel (crown radius R); the weave speeds differ from the paper's 3.9 m/s because the "
                 "adapted bicycle's data are our choice (the paper gives none)", fontsize=9)
    fig.tight_layout()
    for ax in axes:  # the layout is final: the legends measure the drawing
        place_legend(ax, outside="below", fontsize=7)
    Path(output).mkdir(parents=True, exist_ok=True)
    return [save(fig, Path(output) / f"{NAME}.png")]

