/*
 * harness.c -- tests of the FMI 2.0 runtime (cosim_runtime.c with fmi2_api.c) against the hand-written
 * model in test_model.c.
 *
 * Build (see run.sh):  cc -std=c99 -I<fmi2 headers> -I.. harness.c test_model.c ../cosim_runtime.c ../fmi2_api.c
 *                         -lm -ldl
 * Run:                 harness SMALL.so SMALL_SAME_GUID.so TWIN.so INIT.so
 *   the first three arguments are other FMUs (the runtime compiled with another model into a shared
 *   library, see run.sh): test_model_small.c with its own GUID, test_model_small.c claiming this
 *   model's GUID, and test_model.c with the GUID TWIN_GUID.  They are the foreign FMUs whose FMU
 *   states the runtime must refuse.  The fourth, test_model_init.c, is a model with an initial equation.
 * Exit code 0 if every check passes.
 */
#define _POSIX_C_SOURCE 200809L /* dlopen under -std=c99 */
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "cosim_model.h"

extern long test_model_evals;

#define GUID "{8c4e810f-3df3-4a00-8276-176fa3c9f000}"
#define SMALL_GUID "{5d1b2c3a-7f4e-4b21-9a63-0c2d7e8f1a42}" /* default of test_model_small.c */
#define TWIN_GUID "{8c4e810f-3df3-4a00-8276-176fa3c9f001}"  /* passed by run.sh */

enum { VR_S, VR_V, VR_W, VR_DS, VR_DV, VR_DW, VR_U, VR_K, VR_N, VR_B, VR_H, VR_OMEGA, VR_N10, VR_F, VR_E, NV };

/* ------------------------------------------------------------------------------------------ */
/* Checks                                                                                       */

#include "check.h"

#define CHECK_OK(call) check((call) == fmi2OK, #call " == fmi2OK", __FILE__, __LINE__)
#define CHECK_ERR(call) check((call) == fmi2Error, #call " == fmi2Error", __FILE__, __LINE__)
#define CHECK_DISCARD(call) check((call) == fmi2Discard, #call " == fmi2Discard", __FILE__, __LINE__)

/* ------------------------------------------------------------------------------------------ */
/* Callbacks: a logger that keeps the last message per instance, and a counting allocator      */

typedef struct {
    char last[2048];       /* last message, formatted */
    char last_category[64];
    fmi2Status last_status;
    int n_messages;
    int echo;
} logbook;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    logbook *lb = (logbook *)env;
    va_list ap;

    va_start(ap, message);
    vsnprintf(lb->last, sizeof lb->last, message, ap); /* messages are format strings */
    va_end(ap);
    snprintf(lb->last_category, sizeof lb->last_category, "%s", category);
    lb->last_status = status;
    lb->n_messages++;
    if (lb->echo) printf("    [%s] %s: %s\n", category, name, lb->last);
}

static long n_live_allocations = 0;

static void *counting_calloc(size_t n, size_t size)
{
    void *p = calloc(n, size);
    if (p) n_live_allocations++;
    return p;
}

static void counting_free(void *p)
{
    if (p) n_live_allocations--;
    free(p);
}

static fmi2CallbackFunctions callbacks(logbook *lb)
{
    fmi2CallbackFunctions cb;
    memset(lb, 0, sizeof *lb);
    cb.logger = logger;
    cb.allocateMemory = counting_calloc;
    cb.freeMemory = counting_free;
    cb.stepFinished = NULL;
    cb.componentEnvironment = lb;
    return cb;
}

/* Did the last message contain all of the given fragments? */
static int logged(const logbook *lb, const char *a, const char *b)
{
    return strstr(lb->last, a) != NULL && (!b || strstr(lb->last, b) != NULL);
}

/* ------------------------------------------------------------------------------------------ */
/* Helpers                                                                                      */

static double get(fmi2Component c, fmi2ValueReference vr)
{
    double v = NAN;
    if (fmi2GetReal(c, &vr, 1, &v) != fmi2OK) printf("    (fmi2GetReal(%u) failed)\n", vr);
    return v;
}

static fmi2Status set(fmi2Component c, fmi2ValueReference vr, double v)
{
    return fmi2SetReal(c, &vr, 1, &v);
}

/* Instantiates, sets up with the tolerance and enters initialization mode. */
static fmi2Component start_init(fmi2Type type, fmi2CallbackFunctions *cb, double tol)
{
    fmi2Component c = fmi2Instantiate("inst", type, GUID, "", cb, fmi2False, fmi2False);
    if (!c) return NULL;
    fmi2SetupExperiment(c, tol > 0, tol, 0.0, fmi2False, 0.0);
    fmi2EnterInitializationMode(c);
    return c;
}

static fmi2Component start(fmi2Type type, fmi2CallbackFunctions *cb, double tol)
{
    fmi2Component c = start_init(type, cb, tol);
    if (c) fmi2ExitInitializationMode(c);
    return c;
}

/* Exact solution of s'' + d s' + k s = g (u0 + r t), s(0) = s0, s'(0) = v0 (underdamped). */
static void exact_sv(double t, double k, double d, double u0, double r, double s0, double v0,
                     double *s, double *v)
{
    const double a = d / 2.0, wd = sqrt(k - a * a);
    const double beta = r / k, alpha = (u0 - d * beta) / k;
    const double A = s0 - alpha, B = (v0 - beta + a * A) / wd;
    const double e = exp(-a * t), co = cos(wd * t), si = sin(wd * t);
    *s = e * (A * co + B * si) + alpha + beta * t;
    *v = e * ((-a * A + wd * B) * co + (-a * B - wd * A) * si) + beta;
}

/* Runs a CS instance (k = 4, d = 0.2, u = 0.5 + r t) with DoStep size H to t = 10;
   returns the largest deviation of s, v, w from the exact solution. */
static double cs_error(double tol, double H, double h_fixed, double r, long *evals_per_step)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start_init(fmi2CoSimulation, &cb, tol);
    const fmi2ValueReference vu = VR_U;
    const fmi2Integer order = 1;
    double t = 0.0, err = 0.0;
    long evals0;
    int i, n = (int)(10.0 / H + 0.5);

    set(c, VR_H, h_fixed);
    fmi2ExitInitializationMode(c);
    evals0 = test_model_evals;
    for (i = 0; i < n; i++) {
        double s, v;
        set(c, VR_U, 0.5 + r * t);
        if (r != 0.0) fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r);
        if (fmi2DoStep(c, t, H, fmi2True) != fmi2OK) {
            printf("    DoStep failed: %s\n", lb.last);
            err = INFINITY;
            break;
        }
        t = (i + 1) * H;
        exact_sv(t, 4.0, 0.2, 0.5, r, 1.0, 0.0, &s, &v);
        err = fmax(err, fabs(get(c, VR_S) - s));
        err = fmax(err, fabs(get(c, VR_V) - v));
        err = fmax(err, fabs(get(c, VR_W) - 2.0 * exp(-t)));
    }
    if (evals_per_step) *evals_per_step = (test_model_evals - evals0) / n;
    fmi2FreeInstance(c);
    return err;
}

/* ------------------------------------------------------------------------------------------ */
/* Tests                                                                                        */

static void test_basics(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2CallbackFunctions bad = cb;
    fmi2Component c;

    CHECK(strcmp(fmi2GetVersion(), "2.0") == 0);
    CHECK(strcmp(fmi2GetTypesPlatform(), "default") == 0);

    c = fmi2Instantiate("inst", fmi2CoSimulation, "{wrong}", "", &cb, fmi2False, fmi2False);
    CHECK(c == NULL);
    CHECK(logged(&lb, "GUID", "{wrong}"));
    CHECK(lb.last_status == fmi2Error);

    bad.allocateMemory = NULL;
    CHECK(fmi2Instantiate("inst", fmi2CoSimulation, GUID, "", &bad, fmi2False, fmi2False) == NULL);
    CHECK(fmi2Instantiate("", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False) == NULL);
    CHECK(fmi2Instantiate("inst", (fmi2Type)7, GUID, "", &cb, fmi2False, fmi2False) == NULL);
    CHECK(fmi2Instantiate("inst", fmi2CoSimulation, GUID, "", NULL, fmi2False, fmi2False) == NULL);

    /* NULL components are rejected, not dereferenced */
    CHECK_ERR(fmi2DoStep(NULL, 0.0, 1.0, fmi2True));
    CHECK_ERR(fmi2GetReal(NULL, NULL, 0, NULL));
    fmi2FreeInstance(NULL);
}

static void test_state_machine(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = fmi2Instantiate("sm", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    fmi2EventInfo info;
    double x;
    fmi2ValueReference vr = VR_S;

    CHECK(c != NULL);
    CHECK_ERR(fmi2GetReal(c, &vr, 1, &x));
    CHECK(logged(&lb, "fmi2GetReal", "instantiated"));
    CHECK(strcmp(lb.last_category, "logStatusError") == 0);
    CHECK_ERR(fmi2DoStep(c, 0.0, 0.1, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "instantiated"));
    CHECK_ERR(fmi2ExitInitializationMode(c));
    CHECK_ERR(fmi2Terminate(c));
    CHECK_ERR(fmi2EnterEventMode(c));
    CHECK(logged(&lb, "fmi2EnterEventMode", "CoSimulation"));
    CHECK_ERR(fmi2NewDiscreteStates(c, &info));
    CHECK_ERR(fmi2SetTime(c, 1.0));
    CHECK_ERR(fmi2SetupExperiment(c, fmi2True, -1.0, 0.0, fmi2False, 0.0)); /* bad tolerance */

    /* rejected calls leave the instance usable */
    CHECK_OK(fmi2SetupExperiment(c, fmi2True, 1e-8, 2.0, fmi2False, 0.0));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_ERR(fmi2EnterInitializationMode(c));
    CHECK(logged(&lb, "fmi2EnterInitializationMode", "initializationMode"));
    CHECK_ERR(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_ERR(fmi2DoStep(c, 2.0, 0.1, fmi2True));
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_ERR(fmi2ExitInitializationMode(c));
    CHECK(logged(&lb, "fmi2ExitInitializationMode", "stepComplete"));
    CHECK_ERR(fmi2EnterInitializationMode(c));

    /* communication points */
    CHECK_ERR(fmi2DoStep(c, 0.0, 0.1, fmi2True)); /* start time is 2 */
    CHECK(logged(&lb, "currentCommunicationPoint", NULL));
    CHECK_ERR(fmi2DoStep(c, 2.0, -0.1, fmi2True));
    CHECK_ERR(fmi2DoStep(c, 2.0, NAN, fmi2True));
    CHECK_ERR(fmi2DoStep(c, 2.0, INFINITY, fmi2True));
    CHECK_ERR(fmi2DoStep(c, 2.0 + 1e-14, 0.0, fmi2True)); /* see test_zero_step_and_step_past_stop_time... */
    CHECK_NEAR(get(c, VR_S), 1.0, 0.0);
    CHECK_OK(fmi2DoStep(c, 2.0 + 1e-14, 1e-15, fmi2True)); /* within the tolerance; too short to integrate */
    CHECK_NEAR(get(c, VR_S), 1.0, 1e-14);
    CHECK_OK(fmi2DoStep(c, 2.0 + 1e-14, 0.5, fmi2True));
    CHECK_OK(fmi2DoStep(c, 2.5 + 1e-14, 0.5, fmi2True));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &x));
    CHECK_NEAR(x, 3.0, 1e-13);

    CHECK_OK(fmi2Terminate(c));
    CHECK_ERR(fmi2Terminate(c));
    CHECK_ERR(fmi2DoStep(c, 3.0, 0.1, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "terminated"));
    CHECK(!isnan(get(c, VR_F))); /* getters work after termination */
    CHECK_ERR(set(c, VR_U, 1.0));

    /* reset: back to the start values as after instantiation */
    CHECK_OK(fmi2Reset(c));
    CHECK_ERR(fmi2DoStep(c, 0.0, 0.1, fmi2True));
    CHECK_OK(set(c, VR_K, 9.0));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_NEAR(get(c, VR_OMEGA), 3.0, 0.0);
    CHECK_OK(fmi2Reset(c));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_NEAR(get(c, VR_K), 4.0, 0.0);
    CHECK_NEAR(get(c, VR_S), 1.0, 0.0);
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_OK(fmi2DoStep(c, 0.0, 0.1, fmi2True)); /* the time was reset to 0 */
    fmi2FreeInstance(c);
}

static void test_get_set(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = fmi2Instantiate("gs", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    fmi2ValueReference vr2[2] = { VR_K, VR_DS };
    double two[2] = { 16.0, 1.0 };
    fmi2ValueReference vr;
    fmi2Integer iv;
    fmi2Boolean bv;
    fmi2String sv;
    double x = 0.0;

    /* types */
    vr = VR_N;
    CHECK_ERR(fmi2SetReal(c, &vr, 1, &x));
    CHECK(logged(&lb, "Integer", "8"));
    vr = VR_K;
    iv = 3;
    CHECK_ERR(fmi2SetInteger(c, &vr, 1, &iv));
    CHECK_ERR(fmi2SetBoolean(c, &vr, 1, &bv));
    vr = NV;
    CHECK_ERR(fmi2SetReal(c, &vr, 1, &x));
    CHECK(logged(&lb, "out of range", NULL));
    CHECK_ERR(fmi2SetReal(c, NULL, 1, &x));

    /* what may be set before initialization */
    CHECK_ERR(set(c, VR_DS, 1.0));
    CHECK(logged(&lb, "value reference 3", "derivative"));
    CHECK_ERR(set(c, VR_OMEGA, 1.0));
    CHECK(logged(&lb, "value reference 11", NULL));
    CHECK_ERR(set(c, VR_F, 1.0));
    CHECK(logged(&lb, "value reference 13", NULL));
    CHECK_OK(set(c, VR_S, 2.0));
    CHECK_OK(set(c, VR_U, 0.25));
    vr = VR_N;
    iv = 3;
    CHECK_OK(fmi2SetInteger(c, &vr, 1, &iv));
    vr = VR_B;
    bv = 5; /* any non-zero value is true */
    CHECK_OK(fmi2SetBoolean(c, &vr, 1, &bv));
    /* a failed Set changes nothing */
    CHECK_ERR(fmi2SetReal(c, vr2, 2, two));

    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_NEAR(get(c, VR_K), 4.0, 0.0);
    vr = VR_N10;
    CHECK_OK(fmi2GetInteger(c, &vr, 1, &iv));
    CHECK(iv == 30);
    vr = VR_B;
    CHECK_OK(fmi2GetBoolean(c, &vr, 1, &bv));
    CHECK(bv == fmi2True);
    CHECK_ERR(fmi2GetReal(c, &vr, 1, &x));
    CHECK(logged(&lb, "Boolean", "not Real"));
    CHECK_ERR(fmi2GetInteger(c, &vr, 1, &iv));
    vr = VR_K;
    CHECK_ERR(fmi2GetInteger(c, &vr, 1, &iv));
    CHECK(logged(&lb, "Real", "not Integer"));
    vr = VR_N;
    CHECK_ERR(fmi2GetBoolean(c, &vr, 1, &bv));
    vr = NV + 100;
    CHECK_ERR(fmi2GetReal(c, &vr, 1, &x));

    /* strings: there are none */
    CHECK_OK(fmi2GetString(c, NULL, 0, NULL));
    CHECK_OK(fmi2SetString(c, NULL, 0, NULL));
    vr = VR_S;
    CHECK_ERR(fmi2GetString(c, &vr, 1, &sv));
    CHECK_ERR(fmi2SetString(c, &vr, 1, &sv));
    CHECK_OK(fmi2GetReal(c, NULL, 0, NULL));

    /* derivatives and algebraics are evaluated lazily from the current values */
    CHECK_NEAR(get(c, VR_DV), -4.0 * 2.0 - 0.3 * 0.0 + 0.25, 1e-15);
    CHECK_NEAR(get(c, VR_F), 4.0 * 2.0 + 0.25, 1e-15);
    CHECK_OK(set(c, VR_V, 1.0));
    CHECK_NEAR(get(c, VR_DV), -4.0 * 2.0 - 0.3 * 1.0 + 0.25, 1e-15);
    CHECK_NEAR(get(c, VR_E), 1.0 + 2.0, 1e-15); /* w = k / 2 = 2 */

    CHECK_OK(fmi2ExitInitializationMode(c));
    /* after initialization: parameters and states are fixed, inputs remain settable */
    CHECK_ERR(set(c, VR_K, 5.0));
    CHECK(logged(&lb, "value reference 7", "parameter"));
    CHECK_ERR(set(c, VR_S, 5.0));
    CHECK(logged(&lb, "value reference 0", "stepComplete"));
    vr = VR_N;
    iv = 1;
    CHECK_ERR(fmi2SetInteger(c, &vr, 1, &iv));
    CHECK_OK(set(c, VR_U, 1.0));
    CHECK_NEAR(get(c, VR_F), 4.0 * 2.0 + 1.0, 1e-15);
    fmi2FreeInstance(c);
}

static void test_calculated(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start_init(fmi2CoSimulation, &cb, 0.0);

    /* calculated parameters and calculated state starts follow parameter changes in init mode */
    CHECK_NEAR(get(c, VR_OMEGA), 2.0, 0.0);
    CHECK_NEAR(get(c, VR_W), 2.0, 0.0);
    CHECK_OK(set(c, VR_K, 9.0));
    CHECK_NEAR(get(c, VR_OMEGA), 3.0, 0.0);
    CHECK_NEAR(get(c, VR_W), 4.5, 0.0);
    CHECK_NEAR(get(c, VR_DW), -4.5, 0.0);
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_NEAR(get(c, VR_W), 4.5, 0.0);
    CHECK_NEAR(get(c, VR_OMEGA), 3.0, 0.0);
    fmi2FreeInstance(c);

    /* a state set explicitly wins over its calculated start */
    c = fmi2Instantiate("calc", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    CHECK_OK(set(c, VR_W, 7.0));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_OK(set(c, VR_K, 16.0));
    CHECK_NEAR(get(c, VR_W), 7.0, 0.0);
    CHECK_NEAR(get(c, VR_OMEGA), 4.0, 0.0);
    fmi2FreeInstance(c);

    /* a failing calc_parameters puts the instance into the error state */
    c = fmi2Instantiate("calc", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    CHECK_OK(set(c, VR_K, -1.0));
    CHECK_ERR(fmi2EnterInitializationMode(c));
    CHECK(logged(&lb, "calculated parameters", NULL));
    CHECK_ERR(fmi2ExitInitializationMode(c));
    CHECK(logged(&lb, "error", NULL));
    CHECK_OK(fmi2Reset(c));
    CHECK_OK(fmi2EnterInitializationMode(c));
    fmi2FreeInstance(c);
}

static void test_cs_accuracy(void)
{
    long evals;
    double e;

    e = cs_error(1e-10, 0.1, 0.0, 0.0, NULL);
    printf("  adaptive, tol 1e-10, H = 0.1:  max error %.3g\n", e);
    CHECK(e < 1e-9);
    e = cs_error(1e-10, 1.0, 0.0, 0.0, NULL);
    printf("  adaptive, tol 1e-10, H = 1:    max error %.3g\n", e);
    CHECK(e < 1e-9);
    e = cs_error(1e-6, 0.5, 0.0, 0.0, NULL);
    printf("  adaptive, tol 1e-6,  H = 0.5:  max error %.3g\n", e);
    CHECK(e < 1e-5);
    e = cs_error(1e-10, 10.0, 0.0, 0.0, NULL);
    printf("  adaptive, tol 1e-10, H = 10:   max error %.3g\n", e);
    CHECK(e < 1e-9);

    /* step size memory: with small communication steps each DoStep is one step of 6 evaluations */
    e = cs_error(1e-6, 0.01, 0.0, 0.0, &evals);
    printf("  adaptive, tol 1e-6,  H = 0.01: max error %.3g, %ld evaluations per DoStep\n", e, evals);
    CHECK(e < 1e-6);
    CHECK(evals <= 6);

    /* fixed steps: exactly H / h steps of 6 evaluations (FSAL), the last one shortened */
    e = cs_error(1e-10, 0.1, 0.01, 0.0, &evals);
    printf("  fixed h = 0.01, H = 0.1:       max error %.3g, %ld evaluations per DoStep\n", e, evals);
    CHECK(e < 1e-8);
    CHECK(evals == 60);
    e = cs_error(1e-10, 0.125, 0.01, 0.0, &evals);
    printf("  fixed h = 0.01, H = 0.125:     max error %.3g, %ld evaluations per DoStep\n", e, evals);
    CHECK(e < 1e-8);
    CHECK(evals == 78);
    e = cs_error(1e-10, 0.1, 0.1, 0.0, &evals);
    printf("  fixed h = 0.1, H = 0.1:        max error %.3g\n", e);
    CHECK(e < 1e-4 && e > 1e-9); /* visibly less accurate: no error control */
}

/* Far from t = 0 the rounding of the time must not produce tiny steps or failures. */
static void test_cs_late_start(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    const double t0 = 1e6;
    double h_fixed, s, v;
    int i, j, ok;

    for (j = 0; j < 2; j++) {
        fmi2Component c = fmi2Instantiate("late", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
        h_fixed = j == 0 ? 0.0 : 1e-3;
        fmi2SetupExperiment(c, fmi2True, 1e-10, t0, fmi2False, 0.0);
        fmi2EnterInitializationMode(c);
        set(c, VR_H, h_fixed);
        fmi2ExitInitializationMode(c);
        ok = 1;
        for (i = 0; i < 30 && ok; i++) ok = fmi2DoStep(c, t0 + 0.1 * i, 0.1, fmi2True) == fmi2OK;
        CHECK(ok);
        exact_sv(3.0, 4.0, 0.2, 0.5, 0.0, 1.0, 0.0, &s, &v);
        /* t itself has a resolution of 1.2e-10 here; x must not drift against it */
        CHECK_NEAR(get(c, VR_S), s, 2e-9);
        fmi2FreeInstance(c);
    }
}

static void test_cs_outputs_and_inputs(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c, me;
    const fmi2ValueReference vu = VR_U, vk = VR_K;
    fmi2Integer order = 1;
    double r = 0.3, e, s, x, u;
    int i;

    /* linearly interpolated inputs reproduce the exact solution for u = 0.5 + 0.3 t */
    e = cs_error(1e-10, 0.1, 0.0, 0.3, NULL);
    printf("  input derivatives, tol 1e-10:  max error %.3g\n", e);
    CHECK(e < 1e-9);
    e = cs_error(1e-10, 1.0, 0.0, 0.3, NULL);
    CHECK(e < 1e-9);
    /* while holding the input constant over each step is visibly wrong */
    {
        c = start(fmi2CoSimulation, &cb, 1e-10);
        for (i = 0; i < 10; i++) {
            set(c, VR_U, 0.5 + 0.3 * i);
            fmi2DoStep(c, i, 1.0, fmi2True);
        }
        exact_sv(10.0, 4.0, 0.2, 0.5, 0.3, 1.0, 0.0, &s, &x);
        CHECK(fabs(get(c, VR_S) - s) > 1e-3);
        fmi2FreeInstance(c);
    }

    c = start(fmi2CoSimulation, &cb, 1e-10);
    /* outputs at the end of a step are consistent with the states there */
    CHECK_OK(fmi2DoStep(c, 0.0, 0.7, fmi2True));
    s = get(c, VR_S);
    CHECK(get(c, VR_F) == 4.0 * s + 0.5);
    CHECK(get(c, VR_DV) == -4.0 * s - 0.2 * get(c, VR_V) + 0.5);
    CHECK(get(c, VR_DS) == get(c, VR_V));

    /* after a step with input derivatives the model sees the input's end value (the input itself
       stays as set, see test_input_derivative_does_not_overwrite_input), the derivative is reset */
    CHECK_OK(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r));
    CHECK_OK(fmi2DoStep(c, 0.7, 0.5, fmi2True));
    u = 0.5 + 0.3 * 0.5;
    CHECK(get(c, VR_U) == 0.5);
    CHECK_NEAR(get(c, VR_F), 4.0 * get(c, VR_S) + u, 1e-15);
    CHECK_OK(fmi2DoStep(c, 1.2, 0.5, fmi2True));
    CHECK_NEAR(get(c, VR_F), 4.0 * get(c, VR_S) + u, 1e-15);

    /* a new input value is seen at once by the outputs */
    CHECK_OK(set(c, VR_U, 2.0));
    CHECK(get(c, VR_F) == 4.0 * get(c, VR_S) + 2.0);
    /* non-finite input derivatives are refused */
    r = NAN;
    CHECK_ERR(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r));
    CHECK(logged(&lb, "u (value reference 6)", "finite"));
    r = 0.3;

    /* only first-order derivatives of Real inputs */
    order = 2;
    CHECK_ERR(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r));
    CHECK(logged(&lb, "order 2", NULL));
    order = 1;
    CHECK_ERR(fmi2SetRealInputDerivatives(c, &vk, 1, &order, &r));
    CHECK(logged(&lb, "not an input", NULL));
    CHECK_ERR(fmi2GetRealOutputDerivatives(c, &vk, 1, &order, &r));
    CHECK_OK(fmi2Terminate(c));
    CHECK_ERR(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r));
    fmi2FreeInstance(c);

    me = start(fmi2ModelExchange, &cb, 0.0);
    CHECK_ERR(fmi2SetRealInputDerivatives(me, &vu, 1, &order, &r));
    CHECK(logged(&lb, "ModelExchange", NULL));
    fmi2FreeInstance(me);
}

static void test_cs_status(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start(fmi2CoSimulation, &cb, 0.0);
    fmi2Status st;
    fmi2Real t;
    fmi2Integer i;
    fmi2Boolean b;
    fmi2String s;

    CHECK_OK(fmi2DoStep(c, 0.0, 0.25, fmi2True));
    CHECK_OK(fmi2GetStatus(c, fmi2DoStepStatus, &st));
    CHECK(st == fmi2OK);
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK(t == 0.25);
    CHECK_OK(fmi2GetBooleanStatus(c, fmi2Terminated, &b));
    CHECK(b == fmi2False);
    CHECK(fmi2GetStringStatus(c, fmi2PendingStatus, &s) == fmi2Discard);
    CHECK(fmi2GetIntegerStatus(c, fmi2DoStepStatus, &i) == fmi2Discard);
    CHECK(fmi2GetStatus(c, fmi2PendingStatus, &st) == fmi2Discard);
    CHECK_ERR(fmi2CancelStep(c));
    CHECK(logged(&lb, "fmi2CancelStep", NULL));
    CHECK_OK(fmi2DoStep(c, 0.25, 0.25, fmi2True)); /* none of this harmed the instance */
    fmi2FreeInstance(c);
}

static void test_cs_failures(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start(fmi2CoSimulation, &cb, 1e-8);
    fmi2Real t;

    /* a model that cannot be evaluated at the communication point with the environment's inputs:
       nothing of the step can be computed, an error (integration failures inside the step are
       fmi2Discard, see test_integration_failure_is_discard_with_last_successful_time) */
    CHECK_OK(fmi2DoStep(c, 0.0, 0.5, fmi2True));
    CHECK_OK(set(c, VR_U, 2e6));
    CHECK_ERR(fmi2DoStep(c, 0.5, 0.5, fmi2True));
    CHECK(logged(&lb, "evaluation failed", "at t = 0.5"));
    CHECK_ERR(fmi2DoStep(c, 0.5, 0.5, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "state error"));
    CHECK_ERR(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK_NEAR(get(c, VR_S), get(c, VR_S), 0.0); /* values remain readable for diagnosis */
    CHECK_ERR(set(c, VR_U, 0.0));
    CHECK_ERR(fmi2Terminate(c)); /* FMI 2.0: not in the error state; fmi2FreeInstance or fmi2Reset */
    CHECK_OK(fmi2Reset(c));
    fmi2FreeInstance(c);
}

/* Records the outputs of five steps with changing inputs. */
static void five_steps(fmi2Component c, double t, double out[5][6])
{
    const fmi2ValueReference vu = VR_U, vr[6] = { VR_S, VR_V, VR_W, VR_F, VR_E, VR_DV };
    const fmi2Integer order = 1;
    int i;
    for (i = 0; i < 5; i++) {
        double du = 0.1 * i;
        set(c, VR_U, 0.2 * i);
        fmi2SetRealInputDerivatives(c, &vu, 1, &order, &du);
        fmi2DoStep(c, t + 0.3 * i, 0.3, fmi2False);
        fmi2GetReal(c, vr, 6, out[i]);
    }
}

static void test_fmu_state(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start(fmi2CoSimulation, &cb, 1e-9), me;
    fmi2FMUstate state = NULL, state2 = NULL, state3 = NULL;
    double ref[5][6], again[5][6], t;
    size_t size = 0;
    char *bytes;
    int i;

    for (i = 0; i < 5; i++) fmi2DoStep(c, 0.2 * i, 0.2, fmi2True);
    CHECK_OK(fmi2GetFMUstate(c, &state));
    five_steps(c, 1.0, ref);

    CHECK_OK(fmi2SetFMUstate(c, state));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK(t == 1.0);
    five_steps(c, 1.0, again);
    CHECK(memcmp(ref, again, sizeof ref) == 0);

    /* overwriting an existing state */
    CHECK_OK(fmi2GetFMUstate(c, &state));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK_NEAR(t, 2.5, 1e-14);

    /* serialization round trip */
    CHECK_OK(fmi2SetFMUstate(c, state)); /* t = 2.5 */
    CHECK_OK(fmi2GetFMUstate(c, &state2));
    CHECK_OK(fmi2SerializedFMUstateSize(c, state2, &size));
    bytes = (char *)malloc(size);
    CHECK_OK(fmi2SerializeFMUstate(c, state2, bytes, size));
    CHECK_ERR(fmi2SerializeFMUstate(c, state2, bytes, size - 1));
    CHECK_OK(fmi2FreeFMUstate(c, &state2));
    CHECK(state2 == NULL);
    five_steps(c, 2.5, ref);
    CHECK_OK(fmi2DeSerializeFMUstate(c, bytes, size, &state3));
    CHECK_OK(fmi2SetFMUstate(c, state3));
    five_steps(c, 2.5, again);
    CHECK(memcmp(ref, again, sizeof ref) == 0);

    /* a state restored into a different instance continues identically there, too */
    {
        fmi2Component c2 = start(fmi2CoSimulation, &cb, 1e-3);
        CHECK_OK(fmi2SetFMUstate(c2, state3));
        five_steps(c2, 2.5, again);
        CHECK(memcmp(ref, again, sizeof ref) == 0);
        fmi2FreeInstance(c2);
    }

    /* ... also where the model's hoisted parameter terms (test_model.c: d = 0.1 n) were computed for
       other parameters (n = 9, not 2): they follow the restored state, from fmi2GetFMUstate of the
       other instance and from fmi2DeSerializeFMUstate alike */
    {
        const fmi2ValueReference vn = 8;
        const fmi2Integer n9 = 9;
        fmi2FMUstate restored = NULL;
        int from;
        for (from = 0; from < 2; from++) {
            fmi2Component c2 = start_init(fmi2CoSimulation, &cb, 1e-3);
            CHECK_OK(fmi2SetInteger(c2, &vn, 1, &n9));
            CHECK_OK(fmi2ExitInitializationMode(c2));
            CHECK_OK(fmi2DoStep(c2, 0.0, 0.5, fmi2True));
            if (from == 0) {
                CHECK_OK(fmi2SetFMUstate(c2, state3));
            } else {
                CHECK_OK(fmi2DeSerializeFMUstate(c2, bytes, size, &restored));
                CHECK_OK(fmi2SetFMUstate(c2, restored));
                CHECK_OK(fmi2FreeFMUstate(c2, &restored));
            }
            five_steps(c2, 2.5, again);
            CHECK(memcmp(ref, again, sizeof ref) == 0);
            fmi2FreeInstance(c2);
        }
    }

    /* corrupt input is rejected */
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, size - 1, &state2));
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, 3, &state2));
    bytes[0] ^= 0x5a;
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, size, &state2));
    CHECK(logged(&lb, "magic", NULL));
    bytes[0] ^= 0x5a;
    bytes[4] ^= 0x01;
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, size, &state2));
    CHECK(logged(&lb, "version", NULL));
    bytes[4] ^= 0x01;
    bytes[8] ^= 0x01; /* nv */
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, size, &state2));
    CHECK(logged(&lb, "other sizes", NULL));
    bytes[8] ^= 0x01;
    bytes[8 + 10 * 4 + 5] ^= 0x01; /* a character of the GUID */
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, size, &state2));
    CHECK(logged(&lb, "another FMU", NULL));
    bytes[8 + 10 * 4 + 5] ^= 0x01;
    CHECK(state2 == NULL);
    CHECK_ERR(fmi2SetFMUstate(c, NULL));
    CHECK_ERR(fmi2SetFMUstate(c, (fmi2FMUstate)bytes));

    /* a CoSimulation state does not fit a ModelExchange instance */
    me = start(fmi2ModelExchange, &cb, 0.0);
    CHECK_ERR(fmi2DeSerializeFMUstate(me, bytes, size, &state2));
    CHECK_ERR(fmi2SetFMUstate(me, state3));
    fmi2FreeInstance(me);

    /* a state from initialization mode brings the instance back there */
    fmi2FreeFMUstate(c, &state);
    CHECK_OK(fmi2Reset(c));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_OK(set(c, VR_K, 9.0));
    CHECK_OK(fmi2GetFMUstate(c, &state));
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_OK(fmi2DoStep(c, 0.0, 1.0, fmi2True));
    CHECK_OK(fmi2SetFMUstate(c, state));
    CHECK_OK(set(c, VR_K, 16.0)); /* allowed again */
    CHECK_NEAR(get(c, VR_W), 8.0, 0.0);

    /* restoring recovers from the error state */
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_OK(fmi2GetFMUstate(c, &state));
    CHECK_OK(set(c, VR_U, 2e6));
    CHECK_ERR(fmi2DoStep(c, 0.0, 1.0, fmi2True));
    CHECK_OK(fmi2SetFMUstate(c, state));
    CHECK_OK(fmi2DoStep(c, 0.0, 1.0, fmi2True));

    CHECK_OK(fmi2FreeFMUstate(c, &state));
    CHECK_OK(fmi2FreeFMUstate(c, &state3));
    CHECK_OK(fmi2FreeFMUstate(c, &state3)); /* NULL: nothing to do */
    free(bytes);
    fmi2FreeInstance(c);
}

/* Compares fmi2GetDirectionalDerivative with central differences of the model's eval. */
static void check_jacobian(fmi2Component c, const char *where)
{
    const fmi2ValueReference known[5] = { VR_S, VR_V, VR_W, VR_U, VR_K };
    const fmi2ValueReference unknown[5] = { VR_DS, VR_DV, VR_DW, VR_F, VR_E };
    double x[3], u, p[4], t = 0.0, worst = 0.0, dir[5] = { 0.3, -1.1, 0.7, 2.0, -0.4 };
    double dv[5], fd[5];
    const fmi2ValueReference vp[4] = { VR_K, VR_N, VR_B, VR_H };
    fmi2Integer n;
    fmi2Boolean b;
    int j, m;

    fmi2GetReal(c, known, 3, x);
    u = get(c, VR_U);
    p[0] = get(c, VR_K);
    fmi2GetInteger(c, &vp[1], 1, &n);
    fmi2GetBoolean(c, &vp[2], 1, &b);
    p[1] = n;
    p[2] = b;
    p[3] = get(c, VR_H);

    for (m = 0; m < 6; m++) { /* unit directions, then one mixed direction */
        double seed[5] = { 0, 0, 0, 0, 0 }, xp[3], xm[3], up, um, pp[4], pm[4];
        double fp[3], fm[3], zp[2], zm[2];
        const double eps = 1e-6;
        if (m < 5) seed[m] = 1.0;
        else memcpy(seed, dir, sizeof seed);
        CHECK_OK(fmi2GetDirectionalDerivative(c, unknown, 5, known, 5, seed, dv));
        for (j = 0; j < 3; j++) { xp[j] = x[j] + eps * seed[j]; xm[j] = x[j] - eps * seed[j]; }
        up = u + eps * seed[3];
        um = u - eps * seed[3];
        memcpy(pp, p, sizeof p);
        memcpy(pm, p, sizeof p);
        pp[0] += eps * seed[4];
        pm[0] -= eps * seed[4];
        COSIM_MODEL.eval(t, xp, &up, pp, fp, zp);
        COSIM_MODEL.eval(t, xm, &um, pm, fm, zm);
        for (j = 0; j < 3; j++) fd[j] = (fp[j] - fm[j]) / (2 * eps);
        for (j = 0; j < 2; j++) fd[3 + j] = (zp[j] - zm[j]) / (2 * eps);
        for (j = 0; j < 5; j++) worst = fmax(worst, fabs(dv[j] - fd[j]) / fmax(1.0, fabs(fd[j])));
    }
    printf("  directional derivatives (%s): max deviation from finite differences %.2g\n", where, worst);
    CHECK(worst < 1e-7);
}

static void test_directional_derivatives(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start_init(fmi2CoSimulation, &cb, 1e-8), me;
    fmi2ValueReference vk = VR_S, vu = VR_DS;
    double one = 1.0, out;

    set(c, VR_V, 0.7);
    check_jacobian(c, "CS initializationMode");
    fmi2ExitInitializationMode(c);
    fmi2DoStep(c, 0.0, 1.3, fmi2True);
    check_jacobian(c, "CS stepComplete");

    /* only states, inputs and Real parameters are knowns; only derivatives and algebraics unknowns */
    vk = VR_DS;
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    CHECK(logged(&lb, "value reference 3", "known"));
    vk = VR_OMEGA;
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    vk = VR_N;
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    vk = VR_S;
    vu = VR_S;  /* a state as an unknown (an output that is a state): d s / d s = 1 */
    CHECK_OK(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    CHECK_NEAR(out, 1.0, 0.0);
    vk = VR_V;
    CHECK_OK(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    CHECK_NEAR(out, 0.0, 0.0);
    vk = VR_S;
    vu = VR_OMEGA;
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    vu = NV;
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    vu = VR_DV;
    CHECK_OK(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    CHECK_NEAR(out, -4.0, 0.0);
    fmi2FreeInstance(c);

    me = start(fmi2ModelExchange, &cb, 0.0);
    check_jacobian(me, "ME eventMode");
    fmi2EnterContinuousTimeMode(me);
    {
        const double x[3] = { 0.3, -0.2, 1.5 };
        fmi2SetContinuousStates(me, x, 3);
        fmi2SetTime(me, 0.5);
    }
    check_jacobian(me, "ME continuousTimeMode");
    fmi2FreeInstance(me);

    c = fmi2Instantiate("dd", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    CHECK_ERR(fmi2GetDirectionalDerivative(c, &vu, 1, &vk, 1, &one, &out));
    CHECK(logged(&lb, "fmi2GetDirectionalDerivative", "instantiated"));
    fmi2FreeInstance(c);
}

static void test_model_exchange(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start_init(fmi2ModelExchange, &cb, 0.0);
    fmi2EventInfo info;
    fmi2Boolean enter, term;
    double x[3], dx[3], k1[3], k2[3], k3[3], k4[3], xt[3], nom[3], t = 0.0, s, v;
    const double h = 1e-3;
    fmi2ValueReference vr = VR_N;
    fmi2Integer iv = 2;
    int i, j;

    CHECK_OK(fmi2GetContinuousStates(c, x, 3));
    CHECK(x[0] == 1.0 && x[1] == 0.0 && x[2] == 2.0); /* w(0) = k / 2 */
    CHECK_ERR(fmi2GetContinuousStates(c, x, 2));
    CHECK(logged(&lb, "nx = 2", NULL));
    CHECK_ERR(fmi2SetContinuousStates(c, x, 3)); /* not in initializationMode */
    CHECK_ERR(fmi2DoStep(c, 0.0, 0.1, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "ModelExchange"));
    CHECK_OK(fmi2ExitInitializationMode(c));

    CHECK_OK(fmi2NewDiscreteStates(c, &info));
    CHECK(!info.newDiscreteStatesNeeded && !info.terminateSimulation && !info.nominalsOfContinuousStatesChanged &&
          !info.valuesOfContinuousStatesChanged && !info.nextEventTimeDefined);
    CHECK_OK(fmi2SetInteger(c, &vr, 0, &iv)); /* discrete variables may be set in event mode */
    CHECK_ERR(fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term));
    CHECK_OK(fmi2EnterContinuousTimeMode(c));
    CHECK_ERR(fmi2NewDiscreteStates(c, &info));
    CHECK_ERR(fmi2EnterContinuousTimeMode(c));

    CHECK_OK(fmi2GetNominalsOfContinuousStates(c, nom, 3));
    CHECK(nom[0] == 1.0 && nom[1] == 1.0 && nom[2] == 1.0);
    CHECK_OK(fmi2GetEventIndicators(c, NULL, 0));
    CHECK_ERR(fmi2GetEventIndicators(c, x, 1));
    CHECK_ERR(fmi2GetDerivatives(c, dx, 4));
    CHECK_ERR(set(c, VR_S, 1.0));
    CHECK(logged(&lb, "fmi2SetContinuousStates", NULL));
    CHECK_ERR(set(c, VR_K, 1.0));
    CHECK_ERR(fmi2SetInteger(c, &vr, 1, &iv)); /* no discrete changes in continuous-time mode */
    CHECK_OK(set(c, VR_U, 0.5));

    /* classical Runge-Kutta through the ME interface */
    CHECK_OK(fmi2GetContinuousStates(c, x, 3));
    for (i = 0; i < 1000; i++) {
        fmi2SetTime(c, t);
        fmi2SetContinuousStates(c, x, 3);
        fmi2GetDerivatives(c, k1, 3);
        for (j = 0; j < 3; j++) xt[j] = x[j] + 0.5 * h * k1[j];
        fmi2SetTime(c, t + 0.5 * h);
        fmi2SetContinuousStates(c, xt, 3);
        fmi2GetDerivatives(c, k2, 3);
        for (j = 0; j < 3; j++) xt[j] = x[j] + 0.5 * h * k2[j];
        fmi2SetContinuousStates(c, xt, 3);
        fmi2GetDerivatives(c, k3, 3);
        for (j = 0; j < 3; j++) xt[j] = x[j] + h * k3[j];
        fmi2SetTime(c, t + h);
        fmi2SetContinuousStates(c, xt, 3);
        fmi2GetDerivatives(c, k4, 3);
        for (j = 0; j < 3; j++) x[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        t = (i + 1) * h;
        fmi2SetTime(c, t);
        fmi2SetContinuousStates(c, x, 3);
        CHECK_OK(fmi2CompletedIntegratorStep(c, fmi2True, &enter, &term));
    }
    CHECK(!enter && !term);
    exact_sv(1.0, 4.0, 0.2, 0.5, 0.0, 1.0, 0.0, &s, &v);
    CHECK_NEAR(get(c, VR_S), s, 1e-10);
    CHECK_NEAR(get(c, VR_V), v, 1e-10);
    CHECK_NEAR(get(c, VR_W), 2.0 * exp(-1.0), 1e-10);
    CHECK(get(c, VR_F) == 4.0 * x[0] + 0.5);
    CHECK_OK(fmi2GetDerivatives(c, dx, 3));
    CHECK(dx[0] == x[1]);

    CHECK_OK(fmi2EnterEventMode(c));
    CHECK_OK(fmi2EnterEventMode(c));
    CHECK_OK(fmi2NewDiscreteStates(c, &info));
    CHECK_OK(fmi2EnterContinuousTimeMode(c));
    CHECK_OK(fmi2Terminate(c));
    CHECK_OK(fmi2GetDerivatives(c, dx, 3));
    CHECK_ERR(fmi2SetTime(c, 2.0));
    CHECK_ERR(fmi2EnterEventMode(c));
    fmi2FreeInstance(c);
}

static void test_logging(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = fmi2Instantiate("log", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2True);
    const char *calls[1] = { "logCalls" }, *bad[1] = { "50%#x" }, *errors[1] = { "logStatusError" };
    int n;

    CHECK(logged(&lb, "fmi2Instantiate", NULL)); /* loggingOn = true logs calls */
    CHECK(strcmp(lb.last_category, "logCalls") == 0 && lb.last_status == fmi2OK);
    CHECK_OK(fmi2SetDebugLogging(c, fmi2False, 0, NULL));
    n = lb.n_messages;
    CHECK_ERR(fmi2Terminate(c));
    CHECK(lb.n_messages == n); /* everything off */
    CHECK_OK(fmi2SetDebugLogging(c, fmi2True, 1, calls));
    CHECK_OK(fmi2SetupExperiment(c, fmi2True, 1e-7, 0.5, fmi2False, 0.0));
    CHECK(logged(&lb, "fmi2SetupExperiment(", "startTime = 0.5"));
    n = lb.n_messages;
    CHECK_ERR(fmi2Terminate(c));
    CHECK(lb.n_messages == n + 1); /* only the call, not the error */
    CHECK_ERR(fmi2SetDebugLogging(c, fmi2True, 1, bad));
    CHECK_OK(fmi2SetDebugLogging(c, fmi2True, 0, NULL));
    CHECK_ERR(fmi2SetDebugLogging(c, fmi2True, 1, bad));
    CHECK(logged(&lb, "unknown log category '50%##x'", NULL)); /* '%' and '#' escaped */
    CHECK_ERR(fmi2SetDebugLogging(c, fmi2True, 1, NULL));
    CHECK_OK(fmi2SetDebugLogging(c, fmi2True, 1, errors));
    n = lb.n_messages;
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK(lb.n_messages == n);
    CHECK_ERR(fmi2Terminate(c));
    CHECK(lb.n_messages == n + 1 && lb.last_status == fmi2Error);
    fmi2FreeInstance(c);
}

static void test_instances(void)
{
    logbook lb1, lb2;
    fmi2CallbackFunctions cb1 = callbacks(&lb1), cb2 = callbacks(&lb2);
    fmi2Component a = start_init(fmi2CoSimulation, &cb1, 1e-10);
    fmi2Component b = start_init(fmi2CoSimulation, &cb2, 1e-10);
    double s, v;
    int i;

    set(b, VR_K, 9.0);
    fmi2ExitInitializationMode(a);
    fmi2ExitInitializationMode(b);
    for (i = 0; i < 20; i++) {
        fmi2DoStep(a, 0.1 * i, 0.1, fmi2True);
        fmi2DoStep(b, 0.1 * i, 0.1, fmi2True);
    }
    exact_sv(2.0, 4.0, 0.2, 0.5, 0.0, 1.0, 0.0, &s, &v);
    CHECK_NEAR(get(a, VR_S), s, 1e-9);
    exact_sv(2.0, 9.0, 0.2, 0.5, 0.0, 1.0, 0.0, &s, &v);
    CHECK_NEAR(get(b, VR_S), s, 1e-9);
    CHECK_NEAR(get(b, VR_W), 4.5 * exp(-2.0), 1e-9);
    CHECK_ERR(fmi2Terminate(NULL));
    CHECK_ERR(set(a, VR_K, 1.0));
    CHECK(logged(&lb1, "fmi2SetReal", NULL) && lb2.n_messages == 0); /* each instance its own logger */
    fmi2FreeInstance(a);
    fmi2FreeInstance(b);
}

/* ------------------------------------------------------------------------------------------ */
/* Another FMU in the same process: a shared library built by run.sh                            */

typedef struct {
    void *lib;
    const char *guid;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup_experiment;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2DoStepTYPE *do_step;
    fmi2GetFMUstateTYPE *get_state;
    fmi2SetFMUstateTYPE *set_state;
    fmi2FreeFMUstateTYPE *free_state;
    fmi2SerializedFMUstateSizeTYPE *serialized_size;
    fmi2SerializeFMUstateTYPE *serialize;
    fmi2DeSerializeFMUstateTYPE *deserialize;
    fmi2GetRealTYPE *get_real;
    fmi2SetRealTYPE *set_real;
} other_fmu;

static int load_other(other_fmu *o, const char *path, const char *guid)
{
    memset(o, 0, sizeof *o);
    o->guid = guid;
    o->lib = path ? dlopen(path, RTLD_NOW | RTLD_LOCAL) : NULL;
    if (!o->lib) {
        printf("    cannot load the other FMU %s: %s\n", path ? path : "(not given)", path ? dlerror() : "");
        return 0;
    }
    return SYMBOL(o, instantiate, "fmi2Instantiate") && SYMBOL(o, free_instance, "fmi2FreeInstance") &&
           SYMBOL(o, setup_experiment, "fmi2SetupExperiment") &&
           SYMBOL(o, enter_init, "fmi2EnterInitializationMode") &&
           SYMBOL(o, exit_init, "fmi2ExitInitializationMode") && SYMBOL(o, do_step, "fmi2DoStep") &&
           SYMBOL(o, get_state, "fmi2GetFMUstate") && SYMBOL(o, set_state, "fmi2SetFMUstate") &&
           SYMBOL(o, free_state, "fmi2FreeFMUstate") &&
           SYMBOL(o, serialized_size, "fmi2SerializedFMUstateSize") &&
           SYMBOL(o, serialize, "fmi2SerializeFMUstate") && SYMBOL(o, deserialize, "fmi2DeSerializeFMUstate") &&
           SYMBOL(o, get_real, "fmi2GetReal") && SYMBOL(o, set_real, "fmi2SetReal");
}

static const char *other_paths[4];

/* ------------------------------------------------------------------------------------------ */
/* Defect tests: foreign FMU states, refused calls                                             */

/* One foreign FMU: its FMU states are refused by this model's instances and the other way round,
   in memory and serialized, and nothing of either instance changes. */
static void foreign_state_case(const char *path, const char *guid, const char *why)
{
    logbook lb, lbo;
    fmi2CallbackFunctions cb = callbacks(&lb), cbo = callbacks(&lbo);
    other_fmu o;
    fmi2Component c, oc;
    fmi2FMUstate mine = NULL, theirs = NULL, kept, restored = NULL;
    size_t n = 0, n_mine = 0;
    char *bytes, *bytes_mine;
    double s;

    printf("  foreign FMU state from %s (%s)\n", path ? path : "(missing)", why);
    CHECK(load_other(&o, path, guid));
    if (!o.lib) return;
    c = start(fmi2CoSimulation, &cb, 1e-8);
    oc = o.instantiate("other", fmi2CoSimulation, o.guid, "", &cbo, fmi2False, fmi2False);
    CHECK(oc != NULL);
    if (!oc) { fmi2FreeInstance(c); dlclose(o.lib); return; }
    CHECK_OK(o.setup_experiment(oc, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_OK(o.enter_init(oc));
    CHECK_OK(o.exit_init(oc));
    CHECK_OK(o.do_step(oc, 0.0, 0.5, fmi2True));
    CHECK_OK(o.get_state(oc, &theirs));
    CHECK_OK(fmi2DoStep(c, 0.0, 0.5, fmi2True));
    CHECK_OK(fmi2GetFMUstate(c, &mine));
    s = get(c, VR_S);

    /* in memory: refused before anything is read beyond the identity */
    CHECK_ERR(fmi2SetFMUstate(c, theirs));
    CHECK(logged(&lb, "fmi2SetFMUstate", why));
    CHECK_ERR(o.set_state(oc, mine));
    CHECK(logged(&lbo, "fmi2SetFMUstate", why));
    kept = theirs;
    CHECK_ERR(fmi2GetFMUstate(c, &theirs)); /* would overwrite the other FMU's state */
    CHECK(theirs == kept);
    CHECK_ERR(fmi2FreeFMUstate(c, &theirs)); /* would free it with the wrong allocator */
    CHECK(theirs == kept);
    CHECK_ERR(fmi2SerializedFMUstateSize(c, theirs, &n));
    CHECK_ERR(fmi2SerializeFMUstate(c, theirs, (fmi2Byte *)&n, sizeof n));

    /* serialized: lengths and identity are checked before anything is copied */
    CHECK_OK(o.serialized_size(oc, theirs, &n));
    bytes = (char *)malloc(n);
    CHECK_OK(o.serialize(oc, theirs, bytes, n));
    CHECK_ERR(fmi2DeSerializeFMUstate(c, bytes, n, &restored));
    CHECK(logged(&lb, "fmi2DeSerializeFMUstate", why));
    CHECK(restored == NULL);
    CHECK_OK(fmi2SerializedFMUstateSize(c, mine, &n_mine));
    bytes_mine = (char *)malloc(n_mine);
    CHECK_OK(fmi2SerializeFMUstate(c, mine, bytes_mine, n_mine));
    CHECK_ERR(o.deserialize(oc, bytes_mine, n_mine, &restored));
    CHECK(restored == NULL);

    /* neither instance was harmed */
    CHECK(get(c, VR_S) == s);
    CHECK_OK(fmi2DoStep(c, 0.5, 0.5, fmi2True));
    CHECK_OK(fmi2SetFMUstate(c, mine));
    CHECK(get(c, VR_S) == s);
    CHECK_OK(o.do_step(oc, 0.5, 0.5, fmi2True));
    CHECK_OK(o.set_state(oc, theirs));

    free(bytes);
    free(bytes_mine);
    CHECK_OK(fmi2FreeFMUstate(c, &mine));
    CHECK_OK(o.free_state(oc, &theirs));
    o.free_instance(oc);
    fmi2FreeInstance(c);
    dlclose(o.lib);
}

static void test_fmu_state_of_another_fmu_is_refused(void)
{
    foreign_state_case(other_paths[0], SMALL_GUID, "another FMU");
    foreign_state_case(other_paths[1], GUID, "sizes");        /* same GUID, other sizes */
    foreign_state_case(other_paths[2], TWIN_GUID, "another FMU"); /* same sizes, other GUID */
}

/* ------------------------------------------------------------------------------------------ */
/* Initial equations: test_model_init.c, theta solved from L sin(theta) = h + u + omega  */

/* its value references start at 1 (first_vr): 0 and 10 are none */
enum { I_NONE, I_THETA, I_OMEGA, I_DTHETA, I_DOMEGA, I_U, I_L, I_H, I_STEP, I_Y, I_PAST };

static double other_get(const other_fmu *o, fmi2Component c, fmi2ValueReference vr)
{
    double v = NAN;
    if (o->get_real(c, &vr, 1, &v) != fmi2OK) return NAN;
    return v;
}

static fmi2Status other_set(const other_fmu *o, fmi2Component c, fmi2ValueReference vr, double v)
{
    return o->set_real(c, &vr, 1, &v);
}

static void test_initial_equations(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    other_fmu o;
    fmi2Component c;
    const char *guid = "{0b7a1c55-2f0e-4c8e-9d3b-6a1e5f4c3b20}";

    printf("  initial equations (%s)\n", other_paths[3] ? other_paths[3] : "(missing)");
    CHECK(load_other(&o, other_paths[3], guid));
    if (!o.lib) return;
    c = o.instantiate("init", fmi2CoSimulation, guid, "", &cb, fmi2False, fmi2False);
    CHECK(c != NULL);
    if (!c) { dlclose(o.lib); return; }
    CHECK(!logged(&lb, "vr_fixed_step", NULL)); /* value reference 8 is solver.fixedStepSize */

    /* solved with the default parameters: sin(theta) = (0.5 + 0 + 0.5) / 2 */
    CHECK_OK(o.setup_experiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_OK(o.enter_init(c));
    CHECK_NEAR(other_get(&o, c, I_THETA), asin(0.5), 1e-14);
    /* parameters, inputs and fixed states set in initializationMode are used: solved again */
    CHECK_OK(other_set(&o, c, I_H, 0.7));
    CHECK_NEAR(other_get(&o, c, I_THETA), asin(0.6), 1e-14);
    CHECK_OK(other_set(&o, c, I_U, 0.2));
    CHECK_OK(other_set(&o, c, I_OMEGA, 0.1));
    CHECK_OK(o.exit_init(c));
    CHECK_NEAR(other_get(&o, c, I_THETA), asin(0.5), 1e-14);
    CHECK_NEAR(other_get(&o, c, I_OMEGA), 0.1, 0.0);
    CHECK_NEAR(other_get(&o, c, I_Y), 1.0, 1e-14);
    /* value references start at 1: 0 and the one after the last are none, and refused */
    CHECK(isnan(other_get(&o, c, I_NONE)));
    CHECK(logged(&lb, "fmi2GetReal: value reference 0 is out of range", "value references 1 to 9)"));
    CHECK(isnan(other_get(&o, c, I_PAST)));
    CHECK(logged(&lb, "fmi2GetReal: value reference 10 is out of range", "value references 1 to 9)"));
    CHECK(other_set(&o, c, I_NONE, 1.0) == fmi2Error);
    CHECK(logged(&lb, "fmi2SetReal: value reference 0 is out of range", NULL));
    CHECK_OK(o.do_step(c, 0.0, 0.1, fmi2True));
    o.free_instance(c);

    /* a guess set before initialization selects the other root; it is replaced by the solution */
    c = o.instantiate("init", fmi2CoSimulation, guid, "", &cb, fmi2False, fmi2False);
    CHECK_OK(o.setup_experiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_OK(other_set(&o, c, I_THETA, 2.5));
    CHECK_OK(o.enter_init(c));
    CHECK_OK(o.exit_init(c));
    CHECK_NEAR(other_get(&o, c, I_THETA), 4.0 * atan(1.0) - asin(0.5), 1e-14);
    o.free_instance(c);

    /* no real solution: fmi2ExitInitializationMode fails, naming the unknown and the residual;
       fmi2EnterInitializationMode does not solve yet (a parameter may still be changed) */
    c = o.instantiate("init", fmi2CoSimulation, guid, "", &cb, fmi2False, fmi2False);
    CHECK_OK(o.setup_experiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_OK(other_set(&o, c, I_H, 3.0));
    CHECK_OK(o.enter_init(c));
    CHECK_ERR(o.exit_init(c));
    CHECK(logged(&lb, "fmi2ExitInitializationMode: initialization failed: the initial equations for theta "
                      "did not converge", "|residual| = "));
    CHECK(lb.last_status == fmi2Error);
    CHECK_ERR(o.do_step(c, 0.0, 0.1, fmi2True)); /* the error state */
    o.free_instance(c);
    c = o.instantiate("init", fmi2CoSimulation, guid, "", &cb, fmi2False, fmi2False);
    CHECK_OK(o.setup_experiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK_OK(other_set(&o, c, I_H, 3.0));
    CHECK_OK(o.enter_init(c));
    CHECK_OK(other_set(&o, c, I_H, -0.5));
    CHECK_OK(o.exit_init(c));
    CHECK_NEAR(other_get(&o, c, I_THETA), 0.0, 1e-14);
    o.free_instance(c);
    dlclose(o.lib);
}

static void test_input_derivative_does_not_overwrite_input(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start(fmi2CoSimulation, &cb, 1e-10);
    const fmi2ValueReference vu = VR_U;
    const fmi2Integer order = 1;
    const double r = 1.0;
    double s;

    CHECK_OK(set(c, VR_U, 1.0));
    CHECK_OK(fmi2SetRealInputDerivatives(c, &vu, 1, &order, &r));
    CHECK_OK(fmi2DoStep(c, 0.0, 0.1, fmi2True));
    CHECK(get(c, VR_U) == 1.0); /* as the environment set it */
    /* the model saw the input extrapolated to the end of the step, u(0.1) = 1 + 0.1 r */
    s = get(c, VR_S);
    CHECK_NEAR(get(c, VR_F), 4.0 * s + 1.1, 1e-15);
    /* the derivative applies to one step; without new inputs the end value is held */
    CHECK_OK(fmi2DoStep(c, 0.1, 0.1, fmi2True));
    CHECK(get(c, VR_U) == 1.0);
    s = get(c, VR_S);
    CHECK_NEAR(get(c, VR_F), 4.0 * s + 1.1, 1e-15);
    /* setting the input again, even to the value it reads, ends the extrapolation */
    CHECK_OK(set(c, VR_U, 1.0));
    CHECK(get(c, VR_F) == 4.0 * s + 1.0);
    CHECK(get(c, VR_U) == 1.0);
    fmi2FreeInstance(c);
}

static void test_zero_step_and_step_past_stop_time_are_refused(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = fmi2Instantiate("stop", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    double t, s;
    int i;

    /* an undefined stop time is ignored; a defined one must be a time not before the start */
    CHECK_ERR(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, -1.0));
    CHECK(logged(&lb, "stopTime = -1", "startTime = 0"));
    CHECK_ERR(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, NAN));
    CHECK_OK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, NAN));
    CHECK_OK(fmi2Reset(c));
    CHECK_OK(fmi2SetupExperiment(c, fmi2True, 1e-8, 0.0, fmi2True, 1.0));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_OK(fmi2ExitInitializationMode(c));

    /* h = 0 is an event iteration in FMI 2.0, which the runtime does not support; h < 0 is wrong */
    CHECK_ERR(fmi2DoStep(c, 0.0, 0.0, fmi2True));
    CHECK(logged(&lb, "communicationStepSize = 0", "event iteration"));
    CHECK_ERR(fmi2DoStep(c, 0.0, -0.1, fmi2True));
    CHECK(logged(&lb, "communicationStepSize = -0.1", "> 0"));
    CHECK_ERR(fmi2DoStep(c, 0.0, -0.0, fmi2True));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK(t == 0.0 && get(c, VR_S) == 1.0); /* nothing happened */

    for (i = 0; i < 3; i++) CHECK_OK(fmi2DoStep(c, 0.3 * i, 0.3, fmi2True));
    s = get(c, VR_S);
    CHECK_ERR(fmi2DoStep(c, 0.9, 0.3, fmi2True)); /* would end at 1.2 */
    CHECK(logged(&lb, "ends at t = 1.2", "stopTime = 1"));
    CHECK(get(c, VR_S) == s);
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK_NEAR(t, 0.9, 1e-15);
    CHECK_OK(fmi2DoStep(c, t, 1.0 - t, fmi2True)); /* the last, shorter step lands on stopTime */
    CHECK_ERR(fmi2DoStep(c, 1.0, 1e-9, fmi2True));
    CHECK(logged(&lb, "stopTime", NULL));
    fmi2FreeInstance(c);

    /* a master adding up its time overshoots stopTime by rounding only: accepted */
    c = fmi2Instantiate("stop", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    CHECK_OK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, 0.3));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_OK(fmi2ExitInitializationMode(c));
    for (i = 0, t = 0.0; i < 3; i++, t += 0.1) CHECK_OK(fmi2DoStep(c, t, 0.1, fmi2True));
    CHECK(t > 0.3); /* 0.30000000000000004 */
    fmi2FreeInstance(c);

    /* ... but not by more */
    c = fmi2Instantiate("stop", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    CHECK_OK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, 0.3));
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK_OK(fmi2ExitInitializationMode(c));
    CHECK_OK(fmi2DoStep(c, 0.0, 0.2, fmi2True));
    CHECK_ERR(fmi2DoStep(c, 0.2, 0.1 + 1e-12, fmi2True));
    fmi2FreeInstance(c);
}

/* The escape time of w' = w^2 from w(t0) = w0. */
static double escape_time(double t0, double w0) { return t0 + 1.0 / w0; }

static void test_integration_failure_is_discard_with_last_successful_time(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = start(fmi2CoSimulation, &cb, 1e-8);
    fmi2FMUstate before = NULL, failed = NULL;
    fmi2Status st = fmi2OK;
    fmi2Boolean terminated = fmi2False;
    double t, t_esc, s0, v0, s, v, w, x;

    /* adaptive steps: w' = w^2 escapes at t_esc inside the step; the step size underflows there */
    CHECK_OK(fmi2DoStep(c, 0.0, 0.5, fmi2True));
    s0 = get(c, VR_S);
    v0 = get(c, VR_V);
    t_esc = escape_time(0.5, get(c, VR_W));
    CHECK_OK(fmi2GetFMUstate(c, &before));
    CHECK_OK(set(c, VR_U, 1001.0));
    CHECK_DISCARD(fmi2DoStep(c, 0.5, 1.0, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "last successful time"));
    CHECK(lb.last_status == fmi2Discard);
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    printf("  escape at t = %.15g, Discard with last successful time %.15g\n", t_esc, t);
    CHECK(t > 0.5 && fabs(t - t_esc) < 1e-6); /* the numerical escape time is off by ~ the tolerance */
    /* the state and the outputs are those at the last successful time */
    w = get(c, VR_W);
    CHECK(isfinite(w) && w > 1e5);
    CHECK(get(c, VR_DW) == w * w);
    exact_sv(t - 0.5, 4.0, 0.2, 1001.0, 0.0, s0, v0, &s, &v);
    CHECK_NEAR(get(c, VR_S), s, 1e-6 * fabs(s));
    CHECK_NEAR(get(c, VR_V), v, 1e-6 * fabs(v));
    CHECK(get(c, VR_F) == 4.0 * get(c, VR_S) + 1001.0);
    CHECK(get(c, VR_U) == 1001.0);
    /* FMI 2.0 status functions after fmi2Discard */
    CHECK_OK(fmi2GetBooleanStatus(c, fmi2Terminated, &terminated));
    CHECK(terminated == fmi2True); /* the slave cannot continue past t */
    CHECK_OK(fmi2GetStatus(c, fmi2DoStepStatus, &st));
    CHECK(st == fmi2Discard);
    /* stepFailed: no more steps and no inputs; FMU states, termination, reset are possible */
    CHECK_ERR(fmi2DoStep(c, t, 0.1, fmi2True));
    CHECK(logged(&lb, "fmi2DoStep", "stepFailed"));
    CHECK_ERR(set(c, VR_U, 0.0));
    CHECK_OK(fmi2GetFMUstate(c, &failed));
    CHECK_OK(fmi2GetDirectionalDerivative(c, (const fmi2ValueReference[]){ VR_DW }, 1,
                                          (const fmi2ValueReference[]){ VR_W }, 1, (const double[]){ 1.0 }, &x));
    CHECK(x == 2.0 * w);
    /* redo from the state before the step (here: without the input that made it fail) */
    CHECK_OK(fmi2SetFMUstate(c, before));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK(t == 0.5);
    CHECK_OK(fmi2DoStep(c, 0.5, 0.5, fmi2True));
    CHECK_OK(fmi2GetStatus(c, fmi2DoStepStatus, &st));
    CHECK(st == fmi2OK);
    /* and terminate after the failure, as a master does in its clean-up */
    CHECK_OK(fmi2SetFMUstate(c, failed));
    CHECK_OK(fmi2Terminate(c));
    CHECK(get(c, VR_W) == w);
    CHECK_OK(fmi2FreeFMUstate(c, &before));
    CHECK_OK(fmi2FreeFMUstate(c, &failed));
    fmi2FreeInstance(c);

    /* fixed steps: the first non-finite state ends the step at the last finite one */
    c = start_init(fmi2CoSimulation, &cb, 1e-8);
    set(c, VR_H, 0.01);
    fmi2ExitInitializationMode(c);
    CHECK_OK(fmi2DoStep(c, 0.0, 0.5, fmi2True));
    CHECK_OK(set(c, VR_U, 1001.0));
    CHECK_DISCARD(fmi2DoStep(c, 0.5, 1.5, fmi2True));
    CHECK(logged(&lb, "non-finite", "last successful time"));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK(t > 1.0 && t < 2.0);
    CHECK_NEAR(t / 0.01, floor(t / 0.01 + 0.5), 1e-9); /* on the fixed grid */
    CHECK(isfinite(get(c, VR_W)) && isfinite(get(c, VR_DW)));
    CHECK_OK(fmi2Reset(c)); /* reset works after a failure, too */
    fmi2FreeInstance(c);

    /* too many steps: the step ends where the budget ran out */
    c = start_init(fmi2CoSimulation, &cb, 1e-8);
    set(c, VR_H, 1e-7);
    fmi2ExitInitializationMode(c);
    CHECK_DISCARD(fmi2DoStep(c, 0.0, 1.0, fmi2True));
    CHECK(logged(&lb, "more than 1000000 steps", "last successful time"));
    CHECK_OK(fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &t));
    CHECK_NEAR(t, 0.1, 1e-9);
    exact_sv(t, 4.0, 0.2, 0.5, 0.0, 1.0, 0.0, &s, &v);
    CHECK_NEAR(get(c, VR_S), s, 1e-8);
    CHECK_OK(fmi2Terminate(c));
    fmi2FreeInstance(c);
}

static void test_nonfinite_derivatives_are_reported(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component me = start(fmi2ModelExchange, &cb, 0.0), c;
    fmi2Boolean enter, term;
    double x[3] = { 1.0, 0.0, 1e200 }, dx[3], f;
    const fmi2ValueReference vf = VR_F;

    /* Model Exchange: fmi2Discard, so that the integrator can retry with a smaller step */
    CHECK_OK(fmi2EnterContinuousTimeMode(me));
    CHECK_OK(set(me, VR_U, 1001.0));
    CHECK_OK(fmi2SetContinuousStates(me, x, 3));
    CHECK_DISCARD(fmi2GetDerivatives(me, dx, 3));
    CHECK(logged(&lb, "der(w)", "inf"));
    CHECK(lb.last_status == fmi2Discard);
    CHECK_DISCARD(fmi2GetDerivatives(me, dx, 3)); /* not remembered as evaluated */
    CHECK_DISCARD(fmi2GetReal(me, &vf, 1, &f));   /* every getter that evaluates the model */
    x[2] = 1.0;
    CHECK_OK(fmi2SetContinuousStates(me, x, 3)); /* the instance is still usable */
    CHECK_OK(fmi2GetDerivatives(me, dx, 3));
    CHECK(dx[2] == 1.0);
    CHECK_OK(fmi2CompletedIntegratorStep(me, fmi2True, &enter, &term));
    /* a failing evaluation, too */
    CHECK_OK(set(me, VR_U, 2e6));
    CHECK_DISCARD(fmi2GetDerivatives(me, dx, 3));
    CHECK(logged(&lb, "evaluation failed", NULL));
    CHECK_OK(set(me, VR_U, 0.5));
    CHECK_OK(fmi2GetDerivatives(me, dx, 3));
    CHECK_OK(fmi2Terminate(me));
    fmi2FreeInstance(me);

    /* initialization mode: a start point with non-finite derivatives is an error */
    c = start_init(fmi2CoSimulation, &cb, 0.0);
    CHECK_OK(set(c, VR_W, 1e200));
    CHECK_OK(set(c, VR_U, 1001.0));
    CHECK_ERR(fmi2GetReal(c, &vf, 1, &f));
    CHECK(logged(&lb, "der(w)", "inf"));
    CHECK_ERR(fmi2ExitInitializationMode(c));
    fmi2FreeInstance(c);
}

static void test_nonfinite_real_is_refused(void)
{
    logbook lb;
    fmi2CallbackFunctions cb = callbacks(&lb);
    fmi2Component c = fmi2Instantiate("nan", fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False);
    const fmi2ValueReference vr[2] = { VR_S, VR_K };
    const double values[2] = { 3.0, NAN };

    CHECK_ERR(set(c, VR_K, NAN));
    CHECK(logged(&lb, "k (value reference 7)", "nan"));
    CHECK_ERR(set(c, VR_S, INFINITY));
    CHECK(logged(&lb, "s (value reference 0)", "inf"));
    CHECK_ERR(set(c, VR_U, -INFINITY));
    CHECK_ERR(fmi2SetReal(c, vr, 2, values)); /* nothing of a refused call is applied */
    CHECK_OK(fmi2EnterInitializationMode(c));
    CHECK(get(c, VR_K) == 4.0 && get(c, VR_S) == 1.0 && get(c, VR_U) == 0.5);
    CHECK_ERR(set(c, VR_H, NAN));
    fmi2FreeInstance(c);
}

int main(int argc, char **argv)
{
    int i;

    for (i = 0; i < 4; i++) other_paths[i] = i + 1 < argc ? argv[i + 1] : NULL;
    printf("FMI 2.0 runtime tests (cosim_runtime.c, fmi2_api.c)\n");
    test_basics();
    test_state_machine();
    test_get_set();
    test_calculated();
    test_cs_accuracy();
    test_cs_late_start();
    test_cs_outputs_and_inputs();
    test_cs_status();
    test_cs_failures();
    test_fmu_state();
    test_directional_derivatives();
    test_model_exchange();
    test_logging();
    test_instances();
    test_fmu_state_of_another_fmu_is_refused();
    test_input_derivative_does_not_overwrite_input();
    test_zero_step_and_step_past_stop_time_are_refused();
    test_integration_failure_is_discard_with_last_successful_time();
    test_nonfinite_derivatives_are_reported();
    test_nonfinite_real_is_refused();
    test_initial_equations();
    CHECK(n_live_allocations == 0); /* everything allocated through the callbacks was freed */
    printf("%d checks, %d failed\n", n_checks, n_failed);
    return n_failed == 0 ? 0 : 1;
}
