"""A new engine or coupling algorithm is one class registered where the others are: defined here
(test-only), it is picked up by the parametrised engine tests, by system files, the master, the
matrix's prediction and the SSP export, with nothing else changed."""
from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

import numpy as np
import pytest

import test_fmus
from cosim import engines
from cosim.cosimulation import algorithms
from cosim.cosimulation.algorithms.jacobi import Jacobi
from cosim.cosimulation.factory import create_components, run_system
from cosim.cosimulation.master import System
from cosim.cosimulation.ssp import system_structure
from cosim.cosimulation.system import SystemError_, load_system, system_from_dict
from cosim.fmu.simulate import simulate
from cosim.matrix.predict import predict_case
from cosim.matrix.spec import SpecError, spec_from_dict
from registered_engines import engine_params

ROOT = Path(__file__).resolve().parents[1]
SYSTEM = ROOT / "cosim" / "systems" / "rider-p-control.toml"


@pytest.fixture()
def python_jacobi():
    """Jacobi stepped by the master's Python loop only (no code for the C loop): a trivially
    correct variant, registered for the test and removed afterwards."""

    @algorithms.register
    class PythonJacobi(Jacobi):
        name = "python-jacobi"
        fast_code = None

    yield algorithms.algorithm("python-jacobi")
    algorithms.unregister("python-jacobi")


@pytest.fixture()
def delegate():
    """An independent engine in name only: every call goes to FMPy's engine. Registered for the
    test and removed afterwards."""

    @engines.register
    class Delegate(engines.Engine):
        name = "delegate"
        module = "fmpy"
        independent = True

        def load(self):
            return engines.engine("fmpy").load()

        def run_fmu(self, fmu, stop_time, step, start_values=None, outputs=None):
            return engines.engine("fmpy").run_fmu(fmu, stop_time, step, start_values, outputs)

    yield engines.engine("delegate")
    engines.unregister("delegate")


def test_registered_engine_joins_the_parametrised_engine_tests(delegate, fmus):
    """The parameters of test_fmus.py's engine tests now include the delegate (runs FMUs of FMI
    2.0 and 3.0, not SSPs); its check runs on it unchanged (test_cs_engines_agree)."""
    assert "delegate" in {p.id for p in engine_params("fmu", reference=False)}
    params = {p.id: p for p in engine_params("fmu", independent=True, reference=False)}
    assert params["delegate"].values == (delegate,) and not params["delegate"].marks
    assert "delegate" in {p.id for p in engine_params("fmu", "3.0", independent=True, reference=False)}
    assert "delegate" not in {p.id for p in engine_params("ssp")}
    assert delegate.load().__name__ == delegate.module
    fmu = fmus[test_fmus.SELF]
    fmpy_cs = simulate(fmu, test_fmus.STOP, test_fmus.STEP, "cs", test_fmus.START, outputs=["phi", "delta"])[1:]
    test_fmus.test_cs_engines_agree(fmus, fmpy_cs, delegate)
    with pytest.raises(engines.EngineUnsupported, match="the engine delegate does not run SSP archives"):
        delegate.run_ssp("system.ssp", ["bike.phi"])


def test_engine_names_are_unique_and_known(delegate):
    with pytest.raises(ValueError, match="the engine name 'ecos' is taken by Ecos"):
        engines.register(type("OtherEcos", (engines.Engine,), {"name": "ecos"}))
    with pytest.raises(engines.UnknownEngine, match=r"unknown engine 'nope' \(known: libcosim, ecos, fmpy, "
                                                    r"cosim, delegate\)"):
        engines.engine("nope")


def _fast_loop_used(spec, fmu_dir, monkeypatch) -> tuple[np.ndarray, bool]:
    """The recorded signals of ``spec`` and whether the master's C loop stepped it."""
    used = []
    original = System._fast_steps

    def spy(self, *args):
        used.append(True)
        return original(self, *args)

    monkeypatch.setattr(System, "_fast_steps", spy)
    return run_system(spec, fmu_dir).data, bool(used)


def test_registered_algorithm_is_run_by_the_master(python_jacobi, fmus, monkeypatch):
    """A system file may name it; the master steps it in Python (it has no C loop code) to the
    Jacobi result of the C loop, bit for bit."""
    fmu_dir = next(iter(fmus.values())).parent
    jacobi = load_system(SYSTEM)
    assert jacobi.algorithm == "jacobi"
    data = tomllib.loads(SYSTEM.read_text())
    data["system"]["algorithm"] = "Python-Jacobi"  # as a system file may write it
    variant = system_from_dict(data, SYSTEM)
    assert variant.algorithm == "python-jacobi"
    reference, reference_in_c = _fast_loop_used(jacobi, fmu_dir, monkeypatch)
    data, in_c = _fast_loop_used(variant, fmu_dir, monkeypatch)
    assert reference_in_c and not in_c
    assert data.dtype == reference.dtype and len(data) == len(reference) > 100
    for name in data.dtype.names:
        np.testing.assert_array_equal(data[name], reference[name], err_msg=name)


def test_registered_algorithm_is_exported_and_predicted(python_jacobi, fmus):
    """SSP export describes it as it describes Jacobi (OSP FixedStepAlgorithm, OMSimulator's
    fixed-step master); the matrix accepts it and predicts Jacobi's lags, not Gauss-Seidel's."""
    spec = load_system(SYSTEM)
    components = create_components(spec, next(iter(fmus.values())).parent)
    try:
        files = {name: Path(c.fmu.path) for name, c in components.items() if hasattr(c, "fmu")}
    finally:
        for component in components.values():
            component.close()
    assert files
    variant = dataclasses.replace(spec, algorithm="python-jacobi")
    assert system_structure(variant, files) == system_structure(spec, files)
    with pytest.raises(SystemError_, match="the system uses 'gauss-seidel'"):
        system_structure(dataclasses.replace(spec, algorithm="gauss-seidel"), files)

    def max_re(algorithm: str) -> float:
        study = {"name": "rider", "observe": "bike.phi",
                 "connections": ["bike.phi -> rider.phi", "rider.delta -> bike.delta"],
                 "components": {"bike": {"model": "Bicycle.Bicycles.InvertedPendulum", "parameters": {"V": "=V"}},
                                "rider": {"python": "SteerAngleFeedback", "parameters": {"k2": 1.0}}},
                 "axes": {"V": [3.0]}}
        spec = spec_from_dict({"matrix": {"algorithm": algorithm, "step": 0.05}, "study": [study]})
        return predict_case(spec.cases()[0], {})[1]["max_re"]

    assert max_re("python-jacobi") == max_re("jacobi") != max_re("gauss-seidel")
    with pytest.raises(SpecError, match="'algorithm' must be one of jacobi, gauss-seidel, python-jacobi, "
                                        "got 'model-exchange'"):
        spec_from_dict({"matrix": {"algorithm": "model-exchange"}, "study": []})


def test_algorithm_names_are_lower_case_and_unique(python_jacobi):
    with pytest.raises(ValueError, match="the coupling algorithm name 'jacobi' is taken by Jacobi"):
        algorithms.register(type("OtherJacobi", (Jacobi,), {"name": "jacobi"}))
    with pytest.raises(ValueError, match="a coupling algorithm needs a lower-case name, got 'Newton'"):
        algorithms.register(type("Newton", (Jacobi,), {"name": "Newton"}))
    with pytest.raises(SystemError_, match=r"\[system\] algorithm: must be one of jacobi, gauss-seidel, "
                                           r"model-exchange, python-jacobi, got 'newton'"):
        system_from_dict({"system": {"algorithm": "newton"}})
