"""Bad input: one clear message, non-zero exit, no traceback, nothing half-written."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from conftest import ROOT, run_cli

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
