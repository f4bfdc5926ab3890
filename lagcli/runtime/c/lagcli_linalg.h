/* ------------------------------------------------------------------------
 * The dense solves of a generated model's right-hand side, in place, no allocation:
 *
 *   int lagcli_solve_lu(n, K, r)             K x = r, any regular K (the augmented
 *                                            system [[M, -A^T], [A, 0]] of a
 *                                            constrained model): Gaussian elimination
 *                                            with partial pivoting
 *   int lagcli_solve_symmetric(n, K, r, d)   M x = r for the symmetric mass matrix of
 *                                            an unconstrained model: LU below
 *                                            LAGCLI_CHOLESKY_MIN rows, else Cholesky
 *                                            (M = U^T U, n^3/6 multiply-adds against
 *                                            LU's n^3/3, no pivot search), and LU when
 *                                            M is not positive definite at this state
 *
 * K is n x n, row-major; r (n values) is overwritten by x, K by the factors; d is
 * room for n values (M's diagonal, kept for the LU fallback). Returns 0, 1 when K is
 * exactly singular (a zero pivot), 2 when K, r or x is not finite.
 *
 * Static inline functions in a header, so `<name>.c` still compiles on its own
 * (`cc -shared <name>.c`), and the solve is written once here for every model
 * rather than once per generated file. At N = 40 links the LU was 85% of the
 * right-hand side (bench/README.md, issue 24).
 * ------------------------------------------------------------------------ */
#ifndef LAGCLI_LINALG_H
#define LAGCLI_LINALG_H

#include <math.h>

static inline int lagcli_all_finite(int count, const double *v)
{
    int i;
    for (i = 0; i < count; ++i)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static inline int lagcli_solve_lu(int n, double *K, double *r)
{
    int i, j, k;
    if (!lagcli_all_finite(n * n, K) || !lagcli_all_finite(n, r))
        return 2;
    for (k = 0; k < n; ++k) {
        int pivot = k;
        double big = fabs(K[k * n + k]);
        for (i = k + 1; i < n; ++i) {
            if (fabs(K[i * n + k]) > big) {
                big = fabs(K[i * n + k]);
                pivot = i;
            }
        }
        if (big == 0.0)
            return 1;
        if (pivot != k) {
            double swap;
            for (j = k; j < n; ++j) {
                swap = K[k * n + j];
                K[k * n + j] = K[pivot * n + j];
                K[pivot * n + j] = swap;
            }
            swap = r[k];
            r[k] = r[pivot];
            r[pivot] = swap;
        }
        for (i = k + 1; i < n; ++i) {
            const double factor = K[i * n + k] / K[k * n + k];
            for (j = k + 1; j < n; ++j)
                K[i * n + j] -= factor * K[k * n + j];
            r[i] -= factor * r[k];
        }
    }
    for (k = n - 1; k >= 0; --k) {
        double sum = r[k];
        for (j = k + 1; j < n; ++j)
            sum -= K[k * n + j] * r[j];
        r[k] = sum / K[k * n + k];
    }
    return lagcli_all_finite(n, r) ? 0 : 2;
}

/* sum_k<m a[k] b[k] with four running sums (independent additions pipeline) */
static inline double lagcli_dot(int m, const double *a, const double *b)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int k = 0;
    for (; k + 4 <= m; k += 4) {
        s0 += a[k] * b[k];
        s1 += a[k + 1] * b[k + 1];
        s2 += a[k + 2] * b[k + 2];
        s3 += a[k + 3] * b[k + 3];
    }
    for (; k < m; ++k)
        s0 += a[k] * b[k];
    return (s0 + s1) + (s2 + s3);
}

static inline int lagcli_cholesky(int n, double *K)
{
    int i, j;
    for (j = 0; j < n; ++j) {
        const double *row_j = K + j * n;
        double pivot = row_j[j] - lagcli_dot(j, row_j, row_j);
        if (!(pivot > 0.0))
            return 1;
        pivot = sqrt(pivot);
        K[j * n + j] = pivot;
        for (i = j + 1; i < n; ++i) {
            double *row_i = K + i * n;
            row_i[j] = (row_i[j] - lagcli_dot(j, row_i, row_j)) / pivot;
        }
    }
    return 0;
}

/* Below this size LU is the faster solve: the generated RHS of the planar chain, CPU us
 * per call, Cholesky / LU: N = 5 0.156 / 0.131, N = 10 0.429 / 0.404, N = 15 0.915 / 1.445
 * (gcc 12 -O2, medians of alternated runs; bench/README.md, issue 24). */
#define LAGCLI_CHOLESKY_MIN 11

static inline int lagcli_solve_symmetric(int n, double *K, double *r, double *d)
{
    int i, k;
    if (n < LAGCLI_CHOLESKY_MIN)
        return lagcli_solve_lu(n, K, r);
    if (!lagcli_all_finite(n * n, K) || !lagcli_all_finite(n, r))
        return 2;
    for (i = 0; i < n; ++i)
        d[i] = K[i * n + i];
    if (lagcli_cholesky(n, K) != 0) {      /* not positive definite here: K back, then LU */
        for (i = 0; i < n; ++i) {
            K[i * n + i] = d[i];
            for (k = 0; k < i; ++k)
                K[i * n + k] = K[k * n + i];
        }
        return lagcli_solve_lu(n, K, r);
    }
    for (i = 0; i < n; ++i)                 /* L z = r */
        r[i] = (r[i] - lagcli_dot(i, K + i * n, r)) / K[i * n + i];
    for (i = n - 1; i >= 0; --i) {          /* L^T x = z */
        double sum = r[i];
        for (k = i + 1; k < n; ++k)
            sum -= K[k * n + i] * r[k];
        r[i] = sum / K[i * n + i];
    }
    return lagcli_all_finite(n, r) ? 0 : 2;
}

#endif
