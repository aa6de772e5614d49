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
rounding (relative 1e-15) and so the same weave speeds. The other differences of a torus from
a knife edge (the roll axis through the crown centre, the moving contact point in the rolling
constraint and in the steering geometry) leave the linearized equations unchanged: only K0[0,0]
changes, by exactly the term above (``tests/test_fig5_fig15.py`` checks the matrices at several
speeds and the weave speeds by root finding on the torus FMU).

Adapted bicycle (the paper gives no numbers; our choice): ``cosim/params/adapted/fig15.toml``
(:mod:`cosim.analytic.roller`, the same bicycle as the app's "crowned roller"): a bicycle with
rider whose centre of mass is 0.4 m high, with a heavy front wheel (3 kg in the rim), found by a
search over physically admissible data so that it reproduces the paper's statements: weave speed
3.880 m/s (R = 0.3 m) and 3.935 m/s (R = 0.4 m), capsize mode stable at every speed, real parts
inside those of Figure 9 at every speed from 0 to 12 m/s (docs/figures/README.md). Every
eigenvalue comes from an FMU linearization of ``Bicycle.Bicycles.WhippleLinear``; plotted as in
Fig 9 (dot real, o complex, red unstable, blue stable), with the envelope of Figure 9's real
parts (the paper's bicycle with rider, ``astrom2005``) for the comparison the caption makes.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend
from cosim.analytic import roller
from cosim.analytic.parameters import parameters_for_model
from cosim.figures.fig9 import plot_real_parts

NAME = "fig15"
FIG9 = "astrom2005"  # the bicycle of Figure 9, with which the caption compares
ROLLER_RADII = roller.RADII  # m: caption, text
SPEEDS = np.linspace(-10.0, 15.0, 201)
adapted_parameters = roller.adapted_parameters
roller_stiffness = roller.roller_stiffness


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
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    plt = pyplot()
    fmu = WP.whipple_fmu()
    _, results = compute(fmu)
    fig9 = np.array([WP.sorted_eigenvalues(A) for A, _ in WP.state_spaces(fmu, parameters_for_model(FIG9), SPEEDS)])
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.8), sharey=True)
    for ax, R in zip(axes, ROLLER_RADII):
        ev, vw, vc = results[R]
        plot_real_parts(ax, SPEEDS, ev, vw, vc, no_capsize_note="capsize mode stable at all speeds up to 200 m/s")
        forward = SPEEDS >= 0.0  # the caption compares riding forwards
        ax.fill_between(SPEEDS[forward], fig9.real.min(axis=1)[forward], fig9.real.max(axis=1)[forward],
                        color="0.85", zorder=0, label="range of the real parts in Fig. 9, v >= 0 "
                        "(the paper's bicycle with rider)")
        ev0, vw0, vc0 = results[0.0]
        ax.plot(SPEEDS, ev0.real.max(axis=1), color="0.5", lw=0.8, ls="--",
                label=f"max Re, knife-edge rear wheel (R = 0): stable {vw0:.2f}..{vc0:.2f} m/s")
        ax.set_title(f"crowned rear roller R = {R:g} m ({'caption' if R == 0.3 else 'text'}): "
                     f"weave speed {vw:.2f} m/s", fontsize=9)
        ax.set_ylim(-16, 16)
    axes[1].set_ylabel("")
    fig.suptitle("Fig. 15: adapted bicycle with rider (our data, cosim/params/adapted/fig15.toml: centre of mass "
                 "0.4 m high, front wheel 3 kg in the rim), crowned rear roller;\n"
                 "the roller modelled as a restoring roll torque T_phi = -g mT (1 - xT/w) R phi (eq (27) for a "
                 "rear roller) on the linear Whipple FMU, the exact linearization of a toroidal rear wheel;\n"
                 "paper: weave stable from 3.9 m/s, capsize stable at all speeds, real parts smaller than in Fig. 9 "
                 "(grey band)", fontsize=9)
    fig.tight_layout()
    for ax in axes:  # the layout is final: the legends measure the drawing
        place_legend(ax, outside="below", fontsize=7)
    Path(output).mkdir(parents=True, exist_ok=True)
    return [save(fig, Path(output) / f"{NAME}.png")]
