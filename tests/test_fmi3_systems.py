"""Systems with FMI 3.0 components: the co-simulation master runs FMI 3 Co-Simulation
FMUs beside FMI 2 ones and Python blocks, through the C stepping loop (fastloop.c's FMI 3
adapters) and the Python loop alike; the model-exchange coupling integrates FMI 3 Model Exchange
FMUs; `cosim export-ssp --fmi-version 3` writes an SSP of FMI 3 FMUs that Ecos runs to the
master's result, and libcosim (no FMI 3) refuses such an SSP or FMU before it is loaded.

Our FMI 3 FMUs are built from the same model source and run on the same runtime core as the FMI 2
ones, so a system gives the FMI 2 result to round-off (1e-12). The foreign FMI 3 FMUs are the
Reference FMUs (tests/reference_fmus.py) and `fmucontainer -fmi 3` containers of our FMI 2 FMUs.
"""
from __future__ import annotations

import dataclasses
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, run_cli

from cosim.cosimulation.factory import run_system
from cosim.cosimulation.master import RunFailed, System
from cosim.cosimulation.modelica_twins import with_twins
from cosim.cosimulation.ssp import export_ssp
from cosim.cosimulation.system import SystemError_, load_system, system_from_dict

# the quick run (-m 'not slow') leaves this module out: it builds FMI 3 FMUs and the Reference FMUs
pytestmark = pytest.mark.slow

SYSTEMS = sorted((ROOT / "cosim" / "systems").glob("*.toml"))
SAME = 1e-12      # our FMI 3 FMU against its FMI 2 twin: the same C core, round-off only (relative, floor 1)
ECOS = 1e-9       # Ecos against our master on the same SSP, as tests/test_cosimulation.py
CONTAINER = 1e-12  # an fmucontainer FMI 3 wrapper of our FMI 2 FMU: see test_container_component_equals_fmi2


@pytest.fixture(scope="module")
def fmu_dir() -> Path:
    """Where the models are built (on demand, FMI 3 ones under fmi3/): the session's FMU folder."""
    return Path(os.environ["COSIM_FMU_DIR"])


def _as_fmi(spec, version: str, which=None):
    """The system with the model components ``which`` (default: all) built as FMI ``version``."""
    return dataclasses.replace(spec, components={
        name: dataclasses.replace(c, fmi_version=version) if c.kind == "model" and (which is None or name in which)
        else c for name, c in spec.components.items()})


def _run(spec, fmu_dir, fast: bool = True):
    """Run with the C loop (``fast``) or the Python loop; a failed run's result is returned too."""
    saved = System.use_fast_loop
    System.use_fast_loop = fast
    try:
        return run_system(spec, fmu_dir)
    except RunFailed as exc:
        return exc.result
    finally:
        System.use_fast_loop = saved


def _worst(ours: np.ndarray, other: np.ndarray) -> float:
    """Largest difference over every recorded signal, relative with a floor of 1 (rows equal in number)."""
    assert ours.dtype.names == other.dtype.names and len(ours) == len(other), (len(ours), len(other))
    return max(float(np.max(np.abs(ours[n] - other[n]) / np.maximum(1.0, np.abs(ours[n])))) for n in ours.dtype.names)


def _fmi_versions(ssp: Path) -> dict[str, str]:
    """fmiVersion of every FMU under resources/ of an SSP archive."""
    import io
    import xml.etree.ElementTree as ET

    found = {}
    with zipfile.ZipFile(ssp) as archive:
        for name in archive.namelist():
            if name.startswith("resources/") and name.endswith(".fmu"):
                with zipfile.ZipFile(io.BytesIO(archive.read(name))) as fmu:
                    found[name] = ET.fromstring(fmu.read("modelDescription.xml")).get("fmiVersion")
    return found


# ----------------------------------------------------------------- our FMI 3 FMUs beside FMI 2 ones

VARIANTS = {  # which components of a system are FMI 3
    "bike-fmi3": lambda spec: {"bike"},
    "others-fmi3": lambda spec: set(spec.components) - {"bike"},
    "all-fmi3": lambda spec: set(spec.components),
}


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("path", SYSTEMS, ids=[p.stem for p in SYSTEMS])
def test_mixed_system_equals_all_fmi2(path, variant, fmu_dir):
    """Every bundled system as FMUs only (Python blocks replaced by their Modelica twins), some or
    all of its models built as FMI 3.0: the same outcome and signals as the all-FMI-2.0 system to
    1e-12, in the C stepping loop."""
    spec, _ = with_twins(load_system(path))
    reference = _run(spec, fmu_dir)
    mixed = _run(_as_fmi(spec, "3", VARIANTS[variant](spec)), fmu_dir)
    assert mixed.outcome.status == reference.outcome.status, mixed.outcome.message
    assert _worst(reference.data, mixed.data) <= SAME


@pytest.mark.parametrize("loop", ["C", "Python"])
@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_fmi3_bike_with_python_blocks(algorithm, loop, fmu_dir):
    """The LQR autopilot with its Python blocks (native blocks in the C loop: the exact delay, the
    pulse) and the bicycle as an FMI 3 FMU: the FMI 2 result to 1e-12 in both loops and under both
    stepping algorithms; the two loops give bit-identical results (as for FMI 2)."""
    spec = dataclasses.replace(load_system(ROOT / "cosim" / "systems" / "lqr-autopilot.toml"), algorithm=algorithm)
    fmi3 = _as_fmi(spec, "3")
    reference = _run(spec, fmu_dir, fast=loop == "C")
    result = _run(fmi3, fmu_dir, fast=loop == "C")
    assert result.outcome.status == "completed", result.outcome.message
    assert _worst(reference.data, result.data) <= SAME
    other_loop = _run(fmi3, fmu_dir, fast=loop != "C")
    assert _worst(result.data, other_loop.data) == 0.0


WHIPPLE_FALLING = {"u_R0": -5.0, "u_phi0": 0.3}  # as tests/test_runtime_c.py: the steer passes pi/2 near 1 s


@pytest.mark.parametrize("loop", ["C", "Python"])
def test_fmi3_discard_reports_last_successful_time(loop, fmu_dir):
    """The nonlinear Whipple bicycle falling: its integrator fails inside a communication step.
    FMI 3's fmi3DoStep returns Discard with lastSuccessfulTime (an out-argument, not FMI 2's
    fmi2GetRealStatus); the run stops with the rows before the failure and the message names
    fmi3DoStep and the last successful time, which equals the FMI 2 FMU's to 1e-12."""
    system = {"system": {"stop": 3.0, "step": 0.01},
              "components": {"bike": {"model": "Bicycle.Bicycles.Whipple", "parameters": WHIPPLE_FALLING}},
              "connections": []}
    fmi2 = system_from_dict(system)
    fmi3 = _as_fmi(fmi2, "3")
    saved = System.use_fast_loop
    System.use_fast_loop = loop == "C"
    failures = {}
    try:
        for version, spec in (("2", fmi2), ("3", fmi3)):
            with pytest.raises(RunFailed) as info:
                run_system(spec, fmu_dir)
            failures[version] = info.value.result
    finally:
        System.use_fast_loop = saved
    two, three = failures["2"].outcome, failures["3"].outcome
    assert three.status == "failed" and "fmi3DoStep failed at t = " in three.message
    assert "(status Discard), last successful time " in three.message
    assert three.time == two.time and 0.5 < three.time < 1.5
    last = {v: float(o.message.split("last successful time ")[1].split(" s")[0]) for v, o in (("2", two), ("3", three))}
    assert three.time < last["3"] < three.time + 0.01
    assert abs(last["3"] - last["2"]) <= SAME
    assert _worst(failures["2"].data, failures["3"].data) <= SAME


def test_fmi3_model_exchange_equals_fmi2(fmu_dir):
    """algorithm = "model-exchange" with the bicycle's FMI 3 Model Exchange interface (fmi3SetFloat64,
    fmi3GetContinuousStateDerivatives, ...) and a Python controller: the FMI 2 result to 1e-12."""
    system = {"system": {"stop": 5.0, "step": 0.01, "algorithm": "model-exchange"},
              "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear", "parameters": {"v": 4.0, "phi0": 0.1}},
                             "rider": {"python": "Proportional", "parameters": {"k": 20.0}}},
              "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]}
    spec = system_from_dict(system)
    reference, result = _run(spec, fmu_dir), _run(_as_fmi(spec, "3"), fmu_dir)
    assert result.outcome.status == "completed", result.outcome.message
    assert np.max(np.abs(result.data["bike.phi"])) > 0.05  # something moves
    assert _worst(reference.data, result.data) <= SAME


# ----------------------------------------------------------------- foreign FMI 3 FMUs


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """Reference FMUs (FMI 3.0, foreign) by name, compiled on first use into one module folder."""
    from reference_fmus import reference_fmu

    folder, built = tmp_path_factory.mktemp("reference-fmus"), {}

    def get(name: str) -> Path:
        if name not in built:
            built[name] = reference_fmu(name, folder)
        return built[name]

    return get


@pytest.fixture(scope="module")
def dahlquist(reference) -> Path:
    return reference("Dahlquist")


@pytest.mark.parametrize("loop", ["C", "Python"])
@pytest.mark.parametrize("name,outputs", [("BouncingBall", ["h", "v"]), ("VanDerPol", ["x0", "x1"])],
                         ids=["BouncingBall", "VanDerPol"])
def test_reference_fmu_component_equals_fmpy(reference, name, outputs, loop):
    """A Reference FMU (FMI 3.0 CS, foreign; the bouncing ball with its state events handled inside
    the step) as the one component of a system: the master's samples equal FMPy's simulate_fmu
    with the same communication step to 1e-12 (the same calls of the same binary)."""
    from fmpy import simulate_fmu

    fmu = reference(name)
    spec = system_from_dict({"system": {"stop": 3.0, "step": 0.01}, "components": {"ref": {"fmu": str(fmu)}},
                             "connections": []})
    ours = _run(spec, None, fast=loop == "C").data
    theirs = simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=3.0, output_interval=0.01, output=outputs)
    assert len(ours) == len(theirs) == 301
    assert np.max(np.abs(ours["time"] - theirs["time"])) <= 1e-12
    for output in outputs:
        assert np.max(np.abs(ours[f"ref.{output}"] - theirs[output])) <= 1e-12
    assert np.ptp(ours[f"ref.{outputs[0]}"]) > 0.5  # it moves


@pytest.mark.parametrize("k,step", [(1.0, 0.1), (2.0, 0.05)], ids=["k1-h0.1", "k2-h0.05"])
def test_reference_dahlquist_model_exchange_is_rk4(dahlquist, k, step):
    """The Reference FMU Dahlquist (x' = -k x, x(0) = 1; FMI 3.0 ME, foreign) under the master's
    model-exchange coupling: at every communication point the classic RK4 recurrence
    x_(n+1) = R(-k h) x_n with R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24, to 1e-12."""
    spec = system_from_dict({"system": {"stop": 1.0, "step": step, "algorithm": "model-exchange"},
                             "components": {"d": {"fmu": str(dahlquist), "parameters": {"k": k}}}, "connections": []})
    result = run_system(spec)
    z = -k * step
    growth = 1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24
    expected = growth ** np.arange(len(result.data))
    assert len(result.data) == round(1.0 / step) + 1
    assert np.max(np.abs(result.data["d.x"] - expected)) <= 1e-12


def _container(fmu: Path, folder: Path) -> Path:
    """An FMI 3.0 Co-Simulation container of ``fmu`` made by fmu-manipulation-toolbox (offline),
    stepping the FMU once per 0.01 s, its parameters exposed as ``<fmu stem, lower case>.NAME``."""
    tool = shutil.which("fmucontainer")
    assert tool, "fmucontainer (fmu-manipulation-toolbox, in the test extra) is not installed"
    shutil.copy(fmu, folder / fmu.name)
    (folder / "bike3.csv").write_text(f"rule;from_fmu;from_port;to_fmu;to_port\nFMU;{fmu.name};;;\n")
    result = subprocess.run([tool, "-container", "bike3.csv:0.01", "-fmi", "3", "-auto-parameter"], cwd=folder,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0 and (folder / "bike3.fmu").is_file(), result.stdout + result.stderr
    return folder / "bike3.fmu"


@pytest.fixture(scope="module")
def container(fmu_dir, tmp_path_factory) -> Path:
    from cosim.compiler.build import build_model
    from cosim.compiler.library import load_library

    fmu = build_model("Bicycle.Bicycles.WhippleLinear", fmu_dir, load_library()).fmu
    return _container(fmu, tmp_path_factory.mktemp("container"))


def _with_container(spec, container: Path):
    """The system with its bicycle (WhippleLinear) replaced by the FMI 3 container of it."""
    bike = spec.components["bike"]
    prefix = "bicycle_bicycles_whipplelinear."
    return dataclasses.replace(spec, components={**spec.components, "bike": dataclasses.replace(
        bike, kind="fmu", source=str(container), parameters={prefix + k: v for k, v in bike.parameters.items()},
        fmi_version="2")})


@pytest.mark.parametrize("loop", ["C", "Python"])
def test_container_component_equals_fmi2(container, loop, fmu_dir):
    """The lane change with the bicycle as a foreign FMI 3.0 FMU (an fmucontainer wrapper of our
    FMI 2 FMU, with the Python driver), under Jacobi: the FMI 2 result to 1e-12. The container
    steps the same binary once per communication step, but with its own fixed step and clock,
    where the master steps by differences of its grid points start + k h, which differ from
    0.01 s in the last bits: equal to round-off (measured 2.9e-15), not bit-identical. (Not under Gauss-Seidel: the
    container declares no output dependencies, so every output feeds through and the loop with
    the driver is refused as a cycle without delay.)"""
    spec = load_system(ROOT / "cosim" / "systems" / "lane-change.toml")
    reference = _run(spec, fmu_dir, fast=loop == "C")
    result = _run(_with_container(spec, container), fmu_dir, fast=loop == "C")
    assert result.outcome.status == reference.outcome.status == "completed", result.outcome.message
    assert _worst(reference.data, result.data) <= CONTAINER


def test_fmi3_without_c_compiler(container, fmu_dir, monkeypatch):
    """Where fastloop.c cannot be compiled (no C compiler) the FMI 3 component is adapted in
    Python and the Python loop steps: bit-identical to the C loop with the C adapters."""
    from cosim.cosimulation import fastloop

    spec = _with_container(load_system(ROOT / "cosim" / "systems" / "lane-change.toml"), container)
    with_c = _run(spec, fmu_dir)
    monkeypatch.setattr(fastloop, "library", lambda: None)
    without = _run(spec, fmu_dir)
    assert without.outcome.status == "completed", without.outcome.message
    assert _worst(with_c.data, without.data) == 0.0


# ----------------------------------------------------------------- SSP: Ecos runs FMI 3, libcosim refuses


def _ecos_agrees(spec, ssp: Path, fmu_dir) -> float:
    """Largest relative difference between Ecos running ``ssp`` and our master running ``spec``
    (recording after the transfer, as Ecos does; the engines run to the end: no fall criterion)."""
    from cosim.cosimulation.engines import run_ssp_ecos

    free = dataclasses.replace(spec, fall_signal=None, fall_limit=None, sampling="after-transfer")
    ours = run_system(free, fmu_dir).data
    names = [n for n in ours.dtype.names if n != "time"]
    other = run_ssp_ecos(ssp, names)
    assert len(ours) - 1 == len(other)
    np.testing.assert_allclose(other["time"], ours["time"][1:], rtol=0, atol=1e-9)
    return max(float(np.max(np.abs(ours[n][1:] - other[n]) / np.maximum(1.0, np.abs(ours[n][1:])))) for n in names)


@pytest.mark.needs_ecos
@pytest.mark.parametrize("path", SYSTEMS, ids=[p.stem for p in SYSTEMS])
def test_fmi3_ssp_runs_in_ecos_like_the_master(path, fmu_dir, tmp_path):
    """export_ssp(fmi_version="3"): every component of the archive is an FMI 3.0 FMU, and Ecos
    runs the SSP to our master's result (the same system, its models built as FMI 3) to 1e-9."""
    spec, _ = with_twins(load_system(path))
    ssp, _ = export_ssp(spec, tmp_path / f"{path.stem}.ssp", fmu_dir, fmi_version="3")
    versions = _fmi_versions(ssp)
    assert len(versions) == len(spec.components) and set(versions.values()) == {"3.0"}, versions
    assert _ecos_agrees(_as_fmi(spec, "3"), ssp, fmu_dir) <= ECOS


@pytest.mark.needs_ecos
def test_container_ssp_runs_in_ecos_like_the_master(container, fmu_dir, tmp_path):
    """An SSP mixing a foreign FMI 3.0 FMU (the container of the bicycle) and our FMI 2.0 twin of
    the driver: Ecos runs it to the master's result to 1e-9."""
    spec, _ = with_twins(load_system(ROOT / "cosim" / "systems" / "lane-change.toml"))
    spec = _with_container(spec, container)
    ssp, _ = export_ssp(spec, tmp_path / "lane-change.ssp", fmu_dir)
    assert sorted(_fmi_versions(ssp).values()) == ["2.0", "3.0"]
    assert _ecos_agrees(spec, ssp, fmu_dir) <= ECOS


REFUSAL = "libcosim has no FMI 3.0 support (an FMI 3 FMU crashes it)"


@pytest.fixture(scope="module")
def ssps(fmu_dir, tmp_path_factory) -> dict[str, Path]:
    """The LQR autopilot (twins) exported with every model as FMI 3, and with only the bicycle as FMI 3."""
    spec, _ = with_twins(load_system(ROOT / "cosim" / "systems" / "lqr-autopilot.toml"))
    folder = tmp_path_factory.mktemp("ssp")
    return {"all": export_ssp(spec, folder / "all.ssp", fmu_dir, fmi_version="3")[0],
            "bike": export_ssp(_as_fmi(spec, "3", {"bike"}), folder / "bike.ssp", fmu_dir)[0]}


@pytest.mark.parametrize("case,named", [
    ("all", ["autopilot (resources/autopilot.fmu)", "bike (resources/bike.fmu)", "delay (resources/delay.fmu)",
             "push (resources/push.fmu)"]),
    ("bike", ["component bike (resources/bike.fmu) is FMI 3.0"]),
    ("fmu", ["Bicycle_Bicycles_WhippleLinear.fmu: ", "this FMU is FMI 3.0"]),
], ids=["ssp-all-fmi3", "ssp-one-fmi3", "fmu"])
def test_libcosim_refuses_fmi3_before_loading(ssps, fmu_dir, case, named):
    """cosim's libcosim runners refuse an FMI 3 FMU, or an SSP with FMI 3 components (naming
    exactly those), with one EngineUnsupported message — in a fresh interpreter in which libcosim
    is then still not loaded (it would crash on the FMU)."""
    target = fmu_dir / "fmi3" / "Bicycle_Bicycles_WhippleLinear.fmu" if case == "fmu" else ssps[case]
    call = (f"engines.run_libcosim({str(target)!r}, 1.0, 0.01)" if case == "fmu"
            else f"engines.run_ssp_libcosim({str(target)!r}, ['bike.phi'])")
    code = ("import sys\nfrom cosim.cosimulation import engines\n"
            f"try:\n    {call}\nexcept engines.EngineUnsupported as exc:\n    print('REFUSED', exc)\n"
            "print('libcosimpy loaded' if 'libcosimpy' in sys.modules else 'libcosimpy not loaded')\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith("REFUSED ") and lines[1] == "libcosimpy not loaded", result.stdout
    assert REFUSAL in lines[0] and all(n in lines[0] for n in named), lines[0]
    assert ("run the SSP in Ecos" if case != "fmu" else "run it in Ecos") in lines[0]
    if case == "bike":
        assert "autopilot" not in lines[0] and "delay" not in lines[0]


# ----------------------------------------------------------------- export-ssp --fmi-version 3


SSP2_SCHEMAS = ROOT / "tests" / "data" / "ssp-2.0"  # the SSP 2.0 standard's XSDs, vendored with their licence
SSP_NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
          "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
          "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
          "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
          "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"}


def _schema_problems(ssp: Path, version: str = "1.0") -> list[str]:
    """Problems of SystemStructure.ssd against the SSP ``version`` schema (FMPy ships the 1.0
    XSDs; the 2.0 ones are in tests/data/ssp-2.0). Under 2.0 every inline ssv:ParameterSet is
    also checked against the SSV 2.0 schema, which the SSD schema leaves unchecked."""
    import fmpy
    from lxml import etree

    folder = Path(fmpy.__file__).parent / "ssp" / "schema" if version == "1.0" else SSP2_SCHEMAS
    schema = etree.XMLSchema(etree.parse(str(folder / "SystemStructureDescription.xsd")))
    with zipfile.ZipFile(ssp) as archive:
        document = etree.fromstring(archive.read("SystemStructure.ssd"))
    problems = [] if schema.validate(document) else [str(e) for e in schema.error_log]
    if version == "2.0":
        values = etree.XMLSchema(etree.parse(str(folder / "SystemStructureParameterValues.xsd")))
        for parameter_set in document.iter(f"{{{SSP_NS['ssv']}}}ParameterSet"):
            if not values.validate(parameter_set):
                problems += [str(e) for e in values.error_log]
    return problems


@pytest.mark.parametrize(("ssp_version", "version"), [("1.0", "2"), ("1.0", "3"), ("2.0", "2"), ("2.0", "3")],
                         ids=["ssp1.0-fmi2", "ssp1.0-fmi3", "ssp2.0-fmi2", "ssp2.0-fmi3"])
def test_cli_export_ssp_fmi_version(ssp_version, version, tmp_path):
    """`cosim export-ssp --ssp-version V --fmi-version N`: the SSD passes the SSP V schema and
    says version V, every component is an FMU of that FMI version with its binary for this
    platform (FMI 3: binaries/x86_64-linux), the parameter values are bound; the connectors are
    typed ssc:Real, except FMI 3 ones under SSP 2.0 (ssc:Float64). The master settings are where
    other engines read them: start and stop in ssd:DefaultExperiment, the step in the OSP
    annotation and in OMSimulator's fixed-step master annotation, the first of the system's."""
    import xml.etree.ElementTree as ET

    system = ROOT / "cosim" / "systems" / "lqr-autopilot.toml"
    spec = load_system(system)
    ssp = tmp_path / "lqr.ssp"
    result = run_cli("export-ssp", str(system), "-o", str(ssp), "--fmi-version", version,
                     *(["--ssp-version", ssp_version] if ssp_version != "1.0" else []))
    assert result.returncode == 0, result.stderr
    assert "twin: delay: Python TransportDelay -> Bicycle.Rider.PadeDelay" in result.stdout
    assert _schema_problems(ssp, ssp_version) == []
    versions = _fmi_versions(ssp)
    assert sorted(versions) == [f"resources/{n}.fmu" for n in ("autopilot", "bike", "delay", "push")]
    assert set(versions.values()) == {f"{version}.0"}
    binaries = "binaries/x86_64-linux/" if version == "3" else "binaries/linux64/"
    import io

    with zipfile.ZipFile(ssp) as archive:
        with zipfile.ZipFile(io.BytesIO(archive.read("resources/bike.fmu"))) as bike:
            assert any(n.startswith(binaries) and n.endswith(".so") for n in bike.namelist())
        root = ET.fromstring(archive.read("SystemStructure.ssd"))
    ns = SSP_NS
    assert root.get("version") == ssp_version
    real = "Float64" if (ssp_version, version) == ("2.0", "3") else "Real"
    bike = root.find(".//ssd:Component[@name='bike']", ns)
    connectors = {c.get("name"): c for c in bike.findall("ssd:Connectors/ssd:Connector", ns)}
    assert {"T_delta", "T_phi", "phi", "delta"} <= set(connectors)
    assert all(c.find(f"ssc:{real}", ns) is not None for c in connectors.values())
    assert {p.get("version") for p in root.iterfind(".//ssv:ParameterSet", ns)} == {ssp_version}
    v = bike.find(f".//ssv:Parameter[@name='v']/ssv:{real}", ns)
    assert v is not None and float(v.get("value")) == 3.0
    experiment = root.find("ssd:DefaultExperiment", ns)
    assert (float(experiment.get("startTime")), float(experiment.get("stopTime"))) == (spec.start, spec.stop)
    osp = experiment.find("ssd:Annotations/ssc:Annotation/osp:Algorithm/osp:FixedStepAlgorithm", ns)
    assert float(osp.get("baseStepSize")) == spec.step
    first = root.find("ssd:System/ssd:Annotations/ssc:Annotation", ns)  # OMSimulator reads only the first
    assert first.get("type") == "org.openmodelica"
    master = first.find("oms:Annotations/oms:SimulationInformation/oms:FixedStepMaster", ns)
    assert master.get("description") == "oms-ma" and float(master.get("stepSize")) == spec.step


def test_export_ssp_refuses_unknown_ssp_version(tmp_path):
    """An SSP version other than 1.0 or 2.0 is refused with a message naming it, before anything
    is built or written; the command line offers only the two."""
    spec = load_system(ROOT / "cosim" / "systems" / "lqr-autopilot.toml")
    with pytest.raises(SystemError_, match=r"SSP version '1\.1' cannot be exported \(choose 1\.0 or 2\.0\)"):
        export_ssp(spec, tmp_path / "x.ssp", tmp_path / "fmus", ssp_version="1.1")
    assert list(tmp_path.iterdir()) == []
    result = run_cli("export-ssp", "cosim/systems/lqr-autopilot.toml", "-o", str(tmp_path / "x.ssp"),
                     "--ssp-version", "1.1")
    assert result.returncode == 2 and "--ssp-version" in result.stderr and "1.1" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_cli_export_ssp_fmi3_notes_fmu_files_of_fmi2(fmu_dir, tmp_path):
    """An FMU file of the system that is FMI 2.0 is copied as it is under --fmi-version 3, and the
    command says so (the models are built as FMI 3)."""
    from cosim.compiler.build import build_model
    from cosim.compiler.library import load_library

    fmu = build_model("Bicycle.Control.Proportional", fmu_dir, load_library()).fmu
    path = tmp_path / "s.toml"
    path.write_text(f'connections = ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]\n[system]\nstop = 1.0\n'
                    f'[components.bike]\nmodel = "Bicycle.Bicycles.WhippleLinear"\n'
                    f'[components.rider]\nfmu = "{fmu}"\n')
    ssp = tmp_path / "s.ssp"
    result = run_cli("export-ssp", str(path), "-o", str(ssp), "--fmi-version", "3")
    assert result.returncode == 0, result.stderr
    assert f"note: rider: the FMU file {fmu.name} is FMI 2.0, copied as it is" in result.stdout
    assert _fmi_versions(ssp) == {"resources/bike.fmu": "3.0", "resources/rider.fmu": "2.0"}
    assert _schema_problems(ssp) == []


def test_cli_run_system_file_with_fmi_version(tmp_path):
    """`cosim run` of a system file whose bicycle has fmi_version = 3 beside the FMI 2 controller
    model: the same CSV as with fmi_version = 2, to 1e-12."""
    results = {}
    for version in ("2", "3"):
        path = tmp_path / f"s{version}.toml"
        path.write_text('connections = ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]\n'
                        '[system]\nstop = 2.0\nstep = 0.01\n'
                        f'[components.bike]\nmodel = "Bicycle.Bicycles.WhippleLinear"\nfmi_version = {version}\n'
                        'parameters = { v = 4.0, phi0 = 0.1 }\n'
                        '[components.rider]\nmodel = "Bicycle.Control.Proportional"\n')
        out = tmp_path / f"s{version}.npy"
        result = run_cli("run", str(path), "-o", str(out))
        assert result.returncode == 0, result.stderr
        results[version] = np.load(out)
    assert _worst(results["2"], results["3"]) <= SAME


@pytest.mark.parametrize("entry,message", [
    ({"model": "Bicycle.Bicycles.WhippleLinear", "fmi_version": 4},
     "[components.bike] fmi_version: must be 2 or 3, got an integer (4)"),
    ({"model": "Bicycle.Bicycles.WhippleLinear", "fmi_version": True}, "fmi_version: must be 2 or 3, got a boolean"),
    ({"fmu": "bike.fmu", "fmi_version": 3},
     "[components.bike] fmi_version: applies to model components only (an FMU file has its own FMI version)"),
    ({"python": "Proportional", "fmi_version": 3}, "applies to model components only (a Python block is no FMU)"),
], ids=["four", "boolean", "fmu-file", "python-block"])
def test_system_file_fmi_version_refused(entry, message):
    """A wrong fmi_version in a system file: one SystemError_ naming the entry, before anything is built."""
    with pytest.raises(SystemError_) as info:
        system_from_dict({"system": {}, "components": {"bike": entry}, "connections": []})
    assert message in str(info.value)


@pytest.mark.parametrize("value", [3, "3", "3.0", 3.0], ids=["int", "str", "str-3.0", "float"])
def test_system_file_fmi_version_accepted(value):
    spec = system_from_dict({"system": {}, "components": {"bike": {"model": "Bicycle.Bicycles.WhippleLinear",
                                                                    "fmi_version": value}}, "connections": []})
    assert spec.components["bike"].fmi_version == "3"


@pytest.mark.parametrize("flag,message", [
    ("terminate", "fmi3DoStep at t = 1 s: the FMU asks to terminate the simulation (terminateSimulation)"),
    ("early", "fmi3DoStep at t = 1 s: the FMU returned early (earlyReturn), which its instantiation did not allow"),
], ids=["terminate-simulation", "early-return"])
def test_fmi3_step_that_asks_to_stop_ends_the_run(container, fmu_dir, monkeypatch, flag, message):
    """fmi3DoStep returning OK but asking to terminate, or returning early (which the master's
    instantiation does not allow): the run ends there as after a Discard, the rows before kept,
    the message naming what the FMU asked (the FMU's own fmi3DoStep wrapped from t = 1 s on)."""
    from ctypes import CFUNCTYPE, POINTER, c_bool, c_double, c_int, c_void_p, cast

    from cosim.cosimulation.component import FMUComponent

    original = FMUComponent._setup_fmi3
    kept = []

    def setup(self, functions):
        original(self, functions)
        real = functions["fmi3DoStep"]

        @CFUNCTYPE(c_int, c_void_p, c_double, c_double, c_bool, POINTER(c_bool), POINTER(c_bool), POINTER(c_bool),
                   POINTER(c_double))
        def do_step(instance, t, h, no_prior, event, terminate, early, last):
            status = real(instance, t, h, no_prior, event, terminate, early, last)
            if t >= 1.0 - 1e-9:
                (terminate if flag == "terminate" else early)[0] = True
                if flag == "early":
                    last[0] = t + h / 2
            return status

        kept.append(do_step)
        self._adapter.do_step = cast(do_step, c_void_p)

    monkeypatch.setattr(FMUComponent, "_setup_fmi3", setup)
    spec = _with_container(load_system(ROOT / "cosim" / "systems" / "lane-change.toml"), container)
    result = _run(spec, fmu_dir)
    assert result.outcome.status == "failed" and message in result.outcome.message, result.outcome.message
    assert result.data["time"][-1] == pytest.approx(1.0, abs=1e-12)
    if flag == "early":
        assert "last successful time 1.005 s" in result.outcome.message
