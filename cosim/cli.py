"""The `cosim` command line."""
from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from . import __version__
from .errors import CosimError


def _cmd_build(args) -> int:
    from .compiler.build import build

    results = build(args.models or None, args.output, jobs=args.jobs, library_path=args.library, force=args.force)
    for r in results:
        print(f"{'built ' if r.rebuilt else 'up to date'} {r.fmu}  ({r.seconds:.1f} s)")
    return 0


def _cmd_list(args) -> int:
    from .catalog import catalog
    from .compiler.library import load_library

    summaries = catalog(load_library(args.library), exported_only=args.exported)
    if args.json:
        print(json.dumps([s.to_dict() for s in summaries], indent=2))
        return 0
    for s in summaries:
        mark = "*" if s.exported else " "
        print(f"{mark} {s.name}: {s.description}")
        for label, signals in (("inputs", s.inputs), ("outputs", s.outputs)):
            if signals:
                print(f"      {label}: " + ", ".join(f"{x.name} [{x.unit or '-'}]" for x in signals))
        if s.parameters:
            print("      parameters: " + ", ".join(f"{p.name}={p.value}" for p in s.parameters))
    print("\n* exported by `cosim build`")
    return 0


def _cmd_info(args) -> int:
    from .info import describe_target

    print(describe_target(args.target, as_json=args.json))
    return 0


def _cmd_validate(args) -> int:
    from .target import resolve_fmu
    from .validation import validate

    failed = 0
    for target in args.targets:
        fmu = resolve_fmu(target)
        problems = validate(fmu)
        if problems:
            failed += 1
            print(f"{fmu}: {len(problems)} problem(s)")
            for p in problems:
                print(f"  - {p}")
        else:
            print(f"{fmu}: valid")
    return 1 if failed else 0


def _cmd_simulate(args) -> int:
    from fmpy import read_model_description

    from .parameters import from_command_line
    from .simulation import input_signals, plot, simulate, write_csv
    from .target import resolve_fmu

    params = from_command_line(args.target, args.param, parameter_set=args.params)  # before any build
    fmu = resolve_fmu(args.target)
    md = read_model_description(str(fmu))
    t0 = float(md.defaultExperiment.startTime or 0.0) if md.defaultExperiment else 0.0
    inputs = input_signals(fmu, args.input, t0, args.stop_time)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    result = simulate(fmu, args.stop_time, args.step, args.fmi_type, params, inputs,
                      outputs=outputs or None, progress=sys.stderr.isatty())
    output = args.output or f"{fmu.stem}.csv"
    write_csv(result, output)
    print(f"wrote {output} ({len(result)} rows: {', '.join(result.dtype.names)})")
    if args.plot:
        plot(result, args.plot, title=md.modelName)
        print(f"wrote {args.plot}")
    return 0


SPEED_NAMES = ("V", "v")


def _speed_parameter(target: str) -> str:
    from .parameters import declarations

    declared = declarations(target)
    for name in SPEED_NAMES:
        if name in declared and declared[name].causality == "parameter":
            return name
    from .errors import ParameterError

    raise ParameterError(f"{target} has no speed parameter ({' or '.join(SPEED_NAMES)})")


def _cmd_linearize(args) -> int:
    from .linearize import linearize
    from .parameters import from_command_line
    from .target import resolve_fmu

    extra = {_speed_parameter(args.target): args.speed} if args.speed is not None else {}
    params = from_command_line(args.target, args.param, extra, parameter_set=args.params)
    result = linearize(resolve_fmu(args.target), params)
    if args.json:
        print(result.to_json())
        return 0
    import numpy as np

    np.set_printoptions(precision=6, suppress=False, linewidth=120)
    print(f"{result.model} linearized ({result.method}) at {params or 'default parameters'}")
    print(f"states:  {', '.join(result.states)}\ninputs:  {', '.join(result.inputs)}\n"
          f"outputs: {', '.join(result.outputs)}")
    for name in "ABCD":
        print(f"{name} =\n{getattr(result, name)}")
    print("eigenvalues:", ", ".join(f"{e:.6g}" for e in result.eigenvalues))
    return 0


def _cmd_compare(args) -> int:
    from .compare import compare_systems, format_table, parse_speeds
    from .linearize import linearize
    from .parameters import declarations, from_command_line
    from .target import is_fmu_path, resolve_fmu
    from .twins import analytic_system

    if is_fmu_path(args.model):
        from .errors import ParameterError

        raise ParameterError("compare needs a model name (the analytic twin is chosen by model)")
    speed = _speed_parameter(args.model)
    speeds = parse_speeds(args.speeds) if args.speeds else [None]
    base = from_command_line(args.model, args.param, parameter_set=args.params)
    declared = declarations(args.model)
    for v in speeds:
        if v is not None:
            from .parameters import check

            check({speed: v}, declared)
    fmu = resolve_fmu(args.model)
    defaults = _parameter_defaults(fmu)
    comparisons = []
    for v in speeds:
        params = {**base, **({speed: v} if v is not None else {})}
        found = linearize(fmu, params).to_statespace()
        expected = analytic_system(args.model, {**defaults, **params})
        comparisons.append(compare_systems(args.model, {**defaults, **params}, found, expected))
    worst = max(c.error for c in comparisons)
    if args.json:
        print(json.dumps({"model": args.model, "tolerance": args.tol, "largest_error": worst,
                          "comparisons": [c.to_dict() for c in comparisons]}, indent=2))
    else:
        print(f"{args.model}: FMU linearization vs analytic model (relative errors)")
        print(format_table(comparisons, speed))
    if worst > args.tol:
        print(f"cosim compare: largest relative error {worst:.2e} exceeds --tol {args.tol:g}", file=sys.stderr)
        return 1
    return 0


def _parameter_defaults(fmu) -> dict:
    """Start values of the FMU's top-level Real parameters."""
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and "." not in v.name and v.type == "Real" and v.start is not None}


def _cmd_run(args) -> int:
    from .cosimulation.factory import run_system
    from .simulation import plot, write_csv

    result = run_system(args.system)
    output = args.output or f"{Path(args.system).stem}.csv"
    if output.endswith(".npy"):
        import numpy as np

        np.save(output, result.data)  # structured array: time and "component.output" columns
    else:
        write_csv(result.data, output)
    print(f"{result.outcome.message}; wrote {output} ({result.steps} steps)")
    if args.plot:
        plot(result.data, args.plot, title=Path(args.system).stem)
        print(f"wrote {args.plot}")
    return 0 if result.outcome.status == "completed" or args.allow_fall else 3


def _cmd_export_ssp(args) -> int:
    from .cosimulation.ssp import export_ssp
    from .cosimulation.system import load_system

    path, notes = export_ssp(load_system(args.system), args.output)
    for note in notes:
        print(f"twin: {note}")
    print(f"wrote {path}")
    return 0


def _cmd_figures(args) -> int:
    from .figures import make_figures

    for path in make_figures(args.names, args.output):
        print(f"wrote {path}")
    return 0


def _cmd_demo(args) -> int:
    from .demo import run_demo

    run_demo(Path(args.output))
    return 0


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="cosim", description="Bicycle models of Astrom, Klein and Lennartsson (2005) as FMI 2.0 FMUs: build, validate, simulate.")
    p.add_argument("--version", action="version", version=f"cosim {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    b = sub.add_parser("build", help="compile Modelica models to FMUs (ME + CS)")
    b.add_argument("models", nargs="*", help="model names (default: every exported model)")
    b.add_argument("-o", "--output", default=None, help="output folder (default: fmus/)")
    b.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1, help="parallel builds")
    b.add_argument("--force", action="store_true", help="rebuild even if up to date")
    b.add_argument("--library", default=None, help="Modelica library folder (default: modelica/)")
    b.set_defaults(func=_cmd_build)

    ls = sub.add_parser("list", help="models of the library with inputs, outputs, parameters")
    ls.add_argument("--json", action="store_true")
    ls.add_argument("--exported", action="store_true", help="only models that `cosim build` exports")
    ls.add_argument("--library", default=None)
    ls.set_defaults(func=_cmd_list)

    i = sub.add_parser("info", help="describe an FMU or a model")
    i.add_argument("target", help="FMU file or model name")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=_cmd_info)

    v = sub.add_parser("validate", help="check FMUs (FMPy validation + own checks)")
    v.add_argument("targets", nargs="+", help="FMU files or model names")
    v.set_defaults(func=_cmd_validate)

    s = sub.add_parser("simulate", help="simulate an FMU or model")
    s.add_argument("target", help="FMU file or model name (built first if needed)")
    s.add_argument("--stop-time", type=float, required=True, help="stop time [s]")
    s.add_argument("--step", type=float, default=None, help="output / communication interval [s]")
    s.add_argument("--fmi-type", choices=("cs", "me"), default="cs")
    s.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    s.add_argument("--params", default=None, metavar="NAME|FILE",
                     help="Meijaard parameter set (benchmark, astrom2005, astrom2005-riderless or a TOML file)")
    s.add_argument("--input", action="append", default=[], metavar="NAME=FILE.csv|NAME=step:T0:VALUE")
    s.add_argument("-o", "--output", default=None, help="result CSV (default: <model>.csv)")
    s.add_argument("--plot", default=None, help="save a plot of the result (PNG)")
    s.set_defaults(func=_cmd_simulate)

    lin = sub.add_parser("linearize", help="A, B, C, D of an FMU or model at its initial point")
    lin.add_argument("target", help="FMU file or model name")
    lin.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    lin.add_argument("--params", default=None, metavar="NAME|FILE",
                     help="Meijaard parameter set (benchmark, astrom2005, astrom2005-riderless or a TOML file)")
    lin.add_argument("--speed", type=float, default=None, help="forward speed [m/s] (sets V)")
    lin.add_argument("--json", action="store_true")
    lin.set_defaults(func=_cmd_linearize)

    cmp_ = sub.add_parser("compare", help="FMU linearization vs the analytic model")
    cmp_.add_argument("model", help="model name (with an analytic twin)")
    cmp_.add_argument("--speeds", default=None, help="A:B:STEP or V1,V2,... [m/s]")
    cmp_.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    cmp_.add_argument("--params", default=None, metavar="NAME|FILE",
                     help="Meijaard parameter set (benchmark, astrom2005, astrom2005-riderless or a TOML file)")
    cmp_.add_argument("--tol", type=float, default=1e-9, help="largest accepted relative error")
    cmp_.add_argument("--json", action="store_true")
    cmp_.set_defaults(func=_cmd_compare)

    run = sub.add_parser("run", help="co-simulate a system file (FMUs and Python components)")
    run.add_argument("system", help="system file (TOML)")
    run.add_argument("-o", "--output", default=None, help="result .csv or .npy (default: <system>.csv)")
    run.add_argument("--plot", default=None, help="save a plot of the recorded signals (PNG)")
    run.add_argument("--allow-fall", action="store_true", help="exit 0 even if the bicycle falls")
    run.set_defaults(func=_cmd_run)

    ssp = sub.add_parser("export-ssp", help="export a system as SSP 1.0 (FMUs in resources/)")
    ssp.add_argument("system", help="system file (TOML); Python blocks must be replaced by Modelica twins")
    ssp.add_argument("-o", "--output", required=True, help="the .ssp file to write")
    ssp.set_defaults(func=_cmd_export_ssp)

    fig = sub.add_parser("figures", help="the paper's figures from FMU simulation and linearization")
    fig.add_argument("names", nargs="*", help="figure names, e.g. fig5 fig8 (default: all)")
    fig.add_argument("-o", "--output", default="figures", help="output folder (default: figures/)")
    fig.set_defaults(func=_cmd_figures)

    from . import analytic_cli
    from .matrix import cli as matrix_cli

    analytic_cli.add_parser(sub)
    matrix_cli.add_parser(sub)

    d = sub.add_parser("demo", help="build, validate and simulate the bundled bicycle")
    d.add_argument("-o", "--output", default="demo", help="folder for results (default: demo/)")
    d.set_defaults(func=_cmd_demo)
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    if getattr(args, "output", None) is None and args.command == "build":
        from .compiler.build import DEFAULT_OUTPUT

        args.output = DEFAULT_OUTPUT
    try:
        return args.func(args)
    except (CosimError, FileNotFoundError, ValueError) as exc:
        print(f"cosim {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. `cosim info ... | head`
        return 0
    except KeyboardInterrupt:
        print(f"cosim {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
