"""The recipe of Bicycle.UsersGuide.Variants works as printed: its package file, saved into a folder
of one's own, builds and simulates with the commands printed there (``--library variants`` adds the
folder to the shipped library), and the variants do what the guide says."""
from __future__ import annotations

import html
import re
import shlex
from pathlib import Path

import pytest

from conftest import cli_in_process
from cosim.analytic.parameters import load_parameters
from cosim.compiler.build import DEFAULT_OUTPUT, build_model
from cosim.compiler.library import Library

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "modelica" / "Bicycle" / "UsersGuide" / "Variants.mo"
FOLDER = "variants"  # the folder of one's own the guide names

pytestmark = pytest.mark.slow


def _blocks() -> list[str]:
    """The text of each <pre> block of the guide, as a reader sees it."""
    text = GUIDE.read_text().replace('\\"', '"')
    return [html.unescape(b).strip() for b in re.findall(r"<pre>(.*?)</pre>", text, re.S)]


def _package() -> tuple[str, str]:
    """(package name, Modelica text of the file) of the guide's package block."""
    block = next(b for b in _blocks() if b.startswith("package "))
    return re.match(r"package (\w+)", block).group(1), block


def _commands() -> list[list[str]]:
    """The guide's ``cosim ...`` commands (inline code), split into arguments (without ``cosim``)."""
    text = GUIDE.read_text().replace('\\"', '"')
    return [shlex.split(html.unescape(c))[1:] for c in re.findall(r"<code>(cosim [^<]*)</code>", text)]


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """The guide's folder (``variants``), holding the package file the guide prints (``variants/Mine.mo``)."""
    name, text = _package()
    where = tmp_path_factory.mktemp("guide") / FOLDER
    where.mkdir()
    file = re.search(rf"<code>{FOLDER}/(\w+\.mo)</code>", GUIDE.read_text()).group(1)
    assert file == f"{name}.mo"  # the file name the guide gives is the package's (Modelica's layout)
    (where / file).write_text(text + "\n", encoding="utf-8")
    return where


@pytest.fixture(scope="module")
def built(folder):
    name, text = _package()
    library = Library(folder)  # the shipped library is searched after the folder
    models = re.findall(r"^  model (\w+)", text, re.M)
    # into the session's COSIM_FMU_DIR, where the guide's commands find them up to date
    return {m: build_model(f"{name}.{m}", DEFAULT_OUTPUT, library).fmu for m in models}


def _start(fmu, name):
    from fmpy import read_model_description

    return {v.name: v.start for v in read_model_description(str(fmu)).modelVariables}[name]


def test_guide_shows_the_two_variants():
    name, text = _package()
    assert name == "Mine"
    assert re.findall(r"^  model (\w+)", text, re.M) == ["WhippleRollerRear", "AstromBicycle"]
    assert [c[:2] for c in _commands()] == [["build", "Mine.WhippleRollerRear"], ["simulate", "Mine.WhippleRollerRear"]]


def test_commands_of_the_guide_build_and_simulate(folder, tmp_path):
    """The printed commands, run beside the folder: the variant extends the shipped
    Bicycle.Bicycles.Whipple, which is found after the user's folder."""
    for args in _commands():
        args = [str(folder) if a == FOLDER else a for a in args]
        status, out, err = cli_in_process(args, tmp_path)
        assert status == 0, (args, err)
    assert (DEFAULT_OUTPUT / "Mine_WhippleRollerRear.fmu").is_file()  # the session's COSIM_FMU_DIR
    rows = (tmp_path / "Mine_WhippleRollerRear.csv").read_text().splitlines()
    header = rows[0].split(",")
    phi = [float(r.split(",")[header.index("phi")]) for r in rows[1:]]
    assert phi[0] == pytest.approx(0.05, abs=1e-12)  # --param phi0=0.05 of the guide took effect
    assert len(phi) > 100


def test_roller_variant_runs_on_the_crowned_roller(built):
    from fmpy import simulate_fmu

    fmu = built["WhippleRollerRear"]
    assert float(_start(fmu, "rearWheel.R")) == pytest.approx(0.4, abs=0)
    result = simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.1, relative_tolerance=1e-10,
                          start_values={"phi0": 0.05},
                          output=["phi", "residual", "E"])
    assert abs(result["residual"]).max() <= 1e-10
    assert abs(result["E"] - result["E"][0]).max() <= 1e-8 * abs(result["E"][0])


def test_data_set_variant_takes_the_set_and_the_modifier(built):
    astrom = load_parameters("astrom2005")
    fmu = built["AstromBicycle"]
    assert float(_start(fmu, "c")) == 0.06
    for name in ("lam", "mB", "IBxz", "rF"):
        assert float(_start(fmu, name)) == astrom[name], name
