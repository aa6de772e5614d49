"""The command line as a user runs it."""
from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import ROOT, run_cli

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
    assert png.stat().st_size > 10_000


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
    assert (tmp_path / "fig5.png").stat().st_size > 10_000


def test_unknown_figure(tmp_path):
    result = run_cli("figures", "fig99", "-o", str(tmp_path))
    assert result.returncode != 0 and "unknown figure(s) fig99" in result.stderr


def test_run_and_export_ssp(tmp_path):
    from cosim.engines import run_ssp_libcosim

    system = ROOT / "cosim" / "systems" / "rider-p-control.toml"
    npy, ssp = tmp_path / "r.npy", tmp_path / "r.ssp"
    result = run_cli("run", str(system), "-o", str(npy))
    assert result.returncode == 0, result.stderr
    data = np.load(npy)
    assert {"time", "bike.phi", "rider.T"} <= set(data.dtype.names)
    result = run_cli("export-ssp", str(system), "-o", str(ssp))
    assert result.returncode == 0, result.stderr
    assert "twin: rider: Python Proportional -> Bicycle.Control.Proportional" in result.stdout
    assert run_ssp_libcosim(ssp, ["bike.phi"])["bike.phi"].size == 2000


def test_run_reports_fall(tmp_path):
    result = run_cli("run", str(ROOT / "cosim" / "systems" / "rear-steered-p.toml"), "-o", str(tmp_path / "r.csv"))
    assert result.returncode == 3 and "fell at t = " in result.stdout
