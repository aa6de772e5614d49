"""The library index: `cosim list`, `cosim info MODEL` and the up-to-date check of a
built model answer without parsing the library (no pymoca, no CasADi imported), the index is
rebuilt when a ``.mo`` file changes, a damaged index is ignored, and what the index answers is
exactly what parsing answers.

Each test has its own small library (a copy in ``tmp_path``) and its own XDG_CACHE_HOME, so the
index files stay in ``tmp_path``.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import hide_shipped_library
from cosim.compiler.catalog import catalog, index_key, summarize
from cosim.compiler.library import Library, compiler_digest, fmu_up_to_date, library_digest, load_library

ROOT = Path(__file__).resolve().parents[1]

PACKAGE = 'within;\npackage Small "models for the index tests"\nend Small;\n'
DECAY = '''within Small;
model Decay "dx/dt = -k x"
  parameter Real k(unit = "1/s") = 2.5 "rate";
  input Real u "forcing";
  output Real y(unit = "m") "the state";
  Real x(start = 1, fixed = true, unit = "m") "state";
equation
  der(x) = -k*x + u;
  y = x;
  annotation(__Cosim(export = true), experiment(StopTime = 2, Interval = 0.01));
end Decay;
'''
PLAIN = '''within Small;
model Plain "not exported"
  parameter Real a = 1 "gain";
  Real x(start = 0, fixed = true) "state";
equation
  der(x) = a;
end Plain;
'''
UNBALANCED = '''within Small;
model Undeclared "uses an undeclared variable"
  Real x(start = 1, fixed = true) "state";
equation
  der(x) = -q*x;
end Undeclared;
'''
SYNTAX = "within Small;\nmodel Bad \"broken\"\n  Real x\nequation\n  der(x) = ;\nend Bad;\n"

# Runs `cosim ARGS` with every import of pymoca and CasADi failing: a command that needs the
# compiler then fails, one that is answered from the index does not notice.
BLOCKED = """\
import sys

class Blocker:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("pymoca", "casadi"):
            raise ImportError(f"{name} is blocked by the test")

sys.meta_path.insert(0, Blocker())
from cosim.cli import main
sys.exit(main(sys.argv[1:]))
"""


def small_library(tmp_path: Path, files: dict[str, str]) -> Path:
    """The package Small with ``files``; these tests index it alone (:func:`hide_shipped_library`)."""
    package = hide_shipped_library(tmp_path / "lib") / "Small"
    package.mkdir(parents=True)
    (package / "package.mo").write_text(PACKAGE, encoding="utf-8")
    (package / "package.order").write_text("".join(f"{name}\n" for name in files), encoding="utf-8")
    for name, text in files.items():
        (package / f"{name}.mo").write_text(text, encoding="utf-8")
    return tmp_path / "lib"


def cosim(tmp_path: Path, *args: str, blocked: bool = False, cache: str = "cache") -> subprocess.CompletedProcess:
    """`cosim ARGS` in a fresh process with this test's cache folder ``tmp_path/cache``."""
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / cache), "COSIM_FMU_DIR": str(tmp_path / "fmus")}
    env.pop("COSIM_MODELICA_PATH", None)
    command = [sys.executable, "-c", BLOCKED] if blocked else [sys.executable, "-m", "cosim"]
    return subprocess.run([*command, *args], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600)


@pytest.fixture
def library(tmp_path, monkeypatch) -> Path:
    """A small library (an exported model, a plain one, one that cannot be flattened, one that
    does not parse) made the default library of this process, with this test's cache folder."""
    lib = small_library(tmp_path, {"Decay": DECAY, "Plain": PLAIN, "Undeclared": UNBALANCED, "Bad": SYNTAX})
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setenv("COSIM_MODELICA_PATH", str(lib))
    load_library.cache_clear()
    yield lib
    load_library.cache_clear()


def listed(summaries) -> str:
    return json.dumps([s.to_dict() for s in summaries], sort_keys=True)


@pytest.mark.parametrize("exported_only", [False, True], ids=["all", "exported"])
def test_index_gives_what_parsing_gives(library, exported_only):
    parsed_warnings, indexed_warnings, again_warnings = [], [], []
    parsed = catalog(Library(library), exported_only=exported_only, warn=parsed_warnings.append)
    indexed = catalog(exported_only=exported_only, warn=indexed_warnings.append)  # builds the index
    file, _ = index_key()
    assert file.is_file() and file.parent == library.parent / "cache" / "cosim"
    again = catalog(exported_only=exported_only, warn=again_warnings.append)  # read from the index
    assert listed(parsed) == listed(indexed) == listed(again)
    assert parsed_warnings == indexed_warnings == again_warnings
    names = [s.name for s in parsed]
    assert names == (["Small.Decay"] if exported_only else ["Small.Decay", "Small.Plain"])
    assert any("Bad.mo:4:1: syntax error" in w for w in parsed_warnings)
    assert any("Small.Undeclared is not listed" in w for w in parsed_warnings) != exported_only
    # one model: the same summary from the index as from its own flattening
    assert summarize("Small.Decay").to_dict() == summarize("Small.Decay", Library(library)).to_dict()


def test_list_and_info_use_the_index_without_the_compiler(tmp_path):
    lib = small_library(tmp_path, {"Decay": DECAY, "Plain": PLAIN})
    # without an index the blocked command must fail: the blocker works
    refused = cosim(tmp_path, "list", "--library", str(lib), blocked=True)
    assert refused.returncode != 0 and "blocked by the test" in refused.stderr
    first = cosim(tmp_path, "list", "--library", str(lib))  # parses, writes the index
    assert first.returncode == 0, first.stderr
    assert "Small.Decay" in first.stdout and "k=2.5" in first.stdout
    for args in (["list"], ["list", "--json"], ["list", "--exported"], ["info", "Small.Decay"],
                 ["info", "Small.Decay", "--json"]):
        indexed = cosim(tmp_path, *args, "--library", str(lib), blocked=True)
        parsed = cosim(tmp_path, *args, "--library", str(lib), cache=f"fresh-{len(args)}-{args[-1]}")
        assert indexed.returncode == 0, (args, indexed.stderr)
        assert (indexed.stdout, indexed.stderr) == (parsed.stdout, parsed.stderr), args
    info = json.loads(cosim(tmp_path, "info", "Small.Decay", "--json", "--library", str(lib), blocked=True).stdout)
    assert info["parameters"] == [{"name": "k", "unit": "1/s", "description": "rate", "value": 2.5,
                                   "min": None, "max": None, "type": "Real"}]
    assert info["experiment"] == {"StopTime": 2, "Interval": 0.01}


def test_index_is_rebuilt_after_a_mo_edit(tmp_path):
    lib = small_library(tmp_path, {"Decay": DECAY})
    assert "k=2.5" in cosim(tmp_path, "list", "--library", str(lib)).stdout
    file = lib / "Small" / "Decay.mo"
    file.write_text(DECAY.replace("= 2.5", "= 4.75"), encoding="utf-8")
    # the index no longer matches the files: the blocked command needs the compiler now
    assert cosim(tmp_path, "list", "--library", str(lib), blocked=True).returncode != 0
    edited = cosim(tmp_path, "list", "--library", str(lib))
    assert edited.returncode == 0 and "k=4.75" in edited.stdout and "k=2.5" not in edited.stdout
    again = cosim(tmp_path, "list", "--library", str(lib), blocked=True)
    assert again.returncode == 0 and again.stdout == edited.stdout
    assert len(list((tmp_path / "cache" / "cosim").glob("library-index-*.json"))) == 1  # replaced, not added


USES_SMALL = '''within Other;
model UsesSmall "a model of another package that extends one of Small"
  extends Small.Decay;
end UsesSmall;
'''
ALONE = '''within Alone;
model Counter "names no other package"
  Real n(start = 0, fixed = true);
equation
  der(n) = 1;
end Counter;
'''


def _package(folder: Path, name: str, models: dict[str, str]) -> None:
    (folder / name).mkdir(parents=True)
    (folder / name / "package.mo").write_text(f"within;\npackage {name}\nend {name};\n", encoding="utf-8")
    for model, text in models.items():
        (folder / name / f"{model}.mo").write_text(text, encoding="utf-8")


def test_another_library_flattens_only_the_packages_it_changes(library, tmp_path, monkeypatch):
    """A library of two folders reuses the summaries of the packages whose files (and those of the
    packages they name) are unchanged: only the new packages' models are flattened, and what it
    lists is what flattening everything lists; editing a package re-summarizes it and the packages
    that name it, not the others."""
    from cosim.compiler import catalog as catalog_module

    mine = tmp_path / "mine"
    _package(mine, "Other", {"UsesSmall": USES_SMALL})
    _package(mine, "Alone", {"Counter": ALONE})
    flattened = []
    real = catalog_module.summarize
    monkeypatch.setattr(catalog_module, "summarize", lambda name, lib=None: flattened.append(name) or real(name, lib))
    catalog(warn=lambda message: None)  # the library of the fixture: Small
    assert "Small.Decay" in flattened

    def listing(paths) -> tuple[str, list]:
        flattened.clear()
        monkeypatch.setenv("COSIM_MODELICA_PATH", os.pathsep.join(map(str, paths)))
        load_library.cache_clear()
        warnings = []
        return listed(catalog(warn=warnings.append)), warnings

    both = [mine, library]
    found, warnings = listing(both)
    assert sorted(flattened) == ["Alone.Counter", "Other.UsesSmall"]
    fresh = []
    assert found == listed(catalog(Library(both), warn=fresh.append)) and warnings == fresh
    assert '"Other.UsesSmall"' in found and '"Small.Decay"' in found
    # Small changes: it and Other (which names Small) are flattened again, Alone is not
    (library / "Small" / "Decay.mo").write_text(DECAY.replace("= 2.5", "= 4.75"), encoding="utf-8")
    found, _ = listing(both)
    assert sorted(flattened) == ["Other.UsesSmall", "Small.Decay", "Small.Plain", "Small.Undeclared"]
    uses = next(s for s in catalog(warn=lambda message: None) if s.name == "Other.UsesSmall")
    assert {p.name: p.value for p in uses.parameters}["k"] == 4.75
    # a damaged store of one package is ignored: that package is flattened again, same listing
    store, _ = catalog_module._package_keys()["Alone"]
    store.write_text(store.read_text(encoding="utf-8")[:40], encoding="utf-8")
    index, _ = index_key()
    index.unlink()
    again, _ = listing(both)
    assert flattened == ["Alone.Counter"] and again == found


@pytest.mark.parametrize("damage", [
    pytest.param(lambda text: text[: len(text) // 2], id="truncated"),
    pytest.param(lambda text: "", id="empty"),
    pytest.param(lambda text: "[1, 2, 3]", id="not-an-object"),
    pytest.param(lambda text: text.replace('"summary"', '"summery"'), id="wrong-record"),
    pytest.param(lambda text: text.replace('"inputs"', '"inputz"'), id="wrong-summary"),
    pytest.param(lambda text: text.replace('"complete": true', '"complete": "yes"'), id="wrong-flag"),
])
def test_damaged_index_is_ignored(library, damage):
    warnings = []
    expected = listed(catalog(Library(library), warn=warnings.append))
    catalog(warn=lambda message: None)  # writes the index
    file, key = index_key()
    text = file.read_text(encoding="utf-8")
    assert key in text
    file.write_text(damage(text), encoding="utf-8")
    found = []
    assert listed(catalog(warn=found.append)) == expected and found == warnings
    assert json.loads(file.read_text(encoding="utf-8"))["key"] == key  # rewritten, whole


def test_info_of_a_model_fills_a_partial_index(library):
    file, _ = index_key()
    assert not file.exists()
    assert summarize("Small.Plain").parameters[0].value == 1
    stored = json.loads(file.read_text(encoding="utf-8"))
    assert stored["complete"] is False and [r["name"] for r in stored["models"]] == ["Small.Plain"]
    # a partial index is not a list of the library: `list` parses everything and completes it
    warnings = []
    assert [s.name for s in catalog(warn=warnings.append)] == ["Small.Decay", "Small.Plain"]
    assert json.loads(file.read_text(encoding="utf-8"))["complete"] is True


@pytest.mark.parametrize("name, error", [("Small.Nothing", "unknown model 'Small.Nothing'"),
                                         ("Small.Bad", "Bad.mo:4:1: syntax error"),
                                         ("Small.Undeclared", "undeclared variable 'q'")],
                         ids=["unknown", "syntax-error", "not-flattenable"])
def test_errors_are_those_of_parsing(library, name, error):
    catalog(warn=lambda message: None)  # a complete index: the name has no summary in it
    from cosim.errors import CosimError

    with pytest.raises(CosimError) as indexed:
        summarize(name)
    with pytest.raises(CosimError) as parsed:
        summarize(name, Library(library))
    assert str(indexed.value) == str(parsed.value) and error in str(parsed.value)


def test_unwritable_cache_folder_still_lists(library, tmp_path, monkeypatch):
    blocker = tmp_path / "cache-is-a-file"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert [s.name for s in catalog(warn=lambda message: None)] == ["Small.Decay", "Small.Plain"]
    assert blocker.read_text() == ""


def test_digests_without_parsing_equal_the_compilers(library):
    from cosim.compiler import build

    assert library_digest() == Library(library).digest()
    assert build.compiler_digest is compiler_digest  # one digest for the build and the index


def test_up_to_date_check_needs_no_compiler(tmp_path):
    lib = small_library(tmp_path, {"Decay": DECAY})
    built = cosim(tmp_path, "build", "Small.Decay", "--library", str(lib), "-o", str(tmp_path / "fmus"))
    assert built.returncode == 0, built.stderr
    fmu = tmp_path / "fmus" / "Small_Decay.fmu"
    assert fmu_up_to_date("Small.Decay", fmu, lib)
    assert not fmu_up_to_date("Small.Other", fmu, lib)  # the manifest names its model
    run = ["simulate", "Small.Decay", "--stop-time", "0.1", "-o", str(tmp_path / "r.csv"), "--library", str(lib)]
    done = cosim(tmp_path, *run, blocked=True)
    assert done.returncode == 0 and (tmp_path / "r.csv").is_file(), done.stderr
    (lib / "Small" / "Decay.mo").write_text(DECAY.replace("= 2.5", "= 3.5"), encoding="utf-8")
    assert not fmu_up_to_date("Small.Decay", fmu, lib)
    stale = cosim(tmp_path, *run, blocked=True)  # must rebuild, which needs the compiler
    assert stale.returncode != 0 and "blocked by the test" in stale.stderr
    assert not fmu_up_to_date("Small.Decay", tmp_path / "missing.fmu", lib)
