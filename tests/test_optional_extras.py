"""Optional extras: sympy (`generate`) and dask.distributed (`cluster`) serve one feature each;
without them that feature stops with one line naming the extra, and nothing else needs them."""
from __future__ import annotations

import subprocess
import sys
import tomllib

import pytest

from conftest import ROOT

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

EXTRAS = {"generate": "sympy", "cluster": "dask[distributed]", "wasm": "ziglang"}
# Modules that need sympy by design: the derivation and its printer (run by the generator only).
SYMPY_MODULES = {"cosim.nonlinear.derivation", "cosim.nonlinear.modelica"}
BLOCK = "import sys\nfor name in ('sympy', 'dask', 'distributed'):\n    sys.modules[name] = None\n"


def _project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


@pytest.mark.parametrize("extra, requirement", EXTRAS.items())
def test_single_feature_dependency_is_an_extra_brought_by_the_test_extra(extra, requirement):
    project = _project()
    core = " ".join(project["dependencies"])
    assert requirement.split("[")[0] not in core, f"{requirement} is still a core dependency"
    assert any(r.startswith(requirement) for r in project["optional-dependencies"][extra])
    test = project["optional-dependencies"]["test"]
    assert any(r.startswith("bicycle-cosim[") and extra in r for r in test), f"[test] does not bring [{extra}]"


def test_psutil_used_by_build_is_a_core_dependency():
    assert any(r.startswith("psutil") for r in _project()["dependencies"])


def test_scheduler_without_distributed_names_the_cluster_extra(monkeypatch, tmp_path, capsys):
    from cosim.cli import main

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if the extra were not installed
    status = main(["matrix", "paper", "-o", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:1"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.strip().splitlines() == [
        "cosim matrix: error: --scheduler needs dask.distributed, from the optional extra 'cluster': "
        "pip install 'bicycle-cosim[cluster]'"]
    assert not (tmp_path / "out" / "results.jsonl").exists()


def test_generator_without_sympy_names_the_generate_extra(monkeypatch, tmp_path, capsys):
    import importlib

    import cosim.nonlinear

    monkeypatch.setitem(sys.modules, "sympy", None)  # as if the extra were not installed
    for name in ("cosim.nonlinear.generate", *SYMPY_MODULES):  # imported afresh, restored afterwards
        monkeypatch.delitem(sys.modules, name, raising=False)
    monkeypatch.setattr(cosim.nonlinear, "generate", None, raising=False)
    generate = importlib.import_module("cosim.nonlinear.generate")
    monkeypatch.setitem(sys.modules, "cosim.nonlinear.generate", generate)  # removed again at teardown
    status = generate.main(["-o", str(tmp_path / "models")])
    err = capsys.readouterr().err
    assert status == 2
    assert err.strip().splitlines() == [
        "python -m cosim.nonlinear.generate: error: regenerating the nonlinear Whipple models needs sympy, "
        "from the optional extra 'generate': pip install 'bicycle-cosim[generate]'"]
    assert not (tmp_path / "models").exists()


def test_no_module_imports_an_extra_at_import_time():
    """Every module of the package (but the sympy derivation) imports with sympy, dask and
    distributed missing: the extras are imported only by the features that need them."""
    code = BLOCK + (
        "import importlib, pkgutil, cosim\n"
        f"skip = {sorted(SYMPY_MODULES)!r}\n"
        "names = [m.name for m in pkgutil.walk_packages(cosim.__path__, 'cosim.')\n"
        "         if m.name not in skip and not m.name.endswith('__main__')]\n"
        "for name in names:\n"
        "    importlib.import_module(name)\n"
        "print(len(names))\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert run.returncode == 0, run.stderr
    assert int(run.stdout) > 50


@pytest.mark.parametrize("argv", [
    ["analytic", "--params", "benchmark", "--speed", "5"],
    ["list", "--exported"],
    ["linearize", "Bicycle.Bicycles.SelfStabilizing", "--speed", "5"],
    ["simulate", "Bicycle.Bicycles.SelfStabilizing", "--stop-time", "1", "-o", "{tmp}/ss.csv"],
], ids=["analytic", "list", "linearize", "simulate"])
def test_default_commands_run_without_the_extras(argv, fmus, tmp_path):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code = BLOCK + f"from cosim.cli import main\nsys.exit(main({argv!r}))\n"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr and "error" not in run.stderr
