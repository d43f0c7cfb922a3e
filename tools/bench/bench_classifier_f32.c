/* SPDX-License-Identifier: MIT */
/**
 * @file bench_classifier_f32.c
 * @brief `aenl_classifier_bench_f32`: the classifier of the float32 core (aenl_core_f32, the MCU
 *        build with the default aenl_config.h capacities): its state size, and the cost of one
 *        update on this host. Run by `aenl bench identify`.
 *
 * Record: a single-DOF oscillator with a freeplay spring (zero stiffness for |x| < 0.25, unit
 * slope outside, 40 samples per period, 2 % damping) driven by white noise (symplectic Euler, 8
 * steps per sample), 40 000 samples, plus measurement noise at SNR 3. Moments: 24 nodes over the
 * range (what the default 384 cells hold with 4 symmetric lags and the direction split),
 * bandwidth one spacing, lags 1, 2, 3, 5; the classifier at order 3, as the host pipeline uses,
 * with its other defaults. Figures are printed, never asserted; the exit status is 0 unless the
 * core rejects the configuration.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "aenl/aenl_classifier.h"
#include "aenl/aenl_moments.h"
#include "aenl_tools/aenl_clock.h"

#define N_REC 40000u

static aenl_moments_t g_m;
static aenl_classifier_t g_c;
static double g_rec[N_REC];

static uint64_t g_rng = 7u;

static double uniform(void)
{
    g_rng = g_rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

/* Sum of 12 uniforms minus 6: unit variance, approximately normal. */
static double noise(void)
{
    double s = 0.0;
    for (int i = 0; i < 12; ++i)
    {
        s += uniform();
    }
    return s - 6.0;
}

/* The noisy freeplay-oscillator record into g_rec; its range into lo, hi. */
static void make_record(double *lo, double *hi)
{
    const double w = 6.283185307179586 / 40.0, h = 1.0 / 8.0;
    double x = 0.0, v = 0.0, s1 = 0.0, s2 = 0.0;
    for (size_t k = 0; k < N_REC; ++k)
    {
        for (int j = 0; j < 8; ++j)
        {
            const double r = fabs(x) < 0.25 ? 0.0 : x - copysign(0.25, x);
            v += h * (-2.0 * 0.02 * w * v - w * w * r + 0.02 * noise());
            x += h * v;
        }
        g_rec[k] = x;
        s1 += x;
        s2 += x * x;
    }
    const double mean = s1 / N_REC, sd = sqrt(s2 / N_REC - mean * mean);
    *lo = 1e300;
    *hi = -1e300;
    for (size_t k = 0; k < N_REC; ++k)
    {
        g_rec[k] += sd / 3.0 * noise();
        *lo = g_rec[k] < *lo ? g_rec[k] : *lo;
        *hi = g_rec[k] > *hi ? g_rec[k] : *hi;
    }
}

int main(void)
{
    const uint16_t n_grid = 24u; /* 24 nodes x 8 lags (symmetric) x 2 directions = 384 cells */
    aenl_moments_cfg_t mc;
    aenl_classifier_cfg_t cc;
    double lo, hi;
    make_record(&lo, &hi);
    memset(&mc, 0, sizeof(mc));
    mc.x_min = (aenl_real_t)lo;
    mc.x_max = (aenl_real_t)hi;
    mc.n_grid = n_grid;
    mc.bandwidth = (mc.x_max - mc.x_min) / (aenl_real_t)(n_grid - 1u);
    mc.n_lags = 4u;
    mc.lags[0] = 1u;
    mc.lags[1] = 2u;
    mc.lags[2] = 3u;
    mc.lags[3] = 5u;
    mc.forgetting = 1.0f;
    mc.direction_split = 1u;
    mc.symmetric = 1u;
    aenl_classifier_cfg_default(&cc);
    cc.taylor_order = 3u;
    if (aenl_moments_init(&g_m, &mc) != AENL_OK || aenl_classifier_init(&g_c, &cc) != AENL_OK)
    {
        fprintf(stderr, "aenl_classifier_bench_f32: configuration rejected\n");
        return 1;
    }
    for (size_t k = 0; k < N_REC; ++k)
    {
        (void)aenl_moments_push(&g_m, (aenl_real_t)g_rec[k]);
    }
    double best = 1e30;
    for (int round = 0; round < 5; ++round)
    {
        const double t0 = aenl_now_s();
        for (int r = 0; r < 50; ++r)
        {
            (void)aenl_classifier_update(&g_c, &g_m);
        }
        const double t = (aenl_now_s() - t0) / 50.0;
        best = t < best ? t : best;
    }
    const aenl_classifier_result_t *res = aenl_classifier_result(&g_c);
    printf("  sizeof(aenl_classifier_t) = %zu B, sizeof(aenl_moments_t) = %zu B (float32, default "
           "capacities: %u classifier nodes, %u grid nodes, %u lags)\n",
           sizeof(aenl_classifier_t), sizeof(aenl_moments_t), (unsigned)AENL_CLASSIFIER_MAX_NODES,
           (unsigned)AENL_MOMENTS_MAX_GRID, (unsigned)AENL_MOMENTS_MAX_LAGS);
    printf("  one update on this host (float32, %u nodes, 4 symmetric lags, order 3): %.0f ns "
           "(freeplay oscillator at SNR 3 -> %s, %u points used)\n",
           (unsigned)n_grid, 1e9 * best, aenl_class_name(res->cls), (unsigned)res->n_nodes);
    return 0;
}
