"""Tools for FMU files, whoever built them: opening them safely (:mod:`.access`), resolving a
model name or file to an FMU (:mod:`.target`), checking parameter values against their
declarations (:mod:`.parameters`), simulating (:mod:`.simulate`), linearizing
(:mod:`.linearize`), validating (:mod:`.validate`), describing (:mod:`.info`) and the stability
of the Whipple FMUs over speed (:mod:`.stability`). Running them in other co-simulation engines
(libcosim, Ecos): :mod:`cosim.engines`."""
