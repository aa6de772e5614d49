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
enum { CALL_SET = 0, CALL_STEP = 1, CALL_GET = 2 };  /* *failed_call */

/* Each returns the FMI status of its call (0 when nothing had to be called). */
static int feed(fast_component *c, const double *signals) {
    int i;
    if (c->n_in == 0) return 0;
    for (i = 0; i < c->n_in; i++) c->in_buf[i] = signals[c->in_src[i]];
    return c->set_real(c->instance, c->in_vr, (size_t)c->n_in, c->in_buf);
}

static int read_outputs(fast_component *c, double *into) {
    if (c->n_out == 0) return 0;
    return c->get_real(c->instance, c->out_vr, (size_t)c->n_out, into + c->out_offset);
}

/* A component with step multiple m steps at base steps k = 0, m, 2m, ... from times[k] to
   times[min(k + m, n_steps)]: the grid's last step may be shorter, so every component ends on
   the stop time exactly. */
static double step_length(const fast_component *c, const double *times, long k, long n_steps) {
    long end = k + c->multiple;
    if (end > n_steps) end = n_steps;
    return times[end] - times[k];
}

/* times: the communication grid, n_steps + 1 points from start to stop.
   sampled: scratch vector of n_signals for after-transfer sampling.
   Returns COMPLETED, FELL, DIVERGED or FMI_ERROR; on FMI_ERROR *failed is the index of the
   failing component, *fmi_status the status its call returned (2 Discard, 3 Error, 4 Fatal) and
   *failed_call which call it was (CALL_SET fmi2SetReal, CALL_STEP fmi2DoStep, CALL_GET fmi2GetReal),
   on DIVERGED *failed is the index of the first non-finite signal. *steps_done counts the base
   steps whose results are recorded (rows 0 .. *steps_done of rec). */
int cosim_fast_run(int nc, fast_component *comps, const int *order, int gauss_seidel, int after_transfer,
                   double *signals, double *sampled, int n_signals, const double *times, long n_steps,
                   int n_rec, const int *rec_idx, double *rec,
                   int fall_idx, double fall_limit, long *steps_done, int *failed, int *fmi_status,
                   int *failed_call) {
    long k;
    int j, i, status;
#define FAIL_IF(what, call) do { status = (call); if (status > 1) { *failed = order[j]; \
        *fmi_status = status; *failed_call = (what); *steps_done = k; return FMI_ERROR; } } while (0)
    for (k = 0; k < n_steps; k++) {
        double t = times[k];
        double *row;
        if (gauss_seidel) {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple) continue;
                FAIL_IF(CALL_SET, feed(c, signals));
                FAIL_IF(CALL_STEP, c->do_step(c->instance, t, step_length(c, times, k, n_steps), 1));
                FAIL_IF(CALL_GET, read_outputs(c, signals));
            }
        } else {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0) FAIL_IF(CALL_SET, feed(c, signals));
            }
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0) FAIL_IF(CALL_STEP, c->do_step(c->instance, t, step_length(c, times, k, n_steps), 1));
            }
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0) FAIL_IF(CALL_GET, read_outputs(c, signals));
            }
        }
        if (after_transfer) {
            /* Record the outputs once the connected inputs took the new values (direct
               feedthrough); the next step still transfers the after-step values. */
            for (i = 0; i < n_signals; i++) sampled[i] = signals[i];
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                FAIL_IF(CALL_SET, feed(c, signals));
                FAIL_IF(CALL_GET, read_outputs(c, sampled));
            }
        }
        row = rec + (size_t)(k + 1) * (size_t)(n_rec + 1);
        row[0] = times[k + 1];
        for (i = 0; i < n_rec; i++) row[i + 1] = (after_transfer ? sampled : signals)[rec_idx[i]];
        for (i = 0; i < n_signals; i++) {
            if (!isfinite(signals[i])) { *failed = i; *steps_done = k + 1; return DIVERGED; }
        }
        if (fall_idx >= 0 && fabs(signals[fall_idx]) > fall_limit) { *steps_done = k + 1; return FELL; }
    }
#undef FAIL_IF
    *steps_done = n_steps;
    return COMPLETED;
}
