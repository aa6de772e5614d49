"""The Modelica library on disk: parsing, the list of models, their annotations.

One class per file (Modelica Standard Library layout): ``Bicycle/Components/RearFrame.mo``
holds ``Bicycle.Components.SecondOrderRearFrame``; a ``package.mo`` holds its package and any classes
nested in it.

A file that cannot be read or parsed (not UTF-8, empty, a syntax error, a class that does not
match the file's place in the library) does not stop the others: its error is recorded in
:attr:`Library.errors` and raised only for the models that are defined in it or use its
classes (:meth:`Library.entry`, :meth:`Library.broken_class`).
"""
from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from cosim.errors import ModelicaError, UnknownModelError
from cosim import __version__
from cosim.compiler import pymoca_patches


def _bundled_library() -> Path:
    """``cosim/modelica`` of an installed wheel, else ``modelica/`` of the source tree (editable
    install or checkout): setup.py maps the one to the other."""
    package = Path(__file__).resolve().parents[1]
    installed = package / "modelica"
    return installed if (installed / "Bicycle").is_dir() else package.parent / "modelica"


DEFAULT_LIBRARY = _bundled_library()

CLASS_KEYWORDS = r"(?:model|block|class|connector|record|package|function|type|operator)"


def library_path(path: str | os.PathLike | None = None) -> Path:
    """One folder that holds top-level Modelica packages, checked.

    Taken from ``path``, else the environment variable ``COSIM_MODELICA_PATH`` (one folder),
    else the library that ships with the package (``modelica/`` of the source tree).

    Raises
    ------
    ModelicaError
        If the folder does not exist or is a file.
    """
    chosen = path or os.environ.get("COSIM_MODELICA_PATH") or DEFAULT_LIBRARY
    chosen = Path(chosen).resolve()
    if _is_file(chosen):
        raise ModelicaError(f"{chosen}: is a file; the Modelica library must be a folder of packages")
    if not _is_dir(chosen):
        raise ModelicaError(f"{chosen}: Modelica library folder not found")
    return chosen


def _is_file(path: Path) -> bool:
    """``path.is_file()``, False where the name cannot be a file at all (too long, a NUL byte)."""
    try:
        return path.is_file()
    except (OSError, ValueError):
        return False


def _is_dir(path: Path) -> bool:
    """``path.is_dir()``, False where the name cannot be a folder at all (too long, a NUL byte)."""
    try:
        return path.is_dir()
    except (OSError, ValueError):
        return False


def library_paths(path=None) -> list[Path]:
    """The folders searched for top-level Modelica packages, in order (like ``MODELICAPATH``):
    the user's folders, then the library that ships with the package, always last.

    ``path`` is one folder, several folders joined by ``os.pathsep`` (``mine:tests/oracle``) or a
    list of folders; None takes ``COSIM_MODELICA_PATH`` (which may list several folders the same
    way), else only the shipped library. Each folder is checked as in :func:`library_path`; a
    folder named twice counts once (the shipped library named among the user's folders still
    comes last). A top-level package (``Bicycle``) is taken from the first folder that holds it:
    a user's ``Bicycle`` hides the shipped one (see :func:`library_files`).

    Raises
    ------
    ModelicaError
        If a folder does not exist or is a file.
    """
    if path is None:
        path = os.environ.get("COSIM_MODELICA_PATH") or ""
    items = list(path) if isinstance(path, (list, tuple)) else [path]
    parts = [part for item in items for part in
             (str(item).split(os.pathsep) if isinstance(item, str) else [item]) if str(part).strip()]
    shipped = DEFAULT_LIBRARY.resolve()
    folders = [folder for folder in dict.fromkeys(library_path(part) for part in parts) if folder != shipped]
    return folders + [shipped]


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
        cosim = self.annotation.get("__Cosim")
        return isinstance(cosim, dict) and cosim.get("export") is True

    @property
    def experiment(self) -> dict:
        """The ``experiment(...)`` annotation as a dict (StartTime, StopTime, Tolerance, Interval).

        Raises
        ------
        ModelicaError
            If an entry is not a finite literal number, Tolerance or Interval is not positive or
            StopTime is not after StartTime (the FMU's default experiment must make sense).
        """
        import math

        found = self.annotation.get("experiment", {})

        def refuse(what: str) -> ModelicaError:
            where = self._where(r"\bexperiment\b")
            return ModelicaError(f"{where}: {self.name}: annotation {what}")

        if not isinstance(found, dict):
            raise refuse(f"experiment must be experiment(...), got {_describe_value(found)}")
        found = dict(found)
        for key, value in found.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise refuse(f"experiment({key} = ...) must be a finite literal number, got {_describe_value(value)}")
        for key in ("Tolerance", "Interval"):
            if key in found and found[key] <= 0:
                raise refuse(f"experiment({key} = {found[key]}) must be positive")
        if found.get("StopTime", math.inf) <= found.get("StartTime", 0.0):
            raise refuse(f"experiment: StopTime = {found['StopTime']} must be after "
                         f"StartTime = {found.get('StartTime', 0.0)}")
        return found

    def _where(self, pattern: str) -> str:
        file, line = locate_in_file(self.file, self.name, pattern)
        return f"{file}:{line}" if line else str(file)


def _describe_value(value) -> str:
    if isinstance(value, (str, bool, int, float)) or value is None:
        return repr(value)
    return f"an expression ({type(value).__name__})"


def _signed_literal(node):
    """``-1`` (pymoca: unary minus of a literal) as the number; anything else unchanged."""
    operator, operands = getattr(node, "operator", None), getattr(node, "operands", None)
    if operator in ("-", "+") and operands and len(operands) == 1:
        value = getattr(operands[0], "value", None)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return -value if operator == "-" else value
    return node


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
            else:  # an expression such as StopTime = 2*5: kept, refused where a number is needed
                value = _signed_literal(mod)
        result[name] = value
    return result


def decode_source(file: Path, data: bytes) -> str:
    """The text of a Modelica file (UTF-8, as the Modelica specification requires).

    Raises
    ------
    ModelicaError
        Naming the file, and for undecodable bytes their line, column and byte offset.
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        column = exc.start - (before.rfind(b"\n") + 1) + 1
        raise ModelicaError(
            f"{file}:{line}:{column}: not UTF-8: byte 0x{data[exc.start]:02x} at byte offset {exc.start} "
            "cannot be decoded (Modelica files must be UTF-8; re-save the file as UTF-8)") from None
    if not text.strip():
        raise ModelicaError(f"{file}: empty file (a Modelica file must define one class)")
    return text.removeprefix("\ufeff")


def _parse_text(text: str):
    """pymoca's parse of one file's text; without its on-disk cache if that cannot be written
    (an unwritable home or XDG_CACHE_HOME must not stop the compiler)."""
    import sqlite3

    from pymoca import parser

    pymoca_patches.apply()  # the parser patches must see every file
    try:
        return parser.parse_text(text, cache_db=pymoca_patches.PARSE_CACHE_DB)
    except (OSError, sqlite3.Error):
        return parser.parse_text(text, bypass_cache=True)


def expected_class(path: Path, file: Path) -> tuple[str, str]:
    """``(within, class name)`` a file must declare at its place in the library (MSL layout)."""
    parts = list(file.relative_to(path).with_suffix("").parts)
    if parts[-1] == "package":
        parts = parts[:-1]
    return ".".join(parts[:-1]), parts[-1] if parts else ""


_NOT_CODE = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/', re.DOTALL)


def code_only(text: str) -> str:
    """``text`` with strings and comments blanked out (newlines kept, so lines still count)."""
    return _NOT_CODE.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), text)


def line_of(text: str, pattern: str, start: int = 0) -> int | None:
    """1-based line of the first match of ``pattern`` in ``text`` from ``start`` (None if none)."""
    match = re.compile(pattern, re.MULTILINE).search(text, start)
    return text.count("\n", 0, match.start()) + 1 if match else None


def locate_in_file(file: Path, class_name: str, pattern: str) -> tuple[Path, int | None]:
    """``(file, line)`` of the first match of ``pattern`` in the code (not in strings or comments)
    of ``file`` from the definition of ``class_name`` on (line None if there is none)."""
    try:
        text = code_only(file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError):
        return file, None
    short = class_name.rsplit(".", 1)[-1]
    start = re.search(rf"\b{CLASS_KEYWORDS}\s+{re.escape(short)}\b", text)
    return file, line_of(text, pattern, start.start() if start else 0)


class Library:
    """A parsed Modelica library folder.

    Parameters
    ----------
    path : path-like, list of path-like, optional
        Folder that contains top-level packages, or several such folders (a list, or joined by
        ``os.pathsep``), e.g. a folder of packages that use the shipped library; the shipped
        library is always searched after them (see :func:`library_paths`; default: only
        ``COSIM_MODELICA_PATH`` and the shipped library).

    Attributes
    ----------
    path : Path
        The first folder (where a class name that is found nowhere is reported).
    paths : list of Path
        Every folder, in search order (the shipped library last).
    files : list of Path
        Every ``.mo`` file of the library (without those of a top-level package that an earlier
        folder holds too, see :func:`library_files`).
    errors : dict of Path to ModelicaError
        The files that could not be read or parsed, with their error (``file:line:col``).
    """

    def __init__(self, path: str | os.PathLike | None = None):
        from pymoca import ast

        self.paths = library_paths(path)
        self.path = self.paths[0]
        self._roots = library_files(self.paths)  # file -> the library folder it lies in
        self.files = list(self._roots)
        empty = next((folder for folder in self.paths if not any(folder.rglob("*.mo"))), None)
        if empty is not None:  # most likely the wrong folder was named
            raise ModelicaError(f"{empty}: no .mo files in the Modelica library folder")
        self.errors: dict[Path, ModelicaError] = {}
        self.tree = ast.Tree()
        defined: dict[str, Path] = {}  # class name -> the file that defines it
        for file in self.files:
            try:
                parsed = self._parse_file(file)
                names = self._defined_classes(file, parsed)
                twice = next((n for n in names if n in defined), None)
                if twice:
                    raise ModelicaError(f"{file}: class '{twice}' is defined a second time "
                                        f"(first in {defined[twice]}); remove one of the two")
            except ModelicaError as exc:
                self.errors[file] = exc
                continue
            defined.update(dict.fromkeys(names, file))
            self.tree.extend(parsed)
        self.entries = {entry.name: entry for entry in self._walk(self.tree, "")}

    def _parse_file(self, file: Path):
        from pymoca import parser

        try:
            data = file.read_bytes()
        except OSError as exc:
            raise ModelicaError(f"{file}: cannot read: {exc.strerror or exc}") from None
        text = decode_source(file, data)
        try:
            parsed = _parse_text(text)
        except parser.ModelicaSyntaxError as exc:
            line, col = exc.lineno or 0, exc.offset or 1  # pymoca columns are 1-based
            raise ModelicaError(f"{file}:{line}:{col}: syntax error: {exc.msg}") from None
        except RecursionError:
            raise ModelicaError(f"{file}: cannot parse: expressions nested too deeply") from None
        except Exception as exc:  # pymoca raises plain exceptions for unsupported constructs
            raise ModelicaError(f"{file}: cannot parse: {exc}") from None
        self._check_place(file, text, parsed)
        return parser.file_to_tree(parsed)

    def _defined_classes(self, file: Path, tree) -> list[str]:
        """Names of the classes the file itself defines (its class and the classes nested in
        it), not the enclosing packages its ``within`` names."""
        from pymoca import ast

        within, name = expected_class(self._roots[file], file)
        node, prefix = tree, ""
        for part in within.split(".") if within else []:
            node, prefix = node.classes[part], f"{prefix}{part}."
        found = []
        # an ast.Tree starts with the built-in classes (Real, ...): not classes of the file
        builtin = set(ast.Tree().classes) if not within else set()

        def walk(cls, full):
            found.append(full)
            for child_name, child in cls.classes.items():
                walk(child, f"{full}.{child_name}")

        for class_name, cls in node.classes.items():
            if class_name not in builtin:
                walk(cls, f"{prefix}{class_name}")
        return found

    def _check_place(self, file: Path, text: str, parsed) -> None:
        """A file must hold the one class its path names, ``within`` its folder's package."""
        within, name = expected_class(self._roots[file], file)
        declared_within = ".".join(parsed.within[0].to_tuple()) if parsed.within else ""
        classes = list(parsed.classes)
        if not classes:
            raise ModelicaError(f"{file}: defines no class (expected '{name}')")
        if not name:  # a package.mo at the top of the library folder: no place to check
            return
        if declared_within != within:
            line = line_of(text, r"^\s*within\b") or 1
            expected = f"within {within};" if within else "within;"
            raise ModelicaError(f"{file}:{line}: '{expected}' expected for a file at this place in the library, "
                                f"found 'within {declared_within};'" if parsed.within else
                                f"{file}:{line}: '{expected}' expected as the first statement")
        if classes != [name]:
            line = line_of(text, rf"\b{CLASS_KEYWORDS}\s+{re.escape(classes[0])}\b") or 1
            raise ModelicaError(f"{file}:{line}: the file must define exactly the class '{name}' "
                                f"(its file name), found {', '.join(repr(c) for c in classes)}")

    def digest(self) -> str:
        """SHA-256 over every source file (name and content): changes when any source changes."""
        if getattr(self, "_digest", None):
            return self._digest
        self._digest = _files_digest(self.paths, self._roots)
        return self._digest

    def relative_name(self, file: Path) -> str:
        """The name of a library file relative to its library folder; prefixed by the folder's
        position (``1:BicycleOracle/Whipple.mo``) for every folder after the first."""
        return _relative_name(self.paths, self._roots, file)

    def _file_of(self, name: str) -> Path:
        parts = name.split(".")
        for n in range(len(parts), 0, -1):
            for root in self.paths:
                stem = root.joinpath(*parts[:n])
                for candidate in (stem.with_suffix(".mo"), stem / "package.mo"):
                    if candidate in self._roots:  # a file of the library (not one hidden by an earlier folder)
                        return candidate
        return self.path

    def file_of(self, class_name: str) -> Path:
        """The file that defines ``class_name`` (or its innermost enclosing package)."""
        return self._file_of(class_name)

    def locate(self, class_name: str, pattern: str) -> tuple[Path, int | None]:
        """The file of ``class_name`` and the line of the first match of the regular expression
        ``pattern`` inside its definition (None if there is none)."""
        return locate_in_file(self._file_of(class_name), class_name, pattern)

    def where(self, candidates: list[tuple[str, str]]) -> tuple[str, str]:
        """``(file:line, class name)`` of the first ``(class name, pattern)`` that matches, else
        the file of the first class and that class."""
        for class_name, pattern in candidates:
            file, line = self.locate(class_name, pattern)
            if line is not None:
                return f"{file}:{line}", class_name
        first = candidates[0][0] if candidates else ""
        return str(self._file_of(first) if first else self.path), first

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

    def broken_classes(self) -> dict[str, Path]:
        """Class name -> file for every file that did not parse (the class its path names)."""
        found = {}
        for file in self.errors:
            within, name = expected_class(self._roots[file], file)
            if name:
                found[f"{within}.{name}" if within else name] = file
        return found

    def broken_class(self, name: str, scope: str = "") -> tuple[str, Path] | None:
        """The broken class (and its file) that ``name``, looked up from ``scope``, refers to.

        Modelica looks a name up in the enclosing scopes from the innermost outwards; every
        candidate ``scope[:k].name`` that is, or lies inside, a class of a broken file counts.
        """
        broken = self.broken_classes()
        if not broken:
            return None
        parts = scope.split(".") if scope else []
        for n in range(len(parts), -1, -1):
            candidate = ".".join(parts[:n] + [name]) if n else name
            for cls, file in broken.items():
                if candidate == cls or candidate.startswith(cls + "."):
                    return cls, file
        return None

    def broken_error(self, name: str, scope: str = "", user: str | None = None) -> ModelicaError | None:
        """The error to report when ``user`` needs ``name`` and it lies in a broken file."""
        hit = self.broken_class(name, scope)
        if hit is None:
            return None
        cls, file = hit
        need = f"{user} is defined in this file" if user in (None, cls) or user.startswith(cls + ".") \
            else f"{user} uses {cls}, which is defined in this file"
        return ModelicaError(f"{self.errors[file]} ({need})")

    def models(self, exported_only: bool = False) -> list[ModelEntry]:
        """Non-partial models and blocks, in library order."""
        found = [e for e in self.entries.values() if e.kind in ("model", "block") and not e.partial]
        return [e for e in found if e.exported] if exported_only else found

    def entry(self, name: str) -> ModelEntry:
        """The model called ``name``.

        Raises
        ------
        ModelicaError
            If ``name`` is defined in a file that did not parse (the file's error).
        UnknownModelError
            Otherwise, if there is no such model; the message lists the known models.
        """
        entry = self.entries.get(name)
        if entry is not None and entry.kind in ("model", "block") and not entry.partial:
            return entry
        if entry is None:
            broken = self.broken_error(name, user=name)
            if broken is not None:
                raise broken
            problem = f"unknown model '{name}'"
        elif entry.partial:
            problem = f"'{name}' is a partial {entry.kind} ({entry.file}): extend it in a model to build it"
        else:
            problem = f"'{name}' is a {entry.kind} ({entry.file}), not a model or block"
        known = "\n  ".join(e.name for e in self.models())
        where = os.pathsep.join(map(str, self.paths))
        raise UnknownModelError(f"{problem}; the library at {where} has:\n  {known}")



# --------------------------------------------------------------------------- without parsing
# `cosim list`, `cosim info MODEL` and the up-to-date check of an FMU need the library's digest,
# not its parse: these functions read the files only (no pymoca, no CasADi is imported).

def top_level_class(file: Path, root: Path) -> str:
    """The top-level class that ``file`` of the library folder ``root`` belongs to: the package
    folder ``Name/`` it lies in, or ``Name`` of a file ``Name.mo`` directly in ``root``."""
    parts = file.relative_to(root).parts
    return parts[0] if len(parts) > 1 else file.stem


def library_files(paths: list[Path]) -> dict[Path, Path]:
    """Every ``.mo`` file of the library folders ``paths`` (sorted per folder) -> its folder.

    As with ``MODELICAPATH`` (Modelica Language Specification, section 13.3.3), a top-level class
    (a package folder ``Name/`` or a file ``Name.mo``) is taken from the first folder that holds
    it: the files of the same top-level class in later folders are left out, so a user's folder
    with its own ``Bicycle`` package hides the shipped one as a whole. A folder nested in another
    listed folder counts as part of the outer one.
    """
    roots: dict[Path, Path] = {}
    taken: set[str] = set()  # the top-level classes of the folders before
    for root in paths:
        found = set()
        for file in sorted(p for p in root.rglob("*.mo") if p.is_file()):
            if file in roots:
                continue
            top = top_level_class(file, root)
            if top in taken:
                continue
            found.add(top)
            roots[file] = root
        taken |= found
    return roots


def _relative_name(paths: list[Path], roots: dict[Path, Path], file) -> str:
    root = roots.get(Path(file))
    if root is None:
        return str(file)
    index = paths.index(root)
    relative = str(Path(file).relative_to(root))
    return f"{index}:{relative}" if index else relative


def _files_digest(paths: list[Path], roots: dict[Path, Path]) -> str:
    h = hashlib.sha256()
    for file in roots:
        h.update(_relative_name(paths, roots, file).encode())
        h.update(b"\0")
        try:
            h.update(file.read_bytes())
        except OSError:  # recorded in Library.errors; an unreadable file still changes the digest
            h.update(b"\0unreadable")
    return h.hexdigest()


def library_digest(path=None) -> str:
    """:meth:`Library.digest` of the library at ``path`` (as for :func:`library_paths`),
    computed from the files alone, without parsing them.

    Raises
    ------
    ModelicaError
        If a folder does not exist or is a file.
    """
    paths = library_paths(path)
    return _files_digest(paths, library_files(paths))


def tool_versions() -> dict:
    """Versions of cosim, pymoca, CasADi and Python, from the installed distributions' metadata
    (importing pymoca and CasADi to ask them would take most of a second)."""
    import platform
    from importlib import metadata

    def version(name: str) -> str:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return "missing"

    return {"cosim": __version__, "pymoca": version("pymoca"), "casadi": version("casadi"),
            "python": platform.python_version()}


@lru_cache(maxsize=1)
def compiler_digest() -> str:
    """Changes whenever the compiler (``cosim/compiler/*.py``), the FMU runtime
    (``cosim/runtime/*.[ch]``) or the tools behind them (:func:`tool_versions`) change; the same
    value as :func:`cosim.compiler.build.compiler_digest`, without importing pymoca or CasADi."""
    import json

    h = hashlib.sha256(json.dumps(tool_versions(), sort_keys=True).encode())
    here = Path(__file__).resolve().parent
    runtime = here.parent / "runtime"
    for path in sorted(list(here.glob("*.py")) + list(runtime.glob("*.[ch]"))):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def sources_digest(path=None) -> str:
    """What the manifest of an FMU built by cosim records as ``sources_digest``: the digest of
    the library's files and of the compiler (:func:`library_digest`, :func:`compiler_digest`)."""
    return hashlib.sha256((library_digest(path) + compiler_digest()).encode()).hexdigest()


def fmu_up_to_date(model_name: str, fmu: Path, path=None, fmi_version: str = "2") -> bool:
    """True if ``fmu`` was built by cosim from ``model_name`` as an FMU of ``fmi_version`` ("2"
    or "3") and the library at ``path`` and compiler exactly as they are now (no source file, no
    part of the compiler changed): the fast path of :func:`cosim.compiler.build.build_model`,
    answered without parsing the library and without importing pymoca or CasADi. False means
    "not known to be up to date" (the build decides), never an error.
    """
    import json
    import zipfile

    try:
        with zipfile.ZipFile(fmu) as archive:
            manifest = json.loads(archive.read("documentation/build.json"))
        expected = sources_digest(path)
    except (OSError, KeyError, zipfile.BadZipFile, ValueError):
        return False
    return (isinstance(manifest, dict) and manifest.get("model") == model_name
            and manifest.get("fmi_version", "2") == str(fmi_version)
            and manifest.get("sources_digest") == expected)


def load_library(path=None) -> Library:
    """Parse the library once per process and path (one folder, or several as for
    :class:`Library`)."""
    return _load_library(tuple(map(str, path)) if isinstance(path, (list, tuple)) else path)


@lru_cache(maxsize=4)
def _load_library(path) -> Library:
    return Library(list(path) if isinstance(path, tuple) else path)


load_library.cache_clear = _load_library.cache_clear  # callers clear the cache after editing files
