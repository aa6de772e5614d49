"""The measured bicycles of ``cosim/params/measured``: BicycleParameters' published data.

Each TOML file must carry exactly the nominal values of its source file (vendored verbatim in
tests/data/bicycleparameters, with the licence), waive exactly the checks its values fail, and be
reachable as ``measured/<stem>`` wherever a parameter set is accepted.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from cosim import cli
from cosim.analytic import parameters as P
from cosim.app import bicycles

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "tests" / "data" / "bicycleparameters"
MEASURED = ROOT / "cosim" / "params" / "measured"

#: Set name -> BicycleParameters' name of the bicycle.
SOURCES = {
    "measured/browser": "Browser",
    "measured/crescendo": "Crescendo",
    "measured/fisher": "Fisher",
    "measured/pista": "Pista",
    "measured/rigid": "Rigid",
    "measured/yellow": "Yellow",
    "measured/yellow-reversed": "Yellowrev",
}


def _nominal(name: str) -> dict[str, float]:
    """The nominal values (before ``+/-``) of BicycleParameters' NAMEBenchmark.txt."""
    values = {}
    for line in (SOURCE / f"{name}Benchmark.txt").read_text().splitlines():
        key, _, value = line.partition("=")
        if value:
            values[key.strip()] = float(value.split("+/-")[0])
    return values


def _failed_checks(values: dict[str, float]) -> list[str]:
    """The waivable checks the values fail, each named by its parameter."""
    failed = []
    for key in P.WAIVABLE:
        others = tuple(k for k in P.WAIVABLE if k != key)
        try:
            P.validate_parameters(values, waive=others)
        except ValueError:
            failed.append(key)
    return failed


def test_every_measured_file_has_its_source():
    assert P.measured_parameter_sets() == sorted(SOURCES)
    assert (MEASURED / "LICENSE-BicycleParameters.txt").read_bytes() == (SOURCE / "LICENSE.txt").read_bytes()


@pytest.mark.parametrize("name", sorted(SOURCES), ids=lambda n: n.split("/")[1])
def test_measured_values_are_the_published_ones(name):
    """Every Meijaard symbol equals the source's nominal value exactly; the file waives exactly the
    triangle inequalities those values fail (and says so in its reason)."""
    published = _nominal(SOURCES[name])
    loaded = P.load_parameter_set(name)
    assert loaded.values == {k: published[k] for k in P.PARAMETER_NAMES}
    failed = _failed_checks(dict(loaded.values))
    assert sorted(loaded.waiver.checks if loaded.waiver else ()) == sorted(failed)
    if failed:
        assert all(k in loaded.waiver.reason for k in failed)


def test_source_conventions_are_those_of_the_bundled_benchmark():
    """BicycleParameters' benchmark file is cosim's benchmark set: same symbols, signs (I*xz) and axes."""
    published = _nominal("Benchmark")
    assert {k: published[k] for k in P.PARAMETER_NAMES} == pytest.approx(P.load_parameters("benchmark"), rel=1e-15)


def test_the_app_offers_them_with_their_source():
    offered = [b for b in bicycles.BICYCLES if b.parameter_set.startswith("measured/")]
    assert [b.parameter_set for b in offered] == list(bicycles.MEASURED_LABELS)
    assert set(bicycles.MEASURED_LABELS) <= set(SOURCES)
    for b in offered:
        entry = bicycles.bicycle_data(b)
        assert "BicycleParameters" in entry["explanation"] and "BSD" in entry["explanation"]
        assert "{" not in entry["explanation"]  # the speeds are printed


@pytest.mark.parametrize("given, message", [
    ("measured/nope", "unknown measured bicycle 'measured/nope'; bundled: measured/browser"),
    ("nope", "measured: measured/browser"),
], ids=["unknown-measured", "unknown-name-lists-measured"])
def test_unknown_names_are_one_clear_line(capsys, given, message):
    assert cli.main(["analytic", "--params", given]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err
