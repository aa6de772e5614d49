"""``--lenient``: an FMU whose modelDescription.xml fails FMPy's validation in a way that does not
stop it from running (as FMPy's ``validate=False`` and OMSimulator run it) is refused by default,
naming the defect and the flag, and opened with the flag: each defect one warning line, the run
giving FMPy's ``simulate_fmu(validate=False)`` result."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import cosim
from conftest import cli_in_process
from cosim.errors import FMUError
from cosim.fmu import access
from reference_fmus import reference_fmu, reference_fmu2

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

#: Defects FMPy's validation reports but FMPy's validate=False run does not mind:
#: (id, builder, modelDescription.xml edits, a word of FMPy's finding)
DEFECTS = [
    ("fmi2-undefined-unit", reference_fmu2, [('<Real start="1"/>', '<Real start="1" unit="furlong"/>')],
     'unit "furlong"'),
    ("fmi2-calculated-parameter-with-start", reference_fmu2,
     [('causality="parameter" variability="fixed" initial="exact"',
       'causality="parameter" variability="fixed" initial="calculated"')], 'initial="calculated"'),
    ("fmi3-undefined-unit", reference_fmu, [('initial="exact" start="1"/>\n  </ModelVariables>',
                                              'initial="exact" start="1" unit="furlong"/>\n  </ModelVariables>')],
     'unit "furlong"'),
]
IDS = [d[0] for d in DEFECTS]
SIMULATE_TOLERANCE = 1e-12  # [state units] the same FMU binary and solver settings: equal up to rounding
LINEARIZE_TOLERANCE = 1e-9  # [1/s] directional derivatives against the analytic Jacobian


@pytest.fixture(scope="module")
def defective(tmp_path_factory) -> dict[str, Path]:
    """The VanDerPol Reference FMU with each defect of :data:`DEFECTS`, built once for this module."""
    folder = tmp_path_factory.mktemp("lenient-fmus")
    return {name: build("VanDerPol", folder, edits={"modelDescription.xml": edits}, fmu_name=name)
            for name, build, edits, _ in DEFECTS}


@pytest.fixture(autouse=True)
def fresh_warnings():
    """Each test sees the warnings of its own reading (they are given once per file and process)."""
    access._WARNED.clear()
    yield
    access._WARNED.clear()


def warning_lines(err: str, verb: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith(f"cosim {verb}: warning: FMU: ")]


@pytest.mark.parametrize("verb", ["info", "simulate", "linearize"])
@pytest.mark.parametrize("defect", DEFECTS, ids=IDS)
def test_refused_without_lenient(defective, tmp_path, defect, verb):
    """Without --lenient: exit 2, one error line naming the defect and the flag, nothing written."""
    name, _, _, finding = defect
    argv = [verb, str(defective[name])] + (["--stop-time", "1", "-o", "out.csv"] if verb == "simulate" else [])
    status, out, err = cli_in_process(argv, tmp_path)
    assert status == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"cosim {verb}: error: "), err
    assert finding in lines[0] and "use --lenient to run it anyway" in lines[0]
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize("defect", DEFECTS, ids=IDS)
def test_info_with_lenient_warns_and_describes(defective, tmp_path, defect):
    name, _, _, finding = defect
    status, out, err = cli_in_process(["info", str(defective[name]), "--lenient"], tmp_path)
    assert status == 0, err
    warnings = warning_lines(err, "info")
    assert warnings and any(finding in w for w in warnings), err
    assert len(warnings) == len(err.strip().splitlines())  # nothing but the warnings
    assert "mu" in out


@pytest.mark.parametrize("kind", ["cs", "me"])
@pytest.mark.parametrize("defect", DEFECTS, ids=IDS)
def test_simulate_with_lenient_equals_fmpy(defective, tmp_path, defect, kind):
    """The run goes ahead and gives FMPy's simulate_fmu(validate=False) result, to rounding."""
    from fmpy import simulate_fmu

    name, _, _, finding = defect
    fmu = defective[name]
    status, out, err = cli_in_process(["simulate", str(fmu), "--stop-time", "2", "--step", "0.01",
                                       "--fmi-type", kind, "--lenient", "-o", "out.csv"], tmp_path)
    assert status == 0, err
    assert any(finding in w for w in warning_lines(err, "simulate")), err
    ours = np.genfromtxt(tmp_path / "out.csv", delimiter=",", names=True, deletechars="", ndmin=1)
    theirs = simulate_fmu(str(fmu), validate=False, stop_time=2.0, output_interval=0.01, output=["x0", "x1"],
                          fmi_type="CoSimulation" if kind == "cs" else "ModelExchange")
    assert len(ours) == len(theirs) > 100
    for column in ("time", "x0", "x1"):
        np.testing.assert_allclose(ours[column], theirs[column], rtol=0, atol=SIMULATE_TOLERANCE, err_msg=column)


@pytest.mark.parametrize("defect", DEFECTS, ids=IDS)
def test_linearize_with_lenient(defective, tmp_path, defect):
    """Model Exchange linearization at x0 = 2, x1 = 0, mu = 1: A = [[0, 1], [-1, -3]]."""
    name, _, _, finding = defect
    status, out, err = cli_in_process(["linearize", str(defective[name]), "--lenient", "--json"], tmp_path)
    assert status == 0, err
    assert any(finding in w for w in warning_lines(err, "linearize")), err
    np.testing.assert_allclose(np.array(json.loads(out)["A"], dtype=float), [[0.0, 1.0], [-1.0, -3.0]],
                               rtol=0, atol=LINEARIZE_TOLERANCE)


def test_python_api_takes_lenient(defective):
    """cosim.simulate / cosim.linearize / read_fmu: refused by default, warnings with lenient=True."""
    fmu = defective["fmi2-undefined-unit"]
    with pytest.raises(FMUError, match="furlong.*--lenient"):
        cosim.simulate(fmu, stop_time=1.0)
    with pytest.raises(FMUError, match="--lenient"):
        access.read_fmu(fmu, access.ALL_FMI_VERSIONS)
    with pytest.warns(UserWarning, match='FMU: .*unit "furlong"'):
        result = cosim.simulate(fmu, stop_time=1.0, step=0.1, lenient=True)
    assert result["time"][-1] == pytest.approx(1.0, abs=1e-12)
    linear = cosim.linearize(fmu, lenient=True)
    np.testing.assert_allclose(linear.system.A, [[0.0, 1.0], [-1.0, -3.0]], rtol=0, atol=LINEARIZE_TOLERANCE)
    assert access.FMU(fmu, access.ALL_FMI_VERSIONS, lenient=True).description.modelName


def test_lenient_keeps_the_safety_checks(tmp_path):
    """An unsafe member name is refused with --lenient too (only FMPy's findings become warnings)."""
    import zipfile

    fmu = tmp_path / "evil.fmu"
    with zipfile.ZipFile(fmu, "w") as archive:
        archive.writestr("modelDescription.xml", "<fmiModelDescription fmiVersion='2.0'/>")
        archive.writestr("../escape.txt", "x")
    status, _, err = cli_in_process(["info", str(fmu), "--lenient"], tmp_path)
    assert status == 2 and "unsafe member name" in err, err


@pytest.mark.parametrize("defect", DEFECTS[:2], ids=IDS[:2])
def test_run_applies_lenient_to_every_fmu_component(defective, tmp_path, defect):
    """`cosim run`: refused without the flag; with it the co-simulation (communication step
    0.1 s) gives FMPy's Co-Simulation run with the same step."""
    import shutil

    from fmpy import simulate_fmu

    name, _, _, finding = defect
    fmu = shutil.copy(defective[name], tmp_path / "vdp.fmu")
    (tmp_path / "system.toml").write_text('connections = []\n[system]\nstop = 1.0\nstep = 0.1\n'
                                          '[components.vdp]\nfmu = "vdp.fmu"\n')
    status, _, err = cli_in_process(["run", "system.toml", "-o", "out.csv"], tmp_path)
    assert status == 2 and finding in err and "--lenient" in err, err
    assert not (tmp_path / "out.csv").exists()
    status, out, err = cli_in_process(["run", "system.toml", "-o", "out.csv", "--lenient"], tmp_path)
    assert status == 0, err
    assert any(finding in w for w in warning_lines(err, "run")), err
    ours = np.genfromtxt(tmp_path / "out.csv", delimiter=",", names=True, deletechars="", ndmin=1)
    theirs = simulate_fmu(str(fmu), validate=False, stop_time=1.0, output_interval=0.1, output=["x0", "x1"])
    assert len(ours) == len(theirs) == 11
    for column in ("x0", "x1"):
        np.testing.assert_allclose(ours[f"vdp.{column}"], theirs[column], rtol=0, atol=SIMULATE_TOLERANCE)


def test_validate_names_the_defect_without_offering_lenient(defective, tmp_path):
    """`cosim validate` reports model-description defects itself: its refusal names the defect
    but no --lenient (it has none)."""
    status, _, err = cli_in_process(["validate", str(defective["fmi2-undefined-unit"])], tmp_path)
    assert status == 2 and 'unit "furlong"' in err, err
    assert "--lenient" not in err
