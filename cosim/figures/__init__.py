"""`cosim figures`: the paper's figures, each made by one module of this package.

A figure module defines ``NAME`` (e.g. ``"fig5"``), ``TITLE`` and ``make(output: Path) -> list[Path]``
which computes the figure from FMU simulations or linearizations and writes image files.
"""
from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path

from ..errors import ParameterError


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
    """Make the named figures (all if ``names`` is empty) into ``output``."""
    figures = registry()
    unknown = [n for n in names if n not in figures]
    if unknown:
        raise ParameterError(f"unknown figure(s) {', '.join(unknown)}; available: {', '.join(figures)}")
    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    written = []
    for name in names or list(figures):
        written += figures[name].make(output)
    return written


def save(fig, path: Path) -> Path:
    """Save a matplotlib figure as PNG and close it."""
    fig.savefig(path, dpi=120, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path


def pyplot():
    """matplotlib.pyplot with a non-interactive backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
