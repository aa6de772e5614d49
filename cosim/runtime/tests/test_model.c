/*
 * test_model.c -- a hand-written COSIM_MODEL for testing the runtime (cosim_runtime.c with fmi2_api.c
 * or fmi3_api.c).
 *
 * A damped oscillator driven by an input, plus a decaying state with a calculated start:
 *
 *   s' = v
 *   v' = -k s - d v + g u       d = 0.1 n (Integer parameter n), g = b ? 1 : 0 (Boolean parameter b)
 *   w' = -w                     w(0) = k / 2 (calculated start), for u <= 1000
 *   w' = w^2                    for u > 1000: w = 1 / (t_esc - t) escapes to infinity in finite time
 *
 *   calculated parameters: omega = sqrt(k) (Real), n10 = 10 n (Integer)
 *   algebraics:            f = k s + u,  e = v^2 + w
 *
 * d and g are the model's hoisted parameter terms q = (d, g) (calc_hoisted, eval_hoisted of cosim_model.h),
 * so that the harness sees whether the runtime keeps them in step with n and b.
 *
 * eval fails for finite u > 1e6, so that the harness can test error handling; u > 1000 gives a solution
 * that cannot be continued past a finite time (an integration failure inside fmi2DoStep).
 *
 * jvp and vjp are the hand-written forward and reverse derivatives of (der(x), z) with respect to (x, u, p).
 * Compiled with -DTEST_MODEL_ARRAYS, the states s, v, w are one FMI 3 array variable x[3] (value
 * reference 0, fmi3_length) and so are their derivatives (value reference 3); FMI 2 ignores it.
 *
 * Compiled with -DTEST_MODEL_GUID='"{...}"' it is a different FMU of the same sizes (run.sh builds such
 * a twin as a shared library, to test that an FMU state of another FMU is refused).
 *
 * Value references:
 *   0 s   1 v   2 w   3 der(s)   4 der(v)   5 der(w)   6 u
 *   7 k   8 n   9 b   10 fixedStepSize   11 omega   12 n10   13 f   14 e
 */
#include <math.h>

#include "cosim_model.h"

#ifndef TEST_MODEL_GUID
#define TEST_MODEL_GUID "{8c4e810f-3df3-4a00-8276-176fa3c9f000}"
#endif

/* Number of eval calls, so that the harness can count integrator steps (test code only). */
long test_model_evals = 0;

enum { P_K, P_N, P_B, P_H };

static int calc_parameters(const double *p, double *c)
{
    if (p[P_K] < 0.0) return 1; /* sqrt of a negative stiffness */
    c[0] = sqrt(p[P_K]);
    c[1] = 10.0 * p[P_N];
    return 0;
}

static int start_states(double t, const double *u, const double *p, const unsigned char *given, double *x0,
                        double *residual)
{
    (void)t;
    (void)u;
    (void)given;
    x0[2] = p[P_K] / 2.0;
    *residual = 0.0;
    return 0;
}

static int calc_hoisted(const double *p, double *q)
{
    q[0] = 0.1 * p[P_N];
    q[1] = p[P_B] != 0.0 ? 1.0 : 0.0;
    return 0;
}

static int eval_hoisted(double t, const double *x, const double *u, const double *p, const double *q,
                        double *xdot, double *z)
{
    const double k = p[P_K], d = q[0], g = q[1];

    (void)t;
    test_model_evals++;
    if (isfinite(u[0]) && u[0] > 1e6) return 1;
    xdot[0] = x[1];
    xdot[1] = -k * x[0] - d * x[1] + g * u[0];
    xdot[2] = u[0] > 1000.0 ? x[2] * x[2] : -x[2];
    z[0] = k * x[0] + u[0];
    z[1] = x[1] * x[1] + x[2];
    return 0;
}

static int eval(double t, const double *x, const double *u, const double *p, double *xdot, double *z)
{
    double q[2];
    calc_hoisted(p, q);
    return eval_hoisted(t, x, u, p, q, xdot, z);
}

static int jvp(double t, const double *x, const double *u, const double *p,
               const double *dx, const double *du, const double *dp, double *dxdot, double *dz)
{
    const double k = p[P_K], d = 0.1 * p[P_N], g = p[P_B] != 0.0 ? 1.0 : 0.0;

    (void)t;
    dxdot[0] = dx[1];
    dxdot[1] = -k * dx[0] - dp[P_K] * x[0] - d * dx[1] + g * du[0];
    dxdot[2] = u[0] > 1000.0 ? 2.0 * x[2] * dx[2] : -dx[2];
    dz[0] = k * dx[0] + dp[P_K] * x[0] + du[0];
    dz[1] = 2.0 * x[1] * dx[1] + dx[2];
    return 0;
}

/* The transpose of jvp: (wx, wu, wp) = J^T (wxdot, wz); the Integer n and Boolean b get 0. */
static int vjp(double t, const double *x, const double *u, const double *p,
               const double *wxdot, const double *wz, double *wx, double *wu, double *wp)
{
    const double k = p[P_K], d = 0.1 * p[P_N], g = p[P_B] != 0.0 ? 1.0 : 0.0;

    (void)t;
    wx[0] = -k * wxdot[1] + k * wz[0];
    wx[1] = wxdot[0] - d * wxdot[1] + 2.0 * x[1] * wz[1];
    wx[2] = (u[0] > 1000.0 ? 2.0 * x[2] : -1.0) * wxdot[2] + wz[1];
    wu[0] = g * wxdot[1] + wz[0];
    wp[P_K] = -x[0] * wxdot[1] + x[0] * wz[0];
    wp[P_N] = 0.0;
    wp[P_B] = 0.0;
    wp[P_H] = 0.0;
    return 0;
}

#ifdef TEST_MODEL_ARRAYS
static const int fmi3_length[15] = { 3, 0, 0, 3, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1 };
#define FMI3_LENGTH fmi3_length
#else
#define FMI3_LENGTH 0
#endif

static const cosim_type types[15] = {
    COSIM_REAL, COSIM_REAL, COSIM_REAL,                        /* x */
    COSIM_REAL, COSIM_REAL, COSIM_REAL,                        /* der(x) */
    COSIM_REAL,                                                /* u */
    COSIM_REAL, COSIM_INTEGER, COSIM_BOOLEAN, COSIM_REAL,      /* p */
    COSIM_REAL, COSIM_INTEGER,                                 /* c */
    COSIM_REAL, COSIM_REAL                                     /* z */
};

static const double start[15] = {
    1.0, 0.0, 0.0,
    0.0, 0.0, 0.0,
    0.5,
    4.0, 2.0, 1.0, 0.0,
    0.0, 0.0,
    0.0, 0.0
};

static const unsigned char state_start_calculated[3] = { 0, 0, 1 };

static const char *const names[15] = {
    "s", "v", "w", "der(s)", "der(v)", "der(w)", "u", "k", "n", "b", "solver.fixedStepSize", "omega", "n10",
    "f", "e"
};

const cosim_model COSIM_MODEL = {
    TEST_MODEL_GUID,
    3, 1, 4, 2, 2,
    1e-6,
    10,
    types,
    start,
    state_start_calculated,
    calc_parameters,
    start_states,
    eval,
    jvp,
    names,
    0, /* no initial equations */
    0, /* dz of jvp: all algebraic variables */
    0, /* eval computes all of z */
    2, calc_hoisted, eval_hoisted,
    vjp,
    FMI3_LENGTH,
    0 /* value references from 0 */
};
