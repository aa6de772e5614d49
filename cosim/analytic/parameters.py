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
symbol, comments document source and conversion).
"""
from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Iterable, Mapping
from importlib import resources
from pathlib import Path

__all__ = [
    "PARAMETER_NAMES",
    "UNITS",
    "WAIVABLE",
    "BUNDLED_WAIVERS",
    "bundled_parameter_sets",
    "load_parameters",
    "validate_parameters",
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

_TRIANGLE_WAIVER_REASON = (
    "Astrom, Klein & Lennartsson (2005), Table 1 prints frame inertias that violate the "
    "triangle inequality of principal moments (rear frame by more than its rounding); "
    "IByy and IHyy do not enter the linearized model, so the printed values are kept"
)

#: Checks waived for bundled sets, ``{name: {key: reason}}``.  Applied when a
#: bundled set is loaded by name or by the path of its bundled file.
BUNDLED_WAIVERS: dict[str, dict[str, str]] = {
    "astrom2005": {"IByy": _TRIANGLE_WAIVER_REASON, "IHyy": _TRIANGLE_WAIVER_REASON},
    "astrom2005-riderless": {"IByy": _TRIANGLE_WAIVER_REASON, "IHyy": _TRIANGLE_WAIVER_REASON},
}

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


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


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


def _resolve(name_or_path: str | os.PathLike[str]) -> tuple[Path, str | None]:
    """File to read and, if it is a bundled file, its bundled name."""
    bundled = {p.stem: p for p in _params_dir().glob("*.toml")}
    text = os.fspath(name_or_path)
    looks_like_path = isinstance(name_or_path, os.PathLike) or text.endswith(".toml") or os.sep in text \
        or (os.altsep is not None and os.altsep in text)
    if not looks_like_path:
        if text not in bundled:
            raise ValueError(f"unknown bundled parameter set {text!r}; bundled: "
                             f"{', '.join(sorted(bundled))} (or pass a path to a .toml file)")
        return bundled[text], text
    path = Path(text).expanduser()
    if not path.is_file():
        raise FileNotFoundError(f"parameter file not found: {path}")
    resolved = path.resolve()
    for name, bundled_path in bundled.items():
        if bundled_path.resolve() == resolved:
            return path, name
    return path, None


def load_parameters(name_or_path: str | os.PathLike[str], *, waive: Iterable[str] = ()) -> dict[str, float]:
    """Load and validate a parameter set.

    Parameters
    ----------
    name_or_path : str or path-like
        A bundled name (see :func:`bundled_parameter_sets`, e.g.
        ``"benchmark"``, ``"astrom2005"``, ``"astrom2005-riderless"``) or the
        path of a TOML file with one top-level ``key = number`` entry per
        symbol of :data:`PARAMETER_NAMES` (SI units).  Strings ending in
        ``.toml`` or containing a path separator are treated as paths.
    waive : iterable of str, optional
        Extra triangle-inequality checks to skip (keys from
        :data:`WAIVABLE`).  Bundled sets get their documented waivers
        (:data:`BUNDLED_WAIVERS`) automatically, also when loaded by the path
        of the bundled file.

    Returns
    -------
    dict of str to float
        Validated parameters in :data:`PARAMETER_NAMES` order.

    Raises
    ------
    ValueError
        Unknown bundled name, malformed TOML, or any failure of
        :func:`validate_parameters` (message starts with the offending key).
    FileNotFoundError
        A path that does not exist.
    """
    path, bundled_name = _resolve(name_or_path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    waived = set(waive) | set(BUNDLED_WAIVERS.get(bundled_name or "", {}))
    try:
        return validate_parameters(data, waive=waived)
    except ValueError as exc:
        raise ValueError(f"{exc} [in {path}]") from exc
