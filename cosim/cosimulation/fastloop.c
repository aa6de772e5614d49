/*
 * fastloop.c -- the stepping loop of the co-simulation master for systems made only of FMUs.
 *
 * Python sets the system up (instantiation, parameters, initialization) and hands over the raw
 * FMI function pointers and instance handles; this loop then does exactly what the Python loop
 * in master.py does, without an interpreter round trip per FMI call.
 */
#include <math.h>
#include <stddef.h>

typedef int (*set_real_fn)(void *, const unsigned int *, size_t, const double *);
typedef int (*get_real_fn)(void *, const unsigned int *, size_t, double *);
typedef int (*do_step_fn)(void *, double, double, int);

typedef struct {
    void *instance;
    set_real_fn set_real;
    get_real_fn get_real;
    do_step_fn do_step;
    int n_in;                  /* connected inputs only */
    const unsigned int *in_vr;
    const int *in_src;         /* index of the source output in the signal vector */
    double *in_buf;
    int n_out;
    const unsigned int *out_vr;
    int out_offset;            /* first output in the signal vector */
    int multiple;              /* steps every `multiple` base steps */
} fast_component;

enum { COMPLETED = 0, FELL = 1, DIVERGED = 2, FMI_ERROR = 3 };

static int feed(fast_component *c, const double *signals) {
    int i;
    if (c->n_in == 0) return 0;
    for (i = 0; i < c->n_in; i++) c->in_buf[i] = signals[c->in_src[i]];
    return c->set_real(c->instance, c->in_vr, (size_t)c->n_in, c->in_buf) > 1;
}

static int read_outputs(fast_component *c, double *into) {
    if (c->n_out == 0) return 0;
    return c->get_real(c->instance, c->out_vr, (size_t)c->n_out, into + c->out_offset) > 1;
}

/* sampled: scratch vector of n_signals for after-transfer sampling.
   Returns COMPLETED, FELL, DIVERGED or FMI_ERROR; *failed is the index of the failing component. */
int cosim_fast_run(int nc, fast_component *comps, const int *order, int gauss_seidel, int after_transfer,
                   double *signals, double *sampled, int n_signals, double t0, double h, long n_steps,
                   int n_rec, const int *rec_idx, double *rec,
                   int fall_idx, double fall_limit, long *steps_done, int *failed) {
    long k;
    int j, i;
    for (k = 0; k < n_steps; k++) {
        double t = t0 + (double)k * h;
        double *row;
        if (gauss_seidel) {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple) continue;
                if (feed(c, signals) || c->do_step(c->instance, t, h * c->multiple, 1) > 1 || read_outputs(c, signals)) {
                    *failed = order[j]; *steps_done = k; return FMI_ERROR;
                }
            }
        } else {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0 && feed(c, signals)) { *failed = order[j]; *steps_done = k; return FMI_ERROR; }
            }
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0 && c->do_step(c->instance, t, h * c->multiple, 1) > 1) {
                    *failed = order[j]; *steps_done = k; return FMI_ERROR;
                }
            }
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0 && read_outputs(c, signals)) { *failed = order[j]; *steps_done = k; return FMI_ERROR; }
            }
        }
        if (after_transfer) {
            /* Record the outputs once the connected inputs took the new values (direct
               feedthrough); the next step still transfers the after-step values. */
            for (i = 0; i < n_signals; i++) sampled[i] = signals[i];
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (feed(c, signals) || read_outputs(c, sampled)) { *failed = order[j]; *steps_done = k; return FMI_ERROR; }
            }
        }
        row = rec + (size_t)(k + 1) * (size_t)(n_rec + 1);
        row[0] = t0 + (double)(k + 1) * h;
        for (i = 0; i < n_rec; i++) row[i + 1] = (after_transfer ? sampled : signals)[rec_idx[i]];
        for (i = 0; i < n_signals; i++) {
            if (!isfinite(signals[i])) { *failed = i; *steps_done = k + 1; return DIVERGED; }
        }
        if (fall_idx >= 0 && fabs(signals[fall_idx]) > fall_limit) { *steps_done = k + 1; return FELL; }
    }
    *steps_done = n_steps;
    return COMPLETED;
}
