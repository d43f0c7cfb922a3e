/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_fit.c
 * @brief `aenl fit`: EM identification of the switching state-space model (the paper's section 4;
 *        docs/fit.md).
 */
#define _POSIX_C_SOURCE 200809L

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_em.h"
#include "aenl_tools/aenl_json.h"

static const char *const k_cmd = "fit";

static void help(void)
{
    printf("usage: aenl fit DATA.csv --thresholds CH:T1[,T2,...] [--states N] [--iter K]\n"
           "                [--channels A,B] [--freeze A,b,Q,R,x0] [--free-c] [--refine]\n"
           "                [--modes-from-data] [--tol REL] [--init arx|subspace] [--plain-em]\n"
           "                [--bootstrap N] [--seed S] [--json] [-o model.ini]\n"
           "                [--c-header model.h] [--name IDENT] [--time COL]\n\n"
           "Identifies x_k = A_s x_{k-1} + b_s + v, y_k = C x_k + w by EM (Kalman filter + RTS\n"
           "smoother, closed-form M-step), the mode s chosen by the thresholds on channel CH (the\n"
           "seed paper's freeplay: --thresholds alpha:ALPHA_F,ALPHA_F+DELTA). Every data column\n"
           "other than the time column is an output (or those of --channels, CH included).\n"
           "The sample step comes from the time column (t, time, tau or timestamp, or the one\n"
           "--time COL names; uniform).\n"
           "Frequencies are |Im s|/(2 pi) with s = ln(lambda)/dt, in cycles per unit of the time\n"
           "column (Hz for seconds); damping = -Re s/|s|.\n"
           "Defaults: 4 states per output, 50 iterations, C = [I 0] fixed, thresholds as given.\n"
           "The iterations are SQUAREM-accelerated EM (--plain-em: plain EM); the start is the\n"
           "delay-embedding regression (--init subspace: covariance-driven stochastic subspace).\n"
           "A lightly excited, heavily damped mode needs hundreds of iterations: check that the\n"
           "log-likelihood has levelled off (--json loglik, or --tol).\n"
           "Each oscillatory pair comes with its Cramer-Rao floor (the spread no unbiased\n"
           "estimate from the mode's samples beats); --bootstrap N adds standard errors and\n"
           "biases from N records simulated from the fit with its noise and fitted again (N\n"
           "times the fit's cost; --seed S, default 1).\n"
           "--json prints {\"modes\": [...], \"C\", \"R\", \"loglik\": [...]}, modes in ascending\n"
           "order of their threshold interval. --c-header writes a const aenl_skf_model_t.\n");
}

static int split_list(char *s, char **items, int cap)
{
    int n = 0;
    for (char *tok = strtok(s, ","); tok != NULL; tok = strtok(NULL, ","))
    {
        if (n == cap)
        {
            return -1;
        }
        items[n++] = tok;
    }
    return n;
}

static cJSON *json_matrix(const double *a, size_t n, size_t m)
{
    cJSON *rows = cJSON_CreateArray();
    for (size_t i = 0; i < n; ++i)
    {
        cJSON *row = cJSON_CreateArray();
        for (size_t j = 0; j < m; ++j)
        {
            cJSON_AddItemToArray(row, cJSON_CreateNumber(a[i * m + j]));
        }
        cJSON_AddItemToArray(rows, row);
    }
    return rows;
}

static cJSON *json_vector(const double *a, size_t n)
{
    cJSON *v = cJSON_CreateArray();
    for (size_t i = 0; i < n; ++i)
    {
        cJSON_AddItemToArray(v, cJSON_CreateNumber(a[i]));
    }
    return v;
}

/* Default C identifier: the header's file stem, non-identifier characters as '_'. */
static void ident_from_path(const char *path, char *out, size_t cap)
{
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    size_t k = 0;
    if (!((base[0] >= 'a' && base[0] <= 'z') || (base[0] >= 'A' && base[0] <= 'Z')))
    {
        out[k++] = 'm';
    }
    for (const char *p = base; *p && *p != '.' && k + 1 < cap; ++p)
    {
        const int ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') ||
                       (*p >= '0' && *p <= '9') || *p == '_';
        out[k++] = *p;
        if (!ok)
        {
            out[k - 1] = '_';
        }
    }
    out[k] = '\0';
}

typedef struct
{
    const char *data, *thr, *channels, *freeze, *out_ini, *out_h, *name, *time_column;
    long states, iter, bootstrap, seed;
    int json, refine, free_c, modes_from_data, plain_em, init;
    double tol;
} fit_args_t;

/* Where the value of option `o` is kept as given; NULL when `o` is not such an option. */
static const char **text_option(const char *o, fit_args_t *a)
{
    if (strcmp(o, "--thresholds") == 0)
    {
        return &a->thr;
    }
    if (strcmp(o, "--channels") == 0)
    {
        return &a->channels;
    }
    if (strcmp(o, "--freeze") == 0)
    {
        return &a->freeze;
    }
    if (strcmp(o, "-o") == 0)
    {
        return &a->out_ini;
    }
    if (strcmp(o, "--c-header") == 0)
    {
        return &a->out_h;
    }
    if (strcmp(o, "--name") == 0)
    {
        return &a->name;
    }
    if (strcmp(o, "--time") == 0)
    {
        return &a->time_column;
    }
    return NULL;
}

/* 1 for the options whose value parse_setting reads. */
static int is_setting(const char *o)
{
    return strcmp(o, "--states") == 0 || strcmp(o, "--iter") == 0 || strcmp(o, "--tol") == 0 ||
           strcmp(o, "--init") == 0 || strcmp(o, "--bootstrap") == 0 || strcmp(o, "--seed") == 0;
}

/* The value v of --init, --states, --iter, --bootstrap, --seed or --tol: 0, or -1 after printing
 * what is wrong. */
static int parse_setting(const char *o, const char *v, fit_args_t *a)
{
    if (strcmp(o, "--init") == 0)
    {
        if (strcmp(v, "arx") == 0)
        {
            a->init = AENL_EM_INIT_ARX;
        }
        else if (strcmp(v, "subspace") == 0)
        {
            a->init = AENL_EM_INIT_SUBSPACE;
        }
        else
        {
            aenl_cli_error(k_cmd, "--init: '%s' is not arx or subspace", v);
            return -1;
        }
    }
    else if (strcmp(o, "--states") == 0)
    {
        if (aenl_cli_parse_long(k_cmd, "--states", v, 1, AENL_EM_MAX_X, &a->states) != 0)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--iter") == 0)
    {
        if (aenl_cli_parse_long(k_cmd, "--iter", v, 0, 100000, &a->iter) != 0)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--bootstrap") == 0)
    {
        if (aenl_cli_parse_long(k_cmd, "--bootstrap", v, 0, 10000, &a->bootstrap) != 0)
        {
            return -1;
        }
    }
    else if (strcmp(o, "--seed") == 0)
    {
        if (aenl_cli_parse_long(k_cmd, "--seed", v, 0, 2147483647L, &a->seed) != 0)
        {
            return -1;
        }
    }
    else if (aenl_cli_parse_double(k_cmd, "--tol", v, &a->tol) != 0 || a->tol < 0.0)
    {
        if (a->tol < 0.0)
        {
            aenl_cli_error(k_cmd, "--tol must be >= 0");
        }
        return -1;
    }
    return 0;
}

/* 1 when `o` is a flag (an option without a value), set in a; 0 otherwise. */
static int set_flag(const char *o, fit_args_t *a)
{
    int *flag = NULL;
    if (strcmp(o, "--json") == 0)
    {
        flag = &a->json;
    }
    else if (strcmp(o, "--refine") == 0)
    {
        flag = &a->refine;
    }
    else if (strcmp(o, "--free-c") == 0)
    {
        flag = &a->free_c;
    }
    else if (strcmp(o, "--modes-from-data") == 0)
    {
        flag = &a->modes_from_data;
    }
    else if (strcmp(o, "--plain-em") == 0)
    {
        flag = &a->plain_em;
    }
    if (flag != NULL)
    {
        *flag = 1;
    }
    return flag != NULL;
}

/* 0 to go on, 1 after the help, -1 after printing what is wrong. */
static int parse_args(int argc, char **argv, fit_args_t *a)
{
    memset(a, 0, sizeof(*a));
    a->iter = 50;
    a->seed = 1;
    for (int i = 1; i < argc; ++i)
    {
        const char *o = argv[i];
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0)
        {
            help();
            return 1;
        }
        const char **text = text_option(o, a);
        if (text != NULL || is_setting(o))
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || (text == NULL && parse_setting(o, v, a) != 0))
            {
                return -1;
            }
            if (text != NULL)
            {
                *text = v;
            }
        }
        else if (!set_flag(o, a) && aenl_cli_positional(k_cmd, o, &a->data, "data file") != 0)
        {
            return -1;
        }
    }
    aenl_cli_set_notes(!a->json);
    aenl_cli_set_time_column(a->time_column);
    if (a->data == NULL)
    {
        aenl_cli_error(k_cmd, "no data file (usage: aenl fit DATA.csv --thresholds CH:LO,HI)");
        return -1;
    }
    if (a->thr == NULL)
    {
        aenl_cli_error(k_cmd, "--thresholds CH:T1[,T2,...] is required");
        return -1;
    }
    return 0;
}

static int parse_freeze(const char *s, unsigned *flags)
{
    char buf[256];
    if (strlen(s) >= sizeof(buf))
    {
        aenl_cli_error(k_cmd, "--freeze: value too long");
        return -1;
    }
    memcpy(buf, s, strlen(s) + 1); /* fits: checked above */
    char *items[16];
    const int n = split_list(buf, items, 16);
    for (int i = 0; i < n; ++i)
    {
        static const char *const names[] = {"A", "b", "Q", "C", "R", "x0"};
        static const unsigned bits[] = {AENL_EM_FREEZE_A, AENL_EM_FREEZE_B, AENL_EM_FREEZE_Q,
                                        AENL_EM_FREEZE_C, AENL_EM_FREEZE_R, AENL_EM_FREEZE_X0};
        int found = 0;
        for (size_t k = 0; k < 6; ++k)
        {
            if (strcmp(items[i], names[k]) == 0)
            {
                *flags |= bits[k];
                found = 1;
            }
        }
        if (!found)
        {
            aenl_cli_error(k_cmd, "--freeze: '%s' is not one of A, b, Q, C, R, x0", items[i]);
            return -1;
        }
    }
    return n < 0 ? -1 : 0;
}

/* Output columns: --channels or every non-time column; *sw = index of the switching channel. */
static int pick_outputs(const aenl_table_t *t, const fit_args_t *a, const char *sw_name, long *cols,
                        size_t *n_out, size_t *sw)
{
    *n_out = 0;
    if (a->channels != NULL)
    {
        char buf[512];
        const int len = snprintf(buf, sizeof(buf), "%s", a->channels);
        if (len < 0 || (size_t)len >= sizeof(buf))
        {
            aenl_cli_error(k_cmd, "--channels: value too long (at most %zu characters)",
                           sizeof(buf) - 1);
            return -1;
        }
        char *items[AENL_EM_MAX_X];
        const int n = split_list(buf, items, AENL_EM_MAX_X);
        if (n <= 0)
        {
            aenl_cli_error(k_cmd, "--channels: '%s' is not a list of column names", a->channels);
            return -1;
        }
        for (int i = 0; i < n; ++i)
        {
            const long c = aenl_cli_pick_channel(k_cmd, t, a->data, items[i]);
            if (c < 0)
            {
                return -1;
            }
            for (size_t k = 0; k < *n_out; ++k)
            {
                if (cols[k] == c)
                {
                    aenl_cli_error(k_cmd, "--channels: '%s' is named twice", items[i]);
                    return -1;
                }
            }
            cols[(*n_out)++] = c;
        }
    }
    else
    {
        for (size_t c = 0; c < t->n_cols && *n_out < AENL_EM_MAX_X; ++c)
        {
            if (!aenl_cli_is_time_column(t->names[c]))
            {
                cols[(*n_out)++] = (long)c;
            }
        }
    }
    for (size_t i = 0; i < *n_out; ++i)
    {
        if (strcmp(t->names[cols[i]], sw_name) == 0)
        {
            *sw = i;
            return 0;
        }
    }
    if (aenl_cli_pick_channel(k_cmd, t, a->data, sw_name) >= 0)
    {
        aenl_cli_error(k_cmd, "--thresholds: channel '%s' is not among the outputs", sw_name);
    }
    return -1;
}

static int time_step(const aenl_table_t *t, const char *path, double *dt)
{
    long tc = -1;
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        if (aenl_cli_is_time_column(t->names[c]))
        {
            tc = (long)c;
            break;
        }
    }
    if (tc < 0)
    {
        aenl_cli_error(k_cmd, "%s: no time column (t, time, tau or timestamp)", path);
        return -1;
    }
    const double *tv = aenl_table_col(t, (size_t)tc);
    const size_t n = t->n_rows;
    *dt = (tv[n - 1] - tv[0]) / (double)(n - 1);
    if (!(*dt > 0.0) || !isfinite(*dt))
    {
        aenl_cli_error(k_cmd, "%s: the time column does not increase", path);
        return -1;
    }
    for (size_t k = 1; k < n; ++k)
    {
        const double d = tv[k] - tv[k - 1];
        if (!isfinite(d) || fabs(d - *dt) > 1e-6 * *dt + 1e-9 * fabs(tv[k]))
        {
            aenl_cli_error(k_cmd, "%s:%zu: the time step is not uniform (%g, expected %g)", path,
                           k + 2, d, *dt);
            return -1;
        }
    }
    return 0;
}

/* The bootstrap's figure q of pair i of mode s as a JSON array member; null where not
 * determined. */
static cJSON *boot_array(const double (*q)[AENL_EM_MAX_X / 2], size_t s, size_t n)
{
    cJSON *a = cJSON_CreateArray();
    for (size_t i = 0; i < n; ++i)
    {
        cJSON_AddItemToArray(a, aenl_json_num(q[s][i]));
    }
    return a;
}

static void print_json(const aenl_em_result_t *r, const aenl_em_boot_t *boot, const char *data,
                       const char *const *names)
{
    const aenl_em_model_t *m = &r->model;
    const size_t nx = m->n_x, nz = m->n_z;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "schema", "aenl-fit/2");
    cJSON_AddStringToObject(root, "aenl_version", AENL_VERSION);
    cJSON_AddStringToObject(root, "file", data);
    cJSON *ch = cJSON_CreateArray();
    for (size_t i = 0; i < nz; ++i)
    {
        cJSON_AddItemToArray(ch, cJSON_CreateString(names[i]));
    }
    cJSON_AddItemToObject(root, "channels", ch);
    cJSON_AddStringToObject(root, "switch_channel", names[m->switch_channel]);
    cJSON_AddItemToObject(root, "thresholds", json_vector(m->thresholds, m->n_modes - 1));
    cJSON_AddNumberToObject(root, "dt", m->dt);
    cJSON_AddNumberToObject(root, "states", (double)nx);
    cJSON *modes = cJSON_CreateArray();
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        cJSON *o = cJSON_CreateObject();
        cJSON *iv = cJSON_CreateArray();
        cJSON_AddItemToArray(iv, aenl_json_num(s == 0 ? -HUGE_VAL : m->thresholds[s - 1]));
        cJSON_AddItemToArray(iv, aenl_json_num(s + 1 == m->n_modes ? HUGE_VAL : m->thresholds[s]));
        cJSON_AddItemToObject(o, "interval", iv);
        cJSON_AddNumberToObject(o, "samples", (double)r->mode_count[s]);
        cJSON_AddItemToObject(o, "A", json_matrix(m->A + s * nx * nx, nx, nx));
        cJSON_AddItemToObject(o, "b", json_vector(m->b + s * nx, nx));
        cJSON_AddItemToObject(o, "Q", json_matrix(m->Q + s * nx * nx, nx, nx));
        aenl_em_eig_t e[AENL_EM_MAX_X];
        size_t n_eig = 0, n_osc = 0;
        aenl_err_t err;
        aenl_err_clear(&err);
        cJSON *eig = cJSON_CreateArray(), *fr = cJSON_CreateArray(), *dz = cJSON_CreateArray();
        cJSON *fr_floor = cJSON_CreateArray(), *dz_floor = cJSON_CreateArray();
        if (aenl_em_modal(m, s, e, &n_eig, &n_osc, &err) == AENL_OK)
        {
            for (size_t i = 0; i < n_eig; ++i)
            {
                const int pair = e[i].im > 0.0;
                for (int c = 0; c < (pair ? 2 : 1); ++c)
                {
                    cJSON *p = cJSON_CreateArray();
                    cJSON_AddItemToArray(p, cJSON_CreateNumber(e[i].re));
                    cJSON_AddItemToArray(p, cJSON_CreateNumber(c ? -e[i].im : e[i].im));
                    cJSON_AddItemToArray(eig, p);
                }
                if (pair)
                {
                    double sf = NAN;
                    double sz = NAN;
                    (void)aenl_em_mode_floor(e[i].frequency, e[i].damping, m->dt,
                                             (double)r->mode_count[s], &sf, &sz);
                    cJSON_AddItemToArray(fr, cJSON_CreateNumber(e[i].frequency));
                    cJSON_AddItemToArray(dz, cJSON_CreateNumber(e[i].damping));
                    cJSON_AddItemToArray(fr_floor, aenl_json_num(sf));
                    cJSON_AddItemToArray(dz_floor, aenl_json_num(sz));
                }
            }
        }
        cJSON_AddItemToObject(o, "eig", eig);
        cJSON_AddItemToObject(o, "frequency", fr);
        cJSON_AddItemToObject(o, "damping", dz);
        cJSON_AddItemToObject(o, "frequency_floor", fr_floor);
        cJSON_AddItemToObject(o, "damping_floor", dz_floor);
        if (boot != NULL)
        {
            const size_t np = boot->n_pairs[s];
            cJSON_AddItemToObject(o, "frequency_se", boot_array(boot->f_sd, s, np));
            cJSON_AddItemToObject(o, "damping_se", boot_array(boot->z_sd, s, np));
            cJSON_AddItemToObject(o, "frequency_bias", boot_array(boot->f_bias, s, np));
            cJSON_AddItemToObject(o, "damping_bias", boot_array(boot->z_bias, s, np));
            cJSON *found = cJSON_CreateArray();
            for (size_t i = 0; i < np; ++i)
            {
                cJSON_AddItemToArray(found, cJSON_CreateNumber((double)boot->found[s][i]));
            }
            cJSON_AddItemToObject(o, "pair_found", found);
        }
        cJSON_AddItemToArray(modes, o);
    }
    cJSON_AddItemToObject(root, "modes", modes);
    cJSON_AddItemToObject(root, "C", json_matrix(m->C, nz, nx));
    cJSON_AddItemToObject(root, "R", json_matrix(m->R, nz, nz));
    cJSON_AddItemToObject(root, "loglik", json_vector(r->loglik, r->n_iter));
    cJSON_AddNumberToObject(root, "loglik_final", r->loglik_final);
    cJSON_AddNumberToObject(root, "missing", (double)r->n_missing);
    if (boot != NULL)
    {
        cJSON *b = cJSON_CreateObject();
        cJSON_AddNumberToObject(b, "requested", (double)boot->n_requested);
        cJSON_AddNumberToObject(b, "refits", (double)boot->n_ok);
        cJSON_AddItemToObject(root, "bootstrap", b);
    }
    char *text = cJSON_Print(root);
    if (text != NULL)
    {
        printf("%s\n", text);
        free(text);
    }
    cJSON_Delete(root);
}

/* One estimate v with its standard error se (also relative), its one-channel floor (relative;
 * when has_floor) and its bias. */
static void print_estimate(const char *what, double v, double se, double floor_rel, int has_floor,
                           double bias)
{
    printf("  %s %.6g +- %.2g (%.3g %%", what, v, se, 100.0 * se / fabs(v));
    if (has_floor)
    {
        printf("; floor %.3g %%", 100.0 * floor_rel);
    }
    printf("; bias %+.2g)", bias);
}

/* Pair i of mode s on its own line with the bootstrap's standard errors and biases (or how
 * few refits found it). */
static void print_pair_boot(const aenl_em_eig_t *e, const aenl_em_boot_t *boot, size_t s, size_t i,
                            double sf, double sz, int has_floor)
{
    if (!isfinite(boot->f_sd[s][i]))
    {
        printf("  f %.6g  zeta %.4g  (the pair is found in %zu of %zu refits: not determined)\n",
               e->frequency, e->damping, boot->found[s][i], boot->n_ok);
        return;
    }
    print_estimate("f", e->frequency, boot->f_sd[s][i], sf, has_floor, boot->f_bias[s][i]);
    print_estimate("zeta", e->damping, boot->z_sd[s][i], sz, has_floor, boot->z_bias[s][i]);
    printf("\n");
}

static void print_text(const aenl_em_result_t *r, const aenl_em_boot_t *boot, const char *data,
                       const char *const *names)
{
    const aenl_em_model_t *m = &r->model;
    printf("%s: %zu outputs, %zu states, %zu modes switching on %s, dt %g\n", data, m->n_z, m->n_x,
           m->n_modes, names[m->switch_channel], m->dt);
    if (r->n_iter > 0)
    {
        printf("log-likelihood %.6f -> %.6f in %zu iterations\n", r->loglik[0], r->loglik_final,
               r->n_iter);
    }
    const int per_line = boot != NULL && boot->n_ok > 0; /* a line per pair, with its errors */
    if (per_line)
    {
        printf("parametric bootstrap: %zu of %zu records simulated from the fit, fitted again; "
               "+- standard error, bias = their median - the fit\n",
               boot->n_ok, boot->n_requested);
    }
    else if (boot != NULL)
    {
        printf("parametric bootstrap: none of the %zu records simulated from the fit could be "
               "fitted again (no standard errors)\n",
               boot->n_requested);
    }
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        aenl_em_eig_t e[AENL_EM_MAX_X];
        size_t n_eig = 0, n_osc = 0;
        aenl_err_t err;
        aenl_err_clear(&err);
        printf("mode %zu [%g, %g) %zu samples:", s, s == 0 ? -HUGE_VAL : m->thresholds[s - 1],
               s + 1 == m->n_modes ? HUGE_VAL : m->thresholds[s], r->mode_count[s]);
        if (aenl_em_modal(m, s, e, &n_eig, &n_osc, &err) == AENL_OK)
        {
            if (per_line)
            {
                printf("\n");
            }
            for (size_t i = 0; i < n_osc; ++i)
            {
                double sf = NAN;
                double sz = NAN;
                const int has_floor = aenl_em_mode_floor(e[i].frequency, e[i].damping, m->dt,
                                                         (double)r->mode_count[s], &sf, &sz);
                if (per_line && i < boot->n_pairs[s])
                {
                    print_pair_boot(&e[i], boot, s, i, sf, sz, has_floor);
                    continue;
                }
                printf(" f %.6g zeta %.4g", e[i].frequency, e[i].damping);
                if (has_floor)
                {
                    printf(" (floor %.3g %% / %.3g %%)", 100.0 * sf, 100.0 * sz);
                }
                printf(";");
            }
            if (per_line)
            {
                continue;
            }
        }
        printf("\n");
    }
}

/* --thresholds CH:T1,T2,... into o; thr[cap] gets CH. 0, or -1 after printing what is wrong. */
static int parse_thresholds(const char *s, aenl_em_opts_t *o, char *thr, size_t cap)
{
    const int thr_len = snprintf(thr, cap, "%s", s);
    if (thr_len < 0 || (size_t)thr_len >= cap)
    {
        aenl_cli_error(k_cmd, "--thresholds: value too long (at most %zu characters)", cap - 1);
        return -1;
    }
    char *colon = strrchr(thr, ':');
    if (colon == NULL || colon == thr)
    {
        aenl_cli_error(k_cmd, "--thresholds: '%s' is not CH:T1[,T2,...]", s);
        return -1;
    }
    *colon = '\0';
    char *items[AENL_EM_MAX_MODES];
    const int n_thr = split_list(colon + 1, items, AENL_EM_MAX_MODES - 1);
    if (n_thr <= 0)
    {
        aenl_cli_error(k_cmd, "--thresholds: 1 to %d values after '%s:'", AENL_EM_MAX_MODES - 1,
                       thr);
        return -1;
    }
    o->n_thresholds = (size_t)n_thr;
    for (int i = 0; i < n_thr; ++i)
    {
        if (aenl_cli_parse_double(k_cmd, "--thresholds", items[i], &o->thresholds[i]) != 0)
        {
            return -1;
        }
        if (i > 0 && !(o->thresholds[i] > o->thresholds[i - 1]))
        {
            aenl_cli_error(k_cmd, "--thresholds: values must ascend (%g then %g)",
                           o->thresholds[i - 1], o->thresholds[i]);
            return -1;
        }
    }
    return 0;
}

/* The EM options of the command line; sw_name[cap] gets the switching channel's name. 0, or -1
 * after printing what is wrong. */
static int make_opts(const fit_args_t *a, aenl_em_opts_t *o, char *sw_name, size_t cap)
{
    aenl_em_opts_default(o);
    if (a->freeze != NULL && parse_freeze(a->freeze, &o->freeze) != 0)
    {
        return -1;
    }
    if (a->free_c)
    {
        o->freeze &= ~AENL_EM_FREEZE_C;
    }
    if (parse_thresholds(a->thr, o, sw_name, cap) != 0)
    {
        return -1;
    }
    o->max_iter = (size_t)a->iter;
    o->refine = a->refine;
    o->modes_from_data = a->modes_from_data;
    o->tol = a->tol;
    o->plain_em = a->plain_em;
    o->init = a->init;
    return 0;
}

/* The outputs read from the record: y is n x n_out, row-major. names[i] is filled for i < n_out
 * (== the fitted model's n_z, which print_json reads); the rest are NULL so that the analyser,
 * which cannot see that equality through aenl_em_fit, sees no garbage. */
typedef struct fit_record
{
    double *y;
    size_t n, n_out;
    const char *names[AENL_EM_MAX_X];
} fit_record_t;

/* Columns cols[0..n_out-1] of t into rec (rec->y allocated); an exit code. */
static int copy_outputs(const aenl_table_t *t, const long *cols, size_t n_out, fit_record_t *rec)
{
    static char name_buf[AENL_EM_MAX_X][128];
    rec->y = malloc(t->n_rows * n_out * sizeof(double));
    if (rec->y == NULL)
    {
        aenl_cli_error(k_cmd, "out of memory");
        return AENL_EXIT_FAIL;
    }
    rec->n = t->n_rows;
    rec->n_out = n_out;
    for (size_t i = 0; i < n_out; ++i)
    {
        /* display copy (t is freed before the fit): a name over 127 characters is shown cut */
        (void)snprintf(name_buf[i], sizeof(name_buf[i]), "%s", t->names[cols[i]]);
        rec->names[i] = name_buf[i];
        const double *col = aenl_table_col(t, (size_t)cols[i]);
        for (size_t k = 0; k < t->n_rows; ++k)
        {
            rec->y[k * n_out + i] = col[k];
        }
    }
    return AENL_EXIT_OK;
}

/* The record's outputs, checked, into rec; the sample step, the switching output and the state
 * count into o. An exit code. */
static int read_record(const fit_args_t *a, const char *sw_name, aenl_em_opts_t *o,
                       fit_record_t *rec, aenl_err_t *err)
{
    memset(rec, 0, sizeof(*rec));
    aenl_table_t t;
    if (aenl_table_read(a->data, &t, err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err->msg);
        return AENL_EXIT_USAGE;
    }
    long cols[AENL_EM_MAX_X];
    size_t n_out = 0, sw = 0;
    double dt = 0.0;
    int bad = t.n_rows < 2 || pick_outputs(&t, a, sw_name, cols, &n_out, &sw) != 0;
    for (size_t i = 0; i < n_out && !bad; ++i)
    {
        bad = aenl_cli_check_record(k_cmd, &t, a->data, cols[i]) != 0; /* NaN time, huge, all NaN */
    }
    if (bad || n_out == 0 || time_step(&t, a->data, &dt) != 0)
    {
        if (t.n_rows < 2)
        {
            aenl_cli_error(k_cmd, "%s: fewer than 2 data rows", a->data);
        }
        aenl_table_free(&t);
        return AENL_EXIT_USAGE;
    }
    o->dt = dt;
    o->switch_channel = sw;
    o->n_states = a->states > 0 ? (size_t)a->states : 4 * n_out;
    const int rc = copy_outputs(&t, cols, n_out, rec);
    aenl_table_free(&t);
    return rc;
}

/* The model files asked for: the INI, then the C header; the INI is removed when the header
 * fails (all or nothing). */
static aenl_status_t write_model(const fit_args_t *a, const aenl_em_model_t *m, aenl_err_t *err)
{
    aenl_status_t st = AENL_OK;
    if (a->out_ini != NULL)
    {
        st = aenl_em_write_ini(m, a->out_ini, err);
    }
    if (st == AENL_OK && a->out_h != NULL)
    {
        char ident_buf[128];
        const char *ident = a->name; /* checked (identifier, length) by aenl_em_write_c_header */
        if (ident == NULL)
        {
            ident_from_path(a->out_h, ident_buf, sizeof(ident_buf));
            ident = ident_buf;
        }
        /* on failure the INI written above is undone when the run ends */
        st = aenl_em_write_c_header(m, ident, a->out_h, err);
    }
    return st;
}

int aenl_cmd_fit(int argc, char **argv)
{
    fit_args_t a;
    const int pr = parse_args(argc, argv, &a);
    if (pr != 0)
    {
        return pr > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    aenl_em_opts_t o;
    char sw_name[512];
    if (make_opts(&a, &o, sw_name, sizeof(sw_name)) != 0)
    {
        return AENL_EXIT_USAGE;
    }
    aenl_err_t err;
    aenl_err_clear(&err);
    fit_record_t rec;
    const int rc = read_record(&a, sw_name, &o, &rec, &err);
    if (rc != AENL_EXIT_OK)
    {
        return rc;
    }
    aenl_em_result_t r;
    aenl_status_t st = aenl_em_fit(rec.y, rec.n, rec.n_out, &o, &r, &err);
    free(rec.y);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", a.data, err.msg);
        return AENL_EXIT_USAGE;
    }
    /* before any output is written: a failure leaves nothing behind */
    aenl_em_boot_t boot;
    if (a.bootstrap > 0)
    {
        aenl_cli_bar_t bar;
        aenl_cli_bar_begin(&bar, k_cmd, "bootstrap");
        st = aenl_em_bootstrap(&r, &o, rec.n, (size_t)a.bootstrap, (uint64_t)a.seed, &bar.progress,
                               &boot, &err);
        aenl_cli_bar_end(&bar);
        if (st != AENL_OK)
        {
            aenl_cli_error(k_cmd, "%s", err.msg);
            aenl_em_result_free(&r);
            return aenl_cli_exit(st);
        }
    }
    st = write_model(&a, &r.model, &err);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        aenl_em_result_free(&r);
        return AENL_EXIT_USAGE;
    }
    const aenl_em_boot_t *bp = a.bootstrap > 0 ? &boot : NULL;
    if (a.json)
    {
        print_json(&r, bp, a.data, rec.names);
    }
    else
    {
        print_text(&r, bp, a.data, rec.names);
    }
    aenl_em_result_free(&r);
    return AENL_EXIT_OK;
}
