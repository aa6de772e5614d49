"""The baseline of a side-by-side benchmark: a committed tree of this repository, unpacked.

Every script of ``benchmarks/`` measures this tree against the tree of a git ref in the same run;
this is where that tree comes from (``git archive``, so uncommitted changes never leak into it).
Run as ``python benchmarks/NAME.py``, which puts this folder first on ``sys.path``.
"""
from __future__ import annotations

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
