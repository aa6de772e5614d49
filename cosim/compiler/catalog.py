"""What the library offers: models with their interface (for `cosim list` and `cosim info MODEL`),
and what a model says about itself in its ``__Cosim`` annotation beyond ``export`` (its singular
configurations, :func:`singular_configurations`)."""
from __future__ import annotations

import hashlib
import json
import math
import os
import re
import sys
import tempfile
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

from cosim.compiler.library import (Library, code_only, compiler_digest, library_digest, library_files,
                                    library_paths, load_library, top_level_class)
from cosim.errors import CosimError, ModelicaError
from cosim.compiler.flatten import fewer_collections, flatten


#: Longest parameter value `cosim list` prints in full; longer ones (expressions) are shortened.
SHORT_VALUE = 40


def shorten(value, limit: int = SHORT_VALUE) -> str:
    """``value`` as text of at most ``limit`` characters: a longer one (typically a parameter
    defined by a long expression) is cut to its first ``limit - 3`` characters and ``...``.
    ``None`` (a value that is not known before the model is built) prints as ``?``."""
    text = "?" if value is None else str(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


@dataclass
class Signal:
    """A top-level input, output or parameter of a model."""

    name: str
    unit: str | None = None
    description: str = ""
    value: float | str | None = None
    min: float | None = None
    max: float | None = None
    type: str = "Real"  # the declared type: Real, Integer or Boolean


@dataclass
class ModelSummary:
    """The interface of one Modelica model."""

    name: str
    description: str
    exported: bool
    experiment: dict
    inputs: list[Signal] = field(default_factory=list)
    outputs: list[Signal] = field(default_factory=list)
    parameters: list[Signal] = field(default_factory=list)

    def to_dict(self) -> dict:
        """JSON-ready: full values, ``None`` (JSON ``null``) where a value is unknown."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> ModelSummary:
        """The summary :meth:`to_dict` made (as read back from the library index)."""
        groups = {key: [Signal(**signal) for signal in data[key]] for key in ("inputs", "outputs", "parameters")}
        return cls(data["name"], data["description"], data["exported"], dict(data["experiment"]), **groups)


def summarize(name: str, library: Library | None = None) -> ModelSummary:
    """Flatten ``name`` and list its top-level inputs, outputs and parameters, each with its
    declared type (Real, Integer or Boolean, also behind a derived type such as
    ``Bicycle.Units.Angle``), unit, description, ``min``/``max`` and, for parameters, value.

    Without ``library``, the model of the default library (the folders of ``$COSIM_MODELICA_PATH``
    and the shipped one) is taken from the library index if it is there and up to date (no parse, no
    pymoca or CasADi), else flattened and added to the index.

    Raises
    ------
    UnknownModelError, ModelicaError
        The same errors, with the same messages, whether or not the index is used.
    """
    if library is None:
        cached = _index_summary(name)
        if cached is not None:
            return cached
        library = load_library()
    from cosim.compiler.flatten import flatten  # deferred: pymoca and CasADi, only where the library is parsed

    entry = library.entry(name)
    return _summary(entry, flatten(library, name))


def _summary(entry, flat) -> ModelSummary:
    """The :class:`ModelSummary` of the library entry ``entry`` flattened to ``flat``."""
    name = entry.name
    values = {v.symbol.name(): v.value for v in flat.casadi.parameters}
    summary = ModelSummary(name, entry.description, entry.exported, entry.experiment)
    for decl in flat.declarations.values():
        if "." in decl.name:
            continue
        signal = Signal(decl.name, decl.unit, decl.description, None,
                        decl.min if isinstance(decl.min, (int, float)) else None,
                        decl.max if isinstance(decl.max, (int, float)) else None, decl.type)
        if "parameter" in decl.prefixes:
            value = values.get(decl.name)
            # a number, an expression of other parameters (its text), or unknown (None: JSON null)
            signal.value = value if value is None or isinstance(value, (int, float)) else str(value)
            summary.parameters.append(signal)
        elif "input" in decl.prefixes:
            summary.inputs.append(signal)
        elif "output" in decl.prefixes:
            summary.outputs.append(signal)
    return summary


def _warn_on_stderr(message: str) -> None:
    print(f"cosim: warning: {message}", file=sys.stderr)


def catalog(library: Library | None = None, exported_only: bool = False,
            warn: Callable[[str], None] | None = None) -> list[ModelSummary]:
    """Summaries of all (or only exported) models of the library that can be summarized.

    The others are left out with a warning of one line each: one per Modelica file that did
    not parse (naming the file, the position and the models left out because they are defined
    in it or use its classes), one per other model that cannot be flattened.

    Parameters
    ----------
    library : Library, optional
        A parsed library. Default: the folders of ``$COSIM_MODELICA_PATH`` and the shipped
        library, answered from its index (:func:`load_index`) unless a file or the compiler changed
        since the index was written, without importing pymoca or CasADi.
    exported_only : bool
        Only the models that `cosim build` exports.
    warn : callable, optional
        Called with each warning (default: printed as one line on stderr).

    Raises
    ------
    ModelicaError
        If the library folder does not exist or holds no ``.mo`` file.
    """
    if library is None:
        index = load_index()
    else:
        index = _records(library, exported_only)
    return _assemble(index, exported_only, warn or _warn_on_stderr)


def _records(library: Library, exported_only: bool = False, stored: dict | None = None) -> dict:
    """What `cosim list` reports of the library, JSON-ready: per model (library order) its
    summary, or the first line of why it cannot be summarized, or the file whose parse error
    leaves it out; per file that did not parse, the first line of its error. A model found in
    ``stored`` (name -> record, see :func:`_package_keys`) is taken from there."""
    models = []
    for entry in library.models(exported_only=exported_only):
        if stored and entry.name in stored:
            models.append(stored[entry.name])
            continue
        record = {"name": entry.name, "exported": entry.exported}
        try:
            record["summary"] = summarize(entry.name, library).to_dict()
        except CosimError as exc:
            text = str(exc)
            file = next((f for f, error in library.errors.items() if text.startswith(str(error))), None)
            if file is not None:
                record["broken_file"] = str(file)
            else:
                record["problem"] = text.splitlines()[0]
        models.append(record)
    errors = [[str(file), str(error).splitlines()[0]] for file, error in library.errors.items()]
    return {"models": models, "errors": errors}


def _assemble(index: dict, exported_only: bool, warn: Callable[[str], None]) -> list[ModelSummary]:
    """The summaries of :func:`catalog` from :func:`_records`, warning about the others."""
    left_out: dict = {file: [] for file, _ in index["errors"]}
    summaries = []
    for record in index["models"]:
        if exported_only and not record["exported"]:
            continue
        if "summary" in record:
            summaries.append(ModelSummary.from_dict(record["summary"]))
        elif "broken_file" in record:
            left_out.setdefault(record["broken_file"], []).append(record["name"])
        else:
            warn(f"{record['name']} is not listed: {record['problem']}")
    for file, error in index["errors"]:
        models = f"; not listed: {', '.join(left_out[file])}" if left_out[file] else ""
        warn(f"{error}{models}")
    return summaries


# --------------------------------------------------------------------------- the library index
# Summarizing a model flattens it (pymoca, CasADi): seconds per model, minutes for `cosim list`
# of the whole library. The summaries are therefore kept in an index file beside pymoca's parse
# cache, valid for exactly one state of the library's files and of the compiler.

#: Bumped whenever the layout of the index file changes.
INDEX_FORMAT = 1


def cache_folder() -> Path:
    """``$XDG_CACHE_HOME/cosim`` (default ``~/.cache/cosim``): where the library index is kept,
    beside pymoca's parse cache (``$XDG_CACHE_HOME/pymoca``)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "cosim"


def index_key(path=None) -> tuple[Path, str]:
    """``(index file, key)`` of the library at ``path`` (as for :func:`library_paths`).

    The file is named after the library folders (one index per library, overwritten when it
    changes); the key is the digest of the folders, of every ``.mo`` file (name and content), of
    the compiler and of the tools behind it (:func:`cosim.compiler.library.compiler_digest`).
    """
    paths = library_paths(path)
    folders = os.pathsep.join(map(str, paths))
    name = hashlib.sha256(folders.encode()).hexdigest()[:16]
    key = hashlib.sha256("\0".join([str(INDEX_FORMAT), folders, library_digest(paths),
                                      compiler_digest()]).encode()).hexdigest()
    return cache_folder() / f"library-index-{name}.json", key


def _read_index(file: Path, key: str) -> dict | None:
    """The index stored in ``file`` if it is valid for ``key``; None if it is absent, stale or
    damaged in any way (then the library is parsed again)."""
    try:
        data = json.loads(file.read_text(encoding="utf-8"))
        if not isinstance(data, dict) or data.get("key") != key:
            return None
        index = {"models": list(data["models"]), "errors": [(str(f), str(e)) for f, e in data["errors"]],
                 "complete": data["complete"] is True}
        return index if all(map(_valid_record, index["models"])) else None
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


def _valid_record(record) -> bool:
    """Whether a stored record holds what _assemble and _index_summary rely on.

    Raises
    ------
    KeyError, TypeError, ValueError, AttributeError
        Where it lacks a key or holds something else than JSON of the expected shape.
    """
    if not (isinstance(record["name"], str) and isinstance(record["exported"], bool)):
        return False
    if "summary" in record:
        ModelSummary.from_dict(record["summary"])
        if not isinstance(record.get("declarations", {}), dict):
            return False
        return all(isinstance(d, dict) and isinstance(d["name"], str)
                   for declared in record.get("declarations", {}).values() for d in declared)
    return isinstance(record.get("broken_file"), str) or isinstance(record.get("problem"), str)


# A model's summary depends on the files of its top-level package and of the top-level packages
# whose names that package's code mentions (and theirs, and so on), nothing else: the summaries are
# also kept per top-level package, so that a new or changed package costs the flattening of its
# own models only (`cosim list --library mine` flattens the user's models, not the shipped ones).

_IDENTIFIER = re.compile(r"'(?:[^'\\]|\\.)*'|[A-Za-z_][A-Za-z0-9_]*")


def _package_keys(path=None) -> dict[str, tuple[Path, str]]:
    """Top-level class of the library at ``path`` -> ``(file of its stored summaries, key)``.

    The key is the digest of the index format, the compiler, the class's folder and files, and
    the name, folder and files of every top-level class its code names, directly or through
    another one (a conservative reading: a name in an annotation or a comment-free string of
    code counts too).
    """
    paths = library_paths(path)
    files: dict[str, list[Path]] = {}
    places: dict[str, Path] = {}
    for file, root in library_files(paths).items():
        top = top_level_class(file, root)
        files.setdefault(top, []).append(file)
        places.setdefault(top, root / file.relative_to(root).parts[0])
    digests, named = {}, {}
    for top, members in files.items():
        h, code = hashlib.sha256(), []
        for file in members:
            h.update(str(file.relative_to(places[top])).encode() + b"\0")
            try:
                data = file.read_bytes()
            except OSError:  # reported by the parse; an unreadable file still changes the key
                data = b"\0unreadable"
            h.update(data + b"\0")
            code.append(code_only(data.decode("utf-8", "replace")))
        digests[top] = h.hexdigest()
        named[top] = set(_IDENTIFIER.findall("\n".join(code))) & files.keys()
    keys, compiler = {}, compiler_digest()
    for top in files:
        reached, todo = set(), [top]
        while todo:
            for other in named[todo.pop()] - reached:
                reached.add(other)
                todo.append(other)
        parts = [str(INDEX_FORMAT), compiler, top, str(places[top]), digests[top]]
        parts += [f"{other}\0{places[other]}\0{digests[other]}" for other in sorted(reached - {top})]
        name = hashlib.sha256(str(places[top]).encode()).hexdigest()[:16]
        keys[top] = (cache_folder() / f"library-package-{name}.json",
                     hashlib.sha256("\0".join(parts).encode()).hexdigest())
    return keys


def _read_package(file: Path, key: str) -> list[dict]:
    """The records stored in ``file`` if they are valid for ``key``, else none."""
    try:
        data = json.loads(file.read_text(encoding="utf-8"))
        if isinstance(data, dict) and data.get("key") == key and all(map(_valid_record, data["models"])):
            return list(data["models"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        pass
    return []


def _write_index(file: Path, key: str, index: dict) -> None:
    """Store ``index`` atomically (a temporary file renamed over the old one, so a concurrent
    reader sees the old or the new index, never half of one); silently skipped where the cache
    folder cannot be written (the index only saves time)."""
    try:
        file.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{file.name}.", dir=file.parent)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as out:
                json.dump({"key": key, **index}, out)
            os.replace(tmp, file)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError:
        pass


def load_index(path=None) -> dict:
    """The summaries of every model of the library at ``path`` (see :func:`_records`), from the
    index if it is up to date and complete, else by parsing the library (then stored as the
    index)."""
    file, key = index_key(path)
    index = _read_index(file, key)
    if index is None or not index["complete"]:
        # what a partial index knows of single models' FMUs (fmu_declarations) is kept
        known = {r["name"]: r["declarations"] for r in (index or {}).get("models", []) if "declarations" in r}
        packages = _package_keys(path)
        stored = {r["name"]: r for top, (store, pkey) in packages.items() for r in _read_package(store, pkey)
                  if r["name"].split(".", 1)[0] == top}
        index = {**_records(load_library(path), stored=stored), "complete": True}
        for record in index["models"]:
            record.pop("declarations", None)
            if record["name"] in known and "summary" in record:
                record["declarations"] = known[record["name"]]
        by_package: dict[str, list] = {top: [] for top in packages}
        for record in index["models"]:
            by_package.setdefault(record["name"].split(".", 1)[0], []).append(record)
        for top, (store, pkey) in packages.items():
            if any(r["name"] not in stored for r in by_package[top]):
                _write_index(store, pkey, {"models": [{k: v for k, v in r.items() if k != "declarations"}
                                                      for r in by_package[top]]})
        _write_index(file, key, index)
    return index


def _index_summary(name: str) -> ModelSummary | None:
    """The summary of ``name`` from the index of the default library (``$COSIM_MODELICA_PATH``
    and the shipped one); if the index lacks it, the model alone is parsed and summarized and
    its summary added to the index (so that `cosim info MODEL` after an edit costs one model, not
    the whole library). None where the parse path must decide: no such model, a partial class,
    a model that cannot be flattened (it raises the error there), an unusable library folder."""
    try:
        file, key = index_key()
    except CosimError:  # e.g. a library folder that does not exist: reported by the parse
        return None
    index = _read_index(file, key)
    record = next((r for r in index["models"] if r["name"] == name), None) if index else None
    if record is not None:
        return ModelSummary.from_dict(record["summary"]) if "summary" in record else None
    if index is not None and index["complete"]:
        return None  # not a model that can be summarized: the parse path reports why
    summary = summarize(name, load_library())  # raises for a name without a summary
    index = index or {"models": [], "errors": [], "complete": False}
    index["models"].append({"name": name, "exported": summary.exported, "summary": summary.to_dict()})
    _write_index(file, key, index)
    return summary


# --------------------------------------------------------------------------- what a user may set
# The variables a user may set before a run (``--param``, system files, matrix specs) are those
# of the model's FMU. For an FMU file they are read from its modelDescription.xml; for a model
# name from the modelDescription.xml that `cosim build` would write (the same description as the
# C tables, cosim.compiler.description), read by the same reader and kept in the library index:
# one rule (settable_role) over one description, before anything is built.

#: What :func:`settable_role` calls a calculated parameter (listed so that it can be refused by name).
CALCULATED = "calculated parameter"
#: A state's start value (``initial = "exact"``), and one that is the guess of the initial equations.
START_VALUE, START_GUESS = "start value", "start value (guess of the initial equations)"


def settable_role(causality: str, variability: str, initial: str | None, state_output: bool = False) -> str | None:
    """What a variable of a model description (FMI 2 or 3) is to a user who sets values before
    initialization, or None where it is neither settable nor a parameter.

    * ``parameter``, ``input``: the FMI causality (inputs are signals, refused as constants);
    * :data:`CALCULATED`: a calculated parameter (a ``final`` parameter, or one bound to an
      expression of others): computed by the FMU, never set;
    * :data:`START_VALUE`: a continuous local variable with an exact start value (the states of
      the FMUs built here), or an output that is a state (``state_output``) with one;
    * :data:`START_GUESS`: a continuous variable with ``initial = "approx"`` (a state solved from
      the initial equations: its start value is the guess of the Newton solve).
    """
    if causality in ("parameter", "input"):
        return causality
    if causality == "calculatedParameter":
        return CALCULATED
    if causality in ("local", "output") and variability == "continuous":
        if initial == "approx":
            return START_GUESS
        if initial == "exact" and (causality == "local" or state_output):
            return START_VALUE
    return None


def model_description(name: str, fmi_version: str = "2", library: Library | None = None) -> bytes:
    """The modelDescription.xml (FMI ``fmi_version``: "2" or "3") of the FMU that `cosim build`
    makes of the model ``name``, made as the build makes it (flattened, made explicit, described),
    without generating or compiling code. The GUID is left empty.

    Raises
    ------
    UnknownModelError, ModelicaError, ModelStructureError, ParameterError
        As :func:`cosim.compiler.build.build_model` would for the model.
    """
    return _model_description(library or load_library(), name, fmi_version)[1]


def _model_description(library: Library, name: str, fmi_version: str):
    """``(summary, modelDescription.xml)`` of the model ``name`` (:func:`summarize`,
    :func:`model_description`) from one flattening."""
    # deferred: pymoca and CasADi, only where a model is flattened
    from cosim.compiler.description import describe
    from cosim.compiler.model_description import model_description_xml
    from cosim.compiler.ode import make_explicit

    entry = library.entry(name)
    with fewer_collections():
        flat = flatten(library, name)
        summary = _summary(entry, flat)
        info = describe(entry, flat, make_explicit(flat))
    return summary, model_description_xml(info, "cosim", fmi_version)


def _index_record(name: str):
    """``(index file, key, index, record of name)`` of the default library; None where absent."""
    try:
        file, key = index_key()
    except CosimError:  # e.g. a library folder that does not exist: reported by the parse
        return None, None, None, None
    index = _read_index(file, key)
    record = next((r for r in index["models"] if r["name"] == name), None) if index else None
    return file, key, index, record


def indexed_declarations(name: str, fmi_version: str) -> list[dict] | None:
    """What :func:`fmu_declarations` stored in the library index for the model ``name`` of the
    default library and FMI ``fmi_version``, None if the index does not hold it (no parse)."""
    record = _index_record(name)[3]
    return record.get("declarations", {}).get(fmi_version) if record is not None else None


def fmu_declarations(name: str, fmi_version: str, read: Callable[[bytes], list[dict]],
                     refresh: bool = False) -> list[dict]:
    """``read(xml)`` of the :func:`model_description` of the model ``name`` of the default library
    (``$COSIM_MODELICA_PATH`` and the shipped library), kept in the library index: once the index
    holds it (:func:`indexed_declarations`), no parse, no pymoca, no CasADi. ``read`` turns the
    XML into JSON-ready records of the settable variables (see
    :func:`cosim.fmu.parameters.model_declarations`). ``refresh``: made and stored anew even if
    the index holds them (records its reader cannot use).

    Raises
    ------
    UnknownModelError, ModelicaError, ModelStructureError, ParameterError
        As :func:`model_description`.
    """
    file, key, index, record = _index_record(name)
    if record is not None and fmi_version in record.get("declarations", {}) and not refresh:
        return record["declarations"][fmi_version]
    summary, xml = _model_description(load_library(), name, fmi_version)
    declared = read(xml)
    if file is not None:
        index = index or {"models": [], "errors": [], "complete": False}
        if record is None:
            if index["complete"]:  # a complete index names every model: this one cannot be summarized
                return declared
            record = {"name": name, "exported": summary.exported, "summary": summary.to_dict()}
            index["models"].append(record)
        if "summary" in record:
            record.setdefault("declarations", {})[fmi_version] = declared
            _write_index(file, key, index)
    return declared


# --------------------------------------------------------------------------- singular configurations

@dataclass(frozen=True)
class Singularity:
    """A configuration where a model's equations are singular, as the model declares it::

        annotation(__Cosim(singular(delta(angle_deg = 90, tolerance_deg = 15,
                                          description = "..."))))

    The variable (an angle) is singular at ``+-angle`` (modulo a full turn); a run that fails
    with the variable within ``tolerance`` of it has reached the singularity (the exact singular
    value may depend on the other coordinates, hence the band).

    Attributes
    ----------
    model : str
        The class whose annotation declares it (the model itself or a class it extends).
    variable : str
        Name of the angle in the model (e.g. ``delta``).
    angle, tolerance : float
        Singular angle and band [rad].
    description : str
        What happens there (one sentence).
    quantity : str
        What the variable is, from its declaration's description (``"steer angle"`` from
        ``"Steer angle delta, positive steering right"``); empty if it has none.
    """

    model: str
    variable: str
    angle: float
    tolerance: float
    description: str
    quantity: str = ""

    def distance(self, value: float) -> float:
        """How far ``value`` [rad] is from ``+-angle`` (modulo 2 pi) [rad]; inf for a non-finite value."""
        if not math.isfinite(value):
            return math.inf
        wrapped = abs(math.remainder(value, 2.0 * math.pi))  # in [0, pi]
        return abs(wrapped - self.angle)

    def reached(self, value: float) -> bool:
        """True where ``value`` [rad] lies within the band of the singular angle."""
        return self.distance(value) <= self.tolerance


_SINGULAR_KEYS = {"angle_deg", "tolerance_deg", "description"}
_SINGULAR_PATTERN = r"\bsingular\b"


def singular_configurations(name: str, library: Library | None = None) -> tuple[Singularity, ...]:
    """The singular configurations a model declares (``__Cosim(singular(...))``), its own and those
    of the classes it extends (a variant ``extends Bicycle.Bicycles.Whipple(...)`` has the
    Whipple model's singularities); empty if it declares none.

    Raises
    ------
    UnknownModelError
        ``name`` is not a model of the library.
    ModelicaError
        A malformed annotation (``file:line``): each entry must be ``VARIABLE(angle_deg = A,
        tolerance_deg = T, description = "...")`` with literal numbers ``0 < A <= 180`` and
        ``0 < T < 90`` and a non-empty description.
    """
    library = library or load_library()
    library.entry(name)  # UnknownModelError for a name that is no model
    found: dict[str, Singularity] = {}
    classes = _self_and_bases(library, name)
    for cls in classes:
        entry = library.entries[cls]
        cosim = entry.annotation.get("__Cosim")
        declared = cosim.get("singular") if isinstance(cosim, dict) else None
        if declared is None:
            continue

        def refuse(why: str, entry=entry, cls=cls) -> ModelicaError:
            where = entry._where(_SINGULAR_PATTERN)
            return ModelicaError(f"{where}: {cls}: annotation __Cosim(singular(...)): {why}")

        if not isinstance(declared, dict) or not declared:
            raise refuse("expected singular(VARIABLE(angle_deg = ..., tolerance_deg = ..., "
                         "description = \"...\"), ...)")
        for variable, spec in declared.items():
            if not isinstance(spec, dict) or set(spec) != _SINGULAR_KEYS:
                got = sorted(spec) if isinstance(spec, dict) else spec
                raise refuse(f"{variable}(...) must give exactly {', '.join(sorted(_SINGULAR_KEYS))}; got {got!r}")
            angle, tolerance, text = spec["angle_deg"], spec["tolerance_deg"], spec["description"]
            for key, value, bounds in (("angle_deg", angle, "0 < angle_deg <= 180"),
                                       ("tolerance_deg", tolerance, "0 < tolerance_deg < 90")):
                number = not isinstance(value, bool) and isinstance(value, (int, float))
                if not number or not (0 < value <= 180 if key == "angle_deg" else 0 < value < 90):
                    raise refuse(f"{variable}({key} = ...) must be a literal number of degrees, "
                                 f"{bounds}, got {value!r}")
            if not isinstance(text, str) or not text.strip():
                raise refuse(f"{variable}(description = ...) must be a non-empty string")
            # the model's own declaration wins over an extended class's
            found.setdefault(variable, Singularity(cls, variable, math.radians(angle), math.radians(tolerance),
                                                   " ".join(text.split()), _quantity(library, classes, variable)))
    return tuple(found.values())


def _class_node(library: Library, name: str):
    node = library.tree
    for part in name.split("."):
        node = node.classes[part]
    return node


def _quantity(library: Library, classes: list[str], variable: str) -> str:
    """What ``variable`` is, from the description of its declaration in the nearest of ``classes``:
    the words before the variable's name in the first clause ("Steer angle delta, ..." -> "steer
    angle"), else the whole first clause; empty if it is declared without a description."""
    for cls in classes:
        symbol = getattr(_class_node(library, cls), "symbols", {}).get(variable)
        if symbol is None:
            continue
        clause = (symbol.comment or "").split(",", 1)[0].strip()
        words = clause.split()
        if variable in words:
            words = words[:words.index(variable)]
        text = " ".join(words)
        return text[:1].lower() + text[1:]
    return ""


def _self_and_bases(library: Library, name: str) -> list[str]:
    """``name`` and the library classes it extends, nearest first (each once)."""
    order, todo = [], [name]
    while todo:
        current = todo.pop(0)
        if current in order or current not in library.entries:
            continue
        order.append(current)
        try:
            node = _class_node(library, current)
        except KeyError:
            continue
        scope = current.split(".")[:-1]
        for clause in getattr(node, "extends", []) or []:
            parts, ref = [], getattr(clause, "component", None)
            while ref is not None:
                parts.append(ref.name)
                ref = ref.child[0] if getattr(ref, "child", None) else None
            # Modelica lookup: the enclosing scopes from the innermost outwards
            for depth in range(len(scope), -1, -1):
                candidate = ".".join(scope[:depth] + parts)
                if candidate in library.entries:
                    todo.append(candidate)
                    break
    return order
