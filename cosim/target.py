"""Commands take a model name or an FMU file: this turns either into an FMU path."""
from __future__ import annotations

from pathlib import Path

from .compiler.build import DEFAULT_OUTPUT, build_model
from .compiler.library import load_library


def is_fmu_path(target: str) -> bool:
    return target.endswith(".fmu") or Path(target).is_file()


def resolve_fmu(target: str, output: str | Path | None = None) -> Path:
    """The FMU of ``target``: the file itself, or the model built (if needed) into ``output``."""
    if is_fmu_path(target):
        path = Path(target)
        if not path.is_file():
            raise FileNotFoundError(f"{target}: no such FMU file")
        return path
    return build_model(target, output or DEFAULT_OUTPUT, load_library()).fmu
