"""FMI 3.0 FMUs: `cosim info` reads their model description (FMPy checks it against the FMI 3
schema); the commands that run an FMU accept FMI 3 and refuse one without a binary in
one clear line (exit 2, no traceback). Running FMI 3 FMUs: tests/test_fmi3_import.py."""
from __future__ import annotations

import json
import zipfile

import pytest

from conftest import run_cli
from cosim.errors import FMUError
from cosim.fmu import access

TOKEN = "{8c4e810f-3da3-4a00-8276-176fa3c9f001}"
# The Van der Pol oscillator of the FMI Reference FMUs, as an FMI 3.0 model description (no binary:
# only what `cosim info` reads).
MODEL_DESCRIPTION = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="VanDerPol" description="Van der Pol oscillator"
    instantiationToken="{TOKEN}" generationTool="tests/test_fmi3_read.py">
  <ModelExchange modelIdentifier="VanDerPol" providesDirectionalDerivatives="true"/>
  <CoSimulation modelIdentifier="VanDerPol" providesDirectionalDerivatives="true"/>
  <DefaultExperiment startTime="0" stopTime="20" stepSize="0.01"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="x0" valueReference="1" causality="output" variability="continuous" initial="exact" start="2"
        description="the first state"/>
    <Float64 name="der(x0)" valueReference="2" causality="local" variability="continuous" initial="calculated"
        derivative="1"/>
    <Float64 name="x1" valueReference="3" causality="output" variability="continuous" initial="exact" start="0"/>
    <Float64 name="der(x1)" valueReference="4" causality="local" variability="continuous" initial="calculated"
        derivative="3"/>
    <Float64 name="mu" valueReference="5" causality="parameter" variability="fixed" initial="exact" start="1"
        description="damping"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="1"/>
    <Output valueReference="3"/>
    <ContinuousStateDerivative valueReference="2"/>
    <ContinuousStateDerivative valueReference="4"/>
    <InitialUnknown valueReference="2"/>
    <InitialUnknown valueReference="4"/>
  </ModelStructure>
</fmiModelDescription>
"""


@pytest.fixture
def fmi3_fmu(tmp_path):
    path = tmp_path / "VanDerPol.fmu"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("modelDescription.xml", MODEL_DESCRIPTION)
    return path


def test_info_reads_an_fmi3_model_description(fmi3_fmu):
    text = run_cli("info", str(fmi3_fmu))
    assert text.returncode == 0, text.stderr
    assert f"FMI 3.0 ModelExchange + CoSimulation, instantiation token {TOKEN}" in text.stdout
    assert "states: x0, x1" in text.stdout and "mu = 1 [-]  damping" in text.stdout
    info = json.loads(run_cli("info", str(fmi3_fmu), "--json").stdout)
    assert (info["fmiVersion"], info["guid"], info["states"]) == ("3.0", TOKEN, ["x0", "x1"])
    assert [v["name"] for v in info["variables"]["output"]] == ["x0", "x1"]
    assert info["variables"]["independent"][0]["name"] == "time"


@pytest.mark.parametrize("command", [["simulate", "--stop-time", "1"], ["linearize"], ["run"]],
                         ids=["simulate", "linearize", "run-system"])
def test_commands_that_run_fmus_read_fmi3_and_name_the_missing_binary(fmi3_fmu, tmp_path, command):
    """(`cosim validate` lists the missing binary among its problems: tests of validate.)"""
    if command[0] == "run":  # a system with the FMU as a component
        system = tmp_path / "system.toml"
        system.write_text(f'[system]\nstop = 1.0\nstep = 0.01\n[components.oscillator]\nfmu = "{fmi3_fmu}"\n')
        command = ["run", str(system), "-o", str(tmp_path / "run.csv")]
    else:
        command = [command[0], str(fmi3_fmu), *command[1:]]
    result = run_cli(*command)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"cosim {command[0]}: error: {fmi3_fmu}: "), lines
    assert "no binary for this platform (binaries/x86_64-linux/VanDerPol.so is missing from the archive)" in lines[0]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith("run")], "nothing written"


def test_reading_for_info_does_not_let_fmi3_into_callers_that_run_fmi2_only(fmi3_fmu):
    """A caller that does not pass the versions it handles gets FMI 2.0 only (SUPPORTED_FMI_VERSIONS)."""
    assert access.read_fmu(fmi3_fmu, versions=access.READABLE_FMI_VERSIONS).fmiVersion == "3.0"
    with pytest.raises(FMUError, match="FMI 3.0 FMUs are not supported yet"):
        access.read_fmu(fmi3_fmu)  # the cached description is checked again
