"""The Python example of the README (section "Python API") runs and shows what it says."""
from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import ROOT

README = ROOT / "README.md"
SECTION = "## Python API"


def python_example(text: str, heading: str = SECTION) -> str:
    """The first ```python block after ``heading`` (and before the next heading of its level)."""
    text = "\n" + text  # a heading on the first line too
    start = text.find(f"\n{heading}\n")
    assert start >= 0, f"README.md has no section '{heading}'"
    level = heading.split()[0]
    following = re.search(rf"\n{level} ", text[start + len(heading) + 2:])
    section = text[start:start + len(heading) + 2 + following.start()] if following else text[start:]
    block = re.search(r"\n```python\n(.*?)\n```\n", section, re.S)
    assert block, f"the README section '{heading}' has no ```python block"
    return block.group(1)


@pytest.fixture(scope="module")
def example(fmus, tmp_path_factory):
    """The README's example run in an empty folder; its variables (FMUs in the session's COSIM_FMU_DIR)."""
    import os

    folder = tmp_path_factory.mktemp("readme")
    code = python_example(README.read_text(encoding="utf-8"))
    namespace = {"__name__": "__main__"}
    here = os.getcwd()
    os.chdir(folder)
    try:
        exec(compile(code, f"{README}:{SECTION}", "exec"), namespace)
    finally:
        os.chdir(here)
    return folder, namespace


def test_readme_example_writes_nothing_into_the_working_directory(example):
    folder, _ = example
    assert sorted(p.name for p in folder.iterdir()) == []  # the FMUs went to COSIM_FMU_DIR


def test_readme_example_roll_angle_decays_at_5_m_s(example):
    _, ns = example
    phi = ns["result"]["phi"]
    assert phi[0] == pytest.approx(0.1, abs=1e-12)
    assert abs(phi[-1]) < 0.1 * abs(phi[0])  # self-stable at 5 m/s: the lean dies out


def test_readme_example_compare_agrees_with_the_analytic_model(example):
    _, ns = example
    assert len(ns["comparisons"]) == 3
    assert ns["worst"] < 1e-9


def test_readme_example_weave_mode_turns_stable_at_the_analytic_weave_speed(example):
    _, ns = example
    v = ns["v_weave"]
    assert v == pytest.approx(4.292, abs=5e-4)  # Meijaard et al. (2007), Table 2
    below, above = ns["weave"](v - 0.05), ns["weave"](v + 0.05)
    assert below.shape == above.shape == (2,)
    assert np.all(below.real > 1e-3) and np.all(above.real < -1e-3)


def test_readme_python_block_is_found_under_its_heading():
    text = "# t\n\n## Other\n```python\nwrong = 1\n```\n\n## Python API\n\ntext\n\n```python\nx = 1\n```\n\n## Next\n"
    assert python_example(text) == "x = 1"
    with pytest.raises(AssertionError, match="has no ```python block"):
        python_example("## Python API\n\nno code\n\n## Next\n```python\ny = 2\n```\n")
