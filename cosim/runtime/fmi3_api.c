/*
 * fmi3_api.c -- the FMI 3.0 API of the FMUs built by `cosim build`: every function of
 * fmi3Functions.h (importers such as FMPy look up all of them), on the version-independent core
 * (cosim_runtime.c).  One binary serves Model Exchange and Co-Simulation.
 *
 * This file adds to the core
 *   - the FMI 3.0 state machine (Instantiated, InitializationMode, EventMode, ContinuousTimeMode,
 *     StepMode, Terminated, the error states): a call in a wrong state is refused with fmi3Error and
 *     a message, and changes nothing,
 *   - the FMI 3.0 types: Float64, Int32 and Boolean accessors with nValues; arrays (cosim_model.h
 *     fmi3_length) are read and written as one variable; the independent variable time has the
 *     value reference first_vr + nv, one past the value array (read only),
 *   - the FMI 3.0 logger (instance environment, status, category, message: not a format string),
 *   - fmi3DoStep with lastSuccessfulTime, earlyReturn (never), eventHandlingNeeded (never) and
 *     terminateSimulation (after an integration failure, which returns fmi3Discard as in FMI 2),
 *   - fmi3GetAdjointDerivative through the model's vector-Jacobian product.
 *
 * What the models do not have is refused with fmi3Error and a message naming the function:
 * Scheduled Execution, clocks, intervals and shifts, Configuration and Reconfiguration Mode,
 * String and Binary variables, the Float32 and 8/16/64-bit and unsigned integer types, output
 * derivatives and the (optional) variable dependencies.  The models have no events: no event
 * indicators, UpdateDiscreteStates reports nothing to update and no next event time.  A
 * Co-Simulation instance with eventModeUsed = fmi3True enters Event Mode after initialization (the
 * importer leaves it with fmi3EnterStepMode), but fmi3DoStep never asks for event handling.
 * Intermediate update is not provided (providesIntermediateUpdate = false): the callback and the
 * required intermediate variables are ignored; inputs are constant over a communication step.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A binary FMU exports the plain fmi3* names. */
#undef FMI3_FUNCTION_PREFIX
#include "fmi3Functions.h"
#include "cosim_runtime.h"

/* The core's status is fmi3's, value for value. */
typedef char rt_status_is_fmi3[(RT_OK == (int)fmi3OK && RT_WARNING == (int)fmi3Warning &&
                                RT_DISCARD == (int)fmi3Discard && RT_ERROR == (int)fmi3Error) ? 1 : -1];

static const char *const STATE_NAMES[ST_COUNT] = {
    "Instantiated", "InitializationMode", "EventMode", "ContinuousTimeMode", "StepMode",
    "StepMode after a discarded fmi3DoStep (terminateSimulation = true)", "Terminated", "Error", "Fatal"
};

static const char *const TYPE_NAMES[3] = { "Float64", "Int32", "Boolean" };

static const rt_words WORDS = {
    STATE_NAMES, TYPE_NAMES, "fmi3ExitInitializationMode", "fmi3SetContinuousStates", "fmi3Discard", 1
};

/* Allowed states per function, after the state machine of FMI 3.0 (2.3.1, 3.2, 4.2; as the
   Reference FMUs check them).  Getters are allowed in Instantiated too (start values; a derivative
   or output is evaluated at the start values), and for diagnosis in the error state. */
#define M_ALIVE  (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | \
                  BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) | BIT(ST_TERMINATED) | BIT(ST_ERROR))
#define M_GET    (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | \
                  BIT(ST_STEP_FAILED) | BIT(ST_TERMINATED) | BIT(ST_ERROR))
#define M_SET_FLOAT    (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE))
#define M_SET_DISCRETE (BIT(ST_INSTANTIATED) | BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_STEP_COMPLETE))
#define M_DERIVATIVES (BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | \
                       BIT(ST_STEP_FAILED) | BIT(ST_TERMINATED))
#define M_TERMINATE (BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED))
#define M_ME_GET (BIT(ST_INIT) | BIT(ST_EVENT) | BIT(ST_CONT) | BIT(ST_TERMINATED) | BIT(ST_ERROR))

/* An FMI 3.0 instance: the core's instance (first, so that an fmi3Instance is both), the
   environment's logger and how the instance was instantiated. */
typedef struct {
    rt_instance rt;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log_message;
    int event_mode_used;   /* CS: eventModeUsed of fmi3InstantiateCoSimulation */
} fmi3_instance;

/* ---------------------------------------------------------------------------------------------
 * Logging
 * ------------------------------------------------------------------------------------------- */

/* The core's log callback: env is the fmi3_instance.  FMI 3 messages are plain strings. */
static void fmi3_logger(void *env, const char *instance_name, rt_status status, const char *category,
                        const char *message)
{
    const fmi3_instance *fi = (const fmi3_instance *)env;

    (void)instance_name; /* the environment knows its instance by instanceEnvironment */
    if (fi->log_message) fi->log_message(fi->env, (fmi3Status)status, category, message);
}

/* Logging before an instance exists (the instantiate functions). */
static void RT_PRINTF(3, 4) log_raw(fmi3LogMessageCallback log_message, fmi3InstanceEnvironment env,
                                    const char *fmt, ...)
{
    char raw[1024];
    va_list ap;

    if (!log_message) return;
    va_start(ap, fmt);
    rt_vformat(raw, sizeof raw, fmt, ap);
    va_end(ap);
    log_message(env, fmi3Error, "logStatusError", raw);
}

/* A function this FMU does not provide (checked against the state machine's alive states first). */
static fmi3Status unsupported(fmi3Instance instance, const char *fn, const char *why)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "%s()", fn);
    if (!rt_allowed(in, fn, M_ALIVE, IF_ANY)) return fmi3Error;
    rt_log_error(in, "%s: not supported: %s", fn, why);
    return fmi3Error;
}

#define NO_CLOCKS "the model has no clocks"
#define NO_CONFIGURATION "the model has no structural parameters (no Configuration or Reconfiguration Mode)"

/* ---------------------------------------------------------------------------------------------
 * Inquire version numbers, logging
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT const char *fmi3GetVersion(void) { return fmi3Version; }

RT_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                                         const fmi3String categories[])
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3SetDebugLogging(loggingOn = %d, nCategories = %zu)", (int)loggingOn, nCategories);
    if (!rt_allowed(in, "fmi3SetDebugLogging", M_ALIVE, IF_ANY)) return fmi3Error;
    return rt_set_category(in, "fmi3SetDebugLogging", loggingOn, nCategories, categories) ? fmi3OK : fmi3Error;
}

/* ---------------------------------------------------------------------------------------------
 * Creation and destruction of instances
 * ------------------------------------------------------------------------------------------- */

static fmi3Instance instantiate(const char *fn, rt_kind kind, fmi3String instanceName, fmi3String token,
                                fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback logMessage)
{
    fmi3_instance *fi;
    rt_config cfg;
    const char *problem;

    if (!instanceName || instanceName[0] == '\0') {
        log_raw(logMessage, env, "%s: instanceName must be a non-empty string", fn);
        return NULL;
    }
    if (!token || strcmp(token, COSIM_MODEL.instantiation_token) != 0) {
        log_raw(logMessage, env, "%s: instantiationToken '%s' does not match this FMU's instantiationToken '%s'",
                fn, token ? token : "(null)", COSIM_MODEL.instantiation_token);
        return NULL;
    }
    problem = rt_model_problem();
    if (problem) {
        log_raw(logMessage, env, "%s: invalid model code: %s", fn, problem);
        return NULL;
    }
    fi = (fmi3_instance *)calloc(1, sizeof(fmi3_instance));
    if (!fi) {
        log_raw(logMessage, env, "%s: out of memory", fn);
        return NULL;
    }
    fi->env = env;
    fi->log_message = logMessage;
    fi->event_mode_used = kind == RT_CS && eventModeUsed;
    cfg.alloc = calloc;
    cfg.free = free;
    cfg.log = fmi3_logger;
    cfg.log_env = fi;
    cfg.words = &WORDS;
    cfg.kind = kind;
    cfg.log_calls = loggingOn;
    if (!rt_init(&fi->rt, &cfg, instanceName)) {
        log_raw(logMessage, env, "%s: out of memory", fn);
        rt_release(&fi->rt);
        free(fi);
        return NULL;
    }
    fi->rt.cs_event_mode = fi->event_mode_used;
    rt_check_fixed_step(&fi->rt, fn);
    rt_reset(&fi->rt);
    return fi;
}

RT_EXPORT fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                                    fmi3String resourcePath, fmi3Boolean visible,
                                                    fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
                                                    fmi3LogMessageCallback logMessage)
{
    fmi3Instance in;

    (void)resourcePath;
    (void)visible;
    in = instantiate("fmi3InstantiateModelExchange", RT_ME, instanceName, instantiationToken, loggingOn, 0,
                     instanceEnvironment, logMessage);
    if (in) rt_log_call((rt_instance *)in, "fmi3InstantiateModelExchange(instanceName = %s)", instanceName);
    return in;
}

RT_EXPORT fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                                   fmi3String resourcePath, fmi3Boolean visible,
                                                   fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
                                                   fmi3Boolean earlyReturnAllowed,
                                                   const fmi3ValueReference requiredIntermediateVariables[],
                                                   size_t nRequiredIntermediateVariables,
                                                   fmi3InstanceEnvironment instanceEnvironment,
                                                   fmi3LogMessageCallback logMessage,
                                                   fmi3IntermediateUpdateCallback intermediateUpdate)
{
    fmi3Instance in;

    (void)resourcePath;
    (void)visible;
    /* Early return is allowed but never taken; there is no intermediate update (inputs are held
       over a step), so the callback is never called and no variable is accessed through it. */
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    in = instantiate("fmi3InstantiateCoSimulation", RT_CS, instanceName, instantiationToken, loggingOn,
                     eventModeUsed, instanceEnvironment, logMessage);
    if (in)
        rt_log_call((rt_instance *)in, "fmi3InstantiateCoSimulation(instanceName = %s, eventModeUsed = %d, "
                    "earlyReturnAllowed = %d)", instanceName, (int)eventModeUsed, (int)earlyReturnAllowed);
    return in;
}

RT_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                                         fmi3String resourcePath, fmi3Boolean visible,
                                                         fmi3Boolean loggingOn,
                                                         fmi3InstanceEnvironment instanceEnvironment,
                                                         fmi3LogMessageCallback logMessage,
                                                         fmi3ClockUpdateCallback clockUpdate,
                                                         fmi3LockPreemptionCallback lockPreemption,
                                                         fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    log_raw(logMessage, instanceEnvironment, "fmi3InstantiateScheduledExecution: not supported: the FMU "
            "provides Model Exchange and Co-Simulation only (" NO_CLOCKS ", no model partitions)");
    return NULL;
}

RT_EXPORT void fmi3FreeInstance(fmi3Instance instance)
{
    fmi3_instance *fi = (fmi3_instance *)instance;
    if (!fi) return;
    rt_log_call(&fi->rt, "fmi3FreeInstance()");
    rt_release(&fi->rt);
    free(fi);
}

/* ---------------------------------------------------------------------------------------------
 * Initialization, termination, reset
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                                 fmi3Float64 tolerance, fmi3Float64 startTime,
                                                 fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    static const char fn[] = "fmi3EnterInitializationMode";
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "%s(toleranceDefined = %d, tolerance = %g, startTime = %.16g, stopTimeDefined = %d, "
                "stopTime = %.16g)", fn, (int)toleranceDefined, tolerance, startTime, (int)stopTimeDefined,
                stopTime);
    if (!rt_allowed(in, fn, BIT(ST_INSTANTIATED), IF_ANY)) return fmi3Error;
    if (!rt_setup(in, fn, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime)) return fmi3Error;
    return (fmi3Status)rt_enter_init(in, fn);
}

RT_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    fmi3_instance *fi = (fmi3_instance *)instance;
    rt_instance *in = (rt_instance *)instance;
    rt_state next;

    rt_log_call(in, "fmi3ExitInitializationMode()");
    if (!rt_allowed(in, "fmi3ExitInitializationMode", BIT(ST_INIT), IF_ANY)) return fmi3Error;
    /* ME: Event Mode; CS: Event Mode if the importer uses it, else Step Mode */
    next = in->kind == RT_ME || fi->event_mode_used ? ST_EVENT : ST_STEP_COMPLETE;
    return (fmi3Status)rt_exit_init(in, "fmi3ExitInitializationMode", next);
}

RT_EXPORT fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    fmi3_instance *fi = (fmi3_instance *)instance;
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3EnterEventMode()");
    if (in && in->kind == RT_CS && !fi->event_mode_used) {
        rt_log_error(in, "fmi3EnterEventMode: the Co-Simulation instance was instantiated with "
                     "eventModeUsed = false");
        return fmi3Error;
    }
    if (!rt_allowed(in, "fmi3EnterEventMode", in && in->kind == RT_ME ? BIT(ST_CONT) : BIT(ST_STEP_COMPLETE),
                    IF_ANY))
        return fmi3Error;
    in->s.state = ST_EVENT;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3Terminate(fmi3Instance instance)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3Terminate()");
    if (!rt_allowed(in, "fmi3Terminate", M_TERMINATE, IF_ANY)) return fmi3Error;
    in->s.state = ST_TERMINATED;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3Reset(fmi3Instance instance)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3Reset()");
    if (!rt_allowed(in, "fmi3Reset", M_ALIVE, IF_ANY)) return fmi3Error;
    rt_reset(in);
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------------
 * Getting and setting variable values
 * ------------------------------------------------------------------------------------------- */

/* The value reference of the independent variable time (one past the value array). */
#define VR_TIME(in) ((fmi3ValueReference)rt_vr((in), (in)->nv))

/* The number of values of the FMI 3 variable vr (1: a scalar, n: an array of the values vr ..
   vr+n-1), or 0 after logging why vr is none (an element after the first of an array). */
static size_t n_values(const rt_instance *in, const char *fn, fmi3ValueReference vr)
{
    const size_t i = rt_index(in, vr);
    int n;

    if (i >= in->nv || !COSIM_MODEL.fmi3_length) return 1;
    n = COSIM_MODEL.fmi3_length[i];
    if (n > 0 && (size_t)n <= in->nv - i) return (size_t)n;
    rt_log_error(in, "%s: value reference %u is an element of an array variable, not a variable of its own "
                 "(an array is accessed through the value reference of its first element)", fn, vr);
    return 0;
}

/* Checks a Get or Set call of type `type`: the value references, that nValues is their number of
   values, and for a set (vals: the values converted to double; NULL for a get) the values.  For a
   get, brings the values up to date: the status of that. */
static rt_status check_values(rt_instance *in, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                              const void *values, size_t nValues, cosim_type type, const double *vals)
{
    size_t i, j, k = 0;
    int need_eval = 0, need_locals = 0;

    if (!rt_not_null(in, fn, "valueReferences", vr) || !rt_not_null(in, fn, "values", values)) return RT_ERROR;
    for (i = 0; i < nvr; i++) {
        size_t n;
        if (vr[i] == VR_TIME(in)) {
            if (type != COSIM_REAL) {
                rt_log_error(in, "%s: value reference %u (time) is a Float64 variable, not %s", fn, vr[i],
                             TYPE_NAMES[type == COSIM_INTEGER ? 1 : 2]);
                return RT_ERROR;
            }
            if (vals) {
                rt_log_error(in, "%s: value reference %u is the independent variable time: it is set by "
                             "fmi3EnterInitializationMode, fmi3SetTime or fmi3DoStep", fn, vr[i]);
                return RT_ERROR;
            }
            k++;
            continue;
        }
        n = n_values(in, fn, vr[i]);
        if (n == 0) return RT_ERROR;
        k += n;
    }
    if (k != nValues) {
        rt_log_error(in, "%s: nValues = %zu, but the %zu value references have %zu values", fn, nValues, nvr, k);
        return RT_ERROR;
    }
    for (i = 0, k = 0; i < nvr; i++) {
        const size_t n = vr[i] == VR_TIME(in) ? 0 : n_values(in, fn, vr[i]);
        if (n == 0) k++; /* time */
        for (j = 0; j < n; j++, k++) {
            const unsigned e = vr[i] + (unsigned)j;
            if (vals ? !rt_check_set(in, fn, e, type, vals[k]) : !rt_check_get(in, fn, e, type, &need_eval,
                                                                              &need_locals))
                return RT_ERROR;
        }
    }
    return vals ? RT_OK : rt_finish_get(in, fn, need_eval, need_locals);
}

/* Copies the values of a checked get into out, each converted by convert (the value array holds
   doubles; time is the instance's time). */
#define COPY_VALUES(in, vr, nvr, out, convert)                                        \
    do {                                                                              \
        size_t i_, j_, k_ = 0;                                                        \
        for (i_ = 0; i_ < (nvr); i_++) {                                              \
            if ((vr)[i_] == VR_TIME(in)) { (out)[k_++] = convert((in)->s.time); continue; } \
            for (j_ = 0; j_ < n_values((in), "", (vr)[i_]); j_++)                     \
                (out)[k_++] = convert((in)->s.v[rt_index((in), (vr)[i_]) + j_]);      \
        }                                                                             \
    } while (0)

#define AS_FLOAT64(x) (x)
#define AS_INT32(x) ((fmi3Int32)rt_to_integer(x))
#define AS_BOOLEAN(x) ((x) != 0.0)

RT_EXPORT fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    static const char fn[] = "fmi3GetFloat64";
    rt_instance *in = (rt_instance *)instance;
    rt_status status;

    rt_log_call(in, "%s(nValueReferences = %zu, nValues = %zu)", fn, nValueReferences, nValues);
    if (!rt_allowed(in, fn, M_GET, IF_ANY)) return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    status = check_values(in, fn, valueReferences, nValueReferences, values, nValues, COSIM_REAL, NULL);
    if (status == RT_ERROR) return fmi3Error;
    COPY_VALUES(in, valueReferences, nValueReferences, values, AS_FLOAT64); /* also with fmi3Discard */
    return (fmi3Status)status;
}

RT_EXPORT fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    static const char fn[] = "fmi3GetInt32";
    rt_instance *in = (rt_instance *)instance;
    rt_status status;

    rt_log_call(in, "%s(nValueReferences = %zu, nValues = %zu)", fn, nValueReferences, nValues);
    if (!rt_allowed(in, fn, M_GET, IF_ANY)) return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    status = check_values(in, fn, valueReferences, nValueReferences, values, nValues, COSIM_INTEGER, NULL);
    if (status == RT_ERROR) return fmi3Error;
    COPY_VALUES(in, valueReferences, nValueReferences, values, AS_INT32);
    return (fmi3Status)status;
}

RT_EXPORT fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    static const char fn[] = "fmi3GetBoolean";
    rt_instance *in = (rt_instance *)instance;
    rt_status status;

    rt_log_call(in, "%s(nValueReferences = %zu, nValues = %zu)", fn, nValueReferences, nValues);
    if (!rt_allowed(in, fn, M_GET, IF_ANY)) return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    status = check_values(in, fn, valueReferences, nValueReferences, values, nValues, COSIM_BOOLEAN, NULL);
    if (status == RT_ERROR) return fmi3Error;
    COPY_VALUES(in, valueReferences, nValueReferences, values, AS_BOOLEAN);
    return (fmi3Status)status;
}

/* A Set call of type `type`: converts the values to doubles (a temporary array), checks them all,
   then stores them; nothing is stored if one is refused. */
static fmi3Status set_values(rt_instance *in, const char *fn, unsigned mask, const fmi3ValueReference vr[],
                             size_t nvr, const void *values, size_t nValues, cosim_type type)
{
    double *vals;
    size_t i, j, k = 0;
    rt_status status;

    rt_log_call(in, "%s(nValueReferences = %zu, nValues = %zu)", fn, nvr, nValues);
    if (!rt_allowed(in, fn, mask, IF_ANY)) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "values", values)) return fmi3Error;
    vals = (double *)in->alloc(nValues > 0 ? nValues : 1, sizeof(double));
    if (!vals) {
        rt_log_error(in, "%s: out of memory", fn);
        return fmi3Error;
    }
    for (i = 0; i < nValues; i++) {
        if (type == COSIM_REAL) vals[i] = ((const fmi3Float64 *)values)[i];
        else if (type == COSIM_INTEGER) vals[i] = (double)((const fmi3Int32 *)values)[i];
        else vals[i] = ((const fmi3Boolean *)values)[i] ? 1.0 : 0.0;
    }
    status = check_values(in, fn, vr, nvr, values, nValues, type, vals);
    if (status == RT_OK)
        for (i = 0; i < nvr; i++)
            for (j = 0; j < n_values(in, fn, vr[i]); j++) rt_store(in, vr[i] + (unsigned)j, vals[k++]);
    in->free(vals);
    return status == RT_OK ? fmi3OK : fmi3Error;
}

RT_EXPORT fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    return set_values((rt_instance *)instance, "fmi3SetFloat64", M_SET_FLOAT, valueReferences, nValueReferences,
                      values, nValues, COSIM_REAL);
}

RT_EXPORT fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    return set_values((rt_instance *)instance, "fmi3SetInt32", M_SET_DISCRETE, valueReferences, nValueReferences,
                      values, nValues, COSIM_INTEGER);
}

RT_EXPORT fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    return set_values((rt_instance *)instance, "fmi3SetBoolean", M_SET_DISCRETE, valueReferences,
                      nValueReferences, values, nValues, COSIM_BOOLEAN);
}

/* The accessors of the types the models do not have: nothing to get or set (a call without value
   references succeeds); a value reference is refused, naming the variable's type. */
static fmi3Status no_such_type(fmi3Instance instance, const char *fn, unsigned mask,
                               const fmi3ValueReference vr[], size_t nvr, const char *type)
{
    rt_instance *in = (rt_instance *)instance;
    size_t i;

    rt_log_call(in, "%s(nValueReferences = %zu)", fn, nvr);
    if (!rt_allowed(in, fn, mask, IF_ANY)) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "valueReferences", vr)) return fmi3Error;
    i = rt_index(in, vr[0]);
    if (vr[0] == VR_TIME(in))
        rt_log_error(in, "%s: value reference %u (time) is a Float64 variable, not %s", fn, vr[0], type);
    else if (i >= in->nv)
        rt_log_error(in, "%s: value reference %u is out of range (the model has %zu variables and time, value "
                     "references %u to %u)", fn, vr[0], in->nv, rt_vr(in, 0), VR_TIME(in));
    else
        rt_log_error(in, "%s: value reference %u is a %s variable, not %s (the model has Float64, Int32 and "
                     "Boolean variables only)", fn, vr[0], TYPE_NAMES[COSIM_MODEL.types[i] == COSIM_REAL ? 0 :
                     COSIM_MODEL.types[i] == COSIM_INTEGER ? 1 : 2], type);
    return fmi3Error;
}

#define NO_SUCH_GETTER(name, ctype, type)                                                           \
    RT_EXPORT fmi3Status name(fmi3Instance instance, const fmi3ValueReference valueReferences[],    \
                              size_t nValueReferences, ctype values[], size_t nValues)              \
    {                                                                                               \
        (void)values;                                                                               \
        (void)nValues;                                                                              \
        return no_such_type(instance, #name, M_GET, valueReferences, nValueReferences, type);       \
    }
#define NO_SUCH_SETTER(name, ctype, type)                                                           \
    RT_EXPORT fmi3Status name(fmi3Instance instance, const fmi3ValueReference valueReferences[],    \
                              size_t nValueReferences, const ctype values[], size_t nValues)        \
    {                                                                                               \
        (void)values;                                                                               \
        (void)nValues;                                                                              \
        return no_such_type(instance, #name, M_SET_DISCRETE, valueReferences, nValueReferences, type); \
    }

NO_SUCH_GETTER(fmi3GetFloat32, fmi3Float32, "Float32")
NO_SUCH_GETTER(fmi3GetInt8, fmi3Int8, "Int8")
NO_SUCH_GETTER(fmi3GetUInt8, fmi3UInt8, "UInt8")
NO_SUCH_GETTER(fmi3GetInt16, fmi3Int16, "Int16")
NO_SUCH_GETTER(fmi3GetUInt16, fmi3UInt16, "UInt16")
NO_SUCH_GETTER(fmi3GetUInt32, fmi3UInt32, "UInt32")
NO_SUCH_GETTER(fmi3GetInt64, fmi3Int64, "Int64")
NO_SUCH_GETTER(fmi3GetUInt64, fmi3UInt64, "UInt64")
NO_SUCH_GETTER(fmi3GetString, fmi3String, "String")
NO_SUCH_SETTER(fmi3SetFloat32, fmi3Float32, "Float32")
NO_SUCH_SETTER(fmi3SetInt8, fmi3Int8, "Int8")
NO_SUCH_SETTER(fmi3SetUInt8, fmi3UInt8, "UInt8")
NO_SUCH_SETTER(fmi3SetInt16, fmi3Int16, "Int16")
NO_SUCH_SETTER(fmi3SetUInt16, fmi3UInt16, "UInt16")
NO_SUCH_SETTER(fmi3SetUInt32, fmi3UInt32, "UInt32")
NO_SUCH_SETTER(fmi3SetInt64, fmi3Int64, "Int64")
NO_SUCH_SETTER(fmi3SetUInt64, fmi3UInt64, "UInt64")
NO_SUCH_SETTER(fmi3SetString, fmi3String, "String")

RT_EXPORT fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return no_such_type(instance, "fmi3GetBinary", M_GET, valueReferences, nValueReferences, "Binary");
}

RT_EXPORT fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const size_t valueSizes[], const fmi3Binary values[],
                                   size_t nValues)
{
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return no_such_type(instance, "fmi3SetBinary", M_SET_DISCRETE, valueReferences, nValueReferences, "Binary");
}

RT_EXPORT fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Clock values[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    return unsupported(instance, "fmi3GetClock", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Clock values[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    return unsupported(instance, "fmi3SetClock", NO_CLOCKS);
}

/* ---------------------------------------------------------------------------------------------
 * Variable dependencies (optional: the model description's ModelStructure has them)
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                                         size_t *nDependencies)
{
    (void)valueReference;
    (void)nDependencies;
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies",
                       "the dependencies are those of the ModelStructure in modelDescription.xml");
}

RT_EXPORT fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                                 size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                                 size_t elementIndicesOfIndependents[],
                                                 fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{
    (void)dependent;
    (void)elementIndicesOfDependent;
    (void)independents;
    (void)elementIndicesOfIndependents;
    (void)dependencyKinds;
    (void)nDependencies;
    return unsupported(instance, "fmi3GetVariableDependencies",
                       "the dependencies are those of the ModelStructure in modelDescription.xml");
}

/* ---------------------------------------------------------------------------------------------
 * FMU states
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3GetFMUState()");
    if (!rt_allowed(in, "fmi3GetFMUState", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_get_state(in, "fmi3GetFMUState", FMUState);
}

RT_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3SetFMUState()");
    if (!rt_allowed(in, "fmi3SetFMUState", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_set_state(in, "fmi3SetFMUState", FMUState);
}

RT_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3FreeFMUState()");
    if (!rt_allowed(in, "fmi3FreeFMUState", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_free_state(in, "fmi3FreeFMUState", FMUState);
}

RT_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3SerializedFMUStateSize()");
    if (!rt_allowed(in, "fmi3SerializedFMUStateSize", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_serialized_size(in, "fmi3SerializedFMUStateSize", FMUState, size);
}

RT_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                           size_t size)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3SerializeFMUState(size = %zu)", size);
    if (!rt_allowed(in, "fmi3SerializeFMUState", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_serialize(in, "fmi3SerializeFMUState", FMUState, serializedState, size);
}

RT_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                             fmi3FMUState *FMUState)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3DeserializeFMUState(size = %zu)", size);
    if (!rt_allowed(in, "fmi3DeserializeFMUState", M_ALIVE, IF_ANY)) return fmi3Error;
    return (fmi3Status)rt_deserialize(in, "fmi3DeserializeFMUState", serializedState, size, FMUState);
}

/* ---------------------------------------------------------------------------------------------
 * Directional and adjoint derivatives
 * ------------------------------------------------------------------------------------------- */

/* The values (element value references) of the FMI 3 variables vr, into *out (allocated, the
   caller frees it; NULL if nothing was allocated) with their number *n; 0 after logging if a value
   reference is none or time. */
static int expand(rt_instance *in, const char *fn, const char *arg, const fmi3ValueReference vr[], size_t nvr,
                  unsigned **out, size_t *n)
{
    size_t i, j, k = 0, total = 0;

    *out = NULL;
    *n = 0;
    for (i = 0; i < nvr; i++) {
        size_t m;
        if (vr[i] == VR_TIME(in)) {
            rt_log_error(in, "%s: %s: value reference %u is the independent variable time, which has no "
                         "derivatives here", fn, arg, vr[i]);
            return 0;
        }
        m = n_values(in, fn, vr[i]);
        if (m == 0) return 0;
        total += m;
    }
    *out = (unsigned *)in->alloc(total > 0 ? total : 1, sizeof(unsigned));
    if (!*out) {
        rt_log_error(in, "%s: out of memory", fn);
        return 0;
    }
    for (i = 0; i < nvr; i++)
        for (j = 0; j < n_values(in, fn, vr[i]); j++) (*out)[k++] = vr[i] + (unsigned)j;
    *n = total;
    return 1;
}

typedef rt_status (*rt_derivative)(rt_instance *, const char *, const unsigned[], size_t, const unsigned[], size_t,
                                   const double[], double[]);

/* fmi3GetDirectionalDerivative (adjoint = 0: seed on the knowns, sensitivity of the unknowns) and
   fmi3GetAdjointDerivative (adjoint = 1: seed on the unknowns, sensitivity of the knowns). */
static fmi3Status derivatives(fmi3Instance instance, const char *fn, int adjoint, const fmi3ValueReference unknowns[],
                              size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                              const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],
                              size_t nSensitivity)
{
    rt_instance *in = (rt_instance *)instance;
    const rt_derivative compute = adjoint ? rt_adjoint : rt_directional;
    unsigned *u = NULL, *k = NULL;
    size_t nu = 0, nk = 0;
    fmi3Status status = fmi3Error;

    rt_log_call(in, "%s(nUnknowns = %zu, nKnowns = %zu, nSeed = %zu, nSensitivity = %zu)", fn, nUnknowns, nKnowns,
                nSeed, nSensitivity);
    if (!rt_allowed(in, fn, M_DERIVATIVES, IF_ANY)) return fmi3Error;
    if ((nUnknowns > 0 && !rt_not_null(in, fn, "unknowns", unknowns)) ||
        (nKnowns > 0 && !rt_not_null(in, fn, "knowns", knowns)) ||
        (nSeed > 0 && !rt_not_null(in, fn, "seed", seed)) ||
        (nSensitivity > 0 && !rt_not_null(in, fn, "sensitivity", sensitivity)))
        return fmi3Error;
    if (expand(in, fn, "unknowns", unknowns, nUnknowns, &u, &nu) &&
        expand(in, fn, "knowns", knowns, nKnowns, &k, &nk)) {
        const size_t n_seed = adjoint ? nu : nk, n_sens = adjoint ? nk : nu;
        if (nSeed != n_seed || nSensitivity != n_sens)
            rt_log_error(in, "%s: nSeed = %zu and nSensitivity = %zu, but the %s have %zu values and the %s %zu",
                         fn, nSeed, nSensitivity, adjoint ? "unknowns" : "knowns", n_seed,
                         adjoint ? "knowns" : "unknowns", n_sens);
        else if (n_sens == 0)
            status = fmi3OK;
        else
            status = (fmi3Status)compute(in, fn, u, nu, k, nk, seed, sensitivity);
    }
    if (u) in->free(u);
    if (k) in->free(k);
    return status;
}

RT_EXPORT fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                                  size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                                                  const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],
                                                  size_t nSensitivity)
{
    return derivatives(instance, "fmi3GetDirectionalDerivative", 0, unknowns, nUnknowns, knowns, nKnowns, seed,
                       nSeed, sensitivity, nSensitivity);
}

RT_EXPORT fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                              size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                                              const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[],
                                              size_t nSensitivity)
{
    return derivatives(instance, "fmi3GetAdjointDerivative", 1, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed,
                       sensitivity, nSensitivity);
}

/* ---------------------------------------------------------------------------------------------
 * Configuration mode, clocks, intervals and shifts: not provided
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode", NO_CONFIGURATION);
}

RT_EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode", NO_CONFIGURATION);
}

RT_EXPORT fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                            size_t nValueReferences, fmi3Float64 intervals[],
                                            fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalDecimal", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                             size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                             fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalFraction", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                         size_t nValueReferences, fmi3Float64 shifts[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3GetShiftDecimal", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                          size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3GetShiftFraction", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                            size_t nValueReferences, const fmi3Float64 intervals[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    return unsupported(instance, "fmi3SetIntervalDecimal", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                             size_t nValueReferences, const fmi3UInt64 counters[],
                                             const fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetIntervalFraction", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                         size_t nValueReferences, const fmi3Float64 shifts[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3SetShiftDecimal", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                          size_t nValueReferences, const fmi3UInt64 counters[],
                                          const fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetShiftFraction", NO_CLOCKS);
}

RT_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EvaluateDiscreteStates", NO_CLOCKS " (and no discrete states)");
}

RT_EXPORT fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                                fmi3Float64 activationTime)
{
    (void)clockReference;
    (void)activationTime;
    return unsupported(instance, "fmi3ActivateModelPartition", "no Scheduled Execution (" NO_CLOCKS ")");
}

/* ---------------------------------------------------------------------------------------------
 * Event Mode (the models have no events)
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                              fmi3Boolean *terminateSimulation,
                                              fmi3Boolean *nominalsOfContinuousStatesChanged,
                                              fmi3Boolean *valuesOfContinuousStatesChanged,
                                              fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime)
{
    static const char fn[] = "fmi3UpdateDiscreteStates";
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "%s()", fn);
    if (!rt_allowed(in, fn, BIT(ST_EVENT), IF_ANY)) return fmi3Error;
    if (!rt_not_null(in, fn, "discreteStatesNeedUpdate", discreteStatesNeedUpdate) ||
        !rt_not_null(in, fn, "terminateSimulation", terminateSimulation) ||
        !rt_not_null(in, fn, "nominalsOfContinuousStatesChanged", nominalsOfContinuousStatesChanged) ||
        !rt_not_null(in, fn, "valuesOfContinuousStatesChanged", valuesOfContinuousStatesChanged) ||
        !rt_not_null(in, fn, "nextEventTimeDefined", nextEventTimeDefined) ||
        !rt_not_null(in, fn, "nextEventTime", nextEventTime))
        return fmi3Error;
    *discreteStatesNeedUpdate = false;
    *terminateSimulation = false;
    *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = false;
    *nextEventTimeDefined = false;
    *nextEventTime = 0.0;
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------------
 * Model Exchange
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3EnterContinuousTimeMode()");
    if (!rt_allowed(in, "fmi3EnterContinuousTimeMode", BIT(ST_EVENT), RT_ME)) return fmi3Error;
    in->s.state = ST_CONT;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                                 fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    rt_instance *in = (rt_instance *)instance;

    (void)noSetFMUStatePriorToCurrentPoint;
    rt_log_call(in, "fmi3CompletedIntegratorStep()");
    if (!rt_allowed(in, "fmi3CompletedIntegratorStep", BIT(ST_CONT), RT_ME)) return fmi3Error;
    if (!rt_not_null(in, "fmi3CompletedIntegratorStep", "enterEventMode", enterEventMode) ||
        !rt_not_null(in, "fmi3CompletedIntegratorStep", "terminateSimulation", terminateSimulation))
        return fmi3Error;
    *enterEventMode = false;
    *terminateSimulation = false;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3SetTime(time = %.16g)", time);
    if (!rt_allowed(in, "fmi3SetTime", BIT(ST_EVENT) | BIT(ST_CONT), RT_ME)) return fmi3Error;
    return rt_set_time(in, "fmi3SetTime", time) ? fmi3OK : fmi3Error;
}

RT_EXPORT fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                             size_t nContinuousStates)
{
    static const char fn[] = "fmi3SetContinuousStates";
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "%s(nContinuousStates = %zu)", fn, nContinuousStates);
    if (!rt_allowed(in, fn, BIT(ST_CONT), RT_ME)) return fmi3Error;
    if (!rt_check_length(in, fn, "nContinuousStates", nContinuousStates, in->nx)) return fmi3Error;
    if (nContinuousStates == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "continuousStates", continuousStates)) return fmi3Error;
    memcpy(XV(in), continuousStates, nContinuousStates * sizeof(double));
    in->s.eval_dirty = 1;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                                       size_t nContinuousStates)
{
    static const char fn[] = "fmi3GetContinuousStateDerivatives";
    rt_instance *in = (rt_instance *)instance;
    rt_status status = RT_OK;

    rt_log_call(in, "%s(nContinuousStates = %zu)", fn, nContinuousStates);
    if (!rt_allowed(in, fn, M_ME_GET, RT_ME)) return fmi3Error;
    if (!rt_check_length(in, fn, "nContinuousStates", nContinuousStates, in->nx)) return fmi3Error;
    if (nContinuousStates == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "derivatives", derivatives)) return fmi3Error;
    if (in->s.state != ST_ERROR) status = rt_update_outputs(in, fn);
    if (status == RT_ERROR) return fmi3Error;
    memcpy(derivatives, DXV(in), nContinuousStates * sizeof(double)); /* for diagnosis, also with fmi3Discard */
    return (fmi3Status)status;
}

RT_EXPORT fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                            size_t nEventIndicators)
{
    rt_instance *in = (rt_instance *)instance;

    (void)eventIndicators;
    rt_log_call(in, "fmi3GetEventIndicators(nEventIndicators = %zu)", nEventIndicators);
    if (!rt_allowed(in, "fmi3GetEventIndicators", M_ME_GET, RT_ME)) return fmi3Error;
    return rt_check_length(in, "fmi3GetEventIndicators", "nEventIndicators", nEventIndicators, 0) ? fmi3OK
                                                                                                 : fmi3Error;
}

RT_EXPORT fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                             size_t nContinuousStates)
{
    static const char fn[] = "fmi3GetContinuousStates";
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "%s(nContinuousStates = %zu)", fn, nContinuousStates);
    if (!rt_allowed(in, fn, M_ME_GET, RT_ME)) return fmi3Error;
    if (!rt_check_length(in, fn, "nContinuousStates", nContinuousStates, in->nx)) return fmi3Error;
    if (nContinuousStates == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "continuousStates", continuousStates)) return fmi3Error;
    if (in->s.state != ST_ERROR && !rt_update_parameters(in, fn)) return fmi3Error;
    memcpy(continuousStates, XV(in), nContinuousStates * sizeof(double));
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                                       size_t nContinuousStates)
{
    static const char fn[] = "fmi3GetNominalsOfContinuousStates";
    rt_instance *in = (rt_instance *)instance;
    size_t i;

    rt_log_call(in, "%s(nContinuousStates = %zu)", fn, nContinuousStates);
    if (!rt_allowed(in, fn, BIT(ST_INSTANTIATED) | M_ME_GET, RT_ME)) return fmi3Error;
    if (!rt_check_length(in, fn, "nContinuousStates", nContinuousStates, in->nx)) return fmi3Error;
    if (nContinuousStates == 0) return fmi3OK;
    if (!rt_not_null(in, fn, "nominals", nominals)) return fmi3Error;
    for (i = 0; i < nContinuousStates; i++) nominals[i] = 1.0;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3GetNumberOfEventIndicators()");
    if (!rt_allowed(in, "fmi3GetNumberOfEventIndicators", M_ALIVE, IF_ANY)) return fmi3Error;
    if (!rt_not_null(in, "fmi3GetNumberOfEventIndicators", "nEventIndicators", nEventIndicators)) return fmi3Error;
    *nEventIndicators = 0;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3GetNumberOfContinuousStates()");
    if (!rt_allowed(in, "fmi3GetNumberOfContinuousStates", M_ALIVE, IF_ANY)) return fmi3Error;
    if (!rt_not_null(in, "fmi3GetNumberOfContinuousStates", "nContinuousStates", nContinuousStates))
        return fmi3Error;
    *nContinuousStates = in->nx;
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------------
 * Co-Simulation
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    rt_instance *in = (rt_instance *)instance;

    rt_log_call(in, "fmi3EnterStepMode()");
    if (!rt_allowed(in, "fmi3EnterStepMode", BIT(ST_EVENT), RT_CS)) return fmi3Error;
    in->s.state = ST_STEP_COMPLETE;
    return fmi3OK;
}

RT_EXPORT fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                              size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                              size_t nValues)
{
    rt_instance *in = (rt_instance *)instance;

    (void)orders;
    (void)values;
    (void)nValues;
    rt_log_call(in, "fmi3GetOutputDerivatives(nValueReferences = %zu)", nValueReferences);
    if (!rt_allowed(in, "fmi3GetOutputDerivatives", BIT(ST_STEP_COMPLETE) | BIT(ST_STEP_FAILED) |
                    BIT(ST_TERMINATED) | BIT(ST_ERROR), RT_CS))
        return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    rt_log_error(in, "fmi3GetOutputDerivatives: output derivatives are not provided (maxOutputDerivativeOrder = 0; "
                 "value reference %u)", valueReferences ? valueReferences[0] : 0u);
    return fmi3Error;
}

RT_EXPORT fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                                fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                                fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    static const char fn[] = "fmi3DoStep";
    rt_instance *in = (rt_instance *)instance;
    rt_status status;
    double t, t_end;

    (void)noSetFMUStatePriorToCurrentPoint;
    rt_log_call(in, "%s(currentCommunicationPoint = %.16g, communicationStepSize = %.16g)", fn,
                currentCommunicationPoint, communicationStepSize);
    if (!rt_allowed(in, fn, BIT(ST_STEP_COMPLETE), RT_CS)) return fmi3Error;
    if (!rt_not_null(in, fn, "eventHandlingNeeded", eventHandlingNeeded) ||
        !rt_not_null(in, fn, "terminateSimulation", terminateSimulation) ||
        !rt_not_null(in, fn, "earlyReturn", earlyReturn) ||
        !rt_not_null(in, fn, "lastSuccessfulTime", lastSuccessfulTime))
        return fmi3Error;
    t = in->s.time;
    /* the step is refused (nothing computed, the instance unchanged): */
    *eventHandlingNeeded = false;
    *terminateSimulation = false;
    *earlyReturn = false;
    *lastSuccessfulTime = t;
    if (!isfinite(currentCommunicationPoint) ||
        rt_abs(currentCommunicationPoint - t) > 1e-12 * rt_max(1.0, rt_abs(t))) {
        rt_log_error(in, "%s: currentCommunicationPoint = %.16g differs from the FMU's time %.16g", fn,
                     currentCommunicationPoint, t);
        return fmi3Error;
    }
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize)) {
        rt_log_error(in, "%s: communicationStepSize = %.16g must be finite and > 0", fn, communicationStepSize);
        return fmi3Error;
    }
    t_end = currentCommunicationPoint + communicationStepSize;
    if (in->s.stop_defined && t_end > in->s.stop_time + rt_stop_allowance(in)) {
        rt_log_error(in, "%s: the step from t = %.16g with communicationStepSize = %.16g ends at t = %.16g, "
                     "after stopTime = %.16g of fmi3EnterInitializationMode", fn, currentCommunicationPoint,
                     communicationStepSize, t_end, in->s.stop_time);
        return fmi3Error;
    }
    status = rt_do_step(in, fn, t_end);
    /* the end of the step, or after fmi3Discard the time the failed step reached: the FMU cannot
       continue past it by itself (a master may still redo the step from an earlier FMU state) */
    *lastSuccessfulTime = in->s.time;
    *terminateSimulation = status == RT_DISCARD;
    return (fmi3Status)status;
}
