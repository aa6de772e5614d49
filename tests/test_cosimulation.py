"""The co-simulation master against libcosim and Ecos on the bundled systems, and the outcome of
each bundled system (Python blocks against their Modelica twins: tests/test_block_registry.py)."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from cosim.cosimulation.factory import run_system
from cosim.cosimulation.modelica_twins import with_twins
from cosim.cosimulation.ssp import export_ssp
from cosim.cosimulation.system import load_system
from cosim.cosimulation.engines import run_ssp_ecos, run_ssp_libcosim

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

SYSTEMS = sorted((Path(__file__).resolve().parents[1] / "cosim" / "systems").glob("*.toml"))
AGREEMENT = 1e-9  # same binaries, same algorithm: only round-off may differ (relative, floor 1)


@pytest.fixture(scope="module")
def fmu_dir(fmus):
    """The session's FMU folder: the systems' models are built there already."""
    return next(iter(fmus.values())).parent


def _agree(ours: np.ndarray, other: np.ndarray, names: list[str]) -> float:
    """Largest relative difference over all recorded signals (after-step rows from t = h on)."""
    assert len(ours) - 1 == len(other), (len(ours), len(other))
    worst = 0.0
    np.testing.assert_allclose(other["time"], ours["time"][1:], rtol=0, atol=1e-9)
    for name in names:
        a, b = ours[name][1:], other[name]
        worst = max(worst, float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(a)))))
    return worst


@pytest.mark.needs_libcosim
@pytest.mark.needs_ecos
@pytest.mark.parametrize("path", SYSTEMS, ids=[p.stem for p in SYSTEMS])
def test_master_libcosim_ecos_agree(path, fmu_dir, tmp_path):
    """Python blocks replaced by their Modelica twins: our master, libcosim running the exported
    SSP, and Ecos running it agree to 1e-9 on every recorded signal. libcosim records outputs right
    after the step, Ecos after the connected inputs were updated; the master does either."""
    spec, notes = with_twins(load_system(path))
    ssp, _ = export_ssp(spec, tmp_path / f"{path.stem}.ssp", fmu_dir)
    free_running = dataclasses.replace(spec, fall_signal=None, fall_limit=None)  # the engines run to the end
    after_step = run_system(free_running, fmu_dir)
    after_transfer = run_system(dataclasses.replace(free_running, sampling="after-transfer"), fmu_dir)
    names = [n for n in after_step.data.dtype.names if n != "time"]
    assert _agree(after_step.data, run_ssp_libcosim(ssp, names), names) <= AGREEMENT
    assert _agree(after_transfer.data, run_ssp_ecos(ssp, names), names) <= AGREEMENT


EXPECTED = {
    "riderless-push": "completed",
    "rider-p-control": "completed",
    "rear-steered-p": "fell",
    "lqr-autopilot": "completed",
    "lane-change": "completed",
}


@pytest.mark.parametrize("path", SYSTEMS, ids=[p.stem for p in SYSTEMS])
def test_bundled_system_outcome(path, fmu_dir):
    """With Python blocks (exact delay): the outcome the system file describes."""
    result = run_system(path, fmu_dir)
    assert result.outcome.status == EXPECTED[path.stem], result.outcome.message
    phi, t = result.data["bike.phi"], result.data["time"]
    if result.outcome.status == "completed":  # the roll decays: the last second well below the peak
        assert np.max(np.abs(phi[t > t[-1] - 1.0])) < 0.25 * np.max(np.abs(phi))


def test_lane_change_counter_steers(fmu_dir):
    """The path first moves away from the new lane (inverse response), then settles in it."""
    result = run_system(SYSTEMS[[p.stem for p in SYSTEMS].index("lane-change")], fmu_dir)
    y, t = result.data["bike.y"], result.data["time"]
    assert y[(t > 1.0) & (t < 3.0)].min() < -0.02  # first to the left of the start ...
    assert abs(y[-1] - 1.0) < 0.02  # ... then 1 m to the right
