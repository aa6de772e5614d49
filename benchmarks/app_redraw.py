"""The app's redraw for the crowned-roller bicycle (the nonlinear ``Bicycle.Bicycles.Whipple``
compiled to WebAssembly, ~290 linearizations per redraw: 200 speeds and the bisections of the
weave and capsize speeds), with the continuation of ``static/app.js`` (the module stays in
initialization mode while only the speed changes; its initial pitch is solved from the previous
solution) against the path without it (``cosimApp.continuation = false``: a new initialization at
every speed), and against the app of the committed tree ``--baseline REF`` (default ``ae32022``,
before the continuation: its page and modules, exported from ``git archive REF``), side by side in one headless Chromium.

DRAGS drags of the rear crown radius slider t_R with the mouse per path, the paths alternating;
per drag the redraw of its last input event (``cosimApp.lastRedrawMs``: from the event's handler
to the canvases drawn, the browser's paint not included). Printed: the medians, their ratios,
"meets"/"MISSES" for the goal (median <= GOAL_MS with continuation), the machine's load (it may be
shared), and that the paths give the same numbers: the sweep's eigenvalues, the weave and capsize
speeds and the page's texts, at one parameter set. Nothing is asserted.

Usage: ``python benchmarks/app_redraw.py [--site DIR] [--baseline REF]`` (default: ``cosim app
--export`` into a temporary folder, its FMUs in COSIM_FMU_DIR or ./fmus; the baseline's FMUs and
modules are built in a temporary folder; needs playwright, Chromium at /usr/bin/chromium or
COSIM_CHROMIUM, and the ziglang wheel to export).
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from side_by_side import baseline_tree

DRAGS = 20  # per path
GOAL_MS = 20.0  # [ms] the median redraw with continuation
CHROMIUM = Path(os.environ.get("COSIM_CHROMIUM", "/usr/bin/chromium"))
SLIDER = "#slider-tR"
# the drags' start and end points as fractions of the slider's width (t_R from 0 to 1 m): from
# 0.20 to 0.24 m on, each drag a little further
START, STEP, SPAN = 0.20, 0.01, 0.04


ROOT = Path(__file__).resolve().parent.parent


def export(folder: Path, root: Path = ROOT, fmus: Path | None = None) -> Path:
    """`cosim app --export folder` by the tree ``root`` (first on the path), its FMUs and modules
    in ``fmus`` (default: COSIM_FMU_DIR or ./fmus)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])}
    if fmus is not None:
        env["COSIM_FMU_DIR"] = str(fmus)
    r = subprocess.run([sys.executable, "-m", "cosim", "app", "--export", str(folder)], capture_output=True,
                       text=True, env=env, cwd=folder.parent)
    if r.returncode != 0:
        raise SystemExit(f"cosim app --export of {root} failed: {r.stderr.strip()}")
    return folder


def baseline_site(ref: str, scratch: Path) -> Path:
    """The app of the committed tree ``ref`` (its ``cosim/`` and ``modelica/``), exported."""
    return export(scratch / "site", baseline_tree(ref, scratch / "tree"), scratch / "fmus")


def open_page(browser, site: Path):
    """The exported app at ``site``, the crowned roller chosen."""
    page = browser.new_page(viewport={"width": 1200, "height": 800})
    page.goto((site / "index.html").as_uri())
    page.wait_for_function("window.cosimApp && (window.cosimApp.ready || window.cosimApp.error !== null)",
                           timeout=120_000)
    page.select_option("#set", "crowned-roller")
    if page.evaluate("window.cosimApp.error") is not None:
        raise SystemExit(f"the page of {site} failed: {page.evaluate('window.cosimApp.error')}")
    return page


def drag(page, fraction: float) -> dict:
    """One mouse drag of the slider from ``fraction`` to ``fraction + SPAN`` of its width; the
    state after the redraw of its last input event."""
    box = page.locator(SLIDER).bounding_box()
    y = box["y"] + box["height"] / 2
    before = page.evaluate("window.cosimApp.redraws")
    page.mouse.move(box["x"] + fraction * box["width"], y)
    page.mouse.down()
    page.mouse.move(box["x"] + (fraction + SPAN) * box["width"], y, steps=2)
    page.mouse.up()
    s = page.evaluate("""() => { const a = window.cosimApp;
        return {ms: a.lastRedrawMs, evaluations: a.evaluations, redraws: a.redraws, error: a.error,
                }; }""")
    if s["error"] is not None or s["redraws"] <= before:
        raise SystemExit(f"the drag at {fraction:.2f} did not redraw: {s}")
    return s


SHOWN = """() => { const a = window.cosimApp;
    document.querySelector('%s').dispatchEvent(new Event('input'));
    const text = ['weave', 'capsize', 'self-stable', 'eigenvalues']
      .map((id) => document.getElementById(id).textContent).join('|');
    return {evs: a.sweep.evs, weave: a.weave, capsize: a.capsize, eigenvalues: a.eigenvalues, text}; }""" % SLIDER


def difference(a: dict, b: dict) -> tuple[float, bool]:
    """The largest difference of two redraws' eigenvalues, weave and capsize speeds [1/s, m/s],
    and whether their texts are equal."""
    worst = 0.0
    for x, y in zip(a["evs"] + [a["eigenvalues"]], b["evs"] + [b["eigenvalues"]]):
        for (rx, ix), (ry, iy) in zip(x, y):
            worst = max(worst, abs(rx - ry), abs(ix - iy))
    for name in ("weave", "capsize"):
        if (a[name] is None) != (b[name] is None):
            return float("inf"), False
        if a[name] is not None:
            worst = max(worst, abs(a[name] - b[name]))
    return worst, a["text"] == b["text"]


def main(site: Path, baseline: Path | None) -> None:
    from playwright.sync_api import sync_playwright

    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as config, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                                    args=["--headless", "--no-sandbox", "--disable-gpu", "--disable-crash-reporter"],
                                    env={**os.environ, "XDG_CONFIG_HOME": config})
        try:
            page = open_page(browser, site)
            # label -> (page, continuation: None for a page that has no such switch)
            paths = {"without continuation (new initialization per speed)": (page, False),
                     "with continuation": (page, True)}
            if baseline is not None:
                paths = {"baseline (its page and modules)": (open_page(browser, baseline), None), **paths}
            times = {label: [] for label in paths}
            evaluations = {label: [] for label in paths}
            for k in range(-2, DRAGS):  # two rounds of warm-up (the JIT), not counted
                for label, (tab, on) in paths.items():
                    tab.bring_to_front()
                    if on is not None:
                        tab.evaluate("(on) => { window.cosimApp.continuation = on; }", on)
                    s = drag(tab, START + STEP * (k % 10))
                    if k >= 0:
                        times[label].append(s["ms"])
                        evaluations[label].append(s["evaluations"])
            redraws = {}
            for label, (tab, on) in paths.items():
                if on is not None:
                    tab.evaluate("(on) => { window.cosimApp.continuation = on; }", on)
                tab.locator(SLIDER).fill(str(START + 0.005))  # the same parameters in every path
                redraws[label] = tab.evaluate(SHOWN)
        finally:
            browser.close()
    after = os.getloadavg()
    print(f"crowned-roller redraw after a t_R drag, median of {DRAGS} drags per path, alternating "
          f"(load average {load[0]:.2f} before, {after[0]:.2f} after, {os.cpu_count()} CPUs)")
    width = max(map(len, paths))
    for label in paths:
        t = times[label]
        print(f"  {label:<{width}} {statistics.median(t):6.1f} ms (min {min(t):.1f}, max {max(t):.1f}; "
              f"{statistics.median(evaluations[label]):.0f} linearizations)")
    on = statistics.median(times["with continuation"])
    for label in paths:
        if label != "with continuation":
            print(f"  ratio {label} / with continuation: {statistics.median(times[label]) / on:.2f}")
    print(f"  goal <= {GOAL_MS:g} ms with continuation: {'meets' if on <= GOAL_MS else 'MISSES'}")
    reference = redraws["with continuation"]
    for label in paths:
        if label != "with continuation":
            worst, texts = difference(redraws[label], reference)
            print(f"  same numbers as {label}: max |difference| of eigenvalues, weave and capsize speeds "
                  f"{worst:.1e}; texts shown {'identical' if texts else 'DIFFERENT'}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--site", type=Path, help="an exported app (`cosim app --export DIR`); default: export one")
    parser.add_argument("--baseline", default="ae32022",
                        help="also the app of this git ref (default ae32022: before the continuation), "
                             "exported from its tree; 'none' for none")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp)
        site = args.site.resolve() if args.site is not None else export(scratch / "site")
        before = None
        if args.baseline != "none":
            (scratch / "baseline").mkdir()
            before = baseline_site(args.baseline, scratch / "baseline")
        main(site, before)
