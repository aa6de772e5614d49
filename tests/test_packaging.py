"""A normal (non-editable) install is complete: the wheel carries the Modelica library, and the
installed tool finds its models and builds into the working directory, never into site-packages."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import ROOT

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

SOURCES = ["cosim", "modelica", "setup.py", "pyproject.toml", "README.md"]


def _library_files() -> set[str]:
    return {str(p.relative_to(ROOT / "modelica")) for p in (ROOT / "modelica").rglob("*")
            if p.is_file() and (p.suffix == ".mo" or p.name == "package.order"
                                or (p.suffix == ".svg" and p.parent.name == "Images"))}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The project's wheel, built from a copy of the sources (so nothing is written into the
    checkout) without build isolation (no network: setuptools and wheel come with the test extra)."""
    pytest.importorskip("wheel")
    tmp = tmp_path_factory.mktemp("wheel")
    source = tmp / "src"
    source.mkdir()
    for name in SOURCES:
        path = ROOT / name
        if path.is_dir():
            shutil.copytree(path, source / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            shutil.copy2(path, source / name)
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                             "--no-index", "-q", "-w", str(tmp / "dist"), str(source)],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    (found,) = (tmp / "dist").glob("*.whl")
    return found


def test_wheel_contains_every_modelica_file(wheel):
    with zipfile.ZipFile(wheel) as archive:
        shipped = {n.removeprefix("cosim/modelica/") for n in archive.namelist() if n.startswith("cosim/modelica/")}
    assert _library_files(), "no Modelica files found in the checkout"
    assert shipped == _library_files()


def test_wheel_contains_every_c_source_the_package_compiles(wheel):
    """The C the package compiles at run time (the FMU runtime, the master's stepping loop, the
    matrix pencil, the WebAssembly support): a file missing from the wheel would make a normal
    install fall back or fail where the checkout works."""
    sources = {str(p.relative_to(ROOT)) for p in (ROOT / "cosim").rglob("*") if p.suffix in (".c", ".h")
               and "tests" not in p.relative_to(ROOT).parts}
    with zipfile.ZipFile(wheel) as archive:
        shipped = set(archive.namelist())
    assert {"cosim/matrix/pencil.c", "cosim/cosimulation/fastloop.c"} <= sources
    assert sources <= shipped, sorted(sources - shipped)


def test_wheel_contains_the_apps_shipped_modules(wheel):
    """The WebAssembly modules and diagrams `cosim app` uses without a compiler
    (cosim/app/modules/, :mod:`cosim.app.shipped`): every one of them, byte for byte."""
    shipped = {p.name: p.read_bytes() for p in (ROOT / "cosim" / "app" / "modules").iterdir()}
    assert {"manifest.json", "diagrams.json", "Bicycle_Bicycles_Whipple.wasm"} <= set(shipped)
    with zipfile.ZipFile(wheel) as archive:
        packed = {n.removeprefix("cosim/app/modules/"): archive.read(n) for n in archive.namelist()
                  if n.startswith("cosim/app/modules/")}
    assert packed == shipped


def test_installed_wheel_finds_its_models_and_builds_into_the_working_directory(wheel, tmp_path):
    """Install the wheel's package alone (dependencies come from this interpreter) and use it
    from an unrelated folder: `cosim list` and `cosim build` work, the FMU lands in ./fmus."""
    target = tmp_path / "site"
    result = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "--no-index", "-q",
                             "--target", str(target), str(wheel)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    work = tmp_path / "elsewhere"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("COSIM_FMU_DIR", "COSIM_MODELICA_PATH")}
    env["PYTHONPATH"] = str(target)

    def cosim(*args):
        return subprocess.run([sys.executable, "-m", "cosim", *args], capture_output=True, text=True, cwd=work,
                              env=env, timeout=600)

    probe = cosim("--version")
    assert probe.returncode == 0, probe.stderr
    where = subprocess.run([sys.executable, "-c", "import cosim; print(cosim.__file__)"], capture_output=True,
                           text=True, cwd=work, env=env)
    assert Path(where.stdout.strip()).is_relative_to(target), where.stdout + where.stderr
    listed = cosim("list", "--exported")
    assert listed.returncode == 0, listed.stderr
    assert "Bicycle.Bicycles.SelfStabilizing" in listed.stdout
    built = cosim("build", "Bicycle.Bicycles.SelfStabilizing")
    assert built.returncode == 0, built.stderr
    assert (work / "fmus" / "Bicycle_Bicycles_SelfStabilizing.fmu").is_file()
    assert not list(target.rglob("*.fmu")), "an FMU was built into the installed package"
    # The app from the modules the wheel ships: no FMU built, no Zig cache made (nothing compiled).
    cache = tmp_path / "cache"
    env.update(XDG_CACHE_HOME=str(cache), COSIM_FMU_DIR=str(tmp_path / "app-fmus"))
    exported = cosim("app", "--export", "site")
    assert exported.returncode == 0, exported.stderr
    assert (work / "site" / "bundle.js").is_file()
    assert not (tmp_path / "app-fmus").exists() and not (cache / "cosim" / "zig").exists()
