/*
 * fmi2_api.c -- the FMI 2.0 API of the FMUs built by `cosim build`: the 44 fmi2* functions on the
 * version-independent core (cosim_runtime.c).  One binary serves both ModelExchange and
 * CoSimulation.
 *
 * This file adds to the core
 *   - the FMI 2.0 state machine: which call is allowed in which state (the masks below follow the
 *     state tables of FMI 2.0, 3.2.3 for ModelExchange and 4.2.4 for CoSimulation),
 *   - the FMI 2.0 types, callbacks and logger (whose message is a format string: '%' and '#' are
 *     doubled),
 *   - the CoSimulation status functions and input derivatives.
 * Conventions as in cosim_runtime.c; in particular an integration failure inside fmi2DoStep
 * returns fmi2Discard and moves the instance to stepFailed at the last successful time, which
 * fmi2GetRealStatus(fmi2LastSuccessfulTime) returns; fmi2GetBooleanStatus(fmi2Terminated) is then
 * fmi2True.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* A binary FMU exports the plain fmi2* names. */
#undef FMI2_FUNCTION_PREFIX
#include "fmi2Functions.h"
#include "cosim_runtime.h"

/* The core's status and interface type are fmi2's, value for value. */
typedef char rt_status_is_fmi2[(RT_OK == (int)fmi2OK && RT_WARNING == (int)fmi2Warning &&
                                RT_DISCARD == (int)fmi2Discard && RT_ERROR == (int)fmi2Error &&
                                RT_ME == (int)fmi2ModelExchange && RT_CS == (int)fmi2CoSimulation) ? 1 : -1];

static const char *const STATE_NAMES[ST_COUNT] = {
    "instantiated", "initializationMode", "eventMode", "continuousTimeMode",
    "stepComplete", "stepFailed", "terminated", "error", "fatal"
};

static const char *const TYPE_NAMES[3] = { "Real", "Integer", "Boolean" };

static const rt_words WORDS = {
    STATE_NAMES, TYPE_NAMES, "fmi2ExitInitializationMode", "fmi2SetContinuousStates", "fmi2Discard", 1
};

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

/* An FMI 2.0 instance: the core's instance (first, so that an fmi2Component is both) and the
   environment's callbacks. */
typedef struct {
    rt_instance rt;
    fmi2CallbackFunctions cb;
} fmi2_instance;

/* ---------------------------------------------------------------------------------------------
 * Logging
 * ------------------------------------------------------------------------------------------- */

/* Passes a finished message to the FMI 2 logger, which treats it as a format string and '#' as
   the start of a variable reference: literal '%' and '#' are doubled. */
static void fmi2_emit(const fmi2CallbackFunctions *cb, const char *instance_name, rt_status status,
                      const char *category, const char *raw)
{
    char msg[2048];
    size_t i, j = 0;

    if (!cb || !cb->logger) return;
    for (i = 0; raw[i] != '\0' && j + 2 < sizeof msg; i++) {
        if (raw[i] == '%' || raw[i] == '#') msg[j++] = raw[i];
        msg[j++] = raw[i];
    }
    msg[j] = '\0';
    cb->logger(cb->componentEnvironment, instance_name, (fmi2Status)status, category, msg);
}

/* The core's log callback: env is the fmi2_instance. */
static void fmi2_logger(void *env, const char *instance_name, rt_status status, const char *category,
                        const char *message)
{
    fmi2_emit(&((const fmi2_instance *)env)->cb, instance_name, status, category, message);
}

/* Logging before an instance exists (fmi2Instantiate). */
static void RT_PRINTF(3, 4) log_raw(const fmi2CallbackFunctions *cb, const char *instance_name,
                                    const char *fmt, ...)
{
    char raw[1024];
    va_list ap;

    va_start(ap, fmt);
    rt_vformat(raw, sizeof raw, fmt, ap);
    va_end(ap);
    fmi2_emit(cb, instance_name ? instance_name : "", RT_ERROR, "logStatusError", raw);
}

/* ---------------------------------------------------------------------------------------------
 * Common functions
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

RT_EXPORT const char *fmi2GetVersion(void) { return fmi2Version; }

RT_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                                         const fmi2String categories[])
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SetDebugLogging(loggingOn = %d, nCategories = %zu)", loggingOn, nCategories);
    if (!rt_allowed(in, "fmi2SetDebugLogging", M_ALIVE, IF_ANY)) return fmi2Error;
    return rt_set_category(in, "fmi2SetDebugLogging", loggingOn != fmi2False, nCategories, categories)
           ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                        fmi2String fmuResourceLocation,
                                        const fmi2CallbackFunctions *functions,
                                        fmi2Boolean visible, fmi2Boolean loggingOn)
{
    fmi2_instance *fi;
    rt_instance *in;
    rt_config cfg;
    const char *problem;

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
    problem = rt_model_problem();
    if (problem) {
        log_raw(functions, instanceName, "fmi2Instantiate: invalid model code: %s", problem);
        return NULL;
    }

    fi = (fmi2_instance *)functions->allocateMemory(1, sizeof(fmi2_instance));
    if (!fi) {
        log_raw(functions, instanceName, "fmi2Instantiate: out of memory");
        return NULL;
    }
    memset(fi, 0, sizeof *fi);
    fi->cb = *functions;
    in = &fi->rt;
    cfg.alloc = functions->allocateMemory;
    cfg.free = functions->freeMemory;
    cfg.log = fmi2_logger;
    cfg.log_env = fi;
    cfg.words = &WORDS;
    cfg.kind = fmuType == fmi2ModelExchange ? RT_ME : RT_CS;
    cfg.log_calls = loggingOn != fmi2False;
    if (!rt_init(in, &cfg, instanceName)) {
        log_raw(functions, instanceName, "fmi2Instantiate: out of memory");
        rt_release(in);
        functions->freeMemory(fi);
        return NULL;
    }
    rt_check_fixed_step(in, "fmi2Instantiate");
    rt_reset(in);
    rt_log_call(in, "fmi2Instantiate(instanceName = %s, fmuType = %s)", instanceName, rt_kind_name(in->kind));
    return fi;
}

RT_EXPORT void fmi2FreeInstance(fmi2Component c)
{
    fmi2_instance *fi = (fmi2_instance *)c;
    if (!fi) return;
    rt_log_call(&fi->rt, "fmi2FreeInstance()");
    rt_release(&fi->rt);
    fi->cb.freeMemory(fi);
}

RT_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                         fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SetupExperiment(toleranceDefined = %d, tolerance = %g, startTime = %.16g, "
                "stopTimeDefined = %d, stopTime = %.16g)", toleranceDefined, tolerance, startTime,
                stopTimeDefined, stopTime);
    if (!rt_allowed(in, "fmi2SetupExperiment", BIT(ST_INSTANTIATED), IF_ANY)) return fmi2Error;
    return rt_setup(in, "fmi2SetupExperiment", toleranceDefined != fmi2False, tolerance, startTime,
                    stopTimeDefined != fmi2False, stopTime) ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2EnterInitializationMode()");
    if (!rt_allowed(in, "fmi2EnterInitializationMode", BIT(ST_INSTANTIATED), IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_enter_init(in, "fmi2EnterInitializationMode");
}

RT_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2ExitInitializationMode()");
    if (!rt_allowed(in, "fmi2ExitInitializationMode", BIT(ST_INIT), IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_exit_init(in, "fmi2ExitInitializationMode",
                                    in->kind == RT_ME ? ST_EVENT : ST_STEP_COMPLETE);
}

RT_EXPORT fmi2Status fmi2Terminate(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2Terminate()");
    if (!rt_allowed(in, "fmi2Terminate", M_TERMINATE, IF_ANY)) return fmi2Error;
    in->s.state = ST_TERMINATED;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2Reset(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2Reset()");
    if (!rt_allowed(in, "fmi2Reset", M_ALIVE, IF_ANY)) return fmi2Error;
    rt_reset(in);
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------------
 * Getters and setters
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;
    rt_status status;
    size_t i;

    rt_log_call(in, "fmi2GetReal(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2GetReal", M_GET, IF_ANY)) return fmi2Error;
    status = rt_prepare_get(in, "fmi2GetReal", vr, nvr, value, COSIM_REAL);
    if (status == RT_ERROR) return fmi2Error;
    for (i = 0; i < nvr; i++) value[i] = in->s.v[rt_index(in, vr[i])]; /* for diagnosis, also with fmi2Discard */
    return (fmi2Status)status;
}

RT_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    rt_instance *in = (rt_instance *)c;
    rt_status status;
    size_t i;

    rt_log_call(in, "fmi2GetInteger(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2GetInteger", M_GET, IF_ANY)) return fmi2Error;
    status = rt_prepare_get(in, "fmi2GetInteger", vr, nvr, value, COSIM_INTEGER);
    if (status == RT_ERROR) return fmi2Error;
    for (i = 0; i < nvr; i++) value[i] = rt_to_integer(in->s.v[rt_index(in, vr[i])]); /* for diagnosis, also with fmi2Discard */
    return (fmi2Status)status;
}

RT_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    rt_instance *in = (rt_instance *)c;
    rt_status status;
    size_t i;

    rt_log_call(in, "fmi2GetBoolean(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2GetBoolean", M_GET, IF_ANY)) return fmi2Error;
    status = rt_prepare_get(in, "fmi2GetBoolean", vr, nvr, value, COSIM_BOOLEAN);
    if (status == RT_ERROR) return fmi2Error;
    /* for diagnosis, also with fmi2Discard */
    for (i = 0; i < nvr; i++) value[i] = in->s.v[rt_index(in, vr[i])] != 0.0 ? fmi2True : fmi2False;
    return (fmi2Status)status;
}

RT_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    rt_log_call(in, "fmi2GetString(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2GetString", M_GET, IF_ANY)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    rt_log_error(in, "fmi2GetString: the model has no String variables (value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

/* Checks a whole Set call before anything is changed (value: n doubles, or the typed values
   converted by the caller). */
static int prepare_set(const rt_instance *in, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                       const void *value, cosim_type type)
{
    size_t i;

    if (nvr == 0) return 1;
    if (!rt_not_null(in, fn, "vr", vr) || !rt_not_null(in, fn, "value", value)) return 0;
    for (i = 0; i < nvr; i++) {
        double v;
        if (type == COSIM_REAL) v = ((const fmi2Real *)value)[i];
        else if (type == COSIM_INTEGER) v = (double)((const fmi2Integer *)value)[i];
        else v = ((const fmi2Boolean *)value)[i] ? 1.0 : 0.0;
        if (!rt_check_set(in, fn, vr[i], type, v)) return 0;
    }
    return 1;
}

RT_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    rt_log_call(in, "fmi2SetReal(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2SetReal", M_SET_REAL, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetReal", vr, nvr, value, COSIM_REAL)) return fmi2Error;
    for (i = 0; i < nvr; i++) rt_store(in, vr[i], value[i]);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    rt_log_call(in, "fmi2SetInteger(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2SetInteger", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetInteger", vr, nvr, value, COSIM_INTEGER)) return fmi2Error;
    for (i = 0; i < nvr; i++) rt_store(in, vr[i], (double)value[i]);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    rt_log_call(in, "fmi2SetBoolean(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2SetBoolean", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (!prepare_set(in, "fmi2SetBoolean", vr, nvr, value, COSIM_BOOLEAN)) return fmi2Error;
    for (i = 0; i < nvr; i++) rt_store(in, vr[i], value[i] ? 1.0 : 0.0);
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    rt_log_call(in, "fmi2SetString(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2SetString", M_SET_DISCRETE, IF_ANY)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    rt_log_error(in, "fmi2SetString: the model has no String variables (value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

/* ---------------------------------------------------------------------------------------------
 * FMU states
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2GetFMUstate()");
    if (!rt_allowed(in, "fmi2GetFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_get_state(in, "fmi2GetFMUstate", FMUstate);
}

RT_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SetFMUstate()");
    if (!rt_allowed(in, "fmi2SetFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_set_state(in, "fmi2SetFMUstate", FMUstate);
}

RT_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2FreeFMUstate()");
    if (!rt_allowed(in, "fmi2FreeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_free_state(in, "fmi2FreeFMUstate", FMUstate);
}

RT_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SerializedFMUstateSize()");
    if (!rt_allowed(in, "fmi2SerializedFMUstateSize", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_serialized_size(in, "fmi2SerializedFMUstateSize", FMUstate, size);
}

RT_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                           size_t size)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SerializeFMUstate(size = %zu)", size);
    if (!rt_allowed(in, "fmi2SerializeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_serialize(in, "fmi2SerializeFMUstate", FMUstate, (unsigned char *)serializedState, size);
}

RT_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                             fmi2FMUstate *FMUstate)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2DeSerializeFMUstate(size = %zu)", size);
    if (!rt_allowed(in, "fmi2DeSerializeFMUstate", M_ALIVE, IF_ANY)) return fmi2Error;
    return (fmi2Status)rt_deserialize(in, "fmi2DeSerializeFMUstate", (const unsigned char *)serializedState, size,
                                      FMUstate);
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

    rt_log_call(in, "%s(nUnknown = %zu, nKnown = %zu)", fn, nUnknown, nKnown);
    if (!rt_allowed(in, fn, M_DIR_DER, IF_ANY)) return fmi2Error;
    if (nUnknown == 0) return fmi2OK;
    if (!rt_not_null(in, fn, "vUnknown_ref", vUnknown_ref) || !rt_not_null(in, fn, "dvUnknown", dvUnknown))
        return fmi2Error;
    if (nKnown > 0 && (!rt_not_null(in, fn, "vKnown_ref", vKnown_ref) || !rt_not_null(in, fn, "dvKnown", dvKnown)))
        return fmi2Error;
    return (fmi2Status)rt_directional(in, fn, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown, dvUnknown);
}

/* ---------------------------------------------------------------------------------------------
 * Model Exchange
 * ------------------------------------------------------------------------------------------- */

RT_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2EnterEventMode()");
    if (!rt_allowed(in, "fmi2EnterEventMode", M_ME_RUNNING, fmi2ModelExchange)) return fmi2Error;
    in->s.state = ST_EVENT;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2NewDiscreteStates()");
    if (!rt_allowed(in, "fmi2NewDiscreteStates", BIT(ST_EVENT), fmi2ModelExchange)) return fmi2Error;
    if (!rt_not_null(in, "fmi2NewDiscreteStates", "eventInfo", eventInfo)) return fmi2Error;
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

    rt_log_call(in, "fmi2EnterContinuousTimeMode()");
    if (!rt_allowed(in, "fmi2EnterContinuousTimeMode", BIT(ST_EVENT), fmi2ModelExchange)) return fmi2Error;
    in->s.state = ST_CONT;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                                 fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    rt_instance *in = (rt_instance *)c;

    (void)noSetFMUStatePriorToCurrentPoint;
    rt_log_call(in, "fmi2CompletedIntegratorStep()");
    if (!rt_allowed(in, "fmi2CompletedIntegratorStep", BIT(ST_CONT), fmi2ModelExchange)) return fmi2Error;
    if (!rt_not_null(in, "fmi2CompletedIntegratorStep", "enterEventMode", enterEventMode) ||
        !rt_not_null(in, "fmi2CompletedIntegratorStep", "terminateSimulation", terminateSimulation))
        return fmi2Error;
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SetTime(time = %.16g)", time);
    if (!rt_allowed(in, "fmi2SetTime", M_ME_RUNNING, fmi2ModelExchange)) return fmi2Error;
    return rt_set_time(in, "fmi2SetTime", time) ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2SetContinuousStates(nx = %zu)", nx);
    if (!rt_allowed(in, "fmi2SetContinuousStates", BIT(ST_CONT), fmi2ModelExchange)) return fmi2Error;
    if (!rt_check_length(in, "fmi2SetContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!rt_not_null(in, "fmi2SetContinuousStates", "x", x)) return fmi2Error;
    memcpy(XV(in), x, nx * sizeof(double));
    in->s.eval_dirty = 1;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;
    rt_status status = RT_OK;

    rt_log_call(in, "fmi2GetDerivatives(nx = %zu)", nx);
    if (!rt_allowed(in, "fmi2GetDerivatives", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    if (!rt_check_length(in, "fmi2GetDerivatives", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!rt_not_null(in, "fmi2GetDerivatives", "derivatives", derivatives)) return fmi2Error;
    if (in->s.state != ST_ERROR) status = rt_update_outputs(in, "fmi2GetDerivatives");
    if (status == RT_ERROR) return fmi2Error;
    memcpy(derivatives, DXV(in), nx * sizeof(double)); /* for diagnosis, also with fmi2Discard */
    return (fmi2Status)status;
}

RT_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    rt_instance *in = (rt_instance *)c;

    (void)eventIndicators;
    rt_log_call(in, "fmi2GetEventIndicators(ni = %zu)", ni);
    if (!rt_allowed(in, "fmi2GetEventIndicators", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    return rt_check_length(in, "fmi2GetEventIndicators", "ni", ni, 0) ? fmi2OK : fmi2Error;
}

RT_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2GetContinuousStates(nx = %zu)", nx);
    if (!rt_allowed(in, "fmi2GetContinuousStates", M_ME_GET, fmi2ModelExchange)) return fmi2Error;
    if (!rt_check_length(in, "fmi2GetContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!rt_not_null(in, "fmi2GetContinuousStates", "x", x)) return fmi2Error;
    if (in->s.state != ST_ERROR && !rt_update_parameters(in, "fmi2GetContinuousStates")) return fmi2Error;
    memcpy(x, XV(in), nx * sizeof(double));
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    rt_instance *in = (rt_instance *)c;
    size_t i;

    rt_log_call(in, "fmi2GetNominalsOfContinuousStates(nx = %zu)", nx);
    if (!rt_allowed(in, "fmi2GetNominalsOfContinuousStates", BIT(ST_INSTANTIATED) | M_ME_GET, fmi2ModelExchange))
        return fmi2Error;
    if (!rt_check_length(in, "fmi2GetNominalsOfContinuousStates", "nx", nx, in->nx)) return fmi2Error;
    if (nx == 0) return fmi2OK;
    if (!rt_not_null(in, "fmi2GetNominalsOfContinuousStates", "x_nominal", x_nominal)) return fmi2Error;
    for (i = 0; i < nx; i++) x_nominal[i] = 1.0;
    return fmi2OK;
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

    rt_log_call(in, "%s(nvr = %zu)", fn, nvr);
    if (!rt_allowed(in, fn, M_BEFORE_EXIT | BIT(ST_STEP_COMPLETE), fmi2CoSimulation)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    if (!rt_not_null(in, fn, "vr", vr) || !rt_not_null(in, fn, "order", order) ||
        !rt_not_null(in, fn, "value", value))
        return fmi2Error;
    for (i = 0; i < nvr; i++) {
        char label[160];
        if (!rt_check_vr(in, fn, vr[i], COSIM_REAL)) return fmi2Error;
        if (rt_block_of(in, rt_index(in, vr[i])) != B_U) {
            rt_log_error(in, "%s: value reference %u is not an input", fn, vr[i]);
            return fmi2Error;
        }
        if (order[i] != 1) {
            rt_log_error(in, "%s: order %d for value reference %u is not supported (maxInputDerivativeOrder = 1)",
                         fn, (int)order[i], vr[i]);
            return fmi2Error;
        }
        if (!isfinite(value[i])) {
            rt_log_error(in, "%s: the derivative of %s = %g: the value must be finite", fn,
                         rt_vr_label(in, rt_index(in, vr[i]), label, sizeof label), value[i]);
            return fmi2Error;
        }
    }
    for (i = 0; i < nvr; i++) in->s.du[rt_index(in, vr[i]) - in->o_u] = value[i];
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                  const fmi2Integer order[], fmi2Real value[])
{
    rt_instance *in = (rt_instance *)c;

    (void)order;
    (void)value;
    rt_log_call(in, "fmi2GetRealOutputDerivatives(nvr = %zu)", nvr);
    if (!rt_allowed(in, "fmi2GetRealOutputDerivatives", M_CS_STATUS | BIT(ST_ERROR), fmi2CoSimulation))
        return fmi2Error;
    if (nvr == 0) return fmi2OK;
    rt_log_error(in, "fmi2GetRealOutputDerivatives: output derivatives are not provided "
                 "(maxOutputDerivativeOrder = 0; value reference %u)", vr ? vr[0] : 0u);
    return fmi2Error;
}

RT_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    rt_instance *in = (rt_instance *)c;
    double t, t_end;

    (void)noSetFMUStatePriorToCurrentPoint;
    rt_log_call(in, "fmi2DoStep(currentCommunicationPoint = %.16g, communicationStepSize = %.16g)",
                currentCommunicationPoint, communicationStepSize);
    if (!rt_allowed(in, "fmi2DoStep", BIT(ST_STEP_COMPLETE), fmi2CoSimulation)) return fmi2Error;
    t = in->s.time;
    if (!isfinite(currentCommunicationPoint) ||
        rt_abs(currentCommunicationPoint - t) > 1e-12 * rt_max(1.0, rt_abs(t))) {
        rt_log_error(in, "fmi2DoStep: currentCommunicationPoint = %.16g differs from the FMU's time %.16g",
                     currentCommunicationPoint, t);
        return fmi2Error;
    }
    if (communicationStepSize == 0.0) {
        rt_log_error(in, "fmi2DoStep: communicationStepSize = 0 at t = %.16g: a step of size 0 is an event "
                     "iteration in FMI 2.0, which this FMU does not support (it has no events); the step size "
                     "must be > 0", t);
        return fmi2Error;
    }
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize)) {
        rt_log_error(in, "fmi2DoStep: communicationStepSize = %.16g must be finite and > 0", communicationStepSize);
        return fmi2Error;
    }
    t_end = currentCommunicationPoint + communicationStepSize;
    if (in->s.stop_defined && t_end > in->s.stop_time + rt_stop_allowance(in)) {
        rt_log_error(in, "fmi2DoStep: the step from t = %.16g with communicationStepSize = %.16g ends at t = %.16g, "
                     "after stopTime = %.16g of fmi2SetupExperiment", currentCommunicationPoint,
                     communicationStepSize, t_end, in->s.stop_time);
        return fmi2Error;
    }
    return (fmi2Status)rt_do_step(in, "fmi2DoStep", t_end);
}

RT_EXPORT fmi2Status fmi2CancelStep(fmi2Component c)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2CancelStep()");
    if (!rt_allowed(in, "fmi2CancelStep", M_ALIVE, fmi2CoSimulation)) return fmi2Error;
    rt_log_error(in, "fmi2CancelStep: not supported: fmi2DoStep always completes synchronously");
    return fmi2Error;
}

/* The status kinds that do not apply to a synchronous slave. */
static fmi2Status no_status(const rt_instance *in, const char *fn, fmi2StatusKind s)
{
    rt_log_warning(in, RT_DISCARD, "%s: status kind %d is not applicable (fmi2DoStep never returns fmi2Pending)",
                   fn, (int)s);
    return fmi2Discard;
}

RT_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2GetStatus(s = %d)", (int)s);
    if (!rt_allowed(in, "fmi2GetStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!rt_not_null(in, "fmi2GetStatus", "value", value)) return fmi2Error;
    if (s != fmi2DoStepStatus) return no_status(in, "fmi2GetStatus", s);
    /* the status of the last fmi2DoStep: it returns synchronously, never fmi2Pending */
    *value = in->s.state == ST_STEP_FAILED ? fmi2Discard : fmi2OK;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2GetRealStatus(s = %d)", (int)s);
    if (!rt_allowed(in, "fmi2GetRealStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!rt_not_null(in, "fmi2GetRealStatus", "value", value)) return fmi2Error;
    if (s != fmi2LastSuccessfulTime) return no_status(in, "fmi2GetRealStatus", s);
    /* the end of the last step, or after fmi2Discard the time the failed step reached */
    *value = in->s.time;
    return fmi2OK;
}

RT_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    rt_instance *in = (rt_instance *)c;

    (void)value;
    rt_log_call(in, "fmi2GetIntegerStatus(s = %d)", (int)s);
    if (!rt_allowed(in, "fmi2GetIntegerStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    return no_status(in, "fmi2GetIntegerStatus", s);
}

RT_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    rt_instance *in = (rt_instance *)c;

    rt_log_call(in, "fmi2GetBooleanStatus(s = %d)", (int)s);
    if (!rt_allowed(in, "fmi2GetBooleanStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    if (!rt_not_null(in, "fmi2GetBooleanStatus", "value", value)) return fmi2Error;
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
    rt_log_call(in, "fmi2GetStringStatus(s = %d)", (int)s);
    if (!rt_allowed(in, "fmi2GetStringStatus", M_CS_STATUS, fmi2CoSimulation)) return fmi2Error;
    return no_status(in, "fmi2GetStringStatus", s);
}
