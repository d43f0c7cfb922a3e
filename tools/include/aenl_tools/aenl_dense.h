/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_dense.h
 * @brief Host dense linear algebra on small row-major, contiguous double matrices, shared by
 *        the fit (EM), the identification (the record-alone test, the restoring-force
 *        regression) and the simulator: products, symmetrisation, a Cholesky factor with
 *        reciprocal pivots and its solves, a forward substitution, the LAPACK lower Cholesky
 *        factor and solves, and a Gauss-Jordan inverse.
 *
 * Each kernel fixes its arithmetic, which its callers' outputs depend on to the bit: every
 * product entry is the sum over the inner index in ascending order from 0.0, and the solves
 * substitute in index order. Kernels that round differently are separate kernels: the
 * hand-written Cholesky factor and its solve multiply by reciprocal pivots where the forward
 * substitution divides, and LAPACK's factor sums in its own order. The float32 firmware core
 * has its own linear algebra (src/aenl_linalg.c: no heap, no LAPACK).
 */
#ifndef AENL_TOOLS_DENSE_H
#define AENL_TOOLS_DENSE_H

#include <stddef.h>

/* ---- products -------------------------------------------------------------------------------- */

/** C (n x m) = A (n x k) B (k x m); c must not overlap a or b. */
void aenl_dense_mul(double *restrict c, const double *restrict a, const double *restrict b,
                    size_t n, size_t k, size_t m);

/**
 * @brief C (n x n) = A (n x k) B (k x n) for a product that is symmetric in exact arithmetic:
 *        the lower triangle is computed (as aenl_dense_mul would) and copied into the upper one.
 */
void aenl_dense_mul_sym(double *restrict c, const double *restrict a, const double *restrict b,
                        size_t n, size_t k);

/** C (n x m) = A' B with A (k x n), B (k x m); c must not overlap a or b. */
void aenl_dense_mul_tn(double *restrict c, const double *restrict a, const double *restrict b,
                       size_t n, size_t k, size_t m);

/** C (n x n) = A' B (A k x n, B k x n), symmetric: the lower triangle computed and mirrored. */
void aenl_dense_mul_tn_sym(double *restrict c, const double *restrict a, const double *restrict b,
                           size_t n, size_t k);

/* ---- symmetric matrices ---------------------------------------------------------------------- */

/** Copies the lower triangle of s (n x n) into its upper triangle. */
void aenl_dense_mirror_lower(double *s, size_t n);

/** Replaces each off-diagonal pair of a (n x n) by its mean; the diagonal is kept. */
void aenl_dense_symmetrise(double *a, size_t n);

/* ---- Cholesky factor with reciprocal pivots (hand-written) ----------------------------------- */

/**
 * @brief In-place lower Cholesky factor of the symmetric a (n x n, the lower triangle read; the
 *        upper one is left as it was). inv (may be NULL; n entries) receives the reciprocals of
 *        the diagonal, which aenl_dense_chol_solve multiplies by.
 * @return 0, or -1 when a pivot is not positive and finite.
 */
int aenl_dense_chol(double *a, size_t n, double *inv);

/**
 * @brief The factor of a copy of a into l (n x n): plain first, then with a diagonal jitter of
 *        1e-14 of the mean absolute diagonal, multiplied by 100 on each failure (8 attempts).
 * @return 0, or -1 when every attempt fails.
 */
int aenl_dense_chol_jitter(double *l, const double *a, size_t n, double *inv);

/**
 * @brief Solves (L L') X = B in place for B (n x m; each column a right-hand side), L and inv
 *        from aenl_dense_chol.
 */
void aenl_dense_chol_solve(const double *l, const double *inv, size_t n, double *b, size_t m);

/* ---- triangular ------------------------------------------------------------------------------ */

/** Solves L x = b in place (x holds b) for lower-triangular L (n x n), dividing by its pivots. */
void aenl_dense_lower_solve(const double *l, double *x, size_t n);

/* ---- LAPACK, lower factor -------------------------------------------------------------------- */

/**
 * @brief LAPACK's lower Cholesky factor (dpotrf) of the symmetric a (n x n) in place; the upper
 *        triangle is neither read nor written.
 * @return 0, or -1 when a is not positive definite.
 */
int aenl_dense_potrf(double *a, size_t n);

/** Solves (L L') X = B in place (dpotrs) for B (n x nrhs), l from aenl_dense_potrf. */
void aenl_dense_potrs(const double *l, size_t n, double *b, size_t nrhs);

/**
 * @brief Solves A X = B (dposv) for the symmetric positive definite A (n x n, lower triangle
 *        read) and B (n x nrhs): X replaces B, the lower Cholesky factor A.
 * @return 0, or -1 when A is not positive definite.
 */
int aenl_dense_posv(double *a, double *b, size_t n, size_t nrhs);

/* ---- inverse --------------------------------------------------------------------------------- */

/**
 * @brief Inverse of a (n x n) into inv by Gauss-Jordan elimination with partial pivoting (the
 *        first row of the largest magnitude); a is reduced in place.
 * @return 0, or -1 when a pivot is zero (inv is then incomplete).
 */
int aenl_dense_invert(double *a, double *inv, size_t n);

#endif /* AENL_TOOLS_DENSE_H */
