"""`cosim info`: what an FMU or a model offers."""
from __future__ import annotations

import json

from cosim.fmu.target import is_fmu_path
from cosim.compiler.catalog import shorten, summarize


def _number(value):
    return None if value in (None, "") else float(value)


#: What ``cosim info`` reports of each interface: (attribute of FMPy's ModelExchange/CoSimulation,
#: the name in FMI 3, in FMI 2 (None: not in that version), the interface it applies to).
CAPABILITIES = (
    ("providesDirectionalDerivative", "providesDirectionalDerivatives", "providesDirectionalDerivative", None),
    ("providesAdjointDerivatives", "providesAdjointDerivatives", None, None),
    ("canGetAndSetFMUstate", "canGetAndSetFMUState", "canGetAndSetFMUstate", None),
    ("canSerializeFMUstate", "canSerializeFMUState", "canSerializeFMUstate", None),
    ("canHandleVariableCommunicationStepSize", "canHandleVariableCommunicationStepSize",
     "canHandleVariableCommunicationStepSize", "CoSimulation"),
    ("fixedInternalStepSize", "fixedInternalStepSize", None, "CoSimulation"),
    ("canInterpolateInputs", None, "canInterpolateInputs", "CoSimulation"),
    ("maxOutputDerivativeOrder", None, "maxOutputDerivativeOrder", "CoSimulation"),
    ("providesIntermediateUpdate", "providesIntermediateUpdate", None, "CoSimulation"),
    ("canReturnEarlyAfterIntermediateUpdate", "canReturnEarlyAfterIntermediateUpdate", None, "CoSimulation"),
    ("hasEventMode", "hasEventMode", None, "CoSimulation"),
    ("recommendedIntermediateInputSmoothness", "recommendedIntermediateInputSmoothness", None, "CoSimulation"),
)
#: How the text output names a capability (numbers are shown with their value).
CAPABILITY_LABELS = {
    "providesDirectionalDerivatives": "directional derivatives", "providesDirectionalDerivative": "directional derivatives",
    "providesAdjointDerivatives": "adjoint derivatives", "canGetAndSetFMUState": "FMU state get/set",
    "canGetAndSetFMUstate": "FMU state get/set", "canSerializeFMUState": "FMU state serialization",
    "canSerializeFMUstate": "FMU state serialization",
    "canHandleVariableCommunicationStepSize": "variable communication step",
    "fixedInternalStepSize": "fixed internal step {} s", "canInterpolateInputs": "input interpolation",
    "maxOutputDerivativeOrder": "output derivatives up to order {}",
    "providesIntermediateUpdate": "intermediate update", "canReturnEarlyAfterIntermediateUpdate": "early return",
    "hasEventMode": "event mode", "recommendedIntermediateInputSmoothness": "input smoothness {}",
}


def _capabilities(md) -> dict:
    """Per interface the capabilities it declares, named as in the FMU's FMI version."""
    fmi3 = md.fmiVersion.startswith("3.")
    found = {}
    for interface, section in (("ModelExchange", md.modelExchange), ("CoSimulation", md.coSimulation)):
        if section is None:
            continue
        found[interface] = {}
        for attribute, name3, name2, applies in CAPABILITIES:
            name = name3 if fmi3 else name2
            if name is None or applies not in (None, interface):
                continue
            value = getattr(section, attribute, None)
            found[interface][name] = _number(value) if isinstance(value, str) else value
    return found


def _dimensions(md, v) -> list | None:
    """An FMI 3 array's sizes (a number, or the name of the structural parameter that sets it);
    None for a scalar."""
    if not getattr(v, "dimensions", None):
        return None
    names = {x.valueReference: x.name for x in md.modelVariables}
    sizes = []
    for d in v.dimensions:
        if d.start not in (None, ""):
            sizes.append(int(d.start))
        else:
            sizes.append(names.get(d.valueReference, d.valueReference))
    return sizes


def fmu_info(path) -> dict:
    """Model description of an FMU as a plain dict."""
    # deferred: loads numpy, which importing this module does not
    from cosim.fmu.access import READABLE_FMI_VERSIONS, read_fmu

    md = read_fmu(path, versions=READABLE_FMI_VERSIONS, runnable=False)
    experiment = md.defaultExperiment
    groups: dict[str, list] = {}
    for v in md.modelVariables:
        if getattr(v, "alias", None) is not None:  # an FMI 3 <Alias>: another name of a variable listed
            continue
        groups.setdefault(v.causality, []).append({
            "name": v.name, "type": v.type, "unit": getattr(v, "unit", None), "start": v.start,
            "description": v.description or "", "valueReference": v.valueReference,
            "variability": v.variability, "dimensions": _dimensions(md, v),
        })
    return {
        "fmu": str(path),
        "modelName": md.modelName,
        "description": md.description,
        "guid": md.guid,
        "generationTool": md.generationTool,
        "fmiVersion": md.fmiVersion,
        "interfaces": [k for k, s in (("ModelExchange", md.modelExchange), ("CoSimulation", md.coSimulation),
                                      ("ScheduledExecution", getattr(md, "scheduledExecution", None))) if s],
        "capabilities": _capabilities(md),
        "states": [d.variable.derivative.name for d in md.derivatives],
        "defaultExperiment": {
            key: _number(getattr(experiment, key)) for key in ("startTime", "stopTime", "tolerance", "stepSize")
        } if experiment else None,
        "variables": groups,
    }


def _format_fmu(info: dict) -> str:
    title = f"{info['modelName']}: {info['description']}" if info["description"] else info["modelName"]
    lines = [title, f"  file: {info['fmu']}",
             f"  FMI {info['fmiVersion']} {' + '.join(info['interfaces'])}, "
             f"{'instantiation token' if info['fmiVersion'].startswith('3.') else 'GUID'} {info['guid']}",
             f"  generated by {info['generationTool']}"]
    for interface, capabilities in info.get("capabilities", {}).items():
        offered = [CAPABILITY_LABELS[k].format(v) for k, v in capabilities.items()
                   if v not in (None, False) and not (k == "maxOutputDerivativeOrder" and not v)]
        lines.append(f"  {interface}: {', '.join(offered) or '(no optional capabilities)'}")
    fmi3 = info["fmiVersion"].startswith("3.")
    for v in info["variables"].get("independent", []):
        lines.append(f"  independent variable: {v['name']} [{v['unit'] or '-'}]")
    lines.append(f"  states: {', '.join(info['states']) or '(none)'}")
    if info["defaultExperiment"]:
        e = info["defaultExperiment"]
        lines.append(f"  default experiment: {e['startTime']} .. {e['stopTime']} s, tolerance {e['tolerance']}, "
                     f"step {e['stepSize']}")
    for causality in ("input", "output", "parameter", "calculatedParameter"):
        variables = info["variables"].get(causality, [])
        if not variables:
            continue
        lines.append(f"  {causality}s:")
        for v in variables:
            start = f" = {v['start']}" if v["start"] is not None else ""
            shape = f"[{', '.join(map(str, v['dimensions']))}]" if v.get("dimensions") else ""
            # FMI 3 has a type per width (Float32, Int8, UInt64, ...): named where it is not Float64
            kind = f" {v['type']}" if fmi3 and v["type"] != "Float64" else ""
            lines.append(f"    {v['name']}{shape}{start} [{v['unit'] or '-'}]{kind}  {v['description']}")
    return "\n".join(lines)


def _format_model(summary) -> str:
    lines = [f"{summary.name}: {summary.description}",
             f"  exported: {'yes' if summary.exported else 'no'}"]
    if summary.experiment:
        lines.append("  experiment: " + ", ".join(f"{k}={v}" for k, v in summary.experiment.items()))
    for label, signals in (("inputs", summary.inputs), ("outputs", summary.outputs), ("parameters", summary.parameters)):
        if signals:
            lines.append(f"  {label}:")
            for s in signals:
                value = f" = {shorten(s.value)}" if s.value is not None else ""
                lines.append(f"    {s.name}{value} [{s.unit or '-'}]  {s.description}")
    return "\n".join(lines)


def describe_target(target: str, as_json: bool = False) -> str:
    """Text (or JSON) description of an FMU file or a library model."""
    if is_fmu_path(target):
        info = fmu_info(target)
        return json.dumps(info, indent=2, default=str) if as_json else _format_fmu(info)

    summary = summarize(target)
    return json.dumps(summary.to_dict(), indent=2) if as_json else _format_model(summary)
