"""Bicycle physics over FMUs: the layer above the generic FMI tools of :mod:`cosim.fmu` and the
formulas of :mod:`cosim.analytic`.

* :mod:`cosim.bicycle.parameters`: Meijaard parameter sets for a model, the rider's upper body,
  the forward speed (``--params``, ``--speed``);
* :mod:`cosim.bicycle.linearize`: the nonlinear bicycles' steady-motion reduction and speed sweeps;
* :mod:`cosim.bicycle.stability`: eigenvalues, weave and capsize speeds of ``WhippleLinear``'s FMU;
* :mod:`cosim.bicycle.twins`, :mod:`cosim.bicycle.compare`: the analytic twins of the exported
  models and ``cosim compare``.
"""
