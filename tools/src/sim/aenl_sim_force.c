/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_force.c
 * @brief Forced excitation of one DOF: swept sine and random-phase multisine (aenl_sim.h).
 */
#include <math.h>
#include <string.h>

#include "aenl_sim_internal.h"

#define TWO_PI 6.283185307179586

static const char *const FORCE_NAME[AENL_SIM_N_DOF] = {"f_pitch", "f_plunge", "f_flap"};

/* The multisine's first and last grid index j (frequency j / P) inside [f0, f1]. */
static void multisine_lines(const aenl_sim_run_t *run, double *j0, double *j1)
{
    const double P = run->force_period > 0.0 ? run->force_period : run->duration;
    *j0 = fmax(1.0, ceil(run->force_f0 * P - 1e-9));
    *j1 = floor(run->force_f1 * P + 1e-9);
}

/* The signal's settings (amplitude, frequencies, lines), whatever the model. */
static aenl_status_t signal_check(const aenl_sim_run_t *run, aenl_err_t *err)
{
    if (run->force != AENL_SIM_FORCE_SWEEP && run->force != AENL_SIM_FORCE_MULTISINE)
    {
        aenl_err_set(err, "[excitation] type: unknown forced excitation");
        return AENL_E_ARG;
    }
    const char *amp = run->force == AENL_SIM_FORCE_SWEEP ? "amplitude" : "rms";
    if (!isfinite(run->force_amp) || !(run->force_amp > 0.0))
    {
        aenl_err_set(err, "[excitation] %s must be > 0", amp);
        return AENL_E_ARG;
    }
    const char *k0 = run->force == AENL_SIM_FORCE_SWEEP ? "f_start" : "f_min";
    const char *k1 = run->force == AENL_SIM_FORCE_SWEEP ? "f_end" : "f_max";
    const double nyq = 0.5 / run->dt;
    if (!isfinite(run->force_f0) || !(run->force_f0 > 0.0) || !(run->force_f0 < nyq))
    {
        aenl_err_set(err, "[excitation] %s must be > 0 and below the Nyquist frequency %g", k0,
                     nyq);
        return AENL_E_ARG;
    }
    if (!isfinite(run->force_f1) || !(run->force_f1 > 0.0) || !(run->force_f1 < nyq))
    {
        aenl_err_set(err, "[excitation] %s must be > 0 and below the Nyquist frequency %g", k1,
                     nyq);
        return AENL_E_ARG;
    }
    if (run->force == AENL_SIM_FORCE_MULTISINE)
    {
        if (run->force_f1 < run->force_f0)
        {
            aenl_err_set(err, "[excitation] f_max must not be below f_min");
            return AENL_E_ARG;
        }
        if (!isfinite(run->force_period) || run->force_period < 0.0)
        {
            aenl_err_set(err, "[excitation] period must be finite and >= 0 (0: the duration)");
            return AENL_E_ARG;
        }
        double j0 = 0.0;
        double j1 = 0.0;
        multisine_lines(run, &j0, &j1);
        if (j1 < j0)
        {
            aenl_err_set(err, "[excitation] no line of the multisine's grid (1/period) lies in "
                              "[f_min, f_max]: widen the band or lengthen the period");
            return AENL_E_ARG;
        }
        if (j1 - j0 + 1.0 > (double)AENL_SIM_MAX_LINES)
        {
            aenl_err_set(err,
                         "[excitation] the multisine has %.0f lines in [f_min, f_max] (at most "
                         "%d): narrow the band or shorten the period",
                         j1 - j0 + 1.0, AENL_SIM_MAX_LINES);
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

aenl_status_t sim_force_check(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                              aenl_err_t *err)
{
    if (run->force == AENL_SIM_FORCE_NONE)
    {
        return AENL_OK;
    }
    if (run->turbulence || run->kicks)
    {
        aenl_err_set(err, "[excitation] a forced excitation cannot be combined with turbulence "
                          "or kicks");
        return AENL_E_ARG;
    }
    if ((int)run->force_dof < 0 || (int)run->force_dof >= AENL_SIM_N_DOF ||
        (run->force_dof == AENL_SIM_DOF_FLAP && model->type != AENL_SIM_SECTION3DOF))
    {
        aenl_err_set(err, "[excitation] dof: no such DOF in this model");
        return AENL_E_ARG;
    }
    return signal_check(run, err);
}

void sim_force_init(sim_force_t *f, const aenl_sim_run_t *run)
{
    memset(f, 0, sizeof(*f));
    f->kind = run->force;
    f->amp = run->force_amp;
    f->f0 = run->force_f0;
    f->f1 = run->force_f1;
    f->T = run->duration;
    f->log = run->force_log;
    if (f->kind == AENL_SIM_FORCE_MULTISINE)
    {
        const double P = run->force_period > 0.0 ? run->force_period : run->duration;
        double j0 = 0.0;
        double j1 = 0.0;
        multisine_lines(run, &j0, &j1);
        aenl_rng_t rng;
        aenl_rng_seed(&rng, run->force_seed);
        const size_t n_lines = (size_t)(j1 - j0 + 1.0);
        for (size_t i = 0; i < n_lines && f->n_lines < AENL_SIM_MAX_LINES; ++i)
        {
            f->w[f->n_lines] = TWO_PI * (j0 + (double)i) / P;
            f->ph[f->n_lines] = TWO_PI * aenl_rng_uniform(&rng);
            f->n_lines++;
        }
        /* equal lines of amplitude a have the mean square n a^2 / 2 over a period */
        f->amp = f->n_lines > 0 ? run->force_amp * sqrt(2.0 / (double)f->n_lines) : 0.0;
    }
}

double sim_force_eval(const sim_force_t *f, double t)
{
    if (f->kind == AENL_SIM_FORCE_SWEEP)
    {
        double phi;
        const double r = f->f1 / f->f0;
        if (f->log && fabs(r - 1.0) > 1e-12)
        {
            const double k = log(r) / f->T;
            phi = TWO_PI * f->f0 * expm1(k * t) / k;
        }
        else
        {
            phi = TWO_PI * (f->f0 * t + (f->f1 - f->f0) * t * t / (2.0 * f->T));
        }
        return f->amp * sin(phi);
    }
    if (f->kind == AENL_SIM_FORCE_MULTISINE)
    {
        double s = 0.0;
        for (size_t i = 0; i < f->n_lines; ++i)
        {
            s += sin(f->w[i] * t + f->ph[i]);
        }
        return f->amp * s;
    }
    return 0.0;
}

void sim_force_attach(sim_sys_t *sys, const sim_force_t *f, const aenl_sim_run_t *run)
{
    sys->force = NULL;
    sys->force_q = 0;
    if (f == NULL || f->kind == AENL_SIM_FORCE_NONE)
    {
        return;
    }
    for (int q = 0; q < sys->nq; ++q)
    {
        if (sys->dof[q] == (int)run->force_dof)
        {
            sys->force = f;
            sys->force_q = q;
        }
    }
}

aenl_status_t aenl_sim_force_series(const aenl_sim_run_t *run, size_t n, double *f, aenl_err_t *err)
{
    if (run == NULL || f == NULL || run->force == AENL_SIM_FORCE_NONE)
    {
        aenl_err_set(err, "force series: need a run with a forced excitation and an output");
        return AENL_E_ARG;
    }
    if (!isfinite(run->dt) || !(run->dt > 0.0) || !isfinite(run->duration) ||
        !(run->duration > 0.0))
    {
        aenl_err_set(err, "force series: need finite dt > 0 and duration > 0");
        return AENL_E_ARG;
    }
    const aenl_status_t st = signal_check(run, err);
    if (st != AENL_OK)
    {
        return st;
    }
    sim_force_t g;
    sim_force_init(&g, run);
    for (size_t k = 0; k < n; ++k)
    {
        f[k] = sim_force_eval(&g, (double)k * run->dt);
    }
    return AENL_OK;
}

const char *sim_force_name(aenl_sim_dof_t dof)
{
    return (int)dof >= 0 && (int)dof < AENL_SIM_N_DOF ? FORCE_NAME[dof] : "f";
}
