"""Modelica unit strings (``kg.m2/s``, ``N.m``) as FMI 2.0 BaseUnit exponents."""
from __future__ import annotations

import re

BASE = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
# Derived SI units in base-unit exponents.
DERIVED = {
    "N": {"kg": 1, "m": 1, "s": -2},
    "J": {"kg": 1, "m": 2, "s": -2},
    "W": {"kg": 1, "m": 2, "s": -3},
    "Pa": {"kg": 1, "m": -1, "s": -2},
    "Hz": {"s": -1},
    "g": {"kg": 1},  # factor 1e-3 handled below
    "deg": {"rad": 1},
}
FACTORS = {"g": 1e-3, "deg": 3.141592653589793 / 180}
_TOKEN = re.compile(r"^([A-Za-z]+)(-?\d+)?$")


def base_units(unit: str) -> tuple[dict[str, int], float] | None:
    """Exponents of the SI base units and the factor of ``unit``; None if not understood."""
    if unit in ("", "1"):
        return {}, 1.0
    exponents: dict[str, int] = {}
    factor = 1.0
    numerator, *denominators = unit.split("/")
    for sign, part in [(1, numerator)] + [(-1, d) for d in denominators]:
        for token in part.split("."):
            if token == "1":
                continue
            match = _TOKEN.match(token)
            if not match:
                return None
            symbol, power = match.group(1), int(match.group(2) or 1) * sign
            if symbol in BASE:
                parts = {symbol: 1}
            elif symbol in DERIVED:
                parts = DERIVED[symbol]
                factor *= FACTORS.get(symbol, 1.0) ** power
            else:
                return None
            for base, e in parts.items():
                exponents[base] = exponents.get(base, 0) + e * power
    return {k: v for k, v in exponents.items() if v}, factor
