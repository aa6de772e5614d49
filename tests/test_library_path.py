"""Folders of one's own Modelica packages next to the shipped library (``--library DIR``,
``COSIM_MODELICA_PATH``): searched in order before the shipped library, which is always searched
last; a top-level package comes from the first folder that holds it (``MODELICAPATH``); the
library index and the up-to-date check cover every folder; a class name too long for a file is
an exit-2 message, never an internal error."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from conftest import cli_in_process
from cosim.compiler.catalog import index_key, summarize
from cosim.compiler.library import DEFAULT_LIBRARY, Library, library_digest, library_paths, load_library
from cosim.errors import UnknownModelError
from cosim.fmu.parameters import model_declarations

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

ONE = '''package One "the first folder"
  block Gain "y = k u"
    parameter Real k = 2 "gain";
    input Real u "in";
    output Real y "out";
  equation
    y = k*u;
  end Gain;
end One;
'''
TWO = '''package Two "the second folder"
  model Uses "a class of each folder and one of the shipped library"
    Bicycle.Sources.TorqueStep step(amplitude = 4);
    One.Gain gain(k = 3);
    output Real y "gain times the step";
  equation
    gain.u = step.y;
    y = gain.y;
  end Uses;
end Two;
'''


@pytest.fixture
def folders(tmp_path, monkeypatch) -> tuple[Path, Path]:
    """Two folders of one's own packages named by COSIM_MODELICA_PATH (their index is their own:
    it is named after the folders)."""
    one, two = tmp_path / "one", tmp_path / "two"
    one.mkdir()
    two.mkdir()
    (one / "One.mo").write_text(ONE, encoding="utf-8")
    (two / "Two.mo").write_text(TWO, encoding="utf-8")
    monkeypatch.setenv("COSIM_MODELICA_PATH", f"{one}{os.pathsep}{two}")
    load_library.cache_clear()
    yield one, two
    load_library.cache_clear()


def test_two_folders_and_the_shipped_library_resolve_a_class_each(folders):
    one, two = folders
    assert library_paths() == [one.resolve(), two.resolve(), DEFAULT_LIBRARY.resolve()]  # shipped last
    declared = model_declarations("Two.Uses")  # flattened and described: every class was found
    assert (declared["gain.k"].start, declared["step.amplitude"].start) == (3.0, 4.0)
    assert summarize("One.Gain").parameters[0].value == 2


def test_index_and_up_to_date_keys_cover_every_folder(folders):
    """A change in a file of the second folder gives another index key and another digest, and
    what `info MODEL` and the parameter checks answer follow the edit."""
    one, two = folders
    file, key = index_key()
    digest = library_digest()
    assert index_key(one)[0] != file  # one index per list of folders
    assert model_declarations("Two.Uses")["gain.k"].start == 3.0  # stored in the index
    assert summarize("Two.Uses").outputs[0].description == "gain times the step"
    edited = TWO.replace("gain(k = 3)", "gain(k = 5)").replace("gain times the step", "edited")
    (two / "Two.mo").write_text(edited, encoding="utf-8")
    assert index_key() != (file, key) and library_digest() != digest
    assert index_key()[0] == file  # the same folders: the index file is replaced, not added
    load_library.cache_clear()
    assert model_declarations("Two.Uses")["gain.k"].start == 5.0
    assert summarize("Two.Uses").outputs[0].description == "edited"


def test_own_bicycle_package_hides_the_shipped_one(tmp_path):
    """MODELICAPATH: the first folder holding a top-level package wins, as a whole."""
    own = tmp_path / "own" / "Bicycle"
    own.mkdir(parents=True)
    (own / "package.mo").write_text('within;\npackage Bicycle "my own"\n  model Mine "mine"\n'
                                    '    Real x(start = 1, fixed = true);\n  equation\n    der(x) = -x;\n'
                                    '  end Mine;\nend Bicycle;\n', encoding="utf-8")
    library = Library(tmp_path / "own")
    assert library.paths[-1] == DEFAULT_LIBRARY.resolve()
    assert library.files == [own / "package.mo"]  # none of the shipped Bicycle files
    assert [m.name for m in library.models()] == ["Bicycle.Mine"]
    with pytest.raises(UnknownModelError, match=r"unknown model 'Bicycle\.Bicycles\.Whipple'"):
        library.entry("Bicycle.Bicycles.Whipple")


def test_empty_folder_is_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    status, out, err = cli_in_process(["info", "Bicycle.Control.PD", "--library", str(tmp_path / "empty")], tmp_path)
    assert status == 2
    assert err == f"cosim info: error: {tmp_path / 'empty'}: no .mo files in the Modelica library folder\n"


UNKNOWN_LONG = "Bicycle." + "A" * 286  # 294 characters: longer than a file name may be


@pytest.mark.parametrize("args", [["simulate", UNKNOWN_LONG, "--stop-time", "1"], ["build", UNKNOWN_LONG],
                                  ["info", UNKNOWN_LONG], ["linearize", UNKNOWN_LONG],
                                  ["simulate", UNKNOWN_LONG, "--stop-time", "1", "--param", "k=1"]],
                         ids=["simulate", "build", "info", "linearize", "simulate-param"])
def test_unknown_class_name_too_long_for_a_file_is_unknown(tmp_path, args):
    status, out, err = cli_in_process([*args, "-o", str(tmp_path / "out")] if args[0] == "build" else args, tmp_path)
    assert status == 2, err
    assert err.startswith(f"cosim {args[0]}: error: unknown model '{UNKNOWN_LONG}'; the library at ")
    assert list(tmp_path.iterdir()) == []


LONG = "Abcdefghijklmnopqrstuvwxyz" * 11  # Mine.<286 characters>: a valid class, too long for an FMU file


@pytest.mark.parametrize("args, message", [
    (["build", f"Mine.{LONG}"], f"model name 'Mine.{LONG}' is too long for an FMU file: its name 'Mine_{LONG}.fmu' "
                                "has 295 bytes, at most "),
    (["simulate", f"Mine.{LONG}", "--stop-time", "1", "-o", "r.csv"], f"model name 'Mine.{LONG}' is too long for an "
                                                                     "FMU file"),
    (["simulate", f"Mine.{LONG}", "--stop-time", "1"], "the model name is too long for a result file named after it"),
], ids=["build", "simulate", "simulate-default-result"])
def test_existing_class_name_too_long_for_a_file_is_a_clear_message(tmp_path, args, message):
    folder = tmp_path / "lib"
    folder.mkdir()
    (folder / "Mine.mo").write_text(f'package Mine "long names"\n  model {LONG} "long"\n    parameter Real k = 1;\n'
                                    f'    Real x(start = 1, fixed = true);\n  equation\n    der(x) = -k*x;\n'
                                    f'  end {LONG};\nend Mine;\n', encoding="utf-8")
    extra = ["-o", str(tmp_path / "fmus")] if args[0] == "build" else []
    status, out, err = cli_in_process([*args, *extra, "--library", str(folder)], tmp_path)
    assert status == 2, err
    assert err.startswith(f"cosim {args[0]}: error: {message}"), err
    assert "internal error" not in err and not list(tmp_path.rglob("*.fmu")) and not (tmp_path / "r.csv").exists()
