"""rumoca, a Modelica compiler that follows the specification, simulates the library's models as
this project's FMUs do.

Where rumoca 0.10.2 can simulate a model (no top-level inputs: every example, and the nonlinear
bicycles with their torque inputs bound to zero in a test variant), its trajectory over the
model's ``experiment`` equals the one of the project's Co-Simulation FMU: every state and output
at every output point within ``1e-6 * max(1, |value|)``. Both integrators run at a relative
tolerance of 1e-10 (rumoca's explicit Runge-Kutta, the FMU's Dormand-Prince), two orders below the
comparison, so that the comparison sees the models, not the integrators.

rumoca's limitation: models with top-level inputs (the bicycles themselves) are refused by its
``simulate`` ("time-varying inputs ... not yet available"); the variants bind the inputs to zero.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
import rumoca
from fmpy import read_model_description, simulate_fmu

from conftest import variant_library
from cosim.compiler.build import build_model
from cosim.compiler.library import DEFAULT_LIBRARY, Library

pytestmark = pytest.mark.slow

LIBRARY = Library(DEFAULT_LIBRARY)
EXAMPLES = [e.name for e in LIBRARY.models() if e.name.startswith("Bicycle.Examples.")]
#: Nonlinear bicycles started leaning at 5 m/s (parameter values), their inputs zero: bound to zero
#: in rumoca's variant, at their start value 0 in the FMU.
ZERO_INPUTS = {
    "Whipple": ("Bicycle.Bicycles.Whipple", ["T_delta", "T_phi"], {"phi0": 0.1}),
    "WhippleRider": ("Bicycle.Bicycles.WhippleRider", ["T_delta", "T_phi", "T_beta"], {"phi0": 0.1}),
    "WhippleRiderTwist": ("Bicycle.Bicycles.WhippleRiderTwist", ["T_delta", "T_phi", "T_beta", "T_twist"],
                          {"phi0": 0.1, "twist0": 0.05}),
}
RELATIVE = 1e-6
SOLVER_TOLERANCE = 1e-10


@pytest.fixture(scope="module")
def variants(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rumoca-variants")
    models = {}
    for name, (base, inputs, start) in ZERO_INPUTS.items():
        mods = ", ".join([f"{u} = 0" for u in inputs] + [f"{k} = {v}" for k, v in start.items()])
        models[name] = f"model {name} \"Test variant: {base} without inputs\"\n  extends {base}({mods});\nend {name};"
    variant_library(folder, models)
    return folder


def _experiment(name: str) -> dict:
    found = LIBRARY.entry(name).experiment
    return {"start": found.get("StartTime", 0.0), "stop": found["StopTime"], "interval": found["Interval"]}


def _rumoca(file: Path, model: str, stop: float, interval: float, roots=()):
    session = rumoca.Session(roots=[str(r) for r in roots]) if roots else rumoca.Session()
    compiled = session.load(str(file), model=model)
    result = compiled.simulate(t=stop, dt=interval, config=rumoca.SimConfig(
        solver="rk-like", rtol=SOLVER_TOLERANCE, atol=SOLVER_TOLERANCE))
    return np.asarray(result.time), list(result.names), result.to_numpy()


def _states_and_outputs(fmu: Path) -> list[str]:
    description = read_model_description(str(fmu))
    states = [d.variable.derivative.name for d in description.derivatives]
    return states + [v.name for v in description.modelVariables if v.causality == "output" and v.name not in states]


def _compare(fmu: Path, model: str, rumoca_run, stop: float, interval: float, start: dict | None = None) -> float:
    ours = simulate_fmu(str(fmu), stop_time=stop, output_interval=interval, relative_tolerance=SOLVER_TOLERANCE,
                        output=_states_and_outputs(fmu), start_values=start or {})
    time, names, values = rumoca_run
    compared = [n for n in ours.dtype.names if n != "time" and n in names]
    missing = [n for n in ours.dtype.names if n != "time" and n not in names]
    assert not missing, f"{model}: rumoca has no {missing}"
    worst, where = 0.0, None
    for name in compared:
        theirs = np.interp(ours["time"], time, values[names.index(name)])
        error = np.max(np.abs(ours[name] - theirs) / np.maximum(1.0, np.abs(ours[name])))
        if error > worst:
            worst, where = float(error), name
    print(f"{model}: worst {worst:.2e} ({where}) over {len(compared)} variables")
    assert math.isfinite(worst) and worst <= RELATIVE, f"{model}: rumoca differs from the FMU by {worst:.3g} in {where}"
    return worst


@pytest.mark.parametrize("model", EXAMPLES)
def test_example_trajectory_equals_rumoca(model):
    ex = _experiment(model)
    run = _rumoca(LIBRARY.entry(model).file, model, ex["stop"], ex["interval"])
    fmu = build_model(model, os.environ["COSIM_FMU_DIR"], LIBRARY).fmu
    _compare(fmu, model, run, ex["stop"], ex["interval"])


@pytest.mark.parametrize("name", list(ZERO_INPUTS))
def test_nonlinear_bicycle_trajectory_equals_rumoca(variants, name):
    base, _, start = ZERO_INPUTS[name]
    ex = _experiment(base)
    stop = min(ex["stop"], 3.0)  # rumoca's explicit integrator at 1e-10 takes about 2 s per simulated second
    fmu = build_model(base, os.environ["COSIM_FMU_DIR"], LIBRARY).fmu
    run = _rumoca(variants / "TestVariants" / f"{name}.mo", f"TestVariants.{name}", stop, ex["interval"],
                  roots=[DEFAULT_LIBRARY, variants])
    _compare(fmu, name, run, stop, ex["interval"], start)


def test_rumoca_refuses_inputs():
    """The limitation the variants work around is rumoca's (if it goes away, simulate the bicycles)."""
    compiled = rumoca.Session().load(str(LIBRARY.entry("Bicycle.Bicycles.Whipple").file), model="Bicycle.Bicycles.Whipple")
    with pytest.raises(Exception, match="input"):
        compiled.simulate(t=0.1)
