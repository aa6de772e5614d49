"""Generate the Modelica parameter records ``Bicycle.Records`` from the TOML files in ``cosim/params/``.

The TOML files are the one source of the bicycles' parameter values; the records are written
from them, deterministically (byte-identical output), and a test checks that the committed
records equal a fresh generation::

    python -m cosim.analytic.records            # writes modelica/Bicycle/Records/*.mo and package.order
    python -m cosim.analytic.records --check    # exit 1 if the files on disk differ
    python -m cosim.analytic.records -o DIR     # writes into DIR instead

Written classes (one file each, packages of constants; a model takes one as
``replaceable package Data = Bicycle.Records.Benchmark constrainedby Bicycle.Records.PartialWhipple``):

* ``PartialWhipple``: the 26 symbols of Meijaard et al. (2007), Table 1, without values (the
  constraining class), and one package per Meijaard set ``cosim/params/<name>.toml``
  (``Benchmark``, ``Astrom2005``, ``Astrom2005Riderless``);
* ``PartialWhippleRider`` (extends ``PartialWhipple`` by the rider's upper body U) and
  ``BenchmarkRider``: the benchmark with the upper body ``cosim/params/rider/benchmark.toml``
  split off the rear frame (:func:`cosim.analytic.parameters.split_upper_body`);
* ``PartialSecondOrder`` and ``Astrom2005SecondOrder``: the lumped bicycle of the simple models
  of Astrom, Klein & Lennartsson (2005), ``cosim/params/second-order/astrom2005.toml``.

The data sets declare every constant instead of extending their partial package: pymoca 0.12
resolves an ``extends`` with modifiers inside a replaceable package wrongly. The constants are
``Real`` with ``quantity`` and ``unit`` (as ``Bicycle.Units``) for the same reason.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cosim.analytic import parameters as P

ROOT = Path(__file__).resolve().parents[2]
TARGET_DIR = ROOT / "modelica" / "Bicycle" / "Records"
COMMAND = "python -m cosim.analytic.records"
PACKAGE = "Bicycle.Records"

# Modelica quantity and unit of every symbol (the attributes of the Bicycle.Units / Modelica.Units.SI types).
_QUANTITY = {
    "m": ("Length", "m"), "rad": ("Angle", "rad"), "m/s^2": ("Acceleration", "m/s2"), "kg": ("Mass", "kg"),
    "kg m^2": ("MomentOfInertia", "kg.m2"), "m/s": ("Velocity", "m/s"), "s": ("Time", "s"),
    "N m/rad": ("RotationalSpringConstant", "N.m/rad"), "N m s/rad": ("RotationalDampingConstant", "N.m.s/rad"),
}

WHIPPLE_DESCRIPTIONS = {
    "w": "Wheelbase w",
    "c": "Trail c (positive: front contact point behind the steer axis)",
    "lam": "Steer-axis tilt lam from the vertical (pi/2 - head angle)",
    "g": "Gravitational acceleration g",
    "rR": "Rear wheel radius rR (centre height of the upright wheel)",
    "mR": "Rear wheel mass mR",
    "IRxx": "Rear wheel diametral inertia IRxx = IRzz",
    "IRyy": "Rear wheel spin inertia IRyy",
    "xB": "Rear frame centre of mass: x coordinate xB (forward)",
    "zB": "Rear frame centre of mass: z coordinate zB (down; negative above the ground)",
    "mB": "Rear frame mass mB",
    **{f"IB{k}": f"Rear frame inertia-tensor element IB{k} about its centre of mass" for k in ("xx", "xz", "yy", "zz")},
    "xH": "Front frame centre of mass: x coordinate xH (forward)",
    "zH": "Front frame centre of mass: z coordinate zH (down; negative above the ground)",
    "mH": "Front frame mass mH",
    **{f"IH{k}": f"Front frame inertia-tensor element IH{k} about its centre of mass" for k in ("xx", "xz", "yy", "zz")},
    "rF": "Front wheel radius rF (centre height of the upright wheel)",
    "mF": "Front wheel mass mF",
    "IFxx": "Front wheel diametral inertia IFxx = IFzz",
    "IFyy": "Front wheel spin inertia IFyy",
}

UPPER_BODY_DESCRIPTIONS = {
    "mU": "Upper body mass mU",
    "xU": "Hinge (hip) axis and upper body centre of mass: x coordinate xU (forward)",
    "hU": "Height hU of the hinge (hip) axis above the ground (upright bicycle)",
    "lU": "Height lU of the upper body centre of mass above the hinge axis",
    **{f"IU{k}": f"Upper body inertia-tensor element IU{k} about its centre of mass" for k in ("xx", "xz", "yy", "zz")},
    "kU": "Passive stiffness kU of the hip hinge (lean torque per lean angle)",
    "cU": "Passive damping cU of the hip hinge (lean torque per lean rate)",
}

SECOND_ORDER_DESCRIPTIONS = {
    "m": "Total mass m of bicycle and rider",
    "a": "Horizontal distance a from the rear contact point to the centre of mass",
    "h": "Height h of the centre of mass above the ground",
    "b": "Wheel base b",
    "c": "Trail c",
    "lambda": "Head angle lambda (pi/2: vertical steer axis)",
    "J": "Moment of inertia J about the x axis",
    "D": "Inertia product D = -Jxz",
    "g": "Gravitational acceleration g",
    "m_r": "Mass m_r of the rider's upper body (part of m)",
    "J_r": "Moment of inertia J_r of the upper body with respect to the x axis",
    "h_r": "Distance h_r from the centre of mass of the upper body to its lean axis",
    "V": "Forward speed V (default operating point of the models)",
    "R": "Lateral (rocking) radius R of the crowned rollers (default of the roller model)",
    "k3": "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle (default)",
}

#: Class name and description of the package generated for each Meijaard set ``cosim/params/<stem>.toml``.
WHIPPLE_SETS = {
    "benchmark": ("Benchmark", "Benchmark bicycle of Meijaard et al. (2007), Table 1"),
    "astrom2005": ("Astrom2005", "Bicycle with rigid rider of Astrom, Klein and Lennartsson (2005)"),
    "astrom2005-riderless": ("Astrom2005Riderless", "Riderless bicycle of Astrom, Klein and Lennartsson (2005)"),
}


def _class_name(stem: str) -> tuple[str, str]:
    """Class name and description for a Meijaard set (a new TOML file gets a CamelCase name)."""
    if stem in WHIPPLE_SETS:
        return WHIPPLE_SETS[stem]
    name = "".join(part[:1].upper() + part[1:] for part in stem.replace("_", "-").split("-"))
    if not name.isidentifier():
        raise ValueError(f"cosim/params/{stem}.toml: the name does not give a Modelica class name ({name!r})")
    return name, f"Parameter set {stem}"


def _number(value: float) -> str:
    """Shortest round-tripping decimal of a float (``repr``), as Modelica accepts it."""
    text = repr(float(value))
    if "inf" in text or "nan" in text:
        raise ValueError(f"not a finite number: {text}")
    return text


def _constant(name: str, unit: str, description: str, value: float | None) -> str:
    quantity, modelica_unit = _QUANTITY[unit]
    binding = "" if value is None else f" = {_number(value)}"
    return (f'  constant Real {name}(final quantity = "{quantity}", final unit = "{modelica_unit}")'
            f'{binding} "{description}";')


def _package(name: str, description: str, source: str, constants: list[str], *, partial: bool = False,
             extends: str | None = None, info: str = "") -> str:
    lines = [f"within {PACKAGE};",
             f"// Generated from {source} by {COMMAND}: do not edit.",
             f'{"partial " if partial else ""}package {name} "{description}"']
    if extends:
        lines.append(f"  extends {extends};")
    lines += constants
    lines.append(f'  annotation(Documentation(info = "<html>{info}</html>"));')
    lines.append(f"end {name};")
    return "\n".join(lines) + "\n"


def _whipple_constants(values: dict[str, float] | None) -> list[str]:
    return [_constant(k, P.UNITS[k], WHIPPLE_DESCRIPTIONS[k],
                      None if values is None else values[k]) for k in P.PARAMETER_NAMES]


def _upper_body_constants(values: dict[str, float] | None) -> list[str]:
    return [_constant(k, P.UPPER_BODY_UNITS[k], UPPER_BODY_DESCRIPTIONS[k], None if values is None else values[k])
            for k in P.UPPER_BODY_UNITS]


def _second_order_constants(values: dict[str, float] | None) -> list[str]:
    return [_constant(k, P.SECOND_ORDER_UNITS[k], SECOND_ORDER_DESCRIPTIONS[k], None if values is None else values[k])
            for k in P.SECOND_ORDER_UNITS]


_DATA_INFO = ("<p>Data set generated from <code>{source}</code> (the one source of these values) by "
              "<code>" + COMMAND + "</code>. A model takes it as <code>replaceable package Data = "
              + PACKAGE + ".{name} constrainedby " + PACKAGE + ".{partial}</code>.</p>")


def records() -> dict[str, str]:
    """File name -> text of every generated file of ``Bicycle.Records`` (``package.order`` included).

    Raises
    ------
    ValueError
        A TOML file that does not load (see :func:`cosim.analytic.parameters.load_parameters`).
    """
    files: dict[str, str] = {}
    order: list[str] = []

    def add(name: str, text: str) -> None:
        files[f"{name}.mo"] = text
        order.append(name)

    add("PartialWhipple", _package(
        "PartialWhipple", "Parameter set of the Whipple bicycle: the symbols of Meijaard et al. (2007), Table 1",
        "cosim/analytic/parameters.py (PARAMETER_NAMES)", _whipple_constants(None), partial=True,
        info="<p>The constraining class of the Meijaard data sets. Conventions: x forward, y right, z down, "
             "origin at the rear contact point; inertias about each body's own centre of mass, "
             "I*xz = -integral(x z dm); wheels axisymmetric (IRzz = IRxx, IFzz = IFxx). Units SI.</p>"))
    for stem in P.bundled_parameter_sets():
        name, description = _class_name(stem)
        source = f"cosim/params/{stem}.toml"
        add(name, _package(name, f"{description} (generated from {source})", source,
                           _whipple_constants(P.load_parameters(stem)),
                           info=_DATA_INFO.format(source=source, name=name, partial="PartialWhipple")))
    add("PartialWhippleRider", _package(
        "PartialWhippleRider", "Parameter set of the Whipple bicycle with the rider's upper body U on a hip hinge",
        "cosim/analytic/parameters.py (UPPER_BODY_UNITS)", _upper_body_constants(None), partial=True,
        extends=f"{PACKAGE}.PartialWhipple",
        info="<p>The Meijaard symbols (rear frame B <em>without</em> the upper body) and the upper body U: "
             "hinge axis parallel to x at x = xU, height hU; centre of mass lU above the hinge; inertia "
             "about its centre of mass in axes parallel to the rear frame's; passive hinge stiffness kU "
             "and damping cU.</p>"))
    source = "cosim/params/benchmark.toml and cosim/params/rider/benchmark.toml"
    add("BenchmarkRider", _package(
        "BenchmarkRider", "Benchmark bicycle with the rider's upper body split off the rear frame "
        "(generated from cosim/params/benchmark.toml, cosim/params/rider/benchmark.toml)", source,
        _whipple_constants(P.rider_parameters()) + _upper_body_constants(P.load_upper_body("benchmark")),
        info=_DATA_INFO.format(source=source, name="BenchmarkRider", partial="PartialWhippleRider")
        + "<p>With the hinge locked upright, rear frame + upper body is exactly the benchmark's rear frame "
          "(parallel-axis theorem, <code>cosim.analytic.parameters.split_upper_body</code>).</p>"))
    add("PartialSecondOrder", _package(
        "PartialSecondOrder", "Parameter set of the simple second-order bicycle models of Astrom, Klein and "
        "Lennartsson (2005)", "cosim/analytic/parameters.py (SECOND_ORDER_UNITS)", _second_order_constants(None),
        partial=True,
        info="<p>The lumped bicycle of the second-order models (ISO 8855 conventions, lambda is the head "
             "angle), the leaning rider of eqs (22)-(23) and the models' default operating values.</p>"))
    source = "cosim/params/second-order/astrom2005.toml"
    add("Astrom2005SecondOrder", _package(
        "Astrom2005SecondOrder", f"Bicycle of Astrom, Klein and Lennartsson (2005) for the second-order models "
        f"(generated from {source})", source, _second_order_constants(P.load_second_order("astrom2005")),
        info=_DATA_INFO.format(source=source, name="Astrom2005SecondOrder", partial="PartialSecondOrder")))
    files["package.order"] = "\n".join(order) + "\n"
    return files


def write(directory: Path = TARGET_DIR) -> list[Path]:
    """Write the generated files into ``directory`` (created if missing); returns their paths."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in records().items():
        path = directory / name
        path.write_bytes(text.encode())
        written.append(path)
    return written


def stale(directory: Path = TARGET_DIR) -> list[str]:
    """Names of generated files that are missing in ``directory`` or differ from a fresh generation."""
    directory = Path(directory)
    return [name for name, text in records().items()
            if not (directory / name).is_file() or (directory / name).read_bytes() != text.encode()]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog=COMMAND, description="Generate Bicycle.Records from cosim/params/*.toml.")
    parser.add_argument("--check", action="store_true", help="exit 1 if the files on disk differ (write nothing)")
    parser.add_argument("-o", "--output", type=Path, default=TARGET_DIR,
                        help=f"folder to write into (default: {TARGET_DIR.relative_to(ROOT)})")
    args = parser.parse_args(argv)
    try:
        if args.check:
            differ = stale(args.output)
            for name in differ:
                print(f"{args.output / name}: differs from {COMMAND}", file=sys.stderr)
            return 1 if differ else 0
        for path in write(args.output):
            print(f"wrote {path}")
    except (ValueError, OSError) as exc:
        print(f"{COMMAND}: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
