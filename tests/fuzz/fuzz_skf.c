/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_skf.c
 * @brief libFuzzer target: aenl_skf init / step / reset / queries with arbitrary models and
 *        measurement streams. Built twice (AENL_USE_DOUBLE 0 and 1) by tools/scripts/run_fuzz.sh.
 *
 * Input layout (every read past the end gives zeros):
 *   byte 0   flags: bit 0 raw model (every real bit for bit), else structured; bit 1 IMM;
 *            bit 2 raw 16-bit sizes (beyond the maxima), else small ones; bit 3 hysteresis
 *            (thr_falling != thr_rising); bit 4 dir_state = AENL_SKF_DIR_DIFF; bit 5 Q, R and P0
 *            as B B' (PSD) instead of a symmetric matrix from raw bytes (may be indefinite);
 *            bit 6 imm field taken from a raw byte (may be invalid)
 *   ...      sizes, switch/dir state, then the model tables (see read_model)
 *   then ops one op byte each, high 3 bits select: 0-3 a finite z (components from bytes; bit 0..3
 *            of the op byte mark components missing = NaN), 4 z with one +-Inf component, 5 a raw
 *            z (any bit pattern), 6 reset, 7 queries only
 *
 * Properties checked (abort() on violation, which libFuzzer reports as a crash):
 *  - init returns AENL_OK, AENL_E_ARG or AENL_E_DIM; on error the state is byte-identical;
 *  - step returns AENL_OK, AENL_E_NUMERIC or AENL_E_NOT_PD; on error the estimate, covariance,
 *    mode probabilities, mode and direction are byte-identical and *out is all zeros;
 *  - a z with an infinite component gives AENL_E_NUMERIC;
 *  - after AENL_OK from a z without infinities: the estimate x, P from aenl_skf_estimate and the
 *    mode probabilities are finite, the probabilities lie in [0, 1] and sum to 1 (rounding
 *    allowance), out->mode < n_modes, out->n_used is the number of non-NaN components, and
 *    out->nis >= 0 and out->log_lik are finite (nis = 0 when nothing was used);
 *  - reset brings back x0 and P0 (threshold mode: exactly).
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_NAME "fuzz_skf"
#include "fuzz_common.h"

#include "aenl/aenl_skf.h"

#define NX AENL_SKF_MAX_X
#define NZ AENL_SKF_MAX_Z
#define NM AENL_SKF_MAX_MODES

/* A small real from one byte: (int8) / 32, i.e. in [-4, 4). */
static aenl_real_t take_small(input_t *in)
{
    return (aenl_real_t)(int8_t)take_u8(in) / AENL_R(32.0);
}

static aenl_real_t take_real(input_t *in, int raw)
{
    return raw ? take_raw_real(in) : take_small(in);
}

/* An n x n symmetric matrix (stride ld): B B' + eps I when psd, else mirrored raw entries. */
static void take_sym(input_t *in, aenl_real_t *a, size_t ld, uint16_t n, int raw, int psd)
{
    if (n > ld)
    {
        n = (uint16_t)ld;
    }
    if (psd && !raw)
    {
        aenl_real_t b[NX][NX];
        for (uint16_t i = 0; i < n; ++i)
        {
            for (uint16_t j = 0; j < n; ++j)
            {
                b[i][j] = take_small(in);
            }
        }
        for (uint16_t i = 0; i < n; ++i)
        {
            for (uint16_t j = 0; j < n; ++j)
            {
                aenl_real_t s = (i == j) ? AENL_R(1e-3) : AENL_R(0.0);
                for (uint16_t k = 0; k < n; ++k)
                {
                    s += b[i][k] * b[j][k];
                }
                a[i * ld + j] = s;
            }
        }
        return;
    }
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j <= i; ++j)
        {
            const aenl_real_t v = take_real(in, raw);
            a[i * ld + j] = v;
            a[j * ld + i] = v;
        }
    }
}

static void read_model(input_t *in, uint8_t flags, aenl_skf_model_t *m)
{
    const int raw = flags & 1u;
    const int psd = (flags >> 5) & 1u;
    memset(m, 0, sizeof(*m));
    if (flags & 4u)
    {
        m->n_x = take_u16(in);
        m->n_z = take_u16(in);
        m->n_modes = take_u16(in);
    }
    else
    {
        m->n_x = (uint16_t)(take_u8(in) % (NX + 2u)); /* 0 .. NX+1 */
        m->n_z = (uint16_t)(take_u8(in) % (NZ + 2u));
        m->n_modes = (uint16_t)(take_u8(in) % (NM + 2u));
    }
    /* Tables are filled over the capacity, whatever the sizes say. */
    const uint16_t nx = (m->n_x < NX) ? m->n_x : (uint16_t)NX;
    const uint16_t nz = (m->n_z < NZ) ? m->n_z : (uint16_t)NZ;
    const uint16_t nm = (m->n_modes < NM) ? m->n_modes : (uint16_t)NM;
    const uint8_t ss = take_u8(in);
    m->switch_state = (ss & 0x80u) ? (uint16_t)ss : (uint16_t)(ss % (nx ? nx : 1u));
    m->dir_state = (flags & 16u) ? AENL_SKF_DIR_DIFF : (uint16_t)(take_u8(in) % (nx + 1u));
    m->imm = (flags & 64u) ? take_u8(in) : (uint16_t)((flags >> 1) & 1u);
    aenl_real_t t = take_real(in, raw);
    for (uint16_t i = 0; i + 1u < nm; ++i)
    {
        m->thr_rising[i] = t;
        m->thr_falling[i] = (flags & 8u) ? t - AENL_R(0.25) * (aenl_real_t)take_u8(in) : t;
        t += raw ? take_raw_real(in) : (aenl_real_t)take_u8(in) / AENL_R(16.0);
    }
    for (uint16_t s = 0; s < nm; ++s)
    {
        for (uint16_t i = 0; i < nx; ++i)
        {
            for (uint16_t j = 0; j < nx; ++j)
            {
                m->A[s][i][j] = take_real(in, raw);
            }
            m->b[s][i] = take_real(in, raw);
        }
        take_sym(in, &m->Q[s][0][0], NX, nx, raw, psd);
    }
    for (uint16_t r = 0; r < nz; ++r)
    {
        for (uint16_t j = 0; j < nx; ++j)
        {
            m->C[r][j] = take_real(in, raw);
        }
    }
    take_sym(in, &m->R[0][0], NZ, nz, raw, psd);
    for (uint16_t i = 0; i < nx; ++i)
    {
        m->x0[i] = take_real(in, raw);
    }
    take_sym(in, &m->P0[0][0], NX, nx, raw, psd);
    for (uint16_t i = 0; i < nm; ++i)
    {
        if (raw)
        {
            for (uint16_t j = 0; j < nm; ++j)
            {
                m->trans[i][j] = take_raw_real(in);
            }
            continue;
        }
        aenl_real_t w[NM], sum = AENL_R(0.0);
        for (uint16_t j = 0; j < nm; ++j)
        {
            w[j] = (aenl_real_t)take_u8(in) + ((i == j) ? AENL_R(1.0) : AENL_R(0.0));
            sum += w[j];
        }
        for (uint16_t j = 0; j < nm; ++j)
        {
            m->trans[i][j] = w[j] / sum;
        }
    }
}

/* Everything a rejected step must leave alone. */
typedef struct
{
    aenl_real_t x[NX];
    aenl_real_t P[NX * NX];
    aenl_real_t prob[NM];
    uint16_t mode;
    int16_t dir;
} snapshot_t;

static void snap(const aenl_skf_t *f, snapshot_t *s)
{
    memset(s, 0, sizeof(*s));
    CHECK(aenl_skf_estimate(f, s->x, s->P) == AENL_OK, "estimate failed on a valid filter");
    CHECK(aenl_skf_mode_prob(f, s->prob) == AENL_OK, "mode_prob failed on a valid filter");
    s->mode = f->mode;
    s->dir = f->dir;
}

static int all_finite(const aenl_real_t *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        if (!isfinite(v[i]))
        {
            return 0;
        }
    }
    return 1;
}

static void check_ok_step(const aenl_skf_t *f, const aenl_skf_out_t *out, uint16_t n_used)
{
    snapshot_t s;
    snap(f, &s);
    const size_t nx = f->n_x;
    CHECK(all_finite(s.x, nx), "non-finite estimate after AENL_OK");
    CHECK(all_finite(s.P, nx * nx), "non-finite covariance after AENL_OK");
    CHECK(all_finite(s.prob, f->n_modes), "non-finite mode probability after AENL_OK");
    double sum = 0.0;
    for (uint16_t j = 0; j < f->n_modes; ++j)
    {
        CHECK(s.prob[j] >= AENL_R(0.0) && s.prob[j] <= AENL_R(1.0) + AENL_R(1e-4),
              "mode probability outside [0, 1]");
        sum += (double)s.prob[j];
    }
    CHECK(fabs(sum - 1.0) < 1e-3, "mode probabilities do not sum to 1");
    CHECK(out->mode < f->n_modes && out->mode_threshold < f->n_modes, "mode out of range");
    CHECK(out->n_used == n_used, "n_used is not the number of finite components");
    CHECK(isfinite(out->nis) && out->nis >= AENL_R(0.0), "NIS negative or non-finite");
    CHECK(isfinite(out->log_lik), "log-likelihood non-finite");
    CHECK(n_used > 0u || (out->nis == AENL_R(0.0) && out->log_lik == AENL_R(0.0)),
          "predict-only step with a non-zero NIS or likelihood");
}

static void check_reset(aenl_skf_t *f, const aenl_skf_model_t *m)
{
    aenl_skf_reset(f);
    snapshot_t s;
    snap(f, &s);
    for (uint16_t i = 0; i < f->n_x; ++i)
    {
        /* IMM: a mixture of n_modes copies of x0, equal up to rounding. */
        const aenl_real_t tol =
            m->imm ? AENL_R(1e-5) * (AENL_R(1.0) + (aenl_real_t)fabs((double)m->x0[i]))
                   : AENL_R(0.0);
        CHECK(fabs((double)(s.x[i] - m->x0[i])) <= (double)tol, "reset does not restore x0");
    }
    CHECK(f->n_steps == 0u && f->n_not_pd == 0u && f->n_numeric == 0u && f->n_nis == 0u,
          "reset keeps counters");
}

static aenl_skf_t g_f, g_before;
static aenl_skf_model_t g_m;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input_t in = {data, size};
    const uint8_t flags = take_u8(&in);
    read_model(&in, flags, &g_m);

    CHECK(aenl_skf_init(NULL, &g_m) == AENL_E_ARG, "init(NULL) not AENL_E_ARG");
    memset(&g_f, 0xA5, sizeof(g_f));
    memcpy(&g_before, &g_f, sizeof(g_f));
    const aenl_status_t st = aenl_skf_init(&g_f, &g_m);
    CHECK(st == AENL_OK || st == AENL_E_ARG || st == AENL_E_DIM, "init: unexpected status");
    if (st != AENL_OK)
    {
        CHECK(memcmp(&g_f, &g_before, sizeof(g_f)) == 0, "failed init wrote the state");
        return 0;
    }
    const uint16_t nz = g_f.n_z;
    CHECK(g_f.n_x >= 1u && g_f.n_x <= NX && nz >= 1u && nz <= NZ && g_f.n_modes >= 1u &&
              g_f.n_modes <= NM,
          "init accepted sizes outside the maxima");
    CHECK(aenl_skf_step(&g_f, NULL, NULL) == AENL_E_ARG, "step(z = NULL) not AENL_E_ARG");

    size_t n_ops = 0;
    while (in.n > 0u && n_ops++ < 2000u)
    {
        const uint8_t op = take_u8(&in);
        const unsigned kind = op >> 5;
        aenl_real_t z[NZ];
        int has_inf = 0;
        if (kind == 6u)
        {
            check_reset(&g_f, &g_m);
            continue;
        }
        if (kind == 7u)
        {
            snapshot_t s;
            snap(&g_f, &s);
            aenl_real_t mn;
            const aenl_status_t sn = aenl_skf_mean_nis(&g_f, &mn);
            CHECK(sn == AENL_OK || sn == AENL_E_EMPTY, "mean_nis: unexpected status");
            CHECK((sn == AENL_E_EMPTY) == (g_f.n_nis == 0u), "mean_nis EMPTY iff no update");
            continue;
        }
        for (uint16_t r = 0; r < nz; ++r)
        {
            if (kind == 5u)
            {
                z[r] = take_raw_real(&in);
            }
            else
            {
                z[r] = take_small(&in) * (aenl_real_t)(1u + (take_u8(&in) & 63u));
                if (kind <= 3u && ((op >> (r % 4u)) & 1u))
                {
                    z[r] = (aenl_real_t)NAN;
                }
            }
        }
        if (kind == 4u)
        {
            z[op % nz] = (op & 16u) ? (aenl_real_t)-INFINITY : (aenl_real_t)INFINITY;
        }
        uint16_t n_used = 0;
        for (uint16_t r = 0; r < nz; ++r)
        {
            has_inf |= isinf(z[r]) ? 1 : 0;
            n_used = (uint16_t)(n_used + (isnan(z[r]) ? 0u : 1u));
        }
        snapshot_t s0, s1;
        snap(&g_f, &s0);
        aenl_skf_out_t out;
        memset(&out, 0x5A, sizeof(out));
        const aenl_status_t ss = aenl_skf_step(&g_f, z, &out);
        CHECK(ss == AENL_OK || ss == AENL_E_NUMERIC || ss == AENL_E_NOT_PD,
              "step: unexpected status");
        if (has_inf)
        {
            CHECK(ss == AENL_E_NUMERIC, "infinite z component not AENL_E_NUMERIC");
        }
        if (ss != AENL_OK)
        {
            static const aenl_skf_out_t zero;
            snap(&g_f, &s1);
            CHECK(memcmp(&s0, &s1, sizeof(s0)) == 0, "rejected step changed the estimate");
            CHECK(memcmp(&out, &zero, sizeof(out)) == 0, "rejected step left *out non-zero");
            continue;
        }
        if (!has_inf)
        {
            check_ok_step(&g_f, &out, n_used);
        }
    }
    return 0;
}
