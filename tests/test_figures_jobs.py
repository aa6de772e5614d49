"""`cosim figures` in worker processes, and the fast paths under it.

* the figures do not depend on the number of workers: fig7 (on a small seed grid, its two
  variants as parts) and fig9 made with ``jobs=1`` (in this process) and ``jobs=2`` (a pool)
  give JSON numbers equal within ``JOBS_RTOL`` (relative) and PNGs with equal pixels;
* :class:`cosim.fmu.access.DirectCalls` (what :class:`cosim.nonlinear.model.Bicycle` calls)
  gives the states, derivatives and Jacobian FMPy's methods give on a second instance, within
  ``DIRECT_RTOL`` (relative: the same FMI calls, so bit for bit), at start points inside and at
  one the FMU cannot assemble (both raise);
* :func:`cosim.bicycle.stability.state_space` on its kept instance gives what a fresh
  :func:`cosim.fmu.linearize.linearize` gives, within ``DIRECT_RTOL``;
* the variable-name check of ``cosim validate`` parses only the quoted names with FMPy's grammar:
  every name :data:`cosim.fmu.validate.PLAIN_STRUCTURED_NAME` lets through is one FMPy accepts,
  and the findings are FMPy's own, in its order.
"""
from __future__ import annotations

import functools
import json
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import png_pixels
from cosim.figures import fig7, make_figures
from cosim.fmu.access import FMU, DirectCalls
from cosim.fmu.validate import PLAIN_STRUCTURED_NAME, _parser_for_quoted_names_only
from cosim.nonlinear.model import MODEL, Bicycle, parameters, speed_parameters

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

#: Largest relative difference of a JSON number between jobs=1 and jobs=2 (each part is computed
#: by the same code in one process either way: bit for bit in practice).
JOBS_RTOL = 1e-12
#: Largest relative difference between DirectCalls and FMPy's methods, and between a kept and a
#: fresh instance's linearization (the same FMI calls).
DIRECT_RTOL = 0.0


def _numbers(value, path="") -> dict:
    """Every number of a JSON document by its path; strings and Booleans as they are."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() for k, v in _numbers(item, f"{path}/{key}").items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in _numbers(item, f"{path}[{i}]").items()}
    return {path: value}


@pytest.fixture()
def small_fig7(monkeypatch, fmus):
    """fig7 on a small seed grid (two speeds, up to 6 m/s), the grid given to the parts themselves, so that
    a worker computes the same whether it was forked or spawned."""
    from cosim.nonlinear.continuation import Window

    grid = dict(speeds=np.array([1.5, 4.0]), rolls=np.linspace(0.05, 1.5, 8), steers=np.linspace(-np.pi, np.pi, 25))
    compute = functools.partial(fig7.compute, win=Window(v_max=6.0), **grid)
    monkeypatch.setattr(fig7, "parts", lambda: [(compute, (fmus[MODEL], 0.0)), (compute, (fmus[MODEL], fig7.CROWN))])


@pytest.mark.parametrize("jobs", [2], ids=["two-workers"])
def test_figures_do_not_depend_on_jobs(small_fig7, tmp_path, jobs):
    one, many = tmp_path / "one", tmp_path / "many"
    written_one = make_figures(["fig7", "fig9"], one, jobs=1)
    written_many = make_figures(["fig7", "fig9"], many, jobs=jobs)
    assert [p.name for p in written_one] == [p.name for p in written_many] == \
        ["fig7.png", "fig7.json", "fig9.png"]
    a, b = (_numbers(json.loads((folder / "fig7.json").read_text())) for folder in (one, many))
    assert a.keys() == b.keys()
    assert a["/toroidal/turning_branches[0]/points"] > 10, "the small grid found no turning branch"
    for key, x in a.items():
        if isinstance(x, float) and not isinstance(x, bool):
            assert b[key] == pytest.approx(x, rel=JOBS_RTOL, abs=0.0), key
        else:
            assert b[key] == x, key
    for name in ("fig7.png", "fig9.png"):
        assert np.array_equal(png_pixels(one / name), png_pixels(many / name)), name


# --------------------------------------------------------------------------- DirectCalls

START_POINTS = [
    pytest.param({"phi0": 0.0, "delta0": 0.0, "u_R0": -20.0}, True, id="upright"),
    pytest.param({"phi0": 0.4, "delta0": -1.9, "u_R0": -5.0}, True, id="turning"),
    pytest.param({"phi0": 1.5707, "delta0": 3.1, "u_R0": -5.0}, False, id="flat-on-the-ground"),
]


@pytest.mark.parametrize("start, assembles", START_POINTS)
def test_direct_calls_equal_fmpy(fmus, start, assembles):
    from fmpy.fmi1 import FMICallException

    params = speed_parameters({**parameters("astrom2005"), "tR": 0.03, "tF": 0.03}, 3.0)
    fmu = FMU(fmus[MODEL])
    reference = fmu.instantiate("me")
    try:
        fmu.set(reference, {**params, **start})
        with Bicycle(fmus[MODEL], params) as bike:
            if not assembles:
                with pytest.raises(FMICallException):
                    fmu.initialize_me(reference)
                with pytest.raises(FMICallException):
                    bike.initialize(start)
                bike.initialize(START_POINTS[0].values[0])  # an instance that can be terminated
                return
            fmu.initialize_me(reference)
            x = bike.initialize(start)
            nx = len(fmu.states)
            x_ref = (np.ctypeslib.as_ctypes(np.zeros(nx)))
            reference.getContinuousStates(x_ref, nx)
            dx_ref = np.ctypeslib.as_ctypes(np.zeros(nx))
            reference.getDerivatives(dx_ref, nx)
            unknown = [fmu.vr[n] for n in fmu.derivatives]
            known = [fmu.vr[n] for n in fmu.states]
            J_ref = np.column_stack([reference.getDirectionalDerivative(unknown, known, list(np.eye(nx)[k]))
                                     for k in range(nx)])
            np.testing.assert_allclose(x, np.array(x_ref[:]), rtol=DIRECT_RTOL, atol=0.0)
            np.testing.assert_allclose(bike.derivatives(), np.array(dx_ref[:]), rtol=DIRECT_RTOL, atol=0.0)
            np.testing.assert_allclose(bike.jacobian(), J_ref, rtol=DIRECT_RTOL, atol=0.0)
            assert isinstance(bike.calls, DirectCalls)
    finally:
        reference.freeInstance()


@pytest.mark.parametrize("name", ["benchmark", "astrom2005-riderless"], ids=["benchmark", "riderless"])
def test_kept_instance_equals_linearization(fmus, name):
    """stability.state_space on its kept instance (one per parameter set) against a fresh
    linearize() per speed, also after another parameter set was used in between."""
    from cosim.bicycle import stability as WP

    fmu = fmus[WP.MODEL]
    params = WP.parameters_for_model(name)
    other = {**params, "IFyy": 0.01}
    for v in (0.0, 2.5, 4.0, 12.0):
        for p in (params, other):
            A, B = WP.state_space(fmu, p, v)
            system = WP.linearization(fmu, p, v).system
            A_ref, B_ref = WP._bicycle_blocks(fmu, system.states, system.inputs, [system.A], [system.B])[0]
            np.testing.assert_allclose(A, A_ref, rtol=DIRECT_RTOL, atol=0.0)
            np.testing.assert_allclose(B, B_ref, rtol=DIRECT_RTOL, atol=0.0)
    assert len(WP._LINEARIZERS) <= WP.KEPT_INSTANCES


# --------------------------------------------------------------------------- variable names

NAMES = [
    pytest.param("x", True, id="identifier"),
    pytest.param("frame.phi", True, id="dotted"),
    pytest.param("a[1].b_2[3,4]", True, id="subscripts"),
    pytest.param("der(frame.phi)", True, id="der"),
    pytest.param("der(x,2)", True, id="der-order"),
    pytest.param("'a b'.c", False, id="quoted"),
    pytest.param("_under", True, id="underscore"),
    pytest.param("1x", False, id="leading-digit"),
    pytest.param("a..b", False, id="empty-part"),
    pytest.param("a[]", False, id="empty-subscript"),
    pytest.param("a b", False, id="space"),
    pytest.param("der(x", False, id="open-der"),
    pytest.param("x[1", False, id="open-subscript"),
    pytest.param("\u00e4", False, id="non-ascii"),
]


@pytest.mark.parametrize("name, plain", NAMES)
def test_plain_names_are_ones_fmpy_accepts(name, plain):
    from fmpy import validation

    assert bool(PLAIN_STRUCTURED_NAME.fullmatch(name)) == plain
    md = SimpleNamespace(variableNamingConvention="structured",
                         modelVariables=[SimpleNamespace(name=name, sourceline=7), SimpleNamespace(name="y", sourceline=8)])
    findings = validation._validate_variable_names(md)
    if plain:
        assert findings == [], "a name the fast path lets through must be one FMPy accepts"
    with _parser_for_quoted_names_only():
        assert validation._validate_variable_names(md) == findings
