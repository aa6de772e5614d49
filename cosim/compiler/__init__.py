"""Modelica -> FMI 2.0 compiler: pymoca flattens, CasADi makes the ODE and its C code,
gcc links it with the shared runtime in :mod:`cosim.runtime`."""
