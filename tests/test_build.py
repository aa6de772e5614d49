"""Incremental and parallel builds, content-derived GUIDs, the build manifest."""
from __future__ import annotations

import json
import shutil
import zipfile

import pytest

from conftest import ROOT
from cosim.compiler.fmu import MANIFEST
from cosim.compiler.library import Library

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

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
    assert {"modelDescription.xml", "sources/model.c", "sources/cosim_runtime.c", "sources/fmi2_api.c",
            "sources/model_functions.c", "sources/cosim_model.h", "sources/cosim_runtime.h",
            "sources/fmi2Functions.h"} <= names
    assert not any("fmi3" in n or n == "sources/model_vjp.c" for n in names), "FMI 2: no FMI 3 API, no adjoint code"
    assert any(n.startswith("binaries/") and n.endswith(".so") for n in names)
    import casadi
    import pymoca

    # the manifest records the tools that built the FMU (whatever their versions are)
    assert manifest["model"] == MODEL
    assert (manifest["tools"]["casadi"], manifest["tools"]["pymoca"]) == (casadi.__version__, pymoca.__version__)
    assert set(manifest["sources"]) == {n.split("/", 1)[1] for n in names if n.startswith("sources/")}


SMALL = "Bicycle.Control.PD"


def test_fmi_versions_do_not_invalidate_each_other(tmp_path):
    """FMI 2 (OUTPUT/NAME.fmu) and FMI 3 (OUTPUT/fmi3/NAME.fmu) of one model, built together from
    one compilation (one result each, the same GUID); a no-op build of both touches neither; a
    forced FMI 3 build leaves the FMI 2 FMU as it was, and an FMI 2 build finds it up to date."""
    from cosim.compiler.build import build, build_model, fmu_path

    out = tmp_path / "out"
    both = build([SMALL], out, fmi_versions=("3", "2", "3"))
    assert [(r.fmi_version, r.rebuilt) for r in both] == [("2", True), ("3", True)]
    assert [r.fmu for r in both] == [out / "Bicycle_Control_PD.fmu", out / "fmi3" / "Bicycle_Control_PD.fmu"]
    assert [r.fmu for r in both] == [fmu_path(SMALL, out), fmu_path(SMALL, out, "3")]
    assert _guid(both[0].fmu) == _guid(both[1].fmu)
    for result in both:
        with zipfile.ZipFile(result.fmu) as archive:
            assert json.loads(archive.read(MANIFEST))["fmi_version"] == result.fmi_version
            version = archive.read("modelDescription.xml").split(b'fmiVersion="', 1)[1][:3]
            assert version == f"{result.fmi_version}.0".encode()
    stamps = [r.fmu.stat().st_mtime_ns for r in both]
    again = build([SMALL], out, fmi_versions=("2", "3"))
    assert [r.rebuilt for r in again] == [False, False]
    assert [r.fmu.stat().st_mtime_ns for r in again] == stamps
    forced = build_model(SMALL, out, fmi_version="3", force=True)
    assert forced.rebuilt and forced.fmi_version == "3" and forced.fmu.stat().st_mtime_ns != stamps[1]
    fmi2 = build_model(SMALL, out)
    assert not fmi2.rebuilt and fmi2.fmu.stat().st_mtime_ns == stamps[0]


def test_fmi_version_in_the_up_to_date_check(tmp_path):
    """An FMU of the other FMI version under a model's name is not taken for up to date (the
    quick check of commands that build on demand, and the build itself rebuilds it)."""
    from cosim.compiler.build import build_model, fmu_path
    from cosim.compiler.library import fmu_up_to_date

    out = tmp_path / "out"
    fmi3 = build_model(SMALL, out, fmi_version="3").fmu
    assert fmu_up_to_date(SMALL, fmi3, fmi_version="3") and not fmu_up_to_date(SMALL, fmi3)
    fmi2 = fmu_path(SMALL, out)
    shutil.copyfile(fmi3, fmi2)  # an FMI 3 FMU where the FMI 2 one belongs
    result = build_model(SMALL, out)
    assert result.rebuilt and fmu_up_to_date(SMALL, fmi2)


@pytest.mark.parametrize("versions", [("4",), (), ("2", "x")], ids=["four", "none", "two-and-garbage"])
def test_bad_fmi_version_refused_before_any_work(tmp_path, versions):
    from cosim.compiler.build import build
    from cosim.errors import ParameterError

    with pytest.raises(ParameterError, match="FMI version"):
        build([SMALL], tmp_path / "out", fmi_versions=versions)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("*.fmu"))


@pytest.mark.parametrize("argv", [["--fmi-version", "3", SMALL], [SMALL, "--fmi-version", "3"],
                                  ["--fmi-version", "2", "--fmi-version", "3", SMALL], ["--fmi-version", "2", "3", SMALL]],
                         ids=["version-then-model", "model-then-version", "repeated", "listed"])
def test_cli_fmi_version_forms(argv):
    """The forms of --fmi-version: a model name right after the option is a model, not a version."""
    from cosim.cli import parser

    args = parser().parse_args(["build", *argv])
    assert (args.models or []) + getattr(args, "models_after_versions", []) == [SMALL]
    assert args.fmi_version == ([v for v in argv if v in ("2", "3")])


def _variables(spec):
    """Variables in position order from (name, role, initial, derivative_of) tuples."""
    from cosim.compiler.description import Variable

    return [Variable(name=name, position=i, role=role, causality="local", variability="continuous", initial=initial,
                     start=0.0 if initial == "exact" else None, derivative_of=derivative_of)
            for i, (name, role, initial, derivative_of) in enumerate(spec)]


@pytest.mark.parametrize("spec, expected", [
    ([("x[1]", "state", "exact", None), ("x[2]", "state", "exact", None),
      ("der(x[1])", "derivative", "calculated", 0), ("der(x[2])", "derivative", "calculated", 1)],
     {0: ("x", 2), 2: ("der(x)", 2)}),
    # x[1] computed, x[2] exact: not one declaration's uniform elements, both stay scalars (their derivatives too)
    ([("x[1]", "state", "calculated", None), ("x[2]", "state", "exact", None),
      ("der(x[1])", "derivative", "calculated", 0), ("der(x[2])", "derivative", "calculated", 1)], {}),
    # the derivatives in another order than the states: no array
    ([("x[1]", "state", "exact", None), ("x[2]", "state", "exact", None),
      ("der(x[1])", "derivative", "calculated", 1), ("der(x[2])", "derivative", "calculated", 0)], {}),
    # not consecutive (another variable between the elements)
    ([("x[1]", "state", "exact", None), ("y", "state", "exact", None), ("x[2]", "state", "exact", None),
      ("der(x[1])", "derivative", "calculated", 0), ("der(y)", "derivative", "calculated", 1),
      ("der(x[2])", "derivative", "calculated", 2)], {}),
    # local arrays stay scalars (FMI3_ARRAY_ROLES), as does a one-element array
    ([("r[1]", "algebraic", "calculated", None), ("r[2]", "algebraic", "calculated", None),
      ("s[1]", "state", "exact", None), ("der(s[1])", "derivative", "calculated", 2)], {}),
], ids=["pade-like", "mixed-initial", "derivatives-permuted", "interleaved", "locals-and-single"])
def test_fmi3_arrays_group_only_uniform_consecutive_state_arrays(spec, expected):
    from cosim.compiler.description import fmi3_arrays

    assert fmi3_arrays(_variables(spec)) == expected


def test_pack_deflates_every_file_at_the_fast_level(tmp_path):
    """pack() writes each file deflated at PACK_LEVEL (zipfile ignores the archive's level for an
    entry given as a ZipInfo; the level is given per entry) with fixed dates and modes."""
    import zipfile
    import zlib

    from cosim.compiler.fmu import PACK_LEVEL, pack

    staging = tmp_path / "staging"
    (staging / "sources").mkdir(parents=True)
    text = "".join(f"a{k} = b{k} * {k}.0 + sin(c{k});\n" for k in range(3000)).encode()
    (staging / "sources" / "model.c").write_bytes(text)
    (staging / "modelDescription.xml").write_bytes(b"<fmiModelDescription/>\n" * 50)
    pack(staging, tmp_path / "x.fmu")
    with zipfile.ZipFile(tmp_path / "x.fmu") as archive:
        infos = {i.filename: i for i in archive.infolist()}
        assert set(infos) == {"sources/model.c", "modelDescription.xml"}
        for name, info in infos.items():
            data = (staging / name).read_bytes()
            deflate = zlib.compressobj(PACK_LEVEL, zlib.DEFLATED, -15)
            assert info.compress_type == zipfile.ZIP_DEFLATED
            assert info.compress_size == len(deflate.compress(data) + deflate.flush()), name
            assert info.date_time == (2000, 1, 1, 0, 0, 0) and info.external_attr == 0o644 << 16
            assert archive.read(name) == data
