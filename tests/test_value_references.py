"""Value references of the FMUs `cosim build` writes start at 1 (``FIRST_VALUE_REFERENCE``), in
FMI 2.0 and FMI 3.0, Model Exchange and Co-Simulation (one binary and one model description
serve both): no variable has value reference 0 (OMSimulator refuses it in FMI 3), FMI 3's
``time`` included.

The model description and the C tables come from one description: the XML's numbering is checked
here attribute by attribute (FMI 3's ``derivative`` and ModelStructure ``dependencies`` are value
references of existing variables; FMI 2's ModelStructure ``index`` and ``derivative`` are 1-based
places in ModelVariables, which must name the right variables, not value references), and the
binary's by calling it (value reference 0 is refused, the first one reads the first state).
"""
from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest
from conftest import run_cli, shipped_models

from cosim.compiler.build import fmu_path
from cosim.compiler.description import FIRST_VALUE_REFERENCE

EXPORTED = shipped_models(exported_only=True)
VERSIONS = ("2", "3")
FMI3_TYPES = ("Float64", "Int32", "Boolean")
# the models called through their binaries: a linear one with an input, one with an FMI 3 array
# state, one with initial equations and locals
CALLED = ["Bicycle.Bicycles.SelfStabilizing", "Bicycle.Rider.PadeDelay", "Bicycle.Bicycles.WhippleRider"]
START_TOL = 0.0  # a start value read back from the binary is the one in the XML, exactly [state's unit]


@pytest.fixture(scope="module")
def built(fmus) -> dict[tuple[str, str], Path]:
    """(model, "2" | "3") -> FMU: every exported model in both versions, in the session's FMU
    folder (where the ``fmus`` fixture and the FMI 3 export tests build them: up to date there)."""
    folder = Path(os.environ["COSIM_FMU_DIR"])
    result = run_cli("build", "--fmi-version", "2", "3", "-o", str(folder), "-j", "2")
    assert result.returncode == 0, result.stderr
    return {(m, v): fmu_path(m, folder, v) for m in EXPORTED for v in VERSIONS}


def _description(fmu: Path) -> ET.Element:
    with zipfile.ZipFile(fmu) as archive:
        return ET.fromstring(archive.read("modelDescription.xml"))


def _variables(root: ET.Element) -> list[ET.Element]:
    """The ModelVariables in document order (FMI 2 ScalarVariable, FMI 3 typed elements)."""
    return list(root.find("ModelVariables"))


def _size(variable: ET.Element) -> int:
    """Number of values of an FMI 3 variable: 1, or the start of its one <Dimension>."""
    dimension = variable.find("Dimension")
    return int(dimension.get("start")) if dimension is not None else 1


def _values(variable) -> int:
    """Number of values of a variable of FMPy's model description (FMI 3 arrays: of their one dimension)."""
    dimensions = getattr(variable, "dimensions", None)
    return int(dimensions[0].start) if dimensions else 1


def _state_name(derivative_name: str) -> str:
    """``x`` for ``der(x)`` (an array's ``der(x)`` too)."""
    match = re.fullmatch(r"der\((.+)\)", derivative_name)
    assert match, derivative_name
    return match[1]


CASES = [pytest.param(m, v, id=f"{m.rsplit('.', 1)[-1]}-fmi{v}") for m in EXPORTED for v in VERSIONS]


@pytest.mark.parametrize("model, version", CASES)
def test_value_references_start_at_one_without_gaps(built, model, version):
    """The values of the value array (and FMI 3's time, one past them) have the value references
    1, 2, ..., n: each exactly once, none is 0. FMI 2 lists them in that order."""
    variables = _variables(_description(built[model, version]))
    covered = []
    for v in variables:
        first = int(v.get("valueReference"))
        covered += range(first, first + (_size(v) if version == "3" else 1))
    assert FIRST_VALUE_REFERENCE == 1
    assert 0 not in covered
    assert sorted(covered) == list(range(FIRST_VALUE_REFERENCE, FIRST_VALUE_REFERENCE + len(covered)))
    if version == "2":
        assert covered == sorted(covered), "FMI 2: ModelVariables in value-reference order"
    else:
        time = [v for v in variables if v.get("causality") == "independent"]
        assert [v.get("name") for v in time] == ["time"]
        assert int(time[0].get("valueReference")) == max(covered), "time is one past the value array"


@pytest.mark.parametrize("model", [pytest.param(m, id=m.rsplit(".", 1)[-1]) for m in EXPORTED])
def test_fmi3_dependencies_and_derivatives_are_value_references(built, model):
    """FMI 3: every ModelStructure valueReference and dependency, and every ``derivative``, is the
    value reference of a variable; each names the right one (a derivative's state by name, the
    outputs exactly the output variables, the dependencies states and inputs)."""
    root = _description(built[model, "3"])
    by_vr = {int(v.get("valueReference")): v for v in _variables(root)}
    for v in by_vr.values():
        if v.get("derivative") is not None:
            state = by_vr[int(v.get("derivative"))]
            assert state.get("name") == _state_name(v.get("name")), v.get("name")
    structure = root.find("ModelStructure")
    knowns = {vr for vr, v in by_vr.items() if v.get("causality") == "input"}
    knowns |= {int(v.get("derivative")) for v in by_vr.values() if v.get("derivative") is not None}
    outputs = []
    for element in structure:
        vr = int(element.get("valueReference"))
        assert vr in by_vr, (element.tag, vr)
        dependencies = [int(d) for d in (element.get("dependencies") or "").split()]
        assert set(dependencies) <= knowns, (element.tag, by_vr[vr].get("name"), dependencies)
        if element.tag == "Output":
            outputs.append(vr)
        elif element.tag == "ContinuousStateDerivative":
            assert by_vr[vr].get("derivative") is not None, by_vr[vr].get("name")
    assert outputs == sorted(vr for vr, v in by_vr.items() if v.get("causality") == "output")


@pytest.mark.parametrize("model", [pytest.param(m, id=m.rsplit(".", 1)[-1]) for m in EXPORTED])
def test_fmi2_indices_are_places_in_model_variables(built, model):
    """FMI 2: ModelStructure ``index``/``dependencies`` and ``derivative`` are 1-based places in
    ModelVariables and name the right variables: Outputs exactly the output variables, Derivatives
    the derivatives (each ``derivative`` its state, by name), their dependencies states and inputs;
    and the same structure as FMI 3 once places are turned into value references."""
    root = _description(built[model, "2"])
    variables = _variables(root)

    def at(index: str) -> ET.Element:
        assert 1 <= int(index) <= len(variables), index
        return variables[int(index) - 1]

    def real(v: ET.Element) -> ET.Element:
        return next(iter(v))

    states = set()
    for v in variables:
        if real(v).get("derivative") is not None:
            state = at(real(v).get("derivative"))
            assert state.get("name") == _state_name(v.get("name")), v.get("name")
            states.add(state.get("name"))
    structure = root.find("ModelStructure")
    outputs = [at(u.get("index")) for u in structure.find("Outputs")]
    assert [v.get("name") for v in outputs] == [v.get("name") for v in variables if v.get("causality") == "output"]
    structure2 = {}
    for group in structure:
        for unknown in group:
            variable = at(unknown.get("index"))
            if group.tag == "Derivatives":
                assert real(variable).get("derivative") is not None, variable.get("name")
            for d in (unknown.get("dependencies") or "").split():
                known = at(d)
                assert known.get("causality") == "input" or known.get("name") in states, known.get("name")
            structure2[group.tag, variable.get("valueReference")] = sorted(
                int(at(d).get("valueReference")) for d in (unknown.get("dependencies") or "").split())
    # the same unknowns and dependencies as FMI 3 (value references there), where FMI 3 has no arrays
    root3 = _description(built[model, "3"])
    if not any(v.find("Dimension") is not None for v in _variables(root3)):
        tags = {"Outputs": "Output", "Derivatives": "ContinuousStateDerivative", "InitialUnknowns": "InitialUnknown"}
        structure3 = {(tag, e.get("valueReference")): sorted(int(d) for d in (e.get("dependencies") or "").split())
                      for e in root3.find("ModelStructure") for tag in tags if tags[tag] == e.tag}
        # FMI 3 InitialUnknown elements carry no dependencies here
        assert {k: v for k, v in structure2.items() if k[0] != "InitialUnknowns"} == \
            {k: v for k, v in structure3.items() if k[0] != "InitialUnknowns"}
        assert {k for k in structure2 if k[0] == "InitialUnknowns"} == {k for k in structure3 if k[0] == "InitialUnknowns"}


@pytest.mark.parametrize("fmi_type", ["ModelExchange", "CoSimulation"], ids=["me", "cs"])
@pytest.mark.parametrize("version", VERSIONS, ids=[f"fmi{v}" for v in VERSIONS])
@pytest.mark.parametrize("model", [pytest.param(m, id=m.rsplit(".", 1)[-1]) for m in CALLED])
def test_binary_refuses_value_reference_zero(built, model, version, fmi_type, tmp_path):
    """The binary numbers as its XML: the first state (value reference 1) reads its start value,
    FMI 3's time its start time; value reference 0 and the one past the last are refused with an
    error naming it, and the instance stays usable."""
    from fmpy import extract, instantiate_fmu, read_model_description
    from fmpy.fmi1 import FMICallException

    unzipdir = extract(str(built[model, version]), str(tmp_path / "fmu"))
    md = read_model_description(unzipdir)
    messages = []
    instance = instantiate_fmu(unzipdir, md, fmi_type=fmi_type,
                               logger=lambda *args: messages.append(args[-1]))
    fmi3 = version == "3"
    get = instance.getFloat64 if fmi3 else instance.getReal
    try:
        if fmi3:
            instance.enterInitializationMode(startTime=0.0)
        else:
            instance.setupExperiment(startTime=0.0)
            instance.enterInitializationMode()
        instance.exitInitializationMode()
        first = min(md.modelVariables, key=lambda v: v.valueReference)
        n = _values(first)
        assert first.valueReference == FIRST_VALUE_REFERENCE and md.derivatives[0].variable.derivative is first
        if first.start is not None:
            starts = [float(s) for s in str(first.start).split()]
            values = instance.getFloat64([first.valueReference], n) if fmi3 else get([first.valueReference])
            assert max(abs(a - b) for a, b in zip(values, starts, strict=True)) <= START_TOL
        if fmi3:
            time = next(v for v in md.modelVariables if v.causality == "independent")
            assert get([time.valueReference]) == [0.0]
        last = max(v.valueReference + _values(v) - 1 for v in md.modelVariables)
        output = next(v.valueReference for v in md.modelVariables if v.causality == "output" and _values(v) == 1)
        before = get([output])
        for vr in (0, last + 1):
            with pytest.raises(FMICallException):
                get([vr])
            assert any(f"value reference {vr} is out of range" in str(m) for m in messages), messages
        assert get([output]) == before, "a refused value reference leaves the instance usable"
    finally:
        instance.terminate()
        instance.freeInstance()


def _small_info():
    """A hand-made description: x (state, output), der(x), u (input), k (parameter), the fixed
    step parameter, y (output) and w (local); der(x) depends on x and u, y on x."""
    from cosim.compiler.description import FIXED_STEP_PARAMETER, ModelInfo, Variable

    spec = [("x", "state", "output", "continuous", "exact", 1.0, None),
            ("der(x)", "derivative", "local", "continuous", "calculated", None, 0),
            ("u", "input", "input", "continuous", None, 0.0, None),
            ("k", "parameter", "parameter", "fixed", "exact", 2.0, None),
            (FIXED_STEP_PARAMETER, "parameter", "parameter", "fixed", "exact", 0.0, None),
            ("y", "algebraic", "output", "continuous", "calculated", None, None),
            ("w", "algebraic", "local", "continuous", "calculated", None, None)]
    variables = [Variable(name=n, position=i, role=r, causality=c, variability=va, initial=ini, start=s,
                          derivative_of=d) for i, (n, r, c, va, ini, s, d) in enumerate(spec)]
    return ModelInfo(name="Small", identifier="Small", description="", variables=variables,
                     sizes={"nx": 1, "nu": 1, "np": 2, "nc": 0, "nz": 2}, experiment={},
                     output_dependencies={0: [0], 5: [0]}, derivative_dependencies={1: [0, 2]}, guid="{0}")


@pytest.mark.parametrize("first", [1, 7], ids=["first-1", "first-7"])
def test_one_offset_numbers_both_versions(monkeypatch, first):
    """``FIRST_VALUE_REFERENCE`` is the one place the numbering comes from: moved, every value
    reference of both versions (FMI 3's time, derivative and dependencies too) moves with it, while
    FMI 2's ModelStructure indices and derivative (places in ModelVariables) stay as they are."""
    from cosim.compiler import description
    from cosim.compiler.model_description import model_description_xml

    monkeypatch.setattr(description, "FIRST_VALUE_REFERENCE", first)
    info = _small_info()
    root2, root3 = (ET.fromstring(model_description_xml(info, "test", v)) for v in VERSIONS)
    assert [int(v.get("valueReference")) for v in _variables(root2)] == list(range(first, first + 7))
    assert next(iter(_variables(root2)[1])).get("derivative") == "1"  # x, the first in ModelVariables
    unknowns2 = [(g.tag, u.get("index"), u.get("dependencies")) for g in root2.find("ModelStructure") for u in g]
    assert unknowns2 == [("Outputs", "1", "1"), ("Outputs", "6", "1"), ("Derivatives", "2", "1 3"),
                         ("InitialUnknowns", "2", None), ("InitialUnknowns", "6", None)]
    by_name = {v.get("name"): v for v in _variables(root3)}
    assert int(by_name["time"].get("valueReference")) == first + 7
    assert by_name["der(x)"].get("derivative") == str(first)
    unknowns3 = [(e.tag, e.get("valueReference"), e.get("dependencies")) for e in root3.find("ModelStructure")]
    assert unknowns3 == [("Output", str(first), str(first)), ("Output", str(first + 5), str(first)),
                         ("ContinuousStateDerivative", str(first + 1), f"{first} {first + 2}"),
                         ("InitialUnknown", str(first + 1), None), ("InitialUnknown", str(first + 5), None)]
    assert info.fixed_step_vr == first + 4 and info.independent_vr == first + 7
