"""`cosim app` for everyone: accessibility (axe-core), names of the controls, the help, the ride
without WebGL, and a page that logs no console error; in a real headless Chromium, from `cosim
app --export` opened from file://. (The plain words of the demos' results are checked where every
demo runs, tests/test_app_ride.py.)

axe-core is vendored for these tests only (tests/data/axe-core, its version and source in the
README there), injected into the page after it loaded; the page's bundle does not carry it. One
page serves the module (opened once: the tests run in their order and leave the page usable),
plus one page without WebGL (getContext refuses every WebGL context, as in a browser where it is
switched off). Nothing is timed.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from test_wasm import browser, offline_page  # noqa: F401 (browser: the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site
pytestmark = pytest.mark.slow

AXE = Path(__file__).parent / "data" / "axe-core" / "axe.min.js"
BLOCKING = ("critical", "serious")  # axe impacts that fail a test; "moderate" and "minor" are printed
READY = "window.cosimApp && window.cosimApp.ready && window.cosimRide && window.cosimRide.ready"


@pytest.fixture(scope="module")
def page(browser, app_site):  # noqa: F811 (the imported fixture)
    """The exported page from file://, both halves ready; a request that is not file://, an error
    in the page or a message it logs as an error fails the module (offline_page); what it logs as
    an error is also kept in ``page.logged`` for the test that asserts on it. Reduced motion: a
    finished ride waits for "play" (SwiftShader's frames cost CPU)."""
    with offline_page(browser, (app_site / "index.html").as_uri(), READY, console_errors=True,
                      viewport={"width": 1280, "height": 900}, reduced_motion="reduce") as page:
        page.logged = []
        page.on("console", lambda m: page.logged.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: page.logged.append(str(e)))
        page.add_script_tag(content=AXE.read_text(encoding="utf-8"))
        yield page


def _axe(page) -> list[dict]:
    """axe-core's violations of the whole page: [{id, impact, help, targets}]."""
    return page.evaluate("""async () => {
        const r = await axe.run(document, {resultTypes: ["violations"]});
        return r.violations.map((v) => ({id: v.id, impact: v.impact, help: v.help,
                                         targets: v.nodes.slice(0, 5).map((n) => n.target.join(" "))})); }""")


def _run_demo(page, name: str):
    page.click(f"#demo-run-{name}")
    page.wait_for_function("(n) => window.cosimRide.demo === n && window.cosimRide.finished || "
                           "window.cosimRide.error !== null", arg=name, timeout=60_000)
    assert page.evaluate("window.cosimRide.error") is None


def _short_ride(page, steps: int = 20):
    """A ride of your own started and stopped after ``steps`` steps (0.01 s each, real time)."""
    page.uncheck("#live-push")
    page.click("#live-start")
    page.wait_for_function("(n) => window.cosimRide.live && window.cosimRide.live.steps > n", arg=steps)
    page.click("#live-stop")
    assert page.evaluate("window.cosimRide.live.active") is False


def _check(page, when: str):
    violations = _axe(page)
    print(f"\n{when}: " + ("; ".join(f"{v['impact']} {v['id']} ({len(v['targets'])})" for v in violations)
                           or "no violation"))
    blocking = [v for v in violations if v["impact"] in BLOCKING]
    assert not blocking, blocking


def test_axe_finds_no_critical_or_serious_violation_on_the_first_view(page):
    _check(page, "first view")


def test_no_console_error_on_the_way_through_the_page(page):
    """Every bicycle chosen, a demo run (its first frame drawn in 3-D), a ride of your own started
    and stopped: the page logs no error (the SwiftShader driver's performance warnings are
    warnings). The tests of tests/test_app_ride.py, every demo played, hold their pages to the same."""
    for name in page.evaluate("[...document.getElementById('set').options].map((o) => o.value)"):
        page.select_option("#set", name)
        assert page.evaluate("window.cosimApp.error") is None, name
    _run_demo(page, "lane-change")
    _short_ride(page)
    assert page.locator("#live-verdict").inner_text().startswith("You stopped at")
    assert page.logged == []


# what the page shows when axe looks again: the ride section used (a demo's result, then a ride of
# your own: the state the test above leaves), or the help dialog open
def _ride_section_used(page):
    if page.evaluate("window.cosimRide.live") is None:  # this test alone: the page as it would be
        _run_demo(page, "lane-change")
        _short_ride(page)


LATER = {"ride-section-used": _ride_section_used, "help-open": lambda page: page.click("#help-open")}


@pytest.mark.parametrize("setup", list(LATER), ids=list(LATER))
def test_axe_finds_no_critical_or_serious_violation_later(page, setup):
    LATER[setup](page)
    if setup == "help-open":
        assert page.locator("#help").is_visible() and page.locator("#help-title").is_visible()
    _check(page, setup)
    if setup == "help-open":
        page.keyboard.press("Escape")  # a modal dialog closes with Escape
        assert not page.locator("#help").is_visible()


def test_every_control_has_an_accessible_name(page):
    """Every input, select and button (those made by the scripts too) has a name that a screen
    reader announces: axe-core's accessible-name computation (the W3C accname rules), not ours.
    The demos' buttons are told apart by their names."""
    names = page.evaluate("""() => {
        axe.setup(document);
        try {
          return [...document.querySelectorAll("input, select, button, textarea")].map((e) => ({
            id: e.id, tag: e.tagName.toLowerCase(), type: e.type,
            name: axe.commons.text.accessibleTextVirtual(axe.utils.getNodeFromTree(e), {includeHidden: true}).trim()}));
        } finally { axe.teardown(); } }""")
    assert len(names) > 40  # the sliders, the editor, the demos, the player, the rider's controls
    nameless = [n for n in names if not n["name"]]
    assert not nameless, nameless
    demo_buttons = [n["name"] for n in names if n["id"].startswith("demo-run-")]
    assert len(demo_buttons) == len(set(demo_buttons)) >= 6, demo_buttons
    touch = {n["id"]: n["name"] for n in names if n["id"] in ("live-left", "live-right")}
    assert "left" in touch["live-left"] and "right" in touch["live-right"], touch


def test_weave_and_capsize_are_explained_beside_their_speeds_and_in_the_help(page):
    about = page.locator("#speeds-about")
    assert about.is_visible()
    text = about.inner_text()
    assert "Weave" in text and "Capsize" in text and "sways" in text and "falls" in text
    help_text = page.locator("#help").text_content()
    for topic in ("Weave and capsize", "Figure 9", "root locus", "ride plots", "counter-steering"):
        assert topic in help_text, topic


@pytest.fixture(scope="module")
def page_without_webgl(browser, app_site):  # noqa: F811 (the imported fixture)
    """The exported page in a browser whose canvases give no WebGL context (as with WebGL
    switched off); any message logged as an error fails the test."""
    refuse = """(() => { const get = HTMLCanvasElement.prototype.getContext;
        HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
          return /webgl/i.test(kind) ? null : get.call(this, kind, ...rest); }; })();"""
    # the refusal must be in place before the page's scripts run: an init script of the context,
    # which is added to a blank page's context first and then navigated to the app
    with offline_page(browser, "about:blank", "true", allowed="", console_errors=True,
                      viewport={"width": 1000, "height": 900}, reduced_motion="reduce") as page:
        page.context.add_init_script(refuse)
        page.goto((app_site / "index.html").as_uri())
        page.wait_for_function(READY, timeout=60_000)
        yield page
    assert all(u == "about:blank" or u.startswith("file://") for u in page.requests), page.requests


def _drawn_colours(page, canvas: str) -> int:
    """Distinct colours (to 1/32) on a 2-D canvas: a drawing has many, a blank canvas one."""
    return page.evaluate("""(id) => { const c = document.getElementById(id);
        const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data, seen = new Set();
        for (let i = 0; i < d.length; i += 4 * 7) seen.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | d[i + 2] >> 3);
        return seen.size; }""", canvas)


def test_without_webgl_the_ride_is_drawn_in_2d_with_a_plain_message(page_without_webgl):
    """A ride of your own and a demo: drawn in 2-D (a top view and a rear view) on the ride's
    canvas, the message says why in plain words, the ride of your own stops (not left "active")
    and the page logs no error (the fixture)."""
    page = page_without_webgl
    assert not page.locator("#ride-no-webgl").is_visible()  # nothing said before there is a ride
    page.select_option("#live-goal", "lane-change")
    page.uncheck("#live-push")
    page.click("#live-start")
    page.wait_for_function("window.cosimRide.live && window.cosimRide.live.steps > 30 && window.cosimRide.frames > 5")
    page.click("#live-stop")
    assert page.evaluate("[window.cosimRide.view2d, window.cosimRide.live.active]") == [True, False]
    message = page.locator("#ride-no-webgl")
    assert message.is_visible() and "WebGL" in message.inner_text() and "from above" in message.inner_text()
    assert _drawn_colours(page, "ride-canvas") > 20
    assert page.locator("#live-verdict").inner_text() != ""
    _run_demo(page, "lane-change")
    frames = page.evaluate("window.cosimRide.frames")
    page.click("#ride-play")
    page.wait_for_function("(n) => window.cosimRide.frames > n + 3", arg=frames)
    page.click("#ride-play")
    assert _drawn_colours(page, "ride-canvas") > 20


def _lane(x: np.ndarray, speed: float, lane: dict) -> np.ndarray:
    """The lane's centre of ride.js (a cosine blend from lane.from to lane.to seconds of riding)."""
    a, b = lane["from"] * speed, lane["to"] * speed
    u = np.clip((x - a) / (b - a), 0.0, 1.0)
    return lane["shift"] * (1 - np.cos(np.pi * u)) / 2


VERDICTS = [
    # goal, the ride (fell, its end [s], how far off the lane [m], a counter-steering dip [m]), the words
    pytest.param("stay-up", False, 20.0, 0.0, 0.0, "Goal reached: you kept the bicycle up for 20 s", id="stay-up-reached"),
    pytest.param("stay-up", True, 6.5, 0.0, 0.0, "Goal not reached: the bicycle fell after 6.5 s, before 20 s",
                 id="stay-up-fell"),
    pytest.param("lane-change", False, 10.0, 0.2, 0.05, "Goal reached: you followed the lane; your path was at most "
                 "0.20 m from the lane's centre", id="lane-followed-counter-steering"),
    pytest.param("lane-change", False, 10.0, 0.8, 0.0, "Goal not reached: your path was at most 0.80 m from the "
                 "lane's centre", id="lane-missed"),
    pytest.param("free", False, 3.0, 0.0, 0.0, "You stopped at 3 s; the largest lean was", id="free-stopped"),
]


@pytest.mark.parametrize("goal, fell, end, off, dip, words", VERDICTS)
def test_goal_verdicts_in_words(page, goal, fell, end, off, dip, words):
    """The words at the end of a ride of your own, for rides made here (a goal reached takes 20 s
    of riding in real time): reached or not, how far off the lane, counter-steering named when the
    path first went the other way."""
    speed, lane = 5.0, page.evaluate("window.cosimRide.lane")
    t = np.round(np.arange(0.0, end + 1e-9, 0.01), 2)
    x = speed * t
    y = _lane(x, speed, lane) + off * np.sin(np.pi * t / end) ** 2  # off the lane the most half-way
    if dip:  # first a little the other way, as a rider who counter-steers
        y = y - dip * np.exp(-((t - lane["from"] - 0.15) / 0.1) ** 2)
    phi = 0.1 * np.sin(t)
    text = page.evaluate("([live, tr]) => window.cosimRide.verdictOf(live, tr)",
                         [{"goal": goal, "speed": speed},
                          {"t": t.tolist(), "x": x.tolist(), "y": y.tolist(), "phi": phi.tolist(), "fell": fell}])
    assert text.startswith(words), text
    assert ("counter-steering" in text) == bool(dip), text


def test_rear_steered_starts_slow_and_in_slow_motion(page):
    """Chosen for a ride of your own, the rear-steered bicycle gets 2 m/s and slow motion 0.25x
    (the page says so); the front-steered one real time."""
    page.select_option("#live-bicycle", "rear-steered")
    assert page.locator("#live-speed").input_value() == "2" and page.locator("#live-pace").input_value() == "0.25"
    assert page.locator("#live-speed-value").inner_text() == "2 m/s"
    assert "2 m/s in slow motion" in page.locator("#live").inner_text()
    page.select_option("#live-bicycle", "benchmark")
    assert page.locator("#live-pace").input_value() == "1"


def test_on_a_phone_the_buttons_stay_under_the_ride_while_riding(page):
    """At 390x844 a ride of your own scrolls the 3-D view onto the screen and keeps the hold
    buttons at the bottom of it (they are a screen below the view in the page's flow); after the
    ride they are back in their place."""
    page.set_viewport_size({"width": 390, "height": 844})
    try:
        page.uncheck("#live-push")
        page.click("#live-start")
        page.wait_for_function("window.cosimRide.live && window.cosimRide.live.steps > 5")
        pad, view = page.locator("#live-pad").bounding_box(), page.locator("#ride-canvas").bounding_box()
        assert pad["y"] + pad["height"] <= 844 + 0.5 and pad["y"] > 844 / 2, pad  # at the bottom, on screen
        assert view["y"] < pad["y"] and view["y"] + view["height"] > 0, (view, pad)  # the view above it, seen
        assert pad["width"] >= 380 and page.locator("#live-right").bounding_box()["height"] >= 44  # thumb-sized
        page.locator("#live-right").dispatch_event("pointerdown")
        page.wait_for_function("window.cosimRide.live.steps > 30")
        page.locator("#live-right").dispatch_event("pointerup")
        page.click("#live-stop")
        assert page.evaluate("getComputedStyle(document.getElementById('live-pad')).position") == "static"
    finally:
        page.set_viewport_size({"width": 1280, "height": 900})
