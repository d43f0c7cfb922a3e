/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_bench.c
 * @brief `aenl bench [moments|all]`: performance figures, each with a ratio against a simple
 *        reference computed in the same run. Figures are printed, never asserted.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "aenl_cli.h"
#include "aenl/aenl_moments.h"
#include "aenl_tools/aenl_clock.h"

static const char *const k_cmd = "bench";

/* A noisy two-mode oscillation (AR(2) driven by a xorshift generator): realistic node coverage. */
static void bench_signal(double *x, size_t n)
{
    uint64_t s = 0x9E3779B97F4A7C15ull;
    double y1 = 0.0, y2 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        const double e = (double)(s >> 11) * (1.0 / 9007199254740992.0) - 0.5;
        const double y = 1.8 * y1 - 0.9 * y2 + e;
        y2 = y1;
        y1 = y;
        x[i] = y;
    }
}

/* The direct evaluation: for every lag and node, one pass over all pairs (O(N * nodes * lags)). */
static double direct_eval(const double *x, size_t n, const aenl_moments_cfg_t *c, double *sink)
{
    const double dx = (c->x_max - c->x_min) / (double)(c->n_grid - 1u);
    const double h = c->bandwidth;
    const double inv_h = 1.0 / h;
    double acc = 0.0;
    for (uint16_t li = 0; li < c->n_lags; ++li)
    {
        const size_t lag = c->lags[li];
        for (uint16_t k = 0; k < c->n_grid; ++k)
        {
            const double node = c->x_min + dx * k;
            double sw[2] = {0, 0}, s1[2] = {0, 0}, s2[2] = {0, 0};
            for (size_t i = lag + 1u; i < n; ++i)
            {
                const double u = x[i - lag];
                const double d = fabs(u - node);
                if (d < h)
                {
                    const int dir = (c->direction_split && !(u > x[i - lag - 1u])) ? 1 : 0;
                    const double w = (1.0 - d * inv_h) * inv_h;
                    sw[dir] += w;
                    s1[dir] += w * x[i];
                    s2[dir] += w * x[i] * x[i];
                }
            }
            for (int d = 0; d < 2; ++d)
            {
                if (sw[d] > 0.0)
                {
                    const double m = s1[d] / sw[d];
                    acc += m + (s2[d] / sw[d] - m * m);
                }
            }
        }
    }
    *sink += acc;
    return acc;
}

static void bench_moments_case(const char *name, uint16_t n_grid, uint16_t n_lags, size_t n_stream,
                               size_t n_direct)
{
    aenl_moments_cfg_t c;
    memset(&c, 0, sizeof(c));
    c.x_min = -6.0;
    c.x_max = 6.0;
    c.n_grid = n_grid;
    c.bandwidth = 3.0 * (c.x_max - c.x_min) / (double)(n_grid - 1u);
    c.n_lags = n_lags;
    static const uint16_t k_std_lags[3] = {1, 10, 30};
    for (uint16_t i = 0; i < n_lags; ++i)
    {
        c.lags[i] = (n_lags == 3) ? k_std_lags[i] : (uint16_t)(1u + 2u * i);
    }
    c.forgetting = 1.0;
    c.direction_split = 1;

    double *x = malloc(n_stream * sizeof(double));
    aenl_moments_t *m = malloc(sizeof(*m));
    if (x == NULL || m == NULL)
    {
        free(x);
        free(m);
        aenl_cli_error(k_cmd, "out of memory");
        return;
    }
    bench_signal(x, n_stream);
    /* Scale the signal to fill the grid's interior (std about 1.5). */
    double ss = 0.0;
    for (size_t i = 0; i < n_stream; ++i)
    {
        ss += x[i] * x[i];
    }
    const double sd = sqrt(ss / (double)n_stream);
    for (size_t i = 0; i < n_stream; ++i)
    {
        x[i] *= 1.5 / sd;
    }
    if (aenl_moments_init(m, &c) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: configuration rejected", name);
        free(x);
        free(m);
        return;
    }
    double best_stream = 1e30;
    for (int rep = 0; rep < 3; ++rep)
    {
        aenl_moments_reset(m);
        const double t0 = aenl_now_s();
        for (size_t i = 0; i < n_stream; ++i)
        {
            aenl_moments_push(m, x[i]);
        }
        const double t = aenl_now_s() - t0;
        best_stream = t < best_stream ? t : best_stream;
    }
    double sink = 0.0;
    const double t0 = aenl_now_s();
    direct_eval(x, n_direct, &c, &sink);
    const double t_direct = aenl_now_s() - t0;
    const double ns_stream = 1e9 * best_stream / (double)n_stream;
    const double ns_direct = 1e9 * t_direct / (double)n_direct;
    printf("  %-9s %4u nodes x %2u lags, split: stream %8.1f ns/sample | direct %10.1f ns/sample "
           "| ratio %6.0fx   (checksum %.3g)\n",
           name, (unsigned)n_grid, (unsigned)n_lags, ns_stream, ns_direct, ns_direct / ns_stream,
           sink);
    free(x);
    free(m);
}

/* The float32 MCU figures come from the real cross build (tools/scripts/check_m4f.sh): state sizes
 * from the symbol table of a probe object, code size from arm-none-eabi-size. */
static void m4f_report(void)
{
    char script[1024];
    aenl_err_t perr;
    aenl_err_clear(&perr);
    const int found = aenl_share_path("source/tools/scripts/check_m4f.sh", script, sizeof(script),
                                      &perr) == AENL_OK;
    FILE *probe = found ? fopen(script, "r") : NULL;
    /* A fixed command line: no user input reaches the shell. */
    if (probe == NULL ||
        system("command -v arm-none-eabi-gcc >/dev/null 2>&1") != 0) /* NOLINT(cert-env33-c) */
    {
        if (probe != NULL)
        {
            (void)fclose(probe);
        }
        printf("  Cortex-M4F figures: skipped (needs the build tree's link to the sources and "
               "arm-none-eabi-gcc)\n");
        return;
    }
    (void)fclose(probe);
    char dir[] = "/tmp/aenl_bench_m4f_XXXXXX";
    if (mkdtemp(dir) == NULL)
    {
        printf("  Cortex-M4F figures: skipped (no temporary folder)\n");
        return;
    }
    char cmd[2200];
    if (snprintf(cmd, sizeof(cmd), "'%s' '%s/b' 2>&1; rm -rf '%s'", script, dir, dir) >=
        (int)sizeof(cmd))
    {
        return;
    }
    /* The script path comes from the build tree's link to the sources, the folder from mkdtemp. */
    FILE *p = popen(cmd, "r"); /* NOLINT(cert-env33-c) */
    if (p == NULL)
    {
        return;
    }
    char line[512];
    printf("  Cortex-M4F (arm-none-eabi-gcc -Os, float32, default aenl_config.h):\n");
    int in_sizes = 0;
    while (fgets(line, sizeof(line), p) != NULL)
    {
        if (strstr(line, "text") != NULL && strstr(line, "filename") != NULL)
        {
            in_sizes = 1;
        }
        if (in_sizes || strstr(line, "sizeof") != NULL || strstr(line, "COMPENSATED") != NULL ||
            strstr(line, "FAIL") != NULL || strstr(line, "worst frame") != NULL)
        {
            printf("    %s", line);
        }
        if (strstr(line, "(TOTALS)") != NULL)
        {
            in_sizes = 0;
        }
    }
    pclose(p);
}

static int bench_moments(void)
{
    printf(
        "moments (host, double, -O2; best of 3 streaming runs of 10^6 samples; the direct\n"
        "O(N x nodes x lags) evaluation of the same formulas over the first 2 x 10^4 samples):\n");
    bench_moments_case("standard", 64, 3, 1000000u, 20000u);
    bench_moments_case("heavy", 128, 16, 1000000u, 20000u);
    printf("  host sizeof(aenl_moments_t) = %zu B (double, host capacities)\n",
           sizeof(aenl_moments_t));
    m4f_report();
    return AENL_EXIT_OK;
}

/* `aenl bench stream [N] [--plain]`: float32 core over N samples (default 10^9) against a double
 * reference, by aenl_stream_bench (tools/bench/bench_stream_f32.c); --plain also runs the build
 * without compensated summation (AENL_MOMENTS_COMPENSATED=0). */
static int bench_stream(int argc, char **argv)
{
    char *n_arg[1] = {NULL};
    int plain = 0;
    for (int i = 1; i < argc; ++i)
    {
        if (strcmp(argv[i], "--plain") == 0)
        {
            plain = 1;
        }
        else if (n_arg[0] == NULL && argv[i][0] != '-')
        {
            n_arg[0] = argv[i];
        }
        else
        {
            aenl_cli_error(k_cmd, "usage: aenl bench stream [N] [--plain]");
            return AENL_EXIT_USAGE;
        }
    }
    const int na = n_arg[0] != NULL ? 1 : 0;
    int rc = aenl_bench_run_sibling("aenl_stream_bench", n_arg, na);
    if (rc == AENL_EXIT_OK && plain)
    {
        printf("\n");
        rc = aenl_bench_run_sibling("aenl_stream_bench_plain", n_arg, na);
    }
    return rc;
}

int aenl_cmd_bench(int argc, char **argv)
{
    const char *what = argc > 1 ? argv[1] : "all";
    if (strcmp(what, "--help") == 0 || strcmp(what, "-h") == 0)
    {
        printf(
            "usage: aenl bench [moments|simulate|fit|all]\n"
            "       aenl bench diagnose [--long] [--seeds N] [--rk4] [--dryden] [--bound]\n"
            "                                         (hidden-effect matrix; minutes)\n"
            "       aenl bench identify [--cases N] [--seed S] [--rk4] [--dryden] [--write DIR]\n"
            "                           [--verbose] [--regime R] [--rows N] [--from K] [--model]\n"
            "                           [--unknown-gusts] [--method test [--impulsive]]\n"
            "                                         (identification suite; minutes)\n"
            "       aenl bench null [--records N] [--from K] [--level A] [--verbose]\n"
            "                       [--force-given] [--impulsive]\n"
            "                                         (level of identify, the test; minutes)\n"
            "Each kind's own --help (aenl bench null --help, ...) says more.\n"
            "       aenl bench stream [N] [--plain]   (float32 core over N = 10^9 samples vs "
            "double; minutes)\n");
        return AENL_EXIT_OK;
    }
    if (strcmp(what, "moments") == 0)
    {
        return argc > 2 ? (aenl_cli_error(k_cmd, "bench moments takes no options"), AENL_EXIT_USAGE)
                        : bench_moments();
    }
    if (strcmp(what, "stream") == 0)
    {
        return bench_stream(argc - 1, argv + 1);
    }
    if (strcmp(what, "simulate") == 0)
    {
        return aenl_bench_simulate(argc - 1, argv + 1);
    }
    if (strcmp(what, "fit") == 0)
    {
        return aenl_bench_fit(argc - 1, argv + 1);
    }
    if (strcmp(what, "diagnose") == 0)
    {
        return aenl_bench_diagnose(argc - 1, argv + 1);
    }
    if (strcmp(what, "identify") == 0)
    {
        return aenl_bench_identify(argc - 1, argv + 1);
    }
    if (strcmp(what, "null") == 0)
    {
        return aenl_bench_null(argc - 1, argv + 1);
    }
    if (strcmp(what, "all") == 0 && argc <= 2)
    {
        int rc = bench_moments();
        printf("\n");
        char arg_sim[] = "simulate";
        char *sub_sim[] = {arg_sim, NULL};
        const int rc2 = aenl_bench_simulate(1, sub_sim);
        printf("\n");
        char arg_fit[] = "fit";
        char *sub_fit[] = {arg_fit, NULL};
        const int rc3 = aenl_bench_fit(1, sub_fit);
        printf("\n");
        char arg_id[] = "identify";
        char *sub_id[] = {arg_id, NULL};
        const int rc4 = aenl_bench_identify(1, sub_id);
        return rc != AENL_EXIT_OK    ? rc
               : rc2 != AENL_EXIT_OK ? rc2
               : rc3 != AENL_EXIT_OK ? rc3
                                     : rc4;
    }
    aenl_cli_error(
        k_cmd,
        "unknown benchmark '%s' (moments, simulate, fit, identify, null, diagnose, stream "
        "or all)",
        what);
    return AENL_EXIT_USAGE;
}
