"""What the side-by-side benchmarks share: the baseline tree, the CPU time of child processes and
the verdict on a goal.

Every script of ``benchmarks/`` measures this tree against the tree of a git ref in the same run;
:func:`baseline_tree` is where that tree comes from (``git archive``, so uncommitted changes never
leak into it). Run as ``python benchmarks/NAME.py``, which puts this folder first on ``sys.path``.
"""
from __future__ import annotations

import resource
import subprocess
import tarfile
from io import BytesIO
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: What a tree needs to build and run models: the package and its Modelica library.
PACKAGE = ("cosim", "modelica")


def baseline_tree(ref: str, folder: Path, paths: tuple[str, ...] = PACKAGE) -> Path:
    """The committed ``paths`` of ``ref`` (all of it for ``()``), unpacked into ``folder``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", ref, *paths],
                             capture_output=True, check=True).stdout
    with tarfile.open(fileobj=BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    return folder


def children_cpu() -> float:
    """CPU time [s] of the ended child processes of this one (and theirs)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def verdict(what: str, seconds: float, target: float) -> None:
    """Print whether ``seconds`` meets the goal ``target`` [s] on 2 cores."""
    print(f"  target: {what} <= {target:g} s on 2 cores: {seconds:.2f} s, "
          f"{'meets' if seconds <= target else 'MISSES'} ({seconds / target:.2f}x the target)")
