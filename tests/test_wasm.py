"""The bicycle FMUs as WebAssembly (`cosim build --wasm`, cosim/wasm) in a real headless Chromium.

The module is compiled from the FMI 2.0 FMU's own C sources with the ``ziglang`` wheel and run by
cosim/wasm/fmu.js, served from a temporary folder over http.server on 127.0.0.1 (a page opened
from file:// cannot fetch the module). A 10 s Co-Simulation ride in the browser must equal the
native FMU's, as `cosim simulate` runs it (FMPy's simulate_fmu: the same communication step, the
same tolerance), to 1e-9; the largest difference and whether the ride is bit-identical are
printed. Chromium is Debian's (``/usr/bin/chromium``, or ``$COSIM_CHROMIUM``) driven by pip
``playwright`` (no browser download). Without Chromium, playwright or ziglang the browser tests
are skipped with the reason, except in CI (``$CI`` set), where they fail.
"""
from __future__ import annotations

import base64
import contextlib
import functools
import http.server
import json
import os
import re
import shutil
import threading
import zipfile
from pathlib import Path

import numpy as np
import pytest

from cosim.errors import BuildError, FMUError, MissingExtraError
from cosim.wasm import build as wasm_build
from conftest import cli_in_process, unavailable as _unavailable

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site or animation
pytestmark = pytest.mark.slow

CHROMIUM = Path(os.environ.get("COSIM_CHROMIUM", "/usr/bin/chromium"))
LINEAR, NONLINEAR = "Bicycle.Bicycles.WhippleLinear", "Bicycle.Bicycles.Whipple"
MODELS = (LINEAR, NONLINEAR)
RIDE = 10.0  # s
STEP = 0.01  # s, the communication step of both runs
TOLERANCE = 1e-9  # largest difference allowed between the browser's and the native ride


def _api_names() -> set[str]:
    """The functions wasm_api.c exports (``WASM_EXPORT(name)``)."""
    return set(re.findall(r"WASM_EXPORT\((wasm_\w+)\)", wasm_build.SHIM.read_text()))


# --- fixtures: the FMUs, their modules, a site on 127.0.0.1, the browser ----------------------

@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """A temporary folder with fmu.js, a page importing it and wasm/NAME.wasm + NAME.json of the
    two bicycles, compiled from the FMUs of the session's FMU folder."""
    from cosim.compiler.build import build

    if not _has_ziglang():
        _unavailable("the ziglang wheel is not installed (pip install ziglang)")
    folder = tmp_path_factory.mktemp("wasm-site")
    results = build(list(MODELS), output=os.environ["COSIM_FMU_DIR"], jobs=2)
    for r in results:
        wasm_build.build_wasm(r.fmu, folder)
    shutil.copyfile(wasm_build.LOADER, folder / "fmu.js")
    (folder / "index.html").write_text(
        '<!DOCTYPE html><meta charset="utf-8"><title>cosim wasm test</title>\n'
        '<script type="module">import * as cosim from "./fmu.js"; window.cosim = cosim; '
        'window.cosimReady = true;</script>\n', encoding="utf-8")
    return folder


def _has_ziglang() -> bool:
    import importlib.util

    return importlib.util.find_spec("ziglang") is not None


@pytest.fixture(scope="module")
def fmu_files(site) -> dict[str, Path]:
    """Model name -> native FMI 2.0 FMU (built by the ``site`` fixture)."""
    from cosim.compiler.build import fmu_path

    return {m: fmu_path(m, Path(os.environ["COSIM_FMU_DIR"])) for m in MODELS}


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".wasm": "application/wasm",
                      ".js": "text/javascript"}

    def log_message(self, format, *args):  # noqa: A002 (the base class's name)
        pass


@pytest.fixture(scope="module")
def server(site):
    """http://127.0.0.1:PORT/ serving ``site`` (a port the system chose), stopped after the module."""
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_QuietHandler, directory=str(site)))
    thread = threading.Thread(target=httpd.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(timeout=10)


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    """Headless Debian Chromium through playwright (no browser download). Its configuration
    folder (crash report settings) goes to a temporary folder, not ~/.config/chromium."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable("playwright is not installed (pip install playwright)")
    if not CHROMIUM.is_file():
        _unavailable(f"Chromium not found at {CHROMIUM} (apt-get install chromium, or set COSIM_CHROMIUM)")
    with sync_playwright() as p:
        config = tmp_path_factory.mktemp("chromium-config")
        b = p.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                              args=["--headless", "--no-sandbox", "--disable-gpu", "--disable-crash-reporter"],
                              env={**os.environ, "XDG_CONFIG_HOME": str(config)})
        try:
            yield b
        finally:
            b.close()


@contextlib.contextmanager
def offline_page(browser, url: str, ready: str, *, allowed: str = "file://", timeout: float = 60_000,
                 console_errors: bool = False, **context_options):
    """``url`` opened in a new context of ``browser``, once the JavaScript expression ``ready`` is
    true. Every request whose URL does not start with ``allowed`` is refused; at the end the test
    fails if there was one, or an error in the page (with ``console_errors``, also a message the
    page logs as an error). ``page.requests`` lists every URL requested.
    ``context_options`` go to ``browser.new_context`` (viewport, accept_downloads, ...)."""
    context = browser.new_context(**context_options)
    page = context.new_page()
    page.requests, errors = [], []
    page.on("request", lambda r: page.requests.append(r.url))
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    if console_errors:
        page.on("console", lambda m: errors.append(f"console: {m.text}") if m.type == "error" else None)
    page.route("**/*", lambda route: route.continue_() if route.request.url.startswith(allowed) else route.abort())
    try:
        page.goto(url)
        page.wait_for_function(ready, timeout=timeout)
        yield page
    finally:
        context.close()
    foreign = [u for u in page.requests if not u.startswith(allowed)]
    assert not foreign, f"requests left {allowed}: {foreign}"
    assert not errors, f"errors in the page: {errors}"


@pytest.fixture()
def page(browser, server):
    """The test page, loaded; every request that would leave 127.0.0.1 is refused (the test
    fails if there is one), as is an error in the page."""
    with offline_page(browser, server + "index.html", "window.cosimReady === true", allowed=server,
                      timeout=30_000) as page:
        yield page


# A ride in the page: load the model, simulate as FMPy does, return every column as the base64 of
# its float64 bytes (exact, whatever the transport does to numbers).
RIDE_JS = """
async ({json, options}) => {
  const fmu = await window.cosim.WasmFMU.load(json);
  const bike = fmu.instantiate({name: "ride"});
  const r = bike.simulate(options);
  const b64 = (a) => { let s = ""; const u = new Uint8Array(a.buffer, a.byteOffset, a.byteLength);
                      for (let i = 0; i < u.length; i += 0x8000) s += String.fromCharCode(...u.subarray(i, i + 0x8000));
                      return btoa(s); };
  bike.free();
  const bytes = await (await fetch(new URL(fmu.description.wasm.file, new URL(json, location.href)))).arrayBuffer();
  const imports = WebAssembly.Module.imports(await WebAssembly.compile(bytes)).length;
  return {time: b64(r.time), names: r.names, values: r.values.map(b64), status: r.status, seconds: r.seconds,
          imports, log: bike.log};
}
"""


def _ride(page, model: str, **options) -> dict:
    out = page.evaluate(RIDE_JS, {"json": f"wasm/{model.replace('.', '_')}.json", "options": options})
    decode = lambda text: np.frombuffer(base64.b64decode(text), dtype="<f8")  # noqa: E731
    out["time"] = decode(out["time"])
    out["values"] = {n: decode(v) for n, v in zip(out["names"], out["values"])}
    return out


# --- the module ---------------------------------------------------------------------------------

@pytest.mark.parametrize("model", MODELS, ids=["WhippleLinear", "Whipple"])
def test_module_imports_nothing_and_exports_the_api(site, model):
    data = (site / "wasm" / f"{model.replace('.', '_')}.wasm").read_bytes()
    imports, exports = wasm_build.module_interface(data)
    print(f"\n{model}: module of {len(data) / 1e3:.0f} kB, {len(imports)} imports, {len(exports)} exports")
    assert imports == []  # no WASI: the page gives the module nothing
    functions = {name for name, kind in exports if kind == "function"}
    assert len(_api_names()) > 20 and functions == _api_names() | {"_initialize"}  # the API of wasm_api.c only
    assert ("memory", "memory") in exports


@pytest.mark.parametrize("model", MODELS, ids=["WhippleLinear", "Whipple"])
def test_description_has_the_fmus_value_references(site, fmu_files, model):
    from fmpy import read_model_description

    md = read_model_description(str(fmu_files[model]))
    table = json.loads((site / "wasm" / f"{model.replace('.', '_')}.json").read_text())
    assert table["format"] == wasm_build.JSON_FORMAT and table["guid"] == md.guid
    assert table["modelName"] == model
    assert {v["name"]: (v["valueReference"], v["type"], v["causality"]) for v in table["variables"]} == \
           {v.name: (v.valueReference, v.type, v.causality) for v in md.modelVariables}
    assert table["defaultExperiment"] == {key: float(getattr(md.defaultExperiment, key))
                                          for key in ("startTime", "stopTime", "tolerance", "stepSize")}
    starts = {v.name: float(v.start) for v in md.modelVariables if v.type == "Real" and v.start is not None}
    assert {v["name"]: v["start"] for v in table["variables"] if "start" in v and v["type"] == "Real"} == starts
    assert table["wasm"]["bytes"] == (site / "wasm" / table["wasm"]["file"]).stat().st_size


# --- the ride: browser == native ---------------------------------------------------------------

RIDES = [
    # model, parameters and start values, relative tolerance of the FMU's integrator
    pytest.param(LINEAR, {"phi_dot0": 0.5}, 1e-8, id="WhippleLinear-push-5m/s"),
    pytest.param(LINEAR, {"phi_dot0": 0.5, "v": 3.0}, 1e-8, id="WhippleLinear-push-3m/s-weave-unstable"),
    pytest.param(NONLINEAR, {"u_phi0": 0.5}, 1e-10, id="Whipple-push-5m/s"),
    pytest.param(NONLINEAR, {"u_phi0": 0.5, "solver.fixedStepSize": 0.002}, 1e-10, id="Whipple-push-fixed-step"),
]


@pytest.mark.parametrize("model, values, tolerance", RIDES)
def test_browser_ride_equals_native_fmu(page, fmu_files, model, values, tolerance):
    from cosim.fmu.simulate import simulate

    native = simulate(fmu_files[model], stop_time=RIDE, step=STEP, fmi_type="cs", parameters=values,
                      relative_tolerance=tolerance)
    web = _ride(page, model, stopTime=RIDE, stepSize=STEP, tolerance=tolerance, startValues=values)
    assert web["status"] == 0 and web["imports"] == 0
    assert not [line for line in web["log"] if line["status"] >= 2], web["log"]
    names = list(native.dtype.names[1:])
    assert web["names"] == names  # the outputs, in the order of modelDescription.xml
    assert web["time"].shape == native["time"].shape == (round(RIDE / STEP) + 1,)
    assert np.array_equal(web["time"], native["time"])  # the same communication points, bit for bit
    differences = {n: float(np.max(np.abs(web["values"][n] - native[n]))) for n in names}
    worst = max(differences, key=differences.get)
    identical = sum(np.array_equal(web["values"][n], native[n]) for n in names)
    print(f"\n{model} {values}: largest |browser - native| = {differences[worst]:.3g} ({worst}; phi "
          f"{differences['phi']:.3g} rad, delta {differences['delta']:.3g} rad); "
          f"{identical} of {len(names)} outputs bit-identical over {len(native)} points")
    assert all(np.isfinite(web["values"][n]).all() for n in names)
    assert differences[worst] <= TOLERANCE, differences
    # the ride is a ride: the push moved the bicycle (a comparison of two zero signals proves nothing)
    assert np.ptp(native["phi"]) > 1e-3


def test_nonlinear_bicycle_steps_per_second_in_the_browser(page):
    """Reported, not asserted (no wall-clock limit): WebAssembly steps per second of the nonlinear
    bicycle and the multiple of real time, the best of three 10 s rides."""
    rides = [_ride(page, NONLINEAR, stopTime=RIDE, stepSize=STEP, startValues={"u_phi0": 0.5}) for _ in range(3)]
    assert all(r["status"] == 0 and r["time"][-1] == pytest.approx(RIDE, abs=1e-12) for r in rides)
    seconds = min(r["seconds"] for r in rides)
    steps = len(rides[0]["time"]) - 1
    print(f"\n{NONLINEAR} in Chromium: {steps} steps of {STEP} s in {seconds * 1e3:.1f} ms: "
          f"{steps / seconds:,.0f} steps/s, {RIDE / seconds:,.0f} x real time")
    assert seconds > 0


def test_wrong_guid_is_refused_with_the_runtimes_message(page):
    """The C logger's buffer reaches the page: fmi2Instantiate's refusal names both GUIDs."""
    message = page.evaluate("""async () => {
        const fmu = await window.cosim.WasmFMU.load("wasm/Bicycle_Bicycles_WhippleLinear.json");
        fmu.description.guid = "{00000000-0000-0000-0000-000000000000}";
        try { fmu.instantiate(); return "instantiated"; }
        catch (e) { return e.name + ": " + e.log.map(l => l.message).join(" | "); }
    }""")
    assert message.startswith("FMIError: ") and "does not match" in message
    assert "{00000000-0000-0000-0000-000000000000}" in message


def test_logging_and_fmu_state_in_the_browser(page):
    """loggingOn logs every FMI call (category logCalls); an FMU state taken at 1 s and set after
    2 s repeats the second second bit for bit; a freed instance and an unknown name are refused."""
    out = page.evaluate("""async () => {
        const fmu = await window.cosim.WasmFMU.load("wasm/Bicycle_Bicycles_Whipple.json");
        const bike = fmu.instantiate({name: "bike", loggingOn: true});
        bike.set({u_phi0: 0.5});
        bike.setupExperiment({tolerance: 1e-10, startTime: 0});
        bike.enterInitializationMode(); bike.exitInitializationMode();
        let t = 0;
        for (; t < 100; t++) bike.doStep(t * 0.01, 0.01);
        const state = bike.getFMUState();
        for (; t < 200; t++) bike.doStep(t * 0.01, 0.01);
        const first = bike.get(["phi", "delta", "x"]);
        bike.setFMUState(state);
        for (t = 100; t < 200; t++) bike.doStep(t * 0.01, 0.01);
        const again = bike.get(["phi", "delta", "x"]);
        bike.freeFMUState(state);
        bike.terminate(); bike.free();
        const refusals = [];
        for (const call of [() => bike.doStep(2, 0.01), () => bike.get("phi"), () => fmu.variable("no_such_variable")])
          try { call(); refusals.push("accepted"); } catch (e) { refusals.push(e.name + ": " + e.message); }
        return {first, again, refusals, calls: bike.log.filter(l => l.category === "logCalls").map(l => l.message)};
    }""")
    assert out["first"] == out["again"] and abs(out["first"][0]) > 1e-4
    assert out["refusals"] == ["FMIError: the instance of Bicycle.Bicycles.Whipple was freed"] * 2 + \
        ["FMIError: Bicycle.Bicycles.Whipple has no variable 'no_such_variable'"]
    assert any(m.startswith("fmi2DoStep(") for m in out["calls"])
    assert any(m.startswith("fmi2SetFMUstate") for m in out["calls"])


# --- the build: incremental, atomic, clear errors ------------------------------------------------

def test_build_is_incremental_and_keyed_on_the_toolchain(site, fmu_files, tmp_path, monkeypatch):
    fmu = fmu_files[LINEAR]
    first = wasm_build.build_wasm(fmu, tmp_path)
    again = wasm_build.build_wasm(fmu, tmp_path)
    assert first.rebuilt and not again.rebuilt and again.size == first.size
    assert first.wasm.read_bytes() == (site / "wasm" / first.wasm.name).read_bytes()  # reproducible
    monkeypatch.setattr(wasm_build, "zig_version", lambda: "0.0.0-another-zig")
    assert wasm_build.build_wasm(fmu, tmp_path).rebuilt  # another compiler: compiled again
    monkeypatch.undo()
    assert wasm_build.build_wasm(fmu, tmp_path).rebuilt  # and back
    assert wasm_build.build_wasm(fmu, tmp_path, force=True).rebuilt
    # nothing but the two files (no temporary name, no lock) is left
    assert sorted(p.name for p in (tmp_path / "wasm").iterdir()) == sorted([first.wasm.name, first.description.name])


def test_concurrent_builds_compile_once(site, fmu_files, tmp_path):
    """Two builds of one module at once: one compiles, the other waits for its lock and finds the
    module up to date."""
    results = []
    threads = [threading.Thread(target=lambda: results.append(wasm_build.build_wasm(fmu_files[LINEAR], tmp_path)))
               for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=600)
    assert sorted(r.rebuilt for r in results) == [False, True]


def test_failed_compilation_leaves_nothing(site, fmu_files, tmp_path, monkeypatch):
    """A compiler error is a BuildError with the compiler's words; no module, no description and
    no temporary file is left."""
    monkeypatch.setattr(wasm_build, "CFLAGS", (*wasm_build.CFLAGS, "-include",
                                               "no_such_header_for_the_test.h"))
    with pytest.raises(BuildError, match="WebAssembly compilation failed:(.|\n)*no_such_header_for_the_test"):
        wasm_build.build_wasm(fmu_files[LINEAR], tmp_path)
    assert not list((tmp_path / "wasm").iterdir())


def test_cli_build_wasm(site, tmp_path):
    status, out, err = cli_in_process(["build", "--wasm", LINEAR, "-o", str(tmp_path)], tmp_path)
    assert status == 0, err
    wasm, description = wasm_build.wasm_paths(tmp_path / "Bicycle_Bicycles_WhippleLinear.fmu")
    assert f"built  {wasm}" in out and wasm.is_file() and description.is_file()
    status, out, err = cli_in_process(["build", "--wasm", LINEAR, "-o", str(tmp_path)], tmp_path)
    assert status == 0 and f"up to date {wasm}" in out


def test_missing_ziglang_is_one_message_before_any_work(tmp_path, monkeypatch):
    import importlib.util

    find_spec = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "ziglang" else find_spec(name, *a))
    status, out, err = cli_in_process(["build", "--wasm", LINEAR, "-o", str(tmp_path / "out")], tmp_path)
    assert status == 2 and "pip install 'bicycle-cosim[wasm]'" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()  # no FMU was built first
    with pytest.raises(MissingExtraError, match=r"optional extra 'wasm'"):
        wasm_build.zig_command()


def _fake_fmu(path: Path, description: str) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("modelDescription.xml", description)
    return path


@pytest.mark.parametrize("description, message", [
    pytest.param('<fmiModelDescription fmiVersion="3.0" modelName="M" instantiationToken="x"/>',
                 "compiles FMI 2.0 FMUs", id="fmi3"),
    pytest.param('<fmiModelDescription fmiVersion="2.0" modelName="M" guid="x"><ModelExchange '
                 'modelIdentifier="M"/></fmiModelDescription>', "no Co-Simulation", id="model-exchange-only"),
    pytest.param('<fmiModelDescription fmiVersion="2.0" modelName="M" guid="x"><CoSimulation '
                 'modelIdentifier="M"/></fmiModelDescription>', "binary-only", id="no-sources"),
    pytest.param('<fmiModelDescription fmiVersion="2.0"', "not well-formed", id="broken-xml"),
])
def test_unusable_fmu_is_refused_by_name(tmp_path, description, message):
    fmu = _fake_fmu(tmp_path / "M.fmu", description)
    with pytest.raises(FMUError, match=message) as info:
        wasm_build.build_wasm(fmu, tmp_path)
    assert str(fmu) in str(info.value)
    assert not (tmp_path / "wasm").exists() or not list((tmp_path / "wasm").iterdir())


def test_not_an_fmu(tmp_path):
    with pytest.raises(FMUError, match="no such FMU"):
        wasm_build.build_wasm(tmp_path / "missing.fmu", tmp_path)
    (tmp_path / "text.fmu").write_text("not a zip")
    with pytest.raises(FMUError, match="cannot read the FMU"):
        wasm_build.build_wasm(tmp_path / "text.fmu", tmp_path)
    with pytest.raises(BuildError, match="not a WebAssembly"):
        wasm_build.module_interface(b"\x7fELF")
