"""modelDescription.xml (FMI 2.0) from the same :class:`ModelInfo` the C tables come from."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from cosim.compiler.codegen import source_files
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


def _scalar_variable(parent: ET.Element, v) -> None:
    attributes = {"name": v.name, "valueReference": str(v.vr)}
    if v.description:
        attributes["description"] = v.description
    attributes["causality"] = v.causality
    attributes["variability"] = v.variability
    if v.initial and v.causality != "input":
        attributes["initial"] = v.initial
    element = ET.SubElement(parent, "ScalarVariable", attributes)
    typed = {}
    if v.type == "Real":
        if v.unit:
            typed["unit"] = v.unit
            if v.display_unit and (v.unit, v.display_unit) in DISPLAY_UNITS:
                typed["displayUnit"] = v.display_unit
    if v.min is not None and v.type != "Boolean":
        typed["min"] = _fmt(int(v.min) if v.type == "Integer" else v.min)
    if v.max is not None and v.type != "Boolean":
        typed["max"] = _fmt(int(v.max) if v.type == "Integer" else v.max)
    if v.start is not None and (v.initial in ("exact", "approx") or v.causality == "input"):
        start = {"Real": float, "Integer": int, "Boolean": bool}[v.type](v.start)
        typed["start"] = _fmt(start)
    if v.derivative_of is not None:
        typed["derivative"] = str(v.derivative_of + 1)
    ET.SubElement(element, v.type, typed)


def _unknowns(parent: ET.Element, items: dict[int, list[int]] | list[int]) -> None:
    for vr in sorted(items):
        attributes = {"index": str(vr + 1)}
        if isinstance(items, dict):
            attributes["dependencies"] = " ".join(str(d + 1) for d in items[vr])
        ET.SubElement(parent, "Unknown", attributes)


def model_description_xml(info: ModelInfo, generation_tool: str) -> bytes:
    """The XML text of modelDescription.xml."""
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
        for name in source_files(info):
            ET.SubElement(files, "File", name=name)
    _unit_definitions(info, root)
    categories = ET.SubElement(root, "LogCategories")
    for name, description in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=description)
    experiment = {}
    for key, attribute in (("StartTime", "startTime"), ("StopTime", "stopTime"),
                           ("Tolerance", "tolerance"), ("Interval", "stepSize")):
        if key in info.experiment and info.experiment[key] is not None:
            experiment[attribute] = _fmt(float(info.experiment[key]))
    if experiment:
        ET.SubElement(root, "DefaultExperiment", experiment)
    variables = ET.SubElement(root, "ModelVariables")
    for v in info.variables:
        _scalar_variable(variables, v)
    structure = ET.SubElement(root, "ModelStructure")
    if info.output_dependencies:
        _unknowns(ET.SubElement(structure, "Outputs"), info.output_dependencies)
    if info.derivative_dependencies:
        _unknowns(ET.SubElement(structure, "Derivatives"), info.derivative_dependencies)
    initial = [v.vr for v in info.variables
               if (v.causality in ("output", "calculatedParameter") and v.initial in ("calculated", "approx"))
               or v.role == "derivative"
               or (v.role == "state" and v.initial in ("calculated", "approx"))]
    if initial:
        _unknowns(ET.SubElement(structure, "InitialUnknowns"), sorted(set(initial)))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"
