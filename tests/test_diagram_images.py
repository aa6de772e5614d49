"""The diagrams the documentation shows (``modelica/Bicycle/Resources/Images``: the UsersGuide,
the README, docs/diagrams.md) are those the library draws today (``python -m
cosim.diagram.images`` writes them), and the documentation shows the Whipple bicycle's."""
from __future__ import annotations

from pathlib import Path

import pytest

from cosim.compiler.library import DEFAULT_LIBRARY
from cosim.diagram.images import drawings, image_folder

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
DRAWN = drawings()


@pytest.mark.parametrize("name", sorted(DRAWN))
def test_committed_diagram_is_current(name):
    committed = image_folder() / name
    assert committed.is_file(), f"{committed} missing: run python -m cosim.diagram.images"
    assert committed.read_text(encoding="utf-8") == DRAWN[name], \
        f"{committed} is not what the library draws: run python -m cosim.diagram.images"


def test_no_stale_diagrams():
    assert sorted(p.name for p in image_folder().glob("*.svg")) == sorted(DRAWN)


@pytest.mark.parametrize("document, reference", [
    (DEFAULT_LIBRARY / "Bicycle" / "UsersGuide" / "Structure.mo", "modelica://Bicycle/Resources/Images/Whipple.svg"),
    (ROOT / "README.md", "modelica/Bicycle/Resources/Images/Whipple.svg"),
    (ROOT / "docs" / "diagrams.md", "../modelica/Bicycle/Resources/Images/Whipple.svg"),
], ids=["UsersGuide", "README", "docs"])
def test_documentation_shows_the_whipple_diagram(document, reference):
    assert reference in document.read_text(encoding="utf-8")


def test_docs_list_every_diagram():
    text = (ROOT / "docs" / "diagrams.md").read_text(encoding="utf-8")
    missing = [name for name in DRAWN if f"Images/{name}" not in text]
    assert not missing, f"docs/diagrams.md does not show {missing}"
