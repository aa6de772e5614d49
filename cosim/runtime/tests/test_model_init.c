/*
 * test_model_init.c -- a COSIM_MODEL with an initial equation: the "initial equations" FMU of the
 * harness (run.sh builds it with the runtime into a shared library).
 *
 *   theta' = omega,  omega' = -sin(theta),  y = L sin(theta)
 *   initial equation:  L sin(theta) = h + u + omega     (theta: fixed = false, guess 0.3;
 *                                                         omega: fixed = true, start 0.5)
 *
 * The input u and the fixed state omega enter the initial equation, so that the harness can check
 * that values set in initializationMode are used.  start_states solves it by Newton's method as the
 * generated code does and reports COSIM_START_NOT_CONVERGED when max |residual| > 1e-10 (or NaN):
 * no real solution for |h + u + omega| > L.
 *
 * Value references (from 1, as in the FMUs `cosim build` writes; the other test models start at 0):
 *                   1 theta   2 omega   3 der(theta)   4 der(omega)   5 u   6 L   7 h
 *                   8 solver.fixedStepSize   9 y
 */
#include <math.h>

#include "cosim_model.h"

enum { P_L, P_H };

static int start_states(double t, const double *u, const double *p, const unsigned char *given, double *x0,
                        double *residual)
{
    double theta = given[0] ? x0[0] : 0.3, r = 0.0;
    const double omega = given[1] ? x0[1] : 0.5, target = p[P_H] + u[0] + omega;
    int i;

    (void)t;
    for (i = 0; i < 50; i++) {
        r = p[P_L] * sin(theta) - target;
        if (fabs(r) <= 1e-14) break;
        theta -= r / (p[P_L] * cos(theta));
    }
    r = p[P_L] * sin(theta) - target;
    x0[0] = theta;
    x0[1] = omega;
    *residual = fabs(r);
    return *residual <= 1e-10 ? 0 : COSIM_START_NOT_CONVERGED;
}

static int eval(double t, const double *x, const double *u, const double *p, double *xdot, double *z)
{
    (void)t;
    (void)u;
    xdot[0] = x[1];
    xdot[1] = -sin(x[0]);
    z[0] = p[P_L] * sin(x[0]);
    return 0;
}

static int jvp(double t, const double *x, const double *u, const double *p,
               const double *dx, const double *du, const double *dp, double *dxdot, double *dz)
{
    (void)t;
    (void)u;
    (void)du;
    dxdot[0] = dx[1];
    dxdot[1] = -cos(x[0]) * dx[0];
    dz[0] = dp[P_L] * sin(x[0]) + p[P_L] * cos(x[0]) * dx[0];
    return 0;
}

/* The transpose of jvp. */
static int vjp(double t, const double *x, const double *u, const double *p,
               const double *wxdot, const double *wz, double *wx, double *wu, double *wp)
{
    (void)t;
    (void)u;
    wx[0] = -cos(x[0]) * wxdot[1] + p[P_L] * cos(x[0]) * wz[0];
    wx[1] = wxdot[0];
    wu[0] = 0.0;
    wp[P_L] = sin(x[0]) * wz[0];
    wp[P_H] = 0.0;
    wp[2] = 0.0; /* solver.fixedStepSize */
    return 0;
}

static const cosim_type types[9] = { COSIM_REAL, COSIM_REAL, COSIM_REAL, COSIM_REAL, COSIM_REAL,
                                     COSIM_REAL, COSIM_REAL, COSIM_REAL, COSIM_REAL };
static const double start[9] = { 0.3, 0.5, 0.0, 0.0, 0.0, 2.0, 0.5, 0.0, 0.0 };
static const unsigned char state_start_calculated[2] = { 2, 0 };
static const char *const names[9] = { "theta", "omega", "der(theta)", "der(omega)", "u", "L", "h",
                                      "solver.fixedStepSize", "y" };

const cosim_model COSIM_MODEL = {
    "{0b7a1c55-2f0e-4c8e-9d3b-6a1e5f4c3b20}",
    2, 1, 3, 0, 1,
    1e-6,
    8,
    types,
    start,
    state_start_calculated,
    0,
    start_states,
    eval,
    jvp,
    names,
    "theta",
    0, /* dz of jvp: all algebraic variables */
    0, /* eval computes all of z */
    0, 0, 0, /* no hoisted parameter terms */
    vjp,
    0,       /* FMI 3: all scalars */
    1        /* value references from 1 */
};
