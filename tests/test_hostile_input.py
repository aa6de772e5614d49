"""Property-based: whatever a user feeds the command line, it answers with a result or one message.

Hypothesis generates system TOMLs, Meijaard parameter files, input CSVs and FMU archives (random
bytes, truncations, path-traversal member names, broken or foreign ``modelDescription.xml``) and
runs the CLI on them in-process (``cosim.cli.main``). For every example:

- the exit status is one of the documented ones (0 success, 1 problems found by ``validate``,
  2 bad input, 3 the bicycle fell, 4 incomplete result written), never the internal-error status
  (70) and never an uncaught exception;
- a failure prints exactly one ``cosim VERB: error: ...`` line and no traceback;
- nothing is written outside the example's own folder (traversal names stay inside), no
  ``*.partial*`` file is left, and a refused command leaves no output under its final name.
"""
from __future__ import annotations

import io
import tempfile
import uuid
import zipfile
from pathlib import Path

import pytest

# the quick run (-m 'not slow') leaves this module out: it compiles and runs defective or foreign FMUs
pytestmark = pytest.mark.slow

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from conftest import cli_in_process, toml_value  # noqa: E402

EXPECTED_STATUS = {0, 2, 3, 4}
SETTINGS = settings(max_examples=40, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@pytest.fixture(scope="module")
def real_fmus(fmus):
    """Two small real FMUs of the session's build: a simple bicycle with a torque input and the
    linear Whipple model (Meijaard parameters)."""
    return {"simple": fmus["Bicycle.Bicycles.SelfStabilizing"], "whipple": fmus["Bicycle.Bicycles.WhippleLinear"]}


def run(argv: list[str], cwd: Path) -> tuple[int, str, str]:
    """``cosim ARGV`` in-process in ``cwd``: (exit status, stdout, stderr)."""
    return cli_in_process(argv, cwd)


def files_under(folder: Path) -> set[Path]:
    return {p.relative_to(folder) for p in folder.rglob("*") if p.is_file()}


def check_answer(argv, status, stdout, stderr, folder: Path, before: set[Path], outputs: list[str],
                 escape: str | None = None):
    """The properties every run must have (see the module docstring)."""
    shown = f"cosim {' '.join(argv)}\nexit {status}\nstdout:\n{stdout[-2000:]}\nstderr:\n{stderr[-3000:]}"
    # validate: 1 = a readable FMU with problems (listed); 2 = a file it cannot read at all
    assert status in EXPECTED_STATUS | ({1} if argv[0] == "validate" else set()), shown
    assert "Traceback" not in stderr and "internal error" not in stderr, shown
    if status == 2:
        errors = [line for line in stderr.splitlines() if line.startswith("cosim") and "error" in line]
        assert len(errors) == 1, shown
    after = files_under(folder)
    partial = [p for p in after if ".partial" in p.name]
    assert not partial, f"partial files left: {partial}\n{shown}"
    if status == 2:
        for name in outputs:
            assert Path(name) not in after - before, f"refused, yet {name} was written\n{shown}"
    if escape:
        for place in {folder.parent, Path(tempfile.gettempdir()), Path("/"), Path.cwd()}:
            assert not list(place.glob(f"{escape}*")), f"{escape} escaped into {place}\n{shown}"


# --- FMU archives ---------------------------------------------------------------------------

XML_EDITS = [
    ('fmiVersion="2.0"', 'fmiVersion="3.0"'),
    ('fmiVersion="2.0"', 'fmiVersion="1.0"'),
    ('fmiVersion="2.0"', ''),
    ("guid=", "guId="),
    ("modelIdentifier=", "modelIdentifer="),
    ('causality="input"', 'causality="sideways"'),
    ('valueReference="1"', 'valueReference="0"'),  # none the binary knows (ours start at 1)
    ('valueReference="3"', 'valueReference="1"'),  # a duplicate
    ('valueReference="2"', 'valueReference="-4"'),
    ("<ModelStructure>", "<ModelStructure><Outputs><Unknown index=\"9999\"/></Outputs>"),
    ('numberOfEventIndicators="0"', 'numberOfEventIndicators="x"'),
    ("<Real", "<Reel"),
    ("</fmiModelDescription>", ""),
]


#: The same for an FMI 3.0 FMU (the Reference VanDerPol: instantiationToken, typed variables,
#: ModelStructure with ContinuousStateDerivative, the independent time).
FMI3_XML_EDITS = [
    ('fmiVersion="3.0"', 'fmiVersion="2.0"'),
    ('fmiVersion="3.0"', 'fmiVersion="3.9"'),
    ("instantiationToken=", "instantiationTokn="),
    ('instantiationToken="{BD4', 'instantiationToken="{0D4'),
    ('modelIdentifier="VanDerPol"', 'modelIdentifier="Other"'),
    ('causality="independent"', 'causality="output"'),
    ('valueReference="3"', 'valueReference="1"'),
    ('derivative="1"', 'derivative="99"'),
    ('derivative="3"', 'derivative="5"'),
    ('<Float64 name="mu"', '<Float46 name="mu"'),
    ('<ContinuousStateDerivative valueReference="4"/>', ""),
    ('<Output valueReference="3"/>', '<Output valueReference="77"/>'),
    ('start="2"', 'start="x"'),
    ('variability="fixed"', 'variability="constant"'),
    ("</fmiModelDescription>", ""),
]


@st.composite
def fmu_archives(draw, original: bytes, escape: str, xml_edits=tuple(XML_EDITS)):
    """Bytes of a damaged FMU: random bytes, a truncation, a traversal member, or a damaged
    modelDescription.xml (``xml_edits``) in an otherwise real archive."""
    kind = draw(st.sampled_from(["random", "truncated", "traversal", "xml-cut", "xml-edit", "xml-missing",
                                 "xml-noise", "binary-missing"]))
    if kind == "random":
        return draw(st.binary(max_size=4096))
    if kind == "truncated":
        return original[:draw(st.integers(0, len(original) - 1))]
    with zipfile.ZipFile(io.BytesIO(original)) as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    xml = members["modelDescription.xml"].decode()
    if kind == "traversal":
        name = draw(st.sampled_from([f"../{escape}", f"../../{escape}", f"/tmp/{escape}",
                                     f"binaries/../../{escape}", f"./../{escape}"]))
        members[name] = b"escaped"
    elif kind == "xml-cut":
        members["modelDescription.xml"] = xml[:draw(st.integers(0, len(xml) - 1))].encode()
    elif kind == "xml-edit":
        edits = draw(st.lists(st.sampled_from(list(xml_edits)), min_size=1, max_size=3, unique=True))
        for old, new in edits:
            xml = xml.replace(old, new, 1)
        members["modelDescription.xml"] = xml.encode()
    elif kind == "xml-missing":
        del members["modelDescription.xml"]
    elif kind == "xml-noise":
        position = draw(st.integers(0, len(xml) - 1))
        noise = draw(st.binary(min_size=1, max_size=16))
        members["modelDescription.xml"] = xml.encode()[:position] + noise + xml.encode()[position:]
    elif kind == "binary-missing":
        members = {n: b for n, b in members.items() if not n.startswith("binaries/")}
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, data in members.items():
            archive.writestr(zipfile.ZipInfo(name), data)
    return buffer.getvalue()


@pytest.mark.parametrize("verb", ["info", "validate", "simulate", "linearize", "run"])
def test_damaged_fmu_gets_one_message(verb, real_fmus):
    original = real_fmus["simple"].read_bytes()
    escape = f"cosim-escape-{uuid.uuid4().hex}"

    @SETTINGS
    @given(data=fmu_archives(original, escape))
    def property_(data):
        _answer_damaged_fmu(data, verb, escape)

    property_()


def _answer_damaged_fmu(data: bytes, verb: str, escape: str) -> None:
    """``cosim VERB`` on the damaged FMU ``data`` (as model.fmu in a fresh folder; ``simulate-me``:
    simulate as Model Exchange, ``run``: a one-component system): one clear answer (check_answer)."""
    with tempfile.TemporaryDirectory(prefix="cosim-hostile-") as tmp:
        folder = Path(tmp) / "work"
        folder.mkdir()
        (folder / "model.fmu").write_bytes(data)
        outputs = []
        if verb.startswith("simulate"):
            argv, outputs = ["simulate", "model.fmu", "--stop-time", "0.5", "-o", "out.csv"], ["out.csv"]
            if verb == "simulate-me":
                argv += ["--fmi-type", "me"]
        elif verb == "run":
            (folder / "system.toml").write_text(
                'connections = []\n[system]\nstop = 0.5\nstep = 0.1\n[components.bike]\nfmu = "model.fmu"\n')
            argv, outputs = ["run", "system.toml", "-o", "out.csv"], ["out.csv"]
        else:
            argv = [verb, "model.fmu"]
        before = files_under(folder)
        status, out, err = run(argv, folder)
        check_answer(argv, status, out, err, folder, before, outputs, escape)


@pytest.fixture(scope="module")
def fmi3_fmu(tmp_path_factory):
    """A foreign FMI 3.0 FMU with ME, CS, directional and adjoint derivatives: the Reference
    VanDerPol compiled from the vendored sources (tests/reference_fmus.py)."""
    from reference_fmus import reference_fmu

    return reference_fmu("VanDerPol", tmp_path_factory.mktemp("fmi3"))


@pytest.mark.parametrize("verb", ["info", "simulate", "simulate-me", "linearize"])
def test_damaged_fmi3_fmu_gets_one_message(verb, fmi3_fmu):
    original = fmi3_fmu.read_bytes()
    escape = f"cosim-escape-{uuid.uuid4().hex}"

    @SETTINGS
    @given(data=fmu_archives(original, escape, tuple(FMI3_XML_EDITS)))
    def property_(data):
        _answer_damaged_fmu(data, verb, escape)

    property_()


# --- system files ---------------------------------------------------------------------------


scalars = st.one_of(st.booleans(), st.integers(-10**6, 10**6), st.floats(allow_nan=True, allow_infinity=True),
                    st.text(max_size=12))
anything = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                         st.dictionaries(st.text(max_size=6), inner, max_size=3)),
                        max_leaves=6)


def maybe(key_values: dict):
    """Each key: absent, a plausible value or anything at all."""
    return st.fixed_dictionaries({}, optional={k: st.one_of(v, anything) for k, v in key_values.items()})


SIGNALS = ["bike.phi", "bike.delta", "bike.T", "rider.T", "rider.phi", "ctl.y", "bike", "x.y.z", ""]
system_settings = maybe({
    "name": st.text(max_size=8), "start": st.floats(-1, 1), "stop": st.floats(-1, 3),
    "step": st.one_of(st.floats(0, 3), st.sampled_from([0.3, 0.1, 0.05])),
    "algorithm": st.sampled_from(["jacobi", "gauss-seidel", "JACOBI", "newton"]),
    "initialize": st.booleans(), "sampling": st.sampled_from(["after-step", "after-transfer", "never"]),
    "fall": st.fixed_dictionaries({}, optional={"signal": st.sampled_from(SIGNALS), "limit": st.floats(-2, 2)}),
    "record": st.lists(st.sampled_from(SIGNALS), max_size=3),
})
bike = maybe({"fmu": st.just("simple.fmu"), "parameters": st.dictionaries(
    st.sampled_from(["V", "m", "T", "phi", "nope", "solver.fixedStepSize"]),
    st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-5, 5), st.text(max_size=4)), max_size=3),
    "step_multiple": st.one_of(st.integers(-2, 3), st.floats(0, 3)), "params": st.sampled_from(["benchmark", "x"])})
rider = maybe({"python": st.sampled_from(["Proportional", "PD", "TransportDelay", "Nope"]),
               "parameters": st.dictionaries(st.sampled_from(["k", "kp", "kd", "tau", "zz"]),
                                             st.one_of(st.floats(allow_nan=True), st.text(max_size=3)), max_size=2)})
systems = st.fixed_dictionaries(
    {"connections": st.one_of(st.lists(st.sampled_from(["bike.phi -> rider.phi", "rider.T -> bike.T",
                                                        "bike.delta -> rider.u", "rider.y -> bike.T", "a -> b",
                                                        "bike.phi -> bike.T", "rider.T -> bike.T"]), max_size=3),
                              anything)},
    optional={"system": st.one_of(system_settings, anything),
              "components": st.one_of(st.fixed_dictionaries({}, optional={"bike": bike, "rider": rider}), anything)})


def system_toml(data: dict) -> str:
    lines = [f"connections = {toml_value(data['connections'])}"]
    if "system" in data:
        lines.append(f"system = {toml_value(data['system'])}")
    if "components" in data:
        lines.append(f"components = {toml_value(data['components'])}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("verb", ["run", "export-ssp"])
def test_generated_system_files_get_a_result_or_one_message(verb, real_fmus):
    @SETTINGS
    @given(data=systems)
    def property_(data):
        with tempfile.TemporaryDirectory(prefix="cosim-hostile-") as tmp:
            folder = Path(tmp)
            (folder / "simple.fmu").write_bytes(real_fmus["simple"].read_bytes())
            (folder / "system.toml").write_text(system_toml(data))
            output = "out.csv" if verb == "run" else "out.ssp"
            argv = [verb, "system.toml", "-o", output]
            before = files_under(folder)
            status, out, err = run(argv, folder)
            check_answer(argv, status, out, err, folder, before, [output])

    property_()


# --- parameter files and input CSVs ---------------------------------------------------------

MEIJAARD_KEYS = ["w", "c", "lam", "g", "rR", "mR", "IRxx", "IRyy", "xB", "zB", "mB", "IBxx", "IByy", "IBzz",
                 "IBxz", "xH", "zH", "mH", "IHxx", "IHyy", "IHzz", "IHxz", "rF", "mF", "IFxx", "IFyy"]
parameter_files = st.dictionaries(
    st.one_of(st.sampled_from(MEIJAARD_KEYS), st.text(max_size=5)),
    st.one_of(st.floats(-5, 5), st.floats(allow_nan=True, allow_infinity=True), st.integers(-3, 3),
              st.text(max_size=4), st.booleans(), st.lists(st.floats(0, 1), max_size=2)),
    max_size=30)


def test_generated_parameter_files_get_a_result_or_one_message(real_fmus):
    from cosim.analytic.parameters import load_parameters  # the benchmark values as a base

    base = dict(load_parameters("benchmark"))

    @SETTINGS
    @given(changes=parameter_files, drop=st.lists(st.sampled_from(MEIJAARD_KEYS), max_size=3),
           garbage=st.one_of(st.none(), st.text(max_size=40)))
    def property_(changes, drop, garbage):
        values = {k: v for k, v in {**base, **changes}.items() if k not in drop}
        with tempfile.TemporaryDirectory(prefix="cosim-hostile-") as tmp:
            folder = Path(tmp)
            text = garbage if garbage is not None else \
                "\n".join(f"{toml_value(str(k))} = {toml_value(v)}" for k, v in values.items())
            (folder / "set.toml").write_text(text)
            argv = ["linearize", str(real_fmus["whipple"]), "--params", "set.toml", "--json"]
            status, out, err = run(argv, folder)
            check_answer(argv, status, out, err, folder, files_under(folder), [])

    property_()


csv_cells = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers(-3, 30).map(str),
                      st.sampled_from(["", "nan", "inf", "-inf", "x", "1e400", " 1", "1,2"]))
csv_files = st.tuples(
    st.sampled_from(["time,T", "t,value", "", "time", "time,T,extra", "# comment"]),
    st.lists(st.lists(csv_cells, min_size=0, max_size=3), max_size=6))


def test_generated_input_csvs_get_a_result_or_one_message(real_fmus):
    @SETTINGS
    @given(csv=csv_files, kind=st.sampled_from(["cs", "me"]))
    def property_(csv, kind):
        header, rows = csv
        with tempfile.TemporaryDirectory(prefix="cosim-hostile-") as tmp:
            folder = Path(tmp)
            (folder / "in.csv").write_text("\n".join([header, *(",".join(r) for r in rows)]) + "\n")
            argv = ["simulate", str(real_fmus["simple"]), "--stop-time", "1", "--fmi-type", kind,
                    "--input", "T=in.csv", "-o", "out.csv"]
            before = files_under(folder)
            status, out, err = run(argv, folder)
            check_answer(argv, status, out, err, folder, before, ["out.csv"])

    property_()
