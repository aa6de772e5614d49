"""Co-simulation test matrix: many co-simulations, each with its analytic prediction, in parallel."""
