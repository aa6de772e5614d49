"""The block registry: every registered Python block equals the FMU of its Modelica twin and its own
linear model, and one class is all a new block needs for every consumer (factory, SSP twins,
prediction, docs)."""
from __future__ import annotations

import inspect

import numpy as np
import pytest
from scipy.signal import cont2discrete

from cosim.cosimulation import registry
from cosim.cosimulation.blocks import Affine
from cosim.cosimulation.component import FMUComponent
from cosim.cosimulation.factory import python_block
from cosim.cosimulation.modelica_twins import with_twins
from cosim.cosimulation.system import SystemError_, system_from_dict
from cosim.matrix import predict
from cosim.statespace import StateSpace

BLOCKS = registry.registered()
H, STOP = 0.01, 2.0  # communication step and end of the step responses [s]
AGREEMENT = 1e-9     # relative, floor 1: Python = twin FMU (tolerance 1e-12) = linear model
SETTINGS = {"pade_order": 2}  # the order of the exact delay's twin


def _test_parameters(cls) -> dict:
    """Every float parameter moved off its default (a wrong mapping to the twin shows), on the grid."""
    values = {}
    for key, default in cls.defaults().items():
        if isinstance(default, float) and np.isfinite(default):
            values[key] = round(1.3 * default + 0.2, 2)
    return values


def _inputs(t: float, count: int) -> np.ndarray:
    """Input j steps to 0.1 (j + 1) at t = 0.05 (j + 1) s (on communication points)."""
    return np.array([0.1 * (j + 1) if t >= 0.05 * (j + 1) - 1e-9 else 0.0 for j in range(count)])


def _respond(component, count: int) -> np.ndarray:
    """Outputs through the component protocol: row 2k at t_k after set_inputs, row 2k+1 at t_(k+1)
    after the step (inputs still those of t_k)."""
    grid = np.arange(round(STOP / H) + 1) * H
    rows = []
    component.configure_step(H)
    component.setup(0.0)
    component.set_inputs(_inputs(0.0, count))
    component.end_initialization()
    try:
        for t, t_next in zip(grid[:-1], grid[1:]):
            component.set_inputs(_inputs(t, count))
            rows.append(component.get_outputs().copy())
            component.step(t, t_next - t)
            rows.append(component.get_outputs().copy())
    finally:
        component.close()
    return np.array(rows)


def _linear_response(block, model: StateSpace) -> np.ndarray:
    """The declared linear model y = C x + D u + r(t), discretized exactly (ZOH, scipy)."""
    grid = np.arange(round(STOP / H) + 1) * H
    count = len(model.inputs)
    if model.n:
        Ad, Bd, *_ = cont2discrete((model.A, model.B, model.C, model.D), H, method="zoh")
    x = np.zeros(model.n)
    rows = []
    for t, t_next in zip(grid[:-1], grid[1:]):
        u = _inputs(t, count)
        rows.append(model.C @ x + model.D @ u + block.exogenous(t))
        if model.n:
            x = Ad @ x + Bd @ u
        rows.append(model.C @ x + model.D @ u + block.exogenous(t_next))
    return np.array(rows)


def _exact_delay(tau: float) -> np.ndarray:
    """y(t) = u(t - tau) of the step input, the initial value before tau."""
    grid = np.arange(round(STOP / H) + 1) * H
    rows = []
    for t, t_next in zip(grid[:-1], grid[1:]):
        rows += [_inputs(t - tau, 1), _inputs(t_next - tau, 1)]
    return np.array(rows)


def _difference(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(a)))) if a.size else 0.0


@pytest.mark.parametrize("name", list(BLOCKS))
def test_python_block_equals_twin_fmu_and_linear_model(name, fmus):
    """Step responses on the same grid (h = 0.01 s): the Python block, the FMU of its Modelica twin
    (with the parameters the block gives it) and the block's linear model agree to 1e-9. The exact
    transport delay equals u(t - tau) instead, and its Pade twin equals its linear model."""
    cls = BLOCKS[name]
    assert cls.twin in fmus, f"{name}: twin {cls.twin} is not an exported model"
    parameters = _test_parameters(cls)
    block = cls.create("block", parameters)
    count = len(cls.inputs)
    python = _respond(block, count)
    twin = _respond(FMUComponent("twin", fmus[cls.twin], block.twin_parameters(), tolerance=1e-12), count)
    linear = _linear_response(block, block.linear(SETTINGS))
    assert python.shape == twin.shape == linear.shape
    assert np.ptp(twin) > 0.05, f"{name}: the step response is flat, the test would see nothing"
    assert _difference(twin, linear) <= AGREEMENT
    if cls.twin_approximation:  # the exact delay: its Python stepping is the exact delay
        assert _difference(python, _exact_delay(block.tau)) <= 1e-12
        assert _difference(python, twin) > 1e-3  # and the twin is only an approximation
    else:
        assert _difference(python, twin) <= AGREEMENT


@pytest.mark.parametrize("name", [n for n, c in BLOCKS.items() if c.twin_same_parameters])
def test_twin_has_the_blocks_interface_and_defaults(name, fmus):
    """Same inputs and outputs in the same order (the master addresses them by index), every block
    parameter a twin parameter with the block's default: a system may omit any parameter."""
    from fmpy import read_model_description

    cls = BLOCKS[name]
    md = read_model_description(str(fmus[cls.twin]))
    causal = {c: [v.name for v in md.modelVariables if v.causality == c] for c in ("input", "output")}
    assert (causal["input"], causal["output"]) == (list(cls.inputs), list(cls.outputs))
    starts = {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter"}
    defaults = cls.defaults()
    assert {k: starts.get(k) for k in defaults} == {k: float(v) for k, v in defaults.items()}


@pytest.mark.parametrize("name", list(BLOCKS))
def test_prediction_reads_the_blocks_linear_model(name, fmus):
    """The matrix prediction of the block, and of its twin's FMU where the twin has the block's
    parameters, is the linear model the block declares."""
    cls = BLOCKS[name]
    parameters = _test_parameters(cls)
    model = cls.create("block", parameters).linear(SETTINGS)
    entries = [{"python": name, "parameters": parameters}]
    if cls.twin_same_parameters:
        entries.append({"model": cls.twin, "parameters": parameters})
    for entry in entries:
        lti = predict.component_lti("block", entry, {cls.twin: str(fmus[cls.twin])}, SETTINGS)
        ours = lti.system
        for found, declared in ((ours.A, model.A), (ours.B, model.B), (ours.C, model.C), (ours.D, model.D)):
            np.testing.assert_array_equal(found, declared)
        assert (ours.inputs, ours.outputs) == (list(cls.inputs), list(cls.outputs))
        assert lti.kind == ("delay" if cls.interpolates else "static" if not model.n else "dynamic")


def test_every_block_is_exported_through_its_twin():
    """A system using every registered block becomes an all-FMU system (SSP export): each block its
    twin with the twin's parameters, the approximation named in the note."""
    spec = system_from_dict({"system": {"stop": 1.0, "step": 0.01},
                             "components": {n.lower(): {"python": n} for n in BLOCKS}})
    swapped, notes = with_twins(spec)
    assert {c.kind for c in swapped.components.values()} == {"model"}
    assert {c.source for c in swapped.components.values()} == {c.twin for c in BLOCKS.values()}
    assert "step: Python Step -> Bicycle.Sources.TorqueStep" in notes
    assert "transportdelay: Python TransportDelay -> Bicycle.Rider.PadeDelay (exact delay -> Pade " \
           "approximation, n = 2)" in notes
    lqr = swapped.components["lqr"].parameters
    assert sorted(lqr) == ["K1", "K2", "K3", "K4"] and abs(lqr["K1"]) > 1


def test_pade_twin_with_another_order_is_refused():
    spec = system_from_dict({"components": {"d": {"python": "PadeDelay", "parameters": {"n": 3}}}})
    with pytest.raises(SystemError_, match=r"component 'd' \(PadeDelay\): the Modelica twin "
                                           r"Bicycle.Rider.PadeDelay is built with n = 2"):
        with_twins(spec)


@pytest.fixture
def new_block():
    """A block defined in the test, the way a user adds one; removed from the registry afterwards."""

    class DoubleGain(Affine):
        """y1 = a u, y2 = -a u (a dimensionless)."""

        inputs, outputs = ["u"], ["y1", "y2"]

        def __init__(self, name: str, a: float = 2.0):
            super().__init__(name)
            self.a = float(a)

        def gain(self):
            return [[self.a], [-self.a]]

    yield DoubleGain
    registry.BLOCKS.pop("DoubleGain", None)


def test_one_class_is_a_block_for_every_consumer(new_block):
    """Defining the class registers it: the factory creates it with checked parameters, the
    prediction reads its linear model, the docs list it, SSP export names the missing twin."""
    block = python_block("g", "DoubleGain", {"a": 3.0})
    block.setup(0.0)
    block.set_inputs(np.array([0.5]))
    np.testing.assert_array_equal(block.get_outputs(), [1.5, -1.5])
    with pytest.raises(SystemError_, match=r"component 'g' \(DoubleGain\): parameter 'a': expected a number"):
        python_block("g", "DoubleGain", {"a": "big"})
    lti = predict.component_lti("g", {"python": "DoubleGain", "parameters": {"a": 3.0}}, {}, SETTINGS)
    np.testing.assert_array_equal(lti.system.D, [[3.0], [-3.0]])
    assert "`DoubleGain` (u -> y1, y2; twin `None`): y1 = a u, y2 = -a u (a dimensionless)." in registry.markdown()
    spec = system_from_dict({"components": {"g": {"python": "DoubleGain"}}})
    with pytest.raises(SystemError_, match="the Python block 'DoubleGain' has no Modelica twin"):
        with_twins(spec)


def test_block_defined_twice_is_refused():
    """Two classes of the same name would make the system files ambiguous."""
    with pytest.raises(TypeError, match=r"Python block 'PD' is defined twice: in cosim.cosimulation.controllers "
                                        r"and test_block_registry"):
        type("PD", (Affine,), {"__module__": "test_block_registry", "__qualname__": "PD"})
    assert BLOCKS["PD"].__module__ == "cosim.cosimulation.controllers"


def test_unknown_block_lists_the_registry():
    with pytest.raises(SystemError_, match=r"component 'x': unknown Python block 'Nope' \(available: .*PID"):
        python_block("x", "Nope", {})
    with pytest.raises(predict.PredictionError, match=r"component 'x': unknown Python block 'Nope'"):
        predict.component_lti("x", {"python": "Nope"}, {}, SETTINGS)


def test_every_block_parameter_is_typed_and_has_a_default():
    """The factory checks system-file values against the annotations; a system may omit any."""
    for name, cls in BLOCKS.items():
        for key, p in cls.parameters().items():
            assert p.default is not inspect.Parameter.empty, f"{name}.{key} has no default"
            assert str(p.annotation).split("|")[0].strip() in ("float", "int", "str"), f"{name}.{key}"


def test_docs_name_every_block_and_its_twin():
    """The block list of docs/cosimulation.md is checked against the registry, so it cannot fall behind
    (the package's own blocks: a test's plugin block registers in the same process)."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "cosimulation.md").read_text()
    for name, cls in registry.registered().items():
        if not cls.__module__.startswith("cosim."):
            continue
        assert f"`{name}`" in text, name
        assert cls.twin.rsplit(".", 1)[-1] in text, (name, cls.twin)
