"""`cosim animate` and the two sign conventions of the library's results.

The page draws Meijaard's axes (roll, steer, yaw, y positive to the right). A result of the paper's
second-order models (ISO 8855: steer, yaw and the path deviation eta positive to the left) must be
converted, or the bicycle is drawn steering and turning away from its lean, on a straight path.
Checked on a real result: SelfStabilizing in the steady turn after a steer-torque step, where a
bicycle leans into its turn, so that roll, steer and yaw rate must have one sign in Meijaard's
axes, and the drawn path must follow the yaw (y' = V psi, the paper's path kinematics).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import cli_in_process
from cosim.app.animate import geometry, read_result, trajectory

SPEED = 5.0  # [m/s] SelfStabilizing's default V
STEP = 0.01  # [s]
PATH_RTOL = 1e-2  # finite differences of a 0.01-s grid against y' = V psi


@pytest.fixture(scope="module")
def turn(tmp_path_factory) -> Path:
    """A result of SelfStabilizing: a steer-torque step of 1 N m at 0.5 s, 3 s (a steady turn)."""
    work = tmp_path_factory.mktemp("signs")
    status, out, err = cli_in_process(["simulate", "Bicycle.Bicycles.SelfStabilizing", "--stop-time", "3",
                                       "--step", str(STEP), "--input", "T=step:0.5:1", "-o", "turn.csv", "-q"], work)
    assert status == 0, err
    return work / "turn.csv"


def _end_of_turn(path: Path, signs: str) -> tuple[dict, list]:
    traj, signals, notes = trajectory(read_result(path), path, geometry(), SPEED, signs)
    t = {k: np.asarray(v) for k, v in traj.items()}
    return {"phi": t["phi"][-1], "delta": t["delta"][-1], "psi": t["psi"][-1],
            "yaw rate": (t["psi"][-1] - t["psi"][-2]) / STEP, "path rate": (t["y"][-1] - t["y"][-2]) / STEP}, notes


@pytest.mark.parametrize("signs", ["auto", "paper"], ids=["auto-detects-eta", "explicit"])
def test_paper_signs_drawn_leaning_into_the_turn(turn, signs):
    end, notes = _end_of_turn(turn, signs)
    assert abs(end["phi"]) > 0.05  # a real turn, not a straight run
    assert np.sign(end["phi"]) == np.sign(end["delta"]) == np.sign(end["yaw rate"]), end
    assert end["path rate"] == pytest.approx(SPEED * end["psi"], rel=PATH_RTOL)
    assert any(note.startswith("the paper's signs (ISO 8855") and "y = -eta" in note for note in notes)


def test_meijaard_signs_would_draw_it_mirrored(turn):
    """The check above can fail: read with Meijaard's signs the same result steers and yaws away
    from its lean and the path stays straight, as the page drew it before."""
    end, notes = _end_of_turn(turn, "meijaard")
    assert np.sign(end["phi"]) != np.sign(end["delta"]) and end["path rate"] == 0.0
    assert any("eta ignored" in note for note in notes)


def test_a_whipple_result_keeps_its_signs(tmp_path):
    csv = tmp_path / "w.csv"
    csv.write_text("time,bike.phi,bike.delta,bike.psi,bike.x,bike.y\n0,0.1,0.2,0.3,0,0\n0.01,0.1,0.2,0.3,0.05,0.01\n")
    traj, _, notes = trajectory(read_result(csv), csv, geometry(), None, "auto")
    assert (traj["phi"][0], traj["delta"][0], traj["psi"][0], traj["y"][1]) == (0.1, 0.2, 0.3, 0.01)
    assert not any("signs" in note for note in notes)


def test_unknown_convention_is_refused(tmp_path, turn):
    status, out, err = cli_in_process(["animate", str(turn), "--speed", "5", "--signs", "iso", "-o", "x.html"], tmp_path)
    assert status == 2 and "invalid choice: 'iso'" in err and not (tmp_path / "x.html").exists()
