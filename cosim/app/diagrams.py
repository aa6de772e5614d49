"""The "How it is built" view of `cosim app` (``COSIM_DATA.diagrams``): the Modelica diagram of
each model the page's bicycles use, as data.

The diagram is drawn at export time by :func:`cosim.diagram.svg.draw` (the diagram layer, MLS
chapter 18: each component a ``<g data-component=NAME>``, each connect equation a
``<g data-connect="A B">``) from the library the FMUs are built from, and inlined by
``static/diagram.js`` in the page: no request at run time. What a student reads next to it, the
parts in plain words, comes from :data:`PARTS` (component name -> words), in the order of
:data:`PARTS` (rear to front, as the paper's Figure 1), then the inputs and outputs.

The eigenvalue view's bicycles use ``Bicycle.Bicycles.WhippleLinear`` (the Meijaard sets and
the rear-steered bicycle) and ``Bicycle.Bicycles.Whipple`` (the crowned roller); the rides run
``Whipple`` too (its rider is rigid, part of the rear frame; ``Bicycle.Bicycles.WhippleRider``
is not a model of the page, so its diagram is not carried).
"""
from __future__ import annotations

import html
import re
from cosim.compiler.library import load_library
from cosim.diagram.graphics import Graphics
from cosim.diagram.svg import draw

#: What each part of a bicycle model is, in a student's words (component name -> words).
PARTS = {
    "rearWheel": "the rear wheel, rolling on the ground without slipping",
    "rearFrame": "the rear frame; the rider, if there is one, sits on it rigidly and is part of this body",
    "steer": "the steer axis: the hinge (head tube) between the rear frame and the front frame; "
             "it turns by the steer angle",
    "frontFrame": "the front frame: fork and handlebar",
    "frontWheel": "the front wheel, rolling on the ground without slipping",
    "ground": "the flat ground: where the wheels touch it and the bicycle's position, heading and lean; "
              "the equations of motion of the whole bicycle are assembled here",
    "torques": "the two pushes from outside: the roll torque (a gust, or the rider leaning) and the "
               "steer torque (the rider's hands)",
    "coordinates": "the roll and steer angles every part shares; the parts' forces are added up here into "
                   "the equations of motion (eq (24) of the paper)",
    "rider": "the rider's upper body, hinged to the rear frame",
}
#: The inputs and outputs of a bicycle model (connector name -> words).
SIGNALS = {
    "T_phi": "roll torque on the rear frame",
    "T_delta": "steer torque on the handlebar",
    "phi": "roll (lean) angle",
    "delta": "steer angle",
    "phi_dot": "roll rate",
    "delta_dot": "steer rate",
    "psi": "heading (yaw) angle",
    "y": "sideways position",
}

_ID = re.compile(r'\bid="([^"]+)"')
_REFERENCE = re.compile(r'(url\(#|href="#)([^)"]+)')
_COMPONENT = re.compile(r'<g data-component="([^"]*)"')


def slug(model: str) -> str:
    """``Bicycle.Bicycles.Whipple`` -> ``Bicycle-Bicycles-Whipple`` (for ids in the page)."""
    return re.sub(r"[^A-Za-z0-9_-]", "-", model)


def inline_svg(svg: str, prefix: str) -> str:
    """The SVG document as an element for an HTML page: without the XML declaration, its ids
    (patterns, gradients) and the references to them prefixed with ``prefix-`` (unique in the page)."""
    text = re.sub(r"^\s*<\?xml[^>]*\?>\s*", "", svg)
    text = _ID.sub(lambda m: f'id="{prefix}-{m.group(1)}"', text)
    return _REFERENCE.sub(lambda m: f"{m.group(1)}{prefix}-{m.group(2)}", text)


def _kind(view) -> str:
    """``input``, ``output`` or ``part`` (a component that is not an input or output connector)."""
    if view.is_connector:
        short = (view.type or view.type_text).rsplit(".", 1)[-1]
        if "input" in view.prefixes or short.endswith("Input"):
            return "input"
        if "output" in view.prefixes or short.endswith("Output"):
            return "output"
    return "part"


def diagram_data(model: str, library=None) -> dict:
    """One entry of ``COSIM_DATA.diagrams``: the diagram of ``model`` and its parts in words.

    Returns
    -------
    dict
        ``model``; ``svg`` (the diagram layer, :func:`inline_svg`); ``title`` and ``notes``
        (what :func:`cosim.diagram.svg.draw` drew by default, e.g. components without a
        Placement); ``components`` (the names of its ``data-component`` groups, in drawing
        order) and ``connections`` (how many connect equations were drawn); ``parts``:
        ``{name, kind, words}`` of each component (``kind`` ``part``, ``input`` or ``output``),
        parts in the order of :data:`PARTS`, then the inputs, then the outputs.

    Raises
    ------
    UnknownModelError, ModelicaError
        As :func:`cosim.diagram.svg.draw`.
    """
    library = library or load_library()
    drawing = draw(model, library=library)
    names = [html.unescape(n) for n in _COMPONENT.findall(drawing.svg)]
    views = {c.name: c for c in Graphics(library).components(model)}
    order = {name: k for k, name in enumerate(PARTS)}
    parts = []
    for name in names:
        view = views.get(name)
        kind = _kind(view) if view is not None else "part"
        words = PARTS.get(name) if kind == "part" else SIGNALS.get(name)
        if words is None:
            words = f"a component of class {view.type or view.type_text}" if view is not None else "a component"
        parts.append({"name": name, "kind": kind, "words": words})
    rank = {"part": 0, "input": 1, "output": 2}
    parts.sort(key=lambda p: (rank[p["kind"]], order.get(p["name"], len(order)) if p["kind"] == "part" else 0))
    return {"model": model, "svg": inline_svg(drawing.svg, f"diagram-{slug(model)}"), "title": drawing.title,
            "notes": list(drawing.notes), "components": names, "connections": drawing.connections,
            "parts": parts}


def page_diagrams(models) -> dict:
    """``COSIM_DATA.diagrams``: model name -> :func:`diagram_data`, for each of ``models`` (once)."""
    return {model: diagram_data(model) for model in dict.fromkeys(models)}
