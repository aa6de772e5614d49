"""`cosim demo`: from a fresh checkout to numbers and a plot in one command.

Builds every exported model, validates the FMUs, and simulates the self-stabilizing bicycle of
eqs (14) + (11) under a steer-torque step, once as Co-Simulation and once as Model Exchange,
comparing the steady state with the one eq (15) predicts.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from cosim.errors import SimulationError
from cosim.fmu.simulate import input_signals, plot, simulate, variable_units, write_csv
from cosim.fmu.validate import validate
from cosim.folder_lock import folder_lock
from cosim.outputs import check_output, check_output_folder
from cosim.progress import active as progress

MODEL = "Bicycle.Bicycles.SelfStabilizing"
STOP = 30.0  # s: long enough for the slow roll mode to settle


def steady_state(T: float, m: float, a: float, h: float, b: float, c: float, lam: float, g: float, V: float, **_):
    """Steady roll and steer angle [rad] under a constant steer torque T [N.m], from (15) and (11)."""
    den = V**2 * math.sin(lam) - b * g * math.cos(lam)
    phi = b * (V**2 * h - a * c * g) * T / (a * c * m * g**2 * (b * h * math.cos(lam) - a * c * math.sin(lam)))
    k1 = b**2 / (den * m * a * c * math.sin(lam))
    k2 = b * g / den
    return phi, k1 * T - k2 * phi


#: The files the demo writes into its output folder.
OUTPUTS = ("self_stabilizing_cs.csv", "self_stabilizing_me.csv", "self_stabilizing.png", "lane_change.csv",
           "lane_change.png")


def run_demo(output: Path) -> None:
    """Build, validate, simulate and co-simulate; results into ``output``.

    Raises
    ------
    OutputError
        If ``output`` or one of its files cannot be written, or another demo is writing
        ``output`` (:class:`cosim.folder_lock.FolderBusy`), before anything is built.
    SimulationError
        If a built FMU fails validation.
    """
    # deferred: loads casadi, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT

    output = check_output_folder(Path(output), "demo folder")  # before the minutes of work below
    for name in OUTPUTS:
        check_output(output / name, "demo result")
    check_output_folder(DEFAULT_OUTPUT, "FMU folder")
    with folder_lock(output, "demo folder"), progress().steps(4):  # one demo writes the folder at a time
        _demo(output)


def _say(text: str) -> None:
    """A line of the demo's account on stdout, on a line of its own under the progress line."""
    progress().clear()
    print(text, flush=True)


def _demo(output: Path) -> None:
    """:func:`run_demo` in a checked and locked output folder."""
    # deferred: loads casadi, fmpy, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build
    from cosim.cosimulation.factory import recorded_units, run_system
    from cosim.cosimulation.system import load_system
    from cosim.fmu.access import read_fmu

    _say("1. building every exported model (pymoca -> CasADi -> C -> gcc) ...")
    progress().item("build every exported model")
    results = build(output=DEFAULT_OUTPUT, jobs=2)
    progress().item("validate the FMUs")
    with progress().steps(len(results)):
        for r in results:
            progress().item(r.model)
            _say(f"   {'built' if r.rebuilt else 'up to date'}: {r.fmu}")
            problems = validate(r.fmu)
            _say(f"   validation: {'no problems' if not problems else problems}")
            if problems:
                raise SimulationError(f"{r.fmu} failed validation")
    fmu = next(r.fmu for r in results if r.model == MODEL)

    V, T = 6.0, 1.0
    _say(f"2. simulating {MODEL} at V = {V} m/s, steer torque step T = {T} N.m at t = 0.5 s ...")
    inputs = input_signals(fmu, [f"T=step:0.5:{T}"], 0.0, STOP)
    runs = {}
    progress().item(f"simulate {MODEL}")
    for kind in ("cs", "me"):
        result = simulate(fmu, STOP, 0.01, kind, {"V": V}, inputs, outputs=["phi", "delta", "T"])
        write_csv(result, output / f"self_stabilizing_{kind}.csv")
        runs[kind] = result
    plot(runs["cs"], output / "self_stabilizing.png", title=f"{MODEL}, V = {V} m/s, T = {T} N.m step",
         units=variable_units(read_fmu(fmu)))
    params = dict(m=92, a=0.5, h=1.0, b=1.0, c=0.08, lam=math.radians(70), g=9.81, V=V)
    phi_ss, delta_ss = steady_state(T, **params)
    cs, me = runs["cs"], runs["me"]
    _say(f"   final roll  phi:   CS {cs['phi'][-1]: .6f} rad, ME {me['phi'][-1]: .6f} rad, eq (15) {phi_ss: .6f} rad")
    _say(f"   final steer delta: CS {cs['delta'][-1]: .6f} rad, ME {me['delta'][-1]: .6f} rad, eq (11) {delta_ss: .6f} rad")
    me_on_cs_grid = np.interp(cs["time"], me["time"], me["phi"])  # ME has an extra row at the input step
    _say(f"   CS vs ME max difference in phi: {np.max(np.abs(cs['phi'] - me_on_cs_grid)):.2e} rad")
    system = Path(__file__).resolve().parents[1] / "systems" / "lane-change.toml"
    _say(f"3. co-simulating {system.name}: WhippleLinear FMU + Python lane-change controller ...")
    progress().item(f"co-simulate {system.name}")
    lane = run_system(system)
    write_csv(lane.data, output / "lane_change.csv")
    plot(lane.data, output / "lane_change.png", title="lane change by counter-steering (benchmark, 5 m/s)",
         units=recorded_units(load_system(system)))
    y = lane.data["bike.y"]
    _say(f"   {lane.outcome.message}; lateral position first {y.min():.3f} m (counter-steer), "
         f"finally {y[-1]:.3f} m")
    _say(f"4. results in {output}/: {', '.join(OUTPUTS)}")
