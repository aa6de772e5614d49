/*
 * cosim_runtime.c -- the version-independent core of the FMUs built by `cosim build`: everything
 * the FMI 2.0 API (fmi2_api.c) and the FMI 3.0 API (fmi3_api.c) share.  See cosim_runtime.h for
 * its interface.
 *
 * Everything model-specific comes from COSIM_MODEL (see cosim_model.h): block sizes, types,
 * start values and the generated evaluation functions.  This file adds
 *   - lazy evaluation of calculated parameters, state starts (including the solve of the initial
 *     equations, which waits for the exit of initialization mode or a getter), derivatives and
 *     algebraics,
 *   - the checks of value references and values of every get and set,
 *   - FMU states (get/set/free/serialize) that carry the model's identity,
 *   - directional (jvp) and adjoint (vjp) derivatives on value references,
 *   - for Co-Simulation an error-controlled embedded Dormand-Prince 5(4) integrator.
 *
 * Conventions:
 *   - Helpers that can fail return 1 on success and 0 on failure, after logging.
 *   - A rejected call (wrong state, bad value reference, bad or non-finite argument) returns
 *     RT_ERROR and leaves the instance unchanged.
 *   - An integration failure inside a DoStep (step size too small, too many steps, a non-finite
 *     solution) returns RT_DISCARD (FMI 2.0, 4.2.2: "the slave computed successfully only a
 *     subinterval of the communication step"; FMI 3.0 fmi3DoStep likewise): the instance moves
 *     to stepFailed with states, derivatives and outputs at the last successful time, which is then
 *     the instance's time.  From stepFailed: getters, status and directional derivatives, FMU
 *     states (setting an earlier state redoes the step), terminate, reset, free.
 *   - In Model Exchange a model evaluation that fails or gives non-finite derivatives in event or
 *     continuous-time mode returns RT_DISCARD (FMI 2.0, 2.1.3: the integrator may retry with a
 *     smaller step) and changes nothing.
 *   - Any other failed computation (model evaluation at the start of a step or in initialization
 *     mode) moves the instance to the error state; only reset, setting an FMU state, free and
 *     getters for diagnosis are possible there.
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

#include "cosim_runtime.h"

/* Tags our FMU state objects ("CSF2"); the layout number changes with rt_snapshot, so that a
   state of an FMU built with another version of this runtime is refused before it is read. */
#define RT_STATE_MAGIC 0x43534632u
#define RT_STATE_LAYOUT 2u

typedef struct {
    uint32_t magic;   /* first, so that it can be checked on any pointer passed in */
    uint32_t layout;
    rt_identity id;
    rt_vars vars;
} rt_snapshot;

/* ---------------------------------------------------------------------------------------------
 * Small numeric helpers (no libm, see top of file)
 * ------------------------------------------------------------------------------------------- */

double rt_abs(double a) { return a < 0.0 ? -a : a; }
double rt_max(double a, double b) { return a > b ? a : b; }
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
#elif defined(__wasm__)
    /* WebAssembly's f64.sqrt is correctly rounded like SSE2's sqrtsd: the browser build of an
       FMU (cosim build --wasm) steps as the native one does */
    if (n == 2) return __builtin_sqrt(x);
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

/* Formats the message and passes it to the API's logger (the API escapes what its standard needs). */
static void emit(const rt_instance *in, rt_status status, const char *category, const char *fmt, va_list ap)
{
    char raw[1024];

    if (!in->log) return;
    vsnprintf(raw, sizeof raw, fmt, ap);
    in->log(in->log_env, in->name, status, category, raw);
}

void rt_vformat(char *buf, size_t size, const char *fmt, va_list ap)
{
    vsnprintf(buf, size, fmt, ap);
}

void rt_log_error(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_error) return;
    va_start(ap, fmt);
    emit(in, RT_ERROR, "logStatusError", fmt, ap);
    va_end(ap);
}

void rt_log_warning(const rt_instance *in, rt_status status, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_warning) return;
    va_start(ap, fmt);
    emit(in, status, "logStatusWarning", fmt, ap);
    va_end(ap);
}

void rt_log_call_always(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_calls) return;
    va_start(ap, fmt);
    emit(in, RT_OK, "logCalls", fmt, ap);
    va_end(ap);
}

/* A step ended early (RT_DISCARD): logged as an error, since the communication step was not done. */
void rt_log_discard(const rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    if (!in || !in->log_error) return;
    va_start(ap, fmt);
    emit(in, RT_DISCARD, "logStatusError", fmt, ap);
    va_end(ap);
}

/* snprintf through vsnprintf: the runtime needs nothing of libc beyond the functions run.sh lists. */
void rt_format(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}

/* "name (value reference vr)" of the variable at index i, or "value reference vr" for a model
   without names; into buf. */
const char *rt_vr_label(const rt_instance *in, size_t i, char *buf, size_t size)
{
    const char *name = COSIM_MODEL.names && i < in->nv ? COSIM_MODEL.names[i] : NULL;
    if (name) rt_format(buf, size, "%s (value reference %u)", name, rt_vr(in, i));
    else rt_format(buf, size, "value reference %u", rt_vr(in, i));
    return buf;
}

/* A computation failed: log and move to the error state. */
void rt_fail(rt_instance *in, const char *fmt, ...)
{
    va_list ap;
    in->s.state = ST_ERROR;
    if (!in->log_error) return;
    va_start(ap, fmt);
    emit(in, RT_ERROR, "logStatusError", fmt, ap);
    va_end(ap);
}

/* ---------------------------------------------------------------------------------------------
 * Call checking
 * ------------------------------------------------------------------------------------------- */

const char *rt_kind_name(rt_kind kind)
{
    return kind == RT_ME ? "ModelExchange" : "CoSimulation";
}

/* The slow path of rt_allowed (cosim_runtime.h): why fn cannot be called now, logged; 0 (1 if it can). */
int rt_refused(const rt_instance *in, const char *fn, unsigned mask, int iface)
{
    if (!in) return 0;
    if (iface != IF_ANY && (int)in->kind != iface) {
        rt_log_error(in, "%s: not available for a %s instance", fn, rt_kind_name(in->kind));
        return 0;
    }
    if (!(mask & BIT(in->s.state))) {
        rt_log_error(in, "%s: not allowed in state %s", fn, in->words->state_names[in->s.state]);
        return 0;
    }
    return 1;
}

int rt_not_null(const rt_instance *in, const char *fn, const char *arg, const void *p)
{
    if (p) return 1;
    rt_log_error(in, "%s: argument %s must not be NULL", fn, arg);
    return 0;
}

int rt_check_length(const rt_instance *in, const char *fn, const char *arg, size_t n, size_t expected)
{
    if (n == expected) return 1;
    rt_log_error(in, "%s: %s = %zu, but the model has %zu", fn, arg, n, expected);
    return 0;
}

/* Can an instance of this kind be in state st (an FMU state being set, or deserialized)? */
int rt_state_fits_kind(const rt_instance *in, rt_state st)
{
    if (st == ST_EVENT) return in->kind == RT_ME || in->cs_event_mode;
    if (st == ST_CONT) return in->kind == RT_ME;
    if (st == ST_STEP_COMPLETE || st == ST_STEP_FAILED) return in->kind == RT_CS;
    return st < ST_FATAL;
}

/* ---------------------------------------------------------------------------------------------
 * Value references
 * ------------------------------------------------------------------------------------------- */

/* The block of the value array that index i is in (B_NONE: none). */
rt_block rt_block_of(const rt_instance *in, size_t i)
{
    if (i < in->o_dx) return B_X;
    if (i < in->o_u) return B_DX;
    if (i < in->o_p) return B_U;
    if (i < in->o_c) return B_P;
    if (i < in->o_z) return B_C;
    if (i < in->nv) return B_Z;
    return B_NONE;
}

/* Index in the Jacobian-vector product's dz of the algebraic variable at index i, -1 if it has none. */
long rt_jvp_slot(const rt_instance *in, size_t i)
{
    const size_t k = i - in->o_z;
    return COSIM_MODEL.z_jvp_slot ? COSIM_MODEL.z_jvp_slot[k] : (long)k;
}

static const char *type_name(const rt_instance *in, cosim_type t)
{
    return in->words->type_names[t == COSIM_REAL ? 0 : t == COSIM_INTEGER ? 1 : 2];
}

/* Is vr an existing variable of the given type? */
int rt_check_vr(const rt_instance *in, const char *fn, unsigned vr, cosim_type type)
{
    const size_t i = rt_index(in, vr);
    if (rt_block_of(in, i) == B_NONE) {
        rt_log_error(in, "%s: value reference %u is out of range (the model has %zu variables, value references "
                     "%u to %u)", fn, vr, in->nv, rt_vr(in, 0), rt_vr(in, in->nv) - 1u);
        return 0;
    }
    if (COSIM_MODEL.types[i] != type) {
        rt_log_error(in, "%s: value reference %u is a %s variable, not %s", fn, vr,
                     type_name(in, COSIM_MODEL.types[i]), type_name(in, type));
        return 0;
    }
    return 1;
}

/* Why a variable of block b cannot be set in the current state, or NULL if it can; into buf. */
static const char *set_refusal(const rt_instance *in, rt_block b, char *buf, size_t size)
{
    const int before_exit = in->s.state == ST_INSTANTIATED || in->s.state == ST_INIT;
    switch (b) {
    case B_X:
        if (before_exit) return NULL;
        rt_format(buf, size, "a state can only be set before %s (ModelExchange: use %s)", in->words->exit_init,
                  in->words->set_states);
        return buf;
    case B_DX: return "a derivative is computed by the model";
    case B_U:  return NULL;
    case B_P:
        if (before_exit) return NULL;
        rt_format(buf, size, "a parameter can only be set before %s", in->words->exit_init);
        return buf;
    case B_C:  return "a calculated parameter is computed by the model";
    case B_Z:  return "an algebraic variable is computed by the model";
    default:   return "out of range";
    }
}

int rt_to_integer(double v)
{
    if (isnan(v)) return 0;
    if (v >= (double)INT_MAX) return INT_MAX;
    if (v <= (double)INT_MIN) return INT_MIN;
    return (int)(v < 0.0 ? v - 0.5 : v + 0.5);
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
int rt_update_parameters(rt_instance *in, const char *fn)
{
    size_t i;

    if (!in->s.params_dirty) return 1;
    if (COSIM_MODEL.calc_parameters && COSIM_MODEL.calc_parameters(PV(in), CV(in)) != 0) {
        rt_fail(in, "%s: computing the calculated parameters failed", fn);
        return 0;
    }
    if (COSIM_MODEL.nq > 0 && COSIM_MODEL.calc_hoisted(PV(in), in->s.q) != 0) {
        rt_fail(in, "%s: computing the parameter-dependent terms of the model failed", fn);
        return 0;
    }
    /* Calculated starts follow the parameters only until the exit of initialization mode. */
    if (in->s.state == ST_INIT && in->has_calc_start) {
        double residual = 0.0;
        int status;
        memcpy(in->xs, XV(in), in->nx * sizeof(double));
        status = COSIM_MODEL.start_states(in->s.time, UE(in), PV(in), in->s.x_set, in->xs, &residual);
        if (status == COSIM_START_NOT_CONVERGED) {
            const char *unknowns = COSIM_MODEL.init_unknowns ? COSIM_MODEL.init_unknowns : "the states";
            rt_fail(in, "%s: initialization failed: the initial equations for %s did not converge "
                 "(|residual| = %g); check the parameters and the start values (guesses) of %s",
                 fn, unknowns, residual, unknowns);
            return 0;
        }
        if (status != 0) {
            rt_fail(in, "%s: computing the start values of the states failed", fn);
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
        rt_format(why, size, "model evaluation failed at t = %.16g", in->s.time);
        return why;
    }
    i = first_nonfinite(DXV(in), in->nx);
    if (i < in->nx) {
        rt_format(why, size, "the derivative %s = %g is not finite at t = %.16g",
               rt_vr_label(in, in->o_dx + i, label, sizeof label), DXV(in)[i], in->s.time);
        return why;
    }
    return NULL;
}

/* A model evaluation failed (why): RT_DISCARD in ModelExchange event or continuous-time mode
   (the instance stays usable, the integrator may retry with a smaller step), else the error state. */
static rt_status evaluation_failed(rt_instance *in, const char *fn, const char *why)
{
    if (in->kind == RT_ME && (in->s.state == ST_EVENT || in->s.state == ST_CONT)) {
        rt_log_discard(in, "%s: %s", fn, why);
        return RT_DISCARD;
    }
    rt_fail(in, "%s: %s", fn, why);
    return RT_ERROR;
}

/* Brings der(x) and z up to date with t, x, u and p.  RT_OK; RT_DISCARD if the model cannot
   be evaluated here but the instance stays usable (ModelExchange in event or continuous-time mode:
   FMI 2.0, 2.1.3, the integrator may retry with a smaller step); else RT_ERROR and the error state. */
rt_status rt_update_outputs(rt_instance *in, const char *fn)
{
    char why[320];

    if (!rt_update_parameters(in, fn)) return RT_ERROR;
    if (!in->s.eval_dirty) return RT_OK;
    /* on failure eval_dirty stays set: the next getter evaluates (and reports) again */
    if (evaluate(in, why, sizeof why)) return evaluation_failed(in, fn, why);
    in->s.eval_dirty = 0;
    return RT_OK;
}

/* Brings the local algebraic variables up to date with der(x) and the outputs (update_outputs
   first).  Status as update_outputs. */
rt_status rt_update_locals(rt_instance *in, const char *fn)
{
    char why[320];

    if (!COSIM_MODEL.eval_locals || !in->s.locals_dirty) return RT_OK;
    if (COSIM_MODEL.eval_locals(in->s.time, XV(in), UE(in), PV(in), ZV(in)) != 0) {
        rt_format(why, sizeof why, "evaluation of the local variables failed at t = %.16g", in->s.time);
        return evaluation_failed(in, fn, why);
    }
    in->s.locals_dirty = 0;
    return RT_OK;
}

/* Checks one value reference of a Get call and notes what has to be computed for it. */
int rt_check_get(const rt_instance *in, const char *fn, unsigned vr, cosim_type type, int *need_eval,
                 int *need_locals)
{
    rt_block b;
    if (!rt_check_vr(in, fn, vr, type)) return 0;
    b = rt_block_of(in, rt_index(in, vr));
    if (b == B_DX || b == B_Z) *need_eval = 1;
    if (b == B_Z && rt_jvp_slot(in, rt_index(in, vr)) < 0) *need_locals = 1;
    return 1;
}

/* Brings the values a checked Get call reads up to date. */
rt_status rt_finish_get(rt_instance *in, const char *fn, int need_eval, int need_locals)
{
    rt_status status;

    /* In the error state report the values as they were when the error occurred. */
    if (in->s.state == ST_ERROR) return RT_OK;
    if (need_eval) {
        status = rt_update_outputs(in, fn);
        return status == RT_OK && need_locals ? rt_update_locals(in, fn) : status;
    }
    return rt_update_parameters(in, fn) ? RT_OK : RT_ERROR;
}

/* Checks a Get call and brings the requested values up to date. */
rt_status rt_prepare_get(rt_instance *in, const char *fn, const unsigned vr[], size_t nvr, const void *value,
                         cosim_type type)
{
    size_t i;
    int need_eval = 0, need_locals = 0;

    if (nvr == 0) return RT_OK;
    if (!rt_not_null(in, fn, "vr", vr) || !rt_not_null(in, fn, "value", value)) return RT_ERROR;
    for (i = 0; i < nvr; i++)
        if (!rt_check_get(in, fn, vr[i], type, &need_eval, &need_locals)) return RT_ERROR;
    return rt_finish_get(in, fn, need_eval, need_locals);
}

/* Checks one value of a Set call (value as it would be stored) before anything is changed. */
int rt_check_set(const rt_instance *in, const char *fn, unsigned vr, cosim_type type, double value)
{
    const char *why;
    char label[160], buf[240];

    if (!rt_check_vr(in, fn, vr, type)) return 0;
    why = set_refusal(in, rt_block_of(in, rt_index(in, vr)), buf, sizeof buf);
    if (why) {
        rt_log_error(in, "%s: cannot set value reference %u in state %s: %s", fn, vr,
                     in->words->state_names[in->s.state], why);
        return 0;
    }
    /* NaN or inf as a start value, parameter or input only fails later, far from its cause
       (in the calculated parameters, or as "step size too small"). */
    if (type == COSIM_REAL && !isfinite(value)) {
        rt_log_error(in, "%s: %s = %g: the value must be finite", fn,
                     rt_vr_label(in, rt_index(in, vr), label, sizeof label),
                     value);
        return 0;
    }
    return 1;
}

/* Stores one checked value and marks what depends on it as stale.  Setting an input also ends
   its extrapolation from an earlier fmi2SetRealInputDerivatives: the model sees the value set. */
void rt_store(rt_instance *in, unsigned vr, double value)
{
    const size_t i = rt_index(in, vr);
    const rt_block b = rt_block_of(in, i);

    if (b == B_X) in->s.x_set[i] = 1;
    /* The initial equations involve the states and inputs: solve them again with the new value. */
    if ((b == B_X || b == B_U) && in->s.state == ST_INIT && COSIM_MODEL.init_unknowns) in->s.params_dirty = 1;
    if (b == B_U && UE(in)[i - in->o_u] != value) {
        UE(in)[i - in->o_u] = value;
        in->s.eval_dirty = 1;
    }
    if (in->s.v[i] == value) return; /* e.g. a master re-sending unchanged inputs */
    in->s.v[i] = value;
    if (b == B_P) in->s.params_dirty = 1;
    in->s.eval_dirty = 1;
}

/* ---------------------------------------------------------------------------------------------
 * Instance data
 * ------------------------------------------------------------------------------------------- */

static void *rt_alloc(const rt_instance *in, size_t n, size_t size)
{
    return in->alloc(n > 0 ? n : 1, size); /* calloc semantics, never ask for 0 bytes */
}

static void rt_free(const rt_instance *in, void *p)
{
    if (p) in->free(p);
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

/* The state right after the instantiation. */
void rt_reset(rt_instance *in)
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

void rt_release(rt_instance *in)
{
    if (!in) return;
    vars_free(in, &in->s);
    rt_free(in, in->work);
    rt_free(in, in->name);
    in->work = NULL;
    in->name = NULL;
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
        rt_format(buf, size, "the state belongs to another FMU (GUID %.*s, this FMU is %s)",
               RT_GUID_MAX - 1, other->guid, COSIM_MODEL.instantiation_token);
        return buf;
    }
    rt_format(buf, size, "the state has other sizes than this FMU (variables %u, states %u, inputs %u, "
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
const char *rt_model_problem(void)
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
 * FMU states
 * ------------------------------------------------------------------------------------------- */

/* The snapshot behind FMUstate if it is one of this model's, else NULL after logging why.  Only
   the tag is read before it is known to be an rt_snapshot of this runtime's layout, and nothing
   of the variables before the identity matched: a state of another FMU may be smaller. */
static rt_snapshot *as_snapshot(const rt_instance *in, const char *fn, void *FMUstate)
{
    rt_snapshot *snap = (rt_snapshot *)FMUstate;
    char why[640];

    if (!snap) {
        rt_log_error(in, "%s: FMUstate is NULL", fn);
        return NULL;
    }
    if (snap->magic != RT_STATE_MAGIC || snap->layout != RT_STATE_LAYOUT) {
        rt_log_error(in, "%s: FMUstate is not an FMU state of this FMU (nor of any FMU built with this "
                  "version of the cosim runtime)", fn);
        return NULL;
    }
    if (identity_mismatch(in, &snap->id, why, sizeof why)) {
        rt_log_error(in, "%s: FMUstate refused: %s", fn, why);
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
        rt_log_error(in, "%s: out of memory", fn);
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

/* The FMU state functions: the API has checked the call's state and logged the call. */
rt_status rt_get_state(rt_instance *in, const char *fn, void **state)
{
    rt_snapshot *snap;

    if (!rt_not_null(in, fn, "FMUstate", state)) return RT_ERROR;
    snap = *state ? as_snapshot(in, fn, *state) /* overwrite a state returned earlier */
                  : snapshot_alloc(in, fn);
    if (!snap) return RT_ERROR;
    vars_copy(in, &snap->vars, &in->s);
    *state = snap;
    return RT_OK;
}

rt_status rt_set_state(rt_instance *in, const char *fn, void *state)
{
    const rt_snapshot *snap = as_snapshot(in, fn, state);

    if (!snap) return RT_ERROR;
    if (!rt_state_fits_kind(in, snap->vars.state)) {
        rt_log_error(in, "%s: a state in %s cannot be set on a %s instance", fn,
                     in->words->state_names[snap->vars.state], rt_kind_name(in->kind));
        return RT_ERROR;
    }
    vars_copy(in, &in->s, &snap->vars);
    return RT_OK;
}

rt_status rt_free_state(rt_instance *in, const char *fn, void **state)
{
    rt_snapshot *snap;

    if (!state || !*state) return RT_OK;
    snap = as_snapshot(in, fn, *state);
    if (!snap) return RT_ERROR;
    snapshot_free(in, snap);
    *state = NULL;
    return RT_OK;
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

rt_status rt_serialized_size(rt_instance *in, const char *fn, void *state, size_t *size)
{
    if (!as_snapshot(in, fn, state)) return RT_ERROR;
    if (!rt_not_null(in, fn, "size", size)) return RT_ERROR;
    *size = serial_size(in);
    return RT_OK;
}

rt_status rt_serialize(rt_instance *in, const char *fn, void *state, unsigned char *bytes, size_t size)
{
    const rt_snapshot *snap;
    const rt_vars *s;
    unsigned char *p;
    int64_t n_steps;

    snap = as_snapshot(in, fn, state);
    if (!snap || !rt_not_null(in, fn, "serializedState", bytes)) return RT_ERROR;
    if (size < serial_size(in)) {
        rt_log_error(in, "%s: size = %zu, but %zu bytes are needed", fn, size, serial_size(in));
        return RT_ERROR;
    }
    s = &snap->vars;
    n_steps = (int64_t)s->n_steps;
    p = bytes;
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
    return RT_OK;
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
        rt_format(buf, buf_size, "size = %zu is too short for a serialized FMU state", size);
        return buf;
    }
    if (tag[0] != RT_SERIAL_MAGIC) return "not a serialized FMU state of a cosim FMU (bad magic)";
    if (tag[1] != RT_SERIAL_VERSION) {
        rt_format(buf, buf_size, "unsupported format version %u (this FMU reads version %u)", (unsigned)tag[1],
               (unsigned)RT_SERIAL_VERSION);
        return buf;
    }
    memset(&id, 0, sizeof id);
    if (!take(&r, fields, sizeof fields) || !take(&r, id.guid, RT_GUID_MAX)) {
        rt_format(buf, buf_size, "size = %zu is too short for a serialized FMU state", size);
        return buf;
    }
    id.nv = fields[0]; id.nx = fields[1]; id.nu = fields[2]; id.np = fields[3]; id.nc = fields[4];
    id.nz = fields[5]; id.n_real = fields[6]; id.n_integer = fields[7]; id.n_boolean = fields[8];
    id.guid_hash = fields[9];
    id.guid[RT_GUID_MAX - 1] = '\0'; /* printed in the message below */
    if (identity_mismatch(in, &id, buf, buf_size)) return buf;
    if (size != serial_size(in)) {
        rt_format(buf, buf_size, "size = %zu, but a serialized state of this FMU has %zu bytes", size, serial_size(in));
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
    if (flags[0] < 0 || flags[0] >= (int32_t)ST_FATAL || !rt_state_fits_kind(in, (rt_state)flags[0]))
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

rt_status rt_deserialize(rt_instance *in, const char *fn, const unsigned char *bytes, size_t size, void **state)
{
    rt_snapshot *snap;
    const char *why;
    char buf[640];

    if (!rt_not_null(in, fn, "serializedState", bytes) || !rt_not_null(in, fn, "FMUstate", state))
        return RT_ERROR;
    why = check_serialized(in, bytes, size, buf, sizeof buf);
    if (why) {
        rt_log_error(in, "%s: %s", fn, why);
        return RT_ERROR;
    }
    snap = snapshot_alloc(in, fn);
    if (!snap) return RT_ERROR;
    why = deserialize(in, bytes, size, &snap->vars);
    if (why) {
        snapshot_free(in, snap);
        rt_log_error(in, "%s: %s", fn, why);
        return RT_ERROR;
    }
    *state = snap;
    return RT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Directional derivatives
 * ------------------------------------------------------------------------------------------- */

/* Are the knowns states, inputs or Real parameters, and the unknowns derivatives or outputs? */
static int check_derivative_refs(const rt_instance *in, const char *fn, const unsigned vKnown_ref[], size_t nKnown,
                                 const unsigned vUnknown_ref[], size_t nUnknown)
{
    size_t i;

    for (i = 0; i < nKnown; i++) {
        const rt_block b = rt_block_of(in, rt_index(in, vKnown_ref[i]));
        if (!rt_check_vr(in, fn, vKnown_ref[i], COSIM_REAL)) return 0;
        if (b != B_X && b != B_U && b != B_P) {
            rt_log_error(in, "%s: known value reference %u is not a state, input or parameter", fn, vKnown_ref[i]);
            return 0;
        }
    }
    for (i = 0; i < nUnknown; i++) {
        const size_t k = rt_index(in, vUnknown_ref[i]);
        const rt_block b = rt_block_of(in, k);
        if (!rt_check_vr(in, fn, vUnknown_ref[i], COSIM_REAL)) return 0;
        if (b == B_X && in->words->state_unknowns) continue;
        if (b != B_DX && b != B_Z && in->words->state_unknowns) {
            rt_log_error(in, "%s: unknown value reference %u is not a state, derivative or algebraic variable", fn,
                         vUnknown_ref[i]);
            return 0;
        }
        if (b != B_DX && b != B_Z) {
            rt_log_error(in, "%s: unknown value reference %u is not a derivative or algebraic variable", fn,
                         vUnknown_ref[i]);
            return 0;
        }
        if (b == B_Z && rt_jvp_slot(in, k) < 0) {
            rt_log_error(in, "%s: unknown value reference %u (%s) is a local variable: directional derivatives "
                         "are provided for the derivatives and the outputs (the ModelStructure unknowns)", fn,
                         vUnknown_ref[i], COSIM_MODEL.names ? COSIM_MODEL.names[k] : "?");
            return 0;
        }
    }
    return 1;
}

/* Directional derivatives (jvp): result[i] = sum_k d unknown[i] / d known[k] * seed[k]. */
rt_status rt_directional(rt_instance *in, const char *fn, const unsigned vUnknown_ref[], size_t nUnknown,
                         const unsigned vKnown_ref[], size_t nKnown, const double dvKnown[], double dvUnknown[])
{
    size_t i;

    if (!COSIM_MODEL.jvp) {
        rt_log_error(in, "%s: the model provides no Jacobian-vector product", fn);
        return RT_ERROR;
    }
    if (!check_derivative_refs(in, fn, vKnown_ref, nKnown, vUnknown_ref, nUnknown)) return RT_ERROR;

    /* Seed direction: the knowns' increments scattered into (dx, du, dp). */
    memset(in->jx, 0, in->nx * sizeof(double));
    memset(in->ju, 0, in->nu * sizeof(double));
    memset(in->jp, 0, in->np * sizeof(double));
    for (i = 0; i < nKnown; i++) {
        const size_t k = rt_index(in, vKnown_ref[i]);
        switch (rt_block_of(in, k)) {
        case B_X: in->jx[k] += dvKnown[i]; break;
        case B_U: in->ju[k - in->o_u] += dvKnown[i]; break;
        default:  in->jp[k - in->o_p] += dvKnown[i]; break;
        }
    }

    if (!rt_update_parameters(in, fn)) return RT_ERROR;
    if (COSIM_MODEL.jvp(in->s.time, XV(in), UE(in), PV(in), in->jx, in->ju, in->jp, in->jdx, in->jz) != 0) {
        rt_fail(in, "%s: Jacobian-vector product failed at t = %.16g", fn, in->s.time);
        return RT_ERROR;
    }
    for (i = 0; i < nUnknown; i++) {
        const size_t k = rt_index(in, vUnknown_ref[i]);
        const rt_block b = rt_block_of(in, k);
        /* a state (FMI 3 state_unknowns): its own seed */
        dvUnknown[i] = b == B_X ? in->jx[k] : b == B_DX ? in->jdx[k - in->o_dx] : in->jz[rt_jvp_slot(in, k)];
    }
    return RT_OK;
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
    if (in->fixed_step < 0) return 0.0;
    h = in->s.v[in->fixed_step];
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

/* Step size factor for an error estimate err, limited to [RT_FAC_MIN, fac_max].
   The factor is RT_SAFETY / err^(1/5) clamped; where err lies clearly (a factor 2, far beyond the
   root's rounding) inside a clamped range, the clamp is returned without the fifth root, a Newton
   iteration that cost a quarter of a linear model's step: the same value, bit for bit. A step
   limited by the communication interval rather than by its error is the usual case. */
static double step_factor(double err, double fac_max)
{
    const double low = RT_SAFETY / fac_max, high = RT_SAFETY / RT_FAC_MIN;
    if (!(err > 0.0)) return fac_max;
    if (err < 0.5 * (low * low * low * low * low)) return fac_max;          /* root < low */
    if (err > 2.0 * (high * high * high * high * high)) return RT_FAC_MIN;  /* root > high */
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

/* Ends the DoStep fn (from t0 to t_end) early at t, the last successful time, where x already is:
   the inputs as extrapolated to t, der(x) and z evaluated there, the instance in stepFailed.
   Returns RT_DISCARD (RT_ERROR if even that evaluation fails). */
static rt_status step_failed(rt_instance *in, const char *fn, double t0, double t, double t_end, const char *why)
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
        rt_fail(in, "%s: %s; at the last successful time t = %.16g: %s", fn, why, t, again);
        return RT_ERROR;
    }
    in->s.eval_dirty = 0;
    in->s.state = ST_STEP_FAILED;
    rt_log_discard(in, "%s: %s; the communication step from t = %.16g to %.16g ends early at the last "
                   "successful time t = %.16g (%s; states and outputs are those at that time)",
                   fn, why, t0, t_end, t, in->words->discard);
    return RT_DISCARD;
}

/* The first non-finite state of xn or derivative of k[6] as "name = value", or NULL; into buf. */
static const char *nonfinite_solution(const rt_instance *in, char *buf, size_t size)
{
    char label[160];
    size_t i = first_nonfinite(in->xn, in->nx);

    if (i < in->nx) {
        rt_format(buf, size, "state %s = %g", rt_vr_label(in, i, label, sizeof label), in->xn[i]);
        return buf;
    }
    i = first_nonfinite(in->k[6], in->nx);
    if (i < in->nx) {
        rt_format(buf, size, "derivative %s = %g",
               rt_vr_label(in, in->o_dx + i, label, sizeof label), in->k[6][i]);
        return buf;
    }
    return NULL;
}

/* Integrates x from the current time to t_end (> time).  RT_OK: the value array holds x, u,
   der(x) and z at t_end.  RT_DISCARD: the integration failed; the instance is in stepFailed at the
   last accepted step (see step_failed).  RT_ERROR: the model cannot be evaluated at the start. */
static rt_status integrate(rt_instance *in, const char *fn, double t_end)
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
    if (rt_update_outputs(in, fn) != RT_OK) return RT_ERROR;
    memcpy(in->k[0], DXV(in), nx * sizeof(double));
    if (h_fix > 0.0) h = h_fix;
    else {
        h = in->s.h_next > 0.0 ? in->s.h_next : initial_step(in, t0, t_end - t0);
        /* A step the time cannot resolve at the scale of t_end (a model at rest starts with
           1e-6 s, which fails at once when t_end is 1e9 s): start at the shortest step that
           advances the time; the error control widens it or, rejecting it, reports the failure. */
        if (h <= min_step(t0, t_end)) h = 2.0 * min_step(t0, t_end);
    }

    while (t < t_end) {
        const double h_min = min_step(t, t_end);
        double h_try = h, h_prop, tn;
        int last = 0;

        if (++steps > RT_MAX_STEPS) {
            rt_format(why, sizeof why, "more than %ld steps in one communication step at t = %.16g "
                   "(tolerance too tight, fixed step too small or model too stiff)", RT_MAX_STEPS, t);
            return step_failed(in, fn, t0, t, t_end, why);
        }
        /* Step exactly onto t_end rather than leaving a sliver (e.g. from rounding in t) that
           would be a step of its own, possibly one too short to advance the time. */
        if (t_end - t - h <= rt_max(1e-9 * h, h_min)) {
            h_try = t_end - t;
            last = 1;
        }
        if (h_try <= h_min) {
            if (nonfinite) rt_format(what, sizeof what, " (the solution becomes non-finite)");
            else if (eval_failed) rt_format(what, sizeof what, " (the model evaluation fails at t = %.16g)", t_bad);
            else what[0] = '\0';
            rt_format(why, sizeof why, "step size %g too small at t = %.16g%s", h_try, t, what);
            return step_failed(in, fn, t0, t, t_end, why);
        }
        /* Integrate over exactly the time step that t can represent: far from t = 0, t + h
           rounds, and x would otherwise drift against the time. */
        tn = last ? t_end : t + h_try;
        h_try = tn - t;
        if (!dp_step(in, t0, t, h_try, tn, &t_bad)) {
            if (h_fix > 0.0) {
                rt_format(why, sizeof why, "model evaluation failed at t = %.16g", t_bad);
                return step_failed(in, fn, t0, t, t_end, why);
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
                rt_format(why, sizeof why, "the solution becomes non-finite at t = %.16g: %s", tn, what);
                return step_failed(in, fn, t0, t, t_end, why);
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
               the shorter step) must not shrink the step size remembered for the next DoStep.
               Where the remembered h is at least h_try times the largest factor, it stays
               whatever the error: the factor is not computed (the same h, bit for bit). */
            const double fac_max = rejected ? 1.0 : RT_FAC_MAX;
            if (!(last && h_try < h && h >= h_try * fac_max)) {
                h_prop = h_try * step_factor(err, fac_max);
                h = last && h_try < h ? rt_max(h, h_prop) : h_prop;
            }
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
    return RT_OK;
}

/* A step without integration (no states, or no time to speak of passes): advance time and
   inputs, then evaluate so that errors surface here. */
static rt_status advance(rt_instance *in, const char *fn, double t_end)
{
    size_t i;
    for (i = 0; i < in->nu; i++) {
        UE(in)[i] += in->s.du[i] * (t_end - in->s.time);
        in->s.du[i] = 0.0;
    }
    in->s.time = t_end;
    in->s.eval_dirty = 1;
    return rt_update_outputs(in, fn);
}

/* How far a step may end after stopTime: the rounding a master accumulates by adding up its
   communication steps (half an ulp of the time scale per step, n_steps so far) plus a few ulps. */
double rt_stop_allowance(const rt_instance *in)
{
    const double scale = rt_max(rt_abs(in->s.start_time), rt_abs(in->s.stop_time));
    return (16.0 + (double)in->s.n_steps) * DBL_EPSILON * scale;
}
/* ---------------------------------------------------------------------------------------------
 * Instances
 * ------------------------------------------------------------------------------------------- */

/* Fills the zeroed instance in (allocated by the API) for the model; 0 if out of memory (then
   rt_release frees what was allocated). */
int rt_init(rt_instance *in, const rt_config *cfg, const char *name)
{
    size_t i, name_len;

    in->alloc = cfg->alloc;
    in->free = cfg->free;
    in->log = cfg->log;
    in->log_env = cfg->log_env;
    in->words = cfg->words;
    in->kind = cfg->kind;
    in->log_error = 1;
    in->log_warning = 1;
    in->log_calls = cfg->log_calls;

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
    in->first_vr = COSIM_MODEL.first_vr;
    in->fixed_step = -1;

    name_len = strlen(name);
    in->name = (char *)rt_alloc(in, name_len + 1, 1);
    if (!in->name || !vars_alloc(in, &in->s) || !work_alloc(in)) return 0;
    memcpy(in->name, name, name_len + 1);
    return 1;
}

/* The model's fixed step size parameter, if it has one (a warning if it is not a Real parameter). */
void rt_check_fixed_step(rt_instance *in, const char *fn)
{
    if (COSIM_MODEL.vr_fixed_step != 0) {
        const int vr = COSIM_MODEL.vr_fixed_step;
        const size_t i = vr > 0 ? rt_index(in, (unsigned)vr) : in->nv;
        if (rt_block_of(in, i) == B_P && COSIM_MODEL.types[i] == COSIM_REAL)
            in->fixed_step = (long)i;
        else
            rt_log_warning(in, RT_WARNING, "%s: vr_fixed_step = %d is not a Real parameter; using adaptive steps",
                           fn, vr);
    }
}

/* The enable flag of a log category (as declared in modelDescription.xml), or NULL. */
static int *category_flag(rt_instance *in, const char *category)
{
    if (!category) return NULL;
    if (strcmp(category, "logStatusError") == 0) return &in->log_error;
    if (strcmp(category, "logStatusWarning") == 0) return &in->log_warning;
    if (strcmp(category, "logCalls") == 0) return &in->log_calls;
    return NULL;
}

/* SetDebugLogging: no categories means all of them; with on exactly the listed ones are logged,
   without it the listed ones are muted (FMI 2.0 and 3.0 alike).  0 (nothing changed) for an unknown
   category. */
int rt_set_category(rt_instance *in, const char *fn, int on, size_t n, const char *const categories[])
{
    size_t i;

    if (n > 0 && !rt_not_null(in, fn, "categories", categories)) return 0;
    for (i = 0; i < n; i++) { /* check all names first, so that an error changes nothing */
        if (!category_flag(in, categories[i])) {
            rt_log_error(in, "%s: unknown log category '%s' (known: logStatusError, "
                         "logStatusWarning, logCalls)", fn, categories[i] ? categories[i] : "(null)");
            return 0;
        }
    }
    if (n == 0) {
        in->log_error = in->log_warning = in->log_calls = on;
        return 1;
    }
    if (on) in->log_error = in->log_warning = in->log_calls = 0;
    for (i = 0; i < n; i++) *category_flag(in, categories[i]) = on;
    return 1;
}

/* The experiment (fmi2SetupExperiment, the arguments of fmi3EnterInitializationMode); 0 if refused. */
int rt_setup(rt_instance *in, const char *fn, int tolerance_defined, double tolerance, double start_time,
             int stop_defined, double stop_time)
{
    if (tolerance_defined && !(tolerance > 0.0 && isfinite(tolerance))) {
        rt_log_error(in, "%s: tolerance = %g must be positive", fn, tolerance);
        return 0;
    }
    if (!isfinite(start_time)) {
        rt_log_error(in, "%s: startTime must be finite", fn);
        return 0;
    }
    /* +inf is no limit and accepted as such */
    if (stop_defined && !(stop_time >= start_time)) {
        rt_log_error(in, "%s: stopTime = %.16g must not be before startTime = %.16g", fn, stop_time, start_time);
        return 0;
    }
    in->s.tolerance = tolerance_defined ? tolerance : default_tolerance();
    in->s.time = start_time;
    in->s.start_time = start_time;
    in->s.stop_defined = stop_defined != 0;
    in->s.stop_time = in->s.stop_defined ? stop_time : 0.0;
    in->s.eval_dirty = 1;
    return 1;
}

rt_status rt_enter_init(rt_instance *in, const char *fn)
{
    in->s.state = ST_INIT;
    in->s.params_dirty = 1; /* now the calculated state starts are computed, too */
    /* The initial equations are solved when their solution is needed (a getter, or the exit of
       initialization mode): parameters and inputs may still change in initializationMode. */
    if (COSIM_MODEL.init_unknowns) return RT_OK;
    return rt_update_parameters(in, fn) ? RT_OK : RT_ERROR;
}

/* Leaves initializationMode for state next. */
rt_status rt_exit_init(rt_instance *in, const char *fn, rt_state next)
{
    /* Evaluate now, so that a model that cannot start fails here and not at some later call
       (in initializationMode every failure is an error, see rt_update_outputs). */
    if (rt_update_outputs(in, fn) != RT_OK) return RT_ERROR;
    in->s.h_next = 0.0;
    in->s.n_steps = 0;
    in->s.state = next;
    return RT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Adjoint derivatives
 * ------------------------------------------------------------------------------------------- */

/* Adjoint derivatives (vjp): result[k] = sum_i seed[i] * d unknown[i] / d known[k]. */
rt_status rt_adjoint(rt_instance *in, const char *fn, const unsigned vUnknown_ref[], size_t nUnknown,
                     const unsigned vKnown_ref[], size_t nKnown, const double seed[], double result[])
{
    size_t i;

    if (!COSIM_MODEL.vjp) {
        rt_log_error(in, "%s: the model provides no vector-Jacobian product (no adjoint derivatives)", fn);
        return RT_ERROR;
    }
    if (!check_derivative_refs(in, fn, vKnown_ref, nKnown, vUnknown_ref, nUnknown)) return RT_ERROR;

    /* Weights: the unknowns' seeds scattered onto (der(x), the outputs' slots). */
    memset(in->jdx, 0, in->nx * sizeof(double));
    memset(in->jz, 0, in->nz * sizeof(double));
    for (i = 0; i < nUnknown; i++) {
        const size_t k = rt_index(in, vUnknown_ref[i]);
        const rt_block b = rt_block_of(in, k);
        if (b == B_DX) in->jdx[k - in->o_dx] += seed[i];
        else if (b == B_Z) in->jz[rt_jvp_slot(in, k)] += seed[i];
    }

    if (!rt_update_parameters(in, fn)) return RT_ERROR;
    if (COSIM_MODEL.vjp(in->s.time, XV(in), UE(in), PV(in), in->jdx, in->jz, in->jx, in->ju, in->jp) != 0) {
        rt_fail(in, "%s: vector-Jacobian product failed at t = %.16g", fn, in->s.time);
        return RT_ERROR;
    }
    /* a state among the unknowns (FMI 3 state_unknowns): d x_i / d x_j = delta_ij */
    for (i = 0; i < nUnknown; i++) {
        const size_t k = rt_index(in, vUnknown_ref[i]);
        if (rt_block_of(in, k) == B_X) in->jx[k] += seed[i];
    }
    for (i = 0; i < nKnown; i++) {
        const size_t k = rt_index(in, vKnown_ref[i]);
        switch (rt_block_of(in, k)) {
        case B_X: result[i] = in->jx[k]; break;
        case B_U: result[i] = in->ju[k - in->o_u]; break;
        default:  result[i] = in->jp[k - in->o_p]; break;
        }
    }
    return RT_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Model Exchange and Co-Simulation steps
 * ------------------------------------------------------------------------------------------- */

int rt_set_time(rt_instance *in, const char *fn, double time)
{
    if (!isfinite(time)) {
        rt_log_error(in, "%s: time must be finite", fn);
        return 0;
    }
    if (time != in->s.time) {
        in->s.time = time;
        in->s.eval_dirty = 1;
    }
    return 1;
}

/* The step from the instance's time to t_end (> time, checked by the API). */
rt_status rt_do_step(rt_instance *in, const char *fn, double t_end)
{
    const double t = in->s.time;
    rt_status status;

    if (in->nx > 0 && t_end - t > min_step(t, t_end)) status = integrate(in, fn, t_end);
    else status = advance(in, fn, t_end);
    if (status == RT_OK) in->s.n_steps++;
    return status;
}
