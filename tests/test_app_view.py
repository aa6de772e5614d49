"""The eigenvalue view of `cosim app` beyond its numbers: the side view of the bicycle
(static/sideview.js), the modes named on the plots and the read-outs under the pointer
(static/modes.js), the chosen speed and Re ranges, saving, loading and sharing a view
(static/viewstate.js), in a real headless Chromium on the exported site from file://.

One page serves the whole module (each test chooses its bicycle first, which resets its
parameters and ranges). The drawings are compared by their pixels (the canvas's PNG data URL);
the read-outs are compared with cosim.analytic to their printed digits, the modes named by the
rules the plot's caption states, written again here. No request other than file:// may be made,
and an error in the page or one it logs fails the module.
"""
from __future__ import annotations

import json
from urllib.parse import parse_qsl

import numpy as np
import pytest

from test_wasm import browser, offline_page  # noqa: F401 (browser: the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site
pytestmark = pytest.mark.slow

READY = "window.cosimApp && (window.cosimApp.ready || window.cosimApp.error !== null)"
IMAG_TOL = 1e-7  # relative: |Im| below it is real (as the page and cosim.analytic.whipple)
DIGITS = 3  # decimals of the read-outs [1/s] (modes.js)


@pytest.fixture(scope="module")
def page(browser, app_site):  # noqa: F811 (the imported fixture)
    with offline_page(browser, (app_site / "index.html").as_uri(), READY, console_errors=True,
                      viewport={"width": 1280, "height": 900}, accept_downloads=True, has_touch=True) as page:
        assert page.evaluate("window.cosimApp.error") is None
        page.base = (app_site / "index.html").as_uri()
        yield page


def _choose(page, name: str) -> None:
    """A real change of the bicycle select: the bicycle's own parameters and ranges."""
    page.select_option("#set", name)
    assert page.evaluate("[window.cosimApp.set, window.cosimApp.error]") == [name, None]


def _picture(page, canvas: str) -> str:
    return page.evaluate("(id) => document.getElementById(id).toDataURL()", canvas)


def _set_parameter(page, name: str, value: float) -> None:
    """The parameter editor's field set to ``value`` (an input event)."""
    page.evaluate("document.querySelector('#all-parameters details').open = true")
    page.fill(f"#param-{name}", repr(value))
    assert page.evaluate("(n) => [window.cosimApp.parameterError, window.cosimApp.parameters[n]]", name) == [None, value]


# --- the side view -------------------------------------------------------------------------

SIDE_VIEW = [
    # bicycle, parameter, new value, whether the drawing changes, the words of its aria-label then
    pytest.param("benchmark", "w", 1.25, True, "wheelbase w = 1.250 m", id="wheelbase"),
    pytest.param("benchmark", "c", 0.15, True, "trail c = 0.150 m", id="trail"),
    pytest.param("astrom2005", "lam", 0.5, True, "tilt \u03bb = 28.6\u00b0", id="head-angle-lam"),
    pytest.param("benchmark", "rR", 0.4, True, "rear wheel radius r_R = 0.400 m", id="rear-wheel-radius"),
    pytest.param("astrom2005-riderless", "rF", 0.3, True, "front wheel radius r_F = 0.300 m",
                 id="front-wheel-radius"),
    pytest.param("crowned-roller", "tR", 0.6, True, "rear crown radius t_R = 0.600 m", id="crown-radius"),
    pytest.param("benchmark", "IBxx", 12.5, False, "wheelbase w = 1.020 m", id="inertia-IBxx-not-drawn"),
]


@pytest.mark.parametrize("name, parameter, value, changes, words", SIDE_VIEW)
def test_side_view_follows_the_geometry(page, name, parameter, value, changes, words):
    """The side view is redrawn from the parameters: its pixels change with the wheelbase, trail,
    head angle, wheel and crown radii, not with a moment of inertia (which it does not show); its
    aria-label states the dimensions; the eigenvalues are those of the new parameters."""
    _choose(page, name)
    before, eigenvalues = _picture(page, "geometry"), page.evaluate("window.cosimApp.eigenvalues")
    _set_parameter(page, parameter, value)
    after = _picture(page, "geometry")
    assert (after != before) is changes
    assert words in page.get_attribute("#geometry", "aria-label")
    assert page.evaluate("window.cosimApp.eigenvalues") != eigenvalues  # the plots did follow


# --- mode names and read-outs --------------------------------------------------------------

def _modes(ev: np.ndarray, v: float) -> list:
    """The modes of four eigenvalues at speed v, by the rules of the plot's caption."""
    osc = np.abs(ev.imag) > IMAG_TOL * np.maximum(1, np.abs(ev))
    names = [None] * len(ev)
    if v < 0 or len(ev) != 4:
        return names
    real = sorted(np.flatnonzero(~osc), key=lambda i: ev[i].real)
    pairs = sorted(np.flatnonzero(osc), key=lambda i: ev[i].real)
    if len(pairs) == 2:
        names[real[0]], names[real[1]] = "castering", "capsize"
        for i in pairs:
            names[i] = "weave"
    elif len(real) == 4:
        names[real[0]], names[real[1]] = "castering", "capsize"
        names[real[2]] = names[real[3]] = "weave"
    else:
        for i in pairs[:2]:
            names[i] = "capsize + castering"
        for i in pairs[2:]:
            names[i] = "weave"
    return names


def _value(e: complex) -> str:
    fixed = lambda x: f"{0.0 if abs(x) < 0.5e-3 else x:.{DIGITS}f}"  # noqa: E731
    return f"{fixed(e.real)} \u00b1 {fixed(abs(e.imag))}i" if abs(e.imag) > IMAG_TOL * max(1, abs(e)) else fixed(e.real)


def _readout(ev: np.ndarray, v: float) -> str:
    """What the plot's read-out prints at v for the eigenvalues ev (cosim.analytic's)."""
    order = np.argsort(ev.real, kind="stable")
    ev, names = ev[order], _modes(ev[order], v)
    groups: dict = {}
    for e, n in zip(ev, names):
        if abs(e.imag) > IMAG_TOL * max(1, abs(e)) and e.imag < 0:
            continue
        groups.setdefault(n or "eigenvalues", []).append(_value(e))
    parts = []
    for key in ("weave", "capsize", "castering", "capsize + castering", "eigenvalues"):
        if key in groups:
            values = groups[key]
            parts.append(f"weave (still real) {' and '.join(values)}" if key == "weave" and len(values) == 2
                         else f"{key} {', '.join(values)}")
    return f"v = {v:.2f} m/s: {'; '.join(parts)} (1/s)"


def _axes(page, which: str) -> dict:
    return page.evaluate("""(w) => { const a = window.cosimApp.axes[w];
        return Object.fromEntries(Object.entries(a).filter(([, x]) => typeof x === "number")); }""", which)


HOVERS = [
    # bicycle, plot, where (plot: fraction of the speed axis; locus: the sweep point k, eigenvalue i)
    pytest.param("benchmark", "plot", 0.55, id="plot-benchmark-6.6m/s"),
    pytest.param("astrom2005", "tap", 0.7, id="plot-astrom2005-8.4m/s-tapped"),
    pytest.param("astrom2005", "plot", 0.05, id="plot-astrom2005-0.6m/s-four-real"),
    pytest.param("astrom2005-riderless", "plot", 0.04, id="plot-riderless-0.5m/s-two-pairs"),
    pytest.param("rear-steered", "plot", 0.3, id="plot-rear-steered-not-named"),
    pytest.param("benchmark", "locus", (150, 3), id="locus-benchmark-weave"),
]


@pytest.mark.parametrize("name, which, where", HOVERS)
def test_hover_reads_out_the_named_eigenvalues(page, name, which, where):
    """A mouse move over the plot (or a tap) prints v and the eigenvalues there with their mode names,
    equal to cosim.analytic's to the printed digits; over the root locus, the nearest eigenvalue
    of the sweep with its speed and mode. The plot names weave, capsize and castering (forwards)."""
    from cosim.analytic.whipple import eigenvalues

    _choose(page, name)
    parameters = page.evaluate("window.cosimApp.parameters")
    tapped, which = which == "tap", "plot" if which == "tap" else which
    page.evaluate("(id) => document.getElementById(id).scrollIntoView()", which)
    box = page.locator(f"#{which}").bounding_box()
    a = _axes(page, which)
    if which == "plot":
        x = a["left"] + where * (a["W"] - a["left"] - a["right"])
        at = (box["x"] + 1 + x, box["y"] + 1 + a["top"] + 20)  # 1: the canvas's border
        page.touchscreen.tap(*at) if tapped else page.mouse.move(*at)
        hover = page.evaluate("window.cosimApp.hover.plot")
        v = hover["v"]
        assert v == round(v, 2) and abs(v - (a["min"] + where * (a["max"] - a["min"]))) < 0.02
        text = page.locator("#plot-readout").inner_text()
        assert text == hover["text"] == _readout(eigenvalues(parameters, v), v)
        if v >= 0:
            assert "weave" in text and "castering" in text and "capsize" in text
    else:
        k, i = where
        s = page.evaluate("(k) => ({v: window.cosimApp.sweep.speeds[k], ev: window.cosimApp.sweep.evs[k]})", k)
        re, im = s["ev"][i]
        X = a["left"] + (re - a["xMin"]) / (a["xMax"] - a["xMin"]) * (a["W"] - a["left"] - a["right"])
        Y = a["top"] + (a["yMax"] - im) / (a["yMax"] - a["yMin"]) * (a["H"] - a["top"] - a["bottom"])
        page.mouse.move(box["x"] + 1 + X, box["y"] + 1 + Y)
        hover = page.evaluate("window.cosimApp.hover.locus")
        ev = eigenvalues(parameters, hover["v"])
        nearest = ev[np.argmin(np.abs(ev - complex(hover["re"], hover["im"])))]
        assert abs(nearest - complex(hover["re"], hover["im"])) < 1e-6
        # the nearest point of the sweep: within a marker's size of the pointer
        hx = a["left"] + (hover["re"] - a["xMin"]) / (a["xMax"] - a["xMin"]) * (a["W"] - a["left"] - a["right"])
        hy = a["top"] + (a["yMax"] - hover["im"]) / (a["yMax"] - a["yMin"]) * (a["H"] - a["top"] - a["bottom"])
        assert np.hypot(hx - X, hy - Y) <= 3.0
        order = np.argsort(ev.real, kind="stable")
        mode = _modes(ev[order], hover["v"])[int(np.argmin(np.abs(ev[order] - nearest)))]
        assert page.locator("#locus-readout").inner_text() == \
            f"\u03bb = {_value(nearest)} 1/s at v = {hover['v']:.2f} m/s: {mode}"


def test_keyboard_reads_out_the_plot(page):
    """The plot takes the keyboard focus: End, Shift+ArrowLeft (1 m/s) and ArrowLeft (0.1 m/s) move
    the read-out's speed, whose text equals cosim.analytic's eigenvalues there, named."""
    from cosim.analytic.whipple import eigenvalues

    _choose(page, "benchmark")
    parameters, top = page.evaluate("window.cosimApp.parameters"), _axes(page, "plot")["max"]
    page.focus("#plot")
    for key, v in (("End", top), ("Shift+ArrowLeft", top - 1), ("ArrowLeft", round(top - 1.1, 2))):
        page.keyboard.press(key)
        hover = page.evaluate("window.cosimApp.hover.plot")
        assert hover["v"] == pytest.approx(v, abs=1e-9), key
        assert page.locator("#plot-readout").inner_text() == hover["text"] == _readout(eigenvalues(parameters, v), v)


# --- ranges --------------------------------------------------------------------------------

RANGES = [
    # bicycle, field values (v from, v to, Re from, Re to), the message beside the fields or None
    pytest.param("benchmark", ("2", "8", "", ""), None, id="speed-2-8"),
    pytest.param("astrom2005", ("-3", "12", "-6", "6"), None, id="backwards-and-forwards-re-minus6-6"),
    pytest.param("benchmark", ("8", "2", "", ""), "speed range from 8 must be less than to 2", id="min-above-max"),
    pytest.param("benchmark", ("0", "fast", "", ""), "speed range to: not a number: 'fast'", id="not-a-number"),
]


def _set_ranges(page, fields) -> None:
    """The four range fields given their texts, then a change event of each range (as a user
    who typed both ends of a range and left the field: no half-typed range on the way)."""
    for field, text in zip(("v-min", "v-max", "re-min", "re-max"), fields):
        page.eval_on_selector(f"#{field}", "(e, text) => { e.value = text; }", text)
    for field in ("v-max", "re-max"):
        page.dispatch_event(f"#{field}", "change")


@pytest.mark.parametrize("name, fields, message", RANGES)
def test_chosen_ranges_redraw_or_say_what_is_wrong(page, name, fields, message):
    """Typed ranges redraw the plots over them (the speed range: a new sweep, the speed slider's
    ends, weave and capsize searched in it); a bad one is a plain message beside its field and
    nothing changes (no console error: the module's page fails on one)."""
    from cosim.analytic.whipple import weave_speed

    _choose(page, name)
    pictures = [_picture(page, c) for c in ("plot", "locus")]
    _set_ranges(page, fields)
    s = page.evaluate("""() => { const a = window.cosimApp; return {range: a.speedRange, re: a.reRange,
        first: a.sweep.speeds[0], last: a.sweep.speeds.at(-1), weave: a.weave, error: a.rangeError.v || a.rangeError.re,
        plot: a.axes.plot, slider: [document.getElementById("speed").min, document.getElementById("speed").max]}; }""")
    shown = page.locator("#v-range-error").inner_text() + page.locator("#re-range-error").inner_text()
    if message is not None:
        assert s["error"] == message and message in shown
        assert [_picture(page, c) for c in ("plot", "locus")] == pictures
        return
    assert shown == "" and s["error"] is None
    v_min, v_max = float(fields[0]), float(fields[1])
    assert (s["range"]["min"], s["range"]["max"], s["first"], s["last"]) == (v_min, v_max, v_min, v_max)
    assert [float(x) for x in s["slider"]] == [v_min, v_max]
    if fields[2]:
        assert s["re"] == {"min": float(fields[2]), "max": float(fields[3])}
        assert (s["plot"]["yMin"], s["plot"]["yMax"]) == (float(fields[2]), float(fields[3]))
    weave = weave_speed(page.evaluate("window.cosimApp.parameters"))  # searched from max(0, v_min) on
    assert s["weave"] == pytest.approx(weave, rel=1e-6) if v_min <= weave <= v_max else s["weave"] is None
    assert page.locator("#weave").inner_text() == (f"{weave:.3f} m/s" if v_min <= weave <= v_max
                                                   else f"none in {max(0, v_min):g}\u2013{v_max:g} m/s")
    assert [_picture(page, c) for c in ("plot", "locus")] != pictures


# --- save, load, share ---------------------------------------------------------------------

def _view(page) -> dict:
    """What the view shows: the eigenvalue table's text, the sliders, speed and range fields."""
    return page.evaluate("""() => ({
        table: document.querySelector("#eigenvalues tbody").innerText,
        inputs: Object.fromEntries([...document.querySelectorAll("#controls input:not([type=file])")]
                                   .filter((e) => !(e.closest("label") && e.closest("label").style.display === "none"))
                                   .map((e) => [e.id, e.value])),  // not the sliders the bicycle hides
        set: document.getElementById("set").value, eigenvalues: window.cosimApp.eigenvalues,
        parameters: window.cosimApp.parameters})""")


def _open(page, url: str) -> None:
    page.goto(url)
    page.wait_for_function(READY)
    assert page.evaluate("window.cosimApp.error") is None


def test_saved_file_and_shared_address_restore_the_view(page, tmp_path):
    """The page's address holds a changed view, and opening it in a new document restores the same
    eigenvalue table, sliders and fields; the view saved (the download) before the page was
    opened anew loads back to the same, after another bicycle was chosen."""
    from cosim.analytic.parameters import load_parameters

    _choose(page, "astrom2005")
    _set_parameter(page, "mB", 70.5)
    _set_parameter(page, "c", 0.0625)
    _set_ranges(page, ("1", "9.5", "-8", "4"))
    page.fill("#speed", "7.31")
    page.dispatch_event("#speed", "input")
    view = _view(page)
    assert view["inputs"]["speed"] == "7.31" and view["inputs"]["slider-mB"] == "70.5"
    with page.expect_download() as info:
        page.click("#view-save")
    assert info.value.suggested_filename == "cosim-bicycle-astrom2005.json"
    saved = tmp_path / "view.json"
    info.value.save_as(str(saved))
    data = json.loads(saved.read_text())
    assert data["format"] == "cosim-app-bicycle" and data["version"] == 1 and data["bicycle"] == "astrom2005"
    assert data["parameters"] == {**load_parameters("astrom2005"), "mB": 70.5, "c": 0.0625}
    assert (data["speed"], data["speedRange"], data["reRange"]) == (7.31, {"min": 1, "max": 9.5}, {"min": -8, "max": 4})
    page.wait_for_function("location.hash === '#' + window.cosimApp.address")  # written at most every 250 ms
    address = page.url
    shared = dict(parse_qsl(address.split("#", 1)[1]))
    assert shared == {"bicycle": "astrom2005", "v": "7.31", "vmin": "1", "vmax": "9.5", "re": "-8,4",
                      "mB": "70.5", "c": "0.0625"}  # the changed parameters only
    _open(page, page.base + "?shared#" + address.split("#", 1)[1])  # another query: a new document
    assert _view(page) == view
    _choose(page, "benchmark")  # the page opened anew, then another bicycle: the file's view comes from the file
    assert _view(page)["set"] == "benchmark"
    page.set_input_files("#view-load", str(saved))
    page.wait_for_function("window.cosimApp.set === 'astrom2005'")
    assert _view(page) == view and page.evaluate("window.cosimApp.viewError") is None
    page.wait_for_function("location.hash === '#' + window.cosimApp.address")
    assert page.url.split("#", 1)[1] == address.split("#", 1)[1]


BROKEN = [
    # what is changed in a good file (key: value; None deletes), the start of the message
    pytest.param({"version": 2}, "version: 2 is not one this page reads (1)", id="version"),
    pytest.param({"bicycle": "penny-farthing"}, "bicycle: no bicycle 'penny-farthing' on this page", id="bicycle"),
    pytest.param({"parameters": {"mB": "heavy"}}, "parameters.mB: not a finite number (got \"heavy\")",
                 id="parameter-not-a-number"),
    pytest.param({"parameters": {"mF": -3.0}}, "parameters.mF: mass must be non-negative", id="negative-mass"),
    pytest.param({"parameters": {"mX": 1.0}}, "parameters.mX: not a parameter of benchmark", id="unknown-parameter"),
    pytest.param("{not json", "not a JSON file", id="not-json"),
    # a hand-written file: only the bicycle and what it changes (the rest the bicycle's own)
    pytest.param({"speed": None, "speedRange": None, "reRange": None}, None, id="partial-file-loads"),
]


@pytest.mark.parametrize("change, message", BROKEN)
def test_broken_parameter_file_is_one_message_naming_the_field(page, change, message):
    """A broken file: one plain message naming the file and the bad field; the view (whatever the
    tests before left) stays. A file with only the bicycle and a parameter loads."""
    from cosim.analytic.parameters import load_parameters

    page.evaluate("window.cosimApp.viewError = 'waiting'")  # the message of this file is waited for
    before = _view(page)
    if isinstance(change, str):
        text = change
    else:
        good = {"format": "cosim-app-bicycle", "version": 1, "bicycle": "benchmark", "parameters": {"mB": 80.0},
                "speed": 4.0, "speedRange": {"min": 0, "max": 12}, "reRange": None}
        text = json.dumps({k: v for k, v in {**good, **change}.items() if change.get(k, "") is not None})
    page.set_input_files("#view-load", files=[{"name": "broken.json", "mimeType": "application/json",
                                               "buffer": text.encode()}])
    page.wait_for_function("window.cosimApp.viewError !== 'waiting'")
    shown = page.locator("#view-error").inner_text()
    if message is None:
        assert shown == "" and page.evaluate("window.cosimApp.viewError") is None
        s = page.evaluate("[window.cosimApp.set, window.cosimApp.parameters, window.cosimApp.speed]")
        assert s == ["benchmark", {**load_parameters("benchmark"), "mB": 80.0}, 5.0]  # the bicycle's speed
        return
    assert shown.startswith(f"broken.json was not loaded: {message}"), shown
    assert _view(page) == before
