"""Export a system as an SSP 1.0 (or 2.0) archive that libcosim, Ecos and other SSP tools run unmodified.

The archive holds ``SystemStructure.ssd`` and the FMUs under ``resources/``. Parameters are
bound inline (ssv:ParameterSet per component). Start and stop time are the SSP default
experiment; the base step and per-component step sizes go into OSP annotations, which libcosim
reads (and ``cosim``'s Ecos runner), and the base step also into OMSimulator's own annotation (a
fixed-step master), because SSP itself has no master step size and OMSimulator otherwise steps at
its default 1e-3 s.

SSP 1.0 is the default: Ecos reads no other version. ``ssp_version="2.0"`` writes the same
system as SSP 2.0 (the namespaces of SSP 2.0 are those of 1.0); its connectors and parameters of
FMI 3 FMUs then carry their own FMI 3 types (``ssc:Float64``), which SSP 1.0 lacks.

The models of the system are built as FMI 2.0 FMUs, or as FMI 3.0 FMUs with ``fmi_version="3"``
(``cosim export-ssp --fmi-version 3``); SSP 1.0 types the connectors and parameters of both the
same way (FMI 3 ``Float64`` is ``ssc:Real``). Ecos runs either; libcosim has no FMI 3.0 (see
:mod:`cosim.engines`).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from cosim.cosimulation import algorithms
from cosim.cosimulation.component import FMUComponent
from cosim.cosimulation.system import FMI_VERSIONS, SystemError_, SystemSpec
from cosim.cosimulation.factory import create_components
from cosim.cosimulation.master import assemble, step_grid
from cosim.cosimulation.modelica_twins import with_twins
from cosim.fmu.access import ALL_FMI_VERSIONS, read_fmu
from cosim.outputs import atomic_output, check_output

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
    # OMSimulator matches the literal prefix "oms:" and declares this namespace for it itself
    # (src/OMSimulatorLib/Snapshot.cpp).
    "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd",
}
#: The SSP versions :func:`export_ssp` writes; the first is the default.
SSP_VERSIONS = ("1.0", "2.0")
# One parameter-set name for all components: libcosim applies every binding; Ecos applies the
# set named at initialization (``init(parameter_set="initialValues")``).
PARAMETER_SET = "initialValues"
#: SSP 1.0 types of the FMI 2 and FMI 3 variable types a connector or parameter may have.
TYPES = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean", "String": "String",
         "Float64": "Real", "Float32": "Real", "Int32": "Integer", "Int16": "Integer", "Int8": "Integer",
         "UInt16": "Integer", "UInt8": "Integer"}
#: SSP 2.0 types of the same variable types: SSP 2.0 has every FMI 3 type under its own name.
TYPES_2 = {kind: kind for kind in TYPES}


class FileNote(str):
    """A note of :func:`export_ssp` on an FMU file of the system (copied as it is), not on a twin."""


def _literal(value, kind: str) -> str:
    if kind == "Boolean":
        return "true" if value else "false"
    if kind in ("Integer", "Int32", "Int16", "Int8", "UInt16", "UInt8"):
        return str(int(value))
    return repr(float(value))


def _omsimulator_master(parent: ET.Element, step: float, master: str) -> None:
    """OMSimulator's annotation of the fixed-step master ``master`` (the coupling algorithm's
    :attr:`~cosim.cosimulation.algorithms.CouplingAlgorithm.omsimulator_master`) of step ``step``
    (s) under ``parent``.

    Element and attribute names follow OMSimulator's reader, src/OMSimulatorLib/ssd/Tags.cpp
    (``oms:Annotations``, ``oms:SimulationInformation``, ``oms:FixedStepMaster``, annotation type
    ``org.openmodelica``) and SystemWC::importFromSSD_SimulationInformation in
    src/OMSimulatorLib/SystemWC.cpp (``description="oms-ma"``, ``stepSize``). OMSimulator reads
    only the first ``ssc:Annotation`` of an ``ssd:Annotations``, so this one comes first.
    """
    annotation = ET.SubElement(parent, "ssc:Annotation", type="org.openmodelica")
    information = ET.SubElement(ET.SubElement(annotation, "oms:Annotations"), "oms:SimulationInformation")
    ET.SubElement(information, "oms:FixedStepMaster", description=master, stepSize=repr(float(step)))


def _coupling(spec: SystemSpec) -> algorithms.CouplingAlgorithm:
    """The coupling algorithm of ``spec``; :class:`SystemError_` if SSP annotations cannot
    describe it (of the built-in algorithms only Jacobi, OSP's FixedStepAlgorithm, can)."""
    coupling = algorithms.algorithm(spec.algorithm)
    if not coupling.exports_to_ssp:
        raise SystemError_(f"{spec.path or spec.name}: SSP export describes a fixed-step Jacobi system "
                           f"(OSP FixedStepAlgorithm); the system uses '{spec.algorithm}'")
    return coupling


def system_structure(spec: SystemSpec, fmus: dict[str, Path], ssp_version: str = "1.0") -> bytes:
    """The SystemStructure.ssd text; ``fmus`` maps component names to their FMU files.

    ``ssp_version`` is one of :data:`SSP_VERSIONS`.
    """
    if ssp_version not in SSP_VERSIONS:
        raise SystemError_(f"SSP version '{ssp_version}' cannot be exported (choose {' or '.join(SSP_VERSIONS)})")
    types = TYPES if ssp_version == "1.0" else TYPES_2
    coupling = _coupling(spec)
    # libcosim's parser wants the literal prefixes ssd: ssc: ssv: osp: declared on the root.
    root = ET.Element("ssd:SystemStructureDescription", {
        **{f"xmlns:{k}": v for k, v in NS.items()}, "version": ssp_version, "name": spec.name,
    })
    system = ET.SubElement(root, "ssd:System", name=spec.name)
    if spec.description:
        system.set("description", spec.description)
    elements = ET.SubElement(system, "ssd:Elements")
    for name, fmu in fmus.items():
        md = read_fmu(fmu, ALL_FMI_VERSIONS)
        variables = {v.name: v for v in md.modelVariables}
        component = ET.SubElement(elements, "ssd:Component", {
            "name": name, "source": f"resources/{name}.fmu", "type": "application/x-fmu-sharedlibrary"})
        connectors = ET.SubElement(component, "ssd:Connectors")
        for v in md.modelVariables:
            if v.causality in ("input", "output") and v.type in TYPES and not getattr(v, "dimensions", None):
                connector = ET.SubElement(connectors, "ssd:Connector", name=v.name, kind=v.causality)
                ET.SubElement(connector, f"ssc:{types[v.type]}")
        parameters = spec.components[name].parameters
        if parameters:
            bindings = ET.SubElement(component, "ssd:ParameterBindings")
            binding = ET.SubElement(bindings, "ssd:ParameterBinding")
            values = ET.SubElement(binding, "ssd:ParameterValues")
            parameter_set = ET.SubElement(values, "ssv:ParameterSet", version=ssp_version, name=PARAMETER_SET)
            container = ET.SubElement(parameter_set, "ssv:Parameters")
            for pname, value in parameters.items():
                v = variables[pname]
                entry = ET.SubElement(container, "ssv:Parameter", name=pname)
                ET.SubElement(entry, f"ssv:{types[v.type]}", value=_literal(value, types[v.type]))
        multiple = spec.components[name].step_multiple
        if multiple != 1:
            annotations = ET.SubElement(component, "ssd:Annotations")
            annotation = ET.SubElement(annotations, "ssc:Annotation", type="com.opensimulationplatform")
            ET.SubElement(annotation, "osp:StepSizeHint", value=repr(spec.step * multiple))
    connections = ET.SubElement(system, "ssd:Connections")
    for c in spec.connections:
        ET.SubElement(connections, "ssd:Connection", startElement=c.source, startConnector=c.output,
                      endElement=c.target, endConnector=c.input)
    # OMSimulator takes the master step of a system from the system's annotations.
    _omsimulator_master(ET.SubElement(system, "ssd:Annotations"), spec.step, coupling.omsimulator_master)
    experiment = ET.SubElement(root, "ssd:DefaultExperiment", startTime=repr(spec.start), stopTime=repr(spec.stop))
    annotations = ET.SubElement(experiment, "ssd:Annotations")
    annotation = ET.SubElement(annotations, "ssc:Annotation", type="com.opensimulationplatform")
    algorithm = ET.SubElement(annotation, "osp:Algorithm")
    ET.SubElement(algorithm, f"osp:{coupling.osp_algorithm}", baseStepSize=repr(spec.step))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"


def _built_as(spec: SystemSpec, fmi_version: str) -> SystemSpec:
    """The system with every model component built as ``fmi_version`` ("2" or "3")."""
    import dataclasses

    version = {"2.0": "2", "3.0": "3"}.get(fmi_version, fmi_version)
    if version not in FMI_VERSIONS:
        raise SystemError_(f"FMI version '{fmi_version}' cannot be exported (choose 2 or 3)")
    return dataclasses.replace(spec, components={
        name: dataclasses.replace(entry, fmi_version=version) if entry.kind == "model" else entry
        for name, entry in spec.components.items()})


def export_ssp(spec: SystemSpec, destination: str | Path, fmu_dir: str | Path | None = None,
               fmi_version: str | None = None, ssp_version: str = "1.0") -> tuple[Path, list[str]]:
    """Write the system as an SSP archive; Python blocks are replaced by their Modelica twins.

    Parameters
    ----------
    spec : SystemSpec
        The system.
    destination : str or Path
        The ``.ssp`` file to write.
    fmu_dir : str or Path, optional
        Where models are built (default: ``COSIM_FMU_DIR`` or ``./fmus``).
    fmi_version : {"2", "3"}, optional
        Build every model (and twin) as this FMI version; None: each component's own
        ``fmi_version`` (default 2). FMU files given in the system keep theirs (noted).
    ssp_version : {"1.0", "2.0"}, optional
        The SSP version of the archive (default 1.0, the one Ecos reads).

    Returns the archive path and one note per replaced block (and per FMU file of another FMI
    version than ``fmi_version``).

    Raises
    ------
    SystemError_
        If a Python block has no Modelica twin, ``fmi_version`` is not 2 or 3, ``ssp_version``
        is not 1.0 or 2.0, or SSP annotations cannot describe the system's coupling algorithm
        (of the built-in ones only Jacobi: OSP's FixedStepAlgorithm).
    """
    destination = check_output(destination, "SSP file")  # before anything is built
    if ssp_version not in SSP_VERSIONS:
        raise SystemError_(f"SSP version '{ssp_version}' cannot be exported (choose {' or '.join(SSP_VERSIONS)})")
    spec, notes = with_twins(spec)
    if fmi_version is not None:
        spec = _built_as(spec, str(fmi_version))
    _coupling(spec)
    grid = step_grid(spec.start, spec.stop, spec.step)
    if len(grid) > 2 and grid[-1] - grid[-2] < 0.999999 * spec.step:
        raise SystemError_(f"{spec.path or spec.name}: step {spec.step:g} s does not divide the run from "
                           f"{spec.start:g} s to {spec.stop:g} s; `cosim run` ends it with a shorter step, "
                           "but the OSP FixedStepAlgorithm of an SSP cannot: choose a step that divides it")
    components = create_components(spec, fmu_dir)  # builds models, checks parameters
    try:
        assemble(spec, components)  # checks the wiring before anything is written
        fmus = {name: Path(comp.fmu.path) for name, comp in components.items() if isinstance(comp, FMUComponent)}
        if fmi_version is not None:
            notes += [FileNote(f"{name}: the FMU file {comp.fmu.path.name} is FMI {comp.fmu.fmi_version}, "
                               "copied as it is")
                      for name, comp in components.items()
                      if isinstance(comp, FMUComponent) and comp.fmu.fmi_version[:1] != str(fmi_version)[:1]]
    finally:
        for comp in components.values():
            comp.close()
    with atomic_output(destination, "SSP file") as partial:  # the archive appears only when complete
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("SystemStructure.ssd", system_structure(spec, fmus, ssp_version))
            for name, fmu in fmus.items():
                archive.write(fmu, f"resources/{name}.fmu")
    return destination, notes
