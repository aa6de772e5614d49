"""Take the screenshots of `cosim app` and `cosim animate` shown in the README and docs/app.md.

    python docs/screenshots/make.py [-o docs/screenshots] [--only NAME ...]

Exports the app into a temporary folder (as ``cosim app --export`` does) and opens it from file://
in Debian's headless Chromium through playwright (``$COSIM_CHROMIUM``, default /usr/bin/chromium),
then writes one PNG per view and per guided demo. A person looks at them before they are committed:
they are pictures for readers, not a test.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

from cosim.cli import main as cosim

CHROMIUM = Path(os.environ.get("COSIM_CHROMIUM", "/usr/bin/chromium"))
READY = "window.cosimRide && (window.cosimRide.ready || window.cosimRide.error !== null) && window.cosimApp"
DEMO_READY = "(n) => window.cosimRide.demo === n && window.cosimRide.finished || window.cosimRide.error !== null"


def _first_screen(page, width, height):
    page.set_viewport_size({"width": width, "height": height})
    page.evaluate("window.scrollTo(0, 0)")
    page.wait_for_timeout(300)
    return page.screenshot()


def _demo(name):
    def shot(page):
        page.click(f"#demo-run-{name}")
        page.wait_for_function(DEMO_READY, arg=name, timeout=120_000)
        # the 3-D view at the ride's end: the scrub bar moved there, as a reader would
        page.evaluate("""() => { const s = document.getElementById('ride-scrub');
            if (document.getElementById('ride-play').textContent === 'pause') document.getElementById('ride-play').click();
            s.value = s.max; s.dispatchEvent(new Event('input', {bubbles: true})); }""")
        page.wait_for_timeout(500)
        return _union(page, ["#ride-layout", "#demo"])
    return shot


def _union(page, selectors):
    """A screenshot of the smallest rectangle holding every element of ``selectors``."""
    boxes = [page.evaluate("""(s) => { const r = document.querySelector(s).getBoundingClientRect();
        return {x: r.x + window.scrollX, y: r.y + window.scrollY, width: r.width, height: r.height}; }""", s)
             for s in selectors]  # page coordinates, as the full-page clip takes them
    x0, y0 = min(b["x"] for b in boxes), min(b["y"] for b in boxes)
    x1, y1 = max(b["x"] + b["width"] for b in boxes), max(b["y"] + b["height"] for b in boxes)
    return page.screenshot(full_page=True, clip={"x": x0 - 4, "y": y0 - 4, "width": x1 - x0 + 8, "height": y1 - y0 + 8})


def _readout(page):
    """The Figure-9 plot with the pointer on it: the read-out names the modes at that speed."""
    page.select_option("#set", "astrom2005")
    box = page.locator("#plot").bounding_box()
    page.mouse.move(box["x"] + 0.42 * box["width"], box["y"] + 0.4 * box["height"])
    page.wait_for_timeout(300)
    return _union(page, ["#plot", "#plot-readout"])


def _side_view(name):
    def shot(page):
        page.select_option("#set", name)
        page.wait_for_timeout(300)
        return _union(page, ["#set-label", "#geometry"])
    return shot


def _chosen(name, width=1440, height=900):
    def shot(page):
        page.select_option("#set", name)
        return _first_screen(page, width, height)
    return shot


def _no_webgl(page):
    """A demo where the browser gives no WebGL: the ride drawn in 2-D, and the message why."""
    page.click("#demo-run-lane-change")
    page.wait_for_function(DEMO_READY, arg="lane-change", timeout=120_000)
    page.evaluate("""() => { const s = document.getElementById('ride-scrub');
        s.value = s.max * 0.6; s.dispatchEvent(new Event('input', {bubbles: true})); }""")
    page.wait_for_timeout(500)
    return _union(page, ["#ride-layout"])


#: Refuses every WebGL context, as a browser with WebGL switched off (before the page's scripts run).
NO_WEBGL = """(() => { const get = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
      return /webgl/i.test(kind) ? null : get.call(this, kind, ...rest); }; })();"""


def _help(page):
    page.click("#help-open")
    page.wait_for_timeout(300)
    return page.locator("#help").screenshot()


def _ride_yourself(page):
    """Ride it yourself on a phone, while riding: the 3-D view, the lane and the hold buttons."""
    page.set_viewport_size({"width": 390, "height": 844})
    page.select_option("#live-goal", "lane-change")
    page.click("#live-start")
    right = page.locator("#live-right")
    page.wait_for_function("window.cosimRide.live && window.cosimRide.live.steps > 250", timeout=60_000)
    right.dispatch_event("pointerdown")
    page.wait_for_function("window.cosimRide.live.steps > 330", timeout=60_000)
    shot = page.screenshot()
    right.dispatch_event("pointerup")
    page.click("#live-stop")
    return shot


def _diagram(page):
    page.select_option("#set", "crowned-roller")
    page.wait_for_timeout(500)
    return page.locator("#built").screenshot()


SHOTS = {
    "app-first-screen-1440x900": _chosen("astrom2005"),
    "app-first-screen-1280x800": _chosen("rear-steered", 1280, 800),
    "app-first-screen-390x844": _chosen("astrom2005", 390, 844),
    "app-crowned-roller": _chosen("crowned-roller"),
    "app-readout": _readout,
    "app-no-webgl": _no_webgl,
    "app-side-view-yellow-reversed": _side_view("measured/yellow-reversed"),
    "app-side-view-crowned-roller": _side_view("crowned-roller"),
    "app-help": _help,
    "app-ride-yourself-phone": _ride_yourself,
    "app-diagram-crowned-roller": _diagram,
}
DEMOS = ("push", "lane-change", "rocket", "rear-steered", "crowned-rollers", "rider-delay")
SHOTS.update({f"app-demo-{name}": _demo(name) for name in DEMOS})


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=Path(__file__).resolve().parent)
    parser.add_argument("--only", nargs="*", default=None, help="names of the shots to take (default: all)")
    args = parser.parse_args(argv)
    from playwright.sync_api import sync_playwright

    names = args.only or list(SHOTS)
    args.output.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        site = Path(tmp) / "site"
        if cosim(["app", "--export", str(site), "-q"]) != 0:
            return 1
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                                        args=["--no-sandbox", "--disable-crash-reporter"],
                                        env={**os.environ, "XDG_CONFIG_HOME": tmp})
            for name in names:
                context = browser.new_context(viewport={"width": 1440, "height": 900}, device_scale_factor=1,
                                              has_touch=True)
                if name == "app-no-webgl":
                    context.add_init_script(NO_WEBGL)
                page = context.new_page()
                page.goto((site / "index.html").as_uri())
                page.wait_for_function(READY, timeout=60_000)
                png = SHOTS[name](page)
                (args.output / f"{name}.png").write_bytes(png)
                print(f"wrote {args.output / name}.png", flush=True)
                context.close()
            browser.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
