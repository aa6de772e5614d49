/*
 * wasm_api.c -- a JavaScript-friendly API on the FMI 2.0 Co-Simulation API of an FMU built by
 * `cosim build`, for the WebAssembly module that `cosim build --wasm` compiles from the FMU's own
 * C sources (generated model code + cosim_runtime.c + fmi2_api.c + cosim_tape.c) with this file.
 *
 * JavaScript cannot pass C callbacks or arrays by value, so
 *   - the FMI 2 callbacks are C functions here: memory comes from wasi-libc's calloc/free and the
 *     logger formats each message into a log buffer in the module's memory that the page reads
 *     (wasm_log_pointer, wasm_log_length) and empties (wasm_log_clear); no JavaScript callback;
 *   - values are passed one at a time by value reference (wasm_set_real(c, vr, value),
 *     wasm_get_real(c, vr)), or many at once through arrays in the module's memory
 *     (wasm_alloc, wasm_set_reals, wasm_get_reals);
 *   - a function that returns a value rather than an fmi2Status leaves the status of its FMI call
 *     in wasm_last_status() (0 fmi2OK, 1 fmi2Warning, 2 fmi2Discard, 3 fmi2Error, 4 fmi2Fatal).
 * Every other function returns the fmi2Status of the FMI 2 call it makes, unchanged.
 *
 * The value references, names and default experiment are not compiled in: `cosim build --wasm`
 * writes them into NAME.json beside NAME.wasm from the FMU's modelDescription.xml. The GUID of
 * that file is passed to wasm_instantiate, which (like fmi2Instantiate) refuses a different one,
 * so a JSON file of another model or build is caught.
 *
 * The instance is always a Co-Simulation one (the runtime's Dormand-Prince 5(4) integrator with
 * error control, or fixed steps with solver.fixedStepSize > 0): the browser has no ODE solver of
 * its own to drive a Model Exchange instance with.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define WASM_EXPORT(name) __attribute__((export_name(#name))) name

/* ---------------------------------------------------------------------------------------------
 * Log buffer: one line per message, "STATUS<TAB>CATEGORY<TAB>INSTANCE<TAB>MESSAGE\n", STATUS the
 * fmi2Status as a number; tabs, carriage returns and newlines inside the fields become spaces so
 * that a line is always one record.  When the buffer is full, further messages are counted in
 * log_dropped (wasm_log_dropped) instead of overwriting what the page has not read yet.
 * ------------------------------------------------------------------------------------------- */

#define LOG_CAPACITY 65536

static char log_buffer[LOG_CAPACITY];
static size_t log_length;
static unsigned log_dropped;
static int last_status;

/* Appends text to the record being written at *at (bounded by end), as one field. */
static void put_field(char **at, const char *end, const char *text)
{
    for (; *text != '\0' && *at < end; text++, (*at)++) {
        char ch = *text;
        **at = (ch == '\t' || ch == '\n' || ch == '\r') ? ' ' : ch;
    }
}

static void logger(fmi2ComponentEnvironment env, fmi2String instance_name, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    char formatted[4096], text[4096], record[4096 + 512];
    char *at = record;
    const char *end = record + sizeof record - 1; /* room for the newline */
    size_t i, j, n;
    va_list ap;

    (void)env;
    /* FMI 2.0 (2.1.5): the message is a format string, and "##" stands for "#" ("#r12#" would
       reference a variable; the runtime never writes one, it doubles every literal '#'). */
    va_start(ap, message);
    vsnprintf(formatted, sizeof formatted, message ? message : "", ap);
    va_end(ap);
    for (i = 0, j = 0; formatted[i] != '\0' && j + 1 < sizeof text; i++) {
        text[j++] = formatted[i];
        if (formatted[i] == '#' && formatted[i + 1] == '#') i++;
    }
    text[j] = '\0';

    snprintf(record, sizeof record, "%d\t", (int)status);
    at = record + strlen(record);
    put_field(&at, end, category ? category : "");
    if (at < end) *at++ = '\t';
    put_field(&at, end, instance_name ? instance_name : "");
    if (at < end) *at++ = '\t';
    put_field(&at, end, text);
    *at++ = '\n';
    n = (size_t)(at - record);
    if (log_length + n > LOG_CAPACITY) {
        log_dropped++;
        return;
    }
    memcpy(log_buffer + log_length, record, n);
    log_length += n;
}

/* The log lines written since the last wasm_log_clear (not NUL-terminated: read wasm_log_length
   bytes). */
const char *WASM_EXPORT(wasm_log_pointer)(void) { return log_buffer; }

size_t WASM_EXPORT(wasm_log_length)(void) { return log_length; }

/* Messages that did not fit into the buffer since the last wasm_log_clear. */
unsigned WASM_EXPORT(wasm_log_dropped)(void) { return log_dropped; }

void WASM_EXPORT(wasm_log_clear)(void)
{
    log_length = 0;
    log_dropped = 0;
}

int WASM_EXPORT(wasm_last_status)(void) { return last_status; }

/* ---------------------------------------------------------------------------------------------
 * Memory for strings and arrays passed from JavaScript
 * ------------------------------------------------------------------------------------------- */

void *WASM_EXPORT(wasm_alloc)(size_t size) { return calloc(size ? size : 1, 1); }

void WASM_EXPORT(wasm_free)(void *pointer) { free(pointer); }

/* ---------------------------------------------------------------------------------------------
 * Instances
 * ------------------------------------------------------------------------------------------- */

static const fmi2CallbackFunctions CALLBACKS = { logger, calloc, free, NULL, NULL };

/* A Co-Simulation instance (0 if fmi2Instantiate refused: the log says why).  name and guid are
   NUL-terminated UTF-8 strings in the module's memory; logging_on as fmi2Instantiate's loggingOn
   (every call logged, category logCalls). */
fmi2Component WASM_EXPORT(wasm_instantiate)(const char *name, const char *guid, int logging_on)
{
    return fmi2Instantiate(name, fmi2CoSimulation, guid, "", &CALLBACKS, fmi2False,
                           logging_on ? fmi2True : fmi2False);
}

void WASM_EXPORT(wasm_free_instance)(fmi2Component c) { fmi2FreeInstance(c); }

int WASM_EXPORT(wasm_setup_experiment)(fmi2Component c, int tolerance_defined, double tolerance,
                                       double start_time, int stop_time_defined, double stop_time)
{
    return fmi2SetupExperiment(c, tolerance_defined ? fmi2True : fmi2False, tolerance, start_time,
                               stop_time_defined ? fmi2True : fmi2False, stop_time);
}

int WASM_EXPORT(wasm_enter_initialization_mode)(fmi2Component c) { return fmi2EnterInitializationMode(c); }

int WASM_EXPORT(wasm_exit_initialization_mode)(fmi2Component c) { return fmi2ExitInitializationMode(c); }

int WASM_EXPORT(wasm_terminate)(fmi2Component c) { return fmi2Terminate(c); }

int WASM_EXPORT(wasm_reset)(fmi2Component c) { return fmi2Reset(c); }

int WASM_EXPORT(wasm_do_step)(fmi2Component c, double current_communication_point,
                              double communication_step_size, int no_set_fmu_state_prior)
{
    return fmi2DoStep(c, current_communication_point, communication_step_size,
                      no_set_fmu_state_prior ? fmi2True : fmi2False);
}

/* fmi2GetRealStatus (kind 2: fmi2LastSuccessfulTime); the status in wasm_last_status(). */
double WASM_EXPORT(wasm_get_real_status)(fmi2Component c, int kind)
{
    fmi2Real value = 0.0;
    last_status = fmi2GetRealStatus(c, (fmi2StatusKind)kind, &value);
    return value;
}

/* fmi2GetBooleanStatus (kind 3: fmi2Terminated) as 0 or 1; the status in wasm_last_status(). */
int WASM_EXPORT(wasm_get_boolean_status)(fmi2Component c, int kind)
{
    fmi2Boolean value = fmi2False;
    last_status = fmi2GetBooleanStatus(c, (fmi2StatusKind)kind, &value);
    return value != fmi2False;
}

/* ---------------------------------------------------------------------------------------------
 * Values by value reference: one at a time ...
 * ------------------------------------------------------------------------------------------- */

int WASM_EXPORT(wasm_set_real)(fmi2Component c, unsigned vr, double value)
{
    const fmi2ValueReference ref = vr;
    return fmi2SetReal(c, &ref, 1, &value);
}

/* The value (NaN if the call failed); the status in wasm_last_status(). */
double WASM_EXPORT(wasm_get_real)(fmi2Component c, unsigned vr)
{
    const fmi2ValueReference ref = vr;
    fmi2Real value = 0.0;
    last_status = fmi2GetReal(c, &ref, 1, &value);
    return last_status <= fmi2Warning ? value : __builtin_nan("");
}

int WASM_EXPORT(wasm_set_integer)(fmi2Component c, unsigned vr, int value)
{
    const fmi2ValueReference ref = vr;
    const fmi2Integer v = value;
    return fmi2SetInteger(c, &ref, 1, &v);
}

/* The value (0 if the call failed); the status in wasm_last_status(). */
int WASM_EXPORT(wasm_get_integer)(fmi2Component c, unsigned vr)
{
    const fmi2ValueReference ref = vr;
    fmi2Integer value = 0;
    last_status = fmi2GetInteger(c, &ref, 1, &value);
    return last_status <= fmi2Warning ? value : 0;
}

int WASM_EXPORT(wasm_set_boolean)(fmi2Component c, unsigned vr, int value)
{
    const fmi2ValueReference ref = vr;
    const fmi2Boolean v = value ? fmi2True : fmi2False;
    return fmi2SetBoolean(c, &ref, 1, &v);
}

/* The value as 0 or 1 (0 if the call failed); the status in wasm_last_status(). */
int WASM_EXPORT(wasm_get_boolean)(fmi2Component c, unsigned vr)
{
    const fmi2ValueReference ref = vr;
    fmi2Boolean value = fmi2False;
    last_status = fmi2GetBoolean(c, &ref, 1, &value);
    return last_status <= fmi2Warning && value != fmi2False;
}

/* ... and many at once: vrs (n unsigned 32-bit integers) and values (n doubles) are arrays in
   the module's memory (wasm_alloc), as fmi2SetReal and fmi2GetReal take them. */

int WASM_EXPORT(wasm_set_reals)(fmi2Component c, const fmi2ValueReference *vrs, size_t n, const double *values)
{
    return fmi2SetReal(c, vrs, n, values);
}

int WASM_EXPORT(wasm_get_reals)(fmi2Component c, const fmi2ValueReference *vrs, size_t n, double *values)
{
    return fmi2GetReal(c, vrs, n, values);
}

/* ---------------------------------------------------------------------------------------------
 * FMU states: rewinding a ride (the page's scrub and restart) without a new initialization
 * ------------------------------------------------------------------------------------------- */

/* A copy of the instance's state (0 if the call failed; the status in wasm_last_status()). */
fmi2FMUstate WASM_EXPORT(wasm_get_fmu_state)(fmi2Component c)
{
    fmi2FMUstate state = NULL;
    last_status = fmi2GetFMUstate(c, &state);
    return last_status <= fmi2Warning ? state : NULL;
}

int WASM_EXPORT(wasm_set_fmu_state)(fmi2Component c, fmi2FMUstate state) { return fmi2SetFMUstate(c, state); }

int WASM_EXPORT(wasm_free_fmu_state)(fmi2Component c, fmi2FMUstate state)
{
    fmi2FMUstate s = state;
    return fmi2FreeFMUstate(c, &s);
}

/* ---------------------------------------------------------------------------------------------
 * Directional derivatives: columns of the Jacobian (the page's linearization, A = d der(x)/dx)
 * ------------------------------------------------------------------------------------------- */

/* fmi2GetDirectionalDerivative: out = (d unknowns / d knowns) * seed.  unknown_vrs (n_unknown
   unsigned 32-bit integers), known_vrs (n_known), seed (n_known doubles) and out (n_unknown
   doubles) are arrays in the module's memory (wasm_alloc). */
int WASM_EXPORT(wasm_directional)(fmi2Component c, const fmi2ValueReference *unknown_vrs, size_t n_unknown,
                                  const fmi2ValueReference *known_vrs, size_t n_known, const double *seed,
                                  double *out)
{
    return fmi2GetDirectionalDerivative(c, unknown_vrs, n_unknown, known_vrs, n_known, seed, out);
}
