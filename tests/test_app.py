"""`cosim app` (cosim/app): the exported page, opened from file:// in a real headless Chromium.

The page computes the eigenvalues of the bicycles of cosim/app/bicycles.py from the WebAssembly
modules of the FMUs Bicycle.Bicycles.WhippleLinear (the Meijaard sets, the rear-steered bicycle
at negative speeds) and Bicycle.Bicycles.Whipple (the crowned rear roller: the lateral block of
the nonlinear bicycle at upright straight running); A(v) from fmi2GetDirectionalDerivative,
eigenvalues by the vendored ml-matrix. The tests move its sliders and type into its parameter
editor with real mouse and keyboard input and compare what it shows with
:mod:`cosim.analytic.whipple` (an implementation independent of the Modelica, the FMU and the
page) or, for the crowned roller, with the native FMU's lateral linearization (`cosim
linearize --json`): eigenvalues to 1e-6 absolute, weave and capsize speeds to 1e-6 relative.
Refused editor values must give one message naming the parameter and leave the plots as they
were. No request other than file:// may be made. The redraw time of a slider move is
measured and printed, not asserted. The browser fixture and the skip rules (a missing Chromium,
playwright or ziglang skips outside CI, fails in CI) are those of tests/test_wasm.py. The tests of
the page share one page, reset before each test to the state of a page just loaded
(tests/app_page.py); the layout tests open their own (other window sizes and pixel ratios).
"""
from __future__ import annotations

import itertools
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from cosim.analytic import roller
from cosim.cli import EXIT_INTERRUPTED
from cosim.app.bicycles import MEASURED_LABELS
from app_page import SharedPage
from conftest import bound_by_permissions, bundle_data, cli_in_process
from test_wasm import browser, offline_page  # noqa: F401 (browser: the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site or animation
pytestmark = pytest.mark.slow

EIGENVALUE_TOL = 1e-6  # absolute [1/s]: page vs cosim.analytic
SPEED_RTOL = 1e-6  # relative: weave and capsize speeds of the page vs cosim.analytic
V_MAX = 12.0  # [m/s] the page's speed range riding forwards (bicycles.FORWARD)
DIGITS = 3  # decimals of the speeds the page prints (bicycles.SPEED_DIGITS)


@pytest.fixture(scope="module")
def shared_page(browser, app_site):  # noqa: F811 (the imported fixture)
    """The exported page opened from file://, one for the module (tests/app_page.py)."""
    with SharedPage(browser, app_site / "index.html", viewport={"width": 1200, "height": 800}) as shared:
        yield shared


@pytest.fixture()
def page(shared_page):
    """The exported page from file://, ready, as it is when it has just loaded (tests/app_page.py);
    a request that is not file:// is refused (and fails the test), as is any error in the page."""
    with shared_page.reset() as page:
        assert page.evaluate("window.cosimApp.error") is None
        yield page


def _state(page) -> dict:
    s = page.evaluate("""() => { const a = window.cosimApp;
        return {set: a.set, parameters: a.parameters, speed: a.speed, eigenvalues: a.eigenvalues,
                weave: a.weave, capsize: a.capsize, lastRedrawMs: a.lastRedrawMs, evaluations: a.evaluations,
                redraws: a.redraws}; }""")
    s["eigenvalues"] = np.array([complex(re, im) for re, im in s["eigenvalues"]])
    return s


def _eigenvalue_difference(web: np.ndarray, analytic: np.ndarray) -> float:
    """Largest |web - analytic| under the pairing of the two sets of 4 that makes it smallest
    (no reliance on both sorting equal real parts of a conjugate pair the same way)."""
    assert web.shape == analytic.shape == (4,)
    return min(float(np.max(np.abs(web[list(order)] - analytic))) for order in itertools.permutations(range(4)))


def _analytic_speeds(params) -> tuple[float | None, float | None]:
    """Weave and capsize speeds of cosim.analytic (its own 0..30 m/s scan), None beyond the page's range."""
    from cosim.analytic.whipple import capsize_speed, weave_speed

    weave, capsize = weave_speed(params), capsize_speed(params)
    return (weave if weave is not None and weave <= V_MAX else None,
            capsize if capsize is not None and capsize <= V_MAX else None)


def _check_against_analytic(s: dict) -> tuple[float, float]:
    """The page's eigenvalues and critical speeds equal cosim.analytic for the page's parameters;
    returns the eigenvalue difference [1/s] and the largest relative difference of the speeds."""
    from cosim.analytic.whipple import eigenvalues

    difference = _eigenvalue_difference(s["eigenvalues"], eigenvalues(s["parameters"], s["speed"]))
    assert difference <= EIGENVALUE_TOL, (s["speed"], s["eigenvalues"])
    relative = 0.0
    for name, web, expected in zip(("weave", "capsize"), (s["weave"], s["capsize"]), _analytic_speeds(s["parameters"])):
        if expected is None:
            assert web is None, f"{name}: page {web}, analytic none in 0..{V_MAX} m/s"
        else:
            assert web is not None and web == pytest.approx(expected, rel=SPEED_RTOL), (name, web, expected)
            relative = max(relative, abs(web - expected) / expected)
    return difference, relative


def test_page_loads_offline_from_two_files(page, app_site):
    """Exactly the two exported files are requested (no module, no font, no CDN)."""
    assert sorted(page.requests) == sorted(p.as_uri() for p in (app_site / "index.html", app_site / "bundle.js"))
    s = _state(page)
    assert s["set"] == "benchmark" and s["redraws"] >= 1 and len(s["eigenvalues"]) == 4


MOVES = [
    # parameter set, slider moved by the keyboard, number of ArrowRight presses, fraction of the
    # speed slider's width clicked with the mouse
    pytest.param("benchmark", "mB", 30, 0.3, id="benchmark-mB-3m/s"),
    pytest.param("astrom2005", "c", 20, 0.45, id="astrom2005-trail-4.5m/s"),
    pytest.param("astrom2005-riderless", "w", 40, 0.8, id="astrom2005-riderless-wheelbase-8m/s"),
    pytest.param("benchmark", "lam", 50, 0.55, id="benchmark-steer-tilt-5.5m/s"),
]


@pytest.mark.parametrize("name, slider, presses, fraction", MOVES)
def test_slider_moves_give_the_analytic_eigenvalues(page, name, slider, presses, fraction):
    from cosim.analytic.parameters import load_parameters

    expected_parameters = load_parameters(name)
    page.select_option("#set", name)  # a real change event
    s0 = _state(page)
    assert s0["set"] == name and s0["parameters"] == expected_parameters  # the TOML's values, unchanged
    d0, r0 = _check_against_analytic(s0)

    # the speed slider: a mouse click at `fraction` of its width
    box = page.locator("#speed").bounding_box()
    page.mouse.click(box["x"] + fraction * box["width"], box["y"] + box["height"] / 2)
    s1 = _state(page)
    shown = float(page.locator("#speed").input_value())
    assert s1["speed"] == shown and abs(shown - fraction * V_MAX) < 0.5  # moved to about where clicked
    assert np.max(np.abs(s1["eigenvalues"] - s0["eigenvalues"])) > 1e-3  # the shown eigenvalues changed
    d1, _ = _check_against_analytic(s1)  # a new speed: the same sweep

    # a parameter slider: ArrowRight presses on the focused slider, one input event each
    page.locator(f"#slider-{slider}").focus()
    for _ in range(presses):
        page.keyboard.press("ArrowRight")
    s2 = _state(page)
    moved = float(page.locator(f"#slider-{slider}").input_value())
    assert s2["parameters"] == {**expected_parameters, slider: moved}  # only that parameter changed
    assert moved > expected_parameters[slider] + 1e-9
    assert s2["redraws"] >= s1["redraws"] + presses
    assert s1["evaluations"] == 1 and s2["evaluations"] > 200  # a speed: one; a parameter: the sweep + bisections
    assert np.max(np.abs(s2["eigenvalues"] - s1["eigenvalues"])) > 1e-6
    d2, r2 = _check_against_analytic(s2)
    print(f"\n{name}: v = {s1['speed']} m/s, {slider} {expected_parameters[slider]:.6g} -> {moved:.6g}: "
          f"max |page - analytic| eigenvalue difference {max(d0, d1, d2):.2e} 1/s; weave {s2['weave']}, "
          f"capsize {s2['capsize']} m/s (relative difference to analytic {max(r0, r2):.1e}); redraw after the speed "
          f"click {s1['lastRedrawMs']:.1f} ms, after the last parameter key press {s2['lastRedrawMs']:.1f} ms "
          f"({s2['evaluations']} linearizations of the FMU: 200 speeds + bisections)")


@pytest.mark.parametrize("canvas", ["plot", "locus"], ids=["eigenvalues-vs-speed", "root-locus"])
def test_plots_are_drawn(page, canvas):
    """The canvas is not blank: reddish and bluish pixels (unstable and stable eigenvalues, the
    paper's colours) are there."""
    pixels = page.evaluate("""(id) => { const c = document.getElementById(id);
        const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
        let red = 0, blue = 0;
        for (let i = 0; i < d.length; i += 4) {
          if (d[i] > 150 && d[i + 1] < 80 && d[i + 2] < 100) red++;
          if (d[i] < 100 && d[i + 1] < 120 && d[i + 2] > 150) blue++;
        }
        return {red, blue}; }""", canvas)
    assert pixels["red"] > 200 and pixels["blue"] > 200, pixels


@pytest.mark.parametrize("make, message", [
    pytest.param(lambda tmp: (tmp / "taken").write_text("x") and tmp / "taken", "is a file, not a folder",
                 id="existing-file"),
    pytest.param(lambda tmp: (tmp / "taken").write_text("x") and tmp / "taken" / "site",
                 "'{tmp}/taken' is a file, not a folder", id="below-a-file"),
    pytest.param(lambda tmp: (tmp / "ro").mkdir(mode=0o555) or tmp / "ro" / "site", "is not writable",
                 id="read-only-folder"),
])
def test_export_to_an_unusable_path_is_one_clear_error(tmp_path, make, message):
    target = make(tmp_path)

    def export():
        return cli_in_process(["app", "--export", str(target)], tmp_path)

    # a read-only folder: in a child that its mode binds, as root too
    status, out, err = bound_by_permissions(export, target.parent) if message == "is not writable" else export()
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("cosim app: error: app folder ") and "Traceback" not in err
    assert message.format(tmp=tmp_path) in err


@pytest.mark.parametrize("stop, status", [(signal.SIGINT, EXIT_INTERRUPTED), (signal.SIGTERM, 128 + signal.SIGTERM)],
                         ids=["ctrl-c", "sigterm"])
def test_serves_the_same_site_on_localhost(app_site, tmp_path, stop, status):
    """`cosim app --port 0` serves the exported files on 127.0.0.1 (a free port), byte for byte;
    Ctrl-C or SIGTERM stops it and its temporary folder is gone."""
    folders = set(Path(tempfile.gettempdir()).glob("cosim-app-*"))  # (another test's, if it failed)
    env = {**os.environ, "PYTHONFAULTHANDLER": "1"}  # a server that does not stop shows where it hangs
    process = subprocess.Popen([sys.executable, "-m", "cosim", "app", "--port", "0"], cwd=tmp_path, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    try:
        line = process.stdout.readline()
        match = re.search(r"serving the app on (http://127\.0\.0\.1:\d+/)", line)
        assert match, (line, process.stderr.read() if process.poll() is not None else "")
        for name in ("index.html", "bundle.js"):
            with urllib.request.urlopen(match.group(1) + name, timeout=30) as response:
                assert response.read() == (app_site / name).read_bytes(), name
        process.send_signal(stop)
        try:
            code = process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.send_signal(signal.SIGABRT)  # faulthandler writes every thread's stack to stderr
            process.wait(timeout=30)
            pytest.fail(f"the server had not stopped 30 s after {stop.name}:\n{process.stderr.read()[-6000:]}")
        assert code == status
        assert set(Path(tempfile.gettempdir()).glob("cosim-app-*")) == folders
    finally:
        if process.poll() is None:
            process.kill()
            process.wait(timeout=30)
        process.stdout.close()
        process.stderr.close()


def _start_server(cwd: Path) -> tuple[subprocess.Popen, str]:
    """`cosim app --port 0` in ``cwd``, once it serves: (process, the line with the URL)."""
    process = subprocess.Popen([sys.executable, "-m", "cosim", "app", "--port", "0"], cwd=cwd, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    line = process.stdout.readline()
    assert "serving the app on http://127.0.0.1:" in line, (line, process.stderr.read() if process.poll() else "")
    return process, line


def test_folder_of_a_killed_server_is_removed_by_the_next_one(app_site, tmp_path):
    """kill -9 of `cosim app` leaves its temporary folder (TMPDIR/cosim-app-PID-*: no handler
    runs); the next `cosim app` removes it, and one of an ended process that never served
    (a finished child's pid), while a folder of a live process stays."""
    tmp = Path(tempfile.gettempdir())
    ended = subprocess.Popen([sys.executable, "-c", "pass"])
    ended.wait()  # reaped: its pid names no process
    stale = tmp / f"cosim-app-{ended.pid}-leftover"
    live = tmp / f"cosim-app-{os.getpid()}-in-use"  # this test process: alive
    for folder in (stale, live):
        folder.mkdir()
        (folder / "bundle.js").write_text("// left behind\n")
    first, _ = _start_server(tmp_path)
    try:
        killed = list(tmp.glob(f"cosim-app-{first.pid}-*"))
        assert len(killed) == 1 and (killed[0] / "bundle.js").exists(), killed
        first.send_signal(signal.SIGKILL)
        first.wait(timeout=30)
        assert killed[0].exists(), "SIGKILL runs no cleanup: the folder is left"
        second, _ = _start_server(tmp_path)
        try:
            assert not killed[0].exists() and not stale.exists(), "the next server removes what ended ones left"
            assert (live / "bundle.js").exists(), "a live process's folder stays"
        finally:
            second.send_signal(signal.SIGINT)
            assert second.wait(timeout=30) == EXIT_INTERRUPTED
    finally:
        for process in (first, locals().get("second")):
            if process is not None:
                if process.poll() is None:
                    process.kill()
                    process.wait(timeout=30)
                process.stdout.close()
                process.stderr.close()
        shutil.rmtree(live, ignore_errors=True)


@pytest.mark.parametrize("speed", [0.0, 3.0, 5.0, -2.0], ids=["0m/s", "3m/s", "5m/s", "backwards-2m/s"])
def test_directional_derivatives_are_the_analytic_state_matrix(page, speed):
    """fmu.js's directional() over wasm_directional (fmi2GetDirectionalDerivative in the module):
    the 4x4 Jacobian of the lateral state derivatives of WhippleLinear equals A(v) of
    cosim.analytic.whipple.state_matrices, entry by entry, to 1e-12 relative to max |A|."""
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import state_matrices

    params = load_parameters("astrom2005")
    out = page.evaluate("""async ({params, speed}) => {
        const D = window.COSIM_DATA.modules[window.COSIM_DATA.model];
        const fmu = await window.CosimFMU.WasmFMU.fromBytes(D.description,
            Uint8Array.from(atob(D.wasm), (ch) => ch.charCodeAt(0)));
        const bike = fmu.instantiate({name: "jacobian"});
        const write = bike.writer([...Object.keys(params), "v"]);
        write([...Object.values(params), speed]);
        bike.setupExperiment({startTime: 0});
        bike.enterInitializationMode(); bike.exitInitializationMode();
        const d = bike.directional(["der(phi)", "der(delta)", "der(phi_dot)", "der(delta_dot)"],
                                   ["phi", "delta", "phi_dot", "delta_dot"]);
        const A = d.jacobian();
        const column = Array.from(d([0, 0, 1, 0]));  // one seed: the third column
        let refused;
        try { d([1, 2]); refused = "accepted"; } catch (e) { refused = e.message; }
        d.free(); write.free(); bike.free();
        return {A, column, refused};
    }""", {"params": params, "speed": speed})
    A, _ = state_matrices(params, speed)
    web = np.array(out["A"])
    assert web.shape == (4, 4)
    assert np.max(np.abs(web - A)) <= 1e-12 * np.max(np.abs(A)), web - A
    assert np.array_equal(np.array(out["column"]), web[:, 2])
    assert out["refused"] == "a seed of 4 values is needed, got 2"


def test_port_in_use_is_one_clear_error(tmp_path):
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        status, out, err = cli_in_process(["app", "--port", str(port)], tmp_path)
    assert status == 2 and out == "" and "Traceback" not in err
    assert err.strip().splitlines() == [f"cosim app: error: cannot serve on 127.0.0.1:{port}: Address already in use"]


# --- the bicycle choices (cosim/app/bicycles.py): rear-steered, crowned roller, every parameter --

BACKWARD_MIN = -10.0  # [m/s] the rear-steered bicycle's speed range is -10..0 (bicycles.BACKWARD)


def _choose(page, name: str) -> dict:
    """Choose a bicycle with a real change event of the select; its state."""
    page.select_option("#set", name)
    s = _state(page)
    assert s["set"] == name and page.evaluate("window.cosimApp.error") is None
    return s


def _click_speed(page, fraction: float) -> float:
    """A mouse click at ``fraction`` of the speed slider's width; the speed shown [m/s]."""
    box = page.locator("#speed").bounding_box()
    page.mouse.click(box["x"] + fraction * box["width"], box["y"] + box["height"] / 2)
    shown = float(page.locator("#speed").input_value())
    assert page.evaluate("window.cosimApp.speed") == shown
    return shown


def _type_parameter(page, name: str, text: str) -> None:
    """Replace the editor's value of ``name`` by ``text`` with real keyboard input (select all,
    then one key event per character, each an input event: intermediate values included)."""
    page.evaluate("document.querySelector('#all-parameters details').open = true")
    field = page.locator(f"#param-{name}")
    field.click()
    page.keyboard.press("Control+A")
    if text:
        page.keyboard.type(text)
    else:
        page.keyboard.press("Backspace")


def _pictures(page) -> tuple[str, str]:
    """What the two canvases show (PNG data URLs)."""
    return tuple(page.evaluate("(id) => document.getElementById(id).toDataURL()", c) for c in ("plot", "locus"))


def _extra(page) -> dict:
    return page.evaluate("""() => { const a = window.cosimApp;
        return {module: a.module, speedRange: a.speedRange, selfStable: a.selfStable, parameterError: a.parameterError,
                leastUnstable: a.leastUnstable, error: a.error}; }""")


REAR_MOVES = [
    # slider, key, presses, fraction of the speed slider clicked (-10 + 10 fraction m/s)
    pytest.param("w", "ArrowRight", 30, 0.25, id="wheelbase-up--7.5m/s"),
    pytest.param("c", "ArrowLeft", 40, 0.7, id="trail-down--3m/s"),
    pytest.param("mB", "ArrowRight", 20, 0.95, id="rear-frame-mass-up--0.5m/s"),
]


@pytest.mark.parametrize("slider, key, presses, fraction", REAR_MOVES)
def test_rear_steered_is_the_benchmark_at_negative_speeds(page, slider, key, presses, fraction):
    """The rear-steered choice is WhippleLinear at v in -10..0 m/s with the benchmark's values:
    after real speed and parameter slider moves its eigenvalues equal cosim.analytic's at the
    negative speed, and it is self-stable nowhere (as cosim.analytic.whipple.self_stable_interval)."""
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import eigenvalues, self_stable_interval

    benchmark = load_parameters("benchmark")
    s0 = _choose(page, "rear-steered")
    x0 = _extra(page)
    assert s0["parameters"] == benchmark and x0["module"] == "Bicycle.Bicycles.WhippleLinear"
    assert (x0["speedRange"]["min"], x0["speedRange"]["max"]) == (BACKWARD_MIN, 0.0)
    speed = _click_speed(page, fraction)
    assert speed < 0 and abs(speed - (BACKWARD_MIN + 10.0 * fraction)) < 0.5
    d1, _ = _check_rear_steered(page, eigenvalues)
    page.locator(f"#slider-{slider}").focus()
    for _ in range(presses):
        page.keyboard.press(key)
    s2 = _state(page)
    moved = float(page.locator(f"#slider-{slider}").input_value())
    assert s2["parameters"] == {**benchmark, slider: moved} and abs(moved - benchmark[slider]) > 1e-9
    assert float(page.locator(f"#param-{slider}").input_value()) == moved  # the editor follows the slider
    assert s2["evaluations"] > 200  # a parameter: the whole sweep again
    d2, least = _check_rear_steered(page, eigenvalues)
    x2 = _extra(page)
    assert x2["selfStable"] is None and self_stable_interval(s2["parameters"], v_min=BACKWARD_MIN, v_max=0.0) is None
    assert s2["weave"] is None and s2["capsize"] is None
    assert "self-stable at no speed" in page.locator("#self-stable").inner_text()
    print(f"\nrear-steered at v = {speed} m/s, {slider} {benchmark[slider]:.6g} -> {moved:.6g}: max |page - analytic| "
          f"{max(d1, d2):.2e} 1/s; smallest largest real part {least:.4f} 1/s; redraw {s2['lastRedrawMs']:.1f} ms "
          f"({s2['evaluations']} linearizations)")


def _check_rear_steered(page, eigenvalues) -> tuple[float, float]:
    """Eigenvalues at the page's (negative) speed vs cosim.analytic, and the page's smallest
    largest real part over the sweep vs cosim.analytic at the same speed; both differences <= tol."""
    s, x = _state(page), _extra(page)
    assert s["speed"] <= 0.0
    difference = _eigenvalue_difference(s["eigenvalues"], eigenvalues(s["parameters"], s["speed"]))
    assert difference <= EIGENVALUE_TOL, (s["speed"], s["eigenvalues"])
    least = x["leastUnstable"]
    assert least["re"] > 0  # unstable at every speed of the range
    assert abs(least["re"] - eigenvalues(s["parameters"], least["speed"]).real.max()) <= EIGENVALUE_TOL
    return difference, least["re"]


def _native_lateral(parameters: dict, speed: float, cwd: Path) -> np.ndarray:
    """The lateral eigenvalues of `cosim linearize Bicycle.Bicycles.Whipple --speed V --json`
    (the native FMU, cosim.bicycle.linearize.steady_motion) for the page's parameters."""
    import json

    args = ["linearize", "Bicycle.Bicycles.Whipple", "--speed", repr(speed), "--json"]
    for name, value in parameters.items():
        args += ["--param", f"{name}={value!r}"]
    status, out, err = cli_in_process(args, cwd)
    assert status == 0, err
    steady = json.loads(out)["steady_motion"]
    assert steady["states"] == ["phi", "delta", "u_phi", "u_delta"]
    return np.array([complex(re, im) for re, im in steady["eigenvalues"]])


CROWNS = [
    pytest.param(None, id="tR-0.3-figure-15"),
    pytest.param("0.6", id="tR-0.6-typed"),
    pytest.param("0", id="tR-0-knife-edge-typed"),
]


@pytest.mark.parametrize("typed", CROWNS)
def test_crowned_roller_is_the_native_lateral_linearization(page, tmp_path, typed):
    """The crowned-roller choice (the nonlinear Whipple module, u_R0 = -v/rR) equals the native
    FMU's exact lateral reduction (`cosim linearize --speed V --json`, steady_motion) at three
    speeds to 1e-6; with a knife-edge roller (tR = 0) also cosim.analytic (the reduction is
    right). tR is typed into the parameter editor with real key events."""
    from cosim.analytic.whipple import eigenvalues

    expected = {**roller.adapted_parameters(), "tR": 0.3, "tF": 0.0}
    s = _choose(page, "crowned-roller")
    assert s["parameters"] == expected and _extra(page)["module"] == "Bicycle.Bicycles.Whipple"
    if typed is not None:
        _type_parameter(page, "tR", typed)
        expected["tR"] = float(typed)
        assert _state(page)["parameters"] == expected and _extra(page)["parameterError"] is None
        assert float(page.locator("#slider-tR").input_value()) == float(typed)  # the slider follows the editor
    worst = worst_analytic = 0.0
    for fraction in (0.2, 0.55, 0.9):
        speed = _click_speed(page, fraction)
        s = _state(page)
        native = _native_lateral(s["parameters"], speed, tmp_path)
        worst = max(worst, _eigenvalue_difference(s["eigenvalues"], native))
        if expected["tR"] == 0.0:
            worst_analytic = max(worst_analytic, _eigenvalue_difference(s["eigenvalues"], eigenvalues(
                {k: v for k, v in s["parameters"].items() if k not in ("tR", "tF")}, speed)))
    assert worst <= EIGENVALUE_TOL and worst_analytic <= EIGENVALUE_TOL, (worst, worst_analytic)
    if expected["tR"] == 0.0:  # the knife edge: the weave and capsize speeds of cosim.analytic
        s = _state(page)
        meijaard = {k: v for k, v in s["parameters"].items() if k not in ("tR", "tF")}
        for name, web, analytic in zip(("weave", "capsize"), (s["weave"], s["capsize"]), _analytic_speeds(meijaard)):
            assert (web is None and analytic is None) or web == pytest.approx(analytic, rel=SPEED_RTOL), (name, web)
    # a parameter slider: the sweep of 200 nonlinear linearizations (+ bisections), timed
    page.locator("#slider-tR").focus()
    page.keyboard.press("ArrowRight")
    s = _state(page)
    assert s["parameters"]["tR"] == pytest.approx(expected["tR"] + 0.001, abs=1e-12) and s["evaluations"] > 200
    print(f"\ncrowned roller tR = {expected['tR']} m: max |page - native lateral| {worst:.2e} 1/s"
          + (f", |page - analytic| {worst_analytic:.2e} 1/s" if expected["tR"] == 0.0 else "")
          + f"; redraw after a tR slider step {s['lastRedrawMs']:.1f} ms ({s['evaluations']} linearizations "
          f"of the nonlinear module); weave {s['weave']}, capsize {s['capsize']} m/s")


CONTINUED = [
    # bicycle, parameter typed (a new parameter set after the bicycle's own), its value
    pytest.param("crowned-roller", "tR", "0.6", id="crowned-roller-tR-0.6"),
    pytest.param("crowned-roller", "rF", "0.45", id="crowned-roller-rF-0.45"),
    pytest.param("benchmark", "c", "0.1", id="benchmark-trail-0.1"),
]
CONTINUATION_TOL = 1e-12  # relative to max(1, |value|): continuation vs new initializations


def _shown(page) -> dict:
    """What a redraw computed and shows: the sweep's eigenvalues, the speeds and the texts."""
    return page.evaluate("""() => { const a = window.cosimApp;
        return {evs: a.sweep.evs, eigenvalues: a.eigenvalues, weave: a.weave, capsize: a.capsize,
                selfStable: a.selfStable, leastUnstable: a.leastUnstable, evaluations: a.evaluations,
                text: ['weave', 'capsize', 'self-stable', 'eigenvalues', 'speed-value']
                  .map((id) => document.getElementById(id).textContent)}; }""")


@pytest.mark.parametrize("name, parameter, text", CONTINUED)
def test_continuation_gives_the_numbers_of_new_initializations(page, name, parameter, text):
    """By continuation (the default: the module stays in initialization mode while only the speed
    changes; a new parameter set starts its pitch from the previous one's) a redraw gives the
    sweep, the weave and capsize speeds and the texts that a new initialization at every speed
    (cosimApp.continuation = false) gives, to 1e-12; switched on again, the same."""
    _choose(page, name)
    assert page.evaluate("window.cosimApp.continuation") is True
    _type_parameter(page, parameter, text)  # the new parameter set, continued from the bicycle's own
    runs = [_shown(page)]
    for on in (False, True):
        page.evaluate("(on) => { window.cosimApp.continuation = on; }", on)
        page.dispatch_event(f"#param-{parameter}", "input")  # the same parameters, redrawn
        runs.append(_shown(page))
    assert page.evaluate("window.cosimApp.error") is None and _state(page)["parameters"][parameter] == float(text)
    new = runs[1]
    assert new["evaluations"] > 200
    worst = 0.0
    for run in (runs[0], runs[2]):
        assert run["text"] == new["text"] and run["evaluations"] == new["evaluations"]
        a = np.array([*run["evs"], run["eigenvalues"]], float)
        b = np.array([*new["evs"], new["eigenvalues"]], float)
        worst = max(worst, float((np.abs(a - b) / np.maximum(1.0, np.abs(b))).max()))
        for key in ("weave", "capsize"):
            assert (run[key] is None) == (new[key] is None), key
            if run[key] is not None:
                worst = max(worst, abs(run[key] - new[key]) / max(1.0, abs(new[key])))
        assert (run["selfStable"] is None) == (new["selfStable"] is None)
        if run["selfStable"] is not None:
            assert np.allclose(run["selfStable"], new["selfStable"], rtol=CONTINUATION_TOL, atol=CONTINUATION_TOL)
    assert worst <= CONTINUATION_TOL, worst
    print(f"\n{name}, {parameter} = {text}: continuation vs new initializations: max relative difference "
          f"{worst:.1e} ({new['evaluations']} linearizations)")


EDITS = [
    # bicycle, parameter without a slider (but mB), typed value
    pytest.param("benchmark", "IBxx", "12.5", id="benchmark-IBxx"),
    pytest.param("astrom2005", "xH", "0.95", id="astrom2005-xH"),
    pytest.param("astrom2005-riderless", "mF", "4.5", id="riderless-mF"),
    pytest.param("rear-steered", "zB", "-1.1", id="rear-steered-zB"),
    pytest.param("benchmark", "mB", "70", id="benchmark-mB-slider-follows"),
]


@pytest.mark.parametrize("name, parameter, text", EDITS)
def test_typed_parameter_gives_the_analytic_eigenvalues(page, name, parameter, text):
    """A value typed into the editor with real key events (intermediate values included, some
    refused on the way) gives cosim.analytic's eigenvalues and speeds for the new parameters."""
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import eigenvalues

    base = load_parameters(name if name != "rear-steered" else "benchmark")
    s0 = _choose(page, name)
    _type_parameter(page, parameter, text)
    s = _state(page)
    assert s["parameters"] == {**base, parameter: float(text)} and _extra(page)["parameterError"] is None
    assert s["redraws"] > s0["redraws"]
    if name == "rear-steered":
        difference = _eigenvalue_difference(s["eigenvalues"], eigenvalues(s["parameters"], s["speed"]))
        assert difference <= EIGENVALUE_TOL
    else:
        difference, _ = _check_against_analytic(s)
    if parameter == "mB":
        assert float(page.locator("#slider-mB").input_value()) == float(text)
        assert page.locator("#value-mB").inner_text() == text
    print(f"\n{name}: {parameter} typed {base[parameter]:.6g} -> {text}: |page - analytic| {difference:.2e} 1/s, "
          f"redraw {s['lastRedrawMs']:.1f} ms")


BAD = [
    # bicycle, parameter, typed text (refused after every key), the message's start (None:
    # cosim.analytic's message for the value)
    pytest.param("benchmark", "IBxx", "", "IBxx: empty", id="empty"),
    pytest.param("benchmark", "mB", "heavy", "mB: not a number: 'heavy'", id="not-a-number"),
    pytest.param("benchmark", "mF", "-3", None, id="negative-mass"),
    pytest.param("astrom2005", "rR", "0", None, id="zero-radius"),
    pytest.param("benchmark", "IBxz", "9", None, id="inertia-not-positive-semidefinite"),
    pytest.param("benchmark", "IByy", "30", None, id="inertia-triangle-inequality"),
    pytest.param("rear-steered", "c", "2", None, id="trail-longer-than-wheelbase"),
    pytest.param("benchmark", "zH", "0.2", None, id="centre-of-mass-below-ground"),
    pytest.param("crowned-roller", "tR", "-1", "tR: must be >= 0", id="negative-crown-radius"),
]


@pytest.mark.parametrize("name, parameter, text, message", BAD)
def test_bad_editor_value_is_one_message_and_the_plots_stay(page, name, parameter, text, message):
    """A refused value: one message naming the parameter (the words of
    cosim.analytic.parameters.validate_parameters where it applies), the plots, eigenvalues and
    parameters stay those of the last valid state; the valid value typed back clears it."""
    from cosim.analytic.parameters import validate_parameters

    s0 = _choose(page, name)
    pictures = _pictures(page)
    original = page.locator(f"#param-{parameter}").input_value()
    _type_parameter(page, parameter, text)
    s, x = _state(page), _extra(page)
    shown = page.locator("#parameter-error").inner_text()
    if message is None:  # the same check in Python: its message up to the first "="
        with pytest.raises(ValueError) as refused:
            validate_parameters({k: v for k, v in {**s0["parameters"], parameter: float(text)}.items()
                                 if k not in ("tR", "tF")}, waive=("IByy", "IHyy") if parameter != "IByy" else ())
        message = str(refused.value).split("=")[0]
    assert x["parameterError"] is not None and x["parameterError"].startswith(message), (x["parameterError"], message)
    assert x["parameterError"].startswith(f"{parameter}: ") and message in shown
    assert x["error"] is None
    assert s["parameters"] == s0["parameters"] and np.array_equal(s["eigenvalues"], s0["eigenvalues"])
    assert np.all(np.isfinite(s["eigenvalues"]))
    assert _pictures(page) == pictures  # nothing redrawn
    _type_parameter(page, parameter, original)
    assert _extra(page)["parameterError"] is None and page.locator("#parameter-error").inner_text() == ""
    assert _state(page)["parameters"] == s0["parameters"]


@pytest.mark.parametrize("name", ["benchmark", "astrom2005", "astrom2005-riderless", "rear-steered", "crowned-roller",
                                  "measured/fisher"])
def test_weave_and_capsize_speeds_shown(page, tmp_path, name):
    """The numbers shown for each choice: the linear ones equal cosim.analytic (1e-6 relative);
    rear-steered: none, self-stable nowhere (as cosim.analytic); crowned roller: the weave speed
    is where the native FMU's oscillatory mode changes sign (1e-6 either side), the capsize mode
    is stable up to 12 m/s in the native FMU as the page says. The speeds are printed with
    DIGITS decimals, and the explanations print the same numbers."""
    from cosim.analytic.whipple import self_stable_interval

    s = _choose(page, name)
    weave_text, capsize_text = page.locator("#weave").inner_text(), page.locator("#capsize").inner_text()
    if name in ("benchmark", "astrom2005", "astrom2005-riderless", "measured/fisher"):
        _check_against_analytic(s)
        stable, expected = _extra(page)["selfStable"], self_stable_interval(s["parameters"], v_max=V_MAX)
        assert stable[0] == pytest.approx(expected[0], rel=SPEED_RTOL)
        assert stable[1] == pytest.approx(expected[1], rel=SPEED_RTOL)  # inf: stable up to 10 m/s in both
        # printed: cosim.analytic's speeds to the printed digits, in the numbers and in the explanation
        analytic = _analytic_speeds(s["parameters"])
        assert [weave_text, capsize_text] == [f"{x:.{DIGITS}f} m/s" for x in analytic]
        assert [weave_text, capsize_text] == [f"{x:.{DIGITS}f} m/s" for x in (s["weave"], s["capsize"])]
        assert page.locator("#self-stable").inner_text() == \
            f"self-stable from {expected[0]:.{DIGITS}f} to {expected[1]:.{DIGITS}f} m/s"
        explanation = page.locator("#bicycle-explanation").text_content()
        assert f"{analytic[0]:.{DIGITS}f} m/s" in explanation and f"{analytic[1]:.{DIGITS}f} m/s" in explanation
        if name == "astrom2005":
            assert capsize_text == "10.368 m/s"
        if name == "astrom2005-riderless":  # the paper's Figure 8 is the bicycle with rider
            assert "Figure 8 of the paper" not in explanation
            assert "Figures 8 and 9 are the bicycle with rider" in explanation
    elif name == "rear-steered":
        assert s["weave"] is None and s["capsize"] is None and _extra(page)["selfStable"] is None
        assert self_stable_interval(s["parameters"], v_min=BACKWARD_MIN, v_max=0.0) is None
        assert weave_text == capsize_text == "not defined riding backwards"
    else:
        from cosim.bicycle.linearize import linearize_speeds

        fmu = Path(os.environ["COSIM_FMU_DIR"]) / "Bicycle_Bicycles_Whipple.fmu"
        weave = s["weave"]
        assert weave is not None and weave_text == f"{weave:.{DIGITS}f} m/s"
        assert s["capsize"] is None and capsize_text == "none in 0\u201312 m/s"
        sweep = linearize_speeds(fmu, [weave * (1 - 1e-6), weave * (1 + 1e-6), V_MAX], s["parameters"])
        ev = sweep.lateral_eigenvalues
        oscillatory = [e[np.abs(e.imag) > 1e-7 * np.maximum(1, np.abs(e))].real.max() for e in ev[:2]]
        assert oscillatory[0] > 0 > oscillatory[1], oscillatory
        real = ev[2][np.abs(ev[2].imag) <= 1e-7 * np.maximum(1, np.abs(ev[2]))]
        assert real.size and real.real.max() < 0  # capsize stable at 12 m/s
        stable = _extra(page)["selfStable"]
        assert stable[0] == pytest.approx(weave, rel=SPEED_RTOL)
        # Figure 15's bicycle, as `cosim figures fig15` (cosim.analytic.roller): the paper's 3.9 m/s
        adapted = roller.adapted_parameters()
        assert s["parameters"] == {**adapted, "tR": roller.RADII[0], "tF": 0.0}
        expected = roller.weave_speed(adapted, roller.RADII[0])
        assert weave == pytest.approx(expected, rel=SPEED_RTOL) and abs(weave - 3.9) < 0.05, (weave, expected)
        assert f"{expected:.{DIGITS}f} m/s" in page.locator("#bicycle-explanation").text_content()
    folder = Path(os.environ["COSIM_SCREENSHOTS"]) if os.environ.get("COSIM_SCREENSHOTS") else tmp_path
    folder.mkdir(parents=True, exist_ok=True)
    shot = folder / f"app-eigenvalues-{name}.png"
    page.locator("#layout").screenshot(path=str(shot))
    print(f"\n{name}: weave {weave_text}, capsize {capsize_text}; {page.locator('#self-stable').inner_text()} "
          f"(screenshot {shot})")


def test_bicycle_data_refuses_what_does_not_fit(app_site, monkeypatch):
    """bicycles.page_data names an unknown parameter, a value outside its slider and a missing
    state (a bug of bicycles.py), with the modules' descriptions (those of the exported page)."""
    import dataclasses

    from cosim.app import bicycles

    modules = bundle_data(app_site)["modules"]
    descriptions = {m: modules[m]["description"] for m in (bicycles.LINEAR, bicycles.NONLINEAR)}
    data = bicycles.page_data(descriptions[bicycles.LINEAR], descriptions)
    assert [b["name"] for b in data["bicycles"]] == ["benchmark", "astrom2005", "astrom2005-riderless",
                                                     "crowned-roller", "rear-steered", *MEASURED_LABELS]
    assert all(len(b["derivatives"]) == 4 for b in data["bicycles"])
    crowned = dataclasses.replace(bicycles.BICYCLES[3], modifiers={"tR": 0.3, "tX": 1.0})
    with pytest.raises(ValueError, match=r"bicycle crowned-roller: tX not parameters of Bicycle.Bicycles.Whipple"):
        bicycles.bicycle_data(crowned, descriptions[bicycles.NONLINEAR])
    linear = dataclasses.replace(bicycles.BICYCLES[0], modifiers={"tR": 0.3})
    with pytest.raises(ValueError, match=r"bicycle benchmark: tR not parameters of Bicycle.Bicycles.WhippleLinear"):
        bicycles.bicycle_data(linear, descriptions[bicycles.LINEAR])
    outside = dataclasses.replace(bicycles.BICYCLES[3], modifiers={"tR": 1.5})
    with pytest.raises(ValueError, match=r"bicycle crowned-roller: tR = 1.5 outside its slider \[0.0, 1.0\]"):
        bicycles.bicycle_data(outside)
    monkeypatch.setitem(bicycles.LATERAL_STATES, bicycles.NONLINEAR, ("phi", "delta", "phi_dot", "delta_dot"))
    with pytest.raises(ValueError, match=r"Bicycle.Bicycles.Whipple has no state\(s\) phi_dot, delta_dot"):
        bicycles.bicycle_data(bicycles.BICYCLES[3], descriptions[bicycles.NONLINEAR])


@pytest.mark.parametrize("width, height, beside", [(1440, 900, True), (1280, 800, True), (390, 844, False)],
                         ids=["laptop-1440x900", "laptop-1280x800", "phone-390x844"])
def test_layout_plot_on_first_screen(browser, app_site, width, height, beside):  # noqa: F811
    """At a laptop's and a phone's window size, at a pixel ratio of 2: the eigenvalue plot lies
    inside the first screen, beside the speed slider (laptop) or below it (phone); the page does
    not scroll sideways; every canvas's backing store is its CSS size times the pixel ratio (to
    1 px: three.js floors); astrom2005's printed capsize speed is cosim.analytic's, 10.368 m/s;
    nothing is logged as an error."""
    from cosim.analytic.whipple import capsize_speed

    dpr = 2
    with offline_page(browser, (app_site / "index.html").as_uri(), "window.cosimApp && window.cosimApp.ready",
                      console_errors=True, viewport={"width": width, "height": height},
                      device_scale_factor=dpr) as page:
        s = _choose(page, "astrom2005")
        geometry = page.evaluate("""() => {
            const box = (id) => { const r = document.getElementById(id).getBoundingClientRect();
                                  return {left: r.left, top: r.top, right: r.right, bottom: r.bottom}; };
            return {plot: box("plot"), speed: box("speed"), scrollWidth: document.documentElement.scrollWidth,
                    dpr: window.devicePixelRatio,
                    canvases: [...document.querySelectorAll("canvas")].map((c) =>
                      ({id: c.id, width: c.width, height: c.height, css: [c.clientWidth, c.clientHeight]}))}; }""")
        capsize_text = page.locator("#capsize").inner_text()
    plot, speed = geometry["plot"], geometry["speed"]
    assert geometry["dpr"] == dpr
    assert 0 <= plot["top"] and plot["bottom"] <= height and 0 <= plot["left"] and plot["right"] <= width, geometry
    if beside:
        assert plot["left"] >= speed["right"] and plot["top"] <= speed["bottom"], geometry
    else:
        assert plot["top"] >= speed["bottom"], geometry
    assert geometry["scrollWidth"] <= width, geometry
    assert len(geometry["canvases"]) >= 4
    for c in geometry["canvases"]:
        assert c["css"][0] > 0 and c["css"][1] > 0, c
        assert abs(c["width"] - c["css"][0] * dpr) <= 1 and abs(c["height"] - c["css"][1] * dpr) <= 1, c
    assert s["capsize"] == pytest.approx(capsize_speed(s["parameters"]), rel=SPEED_RTOL)
    assert capsize_text == f"{capsize_speed(s['parameters']):.{DIGITS}f} m/s" == "10.368 m/s"


def test_a_used_page_is_reset_to_the_loaded_one(shared_page):
    """The module's page (tests/app_page.py), after what its tests do to it and more (another
    bicycle, a typed and a refused parameter, a slider moved with the focus left on it, the speed
    clicked, continuation off, a chosen speed range, a read-out under the pointer, a refused view
    file, every <details> open, the page scrolled), is reset to what it held and showed when it had
    just loaded, without opening a new page."""
    with shared_page.reset() as page:
        _choose(page, "crowned-roller")
        _type_parameter(page, "tR", "0.6")
        page.locator("#slider-w").focus()
        page.keyboard.press("ArrowRight")
        _click_speed(page, 0.8)
        page.evaluate("window.cosimApp.continuation = false")
        page.fill("#v-min", "2")
        page.dispatch_event("#v-min", "change")
        page.locator("#plot").hover()  # at its middle: a read-out
        page.set_input_files("#view-load", files=[{"name": "broken.json", "mimeType": "application/json",
                                                   "buffer": b"{"}])
        page.wait_for_function("window.cosimApp.viewError !== null")
        _type_parameter(page, "mF", "-3")
        page.evaluate("document.querySelectorAll('details').forEach((d) => { d.open = true; }); scrollTo(0, 600)")
        used = page.evaluate("""() => { const a = window.cosimApp;
            return [a.set, a.speedRange.min, a.hover.plot !== null, a.viewError !== null, a.parameterError !== null,
                    a.continuation, window.scrollY > 0, document.activeElement.id]; }""")
        assert used == ["crowned-roller", 2, True, True, True, False, True, "param-mF"]
        changed = shared_page.state()
    assert changed != shared_page.loaded
    opened, incomplete = shared_page.opened, len(shared_page.incomplete)
    with shared_page.reset():
        assert shared_page.incomplete[incomplete:] == [] and shared_page.opened == opened
