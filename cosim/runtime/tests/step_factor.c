/*
 * step_factor.c -- the step size factor of the Co-Simulation integrator decides its clamped
 * ranges without the fifth root (cosim_runtime.c, step_factor): this compares it with the full
 * formula, RT_SAFETY / err^(1/5) clamped to [RT_FAC_MIN, fac_max], bit for bit, over err from
 * 1e-300 to 1e300 (a million values, dense around both bounds) and the special values.
 *
 * The runtime's own static functions are under test, so the file includes cosim_runtime.c; run.sh
 * links it with test_model_small.c (a COSIM_MODEL the runtime needs).
 */
#include "cosim_runtime.c"

#include <stdio.h>

static double reference(double err, double fac_max)
{
    if (!(err > 0.0)) return fac_max;
    return rt_min(fac_max, rt_max(RT_FAC_MIN, RT_SAFETY / rt_root(err, 5)));
}

int main(void)
{
    const double fac[2] = { 1.0, RT_FAC_MAX };
    const double special[6] = { 0.0, -1.0, INFINITY, NAN, DBL_MIN, DBL_MAX };
    long checks = 0, failed = 0, shortcut = 0;
    int f, i;
    long k;

    for (f = 0; f < 2; f++) {
        const double low = RT_SAFETY / fac[f], high = RT_SAFETY / RT_FAC_MIN;
        const double bounds[2] = { low * low * low * low * low, high * high * high * high * high };
        for (i = 0; i < 6; i++) {
            const double a = step_factor(special[i], fac[f]), b = reference(special[i], fac[f]);
            checks++;
            if (memcmp(&a, &b, sizeof a) != 0) failed++;
        }
        for (k = 0; k <= 400000; k++) {  /* err = 10^(-300 .. 300) */
            const double err = pow(10.0, -300.0 + 600.0 * (double)k / 400000.0);
            const double a = step_factor(err, fac[f]), b = reference(err, fac[f]);
            checks++;
            if (memcmp(&a, &b, sizeof a) != 0) failed++;
            if (a == fac[f] || a == RT_FAC_MIN) shortcut++;
        }
        for (i = 0; i < 2; i++) {        /* a factor 4 either side of each bound, densely */
            for (k = -50000; k <= 50000; k++) {
                const double err = bounds[i] * pow(4.0, (double)k / 50000.0);
                const double a = step_factor(err, fac[f]), b = reference(err, fac[f]);
                checks++;
                if (memcmp(&a, &b, sizeof a) != 0) failed++;
            }
        }
    }
    printf("step_factor: %ld checks, %ld differ from the full formula (%ld clamped)\n", checks, failed, shortcut);
    return failed != 0;
}
