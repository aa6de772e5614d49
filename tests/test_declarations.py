"""One source of what a user may set: a model name is checked against exactly what its FMU declares
(the modelDescription.xml `cosim build` writes, made without building), by the same rule and with
the same messages as an FMU file, before anything is built (simulate, linearize, run, export-ssp,
matrix specs).

* for every exported model (FMI 2) and for FMI 3 models with state arrays, the declarations made
  from the model name equal those read from the built FMU: names, roles, types, units, min, max
  and start values;
* the README's command line with the model name runs as printed (a state's start value is set);
* a calculated (``final``) parameter is refused for a model name and an FMU file with the same
  message, in every command;
* `cosim run`, `cosim export-ssp` and `cosim matrix` refuse an unknown parameter of a model
  component before anything is built (no FMU is written into their COSIM_FMU_DIR);
* a String parameter (which an FMU built here cannot hold) is refused at build time by name.
"""
from __future__ import annotations

import re
import shlex
from dataclasses import asdict
from pathlib import Path

import pytest

from conftest import ROOT, cli_in_process, run_cli, shipped_models
from cosim.compiler.build import build_model
from cosim.compiler.catalog import model_description
from cosim.compiler.library import DEFAULT_LIBRARY, Library
from cosim.fmu.parameters import _read_description, fmu_declarations, model_declarations

EXPORTED = shipped_models(exported_only=True)
#: Models with state arrays, which FMI 3 exports as array variables (PadeDelay's x), and states
#: solved from the initial equations (Whipple's theta: initial = "approx").
FMI3_MODELS = ["Bicycle.Rider.PadeDelay", "Bicycle.Control.PID"]


@pytest.fixture(scope="module")
def library():
    return Library(DEFAULT_LIBRARY)


def _records(declared: dict) -> list[dict]:
    return [asdict(d) for d in declared.values()]


@pytest.mark.parametrize("model", EXPORTED, ids=lambda m: m.rsplit(".", 1)[-1])
def test_model_name_declares_what_its_fmu_declares(fmus, library, model):
    """The compiler's model description of the name equals the built FMU's: the same names with
    the same role, type, unit, min, max and start (in the FMU's order); the commands' lookup
    (:func:`model_declarations`, from the index or the FMU) gives the same."""
    from_fmu = _records(fmu_declarations(fmus[model]))
    from_name = _read_description(model_description(model, "2", library))
    assert from_name == from_fmu
    assert _records(model_declarations(model)) == from_fmu
    roles = {d["causality"] for d in from_fmu}
    assert "parameter" in roles  # solver.fixedStepSize at least: the comparison is not of empty lists


def test_declarations_of_the_model_names_cover_calculated_parameters_and_states(fmus):
    """What the equality above covers: calculated parameters and start values are among them."""
    linear = fmu_declarations(fmus["Bicycle.Bicycles.WhippleLinear"])
    assert linear["M11"].causality == "calculated parameter" and linear["v"].causality == "parameter"
    stabilizing = fmu_declarations(fmus["Bicycle.Bicycles.SelfStabilizing"])
    assert stabilizing["frame.phi"].causality == "start value" and stabilizing["frame.phi"].unit == "rad"
    whipple = fmu_declarations(fmus["Bicycle.Bicycles.Whipple"])
    assert whipple["theta"].causality == "start value (guess of the initial equations)"


@pytest.mark.parametrize("model", FMI3_MODELS, ids=lambda m: m.rsplit(".", 1)[-1])
def test_fmi3_model_name_declares_what_its_fmu_declares(library, tmp_path, model):
    fmu = build_model(model, tmp_path, library, fmi_version="3").fmu
    from_fmu = _records(fmu_declarations(fmu))
    assert _read_description(model_description(model, "3", library)) == from_fmu
    assert _records(model_declarations(model, "3")) == from_fmu
    if model.endswith("PadeDelay"):  # the state array is one FMI 3 variable, as in the FMU
        assert "x" in {d["name"] for d in from_fmu} and "x[1]" not in {d["name"] for d in from_fmu}


def test_readme_command_line_runs_as_printed(fmus, tmp_path):
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    found = re.search(r"^\$ (cosim simulate Bicycle\.\S+ .*frame\.phi=0\.1.*)$", text, re.M)
    assert found, "README.md: the command-line example was not found"
    args = shlex.split(found.group(1))[1:]
    assert "frame.phi=0.1" in args and args[1] == "Bicycle.Bicycles.SelfStabilizing"  # a model name
    status, out, err = cli_in_process(args, tmp_path)
    assert status == 0, err
    rows = (tmp_path / "Bicycle_Bicycles_SelfStabilizing.csv").read_text().splitlines()
    header = rows[0].split(",")
    phi = [float(row.split(",")[header.index("phi")]) for row in rows[1:]]
    assert phi[0] == pytest.approx(0.1, abs=1e-12)  # frame.phi = 0.1 was set
    assert abs(phi[-1]) < 0.1 * abs(phi[0])  # self-stable at V = 5 m/s


CALCULATED = ("parameter 'M11' is a calculated parameter (final, or bound to an expression of other "
              "parameters) and cannot be set")


@pytest.mark.parametrize("verb", [["simulate", "--stop-time", "1"], ["linearize"], ["linearize", "--speeds", "1,2"]],
                         ids=["simulate", "linearize", "linearize-sweep"])
def test_calculated_parameter_is_refused_for_model_and_fmu_alike(fmus, tmp_path, verb):
    model = "Bicycle.Bicycles.WhippleLinear"
    messages = []
    for target in (model, str(fmus[model])):
        status, out, err = cli_in_process([verb[0], target, *verb[1:], "--param", "M11=1"], tmp_path)
        assert status == 2, err
        messages.append(err)
    assert messages[0] == messages[1] == f"cosim {verb[0]}: error: {CALCULATED}\n"
    assert list(tmp_path.iterdir()) == []


FINALS = '''within Finals;
model Decay "final parameters"
  parameter Real k = 2 "tunable";
  final parameter Real f = 3 "final, a number";
  final parameter Real g = 2*k "final, an expression";
  parameter Real h = 2*k "bound to an expression";
  Real x(start = 1, fixed = true) "a state";
equation
  der(x) = -k*f*g*h*x;
end Decay;
'''


@pytest.mark.parametrize("name", ["f", "g", "h"], ids=["final-number", "final-expression", "bound"])
def test_final_parameter_is_calculated_for_model_and_fmu_alike(tmp_path, name):
    """A final parameter is not settable even when its value is a number: the FMU declares it a
    calculated parameter, and the model name answers the same."""
    package = tmp_path / "lib" / "Finals"
    package.mkdir(parents=True)
    (package / "package.mo").write_text('within;\npackage Finals "test"\nend Finals;\n', encoding="utf-8")
    (package / "Decay.mo").write_text(FINALS, encoding="utf-8")
    library = Library(tmp_path / "lib")
    fmu = build_model("Finals.Decay", tmp_path / "fmus", library).fmu
    from_fmu = fmu_declarations(fmu)
    assert _read_description(model_description("Finals.Decay", "2", library)) == _records(from_fmu)
    assert {n: d.causality for n, d in from_fmu.items()} == {
        "x": "start value", "k": "parameter", "solver.fixedStepSize": "parameter", "f": "calculated parameter",
        "g": "calculated parameter", "h": "calculated parameter"}
    messages = []
    for target in ("Finals.Decay", str(fmu)):
        status, out, err = cli_in_process(["simulate", target, "--stop-time", "0.1", "--param", f"{name}=1",
                                           "--library", str(tmp_path / "lib")], tmp_path)
        assert status == 2, err
        messages.append(err)
    assert messages[0] == messages[1] == (f"cosim simulate: error: parameter '{name}' is a calculated parameter "
                                          "(final, or bound to an expression of other parameters) and cannot be set\n")


def _system(tmp_path: Path, bike: str, parameters: str) -> Path:
    path = tmp_path / "system.toml"
    path.write_text('connections = ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]\n\n'
                    f'[system]\nstop = 0.1\nstep = 0.01\n\n[components.bike]\n{bike}\nparameters = {{ {parameters} }}\n'
                    '\n[components.rider]\nmodel = "Bicycle.Control.Proportional"\nparameters = { k = 2.0 }\n',
                    encoding="utf-8")
    return path


def test_system_file_refuses_a_calculated_parameter_for_model_and_fmu_alike(fmus, tmp_path):
    messages = []
    for bike in ('model = "Bicycle.Bicycles.WhippleLinear"', f'fmu = "{fmus["Bicycle.Bicycles.WhippleLinear"]}"'):
        status, out, err = cli_in_process(["run", str(_system(tmp_path, bike, "M11 = 1.0"))], tmp_path)
        assert status == 2, err
        messages.append(err)
    assert messages[0] == messages[1] == f"cosim run: error: {tmp_path / 'system.toml'}: component 'bike': {CALCULATED}\n"


@pytest.mark.parametrize("verb", [["run"], ["export-ssp", "-o", "system.ssp"]], ids=["run", "export-ssp"])
def test_unknown_parameter_of_a_model_component_fails_before_any_build(tmp_path, verb):
    """The first component (a model with good parameters) is not built either: every component is
    checked first. The declarations come from the compiler (the FMU folder is empty)."""
    path = tmp_path / "system.toml"
    path.write_text('[system]\nstop = 0.1\nstep = 0.01\n\n'
                    '[components.first]\nmodel = "Bicycle.Control.Proportional"\nparameters = { k = 2.0 }\n\n'
                    '[components.second]\nmodel = "Bicycle.Control.PD"\nparameters = { nope = 1.0 }\n',
                    encoding="utf-8")
    fmu_dir = tmp_path / "fmus"
    result = run_cli(verb[0], str(path), *verb[1:], cwd=tmp_path, env={"COSIM_FMU_DIR": str(fmu_dir)})
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith(f"cosim {verb[0]}: error: {path}: component 'second': unknown parameter 'nope'; "
                                    "top-level parameters are: "), result.stderr
    assert not list(tmp_path.rglob("*.fmu")) and not fmu_dir.exists()


MATRIX = '''[matrix]
name = "names"
stop = 0.5
step = 0.01
predict = false

[[study]]
name = "one"
observe = "bike.phi"
connections = []
[study.components.bike]
model = "Bicycle.Bicycles.SelfStabilizing"
parameters = {{ V = "=V" }}
initial = {{ {initial} }}
[study.axes]
V = [1.0, 2.0]
'''


@pytest.mark.parametrize("initial, message", [
    ('"frame.nope" = 0.1', "component 'bike' initial: unknown parameter 'frame.nope'"),
    ('"V" = 0.1', "component 'bike' initial: 'V' is not a state start value that can be set"),
    ('"frame.m" = 0.1', "component 'bike' initial: parameter 'frame.m' is a calculated parameter"),
], ids=["unknown", "a-parameter", "calculated"])
def test_matrix_spec_names_are_checked_before_any_build(tmp_path, initial, message):
    from cosim.matrix.runner import run_matrix
    from cosim.matrix.spec import SpecError

    spec = tmp_path / "names.toml"
    spec.write_text(MATRIX.format(initial=initial), encoding="utf-8")
    with pytest.raises(SpecError) as refused:
        run_matrix(spec, tmp_path / "out", workers=1, fmu_dir=tmp_path / "fmus", progress=False, report=False)
    assert f"{spec}: study 'one': {message}" in str(refused.value)
    assert not list(tmp_path.rglob("*.fmu"))


STRING_PARAMETER = '''within Strings;
model Labelled "a String parameter"
  parameter Real k = 2 "rate";
  parameter String label = "abc" "a label";
  constant String kind = "decay" "a String constant is fine";
  Real x(start = 1, fixed = true);
equation
  der(x) = -k*x;
end Labelled;
'''


def test_string_parameter_is_refused_at_build_by_name(tmp_path):
    package = tmp_path / "lib" / "Strings"
    package.mkdir(parents=True)
    (package / "package.mo").write_text('within;\npackage Strings "test"\nend Strings;\n', encoding="utf-8")
    (package / "Labelled.mo").write_text(STRING_PARAMETER, encoding="utf-8")
    status, out, err = cli_in_process(["build", "Strings.Labelled", "--library", str(tmp_path / "lib"),
                                       "-o", str(tmp_path / "fmus")], tmp_path)
    assert status == 2
    assert err == (f"cosim build: error: {package / 'Labelled.mo'}:4: Strings.Labelled: String parameter 'label' is "
                   "not supported: the FMUs built here have Real, Integer and Boolean variables only (a String "
                   "constant is allowed)\n")
    assert not list(tmp_path.rglob("*.fmu"))
