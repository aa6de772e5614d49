/* A small FMI 2.0 FMU (Model Exchange and Co-Simulation) that misbehaves on purpose.
 *
 * The model: der(x) = -k*x + u, y = x (x(0) = 1, k = 1). The fault is chosen at compile time:
 *
 *   -DFAULT=0   none (a well-behaved FMU: the control case)
 *   -DFAULT=1   segmentation fault          -DFAULT=2   exit(0)
 *   -DFAULT=3   abort()                     -DFAULT=4   endless loop (a hang)
 *   -DFAULT=5   SIGKILL to the parent process
 *   -DFAULT=6   the output y turns NaN (no other sign of trouble)
 *   -DFAULT=7   fmi2Instantiate returns NULL
 *
 * and where it strikes: -DWHERE=0 in fmi2Instantiate, -DWHERE=1 in fmi2DoStep and
 * fmi2GetDerivatives once the time reaches FAULT_TIME (default 0.5 s), -DWHERE=2 in
 * fmi2ExitInitializationMode. The test suite compiles one binary per case with gcc. */
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fmi2Functions.h"

#ifndef FAULT
#define FAULT 0
#endif
#ifndef WHERE
#define WHERE 1
#endif
#ifndef FAULT_TIME
#define FAULT_TIME 0.5
#endif

enum { VR_X = 0, VR_DER_X = 1, VR_K = 2, VR_U = 3, VR_Y = 4 };

typedef struct {
    double time, x, k, u;
    const fmi2CallbackFunctions *callbacks;
} Model;

/* A null pointer the compiler cannot see through (else it may drop the store as undefined). */
static int *volatile nowhere;

static void strike(void) {
    switch (FAULT) {
    case 1: *nowhere = 1; break;
    case 2: exit(0);
    case 3: abort();
    case 4: for (volatile unsigned long i = 0;; i++) { } break;
    case 5: kill(getppid(), SIGKILL); sleep(60); break;
    default: break;
    }
}

static void strike_at(const Model *m) {
    if (WHERE == 1 && m->time >= FAULT_TIME) strike();
}

static double output(const Model *m) {
    if (FAULT == 6 && m->time >= FAULT_TIME) return NAN;
    return m->x;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cat[]) { return fmi2OK; }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String location,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean logging) {
    if (WHERE == 0) strike();
    if (FAULT == 7) return NULL;
    Model *m = calloc(1, sizeof(Model));
    m->x = 1.0;
    m->k = 1.0;
    m->callbacks = callbacks;
    return m;
}

void fmi2FreeInstance(fmi2Component c) { free(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol, fmi2Real start,
                               fmi2Boolean stopDefined, fmi2Real stop) {
    ((Model *)c)->time = start;
    return fmi2OK;
}
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    if (WHERE == 2) strike();
    return fmi2OK;
}
fmi2Status fmi2Terminate(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) {
    Model *m = c;
    m->x = 1.0; m->k = 1.0; m->u = 0.0; m->time = 0.0;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
    Model *m = c;
    for (size_t i = 0; i < n; i++) {
        switch (vr[i]) {
        case VR_X: value[i] = m->x; break;
        case VR_DER_X: value[i] = -m->k * m->x + m->u; break;
        case VR_K: value[i] = m->k; break;
        case VR_U: value[i] = m->u; break;
        case VR_Y: value[i] = output(m); break;
        default: return fmi2Error;
        }
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
    Model *m = c;
    for (size_t i = 0; i < n; i++) {
        switch (vr[i]) {
        case VR_X: m->x = value[i]; break;
        case VR_K: m->k = value[i]; break;
        case VR_U: m->u = value[i]; break;
        default: return fmi2Error;
        }
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) { return n ? fmi2Error : fmi2OK; }
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) { return n ? fmi2Error : fmi2OK; }
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) { return n ? fmi2Error : fmi2OK; }
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { return n ? fmi2Error : fmi2OK; }
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { return n ? fmi2Error : fmi2OK; }
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) { return n ? fmi2Error : fmi2OK; }

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { return fmi2Error; }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { return fmi2Error; }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { return fmi2Error; }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) { return fmi2Error; }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t size) { return fmi2Error; }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t size, fmi2FMUstate *s) { return fmi2Error; }
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz, const fmi2Real dv[], fmi2Real dz[]) {
    return fmi2Error;
}

/* Model Exchange */
fmi2Status fmi2EnterEventMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    memset(info, 0, sizeof(*info));
    return fmi2OK;
}
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSet, fmi2Boolean *enter, fmi2Boolean *terminate) {
    *enter = fmi2False;
    *terminate = fmi2False;
    return fmi2OK;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) {
    ((Model *)c)->time = t;
    return fmi2OK;
}
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    ((Model *)c)->x = x[0];
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Model *m = c;
    strike_at(m);
    dx[0] = -m->k * m->x + m->u;
    if (FAULT == 6 && m->time >= FAULT_TIME) dx[0] = NAN;
    return fmi2OK;
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t nz) { return fmi2OK; }
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    x[0] = ((Model *)c)->x;
    return fmi2OK;
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real n[], size_t nx) {
    n[0] = 1.0;
    return fmi2OK;
}

/* Co-Simulation: explicit Euler in 100 sub-steps */
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[]) { return fmi2Error; }
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[]) { return fmi2Error; }
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Model *m = c;
    m->time = t;
    strike_at(m);
    for (int i = 0; i < 100; i++) m->x += h / 100 * (-m->k * m->x + m->u);
    m->time = t + h;
    return fmi2OK;
}
fmi2Status fmi2CancelStep(fmi2Component c) { return fmi2Error; }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *v) { return fmi2Error; }
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *v) { return fmi2Error; }
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *v) { return fmi2Error; }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *v) { return fmi2Error; }
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *v) { return fmi2Error; }
