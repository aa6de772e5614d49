// diagram.js -- "How it is built" of `cosim app` (cosim/app/export.py bundles it after app.js,
// which fills the bicycle select #set): the Modelica diagram of the model of the bicycle chosen
// in the eigenvalue view, with its parts named in words.
//
// The diagrams are drawn at export time by cosim.diagram (the diagram layer of MLS chapter 18:
// each component a <g data-component=NAME>, each connect equation a <g data-connect="A B">) and
// carried in COSIM_DATA.diagrams (model -> {model, svg, title, notes, components, connections,
// parts [{name, kind: part|input|output, words}]}; cosim/app/diagrams.py); the SVG is inlined
// here, scaled to the width of the page by its viewBox; "enlarge" makes it 2.5 times wider,
// scrolled inside its box (the page itself never gets wider). No request is made.
//
// The caption says "rear wheel on the left, front wheel on the right" (the paper's Figure 1) only
// where the diagram draws them so (rearLeft): a model without Placement annotations is drawn in a
// grid.
//
// window.cosimDiagram is the view's state for tests: {ready, error, bicycle, model, enlarged,
// rearLeft}.
(function () {
  "use strict";
  const DATA = window.COSIM_DATA;
  const state = { ready: false, error: null, bicycle: null, model: null, enlarged: false, rearLeft: false };
  window.cosimDiagram = state;
  const $ = (id) => document.getElementById(id);

  function element(tag, text, className) {
    const e = document.createElement(tag);
    if (text !== undefined) e.textContent = text;
    if (className) e.className = className;
    return e;
  }

  // "a, b and c"
  function words(list) {
    return list.length < 2 ? list.join("") : `${list.slice(0, -1).join(", ")} and ${list[list.length - 1]}`;
  }

  // What a screen reader says for the picture.
  function label(d, rearOnLeft) {
    const parts = d.parts.filter((p) => p.kind === "part").map((p) => p.name);
    const signals = d.parts.length - parts.length;
    return `Modelica diagram of ${d.model}: ${parts.length} parts (${words(parts)})` +
      (signals ? ` and ${signals} inputs and outputs` : "") + `, joined by ${d.connections} connect equations` +
      (rearOnLeft ? "; rear wheel on the left, front wheel on the right." : ".");
  }

  // True if the rear wheel is drawn left of the front wheel (as the paper's Figure 1), as the
  // library's Placement annotations put them; without them (a grid) it may not be.
  function rearLeft(svg) {
    const centre = (name) => {
      const g = svg.querySelector(`[data-component="${name}"]`);
      if (!g) return null;
      const b = g.getBBox();
      return b.x + b.width / 2;
    };
    const rear = centre("rearWheel"), front = centre("frontWheel");
    return rear !== null && front !== null && rear < front;
  }

  function drawDiagram(d) {
    const box = $("built-diagram");
    box.innerHTML = d.svg;
    const svg = box.querySelector("svg");
    if (!svg || !svg.getAttribute("viewBox")) throw new Error(`the diagram of ${d.model} is not an SVG with a viewBox`);
    svg.removeAttribute("width");  // the CSS scales it to the box (viewBox: the aspect ratio)
    svg.removeAttribute("height");
    state.rearLeft = rearLeft(svg);
    $("built-layout").textContent = state.rearLeft
      ? "The rear wheel is on the left and the front wheel on the right, as in Figure 1 of the paper." : "";
    svg.setAttribute("role", "img");
    svg.setAttribute("aria-label", label(d, state.rearLeft));
    $("built-model").textContent = d.model;

    const list = $("built-parts");
    list.innerHTML = "";
    for (const p of d.parts.filter((p) => p.kind === "part")) {
      const li = element("li");
      li.append(element("code", p.name), `: ${p.words}`);
      list.appendChild(li);
    }
    const groups = [["input", "inputs (arrows into the model): "], ["output", "outputs (what the model reports): "]];
    for (const [kind, what] of groups) {
      const signals = d.parts.filter((p) => p.kind === kind);
      if (!signals.length) continue;
      const li = element("li", what);
      signals.forEach((p, k) => li.append(k ? ", " : "", element("code", p.name), ` ${p.words}`));
      list.appendChild(li);
    }
    $("built-notes").textContent = d.notes.length ? `Drawn by default: ${d.notes.join("; ")}.` : "";
  }

  function show(name) {
    const bicycle = DATA.bicycles.find((b) => b.name === name) || DATA.bicycles[0];
    const d = DATA.diagrams[bicycle.module];
    if (!d) throw new Error(`the page carries no diagram of ${bicycle.module}`);
    if (state.model !== d.model) drawDiagram(d);
    const line = $("built-bicycle");
    line.textContent = "";
    line.append("The chosen bicycle, ", element("b", bicycle.label), ", is this model with the values of ",
                "the parameter set ", element("code", bicycle.parameterSet),
                bicycle.speeds.max <= 0 ? " at negative speeds (ridden backwards)" : "",
                ". Bicycles of one model differ in their numbers, not in their parts.");
    state.bicycle = bicycle.name;
    state.model = d.model;
  }

  function fail(e) {
    state.error = String(e && e.message ? e.message : e);
    $("built-error").textContent = `The diagram cannot be shown: ${state.error}`;
  }

  function enlarge() {
    state.enlarged = !state.enlarged;
    $("built-diagram").classList.toggle("enlarged", state.enlarged);
    const button = $("built-zoom");
    button.setAttribute("aria-pressed", String(state.enlarged));
    button.textContent = state.enlarged ? "fit to width" : "enlarge";
  }

  try {
    if (!Array.isArray(DATA.bicycles) || !DATA.diagrams) throw new Error("COSIM_DATA has no bicycles or no diagrams");
    const select = $("set");
    select.addEventListener("change", () => {
      try { show(select.value); state.error = null; $("built-error").textContent = ""; } catch (e) { fail(e); }
    });
    $("built-zoom").addEventListener("click", enlarge);
    show(select.value || DATA.bicycles[0].name);
    state.ready = true;
  } catch (e) {
    fail(e);
  }
})();
