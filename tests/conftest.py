"""Shared fixtures: FMUs are built once per test session into a temporary folder."""
from __future__ import annotations

import atexit
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# FMUs built on demand (model names given to the CLI, figures, systems) go to a temporary folder,
# never into the project's fmus/; set before cosim is imported.
os.environ["COSIM_FMU_DIR"] = tempfile.mkdtemp(prefix="cosim-test-fmus-")
atexit.register(shutil.rmtree, os.environ["COSIM_FMU_DIR"], True)

import pytest  # noqa: E402

from cosim.compiler.build import build  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def fmus() -> dict[str, Path]:
    """Every exported model built from the project's Modelica library: name -> FMU path (into the
    temporary COSIM_FMU_DIR, where on-demand builds of the same models then find them)."""
    return {r.model: r.fmu for r in build(output=os.environ["COSIM_FMU_DIR"], jobs=2)}


def run_cli(*args: str, cwd: Path | None = None, env: dict | None = None) -> subprocess.CompletedProcess:
    """Run `python -m cosim ...` as a user would, capturing its output."""
    environment = {**os.environ, **(env or {})}
    return subprocess.run([sys.executable, "-m", "cosim", *args], capture_output=True, text=True,
                          cwd=cwd or ROOT, env=environment, timeout=600)
