"""The Modelica sources are valid Modelica for a second, independent front end (rumoca)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from cosim.compiler.flatten import flatten
from cosim.compiler.library import DEFAULT_LIBRARY, Library
from cosim.compiler.ode import make_explicit

rumoca = pytest.importorskip("rumoca")

FILES = sorted(DEFAULT_LIBRARY.rglob("*.mo"))
LIBRARY = Library(DEFAULT_LIBRARY)


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(DEFAULT_LIBRARY)) for p in FILES])
def test_file_has_no_diagnostics(path: Path):
    diagnostics = rumoca.validate(str(path))
    assert diagnostics == [], "\n".join(str(d) for d in diagnostics)


@pytest.mark.parametrize("entry", LIBRARY.models(), ids=[e.name for e in LIBRARY.models()])
def test_model_compiles_balanced_in_rumoca(entry):
    """rumoca compiles every non-partial model of the library (bicycles, examples, controllers and
    every component on its own) with the one-member flow sets of MLS 9.2 and finds as many
    equations as unknowns: the connectors are balanced, every component is locally balanced, and
    no model reads the flows of its own top-level connectors."""
    model = rumoca.Session().load(str(entry.file), model=entry.name)
    assert model.name == entry.name


#: Components: compiled on their own by rumoca above; this project's compiler builds them inside
#: the models that connect them (the ground alone, say, has no bodies to give it equations of motion).
COMPONENT_PACKAGES = ("Bicycle.Components.", "Bicycle.Linear.", "Bicycle.Mechanics.", "Bicycle.Wheels.")
ASSEMBLED = [e for e in LIBRARY.models() if not e.name.startswith(COMPONENT_PACKAGES)]


@pytest.mark.parametrize("entry", ASSEMBLED, ids=[e.name for e in ASSEMBLED])
def test_model_compiles_in_rumoca_with_our_inputs_and_states(entry):
    """rumoca finds the inputs and the number of continuous states our compiler (pymoca front end)
    finds: two front ends, one reading of the model."""
    model = rumoca.Session().load(str(entry.file), model=entry.name)
    flat = flatten(LIBRARY, entry.name)
    ours = sorted(name for name, d in flat.declarations.items() if "input" in d.prefixes)
    assert sorted(v.name for v in model.inputs) == ours
    rumoca_states = sum(math.prod(v.dims or [1]) for v in model.states)  # an array state counts its elements
    assert rumoca_states == len(make_explicit(flat).states)


def test_one_class_per_file_with_within():
    """MSL layout: every file starts with `within` naming its package, listed in package.order."""
    for path in FILES:
        first = next(line for line in path.read_text().splitlines() if line.strip())
        package = ".".join(path.relative_to(DEFAULT_LIBRARY).parent.parts)
        expected = f"within {package};" if package else "within;"
        if path.name == "package.mo":
            parent = ".".join(path.relative_to(DEFAULT_LIBRARY).parent.parts[:-1])
            expected = f"within {parent};" if parent else "within;"
        assert first.strip() == expected, f"{path}: first line '{first}', expected '{expected}'"
        if path.name != "package.mo":
            order = path.parent / "package.order"
            assert order.is_file() and path.stem in order.read_text().split(), f"{path.stem} not in {order}"


def test_every_parameter_has_unit_and_description():
    """MSL style: every top-level parameter of every model carries an SI unit and a description."""
    from cosim.compiler.catalog import summarize

    for entry in LIBRARY.models():
        for p in summarize(entry.name, LIBRARY).parameters:
            if p.type == "Real":  # Modelica has no unit attribute for Integer and Boolean
                assert p.unit, f"{entry.name}.{p.name} has no unit"
            assert p.description, f"{entry.name}.{p.name} has no description"


LINEAR = [e for e in LIBRARY.models() if e.name.startswith("Bicycle.Linear.")]


@pytest.mark.parametrize("entry", LINEAR, ids=[e.name for e in LINEAR])
def test_linear_bodies_take_the_coordinates_as_inputs(entry):
    """Compiled on their own, the bodies and the torques of the linear model take the coordinates
    and speeds as inputs of their RollSteer_a connector (the causal half of the connector)."""
    model = rumoca.Session().load(str(entry.file), model=entry.name)
    inputs = {v.name for v in model.inputs}
    if entry.name != "Bicycle.Linear.Coordinates":
        assert {"frame.phi", "frame.delta", "frame.phi_dot", "frame.delta_dot"} <= inputs
