"""What engines read from FMU and SSP archives before running them: FMI versions, the SSP's
default experiment, and the archive unpacked into a temporary folder."""
from __future__ import annotations

import contextlib
import io
import shutil
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
OSP = "http://opensimulationplatform.com/SSP/OSPAnnotations"


def fmi_version(description: bytes) -> str | None:
    """The ``fmiVersion`` attribute of a modelDescription.xml (None if it cannot be read)."""
    try:
        return ET.fromstring(description).get("fmiVersion")
    except ET.ParseError:
        return None


def fmu_fmi_version(fmu: str | Path) -> str | None:
    """The FMI version of an FMU file (None if its model description cannot be read)."""
    try:
        with zipfile.ZipFile(fmu) as archive:
            return fmi_version(archive.read("modelDescription.xml"))
    except (OSError, KeyError, zipfile.BadZipFile):
        return None


def fmi3_components(ssp: str | Path) -> dict[str, str]:
    """The components of an SSP archive whose FMU is FMI 3: name -> its path in the archive (read
    from SystemStructure.ssd and each FMU's modelDescription.xml, nothing extracted)."""
    found = {}
    with zipfile.ZipFile(ssp) as archive:
        root = ET.fromstring(archive.read("SystemStructure.ssd"))
        for component in root.iter(f"{{{SSD}}}Component"):
            source = component.get("source", "")
            try:
                with zipfile.ZipFile(io.BytesIO(archive.read(source))) as fmu:
                    version = fmi_version(fmu.read("modelDescription.xml"))
            except (KeyError, zipfile.BadZipFile):  # not in the archive, or not an FMU: the engine says so
                continue
            if version and version.startswith("3."):
                found[component.get("name", source)] = source
    return found


@contextlib.contextmanager
def unpacked_ssp(ssp: str | Path):
    """:func:`unpack_ssp` as a context: the folder is removed afterwards."""
    unpacked = unpack_ssp(ssp)
    try:
        yield unpacked
    finally:
        shutil.rmtree(unpacked[0], ignore_errors=True)


def unpack_ssp(ssp: str | Path):
    """Extract an SSP into a new temporary folder (the caller removes it); returns
    (folder, start [s], stop [s], base step [s] of its OSP FixedStepAlgorithm)."""
    folder = Path(tempfile.mkdtemp(prefix="cosim-ssp-run-"))
    with zipfile.ZipFile(ssp) as archive:
        archive.extractall(folder)
    root = ET.parse(folder / "SystemStructure.ssd").getroot()
    ns = {"ssd": SSD, "osp": OSP}
    experiment = root.find("ssd:DefaultExperiment", ns)
    start = float(experiment.get("startTime", 0.0))
    stop = float(experiment.get("stopTime"))
    algorithm = experiment.find(".//osp:FixedStepAlgorithm", ns)
    base = float(algorithm.get("baseStepSize"))
    return folder, start, stop, base
