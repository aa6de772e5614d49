"""The app's shipped WebAssembly modules and diagrams (cosim/app/modules/, cosim.app.shipped):
they are what the sources make now, byte for byte; `cosim app --export` uses them while they are
current and then compiles and parses nothing (no Zig needed); an edited library or compiler, a
user's library hiding the shipped one, or a damaged shipped file makes it build as before.

Speed is not asserted here: benchmarks/app.py measures the export against the build it replaces.
"""
from __future__ import annotations

import base64
import json
import os
import shutil
import sys
from pathlib import Path

import pytest

from conftest import ROOT, bundle_data, unavailable
from cosim.app import export, ship, shipped
from cosim.app.export import MODULES, export_app
from cosim.compiler.library import tool_versions


def _forbid(monkeypatch, *targets):
    """Make each ``(object, name)`` raise if called: the export must not build or parse."""
    for owner, name in targets:
        def refuse(*args, _name=name, **kwargs):
            raise AssertionError(f"{_name} was called")
        monkeypatch.setattr(owner, name, refuse)


@pytest.mark.slow
def test_shipped_files_are_what_the_sources_make():
    """Builds the FMUs (session FMU folder) and their modules (Zig), draws the diagrams and
    compares every shipped file byte for byte (the modules, their NAME.json, the diagrams and
    the manifest with the key of the sources)."""
    import importlib.util

    if importlib.util.find_spec("ziglang") is None:
        unavailable("the ziglang wheel is not installed (pip install ziglang)")
    # NAME.json carries the FMU's build key and generation tool, which name these versions: with
    # others the files differ although the sources did not change (CI has the recorded ones)
    recorded = json.loads((shipped.SHIPPED / shipped.MANIFEST).read_text(encoding="utf-8"))["tools"]
    if tool_versions() != recorded:
        unavailable(f"the shipped files were made with {recorded}; this environment has {tool_versions()}")
    files = ship.made(Path(os.environ["COSIM_FMU_DIR"]))
    assert set(files) == {f"{shipped.module_name(m)}.{ext}" for m in MODULES for ext in ("wasm", "json")} | {
        shipped.MANIFEST, shipped.DIAGRAMS}
    changed = ship.differences(files)
    assert not changed, (f"cosim/app/modules/ is not what the sources make ({', '.join(changed)} differ): "
                         "run `python -m cosim.app.ship` and commit the files")


def test_fresh_export_compiles_and_parses_nothing(tmp_path, monkeypatch):
    """Empty FMU folder, fresh cache, no Zig: the page carries the shipped files as they are."""
    import cosim.compiler.build
    import cosim.compiler.library

    fmu_folder = tmp_path / "fmus"
    monkeypatch.setenv("COSIM_FMU_DIR", str(fmu_folder))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("COSIM_MODELICA_PATH", raising=False)
    monkeypatch.setitem(sys.modules, "ziglang", None)  # find_spec("ziglang") is None: not installed
    _forbid(monkeypatch, (cosim.compiler.build, "build"), (export, "build_wasm"), (export, "page_diagrams"),
            (cosim.compiler.library.Library, "__init__"))
    data = bundle_data(export_app(tmp_path / "site").folder)
    manifest = json.loads((shipped.SHIPPED / shipped.MANIFEST).read_text(encoding="utf-8"))
    assert list(data["modules"]) == list(MODULES)
    for model, name in manifest["modules"].items():
        assert base64.b64decode(data["modules"][model]["wasm"]) == (shipped.SHIPPED / f"{name}.wasm").read_bytes()
        assert data["modules"][model]["description"] == json.loads((shipped.SHIPPED / f"{name}.json").read_bytes())
    assert data["diagrams"] == json.loads((shipped.SHIPPED / shipped.DIAGRAMS).read_bytes())
    assert not fmu_folder.exists() and not (tmp_path / "cache").exists()


def _library_copy(tmp_path: Path) -> Path:
    folder = tmp_path / "library"
    shutil.copytree(ROOT / "modelica" / "Bicycle", folder / "Bicycle")
    return folder


def _edit_library(tmp_path: Path, monkeypatch) -> None:
    folder = _library_copy(tmp_path)
    controller = folder / "Bicycle" / "Control" / "PD.mo"
    controller.write_text(controller.read_text(encoding="utf-8") + "// edited\n", encoding="utf-8")
    monkeypatch.setenv("COSIM_MODELICA_PATH", str(folder))


def _add_user_model(tmp_path: Path, monkeypatch) -> None:
    folder = tmp_path / "mine"
    (folder / "Mine").mkdir(parents=True)
    (folder / "Mine" / "package.mo").write_text('within;\npackage Mine "a user\'s models"\nend Mine;\n',
                                                 encoding="utf-8")
    monkeypatch.setenv("COSIM_MODELICA_PATH", str(folder))


def _edit_compiler(tmp_path: Path, monkeypatch) -> None:
    package = tmp_path / "cosim"
    for pattern in shipped.MADE_BY:
        for file in shipped.PACKAGE.glob(pattern):
            target = package / file.relative_to(shipped.PACKAGE)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(file, target)
    runtime = package / "runtime" / "cosim_runtime.c"
    runtime.write_text(runtime.read_text(encoding="utf-8") + "/* edited */\n", encoding="utf-8")
    monkeypatch.setattr(shipped, "PACKAGE", package)


def _nothing(tmp_path: Path, monkeypatch) -> None:
    pass


def _copy_unchanged(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setenv("COSIM_MODELICA_PATH", str(_library_copy(tmp_path)))


CHANGES = [
    pytest.param(_nothing, True, id="installed-sources"),
    pytest.param(_copy_unchanged, True, id="unchanged-library-copy"),
    pytest.param(_edit_library, False, id="edited-library"),
    pytest.param(_add_user_model, False, id="user-library-folder"),
    pytest.param(_edit_compiler, False, id="edited-runtime"),
]


class _Built(RuntimeError):
    """Raised by the stand-in for the build: the export went the building way."""


@pytest.mark.parametrize("change, current", CHANGES)
def test_export_uses_shipped_files_only_while_current(tmp_path, monkeypatch, change, current):
    """The key is recomputed from the files (library, compiler, runtime, ...); anything else than
    the sources the files were made from sends the export to the build (stood in for here: the
    real one is `cosim build` and `cosim build --wasm`, covered by their own tests)."""
    monkeypatch.delenv("COSIM_MODELICA_PATH", raising=False)
    change(tmp_path, monkeypatch)
    assert (shipped.load(MODULES) is not None) == current

    def build_modules(fmu_folder):
        raise _Built(str(fmu_folder))

    monkeypatch.setattr(export, "build_modules", build_modules)
    monkeypatch.setattr(export, "zig_command", lambda: None)  # (the stand-in needs no Zig)
    if current:
        assert export_app(tmp_path / "site").bytes > 0
    else:
        with pytest.raises(_Built):
            export_app(tmp_path / "site")


def _flip_wasm_byte(folder: Path) -> None:
    wasm = folder / "Bicycle_Control_PD.wasm"
    data = bytearray(wasm.read_bytes())
    data[len(data) // 2] ^= 0xFF
    wasm.write_bytes(bytes(data))


def _remove_module(folder: Path) -> None:
    (folder / "Bicycle_Bicycles_Whipple.wasm").unlink()


def _other_key(folder: Path) -> None:
    manifest = json.loads((folder / shipped.MANIFEST).read_text(encoding="utf-8"))
    manifest["key"] = "0" * 64
    (folder / shipped.MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")


def _truncated_manifest(folder: Path) -> None:
    (folder / shipped.MANIFEST).write_bytes((folder / shipped.MANIFEST).read_bytes()[:40])


def _diagrams_of_other_models(folder: Path) -> None:
    diagrams = json.loads((folder / shipped.DIAGRAMS).read_text(encoding="utf-8"))
    (folder / shipped.DIAGRAMS).write_text(json.dumps(dict(list(diagrams.items())[:1])), encoding="utf-8")


@pytest.mark.parametrize("damage", [
    pytest.param(_flip_wasm_byte, id="module-byte-changed"),
    pytest.param(_remove_module, id="module-missing"),
    pytest.param(_other_key, id="key-of-other-sources"),
    pytest.param(_truncated_manifest, id="manifest-truncated"),
    pytest.param(_diagrams_of_other_models, id="diagrams-of-other-models"),
])
def test_damaged_shipped_files_are_not_used(tmp_path, monkeypatch, damage):
    monkeypatch.delenv("COSIM_MODELICA_PATH", raising=False)
    folder = tmp_path / "modules"
    shutil.copytree(shipped.SHIPPED, folder)
    assert shipped.load(MODULES, folder) is not None
    damage(folder)
    assert shipped.load(MODULES, folder) is None
