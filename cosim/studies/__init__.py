"""Studies built on the tools: the set-up demo (:mod:`.demo`), the rider-delay sweep
(:mod:`.delay_sweep`) and the convergence of the co-simulation coupling (:mod:`.convergence`)."""
