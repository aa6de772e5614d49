"""`cosim analytic`: the linearized Whipple bicycle computed by the analytic Python model.

Prints the matrices M, C1, K0, K2 of Meijaard et al. (2007) for a parameter set, the
eigenvalues at the requested speed(s) and the weave and capsize speeds, all from
:mod:`cosim.analytic.whipple` (independent of the Modelica model and its FMU, so it serves as
the reference the FMU is checked against).
"""
from __future__ import annotations

import argparse
import json
import math

from cosim.errors import ParameterError

__all__ = ["add_parser", "run", "analytic_report", "format_report"]

MATRIX_UNITS = {"M": "kg m^2", "C1": "kg m (times v)", "K0": "kg m (times g)", "K2": "kg (times v^2)"}


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``cosim analytic`` on an ``argparse`` subparsers object."""
    p = subparsers.add_parser(
        "analytic",
        help="M, C1, K0, K2, eigenvalues, weave and capsize speeds of the analytic Whipple model",
        description="Linearized Whipple bicycle (Meijaard et al. 2007) from the analytic Python model: "
                    "matrices of M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi, T_delta], eigenvalues at "
                    "the given speeds, weave and capsize speeds. Sign conventions: Meijaard's (steer "
                    "positive to the right).")
    p.add_argument("--params", default="benchmark", metavar="NAME|FILE",
                   help="bundled parameter set (benchmark, astrom2005, astrom2005-riderless) or a TOML "
                        "file with the 26 Meijaard symbols (default: benchmark)")
    p.add_argument("--speed", type=float, nargs="+", default=[], metavar="V",
                   help="forward speed(s) v [m/s] for the eigenvalues (negative: rear-steered)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=run)
    return p


def analytic_report(params_name: str, speeds: list[float]) -> dict:
    """Everything `cosim analytic` prints, as a JSON-ready dict."""
    # deferred: `cosim VERB` for every verb builds this parser, and these load numpy and dataclasses
    from cosim.analytic import whipple as W
    from cosim.analytic.parameters import MAX_SPEED, load_set_for_models

    for v in speeds:
        if not math.isfinite(v):
            raise ParameterError(f"--speed must be finite, got {v}")
        if abs(v) > MAX_SPEED:
            raise ParameterError(f"--speed {v:g}: at most {MAX_SPEED:g} m/s in magnitude")
    loaded = load_set_for_models(params_name)
    params, waiver = loaded.values, loaded.waiver  # the checks the set's file waives, reported with it
    M, C1, K0, K2 = W.matrices(params)
    weave = W.weave_speed(params)
    capsize = W.capsize_speed(params)
    return {
        "params": str(params_name),
        "parameters": params,
        "waiver": None if waiver is None else {"checks": list(waiver.checks), "reason": waiver.reason},
        "conventions": "Meijaard et al. (2007): q = [phi, delta], roll positive leaning right, "
                       "steer positive to the right; M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi, T_delta]",
        "M": M.tolist(), "C1": C1.tolist(), "K0": K0.tolist(), "K2": K2.tolist(),
        "units": MATRIX_UNITS,
        "eigenvalues": [{"v": float(v), "eigenvalues": [[float(e.real), float(e.imag)]
                                                        for e in W.eigenvalues(params, v)]} for v in speeds],
        "weave_speed": weave,
        "capsize_speed": capsize,
        "self_stable": None if weave is None or capsize is None or not weave < capsize else [weave, capsize],
    }


def _matrix_lines(name: str, m) -> list[str]:
    import numpy as np  # here, not at the top: `cosim VERB` for every verb builds this parser

    m = np.asarray(m)
    rows = [" ".join(f"{x:22.14f}" for x in row) for row in m]
    return [f"{name} [{MATRIX_UNITS[name]}]:"] + [f"  {r}" for r in rows]


def _complex(e: complex) -> str:
    if e.imag == 0.0:
        return f"{e.real:.14f}"
    return f"{e.real:.14f} {'+' if e.imag > 0 else '-'} {abs(e.imag):.14f}j"


def format_report(report: dict) -> str:
    """Human-readable text of :func:`analytic_report`."""
    lines = [f"Linearized Whipple bicycle (Meijaard et al. 2007), parameters: {report['params']}",
             "  M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi, T_delta],  q = [phi, delta] "
             "(roll right, steer right positive)"]
    if report.get("waiver"):
        from cosim.analytic.parameters import Waiver  # deferred: as above, not for the parser

        waiver = report["waiver"]
        lines.append(f"  {Waiver(tuple(waiver['checks']), waiver['reason']).describe()}")
    for name in ("M", "C1", "K0", "K2"):
        lines += _matrix_lines(name, report[name])
    for entry in report["eigenvalues"]:
        ev = [complex(re, im) for re, im in entry["eigenvalues"]]
        stable = all(e.real < 0 for e in ev)
        lines.append(f"eigenvalues at v = {entry['v']:g} m/s ({'stable' if stable else 'unstable'}) [1/s]:")
        lines += [f"  {_complex(e)}" for e in ev]
    w, c = report["weave_speed"], report["capsize_speed"]
    lines.append(f"weave speed:   {'none below 30 m/s' if w is None else f'{w:.13f} m/s'}")
    lines.append(f"capsize speed: {'none below 30 m/s' if c is None else f'{c:.13f} m/s'}")
    if report["self_stable"]:
        lines.append(f"self-stable for {w:.4f} m/s < v < {c:.4f} m/s")
    return "\n".join(lines)


def run(args) -> int:
    """Entry point of ``cosim analytic`` (``args.params``, ``args.speed``, ``args.json``)."""
    report = analytic_report(args.params, list(args.speed or []))
    print(json.dumps(report, indent=2) if args.json else format_report(report))
    return 0
