"""The one description of an FMU from which both the C tables and modelDescription.xml are written.

Every variable has a position in one value array laid out as in ``runtime/cosim_model.h``:
``[x | der(x) | u | p | c | z]``. The C tables are indexed by position; the value reference of
the variable at position i is ``FIRST_VALUE_REFERENCE + i`` (:func:`value_reference`, the one
place both the XML and the C tables take it from). The XML lists the variables in position order,
so the FMI 2 ModelStructure index of a variable (its 1-based place in ModelVariables) is its
position + 1, whatever the value references are.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import casadi as ca

from cosim.compiler.flatten import Declaration, FlatModel
from cosim.compiler.library import ModelEntry
from cosim.compiler.ode import ExplicitModel

FIXED_STEP_PARAMETER = "solver.fixedStepSize"
# The value reference of position 0 of the value array (written into the C tables as
# ``first_vr``, see ``runtime/cosim_model.h``). Not 0: OMSimulator refuses value reference 0 in
# FMI 3 FMUs, and no importer needs it.
FIRST_VALUE_REFERENCE = 1
DEFAULT_TOLERANCE = 1e-6
# The element of a one-dimensional array: ``x[3]`` or ``der(x[3])`` (array ``x``, resp. ``der(x)``).
ARRAY_ELEMENT = re.compile(r"^(?P<der>der\()?(?P<array>.+)\[(?P<index>[1-9][0-9]*)\](?(der)\))$")
# Roles whose arrays FMI 3 exports as arrays (<Dimension>): the states (one fmi3GetFloat64 reads
# the Pade delay's state vector) and their derivatives. The local variables of the component
# bicycles (the position vectors r[3] of every frame) stay scalars, as in FMI 2: an importer
# finds them under the names it knows.
FMI3_ARRAY_ROLES = ("state", "derivative")
# The attributes the elements of an FMI 3 array share (its start values may differ).
_SHARED = ("role", "causality", "variability", "initial", "type", "unit", "display_unit", "quantity", "min", "max")


def value_reference(position: int) -> int:
    """The value reference of the variable at ``position`` of the value array (``position`` =
    the number of variables: FMI 3's ``time``, one past the array)."""
    return FIRST_VALUE_REFERENCE + position


@dataclass
class Variable:
    """One FMI scalar variable."""

    name: str
    position: int  # in the value array (and in ModelVariables), from 0
    role: str  # state, derivative, input, parameter, calculated, algebraic
    causality: str
    variability: str
    initial: str | None
    type: str = "Real"
    start: float | None = None
    description: str = ""
    unit: str | None = None
    display_unit: str | None = None
    quantity: str | None = None
    min: float | None = None
    max: float | None = None
    derivative_of: int | None = None  # position of the state this is the derivative of

    @property
    def vr(self) -> int:
        """The value reference (see :func:`value_reference`)."""
        return value_reference(self.position)

    @property
    def index(self) -> int:
        """1-based position in ModelVariables (FMI 2's ModelStructure ``index``)."""
        return self.position + 1


@dataclass
class ModelInfo:
    """Everything `cosim build` writes about one model."""

    name: str
    identifier: str
    description: str
    variables: list[Variable]
    sizes: dict  # nx nu np nc nz
    experiment: dict
    # position -> [positions of the states and inputs it depends on]
    output_dependencies: dict = field(default_factory=dict)
    derivative_dependencies: dict = field(default_factory=dict)
    guid: str = ""
    init_unknowns: str = ""  # "theta, psi": the states solved from the initial equations, for messages

    @property
    def default_tolerance(self) -> float:
        return float(self.experiment.get("Tolerance", DEFAULT_TOLERANCE))

    def by_role(self, role: str) -> list[Variable]:
        return [v for v in self.variables if v.role == role]

    def variable(self, name: str) -> Variable:
        for v in self.variables:
            if v.name == name:
                return v
        raise KeyError(name)

    @property
    def fixed_step_vr(self) -> int:
        return self.variable(FIXED_STEP_PARAMETER).vr

    @property
    def fmi3_arrays(self) -> dict[int, tuple[str, int]]:
        """The FMI 3 array variables: position of the first element -> (name, number of
        elements), see :func:`fmi3_arrays`."""
        return fmi3_arrays(self.variables)

    @property
    def independent_vr(self) -> int:
        """Value reference of FMI 3's independent variable ``time``: one past the value array
        (``first_vr + nv``, see ``runtime/cosim_model.h``); FMI 2 does not list time."""
        return value_reference(len(self.variables))


def fmi3_arrays(variables: list[Variable], roles=FMI3_ARRAY_ROLES) -> dict[int, tuple[str, int]]:
    """The elements ``a[1]``, ..., ``a[n]`` (n >= 2) of one declared one-dimensional Modelica array,
    at consecutive positions with the same FMI attributes and a role of ``roles``, as one FMI 3
    array variable ``a``: position of ``a[1]`` -> (``a``, n). ``variables`` are in position order
    (``variables[i].position == i``).

    A state array is one only with its derivative array (``der(a)``, whose elements are the
    derivatives of ``a[1]``, ..., ``a[n]`` in order): FMI 3's ``derivative`` attribute names one
    variable. Everything else stays a scalar."""
    elements: dict[str, list[tuple[int, Variable]]] = {}
    for v in variables:
        match = ARRAY_ELEMENT.match(v.name)
        if match and v.role in roles:
            name = f"der({match['array']})" if match["der"] else match["array"]
            elements.setdefault(name, []).append((int(match["index"]), v))
    every = {}
    for v in variables:
        match = ARRAY_ELEMENT.match(v.name)
        if match:
            name = f"der({match['array']})" if match["der"] else match["array"]
            every[name] = every.get(name, 0) + 1
    arrays = {}
    for name, items in elements.items():
        items.sort(key=lambda item: item[0])
        first = items[0][1]
        if (len(items) >= 2 and len(items) == every[name]
                and [k for k, _ in items] == list(range(1, len(items) + 1))
                and [v.position for _, v in items] == list(range(first.position, first.position + len(items)))
                and all(getattr(v, a) == getattr(first, a) for _, v in items for a in _SHARED)):
            arrays[first.position] = (name, len(items))
    for head, (name, n) in list(arrays.items()):
        v = variables[head]
        if v.role == "derivative":
            state = v.derivative_of
            consistent = (arrays.get(state, (None, 0))[1] == n
                          and all(variables[head + j].derivative_of == state + j for j in range(n)))
            if not consistent:
                del arrays[head]
    derivative_arrays = {variables[h].derivative_of for h in arrays if variables[h].role == "derivative"}
    return {h: a for h, a in arrays.items() if variables[h].role != "state" or h in derivative_arrays}


def model_identifier(model_name: str) -> str:
    """A C identifier for the model (also the FMU's file name): dots become underscores."""
    return model_name.replace(".", "_")


def _type_of(python_type) -> str:
    return {int: "Integer", bool: "Boolean"}.get(python_type, "Real")


def describe(entry: ModelEntry, flat: FlatModel, model: ExplicitModel) -> ModelInfo:
    """Lay out the value array and collect every variable's FMI attributes."""
    decl = flat.declarations
    variables: list[Variable] = []

    def add(name, role, causality, variability, initial, start=None, python_type=float, **extra):
        d: Declaration | None = decl.get(name)
        v = Variable(
            name=name, position=len(variables), role=role, causality=causality, variability=variability,
            initial=initial, type=_type_of(python_type), start=start,
            description=(d.description if d else "") or "",
            unit=d.unit if d else None, display_unit=d.display_unit if d else None,
            quantity=d.quantity if d else None,
            min=d.min if d and isinstance(d.min, (int, float)) else None,
            max=d.max if d and isinstance(d.max, (int, float)) else None,
        )
        for key, value in extra.items():
            setattr(v, key, value)
        variables.append(v)
        return v

    states = []
    guesses = _default_starts(model)
    for k, s in enumerate(model.states):
        causality = "output" if s.output else "local"
        if k in model.init_unknowns:
            # Solved from the initial equations: FMI 2 initial = "approx", an iteration variable whose
            # start value (the guess, here at the default parameters) may be set before initialization.
            states.append(add(s.name, "state", causality, "continuous", "approx", guesses[k]))
            continue
        calculated = s.start is None
        states.append(add(s.name, "state", causality, "continuous",
                          "calculated" if calculated else "exact", None if calculated else s.start))
    for s, state in zip(model.states, states):
        d = decl.get(s.name)
        add(f"der({s.name})", "derivative", "local", "continuous", "calculated",
            derivative_of=state.position, description=f"der({s.name})",
            unit=_derivative_unit(d.unit if d else None))
    for s in model.inputs:
        add(s.name, "input", "input", "continuous", None, s.start, s.python_type)
    for s in model.parameters:
        add(s.name, "parameter", "parameter", "fixed", "exact", float(s.start), s.python_type)
    add(FIXED_STEP_PARAMETER, "parameter", "parameter", "fixed", "exact", 0.0,
        description="Co-simulation: fixed integration step size (0 = error-controlled Dormand-Prince 5(4))",
        unit="s", min=0.0)
    for s in model.calculated:
        add(s.name, "calculated", "calculatedParameter", "fixed", "calculated", None, s.python_type)
    for s in model.algebraics:
        add(s.name, "algebraic", "output" if s.output else "local", "continuous", "calculated")

    sizes = {
        "nx": len(model.states), "nu": len(model.inputs), "np": len(model.parameters) + 1,
        "nc": len(model.calculated), "nz": len(model.algebraics),
    }
    info = ModelInfo(
        name=flat.name, identifier=model_identifier(flat.name), description=entry.description,
        variables=variables, sizes=sizes, experiment=entry.experiment,
        init_unknowns=", ".join(model.states[k].name for k in model.init_unknowns),
    )
    _dependencies(info, model)
    return info


def _default_starts(model: ExplicitModel) -> list[float]:
    """The start values of the states at the default parameter values."""
    if not model.init_unknowns:
        return [s.start for s in model.states]
    values = ca.Function("x0", [model.p], [model.x0])([float(s.start) for s in model.parameters])
    return [float(v) for v in ca.DM(values).full().ravel()]


def _derivative_unit(unit: str | None) -> str | None:
    """Unit of a time derivative: rad -> rad/s, m/s -> m/s2; None where that is not obvious."""
    if not unit or unit == "1":
        return "1/s" if unit else None
    if unit.endswith("/s"):
        return unit + "2"
    return None if "/" in unit else unit + "/s"


def _dependencies(info: ModelInfo, model: ExplicitModel) -> None:
    """Structural dependencies of derivatives and outputs on states and inputs (Jacobian sparsity)."""
    knowns = ca.vertcat(model.x, model.u)
    known = [v.position for v in info.by_role("state")] + [v.position for v in info.by_role("input")]
    algebraics = info.by_role("algebraic")
    outputs = [k for k, v in enumerate(algebraics) if v.causality == "output"]
    unknowns = ca.vertcat(model.xdot, *[model.z[k] for k in outputs])
    unknown = [v.position for v in info.by_role("derivative")] + [algebraics[k].position for k in outputs]
    deps = {i: [] for i in unknown}
    if knowns.numel() and unknowns.numel():
        sp = ca.jacobian(unknowns, knowns).sparsity()
        for r, c in zip(*sp.get_triplet()):
            deps[unknown[r]].append(known[c])
    for v in info.variables:
        if v.role == "derivative":
            info.derivative_dependencies[v.position] = sorted(deps[v.position])
        elif v.causality == "output":
            info.output_dependencies[v.position] = (sorted(deps[v.position]) if v.role == "algebraic"
                                                    else [v.position])
