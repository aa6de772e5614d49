/*
 * test_model_small.c -- a second, smaller COSIM_MODEL: the "other FMU" of the FMU-state tests.
 *
 *   q' = -a q + u      (4 variables: q, der(q), input u, parameter a)
 *
 * run.sh compiles it with the runtime into shared libraries that the harness loads next to
 * its own model: once with its own GUID (a foreign FMU) and once with -DTEST_MODEL_GUID set to
 * the GUID of test_model.c (an FMU that claims the harness model's identity but has other sizes).
 *
 * It has no vjp (no adjoint derivatives): the FMI 3 harness checks that fmi3GetAdjointDerivative
 * refuses it.
 *
 * Value references: 0 q   1 der(q)   2 u   3 a
 */
#include "cosim_model.h"

#ifndef TEST_MODEL_GUID
#define TEST_MODEL_GUID "{5d1b2c3a-7f4e-4b21-9a63-0c2d7e8f1a42}"
#endif

static int eval(double t, const double *x, const double *u, const double *p, double *xdot, double *z)
{
    (void)t;
    (void)z;
    xdot[0] = -p[0] * x[0] + u[0];
    return 0;
}

static int jvp(double t, const double *x, const double *u, const double *p,
               const double *dx, const double *du, const double *dp, double *dxdot, double *dz)
{
    (void)t;
    (void)u;
    (void)dz;
    dxdot[0] = -p[0] * dx[0] - dp[0] * x[0] + du[0];
    return 0;
}

static const cosim_type types[4] = { COSIM_REAL, COSIM_REAL, COSIM_REAL, COSIM_REAL };
static const double start[4] = { 2.0, 0.0, 0.0, 1.0 };
static const unsigned char state_start_calculated[1] = { 0 };

const cosim_model COSIM_MODEL = {
    TEST_MODEL_GUID,
    1, 1, 1, 0, 0,
    1e-6,
    0,
    types,
    start,
    state_start_calculated,
    0,
    0,
    eval,
    jvp,
    0, /* no names: messages give value references */
    0, /* no initial equations */
    0, /* dz of jvp: all algebraic variables */
    0, /* eval computes all of z */
    0, 0, 0, /* no hoisted parameter terms */
    0,       /* no vjp: no adjoint derivatives */
    0,       /* FMI 3: all scalars */
    0        /* value references from 0 */
};
