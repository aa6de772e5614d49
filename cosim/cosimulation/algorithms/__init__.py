"""The coupling algorithms of the master, one class per file, found by name in a registry.

:mod:`.base` defines the interface (:class:`CouplingAlgorithm`) and the registry
(:func:`register`, :func:`algorithm`, :func:`names`); the modules imported below register the
algorithms a system file may name, in this order (the order error messages list them in). A
new algorithm is one new module with a registered class, imported here.
"""
from cosim.cosimulation.algorithms.base import (CouplingAlgorithm, UnknownAlgorithm, algorithm, algorithms, names,
                                                register, unregister)
from cosim.cosimulation.algorithms import jacobi, gauss_seidel, model_exchange  # noqa: F401  (registers them)

__all__ = ["CouplingAlgorithm", "UnknownAlgorithm", "algorithm", "algorithms", "names", "register", "unregister"]
