"""The rider's upper body on two hinges (``Bicycle.Bicycles.WhippleRiderTwist``): lean about the
rear frame's longitudinal axis and twist about the upper body's vertical axis, each joint owning
its coordinate. The model is ``WhippleRider`` with ``n = 8`` and another hip; no other component
changes.

* With the twist hinge held (a ``Joints.LockedRevolute`` in its place, at zero twist) the
  derivatives of every state of ``WhippleRider`` and its outputs equal those of ``WhippleRider``
  (lean free) at the same random admissible states, with the tolerances of
  tests/test_component_rider.py (normwise 1e-12); with both hinges held they equal those of
  ``WhippleRider`` with its ``LockedHinge``. The held twist neither moves nor accelerates.
* With the twist free the same states give other accelerations (the comparison can fail).
* ``cosim linearize`` at 5 m/s reduces the model exactly and names its zero eigenvalues.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import variant_library
from cosim.analytic.parameters import rider_parameters
from cosim.compiler.build import build_model
from cosim.compiler.library import load_library
from cosim.nonlinear.model import Bicycle
from test_component_bicycle import N_STATES, OUTPUTS
from test_component_rider import UPPER_BODY, Errors, _rider_states

pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.WhippleRiderTwist"
HINGE = '''model {name} "Test variant: the hip of LeanTwistHinge with {what}"
  extends Bicycle.Mechanics.Rider.PartialHinge;
  parameter Real c(final unit = "N.m/rad") = 0 "Lean stiffness";
  parameter Real d(final unit = "N.m.s/rad") = 0 "Lean damping";
  Bicycle.Mechanics.Joints.{lean} lean(n = n, k = k, nx = 1, ny = 0, nz = 0, angle0 = angle0{lean_mods});
  Bicycle.Mechanics.Joints.LockedRevolute twist(n = n, k = k + 1, nx = 0, ny = 0, nz = 1);
equation
  angle = lean.angle;
  omega = lean.omega;
  connect(frame_a, lean.frame_a);
  connect(lean.frame_b, twist.frame_a);
  connect(twist.frame_b, frame_b);
  connect(tau_in, lean.tau_in);
  twist.tau_in = 0;
end {name};'''
VARIANTS = {
    "TwistHeldHinge": HINGE.format(name="TwistHeldHinge", what="the twist held", lean="ActuatedRevolute",
                                   lean_mods=", omega0 = omega0, c = c, d = d"),
    "BothHeldHinge": HINGE.format(name="BothHeldHinge", what="both hinges held", lean="LockedRevolute", lean_mods=""),
    "TwistHeld": 'model TwistHeld "Test variant: WhippleRiderTwist with the twist held"\n'
                 '  extends Bicycle.Bicycles.WhippleRider(n = 8, redeclare TestVariants.TwistHeldHinge hip(c = kU, d = cU));\n'
                 'end TwistHeld;',
    "BothHeld": 'model BothHeld "Test variant: WhippleRiderTwist with both hinges held"\n'
                '  extends Bicycle.Bicycles.WhippleRider(n = 8, redeclare TestVariants.BothHeldHinge hip);\n'
                'end BothHeld;',
    "RiderLocked": 'model RiderLocked "Test variant: WhippleRider with its hinge locked"\n'
                   '  extends Bicycle.Bicycles.WhippleRider(redeclare Bicycle.Mechanics.Rider.LockedHinge hip);\n'
                   'end RiderLocked;',
}
TWIST = ["twist", "u_twist"]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = Path(os.environ["COSIM_FMU_DIR"])
    variants = variant_library(tmp_path_factory.mktemp("rider-twist"), VARIANTS)
    fmus = {name: build_model(f"TestVariants.{name}", out, variants).fmu for name in ("TwistHeld", "BothHeld", "RiderLocked")}
    fmus["rider"] = build_model("Bicycle.Bicycles.WhippleRider", out, load_library()).fmu
    fmus["twist"] = build_model(MODEL, out, load_library()).fmu
    return fmus


def _held_twist_equals(built, variant: str, reference: str, label: str) -> None:
    params = {**rider_parameters(), **UPPER_BODY}
    with Bicycle(built[variant], params) as model, Bicycle(built[reference], params) as rider:
        ix = model.index
        assert set(rider.states) <= set(model.states) and len(model.states) == len(rider.states) + 2
        rows = [ix[s] for s in rider.states]
        errors = Errors([f"der({s})" for s in rider.states] + OUTPUTS)
        rng = np.random.default_rng(21)
        for x_rider, inputs in _rider_states(rider, rng, N_STATES):
            if reference != "rider":  # the lean held upright, at rest
                x_rider[rider.index["beta"]] = x_rider[rider.index["u_beta"]] = 0.0
            x = np.zeros(model.nx)
            x[rows] = x_rider
            rider.set_inputs(inputs)
            model.set_inputs(inputs)
            d = model.derivatives(x)
            held = [k for k in range(model.nx) if k not in rows]
            assert np.all(np.abs(d[held]) <= 1e-14), f"{label}: the held twist moves: {d[held]}"
            errors.add(np.concatenate([d[rows], model.get(OUTPUTS, x)]),
                       np.concatenate([rider.derivatives(x_rider), rider.get(OUTPUTS, x_rider)]))
    errors.check(label)


def test_twist_held_equals_whipple_rider(built):
    _held_twist_equals(built, "TwistHeld", "rider", "twist held = WhippleRider")


def test_both_held_equals_whipple_rider_locked(built):
    _held_twist_equals(built, "BothHeld", "RiderLocked", "both held = WhippleRider with LockedHinge")


def test_free_twist_differs_from_held(built):
    """The comparisons above can fail: with the twist free and twisted, the same states give
    other accelerations."""
    params = {**rider_parameters(), **UPPER_BODY}
    with Bicycle(built["twist"], params) as free, Bicycle(built["TwistHeld"], params) as held:
        assert [s for s in free.states if s in TWIST] == TWIST
        x, inputs = next(_rider_states(free, np.random.default_rng(22), 1))
        free.set_inputs({**inputs, "T_twist": 0.0})
        held.set_inputs(inputs)
        x_held = x.copy()
        x[free.index["twist"]] = 0.3
        k = free.index["u_phi"]
        assert abs(free.derivatives(x)[k] - held.derivatives(x_held)[k]) > 1e-3


def test_linearize_at_5_m_per_s_names_zero_eigenvalues(built):
    def linearize(*extra):
        run = subprocess.run([sys.executable, "-m", "cosim", "linearize", str(built["twist"]), "--speed", "5", *extra],
                             capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stderr
        return run.stdout

    text = linearize()
    for name in ("theta", "u_R", "x", "y", "psi", "thetaR", "thetaF"):
        assert name in text, f"the zero eigenvalue of {name} is not named:\n{text}"
    steady = json.loads(linearize("--json"))
    steady = steady.get("steady_motion", steady)
    assert {z["state"] for z in steady["zero_eigenvalues"]} == {"theta", "u_R", "x", "y", "psi", "thetaR", "thetaF"}
    assert set(steady["states"]) == {"phi", "delta", "beta", "twist", "u_phi", "u_delta", "u_beta", "u_twist"}
    assert len(steady["eigenvalues"]) == 8
