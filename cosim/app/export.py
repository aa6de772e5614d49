"""`cosim app --export DIR`: the app as a static site that works from ``file://``.

Chromium refuses ``fetch`` and ES modules of ``file://`` pages, so the site is two files:

``DIR/index.html``
    the page (``static/index.html``, its style inline);
``DIR/bundle.js``
    one classic script: the data of the page (``window.COSIM_DATA``: the WebAssembly module of
    Bicycle.Bicycles.WhippleLinear as base64 with its NAME.json, the parameter sets of
    ``cosim/params`` read by :func:`cosim.analytic.parameters.load_parameters`, the sliders),
    then the vendored ml-matrix, ``cosim/wasm/fmu.js`` (its ``export`` keywords removed, its
    names as ``window.CosimFMU``) and ``static/app.js``.

The module is built by `cosim build --wasm` machinery (:func:`cosim.wasm.build.build_wasm`) from
the FMU in the FMU folder (``$COSIM_FMU_DIR``, else ``./fmus``), both incremental. The parameter
values are never written by hand into the page: they are read from the TOML files at export time.
"""
from __future__ import annotations

import base64
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

from cosim.errors import OutputError
from cosim.outputs import check_output_folder, write_text

HERE = Path(__file__).resolve().parent
STATIC = HERE / "static"
VENDOR = STATIC / "vendor"
MODEL = "Bicycle.Bicycles.WhippleLinear"
PARAMETER_SETS = ("benchmark", "astrom2005", "astrom2005-riderless")
# The states of Meijaard's 4x4 lateral model, in the order of its state vector; WhippleLinear
# has more (heading psi and lateral position y), which do not enter the eigenvalues of balance.
LATERAL_STATES = ("phi", "delta", "phi_dot", "delta_dot")
# Sliders of Meijaard parameters: (name, label, unit, minimum, maximum, step). Every bundled set
# must lie inside the ranges (checked at export).
SLIDERS = (
    ("w", "wheelbase w", "m", 0.5, 2.0, 0.001),
    ("c", "trail c", "m", -0.1, 0.3, 0.001),
    ("lam", "steer-axis tilt \u03bb", "rad", -0.2, 0.8, 0.001),
    ("mB", "rear frame mass m_B", "kg", 5.0, 150.0, 0.1),
    ("rF", "front wheel radius r_F", "m", 0.1, 0.6, 0.001),
    ("rR", "rear wheel radius r_R", "m", 0.1, 0.6, 0.001),
)
SPEEDS = {"min": 0.0, "max": 10.0, "num": 200, "default": 5.0, "step": 0.01}  # [m/s]


@dataclass
class ExportResult:
    """What :func:`export_app` wrote."""

    folder: Path
    index: Path
    bundle: Path
    wasm_rebuilt: bool
    bytes: int  # size of bundle.js


def _fmu_folder() -> Path:
    from cosim.compiler.build import DEFAULT_OUTPUT

    return Path(os.environ.get("COSIM_FMU_DIR") or DEFAULT_OUTPUT)


def page_data(description: dict) -> dict:
    """``window.COSIM_DATA`` without the module: parameter sets, sliders, speeds, states.

    Raises
    ------
    ValueError
        If a parameter of a set is not a parameter of the model, a lateral state is not a
        state of it, or a set's value lies outside its slider's range (a bug of this file).
    """
    from cosim.analytic.parameters import load_parameters

    variables = {v["name"]: v for v in description["variables"]}
    # a state is what a derivative's `derivative` attribute names (1-based index of the variable)
    states = {description["variables"][v["derivative"] - 1]["name"] for v in description["variables"]
              if "derivative" in v}
    missing = [s for s in LATERAL_STATES if s not in states]
    if missing:
        raise ValueError(f"{MODEL} has no state(s) {', '.join(missing)}")
    sets = {}
    for name in PARAMETER_SETS:
        values = load_parameters(name)
        unknown = [key for key in values if variables.get(key, {}).get("causality") != "parameter"]
        if unknown:
            raise ValueError(f"parameter set {name}: {', '.join(unknown)} are not parameters of {MODEL}")
        for key, _, _, low, high, _ in SLIDERS:
            if not low <= values[key] <= high:
                raise ValueError(f"parameter set {name}: {key} = {values[key]} outside its slider [{low}, {high}]")
        if sets and sorted(values) != sorted(next(iter(sets.values()))):
            raise ValueError(f"parameter set {name} has other parameters than {next(iter(sets))}")
        sets[name] = values
    return {"model": MODEL, "parameterSets": sets, "lateralStates": list(LATERAL_STATES),
            "sliders": [dict(zip(("name", "label", "unit", "min", "max", "step"), s)) for s in SLIDERS],
            "speeds": SPEEDS}


def _module_script(path: Path, global_name: str) -> str:
    """An ES module without imports (fmu.js) as a classic script: its ``export`` keywords
    removed, the exported names gathered in ``window.GLOBAL_NAME``."""
    text = path.read_text(encoding="utf-8")
    if re.search(r"^\s*import\s", text, re.M):
        raise ValueError(f"{path} imports other modules; the bundle inlines modules without imports only")
    names = re.findall(r"^export\s+(?:const|let|class|function|async\s+function)\s+(\w+)", text, re.M)
    body = re.sub(r"^export\s+", "", text, flags=re.M)
    return f"(function () {{\n{body}\nwindow.{global_name} = {{ {', '.join(names)} }};\n}})();\n"


def export_app(folder: str | os.PathLike) -> ExportResult:
    """Write the app into ``folder`` (created if needed): ``index.html`` and ``bundle.js``.

    Parameters
    ----------
    folder : path
        The output folder; existing ``index.html`` and ``bundle.js`` in it are replaced.

    Returns
    -------
    ExportResult
        The paths, whether the WebAssembly module was compiled (False: up to date) and the
        size of the bundle [bytes].

    Raises
    ------
    OutputError
        If ``folder`` is a file or cannot be written (checked before any build).
    BuildError, MissingExtraError
        If the FMU or its WebAssembly module cannot be built (e.g. no ``ziglang`` wheel).
    """
    from cosim.compiler.build import build
    from cosim.wasm.build import LOADER, build_wasm, zig_command

    folder = check_output_folder(folder, "app folder")
    zig_command()  # no ziglang: one message before any work
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"app folder '{folder}': {exc.strerror or exc}") from None
    (result,) = build([MODEL], output=_fmu_folder())
    wasm = build_wasm(result.fmu)
    description = json.loads(wasm.description.read_text(encoding="utf-8"))
    data = {**page_data(description), "description": description,
            "wasm": base64.b64encode(wasm.wasm.read_bytes()).decode("ascii")}
    bundle = "\n".join([
        "// bundle.js of `cosim app --export`: generated, do not edit (sources: cosim/app/static/app.js,",
        "// cosim/wasm/fmu.js, cosim/app/static/vendor/ml-matrix.umd.js (MIT, see its LICENSE), the FMU's module).",
        "window.COSIM_DATA = " + json.dumps(data, separators=(",", ":")) + ";",
        (VENDOR / "ml-matrix.umd.js").read_text(encoding="utf-8"),
        _module_script(LOADER, "CosimFMU"),
        (STATIC / "app.js").read_text(encoding="utf-8"),
    ])
    bundle_path = write_text(folder / "bundle.js", bundle, "app bundle")
    index = write_text(folder / "index.html", (STATIC / "index.html").read_text(encoding="utf-8"), "app page")
    return ExportResult(folder, index, bundle_path, wasm.rebuilt, len(bundle.encode("utf-8")))
