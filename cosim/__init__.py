"""cosim: the bicycle of Astrom, Klein and Lennartsson (2005) as Modelica -> FMI 2.0 co-simulation.

The Modelica models of ``modelica/Bicycle`` are compiled (pymoca -> CasADi -> C -> gcc) into
FMI 2.0 FMUs (Model Exchange and Co-Simulation), simulated, linearized, compared with analytic
models and co-simulated with controllers. SI units throughout: times in s, speeds in m/s, angles
in rad, torques in N m.

Public API (``import cosim`` is fast: each function is imported on first use)
------------------------------------------------------------------------------
Models and FMUs
    build            build several models (default: every exported one) into FMUs
    build_model      build one model into ``OUTPUT/<identifier>.fmu``, unless up to date
    resolve_fmu      the FMU of a model name (built if needed) or of an FMU file
Simulation and analysis of an FMU
    simulate         simulate an FMU (FMPy; Co-Simulation or Model Exchange)
    linearize        A, B, C, D of an FMU at its initial point
    compare          an FMU's linearization against the model's analytic twin
Co-simulation
    load_system      read and check a system file (TOML)
    run_system       run a system of FMUs and Python blocks
Parameters and analytic models
    load_parameters  a Meijaard parameter set (bundled name or TOML file), checked
    analytic_system  the analytic state-space model of an exported model
    whipple          the analytic linearized Whipple bicycle (Meijaard et al. 2007), a module
    eigenvalues      eigenvalues [1/s] of the Whipple bicycle at speed(s) v [m/s]
    weave_speed      speed [m/s] above which the weave mode is stable
    capsize_speed    speed [m/s] above which the capsize mode is unstable
    self_stable_interval   the first speed interval [m/s] in which the bicycle is stable
Errors
    CosimError       base of every error a user can cause (one clear message)

Example
-------
>>> import cosim
>>> params = cosim.load_parameters("benchmark")
>>> round(cosim.weave_speed(params), 4)       # Meijaard et al. (2007): 4.292 m/s
4.2924

The command line ``cosim`` (``cosim --help``) offers the same operations.
"""
from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: Public name -> (module, attribute); the modules are imported on first use (PEP 562).
_API = {
    "build": ("cosim.compiler.build", "build"),
    "build_model": ("cosim.compiler.build", "build_model"),
    "resolve_fmu": ("cosim.fmu.target", "resolve_fmu"),
    "simulate": ("cosim.fmu.simulate", "simulate"),
    "linearize": ("cosim.fmu.linearize", "linearize"),
    "compare": ("cosim.bicycle.compare", "compare_model"),
    "load_system": ("cosim.cosimulation.system", "load_system"),
    "run_system": ("cosim.cosimulation.factory", "run_system"),
    "load_parameters": ("cosim.analytic.parameters", "load_parameters"),
    "analytic_system": ("cosim.bicycle.twins", "analytic_system"),
    "whipple": ("cosim.analytic.whipple", None),
    "eigenvalues": ("cosim.analytic.whipple", "eigenvalues"),
    "weave_speed": ("cosim.analytic.whipple", "weave_speed"),
    "capsize_speed": ("cosim.analytic.whipple", "capsize_speed"),
    "self_stable_interval": ("cosim.analytic.whipple", "self_stable_interval"),
    "CosimError": ("cosim.errors", "CosimError"),
}

__all__ = ["__version__", *_API]


def _resolve(name: str):
    module_name, attribute = _API[name]
    module = importlib.import_module(module_name)
    return module if attribute is None else getattr(module, attribute)


def __getattr__(name: str):
    """Import a public function on first use (PEP 562), so ``import cosim`` loads no CasADi."""
    if name not in _API:
        raise AttributeError(f"module 'cosim' has no attribute '{name}'")
    value = _resolve(name)
    globals()[name] = value  # later look-ups do not come here
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

