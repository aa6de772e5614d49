"""A hostile corpus over every verb of the `cosim` command line: one clear answer, whatever comes in.

Families of cases are generated from tables (verbs x bad values): malformed, missing and odd option
values (NaN, inf, negative, huge, empty, unicode, very long names, unknown parameter names, wrong
types); files given where a file is read (missing, a directory, empty, binary garbage, truncated and
path-traversal zips, a FIFO, a symbolic link to /dev/zero, other encodings, CSV inputs with bad cells,
system TOML files with every kind of mistake, parameter TOML files); FMUs (garbage, foreign model
descriptions, FMI 1.0, a missing or foreign binary); outputs that cannot be written (a missing folder,
a path below a regular file, a name too long, places under /proc and /sys that refuse even root);
and commands interrupted by SIGINT or SIGTERM.

Every case is checked by :func:`check_answer`:

- the exit status is one the command documents (``cosim/cli.py``: 0, 1 for validate, compare and
  matrix, 2, 3 for run, 4 for simulate and run, 130), never the internal-error status 70;
- no traceback and no "internal error" on stderr;
- a failure prints exactly one line ``cosim VERB: error: ...`` (``incomplete:`` for status 4,
  ``interrupted`` for 130), first on stderr (a message may go on over lines of its own, such as
  the models of the library, but none starts with ``cosim``); argparse's ``usage:`` lines may
  precede a usage error; warnings are shown on stderr as from the command line;
- a refused command leaves nothing under its final output name, and no ``.partial`` file is left
  in the case's folder;
- no row is lost: a result written (complete or incomplete) has the rows its message reports;
- every case answers within :data:`LIMIT` seconds.

Most cases run in this process (:func:`conftest.cli_in_process`) under a watchdog that fails the
case when it does not answer in time. Cases whose failure could take the test process down with
them (reading /dev/zero into memory, an FMU binary called with a description that is not its own,
work that is unbounded if not refused) run in a subprocess with a time and memory limit.
"""
from __future__ import annotations

import hashlib
import io
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
import warnings
import zipfile
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from conftest import ROOT, cli_in_process, toml_value

# the quick run (-m 'not slow') leaves this module out: it compiles and runs defective or foreign FMUs
pytestmark = pytest.mark.slow

#: [s] a case that has not answered by then fails (a hang); subprocess cases get the same limit.
LIMIT = 30.0
#: [s] the limit of a case that gives a FIFO nobody writes as an input: the command must not wait
#: for a writer.
FIFO_LIMIT = 10.0
#: [bytes] address-space limit of a subprocess case: reading an endless file fails (MemoryError)
#: within seconds instead of exhausting the machine's memory.
MEMORY_LIMIT = 3 << 29

SIMPLE = "Bicycle.Bicycles.SelfStabilizing"  # one input T, parameters V, m, ...; outputs phi, delta, ...
WHIPPLE = "Bicycle.Bicycles.WhippleLinear"  # Meijaard parameters, inputs T_phi, T_delta, speed v
BENCHMARK = (ROOT / "cosim" / "params" / "benchmark.toml").read_text(encoding="utf-8")


# --- the properties ---------------------------------------------------------------------------


def allowed_status(verb: str) -> set[int]:
    """The exit statuses ``cosim VERB`` documents (cosim/cli.py): 0, 2 and 130 for every verb; 1 for
    the checking verbs, 3 for run (the bicycle fell), 4 for the verbs that write NAME.incomplete.csv."""
    allowed = {0, 2, 130}
    if verb in ("validate", "compare", "matrix"):
        allowed.add(1)
    if verb == "run":
        allowed.add(3)
    if verb in ("simulate", "run"):
        allowed.add(4)
    return allowed


def files_under(folder: Path) -> set[Path]:
    """Every file, link and special file under ``folder`` (relative paths)."""
    return {p.relative_to(folder) for p in folder.rglob("*") if not p.is_dir() or p.is_symlink()}


def result_rows(path: Path) -> int:
    """Rows of a result file: CSV lines after the header, or the length of a .npy array."""
    if path.suffix.lower() == ".npy":
        return len(np.load(path, allow_pickle=False))
    return sum(1 for line in path.read_text(encoding="utf-8").splitlines()[1:] if line.strip())


def _verb(argv: list[str]) -> str:
    return argv[0] if argv and not argv[0].startswith("-") else ""


def check_answer(argv: list[str], status: int, stdout: str, stderr: str, folder: Path, before: set[Path],
                 outputs: tuple[str, ...] = (), escape: str | None = None) -> None:
    """The properties every answer of ``cosim ARGV`` must have (see the module docstring).

    Parameters
    ----------
    argv : list of str
        The command line after ``cosim``.
    status, stdout, stderr
        Its exit status and output.
    folder : Path
        The case's folder (the working directory of the command).
    before : set of Path
        The files in ``folder`` before the command ran.
    outputs : tuple of str
        The final output names the command was asked to write that did not exist before it
        (relative to ``folder`` or absolute).
    escape : str, optional
        A name that archive members tried to write outside the extraction folder: it must not
        appear beside the folder, in the temporary folder or the working directory of the tests.
    """
    verb = _verb(argv)
    shown = (f"cosim {' '.join(a if len(a) < 200 else a[:60] + '...' for a in argv)}\nexit {status}\n"
             f"stdout:\n{stdout[-2000:]}\nstderr:\n{stderr[-3000:]}")
    known = verb in VERBS
    assert status in (allowed_status(verb) if known else {0, 2}), f"undocumented exit status\n{shown}"
    for text in (stderr, stdout):
        assert "Traceback" not in text and "internal error" not in text, shown
    lines = [line for line in stderr.splitlines() if line.strip()]
    prefix = f"cosim {verb}:" if known else "cosim:"
    if status != 0 and lines and lines[0].startswith("usage:"):  # argparse: usage lines, then its error
        assert status == 2, shown
        errors = [line for line in lines if line.startswith(("cosim:", "cosim "))]
        assert len(errors) == 1 and re.match(r"cosim( \S+)?: error: ", errors[0]) and errors[0] == lines[-1], shown
    elif status in (2, 4, 130):
        # the answer line comes first (after warnings); a message may go on over lines of its own
        # (e.g. the models of the library), but no other line speaks for the command
        kind = {2: "error", 4: "incomplete", 130: "interrupted"}[status]
        # (progress lines off a terminal, "cosim VERB: [2/3] ITEM", speak for no outcome)
        message = [line for line in lines if not line.startswith(f"{prefix} warning:")
                   and not re.match(rf"{re.escape(prefix)} \[\d+/\d+\] ", line)]
        answers = [line for line in message if line.startswith(f"{prefix} {kind}")]
        expected = 1
        if verb == "validate" and status == 2:  # one error line per target it cannot read
            expected = len(answers) if 1 <= len(answers) <= len(_validate_targets(argv)) else -1
        assert len(answers) == expected and message and message[0] in answers, \
            f"not exactly one '{prefix} {kind}' line, first\n{shown}"
        assert not [line for line in message if line.startswith("cosim") and line not in answers], shown
    after = files_under(folder)
    partial = sorted(str(p) for p in after if ".partial" in p.name)
    assert not partial, f"partial files left: {partial}\n{shown}"
    for name in outputs:  # (outputs that did not exist before the command)
        path = folder / name  # (an absolute name stays itself)
        if status in (0, 3):
            assert os.path.lexists(path), f"succeeded, yet {name} is missing\n{shown}"
        elif status != 1:
            assert not os.path.lexists(path), f"refused, yet {name} was written\n{shown}"
    _check_rows(verb, status, stdout, stderr, folder, shown)
    if escape:
        for place in {folder.parent, Path(tempfile.gettempdir()), Path(tempfile.gettempdir()).parent, ROOT,
                      Path.cwd(), Path("/tmp")}:
            assert not list(place.glob(f"{escape}*")), f"an archive member escaped into {place}\n{shown}"
        assert not [p for p in folder.rglob(f"{escape}*")], f"an archive member was extracted\n{shown}"


def _validate_targets(argv: list[str]) -> list[str]:
    targets, skip = [], False
    for a in argv[1:]:
        if skip:
            skip = False
        elif a == "--library":
            skip = True
        elif not a.startswith("-"):
            targets.append(a)
    return targets


def _check_rows(verb: str, status: int, stdout: str, stderr: str, folder: Path, shown: str) -> None:
    """No lost rows: the rows a result file holds are the rows the message reports."""
    if status in (0, 3):
        written = re.findall(r"wrote (\S+) \((?:\d+ steps, )?(\d+) rows", stdout)
        assert written or verb not in ("simulate", "run"), f"no result reported\n{shown}"
        for name, rows in written:
            path = Path(name) if Path(name).is_absolute() else folder / name
            assert path.exists() and result_rows(path) == int(rows), f"{name}: not {rows} rows\n{shown}"
    if status == 4:
        found = re.search(r"wrote the (\d+) rows up to t = \S+ s to ([^,;\s]+)", stderr)
        assert found, f"the incomplete result is not reported\n{shown}"
        path = Path(found.group(2)) if Path(found.group(2)).is_absolute() else folder / found.group(2)
        assert path.exists() and result_rows(path) == int(found.group(1)), f"rows lost\n{shown}"


# --- running a case ---------------------------------------------------------------------------


class NoAnswer(BaseException):
    """Raised by the watchdog; a BaseException, so that no handler of the command catches it."""


def _show_warning(message, category, filename, lineno, file=None, line=None):
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def _in_process(argv: list[str], folder: Path, limit: float) -> tuple[int, str, str]:
    """``cosim ARGV`` in this process; fails the test if it has not answered within ``limit`` s.

    Warnings go to the command's stderr as they would from the command line (Python's default
    filters: deprecations of other modules are not shown), not to pytest's warning summary."""
    def expire(signum, frame):
        raise NoAnswer()

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            for category in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
                warnings.simplefilter("ignore", category)
            warnings.showwarning = _show_warning
            return cli_in_process(argv, folder)
    except NoAnswer:
        pytest.fail(f"cosim {' '.join(argv)[:300]}: no answer within {limit:g} s (a hang)")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def _in_subprocess(argv: list[str], folder: Path, limit: float) -> tuple[int, str, str]:
    """``python -m cosim ARGV`` with ``limit`` s and MEMORY_LIMIT bytes; fails the test on a hang."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}  # (threads reserve memory)
    try:
        done = subprocess.run([sys.executable, "-m", "cosim", *argv], cwd=folder, capture_output=True, text=True,
                              env=env, timeout=limit, preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired:
        pytest.fail(f"cosim {' '.join(argv)[:300]}: no answer within {limit:g} s (a hang)")
    return done.returncode, done.stdout, done.stderr


class Case:
    """One command line of the corpus.

    Parameters
    ----------
    argv : list of str
        After ``cosim``; the tokens ``@simple``, ``@whipple`` (FMU paths) and ``@fmudir`` (the
        session's FMU folder) are replaced by paths of the test session.
    files : dict
        Name -> content made in the case's folder before the command: ``str`` (UTF-8 text, with
        the tokens replaced), ``bytes``, or a callable ``make(path, fmus)``.
    outputs : tuple of str
        The final output names (see :func:`check_answer`).
    isolate : bool
        Run in a subprocess with a time and memory limit (see the module docstring).
    escape : bool
        Archive members try to escape with the name ``escape_name(case id)``.
    limit : float, optional
        [s] Time to answer (default: FIFO_LIMIT if a file is a FIFO, else LIMIT).
    """

    def __init__(self, argv, files=None, outputs=(), isolate=False, escape=False, limit=None):
        self.argv, self.files, self.outputs = list(argv), dict(files or {}), tuple(outputs)
        self.isolate, self.escape = isolate, escape
        self.limit = limit if limit is not None else FIFO_LIMIT if fifo in self.files.values() else LIMIT


def escape_name(case_id: str) -> str:
    return "cosim-escape-" + hashlib.sha1(case_id.encode()).hexdigest()[:16]


def _tokens(fmus: dict) -> dict[str, str]:
    return {"@simple": str(fmus[SIMPLE]), "@whipple": str(fmus[WHIPPLE]), "@fmudir": os.environ["COSIM_FMU_DIR"]}


def _replace(text: str, tokens: dict[str, str]) -> str:
    for token, value in tokens.items():
        text = text.replace(token, value)
    return text


def answer(case: Case, case_id: str, folder: Path, fmus: dict) -> None:
    """Make the case's files in ``folder``, run it and check the answer."""
    tokens = _tokens(fmus)
    escape = escape_name(case_id) if case.escape else None
    for name, content in case.files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content(path, {**fmus, "escape": escape})
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(_replace(content, tokens), encoding="utf-8")
    argv = [_replace(a, tokens) for a in case.argv]
    before = files_under(folder)
    outputs = tuple(o for o in case.outputs if not os.path.lexists(folder / o))
    status, out, err = (_in_subprocess if case.isolate else _in_process)(argv, folder, case.limit)
    check_answer(argv, status, out, err, folder, before, outputs, escape)


# --- file makers ------------------------------------------------------------------------------


def fifo(path: Path, fmus: dict) -> None:
    """A named pipe that nobody writes: opening it for reading blocks."""
    os.mkfifo(path)


def dev_zero(path: Path, fmus: dict) -> None:
    """A symbolic link to /dev/zero: an endless file."""
    path.symlink_to("/dev/zero")


def directory(path: Path, fmus: dict) -> None:
    path.mkdir()


def dangling(path: Path, fmus: dict) -> None:
    path.symlink_to(path.parent / "nowhere" / "x")


def loop(path: Path, fmus: dict) -> None:
    path.symlink_to(path.name)


def text_in(encoding: str, text: str) -> bytes:
    return text.encode(encoding)


GARBAGE = bytes((i * 131 + 17) % 256 for i in range(4096))  # binary noise, every byte value


def zip_bytes(members: dict[str, bytes]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, data in members.items():
            archive.writestr(zipfile.ZipInfo(name), data)
    return buffer.getvalue()


def _members(fmu: Path) -> dict[str, bytes]:
    with zipfile.ZipFile(fmu) as archive:
        return {info.filename: archive.read(info) for info in archive.infolist()}


def fmu_variant(edit: Callable[[dict, dict], dict | bytes]) -> Callable:
    """A maker writing the simple FMU changed by ``edit(members, fmus)`` (members: name -> bytes;
    it returns new members, or the bytes of the whole file)."""
    def make(path: Path, fmus: dict) -> None:
        result = edit(_members(fmus[SIMPLE]), fmus)
        path.write_bytes(result if isinstance(result, bytes) else zip_bytes(result))

    return make


def _md(members: dict) -> str:
    return members["modelDescription.xml"].decode("utf-8")


def _with_md(members: dict, xml: str | bytes) -> dict:
    return {**members, "modelDescription.xml": xml.encode("utf-8") if isinstance(xml, str) else xml}


def _without(members: dict, prefix: str) -> dict:
    return {n: b for n, b in members.items() if not n.startswith(prefix)}


SO = f"binaries/linux64/{SIMPLE.replace('.', '_')}.so"

FOREIGN_FMI2 = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Foreign" guid="{00000000-0000-0000-0000-000000000001}"
    generationTool="Another Tool 9.1" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="Foreign" canHandleVariableCommunicationStepSize="true"/>
  <ModelExchange modelIdentifier="Foreign"/>
  <ModelVariables>
    <ScalarVariable name="x" valueReference="0" causality="local" variability="continuous" initial="exact">
      <Real start="1"/></ScalarVariable>
    <ScalarVariable name="der(x)" valueReference="1" causality="local" variability="continuous">
      <Real derivative="1"/></ScalarVariable>
    <ScalarVariable name="u" valueReference="2" causality="input" variability="continuous"><Real start="0"/>
      </ScalarVariable>
    <ScalarVariable name="y" valueReference="3" causality="output" variability="continuous" initial="calculated">
      <Real/></ScalarVariable>
    <ScalarVariable name="k" valueReference="4" causality="parameter" variability="fixed" initial="exact">
      <Integer start="3"/></ScalarVariable>
    <ScalarVariable name="label" valueReference="5" causality="parameter" variability="fixed" initial="exact">
      <String start="\u00e9t\u00e9"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="4"/></Outputs>
    <Derivatives><Unknown index="2"/></Derivatives>
    <InitialUnknowns><Unknown index="4"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""

FMI1 = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="1.0" modelName="Old" modelIdentifier="Old"
    guid="{11111111-1111-1111-1111-111111111111}" numberOfContinuousStates="1" numberOfEventIndicators="0">
  <ModelVariables>
    <ScalarVariable name="x" valueReference="0" variability="continuous" causality="internal">
      <Real start="1" fixed="true"/></ScalarVariable>
    <ScalarVariable name="der(x)" valueReference="1" variability="continuous" causality="internal"><Real/>
      </ScalarVariable>
  </ModelVariables>
  <Implementation><CoSimulation_StandAlone><Capabilities canHandleVariableCommunicationStepSize="true"/>
    </CoSimulation_StandAlone></Implementation>
</fmiModelDescription>
"""

FMI3 = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="Third" instantiationToken="{33333333-3333-3333-3333-333333333333}">
  <CoSimulation modelIdentifier="Third"/>
  <ModelExchange modelIdentifier="Third"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="y" valueReference="1" causality="output" variability="continuous" initial="exact" start="1"/>
  </ModelVariables>
  <ModelStructure><Output valueReference="1"/></ModelStructure>
</fmiModelDescription>
"""


def _traversal(members: dict, fmus: dict) -> dict:
    escape = fmus["escape"]
    return {**members, f"../{escape}": b"escaped", f"../../{escape}-2": b"escaped",
            f"binaries/../../{escape}-3": b"escaped", f"/tmp/{escape}-4": b"escaped"}


def _swap_binary(members: dict, fmus: dict) -> dict:
    other = _members(fmus[WHIPPLE])[f"binaries/linux64/{WHIPPLE.replace('.', '_')}.so"]
    return {**members, SO: other}


def _vr(old: str, new: str) -> Callable:
    """A maker of the simple FMU with its modelDescription.xml edited (the first ``old`` -> ``new``)."""
    return fmu_variant(lambda m, f: _with_md(m, _md(m).replace(old, new, 1)))


#: FMU file kind -> (maker or None for a file that is not there, the file name, calls the binary
#: with a description that is not its own: run in a subprocess for the verbs that load it).
FMU_KINDS = {
    "missing": (None, "model.fmu", False),
    "directory": (directory, "model.fmu", False),
    "empty": (b"", "model.fmu", False),
    "garbage": (GARBAGE, "model.fmu", False),
    "text": (b"not an FMU, just text\n", "model.fmu", False),
    "truncated-half": (fmu_variant(lambda m, f: f[SIMPLE].read_bytes()[:len(f[SIMPLE].read_bytes()) // 2]),
                       "model.fmu", False),
    "truncated-end": (fmu_variant(lambda m, f: f[SIMPLE].read_bytes()[:-30]), "model.fmu", False),
    "empty-zip": (zip_bytes({}), "model.fmu", False),
    "no-model-description": (fmu_variant(lambda m, f: _without(m, "modelDescription.xml")), "model.fmu", False),
    "traversal-members": (fmu_variant(_traversal), "model.fmu", False),
    "md-garbage": (fmu_variant(lambda m, f: _with_md(m, GARBAGE)), "model.fmu", False),
    "md-not-xml": (fmu_variant(lambda m, f: _with_md(m, "this is not XML")), "model.fmu", False),
    "md-truncated": (fmu_variant(lambda m, f: _with_md(m, _md(m)[:len(_md(m)) // 2])), "model.fmu", False),
    "md-empty": (fmu_variant(lambda m, f: _with_md(m, b"")), "model.fmu", False),
    "md-utf16": (fmu_variant(lambda m, f: _with_md(m, _md(m).encode("utf-16"))), "model.fmu", False),
    "md-no-version": (_vr('fmiVersion="2.0"', ""), "model.fmu", False),
    "md-version-9": (_vr('fmiVersion="2.0"', 'fmiVersion="9.0"'), "model.fmu", False),
    "md-vr-not-a-number": (_vr('valueReference="1"', 'valueReference="one"'), "model.fmu", False),
    "md-vr-huge": (_vr('valueReference="1"', 'valueReference="4294967295"'), "model.fmu", False),
    "md-guid-changed": (_vr('guid="{', 'guid="{0'), "model.fmu", False),
    "foreign-fmi2": (fmu_variant(lambda m, f: {"modelDescription.xml": FOREIGN_FMI2.encode()}), "model.fmu", False),
    "foreign-md-real-binary": (fmu_variant(lambda m, f: _with_md(m, FOREIGN_FMI2.replace(
        'modelIdentifier="Foreign"', f'modelIdentifier="{SIMPLE.replace(".", "_")}"'))), "model.fmu", True),
    "fmi1": (fmu_variant(lambda m, f: {"modelDescription.xml": FMI1.encode()}), "model.fmu", False),
    "fmi3-no-binary": (fmu_variant(lambda m, f: {"modelDescription.xml": FMI3.encode()}), "model.fmu", False),
    "no-binary": (fmu_variant(lambda m, f: _without(m, "binaries/")), "model.fmu", False),
    "binary-garbage": (fmu_variant(lambda m, f: {**m, SO: GARBAGE}), "model.fmu", False),
    "binary-empty": (fmu_variant(lambda m, f: {**m, SO: b""}), "model.fmu", False),
    "binary-other-platform": (fmu_variant(lambda m, f: {**_without(m, "binaries/"), SO.replace(
        "linux64", "win64").replace(".so", ".dll"): m[SO]}), "model.fmu", False),
    "binary-of-another-model": (fmu_variant(_swap_binary), "model.fmu", True),
    "fifo": (fifo, "model.fmu", False),
    "dev-zero": (dev_zero, "model.fmu", True),
    "symlink-loop": (loop, "model.fmu", False),
    "name-too-long": (None, "f" * 300 + ".fmu", False),
    "zip-suffix": (fmu_variant(lambda m, f: m), "model.zip", False),
}

#: the verbs that load an FMU's binary into the process (a foreign binary may crash it)
LOADS_BINARY = {"simulate", "linearize", "run"}
#: the kinds given to the system verbs too (the FMU of a component is read as the others read it)
SYSTEM_FMU_KINDS = {"missing", "directory", "garbage", "truncated-half", "traversal-members", "md-garbage",
                    "foreign-fmi2", "fmi1", "fmi3-no-binary", "no-binary", "binary-garbage", "md-guid-changed",
                    "binary-of-another-model", "fifo", "symlink-loop", "name-too-long"}


#: verb -> (argv with NAME for the FMU file, outputs, the FMU is a component of a system file)
FMU_VERBS = {
    "info": (["info", "NAME"], [], False),
    "validate": (["validate", "NAME"], [], False),
    "simulate": (["simulate", "NAME", "--stop-time", "0.2", "-o", "out.csv"], ["out.csv"], False),
    "linearize": (["linearize", "NAME"], [], False),
    "run": (["run", "system.toml", "-o", "out.csv"], ["out.csv"], True),
    "export-ssp": (["export-ssp", "system.toml", "-o", "out.ssp"], ["out.ssp"], True),
}
ONE_COMPONENT = 'connections = []\n[system]\nstop = 0.2\nstep = 0.1\n[components.bike]\nfmu = "{name}"\n'


def fmu_cases() -> list:
    params = []
    for kind, (make, name, foreign) in FMU_KINDS.items():
        for verb, (argv, outputs, in_system) in FMU_VERBS.items():
            if in_system and kind not in SYSTEM_FMU_KINDS or kind == "dev-zero" and verb not in ("info", "simulate"):
                continue
            files = {} if make is None else {name: make}
            if in_system:
                files["system.toml"] = ONE_COMPONENT.format(name=name)
            case = Case([name if a == "NAME" else a for a in argv], files, outputs, escape=kind == "traversal-members",
                        isolate=kind == "dev-zero" or (foreign and verb in LOADS_BINARY))
            params.append(pytest.param(case, id=f"{verb}-fmu-{kind}"))
    return params


# --- option values ----------------------------------------------------------------------------

#: odd values of a number option
NUMBERS = {"nan": "nan", "inf": "inf", "minus-inf": "-inf", "negative": "-1", "zero": "0", "huge": "1e308",
           "overflow": "1e400", "subnormal": "1e-320", "empty": "", "word": "abc", "arabic-digit": "\u0661",
           "comma-decimal": "0,5"}

RESULT_CSV = "time,phi,delta\n" + "".join(f"{k / 10:g},{0.01 * k:g},{0.02 * k:g}\n" for k in range(11))


def _blocker(path: Path, fmus: dict) -> None:
    path.write_text("a regular file, not a folder\n")


#: option -> (argv with VALUE, files, outputs, values that run unbounded work unless refused)
NUMBER_OPTIONS = {
    "simulate-stop-time": (["simulate", "@simple", "-o", "out.csv", "--stop-time", "VALUE"], {}, ["out.csv"],
                           {"huge"}),
    "simulate-step": (["simulate", "@simple", "-o", "out.csv", "--stop-time", "0.5", "--step", "VALUE"], {},
                      ["out.csv"], {"subnormal"}),
    "linearize-speed": (["linearize", "@whipple", "--speed", "VALUE"], {}, [], set()),
    "linearize-speeds": (["linearize", "@whipple", "--speeds", "VALUE"], {}, [], set()),
    "compare-tol": (["compare", WHIPPLE, "--speeds", "5", "--tol", "VALUE"], {}, [], set()),
    "compare-speeds": (["compare", WHIPPLE, "--speeds", "VALUE"], {}, [], set()),
    "analytic-speed": (["analytic", "--speed", "VALUE"], {}, [], set()),
    "animate-speed": (["animate", "r.csv", "-o", "out.html", "--speed", "VALUE"], {"r.csv": RESULT_CSV},
                      ["out.html"], set()),
    "matrix-workers": (["matrix", "missing.toml", "--workers", "VALUE", "-o", "out"], {}, ["out"], set()),
    "build-jobs": (["build", "-j", "VALUE", "-o", "@fmudir", "Bicycle.Sources.TorqueStep"], {}, [], set()),
    "app-port": (["app", "--port", "VALUE", "--export", "blocker/site"], {"blocker": _blocker}, [], set()),
    "simulate-param-V": (["simulate", "@simple", "--stop-time", "0.5", "-o", "out.csv", "--param", "V=VALUE"],
                         {}, ["out.csv"], set()),
    "linearize-param-v": (["linearize", "@whipple", "--param", "v=VALUE"], {}, [], set()),
    "linearize-input": (["linearize", "@whipple", "--input", "T_delta=VALUE"], {}, [], set()),
}


def number_cases() -> list:
    params = []
    for option, (argv, files, outputs, unbounded) in NUMBER_OPTIONS.items():
        for label, value in NUMBERS.items():
            case = Case([a.replace("VALUE", value) for a in argv], files, outputs, isolate=label in unbounded)
            params.append(pytest.param(case, id=f"{option}-{label}"))
    return params


#: odd ``--param`` assignments; {p} is a real parameter of the verb's model
ASSIGNMENTS = {
    "no-equals": "{p}", "empty-name": "=1", "empty": "", "value-empty": "{p}=", "unknown-name": "nope=1",
    "unicode-name": "{p}\u00e9=1", "long-name": "p" * 5000 + "=1", "long-value": "{p}=" + "1" * 5000,
    "double-equals": "{p}=1=2", "spaces": " {p} = 1 ", "bool-value": "{p}=true", "list-value": "{p}=[1,2]",
    "dotted-unknown": "a.b.c=1", "output-name": "phi=1", "input-name": "{input}=1",
    "fixed-step-negative": "solver.fixedStepSize=-1", "fixed-step-nan": "solver.fixedStepSize=nan",
    "newline-in-value": "{p}=1\n2", "state-start-nan": "{state}=nan", "calculated": "{calculated}=1",
}

#: verb -> (argv, outputs, a parameter, an input, a state, a calculated parameter of its model)
PARAM_VERBS = {
    "simulate": (["simulate", "@simple", "--stop-time", "0.5", "-o", "out.csv"], ["out.csv"], "V", "T", "frame.phi",
                 "frame.m"),
    "simulate-model": (["simulate", SIMPLE, "--stop-time", "0.5", "-o", "out.csv"], ["out.csv"], "V", "T",
                       "frame.phi", "frame.m"),
    "linearize": (["linearize", "@whipple"], [], "v", "T_delta", "phi", "rearWheel.r"),
    "compare": (["compare", WHIPPLE, "--speeds", "5"], [], "v", "T_delta", "phi", "rearWheel.r"),
    "animate": (["animate", "r.csv", "-o", "out.html"], ["out.html"], "w", "T", "phi", "rR"),
}


def assignment_cases() -> list:
    params = []
    for verb, (argv, outputs, p, input_name, state, calculated) in PARAM_VERBS.items():
        files = {"r.csv": RESULT_CSV} if verb == "animate" else {}
        for label, text in ASSIGNMENTS.items():
            assignment = text.format(p=p, input=input_name, state=state, calculated=calculated)
            case = Case([*argv, "--param", assignment], files, outputs)
            params.append(pytest.param(case, id=f"{verb}-param-{label}"))
    good = Case(["simulate", SIMPLE, "--stop-time", "0.5", "--param", "frame.phi=0.1", "-o", "out.csv"], {},
                ["out.csv"])
    params.append(pytest.param(good, id="simulate-model-param-state-start"))
    return params


# --- parameter files --------------------------------------------------------------------------


def _benchmark(**changes) -> str:
    """The benchmark parameter file with ``changes`` (symbol -> TOML value text; None drops it)."""
    lines = []
    for line in BENCHMARK.splitlines():
        key = line.split("=")[0].strip() if "=" in line and not line.lstrip().startswith("#") else None
        if key in changes:
            if changes[key] is not None:
                lines.append(f"{key} = {changes[key]}")
        else:
            lines.append(line)
    return "\n".join(lines) + "\n"


#: --params NAME|FILE: (the value given, files)
PARAM_SOURCES = {
    "missing-file": ("nope.toml", {}),
    "unknown-set": ("nope", {}),
    "empty-name": ("", {}),
    "directory": ("set.toml", {"set.toml": directory}),
    "empty-file": ("set.toml", {"set.toml": ""}),
    "binary": ("set.toml", {"set.toml": GARBAGE}),
    "latin1": ("set.toml", {"set.toml": text_in("latin-1", "# r\u00e9glages\n" + BENCHMARK)}),
    "utf16": ("set.toml", {"set.toml": text_in("utf-16", BENCHMARK)}),
    "bad-toml": ("set.toml", {"set.toml": "w = \nc = 0.08\n"}),
    "duplicate-key": ("set.toml", {"set.toml": BENCHMARK + "w = 1.1\n"}),
    "missing-keys": ("set.toml", {"set.toml": "w = 1.5\nc = 0.1\n"}),
    "unknown-key": ("set.toml", {"set.toml": BENCHMARK + "zz = 1.0\n"}),
    "nan": ("set.toml", {"set.toml": _benchmark(w="nan")}),
    "inf": ("set.toml", {"set.toml": _benchmark(mB="inf")}),
    "negative-mass": ("set.toml", {"set.toml": _benchmark(mB="-85.0")}),
    "zero-wheel": ("set.toml", {"set.toml": _benchmark(rR="0.0")}),
    "huge": ("set.toml", {"set.toml": _benchmark(w="1e308")}),
    "string": ("set.toml", {"set.toml": _benchmark(w='"1.5"')}),
    "array": ("set.toml", {"set.toml": _benchmark(c="[0.08, 0.09]")}),
    "table": ("set.toml", {"set.toml": _benchmark(c="{ value = 0.08 }")}),
    "bool": ("set.toml", {"set.toml": _benchmark(c="true")}),
    "deep-nesting": ("set.toml", {"set.toml": "w = " + "[" * 5000 + "]" * 5000 + "\n"}),
    "fifo": ("set.toml", {"set.toml": fifo}),
    "dev-zero": ("set.toml", {"set.toml": dev_zero}),
    "name-too-long": ("p" * 300 + ".toml", {}),
    "etc-passwd": ("/etc/passwd", {}),
}

#: verb -> (argv, outputs, files, the kinds of PARAM_SOURCES given to it: None for all). Every verb
#: reads a parameter set the same way (cosim.analytic.parameters): linearize and analytic get every
#: kind, the others a sample.
PARAMS_VERBS = {
    "linearize": (["linearize", "@whipple"], [], {}, None),
    "analytic": (["analytic", "--speed", "5"], [], {}, None),
    "simulate": (["simulate", "@whipple", "--stop-time", "0.2", "-o", "out.csv"], ["out.csv"], {},
                 {"missing-file", "unknown-set", "directory", "binary", "bad-toml", "nan", "huge", "deep-nesting",
                  "name-too-long", "fifo"}),
    "compare": (["compare", WHIPPLE, "--speeds", "5"], [], {},
                {"missing-file", "unknown-set", "directory", "utf16", "missing-keys", "negative-mass", "huge",
                 "deep-nesting", "name-too-long", "fifo"}),
    "animate": (["animate", "r.csv", "-o", "out.html"], ["out.html"], {"r.csv": RESULT_CSV},
                {"missing-file", "unknown-set", "empty-file", "latin1", "string", "zero-wheel", "huge",
                 "deep-nesting", "name-too-long", "fifo"}),
}


def params_file_cases() -> list:
    params = []
    for verb, (argv, outputs, files, kinds) in PARAMS_VERBS.items():
        for label, (value, more) in PARAM_SOURCES.items():
            if (kinds is None or label in kinds) and not (label == "dev-zero" and verb != "linearize"):
                case = Case([*argv, "--params", value], {**files, **more}, outputs, isolate=label == "dev-zero")
                params.append(pytest.param(case, id=f"{verb}-params-{label}"))
    return params


# --- input CSVs -------------------------------------------------------------------------------

CSV_KINDS = {
    "missing": None,
    "directory": directory,
    "empty": "",
    "header-only": "time,T\n",
    "one-row": "time,T\n0,1\n",
    "nan-cell": "time,T\n0,0\n0.1,nan\n0.2,1\n",
    "inf-cell": "time,T\n0,0\n0.1,inf\n0.2,1\n",
    "word-cell": "time,T\n0,0\n0.1,abc\n0.2,1\n",
    "empty-cell": "time,T\n0,0\n0.1,\n0.2,1\n",
    "nan-time": "time,T\nnan,0\n0.1,1\n",
    "decreasing-time": "time,T\n0,0\n0.3,1\n0.1,2\n0.5,3\n",
    "repeated-time": "time,T\n0,0\n0.1,1\n0.1,2\n0.5,3\n",
    "huge-values": "time,T\n0,1e308\n0.5,-1e308\n",
    "overflow": "time,T\n0,1e400\n0.5,1\n",
    "huge-time": "time,T\n0,0\n1e308,1\n",
    "before-start": "time,T\n-2,0\n-1,1\n",
    "after-stop": "time,T\n10,0\n11,1\n",
    "ragged": "time,T\n0,0\n0.1,1,7\n0.2\n",
    "no-header": "0,0\n0.1,1\n0.2,2\n",
    "bom": "\ufefftime,T\n0,0\n0.5,1\n",
    "latin1": text_in("latin-1", "t\u00efme,T\n0,0\n0.5,1\n"),
    "utf16": text_in("utf-16", "time,T\n0,0\n0.5,1\n"),
    "binary": GARBAGE,
    "nul-bytes": b"time,T\n0,\x000\n0.5,1\n",
    "semicolons": "time;T\n0;0\n0.5;1\n",
    "tabs": "time\tT\n0\t0\n0.5\t1\n",
    "quoted": 'time,T\n"0","0"\n"0.5","1"\n',
    "crlf": "time,T\r\n0,0\r\n0.5,1\r\n",
    "no-column-T": "time,a,b\n0,0,0\n0.5,1,1\n",
    "long-line": "time,T\n0," + "1" * 1_000_000 + "\n",
    "many-rows": "time,T\n" + "".join(f"{k * 2e-5:.5f},{k % 7}\n" for k in range(25_000)),
    "fifo": fifo,
    "dev-zero": dev_zero,
}

#: --input specifications that are not a file
INPUT_SPECS = {
    "step-word-time": "T=step:x:1", "step-nan-time": "T=step:nan:1", "step-inf-value": "T=step:0.1:inf",
    "step-empty": "T=step:", "step-too-many-fields": "T=step:1:2:3", "step-negative-time": "T=step:-5:1",
    "step-huge-time": "T=step:1e308:1", "step-at-start": "T=step:0:1", "unknown-input": "nope=step:0:1",
    "not-an-input": "V=step:0:1", "no-equals": "T", "empty-name": "=in.csv", "empty-file-name": "T=",
    "missing-file": "T=nope.csv", "name-too-long": "T=" + "c" * 300 + ".csv", "unicode-name": "T\u00e9=step:0:1",
}


def input_cases() -> list:
    params = []
    for label, content in CSV_KINDS.items():
        files = {} if content is None else {"in.csv": content}
        kinds = ("cs", "me") if label in ("nan-cell", "decreasing-time", "repeated-time", "huge-values",
                                          "one-row", "after-stop", "ragged", "before-start", "fifo") else ("cs",)
        for kind in kinds:
            case = Case(["simulate", "@simple", "--stop-time", "0.5", "--fmi-type", kind, "--input", "T=in.csv",
                         "-o", "out.csv"], files, ["out.csv"], isolate=label == "dev-zero")
            params.append(pytest.param(case, id=f"simulate-{kind}-csv-{label}"))
    for label, spec in INPUT_SPECS.items():
        case = Case(["simulate", "@simple", "--stop-time", "0.5", "--input", spec, "-o", "out.csv"], {}, ["out.csv"])
        params.append(pytest.param(case, id=f"simulate-input-{label}"))
    twice = Case(["simulate", "@simple", "--stop-time", "0.5", "--input", "T=step:0:1", "--input", "T=step:0:2",
                  "-o", "out.csv"], {}, ["out.csv"])
    params.append(pytest.param(twice, id="simulate-input-given-twice"))
    return params


# --- system files -----------------------------------------------------------------------------


def system(connections=("bike.phi -> rider.phi", "rider.T -> bike.T_delta"), system_table=None, bike=None,
           rider=None) -> str:
    """A system TOML: the linear Whipple bicycle with a proportional rider, changed by the arguments
    (a table given replaces the default one; None keeps it)."""
    settings = {"name": "corpus", "stop": 0.5, "step": 0.05} if system_table is None else system_table
    bike = {"fmu": "@whipple", "parameters": {"v": 4.0, "phi0": 0.01}} if bike is None else bike
    rider = {"python": "Proportional", "parameters": {"k": 2.0}} if rider is None else rider
    lines = [f"connections = {toml_value(list(connections))}", f"system = {toml_value(settings)}",
             f"components = {toml_value({'bike': bike, 'rider': rider})}"]
    return "\n".join(lines) + "\n"


def _settings(**changes):
    return {"name": "corpus", "stop": 0.5, "step": 0.05, **changes}


def _bike(**changes):
    return {"fmu": "@whipple", "parameters": {"v": 4.0, "phi0": 0.01}, **changes}


VALID_SYSTEM = system()

#: system file kind -> (content, runs unbounded work unless refused)
SYSTEM_KINDS = {
    "missing": (None, False),
    "directory": (directory, False),
    "empty": ("", False),
    "binary": (GARBAGE, False),
    "latin1": (text_in("latin-1", "# r\u00e9glage\n" + VALID_SYSTEM.replace("@whipple", "x.fmu")), False),
    "utf16": (text_in("utf-16", VALID_SYSTEM.replace("@whipple", "x.fmu")), False),
    "bad-syntax": ("[system\nstop = 1\n", False),
    "duplicate-key": (VALID_SYSTEM + "connections = []\n", False),
    "deep-nesting": ("connections = " + "[" * 5000 + "]" * 5000 + "\n", False),
    "only-connections": ('connections = ["a.y -> b.u"]\n', False),
    "components-not-table": ('connections = []\ncomponents = 3\n', False),
    "connections-not-list": ('connections = "bike.phi -> rider.phi"\n' + VALID_SYSTEM.split("\n", 1)[1], False),
    "connection-no-arrow": (system(connections=["bike.phi rider.phi"]), False),
    "connection-empty": (system(connections=[""]), False),
    "connection-unknown-component": (system(connections=["ghost.y -> bike.T_delta"]), False),
    "connection-unknown-signal": (system(connections=["bike.nope -> rider.phi"]), False),
    "connection-output-to-output": (system(connections=["bike.phi -> bike.delta"]), False),
    "connection-two-drivers": (system(connections=["bike.phi -> rider.phi", "rider.T -> bike.T_delta",
                                                   "bike.delta -> bike.T_delta"]), False),
    "connection-unicode": (system(connections=["b\u00efke.phi -> rider.phi"]), False),
    "stop-nan": (system(system_table=_settings(stop=float("nan"))), False),
    "stop-inf": (system(system_table=_settings(stop=float("inf"))), False),
    "stop-negative": (system(system_table=_settings(stop=-1.0)), False),
    "stop-before-start": (system(system_table=_settings(start=2.0, stop=1.0)), False),
    "stop-string": (system(system_table=_settings(stop="10")), False),
    "stop-bool": (system(system_table=_settings(stop=True)), False),
    "stop-huge": (system(system_table=_settings(stop=1e300)), True),
    "step-zero": (system(system_table=_settings(step=0.0)), False),
    "step-negative": (system(system_table=_settings(step=-0.1)), False),
    "step-nan": (system(system_table=_settings(step=float("nan"))), False),
    "step-longer-than-run": (system(system_table=_settings(step=5.0)), False),
    "step-subnormal": (system(system_table=_settings(step=5e-324)), True),
    "step-missing": (system(system_table={"name": "corpus", "stop": 0.5}), False),
    "unknown-system-key": (system(system_table=_settings(stpo=1.0)), False),
    "unknown-top-level-key": (VALID_SYSTEM + "extra = 1\n", False),
    "algorithm-unknown": (system(system_table=_settings(algorithm="newton")), False),
    "sampling-unknown": (system(system_table=_settings(sampling="sometimes")), False),
    "fall-unknown-signal": (system(system_table=_settings(fall={"signal": "bike.nope", "limit": 1.0})), False),
    "fall-limit-nan": (system(system_table=_settings(fall={"signal": "bike.phi", "limit": float("nan")})), False),
    "record-unknown": (system(system_table=_settings(record=["bike.nope"])), False),
    "component-empty": (system(rider={}), False),
    "component-two-kinds": (system(rider={"python": "Proportional", "fmu": "@whipple"}), False),
    "component-not-table": (system(rider="Proportional"), False),
    "unknown-component-key": (system(bike=_bike(colour="red")), False),
    "unknown-python-block": (system(rider={"python": "NoSuchBlock"}), False),
    "python-block-bad-parameter": (system(rider={"python": "Proportional", "parameters": {"k": "two"}}), False),
    "python-block-unknown-parameter": (system(rider={"python": "Proportional", "parameters": {"zz": 1}}), False),
    "unknown-model": (system(bike={"model": "Bicycle.Bicycles.Nope"}), False),
    "model-unicode": (system(bike={"model": "Bicycle.Bicycles.\u03a9mega"}), False),
    "fmu-missing": (system(bike=_bike(fmu="nope.fmu")), False),
    "fmu-nul-byte": (system(bike=_bike(fmu="x\u0000.fmu")), False),
    "fmu-directory": (system(bike=_bike(fmu=".")), False),
    "fmu-name-too-long": (system(bike=_bike(fmu="f" * 300 + ".fmu")), False),
    "parameter-unknown": (system(bike=_bike(parameters={"nope": 1.0})), False),
    "parameter-string": (system(bike=_bike(parameters={"v": "fast"})), False),
    "parameter-nan": (system(bike=_bike(parameters={"v": float("nan")})), False),
    "parameter-array": (system(bike=_bike(parameters={"v": [1.0, 2.0]})), False),
    "params-unknown-set": (system(bike=_bike(params="nope")), False),
    "step-multiple-zero": (system(bike=_bike(step_multiple=0)), False),
    "step-multiple-fraction": (system(bike=_bike(step_multiple=0.5)), False),
    "fmi-version-4": (system(bike={"model": WHIPPLE, "fmi_version": 4}), False),
    "long-component-name": (system(connections=[]).replace('"bike"', '"' + "c" * 5000 + '"'), False),
    "fifo": (fifo, False),
    "dev-zero": (dev_zero, True),
}


#: the kinds given to export-ssp too (it reads a system file as run does)
SSP_SYSTEM_KINDS = {"missing", "directory", "binary", "utf16", "bad-syntax", "deep-nesting", "connection-no-arrow",
                    "connection-unknown-signal", "stop-nan", "step-longer-than-run", "unknown-python-block",
                    "unknown-model", "fmu-nul-byte", "fmu-name-too-long", "parameter-unknown", "fmi-version-4",
                    "long-component-name", "fifo"}


def system_cases() -> list:
    params = []
    for label, (content, unbounded) in SYSTEM_KINDS.items():
        files = {} if content is None else {"system.toml": content}
        run = Case(["run", "system.toml", "-o", "out.csv"], files, ["out.csv"], isolate=unbounded)
        params.append(pytest.param(run, id=f"run-system-{label}"))
        if label in SSP_SYSTEM_KINDS:
            ssp = Case(["export-ssp", "system.toml", "-o", "out.ssp"], files, ["out.ssp"], isolate=unbounded)
            params.append(pytest.param(ssp, id=f"export-ssp-system-{label}"))
    return params


# --- model names and libraries ----------------------------------------------------------------

MODEL_NAMES = {
    "empty": "", "package-root": "Bicycle", "unknown": "Bicycle.Bicycles.Nope", "unknown-package": "Nope.Model",
    "double-dot": "Bicycle..Bicycles", "lower-case": "bicycle.bicycles.whipple", "a-package": "Bicycle.Bicycles",
    "past-a-model": f"{SIMPLE}.extra", "unicode": "Bicycle.Bicycles.\u03a9mega", "very-long": "A" * 5000,
    "path-like": "../../../etc/passwd", "shell-chars": "Bicycle.Bicycles.Whipple;echo", "slashes": "Bicycle/Bicycles",
    "not-in-library": "Modelica.Blocks.Sources.Sine", "trailing-dot": "Bicycle.Bicycles.",
}

MODEL_VERBS = {
    "info": (["info", "NAME"], []),
    "validate": (["validate", "NAME"], []),
    "simulate": (["simulate", "NAME", "--stop-time", "0.2", "-o", "out.csv"], ["out.csv"]),
    "linearize": (["linearize", "NAME"], []),
    "compare": (["compare", "NAME"], []),
    "diagram": (["diagram", "NAME", "-o", "out.svg"], ["out.svg"]),
    "build": (["build", "-o", "@fmudir", "NAME"], []),
}


#: the names every verb of MODEL_VERBS gets; info and build get all of MODEL_NAMES (every verb
#: resolves a name the same way, in cosim.compiler.library)
SOME_MODEL_NAMES = {"empty", "unknown", "a-package", "unicode", "very-long", "path-like"}


def model_name_cases() -> list:
    params = []
    for verb, (argv, outputs) in MODEL_VERBS.items():
        for label, name in MODEL_NAMES.items():
            if verb not in ("info", "build") and label not in SOME_MODEL_NAMES:
                continue
            case = Case([name if a == "NAME" else a for a in argv], {}, outputs)
            params.append(pytest.param(case, id=f"{verb}-model-{label}"))
    return params


LIBRARIES = {
    "missing": ("nope", {}),
    "a-file": ("lib", {"lib": "not a folder\n"}),
    "empty-folder": ("lib", {"lib": directory}),
    "garbage-package": ("lib", {"lib/Junk/package.mo": GARBAGE, "lib/Junk/Model.mo": "model ; end\n"}),
    "bad-modelica": ("lib", {"lib/Junk/package.mo": "within;\npackage Junk\n  model M\n    Real x\n  end M;\n"
                                                    "end Junk;\n"}),
    "proc": ("/proc/version", {}),
    "fifo": ("lib", {"lib": fifo}),
}

LIBRARY_VERBS = {
    "list": ["list"],
    "info": ["info", SIMPLE],
    "diagram": ["diagram", "Bicycle.Bicycles.Whipple", "-o", "out.svg"],
    "simulate": ["simulate", "Junk.M", "--stop-time", "0.2", "-o", "out.csv"],
    "build": ["build", "-o", "@fmudir", "Junk.M"],
}


def library_cases() -> list:
    params = []
    for verb, argv in LIBRARY_VERBS.items():
        outputs = [a for a in argv if a.startswith("out.")]
        for label, (value, files) in LIBRARIES.items():
            params.append(pytest.param(Case([*argv, "--library", value], files, outputs), id=f"{verb}-library-{label}"))
    return params


# --- outputs ----------------------------------------------------------------------------------

#: where an output goes: place -> (path with NAME for the file name, files made first)
PLACES = {
    "missing-folder": ("new/deeper/NAME", {}),
    "below-a-file": ("blocker/NAME", {"blocker": _blocker}),
    "below-a-file-deeper": ("blocker/a/b/NAME", {"blocker": _blocker}),
    "name-too-long": ("x" * 300 + "NAME", {}),
    "folder-name-too-long": ("y" * 300 + "/NAME", {}),
    "path-too-long": ("/".join(["z" * 250] * 20) + "/NAME", {}),
    "below-proc-file": ("/proc/version/NAME", {}),
    "in-proc": ("/proc/cosim-corpus-NAME", {}),
    "in-sys": ("/sys/cosim-corpus-NAME", {}),
    "existing-folder": ("folder/NAME", {"folder/NAME": directory}),
    "fifo": ("NAME", {"NAME": fifo}),
    "link-to-dev-zero": ("NAME", {"NAME": dev_zero}),
    "dangling-link": ("NAME", {"NAME": dangling}),
    "link-loop": ("NAME", {"NAME": loop}),
    "empty": ("", {}),
}

#: writing option -> (argv with PATH, file name, files, is a folder)
WRITERS = {
    "simulate-o": (["simulate", "@simple", "--stop-time", "0.2", "-o", "PATH"], "out.csv", {}, False),
    "simulate-o-npy": (["simulate", "@simple", "--stop-time", "0.2", "-o", "PATH"], "out.npy", {}, False),
    "simulate-plot": (["simulate", "@simple", "--stop-time", "0.2", "-o", "ok.csv", "--plot", "PATH"],
                      "plot.png", {}, False),
    "run-o": (["run", "system.toml", "-o", "PATH"], "out.csv", {"system.toml": VALID_SYSTEM}, False),
    "run-plot": (["run", "system.toml", "-o", "ok.csv", "--plot", "PATH"], "plot.svg",
                 {"system.toml": VALID_SYSTEM}, False),
    "export-ssp-o": (["export-ssp", "system.toml", "-o", "PATH"], "out.ssp", {"system.toml": VALID_SYSTEM}, False),
    "animate-o": (["animate", "r.csv", "-o", "PATH"], "out.html", {"r.csv": RESULT_CSV}, False),
    "diagram-o": (["diagram", "Bicycle.Bicycles.Whipple", "-o", "PATH"], "out.svg", {}, False),
    "figures-o": (["figures", "fig5", "-o", "PATH"], "figs", {}, True),
    "demo-o": (["demo", "-o", "PATH"], "demo", {}, True),
    "app-export": (["app", "--export", "PATH"], "site", {}, True),
    "matrix-o": (["matrix", "spec.toml", "--workers", "1", "--no-progress", "-o", "PATH"], "mx", {}, True),
    "build-o": (["build", "Bicycle.Sources.TorqueStep", "-j", "1", "-o", "PATH"], "fmus", {}, True),
}

#: the places a folder writer (figures, demo, app, matrix, build) gets: those it must refuse before
#: any work (in the others, e.g. a missing folder, it would do its whole long work)
FOLDER_PLACES = {"below-a-file", "below-a-file-deeper", "name-too-long", "folder-name-too-long", "path-too-long",
                 "below-proc-file", "fifo", "link-to-dev-zero"}
#: folder writers that make their folder first: /proc and /sys (which a check of the access
#: rights lets root pass) fail them before any work
FAIL_FAST = {"figures-o", "matrix-o", "build-o"}

#: the writers given the other over-long paths too (one name too long is given to every writer)
LONG_PATH_WRITERS = {"simulate-o", "run-plot", "figures-o", "matrix-o"}

MATRIX_SPEC = """[matrix]
name = "corpus"
stop = 0.2
step = 0.05
[[study]]
name = "one"
observe = "bike.phi"
connections = []
[study.components.bike]
model = "Bicycle.Bicycles.WhippleLinear"
parameter_set = "benchmark"
parameters = { v = "=v", phi0 = 0.01 }
[study.axes]
v = [5.0]
"""


def output_cases() -> list:
    params = []
    for writer, (argv, name, files, folder) in WRITERS.items():
        for place, (pattern, more) in PLACES.items():
            if folder and place not in FOLDER_PLACES and not (writer in FAIL_FAST and place in ("in-proc", "in-sys")):
                continue
            if place in ("folder-name-too-long", "path-too-long") and writer not in LONG_PATH_WRITERS:
                continue
            path = pattern.replace("NAME", name) if pattern else ""
            made = {k.replace("NAME", name): v for k, v in more.items()}
            spec = {"spec.toml": MATRIX_SPEC} if writer == "matrix-o" else {}
            outputs = [path] if path and not place.startswith(("fifo", "link", "dangling")) else []
            case = Case([path if a == "PATH" else a for a in argv], {**files, **made, **spec}, outputs,
                        limit=LIMIT)  # (a FIFO here is the output: the command does its work first)
            params.append(pytest.param(case, id=f"{writer}-{place}"))
    return params


# --- matrix specs, animate results, usage -----------------------------------------------------

MATRIX_KINDS = {
    "missing": None,
    "directory": directory,
    "empty": "",
    "binary": GARBAGE,
    "bad-syntax": "[matrix\n",
    "no-study": '[matrix]\nname = "x"\nstop = 1.0\nstep = 0.1\n',
    "unknown-key": MATRIX_SPEC.replace("[matrix]\n", "[matrix]\ncolour = 1\n"),
    "stop-nan": MATRIX_SPEC.replace("stop = 0.2", "stop = nan"),
    "stop-negative": MATRIX_SPEC.replace("stop = 0.2", "stop = -1.0"),
    "step-zero": MATRIX_SPEC.replace("step = 0.05", "step = 0.0"),
    "axis-empty": MATRIX_SPEC.replace("v = [5.0]", "v = []"),
    "axis-nan": MATRIX_SPEC.replace("v = [5.0]", "v = [nan]"),
    "axis-endless": MATRIX_SPEC.replace("v = [5.0]", "v = { from = 0.0, to = 1e300, step = 1e-300 }"),
    "axis-too-many": MATRIX_SPEC.replace("v = [5.0]", "v = { from = 0.0, to = 1e6, step = 1.0 }"),
    "axis-string": MATRIX_SPEC.replace("v = [5.0]", 'v = "fast"'),
    "unknown-model": MATRIX_SPEC.replace("Bicycle.Bicycles.WhippleLinear", "Bicycle.Bicycles.Nope"),
    "unknown-axis-in-expression": MATRIX_SPEC.replace('v = "=v"', 'v = "=speed"'),
    "expression-division-by-zero": MATRIX_SPEC.replace('v = "=v"', 'v = "=v/0"'),
    "expression-code": MATRIX_SPEC.replace('v = "=v"', "v = \"=__import__('os').system('true')\""),
    "unknown-parameter-set": MATRIX_SPEC.replace('"benchmark"', '"nope"'),
    "unknown-check-kind": MATRIX_SPEC + '[[study.checks]]\nkind = "psychic"\n',
    "duplicate-study": MATRIX_SPEC + MATRIX_SPEC[MATRIX_SPEC.index("[[study]]"):],
    "missing-import": MATRIX_SPEC.replace("[matrix]\n", '[matrix]\nimports = ["nope.py"]\n'),
    "bundled-typo": "papr",
    "fifo": fifo,
}


def matrix_cases() -> list:
    params = []
    for label, content in MATRIX_KINDS.items():
        if label == "bundled-typo":
            argv, files = ["matrix", "papr"], {}
        else:
            argv, files = ["matrix", "spec.toml"], ({} if content is None else {"spec.toml": content})
        case = Case([*argv, "--workers", "1", "--no-progress", "-o", "out"], files, ["out"])
        params.append(pytest.param(case, id=f"matrix-spec-{label}"))
    params.append(pytest.param(Case(["matrix", "spec.toml", "--max-cases", "1", "--no-progress", "-o", "out"],
                                    {"spec.toml": MATRIX_KINDS["axis-too-many"]}, ["out"]), id="matrix-over-max-cases"))
    params.append(pytest.param(Case(["matrix", "spec.toml", "--resume", "--force", "-o", "out"],
                                    {"spec.toml": MATRIX_SPEC}, ["out"]), id="matrix-resume-and-force"))
    params.append(pytest.param(Case(["matrix", "spec.toml", "--scheduler", "tcp://256.0.0.1:99999", "-o", "out"],
                                    {"spec.toml": MATRIX_SPEC}, ["out"]), id="matrix-scheduler-bad-address"))
    return params


ANIMATE_KINDS = {
    "missing": ("r.csv", None),
    "directory": ("r.csv", directory),
    "empty": ("r.csv", ""),
    "header-only": ("r.csv", "time,phi,delta\n"),
    "no-phi": ("r.csv", "time,delta\n0,0\n1,1\n"),
    "nan-cell": ("r.csv", "time,phi,delta\n0,0,0\n0.1,nan,0\n"),
    "inf-cell": ("r.csv", "time,phi,delta\n0,0,0\n0.1,inf,0\n"),
    "decreasing-time": ("r.csv", "time,phi,delta\n0,0,0\n1,0.1,0\n0.5,0.2,0\n"),
    "repeated-time": ("r.csv", "time,phi,delta\n0,0,0\n0,0.1,0\n"),
    "one-row": ("r.csv", "time,phi,delta\n0,0.1,0\n"),
    "huge-values": ("r.csv", "time,phi,delta\n0,1e308,0\n1,-1e308,1e308\n"),
    "huge-time": ("r.csv", "time,phi,delta\n0,0,0\n1e308,0.1,0\n"),
    "many-rows-long-time": ("r.csv", "time,phi,delta\n" + "".join(f"{k * 1e5:g},0.01,0\n" for k in range(2000))),
    "ragged": ("r.csv", "time,phi,delta\n0,0\n"),
    "binary": ("r.csv", GARBAGE),
    "utf16": ("r.csv", text_in("utf-16", RESULT_CSV)),
    "npy-garbage": ("r.npy", GARBAGE),
    "npy-pickle": ("r.npy", lambda path, fmus: _pickled_npy(path)),
    "npy-plain-array": ("r.npy", lambda path, fmus: _plain_npy(path)),
    "unknown-suffix": ("r.xyz", RESULT_CSV),
    "fifo": ("r.csv", fifo),
    "dev-zero": ("r.csv", dev_zero),
}


def _pickled_npy(path: Path) -> None:
    np.save(path, np.array([{"time": 0.0}, {"time": 1.0}], dtype=object), allow_pickle=True)


def _plain_npy(path: Path) -> None:
    np.save(path, np.zeros((3, 3)))


def animate_cases() -> list:
    params = []
    for label, (name, content) in ANIMATE_KINDS.items():
        files = {} if content is None else {name: content}
        case = Case(["animate", name, "-o", "out.html"], files, ["out.html"], isolate=label == "dev-zero")
        params.append(pytest.param(case, id=f"animate-result-{label}"))
    return params


#: the shortest command line of each verb that reaches its own options
MINIMAL = {
    "build": ["build"], "list": ["list"], "info": ["info", "x.fmu"], "validate": ["validate", "x.fmu"],
    "simulate": ["simulate", "x.fmu", "--stop-time", "1"], "linearize": ["linearize", "x.fmu"],
    "compare": ["compare", WHIPPLE], "run": ["run", "s.toml"], "export-ssp": ["export-ssp", "s.toml", "-o", "o.ssp"],
    "figures": ["figures"], "analytic": ["analytic"], "matrix": ["matrix", "s.toml"], "app": ["app", "--export", "x"],
    "animate": ["animate", "r.csv"], "diagram": ["diagram", "Bicycle.Bicycles.Whipple"], "demo": ["demo"],
}
VERBS = tuple(MINIMAL)

USAGE = {
    "no-verb": [], "unknown-verb": ["simulat"], "unicode-verb": ["s\u00efmulate"], "empty-verb": [""],
    "version": ["--version"], "simulate-no-target": ["simulate"], "simulate-no-stop-time": ["simulate", "x.fmu"],
    "simulate-stop-time-no-value": ["simulate", "x.fmu", "--stop-time"], "simulate-fmi-type-bad": [
        "simulate", "x.fmu", "--stop-time", "1", "--fmi-type", "xx"], "export-ssp-no-output": ["export-ssp", "s.toml"],
    "run-two-systems": ["run", "a.toml", "b.toml"], "build-fmi-version-4": ["build", "--fmi-version", "4"],
    "figures-unknown": ["figures", "fig99"], "figures-empty-name": ["figures", ""],
    "figures-unicode-name": ["figures", "fig\u0665"], "analytic-speed-word": ["analytic", "--speed", "1", "x"],
    "linearize-speed-and-speeds": ["linearize", "@whipple", "--speed", "1", "--speeds", "1,2"],
    "linearize-matrices-without-sweep": ["linearize", "@whipple", "--matrices"],
    "linearize-lock-hinge-linear": ["linearize", "@whipple", "--lock-hinge"],
    "linearize-speeds-overflow": ["linearize", "@whipple", "--speeds", "0:1e308:1e-300"],
    "linearize-speeds-reversed": ["linearize", "@whipple", "--speeds", "5:1:1"],
    "linearize-speeds-zero-step": ["linearize", "@whipple", "--speeds", "1:5:0"],
    "linearize-speeds-too-many": ["linearize", "@whipple", "--speeds", "0:1e9:1e-3"],
    "linearize-speeds-list-gap": ["linearize", "@whipple", "--speeds", "1,,2"],
    "compare-speeds-overflow": ["compare", WHIPPLE, "--speeds", "0:1e308:1e-300"],
    "compare-no-twin": ["compare", "Bicycle.Control.PD"],
    "validate-two-missing": ["validate", "a.fmu", "b.fmu"],
    "info-json-missing": ["info", "--json", "x.fmu"],
    "diagram-icon-unknown": ["diagram", "--icon", "Bicycle.Nope"],
}


def usage_cases() -> list:
    params = [pytest.param(Case([*argv, "--no-such-option"]), id=f"{verb}-unknown-option")
              for verb, argv in MINIMAL.items()]
    params += [pytest.param(Case(argv), id=f"cosim-{label}") for label, argv in USAGE.items()]
    return params


CASES = (usage_cases() + number_cases() + assignment_cases() + params_file_cases() + input_cases() + fmu_cases()
         + system_cases() + model_name_cases() + library_cases() + output_cases() + matrix_cases() + animate_cases())
assert len({p.id for p in CASES}) == len(CASES), "case ids must be unique"


@pytest.mark.parametrize("case", CASES)
def test_hostile_input_gets_one_clear_answer(case, request, tmp_path, fmus):
    folder = tmp_path / "case"
    folder.mkdir()
    answer(case, request.node.callspec.id, folder, fmus)


# --- signals ----------------------------------------------------------------------------------

#: commands that run long enough to be interrupted mid-way (1e7 communication steps)
LONG = {
    "simulate": (["simulate", "@simple", "--stop-time", "1e5", "--step", "0.01", "-o", "out.csv"], {}),
    "simulate-me": (["simulate", "@simple", "--fmi-type", "me", "--stop-time", "1e5", "--step", "0.01",
                     "-o", "out.csv"], {}),
    "run": (["run", "system.toml", "-o", "out.csv"],
            {"system.toml": system(system_table=_settings(stop=1e5, step=0.01))}),
}
#: signal -> the statuses that report it: 130 (the documented one) or the death by the signal itself,
#: which a shell reports as 128 + the signal number (for SIGINT: 130 too; Python ends so after a
#: KeyboardInterrupt it has seen unhandled somewhere, even one handled later)
SIGNALS = {"sigint": (signal.SIGINT, {130, -signal.SIGINT}),
           "sigterm": (signal.SIGTERM, {130, 128 + signal.SIGTERM, -signal.SIGTERM})}


@pytest.mark.parametrize("command, stop", [
    pytest.param(c, s, id=f"{c}-{s}") for c in LONG for s in SIGNALS if not (c == "simulate-me" and s == "sigterm")])
def test_interrupted_command_ends_cleanly(command, stop, tmp_path, fmus):
    """A long command stopped by SIGINT (Ctrl-C) or SIGTERM once it is working (its FMU has been
    extracted): the status of the interruption (SIGNALS), one line ``cosim VERB: interrupted``
    after SIGINT, no traceback, nothing under the final name and no partial file."""
    argv, files = LONG[command]
    sig, statuses = SIGNALS[stop]
    folder, scratch = tmp_path / "case", tmp_path / "tmp"
    folder.mkdir()
    scratch.mkdir()
    tokens = _tokens(fmus)
    for name, content in files.items():
        (folder / name).write_text(_replace(content, tokens), encoding="utf-8")
    argv = [_replace(a, tokens) for a in argv]
    before = files_under(folder)
    env = {**os.environ, "TMPDIR": str(scratch)}
    process = subprocess.Popen([sys.executable, "-m", "cosim", *argv], cwd=folder, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               # a shell may have started the tests with SIGINT ignored; a terminal user's is not
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + LIMIT
        while not any(scratch.iterdir()) and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)  # until an FMU is extracted: the command is past its imports and checks
        assert process.poll() is None, f"ended before it was interrupted:\n{process.communicate()}"
        time.sleep(0.5)
        process.send_signal(sig)
        try:
            out, err = process.communicate(timeout=LIMIT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"cosim {' '.join(argv)}: still running {LIMIT:g} s after {sig.name}")
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    shown = f"cosim {' '.join(argv)}\nexit {process.returncode}\nstderr:\n{err[-3000:]}"
    assert process.returncode in statuses, shown
    if process.returncode in (130, -signal.SIGINT):
        check_answer(argv, 130, out, err, folder, before, ("out.csv",))
    else:
        assert "Traceback" not in err, shown
        after = files_under(folder)
        assert Path("out.csv") not in after and not [p for p in after if ".partial" in p.name], shown
