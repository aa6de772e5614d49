/*
 * tape_harness.c -- the tape interpreter (cosim_tape.c) on hand-written tapes, run by run.sh also
 * under the address and undefined-behaviour sanitizers: inputs from a NULL argument, outputs to a
 * NULL result, the constants an interpreter makes (infinities, NaN), a work array on the heap, an
 * unknown instruction.  (tests/test_tape.py compares every operation with CasADi's own C.)
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cosim_tape.h"

static int n_checks = 0, n_failed = 0;
#define CHECK(cond) (n_checks++, (cond) ? (void)0 : (void)(n_failed++, printf("FAILED %s:%d: %s\n", \
                                                                   __FILE__, __LINE__, #cond)))

static const double constants[2] = {2.5, -0.0};

/* z[0] = x[0]*2.5 + u (u from a NULL argument: 0), z[1] = -0.0, z[2..4] = inf, -inf, NaN,
   z[5] = hypot(x[0], x[1]) computed in work entry `high` */
#define TAPE(name, high)                                                                      \
    static const cosim_tape_instruction name##_code[] = {                                     \
        {TAPE_INPUT, 0, 0, 0}, {TAPE_INPUT, 1, 1, 0}, {TAPE_CONST, 2, 0, 0}, {TAPE_MUL, 2, 0, 2}, \
        {TAPE_ADD, 2, 2, 1}, {TAPE_OUTPUT, 2, 0, 0}, {TAPE_CONST, 2, 1, 0}, {TAPE_OUTPUT, 2, 0, 1}, \
        {TAPE_CONST, 2, 0, 1}, {TAPE_OUTPUT, 2, 0, 2}, {TAPE_CONST, 2, 0, 2}, {TAPE_OUTPUT, 2, 0, 3}, \
        {TAPE_CONST, 2, 0, 3}, {TAPE_OUTPUT, 2, 0, 4}, {TAPE_INPUT, 1, 0, 1},                   \
        {TAPE_HYPOT, high, 0, 1}, {TAPE_OUTPUT, high, 0, 5}};                                   \
    static const cosim_tape name = {(int)(sizeof name##_code / sizeof name##_code[0]), name##_code, \
                                    constants, high + 1}

TAPE(on_stack, 3);
TAPE(on_heap, 5000); /* more work than the interpreter keeps on the stack */

static void check_tape(const cosim_tape *tape)
{
    const double x[2] = {3.0, 4.0};
    const double *arg[2] = {x, NULL};
    double z[6];
    memset(z, 0, sizeof z);
    CHECK(cosim_tape_run(tape, arg, z) == 0);
    CHECK(z[0] == 7.5);
    CHECK(z[1] == 0.0 && signbit(z[1]));
    CHECK(isinf(z[2]) && z[2] > 0);
    CHECK(isinf(z[3]) && z[3] < 0);
    CHECK(isnan(z[4]));
    CHECK(z[5] == 5.0);
    CHECK(cosim_tape_run(tape, arg, NULL) == 0); /* no result wanted: nothing written */
}

int main(void)
{
    static const cosim_tape_instruction unknown_code[] = {{TAPE_INPUT, 0, 0, 0}, {200, 0, 0, 0}};
    const cosim_tape unknown = {2, unknown_code, constants, 1};
    const double x[1] = {1.0};
    const double *arg[1] = {x};
    double z[1] = {0.0};
    check_tape(&on_stack);
    check_tape(&on_heap);
    CHECK(cosim_tape_run(&unknown, arg, z) == 1);
    printf("tape: %d checks, %d failed\n", n_checks, n_failed);
    return n_failed != 0;
}
