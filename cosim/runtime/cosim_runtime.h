/*
 * cosim_runtime.h -- the internal interface of the version-independent core of the FMUs built by
 * `cosim build` (cosim_runtime.c), used by the two FMI API files: fmi2_api.c (FMI 2.0) and
 * fmi3_api.c (FMI 3.0).  An FMU binary is cosim_runtime.c + one API file + the generated model.
 *
 * The core knows nothing of the FMI headers: it has its own status codes (numerically those of
 * fmi2Status and fmi3Status), its own log callback (which receives the finished message, not a
 * format string) and its own allocator callbacks.  It owns
 *   - the instance: block sizes and offsets of the value array, the variables (rt_vars), work arrays,
 *   - the state machine's states (the API files decide which calls are allowed in which state),
 *   - value references: blocks, types, the checks of a get or set and the storing of values,
 *   - lazy evaluation: calculated parameters and state starts, der(x) and z, the local variables,
 *   - FMU states with the model's identity, and their serialization,
 *   - directional (jvp) and adjoint (vjp) derivatives on value references,
 *   - the embedded Dormand-Prince 5(4) integrator of Co-Simulation,
 *   - logging (error, warning, call and discard messages) through the API's callback.
 *
 * All symbols of the core are hidden (RT_HIDDEN): an FMU exports only the API's functions.
 * Helpers that can fail return 1 on success and 0 on failure, after logging; functions that return
 * rt_status return RT_OK, RT_DISCARD or RT_ERROR (see cosim_runtime.c for when which).
 */
#ifndef COSIM_RUNTIME_H
#define COSIM_RUNTIME_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "cosim_model.h"

#if defined(__GNUC__) && !defined(_WIN32) && !defined(__CYGWIN__)
#define RT_EXPORT __attribute__((visibility("default")))
#define RT_HIDDEN __attribute__((visibility("hidden")))
#define RT_PRINTF(fmt, first) __attribute__((format(printf, fmt, first)))
#else
#define RT_EXPORT
#define RT_HIDDEN
#define RT_PRINTF(fmt, first)
#endif

/* The values of fmi2Status and fmi3Status (both standards number them alike). */
typedef enum { RT_OK = 0, RT_WARNING = 1, RT_DISCARD = 2, RT_ERROR = 3, RT_FATAL = 4 } rt_status;

/* The interface type of an instance (the values of fmi2Type). */
typedef enum { RT_ME = 0, RT_CS = 1 } rt_kind;

/* States of the instance.  They are those of FMI 2.0; FMI 3.0 names them differently (fmi3_api.c):
   stepComplete is Step Mode, stepFailed is Step Mode after a discarded step.  The runtime never
   returns a fatal status, so ST_FATAL is never entered; it is listed to name the full state machine. */
typedef enum {
    ST_INSTANTIATED,
    ST_INIT,           /* initializationMode */
    ST_EVENT,          /* ME eventMode (FMI 3: also CS instances with eventModeUsed) */
    ST_CONT,           /* ME continuousTimeMode */
    ST_STEP_COMPLETE,  /* CS stepComplete (FMI 3: Step Mode) */
    ST_STEP_FAILED,    /* CS stepFailed: the DoStep returned a Discard */
    ST_TERMINATED,
    ST_ERROR,
    ST_FATAL,
    ST_COUNT
} rt_state;

#define BIT(st) (1u << (st))
#define IF_ANY (-1) /* function available for both interface types */

/* The blocks of the value array, in their order. */
typedef enum { B_X, B_DX, B_U, B_P, B_C, B_Z, B_NONE } rt_block;

/* The log callback: status, category ("logStatusError", "logStatusWarning", "logCalls") and the
   finished message (no format string). */
typedef void (*rt_logger)(void *env, const char *instance_name, rt_status status, const char *category,
                          const char *message);

/* The words of one FMI version that the core's messages use. */
typedef struct {
    const char *const *state_names;  /* ST_COUNT names, as the standard calls the states */
    const char *const *type_names;   /* of COSIM_REAL, COSIM_INTEGER, COSIM_BOOLEAN: "Real", ... */
    const char *exit_init;           /* "fmi2ExitInitializationMode" */
    const char *set_states;          /* "fmi2SetContinuousStates" */
    const char *discard;             /* "fmi2Discard" */
    /* A state may be an unknown of directional and adjoint derivatives (an Output of the
       ModelStructure that is a state: its row is d x_i / d x_j = delta_ij, 0 for inputs and
       parameters): FMI 2 and FMI 3 define directional derivatives for every ModelStructure
       unknown, and the bicycles list their states as outputs.  1 in both APIs. */
    int state_unknowns;
} rt_words;

/* Everything an FMU state has to capture. */
typedef struct {
    rt_state state;
    double time;
    double tolerance;
    double start_time;     /* of fmi2SetupExperiment (fmi3EnterInitializationMode) */
    double stop_time;      /* ditto, if stop_defined */
    int stop_defined;
    long n_steps;          /* CS: DoStep calls completed since the exit of initialization mode */
    double h_next;         /* CS: step size proposed for the next DoStep; 0 = estimate anew */
    int params_dirty;      /* c (and, in initializationMode, calculated state starts) are stale */
    int eval_dirty;        /* der(x) and z are stale */
    int locals_dirty;      /* the locals of z are stale (computed on demand, see rt_update_locals) */
    double *v;             /* the value array, nv entries; inputs as the environment set them */
    double *q;             /* COSIM_MODEL.nq parameter-only subexpressions of eval, valid unless params_dirty */
    double *ue;            /* nu inputs as the model sees them: v[u] extrapolated with du in CS */
    double *du;            /* CS: first derivatives of the inputs for the next DoStep, nu entries */
    unsigned char *x_set;  /* nx flags: state set explicitly, its calculated start must not overwrite it */
} rt_vars;

/* Who an FMU state belongs to: the GUID and the sizes of the model.  Two FMUs built by cosim
   share this runtime, so an FMU state of one can reach the other; only the identity tells. */
#define RT_GUID_MAX 64
typedef struct {
    uint32_t nv, nx, nu, np, nc, nz;   /* block sizes */
    uint32_t n_real, n_integer, n_boolean;
    uint32_t guid_hash;                /* of the whole GUID (the copy below may be cut) */
    char guid[RT_GUID_MAX];            /* zero-padded */
} rt_identity;

/* What an API file gives the core when it creates an instance. */
typedef struct {
    void *(*alloc)(size_t n, size_t size);  /* calloc semantics */
    void (*free)(void *p);
    rt_logger log;                          /* NULL: no messages */
    void *log_env;                          /* first argument of log */
    const rt_words *words;
    rt_kind kind;
    int log_calls;                          /* logCalls enabled from the start */
} rt_config;

typedef struct {
    void *(*alloc)(size_t n, size_t size);
    void (*free)(void *p);
    rt_logger log;
    void *log_env;
    const rt_words *words;
    char *name;
    rt_kind kind;
    int cs_event_mode;                      /* a CS instance may be in eventMode (FMI 3 eventModeUsed) */
    int log_error, log_warning, log_calls;  /* enabled log categories */

    size_t nx, nu, np, nc, nz, nv;          /* block sizes */
    rt_identity id;                         /* of this model, see the FMU states in cosim_runtime.c */
    size_t o_dx, o_u, o_p, o_c, o_z;        /* block offsets in the value array */
    int has_calc_start;                     /* some state has a calculated start */
    unsigned first_vr;                      /* value reference of index 0 of the value array */
    long fixed_step;                        /* index of the fixed step size parameter, -1 = none */

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

/* Numbers */
RT_HIDDEN double rt_abs(double a);
RT_HIDDEN double rt_max(double a, double b);

/* Logging.  rt_vformat formats as vsnprintf does (the runtime needs nothing of libc beyond the
   functions run.sh lists). */
RT_HIDDEN void rt_vformat(char *buf, size_t size, const char *fmt, va_list ap);
RT_HIDDEN void rt_format(char *buf, size_t size, const char *fmt, ...) RT_PRINTF(3, 4);
RT_HIDDEN void rt_log_error(const rt_instance *in, const char *fmt, ...) RT_PRINTF(2, 3);
RT_HIDDEN void rt_log_warning(const rt_instance *in, rt_status status, const char *fmt, ...) RT_PRINTF(3, 4);
RT_HIDDEN void rt_log_call_always(const rt_instance *in, const char *fmt, ...) RT_PRINTF(2, 3);
/* logCalls: the category is checked before anything is formatted (every API call logs itself). */
#define rt_log_call(in, ...) ((in) && (in)->log_calls ? rt_log_call_always((in), __VA_ARGS__) : (void)0)
RT_HIDDEN void rt_log_discard(const rt_instance *in, const char *fmt, ...) RT_PRINTF(2, 3);
RT_HIDDEN void rt_fail(rt_instance *in, const char *fmt, ...) RT_PRINTF(2, 3);
RT_HIDDEN const char *rt_vr_label(const rt_instance *in, size_t i, char *buf, size_t size);

/* Call checking */
RT_HIDDEN const char *rt_kind_name(rt_kind kind);
RT_HIDDEN int rt_refused(const rt_instance *in, const char *fn, unsigned mask, int iface);
/* May function fn be called now?  mask: allowed states; iface: IF_ANY or the rt_kind.  0 after
   logging why not (the check itself inline: every API call makes it). */
static inline int rt_allowed(const rt_instance *in, const char *fn, unsigned mask, int iface)
{
    if (in && (iface == IF_ANY || (int)in->kind == iface) && (mask & BIT(in->s.state))) return 1;
    return rt_refused(in, fn, mask, iface);
}
RT_HIDDEN int rt_not_null(const rt_instance *in, const char *fn, const char *arg, const void *p);
RT_HIDDEN int rt_check_length(const rt_instance *in, const char *fn, const char *arg, size_t n, size_t expected);
RT_HIDDEN int rt_state_fits_kind(const rt_instance *in, rt_state st);

/* Value references.  The importer's value reference vr is the variable at index vr - first_vr of
   the value array (cosim_model.h): the API functions pass value references, rt_index turns one
   into the index that the value array, the model's tables and the functions taking an index use. */
/* The index of value reference vr; nv or more (no variable) if vr is out of range. */
static inline size_t rt_index(const rt_instance *in, unsigned vr)
{
    return vr >= in->first_vr ? (size_t)(vr - in->first_vr) : (size_t)-1;
}
/* The value reference of index i (i = nv: FMI 3's time, one past the value array). */
static inline unsigned rt_vr(const rt_instance *in, size_t i)
{
    return (unsigned)(in->first_vr + i);
}
RT_HIDDEN rt_block rt_block_of(const rt_instance *in, size_t i);
RT_HIDDEN long rt_jvp_slot(const rt_instance *in, size_t i);
RT_HIDDEN int rt_check_vr(const rt_instance *in, const char *fn, unsigned vr, cosim_type type);
RT_HIDDEN int rt_to_integer(double v);

/* Lazy evaluation and the values */
RT_HIDDEN int rt_update_parameters(rt_instance *in, const char *fn);
RT_HIDDEN rt_status rt_update_outputs(rt_instance *in, const char *fn);
RT_HIDDEN rt_status rt_update_locals(rt_instance *in, const char *fn);
/* A get: rt_check_get for every value reference (collects what needs evaluating), then rt_finish_get. */
RT_HIDDEN int rt_check_get(const rt_instance *in, const char *fn, unsigned vr, cosim_type type, int *need_eval,
                           int *need_locals);
RT_HIDDEN rt_status rt_finish_get(rt_instance *in, const char *fn, int need_eval, int need_locals);
RT_HIDDEN rt_status rt_prepare_get(rt_instance *in, const char *fn, const unsigned vr[], size_t nvr,
                                   const void *value, cosim_type type);
/* A set: rt_check_set for every value (value: the double to be stored, checked to be finite if Real),
   then rt_store for every value. */
RT_HIDDEN int rt_check_set(const rt_instance *in, const char *fn, unsigned vr, cosim_type type, double value);
RT_HIDDEN void rt_store(rt_instance *in, unsigned vr, double value);

/* Instances */
RT_HIDDEN const char *rt_model_problem(void);
RT_HIDDEN int rt_init(rt_instance *in, const rt_config *cfg, const char *name);  /* 0: out of memory */
RT_HIDDEN void rt_check_fixed_step(rt_instance *in, const char *fn);
RT_HIDDEN void rt_release(rt_instance *in);  /* frees what rt_init allocated, not in itself */
RT_HIDDEN void rt_reset(rt_instance *in);    /* the variables as right after rt_init */
RT_HIDDEN int rt_set_category(rt_instance *in, const char *fn, int on, size_t n, const char *const categories[]);
RT_HIDDEN int rt_setup(rt_instance *in, const char *fn, int tolerance_defined, double tolerance, double start_time,
                       int stop_defined, double stop_time);
RT_HIDDEN rt_status rt_enter_init(rt_instance *in, const char *fn);
RT_HIDDEN rt_status rt_exit_init(rt_instance *in, const char *fn, rt_state next);

/* FMU states (void *: the API's fmi2FMUstate / fmi3FMUState) */
RT_HIDDEN rt_status rt_get_state(rt_instance *in, const char *fn, void **state);
RT_HIDDEN rt_status rt_set_state(rt_instance *in, const char *fn, void *state);
RT_HIDDEN rt_status rt_free_state(rt_instance *in, const char *fn, void **state);
RT_HIDDEN rt_status rt_serialized_size(rt_instance *in, const char *fn, void *state, size_t *size);
RT_HIDDEN rt_status rt_serialize(rt_instance *in, const char *fn, void *state, unsigned char *bytes, size_t size);
RT_HIDDEN rt_status rt_deserialize(rt_instance *in, const char *fn, const unsigned char *bytes, size_t size,
                                   void **state);

/* Derivatives: the value references checked, the arrays not NULL (n > 0). */
RT_HIDDEN rt_status rt_directional(rt_instance *in, const char *fn, const unsigned unknown[], size_t n_unknown,
                                   const unsigned known[], size_t n_known, const double seed[], double result[]);
RT_HIDDEN rt_status rt_adjoint(rt_instance *in, const char *fn, const unsigned unknown[], size_t n_unknown,
                               const unsigned known[], size_t n_known, const double seed[], double result[]);

/* Model Exchange */
RT_HIDDEN int rt_set_time(rt_instance *in, const char *fn, double time);

/* Co-Simulation: the step from the current time to t_end (checked by the API: > time).  RT_OK,
   RT_DISCARD (integration failed, stepFailed at the last successful time) or RT_ERROR. */
RT_HIDDEN rt_status rt_do_step(rt_instance *in, const char *fn, double t_end);
RT_HIDDEN double rt_stop_allowance(const rt_instance *in);

#endif
