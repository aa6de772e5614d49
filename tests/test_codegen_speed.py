"""What makes the generated FMUs and their build fast must not change what they compute:

* the parameter-only subexpressions taken out of ``cosim_eval`` (``cosim_hoist``, computed once per
  parameter change by the runtime) give derivatives and outputs equal, bit for bit, to the model's
  own expressions;
* the compiler commands: a small model as one translation unit (``fmu.UNITY_FILE``), a large one file
  by file, either way with the code no integration step runs (directional derivatives)
  unoptimized and the model's ``eval`` optimized; the local variables are no code but a tape.
"""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from cosim.compiler import fmu as fmu_module
from cosim.compiler.codegen import casadi_functions, unoptimized_sources, write_sources
from cosim.compiler.description import describe
from cosim.compiler.flatten import flatten
from cosim.compiler.library import load_library
from cosim.compiler.ode import make_explicit

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def library():
    return load_library()


def _explicit(library, name):
    flat = flatten(library, name)
    return flat, make_explicit(flat)


@pytest.mark.parametrize("name, hoisted", [("Bicycle.Bicycles.WhippleLinear", True), ("Bicycle.Rider.PadeDelay", True),
                                           ("Bicycle.Bicycles.Whipple", True), ("Bicycle.Control.PD", False)],
                         ids=["linear-bicycle", "pade-delay", "nonlinear-bicycle", "pd-controller"])
def test_hoisted_evaluation_equals_the_model_bit_for_bit(library, name, hoisted):
    _, model = _explicit(library, name)
    calc, start, evaluate, jvp, hoist, *chunks = casadi_functions(model)
    assert (hoist.numel_out(0) > 0) == hoisted
    direct = ca.Function("direct", [model.t, model.x, model.u, model.p], [model.xdot])
    # near the model's own parameter values (where a default is an expression: 1), random states
    defaults = np.array([s.start if isinstance(s.start, (int, float)) else 1.0 for s in model.parameters], float)
    rng = np.random.default_rng(7)
    for _ in range(20):
        x = rng.uniform(-0.5, 0.5, model.x.numel())
        u = rng.uniform(-1.0, 1.0, model.u.numel())
        p = defaults * rng.uniform(0.9, 1.1, defaults.size)
        expected = direct(0.3, x, u, p).full()
        assert np.isfinite(expected).all()
        assert np.array_equal(evaluate(0.3, x, u, p, hoist(p))[0].full(), expected)


def _commands(library, tmp_path, monkeypatch, name, units: list[str] | None = None) -> list[list[str]]:
    """The gcc commands `cosim build` would run for ``name`` (recorded, not run); the text of the
    one translation unit of a small model is appended to ``units``."""
    flat, model = _explicit(library, name)
    info = describe(library.entry(name), flat, model)
    info.guid = "{00000000-0000-0000-0000-000000000000}"
    sources = tmp_path / "sources"
    write_sources(info, model, sources)
    seen: list[list[str]] = []

    def record(commands, *args):
        seen.extend(commands)
        unity = sources / fmu_module.UNITY_FILE
        if unity.exists() and any("-c" in c for c in commands):  # the compilation, not the link
            units.append(unity.read_text())

    units = [] if units is None else units
    monkeypatch.setattr(fmu_module, "_run_compiler", record)
    fmu_module.compile_binary(sources, info.identifier, tmp_path / "x.so", generated=(),
                              unoptimized=tuple(unoptimized_sources(info)), objects=tmp_path / "objects")
    assert not (sources / fmu_module.UNITY_FILE).exists(), "the translation unit is removed after the build"
    return [c for c in seen if "-c" in c]


def _compiled(commands) -> dict[str, list[str]]:
    return {c[c.index("-c") + 1]: c for c in commands}


def test_small_model_is_one_translation_unit(library, tmp_path, monkeypatch):
    compiled = _compiled(_commands(library, tmp_path, monkeypatch, "Bicycle.Control.PD"))
    runtime = {"cosim_runtime.c", "fmi2_api.c", "cosim_tape.c"}  # the core, the FMI 2 API, the tape interpreter
    assert runtime <= set(fmu_module.RUNTIME_SOURCES)
    assert set(compiled) == {fmu_module.UNITY_FILE, *runtime}
    assert fmu_module.UNITY_OPTIMIZATION in compiled[fmu_module.UNITY_FILE]
    for source in runtime:
        assert fmu_module.RUNTIME_OPTIMIZATION in compiled[source]


def test_small_model_compiles_what_integration_never_runs_without_optimization(library, tmp_path, monkeypatch):
    # an assembly small enough for one translation unit still has directional derivatives
    name = "Bicycle.Bicycles.SelfStabilizingGyro"
    units: list[str] = []
    compiled = _compiled(_commands(library, tmp_path, monkeypatch, name, units))
    assert fmu_module.UNITY_FILE in compiled and len(units) == 1
    lines = units[0].splitlines()
    pragma = lines.index(fmu_module.UNOPTIMIZED_PRAGMA)
    included = [line.split('"')[1] for line in lines if line.startswith("#include")]
    _, model = _explicit(library, name)
    unoptimized = unoptimized_sources(model)
    assert "model_jvp.c" in unoptimized
    assert sorted(included) == sorted(["model.c", "model_functions.c", *unoptimized]), "every model file once"
    after = [line.split('"')[1] for line in lines[pragma + 1:]]
    assert sorted(after) == sorted(unoptimized), "only the code no integration step runs follows the pragma"


def test_large_model_optimizes_only_what_integration_runs(library, tmp_path, monkeypatch):
    compiled = _compiled(_commands(library, tmp_path, monkeypatch, "Bicycle.Bicycles.Whipple"))
    assert fmu_module.UNITY_FILE not in compiled
    assert "model_jvp.c" in compiled
    assert not any(f.startswith("model_locals") for f in compiled), "the local variables are a tape in model.c"
    for file, command in compiled.items():
        if file == "model_jvp.c":
            assert "-O0" in command, file
        elif file == "model_functions.c":  # eval: every integration step
            assert "-O0" not in command and "-O1" in command, command
