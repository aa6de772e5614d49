"""Controllers, delays and sources as connectable blocks.

* The blocks of ``Bicycle.Control``, ``Bicycle.Rider`` and ``Bicycle.Sources`` and the second-order
  bicycles declare their signals as ``Bicycle.Interfaces.RealInput`` / ``RealOutput`` connectors,
  and their FMUs keep the interface the last commit exported (names, causality, variability,
  initial, units, display units, descriptions, start values, dependencies).
* Every example that composes a bicycle with a block does it with ``connect()`` only, and the
  examples that mirror a system file (cosim/systems/) are that file with its Modelica twins.
* Each composed example is compared with the co-simulation of its parts by this project's master.
  What "the same system" can mean follows from how the master couples (master.System.run): it
  holds every input over a communication step (zero-order hold; no iteration, no input
  derivatives), Jacobi feeds every component the outputs at t_k, Gauss-Seidel steps the
  components in feedthrough order and feeds the values already advanced to t_k+1. So

  - a **source** feeding a bicycle is exact: the source is piecewise constant between
    communication points, and under Jacobi the bicycle sees it on ``[t_k, t_k+1)`` as in the
    one-model FMU, whose error-controlled integrator shortens its steps at the jump. Recorded
    with ``sampling = "after-transfer"`` a direct-feedthrough output (the static fork's steer
    angle) sees the new input as in the one model. Agreement <= 1e-9 at the same step.
    Gauss-Seidel feeds the source's value at the end of each step (one step early), and
    after-step sampling misses the jump for one step in the feedthrough output: both measured;
  - a **feedback loop** is not exact at any step: the master's loop is a sampled-data system,
    the one model closes it in continuous time; the gap is first order in the step (measured).
    A controller with a state does not change that (the Pade delay case). The exact statements
    are then: (i) the example FMU equals the continuous-time closed loop of the bicycle FMU's
    linearization and the Python blocks' own linear models (matrix exponentials) to <= 1e-9, and
    (ii) the master with the Python blocks equals the master with the FMUs of the Modelica blocks
    the example connects, to <= 1e-9 at the same step, for both algorithms.

* The master's third algorithm, ``model-exchange`` (cosim/cosimulation/model_exchange.py),
  couples in continuous time as the composed model does: every state of every component in one
  ODE, integrated by classic RK4 at the communication step, the bicycle FMU through its Model
  Exchange interface and the Python blocks through their linear models. With it **every** case,
  feedback loops and sources alike, is the same system at the same step: the bicycle FMU + the
  Python blocks equal the example FMU alone run through the same master, to <= 1e-9 (measured:
  to rounding) at h = 1e-3 and 5e-3 s; a gain off by 1e-6 is seen. Against the example's
  Co-Simulation FMU (error-controlled, tolerance 1e-12) the coupling converges at fourth order
  where the inputs are smooth (<= 1e-9 at h = 1e-3 s) and at first order where a source jumps
  inside the run: a jump on a communication point already acts at the last RK4 stage of the
  step that ends there (the FMUs have no events to tell the integrator).
"""
from __future__ import annotations

import json
import os
import re
import shutil
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from cosim.compiler.build import build
from cosim.cosimulation import algorithms, registry
from cosim.cosimulation.component import FMUComponent
from cosim.cosimulation.factory import python_block
from cosim.cosimulation.master import run_components
from cosim.cosimulation.system import load_system, system_from_dict
from cosim.fmu.linearize import linearize
from cosim.fmu.simulate import simulate

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "modelica" / "Bicycle"
TOLERANCE = 1e-12  # of every FMU's integrator in the comparisons
EXACT = 1e-9       # agreement, relative to the signal's largest magnitude (floor 1)

BLOCKS = [f"Bicycle.{p}.{f.stem}" for p in ("Control", "Rider", "Sources")
          for f in sorted((LIBRARY / p).glob("*.mo")) if f.stem != "package"]
BICYCLES = [f"Bicycle.Bicycles.{n}" for n in
            ("InvertedPendulum", "SelfStabilizing", "SelfStabilizingGyro", "RearSteered", "LeaningRider",
             "CrownedRoller")]
EXAMPLES = sorted(f.stem for f in (LIBRARY / "Examples").glob("*.mo") if f.stem != "package")


class Case:
    """An example and the same system as co-simulated parts: the bicycle FMU (its parameters and
    initial state as the example states them) and registered Python blocks, with the example's
    instance names as component names and its connect() equations as connections."""

    def __init__(self, example, bicycle, name, parameters, blocks, connections, stop, signals):
        self.example, self.bicycle, self.name, self.parameters = example, bicycle, name, parameters
        self.blocks, self.connections, self.stop, self.signals = blocks, connections, stop, signals

    @property
    def feedback(self) -> bool:
        return any(c.startswith(self.name + ".") for c in self.connections)

    def components(self, models, twins: bool = False) -> dict:
        comps = {self.name: FMUComponent(self.name, models[self.bicycle], self.parameters, tolerance=TOLERANCE)}
        for name, (block, parameters) in self.blocks.items():
            if twins:
                cls = registry.lookup(block)
                twin = cls.create(name, parameters).twin_parameters()
                comps[name] = FMUComponent(name, models[cls.twin], twin, tolerance=TOLERANCE)
            else:
                comps[name] = python_block(name, block, parameters)
        return comps

    def master(self, models, step, algorithm, twins=False, blocks=None, sampling="after-transfer"):
        # Outputs recorded after the transfer: a direct-feedthrough output (the static fork's steer
        # angle) then already sees the new input, as it does in the one-model FMU.
        spec = system_from_dict({"system": {"stop": self.stop, "step": step, "algorithm": algorithm,
                                            "sampling": sampling, "record": self.signals},
                                 "components": {n: {"python": b} for n, (b, _) in self.blocks.items()}
                                 | {self.name: {"fmu": str(models[self.bicycle])}},
                                 "connections": self.connections})
        case = self if blocks is None else Case(self.example, self.bicycle, self.name, self.parameters, blocks,
                                                self.connections, self.stop, self.signals)
        return run_components(spec, case.components(models, twins)).data


CASES = {
    "InvertedPendulumSteerFeedback": Case(
        "InvertedPendulumSteerFeedback", "Bicycle.Bicycles.InvertedPendulum", "bicycle",
        {"V": 5.0, "frame.phi": 0.05}, {"controller": ("SteerAngleFeedback", {"k2": 0.8})},
        ["bicycle.phi -> controller.phi", "controller.delta -> bicycle.delta"], 5.0,
        ["bicycle.phi", "bicycle.psi", "bicycle.eta"]),
    "RearSteeredSteerFeedback": Case(
        "RearSteeredSteerFeedback", "Bicycle.Bicycles.RearSteered", "bicycle",
        {"V": 5.0, "phi0": 0.01}, {"controller": ("SteerAngleFeedback", {"k2": 0.8})},
        ["bicycle.phi -> controller.phi", "controller.delta -> bicycle.delta"], 3.0,
        ["bicycle.phi", "bicycle.psi", "bicycle.eta"]),
    "WhippleLinearRiderP": Case(
        "WhippleLinearRiderP", "Bicycle.Bicycles.WhippleLinear", "bike",
        {"v": 5.0, "phi0": 0.05}, {"rider": ("Proportional", {"k": 2.0})},
        ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"], 5.0,
        ["bike.phi", "bike.delta", "bike.psi", "bike.y"]),
    "WhippleLinearRiderPush": Case(
        "WhippleLinearRiderPush", "Bicycle.Bicycles.WhippleLinear", "bike",
        {"v": 4.0}, {"rider": ("Proportional", {"k": 2.0}),
                     "push": ("Pulse", {"amplitude": 10.0, "start": 0.5, "duration": 0.2})},
        ["bike.phi -> rider.phi", "rider.T -> bike.T_delta", "push.y -> bike.T_phi"], 5.0,
        ["bike.phi", "bike.delta", "bike.psi", "bike.y"]),
    "WhippleLinearLQRDelay": Case(
        "WhippleLinearLQRDelay", "Bicycle.Bicycles.WhippleLinear", "bike",
        {"v": 3.0}, {"autopilot": ("StateFeedback", {"K1": -27.877794943557305, "K2": 18.21930493503048,
                                                     "K3": -7.030319966648618, "K4": 1.9189718694862468}),
                     "delay": ("PadeDelay", {"tau": 0.1}),
                     "push": ("Pulse", {"amplitude": 20.0, "start": 0.5, "duration": 0.2})},
        ["bike.phi -> autopilot.phi", "bike.delta -> autopilot.delta", "bike.phi_dot -> autopilot.phi_dot",
         "bike.delta_dot -> autopilot.delta_dot", "autopilot.T -> delay.u", "delay.y -> bike.T_delta",
         "push.y -> bike.T_phi"], 5.0, ["bike.phi", "bike.delta", "bike.psi", "bike.y"]),
    "SelfStabilizingTorqueStep": Case(
        "SelfStabilizingTorqueStep", "Bicycle.Bicycles.SelfStabilizing", "bicycle",
        {"V": 6.0}, {"torque": ("Step", {"amplitude": 1.0, "start": 0.0})},
        ["torque.y -> bicycle.T"], 5.0, ["bicycle.phi", "bicycle.delta", "bicycle.psi", "bicycle.eta"]),
}
FEEDBACK = [n for n, c in CASES.items() if c.feedback]


@pytest.fixture(scope="module")
def models() -> dict:  # not the session's `fmus`: only what the comparisons need
    """The bicycles, blocks and composed examples of the comparisons, built once (into the
    session's FMU folder)."""
    names = sorted({c.bicycle for c in CASES.values()} | {f"Bicycle.Examples.{n}" for n in CASES}
                   | {registry.lookup(b).twin for c in CASES.values() for b, _ in c.blocks.values()})
    return {r.model: r.fmu for r in build(names, output=os.environ["COSIM_FMU_DIR"], jobs=2)}


def _difference(a, b, names) -> float:
    """Largest deviation over the signals, each relative to its largest magnitude (floor 1)."""
    return max(float(np.max(np.abs(a[n] - b[n])) / max(1.0, float(np.max(np.abs(a[n]))))) for n in names)


def _example(models, case, step, parameters=None):
    return simulate(models[f"Bicycle.Examples.{case.example}"], case.stop, step, "cs", parameters or {},
                    relative_tolerance=TOLERANCE, outputs=case.signals)


# --------------------------------------------------------------------------- the Modelica text

CONNECTOR = re.compile(r"^\s*Bicycle\.Interfaces\.Real(Input|Output)\s+(\w+)", re.M)
PLAIN_SIGNAL = re.compile(r"^\s*(input|output)\s", re.M)


def _code(path: Path) -> str:
    """The file without comments, string literals (descriptions, documentation) and annotations
    (the graphics of components and connect equations, the class's own annotation)."""
    text = re.sub(r'"(\\.|[^"\\])*"', '""', path.read_text(encoding="utf-8"), flags=re.S)
    text = re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)
    while match := re.search(r"\bannotation\s*\(", text):
        depth, end = 0, match.end() - 1
        for end in range(match.end() - 1, len(text)):
            depth += {"(": 1, ")": -1}.get(text[end], 0)
            if depth == 0:
                break
        text = text[:match.start()] + text[end + 1:]
    return text


def _file(model: str) -> Path:
    return LIBRARY.joinpath(*model.split(".")[1:]).with_suffix(".mo")


@pytest.mark.parametrize("model", BLOCKS + BICYCLES)
def test_signals_are_real_input_and_output_connectors(model):
    """Every input and output of a block or second-order bicycle is a RealInput/RealOutput
    connector (MSL style), none a plain ``input``/``output`` variable."""
    code = _code(_file(model))
    assert not PLAIN_SIGNAL.search(code), f"{model}: plain input/output declaration left"
    assert CONNECTOR.findall(code), f"{model}: no RealInput/RealOutput connector"


def _components(code: str) -> dict[str, str]:
    """Instance name -> class of the Bicycle.* components a model declares."""
    return {m.group(2): m.group(1) for m in re.finditer(r"^\s*(Bicycle\.[\w.]+)\s+(\w+)\s*[(\"]", code, re.M)}


@pytest.mark.parametrize("example", EXAMPLES)
def test_examples_compose_blocks_with_connect_only(example):
    """An example with a controller, delay or source connects every connector of that block and
    has no equation besides connect(); examples without a block bind only constant inputs."""
    code = _code(LIBRARY / "Examples" / f"{example}.mo")
    body = re.split(r"\bend\s+\w+\s*;", code.split("equation", 1)[1])[0] if "equation" in code else ""
    statements = [s.strip() for s in body.split(";") if s.strip()]
    assert all(s.startswith("connect(") for s in statements), f"{example}: equations other than connect()"
    connected = {e.strip() for s in statements for e in s[len("connect("):-1].split(",")}
    blocks = {n: c for n, c in _components(code).items() if c.split(".")[1] in ("Control", "Rider", "Sources")}
    for name, cls in blocks.items():
        for _, connector in CONNECTOR.findall(_code(_file(cls))):
            assert f"{name}.{connector}" in connected, f"{example}: {name}.{connector} is not connected"
    if not blocks:
        assert "*" not in code, f"{example}: a control law written as a binding"
    if example in CASES:  # the cases below mirror exactly these connections
        expected = {tuple(sorted(c.replace(" ", "").split("->"))) for c in CASES[example].connections}
        pairs = {tuple(sorted(e.strip() for e in s[len("connect("):-1].split(","))) for s in statements}
        assert expected <= pairs


def test_every_example_with_a_block_is_compared():
    """Every example that contains a block from Control, Rider or Sources has a comparison case."""
    with_blocks = [e for e in EXAMPLES if any(c.split(".")[1] in ("Control", "Rider", "Sources")
                                              for c in _components(_code(LIBRARY / "Examples" / f"{e}.mo")).values())]
    assert with_blocks and sorted(with_blocks) == sorted(CASES)


# --------------------------------------------------------------------------- the FMU interface

def _interface(fmu: Path) -> dict:
    """What a user of the FMU sees: every variable's attributes (not its value reference), the
    units, the model structure by variable name, and the model's description."""
    root = ET.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    variables = [v for v in root.iter("ScalarVariable")]
    names = [v.get("name") for v in variables]
    out = {"description": root.get("description"),
           "units": sorted(ET.tostring(u, encoding="unicode") for u in root.iter("Unit"))}
    for v in variables:
        attrs = {k: x for k, x in v.attrib.items() if k != "valueReference"}
        kind = v[0]
        out[f"variable {v.get('name')}"] = (attrs, kind.tag, dict(kind.attrib))
    for section in root.find("ModelStructure"):
        for unknown in section:
            deps = unknown.get("dependencies")
            deps = None if deps is None else sorted(names[int(i) - 1] for i in deps.split())
            out[f"{section.tag} {names[int(unknown.get('index')) - 1]}"] = deps
    return out


#: What a user of each block's and bicycle's FMU sees (:func:`_interface`), recorded: a change of the
#: library that changes an interface fails :func:`test_fmu_keeps_its_interface`. After a deliberate
#: change, ``COSIM_RECORD_INTERFACES=1 pytest tests/test_connected_examples.py -k interface`` rewrites
#: the file, and its diff shows what users of the FMUs will see change.
INTERFACES = ROOT / "tests" / "data" / "fmu-interfaces.json"


def _recorded_form(interface: dict) -> dict:
    """An interface as it reads back from JSON (tuples become lists)."""
    return json.loads(json.dumps(interface))


def _interface_changes(before: dict, after: dict) -> dict:
    """Key -> (before, after) for every key of either interface whose entry differs."""
    return {k: (before.get(k), after.get(k)) for k in before.keys() | after.keys() if before.get(k) != after.get(k)}


def _json_lines(interfaces: dict) -> str:
    """The interfaces as JSON with one line per entry, so that a change reads as a short diff."""
    models = [f"{json.dumps(model)}: {{\n" + ",\n".join(f"  {json.dumps(key)}: {json.dumps(value)}"
                                                        for key, value in sorted(entries.items())) + "\n }"
              for model, entries in sorted(interfaces.items())]
    return "{\n " + ",\n ".join(models) + "\n}\n"


@pytest.fixture(scope="module")
def interfaces() -> tuple[dict, dict]:
    """The recorded interfaces and those of the blocks and bicycles built from the working tree."""
    built = {r.model: r.fmu for r in build(BLOCKS + BICYCLES, output=os.environ["COSIM_FMU_DIR"], jobs=2)}
    now = {model: _recorded_form(_interface(fmu)) for model, fmu in sorted(built.items())}
    if os.environ.get("COSIM_RECORD_INTERFACES"):
        INTERFACES.write_text(_json_lines(now), encoding="utf-8")
    return json.loads(INTERFACES.read_text(encoding="utf-8")), now


@pytest.mark.parametrize("model", BLOCKS + BICYCLES)
def test_fmu_keeps_its_interface(model, interfaces):
    """The FMU of each block and bicycle has the recorded interface: same variables with the same
    causality, variability, initial, unit, display unit, start and description; same units and
    output/derivative dependencies."""
    recorded, now = interfaces
    assert model in recorded, f"{model} has no recorded interface in {INTERFACES}"
    after = now[model]
    assert any(k.startswith("variable ") and v[0].get("causality") in ("input", "output") for k, v in after.items()
               if isinstance(v, list))
    changed = _interface_changes(recorded[model], after)
    assert not changed, f"{model}: interface changed: {changed}"


def test_interface_change_is_seen(tmp_path, interfaces):
    """A copy of the library whose PD block has another unit for its gain kd and no input phi_dot
    gives an FMU whose interface differs from the recorded one in exactly those entries."""
    shutil.copytree(ROOT / "modelica", tmp_path / "modelica")
    block = tmp_path / "modelica" / "Bicycle" / "Control" / "PD.mo"
    text = block.read_text(encoding="utf-8")
    for old, new in (('kd(unit = "N.m.s/rad")', 'kd(unit = "N.m.s")'), ("T = -kp*phi - kd*phi_dot;", "T = -kp*phi;")):
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    lines = text.splitlines(keepends=True)
    first = next(i for i, line in enumerate(lines) if "RealInput phi_dot" in line)
    block.write_text("".join(lines[:first] + lines[first + 2:]), encoding="utf-8")
    (result,) = build(["Bicycle.Control.PD"], output=tmp_path / "fmus", jobs=1,
                      library_path=str(tmp_path / "modelica"))
    changed = _interface_changes(interfaces[0]["Bicycle.Control.PD"], _recorded_form(_interface(result.fmu)))
    assert changed.keys() >= {"variable kd", "variable phi_dot"}, changed
    assert changed["variable kd"][1][2]["unit"] == "N.m.s"
    assert changed["variable phi_dot"][1] is None


# --------------------------------------------------------------------------- the same system

@pytest.mark.parametrize("start", [0.0, 1.0], ids=["from-t0", "jump-at-1s"])
def test_source_example_equals_master_with_python_source(models, start):
    """Bicycle + torque source in one FMU = bicycle FMU + Python Step under Jacobi, h = 0.01 s
    (the step at a communication point or at the start), to <= 1e-9."""
    case = CASES["SelfStabilizingTorqueStep"]
    blocks = {"torque": ("Step", {"amplitude": 1.0, "start": start})}
    one = _example(models, case, 0.01, {"torque.start": start})
    parts = case.master(models, 0.01, "jacobi", blocks=blocks)
    assert np.array_equal(one["time"], parts["time"])
    assert np.ptp(one["bicycle.eta"]) > 1.0  # the torque acts: the comparison sees something
    assert _difference(one, parts, case.signals) <= EXACT
    if start > 0:  # recorded right after the step, the steer angle misses the jump for one step
        after_step = case.master(models, 0.01, "jacobi", blocks=blocks, sampling="after-step")
        assert _difference(one, after_step, ["bicycle.delta"]) > 1e-4
        assert _difference(one, after_step, ["bicycle.phi", "bicycle.psi", "bicycle.eta"]) <= EXACT


def test_gauss_seidel_feeds_a_source_one_step_ahead(models):
    """Why the source comparison uses Jacobi: Gauss-Seidel steps the source first and feeds its
    value at the end of each step, so the jump at 1 s reaches the bicycle one step early."""
    case = CASES["SelfStabilizingTorqueStep"]
    blocks = {"torque": ("Step", {"amplitude": 1.0, "start": 1.0})}
    one = _example(models, case, 0.01, {"torque.start": 1.0})
    early = _example(models, case, 0.01, {"torque.start": 0.99})
    parts = case.master(models, 0.01, "gauss-seidel", blocks=blocks)
    assert _difference(one, parts, case.signals) > 1e-4
    # The bicycle integrates as if the torque came at 0.99 s (its steer angle, a direct
    # feedthrough of the torque, is sampled with the source's value at 0.99 s: left out).
    assert _difference(early, parts, ["bicycle.phi", "bicycle.psi", "bicycle.eta"]) <= EXACT


def _closed_loop(case, models, example):
    """The continuous-time closed loop x' = F x + G r(t) of the bicycle FMU's linearization and
    the Python blocks' linear models, wired by the case's connections, and its initial state
    (the example FMU's states at t = 0). Outputs y = M (C x + r)."""
    lin = linearize(models[case.bicycle], {k: v for k, v in case.parameters.items() if "." not in k}).system
    parts = [(case.name, lin.A, lin.B, lin.C, lin.D, lin.inputs, lin.outputs, None)]
    for name, (block, parameters) in case.blocks.items():
        b = registry.lookup(block).create(name, parameters)
        m = b.linear({})
        parts.append((name, m.A, m.B, m.C, m.D, m.inputs, m.outputs, b))
    ins = [f"{p[0]}.{i}" for p in parts for i in p[5]]
    outs = [f"{p[0]}.{o}" for p in parts for o in p[6]]
    n = [p[1].shape[0] for p in parts]
    A = np.zeros((sum(n), sum(n)))
    B = np.zeros((sum(n), len(ins)))
    C = np.zeros((len(outs), sum(n)))
    D = np.zeros((len(outs), len(ins)))
    i = j = k = 0
    for (_, a, b, c, d, pin, pout, _), size in zip(parts, n):
        A[i:i + size, i:i + size], B[i:i + size, j:j + len(pin)] = a, b
        C[k:k + len(pout), i:i + size], D[k:k + len(pout), j:j + len(pin)] = c, d
        i, j, k = i + size, j + len(pin), k + len(pout)
    S = np.zeros((len(ins), len(outs)))  # u = S y
    for text in case.connections:
        source, target = (s.strip() for s in text.split("->"))
        S[ins.index(target), outs.index(source)] = 1.0
    M = np.linalg.inv(np.eye(len(outs)) - D @ S)  # y = M (C x + r): the algebraic loop solved
    F, G = A + B @ S @ M @ C, B @ S @ M

    def exogenous(t):
        r = np.zeros(len(outs))
        for name, *_, block in parts[1:]:
            r[[outs.index(f"{name}.{o}") for o in block.outputs]] = block.exogenous(t)
        return r

    # The bicycle starts where the example starts it; a block's states start where the Python
    # block starts them (the Modelica twin may realize them differently: the Pade delay's
    # controllable canonical form is not python-control's realization, both start at 0).
    states = [f"{case.name}.{s}" for s in lin.states]
    first = simulate(models[f"Bicycle.Examples.{case.example}"], 0.01, 0.01, "cs", {}, outputs=states)[0]
    x0 = np.concatenate([[first[s] for s in states]]
                        + [getattr(p[-1], "x0", np.zeros(p[1].shape[0])) for p in parts[1:]])
    return F, G, M, C, exogenous, outs, x0


@pytest.mark.parametrize("example", sorted(CASES))
def test_example_equals_continuous_closed_loop_of_bicycle_and_python_blocks(models, example):
    """The example FMU (one model, the loop closed by connect()) equals the exact solution
    (matrix exponentials, the sources piecewise constant between communication points) of the
    bicycle FMU's linear model wired to the Python blocks' linear models, to <= 1e-9."""
    case, h = CASES[example], 0.01
    F, G, M, C, exogenous, outs, x = _closed_loop(case, models, example)
    one = _example(models, case, h)
    rows = []
    for t in one["time"]:
        r = exogenous(t)
        rows.append(M @ (C @ x + r))
        E = expm(np.block([[F, (G @ r)[:, None]], [np.zeros((1, F.shape[0] + 1))]]) * h)
        x = E[:-1, :-1] @ x + E[:-1, -1]
    exact = {name: np.array(rows)[:, outs.index(name)] for name in case.signals}
    assert max(np.ptp(exact[s]) for s in case.signals) > 1e-3  # something happens
    assert _difference(exact, one, case.signals) <= EXACT


@pytest.mark.parametrize("algorithm", [a.name for a in algorithms.algorithms(one_ode=False)])
@pytest.mark.parametrize("example", FEEDBACK)
def test_master_with_python_block_equals_master_with_the_examples_block(models, example, algorithm):
    """The co-simulation with the Python block equals the co-simulation with the FMU of the
    Modelica block the example connects (Bicycle.Control.*, Bicycle.Sources.*), to <= 1e-9."""
    case = CASES[example]
    python = case.master(models, 0.01, algorithm)
    modelica = case.master(models, 0.01, algorithm, twins=True)
    assert max(np.ptp(python[s]) for s in case.signals) > 1e-3
    assert _difference(python, modelica, case.signals) <= EXACT


@pytest.mark.parametrize("example", FEEDBACK)
def test_feedback_through_the_master_converges_to_the_example_at_first_order(models, example):
    """The master's loop (torque or steer angle held over each step, Gauss-Seidel) is not the
    example's continuous loop: the gap is clearly above rounding at h = 0.01 s and halves with
    the step (first order), so both describe the same system in the limit."""
    case = CASES[example]
    errors = []
    for h in (0.01, 0.005):
        one, parts = _example(models, case, h), case.master(models, h, "gauss-seidel")
        errors.append(_difference(one, parts, case.signals))
    assert errors[0] > 1e-6
    assert 1.7 < errors[0] / errors[1] < 2.3, errors


def _example_alone(models, case, step) -> dict:
    """The example FMU as the one component of a model-exchange system at ``step`` [s]: the
    signals of its parts (local variables of the composed model, which has no outputs) are
    observed as if they were its outputs, named as in the case."""
    fmu = models[f"Bicycle.Examples.{case.example}"]
    example = FMUComponent("example", fmu, tolerance=TOLERANCE)
    example.outputs = list(case.signals)
    spec = system_from_dict({"system": {"stop": case.stop, "step": step, "algorithm": "model-exchange",
                                        "record": [f"example.{s}" for s in case.signals]},
                             "components": {"example": {"fmu": str(fmu)}}})
    data = run_components(spec, {"example": example}).data
    return {"time": data["time"]} | {s: data[f"example.{s}"] for s in case.signals}


def _jumps(case) -> list[float]:
    """Times in (0, stop) [s] where a source of the case jumps (Pulse, and Step, a Pulse without end)."""
    from cosim.cosimulation.blocks import Pulse

    sources = [registry.lookup(b).create(n, p) for n, (b, p) in case.blocks.items()]
    return sorted(t for b in sources if isinstance(b, Pulse) for t in (b.start, b.start + b.duration)
                  if 0 < t < case.stop)


@pytest.mark.parametrize("step", [1e-3, 5e-3], ids=["h=1e-3", "h=5e-3"])
@pytest.mark.parametrize("example", sorted(CASES))
def test_example_equals_its_parts_under_model_exchange(models, example, step):
    """Same system, same step: the bicycle FMU and the Python blocks coupled in continuous time
    (algorithm = "model-exchange", RK4 at ``step``) equal the example FMU alone through the same
    master at the same step, to <= 1e-9; feedback loops and sources alike."""
    case = CASES[example]
    parts = case.master(models, step, "model-exchange")
    one = _example_alone(models, case, step)
    assert np.array_equal(one["time"], parts["time"]) and len(parts) == round(case.stop / step) + 1
    assert max(np.ptp(parts[s]) for s in case.signals) > 1e-3  # something happens
    assert _difference(one, parts, case.signals) <= EXACT


def test_model_exchange_comparison_sees_a_wrong_gain(models):
    """The comparison above can fail: a steer-feedback gain off by 1e-6 (relative) is 200 times
    the agreement bound away."""
    case = CASES["InvertedPendulumSteerFeedback"]
    block, parameters = case.blocks["controller"]
    wrong = {"controller": (block, {**parameters, "k2": parameters["k2"] * (1 + 1e-6)})}
    parts = case.master(models, 1e-3, "model-exchange", blocks=wrong)
    assert _difference(_example_alone(models, case, 1e-3), parts, case.signals) > 100 * EXACT


@pytest.mark.parametrize("example", sorted(CASES))
def test_model_exchange_converges_to_the_example(models, example):
    """The model-exchange coupling converges to the example's Co-Simulation FMU (its own
    error-controlled integrator, tolerance 1e-12): at fourth order (RK4) where the sources are
    smooth over the run, <= 1e-9 at h = 1e-3 s; at first order where a source jumps inside the
    run (the jump on a communication point acts at the last stage of the step ending there)."""
    case = CASES[example]
    errors = {h: _difference(_example(models, case, h), case.master(models, h, "model-exchange"), case.signals)
              for h in (0.02, 0.01)}
    ratio = errors[0.02] / errors[0.01]
    if _jumps(case):
        assert errors[0.01] > 1e-6 and 1.8 < ratio < 2.2, errors
    else:
        assert errors[0.02] > 1e-10 and 13 < ratio < 19, errors
        assert _difference(_example(models, case, 1e-3), case.master(models, 1e-3, "model-exchange"),
                           case.signals) <= EXACT


MIRRORS = {"WhippleLinearRiderPush": "rider-p-control.toml", "WhippleLinearLQRDelay": "lqr-autopilot.toml"}


@pytest.mark.parametrize("example", sorted(MIRRORS))
def test_example_is_the_system_file_with_its_twins(models, example):
    """The example is its system file with every Python block swapped for its Modelica twin (as
    SSP export does): the same connections, and the example FMU's parameter values are the
    twins' (the LQR design's gains, the delay's tau) and the bicycle's parameter set."""
    from fmpy import read_model_description

    from cosim.cosimulation.modelica_twins import with_twins
    from cosim.analytic.parameters import parameters_for_model

    spec, _ = with_twins(load_system(ROOT / "cosim" / "systems" / MIRRORS[example]))
    case = CASES[example]
    assert sorted(str(c) for c in spec.connections) == sorted(case.connections)
    md = read_model_description(str(models[f"Bicycle.Examples.{example}"]))
    start = {v.name: float(v.start) for v in md.modelVariables if v.start is not None and v.type == "Real"}
    bike = spec.components[case.name]
    assert bike.source == case.bicycle and bike.parameter_set == "benchmark"
    for key, value in {**parameters_for_model("benchmark"), **bike.parameters}.items():
        assert start[f"{case.name}.{key}"] == pytest.approx(value, rel=1e-12, abs=1e-15), key
    assert set(spec.components) == {case.name} | set(case.blocks)
    for name, (block, parameters) in case.blocks.items():
        twin = spec.components[name]
        assert twin.source == registry.lookup(block).twin
        for key, value in twin.parameters.items():
            assert start[f"{name}.{key}"] == pytest.approx(value, rel=1e-9), f"{name}.{key}"
            assert parameters[key] == pytest.approx(value, rel=1e-9), f"{name}.{key}"
