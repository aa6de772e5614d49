/*
 * cosim_tape.c -- the interpreter of the tapes of cosim_tape.h.  Each case is what CasADi 3.7's
 * code generator writes for the operation under C99 (casadi/core/calculus.h and its runtime
 * helpers casadi_sq, casadi_sign, casadi_fmin, ...), so that the results are the same bits
 * (tests/test_tape.py compares them with CasADi's C on ordinary and special values).  Like
 * CasADi's C, it rounds every operation to double: the same bits on SSE2 (x86-64, AArch64), not on
 * x87, where compiled code may keep intermediates in wider registers.
 */
#include <math.h>
#include <stdlib.h>

#include "cosim_runtime.h" /* RT_HIDDEN: an FMU exports only the FMI API */
#include "cosim_tape.h"

/* Work arrays up to this many doubles live on the stack (the rest on the heap). */
#define TAPE_STACK_WORK 1024

static int run(const cosim_tape *tape, const double *const *arg, double *res, double *w)
{
    const cosim_tape_instruction *in = tape->code, *end = tape->code + tape->n;
/* the operands, read only by the operations that have them (an INPUT's b is not a work index) */
#define X (w[in->a])
#define Y (w[in->b])
    for (; in < end; in++) {
        double *r = w + in->o;
        switch ((cosim_tape_op)in->op) {
        case TAPE_INPUT: *r = arg[in->a] ? arg[in->a][in->b] : 0; break;
        case TAPE_OUTPUT: if (res) res[in->b] = w[in->o]; break;
        case TAPE_CONST:
            *r = in->b == 0 ? tape->constants[in->a] : in->b == 1 ? INFINITY : in->b == 2 ? -INFINITY : NAN;
            break;
        case TAPE_ASSIGN: *r = X; break;
        case TAPE_ADD: *r = X + Y; break;
        case TAPE_SUB: *r = X - Y; break;
        case TAPE_MUL: *r = X * Y; break;
        case TAPE_DIV: *r = X / Y; break;
        case TAPE_NEG: *r = -X; break;
        case TAPE_TWICE: *r = 2. * X; break;
        case TAPE_SQ: *r = X * X; break;
        case TAPE_INV: *r = 1. / X; break;
        case TAPE_EXP: *r = exp(X); break;
        case TAPE_LOG: *r = log(X); break;
        case TAPE_POW: case TAPE_CONSTPOW: *r = pow(X, Y); break;
        case TAPE_SQRT: *r = sqrt(X); break;
        case TAPE_SIN: *r = sin(X); break;
        case TAPE_COS: *r = cos(X); break;
        case TAPE_TAN: *r = tan(X); break;
        case TAPE_ASIN: *r = asin(X); break;
        case TAPE_ACOS: *r = acos(X); break;
        case TAPE_ATAN: *r = atan(X); break;
        case TAPE_ATAN2: *r = atan2(X, Y); break;
        case TAPE_SINH: *r = sinh(X); break;
        case TAPE_COSH: *r = cosh(X); break;
        case TAPE_TANH: *r = tanh(X); break;
        case TAPE_ASINH: *r = asinh(X); break;
        case TAPE_ACOSH: *r = acosh(X); break;
        case TAPE_ATANH: *r = atanh(X); break;
        case TAPE_LT: *r = X < Y; break;
        case TAPE_LE: *r = X <= Y; break;
        case TAPE_EQ: *r = X == Y; break;
        case TAPE_NE: *r = X != Y; break;
        case TAPE_NOT: *r = !X; break;
        case TAPE_AND: *r = X && Y; break;
        case TAPE_OR: *r = X || Y; break;
        case TAPE_IF_ELSE_ZERO: *r = X ? Y : 0; break;
        case TAPE_FLOOR: *r = floor(X); break;
        case TAPE_CEIL: *r = ceil(X); break;
        case TAPE_FMOD: *r = fmod(X, Y); break;
        case TAPE_REMAINDER: *r = remainder(X, Y); break;
        case TAPE_FABS: *r = fabs(X); break;
        case TAPE_SIGN: *r = X < 0 ? -1 : X > 0 ? 1 : X; break;
        case TAPE_COPYSIGN: *r = copysign(X, Y); break;
        case TAPE_FMIN: *r = fmin(X, Y); break;
        case TAPE_FMAX: *r = fmax(X, Y); break;
        case TAPE_ERF: *r = erf(X); break;
        case TAPE_LOG1P: *r = log1p(X); break;
        case TAPE_EXPM1: *r = expm1(X); break;
        case TAPE_HYPOT: *r = hypot(X, Y); break;
        default: return 1; /* not a tape of this runtime */
        }
    }
#undef X
#undef Y
    return 0;
}

RT_HIDDEN int cosim_tape_run(const cosim_tape *tape, const double *const *arg, double *res)
{
    double stack[TAPE_STACK_WORK], *heap;
    int status;
    if (tape->nw <= TAPE_STACK_WORK) return run(tape, arg, res, stack);
    heap = (double *)malloc((size_t)tape->nw * sizeof(double));
    if (!heap) return 1;
    status = run(tape, arg, res, heap);
    free(heap);
    return status;
}
