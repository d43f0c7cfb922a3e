/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_flutter.c
 * @brief Linear state matrix, eigenvalues (LAPACKE dgeev) and the flutter speed by bracketing
 *        (the classic airfoil case flutters at U* 6.285, Conner's section at 23.897 m/s).
 */
#include <lapacke.h>
#include <math.h>
#include <string.h>

#include "aenl_sim_internal.h"

aenl_status_t aenl_sim_state_matrix(const aenl_sim_model_t *model, double velocity,
                                    const double *slope, double *A, size_t *n, aenl_err_t *err)
{
    sim_sys_t sys;
    double x[AENL_SIM_MAX_X], dx[AENL_SIM_MAX_X], sq[AENL_SIM_MAX_Q];
    aenl_status_t st;
    int i, j, nx;
    if (model == NULL || A == NULL || n == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    if ((st = aenl_sim_validate(model, NULL, err)) != AENL_OK)
    {
        return st;
    }
    if ((st = sim_sys_build(model, velocity, 0, 1.0, &sys, err)) != AENL_OK)
    {
        return st;
    }
    for (i = 0; i < sys.nq; ++i)
    {
        const aenl_sim_law_t *law = &model->law[sys.dof[i]];
        if (slope != NULL)
        {
            sq[i] = slope[sys.dof[i]];
        }
        else
        {
            sq[i] = (law->kind == AENL_SIM_LAW_POLYNOMIAL) ? law->coeffs[0] : 1.0;
        }
    }
    nx = sys.nx;
    for (j = 0; j < nx; ++j)
    {
        memset(x, 0, sizeof(x));
        x[j] = 1.0;
        sim_rhs_linear(&sys, sq, x, dx);
        for (i = 0; i < nx; ++i)
        {
            A[(size_t)i * (size_t)nx + (size_t)j] = dx[i];
        }
    }
    *n = (size_t)nx;
    return AENL_OK;
}

/* Eigenvalues of the state matrix; *freq_scale converts Im λ to the reported frequency. */
static aenl_status_t eigen(const aenl_sim_model_t *model, double velocity, const double *slope,
                           double *wr, double *wi, size_t *n, double *freq_scale, aenl_err_t *err)
{
    double A[AENL_SIM_MAX_X * AENL_SIM_MAX_X], vl[1], vr[1];
    aenl_status_t st;
    lapack_int info;
    if ((st = aenl_sim_state_matrix(model, velocity, slope, A, n, err)) != AENL_OK)
    {
        return st;
    }
    info = LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', (lapack_int)*n, A, (lapack_int)*n, wr, wi, vl,
                         1, vr, 1);
    if (info != 0)
    {
        aenl_err_set(err, "dgeev failed (info %d) at velocity %g", (int)info, velocity);
        return AENL_E_NUMERIC;
    }
    *freq_scale =
        (model->type == AENL_SIM_AIRFOIL2DOF) ? velocity : 1.0 / (2.0 * 3.14159265358979323846);
    return AENL_OK;
}

aenl_status_t aenl_sim_modes(const aenl_sim_model_t *model, double velocity, const double *slope,
                             aenl_sim_mode_t *modes, size_t cap, size_t *n_modes, aenl_err_t *err)
{
    double wr[AENL_SIM_MAX_X], wi[AENL_SIM_MAX_X], fs = 1.0;
    size_t n = 0, i, m = 0;
    aenl_status_t st;
    if (modes == NULL || n_modes == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    if ((st = eigen(model, velocity, slope, wr, wi, &n, &fs, err)) != AENL_OK)
    {
        return st;
    }
    for (i = 0; i < n && m < cap; ++i)
    {
        if (wi[i] > 0.0)
        {
            const double mag = hypot(wr[i], wi[i]);
            size_t k = m;
            aenl_sim_mode_t md;
            md.re = wr[i];
            md.im = wi[i];
            md.damping = mag > 0.0 ? -wr[i] / mag : 0.0;
            md.frequency = wi[i] * fs;
            while (k > 0 && modes[k - 1].frequency > md.frequency) /* insertion sort */
            {
                modes[k] = modes[k - 1];
                --k;
            }
            modes[k] = md;
            ++m;
        }
    }
    *n_modes = m;
    return AENL_OK;
}

/* Largest real part over the non-neutral eigenvalues, and the frequency of that eigenvalue. */
static aenl_status_t growth(const aenl_sim_model_t *model, double v, const double *slope, double *g,
                            double *f, aenl_err_t *err)
{
    double wr[AENL_SIM_MAX_X], wi[AENL_SIM_MAX_X], fs = 1.0, best = -HUGE_VAL, bf = 0.0;
    size_t n = 0, i;
    aenl_status_t st;
    if ((st = eigen(model, v, slope, wr, wi, &n, &fs, err)) != AENL_OK)
    {
        return st;
    }
    for (i = 0; i < n; ++i)
    {
        if (hypot(wr[i], wi[i]) < 1e-9)
        {
            continue; /* neutral: a DOF with zero total stiffness */
        }
        if (wr[i] > best)
        {
            best = wr[i];
            bf = fabs(wi[i]) * fs;
        }
    }
    *g = best;
    *f = bf;
    return AENL_OK;
}

aenl_status_t aenl_sim_flutter(const aenl_sim_model_t *model, const double *slope, double v_min,
                               double v_max, aenl_sim_flutter_t *out, aenl_err_t *err)
{
    const int n_scan = 4000;
    double lo, hi, glo, ghi, f = 0.0, v_prev, g_prev;
    aenl_status_t st;
    int k, it;
    if (model == NULL || out == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    memset(out, 0, sizeof(*out));
    if (!(v_min > 0.0))
    {
        v_min = (model->type == AENL_SIM_AIRFOIL2DOF) ? 0.05 : 0.5;
    }
    if (!(v_max > 0.0))
    {
        v_max = (model->type == AENL_SIM_AIRFOIL2DOF) ? 50.0 : 200.0;
    }
    if (!(v_max > v_min) || !isfinite(v_max))
    {
        aenl_err_set(err, "flutter search range must satisfy 0 < v_min < v_max");
        return AENL_E_ARG;
    }
    v_prev = v_min;
    if ((st = growth(model, v_prev, slope, &g_prev, &f, err)) != AENL_OK)
    {
        return st;
    }
    if (g_prev > 0.0)
    {
        out->found = 1; /* unstable from the start of the range */
        out->speed = v_min;
        out->frequency = f;
        return AENL_OK;
    }
    for (k = 1; k <= n_scan; ++k)
    {
        const double v = v_min + (v_max - v_min) * (double)k / (double)n_scan;
        double g;
        if ((st = growth(model, v, slope, &g, &f, err)) != AENL_OK)
        {
            return st;
        }
        if (g > 0.0)
        {
            lo = v_prev;
            hi = v;
            glo = g_prev;
            ghi = g;
            for (it = 0; it < 200 && hi - lo > 1e-13 * hi; ++it)
            {
                const double mid = 0.5 * (lo + hi);
                double gm;
                if ((st = growth(model, mid, slope, &gm, &f, err)) != AENL_OK)
                {
                    return st;
                }
                if (gm > 0.0)
                {
                    hi = mid;
                    ghi = gm;
                }
                else
                {
                    lo = mid;
                    glo = gm;
                }
            }
            (void)glo;
            (void)ghi;
            if ((st = growth(model, hi, slope, &g, &f, err)) != AENL_OK)
            {
                return st;
            }
            out->found = 1;
            out->speed = 0.5 * (lo + hi);
            out->frequency = f;
            return AENL_OK;
        }
        v_prev = v;
        g_prev = g;
    }
    return AENL_OK;
}
