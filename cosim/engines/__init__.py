"""Co-simulation engines: one class per engine, one file each, found by name in a registry.

:mod:`.base` defines the interface (:class:`Engine`: run one FMU, run an SSP archive) and the
registry (:func:`register`, :func:`engine`, :func:`engines`); the modules imported below
register the engines this package knows, in this order:

* ``libcosim`` (:mod:`.libcosim`, libcosimpy) and ``ecos`` (:mod:`.ecos`, ecospy): independent
  engines that run our FMUs and SSP exports unmodified (both come with the test extra);
* ``fmpy`` (:mod:`.fmpy_simulate`): FMPy's Co-Simulation, as ``cosim simulate`` runs it;
* ``cosim`` (:mod:`.cosim_master`): this project's own master.

A new engine is one new module with a registered class, imported here.
"""
from cosim.engines.base import (Engine, EngineUnavailable, EngineUnsupported, UnknownEngine, engine, engines,
                                register, unregister)
from cosim.engines import libcosim, ecos, fmpy_simulate, cosim_master  # noqa: F401  (registers them)

__all__ = ["Engine", "EngineUnavailable", "EngineUnsupported", "UnknownEngine", "engine", "engines", "register",
           "unregister"]
