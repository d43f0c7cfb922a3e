/* SPDX-License-Identifier: MIT */
/**
 * @file fw_example.c
 * @brief Firmware-style example: a measured record streamed one sample at a time
 *        through the embeddable core built in float32 (aenl_core_f32, the Cortex-M4F build):
 *        moments -> classifier on the switching channel, and the switching Kalman filter whose
 *        model is the header that `aenl fit --c-header` generated on the ground. Prints the
 *        verdict, the mode sequence and the NIS.
 *
 * Usage: aenl_fw_example RECORD.csv
 *   RECORD.csv: header `t,<output 0>,<output 1>,...` in the order the model was fitted on (the
 *   CSV of `aenl simulate`), one row per sample; NaN cells are missing samples.
 *
 * What would run on the target is everything between the reading of a row and the printing:
 * caller-owned static state, no allocation, one sample per call. Only the CSV reader (the ADC
 * stand-in) and the report use stdio. The moments are configured from a warm-up window of the
 * switching channel (mean, standard deviation and dominant period; its samples are then
 * replayed), as a monitor would do after power-up: grid mean +- 3 sd with 32 nodes (one per
 * bandwidth), three lags up to period / 8, symmetric pairs and the direction split, which is the
 * MCU capacity (3 x 2 x 32 x 2 = 384 cells). The classifier updates every FW_CLASSIFY_EVERY
 * samples; the filter steps on every sample from the first.
 *
 * Exit status: 0 on success, 1 on a read or core error (message on stderr).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl.h"
#include "fw_model.h" /* generated: static const aenl_skf_model_t fw_model */

#define FW_WARMUP         1000u /**< samples of the switching channel used to configure */
#define FW_CLASSIFY_EVERY 1000u /**< classifier update period, samples */
#define FW_GRID           32u   /**< moments nodes */
#define FW_RUNS_SHOWN     16u   /**< mode-sequence runs printed */
#define FW_CHI2_99_2      9.21f /**< 99 % point of chi-square with 2 degrees of freedom */
#define FW_LINE           512   /**< longest CSV line */

/* Target-side state: static, as on the MCU. */
static aenl_moments_t g_moments;
static aenl_classifier_t g_classifier;
static aenl_skf_t g_filter;
static aenl_real_t g_warm[FW_WARMUP];

/* Mode sequence as run lengths (the first FW_RUNS_SHOWN runs), per-mode counts, NIS tail. */
typedef struct
{
    uint16_t mode[FW_RUNS_SHOWN];
    uint32_t len[FW_RUNS_SHOWN];
    uint32_t n_shown; /**< runs stored */
    uint32_t n_runs;  /**< runs so far */
    uint16_t cur;     /**< mode of the current run */
    uint32_t per_mode[AENL_SKF_MAX_MODES];
    uint32_t n_nis_high; /**< updates with NIS above the 99 % point (2 outputs) */
    uint32_t n_steps;
} fw_log_t;

static void log_mode(fw_log_t *lg, uint16_t mode)
{
    if (mode < AENL_SKF_MAX_MODES)
    {
        lg->per_mode[mode]++;
    }
    if (lg->n_runs == 0u || mode != lg->cur)
    {
        lg->n_runs++;
        lg->cur = mode;
        if (lg->n_shown < FW_RUNS_SHOWN)
        {
            lg->mode[lg->n_shown] = mode;
            lg->len[lg->n_shown] = 0u;
            lg->n_shown++;
        }
    }
    if (lg->n_runs == lg->n_shown) /* the current run is the last one stored */
    {
        lg->len[lg->n_shown - 1u]++;
    }
}

/* Mean, standard deviation and dominant period (samples, from upward mean crossings with a
 * +-sd/4 hysteresis) of the warm-up window; NaN samples are skipped. */
static void warmup_stats(const aenl_real_t *x, uint32_t n, aenl_real_t *mean, aenl_real_t *sd,
                         aenl_real_t *period)
{
    aenl_real_t m = AENL_R(0.0), m2 = AENL_R(0.0), c = AENL_R(0.0);
    for (uint32_t k = 0; k < n; ++k)
    {
        if (isfinite(x[k]))
        {
            c += AENL_R(1.0);
            const aenl_real_t d = x[k] - m;
            m += d / c;
            m2 += d * (x[k] - m);
        }
    }
    *mean = m;
    *sd = (c > AENL_R(1.0)) ? aenl_sqrt(m2 / (c - AENL_R(1.0))) : AENL_R(0.0);
    const aenl_real_t band = AENL_R(0.25) * *sd;
    int below = 0;
    uint32_t first = 0, last = 0, n_up = 0;
    for (uint32_t k = 0; k < n; ++k)
    {
        if (!isfinite(x[k]))
        {
            continue;
        }
        if (x[k] < m - band)
        {
            below = 1;
        }
        else if (below && x[k] > m + band)
        {
            below = 0;
            first = (n_up == 0u) ? k : first;
            last = k;
            n_up++;
        }
    }
    *period =
        (n_up >= 2u) ? (aenl_real_t)(last - first) / (aenl_real_t)(n_up - 1u) : (aenl_real_t)n;
}

/* Moments and classifier from the warm-up statistics (see the file comment). */
static aenl_status_t configure(aenl_real_t mean, aenl_real_t sd, aenl_real_t period)
{
    aenl_moments_cfg_t mc;
    memset(&mc, 0, sizeof(mc));
    mc.x_min = mean - AENL_R(3.0) * sd;
    mc.x_max = mean + AENL_R(3.0) * sd;
    mc.n_grid = (uint16_t)FW_GRID;
    mc.bandwidth = (mc.x_max - mc.x_min) / (aenl_real_t)(FW_GRID - 1u);
    uint32_t l3 = (uint32_t)(period / AENL_R(8.0));
    l3 = (l3 < 4u) ? 4u : (l3 > AENL_MOMENTS_MAX_LAG ? AENL_MOMENTS_MAX_LAG : l3);
    mc.n_lags = 3;
    mc.lags[0] = 2; /* not 1: the direction split reads X_{c-1} */
    mc.lags[1] = (uint16_t)((l3 + 2u) / 2u > 2u ? (l3 + 2u) / 2u : 3u);
    mc.lags[2] = (uint16_t)(l3 > mc.lags[1] ? l3 : mc.lags[1] + 1u);
    mc.forgetting = AENL_R(1.0);
    mc.direction_split = 1;
    mc.symmetric = 1;
    aenl_status_t st = aenl_moments_init(&g_moments, &mc);
    if (st != AENL_OK)
    {
        return st;
    }
    aenl_classifier_cfg_t cc;
    aenl_classifier_cfg_default(&cc);
    cc.taylor_order = 3;
    return aenl_classifier_init(&g_classifier, &cc);
}

/* One CSV row into z (n_z outputs after the time column): 1 a row, 0 end, -1 bad row. */
static int read_row(FILE *fp, aenl_real_t *z, uint16_t n_z)
{
    char line[FW_LINE];
    if (fgets(line, sizeof(line), fp) == NULL)
    {
        return 0;
    }
    char *p = line, *end = NULL;
    (void)strtod(p, &end); /* time */
    if (end == p)
    {
        return -1;
    }
    p = end;
    for (uint16_t r = 0; r < n_z; ++r)
    {
        if (*p != ',')
        {
            return -1;
        }
        ++p;
        const double v = strtod(p, &end);
        if (end == p)
        {
            return -1;
        }
        z[r] = (aenl_real_t)v;
        p = end;
    }
    return 1;
}

static void report(const char *path, const fw_log_t *lg, uint32_t n_rows, int configured)
{
    const aenl_skf_model_t *md = &fw_model;
    printf("record %s: %lu samples; model fw_model: %u states, %u outputs, %u modes, float32 "
           "core\n",
           path, (unsigned long)n_rows, (unsigned)md->n_x, (unsigned)md->n_z,
           (unsigned)md->n_modes);
    const aenl_classifier_result_t *res = aenl_classifier_result(&g_classifier);
    printf("verdict (output %u): %s, confidence %.3f", (unsigned)md->switch_state,
           configured ? aenl_class_name(res->cls) : "insufficient", (double)res->confidence);
    for (uint8_t i = 0; configured && i < res->n_switch; ++i)
    {
        printf("%s %.6g +- %.2g", i ? "," : "; switching points", (double)res->switch_points[i],
               (double)res->switch_std[i]);
    }
    printf("\n  the model's thresholds:");
    for (uint16_t i = 0; i + 1u < md->n_modes; ++i)
    {
        printf(" %.6g", (double)md->thr_rising[i]);
    }
    printf("\nmode sequence (mode x samples, first runs):");
    for (uint32_t i = 0; i < lg->n_shown; ++i)
    {
        printf(" %ux%lu", (unsigned)lg->mode[i], (unsigned long)lg->len[i]);
    }
    printf("%s\n  samples per mode:", lg->n_runs > lg->n_shown ? " ..." : "");
    for (uint16_t s = 0; s < md->n_modes; ++s)
    {
        printf(" %u: %lu (%.1f %%)", (unsigned)s, (unsigned long)lg->per_mode[s],
               lg->n_steps ? 100.0 * (double)lg->per_mode[s] / (double)lg->n_steps : 0.0);
    }
    printf("; %lu switches\n", (unsigned long)(lg->n_runs ? lg->n_runs - 1u : 0u));
    aenl_real_t nis = AENL_R(0.0);
    if (aenl_skf_mean_nis(&g_filter, &nis) == AENL_OK)
    {
        /* a consistent filter has mean NIS = n_z; this band is an engineering tolerance */
        const double ratio = (double)nis / (double)md->n_z;
        printf("NIS: mean %.3f over %lu updates (expected %u)", (double)nis,
               (unsigned long)g_filter.n_nis, (unsigned)md->n_z);
        if (md->n_z == 2u)
        {
            printf(", above the 99 %% point %.2f: %.2f %%", (double)FW_CHI2_99_2,
                   g_filter.n_nis ? 100.0 * (double)lg->n_nis_high / (double)g_filter.n_nis : 0.0);
        }
        printf("; %s\n", (ratio > 0.8 && ratio < 1.25) ? "consistent" : "NOT consistent");
    }
    else
    {
        printf("NIS: no update\n");
    }
    printf("filter health: %lu missing, %lu not positive definite, %lu numeric\n",
           (unsigned long)g_filter.n_missing, (unsigned long)g_filter.n_not_pd,
           (unsigned long)g_filter.n_numeric);
}

int main(int argc, char **argv)
{
    if (argc != 2)
    {
        fprintf(stderr, "usage: aenl_fw_example RECORD.csv\n");
        return 1;
    }
    FILE *fp = fopen(argv[1], "r");
    char header[FW_LINE];
    if (fp == NULL || fgets(header, sizeof(header), fp) == NULL)
    {
        fprintf(stderr, "aenl_fw_example: cannot read %s\n", argv[1]);
        if (fp != NULL)
        {
            (void)fclose(fp);
        }
        return 1;
    }
    aenl_status_t st = aenl_skf_init(&g_filter, &fw_model);
    if (st != AENL_OK)
    {
        fprintf(stderr, "aenl_fw_example: the generated model is invalid (%s)\n",
                aenl_status_str(st));
        (void)fclose(fp);
        return 1;
    }
    static fw_log_t lg; /* zero-initialised */
    const uint16_t n_z = fw_model.n_z, ch = fw_model.switch_state;
    aenl_real_t z[AENL_SKF_MAX_Z];
    uint32_t n = 0;
    int configured = 0, rc = 0;
    for (;;)
    {
        const int got = read_row(fp, z, n_z);
        if (got == 0)
        {
            break;
        }
        if (got < 0)
        {
            fprintf(stderr, "aenl_fw_example: %s: bad row %lu\n", argv[1], (unsigned long)n + 2u);
            rc = 1;
            break;
        }
        /* the filter: one step per sample */
        aenl_skf_out_t out;
        st = aenl_skf_step(&g_filter, z, &out);
        if (st != AENL_OK && st != AENL_E_NOT_PD) /* NOT_PD: estimate kept, counted */
        {
            fprintf(stderr, "aenl_fw_example: filter step %lu: %s\n", (unsigned long)n,
                    aenl_status_str(st));
            rc = 1;
            break;
        }
        log_mode(&lg, out.mode);
        lg.n_steps++;
        lg.n_nis_high += (out.n_used == 2u && out.nis > FW_CHI2_99_2) ? 1u : 0u;
        /* the classifier channel: warm-up, then streaming moments */
        const aenl_real_t u = (ch < n_z) ? z[ch] : z[0];
        if (n < FW_WARMUP)
        {
            g_warm[n] = u;
        }
        else
        {
            (void)aenl_moments_push(&g_moments, u); /* NaN: a counted gap */
        }
        ++n;
        if (n == FW_WARMUP)
        {
            aenl_real_t mean, sd, period;
            warmup_stats(g_warm, FW_WARMUP, &mean, &sd, &period);
            st = configure(mean, sd, period);
            if (st != AENL_OK)
            {
                fprintf(stderr, "aenl_fw_example: moments/classifier set-up: %s\n",
                        aenl_status_str(st));
                rc = 1;
                break;
            }
            configured = 1;
            for (uint32_t k = 0; k < FW_WARMUP; ++k)
            {
                (void)aenl_moments_push(&g_moments, g_warm[k]);
            }
        }
        if (configured && n % FW_CLASSIFY_EVERY == 0u)
        {
            (void)aenl_classifier_update(&g_classifier, &g_moments);
        }
    }
    (void)fclose(fp);
    if (rc == 0 && configured)
    {
        (void)aenl_classifier_update(&g_classifier, &g_moments);
    }
    if (rc == 0)
    {
        report(argv[1], &lg, n, configured);
    }
    return rc;
}
