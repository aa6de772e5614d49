"""What makes the generated FMUs and their build fast must not change what they compute:

* the parameter-only subexpressions taken out of ``cosim_eval`` (``cosim_hoist``, computed once per
  parameter change by the runtime) give derivatives and outputs equal, bit for bit, to the model's
  own expressions;
* the compiler commands: a small model as one translation unit (``fmu.UNITY_FILE``), a large one file
  by file with the code no integration step runs (directional derivatives, local variables) at -O0
  and the model's ``eval`` optimized.
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


def _commands(library, tmp_path, monkeypatch, name) -> list[list[str]]:
    """The gcc commands `cosim build` would run for ``name`` (recorded, not run)."""
    flat, model = _explicit(library, name)
    info = describe(library.entry(name), flat, model)
    info.guid = "{00000000-0000-0000-0000-000000000000}"
    sources = tmp_path / "sources"
    write_sources(info, model, sources)
    seen: list[list[str]] = []
    monkeypatch.setattr(fmu_module, "_run_compiler", lambda commands, *args: seen.extend(commands))
    fmu_module.compile_binary(sources, info.identifier, tmp_path / "x.so", generated=(),
                              unoptimized=tuple(unoptimized_sources(info)), objects=tmp_path / "objects")
    assert not (sources / fmu_module.UNITY_FILE).exists(), "the translation unit is removed after the build"
    return [c for c in seen if "-c" in c]


def _compiled(commands) -> dict[str, list[str]]:
    return {c[c.index("-c") + 1]: c for c in commands}


def test_small_model_is_one_translation_unit(library, tmp_path, monkeypatch):
    compiled = _compiled(_commands(library, tmp_path, monkeypatch, "Bicycle.Control.PD"))
    runtime = {"cosim_runtime.c", "fmi2_api.c"}  # the core and the FMI 2 API
    assert runtime <= set(fmu_module.RUNTIME_SOURCES)
    assert set(compiled) == {fmu_module.UNITY_FILE, *runtime}
    assert fmu_module.UNITY_OPTIMIZATION in compiled[fmu_module.UNITY_FILE]
    for source in runtime:
        assert fmu_module.RUNTIME_OPTIMIZATION in compiled[source]


def test_large_model_optimizes_only_what_integration_runs(library, tmp_path, monkeypatch):
    compiled = _compiled(_commands(library, tmp_path, monkeypatch, "Bicycle.Bicycles.Whipple"))
    assert fmu_module.UNITY_FILE not in compiled
    assert "model_jvp.c" in compiled and any(f.startswith("model_locals") for f in compiled)
    for file, command in compiled.items():
        if file == "model_jvp.c" or file.startswith("model_locals"):
            assert "-O0" in command, file
        elif file == "model_functions.c":  # eval: every integration step
            assert "-O0" not in command and "-O1" in command, command
