/*
 * pencil.c -- cosim.matrix.classify.modal_fit in one call: the matrix pencil fit of a signal.
 *
 * The algorithm and every threshold are those of classify.py (Hua & Sarkar, IEEE Trans. ASSP
 * 38(5), 1990; read the docstrings there), step by step with the LAPACK routines numpy calls for
 * them: dgeqrf and dgesdd (the Hankel matrix's R and its SVD), dgesdd again (the pseudo-inverse),
 * dgeev (the eigenvalues of the pencil) and zgelsd (the amplitudes). In numpy, a ten-second case
 * of a matrix spent two thirds of its classification in the per-call overhead around these five
 * small factorizations; here it is one call.
 *
 * The LAPACK routines are those of the process's numpy (its bundled OpenBLAS), handed over by
 * address (cosim/matrix/pencil.py); LAPACK_ILP64, set when this file is compiled for such a
 * library, makes their integers 64 bits wide (numpy's ILP64 OpenBLAS). Nothing here allocates LAPACK memory of its
 * own beyond one work buffer per call.
 */
#include <complex.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#ifdef LAPACK_ILP64
typedef long long lint;
#else
typedef int lint;
#endif

/* Fortran calling convention: every argument by address, a hidden length after the arguments
   for each character argument (gfortran). */
typedef void (*dgeqrf_fn)(const lint *, const lint *, double *, const lint *, double *, double *,
                          const lint *, lint *);
typedef void (*dgesdd_fn)(const char *, const lint *, const lint *, double *, const lint *, double *,
                          double *, const lint *, double *, const lint *, double *, const lint *, lint *,
                          lint *, size_t);
typedef void (*dgesvd_fn)(const char *, const char *, const lint *, const lint *, double *, const lint *,
                          double *, double *, const lint *, double *, const lint *, double *, const lint *,
                          lint *, size_t, size_t);
typedef void (*dgeev_fn)(const char *, const char *, const lint *, double *, const lint *, double *,
                         double *, double *, const lint *, double *, const lint *, double *, const lint *,
                         lint *, size_t, size_t);
typedef void (*zgelsd_fn)(const lint *, const lint *, const lint *, double complex *, const lint *,
                          double complex *, const lint *, double *, const double *, lint *,
                          double complex *, const lint *, double *, lint *, lint *);

typedef struct {
    dgeqrf_fn dgeqrf;
    dgesdd_fn dgesdd;
    dgesvd_fn dgesvd;
    dgeev_fn dgeev;
    zgelsd_fn zgelsd;
} pencil_lapack;

/* The thresholds of classify.py, passed by pencil.py from there (one source). */
typedef struct {
    int max_samples;        /* MODAL_SAMPLES */
    int max_order;          /* MODAL_MAX_ORDER */
    double max_residual;    /* MODAL_RESIDUAL */
    int small_pencil;       /* SMALL_PENCIL, or 0: n/3 only */
    int small_order;        /* SMALL_ORDER */
    double significant;     /* MODAL_SIGNIFICANT */
} pencil_settings;

/* What modal_fit returns (classify.ModalFit): modes [1/s] as (re, im), largest real part first,
   their contributions, the relative residual, the start [s] of the fitted window. */
typedef struct {
    int order;
    double residual, start;
    double *modes_re, *modes_im, *contributions;   /* room for max_order values each */
} pencil_fit;

enum { FIT_NONE = 0, FIT_FOUND = 1, FIT_NO_MEMORY = -1 };

/* ------------------------------------------------------------------ small helpers */

static void *zalloc(size_t n, size_t size) { return calloc(n ? n : 1, size); }

/* The k-th smallest of a[0..n) (rearranges a). */
static double select_kth(double *a, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        const double pivot = a[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot) i++;
            while (a[j] > pivot) j--;
            if (i <= j) {
                const double tmp = a[i]; a[i] = a[j]; a[j] = tmp;
                i++;
                if (j == 0) break;
                j--;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return a[k];
    }
    return a[k];
}

/* np.median of n > 0 values without NaN (rearranges a). */
static double median(double *a, size_t n)
{
    const size_t k = n / 2;
    double upper, lower;
    size_t i;
    upper = select_kth(a, n, k);
    if (n % 2) return upper;
    lower = a[0];  /* after selecting k, a[0..k) holds the k smallest values */
    for (i = 1; i < k; i++) if (a[i] > lower) lower = a[i];
    return (lower + upper) / 2;
}

/* classify._uniform_prefix: the longest prefix of t on one uniform grid (a last short step is
   dropped); 0 on no memory or a non-increasing grid. */
static size_t uniform_prefix(const double *t, size_t n)
{
    double *dt, h;
    size_t i, result = n;
    if (n < 3) return n;
    dt = malloc((n - 1) * sizeof *dt);
    if (!dt) return 0;
    for (i = 0; i + 1 < n; i++) dt[i] = t[i + 1] - t[i];
    h = median(dt, n - 1);
    if (!(h > 0)) {
        free(dt);
        return 0;
    }
    for (i = 0; i + 1 < n; i++) {
        if (fabs((t[i + 1] - t[i]) - h) > 1e-6 * h) {
            result = i + 1;
            break;
        }
    }
    free(dt);
    return result;
}

/* ------------------------------------------------------------------ the pencil */

/* classify._signal_subspace: the numerical rank of the Hankel matrix of x with pencil + 1 columns
   and its right singular vectors (vt: (pencil + 1) x (pencil + 1), column-major, rows are the
   vectors); -1 where the algebra fails or the matrix is 0, -2 on no memory. */
static int signal_subspace(const pencil_lapack *la, const double *x, size_t n, size_t pencil, double *vt)
{
    const lint m = (lint)(n - pencil), c = (lint)(pencil + 1), ldr = c;
    lint info = 0, lwork = -1, k;
    double query = 0.0, *y, *tau, *work, *r, *s, *u, floor, cut;
    lint *iwork;
    size_t i, j, half, count;
    int order = -2;

    if (m <= c) return -1;  /* classify.py takes the SVD of Y itself then; never so here (n >= 30) */
    y = malloc((size_t)m * (size_t)c * sizeof *y);
    tau = malloc((size_t)c * sizeof *tau);
    r = zalloc((size_t)c * (size_t)c, sizeof *r);
    s = malloc((size_t)c * sizeof *s);
    u = malloc((size_t)c * (size_t)c * sizeof *u);
    iwork = malloc(8 * (size_t)c * sizeof *iwork);
    work = NULL;
    if (!y || !tau || !r || !s || !u || !iwork) goto done;
    /* Y[i, j] = x[i + j], column-major: column j is x[j .. j + m) */
    for (j = 0; j < (size_t)c; j++) memcpy(y + j * (size_t)m, x + j, (size_t)m * sizeof *y);
    la->dgeqrf(&m, &c, y, &m, tau, &query, &lwork, &info);
    lwork = info == 0 ? (lint)query : 0;
    {
        lint lw2 = -1, one = 1;
        la->dgesvd("N", "S", &c, &c, r, &ldr, s, u, &one, vt, &c, &query, &lw2, &info, 1, 1);
        if (info == 0 && (lint)query > lwork) lwork = (lint)query;
    }
    if (info != 0 || lwork < 1) { order = -1; goto done; }
    work = malloc((size_t)lwork * sizeof *work);
    if (!work) goto done;
    la->dgeqrf(&m, &c, y, &m, tau, work, &lwork, &info);
    if (info != 0) { order = -1; goto done; }
    for (j = 0; j < (size_t)c; j++)      /* R: the upper triangle of the first c rows */
        for (i = 0; i <= j; i++) r[i + j * (size_t)c] = y[i + j * (size_t)m];
    {   /* the right singular vectors only (numpy's gesdd also forms U, which the pencil does not use) */
        const lint one = 1;
        la->dgesvd("N", "S", &c, &c, r, &ldr, s, u, &one, vt, &c, work, &lwork, &info, 1, 1);
    }
    if (info != 0 || !(s[0] > 0)) { order = -1; goto done; }
    /* the noise floor: the median of the lower half of the (descending) spectrum */
    half = (size_t)c / 2;
    {
        const size_t len = (size_t)c - half, mid = len / 2;
        floor = len % 2 ? s[half + mid] : (s[half + mid - 1] + s[half + mid]) / 2;
    }
    cut = 30.0 * floor > 1e-7 * s[0] ? 30.0 * floor : 1e-7 * s[0];
    for (count = 0, k = 0; k < c; k++) count += s[k] > cut;
    order = (int)count;
done:
    free(y); free(tau); free(r); free(s); free(u); free(iwork); free(work);
    return order;
}

/* classify._pencil on xs (n samples, step h): the exponents lam [1/s], the contributions |a| and
   the residuals of the fit; the number of modes, 0 where the fit fails or needs more than
   max_order modes, -1 on no memory. lam_re, lam_im and contrib have room for n values. */
static int pencil_fit_once(const pencil_lapack *la, const pencil_settings *ps, const double *xs, size_t n,
                           double h, int small, double *lam_re, double *lam_im, double *contrib,
                           double *residual, double *rms)
{
    size_t pencil = 0, L, i, j, k, m;
    int order = -1, result = -1;
    double *vt = NULL, *v1 = NULL, *v2 = NULL, *s = NULL, *u = NULL, *w = NULL, *p = NULL, *work = NULL;
    double *wr = NULL, *wi = NULL, *rwork = NULL, *tmp = NULL;
    double complex *zm = NULL, *b = NULL, *zw = NULL, *z = NULL;
    lint *iwork = NULL;

    if (small && ps->small_pencil > 0 && (size_t)ps->small_pencil < n / 3) {
        pencil = (size_t)ps->small_pencil;
        vt = malloc((pencil + 1) * (pencil + 1) * sizeof *vt);
        if (!vt) return -1;
        order = signal_subspace(la, xs, n, pencil, vt);
        if (order == -2) goto done;
        if (order > ps->small_order || order < 0) {
            order = -1;
            free(vt);
            vt = NULL;
        }
    }
    if (order < 0) {
        pencil = n / 3;
        vt = malloc((pencil + 1) * (pencil + 1) * sizeof *vt);
        if (!vt) return -1;
        order = signal_subspace(la, xs, n, pencil, vt);
        if (order == -2) goto done;
        if (order < 0) { result = 0; goto done; }
    }
    if (order > ps->max_order || order == 0) { result = 0; goto done; }
    L = pencil + 1;   /* rows of v = vt[:order].T */
    {
        /* P = pinv(v[:-1]) @ v[1:] as numpy's pinv: SVD, singular values <= 1e-15 max(s) dropped */
        const lint rows = (lint)(L - 1), r = (lint)order;
        lint info = 0, lwork = -1;
        double query = 0.0, cutoff;
        v1 = malloc((L - 1) * (size_t)order * sizeof *v1);
        v2 = malloc((L - 1) * (size_t)order * sizeof *v2);
        s = malloc((size_t)order * sizeof *s);
        u = malloc((L - 1) * (size_t)order * sizeof *u);
        w = malloc((size_t)order * (size_t)order * sizeof *w);
        p = zalloc((size_t)order * (size_t)order, sizeof *p);
        tmp = zalloc((size_t)order * (size_t)order, sizeof *tmp);
        iwork = malloc(8 * (size_t)order * sizeof *iwork);
        if (!v1 || !v2 || !s || !u || !w || !p || !tmp || !iwork) goto done;
        /* v[i, j] = vt[j, i] (vt column-major with leading dimension L) */
        for (j = 0; j < (size_t)order; j++)
            for (i = 0; i + 1 < L; i++) {
                v1[i + j * (L - 1)] = vt[j + i * L];
                v2[i + j * (L - 1)] = vt[j + (i + 1) * L];
            }
        la->dgesdd("S", &rows, &r, v1, &rows, s, u, &rows, w, &r, &query, &lwork, iwork, &info, 1);
        if (info != 0) { result = 0; goto done; }
        lwork = (lint)query;
        work = malloc((size_t)(lwork > 0 ? lwork : 1) * sizeof *work);
        if (!work) goto done;
        la->dgesdd("S", &rows, &r, v1, &rows, s, u, &rows, w, &r, work, &lwork, iwork, &info, 1);
        if (info != 0) { result = 0; goto done; }
        cutoff = 1e-15 * s[0];
        /* tmp = diag(1/s) U^T v2 (order x order), then P = V tmp, with V = w^T */
        for (j = 0; j < (size_t)order; j++)
            for (i = 0; i < (size_t)order; i++) {
                double acc = 0.0;
                if (!(s[i] > cutoff)) continue;
                for (k = 0; k + 1 < L; k++) acc += u[k + i * (L - 1)] * v2[k + j * (L - 1)];
                tmp[i + j * (size_t)order] = acc / s[i];
            }
        for (j = 0; j < (size_t)order; j++)
            for (i = 0; i < (size_t)order; i++) {
                double acc = 0.0;
                for (k = 0; k < (size_t)order; k++) acc += w[k + i * (size_t)order] * tmp[k + j * (size_t)order];
                p[i + j * (size_t)order] = acc;
            }
        free(work);
        work = NULL;
        /* the eigenvalues z of P */
        wr = malloc((size_t)order * sizeof *wr);
        wi = malloc((size_t)order * sizeof *wi);
        if (!wr || !wi) goto done;
        lwork = -1;
        la->dgeev("N", "N", &r, p, &r, wr, wi, NULL, &r, NULL, &r, &query, &lwork, &info, 1, 1);
        if (info != 0) { result = 0; goto done; }
        lwork = (lint)query;
        work = malloc((size_t)(lwork > 0 ? lwork : 1) * sizeof *work);
        if (!work) goto done;
        {
            const lint one = 1;
            la->dgeev("N", "N", &r, p, &r, wr, wi, NULL, &one, NULL, &one, work, &lwork, &info, 1, 1);
        }
        if (info != 0) { result = 0; goto done; }
        free(work);
        work = NULL;
    }
    z = malloc((size_t)order * sizeof *z);
    if (!z) goto done;
    for (m = 0, j = 0; j < (size_t)order; j++) {
        const double complex zj = wr[j] + I * wi[j];
        if (cabs(zj) > 0) z[m++] = zj;
    }
    if (!m) { result = 0; goto done; }
    {
        /* columns z^(k - k0), anchored at the end for growing modes (as classify.py), by repeated
           multiplication from the anchor; then the least-squares amplitudes (zgelsd, rcond as
           numpy's lstsq: eps max(n, m)) */
        const lint rows = (lint)n, cols = (lint)m, one = 1;
        const double rcond = 2.220446049250313e-16 * (double)(n > m ? n : m);
        lint info = 0, lwork = -1, rank = 0, liwork;
        double complex query = 0.0;
        double rquery = 0.0, err2 = 0.0, x2 = 0.0;
        lint iquery = 0;
        zm = malloc(n * m * sizeof *zm);
        b = malloc(n * sizeof *b);
        if (!zm || !b) goto done;
        for (j = 0; j < m; j++) {
            double complex *col = zm + j * n;
            if (cabs(z[j]) > 1.0) {
                const double complex step = 1.0 / z[j];
                col[n - 1] = 1.0;
                for (k = n - 1; k > 0; k--) col[k - 1] = col[k] * step;
            } else {
                col[0] = 1.0;
                for (k = 1; k < n; k++) col[k] = col[k - 1] * z[j];
            }
            for (k = 0; k < n; k++)
                if (!isfinite(creal(col[k])) || !isfinite(cimag(col[k]))) { result = 0; goto done; }
        }
        for (k = 0; k < n; k++) b[k] = xs[k];
        free(s);
        s = malloc(m * sizeof *s);
        zw = malloc(n * m * sizeof *zw);
        if (!s || !zw) goto done;
        memcpy(zw, zm, n * m * sizeof *zw);  /* zgelsd overwrites it; zm is kept for the fit */
        la->zgelsd(&rows, &cols, &one, zw, &rows, b, &rows, s, &rcond, &rank, &query, &lwork, &rquery,
                   &iquery, &info);
        if (info != 0) { result = 0; goto done; }
        lwork = (lint)creal(query);
        liwork = iquery > 1 ? iquery : 1;
        free(iwork);
        iwork = malloc((size_t)liwork * sizeof *iwork);
        rwork = malloc((size_t)(rquery > 1 ? rquery : 1) * sizeof *rwork);
        {
            double complex *zwork = malloc((size_t)(lwork > 0 ? lwork : 1) * sizeof *zwork);
            if (!iwork || !rwork || !zwork) { free(zwork); goto done; }
            la->zgelsd(&rows, &cols, &one, zw, &rows, b, &rows, s, &rcond, &rank, zwork, &lwork, rwork, iwork,
                       &info);
            free(zwork);
        }
        if (info != 0) { result = 0; goto done; }
        /* fit = Re(Z coef); the residual relative to x and as an RMS */
        for (k = 0; k < n; k++) {
            double complex acc = 0.0;
            double e;
            for (j = 0; j < m; j++) acc += zm[k + j * n] * b[j];
            e = xs[k] - creal(acc);
            err2 += e * e;
            x2 += xs[k] * xs[k];
        }
        *residual = sqrt(err2) / sqrt(x2);
        *rms = sqrt(err2) / sqrt((double)n);
        for (j = 0; j < m; j++) {
            const double complex lam = clog(z[j]) / h;
            lam_re[j] = creal(lam);
            lam_im[j] = cimag(lam);
            contrib[j] = cabs(b[j]);
        }
        result = (int)m;
    }
done:
    free(vt); free(v1); free(v2); free(s); free(u); free(w); free(p); free(tmp); free(work);
    free(wr); free(wi); free(rwork); free(zm); free(b); free(zw); free(z); free(iwork);
    return result;
}

/* ------------------------------------------------------------------ modal_fit */

/* classify.modal_fit of (t, x), n samples: FIT_FOUND with *fit filled, FIT_NONE, or
   FIT_NO_MEMORY. */
int cosim_modal_fit(const pencil_lapack *la, const pencil_settings *ps, const double *t, const double *x,
                    size_t n, int small, pencil_fit *fit)
{
    size_t i, first_k, starts[2];
    double *xs = NULL, *lam_re = NULL, *lam_im = NULL, *contrib = NULL;
    int status = FIT_NO_MEMORY;

    n = uniform_prefix(t, n);
    if (n < 30) return FIT_NONE;
    for (i = 0; i < n; i++) if (!isfinite(x[i])) return FIT_NONE;
    xs = malloc(n * sizeof *xs);
    lam_re = malloc(n * sizeof *lam_re);
    lam_im = malloc(n * sizeof *lam_im);
    contrib = malloc(n * sizeof *contrib);
    if (!xs || !lam_re || !lam_im || !contrib) goto done;
    status = FIT_NONE;
    starts[0] = 0;
    starts[1] = n / 3;
    for (first_k = 0; first_k < 2; first_k++) {
        const size_t first = starts[first_k], size = n - first;
        const size_t stride = size > (size_t)ps->max_samples
            ? (size + (size_t)ps->max_samples - 1) / (size_t)ps->max_samples : 1;
        const size_t count = (size + stride - 1) / stride;
        double peak = 0.0, h, residual = 0.0, rms = 0.0, threshold;
        int found, kept, a, b;
        for (i = 0; i < count; i++) {
            const double v = fabs(x[first + i * stride]);
            if (v > peak) peak = v;
        }
        if (count < 30 || !(peak > 0)) continue;
        h = t[first + stride] - t[first];
        for (i = 0; i < count; i++) xs[i] = x[first + i * stride] / peak;  /* the thresholds are relative */
        found = pencil_fit_once(la, ps, xs, count, h, small, lam_re, lam_im, contrib, &residual, &rms);
        if (found < 0) { status = FIT_NO_MEMORY; goto done; }
        if (found == 0 || residual > ps->max_residual) continue;
        threshold = 100.0 * rms > ps->significant ? 100.0 * rms : ps->significant;
        for (kept = 0, a = 0; a < found; a++) {
            if (!(contrib[a] >= threshold)) continue;
            lam_re[kept] = lam_re[a], lam_im[kept] = lam_im[a], contrib[kept] = contrib[a];
            kept++;
        }
        if (!kept) continue;
        /* largest real part first (a stable insertion sort of at most max_order modes) */
        for (a = 1; a < kept; a++) {
            const double re = lam_re[a], im = lam_im[a], c = contrib[a];
            for (b = a; b > 0 && lam_re[b - 1] < re; b--) {
                lam_re[b] = lam_re[b - 1], lam_im[b] = lam_im[b - 1], contrib[b] = contrib[b - 1];
            }
            lam_re[b] = re, lam_im[b] = im, contrib[b] = c;
        }
        fit->order = kept;
        fit->residual = residual;
        fit->start = t[first];
        for (a = 0; a < kept; a++) {
            fit->modes_re[a] = lam_re[a];
            fit->modes_im[a] = lam_im[a];
            fit->contributions[a] = contrib[a];
        }
        status = FIT_FOUND;
        break;
    }
done:
    free(xs); free(lam_re); free(lam_im); free(contrib);
    return status;
}
