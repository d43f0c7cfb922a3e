/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_classifier.h
 * @brief Incremental nonlinearity classifier over a streaming moments estimator.
 *
 * Evidence. For a response observed with noise, the lag expansion of the conditional mean
 * (aenl_moments_taylor_ex, best on a symmetric estimator: lags -L and +L) gives at every grid node
 * the noise-free position p, the conditional velocity v and acceleration a. Over all pairs of a
 * stationary record E(v | p) = 0 and the points (p_k, a_k) trace the restoring-force curve of the
 * DOF, a(p) = -K(p) up to linear coupling with the other DOFs; per direction of motion (the
 * moments' direction split) a = f(p) + c v, the c v term carrying damping and the coupling a
 * direction changes (for a linear system, or one moving on one harmonic, E(other DOF | p, dir) is
 * linear in p and v). The classifier fits laws f to those points by weighted least squares
 * (weights 1 / se_a^2), the two directions sharing every coefficient:
 *     linear        f = c0 + c1 p                               (+ c v)
 *     polynomial    f = c0 + c1 p + c2 p^2 + c3 p^3             (+ c v)
 *     freeplay      f = c0 + c1 p + d1 (p - b1)+ [+ d2 (p - b2)+]   (+ c v), kinks searched
 *     hysteresis    the two-kink law with the kinks at b + s/2 while rising and b - s/2 while
 *                   falling (s >= 0 searched: a dissipative loop keeps the rising gap higher) and
 *                   an own offset for the rising points
 * The kinks are searched over every pair of points (suffix sums make each candidate O(1)) and
 * refined on the profile of the residual sum of squares; their standard error is where that
 * profile rises by one noise variance. Laws are compared by a robust information criterion:
 * sum of Huber losses of the residuals in units of the noise (the nominal standard errors, or the
 * scatter of the best-fitting law when that is larger) plus k ln n per law, n the independent
 * points (nodes times min(1, grid spacing / bandwidth)); a searched location (kink, shift) counts
 * three parameters (it is the best of many fits). Posterior weights exp(-criterion / 2) give the
 * class probabilities and the confidence. Without the direction split the same laws are fitted to
 * all pairs (no v term) and hysteresis cannot be told from freeplay.
 * Only the well-sampled interior is used: nodes whose pairs have an effective sample size of at
 * least cfg.min_n_eff, inside the central (1 - 2 trim) of the conditioning weight, where p(x)
 * still rises with x at least half as fast (beyond, the measured extremes are mostly noise).
 *
 * Memory: caller-owned state, no allocation; sizeof(aenl_classifier_t) fixed by
 * AENL_CLASSIFIER_MAX_NODES. Threading: none; re-entrant over its own state.
 */
#ifndef AENL_CLASSIFIER_H
#define AENL_CLASSIFIER_H

#include "aenl/aenl_moments.h"
#include "aenl/aenl_types.h"

/** Nodes the classifier reads (a moments grid may not have more). */
#ifndef AENL_CLASSIFIER_MAX_NODES
#define AENL_CLASSIFIER_MAX_NODES 64 /* host builds: 256 (CMakeLists.txt) */
#endif

/** Switching points reported at most (hysteresis: two kinks per direction). */
#define AENL_CLASSIFIER_MAX_SWITCH 4

/** Classes. aenl_class_name() gives the names `aenl identify` prints (docs/identify.md); the
 *  nonlinear classes come last, from AENL_CLASS_POLYNOMIAL on, and loops over them rely on it. */
typedef enum
{
    AENL_CLASS_INSUFFICIENT = 0, /**< not enough well-sampled nodes yet */
    AENL_CLASS_LINEAR = 1,
    AENL_CLASS_POLYNOMIAL = 2, /**< smooth hardening or softening */
    AENL_CLASS_FREEPLAY = 3,   /**< kinks at the same place in both directions */
    AENL_CLASS_HYSTERESIS = 4  /**< kinks that shift with the direction of motion */
} aenl_class_t;

/** Number of classes (for tables). */
#define AENL_CLASS_COUNT 5

/** Models fitted to the restoring-force points, indices into the result's bic[]. */
enum
{
    AENL_CLS_MODEL_LINEAR = 0,
    AENL_CLS_MODEL_POLY = 1,
    AENL_CLS_MODEL_KINK1 = 2,
    AENL_CLS_MODEL_KINK2 = 3,
    AENL_CLS_N_MODELS = 4
};

/** Configuration, copied by aenl_classifier_init(). */
typedef struct aenl_classifier_cfg
{
    uint16_t taylor_order; /**< lag expansion order, 2 .. AENL_MOMENTS_TAYLOR_MAX_ORDER and
                                < the moments' n_lags (default 2) */
    aenl_real_t trim;      /**< conditioning weight left out at each end, [0, 0.25) (0.03) */
    aenl_real_t min_n_eff; /**< least effective sample size of a node used (20) */
    uint16_t min_nodes;    /**< fewer usable nodes: class insufficient (8) */
    uint8_t use_noise_acf; /**< 1: the record was low-pass filtered before the moments; the lag
                                expansion then also fits the filtered noise's correlation
                                (aenl_moments_taylor_ex) with noise_acf (0) */
    aenl_real_t noise_acf[AENL_MOMENTS_MAX_LAGS]; /**< rho(lags[i]) of white noise through the
                                                       filter, rho(0) = 1 */
} aenl_classifier_cfg_t;

/** The decision after an update. */
typedef struct aenl_classifier_result
{
    aenl_class_t cls;                   /**< the class with the largest posterior weight */
    aenl_real_t confidence;             /**< its posterior weight, (0, 1]; 0 when insufficient */
    aenl_real_t prob[AENL_CLASS_COUNT]; /**< posterior weights of the classes (insufficient 0) */
    int8_t hardening; /**< polynomial: +1 hardening, -1 softening (sign of the cubic) */
    uint8_t n_switch; /**< switching points reported */
    aenl_real_t switch_points[AENL_CLASSIFIER_MAX_SWITCH]; /**< ascending, input units */
    aenl_real_t switch_std[AENL_CLASSIFIER_MAX_SWITCH];    /**< standard errors, input units */
    aenl_real_t bic[AENL_CLS_N_MODELS]; /**< criterion of the laws on all pairs, minus linear's */
    aenl_real_t bic_hysteresis; /**< criterion(hysteresis) - criterion(two-kink freeplay) on the
                                     direction-split points (< 0 favours hysteresis) */
    aenl_real_t evidence; /**< (BIC of the linear law - best nonlinear BIC) per independent point,
                               on the points the decision used; > 0 favours a nonlinear law */
    aenl_real_t slope[3]; /**< -da/dp on the segments of the two-kink law (stiffness-like) */
    uint16_t n_nodes;     /**< points used */
    uint32_t n_updates;   /**< updates so far */
    uint32_t n_stable;    /**< consecutive updates with the same class (settling) */
} aenl_classifier_result_t;

/** Working point (one node of one direction), scaled. Private. */
typedef struct aenl_cls_point
{
    aenl_real_t p, a, v, w;
} aenl_cls_point_t;

/** Suffix sums of a sorted point set (see aenl_classifier.c). Private. */
typedef struct aenl_cls_sums
{
    aenl_real_t s0, s1, s2, v0, v1, t0, t1;
} aenl_cls_sums_t;

/** Suffix-sum table of one point set: row i sums points i..n-1. Private. */
typedef struct aenl_cls_table
{
    aenl_cls_sums_t row[AENL_CLASSIFIER_MAX_NODES + 1];
    aenl_real_t wvv, wva, waa; /**< totals without a suffix form */
} aenl_cls_table_t;

/** Classifier state. Caller-owned (declare it static on an MCU); fields read-only. */
typedef struct aenl_classifier
{
    aenl_classifier_cfg_t cfg;
    aenl_classifier_result_t res;
    /* Working storage of one update (kept here, not on the stack): */
    aenl_cls_point_t pt[3][AENL_CLASSIFIER_MAX_NODES]; /**< all, rising, falling */
    aenl_cls_table_t tab[2];
    aenl_real_t cand[AENL_CLASSIFIER_MAX_NODES];      /**< candidate kink positions */
    aenl_real_t resid[2 * AENL_CLASSIFIER_MAX_NODES]; /**< residuals of both directions */
    uint8_t interior[AENL_CLASSIFIER_MAX_NODES];
} aenl_classifier_t;

/** Defaults as documented in aenl_classifier_cfg_t. */
void aenl_classifier_cfg_default(aenl_classifier_cfg_t *cfg);

/**
 * @brief Validate the configuration and set up a classifier with no decision (insufficient).
 * @return AENL_OK; AENL_E_ARG for NULL or a field out of range (*c not written).
 */
aenl_status_t aenl_classifier_init(aenl_classifier_t *c, const aenl_classifier_cfg_t *cfg);

/**
 * @brief Re-read the moments and update the decision.
 * @param[in,out] c  an initialised classifier
 * @param[in]     m  the estimator (read only): at least taylor_order + 1 lags, n_grid at most
 *                   AENL_CLASSIFIER_MAX_NODES; the direction split enables the hysteresis test
 *                   (without it a kinked law is reported as freeplay)
 * @return AENL_OK (the result may be AENL_CLASS_INSUFFICIENT); AENL_E_ARG for NULL or a
 *         configuration mismatch (too few lags for the order); AENL_E_DIM for a grid over
 *         AENL_CLASSIFIER_MAX_NODES. On error the previous result is kept.
 * @note Bounded work, no allocation: O(n_grid (n_lags order^2 + order^3)) for the expansions and
 *       O(n_nodes^2) for the kink searches; stack < 1 KiB.
 */
aenl_status_t aenl_classifier_update(aenl_classifier_t *c, const aenl_moments_t *m);

/** Current decision (never NULL for an initialised classifier). */
static inline const aenl_classifier_result_t *aenl_classifier_result(const aenl_classifier_t *c)
{
    return &c->res;
}

/** Lower-case class name as in the JSON contract ("linear", ...); "unknown" out of range. */
const char *aenl_class_name(aenl_class_t cls);

#endif /* AENL_CLASSIFIER_H */
