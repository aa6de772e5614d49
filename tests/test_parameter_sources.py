"""One source of parameter values: the TOML files in cosim/params/.

* the Modelica records ``Bicycle.Records`` are generated from them (drift test: a fresh generation
  into ``tmp_path`` equals the committed files byte for byte);
* the rider's upper body split off the benchmark's rear frame recombines to the benchmark (1e-12);
* the second-order models' defaults and ``cosim.analytic.simple.SimpleBicycle`` equal the TOML;
* the values appear in no other .mo/.py/.toml file than the sources, the generated records and an
  allow-list of files that check published results (each with its reason);
* the component-assembled ``WhippleLinear`` equals ``cosim.analytic.whipple`` for random physically
  valid bicycles: M, C1, K0, K2 to 1e-12 of the matrix's largest element, the state matrices A, B to
  rtol 1e-12 (the bundled sets are covered by tests/test_whipple_linear.py);
* another data set is one ``redeclare package Data``.
"""
from __future__ import annotations

import math
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import calculated_parameters
from cosim.analytic import parameters as P
from cosim.analytic import records as R
from cosim.analytic import whipple as W
from cosim.analytic.simple import SimpleBicycle
from cosim.compiler.catalog import summarize
from cosim.compiler.library import DEFAULT_LIBRARY, Library
from cosim.bicycle import stability as WP

ROOT = Path(__file__).resolve().parents[1]
RECORDS = ROOT / "modelica" / "Bicycle" / "Records"

# --------------------------------------------------------------------------- generated records


def test_records_are_generated_from_the_toml_files(tmp_path):
    """Regenerating into tmp_path gives the committed files byte for byte."""
    R.write(tmp_path)
    generated = sorted(p.name for p in tmp_path.iterdir())
    assert generated == sorted(R.records())
    for name in generated:
        assert (RECORDS / name).read_bytes() == (tmp_path / name).read_bytes(), \
            f"{RECORDS / name} is stale: run {R.COMMAND}"
    # Every class file of the package is generated (package.mo, the hand-written doc, excepted).
    committed = sorted(p.name for p in RECORDS.iterdir() if p.name != "package.mo")
    assert committed == generated


def test_check_mode_detects_a_hand_edit(tmp_path):
    R.write(tmp_path)
    path = tmp_path / "Benchmark.mo"
    path.write_text(path.read_text().replace("= 0.28 ", "= 0.29 "))
    assert R.stale(tmp_path) == ["Benchmark.mo"]
    assert R.main(["--check", "-o", str(tmp_path)]) == 1
    R.write(tmp_path)
    assert R.main(["--check", "-o", str(tmp_path)]) == 0


@pytest.mark.parametrize("stem", P.bundled_parameter_sets())
def test_record_values_round_trip(stem):
    """Each constant of a data-set record parses back to the TOML float exactly."""
    name, _ = R._class_name(stem)
    text = (RECORDS / f"{name}.mo").read_text()
    found = {m.group(1): float(m.group(2)) for m in re.finditer(r"constant Real (\w+)\([^)]*\) = (\S+) ", text)}
    assert found == P.load_parameters(stem)


# --------------------------------------------------------------------------- rider split

def test_upper_body_split_recombines_to_the_benchmark_rear_frame():
    bench, upper = P.load_parameters("benchmark"), P.load_upper_body("benchmark")
    split = P.split_upper_body(bench, upper)
    m1, m2 = split["mB"], upper["mU"]
    x1, z1, x2, z2 = split["xB"], split["zB"], upper["xU"], -(upper["hU"] + upper["lU"])
    m = m1 + m2
    xc, zc = (m1 * x1 + m2 * x2) / m, (m1 * z1 + m2 * z2) / m
    assert m == pytest.approx(bench["mB"], rel=1e-15)
    assert (xc, zc) == pytest.approx((bench["xB"], bench["zB"]), rel=1e-12, abs=1e-15)

    def composite(k, dx1, dz1, dx2, dz2):
        parallel = {"xx": lambda dx, dz: dz**2, "yy": lambda dx, dz: dx**2 + dz**2,
                    "zz": lambda dx, dz: dx**2, "xz": lambda dx, dz: -dx * dz}[k]
        return split[f"IB{k}"] + upper[f"IU{k}"] + m1 * parallel(dx1, dz1) + m2 * parallel(dx2, dz2)

    for k in ("xx", "yy", "zz", "xz"):
        got = composite(k, x1 - xc, z1 - zc, x2 - xc, z2 - zc)
        assert got == pytest.approx(bench[f"IB{k}"], rel=1e-12, abs=1e-12), k
    # The split set is still a physically valid Whipple bicycle.
    P.validate_parameters({k: split[k] for k in P.PARAMETER_NAMES})


@pytest.mark.parametrize("model, expected", [("Whipple", lambda: P.load_parameters("benchmark")),
                                             ("WhippleRider", P.rider_parameters)], ids=["Whipple", "WhippleRider"])
def test_generated_oracle_defaults_are_the_data_sets(model, expected):
    """The committed oracle models (tests/oracle, written by cosim.nonlinear.generate) carry exactly the
    data set's values (the rider model: the benchmark with the upper body split off)."""
    text = (ROOT / "tests" / "oracle" / "BicycleOracle" / f"{model}.mo").read_text()
    defaults = {m.group(1): float(m.group(2))
                for m in re.finditer(r"^  parameter Real (\w+)\([^\n]*?\) = ([-+0-9.e]+) \"", text, re.M)}
    values = expected()
    assert set(values) <= set(defaults)
    assert {k: defaults[k] for k in values} == values


def test_split_refuses_an_upper_body_heavier_than_the_frame():
    bench = P.load_parameters("benchmark")
    with pytest.raises(ValueError, match=r"^mU: the upper body must be lighter"):
        P.split_upper_body(bench, {**P.load_upper_body("benchmark"), "mU": bench["mB"]})


@pytest.mark.parametrize("folder, loader", [("rider", P.load_upper_body), ("second-order", P.load_second_order)],
                         ids=["rider", "second-order"])
def test_unknown_sub_set_is_refused_with_the_bundled_names(folder, loader):
    with pytest.raises(ValueError, match=rf"unknown {folder} parameter set 'nope'; bundled: "):
        loader("nope")


# --------------------------------------------------------------------------- second-order models

SECOND_ORDER_MODELS = ["InvertedPendulum", "SelfStabilizing", "SelfStabilizingGyro", "RearSteered",
                       "LeaningRider", "CrownedRoller"]


@pytest.mark.parametrize("model", SECOND_ORDER_MODELS)
def test_second_order_defaults_are_the_toml(model):
    data = P.load_second_order("astrom2005")
    params = {p.name: p.value for p in summarize(f"Bicycle.Bicycles.{model}", Library(DEFAULT_LIBRARY)).parameters}
    shared = {k for k in params if k in data}
    assert {"m", "h", "b", "J", "D", "g", "V"} <= shared
    assert {k: params[k] for k in shared} == {k: data[k] for k in shared}
    text = (DEFAULT_LIBRARY / "Bicycle" / "Bicycles" / f"{model}.mo").read_text()
    for k in shared:  # the default is a reference to the record, not a copy of the number
        assert re.search(rf"parameter \S+ {k}(\([^)]*\))? = Bicycle\.Records\.Astrom2005SecondOrder\.{k} ", text), k


def test_simple_bicycle_defaults_are_the_toml():
    data, bike = P.load_second_order("astrom2005"), SimpleBicycle()
    assert (bike.m, bike.a, bike.h, bike.b, bike.c, bike.lam, bike.J, bike.D, bike.g) == \
        tuple(data[k] for k in ("m", "a", "h", "b", "c", "lambda", "J", "D", "g"))
    assert data["lambda"] == math.radians(70.0)


# --------------------------------------------------------------------------- no copies

#: Symbols not checked for copies: standard gravity is a physical constant, the default of every
#: component that feels gravity (as ``Modelica.Mechanics.MultiBody.World.g``), not a bicycle's datum.
NOT_DATA = {"g"}


def _source_values() -> dict[str, float]:
    """``{"<set>.<symbol>": value}`` of every bundled data set, without :data:`NOT_DATA`."""
    values = {}
    for stem in P.bundled_parameter_sets():
        values.update({f"{stem}.{k}": v for k, v in P.load_parameters(stem).items()})
    values.update({f"rider.{k}": v for k, v in P.load_upper_body("benchmark").items()})
    values.update({f"second-order.{k}": v for k, v in P.load_second_order("astrom2005").items()})
    return {k: v for k, v in values.items() if k.split(".", 1)[1] not in NOT_DATA}


def _distinctive(value: float) -> bool:
    """Numbers with three or more significant digits (0.05892, 96.7, 0.1405): a copy of one is no accident."""
    digits = repr(abs(value)).replace(".", "").lstrip("0").rstrip("0")
    return len(digits) >= 3 and "e" not in digits


#: Files that may contain the source values, with the reason.
ALLOWED = {
    "cosim/params/": "the source of truth",
    "modelica/Bicycle/Records/": "generated from the source (drift-tested above)",
    "tests/test_analytic_whipple.py": "published Meijaard (2007) Table 1 and results, checked against the model",
    "tests/test_whipple_linear.py": "published results (Meijaard 2007 matrices, weave/capsize speeds)",
    "tests/reference.py": "independent implementations of the paper's equations with the paper's values",
    "tests/test_analytic_simple.py": "checks the paper's printed values",
    "tests/test_simple_models.py": "analytic results of the paper (p = sqrt(m g h / J) ...)",
    "tests/test_matrix.py": "analytic predictions of the paper's claims",
    "tests/test_cli.py": "formatting of a number (96.7 as a string)",
    "tests/test_parameter_sources.py": "this test",
    "tests/oracle/": "flat test oracle generated by cosim/nonlinear/generate.py (values as literal defaults)",
    "tests/test_pymoca_patches.py": "a self-contained test library for the pymoca patches (illustrative value)",
    "cosim/compiler/pymoca_patches.py": "docstring example of the patched pymoca behaviour (illustrative value)",
}


#: The project's own source folders (a virtual environment or other untracked folder inside the checkout
#: is not the project's: its packages may hold any number).
SOURCE_FOLDERS = ("cosim", "modelica", "tests", "benchmarks", "docs")


def _tracked_files() -> list[str]:
    """The project's .mo/.py/.toml files: tracked or new (not ignored) ones in its source folders."""
    out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "--", *SOURCE_FOLDERS,
                          "*.toml", "*.py"], cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0:
        pytest.skip("not a git work tree")
    files = {f for f in out.stdout.splitlines() if "/" not in f or f.split("/", 1)[0] in SOURCE_FOLDERS}
    return sorted(f for f in files if f.endswith((".mo", ".py", ".toml")) and (ROOT / f).is_file())


def test_distinctive_values_live_only_in_their_source():
    values = {k: v for k, v in _source_values().items() if _distinctive(v)}
    assert {"benchmark.IHxx", "second-order.J", "benchmark.IFxx"} <= set(values)  # 0.05892, 96.7, 0.1405
    patterns = {k: re.compile(rf"(?<![\w.]){re.escape(repr(abs(v)))}(?![\d])") for k, v in values.items()}
    found = {}
    for name in _tracked_files():
        if any(name.startswith(a) for a in ALLOWED):
            continue
        text = (ROOT / name).read_text(errors="replace")
        hits = sorted({k.split(".", 1)[1] + "=" + repr(values[k]) for k, p in patterns.items() if p.search(text)})
        if hits:
            found[name] = hits
    assert found == {}, "copies of parameter values outside cosim/params (read the TOML or the records): " \
                        + "; ".join(f"{n}: {', '.join(h)}" for n, h in found.items())


def test_no_modelica_default_copies_a_data_value():
    """No parameter default in a .mo file (outside the records) is the literal value of the same symbol
    in a data set: the defaults refer to Bicycle.Records instead (9.2, 0.9, 85 are too common for the
    test above, but `IBxx(...) = 9.2` is a copy)."""
    values: dict[str, set[float]] = {}
    for key, v in _source_values().items():
        values.setdefault(key.split(".", 1)[1], set()).add(v)
    decl = re.compile(r"parameter\s+[\w.]+\s+(\w+)\s*(\([^)]*\))?\s*=\s*(-?[0-9][0-9.eE+-]*)\s*\"")
    found = []
    for name in _tracked_files():
        if not name.endswith(".mo") or any(name.startswith(a) for a in ALLOWED):
            continue
        for lineno, line in enumerate((ROOT / name).read_text(errors="replace").splitlines(), 1):
            m = decl.search(line)
            if m and m.group(1) in values and abs(float(m.group(3))) in {abs(v) for v in values[m.group(1)]}:
                found.append(f"{name}:{lineno}: {m.group(1)} = {m.group(3)}")
    assert found == []


def test_the_copy_detectors_can_fail(tmp_path):
    """The patterns above do find a copy (guard against a test that can never fail)."""
    probe = 'parameter Bicycle.Units.MomentOfInertia IHxx(min = 0) = 0.05892 "Front frame inertia";'
    assert re.compile(r"(?<![\w.])0\.05892(?![\d])").search(probe)
    decl = re.compile(r"parameter\s+[\w.]+\s+(\w+)\s*(\([^)]*\))?\s*=\s*(-?[0-9][0-9.eE+-]*)\s*\"")
    assert decl.search(probe).group(1, 3) == ("IHxx", "0.05892")
    assert not decl.search('parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = '
                           'Bicycle.Records.Astrom2005SecondOrder.J "J";')


# --------------------------------------------------------------------------- WhippleLinear assembly

MATRIX_NAMES = {"M11": ("M", 0, 0), "M12": ("M", 0, 1), "M21": ("M", 1, 0), "M22": ("M", 1, 1),
                "C1_12": ("C1", 0, 1), "C1_21": ("C1", 1, 0), "C1_22": ("C1", 1, 1),
                "K0_11": ("K0", 0, 0), "K0_12": ("K0", 0, 1), "K0_21": ("K0", 1, 0), "K0_22": ("K0", 1, 1),
                "K2_12": ("K2", 0, 1), "K2_22": ("K2", 1, 1)}


def _random_bicycle(seed: int) -> dict[str, float]:
    """A physically valid bicycle far from the bundled sets (validated)."""
    rng = np.random.default_rng(seed)
    u = rng.uniform
    p = {"w": u(0.6, 1.6), "lam": u(-0.5, 0.7), "g": u(1.0, 20.0), "rR": u(0.15, 0.5), "rF": u(0.15, 0.5),
         "mR": u(0.5, 6.0), "mB": u(5.0, 120.0), "mH": u(0.5, 8.0), "mF": u(0.5, 6.0),
         "xB": u(-0.2, 0.8), "zB": -u(0.3, 1.4), "xH": u(0.5, 1.4), "zH": -u(0.3, 1.2)}
    p["c"] = u(-0.2, 0.3) * p["w"]
    for wheel in ("R", "F"):
        p[f"I{wheel}xx"] = u(0.02, 0.3)
        p[f"I{wheel}yy"] = u(1.0, 2.0) * p[f"I{wheel}xx"]
    for body in ("B", "H"):
        ixx, izz = u(0.01, 10.0), u(0.01, 10.0)
        p[f"I{body}xx"], p[f"I{body}zz"] = ixx, izz
        p[f"I{body}xz"] = u(-0.9, 0.9) * math.sqrt(ixx * izz)
        p[f"I{body}yy"] = (ixx + izz) * u(0.9, 1.0)
    p = {k: p[k] for k in P.PARAMETER_NAMES}
    return P.validate_parameters(p, waive=P.WAIVABLE)


@pytest.mark.parametrize("seed", [1, 2, 3], ids=lambda s: f"seed{s}")
def test_component_whipple_linear_equals_analytic_for_a_random_bicycle(fmus, seed):
    params = _random_bicycle(seed)
    got = calculated_parameters(fmus["Bicycle.Bicycles.WhippleLinear"], MATRIX_NAMES, params)
    M, C1, K0, K2 = W.matrices(params)
    mats = {"M": M, "C1": C1, "K0": K0, "K2": K2}
    for name, (mat, i, j) in MATRIX_NAMES.items():
        expected = mats[mat][i, j]
        scale = np.abs(mats[mat]).max()
        assert abs(got[name] - expected) <= 1e-12 * scale, (name, got[name], expected)
    # The dynamics come from the connection set (the summed flows), not from these sums: the FMU's
    # state matrices (exact AD directional derivatives) equal the analytic ones.
    for v in (-2.0, 0.0, 6.5):
        A, B = WP.state_space(fmus["Bicycle.Bicycles.WhippleLinear"], params, v)
        A_ref, B_ref = W.state_matrices(params, v)
        np.testing.assert_allclose(A, A_ref, rtol=1e-12, atol=1e-12 * np.abs(A_ref).max())
        np.testing.assert_allclose(B, B_ref, rtol=1e-12, atol=1e-12 * np.abs(B_ref).max())


def test_another_data_set_is_one_redeclaration(tmp_path):
    """``extends WhippleLinear(redeclare package Data = Bicycle.Records.Astrom2005)``: every Meijaard
    parameter of the variant defaults to the astrom2005 TOML values."""
    import shutil

    lib = tmp_path / "lib"
    shutil.copytree(DEFAULT_LIBRARY / "Bicycle", lib / "Bicycle")
    bicycles = lib / "Bicycle" / "Bicycles"
    (bicycles / "WhippleLinearAstrom.mo").write_text(
        "within Bicycle.Bicycles;\nmodel WhippleLinearAstrom \"Test variant: another data set\"\n"
        "  extends Bicycle.Bicycles.WhippleLinear(redeclare package Data = Bicycle.Records.Astrom2005);\n"
        "end WhippleLinearAstrom;\n", encoding="utf-8")
    with open(bicycles / "package.order", "a", encoding="utf-8") as order:
        order.write("WhippleLinearAstrom\n")
    params = {p.name: p.value for p in summarize("Bicycle.Bicycles.WhippleLinearAstrom", Library(lib)).parameters}
    expected = P.load_parameters("astrom2005")
    assert {k: params[k] for k in P.PARAMETER_NAMES} == expected
    assert expected != P.load_parameters("benchmark")  # the redeclaration changed something
