"""The nonlinear bicycle at a singular configuration.

The knowledge of where a model is singular lives in the model: ``Bicycle.Bicycles.Whipple`` and
``WhippleRider`` declare ``annotation(__Cosim(singular(delta(...), phi(...))))`` (steer and roll
at +-90 deg), read by :func:`cosim.compiler.catalog.singular_configurations` (also for a variant
that extends them). When a run fails there, `cosim simulate` says so in one line: the time, the
variable and its value, the model, the rows kept -- and exits 4 without a traceback.

The falling bicycle is the case of tests/test_runtime_c.py (``FALLING``: 5 m/s below the weave
speed with a roll rate of 0.3 rad/s; the steer angle passes pi/2 at about 0.98 s).
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from conftest import run_cli, variant_library
from cosim.compiler.catalog import Singularity, singular_configurations
from cosim.errors import ModelicaError
from cosim.fmu.simulate import physical_cause
from test_runtime_c import FALLING, STEP, STOP

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

NONLINEAR = ["Bicycle.Bicycles.Whipple", "Bicycle.Bicycles.WhippleRider"]
MESSAGE = re.compile(r"^cosim simulate: incomplete: (?P<fmu>\S+): the simulation stopped at t = (?P<t>\S+) s of "
                     r"(?P<stop>\S+) s: steer angle delta = (?P<delta>\S+) rad \((?P<deg>\S+) deg\) reached "
                     r"\+-pi/2 \(\+-90 deg\), a singular configuration of (?P<model>\S+): (?P<why>.+) \(solver: "
                     r"(?P<solver>[^;]+)\); wrote the (?P<rows>\d+) rows up to t = (?P<last>\S+) s to (?P<out>\S+)$")


@pytest.mark.parametrize("model", NONLINEAR, ids=["Whipple", "WhippleRider"])
def test_falling_bicycle_stops_with_one_line_naming_the_singularity(model, tmp_path):
    out = tmp_path / "fall.csv"
    params = [arg for name, value in FALLING.items() for arg in ("--param", f"{name}={value}")]
    result = run_cli("simulate", model, *params, "--stop-time", str(STOP), "--step", str(STEP), "-o", str(out))
    assert result.returncode == 4, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    found = MESSAGE.match(lines[0])
    assert found, lines[0]
    partial = tmp_path / "fall.incomplete.csv"
    assert found["out"] == str(partial) and not out.exists()
    data = np.genfromtxt(partial, delimiter=",", names=True)
    # the message's numbers are the kept rows' last ones
    # t = 0, every communication point before the failure, the failure
    assert int(found["rows"]) == len(data) == math.floor(data["time"][-1] / STEP) + 2
    assert float(found["t"]) == pytest.approx(data["time"][-1], rel=1e-5)
    assert float(found["delta"]) == pytest.approx(data["delta"][-1], rel=1e-3)
    assert float(found["deg"]) == pytest.approx(math.degrees(data["delta"][-1]), abs=0.06)
    assert 0.5 < data["time"][-1] < 1.5 and abs(abs(data["delta"][-1]) - math.pi / 2) < math.radians(15)
    assert found["model"] == model and found["why"] == singular_configurations(model)[0].description
    assert "too small" in found["solver"] or "steps in one communication step" in found["solver"]
    assert np.all(np.isfinite(data["delta"])) and data["phi"][0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("model", NONLINEAR, ids=["Whipple", "WhippleRider"])
def test_nonlinear_bicycles_declare_steer_and_roll_at_90_degrees(model):
    declared = {s.variable: s for s in singular_configurations(model)}
    assert set(declared) == {"delta", "phi"}
    # what the variables are comes from their declarations' descriptions
    assert (declared["delta"].quantity, declared["phi"].quantity) == ("steer angle", "roll angle")
    for s in declared.values():
        assert s.model == model and s.angle == pytest.approx(math.pi / 2, abs=1e-15)
        assert 0 < s.tolerance < math.pi / 4 and s.description


def test_linear_and_simple_models_declare_none():
    for model in ("Bicycle.Bicycles.WhippleLinear", "Bicycle.Bicycles.SelfStabilizing"):
        assert singular_configurations(model) == ()


STEER = Singularity("M", "delta", math.pi / 2, math.radians(15), "steer across")


@pytest.mark.parametrize("value, reached", [
    (math.pi / 2, True), (-math.pi / 2, True), (math.radians(76), True), (math.radians(104), True),
    (math.radians(74), False), (math.radians(106), False), (0.0, False), (math.pi, False),
    (-2 * math.pi + math.pi / 2, True),  # a full turn further: the same configuration
    (-2 * math.pi, False), (math.nan, False), (math.inf, False),
], ids=["+90", "-90", "76", "104", "74", "106", "0", "180", "-270", "-360", "nan", "inf"])
def test_singular_band_modulo_a_full_turn(value, reached):
    assert STEER.reached(value) is reached


def test_physical_cause_uses_only_the_declared_singularities():
    whipple = singular_configurations("Bicycle.Bicycles.Whipple")
    assert physical_cause({"delta": 1.6, "phi": 0.2}, ()) is None  # a model that declares none
    text = physical_cause({"bike.delta": 1.6, "bike.phi": 0.2}, whipple)
    assert text.startswith("steer angle bike.delta = 1.6 rad (91.7 deg) reached +-pi/2")
    assert "phi" not in text
    both = physical_cause({"delta": 1.45, "phi": -1.56, "residual": 3e-5}, whipple)
    # the residual first, then the nearer singularity
    assert both.index("residual") < both.index("roll angle phi = -1.56") < both.index("steer angle delta = 1.45")
    # without the model: the library's declarations, matched by name (a system's component)
    assert physical_cause({"bike.delta": 1.6}) == physical_cause({"bike.delta": 1.6}, whipple)


def test_a_variant_inherits_the_singularities_and_may_override_one(tmp_path):
    library = variant_library(tmp_path, {
        "Shorter": 'model Shorter "Whipple with a shorter trail"\n  extends Bicycle.Bicycles.Whipple(c = 0.06);\n'
                   'end Shorter;',
        "Own": 'model Own "Whipple declaring its own steer singularity"\n  extends Shorter;\n'
               '  annotation(__Cosim(singular(delta(angle_deg = 80, tolerance_deg = 5, description = "own"))));\n'
               'end Own;',
    })
    base = singular_configurations("Bicycle.Bicycles.Whipple", library)
    assert singular_configurations("TestVariants.Shorter", library) == base
    own = {s.variable: s for s in singular_configurations("TestVariants.Own", library)}
    assert own["delta"] == Singularity("TestVariants.Own", "delta", math.radians(80), math.radians(5), "own",
                                       "steer angle")
    assert own["phi"] == next(s for s in base if s.variable == "phi")


@pytest.mark.parametrize("annotation, message", [
    ('singular(delta(angle_deg = 90, description = "x"))', r"must give exactly angle_deg, description, tolerance_deg"),
    ('singular(delta(angle_deg = 200, tolerance_deg = 5, description = "x"))', r"angle_deg = \.\.\.\) must be"),
    ('singular(delta(angle_deg = 90, tolerance_deg = 90, description = "x"))', r"tolerance_deg = \.\.\.\) must be"),
    ('singular(delta(angle_deg = 90, tolerance_deg = 5, description = ""))', r"description = \.\.\.\) must be"),
    ('singular = 1', r"expected singular\(VARIABLE"),
], ids=["missing-key", "angle-out-of-range", "tolerance-too-wide", "empty-description", "not-a-list"])
def test_malformed_singular_annotation_is_refused_with_file_and_line(tmp_path, annotation, message):
    library = variant_library(tmp_path, {
        "Bad": f'model Bad "bad annotation"\n  extends Bicycle.Bicycles.Whipple;\n'
               f'  annotation(__Cosim({annotation}));\nend Bad;'})
    with pytest.raises(ModelicaError, match=message) as info:
        singular_configurations("TestVariants.Bad", library)
    assert str(info.value).startswith(f"{tmp_path / 'TestVariants' / 'Bad.mo'}:4: TestVariants.Bad: ")
