"""`cosim diagram`: a Modelica class's diagram or icon layer (MLS chapter 18) drawn as SVG.

- :mod:`cosim.diagram.annotations` reads the Modelica source: the classes of a file, their
  components, ``extends`` clauses and ``connect`` equations with their annotations (pymoca's AST
  drops the annotations of components and connections), and parses annotation expressions.
- :mod:`cosim.diagram.graphics` turns them into the graphical objects of MLS chapter 18 (layers,
  primitives with their defaults, placements), with inheritance through ``extends``, looking
  classes up in the :class:`~cosim.compiler.library.Library`.
- :mod:`cosim.diagram.svg` draws a layer as SVG.
"""
