"""The `cosim` command line.

Exit status of every command (also in ``cosim --help``):

====  ==========================================================================================
0     success (``simulate``, ``run``: also an FMU that ended the run itself without an error, by
      ``terminateSimulation``; one ``note:`` line on stderr gives the time, and for ``run`` the
      component)
1     a check found problems (``validate``, ``compare`` beyond ``--tol``, ``matrix``)
2     bad input or usage: one message ``cosim VERB: error: ...`` names the file, parameter, key
      or row (or the path and operation of an OS error: a FIFO given as a file, a name too long,
      no permission); nothing was written under the final output name
3     ``run``: the bicycle fell (the system's fall criterion); the result was written
4     incomplete result: the solver failed part-way, an output turned non-finite, or an FMU from
      elsewhere crashed, exited or hung (it runs in a guarded child process, see ``--timeout``); the
      rows up to the failure were written to ``NAME.incomplete.csv`` (``.npy``) and the message
      names the cause. Also: computed results could not be written (disk full, quota, read-only
      file system): the message names the path, the reason and what was kept or lost
70    internal error (a bug): one line; ``COSIM_DEBUG=1`` shows the traceback
130   interrupted (Ctrl-C)
====  ==========================================================================================
"""
from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import traceback
import warnings
from pathlib import Path

# Each command's handler below imports the modules that carry the command out when it runs, so
# that `cosim --help` and `cosim VERB --help` load only the parsers (the implementations bring in
# numpy, fmpy, CasADi, pymoca, scipy, matplotlib or python-control).
from cosim import __version__
from cosim.cli_options import LIBRARY_VARIABLE, library_option, positive_int
from cosim.errors import CosimError, OutputError, ParameterError, ResultNotWritten
from cosim.outputs import check_output, os_error_message
from cosim.progress import NORMAL, QUIET, VERBOSE, Reporter, active, reporting

EXIT_OK, EXIT_CHECK_FAILED, EXIT_BAD_INPUT, EXIT_FELL, EXIT_INCOMPLETE = 0, 1, 2, 3, 4
EXIT_INTERNAL, EXIT_INTERRUPTED = 70, 130

EXIT_CODES = """\
exit status:
  0    success
  1    a check found problems (validate, compare beyond --tol, matrix)
  2    bad input or usage: one message names the file, parameter, key or row (or the path and
       operation of an OS error); nothing is written under the final output name
  3    run: the bicycle fell (the system's fall criterion); the result was written
  4    incomplete result: the solver failed part-way, an output turned non-finite, or an FMU from
       elsewhere crashed, exited or hung (such FMUs run in a guarded child process, see
       --timeout); the rows up to the failure are written to NAME.incomplete.csv (or .npy) beside
       the requested NAME.csv, and the message names the cause (e.g. roll or steer angle near
       +-pi/2, the constraint residual growing, "the FMU crashed (SIGSEGV) during fmi2DoStep");
       also when computed results cannot be written (disk full, quota, read-only file system):
       the message names the path and what was kept or lost
  70   internal error (a bug): one line; set COSIM_DEBUG=1 for the traceback
  130  interrupted"""

FMU_FOLDER = """\
where FMUs go: commands given a model name build it first (incrementally) into ./fmus of the
working directory, or into the folder named by the environment variable COSIM_FMU_DIR; the
Modelica library ships with the package (--library DIR or COSIM_MODELICA_PATH add folders of your
own packages, searched before it)."""

ENVIRONMENT = f"""\
environment variables:
  COSIM_FMU_DIR        folder where model names are built to FMUs (default: ./fmus)
  COSIM_MODELICA_PATH  folders of your own Modelica packages (several separated by '{os.pathsep}'),
                       searched in order before the library shipped with the package, which
                       is always searched last; a top-level package is taken from the first
                       folder that holds it (as MODELICAPATH: your own Bicycle package hides
                       the shipped one); --library DIR of a command takes its place
  COSIM_DEBUG          1: an internal error prints its traceback (default: one line)
  XDG_CACHE_HOME       cache folder (default: ~/.cache): pymoca's parse cache and the library
                       index cosim/library-index-*.json (what `list` and `info MODEL` print,
                       and the parameters each model's FMU declares; rebuilt when a .mo file
                       of any library folder or the compiler changes; safe to delete)"""

RESULTS = """\
results: -o NAME.csv writes CSV (a header row, then one row per output time); -o NAME.npy a
NumPy structured array (numpy.load). Files appear under their final name only when complete
(written to a hidden temporary name, then renamed). If the solver fails part-way, the rows up to
the failure go to NAME.incomplete.csv (.npy, and NAME.incomplete.png for --plot) and the exit
status is 4; NAME.csv is not written."""

SIMULATE_EPILOG = f"""\
parameters: --param NAME=VALUE sets a parameter (or a state's start value) of the FMU; Integer
parameters take whole numbers, Boolean ones true/false. Every FMU built here has the parameter
solver.fixedStepSize [s] (default 0: error-controlled Dormand-Prince 5(4); > 0: fixed steps of that
size in Co-Simulation; refused with --fmi-type me, where FMPy's CVode integrates).

inputs are not parameters: give them with --input NAME=FILE.csv (a header row, then rows of
time [s], value; a column named NAME is used if the file has several), --input NAME=FILE.npy
(numpy.save of a structured array with the fields time [s] and NAME, or of a two-column float
array of time [s], value) or --input NAME=step:T0:VALUE. Values between rows are interpolated
linearly, a repeated time is a jump, and the first and last values hold before and after the
rows; a jump or step at the start time acts from the start. Every value is checked (file, row
and column named); reading time and memory grow in proportion to the rows.

time grid: without --step the output (communication) step is the FMU's DefaultExperiment
stepSize (the model's experiment(Interval=...), 0.01 s for the bicycles of the library), or
0.01 s (100 rows per second) if it declares none, whatever the stop time: a longer run has more
rows, never coarser ones. A run of more than 10,000,000 rows is refused with one message (give a
larger --step or a shorter --stop-time).

{RESULTS}

{FMU_FOLDER}

{EXIT_CODES}"""

RUN_EPILOG = f"""\
time grid: the master takes communication steps of [system] step from start to stop; if step does
not divide stop - start, the last step is the shorter remainder, so the run ends on stop exactly
(the message reports the end time and the number of steps). step must be finite, > 0 and not
longer than the run; start and stop finite with stop > start.

FMI versions: components may be FMI 2.0 or 3.0 Co-Simulation FMUs (fmu = "x.fmu"), mixed freely; a
model component is built as FMI 2.0 unless its table says fmi_version = 3 (OUTPUT/fmi3/NAME.fmu).
FMI 3 inputs are held over each communication step (FMI 3 has no input derivatives).

{RESULTS} A run that ends by the fall criterion is complete (exit 3).

{FMU_FOLDER}

{EXIT_CODES}"""

LINEARIZE_EPILOG = """\
A, B, C, D are the Jacobians at the initial point (after initialization) with the states in the
FMU's order; "eigenvalues" are those of A. FMI 2.0 and 3.0 FMUs with Model Exchange; inputs and
outputs of type Real (FMI 3: Float64) with continuous variability. Directional derivatives are
exact (automatic differentiation) for FMUs built here; an FMU without them is linearized by central
finite differences ("method"). An FMI 3 FMU that also provides adjoint derivatives has its Jacobian
computed a second time from fmi3GetAdjointDerivative (v^T (J u) = (J^T v)^T u, entry by entry):
"adjoint_difference" is the largest difference relative to the largest entry, and one above 1e-12
is refused with the entry named.

nonlinear bicycles (Bicycle.Bicycles.Whipple, WhippleRider): --speed V sets upright straight
running at forward speed V (u_R0 = -V/rR, pitch 0 upright with zero steer). The output adds
"steady_motion", the exact lateral dynamics: the states phi, delta, u_phi, u_delta (WhippleRider:
also beta, u_beta unless --lock-hinge) with their A, B and "eigenvalues" (for Whipple those of
Meijaard et al. 2007), the path rows of psi and y, and "zero_eigenvalues": the other eigenvalues
of A are exact zeros, each named with its reason: theta (pitch, fixed by roll and steer through
the holonomic constraint), u_R (the conserved forward speed) and the ignorable (cyclic)
coordinates x, y, psi, thetaR, thetaF. Numerically A's zero eigenvalues are defective (e.g. y
integrates psi), which is why the lateral ones are reported separately. --lock-hinge holds the
rider's hinge at beta = 0 by its reaction torque (the direction of the lean torque T_beta):
exact, independent of the hinge stiffness kU and damping cU. Off upright straight running the
reduction is refused ("steady_motion": null with "steady_motion_note").

speed sweep: --speeds A:B:STEP (B included) or V1,V2,... linearizes at each speed with one FMU
instance (re-initialized per speed: the same numbers as --speed V one speed at a time). Text: one
line of eigenvalues per speed (the lateral ones for the nonlinear bicycles). --json (one line):
"speeds", the common fields (model, parameters, states, inputs, outputs, method, and for the
nonlinear bicycles "steady_motion" with its states, inputs, hinge and zero_eigenvalues) and
"points": per speed "speed", the speed parameter's value, "eigenvalues" of A and "steady_motion"
(A, B, eigenvalues, path A and B; null with "steady_motion_note" where refused); --matrices adds
A, B, C, D per speed."""

MAIN_EPILOG = f"""\
Run `cosim VERB --help` for the options of a command.

progress: build, figures, demo, run, validate and app --export show their progress on stderr: on a
terminal one line, [3/7] ITEM (run: the percent of its stop time), redrawn and cleared at the end;
elsewhere one line per item, "cosim VERB: [3/7] ITEM". -q (before or after the verb) shows none and
no informational lines (results, warnings and errors stay); -v adds detail lines.

{FMU_FOLDER}

{ENVIRONMENT}

{EXIT_CODES}"""


def _port(text: str) -> int:
    """argparse type: a TCP port 0..65535 (0: one the system chooses)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid port: '{text}' (an integer 0..65535)") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"invalid port: {value} (0..65535)")
    return value


def _finite(text: str) -> float:
    """argparse type of times, steps and tolerances: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got '{text}'")
    return value


def _timeout(text: str) -> float | None:
    """``--timeout SECONDS``: finite and > 0, or 0 / none for no limit."""
    if text.strip().lower() in ("0", "none"):
        return None
    value = _finite(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0 s (or 0 / none for no limit), got {text}")
    return value


def timeout_option(p: argparse.ArgumentParser, what: str) -> None:
    """``--timeout`` of the verbs that call the binary of an FMU from elsewhere."""
    from cosim.fmu.isolation import DEFAULT_TIMEOUT

    p.add_argument("--timeout", type=_timeout, default=DEFAULT_TIMEOUT, metavar="SECONDS",
                   help=f"an FMU not built by cosim runs in a guarded child process; it is stopped when {what} "
                        f"for SECONDS (default {DEFAULT_TIMEOUT:g}; 0 or none: no limit)")


class _FmiVersions(argparse.Action):
    """``--fmi-version 2 3`` (or repeated): the FMI versions to build. The option takes one or
    more values, so model names right after it (``cosim build --fmi-version 3 MODEL``) would be
    taken for versions: they are the models, as if given before the option."""

    def __call__(self, parser, namespace, values, option_string=None):
        first_model = next((k for k, v in enumerate(values) if v not in ("2", "3")), len(values))
        versions = values[:first_model]
        if not versions:
            parser.error(f"argument {option_string}: invalid FMI version '{values[0]}' (choose 2, 3 or both)")
        setattr(namespace, self.dest, (getattr(namespace, self.dest) or []) + versions)
        # argparse sets the positional models after this action: keep these apart, _cmd_build joins them
        namespace.models_after_versions = getattr(namespace, "models_after_versions", []) + values[first_model:]


def _cmd_build(args) -> int:
    from cosim.compiler.build import build

    def report(results):
        for r in results:
            if r.rebuilt or not active().quiet:  # -q: only what changed
                print(f"{'built ' if r.rebuilt else 'up to date'} {r.fmu}  ({r.seconds:.1f} s)")

    versions = args.fmi_version or ("2",)
    if args.wasm:
        from cosim.wasm.build import build_wasm, zig_command

        zig_command()  # no ziglang: one message before any work
        if "2" not in versions:
            versions = ("2", *versions)  # the WebAssembly module is compiled from the FMI 2.0 FMU's sources
    try:
        models = (args.models or []) + getattr(args, "models_after_versions", [])
        results = build(models or None, args.output, jobs=args.jobs, force=args.force, fmi_versions=versions)
    except CosimError as exc:
        report(getattr(exc, "results", []))  # what did build is kept and shown before the error
        raise
    report(results)
    if args.wasm:
        fmi2 = [r for r in results if r.fmi_version == "2"]
        with active().steps(len(fmi2)):
            for r in fmi2:
                active().item(f"{r.model} (WebAssembly)")
                w = build_wasm(r.fmu, args.output, force=args.force)
                if w.rebuilt or not active().quiet:
                    active().clear()
                    print(f"{'built ' if w.rebuilt else 'up to date'} {w.wasm}  ({w.size / 1e3:.0f} kB, "
                          f"{w.seconds:.1f} s)", flush=True)
    return EXIT_OK


def _cmd_list(args) -> int:
    from cosim.compiler.catalog import catalog, shorten

    # the library of --library / $COSIM_MODELICA_PATH, from its index unless a file changed
    summaries = catalog(exported_only=args.exported,
                        warn=lambda message: print(f"cosim list: warning: {message}", file=sys.stderr))
    if args.json:
        print(json.dumps([s.to_dict() for s in summaries], indent=2))
        return EXIT_OK
    for s in summaries:
        mark = "*" if s.exported else " "
        print(f"{mark} {s.name}: {s.description}")
        for label, signals in (("inputs", s.inputs), ("outputs", s.outputs)):
            if signals:
                print(_wrapped(label, [f"{x.name} [{x.unit or '-'}]" for x in signals]))
        if s.parameters:
            print(_wrapped("parameters", [f"{p.name}={shorten(p.value)}" for p in s.parameters]))
    print("\n* exported by `cosim build`; values longer than 40 characters are shortened (--json has them in full)")
    return EXIT_OK


def _wrapped(label: str, items: list[str]) -> str:
    """``label: a, b, ...`` indented and wrapped to the terminal width (items are not split)."""
    import shutil
    import textwrap

    width = max(60, shutil.get_terminal_size((100, 24)).columns)
    return textwrap.fill(", ".join(items), width=width, initial_indent=f"      {label}: ",
                         subsequent_indent=" " * 8, break_long_words=False, break_on_hyphens=False)


def _cmd_info(args) -> int:
    from cosim.fmu.info import describe_target

    print(describe_target(args.target, as_json=args.json))
    return EXIT_OK


def _cmd_validate(args) -> int:
    """Each target is validated; one that cannot be read as an FMU (or built) gets its error
    line and the others are still checked."""
    outcomes = []
    with active().steps(len(args.targets)):
        for target in args.targets:
            active().item(target)
            outcomes.append(_validate_one(target, args.timeout))
    return EXIT_BAD_INPUT if "unreadable" in outcomes else (
        EXIT_CHECK_FAILED if "problems" in outcomes else EXIT_OK)


def _validate_one(target: str, timeout: float | None) -> str:
    """Validate one target of ``cosim validate`` and print its report: "valid", "problems" or
    "unreadable" (the error line printed)."""
    from cosim.fmu.access import ALL_FMI_VERSIONS, LENIENT_HINT
    from cosim.fmu.target import resolve_fmu
    from cosim.fmu.validate import validate_report

    try:
        fmu = resolve_fmu(target, versions=ALL_FMI_VERSIONS)
        report = validate_report(fmu, timeout=timeout or float("inf"))
    except CosimError as exc:  # (validate has no --lenient: a model description's defects are its findings)
        active().clear()
        print(f"cosim validate: error: {str(exc).removesuffix(LENIENT_HINT)}", file=sys.stderr)
        return "unreadable"
    active().clear()  # the report starts on a clean line of the terminal
    what = f"FMI {report.fmi_version}, {len(report.checks)} checks"
    warned = f", {len(report.warnings)} warning(s)" if report.warnings else ""
    if report.problems:
        print(f"{fmu}: {len(report.problems)} problem(s){warned} ({what})")
        for p in report.problems:
            print(f"  - {p}")
    else:
        print(f"{fmu}: valid{warned} ({what})")
    for w in report.warnings:  # allowed by the standard, avoided by a robust FMU: not a problem
        print(f"  warning: {w}")
    for s in report.skipped:  # what does not apply to this FMU: not a problem, but not checked
        print(f"  skipped: {s}")
    return "problems" if report.problems else "valid"


def _default_result(target: str, suffix: str = ".csv") -> Path:
    """``<FMU stem>.csv`` in the working directory, known before the model is built."""
    from cosim.fmu.target import is_fmu_path

    if is_fmu_path(target):
        return Path(Path(target).stem + suffix)
    name = target.replace(".", "_") + suffix  # as cosim.compiler.description.model_identifier
    try:
        limit = os.pathconf(".", "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    # the result is written to a temporary .NAME.partial-XXXXXXXX.csv first
    if len(os.fsencode(name)) + 18 > limit:
        raise ParameterError(f"the model name is too long for a result file named after it ({name[:40]}...): "
                             "give one with -o FILE")
    return Path(name)


def _check_outputs(output: Path, plot_path: str | None) -> None:
    """Refuse unwritable or unknown-format outputs before any work."""
    from cosim.fmu.simulate import check_plot_output, check_result_output

    check_result_output(output)
    if plot_path:
        check_plot_output(plot_path)


def _rows(result) -> str:
    """``N rows (t = A .. B s)`` of a result, for the message of what was written or lost."""
    return f"{len(result)} rows (t = {result['time'][0]:.6g} .. {result['time'][-1]:.6g} s)"


def _signals(args) -> list[str] | None:
    """``--signals a,b,c`` as a list (None: not given); refused without ``--plot``."""
    if args.signals is None:
        return None
    if not args.plot:
        raise ParameterError("--signals chooses the panels of --plot: give --plot FILE too")
    return [s.strip() for s in args.signals.split(",") if s.strip()]


def _write_results(result, output: Path, plot_path: str | None, title: str, complete: bool = True,
                   plotting: dict | None = None) -> list[str]:
    """Write the computed result (and its plot: ``plotting`` holds the keywords of
    :func:`cosim.fmu.simulate.plot`, units, signals and inputs); a write that fails (disk full,
    quota, read-only file system) is one :class:`ResultNotWritten` naming the path and what was
    kept and lost."""
    from cosim.fmu.simulate import incomplete_path, plot, write_result

    targets = [output, plot_path] if complete else [incomplete_path(output),
                                                    plot_path and incomplete_path(plot_path)]
    written: list[str] = []
    try:
        written.append(str(write_result(result, targets[0])))
        if plot_path:
            written.append(str(plot(result, targets[1], title=title if complete else f"{title} (incomplete)",
                                    **(plotting or {}))))
    except OutputError as exc:
        kept = f"; kept: {', '.join(written)}" if written else ""
        raise ResultNotWritten(f"{exc}; the {_rows(result)} computed{' before the failure' if not complete else ''} "
                               f"were not {'plotted' if written else 'written'}{kept}") from None
    return written


def _write_incomplete(exc, output: Path, plot_path: str | None, title: str, verb: str,
                      plotting: dict | None = None) -> int:
    """Keep what was computed before a solver failure: write it beside the final name."""
    result = exc.result
    if result is None or len(result) == 0:
        print(f"cosim {verb}: error: {exc} (nothing computed to write)", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        written = _write_results(result, output, plot_path, title, complete=False, plotting=plotting)
    except ResultNotWritten as lost:
        raise ResultNotWritten(f"incomplete: {exc}; and {lost}") from None
    stale = f"; note: {output} is from an earlier run" if output.exists() else ""
    print(f"cosim {verb}: incomplete: {exc}; wrote the {len(result)} rows up to t = {result['time'][-1]:.6g} s "
          f"to {', '.join(written)}{stale}", file=sys.stderr)
    return EXIT_INCOMPLETE


def _cmd_simulate(args) -> int:
    from cosim.bicycle.parameters import from_command_line
    from cosim.fmu.access import ALL_FMI_VERSIONS, read_fmu
    from cosim.fmu.parameters import declarations
    from cosim.fmu.simulate import (IncompleteResult, SimulationTerminated, check_run, check_signals, input_signals,
                                    simulate, variable_units)
    from cosim.fmu.target import is_fmu_path, resolve_fmu

    # a model first: an unknown one is named before its result file; an FMU is read for --param only
    declared = None if is_fmu_path(args.target) else declarations(args.target)
    output = Path(args.output) if args.output else _default_result(args.target)
    _check_outputs(output, args.plot)  # before any build or run
    signals = _signals(args)
    params = from_command_line(args.target, args.param, parameter_set=args.params, declared=declared)
    check_run(None, args.stop_time, args.step, args.fmi_type, parameters=params)
    fmu = resolve_fmu(args.target, versions=ALL_FMI_VERSIONS)  # FMI 2.0 and 3.0 (FMPy runs both)
    md = read_fmu(fmu, ALL_FMI_VERSIONS)
    t0, t1 = check_run(md, args.stop_time, args.step, args.fmi_type, parameters=params)
    inputs = input_signals(fmu, args.input, t0, t1)
    # an FMI 3 <Alias> (another name, maybe another display unit, of the same value) is no column of its own
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and getattr(v, "alias", None) is None]
    if signals is not None:  # the recorded columns are the outputs (all variables if it has none)
        check_signals(signals, outputs or [v.name for v in md.modelVariables if v.name != "time"])
    plotting = {"units": variable_units(md), "signals": signals,
                "inputs": [v.name for v in md.modelVariables if v.causality == "input"]}
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", SimulationTerminated)
            result = simulate(fmu, args.stop_time, args.step, args.fmi_type, params, inputs,
                              outputs=outputs or None, progress=sys.stderr.isatty() and not active().quiet, timeout=args.timeout,
                              lenient=args.lenient)
    except IncompleteResult as exc:
        return _write_incomplete(exc, output, args.plot, md.modelName, "simulate", plotting)
    for warning in caught:  # the model's own end is a note; any other warning is shown as usual
        if isinstance(warning.message, SimulationTerminated):
            print(f"cosim simulate: note: {warning.message}", file=sys.stderr)
        else:
            warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    _write_results(result, output, args.plot, md.modelName, plotting=plotting)
    print(f"wrote {output} ({len(result)} rows: {', '.join(result.dtype.names)})")
    if args.plot:
        print(f"wrote {args.plot}")
    return EXIT_OK


def _operating_point(target: str, assignments: list[str], declared: dict | None = None) -> dict:
    """``--input NAME=VALUE`` of linearize: input values of the operating point (``declared``:
    the target's declarations, read if not given)."""
    from cosim.fmu.parameters import declarations, split_assignment
    from cosim.fmu.simulate import finite_number

    declared = declarations(target) if declared is None else declared
    inputs = {}
    for text in assignments:
        name, raw = split_assignment(text, "--input")
        d = declared.get(name)
        if d is None or d.causality != "input":
            known = ", ".join(n for n, v in declared.items() if v.causality == "input") or "(none)"
            raise ParameterError(f"--input: '{name}' is not an input; inputs are: {known}")
        inputs[name] = finite_number(raw, f"--input {name}")
    return inputs


def _cmd_linearize(args) -> int:
    from cosim.bicycle.linearize import NotSteadyMotion, is_bicycle, steady_motion
    from cosim.bicycle.parameters import from_command_line
    from cosim.fmu.access import ALL_FMI_VERSIONS
    from cosim.fmu.linearize import linearize
    from cosim.fmu.parameters import declarations
    from cosim.fmu.target import resolve_fmu

    if args.speeds is not None:
        if args.speed is not None:
            raise ParameterError("give either --speed V or --speeds A:B:STEP|V1,V2,..., not both")
        return _linearize_sweep(args)
    if args.matrices:
        raise ParameterError("--matrices applies to a sweep (--speeds) only; the single-speed output has them")
    declared = declarations(args.target)  # a model's are those of its FMU: checked before it is built
    params = from_command_line(args.target, args.param, parameter_set=args.params, speed=args.speed,
                               input_hint="give its operating-point value with --input {name}=VALUE",
                               declared=declared)
    inputs = _operating_point(args.target, args.input, declared)
    result = linearize(resolve_fmu(args.target, versions=ALL_FMI_VERSIONS), params, inputs or None,
                       timeout=args.timeout, lenient=args.lenient)
    steady = note = None
    if is_bicycle(result):  # a nonlinear bicycle: its exact lateral linearization (see the help)
        try:
            steady = steady_motion(result, lock_hinge=args.lock_hinge)
        except NotSteadyMotion as exc:
            if args.lock_hinge:
                raise ParameterError(f"--lock-hinge: {exc}") from None
            note = str(exc)
    elif args.lock_hinge:
        raise ParameterError(f"--lock-hinge: {result.model} is not a nonlinear bicycle with a rider hinge")
    if args.json:
        report = result.to_dict()
        if is_bicycle(result):
            report["steady_motion"] = steady.to_dict() if steady else None
            if note:
                report["steady_motion_note"] = note
        print(json.dumps(report, indent=2))
        return EXIT_OK
    import numpy as np

    np.set_printoptions(precision=6, suppress=False, linewidth=120)
    point = {**params, **inputs}
    print(f"{result.model} linearized ({result.method}) at {point or 'default parameters'}")
    system = result.system
    print(f"states:  {', '.join(system.states)}\ninputs:  {', '.join(system.inputs)}\n"
          f"outputs: {', '.join(system.outputs)}")
    for name in "ABCD":
        print(f"{name} =\n{getattr(system, name)}")
    print("eigenvalues:", ", ".join(f"{e:.6g}" for e in result.eigenvalues))
    if steady is not None:
        print(f"upright straight running at v = {steady.speed:.6g} m/s"
              + (f", rider hinge {steady.hinge}" if steady.hinge else "") + ": lateral dynamics")
        print(f"states:  {', '.join(steady.system.states)}\ninputs:  {', '.join(steady.system.inputs)}")
        print(f"A =\n{steady.system.A}\nB =\n{steady.system.B}")
        print("lateral eigenvalues:", ", ".join(f"{e:.10g}" for e in steady.eigenvalues))
        print("exact zero eigenvalues:")
        for state, reason in steady.zero_modes.items():
            print(f"  {state}: {reason}")
    elif note:
        print(f"no lateral reduction: {note}")
    return EXIT_OK


def _linearize_sweep(args) -> int:
    """``cosim linearize MODEL --speeds ...``: :func:`cosim.bicycle.linearize.linearize_speeds`."""
    from cosim.fmu.access import ALL_FMI_VERSIONS
    from cosim.bicycle.linearize import NotSteadyMotion, linearize_speeds, parse_speeds
    from cosim.bicycle.parameters import forward_speed, from_command_line
    from cosim.fmu.parameters import declarations
    from cosim.fmu.target import resolve_fmu

    speeds = parse_speeds(args.speeds)
    if not speeds:
        raise ParameterError(f"--speeds {args.speeds}: no speeds")
    declared = declarations(args.target)  # a model's are those of its FMU: checked before it is built
    fs = forward_speed(args.target, declared)
    hint = "give its operating-point value with --input {name}=VALUE"
    params = from_command_line(args.target, args.param, parameter_set=args.params, input_hint=hint,
                               declared=declared)
    for v in (min(speeds), max(speeds)):  # the speeds' declared bounds (an interval: the extremes decide)
        try:
            from_command_line(args.target, args.param, parameter_set=args.params, input_hint=hint, speed=v,
                              declared=declared, report=lambda message: None)
        except ParameterError as exc:
            raise ParameterError(f"--speeds {args.speeds}: {exc}") from None
    if fs.parameter in params:
        raise ParameterError(f"--param {fs.parameter}: the speed parameter is set by --speeds")
    inputs = _operating_point(args.target, args.input, declared) if args.input else {}
    fmu = resolve_fmu(args.target, versions=ALL_FMI_VERSIONS)
    try:
        sweep = linearize_speeds(fmu, speeds, params, inputs or None, lock_hinge=args.lock_hinge,
                                 timeout=args.timeout)
    except NotSteadyMotion as exc:
        raise ParameterError(f"--lock-hinge: {exc}") from None
    if args.json:
        print(json.dumps(sweep.to_dict(matrices=args.matrices)))  # one line: 1000 speeds print fast
        return EXIT_OK
    lateral = sweep.steady is not None
    ev = sweep.lateral_eigenvalues if lateral else sweep.eigenvalues
    print(f"{sweep.model} linearized ({sweep.method}) at {len(sweep)} speeds"
          + (f", {params}" if params or inputs else "") + (f", inputs {inputs}" if inputs else ""))
    if lateral:
        first = next((s for s in sweep.steady if not isinstance(s, NotSteadyMotion)), None)
        print("eigenvalues [1/s] of the lateral dynamics about upright straight running"
              + (f" ({', '.join(first.system.states)}; rider hinge {first.hinge})" if first and first.hinge else
                 f" ({', '.join(first.system.states)})" if first else "")
              + "; the other eigenvalues are exact zeros (see cosim linearize --help)")
    else:
        print(f"eigenvalues [1/s] of A ({', '.join(sweep.systems[0].states)})")
    print(f"{fs.label + ' [m/s]':>10}{'eigenvalues':>22}")
    for k, v in enumerate(sweep.speeds):
        row = ev[k]
        if lateral and isinstance(sweep.steady[k], NotSteadyMotion):
            text = f"no lateral reduction: {sweep.steady[k]}"
        else:
            text = "".join(f"{f'{e.real:.6g}{e.imag:+.6g}j' if e.imag else f'{e.real:.6g}':>22}" for e in row)
        print(f"{v:>10.6g}{text}")
    return EXIT_OK


def _cmd_compare(args) -> int:
    from cosim.bicycle.linearize import parse_speeds
    from cosim.fmu.parameters import split_assignment

    # the options are checked before the analytic models (SciPy, python-control) are imported
    if not args.tol > 0:
        raise ParameterError(f"--tol must be > 0, got {args.tol:g}")
    speeds = parse_speeds(args.speeds) if args.speeds else None
    parameters = dict(split_assignment(a) for a in args.param)  # a repeated name: the last wins

    from cosim.analytic.compare import format_table
    from cosim.bicycle.compare import compare_model
    from cosim.bicycle.parameters import forward_speed

    comparisons = compare_model(args.model, speeds, parameters, args.params)
    worst = max(c.error for c in comparisons)
    if args.json:
        print(json.dumps({"model": args.model, "tolerance": args.tol, "largest_error": worst,
                          "comparisons": [c.to_dict() for c in comparisons]}, indent=2))
    else:
        print(f"{args.model}: FMU linearization vs analytic model (relative errors)")
        print(format_table(comparisons, forward_speed(args.model).label))
    if not worst <= args.tol:
        print(f"cosim compare: largest relative error {worst:.2e} exceeds --tol {args.tol:g}", file=sys.stderr)
        return EXIT_CHECK_FAILED
    return EXIT_OK


def _signals_option(parser) -> None:
    parser.add_argument("--signals", default=None, metavar="A,B,...",
                        help="the signals --plot draws, one panel each (default: at most 4: roll and steer "
                             "angles phi, delta, then the inputs, the torques, speed v and lateral position y, "
                             "then the others); an unknown name is refused with the list of those available")


def _run_plotting(spec, data, signals: list[str] | None, plot_path: str | None) -> dict:
    """The plot keywords of a co-simulation result: the units its FMU components declare (a
    Python block declares none), the chosen signals (checked against the recorded columns)."""
    from cosim.cosimulation.factory import recorded_units
    from cosim.fmu.simulate import check_signals, numeric_names

    if not plot_path:
        return {}
    if signals is not None:
        check_signals(signals, numeric_names(data))
    return {"units": recorded_units(spec), "signals": signals}


def _cmd_run(args) -> int:
    from cosim.cosimulation.factory import run_system
    from cosim.cosimulation.master import RunFailed
    from cosim.cosimulation.system import load_system
    from cosim.fmu.simulate import IncompleteResult, incomplete_path

    output = Path(args.output) if args.output else Path(f"{Path(args.system).stem}.csv")
    _check_outputs(output, args.plot)  # before any build or run
    signals = _signals(args)
    spec = load_system(args.system)
    try:
        result = run_system(spec, timeout=args.timeout)
    except RunFailed as exc:  # an FMU failed a step: the rows before it are kept
        result = exc.result
    outcome = result.outcome
    try:  # the recorded columns are known now: an unknown --signals name costs the plot only
        plotting = _run_plotting(spec, result.data, signals, args.plot)
    except ParameterError as exc:
        kept = incomplete_path(output) if not outcome.complete else output
        _write_results(result.data, kept, None, spec.name)
        raise ParameterError(f"{exc}; the {_rows(result.data)} computed were written to {kept}, "
                             "without a plot") from None
    if not outcome.complete:  # an FMU failed or a signal turned non-finite: keep the rows
        exc = IncompleteResult(outcome.message, result.data, outcome.time, outcome.message)
        return _write_incomplete(exc, output, args.plot, spec.name, "run", plotting)
    _write_results(result.data, output, args.plot, spec.name, plotting=plotting)
    end = float(result.data["time"][-1])
    summary = f"wrote {output} ({result.steps} steps, {len(result.data)} rows, t = {spec.start:g} .. {end:g} s)"
    if outcome.status == "terminated":  # the model's own end: one note, as simulate gives it
        print(f"cosim run: note: {outcome.message}", file=sys.stderr)
        print(summary)
    else:
        print(f"{outcome.message}; {summary}")
    if args.plot:
        print(f"wrote {args.plot}")
    return EXIT_OK if outcome.status != "fell" or args.allow_fall else EXIT_FELL


def _cmd_export_ssp(args) -> int:
    from cosim.cosimulation.ssp import FileNote, export_ssp
    from cosim.cosimulation.system import load_system

    check_output(args.output, "SSP file")  # before anything is built
    path, notes = export_ssp(load_system(args.system), args.output, fmi_version=args.fmi_version,
                             ssp_version=args.ssp_version)
    for note in notes:
        print(f"{'note' if isinstance(note, FileNote) else 'twin'}: {note}")
    print(f"wrote {path}")
    return EXIT_OK


def _cmd_figures(args) -> int:
    from cosim.figures import make_figures

    for path in make_figures(args.names, args.output, jobs=args.jobs):
        print(f"wrote {path}")
    return EXIT_OK


def _cmd_app(args) -> int:
    if args.export is not None:
        from cosim.app.export import export_app

        r = export_app(args.export)
        print(f"wrote {r.index} and {r.bundle} ({r.bytes / 1e3:.0f} kB); open {r.index.resolve().as_uri()}")
        if args.open:
            import webbrowser

            webbrowser.open(r.index.resolve().as_uri())
        return EXIT_OK
    from cosim.app.server import serve

    serve(args.port, args.open, announce=lambda line: print(line, flush=True))
    return EXIT_OK


def _cmd_animate(args) -> int:
    from cosim.app.animate import animate

    r = animate(args.result, args.output, params=args.params, param=args.param, speed=args.speed, signs=args.signs)
    for note in r.notes:
        print(f"note: {note}")
    print(f"wrote {r.path} ({r.rows} samples, {r.duration:g} s, {r.bytes / 1e3:.0f} kB); "
          f"open {r.path.resolve().as_uri()}")
    return EXIT_OK


def _cmd_diagram(args) -> int:
    from cosim.diagram.svg import write_diagram

    path, drawing = write_diagram(args.model, args.output, icon=args.icon)
    what = f"{drawing.components} components, {drawing.connections} connections" if drawing.layer == "diagram" \
        else f"{drawing.components} connectors"
    print(f"wrote {path} ({drawing.layer} layer of {drawing.class_name}: {what})")
    for note in drawing.notes:
        print(f"note: {note}")
    return EXIT_OK


def _cmd_demo(args) -> int:
    from cosim.studies.demo import run_demo

    run_demo(Path(args.output))
    return EXIT_OK


def lenient_option(p: argparse.ArgumentParser, what: str = "it") -> None:
    """``--lenient``: open FMUs whose model description fails FMPy's checks (findings as warnings)."""
    p.add_argument("--lenient", action="store_true",
                   help=f"open {what} even if its modelDescription.xml fails FMPy's schema or consistency "
                        "checks (as FMPy's validate=False does): each finding is a warning line, the run is "
                        "attempted; unsafe archives and unsupported FMI versions are still refused")


@contextlib.contextmanager
def use_library(path: str | None):
    """Resolve model names in the folders ``path`` and the shipped library while the command runs.

    The one place where ``--library`` takes effect: its folders (and the shipped library, last)
    become ``COSIM_MODELICA_PATH``, which :func:`cosim.compiler.library.library_paths` reads
    wherever a model is resolved (``build``, ``resolve_fmu``, parameter declarations, system
    files, matrix builds and worker processes). The variable is restored afterwards, so an
    in-process caller of :func:`main` sees no change.

    Raises
    ------
    ModelicaError
        If ``path`` is not a folder, before any work.
    """
    if path is None:
        yield
        return
    from cosim.compiler.library import library_paths, load_library

    previous = os.environ.get(LIBRARY_VARIABLE)
    os.environ[LIBRARY_VARIABLE] = os.pathsep.join(map(str, library_paths(path)))
    load_library.cache_clear()  # a library parsed earlier in this process under the default key
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop(LIBRARY_VARIABLE, None)
        else:
            os.environ[LIBRARY_VARIABLE] = previous
        load_library.cache_clear()


def _parameter_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter value (repeatable; the last of a repeated NAME wins)")
    p.add_argument("--params", default=None, metavar="NAME|FILE",
                   help="Meijaard parameter set (benchmark, astrom2005, astrom2005-riderless or a TOML file)")


def parser() -> argparse.ArgumentParser:
    raw = argparse.RawDescriptionHelpFormatter
    p = argparse.ArgumentParser(
        prog="cosim", formatter_class=raw, epilog=MAIN_EPILOG,
        description="Bicycle models of Astrom, Klein and Lennartsson (2005) as FMI 2.0 FMUs: build, validate, "
                    "simulate, linearize, co-simulate.")
    p.add_argument("--version", action="version", version=f"cosim {__version__}")
    verbosity_options(p, NORMAL)
    sub = p.add_subparsers(dest="command", required=True, metavar="VERB")

    b = sub.add_parser("build", help="compile Modelica models to FMI 2.0 / 3.0 FMUs (ME + CS)", formatter_class=raw,
                       epilog=f"{FMU_FOLDER}\n\n{EXIT_CODES}")
    b.add_argument("models", nargs="*", help="model names (default: every exported model)")
    b.add_argument("-o", "--output", default=None, help="output folder (default: ./fmus or $COSIM_FMU_DIR)")
    b.add_argument("-j", "--jobs", type=positive_int, default=os.cpu_count() or 1,
                   help="parallel builds (>= 1; default: number of CPUs)")
    b.add_argument("--force", action="store_true", help="rebuild even if up to date")
    b.add_argument("--fmi-version", action=_FmiVersions, nargs="+", metavar="{2,3}",
                   help="FMI version(s) to build: 2 (OUTPUT/NAME.fmu, the default), 3 (OUTPUT/fmi3/NAME.fmu); "
                        "repeat or list both (--fmi-version 2 3) to build both from one compilation")
    b.add_argument("--wasm", action="store_true",
                   help="also compile each FMI 2.0 FMU's C sources to WebAssembly for the browser: "
                        "OUTPUT/wasm/NAME.wasm + NAME.json (value references, default experiment); needs "
                        "the optional extra 'wasm' (pip install 'bicycle-cosim[wasm]')")
    library_option(b)
    b.set_defaults(func=_cmd_build)

    ls = sub.add_parser("list", help="models of the library with inputs, outputs, parameters")
    ls.add_argument("--json", action="store_true",
                    help="print JSON (full parameter values; null where a value is unknown)")
    ls.add_argument("--exported", action="store_true", help="only models that `cosim build` exports")
    library_option(ls)
    ls.set_defaults(func=_cmd_list)

    i = sub.add_parser("info", help="describe an FMU or a model", formatter_class=raw, epilog=EXIT_CODES)
    i.add_argument("target", help="FMU file or model name")
    i.add_argument("--json", action="store_true", help="print JSON instead of text")
    lenient_option(i, "the FMU")
    library_option(i)
    i.set_defaults(func=_cmd_info)

    v = sub.add_parser("validate", help="check FMI 2.0/3.0 FMUs (FMPy's static validation + calls into the binary)",
                       formatter_class=raw,
                       epilog="Static checks (FMPy's validate_fmu, sources, binary) and checks that call the binary:\n"
                              "token (a wrong GUID/instantiationToken is refused), state-machine (calls in a wrong\n"
                              "state are refused), directional-derivatives (against central differences, relative\n"
                              "1e-6), adjoint-derivatives (FMI 3: v^T(Ju) = (J^T v)^T u to 1e-12), fmu-state (get/\n"
                              "set/serialize round trips bit-identical), cs-step (FMI 3: earlyReturn and\n"
                              "lastSuccessfulTime of fmi3DoStep), me-run and cs-run (a short run, finite values).\n"
                              "A problem is what the FMI 2.0/3.0 standard rules out (\"must\", \"shall\"): a wrong\n"
                              "derivative, a state not restored, earlyReturn where not allowed, a crash or hang; a\n"
                              "warning is what it allows or leaves undefined but a robust FMU avoids (a forbidden\n"
                              "call accepted, a wrong token accepted, a legal call failing, a failed short run).\n"
                              "Each problem and warning is one line naming its check; checks the FMU does not\n"
                              "declare are listed as skipped. A crash of the binary is reported as a problem of\n"
                              "the check it happened in (the checks run in a child process).\n\n"
                              "Every target is checked; a file that cannot be read as an FMU gets an error line "
                              "(exit 2), an FMU with problems lists them (exit 1); warnings alone exit 0.\n\n"
                              + EXIT_CODES)
    v.add_argument("targets", nargs="+", help="FMU files or model names")
    timeout_option(v, "one check has not ended")
    library_option(v)
    v.set_defaults(func=_cmd_validate)

    s = sub.add_parser("simulate", help="simulate an FMU or model", formatter_class=raw, epilog=SIMULATE_EPILOG)
    s.add_argument("target", help="FMU file or model name (built first if needed)")
    s.add_argument("--stop-time", type=_finite, required=True, help="stop time [s]")
    s.add_argument("--step", type=_finite, default=None,
                   help="output / communication interval [s], > 0 (default: the FMU's DefaultExperiment "
                        "stepSize, else 0.01 s; see 'time grid')")
    s.add_argument("--fmi-type", choices=("cs", "me"), default="cs",
                   help="FMI interface: cs = Co-Simulation (the FMU's own solver, default), "
                        "me = Model Exchange (FMPy's CVode)")
    _parameter_options(s)
    s.add_argument("--input", action="append", default=[], metavar="NAME=FILE.csv|FILE.npy|step:T0:VALUE",
                   help="an input signal (repeatable): a CSV or .npy of time [s], value, or a step of VALUE "
                        "at T0 [s] (see 'inputs')")
    s.add_argument("-o", "--output", default=None, help="result .csv or .npy (default: <model>.csv)")
    s.add_argument("--plot", default=None, help="save a plot of the result (PNG, PDF, SVG, ...)")
    _signals_option(s)
    timeout_option(s, "it completes no step")
    lenient_option(s, "the FMU")
    library_option(s)
    s.set_defaults(func=_cmd_simulate)

    lin = sub.add_parser("linearize", help="A, B, C, D of an FMU or model at its initial point",
                         formatter_class=raw, epilog=f"{LINEARIZE_EPILOG}\n\n{EXIT_CODES}")
    lin.add_argument("target", help="FMU file or model name")
    _parameter_options(lin)
    lin.add_argument("--input", action="append", default=[], metavar="NAME=VALUE",
                     help="input value at the operating point (default: the input's start value)")
    lin.add_argument("--speed", type=_finite, default=None, metavar="V",
                     help="forward speed [m/s]: sets V or v; nonlinear bicycles: upright straight running, "
                          "u_R0 = -V/rR (V >= 0)")
    lin.add_argument("--speeds", default=None, metavar="A:B:STEP|V1,V2,...",
                     help="a speed sweep [m/s] (a range, B included, or a list): one FMU instance, per speed "
                          "the eigenvalues (and --json: the lateral reduction); not with --speed")
    lin.add_argument("--matrices", action="store_true",
                     help="with --speeds --json: also A, B, C, D per speed")
    lin.add_argument("--lock-hinge", action="store_true",
                     help="WhippleRider: lock the rider's hip hinge (exactly, by its reaction torque) in the "
                          "lateral linearization")
    lin.add_argument("--json", action="store_true", help="print A, B, C, D and the eigenvalues as JSON")
    timeout_option(lin, "the linearization has not ended")
    lenient_option(lin, "the FMU")
    library_option(lin)
    lin.set_defaults(func=_cmd_linearize)

    cmp_ = sub.add_parser("compare", help="FMU linearization vs the analytic model", formatter_class=raw,
                          epilog=EXIT_CODES)
    cmp_.add_argument("model", help="model name (with an analytic twin)")
    cmp_.add_argument("--speeds", default=None, metavar="A:B:STEP|V1,V2,...",
                      help="forward speeds [m/s] to compare at: a range or a list (default: the model's V)")
    _parameter_options(cmp_)
    cmp_.add_argument("--tol", type=_finite, default=1e-9, help="largest accepted relative error (> 0)")
    cmp_.add_argument("--json", action="store_true", help="print the comparison as JSON")
    library_option(cmp_)
    cmp_.set_defaults(func=_cmd_compare)

    run = sub.add_parser("run", help="co-simulate a system file (FMUs and Python components)",
                         formatter_class=raw, epilog=RUN_EPILOG)
    run.add_argument("system", help="system file (TOML)")
    run.add_argument("-o", "--output", default=None, help="result .csv or .npy (default: <system>.csv)")
    run.add_argument("--plot", default=None, help="save a plot of the recorded signals (PNG, PDF, SVG, ...)")
    _signals_option(run)
    run.add_argument("--allow-fall", action="store_true", help="exit 0 even if the bicycle falls")
    timeout_option(run, "the system completes no communication step")
    lenient_option(run, "every FMU component of the system")
    library_option(run)
    run.set_defaults(func=_cmd_run)

    ssp = sub.add_parser("export-ssp", help="export a system as SSP 1.0 or 2.0 (FMUs in resources/)",
                         formatter_class=raw,
                         epilog="The OSP fixed-step algorithm of the SSP needs a step that divides stop - start.\n\n"
                                f"{FMU_FOLDER}\n\n{EXIT_CODES}")
    ssp.add_argument("system", help="system file (TOML); Python blocks must be replaced by Modelica twins")
    ssp.add_argument("-o", "--output", required=True, help="the .ssp file to write")
    ssp.add_argument("--fmi-version", choices=("2", "3"), default=None,
                     help="build every model (and Python block twin) as an FMI 2.0 or 3.0 FMU (default: each "
                          "component's fmi_version in the system file, else 2); FMU files keep theirs. "
                          "Ecos runs both, libcosim FMI 2.0 only")
    ssp.add_argument("--ssp-version", choices=("1.0", "2.0"), default="1.0",
                     help="the SSP version of the archive (default: 1.0, the only one Ecos reads)")
    library_option(ssp)
    ssp.set_defaults(func=_cmd_export_ssp)

    fig = sub.add_parser("figures", help="the paper's figures from FMU simulation and linearization",
                         formatter_class=raw, epilog=f"{FMU_FOLDER}\n\n{EXIT_CODES}")
    fig.add_argument("names", nargs="*", help="figure names, e.g. fig5 fig8 (default: all)")
    fig.add_argument("-o", "--output", default="figures", help="output folder (default: figures/)")
    fig.add_argument("-j", "--jobs", type=positive_int, default=None, metavar="N",
                     help="worker processes (default: the number of CPUs; 1: all in this process); "
                          "the figures are the same for any N")
    library_option(fig)
    fig.set_defaults(func=_cmd_figures)

    # loaded when the parser is built, so that importing cosim.cli stays cheap
    from cosim.analytic import cli as analytic_cli
    from cosim.matrix import cli as matrix_cli

    analytic_cli.add_parser(sub)
    matrix_cli.add_parser(sub)

    app = sub.add_parser("app", help="the bicycles in the browser: eigenvalues, 3-D rides, demos (the FMUs as WebAssembly)",
                         formatter_class=raw,
                         epilog="Serves the app on 127.0.0.1, or writes it with --export as a static site (index.html\n"
                                "+ bundle.js) that works from file:// with no network. Builds the FMUs the page runs\n"
                                "(the linear and nonlinear Whipple bicycles, the PD and LaneChange controllers) and\n"
                                "their WebAssembly modules first (incremental); needs\n"
                                "the optional extra 'wasm' (pip install 'bicycle-cosim[wasm]').\n\n"
                                f"{FMU_FOLDER}\n\n{EXIT_CODES}")
    app.add_argument("--export", default=None, metavar="DIR", help="write the static site into DIR and exit")
    app.add_argument("--port", type=_port, default=8000, help="TCP port on 127.0.0.1 (default 8000; 0: any free one)")
    app.add_argument("--open", action="store_true", help="open the page in the default web browser (also with --export)")
    library_option(app)
    app.set_defaults(func=_cmd_app)

    an = sub.add_parser("animate", help="a self-contained 3-D animation (HTML) of a bicycle result",
                        formatter_class=raw,
                        epilog="RESULT is a .csv or .npy of `cosim simulate` or `cosim run` with the configuration\n"
                               "signals time, phi, delta (required) and x, y, psi, theta, thetaR, thetaF, named with or\n"
                               "without the prefix of one component (bike.phi or phi; the component that has both phi\n"
                               "and delta). Results of the linear models have no x:\n"
                               "--speed V draws x = V t; missing y, psi, theta are 0, missing wheel angles are rolled\n"
                               "along the path. The page (three.js inlined) opens from file:// with no network.\n"
                               "Signs: the page draws Meijaard's axes (roll, steer, yaw, y positive to the right); the\n"
                               "paper's second-order models write ISO 8855 signs (steer, yaw and the path eta positive\n"
                               "to the left): --signs auto (default) takes those for a result with eta and no y.\n\n"
                               + EXIT_CODES)
    an.add_argument("result", help="result file (.csv or .npy)")
    an.add_argument("-o", "--output", default=None,
                    help="the HTML file (default: the result's name with .html, in the working directory)")
    an.add_argument("--params", default=None, metavar="NAME|FILE",
                    help="parameter set of the drawn geometry (default: benchmark; or a TOML file)")
    an.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                    help="a geometry value overriding --params: w, c, lam, rR, rF, tR, tF [m, rad] (repeatable)")
    an.add_argument("--speed", type=_finite, default=None, metavar="V",
                    help="forward speed [m/s] for a result without x (x = V t)")
    an.add_argument("--signs", choices=("auto", "meijaard", "paper"), default="auto",
                    help="sign convention of the result: meijaard (Whipple models), paper (ISO 8855, the "
                         "second-order models: steer, yaw, eta positive to the left) or auto (default: paper "
                         "for a result with eta and no y)")
    an.set_defaults(func=_cmd_animate)

    dg = sub.add_parser("diagram", help="a class's diagram (or icon) layer as SVG, from its graphical annotations",
                        formatter_class=raw,
                        epilog="Draws the Diagram annotation of the class and its bases, each component as its class's\n"
                               "icon in the extent of its Placement (flipped, rotated; its connectors at their own\n"
                               "placements) with its name, and each connect() as its Line annotation (MLS chapter 18).\n"
                               "A component without a Placement is drawn as a labelled box at a default position and a\n"
                               "connection without a Line as a straight grey line; the SVG's title says so. The SVG\n"
                               "groups each component in <g data-component=NAME> and each connection in\n"
                               "<g data-connect=\"A B\">.\n\n" + EXIT_CODES)
    dg.add_argument("model", help="full class name, e.g. Bicycle.Bicycles.Whipple")
    dg.add_argument("-o", "--output", default=None,
                    help="the SVG file (default: <class name with _>.svg, -icon.svg with --icon, in the working "
                         "directory)")
    dg.add_argument("--icon", action="store_true", help="draw the icon layer (with the connectors) instead")
    library_option(dg)
    dg.set_defaults(func=_cmd_diagram)

    d = sub.add_parser("demo", help="build, validate and simulate the bundled bicycle", formatter_class=raw,
                       epilog=f"{FMU_FOLDER}\n\n{EXIT_CODES}")
    d.add_argument("-o", "--output", default="demo", help="folder for results (default: demo/)")
    library_option(d)
    d.set_defaults(func=_cmd_demo)
    for verb in sub.choices.values():  # `cosim VERB -q` as well as `cosim -q VERB`
        verbosity_options(verb, argparse.SUPPRESS)
    return p


def verbosity_options(p: argparse.ArgumentParser, default) -> None:
    """``-q``/``--quiet`` and ``-v``/``--verbose`` (a verb's own take the place of the main
    parser's only when given: their default there is ``argparse.SUPPRESS``)."""
    group = p.add_mutually_exclusive_group()
    group.add_argument("-q", "--quiet", dest="verbosity", action="store_const", const=QUIET, default=default,
                       help="no progress and no informational lines (results, warnings and errors are printed)")
    group.add_argument("-v", "--verbose", dest="verbosity", action="store_const", const=VERBOSE, default=default,
                       help="more detail on stderr: the time of each step and the paths written")


def _debug() -> bool:
    return os.environ.get("COSIM_DEBUG", "").strip() not in ("", "0")


@contextlib.contextmanager
def _lenient(args):
    """``--lenient`` for every FMU the command opens: each finding one ``warning: FMU: ...`` line."""
    if not getattr(args, "lenient", False):
        yield
        return
    from cosim.fmu.access import lenient_reading

    with lenient_reading(warn=lambda message: print(f"cosim {args.command}: warning: {message}", file=sys.stderr)):
        yield


def main(argv: list[str] | None = None) -> int:
    """Run one command; see the module docstring for the exit status."""
    args = parser().parse_args(argv)
    if getattr(args, "output", None) is None and args.command == "build":
        from cosim.compiler.build import DEFAULT_OUTPUT

        args.output = DEFAULT_OUTPUT
    reporter = Reporter(args.command, args.verbosity)
    try:
        with use_library(getattr(args, "library", None)), _lenient(args), reporting(reporter):
            return args.func(args)
    except ResultNotWritten as exc:  # computed, but (partly) lost to a full disk, ...
        print(f"cosim {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    except CosimError as exc:
        print(f"cosim {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except FileNotFoundError as exc:  # a path the user named (e.g. --params FILE) does not exist
        print(f"cosim {args.command}: error: {os_error_message(exc) if exc.filename else exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:  # e.g. `cosim info ... | head`
        return EXIT_OK
    except OSError as exc:  # one no layer named: still one line with the path, never exit 70
        print(f"cosim {args.command}: error: {os_error_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(f"cosim {args.command}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # the safety net: a bug, reported in one line
        if _debug():
            traceback.print_exc()
        text = " ".join(str(exc).split())
        print(f"cosim {args.command}: internal error: {type(exc).__name__}: {text} "
              "(set COSIM_DEBUG=1 for the traceback)", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
