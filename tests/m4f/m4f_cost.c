/* SPDX-License-Identifier: MIT */
/**
 * @file m4f_cost.c
 * @brief Instructions per sample of the core's streaming calls on the emulated Cortex-M4F.
 *
 * Run under QEMU with `-icount shift=0`: the emulator then advances its clock by one nanosecond
 * per instruction, and SysTick counts that clock. A loop of known length (two instructions per
 * turn) converts ticks to instructions in the same run, so no clock rate is assumed. Figures are
 * printed, never asserted; the exit status is 0 unless the core rejects a configuration.
 *
 * Measured: aenl_moments_push in the standard configuration (64 nodes, lags 1, 10, 30, direction
 * split, bandwidth three node spacings) over an AR(2) record; aenl_skf_step of an 8-state,
 * 2-output, 3-mode threshold model (four oscillators, the first one's stiffness switching with
 * its position); aenl_classifier_update on that moments state.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "aenl/aenl.h"
#include "aenl_bench_cfg.h"

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define SYST_MAX 0xFFFFFFu

#define N_SAMPLES 4000u
#define N_SPIN    1000000u

static aenl_moments_t g_moments;
static aenl_classifier_t g_classifier;
static aenl_skf_t g_filter;
static aenl_skf_model_t g_model;
static float g_x[N_SAMPLES];
static float g_z[N_SAMPLES][2];

/* SysTick from its top, on the processor clock; ticks() is the count since (under 2^24). */
static void ticks_start(void)
{
    SYST_CSR = 0u;
    SYST_RVR = SYST_MAX;
    SYST_CVR = 0u;
    SYST_CSR = 5u; /* enable, processor clock, no interrupt */
}

static int g_wrapped = 0;

static uint32_t ticks(void)
{
    const uint32_t t = SYST_MAX - (SYST_CVR & SYST_MAX);
    g_wrapped |= (SYST_CSR & (1u << 16)) != 0u; /* COUNTFLAG: the counter went past zero */
    return t;
}

/* Exactly two instructions per turn (subtract, branch). */
static void spin(uint32_t n)
{
    __asm volatile("1:\n\tsubs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

static uint32_t g_lcg = 2024u;

static float uniform(void)
{
    g_lcg = g_lcg * 1664525u + 1013904223u;
    return (float)(g_lcg >> 8) * (1.0f / 16777216.0f);
}

static void make_records(void)
{
    float y1 = 0.0f, y2 = 0.0f;
    float p[8] = {0.0f};
    for (uint32_t n = 0; n < N_SAMPLES; ++n)
    {
        const float y = 1.6f * y1 - 0.8f * y2 + 0.735f * (uniform() + uniform() - 1.0f);
        y2 = y1;
        y1 = y;
        g_x[n] = 1000.0f + y;
        for (unsigned i = 0; i < 8u; i += 2u) /* four lightly damped oscillators, noise-driven */
        {
            const float a = p[i], b = p[i + 1u];
            p[i] = 0.98f * (0.95f * a - 0.31f * b) + 0.05f * (uniform() - 0.5f);
            p[i + 1u] = 0.98f * (0.31f * a + 0.95f * b);
        }
        g_z[n][0] = p[0] + p[2] + 0.01f * (uniform() - 0.5f);
        g_z[n][1] = p[4] - p[6] + 0.01f * (uniform() - 0.5f);
    }
}

/* Four 2 x 2 rotation blocks; mode 1 (inside +-0.02 of the first state) has the first
 * oscillator's frequency lower, as a freeplay softens it. */
static void make_model(void)
{
    memset(&g_model, 0, sizeof(g_model));
    g_model.n_x = 8u;
    g_model.n_z = 2u;
    g_model.n_modes = 3u;
    g_model.switch_state = 0u;
    g_model.dir_state = AENL_SKF_DIR_DIFF;
    g_model.thr_rising[0] = g_model.thr_falling[0] = -0.02f;
    g_model.thr_rising[1] = g_model.thr_falling[1] = 0.02f;
    for (unsigned s = 0; s < 3u; ++s)
    {
        for (unsigned i = 0; i < 8u; i += 2u)
        {
            const float c = (s == 1u && i == 0u) ? 0.97f : 0.95f;
            const float w = (s == 1u && i == 0u) ? 0.24f : 0.31f;
            g_model.A[s][i][i] = 0.98f * c;
            g_model.A[s][i][i + 1u] = -0.98f * w;
            g_model.A[s][i + 1u][i] = 0.98f * w;
            g_model.A[s][i + 1u][i + 1u] = 0.98f * c;
            g_model.Q[s][i][i] = 2e-4f;
            g_model.Q[s][i + 1u][i + 1u] = 1e-6f;
        }
    }
    g_model.C[0][0] = g_model.C[0][2] = 1.0f;
    g_model.C[1][4] = 1.0f;
    g_model.C[1][6] = -1.0f;
    g_model.R[0][0] = g_model.R[1][1] = 1e-5f;
    for (unsigned i = 0; i < 8u; ++i)
    {
        g_model.P0[i][i] = 1e-2f;
    }
}

static aenl_status_t setup(void)
{
    aenl_moments_cfg_t c;
    aenl_bench_std_moments(&c, 996.0f, 1004.0f);
    aenl_status_t st = aenl_moments_init(&g_moments, &c);
    aenl_classifier_cfg_t cc;
    aenl_classifier_cfg_default(&cc);
    if (st == AENL_OK)
    {
        st = aenl_classifier_init(&g_classifier, &cc);
    }
    make_model();
    return st == AENL_OK ? aenl_skf_init(&g_filter, &g_model) : st;
}

int main(void)
{
    make_records();
    if (setup() != AENL_OK)
    {
        (void)puts("m4f cost: a configuration was rejected");
        return 1;
    }
    ticks_start();
    spin(N_SPIN);
    const uint32_t t_spin = ticks();
    const double per_tick = 2.0 * (double)N_SPIN / (double)t_spin;

    ticks_start();
    for (uint32_t n = 0; n < N_SAMPLES; ++n)
    {
        (void)aenl_moments_push(&g_moments, g_x[n]);
    }
    const uint32_t t_moments = ticks();

    aenl_skf_out_t out;
    uint32_t n_bad = 0u;
    ticks_start();
    for (uint32_t n = 0; n < N_SAMPLES; ++n)
    {
        n_bad += aenl_skf_step(&g_filter, g_z[n], &out) != AENL_OK;
    }
    const uint32_t t_skf = ticks();

    ticks_start();
    const aenl_status_t st = aenl_classifier_update(&g_classifier, &g_moments);
    const uint32_t t_cls = ticks();

    if (g_wrapped || n_bad > 0u)
    {
        printf("m4f cost: not measured (%s)\n",
               g_wrapped ? "SysTick wrapped" : "the filter rejected a step");
        return 1;
    }
    printf("m4f cost: %lu instructions = %lu ticks (%.2f instructions per tick)\n",
           (unsigned long)(2u * N_SPIN), (unsigned long)t_spin, per_tick);
    printf("m4f cost: aenl_moments_push, 64 nodes, lags 1, 10, 30, split: %.0f instructions per "
           "sample (%lu samples)\n",
           per_tick * (double)t_moments / (double)N_SAMPLES, (unsigned long)N_SAMPLES);
    printf("m4f cost: aenl_skf_step, 8 states, 2 outputs, 3 modes: %.0f instructions per step\n",
           per_tick * (double)t_skf / (double)N_SAMPLES);
    printf("m4f cost: aenl_classifier_update (%s): %.0f instructions per call\n",
           aenl_status_str(st), per_tick * (double)t_cls);
    return 0;
}
