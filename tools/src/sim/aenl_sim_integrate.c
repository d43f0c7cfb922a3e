/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_integrate.c
 * @brief Event-located Dormand-Prince 5(4) integration with dense output (described in
 *        aenl_sim.h), the naive fixed-step RK4 reference, turbulence input and measurement noise.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_sim_internal.h"
#include "aenl_tools/aenl_rng.h"

/* ---- Dormand-Prince 5(4) tableau with Shampine's 4th-order dense output ------------------- */

static const double DP_C[7] = {0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0};
static const double DP_A[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5.0, 0, 0, 0, 0, 0},
    {3.0 / 40.0, 9.0 / 40.0, 0, 0, 0, 0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0, 0, 0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0, 0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0},
    {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0}};
/* Error weights (5th minus 4th order), last entry on the FSAL stage. */
static const double DP_E[7] = {-71.0 / 57600.0,    0.0,           71.0 / 16695.0, -71.0 / 1920.0,
                               17253.0 / 339200.0, -22.0 / 525.0, 1.0 / 40.0};
/* y(t0 + θh) = y0 + h Σ_i K_i Σ_p P[i][p] θ^(p+1). */
static const double DP_P[7][4] = {
    {1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
     -12715105075.0 / 11282082432.0},
    {0.0, 0.0, 0.0, 0.0},
    {0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
     87487479700.0 / 32700410799.0},
    {0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0, -10690763975.0 / 1880347072.0},
    {0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
     701980252875.0 / 199316789632.0},
    {0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0},
    {0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0}};

/* ---- switching functions ------------------------------------------------------------------ */

enum
{
    EV_POS = 0,     /* g = sign (x_q − bound): position boundary of the branch */
    EV_VEL = 1,     /* g = dir ẋ_q: hysteresis reversal */
    EV_SLIP_DN = 2, /* g = R_req − M−(x_q): stuck DOF slips downwards when < 0 */
    EV_SLIP_UP = 3  /* g = M+(x_q) − R_req: stuck DOF slips upwards when < 0 */
};

#define MAX_EV (4 * AENL_SIM_MAX_Q)

typedef struct ev_id
{
    int q, kind, new_region;
    double bound, sign;
} ev_id_t;

typedef struct integ
{
    const sim_sys_t *sys;
    sim_mode_t mode;
    double u; /* gust input held over the current interval */
    double t, x[AENL_SIM_MAX_X], f[AENL_SIM_MAX_X];
    double h;
    double rtol, atol;
    double K[7][AENL_SIM_MAX_X];
    double Q[4][AENL_SIM_MAX_X]; /* dense output coefficients of the last step */
    double t0, hs, x0[AENL_SIM_MAX_X], x1[AENL_SIM_MAX_X];
    ev_id_t ev[MAX_EV];
    int n_ev;
    int armed[MAX_EV];
    double t_arm_end, arm_window;
    double t_burst;
    unsigned long n_burst;
    aenl_sim_info_t info;
    /* output */
    aenl_sim_result_t *res;
    size_t next_k;
    double dt;
    const double *bound;     /* the run's runaway bound per output channel (0: none) */
    unsigned long max_steps; /* the run's budget of accepted steps (0: none) */
} integ_t;

/* 1 and the message when state x has left the run's runaway bound on an output channel. */
static int out_of_bound(const sim_sys_t *s, const aenl_sim_result_t *res, const double *bound,
                        const double *x, double t, aenl_err_t *err)
{
    for (int c = 0; c < s->n_out; ++c)
    {
        const double v = x[s->out_q[c]];
        if (bound[c] > 0.0 && !(fabs(v) <= bound[c]))
        {
            aenl_err_set(err, "channel %s ran away: |%.6g| beyond the bound %.6g at t = %.17g",
                         res->names[c + 1], v, bound[c], t);
            return 1;
        }
    }
    return 0;
}

static void rhs(integ_t *in, const sim_mode_t *mode, double t, const double *x, double *dx,
                double *rreq)
{
    ++in->info.n_rhs;
    sim_rhs(in->sys, mode, t, x, in->u, dx, rreq);
}

static int list_events(const sim_sys_t *s, const sim_mode_t *mode, ev_id_t *ev)
{
    int q, n = 0;
    for (q = 0; q < s->nq; ++q)
    {
        const aenl_sim_law_t *law = &s->law[q];
        const sim_branch_t *b = &mode->b[q];
        double lo, hi;
        if (law->kind != AENL_SIM_LAW_FREEPLAY && law->kind != AENL_SIM_LAW_HYSTERESIS)
        {
            continue;
        }
        if (b->stuck)
        {
            ev[n].q = q;
            ev[n].kind = EV_SLIP_DN;
            ev[n].new_region = 0;
            ev[n].bound = 0.0;
            ev[n++].sign = 1.0;
            ev[n].q = q;
            ev[n].kind = EV_SLIP_UP;
            ev[n].new_region = 0;
            ev[n].bound = 0.0;
            ev[n++].sign = 1.0;
            continue;
        }
        sim_law_bounds(law, b->dir, &lo, &hi);
        if (b->region == 0)
        {
            ev[n].q = q;
            ev[n].kind = EV_POS;
            ev[n].new_region = 1;
            ev[n].bound = lo;
            ev[n++].sign = -1.0;
        }
        else if (b->region == 1)
        {
            ev[n].q = q;
            ev[n].kind = EV_POS;
            ev[n].new_region = 0;
            ev[n].bound = lo;
            ev[n++].sign = 1.0;
            ev[n].q = q;
            ev[n].kind = EV_POS;
            ev[n].new_region = 2;
            ev[n].bound = hi;
            ev[n++].sign = -1.0;
        }
        else
        {
            ev[n].q = q;
            ev[n].kind = EV_POS;
            ev[n].new_region = 1;
            ev[n].bound = hi;
            ev[n++].sign = 1.0;
        }
        if (law->kind == AENL_SIM_LAW_HYSTERESIS)
        {
            ev[n].q = q;
            ev[n].kind = EV_VEL;
            ev[n].new_region = b->region;
            ev[n].bound = 0.0;
            ev[n++].sign = (double)b->dir;
        }
    }
    return n;
}

static double ev_value(integ_t *in, const ev_id_t *e, double t, const double *x)
{
    const sim_sys_t *s = in->sys;
    double dx[AENL_SIM_MAX_X], rreq[AENL_SIM_MAX_Q];
    switch (e->kind)
    {
        case EV_POS:
            return e->sign * (x[e->q] - e->bound);
        case EV_VEL:
            return e->sign * x[s->nq + e->q];
        case EV_SLIP_DN:
            rhs(in, &in->mode, t, x, dx, rreq);
            return rreq[e->q] - aenl_sim_law_eval(&s->law[e->q], x[e->q], -1);
        case EV_SLIP_UP:
        default:
            rhs(in, &in->mode, t, x, dx, rreq);
            return aenl_sim_law_eval(&s->law[e->q], x[e->q], +1) - rreq[e->q];
    }
}

/* State on the dense output of the last step at θ in [0, 1]. */
static void dense(const integ_t *in, double theta, double *y)
{
    int j;
    if (!(theta < 1.0))
    {
        memcpy(y, in->x1, sizeof(double) * (size_t)in->sys->nx);
        return;
    }
    for (j = 0; j < in->sys->nx; ++j)
    {
        y[j] =
            in->x0[j] +
            in->hs * theta *
                (in->Q[0][j] + theta * (in->Q[1][j] + theta * (in->Q[2][j] + theta * in->Q[3][j])));
    }
}

/* Switching function j on the dense output, with the arming hold. */
static double ev_dense(integ_t *in, int j, double theta)
{
    double y[AENL_SIM_MAX_X];
    const double t = in->t0 + theta * in->hs;
    if (in->armed[j] && t < in->t_arm_end)
    {
        return DBL_MIN;
    }
    dense(in, theta, y);
    return ev_value(in, &in->ev[j], t, y);
}

/* Earliest crossing of function j in the step, as θ; 2 if none. Illinois method. */
static double locate(integ_t *in, int j)
{
    const int n_sub = 4;
    double a = 0.0, fa = DBL_MIN, b = 1.0, fb;
    double tol;
    int m, side = 0, it;
    for (m = 1; m <= n_sub; ++m)
    {
        const double th = (double)m / (double)n_sub;
        fb = ev_dense(in, j, th);
        if (!(fb > 0.0))
        {
            b = th;
            break;
        }
        a = th;
        fa = fb;
    }
    if (m > n_sub)
    {
        return 2.0;
    }
    /* An armed function's value at a is fake: restart the bracket at the end of the hold. */
    if (in->armed[j] && in->t0 + a * in->hs < in->t_arm_end)
    {
        a = (in->t_arm_end - in->t0) / in->hs;
        if (!(a < b))
        {
            return b;
        }
        fa = ev_dense(in, j, a);
        if (!(fa > 0.0))
        {
            return a;
        }
    }
    tol = 4.0 * DBL_EPSILON * (1.0 + fabs(in->t0) / in->hs);
    for (it = 0; it < 200 && b - a > tol; ++it)
    {
        double c = b - fb * (b - a) / (fb - fa), fc;
        if (!(c > a && c < b))
        {
            c = 0.5 * (a + b);
        }
        fc = ev_dense(in, j, c);
        if (!(fc > 0.0))
        {
            b = c;
            fb = fc;
            if (!(fc < 0.0))
            {
                break; /* exact zero */
            }
            if (side == -1)
            {
                fa *= 0.5;
            }
            side = -1;
        }
        else
        {
            a = c;
            fa = fc;
            if (side == 1)
            {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    return b;
}

static void arm(integ_t *in)
{
    int j;
    in->n_ev = list_events(in->sys, &in->mode, in->ev);
    in->t_arm_end = in->t + in->arm_window;
    for (j = 0; j < in->n_ev; ++j)
    {
        const double g = ev_value(in, &in->ev[j], in->t, in->x);
        double tol = 0.0;
        if (in->ev[j].kind == EV_SLIP_DN || in->ev[j].kind == EV_SLIP_UP)
        {
            const double xq = in->x[in->ev[j].q];
            tol = 1e-13 * (1.0 + fabs(aenl_sim_law_eval(&in->sys->law[in->ev[j].q], xq, -1)) +
                           fabs(aenl_sim_law_eval(&in->sys->law[in->ev[j].q], xq, 1)));
        }
        in->armed[j] = (g <= tol) ? 1 : 0;
    }
}

/* Branch for the law of q after a reversal or a slip towards dir (hysteresis follows the branch
 * of its direction of motion). */
static void set_dir(const sim_sys_t *s, sim_mode_t *mode, int q, int dir, const double *x)
{
    mode->b[q].dir = dir;
    mode->b[q].stuck = 0;
    mode->b[q].region = sim_law_region(&s->law[q], dir, x[q], dir);
}

/* Decide the new mode at a located event (arming and grazing safeguards, see aenl_sim.h). */
static void transition(integ_t *in, const ev_id_t *e, double *x)
{
    const sim_sys_t *s = in->sys;
    const int q = e->q, nq = s->nq;
    double dx[AENL_SIM_MAX_X];
    sim_mode_t trial;
    ++in->info.n_events;
    switch (e->kind)
    {
        case EV_POS:
        {
            double v, a;
            x[q] = e->bound; /* snap onto the surface */
            v = e->sign * x[nq + q];
            rhs(in, &in->mode, in->t, x, dx, NULL);
            a = e->sign * dx[nq + q]; /* R is continuous here: same on both sides */
            if ((v < 0.0 && !(a > 0.0 && -2.0 * v / a < in->arm_window)) || (!(v < 0.0) && a < 0.0))
            {
                in->mode.b[q].region = e->new_region;
            }
            else
            {
                ++in->info.n_grazing;
            }
            break;
        }
        case EV_VEL:
        {
            const int sdir = in->mode.b[q].dir;
            double a_new, a_old;
            x[nq + q] = 0.0;
            trial = in->mode;
            set_dir(s, &trial, q, -sdir, x);
            rhs(in, &trial, in->t, x, dx, NULL);
            a_new = dx[nq + q];
            if ((double)(-sdir) * a_new > 0.0)
            {
                in->mode = trial;
                break;
            }
            rhs(in, &in->mode, in->t, x, dx, NULL);
            a_old = dx[nq + q];
            if ((double)sdir * a_old > 0.0)
            {
                ++in->info.n_grazing;
                break;
            }
            in->mode.b[q].stuck = 1; /* neither direction is consistent: Filippov sliding */
            ++in->info.n_stuck;
            break;
        }
        case EV_SLIP_DN:
            set_dir(s, &in->mode, q, -1, x);
            ++in->info.n_unstick;
            break;
        case EV_SLIP_UP:
        default:
            set_dir(s, &in->mode, q, +1, x);
            ++in->info.n_unstick;
            break;
    }
}

static void emit(integ_t *in, size_t k, const double *x)
{
    aenl_sim_result_t *r = in->res;
    int c;
    r->t[k] = (double)k * in->dt;
    for (c = 0; c < in->sys->n_out; ++c)
    {
        r->y[(size_t)c * r->n_samples + k] = x[in->sys->out_q[c]];
    }
}

/* Output every grid point in (t0, t0 + θ_end h] from the dense output of the last step. */
static void emit_dense(integ_t *in, double theta_end)
{
    const double t_end = in->t0 + theta_end * in->hs;
    double y[AENL_SIM_MAX_X];
    while (in->next_k < in->res->n_samples)
    {
        const double tk = (double)in->next_k * in->dt;
        double th;
        if (tk > t_end)
        {
            break;
        }
        th = (tk - in->t0) / in->hs;
        if (th > theta_end)
        {
            th = theta_end;
        }
        dense(in, th, y);
        emit(in, in->next_k, y);
        ++in->next_k;
    }
}

static double err_norm(const integ_t *in, const double *e, const double *y0, const double *y1)
{
    double acc = 0.0;
    int j;
    for (j = 0; j < in->sys->nx; ++j)
    {
        const double sc = in->atol + in->rtol * fmax(fabs(y0[j]), fabs(y1[j]));
        const double r = e[j] / sc;
        acc += r * r;
    }
    return sqrt(acc / (double)in->sys->nx);
}

/* Integrate from in->t to t_end (the input u is constant on this interval). */
static aenl_status_t integrate_to(integ_t *in, double t_end, aenl_err_t *err)
{
    const int nx = in->sys->nx;
    double y[AENL_SIM_MAX_X], e[AENL_SIM_MAX_X];
    int i, j, s;
    rhs(in, &in->mode, in->t, in->x, in->f, NULL);
    arm(in);
    while (in->t < t_end)
    {
        double h = in->h, er, fac, best = 2.0;
        int last = 0, jbest = -1;
        if (in->t + h >= t_end || in->t + 1.01 * h >= t_end)
        {
            h = t_end - in->t;
            last = 1;
        }
        if (!(h > 1e-14 * fmax(1.0, fabs(in->t))))
        {
            if (last)
            {
                /* A sliver shorter than the resolution of t: a single Euler step. */
                for (j = 0; j < nx; ++j)
                {
                    in->x[j] += h * in->f[j];
                }
                in->t = t_end;
                while (in->next_k < in->res->n_samples && (double)in->next_k * in->dt <= t_end)
                {
                    emit(in, in->next_k, in->x);
                    ++in->next_k;
                }
                break;
            }
            aenl_err_set(err, "step size underflow at t = %.17g", in->t);
            return AENL_E_NUMERIC;
        }
        memcpy(in->K[0], in->f, sizeof(double) * (size_t)nx);
        for (s = 1; s < 7; ++s)
        {
            for (j = 0; j < nx; ++j)
            {
                double acc = 0.0;
                for (i = 0; i < s; ++i)
                {
                    acc += DP_A[s][i] * in->K[i][j];
                }
                y[j] = in->x[j] + h * acc;
            }
            rhs(in, &in->mode, in->t + DP_C[s] * h, y, in->K[s], NULL);
        }
        /* y now holds the 5th-order solution (row 6 of DP_A is B). */
        for (j = 0; j < nx; ++j)
        {
            double acc = 0.0;
            for (i = 0; i < 7; ++i)
            {
                acc += DP_E[i] * in->K[i][j];
            }
            e[j] = h * acc;
        }
        er = err_norm(in, e, in->x, y);
        if (!(er <= 1.0))
        {
            ++in->info.n_rejected;
            fac = isfinite(er) ? fmax(0.2, 0.9 * pow(er, -0.2)) : 0.1;
            in->h = h * fac;
            continue;
        }
        ++in->info.n_steps;
        if (in->max_steps > 0ul && in->info.n_steps > in->max_steps)
        {
            aenl_err_set(err, "more than %lu integration steps by t = %.17g: too stiff to run",
                         in->max_steps, in->t);
            return AENL_E_NUMERIC;
        }
        for (j = 0; j < nx; ++j)
        {
            if (!isfinite(y[j]))
            {
                aenl_err_set(err, "non-finite state at t = %.17g", in->t + h);
                return AENL_E_NUMERIC;
            }
        }
        if (out_of_bound(in->sys, in->res, in->bound, y, in->t + h, err))
        {
            return AENL_E_NUMERIC;
        }
        /* Dense output of the accepted step. */
        in->t0 = in->t;
        in->hs = h;
        memcpy(in->x0, in->x, sizeof(double) * (size_t)nx);
        memcpy(in->x1, y, sizeof(double) * (size_t)nx);
        for (int p = 0; p < 4; ++p)
        {
            for (j = 0; j < nx; ++j)
            {
                double acc = 0.0;
                for (i = 0; i < 7; ++i)
                {
                    acc += DP_P[i][p] * in->K[i][j];
                }
                in->Q[p][j] = acc;
            }
        }
        fac = (er > 0.0) ? fmin(10.0, fmax(0.2, 0.9 * pow(er, -0.2))) : 10.0;
        in->h = h * fac;
        for (j = 0; j < in->n_ev; ++j)
        {
            const double th = locate(in, j);
            if (th < best)
            {
                best = th;
                jbest = j;
            }
        }
        if (jbest < 0)
        {
            emit_dense(in, 1.0);
            const double tn = last ? t_end : in->t + h;
            in->t = tn;
            memcpy(in->x, y, sizeof(double) * (size_t)nx);
            memcpy(in->f, in->K[6], sizeof(double) * (size_t)nx);
            continue;
        }
        /* Event: cut the step at the root, change branch, restart. */
        {
            ev_id_t ev = in->ev[jbest];
            const double te = (best < 1.0) ? in->t0 + best * h : (last ? t_end : in->t0 + h);
            emit_dense(in, best);
            dense(in, best, y);
            in->t = te;
            if (te - in->t_burst > 1e-3 * in->dt)
            {
                in->t_burst = te;
                in->n_burst = 0;
            }
            if (++in->n_burst > 2000)
            {
                aenl_err_set(err, "event chatter at t = %.17g (more than 2000 events in %g)", te,
                             1e-3 * in->dt);
                return AENL_E_NUMERIC;
            }
            transition(in, &ev, y);
            memcpy(in->x, y, sizeof(double) * (size_t)nx);
            rhs(in, &in->mode, in->t, in->x, in->f, NULL);
            arm(in);
        }
    }
    return AENL_OK;
}

/* ---- common setup ------------------------------------------------------------------------- */

static aenl_status_t alloc_result(const sim_sys_t *s, const aenl_sim_run_t *run,
                                  aenl_sim_result_t *res, aenl_err_t *err)
{
    size_t n = (size_t)floor(run->duration / run->dt + 1e-9) + 1;
    memset(res, 0, sizeof(*res));
    res->n_samples = n;
    res->n_channels = (size_t)s->n_out;
    res->names[0] = "t";
    if (s->type == AENL_SIM_AIRFOIL2DOF)
    {
        res->names[1] = "alpha";
        res->names[2] = "xi";
    }
    else
    {
        res->names[1] = "h";
        res->names[2] = "alpha";
        res->names[3] = "beta";
    }
    res->t = malloc(n * sizeof(double));
    res->y = malloc(n * res->n_channels * sizeof(double));
    if (run->force != AENL_SIM_FORCE_NONE)
    {
        res->u = malloc(n * sizeof(double));
        res->u_name = sim_force_name(run->force_dof);
    }
    if (res->t == NULL || res->y == NULL || (run->force != AENL_SIM_FORCE_NONE && res->u == NULL))
    {
        aenl_sim_result_free(res);
        aenl_err_set(err, "out of memory for %zu samples", n);
        return AENL_E_DIM;
    }
    return AENL_OK;
}

void aenl_sim_result_free(aenl_sim_result_t *res)
{
    if (res == NULL)
    {
        return;
    }
    free(res->t);
    free(res->y);
    free(res->u);
    memset(res, 0, sizeof(*res));
}

/* State index of the kicked DOF's displacement (0 without kicks). */
static int kick_state(const sim_sys_t *s, const aenl_sim_run_t *run)
{
    for (int i = 0; run->kicks && i < s->nq; ++i)
    {
        if (s->dof[i] == (int)run->kick_dof)
        {
            return i;
        }
    }
    return 0;
}

static void initial_state(const aenl_sim_model_t *model, const sim_sys_t *s, double *x)
{
    int i;
    memset(x, 0, sizeof(double) * AENL_SIM_MAX_X);
    for (i = 0; i < s->nq; ++i)
    {
        x[i] = model->x0[s->dof[i]];
        x[s->nq + i] = model->v0[s->dof[i]];
    }
}

/* Gust: the filter's output has std = intensity (see aenl_sim.h). */
typedef struct gust_gen
{
    aenl_rng_t rng;
    double sigma_u;
    int on;
    double e, hold; /* exp(-dt/T); dt/T */
    double g1, g2;  /* the held input's weights on the states over one interval (Dryden) */
} gust_gen_t;

/* 1 - exp(-h) (1 + h), the second lag's step response after h time constants, without the
 * cancellation of the direct form for small h. */
static double second_lag_step(double h)
{
    if (h >= 1.0)
    {
        return 1.0 - exp(-h) * (1.0 + h);
    }
    double term = 0.5 * h * h, sum = 0.0;
    for (int k = 2; k < 40 && term > 1e-18 * sum; ++k)
    {
        sum += term;
        term *= h / (double)(k + 1);
    }
    return exp(-h) * sum;
}

/* Seed the generator and set the input's std so that the filter output has std `intensity`;
 * z[0..n) receives a draw from the filter's stationary distribution (state order as in x). */
static void gust_setup(gust_gen_t *g, const aenl_sim_run_t *run, int n, double T, double intensity,
                       double *z)
{
    memset(g, 0, sizeof(*g));
    g->on = 1;
    aenl_rng_seed(&g->rng, run->turb_seed);
    const double h = run->dt / T, e = exp(-h);
    g->e = e;
    g->hold = h;
    if (n == 1)
    {
        g->sigma_u = intensity * sqrt((1.0 + e) / (1.0 - e));
        z[0] = intensity * aenl_rng_gauss(&g->rng);
        return;
    }
    /* Dryden: z' = A z + b u, A = [[-1, 0], [1, -1]] / T, b = [1, 0]' / T; over one held
     * interval z <- Phi z + gam u with Phi = e [[1, 0], [h, 1]], gam = [1 - e, 1 - e (1 + h)]'.
     * Stationary covariance per unit input variance, P = Phi P Phi' + gam gam', solved in
     * closed form (lower-triangular Phi), then scaled so that var(sqrt3 z1 + (1 - sqrt3) z2) is
     * the intensity squared. */
    g->g1 = -expm1(-h);
    g->g2 = second_lag_step(h);
    const double e2 = e * e, den = -expm1(-2.0 * h);
    const double p11 = g->g1 * g->g1 / den;
    const double p12 = (e2 * h * p11 + g->g1 * g->g2) / den;
    const double p22 = (e2 * (h * h * p11 + 2.0 * h * p12) + g->g2 * g->g2) / den;
    const double c1 = SIM_SQRT3, c2 = 1.0 - SIM_SQRT3;
    const double var_g = c1 * c1 * p11 + 2.0 * c1 * c2 * p12 + c2 * c2 * p22;
    g->sigma_u = intensity / sqrt(var_g);
    const double l11 = sqrt(p11), l21 = p12 / l11, l22 = sqrt(fmax(p22 - l21 * l21, 0.0));
    const double n1 = aenl_rng_gauss(&g->rng), n2 = aenl_rng_gauss(&g->rng);
    z[0] = g->sigma_u * l11 * n1;
    z[1] = g->sigma_u * (l21 * n1 + l22 * n2);
}

static void gust_init(gust_gen_t *g, const aenl_sim_run_t *run, const sim_sys_t *s, double *x)
{
    memset(g, 0, sizeof(*g));
    if (!s->gust)
    {
        return;
    }
    gust_setup(g, run, s->gust, s->gust_T, run->turb_intensity, &x[s->nx - s->gust]);
}

static double gust_next(gust_gen_t *g)
{
    return g->on ? g->sigma_u * aenl_rng_gauss(&g->rng) : 0.0;
}

aenl_status_t aenl_sim_gust_series(const aenl_sim_run_t *run, double T, size_t n, double *w,
                                   aenl_err_t *err)
{
    if (run == NULL || w == NULL || n == 0 || !isfinite(run->dt) || !(run->dt > 0.0) ||
        !isfinite(T) || !(T > 0.0))
    {
        aenl_err_set(err, "gust series: need a run, n > 0 and finite dt > 0, T > 0");
        return AENL_E_ARG;
    }
    gust_gen_t g;
    double z[2] = {0.0, 0.0};
    const int ns = sim_gust_order(run->turb_spectrum);
    gust_setup(&g, run, ns, T, 1.0, z);
    for (size_t k = 0; k < n; ++k)
    {
        w[k] = ns == 1 ? z[0] : sim_dryden_output(z[0], z[1]);
        const double u = gust_next(&g);
        if (ns == 1)
        {
            z[0] = g.e * z[0] + (1.0 - g.e) * u;
        }
        else
        {
            const double z1 = z[0];
            z[0] = g.e * z1 + g.g1 * u;
            z[1] = g.e * (g.hold * z1 + z[1]) + g.g2 * u;
        }
    }
    return AENL_OK;
}

static void add_noise(aenl_sim_result_t *res, const aenl_sim_run_t *run)
{
    aenl_rng_t rng;
    size_t c, k;
    const size_t n = res->n_samples;
    if (!(run->snr > 0.0))
    {
        return;
    }
    aenl_rng_seed(&rng, run->noise_seed);
    for (c = 0; c < res->n_channels; ++c)
    {
        double *y = res->y + c * n, mean = 0.0, var = 0.0, sd;
        for (k = 0; k < n; ++k)
        {
            mean += y[k];
        }
        mean /= (double)n;
        for (k = 0; k < n; ++k)
        {
            var += (y[k] - mean) * (y[k] - mean);
        }
        sd = sqrt(var / (double)n) / run->snr;
        for (k = 0; k < n; ++k)
        {
            y[k] += sd * aenl_rng_gauss(&rng);
        }
    }
}

/* The mode of state x at in->t from scratch: at the start and after a kick (a hysteresis DOF
 * takes the direction of its rate; at rest the direction its branch would move it, or sticks). */
static void initial_mode(integ_t *in, const double *x)
{
    const sim_sys_t *s = in->sys;
    double dx[AENL_SIM_MAX_X];
    int q;
    memset(&in->mode, 0, sizeof(in->mode));
    for (q = 0; q < s->nq; ++q)
    {
        const double v = x[s->nq + q];
        const int mv = v > 0.0 ? 1 : (v < 0.0 ? -1 : 0);
        in->mode.b[q].dir = 1;
        in->mode.b[q].region = sim_law_region(&s->law[q], 1, x[q], mv);
    }
    for (q = 0; q < s->nq; ++q)
    {
        const double v = x[s->nq + q];
        if (s->law[q].kind != AENL_SIM_LAW_HYSTERESIS)
        {
            continue;
        }
        if (v > 0.0 || v < 0.0)
        {
            set_dir(s, &in->mode, q, v > 0.0 ? 1 : -1, x);
            continue;
        }
        /* At rest: the direction the branch itself would move it, or stuck. */
        set_dir(s, &in->mode, q, 1, x);
        rhs(in, &in->mode, in->t, x, dx, NULL);
        if (dx[s->nq + q] > 0.0)
        {
            continue;
        }
        set_dir(s, &in->mode, q, -1, x);
        rhs(in, &in->mode, in->t, x, dx, NULL);
        if (dx[s->nq + q] < 0.0)
        {
            continue;
        }
        in->mode.b[q].stuck = 1;
        ++in->info.n_stuck;
    }
}

/* The run's forced excitation, attached to sys and sampled into res->u (*out: NULL without
 * one; the caller frees it once the integration is over). */
static aenl_status_t force_setup(sim_sys_t *sys, const aenl_sim_run_t *run, aenl_sim_result_t *res,
                                 sim_force_t **out, aenl_err_t *err)
{
    *out = NULL;
    if (run->force == AENL_SIM_FORCE_NONE)
    {
        return AENL_OK;
    }
    sim_force_t *f = calloc(1, sizeof(*f));
    if (f == NULL)
    {
        aenl_sim_result_free(res);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    sim_force_init(f, run);
    sim_force_attach(sys, f, run);
    for (size_t k = 0; k < res->n_samples; ++k)
    {
        res->u[k] = sim_force_eval(f, (double)k * run->dt);
    }
    *out = f;
    return AENL_OK;
}

aenl_status_t aenl_sim_simulate(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                aenl_sim_result_t *res, aenl_err_t *err)
{
    sim_force_t *force = NULL;
    sim_sys_t sys;
    integ_t *in;
    gust_gen_t gg;
    aenl_status_t st;
    size_t n;
    if (res == NULL)
    {
        aenl_err_set(err, "NULL result");
        return AENL_E_ARG;
    }
    memset(res, 0, sizeof(*res));
    if (run == NULL)
    {
        aenl_err_set(err, "NULL run");
        return AENL_E_ARG;
    }
    if ((st = aenl_sim_validate(model, run, err)) != AENL_OK ||
        (st = sim_sys_build(model, aenl_sim_velocity(model), sim_gust_states(run), run->turb_length,
                            &sys, err)) != AENL_OK ||
        (st = alloc_result(&sys, run, res, err)) != AENL_OK ||
        (st = force_setup(&sys, run, res, &force, err)) != AENL_OK)
    {
        return st;
    }
    in = calloc(1, sizeof(*in));
    if (in == NULL)
    {
        free(force);
        aenl_sim_result_free(res);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    in->sys = &sys;
    in->rtol = run->rtol;
    in->atol = run->atol;
    in->res = res;
    in->dt = run->dt;
    in->bound = run->bound;
    in->max_steps = run->max_steps_per_sample > 0.0
                        ? (unsigned long)ceil(run->max_steps_per_sample * (double)res->n_samples)
                        : 0ul;
    in->arm_window = 1e-7 * run->dt;
    in->t_burst = -HUGE_VAL;
    n = res->n_samples;
    initial_state(model, &sys, in->x);
    gust_init(&gg, run, &sys, in->x);
    const size_t kick_steps = sim_kick_steps(run);
    const int kick_q = kick_state(&sys, run);
    sim_kick_gen_t kg;
    if (kick_steps > 0)
    {
        sim_kick_init(&kg, run);
        in->x[sys.nq + kick_q] += sim_kick_next(&kg); /* the first kick, at t = 0 */
    }
    initial_mode(in, in->x);
    emit(in, 0, in->x);
    in->next_k = 1;
    {
        /* Initial step (Hairer & Wanner's d0/d1 heuristic). */
        double f0[AENL_SIM_MAX_X], d0 = 0.0, d1 = 0.0;
        int j;
        in->u = 0.0;
        rhs(in, &in->mode, 0.0, in->x, f0, NULL);
        for (j = 0; j < sys.nx; ++j)
        {
            const double sc = in->atol + in->rtol * fabs(in->x[j]);
            d0 += (in->x[j] / sc) * (in->x[j] / sc);
            d1 += (f0[j] / sc) * (f0[j] / sc);
        }
        in->h = (d0 < 1e-10 || d1 < 1e-10) ? 1e-6 * run->dt : 0.01 * sqrt(d0 / d1);
        in->h = fmin(in->h, run->dt);
    }
    st = AENL_OK;
    if (sys.gust)
    {
        for (size_t k = 0; k + 1 < n && st == AENL_OK; ++k)
        {
            in->u = gust_next(&gg);
            st = integrate_to(in, (double)(k + 1) * run->dt, err);
        }
    }
    else if (kick_steps > 0)
    {
        for (size_t k = kick_steps; st == AENL_OK; k += kick_steps)
        {
            st = integrate_to(in, (double)(k < n - 1 ? k : n - 1) * run->dt, err);
            if (k >= n - 1)
            {
                break;
            }
            in->x[sys.nq + kick_q] += sim_kick_next(&kg);
            initial_mode(in, in->x);
        }
    }
    else
    {
        st = integrate_to(in, (double)(n - 1) * run->dt, err);
    }
    if (st == AENL_OK && in->next_k < n)
    {
        /* The final grid point coincides with the final time. */
        emit(in, n - 1, in->x);
    }
    res->info = in->info;
    free(in);
    free(force);
    if (st != AENL_OK)
    {
        aenl_sim_result_free(res);
        return st;
    }
    add_noise(res, run);
    return AENL_OK;
}

/* ---- naive fixed-step RK4 ----------------------------------------------------------------- */

static void naive_mode(const sim_sys_t *s, const double *x, sim_mode_t *mode)
{
    int q;
    for (q = 0; q < s->nq; ++q)
    {
        const double v = x[s->nq + q];
        if (s->law[q].kind == AENL_SIM_LAW_HYSTERESIS)
        {
            if (v > 0.0)
            {
                mode->b[q].dir = 1;
            }
            else if (v < 0.0)
            {
                mode->b[q].dir = -1;
            }
        }
        mode->b[q].stuck = 0;
        mode->b[q].region = sim_law_region(&s->law[q], mode->b[q].dir, x[q], 0);
    }
}

#define RK4_MAX_STEPS 1e9 /* a bound on the work, far above any run the option is for */

aenl_status_t aenl_sim_simulate_rk4(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                    double h, aenl_sim_result_t *res, aenl_err_t *err)
{
    sim_force_t *force = NULL;
    sim_sys_t sys;
    gust_gen_t gg;
    sim_mode_t mode;
    aenl_status_t st;
    double x[AENL_SIM_MAX_X], k1[AENL_SIM_MAX_X], k2[AENL_SIM_MAX_X], k3[AENL_SIM_MAX_X],
        k4[AENL_SIM_MAX_X], y[AENL_SIM_MAX_X];
    size_t n, k, m, n_sub;
    int j, c;
    if (res == NULL)
    {
        aenl_err_set(err, "NULL result");
        return AENL_E_ARG;
    }
    memset(res, 0, sizeof(*res));
    if (run == NULL || !isfinite(h) || !(h > 0.0))
    {
        aenl_err_set(err, "RK4 step must be > 0");
        return AENL_E_ARG;
    }
    if ((st = aenl_sim_validate(model, run, err)) != AENL_OK)
    {
        return st;
    }
    /* the step divides the sample step into whole substeps; a step above it would silently be
     * the sample step, and a run of more steps than RK4_MAX_STEPS would not end in a usable time */
    const double subs = ceil(run->dt / h - 1e-9);
    const double steps = subs * (floor(run->duration / run->dt + 1e-9) + 1.0);
    if (h > run->dt * (1.0 + 1e-12))
    {
        aenl_err_set(err,
                     "RK4 step %g is larger than the sample step %g: give at most the sample step",
                     h, run->dt);
        return AENL_E_ARG;
    }
    if (!(steps <= RK4_MAX_STEPS))
    {
        aenl_err_set(err,
                     "RK4 step %g makes %.3g steps in all (%.3g a sample), more than %.0e: give a "
                     "larger step",
                     h, steps, subs, RK4_MAX_STEPS);
        return AENL_E_ARG;
    }
    if ((st = sim_sys_build(model, aenl_sim_velocity(model), sim_gust_states(run), run->turb_length,
                            &sys, err)) != AENL_OK ||
        (st = alloc_result(&sys, run, res, err)) != AENL_OK ||
        (st = force_setup(&sys, run, res, &force, err)) != AENL_OK)
    {
        return st;
    }
    n = res->n_samples;
    n_sub = (size_t)subs;
    if (n_sub < 1)
    {
        n_sub = 1;
    }
    h = run->dt / (double)n_sub;
    initial_state(model, &sys, x);
    memset(y, 0, sizeof(y)); /* stages fill y[0..nx); the rest stays defined */
    gust_init(&gg, run, &sys, x);
    const size_t kick_steps = sim_kick_steps(run);
    const int kick_q = kick_state(&sys, run);
    sim_kick_gen_t kg;
    if (kick_steps > 0)
    {
        sim_kick_init(&kg, run);
    }
    memset(&mode, 0, sizeof(mode));
    for (j = 0; j < sys.nq; ++j)
    {
        mode.b[j].dir = x[sys.nq + j] < 0.0 ? -1 : 1;
    }
    for (k = 0; k < n; ++k)
    {
        double u;
        res->t[k] = (double)k * run->dt;
        for (c = 0; c < sys.n_out; ++c)
        {
            res->y[(size_t)c * n + k] = x[sys.out_q[c]];
        }
        if (k + 1 == n)
        {
            break;
        }
        if (kick_steps > 0 && k % kick_steps == 0)
        {
            x[sys.nq + kick_q] += sim_kick_next(&kg);
        }
        u = gust_next(&gg);
        for (m = 0; m < n_sub; ++m)
        {
            const double t = (double)k * run->dt + (double)m * h;
            naive_mode(&sys, x, &mode);
            sim_rhs(&sys, &mode, t, x, u, k1, NULL);
            for (j = 0; j < sys.nx; ++j)
            {
                y[j] = x[j] + 0.5 * h * k1[j];
            }
            naive_mode(&sys, y, &mode);
            sim_rhs(&sys, &mode, t + 0.5 * h, y, u, k2, NULL);
            for (j = 0; j < sys.nx; ++j)
            {
                y[j] = x[j] + 0.5 * h * k2[j];
            }
            naive_mode(&sys, y, &mode);
            sim_rhs(&sys, &mode, t + 0.5 * h, y, u, k3, NULL);
            for (j = 0; j < sys.nx; ++j)
            {
                y[j] = x[j] + h * k3[j];
            }
            naive_mode(&sys, y, &mode);
            sim_rhs(&sys, &mode, t + h, y, u, k4, NULL);
            for (j = 0; j < sys.nx; ++j)
            {
                x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        res->info.n_steps += n_sub;
        res->info.n_rhs += 4 * n_sub;
        for (j = 0; j < sys.nx; ++j)
        {
            if (!isfinite(x[j]))
            {
                free(force);
                aenl_sim_result_free(res);
                aenl_err_set(err, "non-finite state at t = %.17g", (double)(k + 1) * run->dt);
                return AENL_E_NUMERIC;
            }
        }
        if (out_of_bound(&sys, res, run->bound, x, (double)(k + 1) * run->dt, err))
        {
            free(force);
            aenl_sim_result_free(res);
            return AENL_E_NUMERIC;
        }
    }
    free(force);
    add_noise(res, run);
    return AENL_OK;
}
