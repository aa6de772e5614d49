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
# never into the project's fmus/; set before cosim is imported. A developer may name a folder that
# is kept between runs (COSIM_TEST_FMU_DIR): builds are incremental, so reusing it is safe.
if os.environ.get("COSIM_TEST_FMU_DIR"):
    os.environ["COSIM_FMU_DIR"] = os.environ["COSIM_TEST_FMU_DIR"]
else:
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


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    """A test that needs an independent FMI engine which cannot be loaded here is skipped with
    the reason (e.g. Ecos without libtbb.so.12), not failed: one clear line in the summary.
    tests/test_engines.py fails instead when the test extra is installed and an engine still
    does not load."""
    from cosim.engines import EngineUnavailable

    try:
        return (yield)
    except EngineUnavailable as exc:
        pytest.skip(str(exc))
