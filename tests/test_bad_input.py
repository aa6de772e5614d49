"""Bad input: one clear message, non-zero exit, no traceback, nothing half-written."""
from __future__ import annotations

import contextlib
import os
import shutil
import signal
from pathlib import Path

import pytest

from conftest import ROOT, cli_in_process, run_cli

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

GOOD = """within Broken;
model {name} "test model"
  Real x(start = 1, fixed = true) "state";
equation
  der(x) = -x;
end {name};
"""

CASES = {
    "syntax": ("""within Broken;
model Syntax "missing semicolon"
  Real x(start = 1, fixed = true)
equation
  der(x) = -x;
end Syntax;
""", ["Syntax.mo:4:1:", "syntax error"]),
    "unbalanced": ("""within Broken;
model Unbalanced "two unknowns, one equation"
  Real x(start = 1, fixed = true);
  Real y;
equation
  der(x) = -x;
end Unbalanced;
""", ["unbalanced", "1 equations for 2 unknowns"]),
    "index2": ("""within Broken;
model Index2 "constraint on a state: index 2"
  Real x(start = 0, fixed = true);
  Real v(start = 0, fixed = true);
  Real lambda "multiplier";
equation
  der(x) = v;
  der(v) = lambda;
  x = sin(time);
end Index2;
""", ["structurally singular", "x", "lambda", "index > 1"]),
    "nonlinear": ("""within Broken;
model Nonlinear "nonlinear algebraic equation in y"
  Real x(start = 1, fixed = true);
  Real y;
equation
  der(x) = -y;
  y^3 + y = x;
end Nonlinear;
""", ["nonlinear algebraic loop in y", "0 = "]),
}


def make_library(tmp_path: Path, name: str, text: str) -> Path:
    library = tmp_path / "lib"
    shutil.copytree(ROOT / "modelica", library)
    package = library / "Broken"
    package.mkdir()
    (package / "package.mo").write_text('within;\npackage Broken "invalid models for tests"\nend Broken;\n')
    (package / "package.order").write_text(f"{name}\n")
    (package / f"{name}.mo").write_text(text)
    return library


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_build_rejects_bad_model(tmp_path, case):
    text, expected = CASES[case]
    name = case.capitalize() if case != "index2" else "Index2"
    library = make_library(tmp_path, name, text)
    out = tmp_path / "out"
    result = run_cli("build", f"Broken.{name}", "--library", str(library), "-o", str(out), "-j", "1")
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    for fragment in expected:
        assert fragment in result.stderr, result.stderr
    assert not out.exists() or list(out.iterdir()) == [], "partial output left behind"


def test_unknown_model_lists_known_models(tmp_path):
    out = tmp_path / "out"
    result = run_cli("build", "Bicycle.Bicycles.NoSuchBike", "-o", str(out))
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    assert "unknown model 'Bicycle.Bicycles.NoSuchBike'" in result.stderr
    assert "Bicycle.Bicycles.SelfStabilizing" in result.stderr
    assert not out.exists() or list(out.iterdir()) == []


def test_good_model_in_same_library_builds(tmp_path):
    """The broken-library fixture itself is sound: a correct model next to it builds."""
    library = make_library(tmp_path, "Decay", GOOD.format(name="Decay"))
    out = tmp_path / "out"
    result = run_cli("build", "Broken.Decay", "--library", str(library), "-o", str(out), "-j", "1")
    assert result.returncode == 0, result.stderr
    assert (out / "Broken_Decay.fmu").is_file()
    assert [p.name for p in out.iterdir()] == ["Broken_Decay.fmu"]


@pytest.mark.parametrize("param,message", [
    ("V=abc", "parameter 'V': 'abc' is not a number"),
    ("nosuch=1", "unknown parameter 'nosuch'"),
    ("V", "--param expects NAME=VALUE"),
], ids=["not-a-number", "unknown-name", "malformed"])
def test_simulate_rejects_bad_parameter(fmus, tmp_path, param, message):
    fmu = fmus["Bicycle.Bicycles.SelfStabilizing"]
    result = run_cli("simulate", str(fmu), "--stop-time", "1", "--param", param, "-o", str(tmp_path / "r.csv"))
    assert result.returncode != 0
    assert message in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "r.csv").exists()


# ----------------------------------------------------------------- inputs that are not regular files

def _not_a_regular_file(kind: str, path: Path) -> Path:
    """``path`` made a FIFO, a symbolic link to /dev/zero (endless bytes) or a directory."""
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "dev-zero":
        path.symlink_to("/dev/zero")
    else:
        path.mkdir()
    return path


INPUTS = {  # verb: (argv with {path} and {fmu}, name of the input file, what the message calls it)
    "info-fmu": (["info", "{path}"], "x.fmu", "not an FMU file"),
    "run-system": (["run", "{path}", "-o", "out.csv"], "x.toml", "not a system file"),
    "matrix-spec": (["matrix", "{path}", "-o", "out", "--no-progress"], "x.toml", "not a spec file"),
    "params-file": (["simulate", "{fmu}", "--stop-time", "1", "--params", "{path}", "-o", "out.csv"], "x.toml",
                    "not a parameter file"),
    "input-csv": (["simulate", "{fmu}", "--stop-time", "1", "--input", "T={path}", "-o", "out.csv"], "x.csv",
                  "not a file"),
    "animate-result": (["animate", "{path}", "-o", "out.html"], "x.csv", "not a file"),
}
KINDS = {"fifo": "is a FIFO (named pipe)", "dev-zero": "is a character device", "directory": "is a directory"}


@contextlib.contextmanager
def _alarm(seconds: int):
    """A command that blocks (opening a FIFO with no writer, reading /dev/zero) fails the test
    after ``seconds`` instead of hanging it."""
    def hung(signum, frame):  # pytest.fail: a BaseException, which the command line does not catch
        pytest.fail(f"still running after {seconds} s: the input was opened")

    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/zero"), reason="needs FIFOs and /dev/zero")
@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("verb", list(INPUTS))
def test_input_that_is_not_a_regular_file_is_refused_before_opening(fmus, tmp_path, verb, kind):
    """A FIFO named x.fmu used to block `cosim info` forever, a link to /dev/zero to read without
    end: every input file the user names (FMU, system and spec TOML, parameter file, input CSV,
    result) is refused by its type before it is opened, one line naming it, exit 2."""
    argv, name, what = INPUTS[verb]
    path = _not_a_regular_file(kind, tmp_path / name)
    argv = [a.format(path=path, fmu=fmus["Bicycle.Bicycles.SelfStabilizing"]) for a in argv]
    with _alarm(60):
        status, out, err = cli_in_process(argv, tmp_path)
    assert status == 2, out + err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and f"{KINDS[kind]}, {what}" in lines[0], lines
    assert sorted(p.name for p in tmp_path.iterdir()) == [name], "something was written"


@pytest.mark.parametrize("argv, message", [
    (["run", "{blocker}/x.toml", "-o", "r.csv"], "{blocker}/x.toml: cannot read the system file: Not a directory"),
    (["info", "{blocker}/x.fmu"], "{blocker}/x.fmu: cannot read the FMU file: Not a directory"),
    (["run", "{long}.toml", "-o", "r.csv"], "{long}.toml: cannot read the system file: File name too long"),
    (["info", "{long}.fmu"], "{long}.fmu: cannot read the FMU file: File name too long"),
    (["animate", "{long}.csv", "-o", "a.html"], "{long}.csv: cannot read the file: File name too long"),
], ids=["system-under-a-file", "fmu-under-a-file", "system-name-too-long", "fmu-name-too-long",
        "result-name-too-long"])
def test_input_path_the_os_refuses_is_one_line(tmp_path, argv, message):
    """OS errors of an input path (a component that is a file: ENOTDIR; a name of 300
    characters: ENAMETOOLONG) are one line naming the path and the operation, exit 2."""
    blocker = tmp_path / "file.txt"
    blocker.write_text("a file, not a folder\n")
    names = {"blocker": blocker, "long": tmp_path / ("L" * 300)}
    status, out, err = cli_in_process([a.format(**names) for a in argv], tmp_path)
    assert status == 2, out + err
    assert err.strip().splitlines() == [f"cosim {argv[0]}: error: {message.format(**names)}"]


def test_class_name_longer_than_a_file_name_is_one_line(tmp_path):
    """A model of 294 characters (defined in its package's file) builds to an FMU whose name the
    file system refuses: one line naming the FMU, exit 2, before anything is compiled; a
    simulate of it refuses the default result name the same way."""
    name = "A" * 288
    library = tmp_path / "lib"
    (library / "Long").mkdir(parents=True)
    (library / "Long" / "package.mo").write_text(
        f'within;\npackage Long "long names"\n  model {name} "decay"\n    Real x(start = 1, fixed = true);\n'
        f'  equation\n    der(x) = -x;\n  end {name};\nend Long;\n')
    model = f"Long.{name}"
    assert len(model) == 293
    out = tmp_path / "out"
    status, _, err = cli_in_process(["build", model, "--library", str(library), "-o", str(out)], tmp_path)
    assert status == 2 and err.count("\n") == 1, err
    assert err.startswith(f"cosim build: error: model name '{model}' is too long for an FMU file: its name "
                          f"'Long_{name}.fmu' has "), err
    assert not out.exists() or list(out.iterdir()) == []
    status, _, err = cli_in_process(["simulate", model, "--library", str(library), "--stop-time", "1"], tmp_path)
    assert status == 2 and err.count("\n") == 1, err
    assert err.startswith("cosim simulate: error: the model name is too long for a result file named after it"), err
