"""Progress of the long verbs on a terminal, plain lines elsewhere, and -q / -v (cosim.progress)."""
from __future__ import annotations

import contextlib
import fcntl
import io
import os
import pty
import re
import struct
import termios
import threading
from pathlib import Path
from types import SimpleNamespace

import pytest

from conftest import ROOT
from cosim import figures
from cosim.compiler import build as compiler_build
from cosim.cli import main
from cosim.cosimulation.master import System
from cosim.progress import NORMAL, QUIET, VERBOSE, Reporter

MODEL = "Bicycle.Bicycles.WhippleLinear"
DEMO_MODELS = ("Bicycle.Bicycles.SelfStabilizing", MODEL)  # the demo's simulation, its co-simulation


class _Terminal(io.StringIO):
    """A stream that says it is a terminal (what the reporter wrote stays readable)."""

    def isatty(self) -> bool:
        return True


def _report(reporter: Reporter) -> None:
    """Two phases as `cosim demo` makes them: three steps, the second with two items of its own."""
    with reporter.steps(3):
        reporter.item("build")
        reporter.item("validate")
        with reporter.steps(2):
            reporter.item("Bicycle.A")
            reporter.detail("Bicycle.A: valid")
            reporter.item("Bicycle.B")
        reporter.fraction(0.5, "t = 5 s")
        reporter.item("simulate")


@pytest.mark.parametrize("level, expected", [
    (NORMAL, "cosim demo: [1/3] build\ncosim demo: [2/3] validate\ncosim demo: [3/3] simulate\n"),
    (VERBOSE, "cosim demo: [1/3] build\ncosim demo: [2/3] validate\ncosim demo: Bicycle.A: valid\n"
              "cosim demo: [3/3] simulate\n"),
    (QUIET, ""),
], ids=["plain-lines", "verbose", "quiet"])
def test_reporter_off_a_terminal(level, expected):
    """Off a terminal: one plain line per item of the outermost phase (the inner phase and the
    fraction only on a terminal), detail lines with -v only, nothing with -q."""
    stream = io.StringIO()
    _report(Reporter("demo", level, stream))
    assert stream.getvalue() == expected


def test_reporter_on_a_terminal_redraws_one_line_and_survives_a_closed_stream():
    """On a terminal one line redrawn with \\r: the count and item of each open phase, the fraction
    after them, cleared at the end; a closed stream silences the reporter instead of failing."""
    stream = _Terminal()
    reporter = Reporter("demo", NORMAL, stream)
    _report(reporter)
    reporter.close()
    drawn = stream.getvalue()
    assert "\n" not in drawn
    frames = [frame.rstrip() for frame in drawn.split("\r") if frame.strip()]
    assert frames == ["[1/3] build", "[2/3] validate", "[2/3] validate > [1/2] Bicycle.A",
                      "[2/3] validate > [2/2] Bicycle.B", "[2/3] validate", "[2/3] validate >  50% t = 5 s",
                      "[3/3] simulate"]
    assert drawn.endswith("\r" + " " * len("[3/3] simulate") + "\r")  # the last line drawn, cleared
    stream.close()
    _report(reporter)  # ValueError of the closed stream: taken as -q
    assert reporter.quiet


class _Figure:
    """A figure module of :func:`cosim.figures.registry` that writes NAME.txt."""

    def __init__(self, name: str):
        self.name = name

    def make(self, output: Path) -> list[Path]:
        path = Path(output) / f"{self.name}.txt"
        path.write_text(self.name, encoding="utf-8")
        return [path]


def _on_terminal(argv: list[str], cwd) -> tuple[int, str, str]:
    """``cosim ARGV`` in this process with stderr on a pseudo-terminal of 200 columns: (exit
    status, stdout, what the terminal received)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 200, 0, 0))
    received: list[bytes] = []

    def read():
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the slave side is closed
                return
            if not data:
                return
            received.append(data)

    reader = threading.Thread(target=read)
    reader.start()
    here = os.getcwd()
    out = io.StringIO()
    terminal = os.fdopen(slave, "w")
    try:
        os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(terminal):
            status = main(argv)
    finally:
        os.chdir(here)
        terminal.close()
        reader.join(timeout=10)
        os.close(master)
    return status, out.getvalue(), b"".join(received).decode()


@pytest.mark.parametrize("verb, argv, expected", [
    ("build", ["build", MODEL], [rf"\[1/1\] {MODEL}"]),
    ("validate", ["validate", "{fmu}"], [r"\[1/1\] \S+\.fmu", r"\[1/1\] \S+\.fmu > \[11/11\] cs-run"]),
    ("figures", ["figures", "figA", "figB", "-o", "figures", "-j", "1"], [r"\[1/2\] figA", r"\[2/2\] figB"]),
    ("run", ["run", str(ROOT / "cosim" / "systems" / "lane-change.toml"), "-o", "r.csv"],
     [r"\d+% t = [\d.]+ of 20 s"]),
    ("run-c-loop", ["run", str(ROOT / "cosim" / "systems" / "lane-change.toml"), "-o", "r.csv"],
     [r"\d+% t = [\d.]+ of 20 s"]),
    ("demo", ["demo", "-o", "d"], [r"\[1/4\] build every exported model",
                                   rf"\[2/4\] validate the FMUs > \[1/2\] {DEMO_MODELS[0]}",
                                   rf"\[2/4\] validate the FMUs > \[2/2\] {DEMO_MODELS[1]}",
                                   rf"\[3/4\] simulate {DEMO_MODELS[0]}", r"\[4/4\] co-simulate lane-change\.toml"]),
    ("app-export", ["app", "--export", "site"], [r"\[1/4\] load the shipped WebAssembly modules",
                                                 r"\[4/4\] write the bundle"]),
], ids=["build", "validate", "figures", "run", "run-c-loop", "demo", "app-export"])
def test_long_verbs_show_progress_on_a_terminal_and_nothing_with_q(verb, argv, expected, fmus, tmp_path,
                                                                   monkeypatch):
    """Each verb shows the count and current item (``run``: the percent of its stop time, on the
    Python loop that steps one communication point at a time and on the C loop, called for a
    fiftieth of the grid at a time) on a terminal, clears the line at
    the end, and with -q leaves the terminal blank and prints the same result. (The figures are
    two that write a small file each: the paper's take seconds to compute; the demo's build is
    two FMUs of the session; `app --export` uses the shipped modules, as an installed cosim does.)"""
    if verb != "run-c-loop":  # the Python loop, one communication point at a time
        monkeypatch.setattr(System, "use_fast_loop", False)
    monkeypatch.setattr(figures, "registry", lambda: {name: _Figure(name) for name in ("figA", "figB")})
    # the demo's build returns two of the session's FMUs (building and validating all of them takes
    # half a minute); its validation, simulations and co-simulation run as they are
    if verb == "demo":
        monkeypatch.setattr(compiler_build, "build", lambda **_: [
            SimpleNamespace(model=m, fmu=fmus[m], rebuilt=False) for m in DEMO_MODELS])
    argv = [a.format(fmu=fmus[MODEL]) for a in argv]
    if verb == "build":
        argv += ["-o", os.environ["COSIM_FMU_DIR"]]
    status, out, drawn = _on_terminal(argv, tmp_path)
    assert status == 0, drawn
    for pattern in expected:
        assert re.search(pattern, drawn), drawn
    assert "\n" not in drawn and drawn.endswith("\r"), drawn  # one line, redrawn, then cleared
    quiet = ["-q", *argv] if verb == "validate" else [*argv, "--quiet"]  # before or after the verb
    quiet_status, quiet_out, quiet_drawn = _on_terminal(quiet, tmp_path)
    assert (quiet_status, quiet_drawn) == (0, "")
    if verb == "build":  # -q: only what was built (here nothing: the FMU is up to date)
        assert (quiet_out, out.startswith("up to date")) == ("", True)
    else:
        assert quiet_out == out
