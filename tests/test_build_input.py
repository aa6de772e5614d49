"""Bad Modelica input and bad build arguments: one Modelica-level message (file:line, the class,
the name), a non-zero exit, no traceback, nothing written; one broken file does not stop the rest."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from conftest import bound_by_permissions, hide_shipped_library, run_cli
from cosim.compiler.catalog import catalog, summarize
from cosim.compiler import build as build_module
from cosim.compiler.build import build, build_model
from cosim.compiler.library import Library
from cosim.errors import ModelicaError, ModelStructureError, OutputError, ParameterError

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

DECAY = """within Broken;
model Decay "dx/dt = -x"
  Real x(start = 1, fixed = true) "state";
equation
  der(x) = -x;
  annotation(__Cosim(export = true));
end Decay;
"""


def model(name: str, body: str, annotation: str = "") -> str:
    """A model ``Broken.NAME`` whose declarations and equations are ``body``."""
    return f'within Broken;\nmodel {name} "test model {name}"\n{body}\n{annotation}end {name};\n'


def small_library(tmp_path: Path, files: dict[str, str | bytes]) -> Path:
    """A library folder holding only the package ``Broken`` with the given files (class name ->
    text or raw bytes), built and listed alone (:func:`hide_shipped_library`)."""
    package = hide_shipped_library(tmp_path / "lib") / "Broken"
    package.mkdir(parents=True)
    (package / "package.mo").write_text('within;\npackage Broken "models for tests"\nend Broken;\n')
    (package / "package.order").write_text("".join(f"{name}\n" for name in files))
    for name, text in files.items():
        path = package / f"{name}.mo"
        path.write_bytes(text) if isinstance(text, bytes) else path.write_text(text, encoding="utf-8")
    return tmp_path / "lib"


def refused(library: Path, name: str, error=ModelicaError) -> str:
    """The message of building ``Broken.NAME`` in-process (it must fail with ``error``)."""
    with pytest.raises(error) as info:
        build_model(f"Broken.{name}", library.parent / "out", Library(library))
    assert not (library.parent / "out").exists() or not any((library.parent / "out").iterdir())
    return str(info.value)


def assert_one_message(result, *fragments):
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("cosim ")]
    assert len(lines) == 1, result.stderr
    for fragment in fragments:
        assert fragment in result.stderr, result.stderr


# --- 3. output folder ------------------------------------------------------------------------

def _unwritable(tmp_path: Path, case: str) -> tuple[Path, str]:
    blocker = tmp_path / "blocker"
    blocker.write_text("a file\n")
    if case == "output-is-a-file":
        return blocker, "is a file, not a folder"
    if case == "file-in-the-way":
        return blocker / "fmus", "is a file, not a folder"
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    return locked / "fmus", "is not writable"


@pytest.mark.parametrize("case", ["output-is-a-file", "file-in-the-way", "read-only-folder"])
def test_build_into_unwritable_output_is_refused_before_any_work(tmp_path, monkeypatch, case):
    output, message = _unwritable(tmp_path, case)
    library = small_library(tmp_path, {"Decay": DECAY})

    def no_work(*args, **kwargs):
        raise AssertionError("the model was flattened before the output was checked")

    def refused():
        result = run_cli("build", "Broken.Decay", "--library", str(library), "-o", str(output), "-j", "1")
        assert_one_message(result, message, str(output))
        monkeypatch.setattr(build_module, "flatten", no_work)
        for call in (lambda: build(["Broken.Decay"], output, library_path=str(library)),
                     lambda: build_model("Broken.Decay", output, Library(library))):
            with pytest.raises(OutputError, match=message):
                call()

    # a read-only folder: in a child that its mode binds, as root too
    bound_by_permissions(refused, output.parent) if case == "read-only-folder" else refused()
    assert not (tmp_path / "blocker").is_dir() and not list(tmp_path.rglob("*.fmu"))


def test_fmu_name_taken_by_a_folder_is_refused(tmp_path):
    library = small_library(tmp_path, {"Decay": DECAY})
    (tmp_path / "out" / "Broken_Decay.fmu").mkdir(parents=True)
    result = run_cli("build", "Broken.Decay", "--library", str(library), "-o", str(tmp_path / "out"), "-j", "1")
    assert_one_message(result, "Broken_Decay.fmu", "a folder of that name is in the way")


# --- 8. -j ------------------------------------------------------------------------------------

@pytest.mark.parametrize("jobs", [0, -2], ids=["zero", "negative"])
def test_build_jobs_below_one_is_refused(tmp_path, jobs):
    with pytest.raises(ParameterError, match=r"-j/--jobs must be >= 1"):
        build(["Bicycle.Control.PD"], tmp_path / "out", jobs=jobs)
    assert not (tmp_path / "out").exists()


# --- 4. encoding, empty files -----------------------------------------------------------------

def test_modelica_file_not_utf8_is_named_with_line_and_offset(tmp_path):
    text = model("Latin", '  Real x(start = 1, fixed = true) "caf\xe9";\nequation\n  der(x) = -x;')
    library = small_library(tmp_path, {"Latin": text.encode("latin-1"), "Decay": DECAY})
    offset = text.encode("latin-1").index(b"\xe9")
    message = refused(library, "Latin")
    assert f"{library / 'Broken' / 'Latin.mo'}:3:" in message
    assert "not UTF-8" in message and f"byte offset {offset}" in message and "0xe9" in message
    result = run_cli("build", "Broken.Latin", "--library", str(library), "-o", str(tmp_path / "out"))
    assert_one_message(result, "Latin.mo:3:", "not UTF-8")


@pytest.mark.parametrize("content", [b"", b"  \n\t\n"], ids=["empty", "blank"])
def test_empty_modelica_file_is_named(tmp_path, content):
    library = small_library(tmp_path, {"Nothing": content, "Decay": DECAY})
    message = refused(library, "Nothing")
    assert f"{library / 'Broken' / 'Nothing.mo'}: empty file" in message


def test_file_with_another_class_than_its_name_is_named(tmp_path):
    library = small_library(tmp_path, {"Wrong": model("Other", "  Real x;\nequation\n  x = 1;"), "Decay": DECAY})
    message = refused(library, "Wrong")
    assert "Wrong.mo:2:" in message and "exactly the class 'Wrong'" in message and "'Other'" in message


# --- 6. one broken file -----------------------------------------------------------------------

USER = model("User", "  Broken.Bad inner_ \"uses the broken class\";\n  Real y(start = 0, fixed = true);\n"
             "equation\n  der(y) = inner_.x;", "  annotation(__Cosim(export = true));\n")
BAD = ('within Broken;\nmodel Bad "syntax error"\n  Real x(start = 1, fixed = true)\nequation\n  der(x) = -x;\n'
       'end Bad;\n')


def test_one_broken_file_does_not_block_building_the_others(tmp_path):
    library = small_library(tmp_path, {"Bad": BAD, "User": USER, "Decay": DECAY})
    bad = library / "Broken" / "Bad.mo"
    parsed = Library(library)
    assert list(parsed.errors) == [bad] and "Broken.Decay" in parsed.entries
    out = tmp_path / "out"
    # A model that does not need the broken file builds.
    result = run_cli("build", "Broken.Decay", "--library", str(library), "-o", str(out), "-j", "1")
    assert result.returncode == 0, result.stderr
    assert (out / "Broken_Decay.fmu").is_file()
    # The broken file's model and a model using its class fail with its file:line:col.
    for name, need in (("Bad", "Broken.Bad is defined in this file"),
                       ("User", "Broken.User uses Broken.Bad, which is defined in this file")):
        result = run_cli("build", f"Broken.{name}", "--library", str(library), "-o", str(out), "-j", "1")
        assert_one_message(result, f"{bad}:4:1: syntax error", need)
    # Building everything exported builds what it can, then fails naming the file.
    (out / "Broken_Decay.fmu").unlink()
    result = run_cli("build", "--library", str(library), "-o", str(out), "-j", "1")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert f"{bad}:4:1: syntax error" in result.stderr
    assert sorted(p.name for p in out.iterdir()) == ["Broken_Decay.fmu"]


def test_list_shows_what_parsed_and_warns_once_per_broken_file(tmp_path):
    library = small_library(tmp_path, {"Bad": BAD, "User": USER, "Decay": DECAY})
    result = run_cli("list", "--library", str(library))
    assert result.returncode == 0, result.stderr
    assert "Broken.Decay" in result.stdout and "Broken.User" not in result.stdout
    warnings = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(warnings) == 1, result.stderr
    assert "warning" in warnings[0] and f"{library / 'Broken' / 'Bad.mo'}:4:1" in warnings[0]
    assert "not listed: Broken.User" in warnings[0]
    messages = []
    assert [s.name for s in catalog(Library(library), warn=messages.append)] == ["Broken.Decay"]
    assert len(messages) == 1 and "Bad.mo:4:1" in messages[0]


def test_unwritable_parse_cache_does_not_stop_the_compiler(tmp_path):
    library = small_library(tmp_path, {"Decay": DECAY})
    blocker = tmp_path / "cache-is-a-file"
    blocker.write_text("")
    result = run_cli("list", "--library", str(library), env={"XDG_CACHE_HOME": str(blocker)})
    assert result.returncode == 0 and "Broken.Decay" in result.stdout, result.stderr


# --- 5. undeclared variables, undefined functions ---------------------------------------------

INNER = model("Inner", "  Real x(start = 1, fixed = true);\nequation\n  der(x) = -k*x;")
UNDECLARED = {
    "in-equation": ({"Eq": model("Eq", "  Real x(start = 1, fixed = true) \"k is not declared\";\nequation\n"
                                       "  der(x) = -k*x;")},
                    "Eq", ["Eq.mo:5:", "Broken.Eq:", "undeclared variable 'k'"]),
    "in-binding": ({"Bind": model("Bind", "  parameter Real a = b;\n  Real x(start = 1, fixed = true);\nequation\n"
                                          "  der(x) = -a*x;")},
                   "Bind", ["Bind.mo:3:", "Broken.Bind:", "undeclared name 'b'"]),
    "in-component": ({"Inner": INNER, "Outer": model("Outer", "  Broken.Inner c;\n  Real y(start = 0, fixed = true);"
                                                              "\nequation\n  der(y) = c.x;")},
                     "Outer", ["Inner.mo:5:", "Broken.Inner:", "undeclared variable 'k'", "(in Broken.Outer)"]),
    "qualified": ({"Qual": model("Qual", "  Real x(start = 1, fixed = true);\nequation\n  der(x) = -Broken.K.g*x;")},
                  "Qual", ["Qual.mo:5:", "undeclared variable 'Broken.K.g'"]),
    "unknown-class": ({"Type": model("Type", "  NoSuch.Thing a;\n  Real x(start = 1, fixed = true);\nequation\n"
                                             "  der(x) = -x;")},
                      "Type", ["Type.mo:3:", "unknown class 'NoSuch.Thing' (the type of component 'a')"]),
}


@pytest.mark.parametrize("case", list(UNDECLARED))
def test_undeclared_variable_gets_modelica_message(tmp_path, case):
    files, name, fragments = UNDECLARED[case]
    library = small_library(tmp_path, files)
    message = refused(library, name)
    for fragment in fragments:
        assert fragment in message, message
    assert "KeyError" not in message and "cannot translate" not in message


UNDEFINED = {
    "local-name": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -twice(x);", "'twice'"),
    "qualified": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -Broken.Funcs.twice(x);",
                  "'Broken.Funcs.twice'"),
}


@pytest.mark.parametrize("case", list(UNDEFINED))
def test_call_of_undefined_function_gets_modelica_message(tmp_path, case):
    body, quoted = UNDEFINED[case]
    library = small_library(tmp_path, {"Calls": model("Calls", body)})
    message = refused(library, "Calls")
    assert "Calls.mo:5:" in message and "Broken.Calls:" in message
    assert f"call of undefined function {quoted}" in message, message
    assert "MX" not in message and "Unknown function" not in message
    result = run_cli("build", "Broken.Calls", "--library", str(library), "-o", str(tmp_path / "out"))
    assert_one_message(result, "Calls.mo:5:", quoted)


TWICE = """within Broken;
function Twice "2 u"
  input Real u;
  output Real y;
algorithm
  y := 2*u;
end Twice;
"""
LOCAL = model("Local", """  function thrice "3 u"
    input Real u;
    output Real y;
  algorithm
    y := 3*u;
  end thrice;
  Real x(start = 1, fixed = true);
equation
  der(x) = -thrice(x) + Broken.Twice(x);""")


def test_local_and_library_functions_compile_and_evaluate(tmp_path):
    """CasADi refused pymoca's dotted function names; now der(x) = -3x + 2x = -x."""
    from fmpy import simulate_fmu

    library = small_library(tmp_path, {"Twice": TWICE, "Local": LOCAL})
    fmu = build_model("Broken.Local", tmp_path / "out", Library(library)).fmu
    result = simulate_fmu(str(fmu), stop_time=1.0, output=["x"])
    assert result["x"][-1] == pytest.approx(math.exp(-1.0), rel=1e-6)


def test_noevent_smooth_and_homotopy_pass_their_argument(tmp_path):
    from fmpy import simulate_fmu

    body = "  Real x(start = 1, fixed = true);\nequation\n  der(x) = -noEvent(abs(x)) - smooth(1, x) + homotopy(x, 0);"
    library = small_library(tmp_path, {"Smooth": model("Smooth", body)})
    fmu = build_model("Broken.Smooth", tmp_path / "out", Library(library)).fmu
    result = simulate_fmu(str(fmu), stop_time=1.0, output=["x"])
    assert result["x"][-1] == pytest.approx(math.exp(-1.0), rel=1e-6)


# --- 7. fixed ---------------------------------------------------------------------------------

# A state with fixed = false is solved from initial equations (tests/test_initial_equations.py);
# these attributes ask for an initialization problem that cosim does not solve.
FIXED = {
    "state-fixed-expression": ("  parameter Boolean f = true;\n  Real x(start = 1, fixed = f);\nequation\n"
                               "  der(x) = -x;", ["Fixed.mo:4:", "state 'x' has fixed = <expression>"]),
    "parameter-fixed-false": ("  parameter Real k(fixed = false) = 1;\n  Real x(start = 1, fixed = true);\nequation\n"
                              "  der(x) = -k*x;", ["Fixed.mo:3:", "parameter 'k' has fixed = false"]),
    "algebraic-fixed-true": ("  Real x(start = 1, fixed = true);\n  Real y(start = 2, fixed = true);\nequation\n"
                             "  der(x) = -y;\n  y = x;", ["Fixed.mo:4:", "'y' is not a state but has fixed = true"]),
}


@pytest.mark.parametrize("case", list(FIXED))
def test_unsupported_fixed_attributes_are_refused_naming_variable_and_file(tmp_path, case):
    body, fragments = FIXED[case]
    library = small_library(tmp_path, {"Fixed": model("Fixed", body)})
    message = refused(library, "Fixed", ModelStructureError)
    for fragment in fragments:
        assert fragment in message, message
    assert "initial" in message


def test_state_without_fixed_starts_from_its_start_value(tmp_path):
    """No ``fixed`` at all: the start value is the initial value (what other tools do too)."""
    from fmpy import simulate_fmu

    library = small_library(tmp_path, {"Plain": model("Plain", "  Real x(start = 2);\nequation\n  der(x) = -x;")})
    fmu = build_model("Broken.Plain", tmp_path / "out", Library(library)).fmu
    result = simulate_fmu(str(fmu), stop_time=1.0, output=["x"])
    assert result["x"][0] == 2.0 and result["x"][-1] == pytest.approx(2 * math.exp(-1.0), rel=1e-6)


# --- 9. declared types ------------------------------------------------------------------------

def test_model_parameters_report_declared_type(tmp_path):
    pade = {p.name: p.type for p in summarize("Bicycle.Rider.PadeDelay").parameters}
    assert pade == {"tau": "Real", "n": "Integer"}
    body = ("  parameter Integer n = 2 \"order\";\n  parameter Boolean on = true \"switch\";\n"
            "  parameter Bicycle_Angle a = 0.1 \"angle\";\n  type Bicycle_Angle = Real(unit = \"rad\");\n"
            "  Real x(start = 1, fixed = true);\nequation\n  der(x) = if on then -n*a*x else 0;")
    library = small_library(tmp_path, {"Typed": model("Typed", body)})
    declared = {p.name: p.type for p in summarize("Broken.Typed", Library(library)).parameters}
    assert declared == {"n": "Integer", "on": "Boolean", "a": "Real"}


def test_integer_parameter_given_a_fraction_is_refused_by_model_name(tmp_path):
    """The declared type reaches the parameter check: n of the Pade delay is an Integer."""
    out = tmp_path / "r.csv"
    result = run_cli("simulate", "Bicycle.Rider.PadeDelay", "--param", "n=2.5", "--stop-time", "1", "-o", str(out))
    assert_one_message(result, "parameter 'n'", "Integer", "2.5")
    assert not out.exists()


# --- other bad Modelica input -----------------------------------------------------------------

UNSUPPORTED = {
    "when": ("  Real x(start = 1, fixed = true);\n  discrete Real y;\nequation\n  der(x) = -x;\n  when x < 0.5 then\n"
             "    y = 1;\n  end when;", ["Odd.mo:7:", "when-equations are not supported"]),
    "algorithm": ("  Real x(start = 1, fixed = true);\n  Real y;\nequation\n  der(x) = -y;\nalgorithm\n  y := 2*x;",
                  ["Odd.mo:7:", "algorithm sections are supported only inside functions"]),
    "der-der": ("  Real x(start = 1, fixed = true);\nequation\n  der(der(x)) = -x;",
                ["Odd.mo:5:", "der(der(x)) is not supported"]),
    "string-variable": ("  String s = \"a\";\n  Real x(start = 1, fixed = true);\nequation\n  der(x) = -x;",
                        ["Odd.mo:3:", "String variable 's'"]),
    "enumeration": ("  type E = enumeration(a, b);\n  parameter E e = E.a;\n  Real x(start = 1, fixed = true);\n"
                    "equation\n  der(x) = if e == E.a then -x else x;", ["Odd.mo:3:", "enumeration types ('E')"]),
    "pre": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -pre(x);",
            ["Odd.mo:5:", "the built-in 'pre()' is not supported"]),
    "assert": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -x;\n  assert(x > 0, \"positive\");",
               ["Odd.mo:6:", "'assert(...)' as an equation is not supported"]),
    "integer-state": ("  Integer i(start = 1, fixed = true);\nequation\n  der(i) = -i;",
                      ["Odd.mo:3:", "der() of the Integer variable 'i'"]),
    "min-above-max": ("  parameter Real k(min = 2, max = 1) = 1.5;\n  Real x(start = 1, fixed = true);\nequation\n"
                      "  der(x) = -k*x;", ["Odd.mo:3:", "parameter 'k' has min = 2 > max = 1"]),
    "value-out-of-range": ("  parameter Real k(min = 0) = -1;\n  Real x(start = 1, fixed = true);\nequation\n"
                           "  der(x) = -k*x;", ["Odd.mo:3:", "the value -1 of parameter 'k' is outside"]),
    "experiment-expression": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -x;",
                              ["Odd.mo:6:", "experiment(StopTime = ...) must be a finite literal number"]),
    "experiment-negative-tolerance": ("  Real x(start = 1, fixed = true);\nequation\n  der(x) = -x;",
                                      ["Odd.mo:6:", "experiment(Tolerance = -1) must be positive"]),
}
ANNOTATIONS = {"experiment-expression": "  annotation(experiment(StopTime = 2*5));\n",
               "experiment-negative-tolerance": "  annotation(experiment(Tolerance = -1));\n"}


@pytest.mark.parametrize("case", list(UNSUPPORTED))
def test_unsupported_modelica_gets_modelica_message(tmp_path, case):
    body, fragments = UNSUPPORTED[case]
    library = small_library(tmp_path, {"Odd": model("Odd", body, ANNOTATIONS.get(case, ""))})
    message = refused(library, "Odd", (ModelicaError, ModelStructureError))
    for fragment in fragments:
        assert fragment in message, message
    assert "Broken.Odd" in message


def test_partial_model_is_named_as_partial(tmp_path):
    text = 'within Broken;\npartial model Base "a base class"\n  Real x;\nend Base;\n'
    library = small_library(tmp_path, {"Base": text})
    result = run_cli("build", "Broken.Base", "--library", str(library), "-o", str(tmp_path / "out"))
    assert_one_message(result, "'Broken.Base' is a partial model")
    result = run_cli("info", "Broken.Base", env={"COSIM_MODELICA_PATH": str(library)})
    assert_one_message(result, "'Broken.Base' is a partial model")
