/* SPDX-License-Identifier: MIT */
/**
 * @file bench_stream_f32.c
 * @brief `aenl_stream_bench [N]`: the float32 core (aenl_core_f32, the MCU build) over a long
 *        stream, against an exact double reference accumulated alongside: over 10^9 samples
 *        the float32 core's drift from double must stay bounded. Run by `aenl bench stream`.
 *
 * Signal: AR(2) y_n = 1.6 y_{n-1} - 0.8 y_{n-2} + e_n (e uniform-sum, std 0.3) plus an offset of
 * 1000, rounded to float as the MCU would see it. Configuration: the standard one, 64 nodes on
 * [996, 1004], lags 1, 10, 30, direction split, h = 3 grid spacings, no forgetting. The reference
 * sums w, w r, w r^2 of r = x - 1000 in double (an exact shift of the float samples, so no
 * cancellation) at 9 interior nodes, for every lag and direction, pairing samples exactly as the
 * estimator does (conditioning sample n - 30 for all lags at step n). At the end it prints the
 * largest relative errors of the mean's deviation from 1000 (relative to |mean - 1000| + sd), the
 * variance and the weight, the time and ns per sample. Figures are printed, never asserted; the
 * exit status is 0 unless the core rejects something.
 * Build variants: aenl_stream_bench (AENL_MOMENTS_COMPENSATED=1, the float default) and
 * aenl_stream_bench_plain (=0), both in tools/CMakeLists.txt.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl_moments.h"
#include "aenl_tools/aenl_clock.h"
#include "aenl_bench_cfg.h"

#define N_CHECKED 9u
#define OFFSET    1000.0

static aenl_moments_t g_m;
static double g_sw[3][2][N_CHECKED], g_s1[3][2][N_CHECKED], g_s2[3][2][N_CHECKED];

static uint64_t g_rng = 2024u;

static double uniform(void)
{
    g_rng = g_rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

static double rel(double err, double scale)
{
    return scale > 0.0 ? fabs(err) / scale : fabs(err);
}

int main(int argc, char **argv)
{
    uint64_t n_samples = 1000000000ull;
    if (argc > 1)
    {
        char *end = NULL;
        const double v = strtod(argv[1], &end);
        if (end == argv[1] || *end != '\0' || !(v >= 100.0) || !(v <= 1e13))
        {
            fprintf(stderr, "usage: aenl_stream_bench [N >= 100 samples, default 1e9]\n");
            return 2;
        }
        n_samples = (uint64_t)v;
    }
    aenl_moments_cfg_t c;
    aenl_bench_std_moments(&c, 996.0f, 1004.0f);
    if (aenl_moments_init(&g_m, &c) != AENL_OK)
    {
        fprintf(stderr, "aenl_stream_bench: configuration rejected\n");
        return 1;
    }
    uint16_t nodes[N_CHECKED];
    double node_x[N_CHECKED];
    for (unsigned k = 0; k < N_CHECKED; ++k)
    {
        nodes[k] = (uint16_t)(8u + 6u * k); /* 8 .. 56: the well-sampled interior */
        node_x[k] = (double)aenl_moments_node_x(&g_m, nodes[k]);
    }
    const double h = (double)c.bandwidth;
    float hist[64] = {0.0f};
    double y1 = 0.0, y2 = 0.0, t_core = 0.0;
    const double t0 = aenl_now_s();
    printf("aenl stream bench: float32 core (AENL_MOMENTS_COMPENSATED=%d), %.3g samples, AR(2) + "
           "%.0f, 64 nodes, lags 1,10,30, split\n",
           AENL_MOMENTS_COMPENSATED, (double)n_samples, OFFSET);
    (void)fflush(stdout);
    for (uint64_t n = 0; n < n_samples; ++n)
    {
        const double e = (uniform() + uniform() - 1.0) * 0.3 * 2.45;
        const double y = 1.6 * y1 - 0.8 * y2 + e;
        y2 = y1;
        y1 = y;
        const float xf = (float)(OFFSET + y);
        if (aenl_moments_push(&g_m, xf) != AENL_OK)
        {
            fprintf(stderr, "aenl_stream_bench: push rejected at sample %llu\n",
                    (unsigned long long)n);
            return 1;
        }
        hist[n & 63u] = xf;
        if (n < 31u)
        {
            continue;
        }
        const uint64_t cnd = n - 30u;
        const double u = (double)hist[cnd & 63u];
        const int d = u > (double)hist[(cnd - 1u) & 63u] ? 0 : 1;
        for (unsigned k = 0; k < N_CHECKED; ++k)
        {
            const double dist = fabs(u - node_x[k]);
            if (dist < h)
            {
                const double w = (1.0 - dist / h) / h;
                for (unsigned li = 0; li < 3u; ++li)
                {
                    const double r = (double)hist[(cnd + c.lags[li]) & 63u] - OFFSET;
                    g_sw[li][d][k] += w;
                    g_s1[li][d][k] += w * r;
                    g_s2[li][d][k] += w * r * r;
                }
            }
        }
    }
    const double wall = aenl_now_s() - t0;
    /* The core alone, on a fresh estimator, for the ns/sample figure: 160 x 2^16 samples. */
    static aenl_moments_t m2;
    static float buf[1u << 16];
    (void)aenl_moments_init(&m2, &c);
    for (unsigned chunk = 0; chunk < 160u; ++chunk)
    {
        for (size_t i = 0; i < sizeof(buf) / sizeof(buf[0]); ++i)
        {
            const double e = (uniform() + uniform() - 1.0) * 0.3 * 2.45;
            const double y = 1.6 * y1 - 0.8 * y2 + e;
            y2 = y1;
            y1 = y;
            buf[i] = (float)(OFFSET + y);
        }
        const double ta = aenl_now_s();
        for (size_t i = 0; i < sizeof(buf) / sizeof(buf[0]); ++i)
        {
            (void)aenl_moments_push(&m2, buf[i]);
        }
        t_core += aenl_now_s() - ta;
    }
    t_core /= 160.0 * 65536.0;
    double e_mean = 0.0, e_var = 0.0, e_w = 0.0;
    unsigned n_cmp = 0;
    for (unsigned li = 0; li < 3u; ++li)
    {
        for (int d = 0; d < 2; ++d)
        {
            for (unsigned k = 0; k < N_CHECKED; ++k)
            {
                aenl_moments_point_t p;
                const aenl_status_t st =
                    aenl_moments_query(&g_m, (uint16_t)li, nodes[k], (aenl_dir_t)(d + 1), &p);
                if (st != AENL_OK || !(g_sw[li][d][k] > 0.0))
                {
                    printf("  lag %u dir %d node %u: %s\n", (unsigned)c.lags[li], d,
                           (unsigned)nodes[k], aenl_status_str(st));
                    continue;
                }
                const double mean_r = g_s1[li][d][k] / g_sw[li][d][k];
                const double var = g_s2[li][d][k] / g_sw[li][d][k] - mean_r * mean_r;
                e_mean = fmax(e_mean, rel(((double)p.mean - OFFSET) - mean_r,
                                          fabs(mean_r) + sqrt(fmax(var, 0.0))));
                e_var = fmax(e_var, rel((double)p.var - var, var));
                e_w = fmax(e_w, rel((double)p.weight - g_sw[li][d][k], g_sw[li][d][k]));
                ++n_cmp;
            }
        }
    }
    printf("  compared %u (lag, direction, node) cells against the double reference:\n", n_cmp);
    printf("  max relative error: mean - 1000 %.3g, variance %.3g, weight %.3g\n", e_mean, e_var,
           e_w);
    printf("  time %.1f s for the run (reference included), core alone %.1f ns/sample\n", wall,
           1e9 * t_core);
    return 0;
}
