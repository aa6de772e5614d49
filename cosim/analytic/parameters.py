"""Parameter sets of the linearized Whipple bicycle (Meijaard et al. 2007).

A parameter set is a plain ``dict[str, float]`` keyed by exactly the symbols of
Meijaard, Papadopoulos, Ruina & Schwab (2007), "Linearized dynamics equations
for the balance and steer of a bicycle: a benchmark and review",
Proc. R. Soc. A 463:1955-1982, Table 1 (see :data:`PARAMETER_NAMES`).

Conventions: x forward, y right, z down, origin at the rear-wheel contact
point; ``lam`` is the steer-axis tilt from the vertical; inertias are tensor
elements about each body's own centre of mass (``I*xz`` = -integral(x z dm));
wheels are axisymmetric (``IRzz = IRxx``, ``IFzz = IFxx``).  Units are SI.

Bundled sets live in ``cosim/params/<name>.toml`` (one ``key = value`` line per
symbol, comments document source and conversion).  A set whose published values are
not physically plausible says so in the file itself (:data:`WAIVER_KEY`,
:data:`REASON_KEY`, see :func:`load_parameter_set`): the same rule holds for the
bundled files and for any copy or user file, and the waiver is reported wherever
the set is used.  The same folder holds the
rider's upper body (``rider/``, :func:`load_upper_body`, :func:`rider_parameters`)
and the lumped bicycle of the simple second-order models (``second-order/``,
:func:`load_second_order`).  These files are the one source of the parameter
values: the Modelica records ``Bicycle.Records`` are generated from them
(:mod:`cosim.analytic.records`).
"""
from __future__ import annotations

import math
import os
import re
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from cosim.errors import ParameterError
from cosim.outputs import check_input_file

__all__ = [
    "PARAMETER_NAMES",
    "UNITS",
    "WAIVABLE",
    "WAIVER_KEY",
    "REASON_KEY",
    "Waiver",
    "ParameterSet",
    "bundled_parameter_sets",
    "measured_parameter_sets",
    "load_parameter_set",
    "load_parameters",
    "load_set_for_models",
    "parameters_for_model",
    "MAX_SPEED",
    "validate_parameters",
    "UPPER_BODY_UNITS",
    "SECOND_ORDER_UNITS",
    "load_upper_body",
    "split_upper_body",
    "merged_rear_frame",
    "rider_parameters",
    "load_second_order",
]

#: The 26 symbols of Meijaard et al. (2007), Table 1, in the paper's order.
PARAMETER_NAMES: tuple[str, ...] = (
    "w", "c", "lam", "g",
    "rR", "mR", "IRxx", "IRyy",
    "xB", "zB", "mB", "IBxx", "IBxz", "IByy", "IBzz",
    "xH", "zH", "mH", "IHxx", "IHxz", "IHyy", "IHzz",
    "rF", "mF", "IFxx", "IFyy",
)

#: SI unit of every parameter.
UNITS: dict[str, str] = {
    **{k: "m" for k in ("w", "c", "rR", "rF", "xB", "zB", "xH", "zH")},
    "lam": "rad",
    "g": "m/s^2",
    **{k: "kg" for k in ("mR", "mB", "mH", "mF")},
    **{k: "kg m^2" for k in PARAMETER_NAMES if k.startswith("I")},
}

#: Keys whose triangle-inequality check may be waived (the check is reported
#: under this key).  Positivity and positive-(semi)definiteness never can.
WAIVABLE: frozenset[str] = frozenset({"IRyy", "IByy", "IHyy", "IFyy"})

#: TOML key of a parameter file listing the checks (keys of :data:`WAIVABLE`) the set
#: is allowed to fail, e.g. ``allow_nonphysical = ["IByy", "IHyy"]``.
WAIVER_KEY = "allow_nonphysical"
#: TOML key of the reason for :data:`WAIVER_KEY` (a non-empty string, required with it).
REASON_KEY = "nonphysical_reason"


@dataclass(frozen=True)
class Waiver:
    """Checks a parameter file declares it fails, and why (:data:`WAIVER_KEY`, :data:`REASON_KEY`).

    Attributes
    ----------
    checks : tuple of str
        Keys of :data:`WAIVABLE` whose triangle-inequality check is skipped, in
        :data:`PARAMETER_NAMES` order.
    reason : str
        The file's reason (``nonphysical_reason``).
    """

    checks: tuple[str, ...]
    reason: str

    def describe(self) -> str:
        """One line: which checks are waived and why (the same for a file and for its copy)."""
        return (f"non-physical values accepted: triangle inequality of {', '.join(self.checks)} not checked "
                f"({WAIVER_KEY}); reason: {self.reason}")


@dataclass(frozen=True)
class ParameterSet:
    """A loaded, validated Meijaard parameter set (:func:`load_parameter_set`).

    Attributes
    ----------
    values : dict of str to float
        The 26 symbols in :data:`PARAMETER_NAMES` order [SI].
    waiver : Waiver or None
        The checks the file waives, None if it waives none.
    path : Path
        The file read.
    """

    values: dict[str, float]
    waiver: Waiver | None
    path: Path

# Relative slack for the (semi)definiteness and triangle inequalities: thin
# discs (IRyy = 2 IRxx) satisfy them with equality up to rounding.
_REL_TOL = 1e-12


def _params_dir() -> Path:
    return Path(str(resources.files("cosim").joinpath("params")))


def bundled_parameter_sets() -> list[str]:
    """Names of the bundled parameter sets.

    Returns
    -------
    list of str
        Sorted stems of ``cosim/params/*.toml``, e.g. ``["astrom2005",
        "astrom2005-riderless", "benchmark"]``; each is accepted by
        :func:`load_parameters`.
    """
    return sorted(p.stem for p in _params_dir().glob("*.toml"))


#: Subfolder of ``cosim/params`` with measured bicycles; its sets are named ``measured/<stem>``.
MEASURED = "measured"


def measured_parameter_sets() -> list[str]:
    """Names of the bundled measured bicycles (BicycleParameters' published data).

    Returns
    -------
    list of str
        Sorted names ``measured/<stem>`` of ``cosim/params/measured/*.toml``, e.g.
        ``"measured/browser"``; each is accepted by :func:`load_parameters`. They are kept apart
        from :func:`bundled_parameter_sets` (the sets of the papers, which the Modelica records
        and the reference checks are made from).
    """
    return _sets_in(MEASURED)


#: Subfolder of ``cosim/params`` with the adapted bicycles the paper describes without data (our
#: choice, see each file); its sets are named ``adapted/<stem>`` (``adapted/fig15``: Figure 15).
ADAPTED = "adapted"
#: The subfolders whose sets are named ``FOLDER/<stem>``, and what their sets are called.
NAMED_FOLDERS = {MEASURED: "measured bicycle", ADAPTED: "adapted bicycle"}


def _sets_in(folder: str) -> list[str]:
    """Sorted names ``folder/<stem>`` of the sets in ``cosim/params/<folder>``."""
    return sorted(f"{folder}/{p.stem}" for p in (_params_dir() / folder).glob("*.toml"))


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


#: Largest magnitude of a parameter in SI units (a bicycle of 1e6 m or 1e6 kg is already absurd;
#: far larger values overflow the inertia sums).
MAX_MAGNITUDE = 1e6


def _coerce(params: Mapping[str, object]) -> dict[str, float]:
    """Exact key set, finite real numbers -> dict of floats in canonical order."""
    if not isinstance(params, Mapping):
        raise TypeError(f"parameters must be a mapping, got {type(params).__name__}")
    unknown = [k for k in params if k not in PARAMETER_NAMES]
    if unknown:
        raise ValueError(f"{unknown[0]}: unknown parameter (expected the Meijaard 2007 symbols "
                         f"{', '.join(PARAMETER_NAMES)}); unknown keys: {', '.join(map(str, unknown))}")
    missing = [k for k in PARAMETER_NAMES if k not in params]
    if missing:
        raise ValueError(f"{missing[0]}: missing parameter; missing keys: {', '.join(missing)}")
    out: dict[str, float] = {}
    for k in PARAMETER_NAMES:
        value = params[k]
        if hasattr(value, "item") and getattr(value, "ndim", None) == 0:  # numpy scalar
            value = value.item()
        if not _is_number(value):
            raise ValueError(f"{k}: must be a real number [{UNITS[k]}], got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise ValueError(f"{k}: must be finite [{UNITS[k]}], got {value!r}")
        if abs(value) > MAX_MAGNITUDE:  # products of squares of such values overflow
            raise ValueError(f"{k}: {value:g} [{UNITS[k]}] is beyond any bicycle (|value| <= {MAX_MAGNITUDE:g})")
        out[k] = value
    return out



def validate_parameters(params: Mapping[str, object], *, waive: Iterable[str] = ()) -> dict[str, float]:
    """Check a parameter set for completeness and physical plausibility.

    Parameters
    ----------
    params : mapping of str to float
        Exactly the keys :data:`PARAMETER_NAMES` (SI units, see :data:`UNITS`).
    waive : iterable of str, optional
        Keys from :data:`WAIVABLE` whose triangle-inequality check is skipped
        (documented data-set quirks only).

    Returns
    -------
    dict of str to float
        The parameters as floats, in :data:`PARAMETER_NAMES` order.

    Raises
    ------
    ValueError
        The message starts with the offending key, ``"<key>: ..."``.  Raised for
        unknown or missing keys; non-numeric or non-finite values; ``w``,
        ``rR``, ``rF``, ``g`` not positive; ``|c| >= w``; ``lam`` outside
        (-pi/2, pi/2); negative masses or ``mH + mF == 0``; rear/front frame
        centre of mass not above the ground (``zB``, ``zH`` must be < 0);
        negative moments of inertia; inertia tensors that are not positive
        semidefinite (``I*xz``) or violate the triangle inequality of the
        principal moments (``IRyy <= 2 IRxx``, ``IFyy <= 2 IFxx``, and for
        the frames ``I*yy <= I*xx + I*zz`` and
        ``sqrt((I*xx - I*zz)**2 + 4 I*xz**2) <= I*yy``, reported under
        ``IByy``/``IHyy``); and for keys in ``waive`` not in :data:`WAIVABLE`.
    """
    waived = set(waive)
    bad = sorted(waived - WAIVABLE)
    if bad:
        raise ValueError(f"{bad[0]}: only the triangle-inequality checks of "
                         f"{', '.join(sorted(WAIVABLE))} can be waived")
    p = _coerce(params)

    def fail(key: str, why: str) -> None:
        raise ValueError(f"{key}: {why} (got {key} = {p[key]!r} {UNITS[key]})")

    for k in ("w", "rR", "rF", "g"):
        if not p[k] > 0.0:
            fail(k, "must be positive")
    if not abs(p["c"]) < p["w"]:
        fail("c", "trail must satisfy |c| < w (wheelbase)")
    if not -math.pi / 2 < p["lam"] < math.pi / 2:
        fail("lam", "steer-axis tilt must lie in (-pi/2, pi/2) rad")
    for k in ("mR", "mB", "mH", "mF"):
        if p[k] < 0.0:
            fail(k, "mass must be non-negative")
    if p["mH"] + p["mF"] <= 0.0:
        fail("mH", "front assembly mass mH + mF must be positive")
    for k in ("zB", "zH"):
        if not p[k] < 0.0:
            fail(k, "centre of mass must be above the ground (z points down, so z < 0)")

    # Wheels: tensor diag(Ixx, Iyy, Ixx).
    for wheel in ("R", "F"):
        ixx, iyy = f"I{wheel}xx", f"I{wheel}yy"
        for k in (ixx, iyy):
            if p[k] < 0.0:
                fail(k, "moment of inertia must be non-negative")
        if iyy not in waived and p[iyy] > 2.0 * p[ixx] * (1 + _REL_TOL):
            fail(iyy, f"triangle inequality violated: {iyy} <= 2 {ixx} = {2 * p[ixx]!r} required "
                      f"for an axisymmetric wheel")

    # Frames: tensor [[Ixx, 0, Ixz], [0, Iyy, 0], [Ixz, 0, Izz]].
    for body in ("B", "H"):
        ixx, ixz, iyy, izz = (f"I{body}{s}" for s in ("xx", "xz", "yy", "zz"))
        for k in (ixx, iyy, izz):
            if p[k] < 0.0:
                fail(k, "moment of inertia must be non-negative")
        scale = max(p[ixx], p[izz], p[iyy], abs(p[ixz]))
        if p[ixx] * p[izz] - p[ixz] ** 2 < -_REL_TOL * scale**2:
            fail(ixz, f"inertia tensor not positive semidefinite: {ixz}**2 <= {ixx}*{izz} "
                      f"= {p[ixx] * p[izz]!r} required")
        if iyy in waived:
            continue
        if p[iyy] > (p[ixx] + p[izz]) * (1 + _REL_TOL):
            fail(iyy, f"triangle inequality of principal moments violated: {iyy} <= {ixx} + {izz} "
                      f"= {p[ixx] + p[izz]!r} required")
        spread = math.hypot(p[ixx] - p[izz], 2.0 * p[ixz])  # difference of the x-z principal moments
        if spread > p[iyy] * (1 + _REL_TOL) + _REL_TOL * scale:
            fail(iyy, f"triangle inequality of principal moments violated: {iyy} >= "
                      f"sqrt(({ixx}-{izz})**2 + 4 {ixz}**2) = {spread!r} required")
    return p


def _resolve(name_or_path: str | os.PathLike[str]) -> Path:
    """The file of a bundled name, or the path given."""
    bundled = {p.stem: p for p in _params_dir().glob("*.toml")}
    text = os.fspath(name_or_path)
    folder = text.split("/", 1)[0]
    if isinstance(name_or_path, str) and folder in NAMED_FOLDERS and "/" in text and not os.path.exists(text):
        named = _sets_in(folder)
        if text not in named:
            raise ValueError(f"unknown {NAMED_FOLDERS[folder]} {text!r}; bundled: {', '.join(named)}")
        return _params_dir() / f"{text}.toml"
    looks_like_path = isinstance(name_or_path, os.PathLike) or text.endswith(".toml") or os.sep in text \
        or (os.altsep is not None and os.altsep in text)
    if not looks_like_path:
        if text not in bundled:
            raise ValueError(f"unknown bundled parameter set {text!r}; bundled: "
                             f"{', '.join(sorted(bundled))}; measured: {', '.join(measured_parameter_sets())} "
                             "(or pass a path to a .toml file)")
        return bundled[text]
    path = Path(text).expanduser()
    if not os.path.exists(path):  # (False also for a name too long to be a file)
        raise FileNotFoundError(f"parameter file not found: {path}")
    return check_input_file(path, ValueError, str(path), "parameter file")  # a folder, a FIFO, a device


def _line(text: str, key: str, item: str | None = None) -> int | None:
    """1-based line of the top-level ``key = ...`` in a TOML text (of ``"item"`` after it if given)."""
    match = re.search(rf"^[ \t]*{re.escape(key)}[ \t]*=", text, re.MULTILINE)
    if match is None:
        return None
    at = match.start()
    if item is not None:
        found = re.compile(rf"[\"']{re.escape(item)}[\"']").search(text, at)
        at = found.start() if found else at
    return text.count("\n", 0, at) + 1


def _read_waiver(data: dict, text: str, path: Path) -> Waiver | None:
    """The waiver a parameter file declares (:data:`WAIVER_KEY`, :data:`REASON_KEY`), checked.

    Raises
    ------
    ValueError
        ``"<file>:<line>: <key>: ..."`` for a waiver that is not a list of distinct keys of
        :data:`WAIVABLE`, an empty list, a reason that is missing, empty or not a string, or a
        reason without a waiver.
    """
    def refuse(key: str, why: str, item: str | None = None) -> ValueError:
        line = _line(text, key, item)
        return ValueError(f"{path}{f':{line}' if line else ''}: {key}: {why}")

    checks, reason = data.get(WAIVER_KEY), data.get(REASON_KEY)
    if checks is None:
        if reason is not None:
            raise refuse(REASON_KEY, f"a reason without a waiver: add {WAIVER_KEY} = [...] (the checks it "
                                     f"explains) or remove {REASON_KEY}")
        return None
    waivable = ", ".join(k for k in PARAMETER_NAMES if k in WAIVABLE)
    if not isinstance(checks, list) or not all(isinstance(k, str) for k in checks):
        raise refuse(WAIVER_KEY, f"must be a list of parameter names, e.g. {WAIVER_KEY} = [\"IByy\"], "
                                 f"got {checks!r}")
    if not checks:
        raise refuse(WAIVER_KEY, f"the list is empty; name the checks to waive or remove {WAIVER_KEY}")
    for k in checks:
        if k not in PARAMETER_NAMES:
            raise refuse(WAIVER_KEY, f"{k!r} is not a parameter; only the triangle-inequality checks of "
                                     f"{waivable} can be waived", k)
        if k not in WAIVABLE:
            raise refuse(WAIVER_KEY, f"the checks of {k} cannot be waived; only the triangle-inequality "
                                     f"checks of {waivable} can", k)
        if checks.count(k) > 1:
            raise refuse(WAIVER_KEY, f"{k} is listed twice", k)
    if not isinstance(reason, str) or not reason.strip():
        got = "it is missing" if reason is None else f"got {reason!r}"
        raise refuse(REASON_KEY if reason is not None else WAIVER_KEY,
                     f"{WAIVER_KEY} needs {REASON_KEY} = \"...\", a non-empty string saying why the set "
                     f"keeps non-physical values ({got})")
    return Waiver(tuple(k for k in PARAMETER_NAMES if k in checks), " ".join(reason.split()))


def _read_file(path: Path) -> tuple[dict, Waiver | None, str]:
    """The parameter entries (waiver keys removed), the waiver and the text of a parameter file."""
    try:
        text = path.read_bytes().decode("utf-8")
        data = tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise ValueError(f"{path}: not valid TOML: nested too deeply") from None
    except OSError as exc:  # e.g. no permission to read it
        raise ValueError(f"{path}: cannot read the parameter file: {exc.strerror or exc}") from None
    waiver = _read_waiver(data, text, path)
    return {k: v for k, v in data.items() if k not in (WAIVER_KEY, REASON_KEY)}, waiver, text


def load_parameter_set(name_or_path: str | os.PathLike[str]) -> ParameterSet:
    """Load and validate a parameter set with the waiver its file declares.

    A file may keep values that fail a triangle-inequality check (a published table's
    rounding, say) only if it says so itself::

        allow_nonphysical = ["IByy", "IHyy"]     # keys of WAIVABLE
        nonphysical_reason = "why the values are kept"

    Bundled files and any other file follow this one rule: a byte-identical copy of a
    bundled file loads exactly as the bundled set.  Each waived check must actually fail
    (a stale waiver is refused), and every other check still applies.

    Parameters
    ----------
    name_or_path : str or path-like
        A bundled name (see :func:`bundled_parameter_sets`, e.g. ``"benchmark"``,
        ``"astrom2005"``, ``"astrom2005-riderless"``) or the path of a TOML file with one
        top-level ``key = number`` entry per symbol of :data:`PARAMETER_NAMES` (SI units)
        and optionally :data:`WAIVER_KEY` with :data:`REASON_KEY`.  Strings ending in
        ``.toml`` or containing a path separator are treated as paths.

    Returns
    -------
    ParameterSet
        Values, waiver (None if none) and the file read.

    Raises
    ------
    ValueError
        Unknown bundled name, malformed TOML, a malformed waiver (``"<file>:<line>: <key>:
        ..."``, see :data:`WAIVABLE`), a waived check that holds, or any failure of
        :func:`validate_parameters` (message starts with the offending key, ends with
        ``[in <file>]``).
    FileNotFoundError
        A path that does not exist.
    """
    path = _resolve(name_or_path)
    values, waiver, text = _read_file(path)
    checks = set(waiver.checks) if waiver else set()
    try:
        params = validate_parameters(values, waive=checks)
    except ValueError as exc:
        raise ValueError(f"{exc} [in {path}]") from exc
    for k in sorted(checks):  # a stale waiver would hide a later error: each waived check must fail
        try:
            validate_parameters(params, waive=checks - {k})
        except ValueError:
            continue
        line = _line(text, WAIVER_KEY, k)
        raise ValueError(f"{path}{f':{line}' if line else ''}: {WAIVER_KEY}: the triangle inequality of {k} "
                         f"holds, there is nothing to waive; remove {k} from {WAIVER_KEY}")
    return ParameterSet(params, waiver, path)


def load_parameters(name_or_path: str | os.PathLike[str], *, waive: Iterable[str] = ()) -> dict[str, float]:
    """Load and validate a parameter set: the values of :func:`load_parameter_set`.

    Parameters
    ----------
    name_or_path : str or path-like
        A bundled name or a TOML file, as for :func:`load_parameter_set` (the file's own
        waiver, :data:`WAIVER_KEY`, applies).
    waive : iterable of str, optional
        Further triangle-inequality checks to skip (keys from :data:`WAIVABLE`), for
        callers that need only what a model uses (e.g. values that never enter it).

    Returns
    -------
    dict of str to float
        Validated parameters in :data:`PARAMETER_NAMES` order, in SI units (lengths [m], masses
        [kg], inertias [kg m^2], angles [rad], g [m/s^2]; see :data:`UNITS`).

    Raises
    ------
    ValueError, FileNotFoundError
        As :func:`load_parameter_set`; also for keys in ``waive`` not in :data:`WAIVABLE`.
    """
    extra = set(waive)
    if not extra:
        return load_parameter_set(name_or_path).values
    path = _resolve(name_or_path)
    values, waiver, _ = _read_file(path)
    try:
        return validate_parameters(values, waive=extra | set(waiver.checks if waiver else ()))
    except ValueError as exc:
        raise ValueError(f"{exc} [in {path}]") from exc


def load_set_for_models(name_or_path: str | os.PathLike[str], option: str = "--params") -> ParameterSet:
    """:func:`load_parameter_set` of a set a user names for a model (``--params``, system files).

    The one loader of such sets: the Modelica models with Meijaard's parameters
    (``Bicycle.Bicycles.WhippleLinear``, ``Whipple``, ...) name them exactly as the symbols of
    :data:`PARAMETER_NAMES`, so the values apply to a model unchanged.

    Parameters
    ----------
    name_or_path : str or path-like
        A bundled name or a TOML file, as for :func:`load_parameter_set`.
    option : str
        How the user named the set, the start of every message.

    Returns
    -------
    ParameterSet
        Values [SI], waiver and file.

    Raises
    ------
    ParameterError
        Unknown bundled name, malformed TOML or an invalid set (the message names the option,
        the set and the key).
    FileNotFoundError
        A path that does not exist.
    """
    try:
        return load_parameter_set(name_or_path)
    except ValueError as exc:
        raise ParameterError(f"{option} {os.fspath(name_or_path)}: {exc}") from None


def parameters_for_model(name_or_path: str | os.PathLike[str]) -> dict[str, float]:
    """Parameter values [SI] of a Meijaard set for the models that carry Meijaard's names, by
    symbol of :data:`PARAMETER_NAMES` (the values of :func:`load_set_for_models`; errors as there).
    The forward speed is not part of a set."""
    return dict(load_set_for_models(name_or_path).values)


#: Largest forward speed [m/s] in magnitude that --speed/--speeds accept (beyond it the squares of
#: the speed in the equations of motion lose every digit of the other terms, then overflow).
MAX_SPEED = 1e4


# --------------------------------------------------------------------------- further data sets
# Files in sub-folders of cosim/params/ (not Meijaard sets, so not listed by bundled_parameter_sets):
#   rider/<name>.toml         the rider's upper body on a hip hinge (WhippleRider)
#   second-order/<name>.toml  the lumped bicycle of the simple models of Astrom et al. (2005)

#: Symbols of the rider's upper body U (``cosim/params/rider/*.toml``) and their SI units.
UPPER_BODY_UNITS: dict[str, str] = {
    "mU": "kg", "xU": "m", "hU": "m", "lU": "m",
    "IUxx": "kg m^2", "IUxz": "kg m^2", "IUyy": "kg m^2", "IUzz": "kg m^2",
    "kU": "N m/rad", "cU": "N m s/rad",
}

#: Symbols of the simple second-order models (``cosim/params/second-order/*.toml``), SI units.
SECOND_ORDER_UNITS: dict[str, str] = {
    "m": "kg", "a": "m", "h": "m", "b": "m", "c": "m", "lambda": "rad", "J": "kg m^2", "D": "kg m^2",
    "g": "m/s^2", "m_r": "kg", "J_r": "kg m^2", "h_r": "m", "V": "m/s", "R": "m", "k3": "s",
}


def _load_table(folder: str, name: str, units: Mapping[str, str]) -> dict[str, float]:
    """Exactly the keys of ``units`` from ``cosim/params/<folder>/<name>.toml``, as finite floats."""
    directory = _params_dir() / folder
    path = directory / f"{name}.toml"
    if not path.is_file():
        known = ", ".join(sorted(p.stem for p in directory.glob("*.toml"))) or "none"
        raise ValueError(f"unknown {folder} parameter set {name!r}; bundled: {known}")
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise ValueError(f"{path}: not valid TOML: nested too deeply") from None
    unknown = [k for k in data if k not in units]
    missing = [k for k in units if k not in data]
    if unknown or missing:
        raise ValueError(f"{path}: keys must be exactly {', '.join(units)} "
                         f"(unknown: {', '.join(unknown) or 'none'}; missing: {', '.join(missing) or 'none'})")
    out = {}
    for k in units:
        value = data[k]
        if not _is_number(value) or not math.isfinite(float(value)):
            raise ValueError(f"{k}: must be a finite real number [{units[k]}], got {value!r} [in {path}]")
        out[k] = float(value)
    return out


def load_upper_body(name: str = "benchmark") -> dict[str, float]:
    """The rider's upper body U on its hip hinge, ``cosim/params/rider/<name>.toml``.

    Parameters
    ----------
    name : str
        Bundled name (``"benchmark"``: the upper body split off the benchmark's rear frame).

    Returns
    -------
    dict of str to float
        ``mU`` [kg], ``xU``, ``hU``, ``lU`` [m], ``IUxx``, ``IUxz``, ``IUyy``, ``IUzz`` [kg m^2]
        about U's centre of mass, ``kU`` [N m/rad], ``cU`` [N m s/rad] (see :data:`UPPER_BODY_UNITS`).

    Raises
    ------
    ValueError
        Unknown name, malformed TOML, missing or unknown keys, or a value that is not a finite number.
    """
    return _load_table("rider", name, UPPER_BODY_UNITS)


def upper_body_for(name_or_path: str | os.PathLike[str]) -> str:
    """The bundled upper body (``cosim/params/rider/<name>.toml``) that a Meijaard set carries.

    A bundled set with an upper body of its own name (``astrom2005``: the paper's rear frame with
    rider, whose roll inertia is too small for the benchmark's upper body) takes that one; every
    other set, and any set given as a path, takes the benchmark's.

    Parameters
    ----------
    name_or_path : str or path-like
        A ``--params`` argument: a bundled name or a TOML file.

    Returns
    -------
    str
        A name for :func:`load_upper_body`.
    """
    text = os.fspath(name_or_path)
    if text in bundled_parameter_sets() and (_params_dir() / "rider" / f"{text}.toml").is_file():
        return text
    return "benchmark"


def split_upper_body(bicycle: Mapping[str, float], upper_body: Mapping[str, float]) -> dict[str, float]:
    """The bicycle with the rider's upper body split off its rear frame.

    With the hip hinge locked upright, rear frame + upper body of the result is exactly the rear
    frame B of ``bicycle`` (same mass, centre of mass and inertia, by the parallel-axis theorem).

    Parameters
    ----------
    bicycle : mapping of str to float
        A Meijaard parameter set (:data:`PARAMETER_NAMES`) whose rear frame B includes the whole rider.
    upper_body : mapping of str to float
        The upper body (:func:`load_upper_body`); its centre of mass is at
        ``x = xU``, ``z = -(hU + lU)``.

    Returns
    -------
    dict of str to float
        The Meijaard symbols (rear frame B now without the upper body) followed by the upper body's.

    Raises
    ------
    ValueError
        If the upper body is not lighter than the rear frame (``mU >= mB``).
    """
    b, u = dict(bicycle), dict(upper_body)
    mB = b["mB"] - u["mU"]
    if not mB > 0.0:
        raise ValueError(f"mU: the upper body must be lighter than the rear frame (mU = {u['mU']!r} kg, "
                         f"mB = {b['mB']!r} kg)")
    xUc, zUc = u["xU"], -(u["hU"] + u["lU"])  # U's centre of mass
    xB = (b["mB"] * b["xB"] - u["mU"] * xUc) / mB
    zB = (b["mB"] * b["zB"] - u["mU"] * zUc) / mB

    # the parts' point-mass contributions about the composite centre (the old rear frame's)
    pu = _point_mass_inertia(u["mU"], xUc - b["xB"], zUc - b["zB"])
    pb = _point_mass_inertia(mB, xB - b["xB"], zB - b["zB"])
    rest = {f"IB{k}": b[f"IB{k}"] - u[f"IU{k}"] - pu[k] - pb[k] for k in ("xx", "yy", "zz", "xz")}
    return {**b, "mB": mB, "xB": xB, "zB": zB, **rest, **u}


def merged_rear_frame(p: Mapping[str, float]) -> dict[str, float]:
    """The Meijaard parameters of a bicycle whose rider's upper body is locked to the rear frame.

    The upper body (mass ``mU``, centre of mass at ``x = xU``, ``z = -(hU + lU)``, inertia
    ``IU..`` about it) and the rear frame ``B`` become one rigid body: mass, centre of mass and
    inertia tensor about the combined centre of mass by the parallel-axis theorem (tensor
    elements, ``I*xz = -integral(x z dm)``). Inverse of :func:`split_upper_body`. Units: SI.
    """
    mB, mU = p["mB"], p["mU"]
    m = mB + mU
    if not m > 0:
        raise ValueError(f"mB + mU must be positive, got {m!r} kg")
    xU, zU = p["xU"], -(p["hU"] + p["lU"])
    x, z = (mB * p["xB"] + mU * xU) / m, (mB * p["zB"] + mU * zU) / m
    parts = [_point_mass_inertia(mB, p["xB"] - x, p["zB"] - z), _point_mass_inertia(mU, xU - x, zU - z)]
    out = {k: p[k] for k in PARAMETER_NAMES}
    out.update(mB=m, xB=x, zB=z, **{f"IB{k}": p[f"IB{k}"] + p[f"IU{k}"] + sum(q[k] for q in parts)
                                    for k in ("xx", "yy", "zz", "xz")})
    return out


def _point_mass_inertia(m: float, dx: float, dz: float) -> dict[str, float]:
    """Inertia-tensor elements (xx, yy, zz, xz) [kg m^2] of a point mass ``m`` at ``(dx, 0, dz)`` from
    the reference point (tensor elements: ``xz = -m dx dz``)."""
    return {"xx": m * dz**2, "yy": m * (dx**2 + dz**2), "zz": m * dx**2, "xz": -m * dx * dz}


def rider_parameters(bicycle: str = "benchmark", upper_body: str = "benchmark") -> dict[str, float]:
    """Bundled bicycle with the bundled upper body split off: the defaults of the rider models.

    ``split_upper_body(load_parameters(bicycle), load_upper_body(upper_body))``; the values of
    ``Bicycle.Records.BenchmarkRider`` and of ``cosim.nonlinear.generate``'s ``WhippleRider``.
    """
    return split_upper_body(load_parameters(bicycle), load_upper_body(upper_body))


def load_second_order(name: str = "astrom2005") -> dict[str, float]:
    """Parameters of the simple second-order models, ``cosim/params/second-order/<name>.toml``.

    Parameters
    ----------
    name : str
        Bundled name (``"astrom2005"``: Astrom, Klein & Lennartsson 2005, Table 1 lumped).

    Returns
    -------
    dict of str to float
        The keys of :data:`SECOND_ORDER_UNITS`: ``m``, ``a``, ``h``, ``b``, ``c``, ``lambda``
        (head angle [rad]), ``J``, ``D``, ``g``, the rider's ``m_r``, ``J_r``, ``h_r`` and the
        models' default operating values ``V``, ``R``, ``k3``.

    Raises
    ------
    ValueError
        Unknown name, malformed TOML, missing or unknown keys, or a value that is not a finite number.
    """
    return _load_table("second-order", name, SECOND_ORDER_UNITS)
