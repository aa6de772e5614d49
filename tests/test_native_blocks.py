"""The C stepping loop steps the linear Python blocks natively.

A system of FMUs and blocks with a native form (:class:`cosim.cosimulation.registry.Native`: the
Affine family with its sources and references, Linear with PID and PadeDelay, the exact
TransportDelay) runs in ``fastloop.c``; its results are bit-identical to those of the Python loop
(forced with ``System.use_fast_loop = False``) for both algorithms, both samplings, step multiples
and a grid whose last step is shorter: the C code does the blocks' operations in the blocks' order.
A block without a native form keeps the system on the Python loop, and a fall, a divergence and an
FMU failure end a native run as they end a Python run.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

from conftest import failing_do_step
from cosim.compiler.build import build
from cosim.cosimulation import fastloop, registry
from cosim.cosimulation.blocks import Pulse, TransportDelay
from cosim.cosimulation.controllers import Proportional
from cosim.cosimulation.factory import create_components
from cosim.cosimulation.master import RunFailed, System, run_components
from cosim.cosimulation.system import system_from_dict

BIKE = "Bicycle.Bicycles.WhippleLinear"
BIKE_OUTPUTS = ["phi", "delta", "phi_dot", "delta_dot", "psi", "y"]
STOP, STEP = 2.995, 0.01  # s: 299 steps of 0.01 s and a last one of 0.005 s
BLOCKS = {n: c for n, c in registry.registered().items() if c.__module__.startswith("cosim.")}
# Parameters where the defaults would leave the loop quiet (state feedback is 0, the step on from the start).
PARAMETERS = {"StateFeedback": {"K1": 5.0, "K2": -1.0, "K3": 0.5, "K4": 0.2}, "Step": {"start": 1.0}}
ALGORITHMS = ["jacobi", "gauss-seidel"]
SAMPLINGS = ["after-step", "after-transfer"]
MULTIPLES = {"m1": {}, "block-m3": {"block": 3}, "bike-m2": {"bike": 2}}  # step_multiple by component

pytestmark = pytest.mark.skipif(fastloop.library() is None, reason="no C compiler: the master has no native loop")


@pytest.fixture(scope="module")
def bike() -> str:
    """The linear benchmark bicycle's FMU (built once into the session's FMU folder)."""
    return str(build([BIKE], output=os.environ["COSIM_FMU_DIR"], jobs=1)[0].fmu)


def _system(bike: str, blocks: dict, connections: list[str], algorithm="jacobi", sampling="after-step",
            multiples: dict | None = None, v: float = 5.0, **settings):
    """The benchmark bicycle at ``v`` [m/s] with an initial roll of 0.01 rad and Python ``blocks``
    (name -> (block, parameters))."""
    components = {"bike": {"fmu": bike, "params": "benchmark", "parameters": {"v": v, "phi0": 0.01}}}
    for name, (block, parameters) in blocks.items():
        components[name] = {"python": block, "parameters": parameters}
    for name, multiple in (multiples or {}).items():
        components[name]["step_multiple"] = multiple
    return system_from_dict({"system": {"stop": STOP, "step": STEP, "algorithm": algorithm, "sampling": sampling,
                                        **settings},
                             "components": components, "connections": connections})


def _run(spec, native: bool, components: dict | None = None):
    """Run ``spec`` (its components created from it unless given) with the native loop allowed or
    the Python loop forced: (result, True if the C loop stepped it, the components)."""
    used = []
    original = System._fast_steps

    def spy(self, *args):
        used.append(True)
        return original(self, *args)

    components = create_components(spec) if components is None else components
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(System, "use_fast_loop", native)
        patch.setattr(System, "_fast_steps", spy)
        try:
            result = run_components(spec, components)
        except RunFailed as exc:  # the rows up to the failure, compared like any result
            result = exc.result
    return result, bool(used), components


def _state(block) -> dict:
    """What a block keeps between steps (its time, inputs, outputs, states, delay history)."""
    keys = ("_t", "_u", "_y", "x", "_times", "_values")
    return {k: np.asarray(list(v) if k in ("_times", "_values") else v, float).tobytes()
            for k in keys if hasattr(block, k) for v in [getattr(block, k)]}


def _assert_identical(python, native):
    """Bit for bit: every recorded value, the outcome and the number of steps."""
    assert python.data.dtype.names == native.data.dtype.names
    for name in python.data.dtype.names:
        a, b = python.data[name], native.data[name]
        assert a.tobytes() == b.tobytes(), \
            f"{name}: native differs from Python by up to {np.max(np.abs(a - b)) if a.shape == b.shape else a.shape}"
    assert (python.outcome, python.steps) == (native.outcome, native.steps)


def _compare(spec, watched: list[str]):
    """Python loop and native loop on ``spec``: identical results and final block states."""
    python, used_python, comps_python = _run(spec, native=False)
    native, used_native, comps_native = _run(spec, native=True)
    assert not used_python and used_native, "the native loop did not step the system"
    _assert_identical(python, native)
    for name in watched:
        assert _state(comps_python[name]) == _state(comps_native[name]), f"{name}: final state differs"
    return native


def _block_case(bike, name, algorithm, sampling, multiples):
    """The block in a loop with the bicycle: its inputs from the bicycle outputs of the same name
    (else the roll angle), its first output on the steer torque (a source's on the roll torque)."""
    cls = BLOCKS[name]
    connections = [f"bike.{i if i in BIKE_OUTPUTS else 'phi'} -> block.{i}" for i in cls.inputs]
    connections.append(f"block.{cls.outputs[0]} -> bike.{'T_delta' if cls.inputs else 'T_phi'}")
    return _system(bike, {"block": (name, PARAMETERS.get(name, {}))}, connections, algorithm, sampling, multiples)


@pytest.mark.parametrize("multiple", list(MULTIPLES))
@pytest.mark.parametrize("sampling", SAMPLINGS)
@pytest.mark.parametrize("algorithm", ALGORITHMS)
@pytest.mark.parametrize("name", list(BLOCKS))
def test_native_loop_equals_python_loop_for_every_block(bike, name, algorithm, sampling, multiple):
    """Every built-in block in a feedback loop (or as the push) of the bicycle: bit-identical signals,
    outcome and final block state from both loops; the block's output moves (the test sees it)."""
    spec = _block_case(bike, name, algorithm, sampling, MULTIPLES[multiple])
    native = _compare(spec, ["block"])
    assert native.outcome.status == "completed"
    output = native.data[f"block.{BLOCKS[name].outputs[0]}"]
    assert np.ptp(output) > 1e-6, f"{name}: the block's output is flat, the comparison would see little"


DELAYS = {"exact-tau0": ("TransportDelay", {"tau": 0.0}), "exact-tau0.004": ("TransportDelay", {"tau": 0.004}),
          "exact-tau0.1": ("TransportDelay", {"tau": 0.1}), "exact-tau0.1234": ("TransportDelay", {"tau": 0.1234}),
          "exact-tau2.5": ("TransportDelay", {"tau": 2.5}),
          "pade-n2": ("PadeDelay", {"tau": 0.1}), "pade-n5": ("PadeDelay", {"tau": 0.1234, "n": 5})}


@pytest.mark.parametrize("multiple", list(MULTIPLES))
@pytest.mark.parametrize("sampling", SAMPLINGS)
@pytest.mark.parametrize("algorithm", ALGORITHMS)
@pytest.mark.parametrize("delay", list(DELAYS))
def test_native_loop_equals_python_loop_for_a_delayed_rider(bike, delay, algorithm, sampling, multiple):
    """The matrix benchmark's rider+delay loop, T = -k phi(t - tau): the exact delay below a step
    (feedthrough), at, off and far beyond the grid (its sample ring), and Pade delays (states)."""
    multiples = {"delay" if k == "block" else k: m for k, m in MULTIPLES[multiple].items()}
    spec = _system(bike, {"rider": ("Proportional", {"k": 0.5}), "delay": DELAYS[delay]},
                   ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"],
                   algorithm, sampling, multiples)
    native = _compare(spec, ["rider", "delay"])
    assert native.outcome.status == "completed" and np.ptp(native.data["delay.y"]) > 1e-6


def test_native_delay_keeps_only_what_it_can_reach(bike):
    """After a native run the exact delay's history is what the Python stepping keeps: the samples
    within tau of the end and one before (not every step's sample)."""
    spec = _system(bike, {"rider": ("Proportional", {"k": 0.5}), "delay": ("TransportDelay", {"tau": 0.1})},
                   ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"])
    _, used, comps = _run(spec, native=True)
    delay = comps["delay"]
    times = np.array(delay._times)
    assert used and delay._t == pytest.approx(STOP, abs=1e-12)  # its time, past the last sample (2.99 s)
    assert times[-1] == pytest.approx(STOP - 0.005, abs=1e-12)
    assert times[1] > delay._t - 0.1 >= times[0] and len(times) <= 0.1 / STEP + 3


class TracedProportional(Proportional, register=False):
    """Proportional that counts its input updates: an override that ``native`` does not describe."""

    def set_inputs(self, values):
        self.updates = getattr(self, "updates", 0) + 1
        super().set_inputs(values)


class OldStylePulse(Pulse, register=False):
    """The pulse with its exogenous part as code instead of a window: nothing the C loop can evaluate."""

    def exogenous(self, t):
        on = self.start <= t + 1e-12 and t + 1e-12 < self.start + self.duration
        return np.array([self.amplitude if on else 0.0])


class Saturated(TransportDelay, register=False):
    """A user's nonlinear block derived from a native kind: the output limited to +-LIMIT (N.m)."""

    LIMIT = 0.01

    def _delayed(self, t):
        return min(self.LIMIT, max(-self.LIMIT, super()._delayed(t)))


PLUGINS = {"overridden-set-inputs": ("rider", TracedProportional, {"k": 0.5}),
           "exogenous-without-window": ("push", OldStylePulse, {"amplitude": 5.0, "start": 0.5, "duration": 0.2}),
           "nonlinear-subclass": ("delay", Saturated, {"tau": 0.1})}


@pytest.mark.parametrize("plugin", list(PLUGINS))
def test_block_without_native_form_keeps_the_python_loop(bike, plugin):
    """A subclass that overrides what the native form describes has none: the system steps in
    Python, and where the override computes the same thing, bit for bit as the native run does."""
    name, cls, parameters = PLUGINS[plugin]
    blocks = {"rider": ("Proportional", {"k": 0.5}), "delay": ("TransportDelay", {"tau": 0.1}),
              "push": ("Pulse", {"amplitude": 5.0, "start": 0.5, "duration": 0.2})}
    connections = ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta", "push.y -> bike.T_phi"]
    spec = _system(bike, blocks, connections, sampling="after-transfer")
    components = create_components(spec)
    components[name] = cls(name, **parameters)
    assert components[name].native_form(np.full(10, STEP)) is None
    with_plugin, used, _ = _run(spec, native=True, components=components)
    assert not used, "a block without a native form was stepped in C"
    reference, used_reference, _ = _run(spec, native=True)
    assert used_reference
    if cls is Saturated:  # a different block: it runs, and differs where the limit acts
        limited = np.max(np.abs(with_plugin.data["delay.y"]))
        assert with_plugin.outcome.status == "completed" and limited == pytest.approx(Saturated.LIMIT, abs=1e-15)
        assert np.max(np.abs(reference.data["delay.y"])) > 1.2 * Saturated.LIMIT
    else:
        _assert_identical(reference, with_plugin)


def test_every_built_in_block_has_a_native_form():
    """So that a system of FMUs and built-in blocks never falls back to the Python loop."""
    steps = np.full(5, STEP)
    kinds = {}
    for name, cls in BLOCKS.items():
        block = cls.create("b", PARAMETERS.get(name, {}))
        block.setup(0.0)
        native = block.native_form(steps)
        assert native is not None, f"{name} has no native form"
        kinds[name] = native.kind
    assert kinds["Proportional"] == kinds["Pulse"] == kinds["LaneChange"] == "affine"
    assert kinds["PID"] == kinds["PadeDelay"] == "linear" and kinds["TransportDelay"] == "delay"


@pytest.mark.parametrize("sampling", SAMPLINGS)
def test_fall_in_the_native_loop_ends_the_run_as_in_python(bike, sampling):
    """Below the weave speed (3 m/s) with a weak delayed rider the bicycle falls: same time,
    message and rows."""
    spec = _system(bike, {"rider": ("Proportional", {"k": 0.1}), "delay": ("TransportDelay", {"tau": 0.1})},
                   ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"],
                   sampling=sampling, v=3.0, fall={"signal": "bike.phi", "limit": 0.02})
    native = _compare(spec, ["rider", "delay"])
    assert native.outcome.status == "fell" and 0.1 < native.outcome.time < STOP - 0.1
    assert len(native.data) == native.steps + 1 < 299


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_divergence_in_the_native_loop_ends_the_run_as_in_python(bike, algorithm):
    """A push of infinite amplitude from 0.5 s: under Jacobi the run ends as diverged, naming the
    signal; under Gauss-Seidel the bicycle is given it in the same step and refuses it (the FMU's
    communication point named, 0.49 s)."""
    blocks = {"rider": ("Proportional", {"k": 0.5}), "delay": ("TransportDelay", {"tau": 0.1}),
              "push": ("Pulse", {"start": 0.5})}
    spec = _system(bike, blocks, ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta",
                                  "push.y -> bike.T_phi"], algorithm)
    results = []
    for native in (False, True):
        components = create_components(spec)
        components["push"] = Pulse("push", amplitude=np.inf, start=0.5)  # the factory refuses inf
        result, used, _ = _run(spec, native, components)
        assert used == native
        results.append(result)
    _assert_identical(*results)
    outcome = results[1].outcome
    if algorithm == "jacobi":
        assert (outcome.status, outcome.message) == ("diverged", "signal push.y is not finite at t = 0.5 s")
    else:
        assert outcome.status == "failed" and results[1].steps == 49
        assert outcome.message.startswith("stopped at t = 0.49 s: bike: fmi2SetReal failed at t = 0.49 s "
                                          "(status Error)")


@pytest.mark.parametrize("status", [2, 3], ids=["discard", "error"])
def test_fmu_failure_in_the_native_loop_is_reported_as_in_python(bike, monkeypatch, status):
    """The bicycle's fmi2DoStep fails at t = 1 s: both loops keep the rows up to the failure and
    name the component, the call and the status."""
    failing_do_step(monkeypatch, status, 1.0)
    spec = _system(bike, {"rider": ("Proportional", {"k": 0.5}), "delay": ("PadeDelay", {"tau": 0.1})},
                   ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"],
                   sampling="after-transfer")
    native = _compare(spec, ["rider", "delay"])
    assert native.outcome.status == "failed" and native.steps == 100
    assert (f"bike: fmi2DoStep failed at t = 1 s (status {'Discard' if status == 2 else 'Error'})"
            in native.outcome.message)


def test_a_full_delay_ring_stops_the_run_instead_of_overwriting(bike, monkeypatch):
    """The ring's capacity is a bound TransportDelay.native computes; were it too small, the loop
    stops with an error naming the delay rather than overwrite samples it still needs."""
    original = TransportDelay.native

    def small_ring(self, steps):
        native = original(self, steps)
        count = int(native.ring[1])
        native.ring_t, native.ring_v = native.ring_t[:count + 3].copy(), native.ring_v[:count + 3].copy()
        return native

    monkeypatch.setattr(TransportDelay, "native", small_ring)
    spec = _system(bike, {"rider": ("Proportional", {"k": 0.5}), "delay": ("TransportDelay", {"tau": 0.1})},
                   ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"])
    # 4 places: the samples of 0, 0.01, 0.02 and 0.03 s (none older than tau yet); 0.04 s does not fit
    with pytest.raises(RuntimeError, match=r"^delay: the native delay's sample ring is full at t = 0\.04 s$"):
        run_components(spec, create_components(spec))
