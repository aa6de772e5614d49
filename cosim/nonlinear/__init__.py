"""Nonlinear Whipple bicycle: Kane's-method derivation (sympy), Modelica generator, steady turns
(continuation) and periodic orbits of the FMU.

* :mod:`.derivation` -- the equations of motion (``sympy.physics.mechanics.KanesMethod``);
* :mod:`.generate` -- writes ``Bicycle.Bicycles.Whipple`` and ``WhippleRider``
  (``python -m cosim.nonlinear.generate``);
* :mod:`.model` -- the FMU evaluated as a vector field (states, derivatives, linearization);
* :mod:`.continuation` -- steady turns over speed (Fig. 7);
* :mod:`.periodic` -- periodic orbits (Fig. 10).
"""
