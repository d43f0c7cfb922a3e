/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nlt_internal.h
 * @brief Pieces of the record-alone test shared by its sources (not installed): the Kalman
 *        filter pass that keeps what the regressions need (aenl_nlt_filter.c), and the
 *        regressions on the innovations' sensitivities (aenl_nlt_design.c).
 */
#ifndef AENL_NLT_INTERNAL_H
#define AENL_NLT_INTERNAL_H

#include <stddef.h>

#include "aenl_tools/aenl_em.h"
#include "aenl_tools/aenl_nltest.h"

#define NLT_MAX_X         12    /* states of the linear model */
#define NLT_STEADY_TOL    1e-11 /* relative change of P at which the filter is taken as steady */
#define NLT_RIDGE         1e-10 /* relative ridge on the scaled normal equations */
#define NLT_IMPULSE_LEVEL 1e-4  /* tail of a jump statistic taken for an impulse */
#define NLT_IMPULSE_AT    2u    /* an impulse's flag at its sample */
#define NLT_IMPULSE_NEAR  1u    /* and within h samples of it, where it may be as well */
#define NLT_CHI2_1_95     3.841458820694124 /* chi-square_1 at 0.95: profile-likelihood intervals */
#define NLT_JUMP_SPAN     8u      /* a jump's window: at most this many times h either side */
#define NLT_DITHER_SEED   0x5EEDu /* the dither's noise: fixed, so a run is repeatable */
#define NLT_ROW_BLOCK     32      /* samples whose regression rows update G together */
#define NLT_NUIS_MAX      (1 + NLT_MAX_X + AENL_EM_MAX_U) /* nuisance series: offset, states, inputs */
#define NLT_R_KEEP_MAX    ((size_t)128 << 20) /* bytes of the nuisance's sensitivities kept */

typedef struct
{
    size_t n, nz, nx;
    double *eps;         /* n x nz whitened innovations (0 on a missing row) */
    unsigned char *used; /* 1: the row entered the update */
    double *u;           /* n x nz filtered outputs C x_{t|t} */
    double *xs;          /* nx x n filtered states, state-major (one series per state) */
    size_t *slot;        /* n: index into F and WC */
    double *F;           /* slots x nx x nx: A (I - K C) */
    double *WC;          /* slots x nz x nx: S^{-1/2} C */
    size_t n_slots, cap_slots;
    const double *in; /* n x n_in known inputs (scaled), NULL when none */
    size_t n_in;
    double ee;   /* sum of squared whitened innovations */
    size_t rows; /* innovations used (samples x channels) */
} kf_t;

/* A design: series (n values each) that are full (nx columns) or directed along dir (1 column). */
typedef struct
{
    size_t n_series;
    const double **g;  /* n_series pointers to n values */
    const int *full;   /* per series */
    const double *dir; /* nx: the direction of the directed series */
    size_t ncols;
    double *G; /* ncols x ncols */
    double *r; /* ncols */
    /* The cross-products of the first n_known columns when they are known already (n_known x
     * n_known, NULL: none): the nuisance's, the same in every design of a run, are accumulated
     * once and copied in instead of summed again. */
    const double *G_known;
    size_t n_known;
    /* The whitened sensitivities of those first n_known columns when they are known already
     * (n samples x nz x n_known, at the samples the filter used; NULL: none): a pass then walks
     * the sensitivities of the other columns only. R_save (n x nz x ncols, NULL: none) receives a
     * pass's sensitivities, to be handed to later designs as R_known. */
    const double *R_known;
    double *R_save;
} design_t;

/* Columns of the directed series, residualised on the nuisance columns 0..nn-1: Gt (ns x ns),
 * rt (ns). */
typedef struct
{
    size_t ns;
    double *Gt;
    double *rt;
} resid_t;

/* ---- aenl_nlt_filter.c (each function's comment is at its definition) ---- */

void nlt_kf_free(kf_t *k);

void nlt_kf_clear_run(kf_t *k);

aenl_status_t nlt_kf_run(kf_t *k, const aenl_em_model_t *m, const double *y,
                         const unsigned char *reset, const double *P_reset, aenl_err_t *err);

aenl_status_t nlt_impulses(const kf_t *k, int windows, unsigned char *flag, size_t *n_imp,
                           aenl_err_t *err);

void nlt_state_range(const kf_t *k, double *P);

/* ---- aenl_nlt_design.c ---- */

aenl_status_t nlt_design_accumulate(design_t *d, const kf_t *k, aenl_err_t *err);

void nlt_design_free(design_t *d);

double nlt_fit_subset(const design_t *d, const size_t *idx, size_t m, double *beta);

aenl_status_t nlt_design_robust(const design_t *d, const kf_t *k, size_t nn, const double *Pi,
                                double *score, double *meat, aenl_err_t *err);

aenl_status_t nlt_partial_coefficients(const design_t *d, size_t nn, double *Pi, aenl_err_t *err);

double nlt_quad_inverse(const double *A, const double *x, size_t n);

aenl_status_t nlt_residualise(const design_t *d, size_t nn, resid_t *out, aenl_err_t *err);

void nlt_resid_free(resid_t *r);

aenl_status_t nlt_design_losses(const design_t *d, const kf_t *k, const double *b, size_t n_fit,
                                double *loss, aenl_err_t *err);

double nlt_long_run_variance(const double *x, size_t n);

#endif
