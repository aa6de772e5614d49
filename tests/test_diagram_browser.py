"""`cosim diagram` of the bicycles and the examples, opened in a real browser (Debian chromium
through playwright, as tests/test_wasm.py): the SVG shows every component of the model by name,
draws one connection line for every ``connect`` equation (the model's and its bases'), and no two
components' drawings overlap on the page (their bounding boxes, as the browser lays them out)."""
from __future__ import annotations

from pathlib import Path

import pytest

from conftest import cli_in_process
from cosim.compiler.library import load_library
from cosim.diagram.graphics import Graphics
from test_wasm import browser, offline_page  # noqa: F401 (browser: the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site or animation
pytestmark = [pytest.mark.slow, pytest.mark.browser]

LIBRARY = load_library()
MODELS = ["Bicycle.Bicycles.Whipple", "Bicycle.Bicycles.WhippleRider", "Bicycle.Bicycles.WhippleRiderTwist",
          "Bicycle.Bicycles.WhippleLinear"] + [e.name for e in LIBRARY.models() if e.name.startswith("Bicycle.Examples.")]
#: Boxes that touch within this many CSS pixels do not count as overlapping (a shared border).
TOUCH = 0.5


@pytest.fixture(scope="module")
def svgs(tmp_path_factory) -> dict[str, Path]:
    """The SVG of each model, written by the command line."""
    folder = tmp_path_factory.mktemp("diagrams")
    found = {}
    for model in MODELS:
        out = folder / f"{model.rsplit('.', 1)[-1]}.svg"
        status, _, err = cli_in_process(["diagram", model, "-o", str(out)], folder)
        assert status == 0, err
        found[model] = out
    return found


INSPECT = """() => {
  const top = [...document.querySelectorAll('[data-component]')]
      .filter(g => !g.parentElement.closest('[data-component]'));
  const components = top.map(g => {
    const r = g.getBoundingClientRect();
    return {name: g.dataset.component, text: g.textContent, box: [r.left, r.top, r.right, r.bottom]};
  });
  const connects = [...document.querySelectorAll('[data-connect]')].map(g => g.dataset.connect);
  return {components, connects, title: (document.querySelector('title') || {}).textContent || ''};
}"""


def _overlap(a, b) -> float:
    dx = min(a[2], b[2]) - max(a[0], b[0])
    dy = min(a[3], b[3]) - max(a[1], b[1])
    return min(dx, dy)


@pytest.mark.parametrize("model", MODELS)
def test_diagram_shows_every_component_and_connection(browser, svgs, model):
    graphics = Graphics(LIBRARY)
    # the components a diagram draws: those of a model, block or connector class (not the
    # parameters and variables of the unit types)
    expected = {c.name for c in graphics.components(model) if c.kind in ("model", "block", "connector", "class")}
    connections = graphics.connections(model)
    with offline_page(browser, svgs[model].as_uri(), "document.readyState === 'complete'",
                      viewport={"width": 1600, "height": 1200}) as page:
        found = page.evaluate(INSPECT)
    names = {c["name"] for c in found["components"]}
    assert names == expected, f"{model}: components drawn {sorted(names)} != declared {sorted(expected)}"
    for c in found["components"]:
        assert c["name"] in c["text"], f"{model}: the drawing of {c['name']} does not show its name"
    assert len(found["connects"]) == len(connections) > 0 or not connections
    assert "default" not in found["title"].lower(), f"{model}: {found['title']}"
    boxes = found["components"]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert _overlap(a["box"], b["box"]) <= TOUCH, f"{model}: {a['name']} and {b['name']} overlap by {_overlap(a['box'], b['box']):.1f} px"
