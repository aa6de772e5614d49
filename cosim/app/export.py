"""`cosim app --export DIR`: the app as a static site that works from ``file://``.

Chromium refuses ``fetch`` and ES modules of ``file://`` pages, so the site is two files:

``DIR/index.html``
    the page (``static/index.html``, its style inline);
``DIR/bundle.js``
    one classic script: the data of the page (``window.COSIM_DATA``: ``modules``, model name ->
    ``{description, wasm}``, the WebAssembly module of each model of :data:`MODULES` as base64
    with its NAME.json; the parameter sets of ``cosim/params`` read by
    :func:`cosim.analytic.parameters.load_parameters`, the sliders; ``ride``, what
    ``static/ride.js`` needs: the ride model, its step, the fall limit, the bicycles of "ride it
    yourself"; ``demos``, the guided demos of ``cosim/app/demos/*.toml`` read and checked by
    :mod:`cosim.app.demos`; ``diagrams``, the Modelica diagram (SVG) of each model the bicycles
    use, drawn by :mod:`cosim.diagram`: :func:`cosim.app.diagrams.page_diagrams`), then the
    scripts of :func:`_scripts` in that order (ES modules without imports, such as
    ``cosim/wasm/fmu.js``, with their ``export`` keywords removed and their names gathered in a
    global).

The modules and diagrams are those the package ships (:mod:`cosim.app.shipped`, made by
``python -m cosim.app.ship``) while they are current for the installed library and compiler:
nothing is compiled, no library parsed. Otherwise (an edited library, a user's library that
hides the shipped one) the modules are built by `cosim build --wasm` machinery
(:func:`cosim.wasm.build.build_wasm`) from the FMUs in the FMU folder (``$COSIM_FMU_DIR``, else
``./fmus``), both incremental, and the diagrams drawn from the parsed library. The parameter
values are never written by hand into the page: they are read from the TOML files at export time.
"""
from __future__ import annotations

import base64
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

from cosim.app.bicycles import CROWN_RADIUS, page_data
from cosim.app.diagrams import page_diagrams
from cosim.folder_lock import folder_lock
from cosim.outputs import check_output_folder, write_text
from cosim.progress import active as progress
from cosim.analytic.parameters import load_parameters
from cosim.app.demos import DEMOS, load_demos
from cosim.app import shipped as shipped_files
from cosim.wasm.build import build_wasm, LOADER, zig_command

HERE = Path(__file__).resolve().parent
STATIC = HERE / "static"
VENDOR = STATIC / "vendor"
MODEL = "Bicycle.Bicycles.WhippleLinear"  # the model of the eigenvalue plots
RIDE_MODEL = "Bicycle.Bicycles.Whipple"  # the nonlinear bicycle of the rides (static/ride.js)
# The library's controllers the rides connect to the bicycle (ride.js: never a control law in JS).
CONTROLLERS = ("Bicycle.Control.PD", "Bicycle.Control.LaneChange")
# Every model whose WebAssembly module the page carries (``COSIM_DATA.modules``).
MODULES = (MODEL, RIDE_MODEL, *CONTROLLERS)
RIDE_STEP = 0.01  # [s] the communication step of the page's rides (the Whipple FMU's default interval)
FALL_ROLL = 1.0  # [rad] |phi| beyond this ends a ride: a fall (as the bundled systems' `fall`)
# The gust of "ride it yourself" (a roll-torque pulse T_phi; unchecked, the upright bicycle stays up),
# 2 s into the ride: time to see it coming (the page counts down to it) and to react.
GUST = {"amplitude": 5.0, "start": 2.0, "duration": 0.2}  # [N.m, s, s]
# What CosimRide3D draws the bicycle from (Meijaard geometry, crown radii of toroidal tyres).
GEOMETRY = ("w", "c", "lam", "rR", "rF", "tR", "tF")
# The bicycles of "ride it yourself": (name, label, parameter set, ridden backwards, other values).
RIDE_BICYCLES = (
    ("benchmark", "benchmark bicycle (front-steered)", "benchmark", False, {}),
    ("rear-steered", "benchmark ridden backwards: rear-steered", "benchmark", True, {}),
    ("astrom2005", "\u00c5str\u00f6m 2005 bicycle", "astrom2005", False, {}),
    ("crowned-roller", f"benchmark with a crowned rear roller, tR = {CROWN_RADIUS} m", "benchmark", False,
     {"tR": CROWN_RADIUS}),
)


@dataclass
class ExportResult:
    """What :func:`export_app` wrote."""

    folder: Path
    index: Path
    bundle: Path
    bytes: int  # size of bundle.js


@dataclass(frozen=True)
class Script:
    """One script of a bundle (`cosim app --export`, `cosim animate`): a file and how to inline it.

    ``kind`` is ``"classic"`` (inlined as it is), ``"module"`` (an ES module without imports: its
    ``export`` keywords removed, the exported names gathered in ``window.GLOBAL_NAME``) or
    ``"commonjs"`` (a CommonJS file without ``require``: run with a ``module``/``exports`` of its
    own, ``module.exports`` becomes ``window.GLOBAL_NAME``).
    """

    path: Path
    global_name: str | None = None
    kind: str = "classic"

    def inline(self) -> str:
        """The script's text for a classic ``<script>`` (or one ``bundle.js``)."""
        if self.kind == "classic":
            return self.path.read_text(encoding="utf-8")
        if self.kind == "module":
            return _module_script(self.path, self.global_name)
        if self.kind == "commonjs":
            text = self.path.read_text(encoding="utf-8")
            if re.search(r"\brequire\s*\(", text):
                raise ValueError(f"{self.path} requires other modules; the bundle inlines self-contained files only")
            return (f"(function () {{\nvar module = {{ exports: {{}} }}, exports = module.exports;\n{text}\n"
                    f"window.{self.global_name} = module.exports;\n}})();\n")
        raise ValueError(f"{self.path}: unknown script kind {self.kind!r}")


def _scripts() -> tuple[Script, ...]:
    """The scripts of ``bundle.js`` in their order: the vendored libraries first, then the
    page's own code (each file one concern, see the comments at their tops)."""
    # three.js before ride3d.js (it uses the global THREE); canvas.js before the scripts that draw on
    # 2-D canvases (plots.js, sideview.js, app.js); ride3d.js, plots.js and ride2d.js before
    # ride.js (which uses CosimRide3D, CosimPlots and CosimRide2D). app.js and ride.js are independent of each other;
    # ride.js comes first so that the rides are defined even if app.js throws while loading (one
    # bundle is one script: an uncaught error stops what follows it). sideview.js, modes.js and
    # viewstate.js before app.js, which uses them. diagram.js after app.js, which fills the bicycle
    # select it follows.
    return (
        Script(VENDOR / "ml-matrix.umd.js"),
        Script(LOADER, "CosimFMU", "module"),
        Script(VENDOR / "three.min.js"),
        Script(STATIC / "ride3d.js"),
        Script(STATIC / "canvas.js"),
        Script(STATIC / "plots.js"),
        Script(STATIC / "ride2d.js"),
        Script(STATIC / "ride.js"),
        Script(STATIC / "sideview.js"),
        Script(STATIC / "modes.js"),
        Script(STATIC / "viewstate.js"),
        Script(STATIC / "app.js"),
        Script(STATIC / "diagram.js"),
        Script(STATIC / "help.js"),
    )


def _fmu_folder() -> Path:
    # deferred: loads casadi, numpy, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT

    return Path(os.environ.get("COSIM_FMU_DIR") or DEFAULT_OUTPUT)



def ride_data(descriptions: dict, demos_folder: str | os.PathLike | None = None) -> dict:
    """``COSIM_DATA.ride`` and ``COSIM_DATA.demos``: what static/ride.js needs besides the modules.

    Parameters
    ----------
    descriptions : dict
        Model name -> NAME.json of every module of the page (names are checked against them).
    demos_folder : path, optional
        The demo files (default ``cosim/app/demos``).

    Raises
    ------
    DemoError
        For a bad demo file (its name and the key).
    ValueError
        If a bicycle of :data:`RIDE_BICYCLES` has a value that is not a parameter of the ride model.
    """
    parameters = {v["name"] for v in descriptions[RIDE_MODEL]["variables"] if v["causality"] == "parameter"}
    bicycles = []
    for name, label, params, backwards, values in RIDE_BICYCLES:
        values = {**load_parameters(params), **values}
        unknown = sorted(set(values) - parameters)
        if unknown:
            raise ValueError(f"ride bicycle {name}: {', '.join(unknown)} are not parameters of {RIDE_MODEL}")
        bicycles.append({"name": name, "label": label, "backwards": backwards, "values": values})
    demos = load_demos(demos_folder or DEMOS, descriptions)
    return {"ride": {"model": RIDE_MODEL, "linearModel": MODEL, "step": RIDE_STEP, "fallRoll": FALL_ROLL,
                     "geometry": list(GEOMETRY), "bicycles": bicycles, "gust": GUST},
            "demos": demos}


def _module_script(path: Path, global_name: str) -> str:
    """An ES module without imports (fmu.js) as a classic script: its ``export`` keywords
    removed, the exported names gathered in ``window.GLOBAL_NAME``."""
    text = path.read_text(encoding="utf-8")
    if re.search(r"^\s*import\s", text, re.M):
        raise ValueError(f"{path} imports other modules; the bundle inlines modules without imports only")
    names = re.findall(r"^export\s+(?:const|let|class|function|async\s+function)\s+(\w+)", text, re.M)
    body = re.sub(r"^export\s+", "", text, flags=re.M)
    return f"(function () {{\n{body}\nwindow.{global_name} = {{ {', '.join(names)} }};\n}})();\n"


def export_app(folder: str | os.PathLike, demos: str | os.PathLike | None = None) -> ExportResult:
    """Write the app into ``folder`` (created if needed): ``index.html`` and ``bundle.js``.

    Parameters
    ----------
    folder : path
        The output folder; existing ``index.html`` and ``bundle.js`` in it are replaced.
    demos : path, optional
        The folder of the guided demos' TOML files (default ``cosim/app/demos``).

    Returns
    -------
    ExportResult
        The paths, whether the WebAssembly module was compiled (False: up to date) and the
        size of the bundle [bytes].

    Raises
    ------
    OutputError
        If ``folder`` is a file or cannot be written, or another command is writing it
        (:class:`cosim.folder_lock.FolderBusy`), checked before any build.
    BuildError, MissingExtraError
        If the shipped modules are not current and an FMU or its WebAssembly module cannot be
        built (e.g. no ``ziglang`` wheel).
    DemoError
        If a demo file is bad (its name and the key; the structure is checked before any build).
    ModelicaError
        If a model the page draws has a malformed graphical annotation (its ``file:line``).
    """
    folder = check_output_folder(folder, "app folder")
    load_demos(demos or DEMOS)  # a bad demo file: its message before any build
    shipped = shipped_files.load(MODULES)
    if shipped is None:
        zig_command()  # no ziglang: one message before any work
    with folder_lock(folder, "app folder"):  # one command writes the folder at a time
        return _export(folder, demos, shipped)


def build_modules(fmu_folder: Path) -> dict:
    """Build the FMU of each model of :data:`MODULES` in ``fmu_folder``, then its WebAssembly
    module beside it (``fmu_folder/wasm/``), both incremental.

    Returns
    -------
    dict
        Model name -> :class:`cosim.wasm.build.WasmResult` (the paths of NAME.wasm and NAME.json).
    """
    # deferred: loads casadi, numpy, which importing this module does not
    from cosim.compiler.build import build

    return {result.model: build_wasm(result.fmu) for result in build(list(MODULES), output=fmu_folder)}


def _page_modules(built: dict) -> dict:
    """``COSIM_DATA.modules`` from :func:`build_modules`: model name -> ``{"description": NAME.json
    as a dict, "wasm": NAME.wasm in base64}``."""
    return {model: {"description": json.loads(wasm.description.read_text(encoding="utf-8")),
                    "wasm": base64.b64encode(wasm.wasm.read_bytes()).decode("ascii")}
            for model, wasm in built.items()}


def diagram_models(bicycles: list) -> list[str]:
    """The models whose diagrams the page carries: those of the bicycles of
    ``COSIM_DATA.bicycles`` (:func:`cosim.app.bicycles.page_data`), each once, in their order."""
    return list(dict.fromkeys(b["module"] for b in bicycles))


def _export(folder: Path, demos: str | os.PathLike | None, shipped) -> ExportResult:
    """:func:`export_app` into a checked and locked folder, with the shipped modules and
    diagrams (:class:`cosim.app.shipped.Shipped`) or, if None, building them."""
    with progress().steps(4):
        progress().item("load the shipped WebAssembly modules" if shipped is not None
                        else "build the FMUs and their WebAssembly modules")
        modules = shipped.modules if shipped is not None else _page_modules(build_modules(_fmu_folder()))
        descriptions = {name: m["description"] for name, m in modules.items()}
        progress().item("compute the bicycles' eigenvalues and the demos")
        data = {**page_data(modules[MODEL]["description"], descriptions), **ride_data(descriptions, demos),
                "modules": modules}
        models = diagram_models(data["bicycles"])
        progress().item("draw the diagrams")
        data["diagrams"] = (shipped.diagrams if shipped is not None and list(shipped.diagrams) == models
                            else page_diagrams(models))
        progress().item("write the bundle")
        return _write_site(folder, data)


def _write_site(folder: Path, data: dict) -> ExportResult:
    """``bundle.js`` (``data`` and the scripts) and ``index.html`` of :func:`export_app`."""
    scripts = _scripts()
    bundle = "\n".join([
        "// bundle.js of `cosim app --export`: generated, do not edit. Sources, in this order: "
        + ", ".join(str(s.path.relative_to(HERE.parent.parent)) for s in scripts)
        + " (vendored ones: see their LICENSE files), and the FMUs' WebAssembly modules.",
        "window.COSIM_DATA = " + json.dumps(data, separators=(",", ":")) + ";",
        *(s.inline() for s in scripts),
    ])
    bundle_path = write_text(folder / "bundle.js", bundle, "app bundle")
    index = write_text(folder / "index.html", (STATIC / "index.html").read_text(encoding="utf-8"), "app page")
    return ExportResult(folder, index, bundle_path, len(bundle.encode("utf-8")))
