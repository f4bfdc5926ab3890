/* ------------------------------------------------------------------------
 * The dense solves of a generated model's right-hand side, in place, no allocation:
 *
 *   int lagcli_solve_lu(n, K, r)             K x = r, any regular K (the augmented
 *                                            system [[M, -A^T], [A, 0]] of a
 *                                            constrained model): Gaussian elimination
 *                                            with partial pivoting
 *   int lagcli_solve_symmetric(n, K, r, d)   M x = r for the symmetric mass matrix of
 *                                            an unconstrained model: square-root-free
 *                                            Cholesky M = L D L^T (n^3/6 multiply-adds
 *                                            against LU's n^3/3, no pivot search, no
 *                                            square root, one division a row), and LU
 *                                            when M is not positive definite at this
 *                                            state
 *
 * K is n x n, row-major; r (n values) is overwritten by x, K by the factors; d is
 * room for n values (the reciprocal pivots 1/D). Returns 0, 1 when K is exactly
 * singular (a zero pivot), 2 when K, r or x is not finite. lagcli_solve_symmetric
 * reads K's lower triangle only (M is symmetric: the generated code writes both
 * triangles from the same expressions) and checks x only: a NaN or inf in that
 * triangle leaves the factorization to LU (see lagcli_ldlt), which checks K and r
 * first; one in r reaches x (L is unit triangular and 1/D finite and > 0).
 *
 * Static inline functions in a header, so `<name>.c` still compiles on its own
 * (`cc -shared <name>.c`), and the solve is written once here for every model
 * rather than once per generated file; the generated code calls them with its size
 * as a constant, which the compiler sees once they are inlined. At N = 40 links
 * the LU was 85% of the right-hand side (bench/README.md, issue 24).
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

/* M = L D L^T, L unit lower triangular: L goes into K's strict lower triangle, 1/D into
 * d; K's diagonal and upper triangle are left as they are (M again, for the LU fallback).
 * Column by column, as the entries of a column are independent of each other (they
 * pipeline; row by row, each entry waits for the one before it): row i holds
 * W[i][j] = L[i][j] D[j] until column i is reached, then L, while D[i] is formed.
 * Returns 1 unless every 1/D[i] is in (0, inf): a pivot that is not > 0, is too small
 * to invert or is NaN leaves the solve to LU. A NaN or inf in row i of the lower
 * triangle makes D[i] NaN or +-inf (the terms W L are >= 0), so it never passes. */
static inline int lagcli_ldlt(int n, double *K, double *d)
{
    int i, j, k;
    for (j = 0; j < n; ++j) {
        double *row_j = K + j * n;
        double pivot = row_j[j], reciprocal;
        for (k = 0; k < j; ++k) {           /* row j: W to L, D[j] = M[j][j] - sum_k W L */
            const double w = row_j[k], l = w * d[k];
            row_j[k] = l;
            pivot -= w * l;
        }
        reciprocal = 1.0 / pivot;
        if (!(reciprocal > 0.0 && reciprocal < INFINITY))
            return 1;
        d[j] = reciprocal;
        for (i = j + 1; i < n; ++i) {       /* column j: W[i][j] = M[i][j] - sum_k W[i][k] L[j][k] */
            double *row_i = K + i * n;
            row_i[j] -= lagcli_dot(j, row_i, row_j);
        }
    }
    return 0;
}

static inline int lagcli_solve_symmetric(int n, double *K, double *r, double *d)
{
    int i, k;
    if (lagcli_ldlt(n, K, d) != 0) {       /* not positive definite here: M back, then LU */
        for (i = 1; i < n; ++i)
            for (k = 0; k < i; ++k)
                K[i * n + k] = K[k * n + i];
        return lagcli_solve_lu(n, K, r);
    }
    for (i = 1; i < n; ++i) {               /* L z = r */
        double z = r[i];
        for (k = 0; k < i; ++k)
            z -= K[i * n + k] * r[k];
        r[i] = z;
    }
    for (i = 0; i < n; ++i)                 /* D y = z */
        r[i] *= d[i];
    for (i = n - 1; i >= 0; --i) {          /* L^T x = y: x[i] taken out of the rows above */
        const double x = r[i];
        for (k = 0; k < i; ++k)
            r[k] -= K[i * n + k] * x;
    }
    return lagcli_all_finite(n, r) ? 0 : 2;
}

#endif
