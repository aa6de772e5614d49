"""Closed-form models, independent of the Modelica: the simple second-order models of Åström,
Klein & Lennartsson, "Bicycle Dynamics and Control" (2005), eqs (1)-(23), (27)
(:mod:`.simple`); the linearized Whipple bicycle of Meijaard et al. (2007) (:mod:`.whipple`) and
its parameter sets (:mod:`.parameters`); the analytic twins of the exported models
(:mod:`.twins`) and their comparison with FMU linearizations (:mod:`.compare`); the
``cosim analytic`` command (:mod:`.cli`).

Nothing is imported here, so that ``cosim`` commands load python-control only when they use it.
"""
