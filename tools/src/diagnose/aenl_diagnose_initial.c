/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_initial.c
 * @brief A free decay's unknown release: the baseline's initial state (positions and rates of
 *        every DOF) fitted to the record's first period by Gauss-Newton least squares, with
 *        standard errors (docs/diagnose.md, "The initial state of a free decay").
 */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_dense.h"

#define N_PAR_MAX (2u * AENL_SIM_N_DOF)
/* Gauss-Newton: at most this many steps, each halved at most HALVINGS times until the misfit
 * falls; a linear baseline's response is linear in the state, so one step is exact there. */
#define GN_STEPS 6u
#define HALVINGS 4u
/* Finite-difference step of a position, in the channel's std (the rates': over the period's
 * angular frequency). Small enough that a law's curvature does not show, large against the
 * integrator's relative tolerance. */
#define FD_STEP 1e-4
#define TWO_PI  6.283185307179586

int aenl_diagnose_initial_wanted(const aenl_sim_model_t *m, const aenl_sim_run_t *run)
{
    if (run->turbulence || m->initial == AENL_SIM_INITIAL_GIVEN)
    {
        return 0;
    }
    if (m->initial == AENL_SIM_INITIAL_ESTIMATE)
    {
        return 1;
    }
    if (run->kicks)
    {
        return 0; /* a kick train moves a baseline from rest: a zero start is a start */
    }
    for (size_t d = 0; d < AENL_SIM_N_DOF; ++d)
    {
        if (fabs(m->x0[d]) > 0.0 || fabs(m->v0[d]) > 0.0)
        {
            return 0;
        }
    }
    return 1;
}

typedef struct
{
    const aenl_sim_model_t *base;
    aenl_sim_run_t run; /* the window's run: no noise */
    const double *y;    /* the record, [channel][sample], n samples a channel */
    size_t n, w, n_ch;
    double *scale; /* per channel: the residuals' divisors */
    aenl_sim_dof_t dof[AENL_SIM_N_DOF];
    size_t n_dof;
} fit_t;

static void set_state(const fit_t *f, const double *p, aenl_sim_model_t *m)
{
    *m = *f->base;
    for (size_t k = 0; k < f->n_dof; ++k)
    {
        m->x0[f->dof[k]] = p[k];
        m->v0[f->dof[k]] = p[f->n_dof + k];
    }
}

/* Residuals (record minus model over the window, each channel in its std) at state p into res
 * (n_ch * w). AENL_E_NUMERIC: the window cannot be simulated from p; AENL_E_DIM: no memory. */
static aenl_status_t residuals(const fit_t *f, const double *p, double *res, aenl_err_t *err)
{
    aenl_sim_model_t m;
    set_state(f, p, &m);
    aenl_sim_result_t r;
    aenl_err_t e;
    aenl_err_clear(&e);
    const aenl_status_t st = aenl_sim_simulate(&m, &f->run, &r, &e);
    if (st == AENL_E_DIM)
    {
        aenl_err_set(err, "%s", e.msg);
        return st;
    }
    if (st != AENL_OK || r.n_samples < f->w)
    {
        if (st == AENL_OK)
        {
            aenl_sim_result_free(&r);
        }
        return AENL_E_NUMERIC;
    }
    for (size_t c = 0; c < f->n_ch; ++c)
    {
        for (size_t i = 0; i < f->w; ++i)
        {
            res[c * f->w + i] = (f->y[c * f->n + i] - r.y[c * r.n_samples + i]) / f->scale[c];
        }
    }
    aenl_sim_result_free(&r);
    return AENL_OK;
}

static double sum_sq(const double *v, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        s += v[i] * v[i];
    }
    return isfinite(s) ? s : HUGE_VAL;
}

/* Jacobian of the residuals at p (forward differences, steps h) into jac (column k: n_res). */
static aenl_status_t jacobian(const fit_t *f, const double *p, const double *res, const double *h,
                              double *jac, double *tmp, aenl_err_t *err)
{
    const size_t n_p = 2u * f->n_dof, n_res = f->n_ch * f->w;
    for (size_t k = 0; k < n_p; ++k)
    {
        double q[N_PAR_MAX];
        memcpy(q, p, n_p * sizeof(double));
        q[k] += h[k];
        const aenl_status_t st = residuals(f, q, tmp, err);
        if (st != AENL_OK)
        {
            return st;
        }
        for (size_t i = 0; i < n_res; ++i)
        {
            jac[k * n_res + i] = (tmp[i] - res[i]) / h[k];
        }
    }
    return AENL_OK;
}

/* Normal equations of the Jacobian: jtj (n_p x n_p) and jtr = J' res. */
static void normal_eq(const double *jac, const double *res, size_t n_res, size_t n_p, double *jtj,
                      double *jtr)
{
    for (size_t a = 0; a < n_p; ++a)
    {
        const double *ja = jac + a * n_res;
        double s = 0.0;
        for (size_t i = 0; i < n_res; ++i)
        {
            s += ja[i] * res[i];
        }
        jtr[a] = s;
        for (size_t b = 0; b <= a; ++b)
        {
            const double *jb = jac + b * n_res;
            double t = 0.0;
            for (size_t i = 0; i < n_res; ++i)
            {
                t += ja[i] * jb[i];
            }
            jtj[a * n_p + b] = t;
            jtj[b * n_p + a] = t;
        }
    }
}

/* Gauss-Newton from p; on return p is the fit, *rss its misfit and jtj the normal matrix at it.
 * A step whose promised reduction of the misfit is negligible is not taken (the fit has
 * converged: a model started at its own fit costs one Jacobian); steps that do not lower the
 * misfit are halved, and the fit stops when none does. */
static aenl_status_t gauss_newton(const fit_t *f, double *p, const double *h, double *rss,
                                  double *jtj, double *buf, aenl_err_t *err)
{
    const size_t n_p = 2u * f->n_dof, n_res = f->n_ch * f->w;
    double *res = buf, *tmp = buf + n_res, *jac = buf + 2u * n_res;
    aenl_status_t st = residuals(f, p, res, err);
    if (st != AENL_OK)
    {
        return st;
    }
    *rss = sum_sq(res, n_res);
    for (unsigned it = 0;; ++it)
    {
        double jtr[N_PAR_MAX], step[N_PAR_MAX], l[N_PAR_MAX * N_PAR_MAX];
        st = jacobian(f, p, res, h, jac, tmp, err); /* the normal matrix at p */
        if (st != AENL_OK)
        {
            return st;
        }
        normal_eq(jac, res, n_res, n_p, jtj, jtr);
        if (it == GN_STEPS)
        {
            break;
        }
        memcpy(l, jtj, n_p * n_p * sizeof(double));
        memcpy(step, jtr, n_p * sizeof(double));
        if (aenl_dense_posv(l, step, n_p, 1u) != 0)
        {
            return AENL_E_NUMERIC; /* the window does not determine the state */
        }
        double promised = 0.0; /* r'J (J'J)^-1 J'r: what a full step takes off the misfit */
        for (size_t a = 0; a < n_p; ++a)
        {
            promised += jtr[a] * step[a];
        }
        if (!(promised > 1e-10 * *rss))
        {
            break;
        }
        int moved = 0;
        for (unsigned k = 0; k <= HALVINGS && !moved; ++k)
        {
            double q[N_PAR_MAX];
            for (size_t a = 0; a < n_p; ++a)
            {
                /* the residuals' Jacobian is -d(response)/dp */
                q[a] = p[a] - ldexp(step[a], -(int)k);
            }
            st = residuals(f, q, tmp, err);
            if (st == AENL_E_DIM)
            {
                return st;
            }
            const double s = st == AENL_OK ? sum_sq(tmp, n_res) : HUGE_VAL;
            if (s < *rss)
            {
                moved = 1;
                memcpy(p, q, n_p * sizeof(double));
                memcpy(res, tmp, n_res * sizeof(double));
                *rss = s;
            }
        }
        if (!moved)
        {
            break; /* jtj is still at p */
        }
    }
    return AENL_OK;
}

/* The period of the model's fastest oscillatory mode at its velocity, in samples of step dt;
 * where the model has none, the shortest dominant period of the record's channels. */
static double fastest_period(const aenl_sim_model_t *m, double dt, const aenl_diagnose_chan_t *chan,
                             size_t n_ch)
{
    aenl_sim_mode_t modes[16];
    size_t n_modes = 0;
    aenl_err_t e;
    aenl_err_clear(&e);
    if (aenl_sim_modes(m, aenl_sim_velocity(m), NULL, modes, 16u, &n_modes, &e) == AENL_OK &&
        n_modes > 0u && modes[n_modes - 1u].im > 0.0)
    {
        return TWO_PI / (modes[n_modes - 1u].im * dt);
    }
    double p = HUGE_VAL;
    for (size_t c = 0; c < n_ch; ++c)
    {
        p = isfinite(chan[c].period) ? fmin(p, chan[c].period) : p;
    }
    return isfinite(p) ? fmax(p, 4.0) : 4.0;
}

aenl_status_t aenl_diagnose_initial_fit(const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                                        const double *y, size_t n, const aenl_diagnose_chan_t *chan,
                                        aenl_sim_model_t *out, aenl_diagnose_initial_t *info,
                                        aenl_err_t *err)
{
    memset(info, 0, sizeof(*info));
    *out = *base;
    fit_t f;
    memset(&f, 0, sizeof(f));
    f.base = base;
    f.y = y;
    f.n = n;
    size_t n_ch = 0;
    (void)aenl_diagnose_channel_names(base->type, &n_ch);
    if (n_ch == 0u || n < 2u)
    {
        aenl_err_set(err, "initial state: %zu samples of %zu channels", n, n_ch);
        return AENL_E_ARG;
    }
    f.n_ch = n_ch;
    f.n_dof = n_ch;
    double scale[AENL_SIM_MAX_Q];
    for (size_t c = 0; c < n_ch; ++c)
    {
        scale[c] = chan[c].scale > 0.0 ? chan[c].scale : 1.0;
    }
    f.scale = scale;
    const aenl_sim_dof_t dofs[3] = {AENL_SIM_DOF_PITCH, AENL_SIM_DOF_PLUNGE, AENL_SIM_DOF_FLAP};
    const size_t n_p = 2u * f.n_dof;
    /* One period of the model's fastest oscillatory mode: the positions are measured, and the
     * rates of every mode show over it; a law the model lacks has had the least time to move
     * the response away from the model's (over a slow mode's period a fast mode's phase drifts
     * by whatever its frequency error is, times the ratio of the two). At least enough
     * samples for the unknowns many times over. */
    const double period = fastest_period(base, run->dt, chan, n_ch);
    size_t w = (size_t)ceil(period) + 1u;
    w = w < 8u * n_p ? 8u * n_p : w;
    f.w = w < n ? w : n;
    f.run = *run;
    f.run.snr = 0.0;
    f.run.duration = (double)(f.w - 1u) * run->dt;
    double p[N_PAR_MAX], h[N_PAR_MAX];
    const double omega = TWO_PI / (period * run->dt); /* per model time unit */
    for (size_t k = 0; k < f.n_dof; ++k)
    {
        f.dof[k] = dofs[k];
        const size_t c = aenl_diagnose_dof_channel(base->type, dofs[k]);
        const int given = base->initial == AENL_SIM_INITIAL_ESTIMATE;
        p[k] = given ? base->x0[dofs[k]] : y[c * n];
        p[f.n_dof + k] = given ? base->v0[dofs[k]] : 0.0;
        h[k] = FD_STEP * scale[c];
        h[f.n_dof + k] = FD_STEP * scale[c] * omega;
    }
    const size_t n_res = n_ch * f.w;
    double *buf = calloc(2u * n_res + n_p * n_res, sizeof(double));
    if (buf == NULL)
    {
        aenl_err_set(err, "out of memory (initial state)");
        return AENL_E_DIM;
    }
    double p_start[N_PAR_MAX];
    memcpy(p_start, p, sizeof(p_start));
    double jtj[N_PAR_MAX * N_PAR_MAX], rss = HUGE_VAL;
    aenl_status_t st = gauss_newton(&f, p, h, &rss, jtj, buf, err);
    const double rms = sqrt(rss / (double)n_res); /* in the channels' stds */
    if (st == AENL_OK)
    {
        /* Each channel's residuals have their own spread (its noise, the model's misfit there):
         * weighted by it, the fit is the efficient one and the usual standard errors hold;
         * with one pooled variance they would be right only for channels of equal spread. The
         * second fit starts at the first and reweights once (feasible generalised least
         * squares). The residuals of the first fit are in buf. */
        for (size_t c = 0; c < n_ch; ++c)
        {
            const double r2 = sum_sq(buf + c * f.w, f.w) / (double)f.w;
            f.scale[c] *= fmax(sqrt(r2), 1e-12);
        }
        st = gauss_newton(&f, p, h, &rss, jtj, buf, err);
    }
    free(buf);
    if (st == AENL_E_DIM)
    {
        return st;
    }
    double inv[N_PAR_MAX * N_PAR_MAX];
    if (st != AENL_OK || !(rss < HUGE_VAL) || aenl_dense_invert(jtj, inv, n_p) != 0)
    {
        set_state(&f, p_start, out); /* not fitted: the start, window 0 */
        info->estimated = 1;
        aenl_err_set(err,
                     "the baseline's initial state cannot be fitted to the record's first %zu "
                     "samples (its response there cannot be simulated or does not depend on it); "
                     "give it in [initial] with estimate = false",
                     f.w);
        return AENL_E_ARG;
    }
    /* Standard errors: the weighted misfit's variance per residual (about 1) times the inverse
     * normal matrix, the parameters in the INI's units. */
    const double s2 = rss / (double)(n_res > n_p ? n_res - n_p : 1u);
    set_state(&f, p, out);
    info->estimated = 1;
    info->window = f.w;
    info->rms = rms;
    for (size_t k = 0; k < f.n_dof; ++k)
    {
        const double vx = inv[k * n_p + k] * s2, vv = inv[(f.n_dof + k) * n_p + f.n_dof + k] * s2;
        info->x0_sd[dofs[k]] = vx > 0.0 ? sqrt(vx) : 0.0;
        info->v0_sd[dofs[k]] = vv > 0.0 ? sqrt(vv) : 0.0;
    }
    return AENL_OK;
}
