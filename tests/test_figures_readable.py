"""Readable figures: legends over no data, units on every axis, `--plot` panels and the matrix heat maps.

The figure modules themselves are checked where they are drawn (tests/test_whipple_linear.py,
tests/test_whipple_nonlinear.py: :func:`conftest.assert_readable`); here the shared pieces, in
this process with the Agg backend.
"""
from __future__ import annotations

from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

from conftest import assert_readable, cli_in_process
from cosim.fmu.simulate import PLOT_PANELS, plot
from cosim.matrix import report
from cosim.plotting import place_legend

matplotlib.use("Agg")

MODEL = "Bicycle.Bicycles.SelfStabilizing"


def _curves(kind: str):
    """(x, [curves]) for a plot: a few waves, or dense noise filling the whole axes."""
    x = np.linspace(0.0, 10.0, 400)
    if kind == "waves":
        return x, [np.sin(x + k) * np.exp(-0.2 * x) for k in range(3)]
    rng = np.random.default_rng(7)
    return x, [rng.uniform(-1.0, 1.0, x.size) for _ in range(3)]


@pytest.mark.parametrize("kind, legend_inside", [("waves", True), ("dense", False)], ids=["waves", "dense"])
def test_place_legend_covers_no_data(kind, legend_inside, tmp_path, drawn_figures):
    """A legend goes to a free corner, or outside the axes when the data fill every corner."""
    import matplotlib.pyplot as plt

    x, curves = _curves(kind)
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for k, y in enumerate(curves):
        ax.plot(x, y, label=f"curve {k}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("roll angle [deg]")
    legend = place_legend(ax)
    fig.savefig(tmp_path / "f.png")
    box, axes_box = legend.get_window_extent(fig.canvas.get_renderer()), ax.get_window_extent()
    plt.close(fig)
    assert_readable(drawn_figures[0])
    assert axes_box.contains(box.x0 + 1, box.y0 + 1) == legend_inside


def test_readability_finds_a_covering_legend_and_a_missing_unit(tmp_path, drawn_figures):
    """The check fails a legend put over dense data and a label without a unit."""
    import matplotlib.pyplot as plt

    x, curves = _curves("dense")
    fig, ax = plt.subplots()
    ax.plot(x, curves[0], label="noise")
    ax.legend(loc="center")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("roll angle")
    fig.savefig(tmp_path / "f.png")
    plt.close(fig)
    found = drawn_figures[0][2]
    assert found["unlabelled"] == ["axes 0 y: 'roll angle'"]
    assert len(found["covered"]) == 1 and found["covered"][0].startswith("legend 'noise' over ")


def _whipple_like(n: int = 50) -> np.ndarray:
    """A result with the Whipple FMU's 20 output columns (and a torque input)."""
    names = ["x", "y", "psi", "phi", "theta", "delta", "thetaR", "thetaF", "u_phi", "u_delta", "u_R", "u_psi",
             "u_theta", "u_F", "v", "E", "residual", "T_delta"]
    t = np.linspace(0.0, 1.0, n)
    result = np.zeros(n, dtype=[("time", float)] + [(name, float) for name in names])
    result["time"] = t
    for k, name in enumerate(names):
        result[name] = np.sin(t * (k + 1))
    return result


UNITS = {"x": "m", "y": "m", "phi": "rad", "delta": "rad", "v": "m/s", "T_delta": "N.m", "E": "J"}


@pytest.mark.parametrize("signals, inputs, labels", [
    (None, ["T_delta"], ["phi [deg]", "delta [deg]", "T_delta [N.m]", "v [m/s]"]),
    (None, [], ["phi [deg]", "delta [deg]", "T_delta [N.m]", "v [m/s]"]),
    (["E", "x", "u_R"], [], ["E [J]", "x [m]", "u_R\n(no unit declared)"]),
], ids=["default-with-inputs", "default", "chosen"])
def test_plot_panels_and_units(signals, inputs, labels, tmp_path, drawn_figures):
    """`--plot` draws at most PLOT_PANELS panels by default (roll, steer, inputs, torques, speed
    first), the chosen signals otherwise, each labelled with its unit, angles in degrees."""
    result = _whipple_like()
    plot(result, tmp_path / "p.png", "Whipple", units=UNITS, signals=signals, inputs=inputs)
    (_, axes, found), = drawn_figures
    assert len(axes) == (PLOT_PANELS if signals is None else len(signals))
    assert found["ylabels"] == labels
    for data, label in zip(axes, labels):
        (t, y), = data
        name = label.split()[0]
        expected = np.degrees(result[name]) if "[deg]" in label else result[name]
        np.testing.assert_allclose(y, expected, rtol=1e-12, atol=0.0)  # the display unit, same data


@pytest.mark.parametrize("argv_tail, message", [
    (["--signals", "phi,nope", "--plot", "p.png"],
     "cosim simulate: error: --signals: unknown signal(s) nope; available: phi, delta, psi, eta"),
    (["--signals", "phi"], "cosim simulate: error: --signals chooses the panels of --plot: give --plot FILE too"),
], ids=["unknown-name", "without-plot"])
def test_signals_refused(fmus, argv_tail, message, tmp_path):
    """A wrong `--signals` is one line (exit 2) before anything is simulated or written."""
    status, out, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", "r.csv",
                                       *argv_tail], tmp_path)
    assert (status, err.strip()) == (2, message)
    assert list(tmp_path.iterdir()) == []


def test_signals_choose_the_panels(fmus, tmp_path, drawn_figures):
    status, out, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", "r.csv",
                                       "--plot", "p.png", "--signals", "eta,phi"], tmp_path)
    assert status == 0, err
    (_, axes, found), = drawn_figures
    assert len(axes) == 2 and not found["unlabelled"]


def _study(boundary: bool):
    """A 4 x 4 study in (V, tau) and its records: growth rates across 0 (``boundary``) or all negative."""
    study = SimpleNamespace(name="s", settings={"margin": 0.05},
                            plots=[{"x": "V", "y": "tau", "x_unit": "m/s", "y_unit": "s"}],
                            axes={"V": [1.0, 2.0, 3.0, 4.0], "tau": [0.1, 0.2, 0.3, 0.4]}, raw={"components": {}})
    cases, records = [], []
    for i, (V, tau) in enumerate((V, tau) for V in study.axes["V"] for tau in study.axes["tau"]):
        rate = (tau - 0.25) * 4.0 if boundary else -1.0 - tau
        cases.append(SimpleNamespace(key=str(i), values={"V": V, "tau": tau}, variables={"V": V, "tau": tau}))
        records.append({"key": str(i), "observed": {"class": "unstable" if rate > 0 else "stable", "growth_rate": rate},
                        "prediction": {"max_re": rate}, "agreement": "agree"})
    return study, cases, records


@pytest.mark.parametrize("boundary", [True, False], ids=["boundary", "no-boundary"])
def test_heat_map_colours_units_and_legend(boundary, tmp_path, drawn_figures):
    """The cells use the blue/orange growth-rate map with a colour bar in 1/s, both axes have units,
    and the predicted boundary is in the legend exactly when its line is drawn."""
    from matplotlib.colors import to_rgb

    study, cases, records = _study(boundary)
    assert report.plot_study(study, cases, records, tmp_path / "s.png") == tmp_path / "s.png"
    (_, _, found), = drawn_figures
    cmap, = found["colormaps"]
    np.testing.assert_allclose([cmap(v)[:3] for v in (0.0, 0.5, 1.0)], [to_rgb(c) for c in report.GROWTH_COLORS],
                               rtol=0.0, atol=2 / 255)  # blue - white - orange, no red or green
    assert found["colorbars"] == ["observed growth rate [1/s] (symmetric log scale)"]
    assert found["ylabels"] == ["tau [s]"] and not found["unlabelled"]
    assert ("predicted boundary (max Re = 0)" in found["legend"]) == boundary


def test_run_keeps_its_result_when_signals_are_refused(tmp_path):
    """`cosim run` knows its recorded columns after the run: an unknown `--signals` name costs the
    plot, not the computed rows (exit 2, one line, the result written)."""
    from conftest import ROOT

    text = (ROOT / "cosim" / "systems" / "rider-p-control.toml").read_text(encoding="utf-8")
    system = tmp_path / "short.toml"
    system.write_text(text.replace("stop = 20.0", "stop = 0.5"), encoding="utf-8")
    status, out, err = cli_in_process(["run", str(system), "-o", "r.csv", "--plot", "r.png",
                                       "--signals", "bike.phi,nope"], tmp_path)
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert err.startswith("cosim run: error: --signals: unknown signal(s) nope; available: bike.phi, ")
    assert err.strip().endswith("computed were written to r.csv, without a plot")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "short.toml"]
