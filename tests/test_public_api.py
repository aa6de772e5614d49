"""`cosim/__init__.py`: the public Python API, documented, lazy."""
from __future__ import annotations

import doctest
import inspect
import re
import subprocess
import sys

import pytest

import cosim

# Every exported function (not the module ``whipple``, the exception or the version string).
FUNCTIONS = [name for name in cosim.__all__ if name not in ("__version__", "whipple", "CosimError")]


def _fresh_python(code: str) -> str:
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr
    return run.stdout


def test_import_cosim_does_not_import_casadi_pymoca_or_fmpy():
    out = _fresh_python("import sys, cosim; print(sorted(m for m in ('casadi', 'pymoca', 'fmpy', 'scipy', "
                        "'cosim.compiler') if m in sys.modules))")
    assert out.strip() == "[]"


@pytest.mark.parametrize("name", cosim.__all__)
def test_public_name_resolves(name):
    assert getattr(cosim, name) is not None
    assert name in dir(cosim)


def test_unknown_public_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'no_such_function'"):
        cosim.no_such_function  # noqa: B018


@pytest.mark.parametrize("name", FUNCTIONS)
def test_public_function_has_a_numpydoc_docstring_with_units(name):
    doc = inspect.getdoc(getattr(cosim, name)) or ""
    assert callable(getattr(cosim, name))
    assert "Parameters\n----------" in doc, f"{name}: no Parameters section"
    assert "Returns\n-------" in doc or "Raises\n------" in doc, f"{name}: no Returns/Raises section"
    assert re.search(r"\[(s|m/s|1/s|rad|N m|kg[^\]]*)\]|SI units|in s\b", doc), f"{name}: no units"


def test_no_public_name_is_also_a_submodule():
    """A submodule ``cosim.X`` would replace the API function ``cosim.X`` once imported."""
    import importlib.util

    clashes = [name for name in cosim.__all__ if name != "__version__" and importlib.util.find_spec(f"cosim.{name}")]
    assert clashes == []
    out = _fresh_python("import cosim, cosim.fmu.linearize, cosim.bicycle.compare, cosim.cli; "
                        "print(type(cosim.linearize).__name__, type(cosim.compare).__name__)")
    assert out.split() == ["function", "function"]


def test_help_cosim_documents_every_public_name():
    out = _fresh_python("import cosim; help(cosim)")
    for name in cosim.__all__:
        if name != "__version__":
            assert name in out, f"help(cosim) does not mention {name}"
    assert "Public API" in out


def test_module_docstring_example_runs():
    failures, tried = doctest.testmod(cosim, verbose=False)[:2]
    assert tried >= 2 and failures == 0

