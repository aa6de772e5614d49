/*
 * harness3.c -- tests of the FMI 3.0 runtime (cosim_runtime.c with fmi3_api.c) against the
 * hand-written model in test_model.c, compiled with -DTEST_MODEL_ARRAYS (the states s, v, w are
 * the FMI 3 array x[3] at value reference 0, their derivatives one at value reference 3).
 *
 * The harness links both APIs on the one core (cosim_runtime.c, fmi2_api.c and fmi3_api.c), so
 * that FMI 3 results can be compared with FMI 2's bit for bit on the same model.
 *
 * Build (see run.sh):  cc -std=c99 -DTEST_MODEL_ARRAYS -I<fmi headers> -I.. harness3.c test_model.c
 *                         ../cosim_runtime.c ../fmi2_api.c ../fmi3_api.c -lm -ldl
 * Run:                 harness3 SMALL3.so TWIN3.so
 *   FMI 3 FMUs (the core and fmi3_api.c compiled with another model into a shared library, see
 *   run.sh): test_model_small.c (no vjp: no adjoint derivatives) and test_model.c with the GUID
 *   TWIN_GUID.  Their FMU states must be refused by this model.
 * Exit code 0 if every check passes.
 */
#define _POSIX_C_SOURCE 200809L /* dlopen under -std=c99 */
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"
#include "cosim_model.h"

#define GUID "{8c4e810f-3df3-4a00-8276-176fa3c9f000}"
#define SMALL_GUID "{5d1b2c3a-7f4e-4b21-9a63-0c2d7e8f1a42}" /* default of test_model_small.c */
#define TWIN_GUID "{8c4e810f-3df3-4a00-8276-176fa3c9f001}"  /* passed by run.sh */

/* Value references of test_model.c; VR_X is the array x = (s, v, w), VR_DX der(x). */
enum { VR_X = 0, VR_DX = 3, VR_U = 6, VR_K, VR_N, VR_B, VR_H, VR_OMEGA, VR_N10, VR_F, VR_E, VR_TIME };
#define NV 15

/* ------------------------------------------------------------------------------------------ */
/* Checks                                                                                       */

#include "check.h"

#define CHECK_OK(call) check((call) == fmi3OK, #call " == fmi3OK", __FILE__, __LINE__)
#define CHECK_ERR(call) check((call) == fmi3Error, #call " == fmi3Error", __FILE__, __LINE__)

/* ------------------------------------------------------------------------------------------ */
/* Logging: the last message of an instance                                                     */

typedef struct {
    char last[2048];
    char last_category[64];
    fmi3Status last_status;
    int n_messages;
} logbook;

static void log_message(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    logbook *lb = (logbook *)env;
    snprintf(lb->last, sizeof lb->last, "%s", message); /* a plain string in FMI 3 */
    snprintf(lb->last_category, sizeof lb->last_category, "%s", category);
    lb->last_status = status;
    lb->n_messages++;
}

/* Did the last message contain both fragments (b may be NULL)? */
static int logged(const logbook *lb, const char *a, const char *b)
{
    int ok = strstr(lb->last, a) != NULL && (!b || strstr(lb->last, b) != NULL);
    if (!ok) printf("    last message: %s\n", lb->last);
    return ok;
}

/* FMI 2 callbacks for the comparison instances (messages are not checked there). */
static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                    fmi2String message, ...)
{
    (void)env;
    (void)name;
    (void)status;
    (void)category;
    (void)message;
}

static const fmi2CallbackFunctions CB2 = { logger2, calloc, free, NULL, NULL };

/* ------------------------------------------------------------------------------------------ */
/* Helpers                                                                                      */

static fmi3Instance cs(logbook *lb, fmi3Boolean event_mode)
{
    memset(lb, 0, sizeof *lb);
    return fmi3InstantiateCoSimulation("cs3", GUID, "", false, false, event_mode, false, NULL, 0, lb, log_message,
                                       NULL);
}

static fmi3Instance me(logbook *lb)
{
    memset(lb, 0, sizeof *lb);
    return fmi3InstantiateModelExchange("me3", GUID, "", false, false, lb, log_message);
}

/* An instance through initialization (tolerance tol, start time 0, no stop time). */
static fmi3Instance started(fmi3Instance c, double tol)
{
    if (!c) return NULL;
    fmi3EnterInitializationMode(c, true, tol, 0.0, false, 0.0);
    fmi3ExitInitializationMode(c);
    return c;
}

static double get3(fmi3Instance c, fmi3ValueReference vr)
{
    double v = NAN;
    if (fmi3GetFloat64(c, &vr, 1, &v, 1) != fmi3OK) printf("    (fmi3GetFloat64(%u) failed)\n", vr);
    return v;
}

static fmi3Status set3(fmi3Instance c, fmi3ValueReference vr, double v)
{
    return fmi3SetFloat64(c, &vr, 1, &v, 1);
}

/* All values of the model through FMI 3 (x and der(x) as arrays), in value reference order. */
static fmi3Status all3(fmi3Instance c, double out[NV])
{
    static const fmi3ValueReference vrs[] = { VR_X, VR_DX, VR_U, VR_K, VR_H, VR_OMEGA, VR_F, VR_E };
    double v[12];
    fmi3Status st = fmi3GetFloat64(c, vrs, 8, v, 12);
    memcpy(out, v, 7 * sizeof(double));  /* x, der(x), u */
    out[VR_K] = v[7];
    out[VR_N] = out[VR_B] = out[VR_N10] = 0.0; /* discrete: compared separately */
    out[VR_H] = v[8];
    out[VR_OMEGA] = v[9];
    out[VR_F] = v[10];
    out[VR_E] = v[11];
    return st;
}

static fmi2Status all2(fmi2Component c, double out[NV])
{
    static const fmi2ValueReference vrs[] = { 0, 1, 2, 3, 4, 5, VR_U, VR_K, VR_H, VR_OMEGA, VR_F, VR_E };
    double v[12];
    fmi2Status st = fmi2GetReal(c, vrs, 12, v);
    memcpy(out, v, 7 * sizeof(double));
    out[VR_K] = v[7];
    out[VR_N] = out[VR_B] = out[VR_N10] = 0.0;
    out[VR_H] = v[8];
    out[VR_OMEGA] = v[9];
    out[VR_F] = v[10];
    out[VR_E] = v[11];
    return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Other FMUs (dlopen)                                                                          */

typedef struct {
    void *lib;
    fmi3InstantiateCoSimulationTYPE *instantiate;
    fmi3FreeInstanceTYPE *free_instance;
    fmi3EnterInitializationModeTYPE *enter_init;
    fmi3ExitInitializationModeTYPE *exit_init;
    fmi3GetFMUStateTYPE *get_state;
    fmi3FreeFMUStateTYPE *free_state;
    fmi3SerializedFMUStateSizeTYPE *serialized_size;
    fmi3SerializeFMUStateTYPE *serialize;
    fmi3GetDirectionalDerivativeTYPE *directional;
    fmi3GetAdjointDerivativeTYPE *adjoint;
} other_fmu;

static int load_other(other_fmu *o, const char *path)
{
    memset(o, 0, sizeof *o);
    o->lib = path ? dlopen(path, RTLD_NOW | RTLD_LOCAL) : NULL;
    if (!o->lib) {
        printf("    cannot load the other FMU %s: %s\n", path ? path : "(not given)", path ? dlerror() : "");
        return 0;
    }
    return SYMBOL(o, instantiate, "fmi3InstantiateCoSimulation") && SYMBOL(o, free_instance, "fmi3FreeInstance") &&
           SYMBOL(o, enter_init, "fmi3EnterInitializationMode") &&
           SYMBOL(o, exit_init, "fmi3ExitInitializationMode") && SYMBOL(o, get_state, "fmi3GetFMUState") &&
           SYMBOL(o, free_state, "fmi3FreeFMUState") && SYMBOL(o, serialized_size, "fmi3SerializedFMUStateSize") &&
           SYMBOL(o, serialize, "fmi3SerializeFMUState") &&
           SYMBOL(o, directional, "fmi3GetDirectionalDerivative") &&
           SYMBOL(o, adjoint, "fmi3GetAdjointDerivative");
}

static const char *small_path, *twin_path;

/* ------------------------------------------------------------------------------------------ */
/* Tests                                                                                        */

static void test_version_and_instantiation(void)
{
    logbook lb;
    fmi3Instance c;

    CHECK(strcmp(fmi3GetVersion(), "3.0") == 0);
    memset(&lb, 0, sizeof lb);
    CHECK(fmi3InstantiateCoSimulation("x", "{wrong}", "", false, false, false, false, NULL, 0, &lb, log_message,
                                      NULL) == NULL);
    CHECK(logged(&lb, "fmi3InstantiateCoSimulation: instantiationToken '{wrong}' does not match", GUID));
    CHECK(lb.last_status == fmi3Error);
    CHECK(fmi3InstantiateModelExchange("x", NULL, "", false, false, &lb, log_message) == NULL);
    CHECK(logged(&lb, "fmi3InstantiateModelExchange: instantiationToken '(null)'", NULL));
    CHECK(fmi3InstantiateModelExchange("", GUID, "", false, false, &lb, log_message) == NULL);
    CHECK(logged(&lb, "instanceName must be a non-empty string", NULL));
    CHECK(fmi3InstantiateModelExchange("x", "{wrong}", "", false, false, NULL, NULL) == NULL); /* no logger */
    CHECK(fmi3InstantiateScheduledExecution("x", GUID, "", false, false, &lb, log_message, NULL, NULL, NULL) == NULL);
    CHECK(logged(&lb, "fmi3InstantiateScheduledExecution: not supported", NULL));
    fmi3FreeInstance(NULL);

    /* earlyReturnAllowed and required intermediate variables are accepted (and never used) */
    {
        const fmi3ValueReference req[1] = { VR_F };
        c = fmi3InstantiateCoSimulation("x", GUID, "", false, true, false, true, req, 1, &lb, log_message, NULL);
        CHECK(c != NULL);
        CHECK(logged(&lb, "fmi3InstantiateCoSimulation(instanceName = x", NULL)); /* loggingOn: logCalls */
        CHECK(strcmp(lb.last_category, "logCalls") == 0 && lb.last_status == fmi3OK);
        fmi3FreeInstance(c);
    }
}

static void test_state_machine(void)
{
    logbook lb;
    fmi3Instance c = cs(&lb, false), m = me(&lb);
    fmi3Boolean ehn = true, term = true, early = true, b = true;
    fmi3Float64 lst = -1.0, x3[3] = { 0 }, f = 0.0;
    size_t n = 99;
    const fmi3ValueReference vr0 = 0;

    /* Instantiated */
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not allowed in state Instantiated", NULL));
    CHECK_ERR(fmi3ExitInitializationMode(c));
    CHECK(logged(&lb, "fmi3ExitInitializationMode: not allowed in state Instantiated", NULL));
    CHECK_ERR(fmi3EnterStepMode(c));
    {
        const fmi3ValueReference vk = VR_K;
        CHECK_OK(fmi3GetFloat64(c, &vk, 1, &f, 1)); /* start values in Instantiated */
        CHECK(f == 4.0);
    }
    CHECK_ERR(fmi3EnterInitializationMode(c, true, -1.0, 0.0, false, 0.0));
    CHECK(logged(&lb, "fmi3EnterInitializationMode: tolerance = -1 must be positive", NULL));
    CHECK_ERR(fmi3EnterInitializationMode(c, false, 0.0, 1.0, true, 0.5));
    CHECK(logged(&lb, "stopTime = 0.5 must not be before startTime = 1", NULL));
    CHECK_OK(fmi3GetNumberOfContinuousStates(c, &n));
    CHECK(n == 3);
    CHECK_OK(fmi3GetNumberOfEventIndicators(c, &n));
    CHECK(n == 0);
    CHECK_ERR(fmi3EnterConfigurationMode(c));
    CHECK(logged(&lb, "fmi3EnterConfigurationMode: not supported", "Configuration"));
    CHECK_ERR(fmi3ExitConfigurationMode(c));
    CHECK(logged(&lb, "fmi3ExitConfigurationMode: not supported", NULL));

    /* InitializationMode, then StepMode (eventModeUsed = false) */
    CHECK_OK(fmi3EnterInitializationMode(c, true, 1e-8, 0.0, true, 10.0));
    CHECK_ERR(fmi3EnterInitializationMode(c, true, 1e-8, 0.0, true, 10.0));
    CHECK(logged(&lb, "not allowed in state InitializationMode", NULL));
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK_OK(fmi3ExitInitializationMode(c));
    CHECK_ERR(fmi3UpdateDiscreteStates(c, &b, &b, &b, &b, &b, &f));
    CHECK(logged(&lb, "fmi3UpdateDiscreteStates: not allowed in state StepMode", NULL));
    CHECK_ERR(fmi3EnterEventMode(c));
    CHECK(logged(&lb, "fmi3EnterEventMode", "eventModeUsed = false"));
    CHECK_ERR(fmi3EnterStepMode(c));
    CHECK(logged(&lb, "fmi3EnterStepMode: not allowed in state StepMode", NULL));
    CHECK_ERR(fmi3GetContinuousStates(c, x3, 3));
    CHECK(logged(&lb, "fmi3GetContinuousStates: not available for a CoSimulation instance", NULL));
    CHECK_ERR(fmi3SetTime(c, 1.0));
    CHECK_ERR(set3(c, VR_K, 5.0));
    CHECK(logged(&lb, "cannot set value reference 7 in state StepMode", "before fmi3ExitInitializationMode"));
    CHECK_ERR(set3(c, VR_F, 1.0));
    CHECK(logged(&lb, "an algebraic variable is computed by the model", NULL));
    {
        const fmi3Float64 three[3] = { 1.0, 2.0, 3.0 };
        const fmi3ValueReference vdx = VR_DX;
        CHECK_ERR(fmi3SetFloat64(c, &vdx, 1, three, 3));
        CHECK(logged(&lb, "a derivative is computed by the model", NULL));
    }
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.0, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: communicationStepSize = 0 must be finite and > 0", NULL));
    CHECK_ERR(fmi3DoStep(c, 0.5, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "currentCommunicationPoint = 0.5 differs from the FMU's time 0", NULL));
    CHECK_ERR(fmi3DoStep(c, 0.0, 11.0, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "after stopTime = 10 of fmi3EnterInitializationMode", NULL));
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.1, false, NULL, &term, &early, &lst));
    CHECK(logged(&lb, "argument eventHandlingNeeded must not be NULL", NULL));
    CHECK_OK(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(!ehn && !term && !early && lst == 0.1);
    CHECK(get3(c, VR_TIME) == 0.1);
    CHECK_ERR(fmi3GetClock(c, &vr0, 1, &b));
    CHECK(logged(&lb, "fmi3GetClock: not supported: the model has no clocks", NULL));
    CHECK_ERR(fmi3SetIntervalDecimal(c, &vr0, 1, &f));
    CHECK(logged(&lb, "fmi3SetIntervalDecimal: not supported", NULL));
    CHECK_ERR(fmi3EvaluateDiscreteStates(c));
    CHECK(logged(&lb, "fmi3EvaluateDiscreteStates: not supported", NULL));
    CHECK_ERR(fmi3ActivateModelPartition(c, 0, 0.0));
    CHECK(logged(&lb, "fmi3ActivateModelPartition: not supported", NULL));
    CHECK_ERR(fmi3GetNumberOfVariableDependencies(c, VR_F, &n));
    CHECK(logged(&lb, "fmi3GetNumberOfVariableDependencies: not supported", "ModelStructure"));
    CHECK_ERR(fmi3GetVariableDependencies(c, VR_F, NULL, NULL, NULL, NULL, 0));
    CHECK(logged(&lb, "fmi3GetVariableDependencies: not supported", NULL));
    {
        const fmi3Int32 order = 1;
        const fmi3ValueReference vf = VR_F;
        CHECK_ERR(fmi3GetOutputDerivatives(c, &vf, 1, &order, &f, 1));
        CHECK(logged(&lb, "fmi3GetOutputDerivatives: output derivatives are not provided", NULL));
    }
    CHECK_OK(fmi3Terminate(c));
    CHECK_ERR(fmi3DoStep(c, 0.1, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not allowed in state Terminated", NULL));
    CHECK_ERR(fmi3Terminate(c));
    CHECK(get3(c, VR_TIME) == 0.1); /* getters in Terminated */
    CHECK_OK(fmi3Reset(c));
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not allowed in state Instantiated", NULL)); /* Instantiated again */
    fmi3FreeInstance(c);

    /* Model Exchange */
    CHECK_ERR(fmi3DoStep(m, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not available for a ModelExchange instance", NULL));
    m = started(m, 1e-6);
    CHECK_ERR(fmi3SetContinuousStates(m, x3, 3)); /* in EventMode */
    CHECK(logged(&lb, "fmi3SetContinuousStates: not allowed in state EventMode", NULL));
    CHECK_ERR(fmi3EnterEventMode(m));
    CHECK(logged(&lb, "fmi3EnterEventMode: not allowed in state EventMode", NULL));
    CHECK_ERR(fmi3EnterStepMode(m));
    CHECK(logged(&lb, "fmi3EnterStepMode: not available for a ModelExchange instance", NULL));
    {
        fmi3Boolean need = true, stop = true, nominals = true, values = true, defined = true;
        fmi3Float64 next = -1.0;
        CHECK_OK(fmi3UpdateDiscreteStates(m, &need, &stop, &nominals, &values, &defined, &next));
        CHECK(!need && !stop && !nominals && !values && !defined);
        CHECK_ERR(fmi3UpdateDiscreteStates(m, &need, &stop, &nominals, &values, NULL, &next));
    }
    CHECK_ERR(fmi3CompletedIntegratorStep(m, true, &b, &b));
    CHECK_OK(fmi3EnterContinuousTimeMode(m));
    CHECK_ERR(fmi3EnterContinuousTimeMode(m));
    CHECK_OK(fmi3CompletedIntegratorStep(m, true, &b, &term));
    CHECK(!b && !term);
    CHECK_OK(fmi3GetEventIndicators(m, NULL, 0));
    CHECK_ERR(fmi3GetEventIndicators(m, x3, 1));
    CHECK(logged(&lb, "nEventIndicators = 1, but the model has 0", NULL));
    CHECK_ERR(fmi3SetContinuousStates(m, x3, 2));
    CHECK(logged(&lb, "nContinuousStates = 2, but the model has 3", NULL));
    CHECK_OK(fmi3EnterEventMode(m));
    CHECK_OK(fmi3EnterContinuousTimeMode(m));
    {
        fmi3Int32 nn = 5;
        const fmi3ValueReference vn = VR_N;
        CHECK_ERR(fmi3SetInt32(m, &vn, 1, &nn, 1)); /* discrete: not in ContinuousTimeMode */
        CHECK(logged(&lb, "fmi3SetInt32: not allowed in state ContinuousTimeMode", NULL));
    }
    CHECK_OK(fmi3Terminate(m));
    fmi3FreeInstance(m);
}

static void test_event_mode_used(void)
{
    logbook lb;
    fmi3Instance c = started(cs(&lb, true), 1e-8);
    fmi3Boolean ehn = true, term = true, early = true;
    fmi3Boolean need = true, stop = true, nominals = true, values = true, defined = true;
    fmi3Float64 lst = -1.0, next = -1.0;

    /* Co-Simulation with eventModeUsed: EventMode after initialization */
    CHECK_ERR(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not allowed in state EventMode", NULL));
    CHECK_OK(fmi3UpdateDiscreteStates(c, &need, &stop, &nominals, &values, &defined, &next));
    CHECK(!need && !stop && !nominals && !values && !defined);
    CHECK_ERR(fmi3EnterContinuousTimeMode(c));
    CHECK(logged(&lb, "not available for a CoSimulation instance", NULL));
    CHECK_OK(fmi3EnterStepMode(c));
    CHECK_OK(fmi3DoStep(c, 0.0, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(!ehn && !term && !early && lst == 0.1); /* no events: eventHandlingNeeded never */
    CHECK_OK(fmi3EnterEventMode(c));
    CHECK_OK(set3(c, VR_U, 0.25)); /* inputs in EventMode */
    CHECK_OK(fmi3EnterStepMode(c));
    CHECK_OK(fmi3DoStep(c, 0.1, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(lst == 0.1 + 0.1);
    fmi3FreeInstance(c);
}

static void test_values(void)
{
    logbook lb;
    fmi3Instance c = cs(&lb, false);
    const fmi3ValueReference vx = VR_X, vdx = VR_DX, vn = VR_N, vb = VR_B, vt = VR_TIME, vk = VR_K;
    const fmi3ValueReference elem = 1, mixed[3] = { VR_X, VR_TIME, VR_K };
    fmi3Float64 x3[3], five[5], f;
    fmi3Int32 n;
    fmi3Boolean b;
    const fmi3Float64 x0[3] = { 0.5, -0.25, 3.0 };
    fmi3Boolean ehn, term, early;
    fmi3Float64 lst;

    /* arrays and time, set in Instantiated */
    CHECK_OK(fmi3SetFloat64(c, &vx, 1, x0, 3));
    CHECK_ERR(fmi3SetFloat64(c, &vx, 1, x0, 2));
    CHECK(logged(&lb, "fmi3SetFloat64: nValues = 2, but the 1 value references have 3 values", NULL));
    CHECK_ERR(fmi3SetFloat64(c, &elem, 1, x0, 1));
    CHECK(logged(&lb, "value reference 1 is an element of an array variable", NULL));
    CHECK_ERR(fmi3SetFloat64(c, &vt, 1, x0, 1));
    CHECK(logged(&lb, "value reference 15 is the independent variable time", NULL));
    n = 3;
    CHECK_OK(fmi3SetInt32(c, &vn, 1, &n, 1));
    b = false;
    CHECK_OK(fmi3SetBoolean(c, &vb, 1, &b, 1));
    CHECK_ERR(fmi3SetFloat64(c, &vn, 1, x0, 1));
    CHECK(logged(&lb, "value reference 8 is a Int32 variable, not Float64", NULL));
    {
        const fmi3Float64 bad = NAN;
        CHECK_ERR(fmi3SetFloat64(c, &vk, 1, &bad, 1));
        CHECK(logged(&lb, "k (value reference 7) = nan: the value must be finite", NULL));
    }
    CHECK_OK(fmi3EnterInitializationMode(c, true, 1e-8, 2.0, false, 0.0));
    CHECK_OK(fmi3GetFloat64(c, &vx, 1, x3, 3));
    CHECK(x3[0] == x0[0] && x3[1] == x0[1] && x3[2] == x0[2]); /* w set: its calculated start does not apply */
    CHECK_OK(fmi3GetFloat64(c, mixed, 3, five, 5));
    CHECK(five[0] == x0[0] && five[2] == x0[2] && five[3] == 2.0 && five[4] == 4.0); /* time = startTime */
    CHECK_ERR(fmi3GetFloat64(c, mixed, 3, five, 4));
    CHECK(logged(&lb, "fmi3GetFloat64: nValues = 4, but the 3 value references have 5 values", NULL));
    CHECK_ERR(fmi3GetFloat64(c, &elem, 1, &f, 1));
    CHECK_OK(fmi3GetInt32(c, &vn, 1, &n, 1));
    CHECK(n == 3);
    CHECK_ERR(fmi3GetInt32(c, &vt, 1, &n, 1));
    CHECK(logged(&lb, "value reference 15 (time) is a Float64 variable, not Int32", NULL));
    CHECK_OK(fmi3GetBoolean(c, &vb, 1, &b, 1));
    CHECK(b == false);
    CHECK_ERR(fmi3GetBoolean(c, &vn, 1, &b, 1));
    CHECK(logged(&lb, "is a Int32 variable, not Boolean", NULL));
    CHECK_OK(fmi3ExitInitializationMode(c));
    /* der(x) as an array: v' = -k s - d v + g u with d = 0.3, g = 0 (b false) */
    CHECK_OK(fmi3GetFloat64(c, &vdx, 1, x3, 3));
    CHECK(x3[0] == x0[1] && x3[1] == -4.0 * x0[0] - 0.1 * 3.0 * x0[1] && x3[2] == -x0[2]);
    CHECK_OK(fmi3DoStep(c, 2.0, 0.5, false, &ehn, &term, &early, &lst));
    CHECK(get3(c, VR_TIME) == 2.5 && lst == 2.5);

    /* the types the model does not have */
    CHECK_OK(fmi3GetFloat32(c, NULL, 0, NULL, 0));
    {
        fmi3Float32 f32;
        fmi3Int8 i8;
        fmi3UInt64 u64;
        fmi3String s;
        size_t size;
        fmi3Binary bin;
        CHECK_ERR(fmi3GetFloat32(c, &vk, 1, &f32, 1));
        CHECK(logged(&lb, "fmi3GetFloat32: value reference 7 is a Float64 variable, not Float32", NULL));
        CHECK_ERR(fmi3GetInt8(c, &vn, 1, &i8, 1));
        CHECK(logged(&lb, "fmi3GetInt8: value reference 8 is a Int32 variable, not Int8", NULL));
        CHECK_ERR(fmi3SetUInt64(c, &vn, 1, &u64, 1));
        CHECK(logged(&lb, "fmi3SetUInt64", "not UInt64"));
        CHECK_ERR(fmi3GetString(c, &vt, 1, &s, 1));
        CHECK(logged(&lb, "fmi3GetString: value reference 15 (time) is a Float64 variable", NULL));
        CHECK_ERR(fmi3GetBinary(c, &vk, 1, &size, &bin, 1));
        CHECK(logged(&lb, "fmi3GetBinary", "not Binary"));
        {
            const fmi3ValueReference far = 99;
            CHECK_ERR(fmi3SetString(c, &far, 1, &s, 1));
            CHECK(logged(&lb, "fmi3SetString: value reference 99 is out of range", NULL));
        }
    }
    fmi3FreeInstance(c);
}

/* The same model through FMI 2 and FMI 3: every DoStep gives the same bits. */
static void test_dostep_equals_fmi2(void)
{
    static const double h_fixed[2] = { 0.0, 0.01 };
    int variant;

    for (variant = 0; variant < 2; variant++) {
        logbook lb;
        fmi3Instance c3 = cs(&lb, false);
        fmi2Component c2 = fmi2Instantiate("cs2", fmi2CoSimulation, GUID, "", &CB2, fmi2False, fmi2False);
        const fmi2ValueReference vh = VR_H;
        double a[NV], b[NV], t = 0.0;
        int k, same = 1, same_status = 1;
        long steps = 0;

        set3(c3, VR_H, h_fixed[variant]);
        fmi2SetReal(c2, &vh, 1, &h_fixed[variant]);
        CHECK_OK(fmi3EnterInitializationMode(c3, true, 1e-9, 0.0, true, 5.0));
        CHECK(fmi2SetupExperiment(c2, fmi2True, 1e-9, 0.0, fmi2True, 5.0) == fmi2OK);
        CHECK(fmi2EnterInitializationMode(c2) == fmi2OK);
        CHECK_OK(fmi3ExitInitializationMode(c3));
        CHECK(fmi2ExitInitializationMode(c2) == fmi2OK);
        for (k = 0; k < 100; k++) {
            const double u = sin(3.0 * t) + 0.5, H = k % 3 == 0 ? 0.05 : 0.025;
            const fmi2ValueReference vu = VR_U;
            fmi3Boolean ehn, term, early;
            fmi3Float64 lst;
            fmi3Status s3;
            fmi2Status s2;
            set3(c3, VR_U, u);
            fmi2SetReal(c2, &vu, 1, &u);
            s3 = fmi3DoStep(c3, t, H, false, &ehn, &term, &early, &lst);
            s2 = fmi2DoStep(c2, t, H, fmi2True);
            same_status &= (int)s3 == (int)s2 && s3 == fmi3OK && lst == t + H;
            t += H;
            steps++;
            all3(c3, a);
            all2(c2, b);
            same &= memcmp(a, b, sizeof a) == 0;
        }
        printf("  %ld DoSteps (%s), FMI 3 and FMI 2 bit-identical: %s\n", steps,
               variant ? "fixed h = 0.01" : "adaptive, tol 1e-9", same ? "yes" : "NO");
        CHECK(same_status);
        CHECK(same);
        CHECK(a[0] != 1.0 && isfinite(a[0])); /* the model moved */
        fmi3FreeInstance(c3);
        fmi2FreeInstance(c2);
    }

    /* Model Exchange: the same derivatives for the same states, inputs and time */
    {
        logbook lb;
        fmi3Instance m3 = started(me(&lb), 1e-6);
        fmi2Component m2 = fmi2Instantiate("me2", fmi2ModelExchange, GUID, "", &CB2, fmi2False, fmi2False);
        const double x[3] = { 0.3, -1.25, 0.7 };
        const fmi2ValueReference vu = VR_U;
        const double u = 2.5;
        double d3[3], d2[3];
        fmi2SetupExperiment(m2, fmi2True, 1e-6, 0.0, fmi2False, 0.0);
        fmi2EnterInitializationMode(m2);
        fmi2ExitInitializationMode(m2);
        CHECK_OK(fmi3EnterContinuousTimeMode(m3));
        CHECK(fmi2EnterContinuousTimeMode(m2) == fmi2OK);
        CHECK_OK(fmi3SetTime(m3, 0.75));
        CHECK(fmi2SetTime(m2, 0.75) == fmi2OK);
        CHECK_OK(fmi3SetContinuousStates(m3, x, 3));
        CHECK(fmi2SetContinuousStates(m2, x, 3) == fmi2OK);
        CHECK_OK(set3(m3, VR_U, u));
        CHECK(fmi2SetReal(m2, &vu, 1, &u) == fmi2OK);
        CHECK_OK(fmi3GetContinuousStateDerivatives(m3, d3, 3));
        CHECK(fmi2GetDerivatives(m2, d2, 3) == fmi2OK);
        CHECK(memcmp(d3, d2, sizeof d3) == 0);
        CHECK(d3[1] == -4.0 * x[0] - 0.2 * x[1] + u);
        CHECK_OK(fmi3GetContinuousStates(m3, d3, 3));
        CHECK(memcmp(d3, x, sizeof d3) == 0);
        CHECK_OK(fmi3GetNominalsOfContinuousStates(m3, d3, 3));
        CHECK(d3[0] == 1.0 && d3[1] == 1.0 && d3[2] == 1.0);
        CHECK(get3(m3, VR_TIME) == 0.75);
        fmi3FreeInstance(m3);
        fmi2FreeInstance(m2);
    }
}

/* Directional and adjoint derivatives: v^T (J u) = (J^T v)^T u, and each against the other's
   unit vectors (the whole Jacobian). */
static void adjoint_case(fmi3Instance c, const char *where)
{
    /* unknowns: der(x) (array, 3 values), f, e; knowns: x (array, 3 values), u, k */
    const fmi3ValueReference unknowns[3] = { VR_DX, VR_F, VR_E }, knowns[3] = { VR_X, VR_U, VR_K };
    const double seed[5] = { 0.3, -1.1, 0.7, 2.0, -0.4 }, weight[5] = { -0.9, 0.25, 1.3, 0.6, -2.2 };
    double ju[5], jtv[5], J[5][5], lhs = 0.0, rhs = 0.0, scale = 0.0, dev = 0.0;
    int i, j;

    CHECK_OK(fmi3GetDirectionalDerivative(c, unknowns, 3, knowns, 3, seed, 5, ju, 5));
    CHECK_OK(fmi3GetAdjointDerivative(c, unknowns, 3, knowns, 3, weight, 5, jtv, 5));
    for (i = 0; i < 5; i++) {
        lhs += weight[i] * ju[i];
        rhs += jtv[i] * seed[i];
        scale += fabs(weight[i] * ju[i]) + fabs(jtv[i] * seed[i]);
    }
    printf("  adjoint vs directional (%s): v'(Ju) = %.17g, (J'v)'u = %.17g\n", where, lhs, rhs);
    CHECK(scale > 1.0);
    CHECK_NEAR(lhs, rhs, 1e-14 * scale);
    /* the Jacobian column by column (directional) and row by row (adjoint) */
    for (j = 0; j < 5; j++) {
        double e[5] = { 0 }, col[5];
        e[j] = 1.0;
        CHECK_OK(fmi3GetDirectionalDerivative(c, unknowns, 3, knowns, 3, e, 5, col, 5));
        for (i = 0; i < 5; i++) J[i][j] = col[i];
    }
    for (i = 0; i < 5; i++) {
        double e[5] = { 0 }, row[5];
        e[i] = 1.0;
        CHECK_OK(fmi3GetAdjointDerivative(c, unknowns, 3, knowns, 3, e, 5, row, 5));
        for (j = 0; j < 5; j++) dev = fmax(dev, fabs(row[j] - J[i][j]));
    }
    CHECK(dev == 0.0); /* the hand-written products of the test model are exact */
}

static void test_directional_and_adjoint(void)
{
    logbook lb;
    fmi3Instance c = started(cs(&lb, false), 1e-8), m;
    const fmi3ValueReference vdx = VR_DX, vx = VR_X, vn = VR_N, vt = VR_TIME, vomega = VR_OMEGA;
    double out[3], seed[3] = { 1.0, 0.0, 0.0 };
    fmi3Boolean ehn, term, early;
    fmi3Float64 lst;
    other_fmu small;

    set3(c, VR_U, 0.8);
    CHECK_OK(fmi3DoStep(c, 0.0, 0.3, false, &ehn, &term, &early, &lst));
    adjoint_case(c, "CS StepMode");
    /* refusals */
    CHECK_ERR(fmi3GetDirectionalDerivative(c, &vdx, 1, &vx, 1, seed, 3, out, 2));
    CHECK(logged(&lb, "nSeed = 3 and nSensitivity = 2, but the knowns have 3 values and the unknowns 3", NULL));
    CHECK_ERR(fmi3GetAdjointDerivative(c, &vdx, 1, &vn, 1, seed, 3, out, 1));
    CHECK(logged(&lb, "value reference 8 is a Int32 variable, not Float64", NULL));
    CHECK_ERR(fmi3GetAdjointDerivative(c, &vdx, 1, &vt, 1, seed, 3, out, 1));
    CHECK(logged(&lb, "knowns: value reference 15 is the independent variable time", NULL));
    CHECK_ERR(fmi3GetDirectionalDerivative(c, &vomega, 1, &vx, 1, seed, 3, out, 1));
    CHECK(logged(&lb, "unknown value reference 11 is not a state, derivative or algebraic variable", NULL));
    CHECK_OK(fmi3GetAdjointDerivative(c, NULL, 0, NULL, 0, NULL, 0, NULL, 0));
    /* states among the unknowns (ModelStructure Outputs that are states): identity rows */
    {
        const fmi3ValueReference unknowns[2] = { VR_X, VR_F }, knowns[2] = { VR_X, VR_U };
        const double s[4] = { 0.5, -2.0, 0.25, 3.0 }, w[4] = { 1.5, 0.75, -1.0, 2.0 };
        double ds[4], jtw[4], f_x[4];
        int i;
        CHECK_OK(fmi3GetDirectionalDerivative(c, unknowns, 2, knowns, 2, s, 4, ds, 4));
        CHECK(ds[0] == s[0] && ds[1] == s[1] && ds[2] == s[2]);
        CHECK(ds[3] == 4.0 * s[0] + s[3]); /* f = k s + u */
        CHECK_OK(fmi3GetAdjointDerivative(c, unknowns, 2, knowns, 2, w, 4, jtw, 4));
        f_x[0] = 4.0; f_x[1] = 0.0; f_x[2] = 0.0; f_x[3] = 1.0; /* the row of f */
        for (i = 0; i < 4; i++) CHECK(jtw[i] == (i < 3 ? w[i] : 0.0) + w[3] * f_x[i]);
        /* an unknown state that is no known: a zero row */
        CHECK_OK(fmi3GetDirectionalDerivative(c, &vx, 1, &vdx, 0, NULL, 0, ds, 3));
        CHECK(ds[0] == 0.0 && ds[1] == 0.0 && ds[2] == 0.0);
    }
    fmi3FreeInstance(c);

    m = started(me(&lb), 1e-6);
    {
        const double x[3] = { 0.4, 1.5, -0.2 };
        fmi3EnterContinuousTimeMode(m);
        fmi3SetContinuousStates(m, x, 3);
        set3(m, VR_U, -0.6);
    }
    adjoint_case(m, "ME ContinuousTimeMode");
    fmi3FreeInstance(m);

    /* a model without a vector-Jacobian product: no adjoint derivatives, directional ones work */
    if (load_other(&small, small_path)) {
        fmi3Instance o = small.instantiate("small", SMALL_GUID, "", false, false, false, false, NULL, 0, &lb,
                                           log_message, NULL);
        const fmi3ValueReference q = 0, dq = 1;
        const double one = 1.0;
        double r = 0.0;
        CHECK(o != NULL);
        CHECK(small.enter_init(o, false, 0.0, 0.0, false, 0.0) == fmi3OK);
        CHECK(small.exit_init(o) == fmi3OK);
        CHECK(small.adjoint(o, &dq, 1, &q, 1, &one, 1, &r, 1) == fmi3Error);
        CHECK(logged(&lb, "fmi3GetAdjointDerivative: the model provides no vector-Jacobian product", NULL));
        CHECK(small.directional(o, &dq, 1, &q, 1, &one, 1, &r, 1) == fmi3OK);
        CHECK(r == -1.0); /* q' = -a q + u, a = 1 */
        small.free_instance(o);
        dlclose(small.lib);
    } else {
        CHECK(!"the FMU without vjp could not be loaded");
    }
}

/* Five steps of 0.1 from time t; out: all values after each. */
static void five_steps(fmi3Instance c, double t, double out[5][NV])
{
    int k;
    for (k = 0; k < 5; k++) {
        fmi3Boolean ehn, term, early;
        fmi3Float64 lst;
        set3(c, VR_U, cos(t));
        fmi3DoStep(c, t, 0.1, false, &ehn, &term, &early, &lst);
        t += 0.1;
        all3(c, out[k]);
    }
}

/* One foreign FMU: a state it serialized is refused by this model (why: the expected reason). */
static void foreign_case(const char *path, const char *guid, const char *why)
{
    logbook lb, lbo;
    other_fmu o;
    fmi3Instance c = started(cs(&lb, false), 1e-8), oc;
    fmi3FMUState os = NULL, mine = NULL;
    size_t size = 0;
    unsigned char *bytes;
    double before[NV], after[NV];

    if (!load_other(&o, path)) {
        CHECK(!"the other FMU could not be loaded");
        fmi3FreeInstance(c);
        return;
    }
    memset(&lbo, 0, sizeof lbo);
    oc = o.instantiate("other", guid, "", false, false, false, false, NULL, 0, &lbo, log_message, NULL);
    CHECK(oc != NULL);
    o.enter_init(oc, false, 0.0, 0.0, false, 0.0);
    o.exit_init(oc);
    CHECK(o.get_state(oc, &os) == fmi3OK);
    CHECK(o.serialized_size(oc, os, &size) == fmi3OK);
    bytes = (unsigned char *)malloc(size);
    CHECK(o.serialize(oc, os, bytes, size) == fmi3OK);
    all3(c, before);
    CHECK_ERR(fmi3DeserializeFMUState(c, bytes, size, &mine));
    CHECK(logged(&lb, "fmi3DeserializeFMUState", why));
    CHECK(mine == NULL);
    CHECK_ERR(fmi3SetFMUState(c, os)); /* the other FMU's state object itself */
    CHECK(logged(&lb, "fmi3SetFMUState: FMUstate refused", why));
    all3(c, after);
    CHECK(memcmp(before, after, sizeof before) == 0);
    printf("  foreign FMU state from %s refused\n", path);
    free(bytes);
    o.free_state(oc, &os);
    o.free_instance(oc);
    dlclose(o.lib);
    fmi3FreeInstance(c);
}

static void test_fmu_state(void)
{
    logbook lb;
    fmi3Instance c = started(cs(&lb, false), 1e-8), d;
    fmi3FMUState s = NULL, copy = NULL;
    double first[5][NV], again[5][NV], from_copy[5][NV];
    size_t size = 0;
    unsigned char *bytes;

    five_steps(c, 0.0, first);
    CHECK_OK(fmi3GetFMUState(c, &s));
    five_steps(c, 0.5, first);
    CHECK_OK(fmi3SetFMUState(c, s));
    CHECK(get3(c, VR_TIME) == 0.5);
    five_steps(c, 0.5, again);
    CHECK(memcmp(first, again, sizeof first) == 0); /* save, step, restore, step: identical */
    CHECK_OK(fmi3SerializedFMUStateSize(c, s, &size));
    bytes = (unsigned char *)malloc(size);
    CHECK_OK(fmi3SerializeFMUState(c, s, bytes, size));
    CHECK_ERR(fmi3SerializeFMUState(c, s, bytes, size - 1));
    CHECK(logged(&lb, "fmi3SerializeFMUState: size", "bytes are needed"));
    /* a new instance of the same model continues from the deserialized state */
    d = cs(&lb, false);
    CHECK_OK(fmi3DeserializeFMUState(d, bytes, size, &copy));
    CHECK_OK(fmi3SetFMUState(d, copy));
    five_steps(d, 0.5, from_copy);
    CHECK(memcmp(first, from_copy, sizeof first) == 0);
    CHECK_ERR(fmi3DeserializeFMUState(d, bytes, size - 8, &copy));
    CHECK_OK(fmi3FreeFMUState(d, &copy));
    CHECK(copy == NULL);
    CHECK_OK(fmi3FreeFMUState(c, &s));
    /* a ModelExchange instance refuses a state in StepMode */
    fmi3FreeInstance(d);
    d = me(&lb);
    CHECK_ERR(fmi3DeserializeFMUState(d, bytes, size, &copy));
    CHECK(logged(&lb, "invalid FMI state for this instance", NULL));
    fmi3FreeInstance(d);
    free(bytes);
    fmi3FreeInstance(c);

    foreign_case(twin_path, TWIN_GUID, "belongs to another FMU");
    foreign_case(small_path, SMALL_GUID, "belongs to another FMU");
}

static void test_discard_with_last_successful_time(void)
{
    logbook lb;
    fmi3Instance c = started(cs(&lb, false), 1e-8);
    fmi2Component c2 = fmi2Instantiate("cs2", fmi2CoSimulation, GUID, "", &CB2, fmi2False, fmi2False);
    const fmi2ValueReference vu = VR_U;
    const double u = 1001.0;
    fmi3Boolean ehn = true, term = false, early = true;
    fmi3Float64 lst = -1.0, lst2 = -2.0, x3[3], dx3[3];
    const fmi3ValueReference vx = VR_X, vdx = VR_DX;
    fmi3Status st;
    char expect[128];

    fmi2SetupExperiment(c2, fmi2True, 1e-8, 0.0, fmi2False, 0.0);
    fmi2EnterInitializationMode(c2);
    fmi2ExitInitializationMode(c2);
    CHECK_OK(fmi3DoStep(c, 0.0, 0.5, false, &ehn, &term, &early, &lst));
    fmi2DoStep(c2, 0.0, 0.5, fmi2True);
    /* w' = w^2 escapes inside the next step: the step size underflows there */
    CHECK_OK(set3(c, VR_U, u));
    fmi2SetReal(c2, &vu, 1, &u);
    st = fmi3DoStep(c, 0.5, 1.0, false, &ehn, &term, &early, &lst);
    CHECK(st == fmi3Discard);
    CHECK(term && !ehn && !early);
    CHECK(lst > 0.5 && lst < 1.5);
    CHECK(get3(c, VR_TIME) == lst);
    CHECK(lb.last_status == fmi3Discard && strcmp(lb.last_category, "logStatusError") == 0);
    snprintf(expect, sizeof expect, "at the last successful time t = %.16g (fmi3Discard", lst);
    CHECK(logged(&lb, "fmi3DoStep: step size", expect));
    /* the same as FMI 2's fmi2Discard on the same model, bit for bit */
    CHECK(fmi2DoStep(c2, 0.5, 1.0, fmi2True) == fmi2Discard);
    CHECK(fmi2GetRealStatus(c2, fmi2LastSuccessfulTime, &lst2) == fmi2OK);
    CHECK(lst == lst2);
    printf("  fmi3Discard with lastSuccessfulTime %.15g (fmi2: %.15g)\n", lst, lst2);
    /* states and outputs are those at the last successful time */
    CHECK_OK(fmi3GetFloat64(c, &vx, 1, x3, 3));
    CHECK_OK(fmi3GetFloat64(c, &vdx, 1, dx3, 3));
    CHECK(isfinite(x3[2]) && x3[2] > 1e5);
    CHECK(dx3[2] == x3[2] * x3[2]);
    /* no further step, but getters, FMU states and Terminate */
    CHECK_ERR(fmi3DoStep(c, lst, 0.1, false, &ehn, &term, &early, &lst));
    CHECK(logged(&lb, "fmi3DoStep: not allowed in state StepMode after a discarded fmi3DoStep", NULL));
    CHECK_OK(fmi3Terminate(c));
    CHECK_OK(fmi3GetFloat64(c, &vx, 1, dx3, 3));
    CHECK(dx3[2] == x3[2]);
    fmi3FreeInstance(c);
    fmi2FreeInstance(c2);
}

static void test_logging(void)
{
    logbook lb;
    fmi3Instance c = cs(&lb, false);
    const fmi3String calls[1] = { "logCalls" }, bad[1] = { "logEverything" };
    int n;

    CHECK_ERR(fmi3SetDebugLogging(c, true, 1, bad));
    CHECK(logged(&lb, "fmi3SetDebugLogging: unknown log category 'logEverything'", NULL));
    CHECK_OK(fmi3SetDebugLogging(c, true, 1, calls));
    n = lb.n_messages;
    set3(c, VR_K, 4.5);
    CHECK(lb.n_messages == n + 1 && logged(&lb, "fmi3SetFloat64(nValueReferences = 1, nValues = 1)", NULL));
    CHECK(strcmp(lb.last_category, "logCalls") == 0);
    /* logCalls only: errors are muted now */
    n = lb.n_messages;
    CHECK_ERR(set3(c, VR_F, 1.0));
    CHECK(lb.n_messages == n + 1); /* the call, not the error */
    CHECK_OK(fmi3SetDebugLogging(c, false, 0, NULL));
    n = lb.n_messages;
    CHECK_ERR(set3(c, VR_F, 1.0));
    CHECK(lb.n_messages == n);
    CHECK_OK(fmi3SetDebugLogging(c, true, 0, NULL));
    CHECK_ERR(set3(c, VR_F, 1.0));
    CHECK(strcmp(lb.last_category, "logStatusError") == 0 && lb.last_status == fmi3Error);
    fmi3FreeInstance(c);
}

static void test_reset(void)
{
    logbook lb;
    fmi3Instance c = started(cs(&lb, false), 1e-8);
    fmi3Boolean ehn, term, early;
    fmi3Float64 lst, x3[3];
    const fmi3ValueReference vx = VR_X;

    CHECK_OK(fmi3DoStep(c, 0.0, 1.0, false, &ehn, &term, &early, &lst));
    CHECK_OK(fmi3Reset(c));
    CHECK_OK(fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0));
    CHECK_OK(fmi3GetFloat64(c, &vx, 1, x3, 3));
    CHECK(x3[0] == 1.0 && x3[1] == 0.0 && x3[2] == 2.0); /* start values, w = k / 2 */
    CHECK(get3(c, VR_TIME) == 0.0);
    fmi3FreeInstance(c);
}

int main(int argc, char **argv)
{
    small_path = argc > 1 ? argv[1] : NULL;
    twin_path = argc > 2 ? argv[2] : NULL;
    printf("FMI 3.0 runtime tests (cosim_runtime.c, fmi3_api.c)\n");
    test_version_and_instantiation();
    test_state_machine();
    test_event_mode_used();
    test_values();
    test_dostep_equals_fmi2();
    test_directional_and_adjoint();
    test_fmu_state();
    test_discard_with_last_successful_time();
    test_logging();
    test_reset();
    printf("%d checks, %d failed\n", n_checks, n_failed);
    return n_failed == 0 ? 0 : 1;
}
