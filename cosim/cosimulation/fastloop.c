/*
 * fastloop.c -- the stepping loop of the co-simulation master for systems of FMUs and native blocks.
 *
 * Python sets the system up (instantiation, parameters, initialization) and hands over the raw
 * FMI function pointers and instance handles (an FMI 3 FMU's through the adapters below, which give
 * its functions the FMI 2 signatures), and for each Python block with a native form
 * (registry.Native: affine, linear, exact delay) its matrices and state arrays; this loop then
 * does exactly what the Python loop in master.py does, without an interpreter round trip per call.
 *
 * The blocks' arithmetic is that of their Python methods (blocks.py) operation by operation:
 * products of a matrix and a vector as blocks.matvec sums them, no fused multiply-adds (compiled
 * with -ffp-contract=off), so both loops give bit-identical results.
 */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

typedef int (*set_real_fn)(void *, const unsigned int *, size_t, const double *);
typedef int (*get_real_fn)(void *, const unsigned int *, size_t, double *);
typedef int (*do_step_fn)(void *, double, double, int);

/* ------------------------------------------------------------------ FMI 3 adapters
 *
 * The loop calls every FMU through the three FMI 2 signatures above. An FMI 3 Co-Simulation FMU
 * gets them from these adapters, whose first argument is an fmi3_adapter (the "instance" of the
 * loop's component) instead of the FMU's instance: fmi3SetFloat64/fmi3GetFloat64 take the number
 * of values besides the number of value references (equal here: the master connects scalars
 * only), and fmi3DoStep reports through four out-arguments what FMI 2 left to fmi2GetStatus. An
 * FMI 2 component calls the FMU directly, so its cost per call is the same as before FMI 3. */
typedef int (*fmi3_set_float64_fn)(void *, const unsigned int *, size_t, const double *, size_t);
typedef int (*fmi3_get_float64_fn)(void *, const unsigned int *, size_t, double *, size_t);
typedef int (*fmi3_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);

typedef struct {
    void *instance;                     /* the fmi3Instance */
    fmi3_set_float64_fn set_float64;
    fmi3_get_float64_fn get_float64;
    fmi3_do_step_fn do_step;
    /* what the last fmi3DoStep said (component.FMUComponent.failed reads them) */
    int status;                         /* the fmi3Status it returned */
    int event_handling_needed, terminate_simulation, early_return;
    double last_successful_time;        /* [s] */
} fmi3_adapter;

int cosim_fmi3_set_real(void *adapter, const unsigned int *vr, size_t n, const double *values) {
    const fmi3_adapter *a = adapter;
    return a->set_float64(a->instance, vr, n, values, n);
}

int cosim_fmi3_get_real(void *adapter, const unsigned int *vr, size_t n, double *values) {
    const fmi3_adapter *a = adapter;
    return a->get_float64(a->instance, vr, n, values, n);
}

/* fmi3DoStep as fmi2DoStep. The instance was made without event mode and without early return,
   so eventHandlingNeeded asks nothing of the master (the FMU handles its events inside the step);
   an early return (forbidden then) or a request to terminate returns fmi2Discard as FMI 2 does,
   with the flags and the last successful time kept: the master reads them to tell the model's own
   end (terminateSimulation) from a failure. */
int cosim_fmi3_do_step(void *adapter, double t, double h, int no_set_state_prior) {
    fmi3_adapter *a = adapter;
    bool event = false, terminate = false, early = false;
    double last = t;
    int status = a->do_step(a->instance, t, h, no_set_state_prior != 0, &event, &terminate, &early, &last);
    a->status = status;
    a->event_handling_needed = event, a->terminate_simulation = terminate, a->early_return = early;
    a->last_successful_time = last;
    if (status <= 1 && (terminate || early)) return 2;
    return status;
}

enum { BLOCK_AFFINE = 1, BLOCK_LINEAR = 2, BLOCK_DELAY = 3 };

/* A native block (registry.Native); the arrays are the Python block's own, updated in place. */
typedef struct {
    int kind;
    int n_in, n_out, n_x;
    double *u, *y, *t;         /* inputs, outputs, the block's time */
    double *u_set;             /* the master's input vector of the block, copied by set_inputs */
    const double *D;           /* n_out x n_in, row-major */
    /* affine: r(t) = on while lo <= t + shift < hi, else off (has_window 0: r = 0) */
    int has_window;
    double lo, hi, shift;
    const double *on, *off;
    /* linear */
    double *x, *x_next;        /* states and scratch */
    const double *C;           /* n_out x n_x */
    const double *Ad, *Bd;     /* one (n_x x n_x, n_x x n_in) pair per distinct step length */
    const int *which;          /* the pair of the block's j-th step */
    /* exact delay: sample times and values in a ring, ring[0] the oldest, ring[1] the count */
    double tau;
    double *ring_t, *ring_v;
    long long *ring;
    long long capacity;
} fast_block;

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
    fast_block *block;         /* NULL for an FMU */
    const int *in_target;      /* block: the input (index in u_set) of each connected input */
    double now;                /* FMU: its communication point (component.FMUComponent.now) */
} fast_component;

enum { COMPLETED = 0, FELL = 1, DIVERGED = 2, FMI_ERROR = 3, RING_FULL = 4 };
enum { CALL_SET = 0, CALL_STEP = 1, CALL_GET = 2 };  /* *failed_call */

/* ------------------------------------------------------------------ native blocks */

/* One row of blocks.matvec: (m[0] v[0] + m[1] v[1]) + ..., 0 without columns. */
static double row_times(const double *m, const double *v, int n) {
    double s;
    int j;
    if (n == 0) return 0.0;
    s = m[0] * v[0];
    for (j = 1; j < n; j++) s = s + m[j] * v[j];
    return s;
}

/* Affine._refresh: y = matvec(D, u) + exogenous(t). */
static void affine_refresh(fast_block *b) {
    int i, on = 0;
    if (b->has_window) {
        double s = *b->t + b->shift;
        on = b->lo <= s && s < b->hi;
    }
    for (i = 0; i < b->n_out; i++) {
        double r = b->has_window ? (on ? b->on[i] : b->off[i]) : 0.0;
        b->y[i] = row_times(b->D + (size_t)i * b->n_in, b->u, b->n_in) + r;
    }
}

/* Linear._update_outputs: y = (matvec(C, x) if states else 0) + matvec(D, u). */
static void linear_outputs(fast_block *b) {
    int i;
    for (i = 0; i < b->n_out; i++) {
        double cx = b->n_x ? row_times(b->C + (size_t)i * b->n_x, b->x, b->n_x) : 0.0;
        b->y[i] = cx + row_times(b->D + (size_t)i * b->n_in, b->u, b->n_in);
    }
}

#define RING_T(b, i) ((b)->ring_t[((b)->ring[0] + (i)) % (b)->capacity])
#define RING_V(b, i) ((b)->ring_v[((b)->ring[0] + (i)) % (b)->capacity])

/* TransportDelay._delayed: the input at t - tau, interpolated linearly between samples. */
static double delayed(const fast_block *b, double t) {
    double target = t - b->tau, t0, t1, v0, v1;
    long long count = b->ring[1], k;
    if (count == 0 || target <= RING_T(b, 0)) return count ? RING_V(b, 0) : b->u[0];
    if (target >= RING_T(b, count - 1)) return RING_V(b, count - 1);
    k = 1;
    while (RING_T(b, k) < target) k++;
    t0 = RING_T(b, k - 1), t1 = RING_T(b, k);
    v0 = RING_V(b, k - 1), v1 = RING_V(b, k);
    return t1 == t0 ? v1 : v0 + (v1 - v0) * (target - t0) / (t1 - t0);
}

/* The block's set_inputs from u_set; -1 if a delay's ring is full (its capacity is a bound that
   blocks.TransportDelay.native computes: a full ring is a bug there). */
static int block_set_inputs(fast_block *b) {
    if (b->kind == BLOCK_DELAY) {
        long long count = b->ring[1];
        b->u[0] = b->u_set[0];
        if (count && RING_T(b, count - 1) == *b->t) {  /* the sample at this time is replaced */
            RING_V(b, count - 1) = b->u[0];
        } else {
            if (count == b->capacity) return -1;
            RING_T(b, count) = *b->t;
            RING_V(b, count) = b->u[0];
            b->ring[1] = count + 1;
        }
        b->y[0] = delayed(b, *b->t);
        return 0;
    }
    memcpy(b->u, b->u_set, (size_t)b->n_in * sizeof(double));
    if (b->kind == BLOCK_AFFINE) affine_refresh(b);
    else linear_outputs(b);
    return 0;
}

/* The block's step(t, h), the block's j-th step. */
static void block_step(fast_block *b, double t, double h, long j) {
    int i;
    *b->t = t + h;
    if (b->kind == BLOCK_AFFINE) {
        affine_refresh(b);
    } else if (b->kind == BLOCK_LINEAR) {
        const double *Ad, *Bd;
        if (b->n_x == 0) return;
        Ad = b->Ad + (size_t)b->which[j] * (size_t)b->n_x * (size_t)b->n_x;
        Bd = b->Bd + (size_t)b->which[j] * (size_t)b->n_x * (size_t)b->n_in;
        for (i = 0; i < b->n_x; i++)
            b->x_next[i] = row_times(Ad + (size_t)i * b->n_x, b->x, b->n_x)
                           + row_times(Bd + (size_t)i * b->n_in, b->u, b->n_in);
        memcpy(b->x, b->x_next, (size_t)b->n_x * sizeof(double));
        linear_outputs(b);
    } else {  /* forget what can no longer be reached (keep one sample before the horizon) */
        double horizon = *b->t - b->tau;
        while (b->ring[1] > 2 && RING_T(b, 1) <= horizon) {
            b->ring[0] = (b->ring[0] + 1) % b->capacity;
            b->ring[1]--;
        }
        b->y[0] = delayed(b, *b->t);
    }
}

/* ------------------------------------------------------------------ components */

/* Each returns the FMI status of its call (0 when nothing had to be called; -1 a full ring). */
static int feed(fast_component *c, const double *signals) {
    int i;
    if (c->n_in == 0) return 0;
    if (c->block) {
        for (i = 0; i < c->n_in; i++) c->block->u_set[c->in_target[i]] = signals[c->in_src[i]];
        return block_set_inputs(c->block);
    }
    for (i = 0; i < c->n_in; i++) c->in_buf[i] = signals[c->in_src[i]];
    return c->set_real(c->instance, c->in_vr, (size_t)c->n_in, c->in_buf);
}

static int read_outputs(fast_component *c, double *into) {
    if (c->n_out == 0) return 0;
    if (c->block) {
        memcpy(into + c->out_offset, c->block->y, (size_t)c->n_out * sizeof(double));
        return 0;
    }
    return c->get_real(c->instance, c->out_vr, (size_t)c->n_out, into + c->out_offset);
}

static int do_step(fast_component *c, double t, double h, long k) {
    int status;
    if (c->block) {
        block_step(c->block, t, h, k / c->multiple);
        return 0;
    }
    status = c->do_step(c->instance, t, h, 1);
    if (status <= 1) c->now = t + h;
    return status;
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
   Returns COMPLETED, FELL, DIVERGED, FMI_ERROR or RING_FULL; on FMI_ERROR *failed is the index of
   the failing component, *fmi_status the status its call returned (2 Discard, 3 Error, 4 Fatal) and
   *failed_call which call it was (CALL_SET fmi2SetReal, CALL_STEP fmi2DoStep, CALL_GET fmi2GetReal),
   and *failed_time the time the call names (the step's start for fmi2DoStep, else the FMU's
   communication point); on RING_FULL *failed is the index of the delay, on DIVERGED the index of
   the first non-finite signal. *steps_done counts the base steps whose results are recorded (rows 0 .. *steps_done of
   rec). Steps first .. last - 1 of the grid are taken (0 and n_steps for all): the master calls again from
   where a call stopped to report progress between calls, with the same results as one call. */
int cosim_fast_run(int nc, fast_component *comps, const int *order, int gauss_seidel, int after_transfer,
                   double *signals, double *sampled, int n_signals, const double *times, long n_steps,
                   long first, long last, int n_rec, const int *rec_idx, double *rec,
                   int fall_idx, double fall_limit, long *steps_done, int *failed, int *fmi_status,
                   int *failed_call, double *failed_time) {
    long k;
    int j, i, status;
#define FAIL_IF(what, call) do { status = (call); if (status > 1 || status < 0) { *failed = order[j]; \
        *fmi_status = status; *failed_call = (what); *steps_done = k; \
        *failed_time = (what) == CALL_STEP ? t : comps[order[j]].now; \
        return status < 0 ? RING_FULL : FMI_ERROR; } } while (0)
    for (k = first; k < last; k++) {
        double t = times[k];
        double *row;
        if (gauss_seidel) {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple) continue;
                FAIL_IF(CALL_SET, feed(c, signals));
                FAIL_IF(CALL_STEP, do_step(c, t, step_length(c, times, k, n_steps), k));
                FAIL_IF(CALL_GET, read_outputs(c, signals));
            }
        } else {
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0) FAIL_IF(CALL_SET, feed(c, signals));
            }
            for (j = 0; j < nc; j++) {
                fast_component *c = &comps[order[j]];
                if (k % c->multiple == 0) FAIL_IF(CALL_STEP, do_step(c, t, step_length(c, times, k, n_steps), k));
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
    *steps_done = last;
    return COMPLETED;
}
