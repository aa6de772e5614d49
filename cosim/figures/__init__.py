"""`cosim figures`: the paper's figures, each made by one module of this package.

A figure module defines ``NAME`` (e.g. ``"fig5"``) and ``make(output: Path) -> list[Path]``, which
computes the figure from FMU simulations or linearizations and writes image files.
"""
from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path

from cosim.errors import ParameterError
from cosim.folder_lock import folder_lock
from cosim.outputs import atomic_output, check_output_folder


def registry() -> dict:
    """Figure name -> module, for every figure module of this package."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        if hasattr(module, "NAME") and hasattr(module, "make"):
            found[module.NAME] = module
    return dict(sorted(found.items(), key=lambda item: (len(item[0]), item[0])))


def make_figures(names: list[str], output: str | Path) -> list[Path]:
    """Make the named figures (all if ``names`` is empty) into ``output``.

    Raises
    ------
    ParameterError
        For an unknown figure name.
    OutputError
        If ``output`` cannot be a writable folder, or another command is writing it
        (:class:`cosim.folder_lock.FolderBusy`), before any figure is computed.
    """
    figures = registry()
    unknown = [n for n in names if n not in figures]
    if unknown:
        raise ParameterError(f"unknown figure(s) {', '.join(unknown)}; available: {', '.join(figures)}")

    output = check_output_folder(output, "figures folder")  # before any figure is computed
    written = []
    with folder_lock(output, "figures folder"):  # one command writes the folder at a time
        for name in names or list(figures):
            written += figures[name].make(output)
    return written


def save(fig, path: Path) -> Path:
    """Save a matplotlib figure (format by suffix) atomically and close it."""
    import matplotlib.pyplot as plt

    try:
        with atomic_output(path, "figure") as tmp:
            fig.savefig(tmp, dpi=120, bbox_inches="tight")
    finally:
        plt.close(fig)
    return Path(path)


def pyplot():
    """matplotlib.pyplot with a non-interactive backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
