"""Nonlinear Whipple bicycle by Kane's method (sympy.physics.mechanics).

The bicycle is the four rigid bodies of Meijaard et al. (2007) -- rear wheel R, rear frame B
(with the rider rigidly attached), front frame H (fork and handlebar), front wheel F -- with
the parameters of Meijaard's Table 1 (same symbols) plus the crown radii ``tR``, ``tF`` of
toroidal wheels (``tR = tF = 0``: knife-edge wheels). Optionally (``rider=True``) the rider's
upper body U is a fifth body hinged to the rear frame about a longitudinal axis.

Axes and signs are Meijaard's: x forward, y right, z down; yaw ``psi`` positive turning right
(about the downward z axis), roll ``phi`` positive leaning right, pitch ``theta`` of the rear
frame positive nose up, steer ``delta`` positive to the right (about the downward steer axis),
wheel angles ``thetaR``, ``thetaF`` relative to their frames about the axles (pointing right, so
rolling forward means a negative wheel rate).

Configuration (nominal = upright, zero steer, zero pitch, rear contact point at the origin;
there the bodies sit where Meijaard's Table 1 puts them):

* ``A``: yaw frame, ``L``: roll frame (``L.y`` is the rear axle, ``L.z`` the downward direction
  in the rear wheel plane), ``B = L`` pitched by ``theta`` about ``L.y``: the rear frame;
* the steer axis has the direction ``(sin lam, 0, cos lam)`` in ``B`` and meets the ground at
  ``(w + c, 0, 0)`` in the nominal configuration; ``H`` is ``B`` rotated by ``delta`` about it;
* a wheel is a torus: tube (crown) radius ``t``, wheel radius ``r`` measured from the centre to
  the ground (so the centre height of the upright wheel is ``r`` for every crown radius and the
  tube centre circle has the radius ``r - t``). Its contact point is the centre plus
  ``(r - t) e + t N.z``, where ``e`` is the unit vector in the wheel plane pointing most steeply
  down; ``t = 0`` is the knife edge.

Constraints: rolling without slip makes the rear contact point's material velocity zero (the
velocities of all points follow from it); the front contact point's material velocity is zero
too -- three nonholonomic constraints (the vertical one is the time derivative of the holonomic
constraint that the front contact point lies on the ground, which fixes the pitch). The
generalized speeds are the roll rate ``u_phi``, the steer rate ``u_delta`` and the rear wheel
rate ``u_R`` (independent) and the yaw rate ``u_psi``, the pitch rate ``u_theta`` and the front
wheel rate ``u_F`` (dependent: ``u_d = A(q) u_i`` with ``A = -Bd^-1 Bi`` from the velocity
constraints ``Bi u_i + Bd u_d = 0``).

Kane's method is applied with ``sympy.physics.mechanics.KanesMethod`` in a form that keeps the
equations compact: the velocity constraints are handed to it in solved form
``u_d - A(t) u_i = 0`` with the nine entries of ``A`` as placeholder functions of time, so
KanesMethod's nonholonomic partial velocities and acceleration constraints come out in terms of
``A`` and ``dA/dt``; the generated model then computes ``B(q)``, ``A`` (Cramer's rule on the
3x3 ``Bd``) and ``dA/dt = -Bd^-1 (dBd/dt A + dBi/dt)`` as intermediate variables. The result is

    Mr(q) du_i/dt = Fr(q, u, T)        (3x3 mass matrix, eq (26) of Astrom et al. 2005)

with ``Mr = Kd [I; A]`` and ``Fr = -fd - Kd[:, dep] (dA/dt u_i)`` from KanesMethod's
``Kd u' + fd = 0`` (the dynamic equations projected on the independent speeds).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import sympy as sm
import sympy.physics.mechanics as me

#: Meijaard's parameters (Table 1) in the order of :mod:`cosim.analytic.parameters`, then the crown radii.
MEIJAARD = ("w", "c", "lam", "g", "rR", "mR", "IRxx", "IRyy", "xB", "zB", "mB", "IBxx", "IBxz", "IByy",
            "IBzz", "xH", "zH", "mH", "IHxx", "IHxz", "IHyy", "IHzz", "rF", "mF", "IFxx", "IFyy")
CROWN = ("tR", "tF")
#: Parameters of the rider's upper body (``rider=True``).
RIDER = ("mU", "xU", "hU", "lU", "IUxx", "IUxz", "IUyy", "IUzz", "kU", "cU")


@dataclass
class Derivation:
    """Symbolic result (plain sympy symbols, no functions of time).

    Names: coordinates ``q``, independent speeds ``ui``, dependent speeds ``ud`` (these are
    intermediate symbols of the model, computed from ``ud = A ui``), ``A``/``Adot`` the 3 x n_i
    placeholder matrices, ``Bi``/``Bd`` the constraint matrices (expressions of q),
    ``Bdot_i``/``Bdot_d`` their time derivatives (expressions of q, qdot), ``qdot`` the
    kinematic differential equations (expressions of q, ui, ud), ``Kd``, ``fd`` KanesMethod's
    projected dynamics ``Kd u' + fd = 0``, ``M``/``F`` the reduced system ``M ui' = F``.
    """

    rider: bool
    params: list
    inputs: list
    q: list
    ui: list
    ud: list
    A: sm.Matrix
    Adot: sm.Matrix
    Bi: sm.Matrix
    Bd: sm.Matrix
    Bdot_i: sm.Matrix
    Bdot_d: sm.Matrix
    qdot: dict
    Kd: sm.Matrix
    fd: sm.Matrix
    M: sm.Matrix
    F: sm.Matrix
    contact_rate: tuple  # (x', y') of the rear contact point
    residual: sm.Expr  # holonomic constraint: height of the front contact point (z down)
    energy: sm.Expr
    extra: dict = field(default_factory=dict)  # other outputs (name -> expression)
    seconds: float = 0.0


def derive(rider: bool = False) -> Derivation:
    """Derive the equations of motion (see the module docstring)."""
    t0 = time.perf_counter()
    t = me.dynamicsymbols._t
    P = {n: sm.Symbol(n, real=True) for n in MEIJAARD + CROWN + (RIDER if rider else ())}
    w, c, lam, g = P["w"], P["c"], P["lam"], P["g"]
    rR, rF, tR, tF = P["rR"], P["rF"], P["tR"], P["tF"]
    T_delta, T_phi = sm.symbols("T_delta T_phi", real=True)
    inputs = [T_delta, T_phi]

    psi, phi, theta, delta, thetaR, thetaF = me.dynamicsymbols("psi phi theta delta thetaR thetaF")
    u_phi, u_delta, u_R, u_psi, u_theta, u_F = me.dynamicsymbols("u_phi u_delta u_R u_psi u_theta u_F")
    q_list = [psi, phi, theta, delta, thetaR, thetaF]
    qrates = {psi: u_psi, phi: u_phi, theta: u_theta, delta: u_delta, thetaR: u_R, thetaF: u_F}
    ui = [u_phi, u_delta, u_R]
    ud = [u_psi, u_theta, u_F]
    if rider:
        beta, u_beta = me.dynamicsymbols("beta u_beta")
        q_list.append(beta)
        qrates[beta] = u_beta
        ui.append(u_beta)
        T_beta = sm.Symbol("T_beta", real=True)
        inputs.append(T_beta)
    ni, nd = len(ui), len(ud)

    # ------------------------------------------------------------------ frames
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", (psi, N.z))  # yaw
    L = A.orientnew("L", "Axis", (phi, A.x))  # roll: L.y = rear axle, L.z = down in the wheel plane
    B = L.orientnew("B", "Axis", (theta, L.y))  # rear frame (pitch)
    R = B.orientnew("R", "Axis", (thetaR, B.y))  # rear wheel
    S = B.orientnew("S", "Axis", (lam, B.y))  # S.z = steer axis (down)
    H = S.orientnew("H", "Axis", (delta, S.z))  # front frame
    Hb = H.orientnew("Hb", "Axis", (-lam, H.y))  # front frame axes parallel to B when delta = 0
    F = H.orientnew("F", "Axis", (thetaF, H.y))  # front wheel
    A.set_ang_vel(N, u_psi * N.z)
    L.set_ang_vel(A, u_phi * A.x)
    B.set_ang_vel(L, u_theta * L.y)
    R.set_ang_vel(B, u_R * B.y)
    H.set_ang_vel(S, u_delta * S.z)
    F.set_ang_vel(H, u_F * H.y)

    # ------------------------------------------------------------------ points
    PR = me.Point("PR")  # rear contact, material point of R: rolling without slip
    PR.set_vel(N, 0)
    Ro = PR.locatenew("Ro", -(rR - tR) * L.z - tR * N.z)  # rear wheel centre
    Ro.v2pt_theory(PR, N, R)
    Bo = Ro.locatenew("Bo", P["xB"] * B.x + (P["zB"] + rR) * B.z)
    Bo.v2pt_theory(Ro, N, B)
    SA = Ro.locatenew("SA", (w + c) * B.x + rR * B.z)  # steer axis meets the ground (nominal)
    SA.v2pt_theory(Ro, N, B)
    Ho = SA.locatenew("Ho", (P["xH"] - w - c) * Hb.x + P["zH"] * Hb.z)
    Ho.v2pt_theory(SA, N, H)
    Fo = SA.locatenew("Fo", -c * Hb.x - rF * Hb.z)  # front wheel centre
    Fo.v2pt_theory(SA, N, H)
    # Unit vector in the front wheel plane pointing most steeply down: e = (N.z - (N.z.H.y) H.y)/|..|
    nzhy = N.z.dot(H.y)
    e_raw = N.z - nzhy * H.y
    e_norm = sm.sqrt(1 - nzhy**2)
    PF = Fo.locatenew("PF", (rF - tF) * e_raw / e_norm + tF * N.z)  # front contact (material point of F)
    PF.v2pt_theory(Fo, N, F)

    bodies = [
        me.RigidBody("R", Ro, R, P["mR"], (me.inertia(B, P["IRxx"], P["IRyy"], P["IRxx"]), Ro)),
        me.RigidBody("B", Bo, B, P["mB"], (me.inertia(B, P["IBxx"], P["IByy"], P["IBzz"], 0, 0, P["IBxz"]), Bo)),
        me.RigidBody("H", Ho, H, P["mH"], (me.inertia(Hb, P["IHxx"], P["IHyy"], P["IHzz"], 0, 0, P["IHxz"]), Ho)),
        me.RigidBody("F", Fo, F, P["mF"], (me.inertia(H, P["IFxx"], P["IFyy"], P["IFxx"]), Fo)),
    ]
    loads = [(b.masscenter, b.mass * g * N.z) for b in bodies]
    loads += [(H, T_delta * S.z), (B, -T_delta * S.z), (B, T_phi * A.x)]
    if rider:
        # Upper body U hinged to B about the longitudinal axis B.x through (xU, 0, -hU) (nominal).
        U = B.orientnew("U", "Axis", (beta, B.x))
        U.set_ang_vel(B, u_beta * B.x)
        Hinge = Ro.locatenew("Hinge", P["xU"] * B.x + (rR - P["hU"]) * B.z)
        Hinge.v2pt_theory(Ro, N, B)
        Uo = Hinge.locatenew("Uo", -P["lU"] * U.z)
        Uo.v2pt_theory(Hinge, N, U)
        bodies.append(me.RigidBody("U", Uo, U, P["mU"],
                                   (me.inertia(U, P["IUxx"], P["IUyy"], P["IUzz"], 0, 0, P["IUxz"]), Uo)))
        hinge_torque = T_beta - P["kU"] * beta - P["cU"] * u_beta
        loads += [(Uo, P["mU"] * g * N.z), (U, hinge_torque * B.x), (B, -hinge_torque * B.x)]

    # ------------------------------------------------------------------ constraints
    all_u = ui + ud
    vPF = PF.vel(N)
    rows = [vPF.dot(A.x), vPF.dot(A.y), vPF.dot(A.z)]  # yaw-free components
    Bfull = sm.Matrix([[r.diff(u) for u in all_u] for r in rows])
    Bi, Bd = Bfull[:, :ni], Bfull[:, ni:]
    # Placeholders: ud = A(t) ui
    Aph = sm.Matrix(nd, ni, lambda i, j: me.dynamicsymbols(f"A_{ud[i].name}_{ui[j].name}"))
    vel_constraints = [ud[i] - sum(Aph[i, j] * ui[j] for j in range(ni)) for i in range(nd)]
    kd = [qq.diff(t) - qrates[qq] for qq in q_list]

    km = me.KanesMethod(N, q_ind=[qq for qq in q_list if qq is not theta], u_ind=ui, kd_eqs=kd,
                        q_dependent=[theta], configuration_constraints=[PF.pos_from(PR).dot(N.z)],
                        u_dependent=ud, velocity_constraints=vel_constraints)
    km.kanes_equations(bodies, loads)
    Kd, fd = km._k_d, km._f_d  # Kd u' + fd = 0: dynamic equations projected with the nonholonomic partials
    kdnh, fdnh = km._k_dnh, km._f_dnh  # acceleration constraints: kdnh u' + fdnh = 0

    # ------------------------------------------------------------------ plain symbols
    qs = {qq: sm.Symbol(qq.name, real=True) for qq in q_list}
    us = {u: sm.Symbol(u.name, real=True) for u in all_u}
    As = sm.Matrix(nd, ni, lambda i, j: sm.Symbol(Aph[i, j].name, real=True))
    Ads = sm.Matrix(nd, ni, lambda i, j: sm.Symbol(Aph[i, j].name + "_dot", real=True))
    rep = {}
    for i in range(nd):
        for j in range(ni):
            rep[Aph[i, j].diff(t)] = Ads[i, j]
    for i in range(nd):
        for j in range(ni):
            rep[Aph[i, j]] = As[i, j]
    rep.update({u.diff(t): sm.Symbol(u.name + "_dot", real=True) for u in all_u})
    rep.update(us)
    rep.update({qq.diff(t): us[qrates[qq]] for qq in q_list})
    rep.update(qs)

    def plain(expr):
        return me.msubs(expr, rep)

    Kd, fd, kdnh, fdnh = plain(Kd), plain(fd), plain(kdnh), plain(fdnh)
    # Acceleration constraints in the solved form: ud' = A ui' + Adot ui.
    Aui = Ads * sm.Matrix([us[u] for u in ui])
    # check that KanesMethod's acceleration constraints are exactly that form
    udot_syms = [sm.Symbol(u.name + "_dot", real=True) for u in all_u]
    acc = kdnh * sm.Matrix(udot_syms) + fdnh
    expected = sm.Matrix(udot_syms[ni:]) - As * sm.Matrix(udot_syms[:ni]) - Aui
    assert sm.simplify(acc - expected) == sm.zeros(nd, 1), "unexpected acceleration constraints"
    M = Kd[:, :ni] + Kd[:, ni:] * As
    Fr = -fd - Kd[:, ni:] * Aui

    Bi, Bd = plain(Bi), plain(Bd)
    qdot_sym = {qs[qq]: us[qrates[qq]] for qq in q_list}

    def ddt(mat):
        return mat.applyfunc(lambda e: sum(e.diff(qq) * qd for qq, qd in qdot_sym.items()))

    Bdot_i, Bdot_d = ddt(Bi), ddt(Bd)

    # Rear contact point (geometric) velocity -> x', y'
    Pgeo_rate = Ro.vel(N) + (rR - tR) * L.ang_vel_in(N).cross(L.z)
    xdot = plain(Pgeo_rate.dot(N.x))
    ydot = plain(Pgeo_rate.dot(N.y))
    # Height of the front contact point: N.z.(PF - PR) = N.z.(Fo - PR) + (rF - tF) sqrt(1 - (N.z.H.y)^2) + tF
    # (the same expression as PF.pos_from(PR).dot(N.z), written compactly).
    residual = plain(sm.trigsimp(Fo.pos_from(PR).dot(N.z)) + (rF - tF) * e_norm + tF)
    # Energy: kinetic + gravitational potential (z down), zero at the ground
    kinetic = sum(b.kinetic_energy(N) for b in bodies)
    potential = sum(-b.mass * g * b.masscenter.pos_from(PR).dot(N.z) for b in bodies)
    if rider:
        potential += P["kU"] * beta**2 / 2
    energy = plain(kinetic + potential)

    return Derivation(
        rider=rider, params=[P[n] for n in P], inputs=inputs,
        q=[qs[qq] for qq in q_list], ui=[us[u] for u in ui], ud=[us[u] for u in ud],
        A=As, Adot=Ads, Bi=Bi, Bd=Bd, Bdot_i=Bdot_i, Bdot_d=Bdot_d,
        qdot={qs[qq]: us[qrates[qq]] for qq in q_list}, Kd=Kd, fd=fd, M=M, F=Fr,
        contact_rate=(xdot, ydot), residual=residual, energy=energy,
        seconds=time.perf_counter() - t0,
    )
