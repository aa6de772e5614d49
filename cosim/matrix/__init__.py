"""Co-simulation test matrix: many co-simulations, each checked against its analytic prediction.

``cosim matrix SPEC.toml [--workers N] [--scheduler tcp://HOST:PORT] [-o DIR] [--resume [--keep-failed] | --force]
[--max-cases N]``. SPEC is a file or the name of a bundled spec
(``cosim/matrix/specs/NAME.toml``; ``paper`` checks the claims of Astrom, Klein & Lennartsson 2005).

Every case is one co-simulation (:mod:`cosim.cosimulation`) plus

* the **prediction**: closed-loop eigenvalues of the analytic linear models of its components,
  exact delays as Pade approximations (python-control), the master's own sample-and-hold and
  Jacobi lags included (:mod:`cosim.matrix.predict`); ``marginal`` when |max Re| < ``margin``;
* the **observation**: fell / diverged / stable / unstable / marginal from the growth rate of the
  observed signal -- the largest Re of the modes a matrix-pencil fit identifies in it, so that the
  verdict does not depend on the stop time, or the envelope for signals that are no sum of modes --,
  max |x| and the 2 % settling time (:mod:`cosim.matrix.classify`); an inconclusive observation of a
  decisive prediction is re-run ``extend`` times longer;
* the **agreement**: agree / disagree / marginal (excluded) / failed.

Spec format (TOML)::

    [matrix]                      # defaults for every study (a study may override each one)
    name = "paper"
    description = "..."
    stop = 10.0                   # co-simulated time per case [s]
    step = 0.01                   # communication step [s]
    algorithm = "jacobi"          # or "gauss-seidel"
    fall_limit = 1.0              # |observed| beyond which the bicycle fell [rad]
    margin = 0.05                 # |max Re| [1/s] below which a prediction is marginal
    observed_margin = 0.01        # |observed growth rate| [1/s] below which an observation is inconclusive
    extend = 3.0                  # inconclusive observations are re-run this many times longer (<= 100)
    pade_order = 6                # order of the Pade approximation of exact delays (1 to 20)
    master_lag = true             # model the master's hold (h/2) and Jacobi (h per static block) lags
    timeout = 120.0               # s per case before its worker is killed (the case fails; finite)
    predict = true                # false: observations only
    imports = ["blocks.py"]       # modules or files (relative to the spec) imported by every worker,
                                  # e.g. to register Python blocks and their linear models

    [[study]]
    name = "delayed-rider"
    title = "..."; claim = "..."; description = "..."
    observe = "bike.phi"          # COMPONENT.OUTPUT classified (default: the fall signal)
    connections = ["bike.phi -> rider.phi", "rider.delta -> delay.u", "delay.y -> bike.delta"]
    system = { record = ["bike.phi", "bike.psi"] }   # [system] keys of a system file (optional)
    [study.variables]             # derived values, in order; strings are expressions
    p = 3.0                       # a number, or an expression of the axes and earlier variables
    ptau = "p*tau"
    vw = "weave_speed('benchmark')"   # functions of cosim.matrix.expr: speeds of a parameter set
    [study.components.bike]       # as in a system file, plus parameter_set and initial
    model = "Bicycle.Bicycles.InvertedPendulum"     # or fmu = "x.fmu" or python = "Block"
    parameter_set = "astrom2005"  # Meijaard parameter set (WhippleLinear), bundled name or file
    parameters = { V = "=V" }     # values: numbers, or expressions of the variables ("=...")
    initial = { "frame.phi" = 0.01 }   # start values of FMU states (the perturbation)
    [study.components.rider]
    python = "SteerAngleFeedback"
    parameters = { k2 = 1.0 }
    [study.components.delay]
    python = "TransportDelay"
    parameters = { tau = "=tau" }
    [study.tune]                  # optional: the value minimizing the predicted max Re (best rider)
    "rider.k2" = { min = 0.01, max = 1000.0, points = 32, scale = "log" }
    [study.axes]                  # the cases: the product of the axes (last fastest)
    V = [1.0, 2.0, 3.0]           # a list, {from, to, step}, {linspace = [a, b, n]} or {values = [...]}
    tau = { from = 0.05, to = 0.8, step = 0.05 }
    [[study.cases]]               # and/or explicit cases
    V = 6.0
    tau = 0.1
    [[study.plots]]               # optional: the heat map's axes (default: the first two axes)
    x = "V"
    y = "ptau"
    hlines = [0.2, 2.0]
    y_unit = "1"                  # optional x_unit, y_unit: else the unit of the model parameter set to "=V"
    [[study.checks]]              # claims: stable-interval, region, growth-rate (see checks.py)
    kind = "region"
    where = "ptau > 2"
    expect = "not-stable"

Names (of the matrix and of studies) are letters, digits and ``_ . + -``: they name files. Every
key is checked when the spec is loaded (:mod:`cosim.matrix.spec`); expressions have bounded cost
(:mod:`cosim.matrix.expr`). ``--max-cases N`` runs at most N cases: a spec with more runs a
stratified sample of N (a Latin hypercube over each study's axes, the same every run, every value
of every axis in it when N allows; stderr and the report say so) without expanding the others;
without it a spec with more than 100000 cases is refused before its axes are expanded.

Output (``-o DIR``, default ``matrix-NAME``): ``results.jsonl`` (one finished case per line,
appended atomically), ``report.md``, ``report.html``, ``STUDY.png`` (heat map of observed
stability over two variables with the predicted boundary, or predicted max Re vs observed growth
rate over one), ``summary.json``, ``matrix.json`` (each written whole under a temporary name and
renamed), ``logs/worker-N.log``. A folder that already holds results is refused unless
``--resume`` (keep them, run only the missing cases and -- unless ``--keep-failed`` -- the failed
ones again) or ``--force`` (discard them). Exit status 0 when nothing disagrees, nothing failed and
every check passes; 1 otherwise; 2 for a spec, usage or output-folder error.

Execution: local worker processes (:mod:`cosim.matrix.pool`; on Linux forked from the command,
so that they start in milliseconds -- ``COSIM_MATRIX_START=spawn`` starts fresh interpreters
instead), or a Dask cluster with ``--scheduler`` (an unreachable one is reported within seconds); a worker that dies (segfaulting
FMU) or hangs fails its case only, and no worker outlives a killed supervisor
(:func:`cosim.processes.die_with_parent`).
"""
from __future__ import annotations

__all__ = ["load_spec", "run_matrix"]


def load_spec(path_or_name):
    from cosim.matrix.spec import load_spec as _load  # deferred: importing a matrix module loads this package

    return _load(path_or_name)


def run_matrix(*args, **kwargs):
    from cosim.matrix.runner import run_matrix as _run  # deferred: importing a matrix module loads this package

    return _run(*args, **kwargs)
