"""modelDescription.xml (FMI 2.0 or 3.0) and buildDescription.xml (FMI 3.0) from the same
:class:`ModelInfo` the C tables come from: value references, causalities, start values and
dependencies are written by one description for both versions, only their XML differs.

:class:`ModelInfo` refers to variables by their position in the value array; the XML names them
by value reference (``Variable.vr``, FMI 3 dependencies and ``derivative`` too) or, in FMI 2's
ModelStructure and ``derivative``, by ``Variable.index``, the 1-based place in ModelVariables."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from cosim.compiler.codegen import FMI_VERSIONS, source_files
from cosim.compiler.description import ModelInfo
from cosim.compiler.units import base_units

LOG_CATEGORIES = {
    "logStatusError": "Errors",
    "logStatusWarning": "Warnings",
    "logCalls": "Every FMI call",
}
DISPLAY_UNITS = {("rad", "deg"): 57.29577951308232}


def _fmt(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return repr(float(value))


def _unit_definitions(info: ModelInfo, root: ET.Element) -> None:
    units = sorted({v.unit for v in info.variables if v.unit})
    if not units:
        return
    definitions = ET.SubElement(root, "UnitDefinitions")
    for unit in units:
        element = ET.SubElement(definitions, "Unit", name=unit)
        parsed = base_units(unit)
        if parsed is not None:
            exponents, factor = parsed
            attributes = {k: str(v) for k, v in exponents.items()}
            if factor != 1.0:
                attributes["factor"] = repr(factor)
            ET.SubElement(element, "BaseUnit", attributes)
        for (base, display), factor in DISPLAY_UNITS.items():
            if base == unit and any(v.unit == unit and v.display_unit == display for v in info.variables):
                ET.SubElement(element, "DisplayUnit", name=display, factor=repr(factor))


_START_TYPE = {"Real": float, "Integer": int, "Boolean": bool}


def _head_attributes(v, name: str, description: str | None) -> dict:
    """name, valueReference, description, causality, variability, initial: the same in FMI 2's
    ScalarVariable and an FMI 3 variable."""
    attributes = {"name": name, "valueReference": str(v.vr)}
    if description:
        attributes["description"] = description
    attributes["causality"] = v.causality
    attributes["variability"] = v.variability
    if v.initial and v.causality != "input":
        attributes["initial"] = v.initial
    return attributes


def _value_attributes(v) -> dict:
    """unit, displayUnit, min, max: on FMI 2's type element, on the FMI 3 variable itself."""
    attributes = {}
    if v.type == "Real" and v.unit:
        attributes["unit"] = v.unit
        if v.display_unit and (v.unit, v.display_unit) in DISPLAY_UNITS:
            attributes["displayUnit"] = v.display_unit
    if v.min is not None and v.type != "Boolean":
        attributes["min"] = _fmt(int(v.min) if v.type == "Integer" else v.min)
    if v.max is not None and v.type != "Boolean":
        attributes["max"] = _fmt(int(v.max) if v.type == "Integer" else v.max)
    return attributes


def _has_start(v) -> bool:
    return v.start is not None and (v.initial in ("exact", "approx") or v.causality == "input")


def _scalar_variable(parent: ET.Element, v, variables) -> None:
    element = ET.SubElement(parent, "ScalarVariable", _head_attributes(v, v.name, v.description))
    typed = _value_attributes(v)
    if _has_start(v):
        typed["start"] = _fmt(_START_TYPE[v.type](v.start))
    if v.derivative_of is not None:
        typed["derivative"] = str(variables[v.derivative_of].index)
    ET.SubElement(element, v.type, typed)


def _unknowns(parent: ET.Element, items: dict[int, list[int]] | list[int], variables) -> None:
    """FMI 2 ``<Unknown>`` elements of the variables at the positions ``items`` (with their
    dependencies if a dict), named by ``index``."""
    for position in sorted(items):
        attributes = {"index": str(variables[position].index)}
        if isinstance(items, dict):
            attributes["dependencies"] = " ".join(str(variables[d].index) for d in items[position])
        ET.SubElement(parent, "Unknown", attributes)


def model_description_xml(info: ModelInfo, generation_tool: str, fmi_version: str = "2") -> bytes:
    """The XML text of modelDescription.xml of an FMU of ``fmi_version`` ("2": FMI 2.0, "3": FMI 3.0).

    Raises
    ------
    ValueError
        If ``fmi_version`` is neither.
    """
    if fmi_version not in FMI_VERSIONS:
        raise ValueError(f"FMI version must be one of {', '.join(FMI_VERSIONS)}, got {fmi_version!r}")
    root = _fmi3(info, generation_tool) if fmi_version == "3" else _fmi2(info, generation_tool)
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"


def _fmi2(info: ModelInfo, generation_tool: str) -> ET.Element:
    """The root element of an FMI 2.0 modelDescription.xml."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0",
        "modelName": info.name,
        "guid": info.guid,
        "description": info.description,
        "generationTool": generation_tool,
        "variableNamingConvention": "structured",
        "numberOfEventIndicators": "0",
    })
    common = {
        "modelIdentifier": info.identifier,
        "canGetAndSetFMUstate": "true",
        "canSerializeFMUstate": "true",
        "providesDirectionalDerivative": "true",
    }
    me = ET.SubElement(root, "ModelExchange", common)
    cs = ET.SubElement(root, "CoSimulation", {
        **common,
        "canHandleVariableCommunicationStepSize": "true",
        "canInterpolateInputs": "true",
        "maxOutputDerivativeOrder": "0",
    })
    for element in (me, cs):
        files = ET.SubElement(element, "SourceFiles")
        for name in source_files(info, "2"):
            ET.SubElement(files, "File", name=name)
    _unit_definitions(info, root)
    categories = ET.SubElement(root, "LogCategories")
    for name, description in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=description)
    _default_experiment(info, root)
    variables = ET.SubElement(root, "ModelVariables")
    for v in info.variables:
        _scalar_variable(variables, v, info.variables)
    structure = ET.SubElement(root, "ModelStructure")
    if info.output_dependencies:
        _unknowns(ET.SubElement(structure, "Outputs"), info.output_dependencies, info.variables)
    if info.derivative_dependencies:
        _unknowns(ET.SubElement(structure, "Derivatives"), info.derivative_dependencies, info.variables)
    initial = _initial_unknowns(info)
    if initial:
        _unknowns(ET.SubElement(structure, "InitialUnknowns"), initial, info.variables)
    return root


def _default_experiment(info: ModelInfo, root: ET.Element) -> None:
    experiment = {}
    for key, attribute in (("StartTime", "startTime"), ("StopTime", "stopTime"),
                           ("Tolerance", "tolerance"), ("Interval", "stepSize")):
        if key in info.experiment and info.experiment[key] is not None:
            experiment[attribute] = _fmt(float(info.experiment[key]))
    if experiment:
        ET.SubElement(root, "DefaultExperiment", experiment)


def _initial_unknowns(info: ModelInfo) -> list[int]:
    """Positions of the unknowns of initialization mode (the same rule in FMI 2 and 3):
    outputs and calculated parameters that are computed, the state derivatives, and the states
    whose start value is computed or solved."""
    return sorted({v.position for v in info.variables
                   if (v.causality in ("output", "calculatedParameter") and v.initial in ("calculated", "approx"))
                   or v.role == "derivative"
                   or (v.role == "state" and v.initial in ("calculated", "approx"))})


# --- FMI 3.0 -----------------------------------------------------------------------------------

# FMI 2 type names -> FMI 3 element names (Integer is a 32-bit int in the runtime's tables too)
FMI3_TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
# The capabilities of the runtime (cosim/runtime/fmi3_api.c), the same for every model. Inputs
# are constant over a communication step (FMI 2's input interpolation has no FMI 3 equivalent:
# no intermediate update, smoothness 0); a step never returns early.
FMI3_COMMON = {
    "canGetAndSetFMUState": "true",
    "canSerializeFMUState": "true",
    "providesDirectionalDerivatives": "true",
    "providesAdjointDerivatives": "true",
}
FMI3_COSIMULATION = {
    "canHandleVariableCommunicationStepSize": "true",
    "maxOutputDerivativeOrder": "0",
    "recommendedIntermediateInputSmoothness": "0",
    "providesIntermediateUpdate": "false",
    "mightReturnEarlyFromDoStep": "false",
    "canReturnEarlyAfterIntermediateUpdate": "false",
    "hasEventMode": "false",
}
TIME_NAME = "time"


def _fmi3(info: ModelInfo, generation_tool: str) -> ET.Element:
    """The root element of an FMI 3.0 modelDescription.xml: the variables of the value array,
    with the same value references as in FMI 2, and ``time`` (causality independent) at the
    value reference one past them (``cosim_model.h``)."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "3.0",
        "modelName": info.name,
        "instantiationToken": info.guid,
        "description": info.description,
        "generationTool": generation_tool,
        "variableNamingConvention": "structured",
    })
    common = {"modelIdentifier": info.identifier, **FMI3_COMMON}
    ET.SubElement(root, "ModelExchange", common)
    ET.SubElement(root, "CoSimulation", {**common, **FMI3_COSIMULATION})
    _unit_definitions(info, root)
    categories = ET.SubElement(root, "LogCategories")
    for name, description in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=description)
    _default_experiment(info, root)
    variables = ET.SubElement(root, "ModelVariables")
    ET.SubElement(variables, "Float64", {"name": TIME_NAME, "valueReference": str(info.independent_vr),
                                         "description": "Simulation time", "causality": "independent",
                                         "variability": "continuous", "unit": "s"})
    arrays = info.fmi3_arrays
    # the position of the FMI 3 variable each value belongs to (an array: its first element's)
    head = list(range(len(info.variables)))
    for first, (_, n) in arrays.items():
        head[first:first + n] = [first] * n
    for v in info.variables:
        if head[v.position] == v.position:
            _fmi3_variable(variables, v, arrays.get(v.position), info.variables)

    def vr(position: int) -> str:
        return str(info.variables[position].vr)

    structure = ET.SubElement(root, "ModelStructure")
    for element, items in (("Output", info.output_dependencies),
                           ("ContinuousStateDerivative", info.derivative_dependencies)):
        merged: dict[int, set[int]] = {}
        for position, dependencies in items.items():
            merged.setdefault(head[position], set()).update(head[d] for d in dependencies)
        for position in sorted(merged):
            ET.SubElement(structure, element, valueReference=vr(position),
                          dependencies=" ".join(vr(d) for d in sorted(merged[position])))
    for position in sorted({head[i] for i in _initial_unknowns(info)}):
        ET.SubElement(structure, "InitialUnknown", valueReference=vr(position))
    return root


def _fmi3_variable(parent: ET.Element, v, array: tuple[str, int] | None = None, variables=()) -> None:
    """One FMI 3 variable: the attributes of FMI 2's ScalarVariable and of its type element in one
    element named after the type, ``derivative`` as the state's value reference. ``array``: (name,
    n) if ``v`` is the first of the n elements of an array (``variables[v.position:v.position + n]``),
    which become one variable with a ``<Dimension>`` and a list of start values."""
    name, n = array or (v.name, 1)
    elements = variables[v.position:v.position + n] if array else [v]
    # a derivative is described by its name (der(x[1])): the array's is der(x)
    description = name if v.description and v.description == v.name else v.description
    attributes = {**_head_attributes(v, name, description), **_value_attributes(v)}
    if _has_start(v):
        convert = _START_TYPE[v.type]
        attributes["start"] = " ".join(_fmt(convert(e.start if e.start is not None else 0.0)) for e in elements)
    if v.derivative_of is not None:
        attributes["derivative"] = str(variables[v.derivative_of].vr)
    element = ET.SubElement(parent, FMI3_TYPES[v.type], attributes)
    if array:
        ET.SubElement(element, "Dimension", start=str(n))


def build_description_xml(info: ModelInfo) -> bytes:
    """The XML text of ``sources/buildDescription.xml`` of an FMI 3.0 FMU: one C99 source file
    set, the same list of files as the FMI 2 ``<SourceFiles>`` of the model (``source_files``),
    compiled in ``sources/`` (the headers are there too)."""
    root = ET.Element("fmiBuildDescription", fmiVersion="3.0")
    configuration = ET.SubElement(root, "BuildConfiguration", modelIdentifier=info.identifier)
    files = ET.SubElement(configuration, "SourceFileSet", language="C99")
    for name in source_files(info, "3"):
        ET.SubElement(files, "SourceFile", name=name)
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"
