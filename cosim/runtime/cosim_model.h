/*
 * cosim_model.h -- the contract between the shared FMI 2.0 runtime (fmi2_runtime.c)
 * and the model-specific code that `cosim build` generates (model.c).
 *
 * All variables of an FMU live in one array of doubles indexed by value reference:
 *
 *   [ states x | derivatives der(x) | inputs u | parameters p | calculated parameters c | algebraics z ]
 *     nx         nx                   nu         np             nc                         nz
 *
 * Integer and Boolean variables are stored as doubles too (types[] tells which is which).
 * The instantiation token (GUID) identifies the model: the runtime refuses FMU states whose GUID
 * or block sizes differ from its own.
 * The generator writes both this model's C tables and modelDescription.xml from one Python
 * description, so value references here and in the XML cannot disagree.
 */
#ifndef COSIM_MODEL_H
#define COSIM_MODEL_H

typedef enum { COSIM_REAL = 0, COSIM_INTEGER = 1, COSIM_BOOLEAN = 2 } cosim_type;

typedef struct {
    const char *instantiation_token;  /* the GUID of modelDescription.xml */
    int nx, nu, np, nc, nz;           /* block sizes of the value array, see above */
    double default_tolerance;         /* relative tolerance when fmi2SetupExperiment gives none */
    int vr_fixed_step;                /* value reference of parameter solver.fixedStepSize (0 = adaptive) */
    const cosim_type *types;          /* nv = 2*nx+nu+np+nc+nz entries */
    const double *start;              /* nv start values (states: exact start; others as declared, 0 if none) */
    const unsigned char *state_start_calculated; /* nx flags: 1 = start of x[i] computed by start_states */

    /* Each returns 0 on success, non-zero if the evaluation failed (e.g. an algebraic solve diverged). */
    int (*calc_parameters)(const double *p, double *c);
    int (*start_states)(const double *p, double *x0);
    int (*eval)(double t, const double *x, const double *u, const double *p, double *xdot, double *z);
    /* Jacobian-vector product of (xdot, z) along the direction (dx, du, dp). */
    int (*jvp)(double t, const double *x, const double *u, const double *p,
               const double *dx, const double *du, const double *dp, double *dxdot, double *dz);
    /* nv variable names as in modelDescription.xml (e.g. "der(phi)"), for messages; may be NULL. */
    const char *const *names;
} cosim_model;

extern const cosim_model COSIM_MODEL;

#endif
