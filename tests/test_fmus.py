"""Every exported FMU: valid, runs in FMPy (ME and CS), libcosim and Ecos with agreeing results,
matches an independent scipy solution, exact directional derivatives, FMU state round trip, and
rebuilds from its own sources."""
from __future__ import annotations

import functools
import math
import shutil
import zipfile

import numpy as np
import pytest

from conftest import shipped_models
from cosim.analytic.twins import TWINS
from cosim.fmu.access import FMU, set_continuous_states
from cosim.fmu.simulate import simulate
from cosim.fmu.validate import validate_report
from reference import SELF_STABILIZING_DEFAULTS, simulate_self_stabilizing
from registered_engines import engine_params

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

SELF = "Bicycle.Bicycles.SelfStabilizing"
STOP, STEP = 5.0, 0.01
START = {"V": 6.0, "T": 1.0}  # constant steer torque from t = 0 (Figure 5 set-up)
CS_AGREEMENT = 1e-9  # the CS engines run the same binary: agreement limited by round-off only
#: The independent engines checked against FMPy.
OTHER_ENGINES = engine_params("fmu", independent=True, reference=False)
DIRECTIONAL_RTOL = 1e-6


def test_every_exported_model_built(fmus):
    from cosim.compiler.library import load_library

    exported = {e.name for e in load_library().models(exported_only=True)}
    assert exported and set(fmus) == exported


EXPORTED = shipped_models(exported_only=True)
SHORT_STOP = 2.0  # s


@pytest.mark.parametrize("model", EXPORTED)
def test_fmu_is_valid(fmus, model):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmus[model])) == []
    report = validate_report(fmus[model])
    assert (report.problems, report.warnings) == ([], [])  # valid, and robust where FMI leaves a choice


def _excitation(fmu) -> dict:
    """A constant 0.1 on every input (the state starts at rest)."""
    from fmpy import read_model_description

    return {v.name: 0.1 for v in read_model_description(str(fmu)).modelVariables if v.causality == "input"}


@functools.cache
def _fmpy_me_cs(fmu) -> tuple[np.ndarray, np.ndarray]:
    """ME and CS results of ``fmu`` in FMPy from :func:`_excitation` (once per FMU)."""
    start = _excitation(fmu)
    return simulate(fmu, SHORT_STOP, STEP, "me", start), simulate(fmu, SHORT_STOP, STEP, "cs", start)


@pytest.mark.parametrize("engine", OTHER_ENGINES)
@pytest.mark.parametrize("model", EXPORTED)
def test_runs_in_fmpy_libcosim_and_ecos(fmus, model, engine):
    """ME in FMPy (CVode) and CS in FMPy and in each independent engine (libcosim, Ecos); the
    CS results agree to 1e-9."""
    fmu = fmus[model]
    start = _excitation(fmu)
    me, cs = _fmpy_me_cs(fmu)
    outputs = [n for n in cs.dtype.names if n != "time"]
    assert outputs and all(np.all(np.isfinite(me[n])) for n in outputs)
    other = engine.run_fmu(fmu, SHORT_STOP, STEP, start, outputs)
    for name in outputs:
        scale = np.maximum(1.0, np.abs(cs[name][1:]))
        assert np.max(np.abs(other[name] - cs[name][1:]) / scale) <= CS_AGREEMENT, (engine.name, name)


@pytest.mark.parametrize("model", sorted(TWINS), ids=sorted(TWINS))
@pytest.mark.parametrize("kind,rtol", [("cs", 1e-6), ("me", 1e-3)], ids=["cs", "me"])
def test_matches_scipy_solution_of_twin(fmus, model, kind, rtol):
    """CS (tolerance 1e-8) and ME (CVode, FMPy's default 1e-5) against scipy's DOP853 solution of
    the analytic twin's equations x' = A x + B u, y = C x + D u from rest, constant inputs 0.1."""
    from scipy.integrate import solve_ivp

    fmu = fmus[model]
    start = _excitation(fmu)
    sys = TWINS[model].system({})
    u = np.array([start[name] for name in sys.input_labels])
    result = simulate(fmu, SHORT_STOP, STEP, kind, start)
    solution = solve_ivp(lambda t, x: sys.A @ x + sys.B @ u, (0.0, SHORT_STOP), np.zeros(sys.nstates),
                         method="DOP853", t_eval=result["time"], rtol=1e-12, atol=1e-14)
    y = sys.C @ solution.y + (sys.D @ u)[:, None]
    for k, name in enumerate(sys.output_labels):
        scale = max(1e-3, np.max(np.abs(y[k])))
        assert np.max(np.abs(result[name] - y[k])) <= rtol * scale, name


@pytest.fixture(scope="module")
def fmpy_cs(fmus):
    # FMPy also records t = 0; the engines record after each step
    return simulate(fmus[SELF], STOP, STEP, "cs", START, outputs=["phi", "delta"])[1:]


@pytest.mark.parametrize("engine", engine_params("fmu", reference=False))
def test_cs_engines_agree(fmus, fmpy_cs, engine):
    """Every engine that runs single FMUs (libcosim, Ecos, our master) runs the self-stabilizing
    bicycle to FMPy's Co-Simulation result, to 1e-9."""
    reference, other = fmpy_cs, engine.run_fmu(fmus[SELF], STOP, STEP, START, ["phi", "delta"])
    assert len(reference) == len(other) == round(STOP / STEP)
    np.testing.assert_allclose(other["time"], reference["time"], rtol=0, atol=1e-9)
    for signal in ("phi", "delta"):
        np.testing.assert_allclose(other[signal], reference[signal], rtol=0, atol=CS_AGREEMENT)


@pytest.mark.parametrize("kind,atol", [("cs", 1e-7), ("me", 1e-5)], ids=["cs-dopri45-tol1e-8", "me-cvode-default"])
def test_matches_scipy_solution(fmus, kind, atol):
    """The FMU solves the same equations as an independent Python implementation of (14)+(11).

    CS uses the model's tolerance 1e-8 (error ≈ 1e-8 · |x| per unit time); FMPy's CVode runs at its
    default relative tolerance 1e-5 in ME."""
    result = simulate(fmus[SELF], STOP, STEP, kind, START, outputs=["phi", "delta"])
    phi, delta = simulate_self_stabilizing(result["time"], lambda t: START["T"], {"V": START["V"]})
    scale = max(1.0, np.max(np.abs(phi)))
    np.testing.assert_allclose(result["phi"], phi, rtol=0, atol=atol * scale)
    np.testing.assert_allclose(result["delta"], delta, rtol=0, atol=atol * scale)


def _analytic_jacobian(V: float):
    """A and B of the momentum-form ODE of (14)+(11): states [phi, L], input T."""
    p = {**SELF_STABILIZING_DEFAULTS, "V": V}
    m, a, h, b, c, lam, J, D, g = (p[k] for k in ("m", "a", "h", "b", "c", "lam", "J", "D", "g"))
    den = V**2 * math.sin(lam) - b * g * math.cos(lam)
    k1 = b**2 / (den * m * a * c * math.sin(lam))
    k2 = b * g / den
    s = math.sin(lam)
    e = m * (V**2 * h - a * c * g) * s / b
    A = np.array([[-D * V * s * k2 / (b * J), 1 / J], [m * g * h - e * k2, 0.0]])
    B = np.array([[D * V * s * k1 / (b * J)], [e * k1]])
    return A, B


@pytest.mark.parametrize("V", [1.0, 6.0, -3.0], ids=["V=1", "V=6", "V=-3"])
def test_directional_derivatives(fmus, V):
    """fmi2GetDirectionalDerivative equals central finite differences (≤1e-6 relative) and the
    analytic Jacobian (≤1e-12 relative)."""
    with FMU(fmus[SELF]) as fmu:
        me = fmu.instantiate("me")
        fmu.set(me, {"V": V})
        me.setupExperiment(startTime=0.0)
        me.enterInitializationMode()
        me.exitInitializationMode()
        me.enterContinuousTimeMode()
        x = np.array([0.05, 0.3, 0.01, 0.02])
        set_continuous_states(me, x)
        fmu.set(me, {"T": 0.7})
        assert fmu.states == ["frame.phi", "frame.L", "path.psi", "path.eta"]
        states = fmu.states[:2]  # the roll dynamics; psi and eta do not act back on them
        der = [fmu.vr[n] for n in fmu.derivatives[:2]]
        knowns = [fmu.vr[n] for n in states] + [fmu.vr["T"]]
        jac = np.column_stack([me.getDirectionalDerivative(der, knowns, list(np.eye(3)[k])) for k in range(3)])
        A, B = _analytic_jacobian(V)
        np.testing.assert_allclose(jac, np.hstack([A, B]), rtol=1e-12, atol=1e-12 * np.max(np.abs(A)))
        fd = np.zeros((2, 3))
        for k in range(3):
            h = 1e-6
            values = []
            for sign in (+1, -1):
                if k < 2:
                    xs = x.copy()
                    xs[k] += sign * h
                    set_continuous_states(me, xs)
                    fmu.set(me, {"T": 0.7})
                else:
                    set_continuous_states(me, x)
                    fmu.set(me, {"T": 0.7 + sign * h})
                values.append(np.array(me.getReal(der)))
            fd[:, k] = (values[0] - values[1]) / (2 * h)
        np.testing.assert_allclose(jac, fd, rtol=DIRECTIONAL_RTOL, atol=DIRECTIONAL_RTOL * np.max(np.abs(fd)))
        # Outputs phi and delta through the output dependency on the input, as a CS master would use.
        out = [fmu.vr["delta"]]
        d_delta_dT = me.getDirectionalDerivative(out, [fmu.vr["T"]], [1.0])[0]
        p = {**SELF_STABILIZING_DEFAULTS, "V": V}
        den = V**2 * math.sin(p["lam"]) - p["b"] * p["g"] * math.cos(p["lam"])
        k1 = p["b"] ** 2 / (den * p["m"] * p["a"] * p["c"] * math.sin(p["lam"]))
        assert d_delta_dT == pytest.approx(k1, rel=1e-12)
        me.terminate()
        me.freeInstance()



def test_directional_derivatives_of_outputs_not_locals(fmus):
    """An assembly's FMU differentiates its derivatives and outputs (the ModelStructure unknowns of
    FMI 2), exactly (<= 1e-6 relative to central differences); a local variable of a component (here
    a connector variable of the rear frame) is refused with a message naming it, not computed."""
    from fmpy.fmi1 import FMICallException

    with FMU(fmus["Bicycle.Bicycles.Whipple"]) as fmu:
        me = fmu.instantiate("me")
        me.setupExperiment(startTime=0.0)
        fmu.set(me, {"phi0": 0.1, "delta0": 0.2, "u_phi0": 0.3})
        me.enterInitializationMode()
        me.exitInitializationMode()
        me.enterContinuousTimeMode()
        x = np.array(me.getReal([fmu.vr[n] for n in fmu.states]))
        outputs = [n for n in ("E", "v", "u_theta_dot") if fmu.variables[n].causality == "output"]
        assert outputs == ["E", "v", "u_theta_dot"]
        known = fmu.states.index("phi")
        seed = list(np.eye(len(x))[known])
        dd = np.array(me.getDirectionalDerivative([fmu.vr[n] for n in outputs], [fmu.vr[n] for n in fmu.states], seed))
        h = 1e-6
        values = []
        for sign in (+1, -1):
            xs = x.copy()
            xs[known] += sign * h
            set_continuous_states(me, xs)
            values.append(np.array(me.getReal([fmu.vr[n] for n in outputs])))
        fd = (values[0] - values[1]) / (2 * h)
        np.testing.assert_allclose(dd, fd, rtol=DIRECTIONAL_RTOL, atol=DIRECTIONAL_RTOL * np.max(np.abs(fd)))
        local = "rearFrame.frame_b.r[3]"
        assert fmu.variables[local].causality == "local"
        with pytest.raises(FMICallException):
            me.getDirectionalDerivative([fmu.vr[local]], [fmu.vr["phi"]], [1.0])
        assert any(local in text and "local variable" in text for _, text in me.log.messages)
        me.terminate()
        me.freeInstance()


def test_local_variables_follow_the_state(fmus):
    """The locals of an assembly are computed when read (the integrators evaluate the derivatives
    and outputs only): a local read after a change of the state, after a Co-Simulation step and
    after restoring an FMU state belongs to that point. The rear hub of the knife-edge Whipple
    bicycle is at height rR cos(phi) whatever the other coordinates (z down)."""
    hub = "rearWheel.hub.r[3]"
    with FMU(fmus["Bicycle.Bicycles.Whipple"]) as fmu:
        rR = float(fmu.variables["rR"].start)
        assert fmu.variables[hub].causality == "local"
        me = fmu.instantiate("me")
        me.setupExperiment(startTime=0.0)
        me.enterInitializationMode()
        me.exitInitializationMode()
        me.enterContinuousTimeMode()
        x = np.array(me.getReal([fmu.vr[n] for n in fmu.states]))
        for phi in (0.3, -0.1):
            x[fmu.states.index("phi")] = phi
            set_continuous_states(me, x)
            assert fmu.get_real(me, [hub])[0] == pytest.approx(-rR * math.cos(phi), rel=1e-14)
        me.terminate()
        me.freeInstance()

        cs = fmu.instantiate("cs")
        fmu.set(cs, {"phi0": 0.1, "u_phi0": 0.5})
        cs.setupExperiment(startTime=0.0)
        cs.enterInitializationMode()
        cs.exitInitializationMode()
        seen = []
        for k in range(3):
            cs.doStep(currentCommunicationPoint=0.1 * k, communicationStepSize=0.1)
            phi, height = fmu.get_real(cs, ["phi", hub])
            assert height == pytest.approx(-rR * math.cos(phi), rel=1e-13)
            seen.append((phi, height))
            if k == 0:
                saved = cs.getFMUstate()
        cs.setFMUstate(saved)
        assert tuple(fmu.get_real(cs, ["phi", hub])) == seen[0]
        cs.freeFMUstate(saved)
        cs.terminate()
        cs.freeInstance()

def test_fmu_state_round_trip(fmus):
    """Save, step, restore, step again gives bit-identical outputs (also through serialization)."""
    with FMU(fmus[SELF]) as fmu:
        cs = fmu.instantiate("cs")
        fmu.set(cs, START)
        cs.setupExperiment(startTime=0.0)
        cs.enterInitializationMode()
        cs.exitInitializationMode()
        watch = [fmu.vr[n] for n in ("phi", "delta", "frame.L")]
        t = 0.0
        for _ in range(10):
            cs.doStep(t, 0.1)
            t += 0.1
        state = cs.getFMUstate()
        first = []
        for k in range(5):
            cs.doStep(t + 0.1 * k, 0.1)
            first.append(cs.getReal(watch))
        cs.setFMUstate(state)
        again = []
        for k in range(5):
            cs.doStep(t + 0.1 * k, 0.1)
            again.append(cs.getReal(watch))
        assert again == first
        blob = cs.serializeFMUstate(state)
        restored = cs.deSerializeFMUstate(blob)
        cs.setFMUstate(restored)
        cs.doStep(t, 0.1)
        assert cs.getReal(watch) == first[0]
        cs.freeFMUstate(state)
        cs.freeFMUstate(restored)
        cs.terminate()
        cs.freeInstance()


def test_rebuild_from_sources(fmus, tmp_path):
    """FMPy's source-build path (CMake) compiles the FMU's own sources into a working binary."""
    from fmpy import simulate_fmu
    from fmpy.build import build_platform_binary

    unzipdir = tmp_path / "unzipped"
    with zipfile.ZipFile(fmus[SELF]) as archive:
        archive.extractall(unzipdir)
    shutil.rmtree(unzipdir / "binaries")
    (tmp_path / "cmake-build").mkdir()
    build_platform_binary(unzipdir, build_dir=tmp_path / "cmake-build")
    assert list((unzipdir / "binaries").rglob("*.so")), "no binary was built"
    rebuilt = simulate_fmu(str(unzipdir), stop_time=STOP, output_interval=STEP, start_values=START,
                           output=["phi", "delta"])
    original = simulate(fmus[SELF], STOP, STEP, "cs", START, outputs=["phi", "delta"])
    np.testing.assert_allclose(rebuilt["phi"], original["phi"], rtol=0, atol=1e-12)
