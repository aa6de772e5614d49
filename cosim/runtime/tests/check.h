/*
 * check.h -- what the C harnesses (harness.c for the FMI 2 API, harness3.c for the FMI 3 API)
 * share: the check counters and macros, and the loader of a second FMU's functions (symbol,
 * SYMBOL). One header, included by each harness (one translation unit each). Each harness
 * defines its own CHECK_OK/CHECK_ERR for its version's status codes.
 */
#ifndef COSIM_TEST_CHECK_H
#define COSIM_TEST_CHECK_H

#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static int n_checks = 0, n_failed = 0;

#define CHECK(cond) check((cond) != 0, #cond, __FILE__, __LINE__)
#define CHECK_NEAR(a, b, tol) check_near((a), (b), (tol), #a, __FILE__, __LINE__)

static void check(int ok, const char *what, const char *file, int line)
{
    n_checks++;
    if (!ok) {
        n_failed++;
        printf("FAILED %s:%d: %s\n", file, line, what);
    }
}

static void check_near(double a, double b, double tol, const char *what, const char *file, int line)
{
    n_checks++;
    if (!(fabs(a - b) <= tol)) {
        n_failed++;
        printf("FAILED %s:%d: %s = %.17g, expected %.17g (+- %g)\n", file, line, what, a, b, tol);
    }
}

/* dlsym returns an object pointer; copying its bytes into a function pointer is the POSIX idiom
   that ISO C (-Wpedantic) accepts. */
static int symbol(void *lib, const char *name, void *fn_ptr, size_t size)
{
    void *p = dlsym(lib, name);
    if (!p) {
        printf("    %s: %s not found\n", name, dlerror());
        return 0;
    }
    memcpy(fn_ptr, &p, size);
    return 1;
}

#define SYMBOL(o, field, name) symbol((o)->lib, name, &(o)->field, sizeof (o)->field)

#endif
