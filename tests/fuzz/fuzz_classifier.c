/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_classifier.c
 * @brief libFuzzer target: aenl_classifier over moments filled from arbitrary streams, with
 *        arbitrary classifier settings. Built twice (AENL_USE_DOUBLE 0 and 1) by
 *        tools/scripts/run_fuzz.sh.
 *
 * Input layout (every read past the end gives zeros):
 *   byte 0        flags: bit 0 direction split, bit 1 symmetric lags, bit 2 noise correlation on,
 *                 bit 3 raw classifier reals (any bit pattern)
 *   then          moments grid (nodes, span, bandwidth), 1..4 lags, classifier order, trim,
 *                 min_n_eff, min_nodes, the noise correlation per lag
 *   then ops      one op byte each, high 3 bits select: 0-3 a sample from a small oscillator
 *                 with kinks, scaled by the low bits, 4 a raw real, 5 NaN/Inf, 6 an update,
 *                 7 a burst of 64 oscillator samples
 *
 * Properties checked (abort() on violation):
 *  - init returns AENL_OK or AENL_E_ARG; update returns AENL_OK, AENL_E_ARG or AENL_E_DIM and,
 *    on error, leaves the result byte-identical;
 *  - every result: a class in range; probabilities finite in [0, 1] summing to 1 (0 when
 *    insufficient), the confidence that of the class; switching points only for freeplay and
 *    hysteresis, at most AENL_CLASSIFIER_MAX_SWITCH, finite, ascending, standard errors finite and
 *    positive; update and stable counters consistent.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_NAME "fuzz_classifier"
#include "fuzz_common.h"

#include "aenl/aenl_classifier.h"

static aenl_moments_t g_m;
static aenl_classifier_t g_c;

static void check_result(const aenl_classifier_result_t *r)
{
    CHECK((unsigned)r->cls < AENL_CLASS_COUNT, "class out of range");
    CHECK(r->n_switch <= AENL_CLASSIFIER_MAX_SWITCH, "too many switching points");
    aenl_real_t sum = AENL_R(0.0);
    for (int i = 0; i < AENL_CLASS_COUNT; ++i)
    {
        CHECK(aenl_is_finite(r->prob[i]), "probability not finite");
        CHECK(r->prob[i] >= AENL_R(0.0) && r->prob[i] <= AENL_R(1.0001), "probability range");
        sum += r->prob[i];
    }
    if (r->cls == AENL_CLASS_INSUFFICIENT)
    {
        CHECK(r->confidence <= AENL_R(0.0) && r->n_switch == 0u, "insufficient with a verdict");
        return;
    }
    CHECK(aenl_fabs(sum - AENL_R(1.0)) < AENL_R(1e-3), "probabilities do not sum to 1");
    CHECK(r->confidence >= r->prob[AENL_CLASS_LINEAR] - AENL_R(1e-6) &&
              r->confidence <= AENL_R(1.0001),
          "confidence is not the winner's probability");
    CHECK(aenl_fabs(r->confidence - r->prob[r->cls]) < AENL_R(1e-6), "confidence mismatch");
    if (r->cls == AENL_CLASS_LINEAR || r->cls == AENL_CLASS_POLYNOMIAL)
    {
        CHECK(r->n_switch == 0u, "switching points for a smooth law");
    }
    for (uint8_t k = 0; k < r->n_switch; ++k)
    {
        CHECK(aenl_is_finite(r->switch_points[k]), "switching point not finite");
        CHECK(aenl_is_finite(r->switch_std[k]) && r->switch_std[k] > AENL_R(0.0),
              "switching point std not finite and positive");
        if (k > 0u)
        {
            CHECK(r->switch_points[k] > r->switch_points[k - 1u], "switching points not ascending");
        }
    }
    CHECK(r->n_stable >= 1u && r->n_stable <= r->n_updates, "stable count");
}

/* A piecewise-linear oscillator, advanced one sample: kinks wherever the input puts them. */
typedef struct
{
    double x, v, gap, force;
} osc_t;

static double osc_step(osc_t *o, double kick)
{
    for (int s = 0; s < 4; ++s)
    {
        const double x = o->x;
        const double r = x > o->gap ? x - o->gap : (x < -o->gap ? x + o->gap : 0.1 * x);
        o->v += (-0.0025 * r - 0.001 * o->v + 0.01 * kick) * 0.25;
        o->x += o->v * 0.25;
    }
    if (!(fabs(o->x) < 1e6) || !(fabs(o->v) < 1e6))
    {
        o->x = 0.5;
        o->v = 0.0;
    }
    return o->x;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input_t in = {data, size};
    const uint8_t flags = take_u8(&in);
    aenl_moments_cfg_t mc;
    memset(&mc, 0, sizeof(mc));
    const aenl_real_t span = (aenl_real_t)(take_u8(&in) + 1) / AENL_R(32.0);
    mc.x_min = -span;
    mc.x_max = span;
    mc.n_grid = (uint16_t)(8u + take_u8(&in) % (AENL_CLASSIFIER_MAX_NODES + 8u));
    mc.bandwidth =
        AENL_R(2.0) * span / (aenl_real_t)mc.n_grid * (aenl_real_t)(1 + take_u8(&in) % 4);
    mc.n_lags = (uint16_t)(1u + take_u8(&in) % 4u);
    for (uint16_t i = 0; i < mc.n_lags; ++i)
    {
        mc.lags[i] = (uint16_t)(i * 2u + 1u + take_u8(&in) % 2u);
    }
    mc.forgetting = AENL_R(1.0);
    mc.direction_split = (uint8_t)(flags & 1u);
    mc.symmetric = (uint8_t)((flags >> 1) & 1u);
    if (aenl_moments_init(&g_m, &mc) != AENL_OK)
    {
        return 0; /* capacities: the moments module's own fuzzer covers its configuration */
    }
    aenl_classifier_cfg_t cc;
    aenl_classifier_cfg_default(&cc);
    if (flags & 8u)
    {
        cc.taylor_order = take_u16(&in);
        cc.trim = take_raw_real(&in);
        cc.min_n_eff = take_raw_real(&in);
        cc.min_nodes = take_u16(&in);
    }
    else
    {
        cc.taylor_order = (uint16_t)(2u + take_u8(&in) % 3u);
        cc.trim = (aenl_real_t)(take_u8(&in) % 25u) / AENL_R(100.0);
        cc.min_n_eff = (aenl_real_t)(1 + take_u8(&in) % 64);
        cc.min_nodes = (uint16_t)(8u + take_u8(&in) % 16u);
    }
    cc.use_noise_acf = (uint8_t)((flags >> 2) & 1u);
    for (uint16_t i = 0; i < AENL_MOMENTS_MAX_LAGS; ++i)
    {
        cc.noise_acf[i] = (aenl_real_t)(int8_t)take_u8(&in) / AENL_R(128.0);
    }
    const aenl_status_t st = aenl_classifier_init(&g_c, &cc);
    CHECK(st == AENL_OK || st == AENL_E_ARG, "init status");
    if (st != AENL_OK)
    {
        return 0;
    }
    osc_t o = {0.5 * (double)span, 0.0, 0.2 * (double)span, 0.0};
    uint32_t updates = 0u;
    while (in.n > 0u)
    {
        const uint8_t op = take_u8(&in);
        const uint8_t sel = (uint8_t)(op >> 5), low = (uint8_t)(op & 31u);
        if (sel <= 3u)
        {
            (void)aenl_moments_push(&g_m, (aenl_real_t)osc_step(&o, (double)low - 15.5));
        }
        else if (sel == 4u)
        {
            (void)aenl_moments_push(&g_m, take_raw_real(&in));
        }
        else if (sel == 5u)
        {
            (void)aenl_moments_push(&g_m, (low & 1u) ? (aenl_real_t)NAN : (aenl_real_t)INFINITY);
        }
        else if (sel == 6u)
        {
            const aenl_classifier_result_t before = *aenl_classifier_result(&g_c);
            const aenl_status_t su = aenl_classifier_update(&g_c, &g_m);
            CHECK(su == AENL_OK || su == AENL_E_ARG || su == AENL_E_DIM, "update status");
            if (su != AENL_OK)
            {
                CHECK(memcmp(&before, aenl_classifier_result(&g_c), sizeof(before)) == 0,
                      "a rejected update changed the result");
            }
            else
            {
                updates++;
                CHECK(aenl_classifier_result(&g_c)->n_updates == updates, "update count");
            }
            check_result(aenl_classifier_result(&g_c));
        }
        else
        {
            for (int k = 0; k < 64; ++k)
            {
                (void)aenl_moments_push(&g_m, (aenl_real_t)osc_step(&o, (double)(k % 7) - 3.0));
            }
        }
    }
    return 0;
}
