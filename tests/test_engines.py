"""The independent FMI engines the tests use load from what `pip install -e '.[test]'` brings.

The other tests skip (naming what is missing) when an engine cannot be loaded; these fail, so a
missing install step cannot hide behind skips."""
from __future__ import annotations

import importlib.metadata
import subprocess
import sys

import pytest

from cosim.fmu import engines


def _installed(distribution: str) -> bool:
    try:
        importlib.metadata.distribution(distribution)
        return True
    except importlib.metadata.PackageNotFoundError:
        return False


@pytest.mark.skipif(not _installed("tbb"), reason="the test extra (pip tbb) is not installed")
@pytest.mark.needs_ecos
def test_ecos_loads_with_the_tbb_wheel_alone():
    """Ecos needs libtbb.so.12; the pip tbb wheel's copy is found although the loader does not
    search <prefix>/lib. Run in a fresh interpreter so no earlier import hides the problem."""
    code = "from cosim.fmu import engines; engines.ecospy(); print('ok')"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stdout.strip() == "ok", result.stderr


@pytest.mark.needs_libcosim
def test_libcosim_loads():
    assert engines.libcosimpy().__name__ == "libcosimpy"


def test_missing_engine_names_what_to_install(monkeypatch):
    """Without TBB the message names both ways to get it (pip tbb, apt libtbb12)."""
    import builtins

    real_import = builtins.__import__

    def no_tbb(name, *args, **kwargs):
        if name == "ecospy":
            raise OSError("libtbb.so.12: cannot open shared object file: No such file or directory")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(engines, "_preload_tbb", lambda: None)
    monkeypatch.setattr(builtins, "__import__", no_tbb)
    with pytest.raises(engines.EngineUnavailable, match=r"libtbb\.so\.12.*pip install tbb.*libtbb12"):
        engines.ecospy()
