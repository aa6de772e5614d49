"""Commands take a model name or an FMU file: this turns either into an FMU path."""
from __future__ import annotations

from pathlib import Path

from .compiler.build import DEFAULT_OUTPUT, build_model
from .compiler.library import load_library


def is_fmu_path(target: str) -> bool:
    """A target is an FMU file if it ends in ``.fmu`` or names an existing file (else a model)."""
    return target.endswith(".fmu") or Path(target).is_file()


def resolve_fmu(target: str, output: str | Path | None = None) -> Path:
    """The FMU of ``target``: the file itself, or the model built (if needed) into ``output``."""
    if is_fmu_path(target):
        from .fmi import read_fmu

        path = Path(target)
        read_fmu(path)  # FMUError naming the file and the problem if it is not a usable FMU
        return path
    return build_model(target, output or DEFAULT_OUTPUT, load_library()).fmu
