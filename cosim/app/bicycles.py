"""The bicycles of the eigenvalue view of `cosim app` (``COSIM_DATA.bicycles``), as data.

Each choice says which WebAssembly module computes the state matrix A(v) (a model of
:data:`cosim.app.export.MODULES`), its parameter values (read from ``cosim/params`` by
:func:`cosim.analytic.parameters.load_parameter_set`, never written into the page by hand), how
the forward speed ``v`` [m/s] enters the module, the lateral states whose derivatives give A(v),
the speed range of the plots and the sliders shown. The page (``static/app.js``) reads nothing
else about a bicycle.

The choices (Astrom, Klein & Lennartsson 2005, "Bicycle dynamics and control", IEEE Control
Systems Magazine 25(4), is "the paper"):

``benchmark``, ``astrom2005``, ``astrom2005-riderless``
    The Meijaard et al. (2007) sets of ``cosim/params`` on ``Bicycle.Bicycles.WhippleLinear``
    (eq (24); Figures 8 and 9 of the paper and eq (25) are astrom2005, the bicycle with rider;
    astrom2005-riderless is the same bicycle without its rider, the values in parentheses of
    Table 1 and eq (25), of which the paper draws no figure), speed parameter ``v``, 0-12 m/s.
    Their explanations print the weave and capsize speeds of :mod:`cosim.analytic.whipple`
    (``{weave}`` and ``{capsize}`` in the text), never numbers typed in by hand.
``rear-steered``
    The benchmark bicycle ridden backwards: the paper's "a model for a bicycle with rear-wheel
    steering is obtained simply by reversing the sign of the velocity" (section "Rear-Wheel
    Steering", eq (18)): WhippleLinear at ``v`` from -10 to 0 m/s. It has an eigenvalue in
    the right half plane at every one of these speeds (no weave or capsize speed: it is
    never self-stable, cosim.analytic.whipple finds the same).
``crowned-roller``
    The paper's Figure 15 ("a crowned roller with lateral radius 0.3 m at the rear and a heavy
    front wheel"; Figure 21, eq (27)): the nonlinear ``Bicycle.Bicycles.Whipple`` with a toroidal
    rear wheel of crown radius ``tR`` = :data:`CROWN_RADIUS` (0.3 m, the caption) and a knife-edge
    front wheel, on the adapted bicycle of :mod:`cosim.analytic.roller`
    (``cosim/params/adapted/fig15.toml``, the bicycle of ``cosim figures fig15``: our data, chosen
    to reproduce the paper's weave speed 3.9 m/s, capsize stable at every speed and real parts
    smaller than Figure 9's; the explanation prints cosim.analytic.roller's speeds). A(v) is the
    lateral block (roll, steer and their rates) of the module's directional derivatives at upright
    straight running, ``u_R0 = -v/rR``: at that point the columns of the pitch, the forward speed
    and the ignorable coordinates in the lateral rows are exactly zero and the pitch rate's row
    has zero roll and steer coefficients (the pitch is even in roll and steer), so the
    elimination of :func:`cosim.bicycle.linearize.steady_motion` changes nothing and the block is
    the exact lateral reduction (tests/test_app.py checks it against ``cosim linearize`` and the
    weave speed against cosim.analytic.roller). ``tR`` has a slider (0-1 m; eq (27) makes the
    paper's pendulum on two rollers statically stable for a rocking radius above the height of
    the centre of mass).

``measured/...``
    Real bicycles without rider measured by Moore et al. (2010, 2012), the published data of
    BicycleParameters (``cosim/params/measured``, :data:`MEASURED_LABELS`), on WhippleLinear;
    their explanations name the source and its licence (:data:`MEASURED_SOURCE`).

Every parameter of a choice can also be typed into the page's parameter editor.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from cosim.analytic import roller, whipple
from cosim.analytic.parameters import load_parameter_set

LINEAR = "Bicycle.Bicycles.WhippleLinear"
NONLINEAR = "Bicycle.Bicycles.Whipple"

#: Crown radius of the crowned rear roller [m]: Figure 15 of the paper (caption).
CROWN_RADIUS = roller.RADII[0]

#: Speed ranges of the plots [m/s]: forwards, and backwards for the rear-steered bicycle.
#: Forwards up to 12 m/s: every weave and capsize speed of the sets offered (astrom2005 capsizes
#: at 10.368 m/s) lies inside, with room to see the capsize mode grow (checked by :func:`page_data`).
FORWARD = {"min": 0.0, "max": 12.0, "num": 200, "default": 5.0, "step": 0.01}
BACKWARD = {"min": -10.0, "max": 0.0, "num": 200, "default": -5.0, "step": 0.01}

#: Sliders (name, label, unit, minimum, maximum, step). Every bicycle's values must lie inside
#: the ranges of the sliders it shows (checked by :func:`page_data`).
SLIDERS = (
    ("w", "wheelbase w", "m", 0.5, 2.0, 0.001),
    ("c", "trail c", "m", -0.1, 0.3, 0.001),
    ("lam", "steer-axis tilt \u03bb", "rad", -0.2, 0.8, 0.001),
    ("mB", "rear frame mass m_B", "kg", 1.0, 150.0, 0.1),
    ("rF", "front wheel radius r_F", "m", 0.1, 0.6, 0.001),
    ("rR", "rear wheel radius r_R", "m", 0.1, 0.6, 0.001),
    ("tR", "rear crown radius t_R", "m", 0.0, 1.0, 0.001),
)
#: The sliders every bicycle shows; the crowned roller adds ``tR``.
COMMON_SLIDERS = ("w", "c", "lam", "mB", "rF", "rR")

#: Lateral states of each module (A(v) is the Jacobian of their derivatives with respect to them).
LATERAL_STATES = {
    LINEAR: ("phi", "delta", "phi_dot", "delta_dot"),
    NONLINEAR: ("phi", "delta", "u_phi", "u_delta"),
}
#: How the forward speed v [m/s] enters each module: ``parameter = sign * v / divisor`` (the
#: divisor a parameter of the bicycle, or None for 1). Whipple: upright straight running,
#: u_R0 = -v/rR (the rear wheel rate is negative rolling forward).
SPEED = {
    LINEAR: {"parameter": "v", "sign": 1.0, "divisor": None},
    NONLINEAR: {"parameter": "u_R0", "sign": -1.0, "divisor": "rR"},
}
#: The pitch a module solves from its initial equations (Newton's method from the guess
#: parameter): the page passes the pitch solved for one parameter set as the guess of the next
#: (continuation; the pitch of upright straight running depends on the geometry, not the speed).
PITCH = {
    NONLINEAR: {"state": "theta", "guess": "theta_guess"},
}


#: The measured bicycles offered (``cosim/params/measured``): set name -> what the page calls it.
MEASURED_LABELS = {
    "measured/browser": "Batavus Browser",
    "measured/crescendo": "Batavus Crescendo",
    "measured/fisher": "Gary Fisher mountain bicycle",
    "measured/pista": "Bianchi Pista",
    "measured/yellow": "Yellow",
    "measured/yellow-reversed": "Yellow with its fork reversed",
}
#: Where the measured values come from and under which licence (shown with each of them).
MEASURED_SOURCE = ("Data: BicycleParameters 1.5.2 (J. K. Moore and the BicycleParameters authors, "
                   "BSD 2-clause licence), nominal values of its benchmark files.")


@dataclass(frozen=True)
class Bicycle:
    """One choice of the page (see the module docstring)."""

    name: str
    label: str
    explanation: str
    module: str
    parameter_set: str  # a bundled Meijaard set of cosim/params (or measured/NAME)
    speeds: dict
    modifiers: dict = field(default_factory=dict)  # further parameters of the module, SI units
    sliders: tuple = COMMON_SLIDERS


BICYCLES = (
    Bicycle("benchmark", "benchmark (Meijaard et al. 2007)",
            "The benchmark bicycle with rider of Meijaard, Papadopoulos, Ruina & Schwab (2007), Table 1, on the "
            "linear Whipple model (eq (24) of the paper). Self-stable between the weave speed {weave} and the "
            "capsize speed {capsize} (cosim analytic).",
            LINEAR, "benchmark", FORWARD),
    Bicycle("astrom2005", "astrom2005 (the paper, with rider)",
            "The bicycle with rider of \u00c5str\u00f6m, Klein & Lennartsson (2005), Table 1 and eq (25): Figure 8 "
            "(the root locus) and Figure 9 (real parts of the eigenvalues vs speed) of the paper. Self-stable from "
            "the weave speed {weave} to the capsize speed {capsize} (cosim analytic).",
            LINEAR, "astrom2005", FORWARD),
    Bicycle("astrom2005-riderless", "astrom2005-riderless (the paper, no rider)",
            "The same bicycle without its rider (Table 1 and eq (25), the values in parentheses); the paper "
            "draws no figure of it (its Figures 8 and 9 are the bicycle with rider). Lighter and with a lower "
            "centre of mass, it is self-stable at lower speeds: from {weave} to {capsize} (cosim analytic).",
            LINEAR, "astrom2005-riderless", FORWARD),
    Bicycle("crowned-roller", "crowned roller at the rear (Figure 15)",
            "The paper's adapted bicycle with a rider for teaching children (Figure 15; Figure 21, eq (27)): a "
            f"crowned rear roller of lateral radius t_R = {CROWN_RADIUS} m (the caption), a heavy front wheel (3 kg "
            "in the rim) and the centre of mass 0.4 m high. The paper gives no other data: this bicycle "
            "(cosim/params/adapted/fig15.toml, the one of `cosim figures fig15`) was chosen to reproduce what it "
            "states: the weave mode becomes stable at {weave} (the paper: 3.9 m/s), the capsize mode is stable at "
            "every speed, and the real parts are smaller than those of the astrom2005 "
            "bicycle (Figure 9), so it is easier to ride. Computed by the nonlinear Whipple model (toroidal rear "
            "wheel) linearized about upright straight running; cosim.analytic.roller gives the same weave speed. "
            "Eq (27) predicts a slower fall for a larger rocking radius: try t_R.",
            NONLINEAR, roller.ADAPTED_NAME, FORWARD, {"tR": CROWN_RADIUS, "tF": 0.0}, (*COMMON_SLIDERS, "tR")),
    Bicycle("rear-steered", "rear-steered (the benchmark ridden backwards)",
            "Rear-wheel steering: \"a model for a bicycle with rear-wheel steering is obtained simply by reversing "
            "the sign of the velocity\" (the paper, section Rear-Wheel Steering, eq (18)). The benchmark bicycle "
            "at negative speeds: an eigenvalue lies in the right half plane at every speed, so it is never "
            "self-stable, and a rider must stabilize a fast unstable mode.",
            LINEAR, "benchmark", BACKWARD),
    *(Bicycle(name, f"measured: {label} (no rider)",
              f"{label}, measured by Moore, Hubbard, Peterson, Schwab & Kooijman (2010) and Moore (2012): the "
              "bicycle alone, without a rider, on the linear Whipple model. Self-stable from the weave speed "
              "{weave} to the capsize speed {capsize} (cosim analytic). " + MEASURED_SOURCE,
              LINEAR, name, FORWARD)
      for name, label in MEASURED_LABELS.items()),
)


def _states_of(description: dict) -> dict[str, str]:
    """State name -> the name of its derivative, from the ``derivative`` attribute (1-based index)."""
    variables = description["variables"]
    return {variables[v["derivative"] - 1]["name"]: v["name"] for v in variables if "derivative" in v}


#: Decimals of the speeds [m/s] the page prints (weave, capsize, self-stable interval).
SPEED_DIGITS = 3


def analytic_speeds(bicycle: Bicycle) -> dict:
    """Weave and capsize speeds of :mod:`cosim.analytic` for a bicycle of :data:`LINEAR`
    (:mod:`cosim.analytic.whipple`) or of :data:`NONLINEAR` on a crowned rear roller
    (:mod:`cosim.analytic.roller`).

    Parameters
    ----------
    bicycle : Bicycle
        A choice ridden forwards: on :data:`LINEAR` without modifiers, or on :data:`NONLINEAR` with
        at most the rear crown radius ``tR`` and a knife-edge front wheel (``tF`` = 0).

    Returns
    -------
    dict
        ``weave`` and ``capsize`` [m/s] (None where cosim.analytic finds none below 30 m/s; for the
        roller, a capsize speed of None means none at any speed).

    Raises
    ------
    ValueError
        A bicycle that cosim.analytic does not describe (another module, modifiers, backwards),
        or a speed outside the bicycle's speed range (the page would print "none").
    """
    params = dict(load_parameter_set(bicycle.parameter_set).values)
    rolling = bicycle.module == NONLINEAR and set(bicycle.modifiers) <= {"tR", "tF"} \
        and bicycle.modifiers.get("tF", 0.0) == 0.0
    if bicycle.speeds["min"] < 0 or not (rolling or bicycle.module == LINEAR and not bicycle.modifiers):
        raise ValueError(f"bicycle {bicycle.name}: cosim.analytic gives no weave or capsize speed for it")
    if rolling:  # a crowned rear roller, knife-edge front wheel: cosim.analytic.roller
        R = bicycle.modifiers.get("tR", 0.0)
        speeds = {"weave": roller.weave_speed(params, R), "capsize": roller.capsize_speed(params, R)}
    else:
        speeds = {"weave": whipple.weave_speed(params), "capsize": whipple.capsize_speed(params)}
    low, high = bicycle.speeds["min"], bicycle.speeds["max"]
    for name, v in speeds.items():
        if v is not None and not low <= v <= high:
            raise ValueError(f"bicycle {bicycle.name}: the {name} speed {v:.{SPEED_DIGITS}f} m/s lies outside "
                             f"its speed range [{low}, {high}] m/s")
    return speeds


def bicycle_data(bicycle: Bicycle, description: dict | None = None) -> dict:
    """One entry of ``COSIM_DATA.bicycles``, checked against its module's description if given.

    Parameters
    ----------
    bicycle : Bicycle
        The choice.
    description : dict, optional
        The module's NAME.json (parsed); without it the names are checked by the page at load.

    Returns
    -------
    dict
        ``name``, ``label``, ``explanation``, ``module``, ``parameterSet``, ``parameters`` (name ->
        value, SI), ``waived`` (the triangle-inequality checks the set's file waives), ``speed``
        (:data:`SPEED`), ``states`` and ``derivatives`` (``derivatives`` only with a description),
        ``speeds`` and ``sliders`` (names), ``pitch`` (:data:`PITCH`, None for a module without).

    Raises
    ------
    ValueError
        A parameter that is not a parameter of the module, a lateral state it lacks, a value
        outside its slider's range or an unknown slider (each named); an explanation that prints
        the speeds of cosim.analytic for a bicycle it does not describe (:func:`analytic_speeds`).
    """
    loaded = load_parameter_set(bicycle.parameter_set)
    values = {**loaded.values, **bicycle.modifiers}
    states = LATERAL_STATES[bicycle.module]
    speed = SPEED[bicycle.module]
    sliders = {s[0]: s for s in SLIDERS}
    for name in bicycle.sliders:
        if name not in sliders:
            raise ValueError(f"bicycle {bicycle.name}: no slider {name}")
        if name not in values:
            raise ValueError(f"bicycle {bicycle.name}: the slider {name} is not one of its parameters")
        _, _, _, low, high, _ = sliders[name]
        if not low <= values[name] <= high:
            raise ValueError(f"bicycle {bicycle.name}: {name} = {values[name]} outside its slider [{low}, {high}]")
    entry = {"name": bicycle.name, "label": bicycle.label, "explanation": bicycle.explanation,
             "module": bicycle.module, "parameterSet": bicycle.parameter_set, "parameters": values,
             "waived": list(loaded.waiver.checks) if loaded.waiver else [], "speed": dict(speed),
             "states": list(states), "speeds": dict(bicycle.speeds), "sliders": list(bicycle.sliders),
             "pitch": dict(PITCH[bicycle.module]) if bicycle.module in PITCH else None}
    if description is not None:
        variables = {v["name"]: v for v in description["variables"]}
        guess = [entry["pitch"]["guess"]] if entry["pitch"] else []
        unknown = [k for k in [*values, speed["parameter"], *guess]
                   if variables.get(k, {}).get("causality") != "parameter"]
        if unknown:
            raise ValueError(f"bicycle {bicycle.name}: {', '.join(unknown)} not parameters of {bicycle.module}")
        derivative = _states_of(description)
        pitch = [entry["pitch"]["state"]] if entry["pitch"] else []
        missing = [s for s in [*states, *pitch] if s not in derivative]
        if missing:
            raise ValueError(f"bicycle {bicycle.name}: {bicycle.module} has no state(s) {', '.join(missing)}")
        entry["derivatives"] = [derivative[s] for s in states]
    if "{weave}" in bicycle.explanation or "{capsize}" in bicycle.explanation:
        speeds = analytic_speeds(bicycle)
        entry["explanation"] = bicycle.explanation.format(
            **{k: "none" if v is None else f"{v:.{SPEED_DIGITS}f} m/s" for k, v in speeds.items()})
    return entry


def page_data(description: dict, descriptions: dict | None = None) -> dict:
    """``window.COSIM_DATA`` without the modules: the bicycles, sliders and (as before, for the
    first three choices) ``model``, ``parameterSets``, ``lateralStates``, ``sliders``, ``speeds``.

    Parameters
    ----------
    description : dict
        NAME.json of :data:`LINEAR`.
    descriptions : dict, optional
        Model name -> NAME.json of every module; the bicycles of a module not given are checked
        by the page when it loads (a missing state or parameter is then its error message).

    Raises
    ------
    ValueError
        As :func:`bicycle_data`, naming the bicycle and the parameter; also if the Meijaard sets
        of :data:`LINEAR` do not share one list of parameters.
    """
    known = {LINEAR: description, **(descriptions or {})}
    bicycles = [bicycle_data(b, known.get(b.module)) for b in BICYCLES]
    sets = {b["parameterSet"]: b["parameters"] for b in bicycles if b["module"] == LINEAR and b["name"] == b["parameterSet"]}
    first = next(iter(sets))
    for name, values in sets.items():
        if sorted(values) != sorted(sets[first]):
            raise ValueError(f"parameter set {name} has other parameters than {first}")
    return {"model": LINEAR, "parameterSets": sets, "lateralStates": list(LATERAL_STATES[LINEAR]),
            "sliders": [dict(zip(("name", "label", "unit", "min", "max", "step"), s)) for s in SLIDERS],
            "speeds": dict(FORWARD), "bicycles": bicycles, "speedDigits": SPEED_DIGITS}
