"""The command line as a user runs it."""
from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import ROOT, line_pixels, png_pixels, run_cli

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.SelfStabilizing"


def test_list_json():
    result = run_cli("list", "--json")
    assert result.returncode == 0, result.stderr
    models = {m["name"]: m for m in json.loads(result.stdout)}
    m = models[MODEL]
    assert m["exported"] and [s["name"] for s in m["inputs"]] == ["T"]
    assert {"phi", "delta"} <= {s["name"] for s in m["outputs"]}
    assert {p["name"]: p["unit"] for p in m["parameters"]}["V"] == "m/s"


def test_info_fmu_and_model(fmus):
    result = run_cli("info", str(fmus[MODEL]), "--json")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["interfaces"] == ["ModelExchange", "CoSimulation"]
    assert info["states"] == ["frame.phi", "frame.L", "path.psi", "path.eta"]
    assert info["defaultExperiment"]["tolerance"] == pytest.approx(1e-8)
    text = run_cli("info", MODEL)
    assert text.returncode == 0 and "inputs:" in text.stdout and "T" in text.stdout


def test_validate_fmu(fmus):
    result = run_cli("validate", str(fmus[MODEL]))
    assert result.returncode == 0 and "valid" in result.stdout, result.stdout + result.stderr


def test_validate_reports_broken_fmu_and_checks_the_others(fmus, tmp_path):
    """A file that is not an FMU gets one error line (exit 2); the valid FMU after it is still checked."""
    broken = tmp_path / "broken.fmu"
    broken.write_bytes(b"not a zip")
    result = run_cli("validate", str(broken), str(fmus[MODEL]))
    assert result.returncode == 2
    assert f"cosim validate: error: {broken}: not an FMU: not a zip archive" in result.stderr
    assert f"{fmus[MODEL]}: valid" in result.stdout
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr


def test_simulate_with_csv_input_and_plot(fmus, tmp_path):
    signal = tmp_path / "torque.csv"
    signal.write_text("time,T\n0,0\n1,0\n1,2\n5,2\n")
    out, png = tmp_path / "out.csv", tmp_path / "out.png"
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "5", "--step", "0.01", "--param", "V=6",
                     "--input", f"T={signal}", "-o", str(out), "--plot", str(png))
    assert result.returncode == 0, result.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert data["time"][-1] == pytest.approx(5.0)
    assert np.all(data["phi"][data["time"] <= 1.0] == 0.0)  # no torque before t = 1 s
    assert data["phi"][-1] > 0.01
    # cosim.fmu.simulate.plot: one 7 in x 1.8 in subplot per signal at 120 dpi, each with its curve
    signals = len(data.dtype.names) - 1
    assert png_pixels(png).shape[:2] == (round(1.8 * 120) * signals, 7 * 120)
    assert line_pixels(png) >= 200 * signals, "the curves were not drawn"


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
def test_simulate_model_name_step_input(fmi_type, tmp_path):
    out = tmp_path / "r.csv"
    result = run_cli("simulate", MODEL, "--stop-time", "2", "--fmi-type", fmi_type, "--input", "T=step:0.5:1",
                     "-o", str(out))
    assert result.returncode == 0, result.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert abs(data["phi"][data["time"] < 0.5]).max() == 0.0 and data["phi"][-1] > 0


def test_linearize_json(fmus):
    result = run_cli("linearize", str(fmus[MODEL]), "--speed", "6", "--json")
    assert result.returncode == 0, result.stderr
    lin = json.loads(result.stdout)
    assert lin["states"] == ["frame.phi", "frame.L", "path.psi", "path.eta"] and lin["inputs"] == ["T"]
    assert np.array(lin["A"]).shape == (4, 4) and len(lin["eigenvalues"]) == 4
    roll = np.linalg.eigvals(np.array(lin["A"])[:2, :2])
    assert all(roll.real < 0)  # V = 6 m/s is above the critical speed; psi and eta are integrators


def test_figure5_command(tmp_path):
    result = run_cli("figures", "fig5", "-o", str(tmp_path))
    assert result.returncode == 0, result.stderr
    png = tmp_path / "fig5.png"
    assert min(png_pixels(png).shape[:2]) >= 500  # 6 in x 6 in at 120 dpi, cropped to its content
    assert line_pixels(png) >= 1000, "the three time histories were not drawn"


def test_unknown_figure(tmp_path):
    result = run_cli("figures", "fig99", "-o", str(tmp_path))
    assert result.returncode != 0 and "unknown figure(s) fig99" in result.stderr


@pytest.mark.needs_libcosim
def test_run_and_export_ssp(tmp_path):
    from cosim.engines import engine

    system = ROOT / "cosim" / "systems" / "rider-p-control.toml"
    npy, ssp = tmp_path / "r.npy", tmp_path / "r.ssp"
    result = run_cli("run", str(system), "-o", str(npy))
    assert result.returncode == 0, result.stderr
    data = np.load(npy)
    assert {"time", "bike.phi", "rider.T"} <= set(data.dtype.names)
    result = run_cli("export-ssp", str(system), "-o", str(ssp))
    assert result.returncode == 0, result.stderr
    assert "twin: rider: Python Proportional -> Bicycle.Control.Proportional" in result.stdout
    assert engine("libcosim").run_ssp(ssp, ["bike.phi"])["bike.phi"].size == 2000


def test_run_reports_fall(tmp_path):
    result = run_cli("run", str(ROOT / "cosim" / "systems" / "rear-steered-p.toml"), "-o", str(tmp_path / "r.csv"))
    assert result.returncode == 3 and "fell at t = " in result.stdout


# ---------------------------------------------------------------- help, --library, messages, `cosim list`

# Verbs that resolve Modelica model names (directly or through system files and specs).
RESOLVING_VERBS = ["build", "list", "info", "validate", "simulate", "linearize", "compare", "run", "export-ssp",
                   "figures", "demo", "matrix", "app", "diagram"]
TINY = """within Tiny;
model Decay "dx/dt = -k x"
  parameter Real k(unit = "1/s") = 2 "rate";
  output Real y "the state";
  Real x(start = 1, fixed = true);
equation
  der(x) = -k * x;
  y = x;
  annotation(__Cosim(export = true));
end Decay;
"""


def _subcommands() -> dict:
    import argparse

    from cosim.cli import parser

    sub = next(a for a in parser()._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def test_every_cli_option_has_help_text():
    import argparse

    from cosim.cli import parser

    missing = [f"cosim {'' if p is None else verb + ' '}{'/'.join(a.option_strings) or a.dest}"
               for verb, p in [(None, parser()), *_subcommands().items()] for a in (p or parser())._actions
               if not isinstance(a, argparse._SubParsersAction) and not (a.help and a.help != argparse.SUPPRESS)]
    assert missing == []


@pytest.mark.parametrize("verb", RESOLVING_VERBS)
def test_every_verb_that_resolves_models_takes_library(verb):
    options = {s for a in _subcommands()[verb]._actions for s in a.option_strings}
    assert "--library" in options


def test_main_help_documents_the_environment_variables():
    result = run_cli("--help")
    assert result.returncode == 0
    for variable in ("COSIM_MODELICA_PATH", "COSIM_FMU_DIR", "COSIM_DEBUG"):
        assert variable in result.stdout


@pytest.mark.parametrize("verb, args", [
    ("build", ["Tiny.Decay"]), ("list", []), ("info", ["Tiny.Decay"]), ("validate", ["Tiny.Decay"]),
    ("simulate", ["Tiny.Decay", "--stop-time", "1"]), ("linearize", ["Tiny.Decay"]),
    ("compare", ["Bicycle.Bicycles.SelfStabilizing"]), ("run", ["system.toml"]),
    ("export-ssp", ["system.toml", "-o", "s.ssp"]), ("figures", ["fig5"]), ("demo", []), ("matrix", ["paper"]),
    ("app", ["--export", "site"]), ("diagram", ["Tiny.Decay", "-o", "d.svg"]),
], ids=lambda x: x if isinstance(x, str) else None)
def test_missing_library_folder_is_refused_before_any_work(verb, args, tmp_path):
    missing = tmp_path / "no-library"
    result = run_cli(verb, *args, "--library", str(missing), cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines() == [
        f"cosim {verb}: error: {missing}: Modelica library folder not found"]
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing built, nothing written


@pytest.fixture(scope="module")
def tiny_library(tmp_path_factory):
    """A library holding only ``Tiny.Decay``, and an FMU folder of its own."""
    root = tmp_path_factory.mktemp("tiny")
    package = root / "lib" / "Tiny"
    package.mkdir(parents=True)
    (package / "package.mo").write_text('within;\npackage Tiny "a library for tests"\nend Tiny;\n')
    (package / "package.order").write_text("Decay\n")
    (package / "Decay.mo").write_text(TINY)
    return root / "lib", root / "fmus"


@pytest.mark.parametrize("how", ["option", "environment"])
@pytest.mark.parametrize("verb, args, expect", [
    ("list", ["--json"], '"name": "Tiny.Decay"'),
    ("info", ["Tiny.Decay"], "Tiny.Decay"),
    ("simulate", ["Tiny.Decay", "--stop-time", "1", "-o", "{tmp}/d.csv"], "wrote"),
    ("linearize", ["Tiny.Decay", "--param", "k=3", "--json"], '"eigenvalues"'),
    ("validate", ["Tiny.Decay"], ": valid"),
], ids=["list", "info", "simulate", "linearize", "validate"])
def test_library_option_and_variable_resolve_models_in_another_library(verb, args, expect, how, tiny_library,
                                                                       tmp_path):
    library, fmu_dir = tiny_library
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    env = {"COSIM_FMU_DIR": str(fmu_dir)}
    if how == "option":
        args += ["--library", str(library)]
    else:
        env["COSIM_MODELICA_PATH"] = str(library)
    result = run_cli(verb, *args, env=env, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert expect in result.stdout and "Traceback" not in result.stderr
    if verb == "linearize":  # dx/dt = -k x at k = 3 1/s
        assert np.allclose(json.loads(result.stdout)["A"], [[-3.0]], rtol=0, atol=1e-9)
    if verb in ("simulate", "linearize", "validate"):  # built into COSIM_FMU_DIR, not ./fmus
        assert [p.name for p in fmu_dir.glob("*.fmu")] == ["Tiny_Decay.fmu"]
        assert not (tmp_path / "fmus").exists()


def test_model_of_another_library_is_unknown_without_library(tiny_library, tmp_path):
    result = run_cli("info", "Tiny.Decay", cwd=tmp_path)
    assert result.returncode == 2 and result.stderr.startswith("cosim info: error: ")
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize("args, message", [
    (["analytic", "--speed", "nan"], "cosim analytic: error: --speed must be finite"),
    (["analytic", "--params", "no-such-set"], "cosim analytic: error: "),
    (["matrix", "paper", "--keep-failed"], "cosim matrix: error: --keep-failed applies only with --resume"),
], ids=["analytic-speed", "analytic-params", "matrix-keep-failed"])
def test_analytic_and_matrix_errors_have_the_one_prefix_style(args, message, tmp_path):
    result = run_cli(*args, cwd=tmp_path)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), result.stderr


@pytest.mark.parametrize("module", ["cosim.analytic.cli", "cosim.matrix.cli"])
def test_cli_module_docstrings_describe_the_command_not_its_wiring(module):
    import importlib

    doc = importlib.import_module(module).__doc__
    assert "hook" not in doc.lower() and "add_parser(sub)" not in doc and "lead" not in doc.lower()


def test_list_shortens_long_parameter_values_and_keeps_them_in_json():
    from cosim.compiler.catalog import SHORT_VALUE

    text = run_cli("list")
    assert text.returncode == 0, text.stderr
    lines = text.stdout.splitlines()
    blocks, current = [], None  # the text of each "parameters:" entry with its wrapped lines
    for line in lines:
        if line.startswith("      parameters: "):
            current = [line.split(": ", 1)[1]]
            blocks.append(current)
        elif current is not None and line.startswith(" " * 8):
            current.append(line.strip())
        else:
            current = None
    values = [item.split("=", 1)[1] for block in blocks for item in " ".join(block).split(", ")]
    assert values and max(len(v) for v in values) <= SHORT_VALUE
    assert any(v.endswith("...") for v in values)  # e.g. WhippleLinear's calculated matrix entries
    assert max(len(line) for line in lines if line.startswith("      ")) < 200  # wrapped
    js = run_cli("list", "--json")
    models = json.loads(js.stdout)
    full = [p["value"] for m in models for p in m["parameters"] if isinstance(p["value"], str)]
    assert max(len(v) for v in full) > SHORT_VALUE  # the full expression, not the shortened text


def test_list_json_gives_null_not_the_string_none():
    result = run_cli("list", "--json")
    assert result.returncode == 0, result.stderr
    assert '"None"' not in result.stdout
    models = {m["name"]: m for m in json.loads(result.stdout)}
    assert [s["value"] for s in models[MODEL]["outputs"]] == [None] * len(models[MODEL]["outputs"])


def test_shorten_cuts_to_the_limit_with_an_ellipsis():
    from cosim.compiler.catalog import shorten

    assert shorten("x" * 40) == "x" * 40
    assert shorten("y" * 41) == "y" * 37 + "..." and len(shorten("y" * 41)) == 40
    assert shorten(12.5) == "12.5" and shorten(None) == "?"
