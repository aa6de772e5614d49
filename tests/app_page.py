"""One exported page of `cosim app` shared by the tests of a module, brought back before each test
to the state it had when it had just loaded.

Opening the page costs most of a short browser test (a new browser context, the 2 MB bundle
parsed, the WebAssembly modules compiled, the first sweep); a reset costs one sweep. The reset
chooses the first bicycle with a change event of the select, as a user would, after setting what a
choice keeps to what the page starts with: the speed, continuation, the read-outs under the
pointer, a refused file's message, the hidden sliders of other bicycles' parameters, which
``<details>`` are open. It leaves the focus, the scroll position and the pointer where a new page
has them and writes the view's address into the URL's hash. Then what the page shows and holds
(:data:`SNAPSHOT`: the public state objects ``cosimApp``, ``cosimRide``, ``cosimDiagram``, every
field's value, every ``<details>``, the text of the page, the pixels of the eigenvalue view's
canvases, the hash, the focus, the scroll positions) is compared with what it was when the page had
just loaded; if anything differs, the page is closed and a new one opened, so that every test
starts where a new page starts. Not compared, because they count or time what happened before:
``cosimApp.redraws``, ``cosimApp.lastRedrawMs`` and the redraw time the page prints. Not reset
either: the module instance the page keeps per bicycle, which starts a new parameter set's
initialization where its last one ended (continuation, static/app.js); where the initialization
solves the pitch, its numbers are those of a new instance to rounding (checked to 1e-12 by
test_app.py's continuation test).

An error in the page or a request that leaves ``file://`` fails the test during which it happened
(at its end) and closes the page; after a failed test the page is closed too. The next test then
gets a new page. ``page.requests`` lists every request since the page was opened.

Usage (a module's ``page`` fixture)::

    @pytest.fixture(scope="module")
    def shared_page(browser, app_site):
        with SharedPage(browser, app_site / "index.html", viewport={"width": 1200, "height": 800}) as shared:
            yield shared

    @pytest.fixture()
    def page(shared_page):
        with shared_page.reset() as page:
            yield page
"""
from __future__ import annotations

import contextlib
import json
from pathlib import Path

from test_wasm import offline_page

#: The page is ready when every view of it is (or has failed, which the tests then report).
READY = ("window.cosimApp && (window.cosimApp.ready || window.cosimApp.error !== null)"
         " && window.cosimRide && (window.cosimRide.ready || window.cosimRide.error !== null)"
         " && window.cosimDiagram && (window.cosimDiagram.ready || window.cosimDiagram.error !== null)")

#: What the page shows and holds, as one JSON text (see the module's docstring).
SNAPSHOT = """() => {
  const $ = (id) => document.getElementById(id);
  const digest = (text) => {
    let h = 0;
    for (let i = 0; i < text.length; i++) h = (Math.imul(h, 31) + text.charCodeAt(i)) | 0;
    return `${text.length}:${h}`;
  };
  const {redraws, lastRedrawMs, ...app} = window.cosimApp;
  const timed = $("redraw"), ms = timed ? timed.textContent : null;
  if (timed) timed.textContent = "";
  const text = document.body.innerText;
  if (timed) timed.textContent = ms;
  const focused = document.activeElement;
  return JSON.stringify({
    app, ride: window.cosimRide, diagram: window.cosimDiagram,
    fields: [...document.querySelectorAll("input, select, textarea")].map((e) =>
      [e.id, e.type === "checkbox" || e.type === "radio" ? e.checked : e.value, e.disabled]),
    details: [...document.querySelectorAll("details")].map((d) => d.open),
    readouts: ["plot-readout", "locus-readout"].map((id) => ($(id) ? $(id).textContent : null)),
    text, hash: location.hash, focus: focused ? focused.id || focused.tagName : null,
    scrolled: [[window.scrollX, window.scrollY], ...[...document.body.querySelectorAll("*")]
      .filter((e) => e.scrollLeft || e.scrollTop).map((e) => [e.id || e.tagName, e.scrollLeft, e.scrollTop])],
    canvases: ["geometry", "plot", "locus"].map((id) => ($(id) ? [$(id).width, $(id).height, digest($(id).toDataURL())]
                                                                : null)),
  }, (key, value) => (typeof value === "function" ? undefined
                      : typeof value === "number" && !Number.isFinite(value) ? String(value) : value));
}"""

#: The reset (see the module's docstring); its argument: ``details``, ``fields`` and ``readouts``
#: of the snapshot of the page just loaded.
RESET = """({details, fields, readouts}) => {
  const app = window.cosimApp, first = window.COSIM_DATA.bicycles[0], $ = (id) => document.getElementById(id);
  if (document.activeElement && document.activeElement !== document.body) document.activeElement.blur();
  app.continuation = true;
  app.speed = first.speeds.default;
  app.hover.plot = app.hover.locus = null;
  ["plot-readout", "locus-readout"].forEach((id, k) => { if ($(id)) $(id).textContent = readouts[k]; });
  app.viewError = null;
  $("view-error").textContent = "";
  const select = $("set");
  select.value = first.name;
  select.dispatchEvent(new Event("input", {bubbles: true}));
  select.dispatchEvent(new Event("change", {bubbles: true}));
  document.querySelectorAll("details").forEach((d, k) => { d.open = details[k]; });
  const loaded = new Map(fields.map(([id, value]) => [id, value]));
  for (const e of document.querySelectorAll("input[type=range]"))  // a parameter the first bicycle has not
    if (!e.checkVisibility() && loaded.has(e.id)) e.value = loaded.get(e.id);
  window.scrollTo(0, 0);
  if (location.hash.replace(/^#/, "") !== app.address) history.replaceState(null, "", `#${app.address}`);
}"""


class SharedPage:
    """The exported page at ``index`` (a path), opened by :func:`test_wasm.offline_page` with
    ``options`` (viewport, console_errors, ...) when a test first needs it and kept open;
    :meth:`reset` gives it to a test. ``opened`` counts the pages opened, ``incomplete`` lists,
    per reset that did not give the loaded state, where the state differed."""

    def __init__(self, browser, index: Path, **options):
        self.browser, self.url, self.options = browser, Path(index).as_uri(), options
        self.page = self.loaded = None
        self.opened = 0
        self.incomplete: list[list[str]] = []
        self._stack = contextlib.ExitStack()
        self._errors: list[str] = []

    def __enter__(self) -> SharedPage:
        return self

    def __exit__(self, *exc) -> None:
        self._close()

    def _open(self):
        self.page = self._stack.enter_context(offline_page(self.browser, self.url, READY, **self.options))
        self.opened += 1
        self.page.on("pageerror", lambda exc: self._errors.append(str(exc)))
        if self.options.get("console_errors"):
            self.page.on("console", lambda m: self._errors.append(m.text) if m.type == "error" else None)
        self.loaded = self.state()
        return self.page

    def _close(self, failed: BaseException | None = None) -> None:
        """Close the page; offline_page then fails if the page had an error or made a request
        that left file:// (not after a test that failed: its failure is reported)."""
        self.page = self.loaded = None
        if failed is None:
            self._stack.close()
        else:
            self._stack.__exit__(type(failed), failed, failed.__traceback__)

    def state(self) -> str:
        """What the page shows and holds now (:data:`SNAPSHOT`)."""
        return self.page.evaluate(SNAPSHOT)

    @contextlib.contextmanager
    def reset(self):
        """The page as a new one is, for the duration of a test; at its end an error in the page
        or a request that left file:// during the test fails it."""
        if self.page is not None:
            loaded = json.loads(self.loaded)
            self.page.evaluate(RESET, {key: loaded[key] for key in ("details", "fields", "readouts")})
            self.page.mouse.move(0, 0)
            now = self.state()
            if now != self.loaded:
                self.incomplete.append(differences(loaded, json.loads(now)))
                self._close()
        page = self.page if self.page is not None else self._open()
        requests = len(page.requests)
        self._errors.clear()
        try:
            yield page
        except BaseException as failed:
            self._close(failed)
            raise
        if self._errors or any(not url.startswith("file://") for url in page.requests[requests:]):
            self._close()  # raises: offline_page's checks


def differences(loaded, now, where: str = "") -> list[str]:
    """Where two snapshots differ: the paths of the differing values (at most 10), each with the
    two values shortened."""
    if isinstance(loaded, dict) and isinstance(now, dict):
        keys = list(loaded) + [k for k in now if k not in loaded]
        found = [d for k in keys for d in differences(loaded.get(k), now.get(k), f"{where}.{k}")]
    elif isinstance(loaded, list) and isinstance(now, list) and len(loaded) == len(now):
        found = [d for k, (a, b) in enumerate(zip(loaded, now)) for d in differences(a, b, f"{where}[{k}]")]
    else:
        found = [] if loaded == now else [f"{where}: {str(loaded)[:80]} -> {str(now)[:80]}"]
    return found[:10]
