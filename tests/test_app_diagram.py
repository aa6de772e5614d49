"""The "How it is built" view of `cosim app` (cosim/app/diagrams.py, static/diagram.js) in a real
headless Chromium, from `cosim app --export` opened from file://.

For each bicycle of the eigenvalue view, chosen with a real change event of its select, the view
shows the Modelica diagram of the bicycle's model (drawn at export by cosim.diagram): every
component of the model's diagram (counted from the Modelica source with cosim.diagram's parser)
is named by a text of the SVG, there is one ``[data-connect]`` group per connect equation of the
source and the caption names every part; it says "rear wheel on the left, front wheel on the
right" (the paper's Figure 1) exactly when the SVG draws them so, and it must where the library
places the wheels (Placement annotations). The SVG is an image for assistive technology
(role="img", an aria-label) and fits the page's width at 360 px (a phone) and 1280 px (a
projector): the section adds no horizontal overflow to the page; "enlarge", pressed with the
keyboard, widens the diagram inside its own scrolling box only. The tests do not depend on where
the components are placed (the annotations of the library may change). Screenshots go to
``$COSIM_SCREENSHOTS`` if set, else to the test's temporary folder. No request other than
file:// may be made, and an error in the page fails the test. Skip rules as tests/test_wasm.py.
The tests share one page per window width, reset before each test to the state of a page just
loaded (tests/app_page.py).
"""
from __future__ import annotations

import contextlib
import os
from pathlib import Path

import pytest

from app_page import SharedPage
from cosim.app.bicycles import BICYCLES
from test_wasm import browser  # noqa: F401 (the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site or animation
pytestmark = [pytest.mark.slow, pytest.mark.browser]

CHOICES = [pytest.param(b.name, b.module, id=b.name) for b in BICYCLES]


@pytest.fixture(scope="module")
def pages(browser, app_site):  # noqa: F811 (the imported fixture)
    """Viewport width [px] -> the exported page at that width (one per width for the module, reset
    before each test: tests/app_page.py), its diagram view ready."""
    with contextlib.ExitStack() as stack:
        yield {width: stack.enter_context(SharedPage(browser, app_site / "index.html",
                                                     viewport={"width": width, "height": 900}))
               for width in (360, 1280)}


def _screenshot_folder(tmp_path: Path) -> Path:
    folder = Path(os.environ["COSIM_SCREENSHOTS"]) if os.environ.get("COSIM_SCREENSHOTS") else tmp_path
    folder.mkdir(parents=True, exist_ok=True)
    return folder


# --- what the Modelica source says ------------------------------------------------------------

def _graphics():
    from cosim.compiler.library import load_library
    from cosim.diagram.graphics import Graphics

    return Graphics(load_library())


def _source_components(model: str) -> list[str]:
    """The components of the model's diagram: those of a model, block or connector class (not
    parameters or constants), inherited ones included, as cosim.diagram reads them."""
    from cosim.diagram.graphics import DRAWN_KINDS

    return [c.name for c in _graphics().components(model)
            if c.kind in DRAWN_KINDS and not ({"parameter", "constant"} & set(c.prefixes))]


def _connect_equations(model: str) -> int:
    """How many connect equations the model's source has: its own (cosim.diagram's parser on its
    file) and those of its base classes."""
    from cosim.diagram.annotations import find_class, parse_file

    graphics = _graphics()
    entry = graphics.library.entries[model]
    own = find_class(parse_file(entry.file), model)
    assert own is not None, model
    return len(own.connections) + sum(_connect_equations(base) for base, _ in graphics.bases(model) if base)


# --- the page ---------------------------------------------------------------------------------

def _view(page) -> dict:
    """What the view shows: its state, the SVG's texts, groups, attributes and boxes."""
    return page.evaluate("""() => {
        const box = document.getElementById("built-diagram"), svg = box.querySelector("svg");
        const centre = (name) => { const g = svg.querySelector(`[data-component="${name}"]`);
            if (!g) return null; const r = g.getBoundingClientRect(); return r.left + r.width / 2; };
        const placed = (name) => { const g = svg.querySelector(`[data-component="${name}"]`);
            return g !== null && !g.classList.contains("unplaced"); };
        const rect = (e) => { const r = e.getBoundingClientRect();
            return {left: r.left, right: r.right, width: r.width}; };
        return {state: {...window.cosimDiagram}, heading: document.getElementById("built-model").textContent,
                texts: [...svg.querySelectorAll("text")].map((t) => t.textContent.trim()),
                components: [...svg.querySelectorAll("[data-component]")].map((g) => g.dataset.component),
                connects: svg.querySelectorAll("[data-connect]").length,
                role: svg.getAttribute("role"), label: svg.getAttribute("aria-label"),
                viewBox: svg.getAttribute("viewBox"),
                parts: [...document.querySelectorAll("#built-parts li > code")].map((c) => c.textContent),
                caption: document.getElementById("built-caption").innerText,
                rear: centre("rearWheel"), front: centre("frontWheel"),
                wheelsPlaced: placed("rearWheel") && placed("frontWheel"),
                svgBox: rect(svg), box: rect(box), boxScroll: [box.scrollWidth, box.clientWidth],
                section: [document.getElementById("built").scrollWidth, document.getElementById("built").clientWidth],
                page: [document.documentElement.scrollWidth, document.documentElement.clientWidth]}; }""")


def _page_width_without_the_view(page) -> int:
    """The page's scroll width with the section hidden (what the other views need)."""
    return page.evaluate("""() => { const s = document.getElementById("built"); s.style.display = "none";
        const w = document.documentElement.scrollWidth; s.style.display = ""; return w; }""")


@pytest.mark.parametrize("name, model", CHOICES)
def test_the_view_shows_the_diagram_of_the_chosen_bicycle(pages, name, model):
    """After a real change of the eigenvalue view's select, the diagram is the bicycle's model's:
    every component of the source named in the SVG, one [data-connect] per connect equation."""
    expected = _source_components(model)
    connects = _connect_equations(model)
    assert {"rearWheel", "rearFrame", "frontFrame", "frontWheel"} <= set(expected) and connects >= 4
    with pages[1280].reset() as page:
        assert page.evaluate("window.cosimDiagram.error") is None
        first = page.evaluate("window.cosimDiagram.bicycle")
        other = next(b.name for b in BICYCLES if b.name != name)
        page.select_option("#set", other if first == name else name)  # a change away first, if needed
        page.select_option("#set", name)
        view = _view(page)
        assert page.evaluate("window.cosimApp.set") == name  # the eigenvalue view has the same bicycle
    assert view["state"]["bicycle"] == name and view["state"]["model"] == model and view["state"]["error"] is None
    assert view["heading"] == model
    missing = [c for c in expected if c not in view["texts"]]
    assert not missing, f"components of {model} not named in the SVG: {missing} (texts {view['texts']})"
    assert sorted(view["components"]) == sorted(expected)
    assert view["connects"] == connects, (view["connects"], connects)
    assert view["rear"] is not None and view["front"] is not None
    said = "The rear wheel is on the left and the front wheel on the right" in view["caption"]
    assert said == view["state"]["rearLeft"] == (view["rear"] < view["front"])  # the caption says what is drawn
    if view["wheelsPlaced"]:  # the library's Placement annotations: as the paper's Figure 1
        assert said, (view["rear"], view["front"])
    assert view["role"] == "img" and model in view["label"] and f"{connects} connect equations" in view["label"]
    assert len(view["viewBox"].split()) == 4
    assert set(view["parts"]) == set(expected)  # the caption names every part, input and output
    assert "connect()" in view["caption"] and "component" in view["caption"]
    assert next(b.label for b in BICYCLES if b.name == name) in view["caption"]
    print(f"\n{name}: {model}, {len(expected)} components, {connects} connect equations; wheels "
          f"{'placed' if view['wheelsPlaced'] else 'at default positions'}, rear wheel "
          f"{'left' if said else 'not left'} of the front wheel")


WIDTHS = [
    pytest.param(360, "benchmark", id="phone-360px-WhippleLinear"),
    pytest.param(360, "crowned-roller", id="phone-360px-Whipple"),
    pytest.param(1280, "benchmark", id="projector-1280px-WhippleLinear"),
    pytest.param(1280, "crowned-roller", id="projector-1280px-Whipple"),
]


@pytest.mark.parametrize("width, name", WIDTHS)
def test_the_diagram_fits_the_width(pages, tmp_path, width, name):
    """The SVG is as wide as its box and inside the viewport; the section adds no horizontal
    overflow to the page (at 1280 px the page has none at all). "enlarge", reached with Tab and
    pressed with Enter, widens the diagram inside its box (which scrolls), not the page; pressed
    again, the diagram fits again. Screenshots: the section fitted, the box enlarged and
    scrolled to its middle."""
    folder = _screenshot_folder(tmp_path)
    with pages[width].reset() as page:
        page.select_option("#set", name)
        fitted = _view(page)
        other_views = _page_width_without_the_view(page)
        page.locator("#built").screenshot(path=str(folder / f"app-diagram-{width}px-{name}.png"))
        page.locator("#built-diagram").focus()  # the scrolling box is focusable; Tab goes on to the button
        page.keyboard.press("Tab")
        assert page.evaluate("document.activeElement.id") == "built-zoom"
        page.keyboard.press("Enter")
        enlarged = _view(page)
        assert page.get_attribute("#built-zoom", "aria-pressed") == "true"
        box = page.locator("#built-diagram")
        scrolled = box.evaluate("(box) => { box.scrollLeft = (box.scrollWidth - box.clientWidth) / 2; "
                                "box.scrollTop = (box.scrollHeight - box.clientHeight) / 2; return box.scrollLeft; }")
        box.screenshot(path=str(folder / f"app-diagram-{width}px-{name}-enlarged.png"))  # the box: its scroll kept
        page.keyboard.press("Enter")
        again = _view(page)
        assert page.get_attribute("#built-zoom", "aria-pressed") == "false"
    client = fitted["page"][1]
    for v in (fitted, again):
        assert v["state"]["enlarged"] is False
        assert abs(v["svgBox"]["width"] - v["box"]["width"]) <= 2.5  # the width of its box (border: 2 px)
        assert v["svgBox"]["left"] >= 0 and v["svgBox"]["right"] <= client + 0.5, v["svgBox"]
        assert v["boxScroll"][0] <= v["boxScroll"][1]  # nothing to scroll
        assert v["section"][0] <= v["section"][1]  # nothing in the section sticks out
        assert v["page"][0] == max(other_views, client)  # no overflow of the page from the diagram
    if width >= 1280:
        assert fitted["page"][0] == client  # the whole page fits a projector's width
    assert enlarged["state"]["enlarged"] is True
    assert enlarged["svgBox"]["width"] > 2 * fitted["svgBox"]["width"]
    assert enlarged["boxScroll"][0] > enlarged["boxScroll"][1] and scrolled > 0  # it scrolls inside its box
    assert enlarged["box"]["right"] <= client + 0.5 and enlarged["page"][0] == fitted["page"][0]
    print(f"\n{width} px, {name}: diagram {fitted['svgBox']['width']:.0f} px wide in a {client} px viewport "
          f"(enlarged {enlarged['svgBox']['width']:.0f} px, scrolled in its box); page scroll width "
          f"{fitted['page'][0]} px, {other_views} px without the section; screenshots in {folder}")


def test_page_diagrams_name_every_part_in_words():
    """cosim.app.diagrams: each model of the page's bicycles has its diagram, its components in
    words (none left to the class-name fallback), ids prefixed, no XML declaration."""
    import re

    from cosim.app.diagrams import PARTS, SIGNALS, page_diagrams

    models = [b.module for b in BICYCLES]
    diagrams = page_diagrams(models)
    assert sorted(diagrams) == sorted(set(models))
    for model, d in diagrams.items():
        assert d["model"] == model and d["svg"].startswith("<svg") and "<?xml" not in d["svg"]
        assert sorted(d["components"]) == sorted(_source_components(model))
        assert d["connections"] == _connect_equations(model)
        for p in d["parts"]:
            assert p["words"] == (PARTS if p["kind"] == "part" else SIGNALS)[p["name"]], (model, p)
        ids = re.findall(r'\bid="([^"]+)"', d["svg"])
        assert all(i.startswith(f"diagram-{model.replace('.', '-')}-") for i in ids), ids
        for reference in re.findall(r"url\(#([^)]+)\)", d["svg"]):
            assert reference in ids, reference
        kinds = [p["kind"] for p in d["parts"]]
        assert kinds == sorted(kinds, key=["part", "input", "output"].index)
