"""Shared fixtures: FMUs are built once per test session into a temporary folder."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from cosim.compiler.build import build

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def fmus(tmp_path_factory) -> dict[str, Path]:
    """Every exported model built from the project's Modelica library: name -> FMU path."""
    out = tmp_path_factory.mktemp("fmus")
    return {r.model: r.fmu for r in build(output=out, jobs=2)}


def run_cli(*args: str, cwd: Path | None = None, env: dict | None = None) -> subprocess.CompletedProcess:
    """Run `python -m cosim ...` as a user would, capturing its output."""
    environment = {**os.environ, **(env or {})}
    return subprocess.run([sys.executable, "-m", "cosim", *args], capture_output=True, text=True,
                          cwd=cwd or ROOT, env=environment, timeout=600)
