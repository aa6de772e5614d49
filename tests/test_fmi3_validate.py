"""`cosim validate` beyond FMPy's static checks: it calls the binary of FMI 2.0 and FMI 3.0 FMUs.

The checks must pass on good FMUs (ours without a warning, every Reference FMU in FMI 2 and FMI 3 with exit
0) and each deliberate defect must be found by exactly the check meant to catch it, as a problem where the
FMI standard rules the behaviour out and as a warning where it allows it or leaves it undefined: the broken
FMUs are the Reference van der Pol FMU built from its vendored C sources with one edit each (a state check
removed or answering Discard, the token check removed, a wrong or an inaccurate Jacobian entry, a wrong
adjoint, an FMU state that is not restored or restored up to its last bits, a crash or a hang in DoStep,
NaN outputs, no binary), for FMI 2 and FMI 3.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from conftest import run_cli
from reference_fmus import REFERENCE_MODELS, REFERENCE_MODELS_FMI2, reference_fmu, reference_fmu2
from cosim.fmu.validate import validate, validate_report
from cosim.fmu.validate_checks import CHECKS, DERIVATIVE_RTOL, DERIVATIVE_WRONG

# the quick run (-m 'not slow') leaves this module out: it builds FMI 3 FMUs and the Reference FMUs
pytestmark = pytest.mark.slow

ALL_CHECKS = ["fmpy", "archive", "binary"] + [c.name for c in CHECKS]
HANG_TIMEOUT = 2.0  # s: how long validate waits for the FMU that hangs in DoStep


def build_reference(version: str, folder: Path, edits: dict | None = None, fmu_name: str | None = None) -> Path:
    if version == "2":
        return reference_fmu2("VanDerPol", folder, edits, fmu_name)
    return reference_fmu("VanDerPol", folder, edits, fmu_name)


def without_binary(fmu: Path) -> Path:
    broken = fmu.with_name(fmu.stem + "-nobinary.fmu")
    with zipfile.ZipFile(fmu) as source, zipfile.ZipFile(broken, "w") as target:
        for info in source.infolist():
            if not info.filename.startswith("binaries/"):
                target.writestr(info, source.read(info))
    return broken


def _api(version: str) -> str:
    return f"fmi{version}Functions.c"


def _defect_edits(defect: str, v: str) -> dict:
    """The C edits that give the van der Pol Reference FMU (FMI ``v``) the defect ``defect``."""
    api = _api(v)
    masks = {  # call -> (its state mask in the FMI 2 API, in the FMI 3 API)
        "DoStep": ("#define MASK_fmi2DoStep                  StepComplete",
                   "#define MASK_fmi3DoStep                   StepMode"),
        "ExitInitializationMode": ("#define MASK_fmi2ExitInitializationMode  InitializationMode",
                                   "#define MASK_fmi3ExitInitializationMode   InitializationMode"),
    }
    step_guard = "    BEGIN_FUNCTION(DoStep);\n"
    if defect == "discard-for-forbidden-call":  # DoStep in a state it is not allowed in: Discard, not Error
        state = "((ModelInstance *)c)->state" if v == "2" else "((ModelInstance *)instance)->state"
        discard = f"    if (!({state} & MASK_fmi{v}DoStep)) return fmi{v}Discard;\n"
        return {api: [(step_guard, discard + step_guard)]}
    if defect == "dostep-before-initialization":  # (the stop time is only set at initialization)
        line = masks["DoStep"][v == "3"]
        return {api: [(line, line + " | Instantiated"),
                      ("if (nextCommunicationPoint > S->stopTime && !isClose(nextCommunicationPoint, S->stopTime)) {",
                       "if (0) {")]}
    if defect == "exit-initialization-twice":
        line = masks["ExitInitializationMode"][v == "3"]
        return {api: [(line, line + (" | EventMode | StepComplete" if v == "2" else " | EventMode | StepMode"))]}
    if defect == "fixed-parameter-in-continuous-time":
        return {"model.c": [("comp->state != EventMode) {",
                             "comp->state != EventMode && comp->state != ContinuousTimeMode) {")]}
    if defect == "no-token-check":
        return {"cosimulation.c": [("if (strcmp(instantiationToken, INSTANTIATION_TOKEN)) {", "if (0) {")]}
    if defect == "token-mismatch":  # modelDescription.xml and the binary disagree
        attribute = "guid" if v == "2" else "instantiationToken"
        return {"modelDescription.xml": [(f'{attribute}="{{BD4', f'{attribute}="{{0D4')]}
    if defect in ("wrong-jacobian", "inaccurate-jacobian"):  # d der(x1) / d x1 off by 1e-3 / 1e-5
        error = "1e-3" if defect == "wrong-jacobian" else "1e-5"
        return {"model.c": [("*partialDerivative = M(mu) * (1 - M(x0) * M(x0));",
                             f"*partialDerivative = M(mu) * (1 - M(x0) * M(x0)) + {error};")]}
    if defect == "wrong-adjoint":  # the adjoint (only) 0.1 % off
        call = "CALL(getPartialDerivative(S, (ValueReference)unknowns[j], (ValueReference)knowns[i], " \
               "&partialDerivative));"
        return {api: [(call, call + " partialDerivative *= 1.001;")]}
    if defect == "state-not-restored":  # (the argument stays used: -Wunused-parameter is an error)
        call = "    setFMUState(S, FMUstate);" if v == "2" else "    CALL(setFMUState(S, FMUState));"
        return {api: [(call, "    UNUSED(FMUstate);" if v == "2" else "    UNUSED(FMUState);")]}
    if defect == "state-restored-but-last-bits":  # x0 restored 2 ulp off (relative 4.4e-16)
        call = "    setFMUState(S, FMUstate);" if v == "2" else "    CALL(setFMUState(S, FMUState));"
        return {api: [(call, call + " S->modelData.x0 *= 1 + 4.4e-16;")]}
    if defect == "crash-in-dostep":  # the second step and later dereference NULL
        return {api: [(step_guard, step_guard + "    if (S->time > 0) *(volatile int *)0 = 0;\n")]}
    if defect == "hang-in-dostep":
        return {api: [(step_guard, step_guard + "    if (S->time > 0) for (;;) {}\n")]}
    if defect == "wrong-last-successful-time":
        return {api: [("*lastSuccessfulTime  = S->time;", "*lastSuccessfulTime = S->time - 1e-3;")]}
    if defect == "early-return-not-allowed":
        return {api: [("*earlyReturn         = S->earlyReturnAllowed && !nextCommunicationPointReached;",
                       "*earlyReturn = fmi3True;")]}
    if defect == "nan-output":  # x0 is NaN after t = 0.5 s
        return {"model.c": [("            values[(*index)++] = M(x0);",
                             '            values[(*index)++] = comp->time > 0.5 ? __builtin_nan("") : M(x0);')]}
    raise KeyError(defect)


def _expected(defect: str, v: str) -> tuple[dict[str, list[str]], dict[str, list[str]]]:
    """(problems, warnings) the defect adds: check name -> the texts its lines contain (one line each)."""
    p = f"fmi{v}"
    setter = "SetReal" if v == "2" else "SetFloat64"
    token = "GUID" if v == "2" else "instantiationToken"
    crashed = "the binary crashed (SIGSEGV) in "
    hung = f"no answer within {HANG_TIMEOUT:g} s"
    last_bits = "in the last bits only"
    discard = [f"CS: {p}DoStep {when} returned Discard, expected Error"
               for when in ("before initialization", "in initialization mode", "after Terminate")]
    problems, warnings = {
        # A call the state machine does not allow, accepted: undefined in FMI 2, FMI 3 requires Error only
        # where the FMU detects it.
        "dostep-before-initialization": ({}, {"state-machine": [f"CS: {p}DoStep before initialization was accepted"]}),
        "exit-initialization-twice": ({}, {"state-machine": [
            f"CS: {p}ExitInitializationMode a second time was accepted",
            f"ME: {p}ExitInitializationMode a second time was accepted"]}),
        "fixed-parameter-in-continuous-time": ({}, {"state-machine": [
            f"ME: {p}{setter} of the fixed parameter 'mu' in continuous-time mode was accepted"]}),
        # Detected, but answered with Discard: FMI 3 requires Error.
        "discard-for-forbidden-call": ({"state-machine": discard}, {}) if v == "3"
                                      else ({}, {"state-machine": discard}),
        "no-token-check": ({}, {"token": [f"CS: instantiation with a wrong {token}",
                                          f"ME: instantiation with a wrong {token}"]}),
        "token-mismatch": ({"token": [f"ME: instantiation with the {token} of modelDescription.xml fails",
                                      f"CS: instantiation with the {token} of modelDescription.xml fails"]}, {}),
        "wrong-jacobian": ({"directional-derivatives": ["d(der(x1))/d(x1) = "]}, {}),
        "inaccurate-jacobian": ({}, {"directional-derivatives": ["d(der(x1))/d(x1) = "]}),
        "wrong-adjoint": ({"adjoint-derivatives": ["v^T(J u) = "] * 3}, {}),
        "state-not-restored": ({"fmu-state": ["CS: right after restoring the state: ",
                                              "CS: right after restoring a serialized and deserialized state: ",
                                              "ME: states and derivatives after restoring a state"]}, {}),
        "state-restored-but-last-bits": ({}, {"fmu-state": [last_bits] * 3}),
        "crash-in-dostep": ({"fmu-state": [crashed], "cs-run": [crashed],
                             **({"cs-step": [crashed]} if v == "3" else {})}, {}),
        "hang-in-dostep": ({"fmu-state": [hung], "cs-step": [hung], "cs-run": [hung]}, {}),
        # Neither finite values nor a successful run is required by the standard.
        "nan-output": ({}, {"me-run": ["'x0' is not finite"], "cs-run": ["'x0' is not finite"]}),
        # "it is allowed that lastSuccessfulTime deviates from" the end of the step.
        "wrong-last-successful-time": ({}, {"cs-step": ["fmi3DoStep to t = 0.04 s returned lastSuccessfulTime = "
                                                        "0.039 s (50 of the steps"]}),
        # earlyReturn = true "is only allowed if earlyReturnAllowed"; FMPy's simulate_fmu refuses it too,
        # which fails the short run.
        "early-return-not-allowed": ({"cs-step": ["fmi3DoStep returned earlyReturn = true at t = 0 s"]},
                                     {"cs-run": ["the run from t = 0 s to 2 s failed"]}),
    }[defect]
    return problems, warnings


BOTH_VERSIONS = ("dostep-before-initialization", "exit-initialization-twice", "fixed-parameter-in-continuous-time",
                 "discard-for-forbidden-call", "no-token-check", "token-mismatch", "wrong-jacobian",
                 "inaccurate-jacobian", "state-not-restored", "state-restored-but-last-bits", "crash-in-dostep",
                 "nan-output")
FMI3_ONLY = ("wrong-adjoint", "hang-in-dostep", "wrong-last-successful-time", "early-return-not-allowed")
DEFECTS = [(v, d) for v in ("2", "3") for d in BOTH_VERSIONS] + [("3", d) for d in FMI3_ONLY]


@pytest.fixture(scope="module")
def workshop(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("validate-fmus")


@pytest.fixture(scope="module")
def good_reference(workshop) -> dict[str, Path]:
    return {v: build_reference(v, workshop, fmu_name=f"VanDerPol-fmi{v}") for v in ("2", "3")}


#: The Reference FMU's one defect repaired: mu can no longer be set in Co-Simulation after
#: initialization (as in Model Exchange already).
REPAIR = {"model.c": [("if (comp->type == ModelExchange &&", "if (")]}


@pytest.fixture(scope="module")
def repaired_reference(workshop) -> dict[str, Path]:
    return {v: build_reference(v, workshop, REPAIR, fmu_name=f"VanDerPol-repaired-fmi{v}") for v in ("2", "3")}


def _by_check(lines: list[str]) -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    for line in lines:
        check, _, text = line.partition(": ")
        found.setdefault(check, []).append(text)
    return found


def _reference_warnings(version: str) -> list[str]:
    """The one warning of the unmodified Reference van der Pol FMU (v0.0.25): in Co-Simulation it
    accepts a new value of its fixed parameter mu after initialization, a call the state machines of
    FMI 2 (4.2.4: in slaveInitialized only inputs and tunable parameters) and FMI 3 (Step Mode: the
    same) do not allow, but which neither requires the FMU to refuse."""
    setter = "fmi2SetReal" if version == "2" else "fmi3SetFloat64"
    return [f"state-machine: CS: {setter} of the fixed parameter 'mu' after initialization was accepted "
            "(the state machine does not allow the call; the standard does not require the FMU to detect it, "
            "but Error would protect the user)"]


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_reference_vanderpol_has_one_warning_and_lists_what_it_skips(good_reference, version):
    """The unmodified Reference FMU (the base of every broken variant below): valid, with one warning;
    what it does not declare or what does not apply is listed as skipped."""
    report = validate_report(good_reference[version])
    assert report.fmi_version == f"{version}.0"
    assert report.problems == []
    assert report.warnings == _reference_warnings(version)
    assert report.checks == ALL_CHECKS
    expected_skips = ["directional-derivatives: outputs that are states (x0, x1) are not asked for as unknowns"]
    if version == "2":
        expected_skips += ["adjoint-derivatives: FMI 2 has no adjoint derivatives",
                           "cs-step: FMI 2's fmi2DoStep has no out-arguments to check"]
    assert report.skipped == expected_skips


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_repaired_reference_vanderpol_is_valid_without_warnings(repaired_reference, version):
    report = validate_report(repaired_reference[version])
    assert (report.problems, report.warnings) == ([], [])
    assert report.checks == ALL_CHECKS


REFERENCE_FMUS = [("3", m) for m in REFERENCE_MODELS] + [("2", m) for m in REFERENCE_MODELS_FMI2]


@pytest.mark.parametrize("version,model", REFERENCE_FMUS, ids=[f"fmi{v}-{m}" for v, m in REFERENCE_FMUS])
def test_every_reference_fmu_passes_cosim_validate(workshop, version, model):
    """The Reference FMUs of the Modelica Association, unmodified, are valid (exit 0); what they do that
    the standard allows but a robust FMU avoids (accepting a fixed parameter after initialization) is
    printed as a warning."""
    build = reference_fmu2 if version == "2" else reference_fmu
    fmu = build(model, workshop, fmu_name=f"{model}-fmi{version}")
    result = run_cli("validate", str(fmu))
    assert result.returncode == 0, result.stdout + result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith(f"{fmu}: valid") and lines[0].endswith(f"(FMI {version}.0, 11 checks)"), lines[0]
    assert not [line for line in lines if line.startswith("  - ")], result.stdout  # no problem
    assert result.stderr == ""


@pytest.mark.parametrize("version,defect", DEFECTS, ids=[f"fmi{v}-{d}" for v, d in DEFECTS])
def test_each_defect_is_found_by_its_check(workshop, version, defect):
    fmu = build_reference(version, workshop, _defect_edits(defect, version), fmu_name=f"fmi{version}-{defect}")
    # A hang is ended after HANG_TIMEOUT; the other variants keep the default (a loaded machine).
    report = validate_report(fmu, **({"timeout": HANG_TIMEOUT} if defect == "hang-in-dostep" else {}))
    # The defect adds exactly these problems and warnings to the warning of the unmodified FMU (which the
    # token mismatch hides: nothing runs after the token check).
    base = [] if defect == "token-mismatch" else _reference_warnings(version)
    assert [w for w in base if w not in report.warnings] == []
    expected_problems, expected_warnings = _expected(defect, version)
    for lines, expected in ((report.problems, expected_problems),
                            ([w for w in report.warnings if w not in base], expected_warnings)):
        found = _by_check(lines)
        assert set(found) == set(expected), lines  # exactly the check meant to catch it
        for check, texts in expected.items():
            assert len(found[check]) == len(texts), found[check]
            for text in texts:
                assert any(text in line for line in found[check]), (text, found[check])
    assert report.checks == ALL_CHECKS  # a crash or hang in one check does not stop the others
    if defect == "token-mismatch":  # nothing else can run, and says so
        assert [s for s in report.skipped if "not run" in s] == \
               [f"{c.name}: not run: the FMU cannot be instantiated (see token)" for c in CHECKS[1:]]


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_missing_binary_is_one_problem_and_the_dynamic_checks_are_skipped(good_reference, version):
    report = validate_report(without_binary(good_reference[version]))
    platform = "linux64" if version == "2" else "x86_64-linux"
    assert report.problems == [f"binary: no binary for this platform (binaries/{platform}/VanDerPol.so is missing "
                               "from the archive)"]  # once: ME and CS share the binary
    assert report.skipped == [f"{c.name}: not run: the FMU has no binary for this platform" for c in CHECKS]


def test_wrong_jacobian_message_quotes_both_values_and_the_tolerance(workshop):
    """At the check's point x = (2.01, 0.02), mu = 1: d der(x1)/d x1 = mu (1 - x0^2) = -3.0401; the
    edited FMU returns 1e-3 more."""
    fmu = build_reference("3", workshop, _defect_edits("wrong-jacobian", "3"), fmu_name="fmi3-jacobian-message")
    (line,) = validate(fmu)
    assert "= -3.0391 from fmi3GetDirectionalDerivative, -3.0401 from central differences" in line, line
    assert f"> {DERIVATIVE_WRONG:g})" in line


def test_inaccurate_jacobian_warning_names_numerical_differentiation(workshop):
    """1e-5 off (relative 3.3e-6): beyond exact derivatives, within numerical differentiation."""
    fmu = build_reference("3", workshop, _defect_edits("inaccurate-jacobian", "3"), fmu_name="fmi3-jacobian-warning")
    report = validate_report(fmu)
    assert report.problems == []
    (line,) = [w for w in report.warnings if w.startswith("directional-derivatives: ")]
    assert "= -3.04009 from fmi3GetDirectionalDerivative, -3.0401 from central differences" in line, line
    assert f"> {DERIVATIVE_RTOL:g}: inaccurate, as from numerical differentiation)" in line


def test_cli_lists_every_problem_and_warning_and_exits_1_without_traceback(workshop, repaired_reference,
                                                                           good_reference):
    broken = build_reference("2", workshop, {**_defect_edits("no-token-check", "2"),
                                             **_defect_edits("crash-in-dostep", "2")}, fmu_name="fmi2-two-defects")
    result = run_cli("validate", str(broken), str(repaired_reference["3"]), str(good_reference["3"]))
    assert result.returncode == 1, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "Traceback" not in result.stdout
    lines = result.stdout.splitlines()
    assert lines[0] == f"{broken}: 2 problem(s), 3 warning(s) (FMI 2.0, 11 checks)"
    second = lines.index(f"{repaired_reference['3']}: valid (FMI 3.0, 11 checks)")
    assert [line.split(":")[0] for line in lines[:second] if line.startswith(("  - ", "  warning: "))] == \
           ["  - fmu-state", "  - cs-run", "  warning", "  warning", "  warning"]
    assert [line.split(": ")[1] for line in lines[:second] if line.startswith("  warning: ")] == \
           ["token", "token", "state-machine"]
    assert "  skipped: adjoint-derivatives: FMI 2 has no adjoint derivatives" in lines
    third = lines.index(f"{good_reference['3']}: valid, 1 warning(s) (FMI 3.0, 11 checks)")
    assert lines[third + 1] == "  warning: " + _reference_warnings("3")[0]


def test_warnings_alone_exit_0(good_reference):
    result = run_cli("validate", str(good_reference["2"]))
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines()[:2] == [f"{good_reference['2']}: valid, 1 warning(s) (FMI 2.0, 11 checks)",
                                              "  warning: " + _reference_warnings("2")[0]]


def test_isolation_off_runs_in_process(good_reference):
    """Without the child process the findings are the same (for FMUs that do not crash)."""
    isolated = validate_report(good_reference["3"])
    in_process = validate_report(good_reference["3"], isolate=False)
    assert (in_process.problems, in_process.warnings, in_process.skipped, in_process.checks) == \
           (isolated.problems, isolated.warnings, isolated.skipped, isolated.checks)
    assert isolated.warnings == _reference_warnings("3")


def test_no_extraction_folder_is_left_by_the_child_processes(workshop, good_reference):
    before = set(Path(os.environ["TMPDIR"]).glob("cosim-fmu-*"))
    validate_report(good_reference["2"])
    fmu = build_reference("3", workshop, _defect_edits("crash-in-dostep", "3"), fmu_name="fmi3-crash-leftovers")
    validate_report(fmu)
    after = set(Path(os.environ["TMPDIR"]).glob("cosim-fmu-*"))
    assert after <= before | {p for p in after if p.name.startswith(f"cosim-fmu-{os.getpid()}-")}


OUR_MODELS = ["Bicycle.Bicycles.InvertedPendulum", "Bicycle.Bicycles.SelfStabilizing", "Bicycle.Bicycles.Whipple"]


@pytest.mark.parametrize("model", OUR_MODELS, ids=[m.split(".")[-1] for m in OUR_MODELS])
def test_our_fmi2_fmus_pass_every_check(fmus, model):
    report = validate_report(fmus[model])
    assert (report.problems, report.warnings) == ([], [])
    assert report.checks == ALL_CHECKS
    # Our FMUs declare everything: the only skips are what FMI 2 lacks and outputs that are states.
    fmi2_lacks = ["adjoint-derivatives: FMI 2 has no adjoint derivatives",
                  "cs-step: FMI 2's fmi2DoStep has no out-arguments to check"]
    assert [s for s in report.skipped if "outputs that are states" not in s] == fmi2_lacks


@pytest.mark.parametrize("model", OUR_MODELS, ids=[m.split(".")[-1] for m in OUR_MODELS])
def test_our_fmi3_fmus_pass_every_check(tmp_path_factory, model):
    from cosim.compiler.build import build_model

    runtime = Path(__file__).resolve().parents[1] / "cosim" / "runtime" / "fmi3_api.c"
    if not runtime.is_file():
        pytest.skip("the FMI 3 runtime (cosim/runtime/fmi3_api.c) is not there yet")
    fmu = build_model(model, os.environ["COSIM_FMU_DIR"], fmi_version="3").fmu
    report = validate_report(fmu)
    assert report.fmi_version == "3.0"
    assert (report.problems, report.warnings) == ([], [])
    assert report.checks == ALL_CHECKS
    assert all("outputs that are states" in s for s in report.skipped), report.skipped


def test_fmi3_container_of_our_fmu_runs_every_check(fmus, tmp_path):
    """A foreign FMI 3 Co-Simulation FMU (fmu-manipulation-toolbox's container around our FMI 2 FMU):
    the checks that apply pass; its two known defects (checked on fmu-manipulation-toolbox 2.0) are
    found by their checks: FMPy's model-structure check (a problem), and no instantiationToken check (a
    warning: FMI 3 lets the FMU check the token, it does not require it)."""
    pytest.importorskip("fmu_manipulation_toolbox")
    shutil.copy2(fmus["Bicycle.Bicycles.WhippleLinear"], tmp_path)
    (tmp_path / "bike.csv").write_text("rule;from_fmu;from_port;to_fmu;to_port\n"
                                       "FMU;Bicycle_Bicycles_WhippleLinear.fmu;;;\n")
    made = subprocess.run(["fmucontainer", "-container", "bike.csv:0.01", "-fmi", "3"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert made.returncode == 0 and (tmp_path / "bike.fmu").is_file(), made.stdout + made.stderr
    report = validate_report(tmp_path / "bike.fmu")
    assert report.fmi_version == "3.0" and report.checks == ALL_CHECKS
    assert set(_by_check(report.problems)) == {"fmpy"}, report.problems
    assert _by_check(report.warnings) == {"token": [
        "CS: instantiation with a wrong instantiationToken {00000000-0000-0000-0000-000000000000} was accepted "
        "(the instantiationToken is there to detect a binary that does not belong to its modelDescription.xml)"]}
    assert "fmu-state: CS: the FMU does not declare canGetAndSetFMUState" in report.skipped
