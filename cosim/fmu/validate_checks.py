"""The dynamic checks of ``cosim validate``: each one loads the FMU's binary and calls it (FMI 2.0 and 3.0,
Model Exchange and Co-Simulation), unlike FMPy's ``validate_fmu``, which reads the XML only.

:data:`CHECKS` lists them in the order they run; each is a function ``check(session, findings)`` that
reports every problem it finds through ``findings.problem(text)`` and every warning through
``findings.warning(text)`` (it never stops at the first one), and every part that does not apply to this
FMU through ``findings.skip(text)`` (an FMU that does not declare ``canGetAndSetFMUState`` has no FMU
state to check: that is skipped, not a problem). The runner (:func:`cosim.fmu.validate.validate_report`)
prefixes each line with the check's name and runs the checks in a child process, so that a crash of the
binary is reported instead of ending ``cosim validate``.

Problems and warnings
    A *problem* is behaviour the FMI standard (2.0.x for FMI 2, 3.0.x for FMI 3) rules out for the FMU
    with a "must" or "shall"; a *warning* is behaviour the standard allows or leaves undefined but a
    robust FMU avoids. The standard's words decide:

    - A call the state machine does not allow: FMI 2.0 leaves the behaviour undefined ("Calling
      sequences not accepted by the state chart are not supported by the FMI. The behavior of an FMU is
      undefined for such a calling sequence"); FMI 3.0 says "When detecting illegal arguments or a
      function call not allowed in the current state according to the respective state machine, the FMU
      must return fmi3Error". Neither requires the FMU to detect the call: accepting it is a warning.
      Refusing it with another status than Error (or Fatal) is a problem in FMI 3, a warning in FMI 2.
    - The GUID (FMI 2) "is used to check", the instantiationToken (FMI 3) "can be used by the FMU to
      check" that the XML and the binary belong together: accepting a wrong one is a warning; refusing
      the right one (the binary and its XML disagree, or the FMU cannot be instantiated) is a problem.
    - A legal call the FMU answers with Discard, Error or Fatal (the standard lets any call fail and say
      so) is a warning naming the call, and ends that check; as do non-finite values and a short run
      that fails (the standard asks for neither finite values nor a successful run). A status outside
      the standard's enumeration is a problem; so is a crash or a hang of the binary (a calling sequence
      the state machine allows must be supported), reported by the runner, which does not tell a
      crash in one of the state-machine check's forbidden calls (behaviour FMI 2 leaves undefined)
      from one in a legal call.
    - Directional and adjoint derivatives are the FMU's partial derivatives, which FMI 2 allows the FMU
      to compute "by numerical differentiation": a difference larger than numerical differentiation
      explains (:data:`DERIVATIVE_WRONG`) is a problem, one beyond the accuracy of exact derivatives
      (:data:`DERIVATIVE_RTOL`, :data:`ADJOINT_RTOL`) a warning.
    - The FMU state "consist[s] of all values that are needed to continue a simulation" (FMI 2.0,
      2.1.8): values that differ after restoring it by more than :data:`STATE_RTOL` are a problem;
      values that differ in their last bits only (recomputed in another order) a warning. Accepting a
      truncated serialized state is a warning (detecting it is not required).
    - ``fmi3DoStep``: ``earlyReturn = fmi3True`` "is only allowed if earlyReturnAllowed = fmi3True"
      (a problem); a ``lastSuccessfulTime`` other than the end of a complete step "is allowed" (a warning).

Checks and their criteria:

``token``
    For each interface the FMU has: instantiation with the GUID (FMI 2) / ``instantiationToken``
    (FMI 3) of ``modelDescription.xml`` succeeds (problem; if it fails for every interface, the other
    checks cannot run and are listed as skipped), instantiation with a wrong one is refused (NULL;
    warning).
``state-machine``
    Calls the standard does not allow in the instance's current state are refused with Error or Fatal:
    ``DoStep`` before and during initialization and after ``Terminate``, ``ExitInitializationMode``
    without ``EnterInitializationMode`` and twice, ``EnterInitializationMode`` after initialization,
    ``SetReal`` (FMI 3: ``SetFloat64``) of a ``fixed`` parameter after initialization
    (Co-Simulation); ``GetDerivatives`` (FMI 3: ``GetContinuousStateDerivatives``) and
    ``EnterContinuousTimeMode`` before initialization, ``SetContinuousStates`` and
    ``CompletedIntegratorStep`` in event mode, ``ExitInitializationMode`` twice, ``SetReal`` (FMI 3:
    ``SetFloat64``) of a ``fixed`` parameter in continuous-time mode (Model Exchange). Each case runs on
    a fresh instance. A call that returns OK or Warning is a warning ("accepted"); Discard is a problem
    in FMI 3 and a warning in FMI 2 ("Discard instead of Error").
``directional-derivatives``
    Model Exchange, if ``providesDirectionalDerivative(s)``: the Jacobian of the state derivatives and
    continuous outputs with respect to the states and continuous inputs, column by column from
    ``GetDirectionalDerivative``, against central differences with the step
    ``FD_STEP * max(1, |z|)``: every element within ``DERIVATIVE_RTOL * max(1, |fd|)`` (else a
    warning), within ``DERIVATIVE_WRONG * max(1, |fd|)`` (else a problem). Outputs that are states
    themselves are not asked for (listed as skipped).
``adjoint-derivatives``
    FMI 3 Model Exchange, if ``providesAdjointDerivatives``: ``v^T (J u) = (J^T v)^T u`` for
    ``ADJOINT_PAIRS`` seeded random pairs, within ``ADJOINT_RTOL * |v| |J|_F |u|`` (else a warning),
    within ``DERIVATIVE_WRONG * |v| |J|_F |u|`` (else a problem; J from the directional derivatives, or
    from central differences if the FMU has none).
``fmu-state``
    If ``canGetAndSetFMUState``: Co-Simulation: get the state, step, set it back: every Real/Float64
    variable bit-identical to when the state was taken, and after the same step again to the first
    step; with ``canSerializeFMUState`` the same through serialize + deserialize, and a truncated
    serialized state (half its bytes) is refused (warning). Model Exchange: the states and derivatives
    after restoring a state taken before changing the states and time are bit-identical. A difference
    beyond ``STATE_RTOL * max(1, |value|)`` is a problem, a smaller one a warning.
``cs-step``
    FMI 3 Co-Simulation: the steps of the short run (below) one by one, on an instance created without
    early return: ``earlyReturn`` stays false (problem), ``lastSuccessfulTime`` is the end of the step
    (within ``TIME_RTOL``; warning); ``terminateSimulation`` ends the loop without a finding.
``me-run``, ``cs-run``
    A short run (``RUN_FRACTION`` of the default experiment, at most ``RUN_MAX`` s, ``RUN_INTERVALS``
    output intervals; FMPy's ``simulate_fmu``, ME with CVode; the CS communication step is rounded up
    to a multiple of a declared ``fixedInternalStepSize``) reaches its stop time with finite values of
    every recorded variable (warnings).
"""
from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from cosim.errors import FMUError
from cosim.fmu.access import FMULog, get_continuous_states, get_state_derivatives, set_continuous_states

#: Relative tolerance of a directional derivative against central differences (elementwise,
#: relative to max(1, |fd|)): what exact derivatives meet; beyond it a warning.
DERIVATIVE_RTOL = 1e-6
#: Beyond this relative difference a derivative is wrong (a problem), not merely inaccurate: forward
#: differences with a step of about sqrt(eps), the numerical differentiation FMI 2 allows inside an
#: FMU, are accurate to about 1e-7 for a well-scaled model. Used for directional derivatives
#: (elementwise, relative to max(1, |fd|)) and for the adjoint identity (relative to |v| |J| |u|).
DERIVATIVE_WRONG = 1e-4
#: Central-difference step relative to max(1, |z|): about eps**(1/3), which balances the
#: truncation error (h**2) against the rounding error (eps/h).
FD_STEP = 6e-6
#: Tolerance of the adjoint identity v^T (J u) = (J^T v)^T u, relative to |v| |J|_F |u|: what
#: exact derivatives meet; beyond it a warning, beyond DERIVATIVE_WRONG a problem.
ADJOINT_RTOL = 1e-12
#: A value that differs after restoring an FMU state by more than this, relative to max(1, |value|),
#: was not restored (a problem); a smaller difference (the last bits: values recomputed in another
#: order) is a warning, since a restored state is expected to reproduce every value bit for bit.
STATE_RTOL = 1e-9
#: Tolerance of fmi3DoStep's lastSuccessfulTime against the end of a complete step, relative to
#: max(1, |t|) (the FMU may sum its internal steps in another order).
TIME_RTOL = 1e-12
#: Number of random seed pairs (u, v) of the adjoint check (fixed seed: the check is reproducible).
ADJOINT_PAIRS = 3
#: Offset added to the states / inputs before the derivative checks [state units], so that they
#: are not evaluated at a trivial point (zero states where many terms vanish).
OFFSET = 0.01
#: Length of the short ME and CS runs: this fraction of the default experiment's duration ...
RUN_FRACTION = 0.1
#: ... and at most this long [s]; 50 output intervals (CS: communication steps).
RUN_MAX = 2.0
RUN_INTERVALS = 50
#: A token no FMU has: used to check that a wrong GUID / instantiationToken is refused.
WRONG_TOKEN = "{00000000-0000-0000-0000-000000000000}"

_REAL_TYPES = ("Real", "Float64")
_STATUS = ("OK", "Warning", "Discard", "Error", "Fatal", "Pending")


class Findings:
    """What one check found: problems (what the standard rules out), warnings (what it allows but a
    robust FMU avoids) and skipped parts, one line each, without the check's name."""

    def __init__(self, progress: Callable[[str], None] | None = None):
        self.problems: list[str] = []
        self.warnings: list[str] = []
        self.skipped: list[str] = []
        self.current = ""  # what the check is calling (see doing)
        self.stop_reason = ""  # set: the checks after this one cannot run (listed as skipped)
        self._progress = progress

    def problem(self, text: str) -> None:
        self.problems.append(text)

    def warning(self, text: str) -> None:
        self.warnings.append(text)

    def skip(self, text: str) -> None:
        self.skipped.append(text)

    def doing(self, text: str) -> None:
        """Say what the check is about to call (named if the binary crashes or a call fails there)."""
        self.current = text
        if self._progress is not None:
            self._progress(text)


class Session:
    """One FMU under test, with the calls that differ between FMI 2 and FMI 3 in one place.

    Parameters
    ----------
    fmu : cosim.fmu.access.FMU
        The extracted FMU (opened with ``versions=ALL_FMI_VERSIONS``).
    """

    def __init__(self, fmu):
        from lxml import etree

        self.fmu = fmu
        self.md = fmu.description
        self.fmi3 = fmu.is_fmi3
        self.prefix = "fmi3" if self.fmi3 else "fmi2"
        experiment = self.md.defaultExperiment
        self.t0 = float(experiment.startTime) if experiment and experiment.startTime else 0.0
        stop = float(experiment.stopTime) if experiment and experiment.stopTime else self.t0 + 1.0
        self.horizon = min(RUN_MAX, RUN_FRACTION * (stop - self.t0)) if stop > self.t0 else RUN_MAX
        self.h = self.horizon / RUN_INTERVALS
        # FMPy 0.3.32 does not read FMI 3's providesDirectionalDerivatives (plural); read the
        # capability flags from the XML itself, for both versions.
        parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
        root = etree.parse(str(fmu.unzipdir) + "/modelDescription.xml", parser).getroot()
        self._sections = {"me": root.find("ModelExchange"), "cs": root.find("CoSimulation")}
        # FMI 3: value reference of an output or state derivative -> the value references its
        # ModelStructure entry declares it depends on (an entry without the attribute, which may
        # depend on every known, is left out; FMI 2 lists unknowns by index and is not read here)
        self.dependencies: dict[int, set[int]] = {}
        structure = root.find("ModelStructure") if self.fmi3 else None
        for entry in (structure if structure is not None else ()):
            if entry.tag in ("Output", "ContinuousStateDerivative") and "dependencies" in entry.attrib:
                try:
                    self.dependencies[int(entry.get("valueReference"))] = {
                        int(d) for d in entry.get("dependencies").split()}
                except (TypeError, ValueError):  # a malformed entry: FMPy's checks report it
                    pass
        # The Co-Simulation step: a multiple of a declared fixedInternalStepSize (FMI 3), since an
        # FMU with a fixed internal step need not handle shorter communication steps.
        fixed = self._sections["cs"].get("fixedInternalStepSize") if self.fmi3 and self._sections["cs"] is not None \
            else None
        try:
            fixed = float(fixed) if fixed else 0.0
        except ValueError:  # FMPy's schema check lets no such value through; be safe anyway
            fixed = 0.0
        self.cs_h = fixed * max(1, math.ceil(self.h / fixed - 1e-9)) if fixed > 0 else self.h
        self.cs_steps = max(1, round(self.horizon / self.cs_h))
        self.variables = list(self.md.modelVariables)
        self.by_vr = {v.valueReference: v for v in self.variables}
        self.latest = None  # the instance made last: its log explains a failed call

    # -- the model description ------------------------------------------------------------------

    def kinds(self) -> list[str]:
        """The interfaces of the FMU: ``"me"`` and/or ``"cs"``."""
        return [k for k in ("me", "cs") if self._sections[k] is not None]

    def flag(self, kind: str, fmi2_name: str, fmi3_name: str | None = None) -> bool:
        """A capability flag of interface ``kind`` (False if the interface is absent)."""
        section = self._sections[kind]
        if section is None:
            return False
        name = (fmi3_name or fmi2_name) if self.fmi3 else fmi2_name
        return section.get(name) in ("true", "1")

    def size(self, v) -> int:
        """Number of scalar elements of a variable (FMI 3 arrays: the product of the dimensions)."""
        return self.fmu.size(v.name)

    def real(self, causality: str, variability: str | None = "continuous") -> list:
        return [v for v in self.variables if v.causality == causality and v.type in _REAL_TYPES
                and (variability is None or v.variability == variability)]

    @property
    def state_vrs(self) -> list[int]:
        return [d.variable.derivative.valueReference for d in self.md.derivatives]

    @property
    def derivative_vrs(self) -> list[int]:
        return [d.variable.valueReference for d in self.md.derivatives]

    @property
    def nx(self) -> int:
        return self.fmu.n_states

    def fixed_parameter(self):
        """A scalar Real/Float64 parameter of variability fixed with a start value (None: none)."""
        for v in self.real("parameter", "fixed"):
            if v.start is not None and self.size(v) == 1:
                return v
        return None

    def all_real_vrs(self) -> list[int]:
        """Every Real/Float64 variable except the independent one (FMI 3 time): compared bitwise."""
        return [v.valueReference for v in self.variables if v.type in _REAL_TYPES and v.causality != "independent"]

    # -- instances ------------------------------------------------------------------------------

    def instance(self, kind: str, name: str = "validate"):
        """A fresh instance of interface ``kind`` (:meth:`cosim.fmu.access.FMU.instantiate`)."""
        self.latest = self.fmu.instantiate(kind, name=name)
        return self.latest

    def raw_instance(self, kind: str, token: str):
        """Instantiate with the given GUID / instantiationToken, bypassing the access layer (which
        always passes the right one). Raises FMPy's Exception if the FMU refuses (NULL)."""
        if self.fmi3:
            from fmpy.fmi3 import FMU3Model as Model, FMU3Slave as Slave
        else:
            from fmpy.fmi2 import FMU2Model as Model, FMU2Slave as Slave
        section = self.md.coSimulation if kind == "cs" else self.md.modelExchange
        log = FMULog()
        instance = (Slave if kind == "cs" else Model)(guid=token, unzipDirectory=self.fmu.unzipdir,
                                                      modelIdentifier=section.modelIdentifier,
                                                      instanceName="wrong-token")
        if self.fmi3:
            instance.instantiate(loggingOn=False, logMessage=log.fmi3_logger)
        else:
            instance.instantiate(loggingOn=False, callbacks=log.callbacks())
        instance.log = log
        return instance

    def enter_initialization(self, instance) -> None:
        if self.fmi3:
            instance.enterInitializationMode(startTime=self.t0)
        else:
            instance.setupExperiment(startTime=self.t0)
            instance.enterInitializationMode()

    def initialize(self, instance, kind: str, continuous: bool = True) -> None:
        """From instantiated to Co-Simulation step mode, or Model Exchange event mode (then
        continuous-time mode if ``continuous``) after the event iteration."""
        self.enter_initialization(instance)
        instance.exitInitializationMode()
        if kind == "me":
            self.event_iteration(instance)
            if continuous:
                instance.enterContinuousTimeMode()

    def event_iteration(self, instance) -> None:
        """The event iteration after initialization, as every Model Exchange run here does it
        (:meth:`cosim.fmu.access.FMU.event_iteration`); a request to terminate there ends the
        check (legally: a warning)."""
        if self.fmu.event_iteration(instance).terminate:
            raise _Terminated(f"{self.prefix}{'UpdateDiscreteStates' if self.fmi3 else 'NewDiscreteStates'} "
                              "asked to terminate the simulation after initialization")

    @staticmethod
    def free(instance) -> None:
        """Free an instance whatever its state (errors ignored: it is discarded)."""
        try:
            instance.freeInstance()
        except Exception:  # an instance in an error state may refuse even this; it is dropped
            pass

    # -- values ---------------------------------------------------------------------------------

    def get(self, instance, vrs: list[int]) -> np.ndarray:
        if not vrs:
            return np.zeros(0)
        if self.fmi3:
            n = sum(self.size(self.by_vr[r]) for r in vrs)
            return np.array(instance.getFloat64(vrs, n))
        return np.array(instance.getReal(vrs))

    def set(self, instance, vrs: list[int], values) -> None:
        if not vrs:
            return
        values = [float(x) for x in np.ravel(values)]
        if self.fmi3:
            instance.setFloat64(vrs, values)
        else:
            instance.setReal(vrs, values)

    def states(self, instance) -> np.ndarray:
        return get_continuous_states(instance, self.nx)

    def set_states(self, instance, x) -> None:
        set_continuous_states(instance, x)

    def derivatives(self, instance) -> np.ndarray:
        return get_state_derivatives(instance, self.nx)

    def do_step(self, instance, t: float, h: float) -> None:
        result = instance.doStep(t, h)
        if self.fmi3 and result[1]:  # (eventEncountered, terminateSimulation, earlyReturn, lastSuccessfulTime)
            raise _Terminated(f"fmi3DoStep at t = {t:g} s asked to terminate the simulation")

    def directional(self, instance, unknowns: list[int], knowns: list[int], seed, n_unknowns: int) -> np.ndarray:
        seed = [float(s) for s in seed]
        if self.fmi3:
            return np.array(instance.getDirectionalDerivative(unknowns, knowns, seed, n_unknowns))
        return np.array(instance.getDirectionalDerivative(unknowns, knowns, seed))

    def adjoint(self, instance, unknowns: list[int], knowns: list[int], seed, n_knowns: int) -> np.ndarray:
        # FMPy's default nSensitivity is the number of unknowns; the adjoint has one per known.
        return np.array(instance.getAdjointDerivative(unknowns, knowns, [float(s) for s in seed], n_knowns))


class _Terminated(FMUError):
    """The FMU asked to terminate the simulation (which the standard allows at any step)."""


def _failed_legally(exc: BaseException) -> bool:
    """Whether ``exc`` is an FMI call the FMU answered with Discard, Error or Fatal, or its request to
    terminate: the standard lets any call fail and say so (a warning). Anything else (a status outside
    the standard's enumeration, a missing function, a fault of this code) is not."""
    from fmpy.fmi1 import FMICallException

    return isinstance(exc, _Terminated) or (isinstance(exc, FMICallException) and exc.status in (2, 3, 4))


def _illegal_status(exc: BaseException) -> bool:
    """Whether ``exc`` is FMPy's report of a return value that is no status of the standard."""
    from fmpy.fmi1 import FMICallException

    return isinstance(exc, FMICallException) and exc.status not in range(len(_STATUS))


def _status_of(call: Callable[[], object]) -> int:
    """The status of an FMI call: 0 (OK or Warning: FMPy raises only beyond Warning), else the
    status FMPy's FMICallException carries."""
    from fmpy.fmi1 import FMICallException

    try:
        call()
    except FMICallException as exc:
        return int(exc.status)
    return 0


def _said(instance) -> str:
    said = instance.log.last_error() if hasattr(instance, "log") else None
    return f" (the FMU says: {said})" if said else ""


# -- token --------------------------------------------------------------------------------------

def check_token(s: Session, f: Findings) -> None:
    what = "instantiationToken" if s.fmi3 else "GUID"
    refused = []
    for kind in s.kinds():  # first the right token: every later check needs it
        f.doing(f"instantiate ({kind.upper()}) with the {what} of modelDescription.xml")
        try:
            s.free(s.instance(kind, name="token"))
        except FMUError as exc:
            refused.append(kind)
            f.problem(f"{kind.upper()}: instantiation with the {what} of modelDescription.xml fails: "
                      f"{str(exc).removeprefix(f'{s.fmu.path}: ')}")
    if refused == s.kinds():
        f.stop_reason = "the FMU cannot be instantiated (see token)"
        return
    for kind in s.kinds():
        if kind in refused:
            continue
        token = WRONG_TOKEN if s.md.guid != WRONG_TOKEN else WRONG_TOKEN.replace("0", "1")
        f.doing(f"instantiate ({kind.upper()}) with a wrong {what}")
        try:
            instance = s.raw_instance(kind, token)
        except Exception:  # FMPy: "Failed to instantiate FMU": refused, as it should be
            continue
        f.warning(f"{kind.upper()}: instantiation with a wrong {what} {token} was accepted (the {what} is there "
                  "to detect a binary that does not belong to its modelDescription.xml)")
        s.free(instance)


# -- state machine ------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Case:
    kind: str  # "cs" / "me"
    state: str  # the state the instance is brought into first
    call: str  # FMI function name without prefix (FMI 2 spelling; _FMI3_NAMES maps)
    when: str  # words for the message
    needs: str = ""  # "states": the model needs continuous states; "fixed": a fixed Real parameter


_CASES = (
    _Case("cs", "instantiated", "DoStep", "before initialization"),
    _Case("cs", "initialization", "DoStep", "in initialization mode"),
    _Case("cs", "instantiated", "ExitInitializationMode", "without EnterInitializationMode"),
    _Case("cs", "initialized", "ExitInitializationMode", "a second time"),
    _Case("cs", "initialized", "EnterInitializationMode", "after initialization"),
    _Case("cs", "terminated", "DoStep", "after Terminate"),
    _Case("cs", "initialized", "SetReal", "after initialization", "fixed"),
    _Case("me", "instantiated", "GetDerivatives", "before initialization", "states"),
    _Case("me", "instantiated", "EnterContinuousTimeMode", "before initialization"),
    _Case("me", "event", "SetContinuousStates", "in event mode", "states"),
    _Case("me", "event", "CompletedIntegratorStep", "in event mode"),
    _Case("me", "event", "ExitInitializationMode", "a second time"),
    _Case("me", "continuous", "SetReal", "in continuous-time mode", "fixed"),
)
_FMI3_NAMES = {"GetDerivatives": "GetContinuousStateDerivatives", "SetReal": "SetFloat64"}


def _bring(s: Session, instance, case: _Case) -> None:
    if case.state == "initialization":
        s.enter_initialization(instance)
    elif case.state in ("initialized", "event"):
        s.initialize(instance, case.kind, continuous=False)
    elif case.state == "continuous":
        s.initialize(instance, case.kind, continuous=True)
    elif case.state == "terminated":
        s.initialize(instance, case.kind, continuous=False)
        instance.terminate()


def _forbidden_call(s: Session, instance, case: _Case, parameter) -> Callable[[], object]:
    if case.call == "DoStep":
        return lambda: instance.doStep(s.t0, s.cs_h)
    if case.call == "ExitInitializationMode":
        return instance.exitInitializationMode
    if case.call == "EnterInitializationMode":
        return lambda: s.enter_initialization(instance)
    if case.call == "EnterContinuousTimeMode":
        return instance.enterContinuousTimeMode
    if case.call == "GetDerivatives":
        return lambda: s.derivatives(instance)
    if case.call == "SetContinuousStates":
        return lambda: s.set_states(instance, np.zeros(s.nx))
    if case.call == "CompletedIntegratorStep":
        return instance.completedIntegratorStep
    if case.call == "SetReal":
        return lambda: s.set(instance, [parameter.valueReference], [float(parameter.start)])
    raise ValueError(f"no forbidden call {case.call!r}")


def check_state_machine(s: Session, f: Findings) -> None:
    parameter = s.fixed_parameter()
    kinds = s.kinds()
    unreachable: dict[tuple[str, str], list[str]] = {}  # (interface, why) -> cases not checked
    for case in _CASES:
        if case.kind not in kinds:
            continue
        name = s.prefix + (_FMI3_NAMES.get(case.call, case.call) if s.fmi3 else case.call)
        label = f"{case.kind.upper()}: {name}" + (f" of the fixed parameter '{parameter.name}'"
                                                   if case.needs == "fixed" and parameter else "")
        if case.needs == "states" and s.nx == 0:
            f.skip(f"{label} {case.when}: the model has no continuous states")
            continue
        if case.needs == "fixed" and parameter is None:
            f.skip(f"{label} of a fixed parameter {case.when}: the FMU has no fixed "
                   f"{'Float64' if s.fmi3 else 'Real'} parameter")
            continue
        f.doing(f"{label} {case.when}")
        instance = s.instance(case.kind, name="state-machine")
        try:
            try:
                _bring(s, instance, case)
            except Exception as exc:  # the legal calls before the forbidden one failed
                key = (case.kind, f"{exc}{_said(instance)}", _failed_legally(exc))
                unreachable.setdefault(key, []).append(f"{name} {case.when}")
                continue
            status = _status_of(_forbidden_call(s, instance, case, parameter))
            if status in (0, 1):
                f.warning(f"{label} {case.when} was accepted (the state machine does not allow the call; the "
                          "standard does not require the FMU to detect it, but Error would protect the user)")
            elif status not in (3, 4):
                label_status = _STATUS[status] if 0 <= status < len(_STATUS) else str(status)
                if not 0 <= status < len(_STATUS):  # no status of the standard at all
                    f.problem(f"{label} {case.when} returned {label_status}, which is no fmi{s.fmi3 + 2}Status")
                elif s.fmi3:  # "When detecting ... a call not allowed ..., the FMU must return fmi3Error"
                    f.problem(f"{label} {case.when} returned {label_status}, expected Error (FMI 3 requires Error "
                              "for a call the FMU detects as not allowed in its state)")
                else:  # FMI 2.0 leaves the behaviour undefined
                    f.warning(f"{label} {case.when} returned {label_status}, expected Error")
        finally:
            s.free(instance)
    for (kind, why, legal), cases in unreachable.items():  # one line per cause, not per case
        text = (f"{kind.upper()}: {len(cases)} case(s) not checked ({'; '.join(cases)}): the legal calls "
                f"leading to the state failed: {why}")
        (f.warning if legal else f.problem)(text)


# -- derivatives --------------------------------------------------------------------------------

class _Point:
    """A Model Exchange instance in continuous-time mode at a point away from the initial one:
    the knowns z = (states, continuous inputs), unknowns (derivatives, continuous outputs)."""

    def __init__(self, s: Session, f: Findings):
        self.s = s
        self.inputs = [v.valueReference for v in s.real("input") if s.size(v) == 1]
        # Outputs that are states themselves (d x/d x = identity) are not asked for: the standard
        # allows them as unknowns, but runtimes (this project's among them) refuse them, and their
        # derivative tells nothing about the model.
        outputs = [v.valueReference for v in s.real("output")]
        self.state_outputs = [s.by_vr[r].name for r in outputs if r in s.state_vrs]
        self.unknowns = s.derivative_vrs + [r for r in outputs if r not in s.derivative_vrs + s.state_vrs]
        self.knowns = s.state_vrs + self.inputs
        self.n_unknowns = sum(s.size(s.by_vr[r]) for r in self.unknowns)
        self.nz = s.nx + len(self.inputs)
        f.doing("Model Exchange initialization")
        self.instance = s.instance("me", name="derivatives")
        s.initialize(self.instance, "me")
        x = s.states(self.instance) + OFFSET * (1 + np.arange(s.nx))
        u = s.get(self.instance, self.inputs) + OFFSET * (1 + np.arange(len(self.inputs)))
        self.z = np.concatenate([x, u])
        self.put(self.z)

    def put(self, z) -> None:
        self.s.set_states(self.instance, z[: self.s.nx])
        self.s.set(self.instance, self.inputs, z[self.s.nx:])

    def values(self, z) -> np.ndarray:
        self.put(z)
        return self.s.get(self.instance, self.unknowns)

    def central_differences(self) -> np.ndarray:
        columns = []
        for k in range(self.nz):
            h = FD_STEP * max(1.0, abs(self.z[k]))
            zp, zm = self.z.copy(), self.z.copy()
            zp[k] += h
            zm[k] -= h
            columns.append((self.values(zp) - self.values(zm)) / (2 * h))
        self.put(self.z)
        return np.array(columns).T

    def directional(self) -> np.ndarray:
        return np.array([self.s.directional(self.instance, self.unknowns, self.knowns, seed, self.n_unknowns)
                         for seed in np.eye(self.nz)]).T

    def declared_independent(self, row: int, column: int) -> bool:
        """Whether the ModelStructure declares unknown ``row`` independent of known ``column``
        (its ``dependencies`` attribute lists other knowns only; scalar knowns and unknowns)."""
        rows = [r for r in self.unknowns for _ in range(self.s.size(self.s.by_vr[r]))]
        if len(rows) != self.n_unknowns or len(self.knowns) != self.nz:
            return False
        declared = self.s.dependencies.get(rows[row])
        return declared is not None and self.knowns[column] not in declared

    def name(self, column: int) -> str:
        if column < self.s.nx:
            return self.s.md.derivatives[column].variable.derivative.name if self.s.nx == len(self.s.md.derivatives) \
                else f"state {column}"
        return self.s.by_vr[self.inputs[column - self.s.nx]].name

    def row_name(self, row: int) -> str:
        names = []
        for r in self.unknowns:
            v = self.s.by_vr[r]
            names += [v.name] * self.s.size(v)
        return names[row]

    def close(self) -> None:
        self.s.free(self.instance)


@contextlib.contextmanager
def _derivative_point(s: Session, f: Findings, flag2: str, flag3: str):
    """The Model Exchange point the derivative checks differentiate at (:class:`_Point`, closed
    at the end), or None after a skip that says why: no Model Exchange, the capability flag
    (``flag2`` in FMI 2, ``flag3`` in FMI 3) not declared, or nothing to differentiate."""
    if "me" not in s.kinds():
        f.skip("the FMU has no Model Exchange interface (the check uses its states and derivatives)")
        yield None
        return
    if not s.flag("me", flag2, flag3):
        f.skip(f"the FMU does not declare {flag3 if s.fmi3 else flag2}")
        yield None
        return
    point = _Point(s, f)
    try:
        if not point.nz or not point.n_unknowns:
            f.skip("no continuous states or inputs, or no derivatives or outputs")
            yield None
        else:
            yield point
    finally:
        point.close()


def check_directional_derivatives(s: Session, f: Findings) -> None:
    with _derivative_point(s, f, "providesDirectionalDerivative", "providesDirectionalDerivatives") as point:
        if point is None:
            return
        if point.state_outputs:
            f.skip(f"outputs that are states ({', '.join(point.state_outputs)}) are not asked for as unknowns")
        f.doing(f"{s.prefix}GetDirectionalDerivative")
        ad = point.directional()
        f.doing("central differences")
        fd = point.central_differences()
        error = np.abs(ad - fd) / np.maximum(1.0, np.abs(fd))
        error[~np.isfinite(error)] = np.inf
        for k in range(point.nz):
            if error[:, k].max() > DERIVATIVE_RTOL:
                i = int(np.argmax(error[:, k]))
                wrong = error[i, k] > DERIVATIVE_WRONG
                tolerance = DERIVATIVE_WRONG if wrong else DERIVATIVE_RTOL
                text = (f"d({point.row_name(i)})/d({point.name(k)}) = {ad[i, k]:.9g} from "
                        f"{s.prefix}GetDirectionalDerivative, {fd[i, k]:.9g} from central differences "
                        f"(relative difference {error[i, k]:.2e} > {tolerance:g}"
                        + ("" if wrong else ": inaccurate, as from numerical differentiation") + ")")
                if wrong and ad[i, k] == 0 and point.declared_independent(i, k):
                    # The derivative keeps to the sparsity the model description declares, which an
                    # importer relies on: the declaration, not the derivative, is what is wrong.
                    f.warning(f"the ModelStructure declares {point.row_name(i)} independent of "
                              f"{point.name(k)}, but central differences give d({point.row_name(i)})/"
                              f"d({point.name(k)}) = {fd[i, k]:.9g} (its dependencies are incomplete)")
                    continue
                (f.problem if wrong else f.warning)(text)


def check_adjoint_derivatives(s: Session, f: Findings) -> None:
    if not s.fmi3:
        f.skip("FMI 2 has no adjoint derivatives")
        return
    with _derivative_point(s, f, "", "providesAdjointDerivatives") as point:
        if point is None:
            return
        directional = s.flag("me", "", "providesDirectionalDerivatives")
        f.doing("fmi3GetDirectionalDerivative" if directional else "central differences")
        jacobian = point.directional() if directional else point.central_differences()
        scale = np.linalg.norm(jacobian) or 1.0
        rng = np.random.default_rng(15)
        for pair in range(ADJOINT_PAIRS):
            u = rng.standard_normal(point.nz)
            v = rng.standard_normal(point.n_unknowns)
            f.doing("fmi3GetAdjointDerivative")
            if directional:
                ju = s.directional(point.instance, point.unknowns, point.knowns, u, point.n_unknowns)
            else:
                ju = jacobian @ u
            jtv = s.adjoint(point.instance, point.unknowns, point.knowns, v, point.nz)
            left, right = float(v @ ju), float(jtv @ u)
            norms = np.linalg.norm(v) * scale * np.linalg.norm(u)
            if not abs(left - right) <= ADJOINT_RTOL * norms:
                wrong = not abs(left - right) <= DERIVATIVE_WRONG * norms
                tolerance = DERIVATIVE_WRONG if wrong else ADJOINT_RTOL
                (f.problem if wrong else f.warning)(
                    f"v^T(J u) = {left:.15g} but (J^T v)^T u = {right:.15g} (random pair {pair + 1}; difference "
                    f"{abs(left - right):.2e} > {tolerance * norms:.2e} = {tolerance:g} |v| |J| |u|)")


# -- FMU state ----------------------------------------------------------------------------------

def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


def _not_restored(f: Findings, a: np.ndarray, b: np.ndarray, text: str) -> None:
    """Report values ``b`` that should equal ``a`` bit for bit: a problem if one differs by more than
    :data:`STATE_RTOL` (or in shape, or in being finite), else a warning (the last bits only)."""
    if a.shape != b.shape:
        f.problem(text)
        return
    with np.errstate(invalid="ignore", over="ignore"):
        close = np.abs(a - b) <= STATE_RTOL * np.maximum(1.0, np.maximum(np.abs(a), np.abs(b)))
    if np.all(close | (a == b) | (np.isnan(a) & np.isnan(b))):
        f.warning(text.removesuffix(")") + f"; in the last bits only, within {STATE_RTOL:g} relative)")
    else:
        f.problem(text)


def _differs(vrs: list[int], s: Session, a: np.ndarray, b: np.ndarray) -> str:
    index = [i for i in range(min(len(a), len(b))) if not (a[i] == b[i] or (np.isnan(a[i]) and np.isnan(b[i])))]
    names = [s.by_vr[vrs[i]].name for i in index[:3]] if len(vrs) == len(a) else []
    example = f", e.g. {names[0]}: {float(a[index[0]])!r} then {float(b[index[0]])!r}" if names else ""
    return f"{len(index)} value(s) differ{example}"


def _cs_state(s: Session, f: Findings) -> None:
    """Take the state at t1, step, restore, step again: the values right after restoring must equal
    those when the state was taken (an FMU that integrates from its own time, as many do, would
    otherwise hide a restore that did nothing), the values after the repeated step those after the
    first."""
    watch = s.all_real_vrs()
    f.doing("Co-Simulation initialization and a step")
    cs = s.instance("cs", name="fmu-state")
    try:
        s.initialize(cs, "cs")
        t1 = s.t0 + s.cs_h
        s.do_step(cs, s.t0, s.cs_h)
        f.doing(f"{s.prefix}GetFMUState")
        state = cs.getFMUState()
        taken = s.get(cs, watch)
        s.do_step(cs, t1, s.cs_h)
        stepped = s.get(cs, watch)

        def compare(how: str) -> None:
            now = s.get(cs, watch)
            if not _same(taken, now):
                _not_restored(f, taken, now, f"CS: right after {how}: {_differs(watch, s, taken, now)} from when "
                                             f"the state was taken at t = {t1:g} s (expected bit-identical)")
                return
            s.do_step(cs, t1, s.cs_h)
            again = s.get(cs, watch)
            if not _same(stepped, again):
                _not_restored(f, stepped, again, f"CS: {how} and the same step again: "
                                                 f"{_differs(watch, s, stepped, again)} from the first step "
                                                 "(expected bit-identical)")

        f.doing(f"{s.prefix}SetFMUState")
        cs.setFMUState(state)
        compare("restoring the state")
        if not s.flag("cs", "canSerializeFMUstate", "canSerializeFMUState"):
            f.skip("CS: serialization: the FMU does not declare canSerializeFMUState")
        else:
            f.doing(f"{s.prefix}SerializeFMUState")
            blob = cs.serializeFMUState(state)
            f.doing(f"{s.prefix}DeserializeFMUState")
            restored = cs.deserializeFMUState(blob)
            cs.setFMUState(restored)  # the instance is one step past the state (compare stepped)
            compare("restoring a serialized and deserialized state")
            cs.freeFMUState(restored)
            f.doing(f"{s.prefix}DeserializeFMUState of a truncated state")
            status = _status_of(lambda: cs.deserializeFMUState(blob[: len(blob) // 2]))
            if status in (0, 1):
                f.warning(f"CS: a truncated serialized state ({len(blob) // 2} of {len(blob)} bytes) was accepted "
                          f"by {s.prefix}DeserializeFMUState (the standard does not require detecting it)")
        cs.freeFMUState(state)
    finally:
        s.free(cs)


def _me_state(s: Session, f: Findings) -> None:
    f.doing("Model Exchange initialization")
    me = s.instance("me", name="fmu-state")
    try:
        s.initialize(me, "me")
        if not s.nx:
            f.skip("ME: the model has no continuous states")
            return
        x = s.states(me) + OFFSET * (1 + np.arange(s.nx))
        s.set_states(me, x)
        before = np.concatenate([s.states(me), s.derivatives(me)])
        f.doing(f"{s.prefix}GetFMUState")
        state = me.getFMUState()
        s.set_states(me, x + 1.0)
        me.setTime(s.t0 + s.h)
        f.doing(f"{s.prefix}SetFMUState")
        me.setFMUState(state)
        after = np.concatenate([s.states(me), s.derivatives(me)])
        if not _same(before, after):
            _not_restored(f, before, after, f"ME: states and derivatives after restoring a state: "
                                            f"{_differs([], s, before, after)} (expected bit-identical)")
        me.freeFMUState(state)
    finally:
        s.free(me)


def check_fmu_state(s: Session, f: Findings) -> None:
    for kind, run in (("cs", _cs_state), ("me", _me_state)):
        if kind not in s.kinds():
            continue
        if not s.flag(kind, "canGetAndSetFMUstate", "canGetAndSetFMUState"):
            f.skip(f"{kind.upper()}: the FMU does not declare canGetAndSetFMUState")
            continue
        try:
            run(s, f)
        except Exception as exc:  # an FMI call failed: report it, go on with the other interface
            said = _said(s.latest) if s.latest is not None else ""
            report = f.warning if _failed_legally(exc) else f.problem
            report(f"{kind.upper()}: stopped in {f.current}: {exc}{said}")


# -- FMI 3 Co-Simulation step results ----------------------------------------------------------

def check_cs_step(s: Session, f: Findings) -> None:
    if "cs" not in s.kinds():
        f.skip("the FMU has no Co-Simulation interface")
        return
    if not s.fmi3:
        f.skip("FMI 2's fmi2DoStep has no out-arguments to check")
        return
    f.doing("Co-Simulation initialization")
    cs = s.instance("cs", name="cs-step")
    try:
        s.initialize(cs, "cs")
        t, early, wrong = s.t0, [], []
        for _ in range(s.cs_steps):
            f.doing(f"fmi3DoStep at t = {t:g} s")
            _, terminate, early_return, last = cs.doStep(t, s.cs_h)
            end = t + s.cs_h
            if early_return:
                early.append(t)
            elif not abs(last - end) <= TIME_RTOL * max(1.0, abs(end)):  # allowed, but unexpected
                wrong.append((end, last))
            if terminate or early_return:  # the FMU ends the run (allowed) or did not reach end
                break
            t = end
        if early:
            f.problem(f"fmi3DoStep returned earlyReturn = true at t = {early[0]:g} s, but the instance was "
                      "created with earlyReturnAllowed = false")
        if wrong:
            end, last = wrong[0]
            f.warning(f"fmi3DoStep to t = {end!r} s returned lastSuccessfulTime = {last!r} s "
                      f"({len(wrong)} of the steps; a complete step ends at t + h, within {TIME_RTOL:g} relative)")
    finally:
        s.free(cs)


# -- short runs ---------------------------------------------------------------------------------

def _short_run(s: Session, f: Findings, kind: str) -> None:
    from fmpy import simulate_fmu

    if kind not in s.kinds():
        f.skip(f"the FMU has no {'Model Exchange' if kind == 'me' else 'Co-Simulation'} interface")
        return
    log = FMULog()
    interval = s.h if kind == "me" else s.cs_h
    stop = s.t0 + (s.horizon if kind == "me" else s.cs_h * s.cs_steps)
    f.doing(f"simulate_fmu ({kind.upper()}) to t = {stop:g} s")
    try:
        result = simulate_fmu(s.fmu.unzipdir, validate=False, model_description=s.md, start_time=s.t0,
                              stop_time=stop, output_interval=interval, solver="CVode",
                              fmi_type="ModelExchange" if kind == "me" else "CoSimulation",
                              logger=log.logger if not s.fmi3 else log.fmi3_logger)
    except Exception as exc:  # FMPy raises FMICallException, or bare Exception
        said = log.last_error()
        report = f.problem if _illegal_status(exc) else f.warning
        report(f"the run from t = {s.t0:g} s to {stop:g} s failed: {exc}" + (f" (the FMU says: {said})"
                                                                              if said else ""))
        return
    if result["time"][-1] < stop - 1e-9 * max(1.0, abs(stop)):
        f.warning(f"the run ended at t = {result['time'][-1]:g} s, before its stop time {stop:g} s")
    for name in result.dtype.names:
        column = np.asarray(result[name])
        if column.dtype.kind in "fiu" and not np.all(np.isfinite(column)):
            first = int(np.argmax(~np.isfinite(column)))
            f.warning(f"'{name}' is not finite ({column[first]}) at t = {result['time'][first]:g} s")


def check_me_run(s: Session, f: Findings) -> None:
    _short_run(s, f, "me")


def check_cs_run(s: Session, f: Findings) -> None:
    _short_run(s, f, "cs")


@dataclass(frozen=True)
class Check:
    name: str
    run: Callable[[Session, Findings], None]


#: The dynamic checks, in the order they run.
CHECKS = (
    Check("token", check_token),
    Check("state-machine", check_state_machine),
    Check("directional-derivatives", check_directional_derivatives),
    Check("adjoint-derivatives", check_adjoint_derivatives),
    Check("fmu-state", check_fmu_state),
    Check("cs-step", check_cs_step),
    Check("me-run", check_me_run),
    Check("cs-run", check_cs_run),
)


def run_check(check: Check, session: Session, progress: Callable[[str], None] | None = None) -> Findings:
    """Run one check; an exception it does not handle ends it with one line naming the call, with what
    the FMU logged: a warning if the FMU answered a legal call with Discard, Error or Fatal or asked to
    terminate (the standard allows any call to fail), else a problem."""
    findings = Findings(progress)
    try:
        check.run(session, findings)
    except Exception as exc:
        during = f" in {findings.current}" if findings.current else ""
        what = str(exc) if isinstance(exc, FMUError) else f"{type(exc).__name__}: {exc}"
        said = _said(session.latest) if session.latest is not None else ""
        (findings.warning if _failed_legally(exc) else findings.problem)(f"stopped{during}: {what}{said}")
    return findings
