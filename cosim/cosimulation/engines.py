"""Run an FMU in independent FMI engines: libcosim (libcosimpy) and Ecos (ecospy).

Used to prove that the FMUs load and run unmodified in other tools; both engines step with a
fixed communication step and the results are returned as FMPy-style structured arrays.

Ecos runs FMI 2.0 and FMI 3.0 Co-Simulation FMUs (and SSPs of either). libcosim has no FMI 3.0:
it crashes the process on an FMI 3 FMU, so its runners refuse one (:class:`EngineUnsupported`)
before libcosim is loaded.
"""
from __future__ import annotations

import contextlib
import ctypes
import shutil
import site
import sys
from pathlib import Path

import numpy as np

from cosim.cosimulation.ssp import PARAMETER_SET
from cosim.cosimulation.system import SystemError_
from cosim.errors import CosimError, SimulationError

NANOSECONDS = 1_000_000_000


class EngineUnavailable(CosimError, ImportError):
    """An independent FMI engine cannot be loaded here; the message says what is missing."""


class EngineUnsupported(CosimError, ValueError):
    """An FMU or SSP the engine cannot run (libcosim and FMI 3.0); the message names the FMUs
    and what runs them instead."""


LIBCOSIM_NO_FMI3 = "libcosim has no FMI 3.0 support (an FMI 3 FMU crashes it)"


def _fmi_version(description: bytes) -> str | None:
    """The ``fmiVersion`` attribute of a modelDescription.xml (None if it cannot be read)."""
    import xml.etree.ElementTree as ET

    try:
        return ET.fromstring(description).get("fmiVersion")
    except ET.ParseError:
        return None


def _refuse_fmi3_fmu_in_libcosim(fmu: str | Path) -> None:
    """:class:`EngineUnsupported` if ``fmu`` is an FMI 3 FMU (other problems are left to libcosim)."""
    import zipfile

    try:
        with zipfile.ZipFile(fmu) as archive:
            version = _fmi_version(archive.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile):
        return
    if version and version.startswith("3."):
        raise EngineUnsupported(f"{fmu}: {LIBCOSIM_NO_FMI3}, and this FMU is FMI {version}; run it in Ecos "
                                "(cosim.cosimulation.engines.run_ecos) or use its FMI 2.0 build (cosim build --fmi-version 2)")


def fmi3_components(ssp: str | Path) -> dict[str, str]:
    """The components of an SSP archive whose FMU is FMI 3: name -> its path in the archive (read
    from SystemStructure.ssd and each FMU's modelDescription.xml, nothing extracted)."""
    import io
    import xml.etree.ElementTree as ET
    import zipfile

    found = {}
    with zipfile.ZipFile(ssp) as archive:
        root = ET.fromstring(archive.read("SystemStructure.ssd"))
        for component in root.iter("{http://ssp-standard.org/SSP1/SystemStructureDescription}Component"):
            source = component.get("source", "")
            try:
                with zipfile.ZipFile(io.BytesIO(archive.read(source))) as fmu:
                    version = _fmi_version(fmu.read("modelDescription.xml"))
            except (KeyError, zipfile.BadZipFile):  # not in the archive, or not an FMU: libcosim says so
                continue
            if version and version.startswith("3."):
                found[component.get("name", source)] = source
    return found


def _refuse_fmi3_ssp_in_libcosim(ssp: str | Path) -> None:
    """:class:`EngineUnsupported` naming the FMI 3 components of ``ssp``, if it has any."""
    found = fmi3_components(ssp)
    if found:
        listed = ", ".join(f"{name} ({source})" for name, source in found.items())
        raise EngineUnsupported(f"{ssp}: {LIBCOSIM_NO_FMI3}, and component{'s' if len(found) > 1 else ''} "
                                f"{listed} {'are' if len(found) > 1 else 'is'} FMI 3.0; run the SSP in Ecos "
                                "(cosim.cosimulation.engines.run_ssp_ecos) or export it with FMI 2.0 components "
                                "(cosim export-ssp --fmi-version 2)")


def _preload_tbb() -> None:
    """Load Intel TBB's ``libtbb.so.12`` by path, for Ecos.

    Ecos' native library links ``libtbb.so.12``. The pip ``tbb`` wheel (part of the test extra)
    installs it into ``<prefix>/lib``, which the dynamic loader does not search; a library that is
    already loaded satisfies the dependency by its soname, so loading it first with RTLD_GLOBAL
    makes ``import ecospy`` work without Debian's ``libtbb12``.
    """
    for prefix in dict.fromkeys((sys.prefix, site.USER_BASE or "", sys.base_prefix)):
        candidate = Path(prefix) / "lib" / "libtbb.so.12"
        if prefix and candidate.is_file():
            ctypes.CDLL(str(candidate), mode=ctypes.RTLD_GLOBAL)
            return


def ecospy():
    """The ``ecospy`` module, importable once TBB is loaded.

    Raises
    ------
    EngineUnavailable
        If ecospy is not installed or its native library cannot be loaded.
    """
    _preload_tbb()
    try:
        import ecospy as module
    except ImportError as exc:
        raise EngineUnavailable(f"Ecos (ecospy) is not installed: pip install ecospy ({exc})") from None
    except OSError as exc:
        raise EngineUnavailable(f"Ecos (ecospy) cannot load its native library: {exc}; "
                                "pip install tbb (in the test extra) or apt-get install libtbb12") from None
    return module


def libcosimpy():
    """The ``libcosimpy`` module; :class:`EngineUnavailable` if it cannot be imported."""
    try:
        import libcosimpy as module
        import libcosimpy.CosimExecution  # noqa: F401  loads the native library
    except (ImportError, OSError) as exc:
        raise EngineUnavailable(f"libcosim (libcosimpy) cannot be loaded: {exc}") from None
    return module


def _result(times, columns: dict[str, list[float]]) -> np.ndarray:
    dtype = [("time", np.float64)] + [(n, np.float64) for n in columns]
    rows = list(zip(times, *columns.values()))
    return np.array(rows, dtype=dtype)


def _steps(stop_time: float, step: float) -> int:
    n = int(round(stop_time / step))
    if n <= 0 or abs(n * step - stop_time) > 1e-9 * max(1.0, stop_time):
        raise SimulationError(f"stop time {stop_time} is not a whole number of steps {step}")
    return n


def run_libcosim(fmu: str | Path, stop_time: float, step: float, start_values: dict | None = None,
                 outputs: list[str] | None = None) -> np.ndarray:
    """Simulate one FMU in libcosim with a fixed step; returns time and the ``outputs`` columns.

    Raises
    ------
    EngineUnsupported
        If the FMU is FMI 3.0 (refused before libcosim is loaded: it would crash the process).
    """
    _refuse_fmi3_fmu_in_libcosim(fmu)
    libcosimpy()
    from libcosimpy import _internal
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from fmpy import read_model_description

    log_output_level(CosimLogLevel.WARNING)  # libcosim traces every FMI call otherwise
    md = read_model_description(str(fmu))
    refs = {v.name: v for v in md.modelVariables}
    names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
    n = _steps(stop_time, step)
    execution = CosimExecution.from_step_size(int(round(step * NANOSECONDS)))
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(Path(fmu).resolve()), instance_name="model"))
    if index < 0:
        raise SimulationError(f"libcosim could not load {fmu}: {_internal.get_last_error_message()}")
    for name, value in (start_values or {}).items():
        v = refs[name]
        setter = {"Real": execution.real_initial_value, "Integer": execution.integer_initial_value,
                  "Boolean": execution.boolean_initial_value}[v.type]
        if not setter(index, v.valueReference, value):
            raise SimulationError(f"libcosim: cannot set {name}: {_internal.get_last_error_message()}")
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    vrs = [refs[name].valueReference for name in names]
    times, columns = [], {name: [] for name in names}

    def record(t):
        values = observer.last_real_values(index, vrs)
        times.append(t)
        for name, value in zip(names, values):
            columns[name].append(value)

    # The first step initializes the FMU; libcosim reports values after each step.
    for k in range(1, n + 1):
        if not execution.step(1):
            raise SimulationError(f"libcosim step {k} failed: {_internal.get_last_error_message()}")
        record(k * step)
    return _result(times, columns)


def run_ecos(fmu: str | Path, stop_time: float, step: float, start_values: dict | None = None,
             outputs: list[str] | None = None) -> np.ndarray:
    """Simulate one FMU (FMI 2.0 or 3.0 Co-Simulation) in Ecos with a fixed step; returns time and
    the ``outputs`` columns."""
    ecospy()
    from ecospy import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
    n = _steps(stop_time, step)
    try:
        structure = EcosSimulationStructure()
        structure.add_model("model", str(Path(fmu).resolve()))
        if start_values:
            structure.add_parameter_set("start", {f"model::{k}": v for k, v in start_values.items()})
        simulation = EcosSimulation(structure=structure, step_size=step)
        simulation.init(parameter_set="start" if start_values else None)
        times, columns = [], {name: [] for name in names}
        for _ in range(n):
            t = simulation.step(1)
            times.append(t)
            for name in names:
                columns[name].append(simulation.get_real(f"model::{name}"))
        simulation.terminate()
    except Exception as exc:
        raise SimulationError(f"Ecos: {exc}") from None
    return _result(times, columns)


def run_ssp_libcosim(ssp: str | Path, signals: list[str], stop_time: float | None = None,
                     step: float | None = None) -> np.ndarray:
    """Run an SSP archive in libcosim and record ``signals`` ("component.variable") after each step.

    Raises
    ------
    EngineUnsupported
        If a component's FMU is FMI 3.0 (refused before libcosim is loaded: it would crash the
        process); the message lists them.
    """
    _refuse_fmi3_ssp_in_libcosim(ssp)
    libcosimpy()
    from libcosimpy import _internal
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)
    with _unpacked_ssp(ssp) as (folder, start, stop, base):
        execution = (CosimExecution.from_ssp_file(str(folder), step) if step
                     else CosimExecution.from_ssp_file(str(folder)))
        if execution is None:
            raise SimulationError(f"libcosim cannot load {ssp}: {_internal.get_last_error_message()}")
        observer = CosimObserver.create_last_value()
        execution.add_observer(observer)
        slaves = {info.name.decode() if isinstance(info.name, bytes) else info.name: info.index
                  for info in execution.slave_infos()}
        refs = []
        for signal in signals:
            comp, _, var = signal.partition(".")
            if comp not in slaves:
                raise SystemError_(f"libcosim: no component '{comp}' in {ssp}")
            variables = {(v.name.decode() if isinstance(v.name, bytes) else v.name): v.reference
                         for v in execution.slave_variables(slaves[comp])}
            refs.append((slaves[comp], variables[var]))
        h = step or base
        n = _steps((stop_time or stop) - start, h)
        times, rows = [], []
        for k in range(1, n + 1):
            if not execution.step(1):
                raise SimulationError(f"libcosim step {k} failed: {_internal.get_last_error_message()}")
            times.append(start + k * h)
            rows.append([observer.last_real_values(s, [r])[0] for s, r in refs])
    return _result(times, {s: [row[j] for row in rows] for j, s in enumerate(signals)})


def run_ssp_ecos(ssp: str | Path, signals: list[str], stop_time: float | None = None,
                 step: float | None = None) -> np.ndarray:
    """Run an SSP archive (FMI 2.0 and/or 3.0 components) in Ecos and record ``signals``
    ("component.variable") after each step."""
    ecospy()
    from ecospy import EcosSimulation

    with _unpacked_ssp(ssp) as (folder, start, stop, base):
        h = step or base
        n = _steps((stop_time or stop) - start, h)
        try:
            simulation = EcosSimulation(ssp_path=str(folder), step_size=h)
            simulation.init(parameter_set=PARAMETER_SET)
            times, columns = [], {s: [] for s in signals}
            for _ in range(n):
                times.append(simulation.step(1))
                for s in signals:
                    comp, _, var = s.partition(".")
                    columns[s].append(simulation.get_real(f"{comp}::{var}"))
            simulation.terminate()
        except Exception as exc:
            raise SimulationError(f"Ecos: {exc}") from None
    return _result(times, columns)


@contextlib.contextmanager
def _unpacked_ssp(ssp: str | Path):
    """:func:`_unpack_ssp` as a context: the folder is removed afterwards."""
    unpacked = _unpack_ssp(ssp)
    try:
        yield unpacked
    finally:
        shutil.rmtree(unpacked[0], ignore_errors=True)


def _unpack_ssp(ssp: str | Path):
    """Extract an SSP into a new temporary folder (the caller removes it); returns
    (folder, start, stop, base step)."""
    import tempfile
    import xml.etree.ElementTree as ET
    import zipfile

    folder = Path(tempfile.mkdtemp(prefix="cosim-ssp-run-"))
    with zipfile.ZipFile(ssp) as archive:
        archive.extractall(folder)
    root = ET.parse(folder / "SystemStructure.ssd").getroot()
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
          "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations"}
    experiment = root.find("ssd:DefaultExperiment", ns)
    start = float(experiment.get("startTime", 0.0))
    stop = float(experiment.get("stopTime"))
    algorithm = experiment.find(".//osp:FixedStepAlgorithm", ns)
    base = float(algorithm.get("baseStepSize"))
    return folder, start, stop, base
