/* SPDX-License-Identifier: MIT */
/**
 * @file bench_fit.c
 * @brief `aenl bench fit`: one switching-Kalman-filter step (8 states, 2 outputs, 3 modes) in ns,
 *        its state size and its Cortex-M4F code size; EM on 20 000 samples x 50 iterations and how
 *        the time grows with samples and states. Figures are printed, never asserted.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "aenl_cli.h"
#include "aenl/aenl_skf.h"
#include "aenl_tools/aenl_em.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t g_rng = 0x9E3779B97F4A7C15ull;

static double gauss(void)
{
    double s = 0.0;
    for (int i = 0; i < 12; ++i)
    {
        g_rng ^= g_rng << 13;
        g_rng ^= g_rng >> 7;
        g_rng ^= g_rng << 17;
        s += (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
    }
    return s - 6.0;
}

/* A 3-mode, 2-output record from four damped oscillators (8 states) switching on output 0. */
static double *make_record(size_t n)
{
    double *y = malloc(n * 2 * sizeof(double));
    if (y == NULL)
    {
        return NULL;
    }
    double x[8] = {0.5, 0, 0.1, 0, 0, 0, 0, 0};
    const double th[3][4] = {
        {0.30, 0.55, 0.9, 1.3}, {0.18, 0.55, 0.9, 1.3}, {0.30, 0.55, 0.9, 1.3}};
    for (size_t k = 0; k < n; ++k)
    {
        y[2 * k] = x[0] + x[4] + 0.03 * gauss();
        y[2 * k + 1] = x[2] + x[6] + 0.02 * gauss();
        const int s = y[2 * k] < -0.2 ? 0 : (y[2 * k] < 0.2 ? 1 : 2);
        double xn[8];
        for (int p = 0; p < 4; ++p)
        {
            const double r = 0.985 - 0.01 * p, c = r * cos(th[s][p]), sn = r * sin(th[s][p]);
            xn[2 * p] = c * x[2 * p] - sn * x[2 * p + 1] + 0.05 * gauss();
            xn[2 * p + 1] = sn * x[2 * p] + c * x[2 * p + 1] + 0.05 * gauss();
        }
        xn[2] += 0.05 * x[0];
        memcpy(x, xn, sizeof(x));
    }
    return y;
}

static double time_em(const double *y, size_t n, size_t states, size_t iters)
{
    aenl_em_opts_t o;
    aenl_em_opts_default(&o);
    o.n_states = states;
    o.n_thresholds = 2;
    o.thresholds[0] = -0.2;
    o.thresholds[1] = 0.2;
    o.max_iter = iters;
    aenl_em_result_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    const double t0 = now_s();
    const aenl_status_t st = aenl_em_fit(y, n, 2, &o, &r, &err);
    const double t = now_s() - t0;
    if (st != AENL_OK)
    {
        printf("  EM failed: %s\n", err.msg);
        return NAN;
    }
    aenl_em_result_free(&r);
    return t;
}

static void skf_step_bench(void)
{
    static aenl_skf_model_t m;
    static aenl_skf_t f;
    memset(&m, 0, sizeof(m));
    m.n_x = 8;
    m.n_z = 2;
    m.n_modes = 3;
    m.dir_state = AENL_SKF_DIR_DIFF;
    m.thr_rising[0] = m.thr_falling[0] = -0.2;
    m.thr_rising[1] = m.thr_falling[1] = 0.2;
    for (int s = 0; s < 3; ++s)
    {
        for (int p = 0; p < 4; ++p)
        {
            const double th = (s == 1 && p == 0) ? 0.18 : 0.3 + 0.3 * p, r = 0.98;
            m.A[s][2 * p][2 * p] = m.A[s][2 * p + 1][2 * p + 1] = r * cos(th);
            m.A[s][2 * p][2 * p + 1] = -r * sin(th);
            m.A[s][2 * p + 1][2 * p] = r * sin(th);
        }
        for (int i = 0; i < 8; ++i)
        {
            m.Q[s][i][i] = 2.5e-3;
        }
    }
    m.C[0][0] = m.C[0][4] = m.C[1][2] = m.C[1][6] = 1.0;
    m.R[0][0] = 9e-4;
    m.R[1][1] = 4e-4;
    for (int i = 0; i < 8; ++i)
    {
        m.P0[i][i] = 1.0;
    }
    if (aenl_skf_init(&f, &m) != AENL_OK)
    {
        printf("  SKF init failed\n");
        return;
    }
    const size_t n = 200000;
    double *z = malloc(2 * n * sizeof(double));
    if (z == NULL)
    {
        return;
    }
    for (size_t k = 0; k < 2 * n; ++k)
    {
        z[k] = 0.3 * gauss();
    }
    double best = 1e30, sink = 0.0;
    for (int rep = 0; rep < 3; ++rep)
    {
        aenl_skf_reset(&f);
        aenl_skf_out_t out;
        const double t0 = now_s();
        for (size_t k = 0; k < n; ++k)
        {
            aenl_skf_step(&f, &z[2 * k], &out);
            sink += out.nis;
        }
        const double t = (now_s() - t0) / (double)n;
        best = t < best ? t : best;
    }
    free(z);
    printf("  SKF step, 8 states, 2 outputs, 3 modes (host, double, -O2, best of 3 x 2e5 steps): "
           "%.0f ns  (mean NIS %.3f)\n",
           best * 1e9, sink / (3.0 * (double)n));
    printf("  host sizeof(aenl_skf_t) = %zu B, sizeof(aenl_skf_model_t) = %zu B (double)\n",
           sizeof(aenl_skf_t), sizeof(aenl_skf_model_t));
}

/* Cortex-M4F: compile the filter's two sources and a sizeof probe with arm-none-eabi-gcc. */
static void skf_m4f(void)
{
    if (system("command -v arm-none-eabi-gcc >/dev/null 2>&1") != 0)
    {
        printf("  Cortex-M4F: skipped (arm-none-eabi-gcc not found)\n");
        return;
    }
    char dir[] = "/tmp/aenl_bench_fit_XXXXXX";
    if (mkdtemp(dir) == NULL)
    {
        return;
    }
    char cmd[4096];
    const char *flags = "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -std=c99 -Os";
    snprintf(cmd, sizeof(cmd),
             "cd '%s' && printf '#include \"aenl/aenl_skf.h\"\\naenl_skf_t s;\\n"
             "aenl_skf_model_t m;\\n' > p.c && "
             "arm-none-eabi-gcc %s -I'%s/include' -I'%s/src' -c '%s/src/aenl_skf.c' -o skf.o && "
             "arm-none-eabi-gcc %s -I'%s/include' -I'%s/src' -c '%s/src/aenl_linalg.c' -o la.o && "
             "arm-none-eabi-gcc %s -I'%s/include' -c p.c -o p.o && "
             "arm-none-eabi-size skf.o la.o | tail -n 2 && arm-none-eabi-nm -S p.o; "
             "cd /; rm -rf '%s'",
             dir, flags, AENL_SOURCE_DIR, AENL_SOURCE_DIR, AENL_SOURCE_DIR, flags, AENL_SOURCE_DIR,
             AENL_SOURCE_DIR, AENL_SOURCE_DIR, flags, AENL_SOURCE_DIR, dir);
    FILE *p = popen(cmd, "r");
    if (p == NULL)
    {
        return;
    }
    char line[512];
    unsigned long text = 0;
    printf("  Cortex-M4F (arm-none-eabi-gcc -Os, float32, default capacities 8/4/4):\n");
    while (fgets(line, sizeof(line), p) != NULL)
    {
        unsigned long tx = 0, da = 0, bs = 0, dec = 0, size = 0;
        char kind = 0, name[64] = "", addr[32] = "";
        if (sscanf(line, "%lu %lu %lu %lu", &tx, &da, &bs, &dec) == 4)
        {
            text += tx;
        }
        else if (sscanf(line, "%31s %lx %c %63s", addr, &size, &kind, name) == 4)
        {
            printf("    sizeof(%s) = %lu B\n",
                   strcmp(name, "s") == 0 ? "aenl_skf_t" : "aenl_skf_model_t", size);
        }
    }
    pclose(p);
    printf("    code (aenl_skf.c + aenl_linalg.c, .text) = %lu B\n", text);
}

int aenl_bench_fit(int argc, char **argv)
{
    if (argc > 1)
    {
        if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)
        {
            printf("usage: aenl bench fit\n");
            return AENL_EXIT_OK;
        }
        aenl_cli_error("bench", "bench fit takes no options");
        return AENL_EXIT_USAGE;
    }
    printf("fit: switching Kalman filter (core) and EM identification (host)\n");
    skf_step_bench();
    skf_m4f();
    double *y = make_record(40000);
    if (y == NULL)
    {
        return AENL_EXIT_FAIL;
    }
    const double t = time_em(y, 20000, 8, 50);
    printf("  EM, 20000 samples x 50 iterations, 8 states, 2 outputs, 3 modes: %.3f s "
           "(goal < 1 s)\n",
           t);
    printf("  growth with samples (8 states, 10 iterations, s per iteration):\n   ");
    const size_t ns[] = {5000, 10000, 20000, 40000};
    for (size_t i = 0; i < 4; ++i)
    {
        printf(" N=%zu: %.4f;", ns[i], time_em(y, ns[i], 8, 10) / 10.0);
    }
    printf("\n  growth with states (20000 samples, 10 iterations, s per iteration):\n   ");
    const size_t nxs[] = {4, 8, 12, 16};
    for (size_t i = 0; i < 4; ++i)
    {
        printf(" n_x=%zu: %.4f;", nxs[i], time_em(y, 20000, nxs[i], 10) / 10.0);
    }
    printf("\n  (time ~ N n_x^3: the E-step's n_x x n_x products and the smoother's Cholesky)\n");
    free(y);
    return AENL_EXIT_OK;
}
