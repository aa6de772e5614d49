"""A thin layer over FMPy for one FMI 2.0 or 3.0 FMU: open it safely, extract once, instantiate as ME or
CS, address variables by name. Every command, linearization, validation and the co-simulation
master go through :func:`read_fmu` / :class:`FMU`, so an FMU file is checked in one place:

- it is a regular file (not a folder, a FIFO or a device) and a zip archive (not random bytes,
  not truncated);
- no member name could land outside the extraction folder (``../x``, ``/abs``, ``C:x``,
  backslashes, symbolic links) and the unpacked size is bounded (no zip bomb);
- ``modelDescription.xml`` exists, is well-formed XML without a DOCTYPE, declares an FMI version
  the caller runs (:func:`check_fmi_version`: FMI 2.0 by default, ``ALL_FMI_VERSIONS`` where a
  command handles FMI 3) and passes FMPy's schema and consistency checks (under
  :func:`lenient_reading` or ``lenient=True``, FMPy's findings become warnings and the FMU is read
  as ``read_model_description(validate=False)`` reads it; the checks above stay strict);
- at instantiation, the binary for this platform exists and loads.

Any failure raises :class:`cosim.errors.FMUError` naming the file and the problem.
"""
from __future__ import annotations

import os
import re
import shutil
import stat
import tempfile
import warnings
import zipfile
from contextlib import contextmanager
import zlib
from ctypes import byref, c_double, c_uint
from pathlib import Path
from typing import NamedTuple

import numpy as np

from cosim.errors import FMUError, OutputError
from cosim.outputs import check_input_file, make_temporary_folder

#: The FMI versions a command runs unless it says otherwise (see :func:`check_fmi_version`).
SUPPORTED_FMI_VERSIONS = ("2.0",)
#: The FMI versions this layer opens and instantiates (:class:`FMU` with ``versions=``); a
#: command passes them once it handles FMI 3 (docs/design/fmi3.md).
ALL_FMI_VERSIONS = ("2.0", "3.0")
#: The FMI versions whose model descriptions are read (``cosim info``; FMPy checks them against
#: the standard's schema).
READABLE_FMI_VERSIONS = ALL_FMI_VERSIONS
#: The end of the refusal of a model description that fails FMPy's checks (the verbs that open FMUs take --lenient).
LENIENT_HINT = "; use --lenient to run it anyway"
#: Largest total unpacked size of an FMU's members [bytes]; beyond it the archive is refused.
MAX_UNPACKED_BYTES = 2 * 1024**3
MODEL_DESCRIPTION = "modelDescription.xml"
#: Most fmi2NewDiscreteStates/fmi3UpdateDiscreteStates calls of an initial event iteration (a
#: guard against an FMU that always asks for another one).
MAX_EVENT_ITERATIONS = 1000

_DESCRIPTIONS: dict[tuple, tuple] = {}  # (path, size, mtime) -> (model description, FMPy's findings)
_WARNED: set[tuple] = set()  # keys whose findings were reported as warnings in this process
_LENIENT: list = []  # the warning callbacks of the open lenient_reading scopes (innermost last)


@contextmanager
def lenient_reading(enabled: bool = True, warn=None):
    """Within this scope, read FMUs whose model description fails FMPy's validation (``enabled``).

    Each finding is reported once per file and process as ``warn("FMU: PATH: FINDING")``
    (default: :func:`warnings.warn`); the safety checks (member names, sizes, well-formed XML,
    FMI version) stay strict. ``enabled=False`` leaves an enclosing scope in force, so a
    function taking ``lenient=False`` does not undo a command's ``--lenient``.
    """
    if not enabled:
        yield
        return
    _LENIENT.append(warn)
    try:
        yield
    finally:
        _LENIENT.pop()


def _warn(message: str) -> None:
    callback = next((w for w in reversed(_LENIENT) if w is not None), None)
    if callback is None:
        warnings.warn(message, stacklevel=3)
    else:
        callback(message)
_EXTRACTED: dict[tuple, str] = {}  # (path, size, mtime) -> unzip folder


def _key(path: Path) -> tuple:
    status = path.stat()
    return str(path.resolve()), status.st_size, status.st_mtime_ns


def unsafe_member(info: zipfile.ZipInfo) -> str | None:
    """Why a zip member may not be extracted (None: it is safe).

    FMI 2.0 (section 2.3) requires relative paths with forward slashes; anything else could
    write outside the extraction folder."""
    name = info.filename
    if "\x00" in name:
        return "contains a NUL character"
    if "\\" in name:
        return "uses backslashes (FMI requires forward slashes)"
    if name.startswith("/") or re.match(r"^[A-Za-z]:", name):
        return "is an absolute path"
    if ".." in name.split("/"):
        return "points outside the FMU ('..')"
    if stat.S_ISLNK(info.external_attr >> 16):
        return "is a symbolic link"
    return None


def check_fmi_version(path: Path, version: str | None, versions: tuple[str, ...] = SUPPORTED_FMI_VERSIONS) -> None:
    """Refuse every FMI version not in ``versions`` (default: 2.0, the one this package runs): the
    one place that decides which FMUs are run, and which are only read (READABLE_FMI_VERSIONS).

    Raises
    ------
    FMUError
        For FMI 1.0, FMI 3.x (not supported yet where not read only) or a missing/unknown
        ``fmiVersion``.
    """
    if version in versions:
        return
    if version is None or not version.strip():
        raise FMUError(f"{path}: modelDescription.xml has no fmiVersion attribute")
    runs = " and ".join(versions)
    if version.startswith("3."):
        readable = " (`cosim info` reads its model description)" if version in READABLE_FMI_VERSIONS else ""
        raise FMUError(f"{path}: FMI {version} FMUs are not supported yet (this command runs FMI {runs}){readable}")
    raise FMUError(f"{path}: FMI version '{version}' is not supported (this command runs FMI {runs})")


def _open_archive(path: Path) -> zipfile.ZipFile:
    check_input_file(path, FMUError, str(path), "FMU file", "an")  # a FIFO or /dev/zero would never end
    try:
        archive = zipfile.ZipFile(path)
    except zipfile.BadZipFile:
        raise FMUError(f"{path}: not an FMU: not a zip archive (random bytes or a truncated file)") from None
    except (OSError, ValueError) as exc:  # unreadable, or a corrupt central directory
        raise FMUError(f"{path}: cannot read the FMU: {exc}") from None
    try:
        total = 0
        for info in archive.infolist():
            why = unsafe_member(info)
            if why:
                raise FMUError(f"{path}: unsafe member name '{info.filename}' in the archive ({why}); "
                               "refusing to extract it")
            total += info.file_size
        if total > MAX_UNPACKED_BYTES:
            raise FMUError(f"{path}: the archive would unpack to {total / 1024**3:.1f} GiB "
                           f"(more than {MAX_UNPACKED_BYTES / 1024**3:.0f} GiB); refusing to extract it")
    except BaseException:
        archive.close()
        raise
    return archive


def _model_description_root(path: Path, archive: zipfile.ZipFile):
    from lxml import etree

    if MODEL_DESCRIPTION not in archive.namelist():
        raise FMUError(f"{path}: not an FMU: no {MODEL_DESCRIPTION} in the archive")
    try:
        data = archive.read(MODEL_DESCRIPTION)
    except (zipfile.BadZipFile, zlib.error, OSError, EOFError, NotImplementedError) as exc:
        raise FMUError(f"{path}: cannot unpack {MODEL_DESCRIPTION}: {exc}") from None
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        where = "" if "line" in str(exc.msg) else f" (line {exc.lineno})"
        raise FMUError(f"{path}: {MODEL_DESCRIPTION} is not well-formed XML: {exc.msg}{where}") from None
    if root.getroottree().docinfo.doctype:
        raise FMUError(f"{path}: {MODEL_DESCRIPTION} has a DOCTYPE declaration, which FMI does not allow")
    if root.tag != "fmiModelDescription":
        raise FMUError(f"{path}: {MODEL_DESCRIPTION}: the root element is <{root.tag}>, "
                       "not <fmiModelDescription>")
    return root


def read_fmu(path: str | os.PathLike, versions: tuple[str, ...] = SUPPORTED_FMI_VERSIONS, lenient: bool = False,
             runnable: bool = True):
    """The checked model description of an FMU file (cached per file version) of one of the FMI
    ``versions`` (default: the ones this package runs).

    Parameters
    ----------
    lenient : bool
        Read a model description that fails FMPy's schema or consistency checks anyway, each
        finding a warning (as within :func:`lenient_reading`); the other checks stay strict.
    runnable : bool
        Require a Model Exchange or Co-Simulation interface (False: also an FMU of FMI 3
        Scheduled Execution only, for describing it).

    Returns
    -------
    fmpy.model_description.ModelDescription

    Raises
    ------
    FMUError
        If the file is missing, not a zip archive, has unsafe member names, lacks or has a broken
        ``modelDescription.xml``, is not FMI 2.0 or fails FMPy's model-description checks (not
        lenient: the message names the findings and ``--lenient``); with ``runnable``, an FMU of
        FMI 3 Scheduled Execution only (named as not supported).
    """
    path = Path(path)
    lenient = lenient or bool(_LENIENT)
    with _open_archive(path) as archive:
        key = _key(path)
        if key in _DESCRIPTIONS:
            md, problems = _DESCRIPTIONS[key]
            check_fmi_version(path, md.fmiVersion, versions)
        else:
            root = _model_description_root(path, archive)
            check_fmi_version(path, root.get("fmiVersion"), versions)
            md, problems = _read_description(path)
            scheduled = getattr(md, "scheduledExecution", None) is not None
            if md.modelExchange is None and md.coSimulation is None and not scheduled:
                raise FMUError(f"{path}: {MODEL_DESCRIPTION} declares neither ModelExchange nor CoSimulation")
            if md.fmiVersion.startswith("3."):
                _fmi3_capabilities(md, root)
            _DESCRIPTIONS[key] = (md, problems)
    if runnable and md.modelExchange is None and md.coSimulation is None:
        raise FMUError(f"{path}: {md.modelName} is an FMI 3 Scheduled Execution FMU (clocked model partitions), "
                       "which is not supported: cosim runs Model Exchange and Co-Simulation FMUs")
    if problems and not lenient:
        raise FMUError(f"{path}: {_invalid(problems)}{LENIENT_HINT}")
    if problems and key not in _WARNED:
        _WARNED.add(key)
        for problem in problems:
            _warn(f"FMU: {path}: {MODEL_DESCRIPTION}: {problem}")
    return md


def _invalid(problems: list[str]) -> str:
    more = f" (and {len(problems) - 3} more)" if len(problems) > 3 else ""
    return f"{MODEL_DESCRIPTION} is invalid: {'; '.join(problems[:3])}{more}"


def _read_description(path: Path) -> tuple:
    """FMPy's reading of the model description and its validation findings (one line each): the
    description as ``validate=False`` reads it where FMPy's checks find problems."""
    from fmpy.model_description import ValidationError, read_model_description

    problems: list[str] = []
    try:
        try:
            md = read_model_description(str(path), validate=True)
        except ValidationError as exc:
            problems = [" ".join(str(p).split()) for p in exc.problems]
            try:
                md = read_model_description(str(path), validate=False)
            except Exception:  # defects that stop FMPy's reading too: --lenient would not help
                raise FMUError(f"{path}: {_invalid(problems)}") from None
    except FMUError:
        raise
    except KeyError as exc:
        if not (exc.args and isinstance(exc.args[0], int)):
            raise FMUError(f"{path}: cannot read {MODEL_DESCRIPTION}: KeyError: {exc}") from None
        # FMPy looks a value reference up (ModelStructure, derivative=...) that no variable has
        raise FMUError(f"{path}: {MODEL_DESCRIPTION} refers to value reference {exc.args[0]}, which no "
                       "variable has (or which two variables share)") from None
    except Exception as exc:  # FMPy raises bare Exception, ValueError, ... on odd XML
        raise FMUError(f"{path}: cannot read {MODEL_DESCRIPTION}: {type(exc).__name__}: {exc}") from None
    return md, problems


def _fmi3_capabilities(md, root) -> None:
    """Copy FMI 3's ``providesDirectionalDerivatives`` (plural) onto FMPy's ``providesDirectionalDerivative``.

    FMPy 0.3.32 copies only the attributes its classes name, and it names the FMI 2 spelling: an
    FMI 3 FMU read by it never provides directional derivatives (``providesAdjointDerivatives``
    has the FMI 3 spelling and is read). Every caller asks ``providesDirectionalDerivative``, for
    either version."""
    for tag, section in (("ModelExchange", md.modelExchange), ("CoSimulation", md.coSimulation)):
        element = root.find(tag)
        if section is not None and element is not None:
            section.providesDirectionalDerivative = element.get("providesDirectionalDerivatives") in ("true", "1")


def _extract_members(path: Path, folder: Path) -> None:
    """Unpack every member below ``folder`` (names were checked by :func:`_open_archive`)."""
    root = folder.resolve()
    with _open_archive(path) as archive:
        for info in archive.infolist():
            target = (root / info.filename).resolve()
            if target != root and root not in target.parents:  # belt and braces after unsafe_member
                raise FMUError(f"{path}: member '{info.filename}' would be extracted outside the FMU folder")
            if info.is_dir():
                try:
                    target.mkdir(parents=True, exist_ok=True)
                except OSError as exc:
                    raise OutputError(f"cannot extract the FMU '{path}' into '{folder}': "
                                      f"{exc.strerror or exc}") from None
                continue
            try:
                target.parent.mkdir(parents=True, exist_ok=True)
                with archive.open(info) as source, open(target, "wb") as sink:
                    shutil.copyfileobj(source, sink)
            except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError) as exc:
                raise FMUError(f"{path}: member '{info.filename}' is damaged: {exc}") from None
            except OSError as exc:  # a full disk, a quota: the temporary folder, not the FMU
                raise OutputError(f"cannot extract the FMU '{path}' into '{folder}': "
                                  f"{exc.strerror or exc}") from None


def _extract(path: Path, versions: tuple[str, ...] = SUPPORTED_FMI_VERSIONS, lenient: bool = False):
    """Check and unzip an FMU once per process (and file version), into a subfolder of this
    process's extraction folder (see :func:`_process_folder`)."""
    md = read_fmu(path, versions, lenient)
    key = _key(path)
    parent = _process_folder()  # first: forgets a forked parent's extractions
    if key not in _EXTRACTED:
        folder = tempfile.mkdtemp(prefix="fmu-", dir=parent)
        try:
            _extract_members(path, Path(folder))
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise
        _EXTRACTED[key] = folder
    return _EXTRACTED[key], md


_PROCESS_FOLDER: tuple[int, Path] | None = None  # (pid, folder) of this process's extractions


def _process_folder() -> Path:
    """The one ``cosim-fmu-<pid>-*`` folder holding every FMU this process unzipped, removed at
    exit as a whole. A forked child (which inherits the module state) makes its own, so it never
    removes its parent's; a process killed with SIGKILL leaves one folder, named after its pid."""
    global _PROCESS_FOLDER
    import atexit

    if _PROCESS_FOLDER is None or _PROCESS_FOLDER[0] != os.getpid():
        _EXTRACTED.clear()  # a forked child's inherited entries point into the parent's folder
        folder = make_temporary_folder("fmu")  # (removes the folders of ended processes)
        _PROCESS_FOLDER = (os.getpid(), folder)
        atexit.register(_remove_extracted, os.getpid(), folder)
    return _PROCESS_FOLDER[1]


def _remove_extracted(owner: int, folder: Path) -> None:
    """Remove this process's extraction folder (only in the process that made it)."""
    global _PROCESS_FOLDER
    if os.getpid() != owner:
        return
    shutil.rmtree(folder, ignore_errors=True)
    _EXTRACTED.clear()
    if _PROCESS_FOLDER is not None and _PROCESS_FOLDER[1] == folder:
        _PROCESS_FOLDER = None


def get_continuous_states(instance, nx: int) -> np.ndarray:
    """The continuous states of an FMPy Model Exchange instance."""
    x = (c_double * nx)()
    if nx:
        instance.getContinuousStates(x, nx)
    return np.array(x[:])


def get_state_derivatives(instance, nx: int) -> np.ndarray:
    """The time derivatives of the continuous states of an FMPy Model Exchange instance
    (``fmi2GetDerivatives`` or ``fmi3GetContinuousStateDerivatives``)."""
    dx = (c_double * nx)()
    if nx:
        get = getattr(instance, "getContinuousStateDerivatives", None) or instance.getDerivatives
        get(dx, nx)
    return np.array(dx[:])


def set_continuous_states(instance, x) -> None:
    """Set the continuous states of an FMPy Model Exchange instance."""
    x = np.asarray(x, float)
    if x.size:
        instance.setContinuousStates((c_double * x.size)(*x), x.size)


class FMULog:
    """Collects an FMU's log messages (instead of FMPy printing them to stdout).

    ``callbacks()`` gives the fmi2CallbackFunctions for ``fmi2Instantiate``; ``logger`` is the
    callable that ``fmpy.simulate_fmu(logger=...)`` takes."""

    def __init__(self, size: int = 50):
        from collections import deque

        self.messages: deque = deque(maxlen=size)  # (status, text)
        self._callbacks = None

    def logger(self, component, instance_name, status, category, message) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append((int(status), text.strip()))

    def fmi3_logger(self, instance_environment, status, category, message) -> None:
        """The ``fmi3LogMessageCallback`` (FMI 3 passes the formatted message, no instance name)."""
        self.logger(None, None, status, category, message)

    def callbacks(self):
        """fmi2CallbackFunctions whose logger is this object (kept alive with it)."""
        from ctypes import byref

        from fmpy import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)

        if self._callbacks is None:
            callbacks = fmi2CallbackFunctions()
            callbacks.logger = fmi2CallbackLoggerTYPE(self.logger)
            callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
            try:  # formats the FMU's printf-style messages
                from fmpy.logging import addLoggerProxy

                addLoggerProxy(byref(callbacks))
            except Exception:  # without the proxy the unformatted text is logged
                pass
            self._callbacks = callbacks
        return self._callbacks

    def last_error(self) -> str | None:
        """The last message with status Discard or worse (None if there is none)."""
        for status, text in reversed(self.messages):
            if status >= 2:
                return text
        return None


# FMPy types the FMI functions of every new instance anew from the Python signatures of its
# methods (inspect.getmembers + inspect.signature: 1.5 ms per instance, most of a co-simulation
# run's set-up, which a batch study pays per run). The types depend on the class only: FMPy's own
# code types them for the first instance of a class, and later instances take them from there.
def _typed_once(cls):
    """A subclass of an FMPy instance class whose FMI function types are found once per class."""
    load = cls._loadFunctions
    table: list[tuple] = []  # (name, argnames, argtypes, restype), from the first instance

    def _loadFunctions(self) -> None:
        if not table:
            load(self)
            table.extend((name, f.argnames, f.argtypes, f.restype) for name, f in self._functions.items())
            return
        for name, argnames, argtypes, restype in table:
            function = getattr(self.dll, name)
            function.argnames, function.argtypes, function.restype = argnames, argtypes, restype
            self._functions[name] = function

    return type(cls.__name__, (cls,), {"_loadFunctions": _loadFunctions, "__module__": cls.__module__})


_CLASSES: dict[tuple[str, str], type] = {}


def _instance_class(kind: str, version: str = "2.0") -> type:
    """FMPy's instance class of FMI ``version`` for ``kind`` (``cs``: FMU2Slave/FMU3Slave, ``me``:
    FMU2Model/FMU3Model), typed once (see _typed_once)."""
    key = (kind, version[:1])
    if key not in _CLASSES:
        if key[1] == "3":
            from fmpy.fmi3 import FMU3Model as Model, FMU3Slave as Slave
        else:
            from fmpy.fmi2 import FMU2Model as Model, FMU2Slave as Slave
        _CLASSES[key] = _typed_once(Slave if kind == "cs" else Model)
    return _CLASSES[key]


#: The setter and getter names of FMPy's instances by FMI version and variable type (FMI 3 has
#: one pair per type and width; the model descriptions name the types accordingly).
_SETTERS = {
    "2": {"Real": "setReal", "Integer": "setInteger", "Enumeration": "setInteger", "Boolean": "setBoolean",
          "String": "setString"},
    "3": {"Float64": "setFloat64", "Float32": "setFloat32", "Int64": "setInt64", "Int32": "setInt32",
          "Int16": "setInt16", "Int8": "setInt8", "UInt64": "setUInt64", "UInt32": "setUInt32",
          "UInt16": "setUInt16", "UInt8": "setUInt8", "Enumeration": "setInt64", "Boolean": "setBoolean",
          "String": "setString"},
}
class DirectCalls:
    """The FMI 2.0 Model Exchange functions of one instance called directly through ctypes, for
    loops that evaluate a model many times (an equilibrium search initializes it some 10^5 times).

    FMPy's methods convert Python lists to new ctypes arrays, build an event-info structure and
    go through a logging wrapper on every call (about 40 us of Python per initialization of a
    small model, six times the model's own work). Here the arrays are made once, the functions
    are FMPy's own typed ctypes functions of the instance, and a status worse than Warning
    raises :class:`fmpy.fmi1.FMICallException` as FMPy does: what the FMU computes is the same,
    call for call. FMPy's call logger (``fmiCallLogger``) does not see these calls.

    Parameters
    ----------
    fmu : FMU
        The FMU of ``instance`` (FMI 2.0).
    instance : fmpy.fmi2.FMU2Model
        A Model Exchange instance of :meth:`FMU.instantiate`.
    """

    def __init__(self, fmu: "FMU", instance):
        from fmpy.fmi1 import FMICallException
        from fmpy.fmi2 import fmi2EventInfo

        if fmu.is_fmi3:
            raise FMUError(f"{fmu.path}: direct calls are made to FMI 2.0 Model Exchange instances only")
        self.fmu, self.instance = fmu, instance
        self._exception = FMICallException
        self._component = instance.component
        self._f = instance._functions  # name -> ctypes function, typed by FMPy
        self.nx = len(fmu.description.derivatives)
        self._event = fmi2EventInfo()
        self._x = (c_double * self.nx)()
        self._dx = (c_double * self.nx)()
        self._setters: dict[tuple, tuple] = {}
        self._jacobian_refs = None

    def _call(self, name: str, *args) -> None:
        status = self._f[name](self._component, *args)
        if status > 1:  # fmi2Warning: FMPy raises for Discard, Error, Fatal
            raise self._exception(function=name, status=status)

    def real_setter(self, names) -> tuple:
        """A prepared ``fmi2SetReal`` of the Real variables ``names`` (in this order): the tuple
        ``(value references, values)`` of ctypes arrays for :meth:`set_reals`; fill the values
        (``values[k] = ...``) before each call. Made once per tuple of names.

        Raises
        ------
        KeyError
            For a name that is not a variable.
        FMUError
            For a variable that is not Real.
        """
        names = tuple(names)
        prepared = self._setters.get(names)
        if prepared is None:
            for name in names:
                if self.fmu.variables[name].type != "Real":
                    raise FMUError(f"{self.fmu.path}: variable '{name}' has type "
                                   f"{self.fmu.variables[name].type}, not Real")
            prepared = ((c_uint * len(names))(*(self.fmu.vr[n] for n in names)), (c_double * len(names))())
            self._setters[names] = prepared
        return prepared

    def set_reals(self, prepared: tuple) -> None:
        """``fmi2SetReal`` of a :meth:`real_setter` with its current values (one call)."""
        refs, values = prepared
        self._call("fmi2SetReal", refs, len(refs), values)

    def reset(self) -> None:
        self._call("fmi2Reset")

    def initialize(self, start_time: float = 0.0) -> None:
        """What :meth:`FMU.initialize_me` does (FMI 2): ``fmi2SetupExperiment`` (no tolerance, no
        stop time), ``fmi2Enter/ExitInitializationMode``, ``fmi2NewDiscreteStates`` until no
        further update is needed, ``fmi2EnterContinuousTimeMode``.

        Raises
        ------
        fmpy.fmi1.FMICallException
            A call the FMU refused.
        FMUError
            The FMU asks to terminate, or the event iteration does not end.
        """
        self._call("fmi2SetupExperiment", 0, 0.0, float(start_time), 0, 0.0)
        self._call("fmi2EnterInitializationMode")
        self._call("fmi2ExitInitializationMode")
        event = self._event
        for _ in range(MAX_EVENT_ITERATIONS):
            event.newDiscreteStatesNeeded = event.terminateSimulation = 0  # as FMPy's fresh structure
            self._call("fmi2NewDiscreteStates", byref(event))
            if event.terminateSimulation:
                raise FMUError(f"{self.fmu.path}: the FMU asks to terminate during its initial event iteration")
            if not event.newDiscreteStatesNeeded:
                break
        else:
            raise FMUError(f"{self.fmu.path}: the event iteration did not end after {MAX_EVENT_ITERATIONS} "
                           "fmi2NewDiscreteStates calls")
        self._call("fmi2EnterContinuousTimeMode")

    def get_states(self) -> np.ndarray:
        """The continuous states (a new array)."""
        if self.nx:
            self._call("fmi2GetContinuousStates", self._x, self.nx)
        return np.array(self._x[:])

    def set_states(self, x) -> None:
        x = np.asarray(x, float)
        if x.size != self.nx:
            raise ValueError(f"{self.nx} continuous states expected, got {x.size}")
        self._x[:] = x.tolist()
        if self.nx:
            self._call("fmi2SetContinuousStates", self._x, self.nx)

    def derivatives(self) -> np.ndarray:
        """The time derivatives of the continuous states (a new array)."""
        if self.nx:
            self._call("fmi2GetDerivatives", self._dx, self.nx)
        return np.array(self._dx[:])

    def state_jacobian(self) -> np.ndarray:
        """d(state derivatives)/d(states) at the current point, column by column from
        ``fmi2GetDirectionalDerivative`` with unit seeds (as FMPy's ``getDirectionalDerivative``
        with the seed ``e_k``)."""
        n = self.nx
        if self._jacobian_refs is None:
            md, vr = self.fmu.description, self.fmu.vr
            unknown = (c_uint * n)(*(vr[d.variable.name] for d in md.derivatives))
            known = (c_uint * n)(*(vr[d.variable.derivative.name] for d in md.derivatives))
            self._jacobian_refs = (unknown, known, (c_double * n)(), (c_double * n)())
        unknown, known, seed, column = self._jacobian_refs
        J = np.zeros((n, n))
        for k in range(n):
            seed[k] = 1.0
            try:
                self._call("fmi2GetDirectionalDerivative", unknown, n, known, n, seed, column)
            finally:
                seed[k] = 0.0
            J[:, k] = column[:]
        return J


class EventUpdate(NamedTuple):
    """What an event iteration (:meth:`FMU.event_iteration`) ended with."""

    terminate: bool  # the FMU asks to terminate the simulation (terminateSimulation)
    next_time: float | None  # its next time event [s], None if it announces none
    states_changed: bool  # the values of the continuous states changed (read them anew)


def indicators_crossed(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """Which event indicators changed their domain between two points: FMI 2.0 and 3.0 define a
    state event as an indicator going from ``z > 0`` to ``z <= 0`` or back."""
    return (np.asarray(before) > 0) != (np.asarray(after) > 0)


def locate_state_event(indicators_at, t0: float, t1: float, z0: np.ndarray, resolution: float) -> float:
    """The time of the first state event in ``(t0, t1]`` [s], by bisection to ``resolution`` [s].

    Parameters
    ----------
    indicators_at : callable
        ``indicators_at(t)``: the event indicators at ``t`` [s] (the caller brings its model
        there, e.g. by one integration step from ``t0``).
    t0, t1 : float
        The step [s]: no indicator crossed at ``t0`` (indicators ``z0``); one did by ``t1``.
    resolution : float
        Largest width of the bracket returned [s].

    Returns
    -------
    float
        The end of the final bracket: the earliest time found at which an indicator has crossed
        (the event is handled there, just after the crossing).
    """
    lo, hi = float(t0), float(t1)
    while hi - lo > resolution:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:  # no double between them
            break
        if np.any(indicators_crossed(z0, indicators_at(mid))):
            hi = mid
        else:
            lo = mid
    return hi


#: The getter names of FMPy's instances by FMI version and variable type (as :data:`_SETTERS`).
_GETTERS = {version: {t: "g" + name[1:] for t, name in setters.items()} for version, setters in _SETTERS.items()}
_CONVERT = {"Real": float, "Float64": float, "Float32": float, "Boolean": bool, "String": str}


class FMU:
    """An extracted FMU with its model description (unzipped once per process and file version).

    Parameters
    ----------
    path : path-like
        The ``.fmu`` file.
    versions : tuple of str
        The FMI versions accepted (see :func:`check_fmi_version`).
    lenient : bool
        Open it even if its model description fails FMPy's checks (see :func:`read_fmu`).
    """

    def __init__(self, path: str | Path, versions: tuple[str, ...] = SUPPORTED_FMI_VERSIONS, lenient: bool = False):
        self.path = Path(path)
        self.unzipdir, self.description = _extract(self.path, versions, lenient)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.variables.items()}

    @property
    def fmi_version(self) -> str:
        """``"2.0"`` or ``"3.0"`` (as in modelDescription.xml)."""
        return self.description.fmiVersion

    @property
    def is_fmi3(self) -> bool:
        return self.fmi_version.startswith("3.")

    def close(self):
        """Nothing to release: the unzipped FMU is shared within the process (see ``_extract``)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def names(self, causality: str) -> list[str]:
        """Variable names of one causality (input, output, parameter, calculatedParameter, local);
        not the FMI 3 aliases (other names of the same variables)."""
        return [v.name for v in self.description.modelVariables
                if v.causality == causality and getattr(v, "alias", None) is None]

    @property
    def states(self) -> list[str]:
        """Names of the continuous states, in the order of ModelStructure/Derivatives."""
        return [d.variable.derivative.name for d in self.description.derivatives]

    @property
    def derivatives(self) -> list[str]:
        return [d.variable.name for d in self.description.derivatives]

    def size(self, name: str) -> int:
        """The number of values of a variable: 1 for a scalar, the product of its ``<Dimension>``
        sizes for an FMI 3 array (a size given by a structural parameter takes that parameter's
        start value: structural parameters change only in Configuration Mode, which is not used)."""
        v = self.variables[name]
        n = 1
        for d in getattr(v, "dimensions", None) or ():
            if d.start not in (None, ""):
                n *= int(d.start)
            else:
                sizes = [x for x in self.description.modelVariables if x.valueReference == d.valueReference]
                if not sizes or sizes[0].start in (None, ""):
                    raise FMUError(f"{self.path}: the size of the array '{name}' refers to value reference "
                                   f"{d.valueReference}, which has no start value")
                n *= int(sizes[0].start)
        return n

    def elements(self, names: list[str]) -> list[str]:
        """The names of the values of ``names``: a scalar's name, ``x[1]``, ``x[2]``, ... for the
        elements of an FMI 3 array ``x`` (1-based, as in Modelica; its value reference is one)."""
        found = []
        for name in names:
            if getattr(self.variables[name], "dimensions", None):
                found += [f"{name}[{k}]" for k in range(1, self.size(name) + 1)]
            else:
                found.append(name)
        return found

    @property
    def n_states(self) -> int:
        """The number of continuous state values (FMI 3 arrays count each element)."""
        return sum(self.size(n) for n in self.states)

    def library(self, kind: str = "cs") -> Path:
        """The shared library of the interface ``kind`` for this platform.

        Raises
        ------
        FMUError
            If the FMU does not offer ``kind`` or has no binary for this platform.
        """
        from fmpy import platform, platform_tuple, sharedLibraryExtension

        if self.is_fmi3:  # FMI 3 names the folder by architecture-os (x86_64-linux)
            platform = platform_tuple

        section = self.description.coSimulation if kind == "cs" else self.description.modelExchange
        if section is None:
            raise FMUError(f"{self.path}: the FMU does not support "
                           f"{'Co-Simulation' if kind == 'cs' else 'Model Exchange'}")
        library = Path(self.unzipdir, "binaries", platform, section.modelIdentifier + sharedLibraryExtension)
        if not library.is_file():
            raise FMUError(f"{self.path}: no binary for this platform "
                           f"(binaries/{platform}/{library.name} is missing from the archive)")
        return library

    def instantiate(self, kind: str = "cs", name: str = "instance", log: "FMULog | None" = None):
        """An FMPy FMU2Slave/FMU3Slave (``cs``) or FMU2Model/FMU3Model (``me``), instantiated
        but not initialized (FMI 3 Co-Simulation without event mode, early return or intermediate
        update).

        The FMU's log messages go to ``log`` (a fresh :class:`FMULog` if None), available as
        ``instance.log``, so that an error message can quote what the FMU said.
        """
        cls = _instance_class(kind, self.fmi_version)
        library = self.library(kind)
        section = self.description.coSimulation if kind == "cs" else self.description.modelExchange
        log = log if log is not None else FMULog()
        try:
            instance = cls(guid=self.description.guid, unzipDirectory=self.unzipdir,
                           modelIdentifier=section.modelIdentifier, instanceName=name)
            if self.is_fmi3:
                instance.instantiate(loggingOn=False, logMessage=log.fmi3_logger)
            else:
                instance.instantiate(loggingOn=False, callbacks=log.callbacks())
        except AttributeError as exc:  # FMPy looks up every function of the standard: one is missing
            missing = re.search(r"undefined symbol: (\w+)", str(exc))
            what = missing.group(1) if missing else str(exc)
            raise FMUError(f"{self.path}: {library.name} does not export {what}, a function every FMI "
                           f"{self.fmi_version} binary must have") from None
        except Exception as exc:  # FMPy raises bare Exception for a library that does not load
            said = log.last_error()
            raise FMUError(f"{self.path}: cannot instantiate {library.name}: {exc}"
                           + (f" (the FMU says: {said})" if said else "")) from None
        instance.log = log
        return instance

    def provides_adjoint_derivatives(self, kind: str = "me") -> bool:
        """Whether the interface ``kind`` offers ``fmi3GetAdjointDerivative`` (never in FMI 2)."""
        section = self.description.coSimulation if kind == "cs" else self.description.modelExchange
        return bool(self.is_fmi3 and section is not None and getattr(section, "providesAdjointDerivatives", False))

    def initialize_me(self, instance, start_time: float = 0.0) -> None:
        """Initialize a Model Exchange instance at ``start_time`` [s] and enter Continuous-Time Mode.

        FMI 2: ``fmi2SetupExperiment``, ``fmi2Enter/ExitInitializationMode``; FMI 3:
        ``fmi3EnterInitializationMode(startTime)``, ``fmi3ExitInitializationMode``. Both then leave
        Event Mode the way the standard's state machine requires (:meth:`initial_event_iteration`)
        and call ``fmi2/fmi3EnterContinuousTimeMode``.

        Raises
        ------
        fmpy.fmi1.FMICallException
            A call the FMU refused (as FMPy raises it; the caller names the FMU).
        FMUError
            The FMU asks to terminate during the initial event iteration, or it does not end.
        """
        if self.is_fmi3:
            instance.enterInitializationMode(startTime=start_time)
        else:
            instance.setupExperiment(startTime=start_time)
            instance.enterInitializationMode()
        instance.exitInitializationMode()
        self.initial_event_iteration(instance)
        instance.enterContinuousTimeMode()

    def initial_event_iteration(self, instance) -> None:
        """Model Exchange after ``fmi2/fmi3ExitInitializationMode`` (Event Mode): call
        ``fmi2NewDiscreteStates`` (FMI 2) or ``fmi3UpdateDiscreteStates`` (FMI 3) until the FMU
        reports that no discrete state needs another update (:meth:`event_iteration`). Both
        standards allow ``EnterContinuousTimeMode`` only after this iteration, and FMUs (Dymola's)
        refuse it otherwise.

        Raises
        ------
        fmpy.fmi1.FMICallException
            The FMU refused the call.
        FMUError
            The FMU asks to terminate, or the iteration does not end after
            :data:`MAX_EVENT_ITERATIONS` calls.
        """
        if self.event_iteration(instance).terminate:
            raise FMUError(f"{self.path}: the FMU asks to terminate during its initial event iteration")

    def event_iteration(self, instance) -> "EventUpdate":
        """In Event Mode (after initialization, or after ``fmi2/fmi3EnterEventMode``): update the
        discrete states until the FMU needs no further update, or asks to terminate.

        Returns
        -------
        EventUpdate
            Whether the FMU asks to terminate, its next time event [s] (None: none announced) and
            whether the values of its continuous states changed (the caller reads them anew).

        Raises
        ------
        fmpy.fmi1.FMICallException
            The FMU refused the call.
        FMUError
            The iteration does not end after :data:`MAX_EVENT_ITERATIONS` calls.
        """
        update = instance.updateDiscreteStates if self.is_fmi3 else instance.newDiscreteStates
        name = "fmi3UpdateDiscreteStates" if self.is_fmi3 else "fmi2NewDiscreteStates"
        changed = False
        for _ in range(MAX_EVENT_ITERATIONS):
            needed, terminate, _, values_changed, time_defined, next_time = update()
            changed = changed or bool(values_changed)
            if terminate or not needed:
                return EventUpdate(bool(terminate), float(next_time) if time_defined else None, changed)
        raise FMUError(f"{self.path}: the event iteration did not end after {MAX_EVENT_ITERATIONS} {name} calls")

    def handle_event(self, instance) -> "EventUpdate":
        """A time, state or step event of a Model Exchange instance in Continuous-Time Mode, as
        both standards' state machines have it: ``fmi2/fmi3EnterEventMode``, the event iteration
        (:meth:`event_iteration`), then ``fmi2/fmi3EnterContinuousTimeMode`` unless the FMU asks
        to terminate (then the caller ends the run).

        Raises
        ------
        fmpy.fmi1.FMICallException, FMUError
            As :meth:`event_iteration`.
        """
        instance.enterEventMode()
        update = self.event_iteration(instance)
        if not update.terminate:
            instance.enterContinuousTimeMode()
        return update

    def set(self, instance, values: dict) -> None:
        """Set values by name, each with the setter of its type (FMI 2 or FMI 3): one call per
        type with all its value references (FMI defines that as setting them one by one; a
        co-simulation case sets some thirty parameters, and each call costs a ctypes round trip)."""
        setters = _SETTERS[self.fmi_version[:1]]
        groups: dict[str, tuple[list, list]] = {}
        for name, value in values.items():
            v = self.variables[name]
            if v.type not in setters:
                raise FMUError(f"{self.path}: variable '{name}' has type {v.type}, which cannot be set here")
            vrs, vals = groups.setdefault(setters[v.type], ([], []))
            vrs.append(v.valueReference)
            vals.append(_CONVERT.get(v.type, int)(value))
        for setter, (vrs, vals) in groups.items():
            getattr(instance, setter)(vrs, vals)

    def get(self, instance, names: list[str]) -> np.ndarray:
        """The values of variables of any numeric or Boolean type by name, as floats (one call
        per type, as :meth:`set`; FMI 3 64-bit integers beyond 2**53 lose digits).

        Raises
        ------
        FMUError
            For a type without a getter here (String, Binary, Clock).
        fmpy.fmi1.FMICallException
            The FMU refused a call.
        """
        getters = _GETTERS[self.fmi_version[:1]]
        values = np.zeros(len(names))
        groups: dict[str, tuple[list, list]] = {}
        arrays: dict[str, list[tuple[int, int]]] = {}  # an array's name -> (slot, element index)
        for k, name in enumerate(names):
            v, index = self.element(name)
            if v.type not in getters or v.type == "String":
                raise FMUError(f"{self.path}: variable '{name}' has type {v.type}, which cannot be read as a number")
            if index is not None:
                arrays.setdefault(v.name, []).append((k, index))
                continue
            slots, vrs = groups.setdefault(getters[v.type], ([], []))
            slots.append(k)
            vrs.append(v.valueReference)
        for getter, (slots, vrs) in groups.items():
            values[slots] = np.asarray(getattr(instance, getter)(vrs), dtype=float)
        for name, wanted in arrays.items():  # one call per array: its values in one value reference
            v = self.variables[name]
            array = np.asarray(getattr(instance, getters[v.type])([v.valueReference], nValues=self.size(name)),
                               dtype=float)
            for k, index in wanted:
                values[k] = array[index]
        return values

    def element(self, name: str):
        """The variable of ``name`` and, for an element ``x[k]`` of an FMI 3 array ``x`` (1-based,
        as :meth:`elements` names them), its 0-based index in the array's values (else None).

        Raises
        ------
        KeyError
            If ``name`` is neither a variable nor an element of an array variable.
        """
        v = self.variables.get(name)
        if v is not None:
            return v, None
        match = re.fullmatch(r"(.+)\[([1-9][0-9]*)\]", name)
        if match and getattr(self.variables.get(match.group(1)), "dimensions", None):
            index = int(match.group(2)) - 1
            if index < self.size(match.group(1)):
                return self.variables[match.group(1)], index
        raise KeyError(name)

    def get_real(self, instance, names: list[str]) -> np.ndarray:
        """The values of real (FMI 3: Float64) variables by name."""
        if not names:
            return np.zeros(0)
        vrs = [self.vr[n] for n in names]
        return np.array(instance.getFloat64(vrs) if self.is_fmi3 else instance.getReal(vrs))
