"""`cosim validate` beyond FMPy's static checks (issue 15): it calls the binary of FMI 2.0 and FMI 3.0 FMUs.

The checks must pass on good FMUs (ours, the Reference FMUs) and each deliberate defect must be found by
exactly the check meant to catch it: the broken FMUs are the Reference van der Pol FMU built from its
vendored C sources with one edit each (a state check removed, the token check removed, a wrong Jacobian
entry, a wrong adjoint, an FMU state that is not restored, a crash or a hang in DoStep, NaN outputs, no
binary), for FMI 2 and FMI 3.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from conftest import run_cli
from reference_fmus import FMI3_HEADERS, SOURCES as REFERENCE_SOURCES, pack, reference_fmu
from cosim.fmu.validate import validate, validate_report
from cosim.fmu.validate_checks import CHECKS, DERIVATIVE_RTOL

FMI2_SOURCES = Path(__file__).resolve().parent / "data" / "reference-fmus-fmi2"
ALL_CHECKS = ["fmpy", "archive", "binary"] + [c.name for c in CHECKS]
HANG_TIMEOUT = 3.0  # s: how long validate waits for the FMU that hangs in DoStep


def reference_fmu2(name: str, folder: Path, edits: dict | None = None, fmu_name: str | None = None) -> Path:
    """The Reference FMU ``name`` built as an FMI 2.0 FMU (ME + CS) into ``folder`` (only VanDerPol has an
    FMI 2 model description in tests/data/reference-fmus-fmi2). ``edits`` as for
    :func:`reference_fmus.reference_fmu`: file name -> (old, new) replacements, each ``old`` must occur."""
    tree = folder / (fmu_name or name)
    if tree.exists():
        shutil.rmtree(tree)
    sources, binaries = tree / "sources", tree / "binaries" / "linux64"
    sources.mkdir(parents=True)
    binaries.mkdir(parents=True)
    shutil.copy2(FMI2_SOURCES / "fmi2Functions.c", sources)
    for file in ("cosimulation.c", "cosimulation.h", "model.h"):
        shutil.copy2(REFERENCE_SOURCES / "common" / file, sources)
    for file in ("model.c", "config.h"):
        shutil.copy2(REFERENCE_SOURCES / name / file, sources)
    # all.c: the one source file the FMI 2 model description lists (as in the Reference FMUs' FMI 2 FMUs).
    (sources / "all.c").write_text('#include "fmi2Functions.c"\n#include "model.c"\n#include "cosimulation.c"\n')
    shutil.copy2(FMI2_SOURCES / name / "modelDescription.xml", tree)
    for file, replacements in (edits or {}).items():
        target = tree / file if file == "modelDescription.xml" else sources / file
        text = target.read_text(encoding="utf-8")
        for old, new in replacements:
            assert old in text, f"edit of {file}: {old!r} does not occur"
            text = text.replace(old, new)
        target.write_text(text, encoding="utf-8")
    result = subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-Werror=implicit-function-declaration",
                             "-DFMI_VERSION=2", "-DDISABLE_PREFIX", f"-I{sources}", f"-I{FMI3_HEADERS}",
                             str(sources / "all.c"), "-lm", "-o", str(binaries / f"{name}.so")],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return pack(tree, folder / f"{fmu_name or name}.fmu")


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
    step_guard = "    ASSERT_STATE(DoStep);\n"
    if defect == "dostep-before-initialization":  # (the stop time is only set at initialization)
        line = masks["DoStep"][v == "3"]
        return {api: [(line, line + " | Instantiated"),
                      ("if (currentCommunicationPoint + communicationStepSize > S->stopTime + EPSILON) {",
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
    if defect == "wrong-jacobian":  # d der(x1) / d x1 off by 1e-3
        return {"model.c": [("*partialDerivative = M(mu) * (1 - M(x0) * M(x0));",
                             "*partialDerivative = M(mu) * (1 - M(x0) * M(x0)) + 1e-3;")]}
    if defect == "wrong-adjoint":  # the adjoint (only) 0.1 % off
        call = "Status s = getPartialDerivative(S, (ValueReference)unknowns[j], (ValueReference)knowns[i], " \
               "&partialDerivative);"
        return {api: [(call, call + " partialDerivative *= 1.001;")]}
    if defect == "state-not-restored":
        call = "    setFMUState(S, FMUstate);" if v == "2" else "    setFMUState(S, FMUState);"
        return {api: [(call, "")]}
    if defect == "crash-in-dostep":  # the second step and later dereference NULL
        return {api: [(step_guard, step_guard + "    if (S->time > 0) *(volatile int *)0 = 0;\n")]}
    if defect == "hang-in-dostep":
        return {api: [(step_guard, step_guard + "    if (S->time > 0) for (;;) {}\n")]}
    if defect == "wrong-last-successful-time":
        return {api: [("*lastSuccessfulTime = S->time;", "*lastSuccessfulTime = S->time - 1e-3;")]}
    if defect == "early-return-not-allowed":
        return {api: [("*earlyReturn = !nextCommunicationPointReached;", "*earlyReturn = fmi3True;")]}
    if defect == "nan-output":  # x0 is NaN after t = 0.5 s
        return {"model.c": [("            values[(*index)++] = M(x0);",
                             '            values[(*index)++] = comp->time > 0.5 ? __builtin_nan("") : M(x0);')]}
    raise KeyError(defect)


def _expected(defect: str, v: str) -> dict[str, list[str]]:
    """check name -> the texts its problem lines contain (one line each), for the defect."""
    p = f"fmi{v}"
    setter = "SetReal" if v == "2" else "SetFloat64"
    token = "GUID" if v == "2" else "instantiationToken"
    crashed = "the binary crashed (SIGSEGV) in "
    hung = f"no answer within {HANG_TIMEOUT:g} s"
    return {
        "dostep-before-initialization": {"state-machine": [f"CS: {p}DoStep before initialization was accepted"]},
        "exit-initialization-twice": {"state-machine": [f"CS: {p}ExitInitializationMode a second time was accepted",
                                                        f"ME: {p}ExitInitializationMode a second time was accepted"]},
        "fixed-parameter-in-continuous-time": {"state-machine": [
            f"ME: {p}{setter} of the fixed parameter 'mu' in continuous-time mode was accepted"]},
        "no-token-check": {"token": [f"CS: instantiation with a wrong {token}",
                                     f"ME: instantiation with a wrong {token}"]},
        "token-mismatch": {"token": [f"ME: instantiation with the {token} of modelDescription.xml fails",
                                     f"CS: instantiation with the {token} of modelDescription.xml fails"]},
        "wrong-jacobian": {"directional-derivatives": ["d(der(x1))/d(x1) = "]},
        "wrong-adjoint": {"adjoint-derivatives": ["v^T(J u) = "] * 3},
        "state-not-restored": {"fmu-state": ["CS: right after restoring the state: ",
                                             "CS: right after restoring a serialized and deserialized state: ",
                                             "ME: states and derivatives after restoring a state"]},
        "crash-in-dostep": {"fmu-state": [crashed], "cs-run": [crashed],
                            **({"cs-step": [crashed]} if v == "3" else {})},
        "hang-in-dostep": {"fmu-state": [hung], "cs-step": [hung], "cs-run": [hung]},
        "nan-output": {"me-run": ["'x0' is not finite"], "cs-run": ["'x0' is not finite"]},
        "wrong-last-successful-time": {"cs-step": ["fmi3DoStep to t = 0.04 s returned lastSuccessfulTime = 0.039 s "
                                                   "(50 of the steps"]},
        # FMPy's simulate_fmu refuses an early return it did not allow: cs-run finds it as well.
        "early-return-not-allowed": {"cs-step": ["fmi3DoStep returned earlyReturn = true at t = 0 s"],
                                     "cs-run": ["the run from t = 0 s to 2 s failed"]},
    }[defect]


BOTH_VERSIONS = ("dostep-before-initialization", "exit-initialization-twice", "fixed-parameter-in-continuous-time",
                 "no-token-check", "token-mismatch", "wrong-jacobian", "state-not-restored", "crash-in-dostep",
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


def _by_check(problems: list[str]) -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    for line in problems:
        check, _, text = line.partition(": ")
        found.setdefault(check, []).append(text)
    return found


def _reference_problems(version: str) -> list[str]:
    """The one problem of the unmodified Reference van der Pol FMU (v0.0.25): in Co-Simulation it
    accepts a new value of its fixed parameter mu after initialization, which FMI 2 (4.2.4: in
    slaveInitialized only inputs and tunable parameters) and FMI 3 (Step Mode: the same) forbid."""
    setter = "fmi2SetReal" if version == "2" else "fmi3SetFloat64"
    return [f"state-machine: CS: {setter} of the fixed parameter 'mu' after initialization was accepted "
            "(the standard forbids it; expected Error)"]


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_reference_vanderpol_has_one_problem_and_lists_what_it_skips(good_reference, version):
    """The unmodified Reference FMU (the base of every broken variant below): one real defect;
    what it does not declare or what does not apply is listed as skipped."""
    report = validate_report(good_reference[version])
    assert report.fmi_version == f"{version}.0"
    assert report.problems == _reference_problems(version)
    assert report.checks == ALL_CHECKS
    expected_skips = ["directional-derivatives: outputs that are states (x0, x1) are not asked for as unknowns"]
    if version == "2":
        expected_skips += ["adjoint-derivatives: FMI 2 has no adjoint derivatives",
                           "cs-step: FMI 2's fmi2DoStep has no out-arguments to check"]
    assert report.skipped == expected_skips


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_repaired_reference_vanderpol_is_valid(repaired_reference, version):
    report = validate_report(repaired_reference[version])
    assert report.problems == []
    assert report.checks == ALL_CHECKS


@pytest.mark.parametrize("version,defect", DEFECTS, ids=[f"fmi{v}-{d}" for v, d in DEFECTS])
def test_each_defect_is_found_by_its_check(workshop, version, defect):
    fmu = build_reference(version, workshop, _defect_edits(defect, version), fmu_name=f"fmi{version}-{defect}")
    # A hang is ended after HANG_TIMEOUT; the other variants keep the default (a loaded machine).
    report = validate_report(fmu, **({"timeout": HANG_TIMEOUT} if defect == "hang-in-dostep" else {}))
    # The defect adds exactly these problems to those of the unmodified FMU (which the token
    # mismatch hides: nothing runs after the token check).
    base = [] if defect == "token-mismatch" else _reference_problems(version)
    assert [p for p in base if p not in report.problems] == []
    found = _by_check([p for p in report.problems if p not in base])
    expected = _expected(defect, version)
    assert set(found) == set(expected), report.problems  # exactly the check meant to catch it
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
    (line,) = [p for p in validate(fmu) if p not in _reference_problems("3")]
    assert "= -3.0391 from fmi3GetDirectionalDerivative, -3.0401 from central differences" in line, line
    assert f"> {DERIVATIVE_RTOL:g}" in line


def test_cli_lists_every_problem_and_exits_1_without_traceback(workshop, repaired_reference):
    broken = build_reference("2", workshop, {**_defect_edits("no-token-check", "2"),
                                             **_defect_edits("crash-in-dostep", "2")}, fmu_name="fmi2-two-defects")
    result = run_cli("validate", str(broken), str(repaired_reference["3"]))
    assert result.returncode == 1, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "Traceback" not in result.stdout
    lines = result.stdout.splitlines()
    assert lines[0] == f"{broken}: 5 problem(s) (FMI 2.0, 11 checks)"
    second = lines.index(f"{repaired_reference['3']}: valid (FMI 3.0, 11 checks)")
    problems = [line for line in lines[:second] if line.startswith("  - ")]
    assert [p.split(":")[0] for p in problems] == \
           ["  - token", "  - token", "  - state-machine", "  - fmu-state", "  - cs-run"]
    assert "  skipped: adjoint-derivatives: FMI 2 has no adjoint derivatives" in lines


def test_isolation_off_runs_in_process(good_reference):
    """Without the child process the findings are the same (for FMUs that do not crash)."""
    isolated = validate_report(good_reference["3"])
    in_process = validate_report(good_reference["3"], isolate=False)
    assert (in_process.problems, in_process.skipped, in_process.checks) == \
           (isolated.problems, isolated.skipped, isolated.checks)


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
    assert report.problems == []
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
    assert report.problems == []
    assert report.checks == ALL_CHECKS
    assert all("outputs that are states" in s for s in report.skipped), report.skipped


def test_fmi3_container_of_our_fmu_runs_every_check(fmus, tmp_path):
    """A foreign FMI 3 Co-Simulation FMU (fmu-manipulation-toolbox's container around our FMI 2 FMU):
    the checks that apply pass; its two known defects (checked on fmu-manipulation-toolbox 2.0) are
    found by their checks: FMPy's model-structure check, and no instantiationToken check."""
    pytest.importorskip("fmu_manipulation_toolbox")
    shutil.copy2(fmus["Bicycle.Bicycles.WhippleLinear"], tmp_path)
    (tmp_path / "bike.csv").write_text("rule;from_fmu;from_port;to_fmu;to_port\n"
                                       "FMU;Bicycle_Bicycles_WhippleLinear.fmu;;;\n")
    made = subprocess.run(["fmucontainer", "-container", "bike.csv:0.01", "-fmi", "3"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert made.returncode == 0 and (tmp_path / "bike.fmu").is_file(), made.stdout + made.stderr
    report = validate_report(tmp_path / "bike.fmu")
    assert report.fmi_version == "3.0" and report.checks == ALL_CHECKS
    found = _by_check(report.problems)
    assert set(found) == {"fmpy", "token"}, report.problems
    assert found["token"] == ["CS: instantiation with a wrong instantiationToken "
                              "{00000000-0000-0000-0000-000000000000} was accepted"]
    assert "fmu-state: CS: the FMU does not declare canGetAndSetFMUState" in report.skipped
