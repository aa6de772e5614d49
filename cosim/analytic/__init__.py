"""Closed-form models from Åström, Klein & Lennartsson, "Bicycle Dynamics and Control" (2005).

See :mod:`cosim.analytic.simple` for the simple second-order models (eqs (1)-(23), (27)).
"""
from cosim.analytic.simple import *  # noqa: F401,F403
from cosim.analytic.simple import __all__  # noqa: F401
