"""The shared FMI 2.0 C runtime's own test harness (hand-written test model, sanitizers, exports)."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from conftest import ROOT


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_runtime_harness():
    result = subprocess.run(["sh", str(ROOT / "cosim/runtime/tests/run.sh")], capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-4000:]
    assert "all runtime tests passed" in result.stdout
