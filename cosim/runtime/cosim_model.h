/*
 * cosim_model.h -- the contract between the shared FMI runtime (cosim_runtime.c with the FMI 2.0
 * API fmi2_api.c or the FMI 3.0 API fmi3_api.c) and the model-specific code that `cosim build`
 * generates (model.c).
 *
 * All variables of an FMU live in one array of doubles, the value array, of nv = 2*nx+nu+np+nc+nz
 * entries:
 *
 *   [ states x | derivatives der(x) | inputs u | parameters p | calculated parameters c | algebraics z ]
 *     nx         nx                   nu         np             nc                         nz
 *
 * The variable at index i of the value array has the value reference first_vr + i (the tables
 * below are indexed like the value array): value references need not start at 0, and some
 * importers refuse 0 in FMI 3.
 * Integer and Boolean variables are stored as doubles too (types[] tells which is which).
 * FMI 3.0 needs the independent variable as a variable of its own: `time` has the value reference
 * first_vr + nv, one past the value array (read only, FMI 2 does not list it).
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
    double default_tolerance;         /* relative tolerance when the importer gives none (fmi2SetupExperiment,
                                         fmi3EnterInitializationMode) */
    int vr_fixed_step;                /* value reference of parameter solver.fixedStepSize (0 = none: adaptive;
                                         first_vr > 0 where the model has one) */
    const cosim_type *types;          /* nv = 2*nx+nu+np+nc+nz entries */
    const double *start;              /* nv start values (states: exact start, or the guess of a state solved
                                         from the initial equations; others as declared, 0 if none) */
    /* nx flags: 0 = x[i] starts at start[i]; 1 = its start is computed from the parameters by
       start_states; 2 = it is solved from the initial equations by start_states (start[i] and a value
       set by the importer are only the guess) */
    const unsigned char *state_start_calculated;

    /* Each returns 0 on success, non-zero if the evaluation failed (e.g. an algebraic solve diverged). */
    int (*calc_parameters)(const double *p, double *c);
    /* Start values of the states at time t with inputs u and parameters p.  x0: on entry the current
       values of the states; given (nx flags) marks those set by the importer.  On return the start
       values: a state set by the importer keeps its value, others get their start value (flag 0 or 1),
       except that a state solved from the initial equations (flag 2) gets the solution, for which its
       value on entry (if given) or its start value was the guess.  residual: on return
       max |residual| of the initial equations (0 without).  Returns COSIM_START_NOT_CONVERGED if the
       initial equations were not solved (max |residual| above the tolerance, or not finite). */
    int (*start_states)(double t, const double *u, const double *p, const unsigned char *given, double *x0,
                        double *residual);
    /* der(x) and z; if eval_locals is not NULL, only the outputs in z (the entries with a slot in
       z_jvp_slot), the others are left as they are. */
    int (*eval)(double t, const double *x, const double *u, const double *p, double *xdot, double *z);
    /* Jacobian-vector product of (xdot, z) along the direction (dx, du, dp); dz holds the algebraic
       variables that have a slot in z_jvp_slot (all of z if z_jvp_slot is NULL). */
    int (*jvp)(double t, const double *x, const double *u, const double *p,
               const double *dx, const double *du, const double *dp, double *dxdot, double *dz);
    /* nv variable names as in modelDescription.xml (e.g. "der(phi)"), for messages; may be NULL. */
    const char *const *names;
    /* The states solved from the initial equations (flag 2), e.g. "theta, psi", for messages;
       NULL if the model has no initial equations.  Their solve waits for fmi2/fmi3ExitInitializationMode
       (or a getter in initializationMode), so that parameters set in initializationMode count. */
    const char *init_unknowns;
    /* nz entries: the index in jvp's dz of z[i], or -1 if z[i] has no directional derivative (a local
       variable: FMI 2 defines them for the ModelStructure unknowns, derivatives and outputs).  NULL:
       dz is all of z. */
    const int *z_jvp_slot;
    /* All of z (the local algebraic variables included), computed only when an importer reads a
       local: the integrators need der(x) and the outputs.  NULL: eval computes all of z.  (`cosim build`
       makes it run a tape, see cosim_tape.h: no code for gcc to compile.) */
    int (*eval_locals)(double t, const double *x, const double *u, const double *p, double *z);
    /* Optional (nq = 0: absent): the subexpressions of der(x) and z that depend on the parameters only,
       q = calc_hoisted(p), computed once when the parameters change instead of in every evaluation
       (the linear bicycle's matrices M, C1, K0, K2 of Meijaard (2007) eq (1): three quarters of its
       eval).  eval_hoisted(t, x, u, p, q, ...) equals eval(t, x, u, p, ...) bit for bit: the same
       operations on the same values, only computed earlier. */
    int nq;
    int (*calc_hoisted)(const double *p, double *q);
    int (*eval_hoisted)(double t, const double *x, const double *u, const double *p, const double *q,
                        double *xdot, double *z);
    /* Vector-Jacobian product (reverse mode, fmi3GetAdjointDerivative) of the same outputs as jvp:
       given weights wxdot (nx) on der(x) and wz (one per slot of jvp's dz) on the outputs, returns
       wx (nx), wu (nu) and wp (np) with (wx, wu, wp) = J^T (wxdot, wz), J the Jacobian of (xdot, dz)
       with respect to (x, u, p); the entries of wp of Integer and Boolean parameters are 0.
       NULL: no adjoint derivatives. */
    int (*vjp)(double t, const double *x, const double *u, const double *p,
               const double *wxdot, const double *wz, double *wx, double *wu, double *wp);
    /* FMI 3 arrays: nv entries; fmi3_length[i] is the number of values of the FMI 3 variable at
       index i of the value array: 1 for a scalar, n > 1 for an array whose values are those at
       i .. i+n-1 (one declared Modelica array, e.g. the Pade delay's states), 0 for the
       elements after the first of an array (no FMI 3 variable of their own).  NULL: all scalars.
       FMI 2 exports every element as a scalar and ignores it. */
    const int *fmi3_length;
    /* The value reference of index 0 of the value array (see above), as in modelDescription.xml. */
    unsigned first_vr;
} cosim_model;

#define COSIM_START_NOT_CONVERGED 2

extern const cosim_model COSIM_MODEL;

#endif
