"""`cosim animate` (cosim/app/animate.py) and the 3-D ride (cosim/app/static/ride3d.js) in a real
headless Chromium, opened from file://.

- A bundled system's result (`cosim run` of cosim/systems/lane-change.toml: the linear bicycle and
  its lane-change controller, no x: ``--speed 5``) is animated; the WebGL canvas is not blank on a
  screenshot, the player's frames and time advance, it plays to its end, and the pose shown at a
  sample time equals the CSV's row exactly (between samples: the linear interpolation).
- The nonlinear Whipple FMU's result (toroidal tyres, a roll and a steer torque so that it rolls
  and steers) checks the drawn kinematics: its pitch solves the holonomic constraint, so the drawn
  front wheel must touch the ground (``frontContactHeight`` <= 1e-6 m over every sample); a wrong
  pitch, trail or crown radius lifts it off or into the ground (so the check can fail).
- Bad inputs: one line ``cosim animate: error: ...``, exit 2, nothing written.

No request other than file:// may be made, and an error in the page fails the test. The browser
fixture and its skip rules (a missing Chromium or playwright skips outside CI, fails in CI) are
those of tests/test_wasm.py. Screenshots go to ``$COSIM_SCREENSHOTS`` if set, else to the test's
temporary folder; the frame rate is printed, not asserted.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import cli_in_process
from test_wasm import browser, offline_page  # noqa: F401 (browser: the shared fixture)

# the quick run (-m 'not slow') leaves this module out: it drives Chromium over the exported site or animation
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parent.parent
VENDOR = ROOT / "cosim" / "app" / "static" / "vendor"
SYSTEM = ROOT / "cosim" / "systems" / "lane-change.toml"
SPEED = 5.0  # [m/s] the lane-change system's bicycle speed (its parameter v)
CONTACT_TOL = 1e-6  # [m] the drawn front wheel's height above the ground for the FMU's poses
WRONG = 1e-3  # [m] a deliberately wrong pitch or trail must lift the front wheel by more than this
# the Whipple run: toroidal tyres (crown radii [m]), leaning and steering at 3.6 m/s
CROWNS = {"tR": 0.02, "tF": 0.025}
WHIPPLE = ["--stop-time", "3", "--step", "0.01", "--param", "phi0=0.1", "--param", "u_R0=-12",
           "--param", f"tR={CROWNS['tR']}", "--param", f"tF={CROWNS['tF']}", "--input", "T_delta=step:1:0.4"]


def _shots(tmp_path: Path) -> Path:
    folder = Path(os.environ["COSIM_SCREENSHOTS"]) if os.environ.get("COSIM_SCREENSHOTS") else tmp_path
    folder.mkdir(parents=True, exist_ok=True)
    return folder


# --- fixtures: results and their animations (one run, one simulate per module) ---------------

@pytest.fixture(scope="module")
def work(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("animate")


@pytest.fixture(scope="module")
def lane(work) -> tuple[Path, Path]:
    """(result CSV, animation HTML) of the bundled lane-change system."""
    status, out, err = cli_in_process(["run", str(SYSTEM), "-o", "lane.csv"], work)
    assert status == 0, err
    status, out, err = cli_in_process(["animate", "lane.csv", "--speed", str(SPEED), "-o", "lane.html"], work)
    assert status == 0, err
    assert "x = V t with V = 5 m/s" in out
    return work / "lane.csv", work / "lane.html"


@pytest.fixture(scope="module")
def whipple(work) -> tuple[Path, Path]:
    """(result CSV, animation HTML) of the nonlinear Whipple FMU with toroidal tyres."""
    status, out, err = cli_in_process(["simulate", "Bicycle.Bicycles.Whipple", *WHIPPLE, "-o", "whipple.csv"], work)
    assert status == 0, err
    status, out, err = cli_in_process(["animate", "whipple.csv", "-o", "whipple.html", "--param",
                                       f"tR={CROWNS['tR']}", "--param", f"tF={CROWNS['tF']}"], work)
    assert status == 0, err
    return work / "whipple.csv", work / "whipple.html"


def _open(browser, html: Path):  # noqa: F811 (the imported fixture)
    """The page from file://, ready; a request that is not file:// is refused and fails the test,
    as does an error in the page."""
    return offline_page(browser, html.as_uri(), "window.cosimAnimate && window.cosimAnimate.player",
                        timeout=30_000, viewport={"width": 1100, "height": 650})


def _csv(path: Path) -> dict[str, np.ndarray]:
    data = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
    return {name: data[name] for name in data.dtype.names}


def _not_blank(png: Path) -> tuple[int, float]:
    """(number of distinct colours, standard deviation of the grey values) of a screenshot."""
    from PIL import Image

    image = np.asarray(Image.open(png).convert("RGB"), dtype=float)
    colours = len(np.unique(image.reshape(-1, 3), axis=0))
    return colours, float(image.mean(axis=2).std())


def _play_to_end(page, rate: float) -> dict:
    page.evaluate(f"cosimAnimate.player.setRate({rate}); cosimAnimate.player.play()")
    page.wait_for_function("cosimAnimate.player.state.finished", timeout=60_000)
    return page.evaluate("({...cosimAnimate.player.state, end: cosimAnimate.data.trajectory.t.at(-1)})")


# --- the lane change ------------------------------------------------------------------------

def test_lane_change_renders_and_plays(browser, lane, tmp_path):  # noqa: F811
    _, html = lane
    with _open(browser, html) as page:
        page.evaluate("cosimAnimate.player.seek(3.0)")
        shot = _shots(tmp_path) / "animate-lane-change.png"
        page.locator("#ride").screenshot(path=str(shot))
        colours, spread = _not_blank(shot)
        assert colours >= 50 and spread >= 10, f"the WebGL canvas looks blank: {colours} colours, grey std {spread:.1f}"
        page.screenshot(path=str(_shots(tmp_path) / "animate-lane-change-page.png"))
        # real-time play: frames and the shown time advance
        before = page.evaluate("({...cosimAnimate.player.state})")
        start = time.perf_counter()
        page.evaluate("cosimAnimate.player.seek(0); cosimAnimate.player.setRate(1); cosimAnimate.player.play()")
        page.wait_for_function(f"cosimAnimate.player.state.frames >= {before['frames']} + 20", timeout=60_000)
        after = page.evaluate("({...cosimAnimate.player.state})")
        elapsed = time.perf_counter() - start
        print(f"headless chromium (SwiftShader): {(after['frames'] - before['frames']) / elapsed:.1f} frames/s")
        assert after["playing"] and after["time"] > 0
        shown = page.locator("#time").inner_text()
        assert re.fullmatch(r"t = \d+\.\d\d s / 20\.00 s", shown), shown
        end = _play_to_end(page, 50)
        assert end["time"] == end["end"] == 20.0 and not end["playing"]
        assert page.locator("#time").inner_text() == "t = 20.00 s / 20.00 s"


def test_lane_change_controls(browser, lane):  # noqa: F811
    """The page's controls drive the player (real clicks and keys); the camera follows the bicycle."""
    _, html = lane
    with _open(browser, html) as page:
        state = "({...cosimAnimate.player.state})"
        page.locator("#scrub").fill("500")  # of 1000: the middle of 0 .. 20 s
        assert page.evaluate(state)["time"] == 10.0
        assert page.locator("#time").inner_text() == "t = 10.00 s / 20.00 s"
        camera = page.evaluate("cosimAnimate.view.camera.position.toArray()")
        page.locator("#scrub").fill("250")
        moved = page.evaluate("cosimAnimate.view.camera.position.toArray()")
        # 5 s earlier at 5 m/s: the camera 25 m back along x (three's X is Meijaard's x)
        assert camera[0] - moved[0] == pytest.approx(25.0, abs=0.5)
        page.locator("#play").click()
        assert page.evaluate(state)["playing"] and page.locator("#play").inner_text() == "Pause"
        page.locator("#play").click()
        paused = page.evaluate(state)
        assert not paused["playing"] and paused["time"] > 5.0
        page.locator("#rate").select_option("10")
        assert page.evaluate("cosimAnimate.player.rate") == 10
        page.locator("#ride").click()  # focus on the page, not on a control
        page.keyboard.press("Space")
        assert page.evaluate(state)["playing"]
        page.keyboard.press("Space")
        assert not page.evaluate(state)["playing"]
        frames = page.evaluate(state)["frames"]
        page.locator("#camera").select_option("top")
        assert page.evaluate("cosimAnimate.view.orbit.elevation") > 1.4
        assert page.evaluate(state)["frames"] == frames + 1  # the paused view redrawn with the new camera
        box = page.locator("#ride").bounding_box()
        azimuth = page.evaluate("cosimAnimate.view.orbit.azimuth")
        page.mouse.move(box["x"] + 200, box["y"] + 200)
        page.mouse.down()
        page.mouse.move(box["x"] + 300, box["y"] + 150, steps=5)
        page.mouse.up()
        assert page.evaluate("cosimAnimate.view.orbit.azimuth") == pytest.approx(azimuth + 100 * 0.008)  # the drag orbits


def test_lane_change_pose_equals_csv(browser, lane):  # noqa: F811
    """The pose the view shows at a sample time is the CSV's row, to the last bit; halfway between
    two samples it is their mean (linear interpolation, 1e-12)."""
    csv, html = lane
    rows = _csv(csv)
    t = rows["time"]
    picks = [0, 1, 137, 420, 1001, len(t) - 1]
    with _open(browser, html) as page:
        for i in picks:
            pose = page.evaluate(f"cosimAnimate.player.seek({float(t[i])!r}), cosimAnimate.view.pose")
            expected = {"phi": rows["bike.phi"][i], "delta": rows["bike.delta"][i], "psi": rows["bike.psi"][i],
                        "y": rows["bike.y"][i], "x": SPEED * t[i], "theta": 0.0}
            assert {k: pose[k] for k in expected} == expected, f"row {i + 2} (t = {t[i]} s)"
            assert pose["thetaR"] <= 0 and pose["thetaF"] <= 0  # rolling forward
        for i in (137, 1001):
            mid = float(0.5 * (t[i] + t[i + 1]))
            pose = page.evaluate(f"CosimRide3D.poseAt(cosimAnimate.data.trajectory, {mid!r})")
            for key, column in (("phi", "bike.phi"), ("delta", "bike.delta"), ("y", "bike.y")):
                assert pose[key] == pytest.approx(0.5 * (rows[column][i] + rows[column][i + 1]), abs=1e-12)


# --- the nonlinear Whipple bicycle: the drawn kinematics against the FMU ----------------------

def test_whipple_front_wheel_touches_the_ground(browser, whipple, tmp_path):  # noqa: F811
    csv, html = whipple
    rows = _csv(csv)
    assert np.abs(rows["phi"]).max() > 0.05 and np.abs(rows["delta"]).max() > 0.05  # it leans and steers
    heights = """(change) => {
        const d = cosimAnimate.data, tr = d.trajectory, g = {...d.geometry, ...change.geometry};
        let worst = 0;
        for (let i = 0; i < tr.t.length; i++) {
            const q = CosimRide3D.poseAt(tr, tr.t[i]);
            q.theta += change.pitch || 0;
            worst = Math.max(worst, Math.abs(CosimRide3D.frontContactHeight(g, q)));
        }
        return worst; }"""
    with _open(browser, html) as page:
        geometry = page.evaluate("cosimAnimate.data.geometry")
        assert {k: geometry[k] for k in CROWNS} == CROWNS
        right = page.evaluate(heights, {"geometry": {}})
        print(f"front wheel above the ground over {len(rows['time'])} samples: at most {right:.2e} m")
        assert right <= CONTACT_TOL
        wrong = {"pitch 0.01 rad": page.evaluate(heights, {"geometry": {}, "pitch": 0.01}),
                 "trail c + 3 cm": page.evaluate(heights, {"geometry": {"c": geometry["c"] + 0.03}}),
                 "knife-edge front tyre": page.evaluate(heights, {"geometry": {"tF": 0.0}})}
        print("wrong kinematics lift the front wheel by: " + ", ".join(f"{k} {v:.2e} m" for k, v in wrong.items()))
        assert wrong["pitch 0.01 rad"] > WRONG and wrong["trail c + 3 cm"] > WRONG
        assert wrong["knife-edge front tyre"] > 100 * CONTACT_TOL  # the torus terms matter
        # the wheels as the scene graph draws them (the meshes' groups, not kinematics()): the rear
        # tyre touches the ground at (x, y), the front tyre touches it
        drawn = page.evaluate("""(pitch) => {
            const tr = cosimAnimate.data.trajectory, view = cosimAnimate.view;
            let rear = 0, front = 0, contact = 0;
            for (let i = 0; i < tr.t.length; i++) {
                const q = CosimRide3D.poseAt(tr, tr.t[i]);
                q.theta += pitch;
                view.setPose(q);
                const w = view.drawnWheels();
                rear = Math.max(rear, Math.abs(w.rear.lowest[2]));
                front = Math.max(front, Math.abs(w.front.lowest[2]));
                contact = Math.max(contact, Math.hypot(w.rear.lowest[0] - q.x, w.rear.lowest[1] - q.y));
            }
            return {rear, front, contact}; }""", 0.0)
        print(f"drawn wheels: rear {drawn['rear']:.1e} m, front {drawn['front']:.1e} m above the ground, "
              f"rear contact {drawn['contact']:.1e} m from (x, y)")
        assert max(drawn.values()) <= CONTACT_TOL
        lifted = page.evaluate("""(pitch) => { const tr = cosimAnimate.data.trajectory, view = cosimAnimate.view;
            const q = CosimRide3D.poseAt(tr, 1.5); q.theta += pitch; view.setPose(q);
            return -view.drawnWheels().front.lowest[2]; }""", 0.01)
        assert lifted > WRONG  # a pitch 0.01 rad too large lifts the drawn front wheel
        page.evaluate("cosimAnimate.player.seek(2.5)")
        shot = _shots(tmp_path) / "animate-whipple.png"
        page.locator("#ride").screenshot(path=str(shot))
        colours, spread = _not_blank(shot)
        assert colours >= 50 and spread >= 10, f"blank canvas: {colours} colours, grey std {spread:.1f}"
        end = _play_to_end(page, 20)
        assert end["time"] == end["end"] == pytest.approx(3.0, abs=1e-12) and end["frames"] > 2


def test_npy_result_gives_the_same_page(lane, work):
    """`cosim animate` of the same result as .npy (structured, as `cosim run -o X.npy` writes)
    embeds the same trajectory as the CSV's."""
    csv, html = lane
    rows = np.genfromtxt(csv, delimiter=",", names=True, deletechars="")
    np.save(work / "lane.npy", rows, allow_pickle=False)
    status, out, err = cli_in_process(["animate", "lane.npy", "--speed", str(SPEED), "-o", "lane-npy.html"], work)
    assert status == 0, err

    def data(path):
        text = path.read_text(encoding="utf-8")
        return json.loads(re.search(r"window\.COSIM_ANIMATION = (\{.*?\});</script>", text).group(1))

    assert data(work / "lane-npy.html")["trajectory"] == data(html)["trajectory"]


# --- bad inputs -----------------------------------------------------------------------------

GOOD = "time,bike.phi,bike.delta,bike.y\n0,0,0,0\n0.01,0.001,0.002,0\n0.02,0.002,0.003,0.0001\n"
BAD = [
    ("missing-file", None, ["animate", "nowhere.csv", "--speed", "5", "-o", "out.html"], r"nowhere\.csv: no such file"),
    ("non-numeric-cell", GOOD.replace("0.01,0.001,0.002", "0.01,abc,0.002"),
     ["animate", "result.csv", "--speed", "5", "-o", "out.html"],
     r"result\.csv: row 3, column 2 \(bike\.phi\): 'abc' is not a number"),
    ("missing-delta", "time,bike.phi,bike.y\n0,0,0\n0.01,0.1,0\n", ["animate", "result.csv", "--speed", "5",
                                                                     "-o", "out.html"],
     r"no configuration signal delta .*found: time, bike\.phi, bike\.y"),
    ("no-x-no-speed", GOOD, ["animate", "result.csv", "-o", "out.html"], r"no signal bike\.x, .*give --speed V"),
    ("two-bicycles", "time,a.phi,a.delta,b.phi,b.delta\n0,0,0,0,0\n", ["animate", "result.csv", "--speed", "5",
                                                                        "-o", "out.html"],
     r"more than one bicycle: a\.phi, b\.phi"),
    ("output-in-a-file", GOOD, ["animate", "result.csv", "--speed", "5", "-o", "result.csv/out.html"],
     r"animation file 'result\.csv/out\.html': 'result\.csv' is a file, not a folder"),
    ("not-a-result", "just some text\nand more\n", ["animate", "result.csv", "--speed", "5", "-o", "out.html"],
     r"result\.csv: row 2, column 1 \(just some text\): 'and more' is not a number"),
    ("time-decreases", "time,phi,delta\n0,0,0\n1,0,0\n0.5,0,0\n", ["animate", "result.csv", "--speed", "5",
                                                                 "-o", "out.html"],
     r"the time decreases at sample 3 \(1 -> 0\.5 s\)"),
    ("unknown-geometry", GOOD, ["animate", "result.csv", "--speed", "5", "--param", "mB=3", "-o", "out.html"],
     r"--param: 'mB' is not a geometry value"),
]


@pytest.mark.parametrize("name, content, argv, message", BAD, ids=[b[0] for b in BAD])
def test_bad_input(tmp_path, name, content, argv, message):
    if content is not None:
        (tmp_path / "result.csv").write_text(content)
    before = sorted(p.name for p in tmp_path.iterdir())
    status, out, err = cli_in_process(argv, tmp_path)
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cosim animate: error: "), err
    assert re.search(message, lines[0]), lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before, "something was written"


def test_vendored_three_is_the_recorded_file():
    """three.min.js is the file vendor/README.md records (SHA-256) and a classic script: it
    defines the global THREE and has no import, export or require."""
    text = (VENDOR / "three.min.js").read_text(encoding="utf-8")
    digest = hashlib.sha256(text.encode("utf-8")).hexdigest()
    row = next(line for line in (VENDOR / "README.md").read_text().splitlines() if line.startswith("| `three.min.js`"))
    assert f"file SHA-256 `{digest}`" in row
    assert re.search(r"^/\*[^\n]*\*/\nvar THREE=", text)
    assert not re.search(r"(^|[;}])\s*(import|export)\s*[{*\w]", text[:2000] + text[-2000:])
    assert "require(" not in text
    assert (VENDOR / "LICENSE-three").read_text().startswith("The MIT License")
