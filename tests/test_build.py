"""Incremental and parallel builds, content-derived GUIDs, the build manifest."""
from __future__ import annotations

import json
import shutil
import zipfile

import pytest

from conftest import ROOT
from cosim.compiler.fmu import MANIFEST
from cosim.compiler.library import Library

MODEL = "Bicycle.Bicycles.SelfStabilizing"


@pytest.fixture()
def library(tmp_path):
    copy = tmp_path / "lib"
    shutil.copytree(ROOT / "modelica", copy)
    return copy


def _build(library, out, models=(MODEL,), jobs=1):
    # A fresh Library each time: the cached one of the process would not see edited files.
    from cosim.compiler import build as build_module
    from cosim.compiler import library as library_module

    library_module.load_library.cache_clear()
    return build_module.build(list(models), out, jobs=jobs, library_path=str(library))


def _guid(fmu):
    with zipfile.ZipFile(fmu) as archive:
        return json.loads(archive.read(MANIFEST))["guid"]


def test_noop_rebuild_and_rebuild_on_change(library, tmp_path):
    out = tmp_path / "out"
    first = _build(library, out)[0]
    assert first.rebuilt
    first_guid = _guid(first.fmu)
    stamp = first.fmu.stat().st_mtime_ns
    again = _build(library, out)[0]
    assert not again.rebuilt and again.fmu.stat().st_mtime_ns == stamp
    # A documentation-only edit of another class does not change the flat model.
    units = library / "Bicycle" / "Units.mo"
    units.write_text(units.read_text().replace("exactly as in", "just as in"))
    assert not _build(library, out)[0].rebuilt
    # A value of the data set the model's parameter defaults come from does.
    data = library / "Bicycle" / "Records" / "Astrom2005SecondOrder.mo"
    text = data.read_text()
    assert '"m/s") = 5.0 "Forward speed V' in text
    data.write_text(text.replace('"m/s") = 5.0 "Forward speed V', '"m/s") = 7.0 "Forward speed V', 1))
    changed = _build(library, out)[0]
    assert changed.rebuilt
    assert _guid(changed.fmu) != first_guid


def test_same_source_same_guid(library, tmp_path):
    a = _build(library, tmp_path / "a")[0]
    b = _build(library, tmp_path / "b")[0]
    assert _guid(a.fmu) == _guid(b.fmu)


def test_parallel_build_equals_serial(library, tmp_path):
    # Four small models keep the test short; the session fixture builds every model in parallel anyway.
    models = [e.name for e in Library(library).models(exported_only=True) if "Whipple" not in e.name][:4]
    serial = _build(library, tmp_path / "serial", models, jobs=1)
    parallel = _build(library, tmp_path / "parallel", models, jobs=2)
    assert [r.model for r in serial] == [r.model for r in parallel] == models
    for s, p in zip(serial, parallel):
        assert _guid(s.fmu) == _guid(p.fmu)


def test_manifest_and_sources(fmus):
    with zipfile.ZipFile(fmus[MODEL]) as archive:
        names = set(archive.namelist())
        manifest = json.loads(archive.read(MANIFEST))
    assert {"modelDescription.xml", "sources/model.c", "sources/fmi2_runtime.c", "sources/model_functions.c",
            "sources/cosim_model.h", "sources/fmi2Functions.h"} <= names
    assert any(n.startswith("binaries/") and n.endswith(".so") for n in names)
    import casadi
    import pymoca

    # the manifest records the tools that built the FMU (whatever their versions are)
    assert manifest["model"] == MODEL
    assert (manifest["tools"]["casadi"], manifest["tools"]["pymoca"]) == (casadi.__version__, pymoca.__version__)
    assert set(manifest["sources"]) == {n.split("/", 1)[1] for n in names if n.startswith("sources/")}
