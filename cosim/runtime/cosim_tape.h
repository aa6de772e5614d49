/*
 * cosim_tape.h -- a CasADi SX function as a tape of scalar instructions that cosim_tape.c
 * interprets: eval_locals of an FMU (every local algebraic variable, computed only when an importer
 * reads one; see cosim_model.h).
 *
 * `cosim build` writes the tape as constant tables in model.c (cosim/compiler/tape.py) instead of
 * C code: gcc reads a table of 10,000 instructions in a few hundredths of a second, where it took
 * most of a second to compile the same function as code, even without optimization.
 *
 * Every instruction computes exactly what CasADi's generated C computes for it (the same IEEE
 * operations and C library functions on the same values): a tape gives the same bits as the
 * function compiled by gcc (double arithmetic on SSE2).  One thing C leaves open: which zero fmin
 * and fmax return for +0 and -0; gcc passes their operands in either order, so compiled code does
 * not fix it either.
 */
#ifndef COSIM_TAPE_H
#define COSIM_TAPE_H

/* The operations (names as in CasADi's casadi::Operation without the OP_ prefix). */
typedef enum {
    TAPE_INPUT, TAPE_OUTPUT, TAPE_CONST, TAPE_ASSIGN,
    TAPE_ADD, TAPE_SUB, TAPE_MUL, TAPE_DIV, TAPE_NEG, TAPE_TWICE, TAPE_SQ, TAPE_INV,
    TAPE_EXP, TAPE_LOG, TAPE_POW, TAPE_CONSTPOW, TAPE_SQRT,
    TAPE_SIN, TAPE_COS, TAPE_TAN, TAPE_ASIN, TAPE_ACOS, TAPE_ATAN, TAPE_ATAN2,
    TAPE_SINH, TAPE_COSH, TAPE_TANH, TAPE_ASINH, TAPE_ACOSH, TAPE_ATANH,
    TAPE_LT, TAPE_LE, TAPE_EQ, TAPE_NE, TAPE_NOT, TAPE_AND, TAPE_OR, TAPE_IF_ELSE_ZERO,
    TAPE_FLOOR, TAPE_CEIL, TAPE_FMOD, TAPE_REMAINDER, TAPE_FABS, TAPE_SIGN, TAPE_COPYSIGN,
    TAPE_FMIN, TAPE_FMAX, TAPE_ERF, TAPE_LOG1P, TAPE_EXPM1, TAPE_HYPOT
} cosim_tape_op;

/* One instruction: w[o] = op(w[a], w[b]); INPUT: w[o] = arg[a][b] (0 if arg[a] is NULL);
   OUTPUT: res[b] = w[o] (nothing if res is NULL); CONST: w[o] = constants[a] if b is 0, else
   +infinity (b = 1), -infinity (2) or NaN (3), which not every C compiler takes in a static table. */
typedef struct {
    unsigned char op;  /* a cosim_tape_op */
    int o, a, b;
} cosim_tape_instruction;

typedef struct {
    int n;                                    /* instructions */
    const cosim_tape_instruction *code;
    const double *constants;
    int nw;                                   /* work doubles */
} cosim_tape;

/* Run the tape on the inputs arg (NULL entries read as zeros) into res; 0 on success, 1 if the work
   array could not be allocated or an instruction is unknown. */
int cosim_tape_run(const cosim_tape *tape, const double *const *arg, double *res);

#endif
