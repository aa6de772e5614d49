"""Command-line options shared by ``cosim`` and the verbs defined in subpackages
(``cosim matrix``): argument types and option groups, without the parser of any verb."""
from __future__ import annotations

import argparse
import os

#: The environment variable that ``--library`` sets (see :func:`cosim.cli.use_library`).
LIBRARY_VARIABLE = "COSIM_MODELICA_PATH"


def positive_int(text: str) -> int:
    """argparse type of counts such as -j/--jobs and --workers: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got '{text}'") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def library_option(p: argparse.ArgumentParser) -> None:
    """``--library DIR`` of every verb that resolves model names (see :func:`cosim.cli.use_library`)."""
    p.add_argument("--library", default=None, metavar="DIR",
                   help=f"folder of your own Modelica packages (several: separated by '{os.pathsep}'), searched "
                        "before the library shipped with the package, which model names always resolve in "
                        f"too (default: ${LIBRARY_VARIABLE}); the first folder holding a top-level package wins")
