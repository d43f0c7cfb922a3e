/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_rfs.h
 * @brief Multi-channel restoring-force regression with blocked cross-validation: which channel
 *        carries a nonlinear stiffness law, which law, and where it switches.
 *
 * The equation of motion of channel i, in discrete time on the pre-filtered record,
 *
 *     d2_i[n] = z[n]' beta + f_i(x_i[n], direction) + e[n]
 *
 * where d2 is the second difference, z holds every channel's position, central first difference
 * and (other channels only) second difference at n, every channel's position at a few longer lags
 * (the aerodynamic and turbulence memory), and a constant; f_i is the law to identify. Coupling to
 * the other degrees of freedom is linear in z, so a linear channel driven by a nonlinear one
 * shows no f: that is what names the channel. Not always in full: noise on the other channels'
 * second differences and aerodynamic states the lags span only in part let some of the force
 * through, and in a channel whose position moves with the nonlinear one's it can pass for a law
 * of its own; aenl_rfs_analyse_given() tells such an echo from its source. f_i is represented on a
 * grid of tent (linear B-spline) functions of x_i, separately for rising and falling motion; a law
 * is a linear map T from a few coefficients onto the tents (a polynomial up to x^5, one kink, a
 * freeplay gap, a direction-shifted hysteresis gap), so every candidate is a small projection on
 * accumulated cross-products.
 *
 * For a linear system driven by Gaussian turbulence the conditional mean of d2_i given z is
 * exactly linear, so no f is expected; for decays it is linear when the regressors span the
 * state. Evidence is not a threshold on a fit statistic but out-of-sample: the record is cut into
 * AENL_RFS_BLOCKS contiguous blocks, each law (its switching points chosen on all data) is fitted
 * with one block left out and scored on that block, and the per-block gains over the linear law
 * give a batch-means t statistic that carries the residual correlation, the kicks of decay
 * trains and non-stationarity with it.
 *
 * Streaming: aenl_rfs_push() takes one filtered row at a time; memory is fixed at creation
 * (cross-products per block), independent of the record's length.
 */
#ifndef AENL_TOOLS_RFS_H
#define AENL_TOOLS_RFS_H

#include <stddef.h>
#include <stdint.h>

#include "aenl/aenl.h"
#include "aenl_tools/aenl_io.h"

#define AENL_RFS_MAX_CH    8
#define AENL_RFS_MAX_NODES 48 /**< tents per direction */
#define AENL_RFS_MAX_LAGS  12 /**< extra position lags */
#define AENL_RFS_BLOCKS    16 /**< cross-validation blocks */
/** Batch-means t statistic (15 degrees of freedom) a nonlinear law must reach: a one-sided 1 %
 *  level, Bonferroni-corrected for the 4 laws of up to 3 channels (12 tests). */
#define AENL_RFS_T_CRIT 4.0

/** Laws of f (the class each belongs to in parentheses). */
typedef enum aenl_rfs_law
{
    AENL_RFS_LINEAR = 0,    /**< no f (linear) */
    AENL_RFS_POLY = 1,      /**< x^2 .. x^5 (polynomial: hardening, or softening whose
                                 stiffness may recover at large amplitude) */
    AENL_RFS_KINK = 2,      /**< one kink: preload or one-sided contact (freeplay) */
    AENL_RFS_GAP = 3,       /**< two kinks, the same in both directions (freeplay) */
    AENL_RFS_HYSTERESIS = 4 /**< a gap shifted between rising and falling motion, plus a
                                 rising-motion offset (hysteresis); the shift lags the motion
                                 (rising motion meets the gap higher up, as in the simulator's
                                 loop); it must beat the laws the same in both directions
                                 when each, and it, is given a rising-motion offset
                                 a + b x^2 */
} aenl_rfs_law_t;

#define AENL_RFS_N_LAWS 5

/** Configuration, copied by aenl_rfs_create(). */
typedef struct aenl_rfs_cfg
{
    size_t n_ch;                      /**< channels, 1..AENL_RFS_MAX_CH */
    double center[AENL_RFS_MAX_CH];   /**< standardisation (x - center) / scale */
    double scale[AENL_RFS_MAX_CH];    /**< > 0 */
    double lo[AENL_RFS_MAX_CH];       /**< tent grid ends per channel (input units); the law is */
    double hi[AENL_RFS_MAX_CH];       /**< extrapolated linearly beyond them */
    uint16_t n_nodes;                 /**< tents per direction, 8..AENL_RFS_MAX_NODES */
    uint16_t n_lags;                  /**< extra position lags, 0..AENL_RFS_MAX_LAGS */
    uint16_t lags[AENL_RFS_MAX_LAGS]; /**< samples, each >= 2 */
    size_t n_total;                   /**< rows that will be pushed (assigns the blocks) */
} aenl_rfs_cfg_t;

/** Result for one channel. */
typedef struct aenl_rfs_fit
{
    aenl_class_t cls;              /**< insufficient, linear, polynomial, freeplay, hysteresis */
    aenl_rfs_law_t law;            /**< the law chosen (linear when cls is linear) */
    double t[AENL_RFS_N_LAWS];     /**< batch-means t of each law's CV gain over linear */
    double gain[AENL_RFS_N_LAWS];  /**< CV gain as a fraction of the linear CV residual */
    double prob[AENL_CLASS_COUNT]; /**< class weights from paired t against the best law */
    double confidence;             /**< prob of cls */
    double evidence;     /**< max t of the laws the same in both directions (polynomial, kink, gap);
                              >= AENL_RFS_T_CRIT is nonlinear */
    int hardening;       /**< polynomial class: +1 hardening, -1 softening (the sign of the
                              cubic term; a saturating gap law is softening) */
    size_t n_points;     /**< switching points of the law chosen (0..4) */
    double points[4];    /**< ascending, input units */
    double point_std[4]; /**< block-jackknife standard errors, input units */
    size_t n_used;       /**< samples in the regression */
    /** The law chosen, fitted on all data, at the tent nodes (rising motion first, standardised
     *  units; 0 for the linear law): what aenl_rfs_analyse_given() adds to another channel. */
    double tents[2 * AENL_RFS_MAX_NODES];
} aenl_rfs_fit_t;

typedef struct aenl_rfs aenl_rfs_t;

/**
 * @brief Allocate and clear an accumulator.
 * @return AENL_OK; AENL_E_ARG (message in err) for a bad configuration; AENL_E_IO out of memory.
 */
aenl_status_t aenl_rfs_create(aenl_rfs_t **out, const aenl_rfs_cfg_t *cfg, aenl_err_t *err);

/** @brief One row of filtered samples (n_ch values, input units); a NaN/Inf value is a missing
 *  sample: no regression row is formed whose window contains it. */
void aenl_rfs_push(aenl_rfs_t *r, const double *row);

/**
 * @brief Choose the law of channel ch from what was pushed.
 * @return AENL_OK (out->cls insufficient when a block has too few rows); AENL_E_ARG for a bad
 *         channel; AENL_E_NUMERIC when the linear regressors are degenerate (message in err).
 */
aenl_status_t aenl_rfs_analyse(const aenl_rfs_t *r, size_t ch, aenl_rfs_fit_t *out,
                               aenl_err_t *err);

/**
 * @brief As aenl_rfs_analyse(), with channel `given`'s law (given_fit, from aenl_rfs_analyse of
 *        that channel) among channel ch's linear regressors, its coefficient free. A law that
 *        channel ch shows only because the nonlinear force of channel `given` reaches its
 *        equation (through the coupling, as a function of a position that moves with the other)
 *        is explained by it and no longer stands out. A linear given law adds nothing.
 * @return as aenl_rfs_analyse(); AENL_E_ARG also for given == ch or out of range.
 */
aenl_status_t aenl_rfs_analyse_given(const aenl_rfs_t *r, size_t ch, size_t given,
                                     const aenl_rfs_fit_t *given_fit, aenl_rfs_fit_t *out,
                                     aenl_err_t *err);

/**
 * @brief Fit every channel's free law (every tent coefficient free, on top of the linear terms)
 *        on all that was pushed, and start a residual pass (aenl_rfs_residual) from the
 *        record's beginning. The accumulated cross-products are kept: aenl_rfs_analyse() still
 *        reads them.
 * @return AENL_OK; AENL_E_NUMERIC for degenerate regressors, AENL_E_IO out of memory (message
 *         in err; the accumulator is unchanged).
 */
aenl_status_t aenl_rfs_model(aenl_rfs_t *r, aenl_err_t *err);

/**
 * @brief One row of a residual pass (rows as for aenl_rfs_push(), from the record's start):
 *        e[ch] is the equation error of channel ch's free-law model at the row before this one,
 *        in the standardised second-difference units the regression uses; NaN while the
 *        window fills, across a gap, or before aenl_rfs_model(). Nothing is accumulated.
 */
void aenl_rfs_residual(aenl_rfs_t *r, const double *row, double *e);

/** @brief Start the residual pass again from the record's beginning (the model is kept). */
void aenl_rfs_rewind(aenl_rfs_t *r);

void aenl_rfs_free(aenl_rfs_t *r);

#endif /* AENL_TOOLS_RFS_H */
