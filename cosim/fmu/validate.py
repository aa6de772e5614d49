"""`cosim validate`: FMPy's validation plus this project's own checks; every problem is listed."""
from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from cosim.compiler.fmu import MANIFEST
from cosim.fmu.access import FMU, get_continuous_states, set_continuous_states

DERIVATIVE_RTOL = 1e-6


def _archive_problems(path: Path, md) -> list[str]:
    problems = []
    with zipfile.ZipFile(path) as archive:
        names = set(archive.namelist())
    for configuration in md.buildConfigurations:
        for file_set in configuration.sourceFileSets:
            for source in file_set.sourceFiles:
                if f"sources/{source}" not in names:
                    problems.append(f"source file '{source}' listed in modelDescription.xml is missing from sources/")
    if md.generationTool and md.generationTool.startswith("cosim") and MANIFEST not in names:
        problems.append(f"build manifest {MANIFEST} is missing")
    return problems


def _runtime_problems(fmu: FMU) -> list[str]:
    """Instantiate in ME and CS, check derivatives against finite differences and FMU state round trips."""
    problems = []
    md = fmu.description
    t1 = float(md.defaultExperiment.stopTime) if md.defaultExperiment and md.defaultExperiment.stopTime else 1.0
    # Model Exchange: directional derivatives against central differences of the derivatives.
    if md.modelExchange is not None and md.derivatives:
        try:
            me = fmu.instantiate("me")
            me.setupExperiment(startTime=0.0)
            me.enterInitializationMode()
            me.exitInitializationMode()
            me.enterContinuousTimeMode()
            nx = len(md.derivatives)
            x = get_continuous_states(me, nx) + 0.01 * (1 + np.arange(nx))  # away from the trivial point
            set_continuous_states(me, x)
            if md.modelExchange.providesDirectionalDerivative:
                unknowns = [fmu.vr[n] for n in fmu.derivatives]
                knowns = [fmu.vr[n] for n in fmu.states]
                for k in range(nx):
                    seed = [0.0] * nx
                    seed[k] = 1.0
                    ad = np.array(me.getDirectionalDerivative(unknowns, knowns, seed))
                    h = 1e-6 * max(1.0, abs(x[k]))
                    xp, xm = x.copy(), x.copy()
                    xp[k] += h
                    xm[k] -= h
                    set_continuous_states(me, xp)
                    fp = np.array(me.getReal(unknowns))
                    set_continuous_states(me, xm)
                    fm = np.array(me.getReal(unknowns))
                    set_continuous_states(me, x)
                    fd = (fp - fm) / (2 * h)
                    worst = np.max(np.abs(ad - fd) / np.maximum(1.0, np.abs(fd)))
                    if worst > DERIVATIVE_RTOL:
                        problems.append(f"directional derivative w.r.t. state '{fmu.states[k]}' differs from "
                                        f"finite differences by {worst:.2e} (relative)")
            me.terminate()
            me.freeInstance()
        except Exception as exc:
            problems.append(f"Model Exchange: {exc}")
    # Co-Simulation: FMU state round trip.
    if md.coSimulation is not None:
        try:
            cs = fmu.instantiate("cs")
            cs.setupExperiment(startTime=0.0)
            cs.enterInitializationMode()
            cs.exitInitializationMode()
            watch = [fmu.vr[n] for n in fmu.names("output")] + [fmu.vr[n] for n in fmu.states]
            h = t1 / 10
            cs.doStep(0.0, h)
            if md.coSimulation.canGetAndSetFMUstate:
                state = cs.getFMUstate()
                cs.doStep(h, h)
                first = cs.getReal(watch)
                cs.setFMUstate(state)
                cs.doStep(h, h)
                second = cs.getReal(watch)
                if first != second:
                    problems.append("FMU state round trip: outputs after restore + step differ")
                if md.coSimulation.canSerializeFMUstate:
                    blob = cs.serializeFMUstate(state)
                    restored = cs.deSerializeFMUstate(blob)
                    cs.setFMUstate(restored)
                    cs.doStep(h, h)
                    if cs.getReal(watch) != first:
                        problems.append("serialized FMU state round trip: outputs differ")
                    cs.freeFMUstate(restored)
                cs.freeFMUstate(state)
            values = np.array(cs.getReal(watch))
            if not np.all(np.isfinite(values)):
                problems.append("Co-Simulation: non-finite outputs after two steps")
            cs.terminate()
            cs.freeInstance()
        except Exception as exc:
            problems.append(f"Co-Simulation: {exc}")
    return problems


def validate(path: str | Path) -> list[str]:
    """All problems found in the FMU (empty list: valid).

    Raises
    ------
    FMUError
        If the file cannot be read as an FMU at all (see :func:`cosim.fmu.access.read_fmu`): not a zip,
        unsafe member names, no or broken ``modelDescription.xml``, not FMI 2.0.
    """
    from fmpy.validation import validate_fmu

    from cosim.fmu.access import read_fmu

    path = Path(path)
    read_fmu(path)  # refuses what must not even be unpacked
    try:
        problems = [f"fmpy: {p}" for p in validate_fmu(str(path))]
    except Exception as exc:  # FMPy's checks raise bare exceptions on odd content
        problems = [f"fmpy: the validation stopped: {type(exc).__name__}: {exc}"]
    if problems:
        return problems  # the model description is unusable for the checks below
    with FMU(path) as fmu:
        problems += _archive_problems(path, fmu.description)
        problems += _runtime_problems(fmu)
    return problems
