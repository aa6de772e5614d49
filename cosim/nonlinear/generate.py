"""Generate the flat Modelica models of the nonlinear Whipple bicycle (with and without the rider's
upper body) from the Kane's-method derivation of :mod:`cosim.nonlinear.derivation`.

Where they go: the test oracle ``BicycleOracle`` (``tests/oracle/BicycleOracle/``: ``Whipple``
and ``WhippleRider``, a self-contained package that is not part of the exported library); the
library's component models ``Bicycle.Bicycles.Whipple`` and ``WhippleRider`` are tested against
it. They are an independent check (sympy's KanesMethod on the whole bicycle at once), not a
user-facing model, and are not exported.

Regenerate all with one command (deterministic: byte-identical output)::

    python -m cosim.nonlinear.generate            # writes tests/oracle/BicycleOracle/*
    python -m cosim.nonlinear.generate --check    # exit 1 if the files on disk differ

The generated model is written for the project's compiler (``cosim.compiler.ode``): explicit
kinematic differential equations ``der(q) = ...``; the dynamics as equations linear in
``der(u_i)`` with the mass-matrix entries ``M_ij`` and the right-hand sides ``F_i`` as
intermediate variables (the compiler solves the small linear system symbolically); common
subexpressions (``sympy.cse``) as intermediate variables ``cse1, cse2, ...``; no nonlinear
algebraic loop. The initial pitch is made consistent with the holonomic constraint by Newton
steps written out as calculated parameters.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

from cosim.analytic.parameters import load_parameters, rider_parameters
from cosim.errors import MissingExtraError

try:  # sympy is the optional extra `generate`: without it, main() refuses in one line
    import sympy as sm

    from cosim.nonlinear.derivation import CROWN, MEIJAARD, RIDER, Derivation, derive
    from cosim.nonlinear.modelica import modelica, number
except ImportError as exc:
    if exc.name is None or exc.name.split(".")[0] != "sympy":
        raise
    MISSING: MissingExtraError | None = MissingExtraError("regenerating the nonlinear Whipple models", "sympy",
                                                        "generate")
else:
    MISSING = None

ROOT = Path(__file__).resolve().parents[2]
#: The oracle package (flat generated models the component models are tested against).
ORACLE_PACKAGE = "BicycleOracle"
ORACLE_DIR = ROOT / "tests" / "oracle" / ORACLE_PACKAGE
COMMAND = "python -m cosim.nonlinear.generate"
NEWTON_STEPS = 6

# ---------------------------------------------------------------------------- parameters

# The oracle's defaults come from the same data files as the Modelica records (cosim/params/):
# the benchmark bicycle of Meijaard et al. (2007), Table 1, and for the rider the benchmark split
# into rear frame (bicycle + lower body) and upper body U, such that with the hinge locked upright
# rear frame + U is exactly the benchmark's rear frame B (parallel-axis theorem).
BENCHMARK = load_parameters("benchmark")


DESCRIPTIONS = {
    "w": ("Length", "Wheelbase w", "min = 1e-6"),
    "c": ("Length", "Trail c (positive: front contact point behind the steer axis)", ""),
    "lam": ("Angle", "Steer-axis tilt lam from the vertical (pi/2 - head angle)",
            "min = -1.5707963267948966, max = 1.5707963267948966"),
    "g": ("Acceleration", "Gravitational acceleration g", "min = 0"),
    "rR": ("Length", "Rear wheel radius rR (centre height of the upright wheel)", "min = 1e-6"),
    "mR": ("Mass", "Rear wheel mass mR", "min = 0"),
    "IRxx": ("MomentOfInertia", "Rear wheel diametral inertia IRxx = IRzz", "min = 0"),
    "IRyy": ("MomentOfInertia", "Rear wheel spin inertia IRyy", "min = 0"),
    "xB": ("Position", "Rear frame centre of mass: x coordinate xB (forward)", ""),
    "zB": ("Position", "Rear frame centre of mass: z coordinate zB (down; negative above the ground)", "max = 0"),
    "mB": ("Mass", "Rear frame mass mB", "min = 0"),
    "IBxx": ("MomentOfInertia", "Rear frame inertia-tensor element IBxx about its centre of mass", "min = 0"),
    "IBxz": ("MomentOfInertia", "Rear frame inertia-tensor element IBxz about its centre of mass", ""),
    "IByy": ("MomentOfInertia", "Rear frame inertia-tensor element IByy about its centre of mass", "min = 0"),
    "IBzz": ("MomentOfInertia", "Rear frame inertia-tensor element IBzz about its centre of mass", "min = 0"),
    "xH": ("Position", "Front frame centre of mass: x coordinate xH (forward)", ""),
    "zH": ("Position", "Front frame centre of mass: z coordinate zH (down; negative above the ground)", "max = 0"),
    "mH": ("Mass", "Front frame mass mH", "min = 0"),
    "IHxx": ("MomentOfInertia", "Front frame inertia-tensor element IHxx about its centre of mass", "min = 0"),
    "IHxz": ("MomentOfInertia", "Front frame inertia-tensor element IHxz about its centre of mass", ""),
    "IHyy": ("MomentOfInertia", "Front frame inertia-tensor element IHyy about its centre of mass", "min = 0"),
    "IHzz": ("MomentOfInertia", "Front frame inertia-tensor element IHzz about its centre of mass", "min = 0"),
    "rF": ("Length", "Front wheel radius rF (centre height of the upright wheel)", "min = 1e-6"),
    "mF": ("Mass", "Front wheel mass mF", "min = 0"),
    "IFxx": ("MomentOfInertia", "Front wheel diametral inertia IFxx = IFzz", "min = 0"),
    "IFyy": ("MomentOfInertia", "Front wheel spin inertia IFyy", "min = 0"),
    "tR": ("Length", "Rear tyre crown radius tR (toroidal wheel; 0: knife edge)", "min = 0"),
    "tF": ("Length", "Front tyre crown radius tF (toroidal wheel; 0: knife edge)", "min = 0"),
    "mU": ("Mass", "Upper body mass mU", "min = 0"),
    "xU": ("Position", "Hinge (hip) axis and upper body centre of mass: x coordinate xU (forward)", ""),
    "hU": ("Length", "Height hU of the hinge (hip) axis above the ground (upright bicycle)", ""),
    "lU": ("Length", "Height lU of the upper body centre of mass above the hinge axis", ""),
    "IUxx": ("MomentOfInertia", "Upper body inertia-tensor element IUxx about its centre of mass", "min = 0"),
    "IUxz": ("MomentOfInertia", "Upper body inertia-tensor element IUxz about its centre of mass", ""),
    "IUyy": ("MomentOfInertia", "Upper body inertia-tensor element IUyy about its centre of mass", "min = 0"),
    "IUzz": ("MomentOfInertia", "Upper body inertia-tensor element IUzz about its centre of mass", "min = 0"),
    "kU": ("RotationalSpringConstant", "Passive stiffness kU of the hip hinge (lean torque per lean angle)", "min = 0"),
    "cU": ("RotationalDampingConstant", "Passive damping cU of the hip hinge (lean torque per lean rate)", "min = 0"),
}

# Types the library's Units package does not have: Real with the attributes of Modelica.Units.SI.
INLINE = {
    "RotationalSpringConstant": 'final quantity = "RotationalSpringConstant", final unit = "N.m/rad"',
    "RotationalDampingConstant": 'final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad"',
    "AngularAcceleration": 'final quantity = "AngularAcceleration", final unit = "rad/s2"',
    "Energy": 'final quantity = "Energy", final unit = "J"',
}

# The library's Units types written out for the oracle package, which must not depend on the
# library it checks (and cannot see it: a Modelica library folder holds one top-level package).
UNITS = {
    "Length": 'final quantity = "Length", final unit = "m"',
    "Position": 'final quantity = "Length", final unit = "m"',
    "Angle": 'final quantity = "Angle", final unit = "rad", displayUnit = "deg"',
    "AngularVelocity": 'final quantity = "AngularVelocity", final unit = "rad/s"',
    "Acceleration": 'final quantity = "Acceleration", final unit = "m/s2"',
    "Velocity": 'final quantity = "Velocity", final unit = "m/s"',
    "Mass": 'final quantity = "Mass", final unit = "kg", min = 0',
    "MomentOfInertia": 'final quantity = "MomentOfInertia", final unit = "kg.m2"',
    "Torque": 'final quantity = "Torque", final unit = "N.m"',
}


def _declare(prefix: str, kind: str, name: str, modifiers: str, value: str | None, description: str) -> str:
    """A declaration with the unit type ``kind`` written out as Real with its attributes."""
    attributes = INLINE.get(kind) or UNITS[kind]
    if "min = " in attributes and "min = " in modifiers:  # the declaration's bound replaces the type's
        attributes = attributes.replace(", min = 0", "")
    modifiers = ", ".join(m for m in (attributes, modifiers) if m)
    type_text = "Real"
    mods = f"({modifiers})" if modifiers else ""
    binding = f" = {value}" if value is not None else ""
    return f"  {prefix}{type_text} {name}{mods}{binding} \"{description}\";"


# ---------------------------------------------------------------------------- model text

def _named_equations(d: Derivation):
    """(name, expression) of every named intermediate variable, in dependency-free order."""
    ni, nd = len(d.ui), len(d.ud)
    rows = ("x", "y", "z")
    named = []
    Bi_s = sm.Matrix(nd, ni, lambda i, j: sm.Symbol(f"B_{rows[i]}_{d.ui[j].name}", real=True))
    Bd_s = sm.Matrix(nd, nd, lambda i, j: sm.Symbol(f"B_{rows[i]}_{d.ud[j].name}", real=True))
    Bdi_s = sm.Matrix(nd, ni, lambda i, j: sm.Symbol(f"Bdot_{rows[i]}_{d.ui[j].name}", real=True))
    Bdd_s = sm.Matrix(nd, nd, lambda i, j: sm.Symbol(f"Bdot_{rows[i]}_{d.ud[j].name}", real=True))
    for S, E in ((Bi_s, d.Bi), (Bd_s, d.Bd), (Bdi_s, d.Bdot_i), (Bdd_s, d.Bdot_d)):
        for s, e in zip(S, E):
            named.append((s, e))
    # Inverse of Bd by the adjugate (Bd is 3 x 3).
    det = sm.Symbol("det_Bd", real=True)
    named.append((det, Bd_s.det(method="berkowitz")))
    adj = Bd_s.adjugate()
    inv = adj / det
    A_expr = -inv * Bi_s
    for s, e in zip(d.A, A_expr):
        named.append((s, e))
    Adot_expr = -inv * (Bdd_s * d.A + Bdi_s)
    for s, e in zip(d.Adot, Adot_expr):
        named.append((s, e))
    for k, s in enumerate(d.ud):
        named.append((s, sum(d.A[k, j] * d.ui[j] for j in range(ni))))
    M_s = sm.Matrix(ni, ni, lambda i, j: sm.Symbol(f"M_{i + 1}{j + 1}", real=True))
    F_s = sm.Matrix(ni, 1, lambda i, j: sm.Symbol(f"F_{i + 1}", real=True))
    for s, e in zip(M_s, d.M):
        named.append((s, e))
    for s, e in zip(F_s, d.F):
        named.append((s, e))
    return named, M_s, F_s


def _zero_entries(named):
    """Drop named variables that are identically zero (replace them by 0 everywhere)."""
    zero = {s: 0 for s, e in named if e == 0}
    kept = [(s, e.xreplace(zero) if zero else e) for s, e in named if s not in zero]
    return kept, zero


def model_text(rider: bool = False, d: Derivation | None = None) -> str:
    """The Modelica text of the generated model in the self-contained oracle package (which writes
    the unit types out)."""
    d = d or derive(rider=rider)
    name = "WhippleRider" if rider else "Whipple"
    defaults = rider_parameters() if rider else BENCHMARK
    defaults = {**defaults, "tR": 0.0, "tF": 0.0}
    ni = len(d.ui)
    sym = {s.name: s for s in d.params + d.q + d.ui + d.ud + d.inputs}

    named, M_s, F_s = _named_equations(d)
    named, zero = _zero_entries(named)
    x_s, y_s = sm.symbols("x y", real=True)
    outputs = {
        "E": d.energy,
        "residual": d.residual,
    }
    kinematic = {"x": d.contact_rate[0], "y": d.contact_rate[1]}
    speed = sm.Symbol("v", real=True)
    outputs["v"] = d.contact_rate[0] * sm.cos(sym["psi"]) + d.contact_rate[1] * sm.sin(sym["psi"])
    rhs = [e for _, e in named] + list(outputs.values()) + list(kinematic.values())
    rhs = [e.xreplace(zero) if zero else e for e in rhs]
    replacements, reduced = sm.cse(rhs, symbols=sm.numbered_symbols("cse", start=1), order="none")
    n_named = len(named)
    named_red = reduced[:n_named]
    out_red = dict(zip(outputs, reduced[n_named:n_named + len(outputs)]))
    kin_red = dict(zip(kinematic, reduced[n_named + len(outputs):]))

    L = []
    add = L.append
    rider_text = " with a leaning rider (upper body hinged to the rear frame)" if rider else ""
    add(f"within {ORACLE_PACKAGE};")
    add(f"model {name} \"Nonlinear Whipple bicycle{rider_text}, eq (26): Kane's method, rolling without slip, "
        "toroidal wheels (Meijaard 2007 parameters)\"")
    add("  // GENERATED FILE - DO NOT EDIT.")
    add("  // Generated from the Kane's-method derivation in cosim/nonlinear/derivation.py by")
    add("  // cosim/nonlinear/generate.py; regenerate (deterministic, byte-identical) with:")
    add(f"  //   {COMMAND}")
    add("  // Common subexpressions (sympy.cse) are the intermediate variables cse1, cse2, ...")
    add("  // Parameters of the bicycle: the symbols of Meijaard et al. (2007), Table 1; defaults: "
        + ("the benchmark bicycle split into rear frame + upper body." if rider else "the benchmark bicycle."))
    order = list(MEIJAARD) + list(CROWN) + (list(RIDER) if rider else [])
    for p in order:
        kind, desc, mods = DESCRIPTIONS[p]
        add(_declare("parameter ", kind, p, mods, number(defaults[p]), desc))
    # Initial state
    init = [
        ("x0", "Position", "Initial x coordinate of the rear contact point", 0.0),
        ("y0", "Position", "Initial y coordinate of the rear contact point (right)", 0.0),
        ("psi0", "Angle", "Initial yaw angle", 0.0),
        ("phi0", "Angle", "Initial roll angle", 0.0),
        ("delta0", "Angle", "Initial steer angle", 0.0),
        ("thetaR0", "Angle", "Initial rear wheel angle", 0.0),
        ("thetaF0", "Angle", "Initial front wheel angle", 0.0),
    ]
    if rider:
        init.append(("beta0", "Angle", "Initial lean angle of the upper body relative to the rear frame", 0.0))
    init += [
        ("u_phi0", "AngularVelocity", "Initial roll rate", 0.0),
        ("u_delta0", "AngularVelocity", "Initial steer rate", 0.0),
        ("u_R0", "AngularVelocity", "Initial rear wheel rate (relative to the rear frame); forward speed "
                                    "v = -u_R0*rR when upright (default: 5 m/s)", -5.0 / 0.3),
    ]
    if rider:
        init.append(("u_beta0", "AngularVelocity", "Initial lean rate of the upper body", 0.0))
    init.append(("theta_guess", "Angle", "Starting value of the Newton iteration for the initial pitch", 0.0))
    for n, kind, desc, value in init:
        add(_declare("parameter ", kind, n, "", number(value), desc))
    # Newton steps for the initial pitch: residual(phi0, theta, delta0) = 0
    res = d.residual
    dres = sm.diff(res, sym["theta"])
    prev = sym_guess = sm.Symbol("theta_guess", real=True)
    subs0 = {sym["phi"]: sm.Symbol("phi0", real=True), sym["delta"]: sm.Symbol("delta0", real=True)}
    if rider:
        subs0[sym["beta"]] = sm.Symbol("beta0", real=True)
    for k in range(1, NEWTON_STEPS + 1):
        cur = sm.Symbol(f"theta0_{k}", real=True)
        s = {**subs0, sym["theta"]: prev}
        step = prev - res.xreplace(s) / dres.xreplace(s)
        add(_declare("final parameter ", "Angle", cur.name, "", modelica(step),
                     f"Initial pitch, Newton step {k} on the holonomic constraint"))
        prev = cur
    del sym_guess
    add(_declare("final parameter ", "Angle", "theta0", "", prev.name,
                 f"Initial pitch consistent with the holonomic constraint ({NEWTON_STEPS} Newton steps)"))

    add(_declare("input ", "Torque", "T_delta", "", None,
                 "Steer torque T_delta between rear frame and front frame, positive tending to steer right"))
    add(_declare("input ", "Torque", "T_phi", "", None,
                 "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)"))
    if rider:
        add(_declare("input ", "Torque", "T_beta", "", None,
                     "Lean torque T_beta of the rider between rear frame and upper body, positive tending to lean the upper body right"))
    states = [
        ("x", "Position", "x coordinate (forward at yaw 0) of the rear contact point", "x0"),
        ("y", "Position", "y coordinate (right at yaw 0) of the rear contact point: lateral position", "y0"),
        ("psi", "Angle", "Yaw angle psi of the rear frame, positive turning right", "psi0"),
        ("phi", "Angle", "Roll angle phi of the rear frame, positive leaning right", "phi0"),
        ("theta", "Angle", "Pitch angle theta of the rear frame, positive nose up (0: upright, zero steer)", "theta0"),
        ("delta", "Angle", "Steer angle delta, positive steering right", "delta0"),
        ("thetaR", "Angle", "Rear wheel angle relative to the rear frame", "thetaR0"),
        ("thetaF", "Angle", "Front wheel angle relative to the front frame", "thetaF0"),
    ]
    if rider:
        states.append(("beta", "Angle", "Lean angle beta of the upper body relative to the rear frame, positive leaning right", "beta0"))
    states += [
        ("u_phi", "AngularVelocity", "Roll rate (independent speed)", "u_phi0"),
        ("u_delta", "AngularVelocity", "Steer rate (independent speed)", "u_delta0"),
        ("u_R", "AngularVelocity", "Rear wheel rate relative to the rear frame (independent speed; negative rolling forward)", "u_R0"),
    ]
    if rider:
        states.append(("u_beta", "AngularVelocity", "Lean rate of the upper body (independent speed)", "u_beta0"))
    for n, kind, desc, start in states:
        add(_declare("output ", kind, n, f"start = {start}, fixed = true", None, desc))
    dep = [("u_psi", "Yaw rate (dependent speed)"), ("u_theta", "Pitch rate (dependent speed)"),
           ("u_F", "Front wheel rate relative to the front frame (dependent speed)")]
    for n, desc in dep:
        add(_declare("output ", "AngularVelocity", n, "", None, desc))
    for n, desc in dep:
        add(_declare("output ", "AngularAcceleration", n + "_dot", "", None, f"Time derivative of {n}"))
    add(_declare("output ", "Velocity", "v", "", None,
                 "Forward speed of the rear contact point (velocity along the heading)"))
    add(_declare("output ", "Energy", "E", "", None,
                 "Total energy: kinetic + gravitational potential (zero at the ground)" +
                 (" + hinge spring" if rider else "")))
    add(_declare("output ", "Length", "residual", "", None,
                 "Holonomic constraint residual: height of the front contact point above the ground (should be 0)"))
    add("protected")
    descs = {}
    for s, _ in named:
        n = s.name
        if n.startswith("Bdot_"):
            descs[n] = "Time derivative of the velocity-constraint coefficient B_" + n[5:]
        elif n.startswith("B_"):
            r, u = n[2], n[4:]
            descs[n] = f"Velocity constraint: coefficient of {u} in the {r} velocity of the front contact point (yaw frame)"
        elif n == "det_Bd":
            descs[n] = "Determinant of the dependent-speed block Bd of the velocity constraints"
        elif n.startswith("A_") and n.endswith("_dot"):
            descs[n] = "Time derivative of " + n[:-4]
        elif n.startswith("A_"):
            descs[n] = "Dependent-speed coefficient: u_d = A u_i, A = -Bd^-1 Bi"
        elif n.startswith("M_"):
            descs[n] = f"Mass matrix M (reduced to the independent speeds), element ({n[2]}, {n[3]})"
        elif n.startswith("F_"):
            descs[n] = f"Generalized forces and velocity terms F (reduced), element {n[2]}"
    for s, _ in named:
        if s.name not in (u.name for u in d.ud):
            add(f"  Real {s.name} \"{descs.get(s.name, '')}\";")
    for s, _ in replacements:
        add(f"  Real {s.name};")
    add("equation")
    add("  // Common subexpressions")
    for s, e in replacements:
        add(f"  {s.name} = {modelica(e)};")
    add("  // Velocity constraints Bi u_i + Bd u_d = 0 (front contact point at rest), dependent speeds u_d = A u_i,")
    add("  // dA/dt = -Bd^-1 (dBd/dt A + dBi/dt)")
    for (s, _), e in zip(named, named_red):
        add(f"  {s.name} = {modelica(e)};")
    add("  // Kinematic differential equations")
    qdot = {s.name: u for s, u in d.qdot.items()}
    for n in [q.name for q in d.q]:
        add(f"  der({n}) = {qdot[n].name};")
    for n, e in kin_red.items():
        add(f"  der({n}) = {modelica(e)};")
    add("  // Dynamic equations M du_i/dt = F (linear in the accelerations)")
    for i in range(ni):
        terms = " + ".join(f"{M_s[i, j].name}*der({d.ui[j].name})" for j in range(ni) if M_s[i, j] not in zero)
        add(f"  {terms} = {F_s[i].name};")
    add("  // Accelerations of the dependent speeds")
    for k, u in enumerate(d.ud):
        terms = " + ".join(f"{d.A[k, j].name}*der({d.ui[j].name}) + {d.Adot[k, j].name}*{d.ui[j].name}"
                           for j in range(ni) if d.A[k, j] not in zero)
        add(f"  {u.name}_dot = {terms};")
    add("  // Outputs")
    for n, e in out_red.items():
        add(f"  {n} = {modelica(e)};")
    add("  annotation(")
    add("    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-10, Interval = 0.01),")
    add("    __Cosim(export = true),")
    add("    Documentation(info = \"<html>")
    add(_documentation(rider))
    add("</html>\"));")
    add(f"end {name};")
    del speed, x_s, y_s
    return "\n".join(L) + "\n"


def _documentation(rider: bool) -> str:
    text = """<p>GENERATED by <code>python -m cosim.nonlinear.generate</code> from the derivation in
<code>cosim/nonlinear/derivation.py</code> (sympy.physics.mechanics, Kane's method); do not edit.</p>
<p>The nonlinear Whipple bicycle: rear wheel R, rear frame B (rider rigidly attached), front frame H,
front wheel F with the parameters of Meijaard et al. (2007), Table 1, and toroidal wheels with crown radii
tR, tF (0: knife edge; rR, rF are the centre heights of the upright wheels). Rolling without slip on
flat ground: the front contact point's height is a holonomic constraint (it fixes the pitch), the
contact points' material velocities vanish (nonholonomic). States: rear contact point x, y; yaw psi,
roll phi, pitch theta, steer delta, wheel angles thetaR, thetaF; the independent speeds roll rate u_phi,
steer rate u_delta and rear wheel rate u_R. Dependent speeds (yaw rate u_psi, pitch rate u_theta, front
wheel rate u_F) follow from the velocity constraints. The dynamics are eq (26) of Astrom, Klein and
Lennartsson (2005), M(q) du/dt = F(q, u, T), with a 3x3 mass matrix.</p>
<p>Signs are Meijaard's: x forward, y right, z down; roll positive leaning right, steer positive to
the right, yaw positive turning right, pitch positive nose up; wheel rates are negative when rolling
forward (forward speed v = -u_R rR upright).</p>
<p>The pitch is integrated with the differentiated constraint; the output <code>residual</code> (height
of the front contact point) shows the drift, <code>E</code> the total energy (conserved without
inputs). The initial pitch is computed from phi0, delta0 by Newton steps.</p>"""
    if rider:
        text += """
<p>The rider's upper body U is a fifth rigid body hinged to the rear frame about the longitudinal axis
through (xU, 0, hU above the ground); its centre of mass lies lU above the hinge. A passive spring kU
and damper cU act in the hinge together with the rider's lean torque T_beta (input). With the default
parameters and the hinge locked upright, rear frame + upper body is the benchmark's rear frame.</p>"""
    return text


# ---------------------------------------------------------------------------- main

def targets(names=None):
    """Model name -> rider? of the generated models."""
    models = {"Whipple": False, "WhippleRider": True}
    return {n: models[n] for n in (names or list(models))}


def oracle_package_text() -> str:
    """``package.mo`` of the oracle package."""
    return (f"within;\npackage {ORACLE_PACKAGE} \"Test oracle: the flat nonlinear Whipple bicycles generated by "
            f"Kane's method (sympy)\"\n  // GENERATED FILE - DO NOT EDIT (regenerate with: {COMMAND})\n"
            "  annotation(Documentation(info = \"<html><p>Not part of the exported library: the flat models "
            "generated from <code>cosim/nonlinear/derivation.py</code>, written out with the unit types "
            "inline so that the package needs no other library. The component models of "
            "<code>Bicycle</code> are tested against them (<code>tests/test_component_bicycle.py</code>)."
            f"</p></html>\"));\nend {ORACLE_PACKAGE};\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m cosim.nonlinear.generate", description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="*", metavar="MODEL", help="Whipple and/or WhippleRider (default: both)")
    parser.add_argument("-o", "--output", default=None,
                        help="write every model into this one folder, within the oracle package "
                             f"(default: {ORACLE_DIR.relative_to(ROOT)})")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 if a file on disk differs")
    args = parser.parse_args(argv)
    if MISSING is not None:
        print(f"{parser.prog}: error: {MISSING}", file=sys.stderr)
        return 2
    unknown = sorted(set(args.models) - set(targets()))
    if unknown:
        parser.error(f"unknown model(s) {', '.join(unknown)}; choose from {', '.join(targets())}")
    if os.environ.get("PYTHONHASHSEED") != "0":
        # sympy's cse and printing are deterministic for a fixed hash seed: pin it.
        env = {**os.environ, "PYTHONHASHSEED": "0"}
        return subprocess.call([sys.executable, "-m", "cosim.nonlinear.generate", *(argv if argv is not None else sys.argv[1:])],
                               env=env)
    status = 0

    def emit(path: Path, text: str, t0: float) -> int:
        if args.check:
            same = path.is_file() and path.read_text(encoding="utf-8") == text
            print(f"{path}: {'up to date' if same else 'DIFFERS'} ({time.perf_counter() - t0:.1f} s)")
            return 0 if same else 1
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        print(f"wrote {path} ({len(text.splitlines())} lines, {time.perf_counter() - t0:.1f} s)")
        return 0

    folder = ORACLE_DIR if args.output is None else Path(args.output)
    for name, rider in targets(args.models).items():
        t0 = time.perf_counter()
        status |= emit(folder / f"{name}.mo", model_text(rider, derive(rider=rider)), t0)
    if args.output is None:
        status |= emit(ORACLE_DIR / "package.mo", oracle_package_text(), time.perf_counter())
        status |= emit(ORACLE_DIR / "package.order", "Whipple\nWhippleRider\n", time.perf_counter())
    return status


if __name__ == "__main__":
    sys.exit(main())
