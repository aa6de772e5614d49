"""Non-physical parameter sets: one rule, the waiver in the TOML file.

A Meijaard parameter file may keep values that fail a triangle-inequality check only if it says
so itself (``allow_nonphysical = [...]`` with ``nonphysical_reason = "..."``). The bundled
``astrom2005`` sets follow the same rule as any user file, so a byte-identical copy loads exactly
as the bundled set: same values, same waiver, the same report in ``cosim analytic`` and in the
one line an FMU command prints for ``--params``. A malformed waiver is refused naming the file,
the line and the key.
"""
from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from cosim.analytic import parameters as P

PARAMS = Path(P.__file__).resolve().parents[1] / "params"
WAIVED_SETS = ["astrom2005", "astrom2005-riderless"]
NOTE = re.compile(r"^cosim: note: --params (?P<set>\S+): (?P<waiver>non-physical values accepted: .*)$", re.MULTILINE)


def _copy(name: str, folder: Path) -> Path:
    copy = folder / f"my-{name}.toml"
    shutil.copyfile(PARAMS / f"{name}.toml", copy)
    return copy


def _edited(name: str, folder: Path, old: str, new: str) -> Path:
    """A copy of a bundled file with one exact text replaced (the replacement must happen)."""
    text = (PARAMS / f"{name}.toml").read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = folder / "edited.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


@pytest.mark.parametrize("name", WAIVED_SETS)
def test_copy_of_a_bundled_file_loads_as_the_bundled_set(name, tmp_path):
    bundled, copy = P.load_parameter_set(name), P.load_parameter_set(_copy(name, tmp_path))
    assert copy.values == bundled.values
    assert copy.waiver == bundled.waiver and bundled.waiver is not None
    assert bundled.waiver.checks == ("IByy", "IHyy")
    assert bundled.waiver.reason and "\n" not in bundled.waiver.describe()
    assert P.load_parameters(copy.path) == P.load_parameters(name)


@pytest.mark.parametrize("name", WAIVED_SETS)
def test_the_waiver_is_the_file_s_not_the_name_s(name, tmp_path):
    """Without its waiver lines the same values are refused: no table keyed by bundled name."""
    text = (PARAMS / f"{name}.toml").read_text(encoding="utf-8")
    kept = [line for line in text.splitlines(keepends=True)
            if not line.startswith((P.WAIVER_KEY, P.REASON_KEY))]
    assert len(kept) == len(text.splitlines()) - 2
    stripped = tmp_path / "stripped.toml"
    stripped.write_text("".join(kept), encoding="utf-8")
    with pytest.raises(ValueError, match=r"^IByy: triangle inequality"):
        P.load_parameter_set(stripped)
    # the explicit API waiver still applies on top of the file's
    assert P.load_parameters(stripped, waive=["IByy", "IHyy"]) == P.load_parameters(name)


def test_a_physical_set_has_no_waiver():
    assert P.load_parameter_set("benchmark").waiver is None


WAIVER_LINE = 'allow_nonphysical = ["IByy", "IHyy"]'


@pytest.mark.parametrize("old, new, message", [
    (WAIVER_LINE, 'allow_nonphysical = ["IByy", "IHyy", "IBzx"]',
     r"allow_nonphysical: 'IBzx' is not a parameter"),
    (WAIVER_LINE, 'allow_nonphysical = ["IByy", "IHyy", "mB"]',
     r"allow_nonphysical: the checks of mB cannot be waived"),
    (WAIVER_LINE, 'allow_nonphysical = ["IByy", "IHyy", "IByy"]', r"allow_nonphysical: IByy is listed twice"),
    (WAIVER_LINE, 'allow_nonphysical = []', r"allow_nonphysical: the list is empty"),
    (WAIVER_LINE, 'allow_nonphysical = "IByy"', r"allow_nonphysical: must be a list of parameter names"),
    (WAIVER_LINE, 'allow_nonphysical = ["IByy", "IHyy", "IFyy"]',
     r"allow_nonphysical: the triangle inequality of IFyy holds, there is nothing to waive"),
    ('nonphysical_reason = "', 'nonphysical_reason_ = "',
     r"allow_nonphysical: allow_nonphysical needs nonphysical_reason .*\(it is missing\)"),
    ('nonphysical_reason = "', 'nonphysical_reason = "  " #',
     r"nonphysical_reason: allow_nonphysical needs nonphysical_reason"),
    (WAIVER_LINE, "", r"nonphysical_reason: a reason without a waiver"),
], ids=["unknown-key", "not-waivable", "twice", "empty", "not-a-list", "stale", "misspelt-reason-key",
        "blank-reason", "reason-alone"])
def test_malformed_waiver_is_refused_with_file_and_line(tmp_path, old, new, message):
    path = _edited("astrom2005", tmp_path, old, new)
    with pytest.raises(ValueError, match=message) as info:
        P.load_parameter_set(path)
    text = str(info.value)
    key = P.REASON_KEY if message.startswith(P.REASON_KEY) else P.WAIVER_KEY
    lines = path.read_text(encoding="utf-8").splitlines()
    line = next(i for i, t in enumerate(lines, 1) if t.startswith(f"{key} ="))
    assert text.startswith(f"{path}:{line}: {key}: "), text


def test_cli_refuses_a_non_waivable_key_without_traceback(tmp_path):
    path = _edited("astrom2005", tmp_path, WAIVER_LINE, 'allow_nonphysical = ["IByy", "IHyy", "IBxx"]')
    result = run_cli("analytic", "--params", str(path))
    assert result.returncode != 0 and "Traceback" not in result.stderr
    assert f"{path}:" in result.stderr and "the checks of IBxx cannot be waived" in result.stderr


@pytest.mark.parametrize("name", WAIVED_SETS)
def test_cosim_analytic_reports_the_same_for_a_copy(name, tmp_path):
    copy = _copy(name, tmp_path)
    runs = {label: run_cli("analytic", "--params", source, "--speed", "5", "--json")
            for label, source in (("bundled", name), ("copy", str(copy)))}
    reports = {}
    for label, result in runs.items():
        assert result.returncode == 0, result.stderr
        reports[label] = json.loads(result.stdout)
    bundled, mine = reports["bundled"], reports["copy"]
    for key in ("parameters", "M", "C1", "K0", "K2", "eigenvalues", "weave_speed", "capsize_speed"):
        assert mine[key] == bundled[key], key
    waiver = P.load_parameter_set(name).waiver
    assert bundled["waiver"] == mine["waiver"] == {"checks": list(waiver.checks), "reason": waiver.reason}
    text = {label: run_cli("analytic", "--params", source) for label, source in (("bundled", name),
                                                                                 ("copy", str(copy)))}
    for result in text.values():
        assert result.returncode == 0, result.stderr
        assert waiver.describe() in result.stdout
    benchmark = run_cli("analytic", "--json")
    assert json.loads(benchmark.stdout)["waiver"] is None


def _note(stderr: str) -> tuple[str, str]:
    found = NOTE.findall(stderr)
    assert len(found) == 1, stderr  # exactly one line
    return found[0]


@pytest.mark.parametrize("name", WAIVED_SETS)
def test_fmu_linearize_with_a_copy_equals_the_bundled_set_and_says_so(name, tmp_path):
    """WhippleLinear: same matrices, the same one-line waiver note (only the set's name differs)."""
    copy = _copy(name, tmp_path)
    runs = {source: run_cli("linearize", "Bicycle.Bicycles.WhippleLinear", "--params", source, "--speed", "4",
                            "--json") for source in (name, str(copy))}
    notes = {}
    for source, result in runs.items():
        assert result.returncode == 0, result.stderr
        notes[source] = _note(result.stderr)
        assert notes[source][0] == source
    assert notes[name][1] == notes[str(copy)][1] == P.load_parameter_set(name).waiver.describe()
    a, b = (json.loads(runs[s].stdout) for s in (name, str(copy)))
    assert np.array_equal(np.array(a["A"]), np.array(b["A"])) and a["A"] != []
    quiet = run_cli("linearize", "Bicycle.Bicycles.WhippleLinear", "--params", "benchmark", "--json")
    assert quiet.returncode == 0 and NOTE.search(quiet.stderr) is None


def test_fmu_simulate_nonlinear_with_a_copy_equals_the_bundled_set(tmp_path):
    """The nonlinear Whipple uses IByy: the run says the set is non-physical, for the copy as well."""
    copy = _copy("astrom2005", tmp_path)
    outputs = {}
    for source in ("astrom2005", str(copy)):
        out = tmp_path / f"run-{len(outputs)}.csv"
        result = run_cli("simulate", "Bicycle.Bicycles.Whipple", "--params", source, "--param", "u_R0=-15",
                         "--stop-time", "0.5", "--step", "0.05", "-o", str(out))
        assert result.returncode == 0, result.stderr
        assert _note(result.stderr)[1] == P.load_parameter_set("astrom2005").waiver.describe()
        outputs[source] = np.genfromtxt(out, delimiter=",", names=True)
    a, b = outputs.values()
    assert len(a) == 11 and all(np.array_equal(a[n], b[n]) for n in a.dtype.names)
