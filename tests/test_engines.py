"""The independent FMI engines the tests use load from what `pip install -e '.[test]'` brings.

The other tests skip (naming what is missing) when an engine cannot be loaded; these fail, so a
missing install step cannot hide behind skips."""
from __future__ import annotations

import importlib.metadata
import subprocess
import sys

import pytest

from cosim.cosimulation import engines

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow


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
    code = "from cosim.cosimulation import engines; engines.ecospy(); print('ok')"
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


@pytest.mark.needs_ecos
def test_ecos_runs_our_fmi3_fmu_like_its_fmi2_build():
    """Ecos runs an FMI 3.0 Co-Simulation FMU of ours (engines.run_ecos) to the result of the FMI 2.0
    build of the same model, to 1e-12 (the same C core: round-off only)."""
    import os

    import numpy as np

    from cosim.compiler.build import build_model
    from cosim.compiler.library import load_library

    results = {}
    for version in ("2", "3"):
        fmu = build_model("Bicycle.Bicycles.WhippleLinear", os.environ["COSIM_FMU_DIR"], load_library(),
                          fmi_version=version).fmu
        results[version] = engines.run_ecos(fmu, 2.0, 0.01, {"v": 4.0, "phi0": 0.1}, ["phi", "delta"])
    assert len(results["3"]) == 200 and np.max(np.abs(results["3"]["phi"])) > 0.05
    for name in ("time", "phi", "delta"):
        assert np.max(np.abs(results["2"][name] - results["3"][name])) <= 1e-12


def test_fmi3_components_of_an_ssp(tmp_path):
    """engines.fmi3_components reads the FMI version of every component's FMU inside an SSP
    without extracting it: only the FMI 3 ones, by component name, with their archive paths."""
    import io
    import zipfile

    def fmu(version: str) -> bytes:
        data = io.BytesIO()
        with zipfile.ZipFile(data, "w") as archive:
            archive.writestr("modelDescription.xml", f'<fmiModelDescription fmiVersion="{version}"/>')
        return data.getvalue()

    ssd = ('<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
           'version="1.0" name="s"><ssd:System name="s"><ssd:Elements>'
           + "".join(f'<ssd:Component name="{n}" source="resources/{n}.fmu"/>' for n in ("a", "b", "c", "missing"))
           + "</ssd:Elements></ssd:System></ssd:SystemStructureDescription>")
    ssp = tmp_path / "s.ssp"
    with zipfile.ZipFile(ssp, "w") as archive:
        archive.writestr("SystemStructure.ssd", ssd)
        for name, version in (("a", "2.0"), ("b", "3.0"), ("c", "3.0")):
            archive.writestr(f"resources/{name}.fmu", fmu(version))
    assert engines.fmi3_components(ssp) == {"b": "resources/b.fmu", "c": "resources/c.fmu"}
