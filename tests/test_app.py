"""`cosim app` (cosim/app): the exported page, opened from file:// in a real headless Chromium.

The page computes the eigenvalues of the linear Whipple bicycle from the WebAssembly module of
the FMU Bicycle.Bicycles.WhippleLinear (A(v) from fmi2GetDirectionalDerivative, eigenvalues by
the vendored ml-matrix); the tests move its sliders with real mouse and keyboard input and
compare what it shows with :mod:`cosim.analytic.whipple` (an implementation independent of the
Modelica, the FMU and the page): eigenvalues to 1e-6 absolute, weave and capsize speeds to 1e-6
relative. No request other than file:// may be made. The redraw time of a slider move is
measured and printed, not asserted. The browser fixture and the skip rules (a missing Chromium,
playwright or ziglang skips outside CI, fails in CI) are those of tests/test_wasm.py.
"""
from __future__ import annotations

import itertools
import os
import re
import signal
import subprocess
import sys
import tempfile
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from cosim.cli import EXIT_INTERRUPTED
from conftest import cli_in_process
from test_wasm import _has_ziglang, _unavailable, browser  # noqa: F401 (browser: the shared fixture)

EIGENVALUE_TOL = 1e-6  # absolute [1/s]: page vs cosim.analytic
SPEED_RTOL = 1e-6  # relative: weave and capsize speeds of the page vs cosim.analytic
V_MAX = 10.0  # [m/s] the page's speed range (export.SPEEDS)


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """`cosim app --export` into a temporary folder (the FMU and its module into COSIM_FMU_DIR)."""
    if not _has_ziglang():
        _unavailable("the ziglang wheel is not installed (pip install ziglang)")
    folder = tmp_path_factory.mktemp("app") / "site"
    status, out, err = cli_in_process(["app", "--export", str(folder)], folder.parent)
    assert status == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["bundle.js", "index.html"]
    return folder


@pytest.fixture()
def page(browser, site):  # noqa: F811 (the imported fixture)
    """The exported page opened from file://, ready; every request is recorded, any that is not
    file:// is refused (and fails the test), as is any error in the page."""
    context = browser.new_context(viewport={"width": 1200, "height": 800})
    page = context.new_page()
    requests, errors = [], []
    page.on("request", lambda r: requests.append(r.url))
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.route("**/*", lambda route: route.continue_() if route.request.url.startswith("file://") else route.abort())
    page.goto((site / "index.html").as_uri())
    page.wait_for_function("window.cosimApp && (window.cosimApp.ready || window.cosimApp.error !== null)",
                           timeout=60_000)
    assert page.evaluate("window.cosimApp.error") is None
    page.requests = requests
    yield page
    context.close()
    foreign = [url for url in requests if not url.startswith("file://")]
    assert not foreign, f"requests left file://: {foreign}"
    assert not errors, f"errors in the page: {errors}"


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


def test_page_loads_offline_from_two_files(page, site):
    """Exactly the two exported files are requested (no module, no font, no CDN)."""
    assert sorted(page.requests) == sorted(p.as_uri() for p in (site / "index.html", site / "bundle.js"))
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
    """The canvas is not blank: reddish and bluish pixels (oscillatory and real modes; low and
    high speeds of the locus) are there."""
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
    if message == "is not writable" and os.access(target.parent, os.W_OK):
        pytest.skip("running as a user who may write into a read-only folder (root)")
    status, out, err = cli_in_process(["app", "--export", str(target)], tmp_path)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("cosim app: error: app folder ") and "Traceback" not in err
    assert message.format(tmp=tmp_path) in err


def test_serves_the_same_site_on_localhost(site, tmp_path):
    """`cosim app --port 0` serves the exported files on 127.0.0.1 (a free port), byte for byte."""
    process = subprocess.Popen([sys.executable, "-m", "cosim", "app", "--port", "0"], cwd=tmp_path, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        line = process.stdout.readline()
        match = re.search(r"serving the app on (http://127\.0\.0\.1:\d+/)", line)
        assert match, (line, process.stderr.read() if process.poll() is not None else "")
        for name in ("index.html", "bundle.js"):
            with urllib.request.urlopen(match.group(1) + name, timeout=30) as response:
                assert response.read() == (site / name).read_bytes(), name
        process.send_signal(signal.SIGINT)  # Ctrl-C: the server stops and removes its folder
        assert process.wait(timeout=30) == EXIT_INTERRUPTED
        assert not list(Path(tempfile.gettempdir()).glob("cosim-app-*"))
    finally:
        if process.poll() is None:
            process.kill()
            process.wait(timeout=30)
        process.stdout.close()
        process.stderr.close()


@pytest.mark.parametrize("speed", [0.0, 3.0, 5.0, -2.0], ids=["0m/s", "3m/s", "5m/s", "backwards-2m/s"])
def test_directional_derivatives_are_the_analytic_state_matrix(page, speed):
    """fmu.js's directional() over wasm_directional (fmi2GetDirectionalDerivative in the module):
    the 4x4 Jacobian of the lateral state derivatives of WhippleLinear equals A(v) of
    cosim.analytic.whipple.state_matrices, entry by entry, to 1e-12 relative to max |A|."""
    from cosim.analytic.parameters import load_parameters
    from cosim.analytic.whipple import state_matrices

    params = load_parameters("astrom2005")
    out = page.evaluate("""async ({params, speed}) => {
        const D = window.COSIM_DATA;
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
