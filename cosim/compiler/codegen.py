"""Model-specific C: CasADi generates the functions, a small template wraps them into the
``cosim_model`` tables (``runtime/cosim_model.h``) that the shared runtime expects: its core
``runtime/cosim_runtime.c`` with the API of one FMI version, ``fmi2_api.c`` or ``fmi3_api.c``, and
the interpreter of the tape of the local variables, ``cosim_tape.c`` (:mod:`cosim.compiler.tape`)."""
from __future__ import annotations

import shutil
from pathlib import Path

import casadi as ca

from cosim.compiler.description import ModelInfo, value_reference
from cosim.compiler.fmu import RUNTIME_FILES
from cosim.compiler.ode import ExplicitModel
from cosim.compiler.tape import tape_tables

RUNTIME_DIR = Path(__file__).resolve().parents[1] / "runtime"
# Above this many doubles the CasADi work array goes to the heap, not the stack (thread stacks are small).
STACK_WORK_LIMIT = 16384
# Newton solve of the initial equations: stop when max |residual| <= NEWTON_ABSTOL (or the step is
# that small) or after NEWTON_MAX_ITER iterations. Newton converges quadratically, so from a guess
# inside its region of attraction it reaches rounding level in a few iterations; the solution is
# accepted when max |residual| <= INIT_TOLERANCE, which leaves room for rounding in residuals of
# larger magnitude (e.g. a few metres), and refused if not (or NaN).
NEWTON_ABSTOL = 1e-14
NEWTON_MAX_ITER = 50
INIT_TOLERANCE = 1e-10
# The FMI versions an FMU can be built for ("2": FMI 2.0, "3": FMI 3.0).
FMI_VERSIONS = ("2", "3")


def fmi_header_dir() -> Path:
    """FMI 2.0 and 3.0 standard headers as shipped by FMPy."""
    import fmpy

    return Path(fmpy.__file__).resolve().parent / "c-code"


def casadi_functions(model: ExplicitModel) -> list[ca.Function]:
    """The functions of the runtime contract, as CasADi functions: ``cosim_calc``, ``cosim_start``,
    ``cosim_eval``, ``cosim_jvp``, ``cosim_hoist``, ``cosim_vjp`` and ``cosim_locals``, all of z
    for ``eval_locals`` (absent if every algebraic variable is an output).

    ``cosim_jvp`` (forward mode, directional derivatives) and ``cosim_vjp`` (reverse mode, adjoint
    derivatives of FMI 3) differentiate the same outputs, der(x) and the output variables, with
    respect to the same inputs, x, u and the Real parameters: ``cosim_vjp(t, x, u, p, wxdot, wz)``
    returns ``(wx, wu, wp) = J^T (wxdot, wz)``, with exact zeros in ``wp`` for the Integer and
    Boolean parameters (not differentiated).

    ``cosim_eval`` takes the parameter-only subexpressions of its outputs as an extra input q,
    which ``cosim_hoist`` computes from p (``nq = 0``: none); the runtime computes q once when the
    parameters change (``calc_hoisted``/``eval_hoisted`` of ``cosim_model.h``)."""
    t, x, u, p = model.t, model.x, model.u, model.p
    dx, du, dp = (ca.SX.sym(n, s.numel(), 1) for n, s in (("dx", x), ("du", u), ("dp", p)))
    # The integrators need the state derivatives and the outputs; the locals of an assembly (every
    # connector variable of every component: 4000 in the Whipple bicycle with a rider) are computed
    # only when an importer reads one (eval_locals), and have no directional derivatives (FMI 2
    # defines them for the ModelStructure unknowns). Compiled with the rest, they took two thirds of
    # the build and of every model evaluation.
    outputs = derivative_outputs(model)
    z_eval = ca.vertcat(*[model.z[k] for k in outputs]) if has_locals(model) else model.z
    differentiated = ca.vertcat(model.xdot, *[model.z[k] for k in outputs])
    # Integer and Boolean parameters are not differentiated (d/dn of (-1)^n is NaN, and NaN*0 is NaN).
    real = [k for k, s in enumerate(model.parameters) if s.python_type is float]
    p_real = ca.vertcat(*[p[k] for k in real]) if real else ca.SX(0, 1)
    dp_real = ca.vertcat(*[dp[k] for k in real]) if real else ca.SX(0, 1)
    seeds = ca.vertcat(dx, du, dp_real)
    directional = (ca.jtimes(differentiated, ca.vertcat(x, u, p_real), seeds) if differentiated.numel()
                   else ca.SX(0, 1))
    nx = model.xdot.numel()
    # Reverse mode (fmi3GetAdjointDerivative) of the same outputs: the weights w on (der(x), outputs)
    # give J^T w for the same (x, u, p_real) in one reverse sweep, without forming the Jacobian.
    wxdot, wz = ca.SX.sym("wxdot", nx), ca.SX.sym("wz", differentiated.numel() - nx)
    weights = ca.vertcat(wxdot, wz)
    knowns = ca.vertcat(x, u, p_real)
    adjoint = (ca.jtimes(differentiated, knowns, weights, True) if differentiated.numel()
               else ca.SX.zeros(knowns.numel()))
    nu = u.numel()
    real_slot = {k: j for j, k in enumerate(real)}
    # every parameter gets an entry (densified: CasADi writes only the structural non-zeros of an
    # output, the runtime expects every entry written); Integer/Boolean ones an exact 0
    wp = ca.vertcat(*[adjoint[nx + nu + real_slot[k]] if k in real_slot else ca.SX.zeros(1)
                      for k in range(p.numel())]) if p.numel() else ca.SX(0, 1)
    adjoint_function = ca.Function(
        "cosim_vjp", [t, x, u, p, wxdot, wz],
        [ca.densify(adjoint[:nx]), ca.densify(adjoint[nx:nx + nu]), ca.densify(wp)],
        ["t", "x", "u", "p", "wxdot", "wz"], ["wx", "wu", "wp"])
    # A subexpression of the parameters only (the linear bicycle's matrices, the Pade delay's
    # coefficients, the sines of the head angle) is the same in every evaluation; taken out, it is
    # computed once per parameter change (a third less time per co-simulation step of the linear
    # bicycle with an LQR rider and a delay). The same operations on the same values: the results
    # do not change by a bit.
    (xdot, z_hoisted), q_symbols, q_values = ca.extract_parametric([model.xdot, z_eval], p)
    q = ca.vertcat(*q_symbols) if q_symbols else ca.SX(0, 1)
    q_value = ca.vertcat(*q_values) if q_values else ca.SX(0, 1)
    return [
        ca.Function("cosim_calc", [p], [model.c], ["p"], ["c"]),
        start_function(model),
        ca.Function("cosim_eval", [t, x, u, p, q], [xdot, z_hoisted], ["t", "x", "u", "p", "q"], ["xdot", "z"]),
        ca.Function("cosim_jvp", [t, x, u, p, dx, du, dp], [directional[:nx] if nx else ca.SX(0, 1),
                                                            directional[nx:]],
                    ["t", "x", "u", "p", "dx", "du", "dp"], ["dxdot", "dz"]),
        ca.Function("cosim_hoist", [p], [q_value], ["p"], ["q"]),
        adjoint_function,
        *([ca.Function("cosim_locals", [t, x, u, p], [ca.densify(model.z)], ["t", "x", "u", "p"], ["z"])]
          if has_locals(model) else []),
    ]


def derivative_outputs(model: ExplicitModel) -> list[int]:
    """Indices into ``z`` of the algebraic variables with directional derivatives, which ``eval``
    computes: the outputs."""
    return [k for k, s in enumerate(model.algebraics) if s.output]


def has_locals(model: ExplicitModel) -> bool:
    """Whether the model has local algebraic variables, which ``eval_locals`` computes (with all
    of z) from a tape that the runtime interprets (:mod:`cosim.compiler.tape`); without them
    ``eval`` computes all of z."""
    return not all(s.output for s in model.algebraics)


def runtime_files(fmi_version: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The runtime's files of an FMU of ``fmi_version``: those of ``cosim/runtime`` (C sources and
    headers) and the FMI standard's headers (from FMPy, :func:`fmi_header_dir`); see
    :data:`cosim.compiler.fmu.RUNTIME_FILES`."""
    return RUNTIME_FILES[_check_version(fmi_version)]


def source_files(model: ExplicitModel | ModelInfo, fmi_version: str = "2") -> list[str]:
    """The C sources of the FMU of ``fmi_version``, in compile order (listed in FMI 2's
    modelDescription.xml and FMI 3's buildDescription.xml): those CasADi writes, then the tables
    and the runtime."""
    runtime = [name for name in runtime_files(fmi_version)[0] if name.endswith(".c")]
    return generated_sources(model, fmi_version) + ["model.c", *runtime]


def generated_sources(model: ExplicitModel | ModelInfo, fmi_version: str = "2") -> list[str]:
    """The C files CasADi writes: the small functions with ``eval``; the Jacobian-vector product,
    the largest function, and (FMI 3 only) the vector-Jacobian product, each in a file of its own
    so that gcc compiles them in parallel with the rest (the build time of a large model is mostly
    gcc's). (``eval_locals`` is no C code but a tape in ``model.c``.)"""
    return ["model_functions.c", *unoptimized_sources(model, fmi_version)]


def unoptimized_sources(model: ExplicitModel | ModelInfo, fmi_version: str = "2") -> list[str]:
    """The C files that no integration step runs, compiled without optimization: the
    Jacobian-vector product (directional derivatives, called per linearization) and the
    vector-Jacobian product (adjoint derivatives, ``fmi3GetAdjointDerivative``). With the local
    variables they were most of gcc's time for the nonlinear bicycles (-O1: 2.0 s of 2.9 s of CPU
    for the one with a rider); at -O0 the 1001-speed linearization sweep of the Whipple bicycle
    takes 0.09 s instead of 0.06 s, and its results do not change by a bit.

    FMI 2 has no adjoint derivatives: its FMUs have no vector-Jacobian product (``vjp = NULL``),
    which would cost them about as much gcc time as the Jacobian-vector product for nothing
    (0.34 s of CPU at -O0 for the nonlinear bicycle with a rider; FMI 3 builds of every model take
    about 6 % more CPU than FMI 2 builds)."""
    adjoint = ["model_vjp.c"] if _check_version(fmi_version) == "3" else []
    return ["model_jvp.c", *adjoint]


def _check_version(fmi_version: str) -> str:
    if fmi_version not in FMI_VERSIONS:
        raise ValueError(f"FMI version must be one of {', '.join(FMI_VERSIONS)}, got {fmi_version!r}")
    return fmi_version


def start_function(model: ExplicitModel) -> ca.Function:
    """``cosim_start``: the start values of the states.

    Without initial equations ``x0 = s(p)`` (an SX function of the parameters). With them an MX
    function of ``(t, u, p, x, given)``: a state flagged in ``given`` (set by the importer) keeps
    the value ``x``, the others start at ``s(p)``; then the states declared ``fixed = false``
    are solved from the initial equations by Newton's method (CasADi ``fast_newton``, which can
    be code-generated; ``newton`` cannot), starting from those values. The second output is the
    residual at the solution: the generated ``fast_newton`` reports success even when it has not
    converged (NaN included), so the C wrapper checks the residual itself (``INIT_TOLERANCE``).
    """
    if not model.init_unknowns:
        return ca.Function("cosim_start", [model.p], [model.x0], ["p"], ["x0"])
    x, nx, free = model.x, model.x.numel(), model.init_unknowns
    others = ca.SX.sym("x_known", nx)
    z = ca.SX.sym("x_solved", len(free))
    slot = {k: j for j, k in enumerate(free)}
    x_trial = ca.vertcat(*[z[slot[k]] if k in slot else others[k] for k in range(nx)])
    known = ca.vertcat(model.t, model.u, model.p, others)
    residual = ca.Function("cosim_init_residual", [z, known],
                           [ca.substitute(model.init_residual, x, x_trial)], ["x_solved", "known"], ["r"])
    solver = ca.rootfinder("cosim_init_newton", "fast_newton", residual,
                           {"abstol": NEWTON_ABSTOL, "abstolStep": NEWTON_ABSTOL, "max_iter": NEWTON_MAX_ITER})
    t, u, p = ca.MX.sym("t"), ca.MX.sym("u", model.u.numel()), ca.MX.sym("p", model.p.numel())
    x_given, given = ca.MX.sym("x", nx), ca.MX.sym("given", nx)
    start = ca.Function("cosim_start_values", [model.p], [model.x0])(p)
    x_start = ca.if_else(given, x_given, start)  # elementwise; the unselected branch is not propagated
    known_values = ca.vertcat(t, u, p, x_start)
    solution = solver(x_start[free], known_values)
    x0 = ca.vertcat(*[solution[slot[k]] if k in slot else x_start[k] for k in range(nx)])
    return ca.Function("cosim_start", [t, u, p, x_given, given], [x0, residual(solution, known_values)],
                       ["t", "u", "p", "x", "given"], ["x0", "residual"])


def _c_double(value) -> str:
    return repr(float(value)) if value is not None else "0.0"


def _c_string(text: str) -> str:
    """``text`` as a C string literal: printable ASCII as is, everything else as octal escapes
    of its UTF-8 bytes (an octal escape ends after three digits, so no digit can join it)."""
    out = []
    for byte in text.encode("utf-8"):
        char = chr(byte)
        if char in '"\\?':  # '?' too: no trigraphs
            out.append("\\" + char)
        elif 0x20 <= byte < 0x7F:
            out.append(char)
        else:
            out.append(f"\\{byte:03o}")
    return '"' + "".join(out) + '"'


def _array(ctype: str, name: str, items: list[str]) -> str:
    body = ", ".join(items) if items else "0"
    return f"static const {ctype} {name}[{max(1, len(items))}] = {{{body}}};\n"


def _wrapper(f: ca.Function, signature: str, args: list[str], results: list[str], c_name: str | None = None) -> str:
    name = f.name()
    sz_arg, sz_res, sz_iw, sz_w = f.sz_arg(), f.sz_res(), f.sz_iw(), f.sz_w()
    arg_init = ", ".join(args + ["0"] * (sz_arg - len(args)))
    res_init = ", ".join(results + ["0"] * (sz_res - len(results)))
    heap = sz_w > STACK_WORK_LIMIT
    lines = [
        f"static int {c_name or 'call_' + name[6:]}({signature}) {{",
        f"    const casadi_real *arg[{max(1, sz_arg)}] = {{{arg_init}}};",
        f"    casadi_real *res[{max(1, sz_res)}] = {{{res_init}}};",
        f"    casadi_int iw[{max(1, sz_iw)}];",
    ]
    if heap:
        lines += [f"    casadi_real *w = (casadi_real *)malloc({sz_w} * sizeof(casadi_real));",
                  "    int status;", "    if (!w) return 1;",
                  f"    status = {name}(arg, res, iw, w, 0);", "    free(w);", "    return status;", "}"]
    else:
        lines += [f"    casadi_real w[{max(1, sz_w)}];", f"    return {name}(arg, res, iw, w, 0);", "}"]
    return "\n".join(lines) + "\n"


def model_c(info: ModelInfo, functions: list[ca.Function], fmi_version: str = "2") -> str:
    """The tables and wrappers of ``model.c`` of an FMU of ``fmi_version`` ("2" or "3": the same
    tables; only FMI 3 has the vector-Jacobian product)."""
    fmi3 = _check_version(fmi_version) == "3"  # adjoint derivatives and arrays
    calc, start, evaluate, jvp, hoist, vjp, *local = functions
    types = [f"COSIM_{v.type.upper()}" for v in info.variables]
    starts = [_c_double(v.start) for v in info.variables]
    names = [_c_string(v.name) for v in info.variables]
    # 0: exact start value, 1: computed from the parameters, 2: solved from the initial equations
    calculated_start = [{"calculated": "1", "approx": "2"}.get(v.initial, "0") for v in info.by_role("state")]
    # Slot of each algebraic variable in the dz of cosim_jvp: the outputs in order, -1 for a local
    # (the same selection as derivative_outputs: an algebraic variable is an output iff declared so).
    outputs = iter(range(info.sizes["nz"]))
    jvp_slots = [str(next(outputs)) if v.causality == "output" else "-1" for v in info.by_role("algebraic")]
    s = info.sizes
    # FMI 3 arrays (cosim_model.h): 1 for a scalar, n for the first element of an array, 0 after it
    lengths = ["1"] * len(info.variables)
    for first, (_, n) in (info.fmi3_arrays.items() if fmi3 else ()):
        lengths[first:first + n] = [str(n)] + ["0"] * (n - 1)
    arrays = fmi3 and any(length != "1" for length in lengths)
    return (
        f"/* Generated by cosim for {info.name}. Do not edit: run `cosim build` instead. */\n"
        "#include <math.h>\n#include <stdlib.h>\n#include \"cosim_model.h\"\n#include \"cosim_tape.h\"\n"
        + "".join(f"#include \"{Path(name).with_suffix('.h')}\"\n"
                  for name in generated_sources(info, fmi_version)) + "\n"
        + _array("cosim_type", "types", types)
        + _array("double", "start", starts)
        + _array("unsigned char", "state_start_calculated", calculated_start)
        + _array("char *const", "names", names)
        + _array("int", "z_jvp_slot", jvp_slots)
        + (_array("int", "fmi3_length", lengths) if arrays else "")
        + "\n"
        + _wrapper(calc, "const double *p, double *c", ["p"], ["c"])
        + _start_wrapper(info, start)
        + _wrapper(hoist, "const double *p, double *q", ["p"], ["q"])
        + _eval_wrappers(info, evaluate, hoist.numel_out(0), local[0] if local else None)
        + _wrapper(jvp, "double t, const double *x, const double *u, const double *p, const double *dx, "
                        "const double *du, const double *dp, double *dxdot, double *dz",
                   ["&t", "x", "u", "p", "dx", "du", "dp"], ["dxdot", "dz"])
        + (_vjp_wrapper(info, vjp) if fmi3 else "")
        + "\nconst cosim_model COSIM_MODEL = {\n"
        f"    \"{info.guid}\",\n"
        f"    {s['nx']}, {s['nu']}, {s['np']}, {s['nc']}, {s['nz']},\n"
        f"    {info.default_tolerance!r},\n"
        f"    {info.fixed_step_vr},\n"
        "    types, start, state_start_calculated,\n"
        "    call_calc, call_start, call_eval, call_jvp,\n"
        "    names,\n"
        f"    {_c_string(info.init_unknowns) if info.init_unknowns else '0'},\n"
        f"    {'z_jvp_slot' if jvp_slots else '0'},\n"
        f"    {'call_locals' if local else '0'},\n"
        f"    {hoist.numel_out(0)}, call_hoist, eval_hoisted,\n"
        f"    {'call_vjp' if fmi3 else '0'},\n"
        f"    {'fmi3_length' if arrays else '0'},\n"
        f"    {value_reference(0)}u\n"  # first_vr: the value reference of position 0, as in the XML
        "};\n"
    )


def _vjp_wrapper(info: ModelInfo, vjp: ca.Function) -> str:
    """``call_vjp`` of the runtime contract: ``cosim_vjp`` writes the weights of the model's
    parameters; the runtime's own parameters after them (``solver.fixedStepSize``), which no
    equation uses, get 0."""
    signature = ("double t, const double *x, const double *u, const double *p, const double *wxdot, "
                 "const double *wz, double *wx, double *wu, double *wp")
    n_model, n_all = vjp.numel_out(2), info.sizes["np"]
    return (_wrapper(vjp, signature, ["&t", "x", "u", "p", "wxdot", "wz"], ["wx", "wu", "wp"], "vjp_model")
            + f"static int call_vjp({signature}) {{\n"
            "    int i;\n"
            f"    for (i = {n_model}; i < {n_all}; i++) wp[i] = 0.0;\n"
            "    return vjp_model(t, x, u, p, wxdot, wz, wx, wu, wp);\n"
            "}\n")


def _eval_wrappers(info: ModelInfo, evaluate: ca.Function, nq: int, local: ca.Function | None) -> str:
    """``eval_hoisted``, ``call_eval`` and ``call_locals`` of the runtime contract. Without locals
    (``local`` None) ``cosim_eval`` computes all of z; with locals only the outputs, which
    ``eval_hoisted`` scatters into z, and ``call_locals`` runs the tape of ``local`` (all of z).
    ``call_eval`` computes the hoisted subexpressions q (``nq`` of them) first."""
    signature = ("double t, const double *x, const double *u, const double *p, const double *q, double *xdot, "
                 "double *z")
    args = ["&t", "x", "u", "p", "q"]
    if local is None:
        text = _wrapper(evaluate, signature, args, ["xdot", "z"], "eval_hoisted")
    else:
        outputs = [str(k) for k, v in enumerate(info.by_role("algebraic")) if v.causality == "output"]
        text = (_wrapper(evaluate, signature.replace("double *z", "double *zo"), args, ["xdot", "zo"],
                         "eval_outputs")
                + _array("int", "z_outputs", outputs)
                + f"static int eval_hoisted({signature}) {{\n"
                f"    double zo[{max(1, len(outputs))}];\n"
                "    int i, status = eval_outputs(t, x, u, p, q, xdot, zo);\n"
                f"    for (i = 0; i < {len(outputs)}; i++) z[z_outputs[i]] = zo[i];\n"
                "    return status;\n"
                "}\n")
    text += ("static int call_eval(double t, const double *x, const double *u, const double *p, double *xdot, "
             "double *z) {\n"
             f"    double q[{max(1, nq)}];\n"
             "    if (call_hoist(p, q) != 0) return 1;\n"
             "    return eval_hoisted(t, x, u, p, q, xdot, z);\n"
             "}\n")
    if local is None:
        return text
    return (text + tape_tables(local, "locals_tape", info.name)
            + "static int call_locals(double t, const double *x, const double *u, const double *p, double *z) {\n"
            "    const double *arg[4] = {&t, x, u, p};\n"
            "    return cosim_tape_run(&locals_tape, arg, z);\n"
            "}\n")


def _start_wrapper(info: ModelInfo, start: ca.Function) -> str:
    """``call_start`` of the runtime contract (see ``cosim_model.h``)."""
    signature = ("double t, const double *u, const double *p, const unsigned char *given, double *x0, "
                 "double *residual")
    nx = info.sizes["nx"]
    if start.n_in() == 1:  # no initial equations: x0 = s(p)
        return (_wrapper(start, "const double *p, double *x0", ["p"], ["x0"], "start_values")
                + f"static int call_start({signature}) {{\n"
                "    (void)t; (void)u; (void)given;\n"
                "    *residual = 0.0;\n"
                "    return start_values(p, x0);\n"
                "}\n")
    n_init = start.size1_out(1)
    solved = [v.position for v in info.by_role("state") if v.initial == "approx"]
    return (
        _wrapper(start, "double t, const double *u, const double *p, const double *x, const double *given, "
                        "double *x0, double *r", ["&t", "u", "p", "x", "given"], ["x0", "r"], "start_solve")
        + _array("int", "solved_states", [str(k) for k in solved])
        + f"/* Start values of the states; the states declared fixed = false are solved from the initial\n"
        f"   equations (Newton). 0: ok, COSIM_START_NOT_CONVERGED: max |residual| > {INIT_TOLERANCE!r} or\n"
        "   not finite (the generated Newton iteration does not report that itself), 1: evaluation failed. */\n"
        f"static int call_start({signature}) {{\n"
        f"    double x[{max(1, nx)}], flags[{max(1, nx)}], r[{n_init}];\n"
        "    int i, status;\n"
        f"    for (i = 0; i < {nx}; i++) {{ x[i] = x0[i]; flags[i] = given[i] ? 1.0 : 0.0; }}\n"
        "    status = start_solve(t, u, p, x, flags, x0, r);\n"
        "    *residual = 0.0;\n"
        "    if (status != 0) return 1;\n"
        f"    for (i = 0; i < {n_init}; i++) {{\n"
        "        const double a = r[i] < 0.0 ? -r[i] : r[i];\n"
        "        if (a != a) { *residual = a; return COSIM_START_NOT_CONVERGED; }\n"
        "        if (a > *residual) *residual = a;\n"
        "    }\n"
        f"    for (i = 0; i < {len(solved)}; i++)\n"
        "        if (!isfinite(x0[solved_states[i]])) return COSIM_START_NOT_CONVERGED;\n"
        f"    return *residual <= {INIT_TOLERANCE!r} ? 0 : COSIM_START_NOT_CONVERGED;\n"
        "}\n"
    )


def shared_subexpressions(f: ca.Function) -> ca.Function:
    """``f`` with each of its common subexpressions computed once (``ca.cse``), for an SX function
    (an MX one is returned as it is).

    CasADi's SX graphs repeat what the model's equations and the differentiation repeat: the sines
    and cosines of the same angles in every connector of an assembly, the same products in the
    directional derivatives. gcc cannot merge calls of ``sin`` or ``cos`` (they may set errno), nor
    anything at -O0: the functions of the nonlinear bicycle with a rider have 18 % fewer operations
    (42,900 instead of 52,300; the locals' tape included), 12 % less gcc time and fewer operations
    per step. The same operations on the same values in the same order: results do not change by
    a bit."""
    if not f.is_a("SXFunction"):
        return f
    inputs = f.sx_in()
    return ca.Function(f.name(), inputs, ca.cse(f.call(inputs)), f.name_in(), f.name_out())


def write_sources(info: ModelInfo, model: ExplicitModel, folder: Path,
                  functions: list[ca.Function] | None = None, fmi_version: str = "2") -> list[str]:
    """Write every C source and header of the FMU of ``fmi_version`` ("2" or "3") into ``folder``;
    returns the file names. ``functions``: those of :func:`casadi_functions` if the caller has
    them already (building them again costs a second symbolic differentiation of the model)."""
    folder.mkdir(parents=True, exist_ok=True)
    functions = functions if functions is not None else casadi_functions(model)
    calc, start, evaluate, jvp, hoist, vjp, *local = functions
    calc, evaluate, jvp, hoist, *local = map(shared_subexpressions, (calc, evaluate, jvp, hoist, *local))
    vjp = shared_subexpressions(vjp) if fmi_version == "3" else vjp  # FMI 2 has no adjoint derivatives
    functions = [calc, start, evaluate, jvp, hoist, vjp, *local]
    groups = [[calc, start, evaluate, hoist], [jvp], *([[vjp]] if fmi_version == "3" else [])]
    for file, group in zip(generated_sources(model, fmi_version), groups, strict=True):
        generator = ca.CodeGenerator(file, {"with_header": True, "casadi_real": "double"})
        for f in group:
            generator.add(f)
        generator.generate(str(folder) + "/")
    (folder / "model.c").write_text(model_c(info, functions, fmi_version))
    runtime, headers = runtime_files(fmi_version)
    for name in runtime:
        shutil.copyfile(RUNTIME_DIR / name, folder / name)
    for name in headers:
        shutil.copyfile(fmi_header_dir() / name, folder / name)
    return sorted(p.name for p in folder.iterdir())
