"""Tests run once per registered engine (:mod:`cosim.engines`): their parameters, each with the
engine's name as id and its pytest marker (``needs_libcosim``, ``needs_ecos``)."""
from __future__ import annotations

import pytest

from cosim.engines import engines


def engine_params(runs: str | None = None, fmi_version: str = "2.0", **where) -> list:
    """One ``pytest.param`` per registered engine that runs ``runs`` ("fmu" or "ssp"; None: any)
    with FMUs of ``fmi_version`` and whose attributes have the values of ``where`` (see
    :func:`cosim.engines.engines`)."""
    return [pytest.param(e, id=e.name, marks=[getattr(pytest.mark, e.marker)] if e.marker else [])
            for e in engines(runs, fmi_version, **where)]
