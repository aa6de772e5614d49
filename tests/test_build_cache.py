"""The cache of the compiled runtime (``$XDG_CACHE_HOME/cosim/runtime/<key>/<stem>.o.entry``, one
entry per runtime source: the core ``cosim_runtime.c``, the tape interpreter ``cosim_tape.c`` and
the API ``fmi2_api.c`` of an FMI 2 FMU):
reused by the next build, rebuilt when the compiler changes, a corrupt entry ignored (and
replaced), concurrent builds safe; an FMU built from the cached objects is the same, byte for
byte, as one built without the cache."""
from __future__ import annotations

import hashlib
import os
import shutil
import stat
import zipfile
from pathlib import Path

import pytest

from cosim.compiler import fmu as fmu_module
from cosim.compiler.build import build, build_model, runtime_cache
from cosim.compiler.library import load_library

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

SMALL = ("Bicycle.Control.PD", "Bicycle.Control.Proportional")
FMI2_RUNTIME = ("cosim_runtime.c", "cosim_tape.c", "fmi2_api.c")  # the runtime sources of an FMI 2 FMU


@pytest.fixture(scope="module")
def library():
    return load_library()


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    """Each test starts without a compiled runtime (the session's cache may have one)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg-cache"))


@pytest.fixture
def compiles(monkeypatch):
    """The source files gcc compiled (``-c``) during the test, in order."""
    seen: list[str] = []
    run = fmu_module._run_compiler

    def spy(commands, *args, **kwargs):
        seen.extend(c[c.index("-c") + 1] for c in commands if "-c" in c)
        return run(commands, *args, **kwargs)

    monkeypatch.setattr(fmu_module, "_run_compiler", spy)
    return seen


def _entries(source: str = "*") -> list[Path]:
    """The cache entries (of the runtime source ``source``, default: of all)."""
    stem = "*" if source == "*" else Path(source).stem
    return sorted(runtime_cache().glob(f"*/{stem}.o.entry"))


def _runtime(compiles: list[str]) -> list[str]:
    """The runtime sources among the compiled files, sorted."""
    return sorted(c for c in compiles if c in fmu_module.RUNTIME_SOURCES)


def _binary(fmu: Path) -> bytes:
    with zipfile.ZipFile(fmu) as archive:
        [name] = [n for n in archive.namelist() if n.startswith("binaries/") and n.endswith(".so")]
        return archive.read(name)


def _valid(entry: Path) -> bool:
    magic, digest, obj = entry.read_bytes().split(b"\n", 2)
    return magic.startswith(b"cosim-runtime-object") and hashlib.sha256(obj).hexdigest().encode() == digest


def test_runtime_compiled_once_and_reused(library, tmp_path, compiles):
    build_model(SMALL[0], tmp_path, library)
    assert _runtime(compiles) == list(FMI2_RUNTIME)
    entries = _entries()
    assert sorted(e.name for e in entries) == ["cosim_runtime.o.entry", "cosim_tape.o.entry", "fmi2_api.o.entry"]
    assert all(map(_valid, entries))
    before = [e.stat().st_mtime_ns for e in entries]
    compiles.clear()
    build_model(SMALL[1], tmp_path, library)
    build_model(SMALL[0], tmp_path, library, force=True)
    assert not _runtime(compiles), "a cached runtime object was compiled again"
    # a small model's C files are compiled as one translation unit (fmu.UNITY_FILE), not shipped
    assert compiles == [fmu_module.UNITY_FILE] * 2, "the model-specific C must still be compiled"
    assert _entries() == entries and [e.stat().st_mtime_ns for e in entries] == before
    with zipfile.ZipFile(tmp_path / "Bicycle_Control_PD.fmu") as archive:
        for name in FMI2_RUNTIME:
            assert f"sources/{name}" in archive.namelist(), "the FMU must still ship the runtime sources"
        assert "sources/model.c" in archive.namelist()
        assert not any(fmu_module.UNITY_FILE in name for name in archive.namelist())


def test_fmu_from_cached_object_is_byte_identical(library, tmp_path):
    """The same FMU with the runtime compiled in the build and taken from the cache."""
    fresh, cached = tmp_path / "fresh", tmp_path / "cached"
    build_model(SMALL[1], cached, library)  # fills the cache of ``cached``
    a = build_model(SMALL[0], fresh, library).fmu
    b = build_model(SMALL[0], cached, library).fmu
    assert _binary(a) == _binary(b)
    assert a.read_bytes() == b.read_bytes()


def test_new_compiler_gets_its_own_object(library, tmp_path, compiles, monkeypatch):
    """Another compiler (here a wrapper of gcc at another path) does not use the object of the
    first: a second cache entry is compiled; the first is kept."""
    build_model(SMALL[0], tmp_path / "out", library)
    first = _entries()
    wrapper = tmp_path / "bin" / "cc-wrapper"
    wrapper.parent.mkdir()
    wrapper.write_text(f'#!/bin/sh\nexec {shutil.which("gcc")} "$@"\n')
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("CC", str(wrapper))
    compiles.clear()
    build_model(SMALL[0], tmp_path / "out", library, force=True)
    assert _runtime(compiles) == list(FMI2_RUNTIME)
    entries = _entries()
    assert len(entries) == 2 * len(FMI2_RUNTIME) and set(first) < set(entries) and all(_valid(e) for e in entries)


@pytest.mark.parametrize("damage", ["truncated", "flipped-byte", "empty", "foreign"])
def test_corrupt_entry_is_ignored_and_replaced(library, tmp_path, compiles, damage):
    good = build_model(SMALL[0], tmp_path, library).fmu.read_bytes()
    [entry] = _entries("cosim_runtime.c")
    data = entry.read_bytes()
    broken = {"truncated": data[: len(data) // 2], "empty": b"", "foreign": b"\x7fELF" + data[4:],
              "flipped-byte": data[:-100] + bytes([data[-100] ^ 0xFF]) + data[-99:]}[damage]
    entry.write_bytes(broken)
    compiles.clear()
    result = build_model(SMALL[0], tmp_path, library, force=True)
    assert _runtime(compiles) == ["cosim_runtime.c"], "a damaged entry must not be used (the intact one is)"
    assert result.fmu.read_bytes() == good
    assert _valid(entry) and entry.read_bytes() == data, "the entry is replaced by a good one"


def test_unwritable_cache_only_costs_time(library, tmp_path, compiles):
    """A cache folder that cannot be written (here a file in its way) is skipped."""
    runtime_cache().parent.mkdir(parents=True)
    runtime_cache().write_text("not a folder")
    result = build_model(SMALL[0], tmp_path, library)
    assert result.rebuilt and _runtime(compiles) == list(FMI2_RUNTIME)
    assert runtime_cache().read_text() == "not a folder"


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two CPUs for builds at the same time")
def test_concurrent_builds_share_one_complete_entry(tmp_path):
    """Parallel builds into a fresh folder all miss the cache at once: each stores a complete
    entry (renamed into place), the last one stays, no partial file is left."""
    results = build(list(SMALL), output=tmp_path, jobs=2)
    assert all(r.rebuilt for r in results)
    entries = _entries()
    assert len(entries) == len(FMI2_RUNTIME) and all(map(_valid, entries))
    for entry in entries:
        assert [p.name for p in entry.parent.iterdir()] == [entry.name], "partial cache file left behind"
    again = build(list(SMALL), output=tmp_path, jobs=2, force=True)
    assert [_binary(r.fmu) for r in again] == [_binary(r.fmu) for r in results]


def test_fmi3_runtime_objects_cached_beside_fmi2(library, tmp_path, compiles):
    """An FMI 3 FMU has the core, the tape interpreter and the FMI 3 API: all compiled by the
    first FMI 3 build (an object's key has the FMI headers beside it, so FMI 2's are not taken),
    then reused; the FMI 2 entries stay as they were."""
    build_model(SMALL[0], tmp_path, library)
    fmi2_entries = {e: e.stat().st_mtime_ns for e in _entries()}
    compiles.clear()
    build_model(SMALL[0], tmp_path, library, fmi_version="3")
    assert _runtime(compiles) == ["cosim_runtime.c", "cosim_tape.c", "fmi3_api.c"]
    compiles.clear()
    build_model(SMALL[1], tmp_path, library, fmi_version="3")
    assert not _runtime(compiles) and compiles == [fmu_module.UNITY_FILE]
    entries = _entries()
    assert len(entries) == 6 and sorted(e.name for e in entries if e not in fmi2_entries) == [
        "cosim_runtime.o.entry", "cosim_tape.o.entry", "fmi3_api.o.entry"]
    assert all(e.stat().st_mtime_ns == stamp for e, stamp in fmi2_entries.items())
