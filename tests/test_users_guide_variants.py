"""The variants shown in Bicycle.UsersGuide.Variants build as written and do what the guide says."""
from __future__ import annotations

import html
import re
from pathlib import Path

import pytest

from conftest import variant_library
from cosim.analytic.parameters import load_parameters
from cosim.compiler.build import build_model

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "modelica" / "Bicycle" / "UsersGuide" / "Variants.mo"

pytestmark = pytest.mark.slow


def _examples() -> dict[str, str]:
    """Model name -> Modelica text of each <pre> block of the guide."""
    text = GUIDE.read_text().replace('\\"', '"')
    blocks = [html.unescape(b).strip() for b in re.findall(r"<pre>(.*?)</pre>", text, re.S)]
    return {re.match(r"model (\w+)", b).group(1): b for b in blocks}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    examples = _examples()
    library = variant_library(tmp_path_factory.mktemp("guide"), examples, package="GuideVariants")
    out = tmp_path_factory.mktemp("fmus")
    return {name: build_model(f"GuideVariants.{name}", out, library).fmu for name in examples}


def _start(fmu, name):
    from fmpy import read_model_description

    return {v.name: v.start for v in read_model_description(str(fmu)).modelVariables}[name]


def test_guide_shows_the_two_variants():
    assert set(_examples()) == {"WhippleRollerRear", "AstromBicycle"}


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
