"""Every writing command: an output that cannot be written is refused before any work; results
appear under their final name only when complete; -o picks the format by suffix."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, run_cli

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.SelfStabilizing"
SYSTEM = ROOT / "cosim" / "systems" / "rider-p-control.toml"


def _blocked(tmp_path):
    """A path below a regular file: no folder can be made there, whoever runs the test (root too)."""
    blocker = tmp_path / "blocker"
    blocker.write_text("a file, not a folder\n")
    return blocker / "sub"


def _commands(fmu, tmp_path):
    """(id, argv, message) of every writing option, each pointed at an unwritable or directory path."""
    blocked = _blocked(tmp_path)
    folder = tmp_path / "existing-folder"
    folder.mkdir()
    ok = str(tmp_path / "ok.csv")
    sim = ["simulate", str(fmu), "--stop-time", "0.5"]
    return [
        ("simulate-o-blocked", [*sim, "-o", str(blocked / "r.csv")], "is a file, not a folder"),
        ("simulate-o-directory", [*sim, "-o", str(folder)], "is a directory"),
        ("simulate-plot-blocked", [*sim, "-o", ok, "--plot", str(blocked / "p.png")], "is a file, not a folder"),
        ("simulate-plot-directory", [*sim, "-o", ok, "--plot", str(folder)], "is a directory"),
        ("run-o-blocked", ["run", str(SYSTEM), "-o", str(blocked / "r.csv")], "is a file, not a folder"),
        ("run-o-directory", ["run", str(SYSTEM), "-o", str(folder)], "is a directory"),
        ("run-plot-directory", ["run", str(SYSTEM), "-o", ok, "--plot", str(folder)], "is a directory"),
        ("export-ssp-blocked", ["export-ssp", str(SYSTEM), "-o", str(blocked / "s.ssp")], "is a file, not a folder"),
        ("export-ssp-directory", ["export-ssp", str(SYSTEM), "-o", str(folder)], "is a directory"),
        ("figures-blocked", ["figures", "fig5", "-o", str(blocked)], "is a file, not a folder"),
        ("figures-file", ["figures", "fig5", "-o", str(tmp_path / "blocker")], "is a file, not a folder"),
        ("demo-blocked", ["demo", "-o", str(blocked)], "is a file, not a folder"),
    ]


CASE_IDS = ["simulate-o-blocked", "simulate-o-directory", "simulate-plot-blocked", "simulate-plot-directory",
            "run-o-blocked", "run-o-directory", "run-plot-directory", "export-ssp-blocked", "export-ssp-directory",
            "figures-blocked", "figures-file", "demo-blocked"]


@pytest.mark.parametrize("case", CASE_IDS)
def test_unwritable_output_is_refused_before_any_work(fmus, tmp_path, case):
    """One message naming the path, exit 2, nothing written; the FMU folder stays empty, so no
    model was built (the demo would otherwise build all of them first)."""
    _, argv, message = next(c for c in _commands(fmus[MODEL], tmp_path) if c[0] == case)
    fresh_fmus = tmp_path / "fresh-fmus"
    before = {p for p in tmp_path.rglob("*")}
    result = run_cli(*argv, env={"COSIM_FMU_DIR": str(fresh_fmus)}, cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    assert message in result.stderr, result.stderr
    assert not fresh_fmus.exists() or not any(fresh_fmus.iterdir()), "work was done before the refusal"
    assert {p for p in tmp_path.rglob("*")} == before, "something was written"


@pytest.mark.parametrize("verb", ["simulate", "run"])
def test_npy_output_is_a_numpy_structured_array(fmus, tmp_path, verb):
    out = tmp_path / "r.npy"
    argv = ["simulate", str(fmus[MODEL]), "--stop-time", "1", "--step", "0.1"] if verb == "simulate" \
        else ["run", str(SYSTEM)]
    result = run_cli(*argv, "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:6] == b"\x93NUMPY"  # not CSV text
    data = np.load(out)
    assert data.dtype.names[0] == "time" and len(data.dtype.names) > 1
    if verb == "simulate":
        assert data["time"][-1] == pytest.approx(1.0, abs=1e-12) and len(data) == 11


@pytest.mark.parametrize("verb", ["simulate", "run"])
@pytest.mark.parametrize("suffix", [".txt", ".json", ""])
def test_unknown_result_suffix_is_refused_listing_csv_and_npy(fmus, tmp_path, verb, suffix):
    out = tmp_path / f"r{suffix}"
    argv = ["simulate", str(fmus[MODEL]), "--stop-time", "1"] if verb == "simulate" else ["run", str(SYSTEM)]
    result = run_cli(*argv, "-o", str(out))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "unknown result format" in result.stderr and ".csv" in result.stderr and ".npy" in result.stderr
    assert not out.exists()


def test_unknown_plot_format_is_refused(fmus, tmp_path):
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", str(tmp_path / "r.csv"),
                     "--plot", str(tmp_path / "p.xyz"))
    assert result.returncode == 2 and "unknown image format '.xyz'" in result.stderr and ".png" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_simulate_csv_is_not_left_half_written_under_final_name(fmus, tmp_path, monkeypatch):
    """The CSV is written to a hidden temporary name and renamed: a failure (or a kill) part-way
    leaves neither a partial file under the final name nor the temporary file."""
    from cosim.fmu import simulate as simulation

    result = simulation.simulate(fmus[MODEL], 1.0, 0.1)
    out = tmp_path / "r.csv"

    def savetxt_dies_half_way(fname, data, **kwargs):
        with open(fname, "w") as f:
            f.write("time,phi\n0,0\n")  # a complete-looking beginning
        raise KeyboardInterrupt  # as a Ctrl-C in the middle of writing

    monkeypatch.setattr(simulation.np, "savetxt", savetxt_dies_half_way)
    with pytest.raises(KeyboardInterrupt):
        simulation.write_csv(result, out)
    assert list(tmp_path.iterdir()) == []


def test_plot_and_figure_json_are_written_atomically(fmus, tmp_path, monkeypatch):
    """Plots and the figures' JSON go through cosim.outputs.atomic_output as well."""
    from cosim import outputs
    from cosim.fmu import simulate as simulation

    used = []
    original = outputs.atomic_output

    def spy(path, what="output file"):
        used.append(os.fspath(path))
        return original(path, what)

    monkeypatch.setattr(outputs, "atomic_output", spy)
    result = simulation.simulate(fmus[MODEL], 1.0, 0.1)
    simulation.plot(result, tmp_path / "p.png")
    simulation.write_result(result, tmp_path / "r.npy")
    outputs.write_text(tmp_path / "fig.json", "{}\n")
    assert [os.path.basename(p) for p in used] == ["p.png", "r.npy", "fig.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig.json", "p.png", "r.npy"]


def test_build_jobs_zero_is_refused(tmp_path):
    result = run_cli("build", MODEL, "-j", "0", "-o", str(tmp_path / "out"))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "-j/--jobs: must be at least 1" in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("argv", [["figures", "fig5", "-o", "{out}"], ["demo", "-o", "{out}"],
                                  ["app", "--export", "{out}"]], ids=["figures", "demo", "app-export"])
def test_folder_being_written_by_another_command_is_refused(tmp_path, argv):
    """Every command that writes a folder holds its lock: while another process (here the test
    itself) holds it, the command is refused in one line naming the holder's pid, before any
    work (nothing built, nothing written); an empty folder it created is removed again."""
    from cosim.folder_lock import folder_lock

    out = tmp_path / "out"
    fresh_fmus = tmp_path / "fresh-fmus"
    with folder_lock(out):
        (out / "earlier.txt").write_text("an earlier result\n")
        before = {p.name: p.read_bytes() for p in out.iterdir()}
        result = run_cli(*[a.format(out=out) for a in argv], env={"COSIM_FMU_DIR": str(fresh_fmus)}, cwd=tmp_path)
        assert result.returncode == 2, result.stdout + result.stderr
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and f"'{out}' is being written by pid {os.getpid()} (" in lines[0], lines
        assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert not fresh_fmus.exists(), "work was done before the refusal"
    assert sorted(p.name for p in out.iterdir()) == ["earlier.txt"], "the lock file is removed at the end"


KILLED_WRITER = """
import sys, time
from cosim.outputs import atomic_output

with atomic_output(sys.argv[1]) as tmp:
    with open(tmp, "w") as f:
        f.write("time,phi\\n" + "0,0\\n" * 100000)
        f.flush()
        print(tmp, flush=True)
        time.sleep(600)  # killed here, in the middle of writing
"""


def test_partial_file_of_a_killed_command_is_removed_by_the_next_one(fmus, tmp_path):
    """kill -9 while a result is written leaves its hidden partial file (named after the
    writer's pid and host); the next command that writes into that folder removes it. It keeps
    what is not certainly garbage: the partial file of a live process, one of another host, one
    without a pid, other hidden files, and partial files in folders it does not write to."""
    from cosim.outputs import host_tag

    out, elsewhere = tmp_path / "results", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    writer = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(out / "big.csv")], cwd=ROOT,
                              stdout=subprocess.PIPE, text=True)
    try:
        partial = Path(writer.stdout.readline().strip())
    finally:
        writer.send_signal(signal.SIGKILL)
        writer.communicate(timeout=60)
    assert partial.parent == out and partial.name.startswith(f".big.partial-{writer.pid}-{host_tag()}-"), partial
    assert partial.stat().st_size > 100_000 and not (out / "big.csv").exists()
    other_host = "0" * 6 if host_tag() != "0" * 6 else "1" * 6
    kept = [out / f".r.partial-{os.getpid()}-{host_tag()}-abcdefgh.csv",  # this (live) process
            out / f".r.partial-{writer.pid}-{other_host}-abcdefgh.csv",  # another host's pid
            out / ".r.partial-abcdefgh.csv",  # no writer named
            out / ".notes.txt",
            elsewhere / partial.name]  # not where the next command writes
    for path in kept:
        path.write_text("kept\n")
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "0.5", "-o", str(out / "r.csv"))
    assert result.returncode == 0, result.stderr
    assert not partial.exists(), "the killed writer's partial file is left"
    assert all(p.read_text() == "kept\n" for p in kept)
    assert sorted(p.name for p in out.iterdir()) == sorted([p.name for p in kept[:4]] + ["r.csv"])


# ----------------------------------------------------------------- OS errors while writing

@pytest.fixture()
def full_disk(monkeypatch):
    """``full_disk(suffixes)``: the partial files of atomic_output for those suffixes become
    symbolic links to /dev/full, so that writing the result fails with the kernel's ENOSPC (as on
    a full disk, without root or a small file system). /dev/full's mode is checked unchanged."""
    from cosim import outputs

    real = outputs._make_partial
    before = os.stat("/dev/full")

    def use(suffixes=(".csv", ".npy", ".png", ".jsonl")):
        def on_full_disk(folder, stem, suffix):
            partial = real(folder, stem, suffix)
            if suffix in suffixes:
                partial.unlink()
                partial.symlink_to("/dev/full")
            return partial

        monkeypatch.setattr(outputs, "_make_partial", on_full_disk)

    yield use
    after = os.stat("/dev/full")
    if after.st_mode != before.st_mode:  # a write that did not fail chmod-ed the device: undo, then fail
        os.chmod("/dev/full", before.st_mode & 0o7777)
    assert after.st_mode == before.st_mode


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("verb, output, full, message", [
    ("simulate", "r.csv", (".csv",), "cannot write result file '{out}/r.csv': No space left on device; the 11 rows "
                                     "(t = 0 .. 1 s) computed were not written"),
    ("simulate", "r.npy", (".npy",), "cannot write result file '{out}/r.npy': No space left on device; the 11 rows "
                                     "(t = 0 .. 1 s) computed were not written"),
    ("simulate-plot", "r.csv", (".png",), "cannot write plot file '{out}/p.png': No space left on device; the 11 rows "
                                          "(t = 0 .. 1 s) computed were not plotted; kept: {out}/r.csv"),
    ("run", "r.csv", (".csv",), "cannot write result file '{out}/r.csv': No space left on device; the 201 rows "
                                "(t = 0 .. 2 s) computed were not written"),
], ids=["simulate-csv", "simulate-npy", "simulate-plot", "run-csv"])
def test_disk_full_while_writing_the_result_is_one_line_saying_what_was_lost(fmus, tmp_path, full_disk, verb,
                                                                            output, full, message):
    """ENOSPC while the computed result is written used to be an internal error (exit 70) that
    named no file: one line naming the file, the reason and what was lost (or kept), exit 4;
    no partial file and nothing under the failed name."""
    from conftest import cli_in_process

    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "short.toml").write_text(SYSTEM.read_text().replace("stop = ", "stop = 2.0 #"))
    argv = {"simulate": ["simulate", str(fmus[MODEL]), "--stop-time", "1", "--step", "0.1"],
            "run": ["run", str(tmp_path / "short.toml")]}[verb.split("-")[0]] + ["-o", str(out / output)]
    if verb == "simulate-plot":
        argv += ["--plot", str(out / "p.png")]
    full_disk(full)
    status, stdout, err = cli_in_process(argv, tmp_path)
    assert status == 4, stdout + err
    assert err.splitlines() == [f"cosim {argv[0]}: error: {message.format(out=out)}"]
    assert sorted(p.name for p in out.iterdir()) == (["r.csv"] if verb == "simulate-plot" else [])


def _file_size_limit(size: int):
    def limit():
        import resource

        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write beyond the limit fails with EFBIG instead
    return limit


def test_write_failing_in_the_kernel_is_one_line(fmus, tmp_path):
    """A real failing write, no monkeypatching: a file size limit of 150 kB (RLIMIT_FSIZE, any
    user) lets the FMU be extracted (its largest member: 92 kB) but not the result of 20001 rows
    (about 500 kB) be written (EFBIG): one line naming the file and what was lost, exit 4,
    nothing left."""
    out = tmp_path / "out"
    out.mkdir()
    result = subprocess.run([sys.executable, "-m", "cosim", "simulate", str(fmus[MODEL]), "--stop-time", "20",
                             "--step", "0.001", "-o", str(out / "r.csv")], cwd=ROOT, capture_output=True, text=True,
                            timeout=300, preexec_fn=_file_size_limit(150_000))
    assert result.returncode == 4, result.stdout + result.stderr
    assert result.stderr.splitlines() == [
        f"cosim simulate: error: cannot write result file '{out}/r.csv': File too large; the 20001 rows "
        "(t = 0 .. 20 s) computed were not written"]
    assert list(out.iterdir()) == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("target", ["/dev/full", "fifo"], ids=["device", "fifo"])
def test_output_that_is_a_device_or_fifo_is_refused_before_any_work(fmus, tmp_path, target):
    """`-o /dev/full` passed the checks, and the result would have been renamed over the device
    (as root): a device or FIFO as output file is refused before any work, and left alone."""
    if target == "fifo":
        target = tmp_path / "fifo.csv"
        os.mkfifo(target)
    before = os.stat(target)
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", str(target))
    assert result.returncode == 2, result.stdout + result.stderr
    kind = "a character device" if str(target).startswith("/dev") else "a FIFO (named pipe)"
    assert result.stderr == f"cosim simulate: error: result file '{target}' is {kind}, not a regular file\n"
    after = os.stat(target)
    assert (after.st_mode, after.st_rdev, after.st_ino) == (before.st_mode, before.st_rdev, before.st_ino)


@pytest.mark.skipif(not os.path.isdir("/sys/kernel"), reason="needs Linux sysfs")
def test_output_where_the_os_denies_writing_is_one_line(fmus, tmp_path):
    """/sys refuses new files to everyone. A user sees it as a folder that is not writable; root
    passes that check (access(2) grants root everything) but not the probe that creates a file
    there before the work. Either way: refused before anything runs, one line naming the file."""
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", "/sys/kernel/r.csv")
    lines = result.stderr.splitlines()
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert lines[0] in ("cosim simulate: error: result file '/sys/kernel/r.csv': folder '/sys/kernel' is not writable",
                        "cosim simulate: error: cannot write result file '/sys/kernel/r.csv': Permission denied")
    assert not os.path.exists("/sys/kernel/r.csv")


def test_output_name_too_long_is_refused_before_any_work(fmus, tmp_path):
    long = tmp_path / ("r" * 300 + ".csv")
    result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", str(long))
    assert result.returncode == 2
    assert result.stderr == f"cosim simulate: error: cannot write result file '{long}': File name too long\n"
    assert list(tmp_path.iterdir()) == []
