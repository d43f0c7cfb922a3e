/* SPDX-License-Identifier: MIT */
/**
 * @file bench_simulate.c
 * @brief `aenl bench simulate`: wall time of the event-located integrator on 100 s of the 3-DOF
 *        flap-freeplay case at 1 kHz output, against a naive fixed-step RK4 of equal accuracy;
 *        and independent runs on one thread against the threads a diagnosis uses.
 */

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_clock.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_sim.h"

static const char *const k_cmd = "bench simulate";

static void bench_case(aenl_sim_model_t *m, aenl_sim_run_t *r)
{
    const double deg = 3.14159265358979323846 / 180.0;
    aenl_sim_model_default(m, AENL_SIM_SECTION3DOF);
    m->section.velocity = 15.0;
    m->x0[AENL_SIM_DOF_PITCH] = 1.0 * deg;
    m->law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_FREEPLAY;
    m->law[AENL_SIM_DOF_FLAP].delta = 2.0 * 2.12 * deg;
    m->law[AENL_SIM_DOF_FLAP].x_f = -2.12 * deg;
    aenl_sim_run_default(r, AENL_SIM_SECTION3DOF);
    r->duration = 100.0;
    r->dt = 1e-3;
}

/* Independent runs of the case (what a diagnosis's batches are): run i simulated and freed. */
typedef struct
{
    const aenl_sim_model_t *m;
    const aenl_sim_run_t *run;
    int failed[AENL_MAX_JOBS * 2u];
} runs_t;

static void one_run(void *ctx, size_t i)
{
    runs_t *r = (runs_t *)ctx;
    aenl_sim_result_t res;
    aenl_err_t err;
    aenl_err_clear(&err);
    r->failed[i] = aenl_sim_simulate(r->m, r->run, &res, &err) != AENL_OK;
    if (!r->failed[i])
    {
        aenl_sim_result_free(&res);
    }
}

/* Wall time of n runs on the current thread setting; -1 when one failed. */
static double runs_wall(runs_t *r, size_t n)
{
    memset(r->failed, 0, sizeof(r->failed));
    const double t0 = aenl_now_s();
    aenl_parallel_for(n, one_run, r);
    const double wall = aenl_now_s() - t0;
    for (size_t i = 0; i < n; ++i)
    {
        if (r->failed[i])
        {
            return -1.0;
        }
    }
    return wall;
}

/* The same independent runs on one thread and on the default threads, in this run. */
static int bench_threads(const aenl_sim_model_t *m, const aenl_sim_run_t *run)
{
    const unsigned jobs = aenl_jobs();
    const size_t n = 2u * (size_t)jobs;
    runs_t r = {m, run, {0}};
    aenl_set_jobs(1);
    const double one = runs_wall(&r, n);
    aenl_set_jobs(jobs);
    const double many = runs_wall(&r, n);
    if (one < 0.0 || many < 0.0)
    {
        aenl_cli_error(k_cmd, "a run of the threads' comparison failed");
        return AENL_EXIT_FAIL;
    }
    printf("  %zu independent runs of the case (a diagnosis's batches): %.3f s on one thread, "
           "%.3f s on %u (ratio %.2f)\n",
           n, one, many, jobs, many / one);
    return AENL_EXIT_OK;
}

/* max over channels of max|y − ref| / max|ref| */
static double rel_error(const aenl_sim_result_t *a, const aenl_sim_result_t *ref)
{
    const size_t n = a->n_samples < ref->n_samples ? a->n_samples : ref->n_samples;
    double worst = 0.0;
    size_t c, k;
    for (c = 0; c < a->n_channels; ++c)
    {
        double emax = 0.0, ymax = 0.0;
        for (k = 0; k < n; ++k)
        {
            const double yr = ref->y[c * ref->n_samples + k];
            emax = fmax(emax, fabs(a->y[c * a->n_samples + k] - yr));
            ymax = fmax(ymax, fabs(yr));
        }
        if (ymax > 0.0)
        {
            worst = fmax(worst, emax / ymax);
        }
    }
    return worst;
}

int aenl_bench_simulate(int argc, char **argv)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run, acc;
    aenl_sim_result_t res, ref, short_ev, rk;
    aenl_err_t err;
    double best = HUGE_VAL, e_ev, e_prev = 0.0, h_prev = 0.0, cost_per_step = 0.0;
    double h_need = 0.0, order = 0.0;
    int rep, reached = 0, k;
    (void)argv;
    aenl_err_clear(&err);
    if (argc > 1)
    {
        aenl_cli_error(k_cmd, "takes no options");
        return AENL_EXIT_USAGE;
    }
    bench_case(&m, &run);
    printf(
        "simulate (3-DOF section, Conner parameters, flap freeplay half gap 2.12 deg, U = 15 m/s,\n"
        "alpha(0) = 1 deg; 100 s at 1 kHz output; host, double):\n");
    for (rep = 0; rep < 3; ++rep)
    {
        const double t0 = aenl_now_s();
        if (aenl_sim_simulate(&m, &run, &res, &err) != AENL_OK)
        {
            aenl_cli_error(k_cmd, "%s", err.msg);
            return AENL_EXIT_FAIL;
        }
        best = fmin(best, aenl_now_s() - t0);
        if (rep < 2)
        {
            aenl_sim_result_free(&res);
        }
    }
    printf("  event-located DP5(4), rtol %.0e atol %.0e: %.3f s wall (best of 3); %lu steps, "
           "%lu rejected, %lu events\n",
           run.rtol, run.atol, best, res.info.n_steps, res.info.n_rejected, res.info.n_events);
    aenl_sim_result_free(&res);

    /* Accuracy on the first 3 s against a much tighter event-located run. */
    acc = run;
    acc.duration = 3.0;
    if (aenl_sim_simulate(&m, &acc, &short_ev, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_FAIL;
    }
    acc.rtol = 1e-13;
    acc.atol = 1e-15;
    if (aenl_sim_simulate(&m, &acc, &ref, &err) != AENL_OK)
    {
        aenl_sim_result_free(&short_ev);
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_FAIL;
    }
    e_ev = rel_error(&short_ev, &ref);
    aenl_sim_result_free(&short_ev);
    printf("  its accuracy over the first 3 s (max error / max amplitude, vs rtol 1e-13): %.2g\n",
           e_ev);
    printf("  naive fixed-step RK4 (branch from the state at every stage), same 3 s:\n");
    acc.rtol = run.rtol;
    acc.atol = run.atol;
    for (k = 0; k < 8; ++k)
    {
        const double h = 1e-4 * ldexp(1.0, -k); /* halved each round */
        double t0, wall, e;
        t0 = aenl_now_s();
        if (aenl_sim_simulate_rk4(&m, &acc, h, &rk, &err) != AENL_OK)
        {
            aenl_sim_result_free(&ref);
            aenl_cli_error(k_cmd, "%s", err.msg);
            return AENL_EXIT_FAIL;
        }
        wall = aenl_now_s() - t0;
        e = rel_error(&rk, &ref);
        cost_per_step = wall / (double)rk.info.n_steps;
        aenl_sim_result_free(&rk);
        printf("    h = %.3g s: error %.2g, %.3f s wall\n", h, e, wall);
        if (e <= e_ev)
        {
            reached = 1;
            h_need = h;
            break;
        }
        if (k > 0 && e_prev > e && e > 0.0)
        {
            order = log(e_prev / e) / log(h_prev / h);
        }
        h_prev = h;
        e_prev = e;
    }
    aenl_sim_result_free(&ref);
    if (!reached)
    {
        if (!(order > 0.1))
        {
            printf("  RK4 does not converge towards the event solution here; no ratio.\n");
            return bench_threads(&m, &run);
        }
        h_need = h_prev * pow(e_ev / e_prev, 1.0 / order);
    }
    {
        double rk_wall = (run.duration / h_need) * cost_per_step;
        int timed = 0;
        printf("  RK4 step reaching the same accuracy: h = %.3g s%s\n", h_need,
               reached ? " (measured)" : "");
        if (!reached)
        {
            printf("    (extrapolated with the observed convergence order %.2f: locating the "
                   "switches costs naive RK4 its 4th order)\n",
                   order);
        }
        if (rk_wall < 60.0)
        {
            /* Affordable: time the whole 100 s RK4 run at that step. */
            const double t0 = aenl_now_s();
            if (aenl_sim_simulate_rk4(&m, &run, h_need, &rk, &err) != AENL_OK)
            {
                aenl_cli_error(k_cmd, "%s", err.msg);
                return AENL_EXIT_FAIL;
            }
            rk_wall = aenl_now_s() - t0;
            aenl_sim_result_free(&rk);
            timed = 1;
        }
        printf("  RK4 wall time for the same 100 s run at that step: %.3g s (%s)\n", rk_wall,
               timed ? "measured" : "measured cost per step x steps");
        printf("  ratio RK4 / event-located: %.3g\n", rk_wall / best);
    }
    return bench_threads(&m, &run);
}
