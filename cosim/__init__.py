"""cosim: the bicycle of Astrom, Klein and Lennartsson (2005) as Modelica -> FMI 2.0 co-simulation."""

__version__ = "0.1.0"
