/*
 * fmi2_runtime.c -- the shared, model-independent FMI 2.0 runtime of the FMUs built by
 * `cosim build`.  One binary serves both ModelExchange and CoSimulation.
 *
 * Everything model-specific comes from COSIM_MODEL (see cosim_model.h): block sizes, types,
 * start values and the generated evaluation functions.  This file adds
 *   - the FMI 2.0 state machine and the checking of every call,
 *   - lazy evaluation of calculated parameters, state starts (including the solve of the initial
 *     equations, which waits for fmi2ExitInitializationMode or a getter), derivatives and algebraics,
 *   - FMU states (get/set/free/serialize),
 *   - for CoSimulation an error-controlled embedded Dormand-Prince 5(4) integrator.
 *
 * Conventions:
 *   - Helpers that can fail return 1 on success and 0 on failure, after logging.
 *   - A rejected call (wrong state, bad value reference, bad or non-finite argument) returns
 *     fmi2Error and leaves the instance unchanged.
 *   - An integration failure inside fmi2DoStep (step size too small, too many steps, a non-finite
 *     solution) returns fmi2Discard (FMI 2.0, 4.2.2: "the slave computed successfully only a
 *     subinterval of the communication step"): the instance moves to stepFailed with states,
 *     derivatives and outputs at the last successful time, which fmi2GetRealStatus(
 *     fmi2LastSuccessfulTime) returns; fmi2GetBooleanStatus(fmi2Terminated) is then fmi2True.
 *     From stepFailed: getters, status and directional derivatives, FMU states (fmi2SetFMUstate
 *     of an earlier state redoes the step), fmi2Terminate, fmi2Reset, fmi2FreeInstance.
 *   - In Model Exchange a model evaluation that fails or gives non-finite derivatives in event or
 *     continuous-time mode returns fmi2Discard (FMI 2.0, 2.1.3: the integrator may retry with a
 *     smaller step) and changes nothing.
 *   - Any other failed computation (model evaluation at the start of a step or in initialization
 *     mode) moves the instance to the error state; only fmi2Reset, fmi2SetFMUstate,
 *     fmi2FreeInstance and getters for diagnosis are possible there.
 *   - FMU states carry the model's identity (GUID and sizes) and are refused by any other model.
 *   - No function of libm is called (only the isfinite macro): fmpy rebuilds FMUs from their
 *     sources with CMake, which does not link libm.
 *   - There is no global mutable state; instances are independent and may run in parallel.
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

/* A binary FMU exports the plain fmi2* names. */
#undef FMI2_FUNCTION_PREFIX
#include "fmi2Functions.h"
#include "cosim_model.h"

/* fmi2Functions.h marks its declarations for export.  Repeat that on the definitions so the
   symbols stay visible under -fvisibility=hidden even with a header that defines FMI2_Export
   empty. */
#if defined(__GNUC__) && !defined(_WIN32) && !defined(__CYGWIN__)
#define RT_EXPORT __attribute__((visibility("default")))
#define RT_PRINTF(fmt, first) __attribute__((format(printf, fmt, first)))
#else
#define RT_EXPORT
#define RT_PRINTF(fmt, first)
#endif

/* ---------------------------------------------------------------------------------------------
 * Types
 * ------------------------------------------------------------------------------------------- */

/* FMI 2.0 states.  The runtime itself never returns fmi2Fatal, so ST_FATAL is never entered;
   it is listed to name the full state machine of the standard. */
typedef enum {
    ST_INSTANTIATED,
    ST_INIT,           /* initializationMode */
    ST_EVENT,          /* ME eventMode */
    ST_CONT,           /* ME continuousTimeMode */
    ST_STEP_COMPLETE,  /* CS stepComplete */
    ST_STEP_FAILED,    /* CS stepFailed: fmi2DoStep returned fmi2Discard */
    ST_TERMINATED,
    ST_ERROR,
    ST_FATAL,
    ST_COUNT
} rt_state;

static const char *const STATE_NAMES[ST_COUNT] = {
    "instantiated", "initializationMode", "eventMode", "continuousTimeMode",
    "stepComplete", "stepFailed", "terminated", "error", "fatal"
};

#define BIT(st) (1u << (st))
/* The masks follow the state tables of FMI 2.0 (3.2.3 for ModelExchange, 4.2.4 for CoSimulation). */
#define M_ALIVE  (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | \
                  BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) | BIT(ST_TERMINATED) | BIT(ST_ERROR))
#define M_BEFORE_EXIT (BIT(ST_INSTANTIATED) | BIT(ST_INIT))
#define M_GET    (BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) | \
                  BIT(ST_TERMINATED) | BIT(ST_ERROR))
#define M_SET_REAL     (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE))
#define M_SET_DISCRETE (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_STEP_COMPLETE))
#define M_DIR_DER (BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) | \
                   BIT(ST_TERMINATED))
#define M_TERMINATE (BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED))
#define M_ME_RUNNING (BIT(ST_EVENT) | BIT(ST_CONT))
#define M_ME_GET (BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_TERMINATED) | BIT(ST_ERROR))
#define M_CS_STATUS (BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) | BIT(ST_TERMINATED))

#define IF_ANY (-1) /* function available for both interface types */

/* The blocks of the value array, in their order. */
typedef enum { B_X, B_DX, B_U, B_P, B_C, B_Z, B_NONE } rt_block;

/* Everything an FMU state has to capture. */
typedef struct {
    rt_state state;
    double time;
    double tolerance;
    double start_time;     /* of fmi2SetupExperiment */
    double stop_time;      /* of fmi2SetupExperiment, if stop_defined */
    int stop_defined;
    long n_steps;          /* CS: fmi2DoStep calls completed since fmi2ExitInitializationMode */
    double h_next;         /* CS: step size proposed for the next DoStep; 0 = estimate anew */
    int params_dirty;      /* c (and, in initializationMode, calculated state starts) are stale */
    int eval_dirty;        /* der(x) and z are stale */
    int locals_dirty;      /* the locals of z are stale (computed on demand, see update_locals) */
    double *v;             /* the value array, nv entries; inputs as the environment set them */
    double *q;             /* COSIM_MODEL.nq parameter-only subexpressions of eval, valid unless params_dirty */
    double *ue;            /* nu inputs as the model sees them: v[u] extrapolated with du in CS */
    double *du;            /* CS: first derivatives of the inputs for the next DoStep, nu entries */
    unsigned char *x_set;  /* nx flags: state set explicitly, its calculated start must not overwrite it */
} rt_vars;

/* Who an FMU state belongs to: the GUID and the sizes of the model.  Two FMUs built by cosim
   share this runtime, so an fmi2FMUstate of one can reach the other; only the identity tells. */
#define RT_GUID_MAX 64
typedef struct {
    uint32_t nv, nx, nu, np, nc, nz;   /* block sizes */
    uint32_t n_real, n_integer, n_boolean;
    uint32_t guid_hash;                /* of the whole GUID (the copy below may be cut) */
    char guid[RT_GUID_MAX];            /* zero-padded */
} rt_identity;

/* Tags our fmi2FMUstate objects ("CSF2"); the layout number changes with rt_snapshot, so that a
   state of an FMU built with another version of this runtime is refused before it is read. */
#define RT_STATE_MAGIC 0x43534632u
#define RT_STATE_LAYOUT 2u

typedef struct {
    uint32_t magic;   /* first, so that it can be checked on any pointer passed in */
    uint32_t layout;
    rt_identity id;
    rt_vars vars;
} rt_snapshot;

typedef struct {
    fmi2CallbackFunctions cb;
    char *name;
    fmi2Type type;
    int log_error, log_warning, log_calls;  /* enabled log categories */

    size_t nx, nu, np, nc, nz, nv;          /* block sizes */
    rt_identity id;                         /* of this model, see rt_snapshot */
    size_t o_dx, o_u, o_p, o_c, o_z;        /* block offsets in the value array */
    int has_calc_start;                     /* some state has a calculated start */
    long vr_fixed_step;                     /* vr of the fixed step size parameter, -1 = none */

    rt_vars s;

    /* work arrays, carved from one allocation */
    double *work;
    double *k[7];        /* Dormand-Prince stages */
    double *xs, *xn;     /* stage argument, new solution */
    double *us, *zs;     /* inputs at stage time, algebraics of the latest stage */
    double *jx, *ju, *jp, *jdx, *jz; /* directional derivative seeds and results */
} rt_instance;

#define XV(in)  ((in)->s.v)
#define DXV(in) ((in)->s.v + (in)->o_dx)
#define PV(in)  ((in)->s.v + (in)->o_p)
#define CV(in)  ((in)->s.v + (in)->o_c)
#define ZV(in)  ((in)->s.v + (in)->o_z)
#define UE(in)  ((in)->s.ue)

/* ---------------------------------------------------------------------------------------------
 * Small numeric helpers (no libm, see top of file)
 * ------------------------------------------------------------------------------------------- */

static double rt_abs(double a) { return a < 0.0 ? -a : a; }
static double rt_max(double a, double b) { return a > b ? a : b; }
static double rt_min(double a, double b) { return a < b ? a : b; }

/* x^(1/n) for x >= 0.  0, NaN and +inf are returned unchanged.  The integrators call it twice
   per step (error norm, step size factor), so it is kept cheap: the square root is the processor's
   instruction where SSE2 has it (correctly rounded, and no libm); otherwise Newton's method,
   starting from the bits of x divided by n (exponent and mantissa: a piecewise linear log2,
   within 10 % of the root), which converges in 4 or 5 iterations. */
static double rt_root(double x, int n)
{
    const int64_t one = (int64_t)1023 << 52; /* the bits of 1.0 */
    uint64_t bits;
    int64_t scaled;
    int i;
    double y;

    if (!(x > 0.0) || !isfinite(x)) return x;
#if defined(__SSE2__) || defined(_M_X64)
    if (n == 2) return _mm_cvtsd_f64(_mm_sqrt_sd(_mm_setzero_pd(), _mm_set_sd(x)));
#endif
    memcpy(&bits, &x, sizeof bits);
    scaled = ((int64_t)bits - one) / n + one;
    bits = (uint64_t)scaled;
    memcpy(&y, &bits, sizeof y);
    for (i = 0; i < 200; i++) {
        double y_pow = 1.0, y_old = y;
        int j;
        for (j = 1; j < n; j++) y_pow *= y;
        y = ((n - 1) * y + x / y_pow) / n;
        if (rt_abs(y - y_old) <= 4.0 * DBL_EPSILON * y) break;
    }
    return y;
}

/* The index of the first non-finite entry of a, or n if all are finite. */
static size_t first_nonfinite(const double *a, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(a[i])) break;
    return i;
}

/* ---------------------------------------------------------------------------------------------
 * Logging
 * ------------------------------------------------------------------------------------------- */

/* Formats the message and passes it to the logger.  The logger treats the message as a format
   string and '#' as the start of a variable reference, so literal '%' and '#' are doubled. */
static void emit(const fmi2CallbackFunctions *cb, const char *instance_name, fmi2Status status,
                 const char *category, const char *fmt, va_list ap)
{
    char raw[1024], msg[2048];
    size_t i, j = 0;

    if (!cb || !cb->logger) return;
    vsnprintf(raw, sizeof raw, fmt, ap);
    for (i = 0; raw[i] != '\0' && j + 2 < sizeof msg; i++) {
        if (raw[i] == '%' || raw[i] == '#') msg[j++] = raw[i];
        msg[j++] = raw[i];
    }
    msg[j] = '\0';
    cb->logger(cb->componentEnvironment, instance_name, status, category, msg);
}

/* Logging before an instance exists (fmi2Instantiate). */
static void RT_PRINTF(3, 4) log_raw(const fmi2CallbackFunctions *cb, const char *instance_name,
                                    const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    emit(cb, instance_name ? instance_name : "", fmi2Error, "logStatusError", fmt, ap);
    va_end(ap);
}

static void RT_PRINTF(2, 3) log_error(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_error) return;
    va_start(ap, fmt);
    emit(&in->cb, in->name, fmi2Error, "logStatusError", fmt, ap);
    va_end(ap);
}

static void RT_PRINTF(3, 4) log_warning(const rt_instance *in, fmi2Status status, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_warning) return;
    va_start(ap, fmt);
    emit(&in->cb, in->name, status, "logStatusWarning", fmt, ap);
    va_end(ap);
}

static void RT_PRINTF(2, 3) log_call(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_calls) return;
    va_start(ap, fmt);
    emit(&in->cb, in->name, fmi2OK, "logCalls", fmt, ap);
    va_end(ap);
}

/* A step ended early (fmi2Discard): logged as an error, since the communication step was not done. */
static void RT_PRINTF(2, 3) log_discard(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_error) return;
    va_start(ap, fmt);
    emit(&in->cb, in->name, fmi2Discard, "logStatusError", fmt, ap);
    va_end(ap);
}

/* snprintf through vsnprintf: the runtime needs nothing of libc beyond the functions run.sh lists. */
static void RT_PRINTF(3, 4) format(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}

/* "name (value reference vr)", or "value reference vr" for a model without names; into buf. */
static const char *vr_label(const rt_instance *in, fmi2ValueReference vr, char *buf, size_t size)
{
    const char *name = COSIM_MODEL.names && vr < in->nv ? COSIM_MODEL.names[vr] : NULL;
    if (name) format(buf, size, "%s (value reference %u)", name, vr);
    else format(buf, size, "value reference %u", vr);
    return buf;
}

/* A computation failed: log and move to the error state. */
static void RT_PRINTF(2, 3) fail(rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    in->s.state = ST_ERROR;
    if (!in->log_error) return;
    va_start(ap, fmt);
    emit(&in->cb, in->name, fmi2Error, "logStatusError", fmt, ap);
    va_end(ap);
}

/* ---------------------------------------------------------------------------------------------
 * Call checking
 * ------------------------------------------------------------------------------------------- */

static const char *type_name(fmi2Type type)
{
    return type == fmi2ModelExchange ? "ModelExchange" : "CoSimulation";
}

/* May function fn be called now?  mask: allowed states; iface: IF_ANY or the fmi2Type. */
static int allowed(const rt_instance *in, const char *fn, unsigned mask, int iface)
{
    if (!in) return 0;
    if (iface != IF_ANY && (int)in->type != iface) {
        log_error(in, "%s: not available for a %s instance", fn, type_name(in->type));
        return 0;
    }
    if (!(mask & BIT(in->s.state))) {
        log_error(in, "%s: not allowed in state %s", fn, STATE_NAMES[in->s.state]);
        return 0;
    }
    return 1;
}

static int not_null(const rt_instance *in, const char *fn, const char *arg, const void *p)
{
    if (p) return 1;
    log_error(in, "%s: argument %s must not be NULL", fn, arg);
    return 0;
}

static int check_length(const rt_instance *in, const char *fn, const char *arg, size_t n, size_t expected)
{
    if (n == expected) return 1;
    log_error(in, "%s: %s = %zu, but the model has %zu", fn, arg, n, expected);
    return 0;
}

static int state_fits_type(rt_state st, fmi2Type type)
{
    if (st == ST_EVENT || st == ST_CONT) return type == fmi2ModelExchange;
    if (st == ST_STEP_COMPLETE || st == ST_STEP_FAILED) return type == fmi2CoSimulation;
    return st < ST_FATAL;
}

/* ---------------------------------------------------------------------------------------------
 * Value references
 * ------------------------------------------------------------------------------------------- */

static rt_block block_of(const rt_instance *in, fmi2ValueReference vr)
{
    if (vr < in->o_dx) return B_X;
    if (vr < in->o_u) return B_DX;
    if (vr < in->o_p) return B_U;
    if (vr < in->o_c) return B_P;
    if (vr < in->o_z) return B_C;
    if (vr < in->nv) return B_Z;
    return B_NONE;
}

/* Index in the Jacobian-vector product's dz of the algebraic variable vr, -1 if it has none. */
static long jvp_slot(const rt_instance *in, fmi2ValueReference vr)
{
    const size_t k = vr - in->o_z;
    return COSIM_MODEL.z_jvp_slot ? COSIM_MODEL.z_jvp_slot[k] : (long)k;
}

static const char *cosim_type_name(cosim_type t)
{
    return t == COSIM_REAL ? "Real" : t == COSIM_INTEGER ? "Integer" : "Boolean";
}

/* Is vr an existing variable of the given type? */
static int check_vr(const rt_instance *in, const char *fn, fmi2ValueReference vr, cosim_type type)
{
    if (block_of(in, vr) == B_NONE) {
        log_error(in, "%s: value reference %u is out of range (the model has %zu variables)", fn, vr, in->nv);
        return 0;
    }
    if (COSIM_MODEL.types[vr] != type) {
        log_error(in, "%s: value reference %u is a %s variable, not %s", fn, vr,
                  cosim_type_name(COSIM_MODEL.types[vr]), cosim_type_name(type));
        return 0;
    }
    return 1;
}

/* Why a variable of block b cannot be set in the current state, or NULL if it can. */
static const char *set_refusal(const rt_instance *in, rt_block b)
{
    const int before_exit = (M_BEFORE_EXIT & BIT(in->s.state)) != 0;
    switch (b) {
    case B_X:  return before_exit ? NULL : "a state can only be set before fmi2ExitInitializationMode "
                                           "(ModelExchange: use fmi2SetContinuousStates)";
    case B_DX: return "a derivative is computed by the model";
    case B_U:  return NULL;
    case B_P:  return before_exit ? NULL : "a parameter can only be set before fmi2ExitInitializationMode";
    case B_C:  return "a calculated parameter is computed by the model";
    case B_Z:  return "an algebraic variable is computed by the model";
    default:   return "out of range";
    }
}

static fmi2Integer to_integer(double v)
{
    if (isnan(v)) return 0;
    if (v >= (double)INT_MAX) return INT_MAX;
    if (v <= (double)INT_MIN) return INT_MIN;
    return (fmi2Integer)(v < 0.0 ? v - 0.5 : v + 0.5);
}

/* ---------------------------------------------------------------------------------------------
 * Lazy evaluation
 * ------------------------------------------------------------------------------------------- */

/* der(x) and z at (t, x, u) with the current parameters, through their hoisted subexpressions
   where the model has them (update_parameters keeps those up to date).  0 on success. */
static int model_eval(const rt_instance *in, double t, const double *x, const double *u, double *xdot, double *z)
{
    if (COSIM_MODEL.nq > 0) return COSIM_MODEL.eval_hoisted(t, x, u, PV(in), in->s.q, xdot, z);
    return COSIM_MODEL.eval(t, x, u, PV(in), xdot, z);
}

/* Recomputes c and the hoisted subexpressions q from p and, in initializationMode, the
   calculated state starts. */
static int update_parameters(rt_instance *in, const char *fn)
{
    size_t i;

    if (!in->s.params_dirty) return 1;
    if (COSIM_MODEL.calc_parameters && COSIM_MODEL.calc_parameters(PV(in), CV(in)) != 0) {
        fail(in, "%s: computing the calculated parameters failed", fn);
        return 0;
    }
    if (COSIM_MODEL.nq > 0 && COSIM_MODEL.calc_hoisted(PV(in), in->s.q) != 0) {
        fail(in, "%s: computing the parameter-dependent terms of the model failed", fn);
        return 0;
    }
    /* Calculated starts follow the parameters only until fmi2ExitInitializationMode. */
    if (in->s.state == ST_INIT && in->has_calc_start) {
        double residual = 0.0;
        int status;
        memcpy(in->xs, XV(in), in->nx * sizeof(double));
        status = COSIM_MODEL.start_states(in->s.time, UE(in), PV(in), in->s.x_set, in->xs, &residual);
        if (status == COSIM_START_NOT_CONVERGED) {
            const char *unknowns = COSIM_MODEL.init_unknowns ? COSIM_MODEL.init_unknowns : "the states";
            fail(in, "%s: initialization failed: the initial equations for %s did not converge "
                 "(|residual| = %g); check the parameters and the start values (guesses) of %s",
                 fn, unknowns, residual, unknowns);
            return 0;
        }
        if (status != 0) {
            fail(in, "%s: computing the start values of the states failed", fn);
            return 0;
        }
        /* A solved state takes the solution even if it was set (its value was the guess). */
        for (i = 0; i < in->nx; i++)
            if (COSIM_MODEL.state_start_calculated[i] == 2
                || (COSIM_MODEL.state_start_calculated[i] && !in->s.x_set[i]))
                XV(in)[i] = in->xs[i];
    }
    in->s.params_dirty = 0;
    in->s.eval_dirty = 1;
    return 1;
}

/* Why the evaluation at the current point is unusable: the model failed, or the derivatives are
   not finite (the first one named).  Returns NULL if der(x) and z are fine. */
static const char *evaluate(rt_instance *in, char *why, size_t size)
{
    size_t i;
    char label[160];

    in->s.locals_dirty = 1;
    if (model_eval(in, in->s.time, XV(in), UE(in), DXV(in), ZV(in)) != 0) {
        format(why, size, "model evaluation failed at t = %.16g", in->s.time);
        return why;
    }
    i = first_nonfinite(DXV(in), in->nx);
    if (i < in->nx) {
        format(why, size, "the derivative %s = %g is not finite at t = %.16g",
               vr_label(in, (fmi2ValueReference)(in->o_dx + i), label, sizeof label), DXV(in)[i], in->s.time);
        return why;
    }
    return NULL;
}

/* A model evaluation failed (why): fmi2Discard in ModelExchange event or continuous-time mode
   (the instance stays usable, the integrator may retry with a smaller step), else the error state. */
static fmi2Status evaluation_failed(rt_instance *in, const char *fn, const char *why)
{
    if (in->type == fmi2ModelExchange && (M_ME_RUNNING & BIT(in->s.state))) {
        log_discard(in, "%s: %s", fn, why);
        return fmi2Discard;
    }
    fail(in, "%s: %s", fn, why);
    return fmi2Error;
}

/* Brings der(x) and z up to date with t, x, u and p.  fmi2OK; fmi2Discard if the model cannot
   be evaluated here but the instance stays usable (ModelExchange in event or continuous-time mode:
   FMI 2.0, 2.1.3, the integrator may retry with a smaller step); else fmi2Error and the error state. */
static fmi2Status update_outputs(rt_instance *in, const char *fn)
{
    char why[320];

    if (!update_parameters(in, fn)) return fmi2Error;
    if (!in->s.eval_dirty) return fmi2OK;
    /* on failure eval_dirty stays set: the next getter evaluates (and reports) again */
    if (evaluate(in, why, sizeof why)) return evaluation_failed(in, fn, why);
    in->s.eval_dirty = 0;
    return fmi2OK;
}

/* Brings the local algebraic variables up to date with der(x) and the outputs (update_outputs
   first).  Status as update_outputs. */
static fmi2Status update_locals(rt_instance *in, const char *fn)
{
    char why[320];

    if (!COSIM_MODEL.eval_locals || !in->s.locals_dirty) return fmi2OK;
    if (COSIM_MODEL.eval_locals(in->s.time, XV(in), UE(in), PV(in), ZV(in)) != 0) {
        format(why, sizeof why, "evaluation of the local variables failed at t = %.16g", in->s.time);
        return evaluation_failed(in, fn, why);
    }
    in->s.locals_dirty = 0;
    return fmi2OK;
}

/* Checks a Get call and brings the requested values up to date. */
static fmi2Status prepare_get(rt_instance *in, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                              const void *value, cosim_type type)
{
    size_t i;
    int need_eval = 0, need_locals = 0;
    fmi2Status status;

    if (nvr == 0) return fmi2OK;
    if (!not_null(in, fn, "vr", vr) || !not_null(in, fn, "value", value)) return fmi2Error;
    for (i = 0; i < nvr; i++) {
        rt_block b;
        if (!check_vr(in, fn, vr[i], type)) return fmi2Error;
        b = block_of(in, vr[i]);
        if (b == B_DX || b == B_Z) need_eval = 1;
        if (b == B_Z && jvp_slot(in, vr[i]) < 0) need_locals = 1;
    }
    /* In the error state report the values as they were when the error occurred. */
    if (in->s.state == ST_ERROR) return fmi2OK;
    if (need_eval) {
        status = update_outputs(in, fn);
        return status == fmi2OK && need_locals ? update_locals(in, fn) : status;
    }
    return update_parameters(in, fn) ? fmi2OK : fmi2Error;
}

/* Checks a whole Set call before anything is changed. */
static int prepare_set(const rt_instance *in, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                       const void *value, cosim_type type)
{
    size_t i;

    if (nvr == 0) return 1;
    if (!not_null(in, fn, "vr", vr) || !not_null(in, fn, "value", value)) return 0;
    for (i = 0; i < nvr; i++) {
        const char *why;
        char label[160];
        if (!check_vr(in, fn, vr[i], type)) return 0;
        why = set_refusal(in, block_of(in, vr[i]));
        if (why) {
            log_error(in, "%s: cannot set value reference %u in state %s: %s", fn, vr[i],
                      STATE_NAMES[in->s.state], why);
            return 0;
        }
        /* NaN or inf as a start value, parameter or input only fails later, far from its cause
           (in the calculated parameters, or as "step size too small"). */
        if (type == COSIM_REAL && !isfinite(((const fmi2Real *)value)[i])) {
            log_error(in, "%s: %s = %g: the value must be finite", fn,
                      vr_label(in, vr[i], label, sizeof label), ((const fmi2Real *)value)[i]);
            return 0;
        }
    }
    return 1;
}

/* Stores one checked value and marks what depends on it as stale.  Setting an input also ends
   its extrapolation from an earlier fmi2SetRealInputDerivatives: the model sees the value set. */
static void store(rt_instance *in, fmi2ValueReference vr, double value)
{
    const rt_block b = block_of(in, vr);

    if (b == B_X) in->s.x_set[vr] = 1;
    /* The initial equations involve the states and inputs: solve them again with the new value. */
    if ((b == B_X || b == B_U) && in->s.state == ST_INIT && COSIM_MODEL.init_unknowns) in->s.params_dirty = 1;
    if (b == B_U && UE(in)[vr - in->o_u] != value) {
        UE(in)[vr - in->o_u] = value;
        in->s.eval_dirty = 1;
    }
    if (in->s.v[vr] == value) return; /* e.g. a master re-sending unchanged inputs */
    in->s.v[vr] = value;
    if (b == B_P) in->s.params_dirty = 1;
    in->s.eval_dirty = 1;
}

/* ---------------------------------------------------------------------------------------------
 * Instance data
 * ------------------------------------------------------------------------------------------- */

static void *rt_alloc(const rt_instance *in, size_t n, size_t size)
{
    return in->cb.allocateMemory(n > 0 ? n : 1, size); /* calloc semantics, never ask for 0 bytes */
}

static void rt_free(const rt_instance *in, void *p)
{
    if (p) in->cb.freeMemory(p);
}

static int vars_alloc(const rt_instance *in, rt_vars *s)
{
    s->v = (double *)rt_alloc(in, in->nv, sizeof(double));
    s->ue = (double *)rt_alloc(in, in->nu, sizeof(double));
    s->du = (double *)rt_alloc(in, in->nu, sizeof(double));
    s->x_set = (unsigned char *)rt_alloc(in, in->nx, 1);
    s->q = (double *)rt_alloc(in, (size_t)COSIM_MODEL.nq, sizeof(double));
    return s->v && s->ue && s->du && s->x_set && s->q;
}

static void vars_free(const rt_instance *in, rt_vars *s)
{
    rt_free(in, s->v);
    rt_free(in, s->ue);
    rt_free(in, s->du);
    rt_free(in, s->x_set);
    rt_free(in, s->q);
    s->q = NULL;
    s->v = NULL;
    s->ue = NULL;
    s->du = NULL;
    s->x_set = NULL;
}

static void vars_copy(const rt_instance *in, rt_vars *dst, const rt_vars *src)
{
    dst->state = src->state;
    dst->time = src->time;
    dst->tolerance = src->tolerance;
    dst->start_time = src->start_time;
    dst->stop_time = src->stop_time;
    dst->stop_defined = src->stop_defined;
    dst->n_steps = src->n_steps;
    dst->h_next = src->h_next;
    dst->params_dirty = src->params_dirty;
    dst->eval_dirty = src->eval_dirty;
    dst->locals_dirty = src->locals_dirty;
    memcpy(dst->v, src->v, in->nv * sizeof(double));
    if (in->nu > 0) memcpy(dst->ue, src->ue, in->nu * sizeof(double));
    if (in->nu > 0) memcpy(dst->du, src->du, in->nu * sizeof(double));
    if (in->nx > 0) memcpy(dst->x_set, src->x_set, in->nx);
    if (COSIM_MODEL.nq > 0) memcpy(dst->q, src->q, (size_t)COSIM_MODEL.nq * sizeof(double));
}

static double default_tolerance(void)
{
    return COSIM_MODEL.default_tolerance > 0.0 ? COSIM_MODEL.default_tolerance : 1e-6;
}

/* The state right after fmi2Instantiate. */
static void vars_reset(rt_instance *in)
{
    rt_vars *s = &in->s;
    s->state = ST_INSTANTIATED;
    s->time = 0.0;
    s->tolerance = default_tolerance();
    s->start_time = 0.0;
    s->stop_time = 0.0;
    s->stop_defined = 0;
    s->n_steps = 0;
    s->h_next = 0.0;
    s->params_dirty = 1;
    s->eval_dirty = 1;
    s->locals_dirty = 1;
    memcpy(s->v, COSIM_MODEL.start, in->nv * sizeof(double));
    if (in->nu > 0) memcpy(s->ue, COSIM_MODEL.start + in->o_u, in->nu * sizeof(double));
    if (in->nu > 0) memset(s->du, 0, in->nu * sizeof(double));
    if (in->nx > 0) memset(s->x_set, 0, in->nx);
}

static void free_instance(rt_instance *in)
{
    if (!in) return;
    vars_free(in, &in->s);
    rt_free(in, in->work);
    rt_free(in, in->name);
    in->cb.freeMemory(in);
}

/* Carves the work arrays out of one allocation. */
static int work_alloc(rt_instance *in)
{
    const size_t nx = in->nx;
    double *w;
    int i;

    in->work = (double *)rt_alloc(in, 11 * nx + 2 * in->nu + in->np + 2 * in->nz, sizeof(double));
    if (!in->work) return 0;
    w = in->work;
    for (i = 0; i < 7; i++) { in->k[i] = w; w += nx; }
    in->xs = w;  w += nx;
    in->xn = w;  w += nx;
    in->us = w;  w += in->nu;
    in->zs = w;  w += in->nz;
    in->jx = w;  w += nx;
    in->ju = w;  w += in->nu;
    in->jp = w;  w += in->np;
    in->jdx = w; w += nx;
    in->jz = w;
    return 1;
}

/* The identity of this model, as FMU states carry it (see rt_snapshot). */
static void make_identity(const rt_instance *in, rt_identity *id)
{
    const char *guid = COSIM_MODEL.instantiation_token;
    const unsigned char *p = (const unsigned char *)guid;
    uint32_t h = 2166136261u; /* FNV-1a */
    size_t i, n = strlen(guid);

    memset(id, 0, sizeof *id); /* compared with memcmp: no stray bytes */
    id->nv = (uint32_t)in->nv;
    id->nx = (uint32_t)in->nx;
    id->nu = (uint32_t)in->nu;
    id->np = (uint32_t)in->np;
    id->nc = (uint32_t)in->nc;
    id->nz = (uint32_t)in->nz;
    for (i = 0; i < in->nv; i++) {
        if (COSIM_MODEL.types[i] == COSIM_INTEGER) id->n_integer++;
        else if (COSIM_MODEL.types[i] == COSIM_BOOLEAN) id->n_boolean++;
        else id->n_real++;
    }
    while (*p) h = (h ^ *p++) * 16777619u;
    id->guid_hash = h;
    memcpy(id->guid, guid, n < RT_GUID_MAX - 1 ? n : RT_GUID_MAX - 1);
}

/* Why the identity `other` (of an FMU state) is not this instance's, or NULL if it is; into buf. */
static const char *identity_mismatch(const rt_instance *in, const rt_identity *other, char *buf, size_t size)
{
    const rt_identity *id = &in->id;
    if (memcmp(other, id, sizeof *id) == 0) return NULL;
    if (other->guid_hash != id->guid_hash || memcmp(other->guid, id->guid, RT_GUID_MAX) != 0) {
        format(buf, size, "the state belongs to another FMU (GUID %.*s, this FMU is %s)",
               RT_GUID_MAX - 1, other->guid, COSIM_MODEL.instantiation_token);
        return buf;
    }
    format(buf, size, "the state has other sizes than this FMU (variables %u, states %u, inputs %u, "
           "parameters %u + %u, algebraics %u; Real/Integer/Boolean %u/%u/%u) although its GUID %s is the same; "
           "this FMU has %u, %u, %u, %u + %u, %u; %u/%u/%u",
           (unsigned)other->nv, (unsigned)other->nx, (unsigned)other->nu, (unsigned)other->np, (unsigned)other->nc,
           (unsigned)other->nz, (unsigned)other->n_real, (unsigned)other->n_integer, (unsigned)other->n_boolean,
           COSIM_MODEL.instantiation_token, (unsigned)id->nv, (unsigned)id->nx, (unsigned)id->nu, (unsigned)id->np,
           (unsigned)id->nc, (unsigned)id->nz, (unsigned)id->n_real, (unsigned)id->n_integer,
           (unsigned)id->n_boolean);
    return buf;
}

/* Checks the generated model description once per instantiation. */
static const char *model_problem(void)
{
    const cosim_model *m = &COSIM_MODEL;
    int i;
    if (m->nx < 0 || m->nu < 0 || m->np < 0 || m->nc < 0 || m->nz < 0) return "negative block size";
    if (!m->types || !m->start || !m->eval) return "types, start or eval missing";
    if (m->nx > 0 && !m->state_start_calculated) return "state_start_calculated missing";
    for (i = 0; i < m->nx; i++)
        if (m->state_start_calculated[i] && !m->start_states) return "start_states missing";
    return NULL;
}

/* ---------------------------------------------------------------------------------------------
 * Common functions
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

RT_EXPORT const char *fmi2GetVersion(void) { return fmi2Version; }

/* The enable flag of a log category (as declared in modelDescription.xml), or NULL. */
static int *category_flag(rt_instance *in, const char *category)
{
    if (!category) return NULL;
    if (strcmp(category, "logStatusError") == 0) return &in->log_error;
    if (strcmp(category, "logStatusWarning") == 0) return &in->log_warning;
    if (strcmp(category, "logCalls") == 0) return &in->log_calls;
    return NULL;
}

RT_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                                         const fmi2String categories[])
{
    rt_instance *in = (rt_instance *)c;
    const int on = loggingOn != fmi2False;
    size_t i;

    log_call(in, "fmi2SetDebugLogging(loggingOn = %d, nCategories = %zu)", loggingOn, nCategories);
    if (!allowed(in, "fmi2SetDebugLogging", M_ALIVE, IF_ANY)) return fmi2Error;
    if (nCategories > 0 && !not_null(in, "fmi2SetDebugLogging", "categories", categories)) return fmi2Error;
    for (i = 0; i < nCategories; i++) { /* check all names first, so that an error changes nothing */
        if (!category_flag(in, categories[i])) {
            log_error(in, "fmi2SetDebugLogging: unknown log category '%s' (known: logStatusError, "
                      "logStatusWarning, logCalls)", categories[i] ? categories[i] : "(null)");
            return fmi2Error;
        }
    }
    /* FMI 2.0: no categories means all of them; with loggingOn exactly the listed ones are logged,
       without it the listed ones are muted. */
    if (nCategories == 0) {
        in->log_error = in->log_warning = in->log_calls = on;
        return fmi2OK;
    }
    if (on) in->log_error = in->log_warning = in->log_calls = 0;
    for (i = 0; i < nCategories; i++) *category_flag(in, categories[i]) = on;
    return fmi2OK;
}

RT_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                        fmi2String fmuResourceLocation,
                                        const fmi2CallbackFunctions *functions,
                                        fmi2Boolean visible, fmi2Boolean loggingOn)
{
    rt_instance *in;
    const char *problem;
    size_t i, name_len;

    (void)fmuResourceLocation;
    (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) {
        log_raw(functions, instanceName, "fmi2Instantiate: allocateMemory and freeMemory callbacks are required");
        return NULL;
    }
    if (!instanceName || instanceName[0] == '\0') {
        log_raw(functions, instanceName, "fmi2Instantiate: instanceName must be a non-empty string");
        return NULL;
    }
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation) {
        log_raw(functions, instanceName, "fmi2Instantiate: unknown fmuType %d", (int)fmuType);
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, COSIM_MODEL.instantiation_token) != 0) {
        log_raw(functions, instanceName, "fmi2Instantiate: GUID '%s' does not match this FMU's GUID '%s'",
                fmuGUID ? fmuGUID : "(null)", COSIM_MODEL.instantiation_token);
        return NULL;
    }
    problem = model_problem();
    if (problem) {
        log_raw(functions, instanceName, "fmi2Instantiate: invalid model code: %s", problem);
        return NULL;
    }

    in = (rt_instance *)functions->allocateMemory(1, sizeof(rt_instance));
    if (!in) {
        log_raw(functions, instanceName, "fmi2Instantiate: out of memory");
        return NULL;
    }
    memset(in, 0, sizeof *in);
    in->cb = *functions;
    in->type = fmuType;
    in->log_error = 1;
    in->log_warning = 1;
    in->log_calls = loggingOn != fmi2False;

    in->nx = (size_t)COSIM_MODEL.nx;
    in->nu = (size_t)COSIM_MODEL.nu;
    in->np = (size_t)COSIM_MODEL.np;
    in->nc = (size_t)COSIM_MODEL.nc;
    in->nz = (size_t)COSIM_MODEL.nz;
    in->o_dx = in->nx;
    in->o_u = in->o_dx + in->nx;
    in->o_p = in->o_u + in->nu;
    in->o_c = in->o_p + in->np;
    in->o_z = in->o_c + in->nc;
    in->nv = in->o_z + in->nz;
    for (i = 0; i < in->nx; i++)
        if (COSIM_MODEL.state_start_calculated[i]) in->has_calc_start = 1;
    make_identity(in, &in->id);

    name_len = strlen(instanceName);
    in->name = (char *)rt_alloc(in, name_len + 1, 1);
    if (!in->name || !vars_alloc(in, &in->s) || !work_alloc(in)) {
        log_raw(functions, instanceName, "fmi2Instantiate: out of memory");
        free_instance(in);
        return NULL;
    }
    memcpy(in->name, instanceName, name_len + 1);

    in->vr_fixed_step = -1;
    if (COSIM_MODEL.vr_fixed_step != 0) {
        const int vr = COSIM_MODEL.vr_fixed_step;
        if (vr > 0 && block_of(in, (fmi2ValueReference)vr) == B_P && COSIM_MODEL.types[vr] == COSIM_REAL)
            in->vr_fixed_step = vr;
        else
            log_warning(in, fmi2Warning, "fmi2Instantiate: vr_fixed_step = %d is not a Real parameter; "
                        "using adaptive steps", vr);
    }
    vars_reset(in);
    log_call(in, "fmi2Instantiate(instanceName = %s, fmuType = %s)", instanceName, type_name(fmuType));
    return in;
}

RT_EXPORT void fmi2FreeInstance(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;
    if (!in) return;
    log_call(in, "fmi2FreeInstance()");
    free_instance(in);
}

RT_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                         fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2SetupExperiment(toleranceDefined = %d, tolerance = %g, startTime = %.16g, "
             "stopTimeDefined = %d, stopTime = %.16g)", toleranceDefined, tolerance, startTime,
             stopTimeDefined, stopTime);
    if (!allowed(in, "fmi2SetupExperiment", BIT(ST_INSTANTIATED), IF_ANY)) return fmi2Error;
    if (toleranceDefined && !(tolerance > 0.0 && isfinite(tolerance))) {
        log_error(in, "fmi2SetupExperiment: tolerance = %g must be positive", tolerance);
        return fmi2Error;
    }
    if (!isfinite(startTime)) {
        log_error(in, "fmi2SetupExperiment: startTime must be finite");
        return fmi2Error;
    }
    /* +inf is no limit and accepted as such */
    if (stopTimeDefined && !(stopTime >= startTime)) {
        log_error(in, "fmi2SetupExperiment: stopTime = %.16g must not be before startTime = %.16g",
                  stopTime, startTime);
        return fmi2Error;
    }
    in->s.tolerance = toleranceDefined ? tolerance : default_tolerance();
    in->s.time = startTime;
    in->s.start_time = startTime;
    in->s.stop_defined = stopTimeDefined != fmi2False;
    in->s.stop_time = in->s.stop_defined ? stopTime : 0.0;
    in->s.eval_dirty = 1;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2EnterInitializationMode()");
    if (!allowed(in, "fmi2EnterInitializationMode", BIT(ST_INSTANTIATED), IF_ANY)) return fmi2Error;
    in->s.state = ST_INIT;
    in->s.params_dirty = 1; /* now the calculated state starts are computed, too */
    /* The initial equations are solved when their solution is needed (a getter, or
       fmi2ExitInitializationMode): parameters and inputs may still change in initializationMode. */
    if (COSIM_MODEL.init_unknowns) return fmi2OK;
    return update_parameters(in, "fmi2EnterInitializationMode") ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2ExitInitializationMode()");
    if (!allowed(in, "fmi2ExitInitializationMode", BIT(ST_INIT), IF_ANY)) return fmi2Error;
    /* Evaluate now, so that a model that cannot start fails here and not at some later call
       (in initializationMode every failure is an error, see update_outputs). */
    if (update_outputs(in, "fmi2ExitInitializationMode") != fmi2OK) return fmi2Error;
    in->s.h_next = 0.0;
    in->s.n_steps = 0;
    in->s.state = in->type == fmi2ModelExchange ? ST_EVENT : ST_STEP_COMPLETE;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2Terminate(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2Terminate()");
    if (!allowed(in, "fmi2Terminate", M_TERMINATE, IF_ANY)) return fmi2Error;
    in->s.state = ST_TERMINATED;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2Reset(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2Reset()");
    if (!allowed(in, "fmi2Reset", M_ALIVE, IF_ANY)) return fmi2Error;
    vars_reset(in);
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------------
 * Getters and setters
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;
    fmi2Status status;
    size_t i;

    log_call(in, "fmi2GetReal(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2GetReal", M_GET, IF_ANY)) return fmi2Error;
    status = prepare_get(in, "fmi2GetReal", vr, nvr, value, COSIM_REAL);
    if (status == fmi2Error) return fmi2Error;
    for (i = 0; i < nvr; i++) value[i] = in->s.v[vr[i]]; /* for diagnosis, also with fmi2Discard */
    return status;
}

RT_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    rt_instance *in = (rt_instance *)c;
    fmi2Status status;
    size_t i;

    log_call(in, "fmi2GetInteger(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2GetInteger", M_GET, IF_ANY)) return fmi2Error;
    status = prepare_get(in, "fmi2GetInteger", vr, nvr, value, COSIM_INTEGER);
    if (status == fmi2Error) return fmi2Error;
    for (i = 0; i < nvr; i++) value[i] = to_integer(in->s.v[vr[i]]); /* for diagnosis, also with fmi2Discard */
    return status;
}

RT_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    rt_instance *in = (rt_instance *)c;
    fmi2Status status;
    size_t i;

    log_call(in, "fmi2GetBoolean(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2GetBoolean", M_GET, IF_ANY)) return fmi2Error;
    status = prepare_get(in, "fmi2GetBoolean", vr, nvr, value, COSIM_BOOLEAN);
    if (status == fmi2Error) return fmi2Error;
    /* for diagnosis, also with fmi2Discard */
    for (i = 0; i < nvr; i++) value[i] = in->s.v[vr[i]] != 0.0 ? fmi2True : fmi2False;
    return status;
}

RT_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    log_call(in, "fmi2GetString(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2GetString", M_GET, IF_ANY)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    log_error(in, "fmi2GetString: the model has no String variables (value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

RT_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "fmi2SetReal(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2SetReal", M_SET_REAL, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetReal", vr, nvr, value, COSIM_REAL)) return fmi2Error;
    for (i = 0; i < nvr; i++) store(in, vr[i], value[i]);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "fmi2SetInteger(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2SetInteger", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetInteger", vr, nvr, value, COSIM_INTEGER)) return fmi2Error;
    for (i = 0; i < nvr; i++) store(in, vr[i], (double)value[i]);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "fmi2SetBoolean(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2SetBoolean", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetBoolean", vr, nvr, value, COSIM_BOOLEAN)) return fmi2Error;
    for (i = 0; i < nvr; i++) store(in, vr[i], value[i] ? 1.0 : 0.0);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    log_call(in, "fmi2SetString(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2SetString", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    log_error(in, "fmi2SetString: the model has no String variables (value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

/* ---------------------------------------------------------------------------------------------
 * FMU states
 * ------------------------------------------------------------------------------------------- */

/* The snapshot behind FMUstate if it is one of this model's, else NULL after logging why.  Only
   the tag is read before it is known to be an rt_snapshot of this runtime's layout, and nothing
   of the variables before the identity matched: a state of another FMU may be smaller. */
static rt_snapshot *as_snapshot(const rt_instance *in, const char *fn, fmi2FMUstate FMUstate)
{
    rt_snapshot *snap = (rt_snapshot *)FMUstate;
    char why[640];

    if (!snap) {
        log_error(in, "%s: FMUstate is NULL", fn);
        return NULL;
    }
    if (snap->magic != RT_STATE_MAGIC || snap->layout != RT_STATE_LAYOUT) {
        log_error(in, "%s: FMUstate is not an FMU state of this FMU (nor of any FMU built with this "
                  "version of the cosim runtime)", fn);
        return NULL;
    }
    if (identity_mismatch(in, &snap->id, why, sizeof why)) {
        log_error(in, "%s: FMUstate refused: %s", fn, why);
        return NULL;
    }
    return snap;
}

static rt_snapshot *snapshot_alloc(const rt_instance *in, const char *fn)
{
    rt_snapshot *snap = (rt_snapshot *)rt_alloc(in, 1, sizeof(rt_snapshot));
    if (!snap || !vars_alloc(in, &snap->vars)) {
        if (snap) vars_free(in, &snap->vars);
        rt_free(in, snap);
        log_error(in, "%s: out of memory", fn);
        return NULL;
    }
    snap->magic = RT_STATE_MAGIC;
    snap->layout = RT_STATE_LAYOUT;
    snap->id = in->id;
    return snap;
}

static void snapshot_free(const rt_instance *in, rt_snapshot *snap)
{
    vars_free(in, &snap->vars);
    snap->magic = 0;
    rt_free(in, snap);
}

RT_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;
    rt_snapshot *snap;

    log_call(in, "fmi2GetFMUstate()");
    if (!allowed(in, "fmi2GetFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    if (!not_null(in, "fmi2GetFMUstate", "FMUstate", FMUstate)) return fmi2Error;
    snap = *FMUstate ? as_snapshot(in, "fmi2GetFMUstate", *FMUstate) /* overwrite a state returned earlier */
                     : snapshot_alloc(in, "fmi2GetFMUstate");
    if (!snap) return fmi2Error;
    vars_copy(in, &snap->vars, &in->s);
    *FMUstate = snap;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    rt_instance *in = (rt_instance *)c;
    const rt_snapshot *snap;

    log_call(in, "fmi2SetFMUstate()");
    if (!allowed(in, "fmi2SetFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    snap = as_snapshot(in, "fmi2SetFMUstate", FMUstate);
    if (!snap) return fmi2Error;
    if (!state_fits_type(snap->vars.state, in->type)) {
        log_error(in, "fmi2SetFMUstate: a state in %s cannot be set on a %s instance",
                  STATE_NAMES[snap->vars.state], type_name(in->type));
        return fmi2Error;
    }
    vars_copy(in, &in->s, &snap->vars);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;
    rt_snapshot *snap;

    log_call(in, "fmi2FreeFMUstate()");
    if (!allowed(in, "fmi2FreeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    if (!FMUstate || !*FMUstate) return fmi2OK;
    snap = as_snapshot(in, "fmi2FreeFMUstate", *FMUstate);
    if (!snap) return fmi2Error;
    snapshot_free(in, snap);
    *FMUstate = NULL;
    return fmi2OK;
}

/* Serialized form (native byte order; an FMU state only travels between instances of the same
   binary):
     header:  uint32 magic, format version, then the identity (see rt_identity): uint32 nv, nx, nu,
              np, nc, nz, n_real, n_integer, n_boolean, guid_hash, char guid[RT_GUID_MAX];
     payload: int32 state, params_dirty, eval_dirty, stop_defined; int64 n_steps; double time,
              tolerance, start_time, stop_time, h_next, v[nv], ue[nu], du[nu]; unsigned char x_set[nx].
   The header is checked completely, and the total size against this model's, before anything is
   allocated or copied. */
#define RT_SERIAL_MAGIC 0x434F5332u /* "COS2" */
#define RT_SERIAL_VERSION 2u
#define RT_SERIAL_HEADER (12 * sizeof(uint32_t) + RT_GUID_MAX)

static size_t serial_size(const rt_instance *in)
{
    return RT_SERIAL_HEADER + 4 * sizeof(int32_t) + sizeof(int64_t) + (5 + in->nv + 2 * in->nu) * sizeof(double)
           + in->nx;
}

static unsigned char *put(unsigned char *p, const void *src, size_t n)
{
    if (n > 0) memcpy(p, src, n);
    return p + n;
}

static unsigned char *put_u32(unsigned char *p, uint32_t v) { return put(p, &v, sizeof v); }
static unsigned char *put_i32(unsigned char *p, int v) { int32_t w = (int32_t)v; return put(p, &w, sizeof w); }
static unsigned char *put_f64(unsigned char *p, double v) { return put(p, &v, sizeof v); }

static unsigned char *put_identity(unsigned char *p, const rt_identity *id)
{
    const uint32_t fields[10] = { id->nv, id->nx, id->nu, id->np, id->nc, id->nz,
                                  id->n_real, id->n_integer, id->n_boolean, id->guid_hash };
    p = put(p, fields, sizeof fields);
    return put(p, id->guid, RT_GUID_MAX);
}

typedef struct { const unsigned char *p, *end; } rt_reader;

static int take(rt_reader *r, void *dst, size_t n)
{
    if ((size_t)(r->end - r->p) < n) return 0;
    if (n > 0) memcpy(dst, r->p, n);
    r->p += n;
    return 1;
}

RT_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2SerializedFMUstateSize()");
    if (!allowed(in, "fmi2SerializedFMUstateSize", M_ALIVE, IF_ANY)) return fmi2Error;
    if (!as_snapshot(in, "fmi2SerializedFMUstateSize", FMUstate)) return fmi2Error;
    if (!not_null(in, "fmi2SerializedFMUstateSize", "size", size)) return fmi2Error;
    *size = serial_size(in);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                           size_t size)
{
    rt_instance *in = (rt_instance *)c;
    const rt_snapshot *snap;
    const rt_vars *s;
    unsigned char *p;
    int64_t n_steps;

    log_call(in, "fmi2SerializeFMUstate(size = %zu)", size);
    if (!allowed(in, "fmi2SerializeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    snap = as_snapshot(in, "fmi2SerializeFMUstate", FMUstate);
    if (!snap || !not_null(in, "fmi2SerializeFMUstate", "serializedState", serializedState)) return fmi2Error;
    if (size < serial_size(in)) {
        log_error(in, "fmi2SerializeFMUstate: size = %zu, but %zu bytes are needed", size, serial_size(in));
        return fmi2Error;
    }
    s = &snap->vars;
    n_steps = (int64_t)s->n_steps;
    p = (unsigned char *)serializedState;
    p = put_u32(p, RT_SERIAL_MAGIC);
    p = put_u32(p, RT_SERIAL_VERSION);
    p = put_identity(p, &snap->id);
    p = put_i32(p, (int)s->state);
    p = put_i32(p, s->params_dirty);
    p = put_i32(p, s->eval_dirty);
    p = put_i32(p, s->stop_defined);
    p = put(p, &n_steps, sizeof n_steps);
    p = put_f64(p, s->time);
    p = put_f64(p, s->tolerance);
    p = put_f64(p, s->start_time);
    p = put_f64(p, s->stop_time);
    p = put_f64(p, s->h_next);
    p = put(p, s->v, in->nv * sizeof(double));
    p = put(p, s->ue, in->nu * sizeof(double));
    p = put(p, s->du, in->nu * sizeof(double));
    put(p, s->x_set, in->nx);
    return fmi2OK;
}

/* Why the serialized state cannot be this model's, or NULL; reads only the header.  Into buf. */
static const char *check_serialized(const rt_instance *in, const unsigned char *bytes, size_t size,
                                    char *buf, size_t buf_size)
{
    rt_reader r;
    uint32_t tag[2], fields[10];
    rt_identity id;

    r.p = bytes;
    r.end = bytes + size;
    if (!take(&r, tag, sizeof tag)) {
        format(buf, buf_size, "size = %zu is too short for a serialized FMU state", size);
        return buf;
    }
    if (tag[0] != RT_SERIAL_MAGIC) return "not a serialized FMU state of a cosim FMU (bad magic)";
    if (tag[1] != RT_SERIAL_VERSION) {
        format(buf, buf_size, "unsupported format version %u (this FMU reads version %u)", (unsigned)tag[1],
               (unsigned)RT_SERIAL_VERSION);
        return buf;
    }
    memset(&id, 0, sizeof id);
    if (!take(&r, fields, sizeof fields) || !take(&r, id.guid, RT_GUID_MAX)) {
        format(buf, buf_size, "size = %zu is too short for a serialized FMU state", size);
        return buf;
    }
    id.nv = fields[0]; id.nx = fields[1]; id.nu = fields[2]; id.np = fields[3]; id.nc = fields[4];
    id.nz = fields[5]; id.n_real = fields[6]; id.n_integer = fields[7]; id.n_boolean = fields[8];
    id.guid_hash = fields[9];
    id.guid[RT_GUID_MAX - 1] = '\0'; /* printed in the message below */
    if (identity_mismatch(in, &id, buf, buf_size)) return buf;
    if (size != serial_size(in)) {
        format(buf, buf_size, "size = %zu, but a serialized state of this FMU has %zu bytes", size, serial_size(in));
        return buf;
    }
    return NULL;
}

/* Reads the payload of a serialized state whose header check_serialized accepted into s; returns
   a reason for rejecting it, or NULL. */
static const char *deserialize(const rt_instance *in, const unsigned char *bytes, size_t size, rt_vars *s)
{
    rt_reader r;
    int32_t flags[4];
    int64_t n_steps;
    double scalars[5];
    size_t i;

    r.p = bytes + RT_SERIAL_HEADER;
    r.end = bytes + size;
    if (!take(&r, flags, sizeof flags) || !take(&r, &n_steps, sizeof n_steps) ||
        !take(&r, scalars, sizeof scalars) || !take(&r, s->v, in->nv * sizeof(double)) ||
        !take(&r, s->ue, in->nu * sizeof(double)) || !take(&r, s->du, in->nu * sizeof(double)) ||
        !take(&r, s->x_set, in->nx))
        return "too short";
    if (flags[0] < 0 || flags[0] >= (int32_t)ST_FATAL || !state_fits_type((rt_state)flags[0], in->type))
        return "invalid FMI state for this instance";
    if (n_steps < 0 || n_steps > (int64_t)LONG_MAX) return "invalid step count";
    s->state = (rt_state)flags[0];
    s->params_dirty = flags[1] != 0;
    s->eval_dirty = flags[2] != 0;
    s->locals_dirty = 1; /* not serialized: recomputed when read */
    s->stop_defined = flags[3] != 0;
    s->n_steps = (long)n_steps;
    s->time = scalars[0];
    s->tolerance = scalars[1];
    s->start_time = scalars[2];
    s->stop_time = scalars[3];
    s->h_next = scalars[4];
    for (i = 0; i < in->nx; i++) s->x_set[i] = s->x_set[i] != 0;
    /* q is not serialized: it follows from p (if the parameters are stale, update_parameters
       computes it again before any evaluation) */
    if (!s->params_dirty && COSIM_MODEL.nq > 0 && COSIM_MODEL.calc_hoisted(s->v + in->o_p, s->q) != 0)
        s->params_dirty = 1;
    return NULL;
}

RT_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                             fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;
    rt_snapshot *snap;
    const char *why;
    char buf[640];

    log_call(in, "fmi2DeSerializeFMUstate(size = %zu)", size);
    if (!allowed(in, "fmi2DeSerializeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    if (!not_null(in, "fmi2DeSerializeFMUstate", "serializedState", serializedState) ||
        !not_null(in, "fmi2DeSerializeFMUstate", "FMUstate", FMUstate))
        return fmi2Error;
    why = check_serialized(in, (const unsigned char *)serializedState, size, buf, sizeof buf);
    if (why) {
        log_error(in, "fmi2DeSerializeFMUstate: %s", why);
        return fmi2Error;
    }
    snap = snapshot_alloc(in, "fmi2DeSerializeFMUstate");
    if (!snap) return fmi2Error;
    why = deserialize(in, (const unsigned char *)serializedState, size, &snap->vars);
    if (why) {
        snapshot_free(in, snap);
        log_error(in, "fmi2DeSerializeFMUstate: %s", why);
        return fmi2Error;
    }
    *FMUstate = snap;
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------------
 * Directional derivatives
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                                  size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                                  size_t nKnown, const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    static const char fn[] = "fmi2GetDirectionalDerivative";
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "%s(nUnknown = %zu, nKnown = %zu)", fn, nUnknown, nKnown);
    if (!allowed(in, fn, M_DIR_DER, IF_ANY)) return fmi2Error;
    if (nUnknown == 0) return fmi2OK;
    if (!not_null(in, fn, "vUnknown_ref", vUnknown_ref) || !not_null(in, fn, "dvUnknown", dvUnknown)) return fmi2Error;
    if (nKnown > 0 && (!not_null(in, fn, "vKnown_ref", vKnown_ref) || !not_null(in, fn, "dvKnown", dvKnown)))
        return fmi2Error;
    if (!COSIM_MODEL.jvp) {
        log_error(in, "%s: the model provides no Jacobian-vector product", fn);
        return fmi2Error;
    }

    for (i = 0; i < nKnown; i++) {
        const rt_block b = block_of(in, vKnown_ref[i]);
        if (!check_vr(in, fn, vKnown_ref[i], COSIM_REAL)) return fmi2Error;
        if (b != B_X && b != B_U && b != B_P) {
            log_error(in, "%s: known value reference %u is not a state, input or parameter", fn, vKnown_ref[i]);
            return fmi2Error;
        }
    }
    for (i = 0; i < nUnknown; i++) {
        const rt_block b = block_of(in, vUnknown_ref[i]);
        if (!check_vr(in, fn, vUnknown_ref[i], COSIM_REAL)) return fmi2Error;
        if (b != B_DX && b != B_Z) {
            log_error(in, "%s: unknown value reference %u is not a derivative or algebraic variable", fn,
                      vUnknown_ref[i]);
            return fmi2Error;
        }
        if (b == B_Z && jvp_slot(in, vUnknown_ref[i]) < 0) {
            log_error(in, "%s: unknown value reference %u (%s) is a local variable: directional derivatives "
                      "are provided for the derivatives and the outputs (the ModelStructure unknowns)", fn,
                      vUnknown_ref[i], COSIM_MODEL.names ? COSIM_MODEL.names[vUnknown_ref[i]] : "?");
            return fmi2Error;
        }
    }

    /* Seed direction: the knowns' increments scattered into (dx, du, dp). */
    memset(in->jx, 0, in->nx * sizeof(double));
    memset(in->ju, 0, in->nu * sizeof(double));
    memset(in->jp, 0, in->np * sizeof(double));
    for (i = 0; i < nKnown; i++) {
        const fmi2ValueReference vr = vKnown_ref[i];
        switch (block_of(in, vr)) {
        case B_X: in->jx[vr] += dvKnown[i]; break;
        case B_U: in->ju[vr - in->o_u] += dvKnown[i]; break;
        default:  in->jp[vr - in->o_p] += dvKnown[i]; break;
        }
    }

    if (!update_parameters(in, fn)) return fmi2Error;
    if (COSIM_MODEL.jvp(in->s.time, XV(in), UE(in), PV(in), in->jx, in->ju, in->jp, in->jdx, in->jz) != 0) {
        fail(in, "%s: Jacobian-vector product failed at t = %.16g", fn, in->s.time);
        return fmi2Error;
    }
    for (i = 0; i < nUnknown; i++) {
        const fmi2ValueReference vr = vUnknown_ref[i];
        dvUnknown[i] = block_of(in, vr) == B_DX ? in->jdx[vr - in->o_dx] : in->jz[jvp_slot(in, vr)];
    }
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------------
 * Model Exchange
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2EnterEventMode()");
    if (!allowed(in, "fmi2EnterEventMode", M_ME_RUNNING, fmi2ModelExchange)) return fmi2Error;
    in->s.state = ST_EVENT;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2NewDiscreteStates()");
    if (!allowed(in, "fmi2NewDiscreteStates", BIT(ST_EVENT), fmi2ModelExchange)) return fmi2Error;
    if (!not_null(in, "fmi2NewDiscreteStates", "eventInfo", eventInfo)) return fmi2Error;
    /* The models have no events. */
    eventInfo->newDiscreteStatesNeeded = fmi2False;
    eventInfo->terminateSimulation = fmi2False;
    eventInfo->nominalsOfContinuousStatesChanged = fmi2False;
    eventInfo->valuesOfContinuousStatesChanged = fmi2False;
    eventInfo->nextEventTimeDefined = fmi2False;
    eventInfo->nextEventTime = 0.0;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2EnterContinuousTimeMode()");
    if (!allowed(in, "fmi2EnterContinuousTimeMode", BIT(ST_EVENT), fmi2ModelExchange)) return fmi2Error;
    in->s.state = ST_CONT;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                                 fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    rt_instance *in = (rt_instance *)c;

    (void)noSetFMUStatePriorToCurrentPoint;
    log_call(in, "fmi2CompletedIntegratorStep()");
    if (!allowed(in, "fmi2CompletedIntegratorStep", BIT(ST_CONT), fmi2ModelExchange)) return fmi2Error;
    if (!not_null(in, "fmi2CompletedIntegratorStep", "enterEventMode", enterEventMode) ||
        !not_null(in, "fmi2CompletedIntegratorStep", "terminateSimulation", terminateSimulation))
        return fmi2Error;
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2SetTime(time = %.16g)", time);
    if (!allowed(in, "fmi2SetTime", M_ME_RUNNING, fmi2ModelExchange)) return fmi2Error;
    if (!isfinite(time)) {
        log_error(in, "fmi2SetTime: time must be finite");
        return fmi2Error;
    }
    if (time != in->s.time) {
        in->s.time = time;
        in->s.eval_dirty = 1;
    }
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2SetContinuousStates(nx = %zu)", nx);
    if (!allowed(in, "fmi2SetContinuousStates", BIT(ST_CONT), fmi2ModelExchange)) return fmi2Error;
    if (!check_length(in, "fmi2SetContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!not_null(in, "fmi2SetContinuousStates", "x", x)) return fmi2Error;
    memcpy(XV(in), x, nx * sizeof(double));
    in->s.eval_dirty = 1;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;
    fmi2Status status = fmi2OK;

    log_call(in, "fmi2GetDerivatives(nx = %zu)", nx);
    if (!allowed(in, "fmi2GetDerivatives", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    if (!check_length(in, "fmi2GetDerivatives", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!not_null(in, "fmi2GetDerivatives", "derivatives", derivatives)) return fmi2Error;
    if (in->s.state != ST_ERROR) status = update_outputs(in, "fmi2GetDerivatives");
    if (status == fmi2Error) return fmi2Error;
    memcpy(derivatives, DXV(in), nx * sizeof(double)); /* for diagnosis, also with fmi2Discard */
    return status;
}

RT_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    rt_instance *in = (rt_instance *)c;

    (void)eventIndicators;
    log_call(in, "fmi2GetEventIndicators(ni = %zu)", ni);
    if (!allowed(in, "fmi2GetEventIndicators", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    return check_length(in, "fmi2GetEventIndicators", "ni", ni, 0) ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2GetContinuousStates(nx = %zu)", nx);
    if (!allowed(in, "fmi2GetContinuousStates", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    if (!check_length(in, "fmi2GetContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!not_null(in, "fmi2GetContinuousStates", "x", x)) return fmi2Error;
    if (in->s.state != ST_ERROR && !update_parameters(in, "fmi2GetContinuousStates")) return fmi2Error;
    memcpy(x, XV(in), nx * sizeof(double));
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "fmi2GetNominalsOfContinuousStates(nx = %zu)", nx);
    if (!allowed(in, "fmi2GetNominalsOfContinuousStates", BIT(ST_INSTANTIATED) | M_ME_GET, fmi2ModelExchange))
        return fmi2Error;
    if (!check_length(in, "fmi2GetNominalsOfContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!not_null(in, "fmi2GetNominalsOfContinuousStates", "x_nominal", x_nominal)) return fmi2Error;
    for (i = 0; i < nx; i++) x_nominal[i] = 1.0;
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------------
 * Co-Simulation: the Dormand-Prince 5(4) integrator
 * ------------------------------------------------------------------------------------------- */

#define RT_MAX_STEPS 1000000L /* per DoStep, rejected steps included */
#define RT_SAFETY 0.9
#define RT_FAC_MIN 0.2
#define RT_FAC_MAX 10.0

/* Butcher tableau; the last row is also the 5th-order weights (FSAL). */
static const double DP_C[7] = { 0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0 };
static const double DP_A[7][6] = {
    { 0 },
    { 1.0 / 5 },
    { 3.0 / 40, 9.0 / 40 },
    { 44.0 / 45, -56.0 / 15, 32.0 / 9 },
    { 19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729 },
    { 9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656 },
    { 35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84 }
};
/* Weights of the error estimate: 5th-order minus embedded 4th-order solution. */
static const double DP_E[7] = { 71.0 / 57600, 0.0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200,
                                22.0 / 525, -1.0 / 40 };

/* Steps shorter than this cannot advance the time in double precision reliably. */
static double min_step(double t, double t_end)
{
    return 16.0 * DBL_EPSILON * rt_max(rt_abs(t), rt_abs(t_end));
}

/* The fixed step size if the model has that parameter and it is > 0, else 0 (adaptive). */
static double fixed_step_size(const rt_instance *in)
{
    double h;
    if (in->vr_fixed_step < 0) return 0.0;
    h = in->s.v[in->vr_fixed_step];
    return h > 0.0 && isfinite(h) ? h : 0.0;
}

/* xdot = f(t, x, u(t)) with the inputs extrapolated linearly from the step start t0 (where ue
   holds them, unchanged during the step); the algebraics of this evaluation are left in zs.
   0 if the model evaluation failed. */
static int rhs(rt_instance *in, double t0, double t, const double *x, double *xdot)
{
    const double *u0 = UE(in);
    size_t i;

    for (i = 0; i < in->nu; i++) in->us[i] = u0[i] + in->s.du[i] * (t - t0);
    return model_eval(in, t, x, in->us, xdot, in->zs) == 0;
}

/* One step from (t, x = XV) of size h with k[0] = f(t, x) given.  Leaves the 5th-order solution
   in xn and f(tn, xn) in k[6].  tn is the end time (t + h, or exactly the communication point).
   0 if a model evaluation failed, at the time *t_bad. */
static int dp_step(rt_instance *in, double t0, double t, double h, double tn, double *t_bad)
{
    const double *x = XV(in);
    int s, j;
    size_t i;

    for (s = 1; s < 7; s++) {
        double *arg = s == 6 ? in->xn : in->xs;
        /* Stages with c = 1 use tn itself, so that the last evaluation is exactly at tn. */
        const double ts = s >= 5 ? tn : t + DP_C[s] * h;
        for (i = 0; i < in->nx; i++) {
            double acc = 0.0;
            for (j = 0; j < s; j++) acc += DP_A[s][j] * in->k[j][i];
            arg[i] = x[i] + h * acc;
        }
        if (!rhs(in, t0, ts, arg, in->k[s])) {
            *t_bad = ts;
            return 0;
        }
    }
    return 1;
}

/* Weighted RMS norm of v with scale atol + rtol * |x| (atol = rtol = tolerance). */
static double wrms(const rt_instance *in, const double *v, const double *x)
{
    const double tol = in->s.tolerance;
    double sum = 0.0;
    size_t i;

    for (i = 0; i < in->nx; i++) {
        const double r = v[i] / (tol + tol * rt_abs(x[i]));
        sum += r * r;
    }
    return rt_root(sum / (double)in->nx, 2);
}

/* Hairer's error norm of the last step: scale atol + rtol * max(|x|, |xn|). */
static double error_norm(const rt_instance *in, double h)
{
    const double tol = in->s.tolerance, *x = XV(in);
    double sum = 0.0;
    size_t i;
    int j;

    for (i = 0; i < in->nx; i++) {
        double e = 0.0, r;
        for (j = 0; j < 7; j++) e += DP_E[j] * in->k[j][i];
        r = h * e / (tol + tol * rt_max(rt_abs(x[i]), rt_abs(in->xn[i])));
        sum += r * r;
    }
    return rt_root(sum / (double)in->nx, 2);
}

/* Step size factor for an error estimate err, limited to [RT_FAC_MIN, fac_max]. */
static double step_factor(double err, double fac_max)
{
    if (!(err > 0.0)) return fac_max;
    return rt_min(fac_max, rt_max(RT_FAC_MIN, RT_SAFETY / rt_root(err, 5)));
}

/* Starting step size (Hairer, Norsett & Wanner, Solving ODEs I, II.4), k[0] = f(t0, x0) given.
   If the probing evaluation fails, the cautious first guess h0 is returned: the step size
   control shrinks it further if needed. */
static double initial_step(rt_instance *in, double t0, double span)
{
    const double *x = XV(in);
    double d0, d1, d2, dmax, h0, h1;
    size_t i;

    d0 = wrms(in, x, x);
    d1 = wrms(in, in->k[0], x);
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = rt_min(h0, span);
    for (i = 0; i < in->nx; i++) in->xs[i] = x[i] + h0 * in->k[0][i];
    if (!rhs(in, t0, t0 + h0, in->xs, in->k[1])) return h0;
    for (i = 0; i < in->nx; i++) in->k[1][i] -= in->k[0][i];
    d2 = wrms(in, in->k[1], x) / h0;
    dmax = rt_max(d1, d2);
    h1 = dmax <= 1e-15 ? rt_max(1e-6, h0 * 1e-3) : rt_root(0.01 / dmax, 5);
    return rt_min(100.0 * h0, h1);
}

/* Ends fmi2DoStep (from t0 to t_end) early at t, the last successful time, where x already is:
   the inputs as extrapolated to t, der(x) and z evaluated there, the instance in stepFailed.
   Returns fmi2Discard (fmi2Error if even that evaluation fails). */
static fmi2Status step_failed(rt_instance *in, double t0, double t, double t_end, const char *why)
{
    char again[320];
    size_t i;

    for (i = 0; i < in->nu; i++) {
        UE(in)[i] += in->s.du[i] * (t - t0);
        in->s.du[i] = 0.0;
    }
    in->s.time = t;
    in->s.h_next = 0.0;
    if (evaluate(in, again, sizeof again)) {
        fail(in, "fmi2DoStep: %s; at the last successful time t = %.16g: %s", why, t, again);
        return fmi2Error;
    }
    in->s.eval_dirty = 0;
    in->s.state = ST_STEP_FAILED;
    log_discard(in, "fmi2DoStep: %s; the communication step from t = %.16g to %.16g ends early at the last "
                "successful time t = %.16g (fmi2Discard; states and outputs are those at that time)",
                why, t0, t_end, t);
    return fmi2Discard;
}

/* The first non-finite state of xn or derivative of k[6] as "name = value", or NULL; into buf. */
static const char *nonfinite_solution(const rt_instance *in, char *buf, size_t size)
{
    char label[160];
    size_t i = first_nonfinite(in->xn, in->nx);

    if (i < in->nx) {
        format(buf, size, "state %s = %g", vr_label(in, (fmi2ValueReference)i, label, sizeof label), in->xn[i]);
        return buf;
    }
    i = first_nonfinite(in->k[6], in->nx);
    if (i < in->nx) {
        format(buf, size, "derivative %s = %g",
               vr_label(in, (fmi2ValueReference)(in->o_dx + i), label, sizeof label), in->k[6][i]);
        return buf;
    }
    return NULL;
}

/* Integrates x from the current time to t_end (> time).  fmi2OK: the value array holds x, u,
   der(x) and z at t_end.  fmi2Discard: the integration failed; the instance is in stepFailed at the
   last accepted step (see step_failed).  fmi2Error: the model cannot be evaluated at the start. */
static fmi2Status integrate(rt_instance *in, double t_end)
{
    const double t0 = in->s.time, h_fix = fixed_step_size(in);
    const size_t nx = in->nx;
    double t = t0, h, t_bad = t0, *swap;
    long steps = 0;
    int rejected = 0, nonfinite = 0, eval_failed = 0;
    char why[480], what[240];
    size_t i;

    /* At the communication point itself: the FMU's own state with the environment's inputs.  A
       failure here is not an integration failure (nothing of the step was computed). */
    if (update_outputs(in, "fmi2DoStep") != fmi2OK) return fmi2Error;
    memcpy(in->k[0], DXV(in), nx * sizeof(double));
    if (h_fix > 0.0) h = h_fix;
    else if (in->s.h_next > 0.0) h = in->s.h_next;
    else h = initial_step(in, t0, t_end - t0);

    while (t < t_end) {
        const double h_min = min_step(t, t_end);
        double h_try = h, h_prop, tn;
        int last = 0;

        if (++steps > RT_MAX_STEPS) {
            format(why, sizeof why, "more than %ld steps in one communication step at t = %.16g "
                   "(tolerance too tight, fixed step too small or model too stiff)", RT_MAX_STEPS, t);
            return step_failed(in, t0, t, t_end, why);
        }
        /* Step exactly onto t_end rather than leaving a sliver (e.g. from rounding in t) that
           would be a step of its own, possibly one too short to advance the time. */
        if (t_end - t - h <= rt_max(1e-9 * h, h_min)) {
            h_try = t_end - t;
            last = 1;
        }
        if (h_try <= h_min) {
            if (nonfinite) format(what, sizeof what, " (the solution becomes non-finite)");
            else if (eval_failed) format(what, sizeof what, " (the model evaluation fails at t = %.16g)", t_bad);
            else what[0] = '\0';
            format(why, sizeof why, "step size %g too small at t = %.16g%s", h_try, t, what);
            return step_failed(in, t0, t, t_end, why);
        }
        /* Integrate over exactly the time step that t can represent: far from t = 0, t + h
           rounds, and x would otherwise drift against the time. */
        tn = last ? t_end : t + h_try;
        h_try = tn - t;
        if (!dp_step(in, t0, t, h_try, tn, &t_bad)) {
            if (h_fix > 0.0) {
                format(why, sizeof why, "model evaluation failed at t = %.16g", t_bad);
                return step_failed(in, t0, t, t_end, why);
            }
            /* e.g. an algebraic solve that diverges off the solution: a shorter step may pass */
            h = h_try * RT_FAC_MIN;
            rejected = 1;
            eval_failed = 1;
            nonfinite = 0;
            continue;
        }

        if (h_fix > 0.0) {
            if (nonfinite_solution(in, what, sizeof what)) {
                format(why, sizeof why, "the solution becomes non-finite at t = %.16g: %s", tn, what);
                return step_failed(in, t0, t, t_end, why);
            }
        } else {
            const double err = error_norm(in, h_try);
            if (!(err <= 1.0)) { /* reject; a non-finite estimate also means "too large a step" */
                nonfinite = !isfinite(err);
                eval_failed = 0;
                h = h_try * (nonfinite ? RT_FAC_MIN : step_factor(err, 1.0));
                rejected = 1;
                continue;
            }
            /* A step shortened to end on t_end (its error estimate only bounds the error of
               the shorter step) must not shrink the step size remembered for the next DoStep. */
            h_prop = h_try * step_factor(err, rejected ? 1.0 : RT_FAC_MAX);
            h = last && h_try < h ? rt_max(h, h_prop) : h_prop;
            rejected = 0;
            nonfinite = 0;
            eval_failed = 0;
        }

        t = tn;
        memcpy(XV(in), in->xn, nx * sizeof(double));
        swap = in->k[0]; in->k[0] = in->k[6]; in->k[6] = swap; /* FSAL */
    }

    /* The last evaluation was at (t_end, x, u(t_end)): it provides der(x) and z there.  The
       model goes on seeing u(t_end) until the environment sets the input again; the input
       variable itself keeps the value the environment set. */
    for (i = 0; i < in->nu; i++) {
        UE(in)[i] += in->s.du[i] * (t_end - t0);
        in->s.du[i] = 0.0;
    }
    memcpy(DXV(in), in->k[0], nx * sizeof(double));
    memcpy(ZV(in), in->zs, in->nz * sizeof(double));
    in->s.eval_dirty = 0;
    in->s.locals_dirty = 1;
    in->s.time = t_end;
    if (h_fix <= 0.0) in->s.h_next = h;
    return fmi2OK;
}

/* A step without integration (no states, or no time to speak of passes): advance time and
   inputs, then evaluate so that errors surface here. */
static fmi2Status advance(rt_instance *in, double t_end)
{
    size_t i;
    for (i = 0; i < in->nu; i++) {
        UE(in)[i] += in->s.du[i] * (t_end - in->s.time);
        in->s.du[i] = 0.0;
    }
    in->s.time = t_end;
    in->s.eval_dirty = 1;
    return update_outputs(in, "fmi2DoStep");
}

/* How far a step may end after stopTime: the rounding a master accumulates by adding up its
   communication steps (half an ulp of the time scale per step, n_steps so far) plus a few ulps. */
static double stop_allowance(const rt_instance *in)
{
    const double scale = rt_max(rt_abs(in->s.start_time), rt_abs(in->s.stop_time));
    return (16.0 + (double)in->s.n_steps) * DBL_EPSILON * scale;
}

/* ---------------------------------------------------------------------------------------------
 * Co-Simulation functions
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                 const fmi2Integer order[], const fmi2Real value[])
{
    static const char fn[] = "fmi2SetRealInputDerivatives";
    rt_instance *in = (rt_instance *)c;
    size_t i;

    log_call(in, "%s(nvr = %zu)", fn, nvr);
    if (!allowed(in, fn, M_BEFORE_EXIT | BIT(ST_STEP_COMPLETE), fmi2CoSimulation)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    if (!not_null(in, fn, "vr", vr) || !not_null(in, fn, "order", order) || !not_null(in, fn, "value", value))
        return fmi2Error;
    for (i = 0; i < nvr; i++) {
        char label[160];
        if (!check_vr(in, fn, vr[i], COSIM_REAL)) return fmi2Error;
        if (block_of(in, vr[i]) != B_U) {
            log_error(in, "%s: value reference %u is not an input", fn, vr[i]);
            return fmi2Error;
        }
        if (order[i] != 1) {
            log_error(in, "%s: order %d for value reference %u is not supported (maxInputDerivativeOrder = 1)",
                      fn, (int)order[i], vr[i]);
            return fmi2Error;
        }
        if (!isfinite(value[i])) {
            log_error(in, "%s: the derivative of %s = %g: the value must be finite", fn,
                      vr_label(in, vr[i], label, sizeof label), value[i]);
            return fmi2Error;
        }
    }
    for (i = 0; i < nvr; i++) in->s.du[vr[i] - in->o_u] = value[i];
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                  const fmi2Integer order[], fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)order;
    (void)value;
    log_call(in, "fmi2GetRealOutputDerivatives(nvr = %zu)", nvr);
    if (!allowed(in, "fmi2GetRealOutputDerivatives", M_CS_STATUS | BIT(ST_ERROR), fmi2CoSimulation))
        return fmi2Error;
    if (nvr == 0) return fmi2OK;
    log_error(in, "fmi2GetRealOutputDerivatives: output derivatives are not provided "
              "(maxOutputDerivativeOrder = 0; value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

RT_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    rt_instance *in = (rt_instance *)c;
    fmi2Status status;
    double t, t_end;

    (void)noSetFMUStatePriorToCurrentPoint;
    log_call(in, "fmi2DoStep(currentCommunicationPoint = %.16g, communicationStepSize = %.16g)",
             currentCommunicationPoint, communicationStepSize);
    if (!allowed(in, "fmi2DoStep", BIT(ST_STEP_COMPLETE), fmi2CoSimulation)) return fmi2Error;
    t = in->s.time;
    if (!isfinite(currentCommunicationPoint) ||
        rt_abs(currentCommunicationPoint - t) > 1e-12 * rt_max(1.0, rt_abs(t))) {
        log_error(in, "fmi2DoStep: currentCommunicationPoint = %.16g differs from the FMU's time %.16g",
                  currentCommunicationPoint, t);
        return fmi2Error;
    }
    if (communicationStepSize == 0.0) {
        log_error(in, "fmi2DoStep: communicationStepSize = 0 at t = %.16g: a step of size 0 is an event "
                  "iteration in FMI 2.0, which this FMU does not support (it has no events); the step size "
                  "must be > 0", t);
        return fmi2Error;
    }
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize)) {
        log_error(in, "fmi2DoStep: communicationStepSize = %.16g must be finite and > 0", communicationStepSize);
        return fmi2Error;
    }
    t_end = currentCommunicationPoint + communicationStepSize;
    if (in->s.stop_defined && t_end > in->s.stop_time + stop_allowance(in)) {
        log_error(in, "fmi2DoStep: the step from t = %.16g with communicationStepSize = %.16g ends at t = %.16g, "
                  "after stopTime = %.16g of fmi2SetupExperiment", currentCommunicationPoint,
                  communicationStepSize, t_end, in->s.stop_time);
        return fmi2Error;
    }
    if (in->nx > 0 && t_end - t > min_step(t, t_end)) status = integrate(in, t_end);
    else status = advance(in, t_end);
    if (status == fmi2OK) in->s.n_steps++;
    return status;
}

RT_EXPORT fmi2Status fmi2CancelStep(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2CancelStep()");
    if (!allowed(in, "fmi2CancelStep", M_ALIVE, fmi2CoSimulation)) return fmi2Error;
    log_error(in, "fmi2CancelStep: not supported: fmi2DoStep always completes synchronously");
    return fmi2Error;
}

/* The status kinds that do not apply to a synchronous slave. */
static fmi2Status no_status(const rt_instance *in, const char *fn, fmi2StatusKind s)
{
    log_warning(in, fmi2Discard, "%s: status kind %d is not applicable (fmi2DoStep never returns fmi2Pending)",
                fn, (int)s);
    return fmi2Discard;
}

RT_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2GetStatus(s = %d)", (int)s);
    if (!allowed(in, "fmi2GetStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!not_null(in, "fmi2GetStatus", "value", value)) return fmi2Error;
    if (s != fmi2DoStepStatus) return no_status(in, "fmi2GetStatus", s);
    /* the status of the last fmi2DoStep: it returns synchronously, never fmi2Pending */
    *value = in->s.state == ST_STEP_FAILED ? fmi2Discard : fmi2OK;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2GetRealStatus(s = %d)", (int)s);
    if (!allowed(in, "fmi2GetRealStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!not_null(in, "fmi2GetRealStatus", "value", value)) return fmi2Error;
    if (s != fmi2LastSuccessfulTime) return no_status(in, "fmi2GetRealStatus", s);
    /* the end of the last step, or after fmi2Discard the time the failed step reached */
    *value = in->s.time;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    log_call(in, "fmi2GetIntegerStatus(s = %d)", (int)s);
    if (!allowed(in, "fmi2GetIntegerStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    return no_status(in, "fmi2GetIntegerStatus", s);
}

RT_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    rt_instance *in = (rt_instance *)c;

    log_call(in, "fmi2GetBooleanStatus(s = %d)", (int)s);
    if (!allowed(in, "fmi2GetBooleanStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!not_null(in, "fmi2GetBooleanStatus", "value", value)) return fmi2Error;
    if (s != fmi2Terminated) return no_status(in, "fmi2GetBooleanStatus", s);
    /* After fmi2Discard the slave cannot continue past the last successful time by itself (FMPy,
       for one, then records that time and terminates); a master may still redo the step from an
       earlier FMU state.  Otherwise the slave never asks to terminate. */
    *value = in->s.state == ST_STEP_FAILED ? fmi2True : fmi2False;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    log_call(in, "fmi2GetStringStatus(s = %d)", (int)s);
    if (!allowed(in, "fmi2GetStringStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    return no_status(in, "fmi2GetStringStatus", s);
}
