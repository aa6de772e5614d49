"""The Modelica library on disk: parsing, the list of models, their annotations.

One class per file (Modelica Standard Library layout): ``Bicycle/Components/RearFrame.mo``
holds ``Bicycle.Components.RearFrame``; a ``package.mo`` holds its package and any classes
nested in it.
"""
from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from ..errors import ModelicaError, UnknownModelError


def _bundled_library() -> Path:
    """``cosim/modelica`` of an installed wheel, else ``modelica/`` of the source tree (editable
    install or checkout): setup.py maps the one to the other."""
    package = Path(__file__).resolve().parents[1]
    installed = package / "modelica"
    return installed if (installed / "Bicycle").is_dir() else package.parent / "modelica"


DEFAULT_LIBRARY = _bundled_library()


def library_path(path: str | os.PathLike | None = None) -> Path:
    """The folder that holds the top-level Modelica packages.

    Taken from ``path``, else the environment variable ``COSIM_MODELICA_PATH``, else the
    library that ships with the package (``modelica/`` of the source tree).
    """
    chosen = path or os.environ.get("COSIM_MODELICA_PATH") or DEFAULT_LIBRARY
    chosen = Path(chosen).resolve()
    if not chosen.is_dir():
        raise ModelicaError(f"{chosen}: Modelica library folder not found")
    return chosen


@dataclass
class ModelEntry:
    """A class of the library as the command line lists it."""

    name: str
    kind: str  # model, block, package, connector, ...
    partial: bool
    description: str
    file: Path
    annotation: dict = field(default_factory=dict)

    @property
    def exported(self) -> bool:
        """True where the class carries ``annotation(__Cosim(export = true))``."""
        return bool(self.annotation.get("__Cosim", {}).get("export", False))

    @property
    def experiment(self) -> dict:
        """The ``experiment(...)`` annotation as a dict (StartTime, StopTime, Tolerance, Interval)."""
        return dict(self.annotation.get("experiment", {}))


def _annotation_to_dict(modification) -> dict:
    """Turn a pymoca ClassModification of an annotation into nested dicts of literal values."""
    result = {}
    if modification is None:
        return result
    for argument in getattr(modification, "arguments", []):
        element = argument.value
        name = getattr(getattr(element, "component", None), "name", None)
        if name is None:
            continue
        value = None
        for mod in getattr(element, "modifications", []):
            if hasattr(mod, "arguments"):
                value = _annotation_to_dict(mod)
            elif hasattr(mod, "value"):
                value = mod.value
        result[name] = value
    return result


class Library:
    """A parsed Modelica library folder.

    Parameters
    ----------
    path : path-like, optional
        Folder that contains the top-level packages (default: :func:`library_path`).
    """

    def __init__(self, path: str | os.PathLike | None = None):
        from pymoca import parser

        self.path = library_path(path)
        self.files = sorted(p for p in self.path.rglob("*.mo") if p.is_file())
        if not self.files:
            raise ModelicaError(f"{self.path}: no .mo files in the Modelica library folder")
        self.tree = None
        for file in self.files:
            text = file.read_text(encoding="utf-8")
            try:
                parsed = parser.parse(text)
            except parser.ModelicaSyntaxError as exc:
                line, col = exc.lineno or 0, exc.offset or 1  # pymoca columns are 1-based
                raise ModelicaError(f"{file}:{line}:{col}: syntax error: {exc.msg}") from None
            except Exception as exc:  # pymoca raises plain exceptions for unsupported constructs
                raise ModelicaError(f"{file}: cannot parse: {exc}") from None
            if self.tree is None:
                self.tree = parsed
            else:
                self.tree.extend(parsed)
        self.entries = {entry.name: entry for entry in self._walk(self.tree, "")}

    def digest(self) -> str:
        """SHA-256 over every source file (name and content): changes when any source changes."""
        if getattr(self, "_digest", None):
            return self._digest
        h = hashlib.sha256()
        for file in self.files:
            h.update(str(file.relative_to(self.path)).encode())
            h.update(b"\0")
            h.update(file.read_bytes())
        self._digest = h.hexdigest()
        return self._digest

    def _file_of(self, name: str) -> Path:
        parts = name.split(".")
        for n in range(len(parts), 0, -1):
            stem = self.path.joinpath(*parts[:n])
            for candidate in (stem.with_suffix(".mo"), stem / "package.mo"):
                if candidate.is_file():
                    return candidate
        return self.path

    def _walk(self, node, prefix):
        for name, cls in node.classes.items():
            full = f"{prefix}{name}"
            yield ModelEntry(
                name=full,
                kind=cls.type,
                partial=bool(cls.partial),
                description=cls.comment or "",
                file=self._file_of(full),
                annotation=_annotation_to_dict(cls.annotation),
            )
            yield from self._walk(cls, full + ".")

    def models(self, exported_only: bool = False) -> list[ModelEntry]:
        """Non-partial models and blocks, in library order."""
        found = [e for e in self.entries.values() if e.kind in ("model", "block") and not e.partial]
        return [e for e in found if e.exported] if exported_only else found

    def entry(self, name: str) -> ModelEntry:
        """The model called ``name``; :class:`UnknownModelError` lists the known models otherwise."""
        entry = self.entries.get(name)
        if entry is None or entry.kind not in ("model", "block") or entry.partial:
            known = "\n  ".join(e.name for e in self.models())
            raise UnknownModelError(f"unknown model '{name}'; the library at {self.path} has:\n  {known}")
        return entry


@lru_cache(maxsize=4)
def load_library(path: str | None = None) -> Library:
    """Parse the library once per process and path."""
    return Library(path)
