"""Temporary and cache folders: removed by the code that made them, and placed where the
environment says (so the suite, through tests/conftest.py, leaves nothing in /tmp or ~).

Each test runs a fresh Python process with its own TMPDIR / XDG_CACHE_HOME inside ``tmp_path``
and looks at what is left there once the process has ended.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from conftest import SESSION_TMP

MODEL = "Bicycle.Control.PD"


def _python(code: str, tmp: Path, **env) -> subprocess.Popen:
    """Start ``python -c code`` with TMPDIR=tmp (and ``env``), stdout piped."""
    tmp.mkdir(exist_ok=True)
    environment = {**os.environ, "TMPDIR": str(tmp), **env}
    return subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=environment)


def _finished(process: subprocess.Popen) -> str:
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    return out


def test_fmu_extraction_folders_are_removed_at_exit(fmus, tmp_path):
    tmp = tmp_path / "tmp"
    out = _finished(_python(f"""
        from cosim.fmu.access import FMU
        a, b = FMU({str(fmus[MODEL])!r}), FMU({str(fmus["Bicycle.Rider.PadeDelay"])!r})
        print(a.unzipdir); print(b.unzipdir)
    """, tmp))
    folders = [Path(line) for line in out.split()]
    assert len(folders) == 2 and folders[0].parent == folders[1].parent, "one parent folder per process"
    assert folders[0].parent.parent == tmp and folders[0].parent.name.startswith("cosim-fmu-")
    assert list(tmp.iterdir()) == [], f"left behind: {list(tmp.iterdir())}"


def test_killed_process_leaves_one_extraction_folder_that_the_next_one_removes(fmus, tmp_path):
    """SIGKILL runs no atexit: what is left is one folder, in TMPDIR, that names the process;
    the next process that unzips an FMU removes it."""
    tmp = tmp_path / "tmp"
    process = _python(f"""
        import sys, time
        from cosim.fmu.access import FMU
        FMU({str(fmus[MODEL])!r}); FMU({str(fmus["Bicycle.Rider.PadeDelay"])!r})
        print("extracted", flush=True)
        time.sleep(600)
    """, tmp)
    try:
        assert process.stdout.readline().strip() == "extracted", process.stderr.read()
    finally:
        process.send_signal(signal.SIGKILL)
        process.communicate(timeout=60)
    left = list(tmp.iterdir())
    assert len(left) == 1 and left[0].name.startswith(f"cosim-fmu-{process.pid}-"), left
    assert len(list(left[0].iterdir())) == 2  # both FMUs, inside that one folder

    # the next process that extracts an FMU removes what the ended one left; a live one's stays
    alive = tmp / "cosim-fmu-1-alive"  # pid 1 (init) is always running
    alive.mkdir()
    _finished(_python(f"from cosim.fmu.access import FMU; FMU({str(fmus[MODEL])!r})", tmp))
    assert list(tmp.iterdir()) == [alive]


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_forked_child_does_not_remove_its_parents_extraction_folder(fmus, tmp_path):
    """A forked child inherits the atexit handlers; exiting normally it must remove only its own."""
    tmp = tmp_path / "tmp"
    out = _finished(_python(f"""
        import os, sys
        from cosim.fmu.access import FMU
        mine = FMU({str(fmus[MODEL])!r}).unzipdir
        child = os.fork()
        if child == 0:
            theirs = FMU({str(fmus[MODEL])!r}).unzipdir
            assert theirs != mine, "the child reused its parent's folder"
            sys.exit(0)  # runs the inherited atexit handlers
        os.waitpid(child, 0)
        print(os.path.isdir(mine), len(os.listdir(os.environ["TMPDIR"])))
    """, tmp))
    assert out.split() == ["True", "1"], "the child removed its parent's folder or left its own"
    assert list(tmp.iterdir()) == []


@pytest.mark.skipif(shutil.which(os.environ.get("CC") or "gcc") is None, reason="no C compiler")
def test_compiled_stepping_loop_goes_to_xdg_cache_home(tmp_path):
    cache = tmp_path / "cache"
    out = _finished(_python("""
        from cosim.cosimulation import fastloop
        print(fastloop.library() is not None)
    """, tmp_path / "tmp", XDG_CACHE_HOME=str(cache)))
    assert out.strip() == "True", "the C stepping loop did not compile or load"
    assert [p.name for p in (cache / "cosim").iterdir()] == [p.name for p in (cache / "cosim").glob("fastloop-*.so")]
    assert len(list((cache / "cosim").glob("fastloop-*.so"))) == 1
    assert list((tmp_path / "tmp").iterdir()) == []


def test_suite_writes_temporary_and_cache_files_into_its_session_folder(tmp_path):
    """tests/conftest.py points every temporary and cache location of the suite (and of the
    processes it starts) into one folder that it removes at exit."""
    import tempfile

    for variable in ("TMPDIR", "XDG_CACHE_HOME", "MPLCONFIGDIR"):
        assert Path(os.environ[variable]).is_relative_to(SESSION_TMP), variable
    assert Path(tempfile.gettempdir()).is_relative_to(SESSION_TMP)
    assert tmp_path.is_relative_to(SESSION_TMP), "pytest's tmp_path base would stay in /tmp"
