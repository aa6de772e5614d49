"""No dead code in the package: vulture finds no unused name in ``cosim/``.

The tests and the benchmarks count as users of the package (a function the tests call is used);
names used only from outside Python's name lookup (FMI callbacks through ctypes, C structures,
pymoca source text, sympy's printer dispatch, Python blocks found by class name) are listed in
``tests/data/vulture-allowlist.py``, each with its reason.
"""
from __future__ import annotations

import re

import vulture

from conftest import ROOT

ALLOWLIST = ROOT / "tests" / "data" / "vulture-allowlist.py"
#: Every confidence vulture reports (60 % for attributes, functions and classes; 90 % and 100 % for
#: imports, unreachable code and unused parameters).
MIN_CONFIDENCE = 60


def test_no_unused_code_in_the_package():
    finder = vulture.Vulture()
    finder.scavenge([str(ROOT / "cosim"), str(ROOT / "tests"), str(ROOT / "benchmarks"), str(ALLOWLIST)])
    package = ROOT / "cosim"
    unused = [item.get_report() for item in finder.get_unused_code(min_confidence=MIN_CONFIDENCE)
              if package in item.filename.resolve().parents]
    assert unused == [], "unused code (remove it, or list it with its reason in " \
                         f"{ALLOWLIST.relative_to(ROOT)}):\n" + "\n".join(unused)


def test_every_allowed_name_is_in_the_package():
    """An entry whose name left the package is removed from the allow-list too."""
    source = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "cosim").rglob("*.py"))
    entries = [line.split("#", 1) for line in ALLOWLIST.read_text(encoding="utf-8").splitlines()
               if line.strip() and not line.startswith("#")]
    assert entries
    for name, reason in entries:
        name = name.strip().removeprefix("_.")
        assert re.search(rf"\b{re.escape(name)}\b", source), f"{name} is not in cosim/ any more"
        assert reason.strip(), f"{name}: no reason given"
