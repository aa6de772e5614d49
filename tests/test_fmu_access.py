"""The FMI function types of an instance are found once per FMPy class (cosim.fmu.access): later
instances take them from the first, with the same types FMPy gives an instance of its own, and
behave the same."""
from __future__ import annotations

import numpy as np
import pytest

from cosim.fmu import access

MODEL = "Bicycle.Bicycles.WhippleLinear"


def _types(instance) -> dict:
    return {name: (f.argnames, f.argtypes, f.restype) for name, f in instance._functions.items()}


@pytest.mark.parametrize("kind", ["cs", "me"], ids=["co-simulation", "model-exchange"])
def test_types_equal_fmpy_own(fmus, kind):
    from fmpy.fmi2 import FMU2Model, FMU2Slave

    fmu = access.FMU(fmus[MODEL])
    section = fmu.description.coSimulation if kind == "cs" else fmu.description.modelExchange
    own = (FMU2Slave if kind == "cs" else FMU2Model)(guid=fmu.description.guid, unzipDirectory=fmu.unzipdir,
                                                      modelIdentifier=section.modelIdentifier)
    first, second = fmu.instantiate(kind, "first"), fmu.instantiate(kind, "second")
    try:
        assert isinstance(second, FMU2Slave if kind == "cs" else FMU2Model)
        assert len(_types(own)) > 30
        assert _types(first) == _types(own) and _types(second) == _types(own)
    finally:
        for instance in (first, second):
            instance.freeInstance()
        own.freeLibrary()


def test_later_instances_step_like_the_first(fmus):
    fmu = access.FMU(fmus[MODEL])
    vr = [fmu.vr["phi"], fmu.vr["delta"]]
    runs = []
    for name in ("first", "second", "third"):
        instance = fmu.instantiate("cs", name)
        instance.setReal([fmu.vr["phi0"], fmu.vr["v"]], [0.05, 3.0])
        instance.setupExperiment(startTime=0.0)
        instance.enterInitializationMode()
        instance.exitInitializationMode()
        rows = []
        for k in range(100):
            instance.doStep(k * 0.01, 0.01)
            rows.append(instance.getReal(vr))
        instance.terminate()
        instance.freeInstance()
        runs.append(np.array(rows))
    assert np.abs(runs[0]).max() > 1e-3  # the bicycle moved
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])
