"""`cosim build` and processes: workers die with a killed parent, concurrent builds of one
model into one folder build it once.

A C compiler that waits for a signal file (``CC``) holds the builds at a known point, so
neither test depends on how long a build takes.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import uuid
import zipfile
from pathlib import Path

import pytest

from conftest import ROOT

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

psutil = pytest.importorskip("psutil")

SMALL = ["Bicycle.Control.Proportional", "Bicycle.Control.PD", "Bicycle.Control.SteerAngleFeedback",
         "Bicycle.Bicycles.SelfStabilizing"]
WAIT = 120.0  # s: upper bound of every wait (never reached when the code works)


def _waiting_compiler(tmp_path: Path) -> tuple[Path, Path]:
    """A ``CC`` that starts gcc only once the file ``go`` exists."""
    go = tmp_path / "go"
    cc = tmp_path / "waiting-cc"
    cc.write_text(f'#!/bin/sh\nwhile [ ! -e "{go}" ]; do sleep 0.05; done\nexec gcc "$@"\n')
    cc.chmod(0o755)
    return cc, go


def _cosim(args: list[str], env: dict, log: Path) -> subprocess.Popen:
    """Start `python -m cosim ARGS`, its output to files (an orphan holding a pipe would block
    reading it)."""
    with open(log.with_suffix(".out"), "w") as stdout, open(log.with_suffix(".err"), "w") as stderr:
        return subprocess.Popen([sys.executable, "-m", "cosim", *args], cwd=ROOT, env={**os.environ, **env},
                                stdout=stdout, stderr=stderr, text=True)


def _output(log: Path) -> tuple[str, str]:
    return log.with_suffix(".out").read_text(), log.with_suffix(".err").read_text()


def _marked(mark: str) -> list:
    """Live processes (not zombies) whose environment carries ``COSIM_TEST_MARK=mark``."""
    found = []
    for process in psutil.process_iter():
        try:
            if process.status() == psutil.STATUS_ZOMBIE:
                continue
            if process.environ().get("COSIM_TEST_MARK") == mark:
                found.append(process)
        except psutil.Error:
            continue
    return found


def _compiling(pid: int) -> bool:
    """True once a descendant of ``pid`` runs the waiting compiler."""
    try:
        return any("waiting-cc" in " ".join(p.cmdline()) or p.name() == "waiting-cc"
                   for p in psutil.Process(pid).children(recursive=True))
    except psutil.Error:
        return False


def _until(condition, what: str, timeout: float = WAIT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    pytest.fail(f"timed out after {timeout:.0f} s waiting for {what}")


def test_killed_parallel_build_leaves_no_worker_and_writes_no_fmu(tmp_path):
    cc, go = _waiting_compiler(tmp_path)
    out, scratch, mark = tmp_path / "out", tmp_path / "tmp", uuid.uuid4().hex
    scratch.mkdir()
    env = {"CC": str(cc), "TMPDIR": str(scratch), "COSIM_TEST_MARK": mark}
    build = _cosim(["build", "-j", "2", "--force", "-o", str(out), *SMALL], env, tmp_path / "build")
    try:
        parent = psutil.Process(build.pid)
        # Both workers exist and at least one of them is in its compiler.
        _until(lambda: len(parent.children()) >= 2 and _compiling(build.pid), "two workers and a compiler")
        fmus_at_kill = sorted(p.name for p in out.glob("*.fmu"))
        os.kill(build.pid, signal.SIGKILL)
        build.wait(timeout=WAIT)
        _until(lambda: not _marked(mark), "every worker and compiler to exit after the parent was killed", 30)
        go.touch()  # a compiler that survived would now build and write its FMU
        time.sleep(1.0)
        assert not _marked(mark)
        assert sorted(p.name for p in out.glob("*.fmu")) == fmus_at_kill, "an FMU appeared after the kill"
        assert not [p.name for p in out.iterdir() if p.name.startswith(".")], "partial FMU or lock file left"
        assert list(scratch.iterdir()) == [], "temporary build files left"
    finally:
        for process in _marked(mark):
            process.kill()


def _waiting_for_lock(pid: int) -> bool:
    """True while process ``pid`` waits for a flock (a ``->`` line of /proc/locks)."""
    return any("->" in line and "FLOCK" in line and f" {pid} " in line
               for line in Path("/proc/locks").read_text().splitlines())


@pytest.mark.skipif(not Path("/proc/locks").exists(), reason="needs Linux /proc/locks")
def test_concurrent_builds_of_one_model_build_once(tmp_path):
    cc, go = _waiting_compiler(tmp_path)
    out, model, mark = tmp_path / "out", "Bicycle.Bicycles.SelfStabilizing", uuid.uuid4().hex
    env = {"COSIM_TEST_MARK": mark}
    first = _cosim(["build", "-j", "1", "--force", "-o", str(out), model], {**env, "CC": str(cc)}, tmp_path / "first")
    try:
        # The first build is in its compiler (holding the lock) and waits there.
        _until(lambda: _compiling(first.pid), "the first build to compile")
        second = _cosim(["build", "-j", "1", "-o", str(out), model], env, tmp_path / "second")
        # The second waits for the lock (without it, it would build at once and exit).
        _until(lambda: second.poll() is not None or _waiting_for_lock(second.pid), "the second build to wait")
        assert second.poll() is None, f"the second build did not wait: {_output(tmp_path / 'second')}"
        go.touch()
        first.wait(timeout=WAIT)
        second.wait(timeout=WAIT)
    finally:
        for process in _marked(mark):
            process.kill()
    (out1, err1), (out2, err2) = _output(tmp_path / "first"), _output(tmp_path / "second")
    assert first.returncode == 0 and second.returncode == 0, (err1, err2)
    assert "Traceback" not in err1 + err2
    assert out1.startswith("built ") and out2.startswith("up to date"), (out1, out2)
    fmu = out / "Bicycle_Bicycles_SelfStabilizing.fmu"
    with zipfile.ZipFile(fmu) as archive:
        assert archive.testzip() is None
        assert "modelDescription.xml" in archive.namelist()
    assert [p.name for p in out.iterdir()] == [fmu.name], "lock or partial file left behind"


def test_killed_build_worker_fails_its_models_with_one_message(tmp_path):
    """A worker killed from outside (the OOM killer) fails the build with one message; the
    other worker stops too and nothing is left behind."""
    cc, go = _waiting_compiler(tmp_path)
    out, scratch, mark = tmp_path / "out", tmp_path / "tmp", uuid.uuid4().hex
    scratch.mkdir()
    env = {"CC": str(cc), "TMPDIR": str(scratch), "COSIM_TEST_MARK": mark}
    build = _cosim(["build", "-j", "2", "--force", "-o", str(out), *SMALL[:2]], env, tmp_path / "build")
    try:
        parent = psutil.Process(build.pid)
        _until(lambda: len(parent.children()) >= 2 and _compiling(build.pid), "two workers and a compiler")
        victim = next(p for p in parent.children() if _compiling(p.pid))
        victim.kill()
        go.touch()
        build.wait(timeout=WAIT)
        _until(lambda: not _marked(mark), "every worker and compiler to exit", 30)
    finally:
        for process in _marked(mark):
            process.kill()
    _, err = _output(tmp_path / "build")
    assert build.returncode == 2, err
    assert "Traceback" not in err and "internal error" not in err, err
    assert "a build worker died unexpectedly" in err
    assert len([line for line in err.splitlines() if line.startswith("cosim build: error:")]) == 1
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")], "partial FMU or lock file left"
    assert list(scratch.iterdir()) == [], "temporary build files left"


def test_interrupted_parallel_build_stops_its_workers(tmp_path):
    """Ctrl-C (SIGINT to the whole foreground process group) stops the workers and their
    compilers, leaves no partial file and exits with the interrupt status."""
    cc, go = _waiting_compiler(tmp_path)
    out, scratch, mark = tmp_path / "out", tmp_path / "tmp", uuid.uuid4().hex
    scratch.mkdir()
    env = {"CC": str(cc), "TMPDIR": str(scratch), "COSIM_TEST_MARK": mark}
    with open(tmp_path / "build.out", "w") as stdout, open(tmp_path / "build.err", "w") as stderr:
        build = subprocess.Popen([sys.executable, "-m", "cosim", "build", "-j", "2", "--force", "-o", str(out),
                                  *SMALL], cwd=ROOT, env={**os.environ, **env}, stdout=stdout, stderr=stderr,
                                 start_new_session=True,
                                 # a shell may have started us with SIGINT ignored; a terminal user's is not
                                 preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        _until(lambda: len(psutil.Process(build.pid).children()) >= 2 and _compiling(build.pid),
               "two workers and a compiler")
        os.killpg(build.pid, signal.SIGINT)
        build.wait(timeout=WAIT)
        _until(lambda: not _marked(mark), "every worker and compiler to exit", 30)
        go.touch()
    finally:
        for process in _marked(mark):
            process.kill()
    _, err = _output(tmp_path / "build")
    assert build.returncode == 130, err
    assert "Traceback" not in err, err
    assert not list(out.glob("*.fmu")) and not [p.name for p in out.iterdir() if p.name.startswith(".")]
    assert list(scratch.iterdir()) == [], "temporary build files left"
