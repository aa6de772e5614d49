"""The pymoca pin and the upstream reports of the bugs cosim's compiler works around
(docs/pymoca-upstream.md, written by docs/pymoca_upstream.py from runs of unpatched pymoca)."""
from __future__ import annotations

import re
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
REPORTS = ROOT / "docs" / "pymoca-upstream.md"
PATCHES = [ROOT / "cosim" / "compiler" / "pymoca_patches.py", ROOT / "cosim" / "compiler" / "pymoca_flattening.py"]
LINK = re.compile(r"docs/pymoca-upstream\.md#([a-z0-9-]+)")


def _anchors() -> set[str]:
    return set(re.findall(r'<a id="([a-z0-9-]+)"></a>', REPORTS.read_text(encoding="utf-8")))


@pytest.mark.parametrize("source", PATCHES, ids=[p.name for p in PATCHES])
def test_every_report_link_of_a_patch_names_a_report(source):
    links = set(LINK.findall(source.read_text(encoding="utf-8")))
    assert links, f"{source.name} links no report"
    assert sorted(links - _anchors()) == []


def test_every_report_is_linked_from_a_patch():
    linked = set().union(*(LINK.findall(p.read_text(encoding="utf-8")) for p in PATCHES))
    anchors = _anchors()
    assert len(anchors) >= 10
    assert sorted(anchors - linked) == []


def test_pymoca_is_pinned_to_the_installed_version():
    """The patches replace private pymoca functions: pyproject.toml names the one release they were
    made (and the reports run) for, and that release is the one installed."""
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    pins = re.findall(r'"pymoca([^"]*)"', pyproject)
    assert pins == [f"=={version('pymoca')}"]


def test_reports_show_what_unpatched_pymoca_prints():
    """A fresh run of every minimal model, in a process where cosim's patches are not applied,
    gives the document as committed (the versions line aside: CasADi is pinned to a range)."""
    result = subprocess.run([sys.executable, str(ROOT / "docs" / "pymoca_upstream.py"), "--stdout"],
                            capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert result.returncode == 0, result.stderr

    def without_versions(text: str) -> list[str]:
        return [line for line in text.splitlines() if not line.startswith("Versions: ")]

    assert without_versions(result.stdout) == without_versions(REPORTS.read_text(encoding="utf-8"))
