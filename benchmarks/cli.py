"""Start-up latency of the `cosim` command line: each verb warm, in fresh processes.

Every command runs once cold (which builds the library index and the FMU the verbs need), then
``--repeat`` times warm, each time in a new Python process; the script prints the median wall
time and CPU time (user + system of the child) [s] per verb, next to floors measured in the same
run (``python -c pass``, ``import numpy``, ...), since on a shared machine only the comparison
within one run means anything.

The library index and the FMUs go to a temporary XDG_CACHE_HOME and COSIM_FMU_DIR, removed at
the end (the user's cache is neither used nor touched)::

    python benchmarks/cli.py            # 7 warm runs per verb
    python benchmarks/cli.py -n 15 --model Bicycle.Bicycles.Whipple
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


#: The goals [s] of warm wall time (docs/benchmarks.md), so that a command feels instant; a verb not
#: listed has none.
TARGETS = {"list": 0.3, "info MODEL": 0.3, "analytic": 0.3, "linearize FMU": 0.3, "up-to-date check": 0.1}

#: In-process time of the up-to-date check of `cosim simulate MODEL` (what runs before the
#: simulation: import of cosim.fmu.target and resolve_fmu of a built, up-to-date model).
CHECK = """\
import sys, time
started = time.perf_counter()
from cosim.fmu.target import resolve_fmu
resolve_fmu(sys.argv[1])
elapsed = time.perf_counter() - started
print("compiler imported:", "pymoca" in sys.modules or "casadi" in sys.modules)
print(elapsed)
"""


def run(command: list[str], env: dict) -> tuple[float, float, str]:
    """``(wall, cpu, stdout)`` [s] of one fresh process; raises if it fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}):\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-n", "--repeat", type=int, default=7, help="warm runs per command (default 7)")
    p.add_argument("--model", default="Bicycle.Bicycles.SelfStabilizing", help="model of info/simulate/linearize")
    p.add_argument("--only", default=None, metavar="NAME,...",
                   help="measure only these verbs (names as printed, e.g. 'list,info MODEL'); floors always")
    args = p.parse_args(argv)

    scratch = Path(tempfile.mkdtemp(prefix="cosim-cli-bench-"))
    env = {**os.environ, "XDG_CACHE_HOME": str(scratch / "cache"), "COSIM_FMU_DIR": str(scratch / "fmus"),
           "MPLCONFIGDIR": str(scratch / "matplotlib")}
    py = [sys.executable]
    cosim = [*py, "-m", "cosim"]
    fmu = scratch / "fmus" / f"{args.model.replace('.', '_')}.fmu"
    result = scratch / "result.csv"
    floors = {
        "python -c pass": [*py, "-c", "pass"],
        "import numpy": [*py, "-c", "import numpy"],
        "import numpy, fmpy": [*py, "-c", "import numpy, fmpy.fmi2"],
        "import scipy.optimize": [*py, "-c", "import scipy.optimize"],
        "import pymoca, casadi": [*py, "-c", "import pymoca.parser, casadi"],
    }
    verbs = {
        "--help": [*cosim, "--help"],
        "list": [*cosim, "list"],
        "list --json": [*cosim, "list", "--json"],
        "info MODEL": [*cosim, "info", args.model],
        "simulate MODEL": [*cosim, "simulate", args.model, "--stop-time", "0.1", "-o", str(result)],
        "up-to-date check": [*py, "-c", CHECK, args.model],
        "info FMU": [*cosim, "info", str(fmu)],
        "analytic": [*cosim, "analytic"],
        "linearize FMU": [*cosim, "linearize", str(fmu)],
    }
    if args.only:
        wanted = [name.strip() for name in args.only.split(",")]
        unknown = [name for name in wanted if name not in verbs]
        if unknown:
            p.error(f"--only: unknown verb(s) {', '.join(unknown)}; known: {', '.join(verbs)}")
        # simulate MODEL first where a verb needs the built FMU
        needs_fmu = any(name in wanted for name in ("up-to-date check", "info FMU", "linearize FMU"))
        verbs = {name: command for name, command in verbs.items()
                 if name in wanted or (name == "simulate MODEL" and needs_fmu)}
    notes = []
    try:
        rows = []
        for group, commands in (("floor", floors), ("verb", verbs)):
            for name, command in commands.items():
                cold_wall, _, _ = run(command, env)  # builds the index / the FMU where needed
                walls, cpus = [], []
                for _ in range(args.repeat):
                    wall, cpu, out = run(command, env)
                    # the check reports its own in-process time (start-up of Python excluded)
                    walls.append(float(out.split()[-1]) if name == "up-to-date check" else wall)
                    cpus.append(cpu)
                rows.append((group, name, cold_wall, statistics.median(walls), statistics.median(cpus)))
                if name == "up-to-date check":
                    notes.append(f"up-to-date check: {out.splitlines()[0]}")
                print(f"  measured {name}", file=sys.stderr)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    print(f"median of {args.repeat} warm runs, each a fresh process [s] (cold = the first run)")
    print(f"{'':6} {'command':24} {'cold':>8} {'wall':>8} {'cpu':>8}  target")
    for group, name, cold, wall, cpu in rows:
        target = TARGETS.get(name)
        mark = "" if target is None else f"<= {target:g} {'ok' if wall <= target else 'MISSED'}"
        print(f"{group:6} {name:24} {cold:8.3f} {wall:8.3f} {cpu:8.3f}  {mark}")
    print("up-to-date check: in-process wall of `from cosim.fmu.target import resolve_fmu; resolve_fmu(MODEL)`")
    for note in notes:
        print(note)
    return 0


if __name__ == "__main__":
    sys.exit(main())
