/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_flutter.c
 * @brief `aenl flutter MODEL.ini [--json] [--sweep]`: linear flutter speed and frequency.
 */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_sim.h"

static const char *const k_cmd = "flutter";

static void help(void)
{
    printf("usage: aenl flutter MODEL.ini [--json] [--sweep] [--range VMIN:VMAX] [--points N]\n\n"
           "Linear flutter speed and frequency from the eigenvalues of the linear state matrix\n"
           "(LAPACKE dgeev), by a scan over velocity and bisection. Each restoring law is\n"
           "linearised at its outer slope (1; polynomial: c1); for freeplay and hysteresis the\n"
           "inner slope (inner_stiffness, usually 0) gives a second speed, the lower bound of\n"
           "freeplay limit cycles. Units: airfoil2dof U* and omega/omega_alpha; section3dof m/s\n"
           "and Hz. --sweep adds velocity, damping and frequency per mode (sorted by frequency)\n"
           "at N velocities (default 25) over the range (default: up to 1.5 x the flutter speed).\n"
           "--json prints {\"speed\": U, \"frequency\": f, \"unit\": ..., ...}; speed is null\n"
           "when no instability lies in the search range (0.05..50 U* or 0.5..200 m/s).\n");
}

typedef struct sweep_row
{
    double v;
    size_t n;
    aenl_sim_mode_t m[AENL_SIM_MAX_X];
} sweep_row_t;

/* What the command line asks for; vmin = vmax = 0 when no --range is given. */
typedef struct flutter_args
{
    const char *ini;
    int json, sweep;
    long points;
    double vmin, vmax;
} flutter_args_t;

/* The model and what is computed from it. */
typedef struct flutter_result
{
    aenl_sim_model_t model;
    double outer[AENL_SIM_N_DOF]; /* each law's outer slope */
    int two;                      /* 1: some law has an inner slope, which gives a second speed */
    aenl_sim_flutter_t fo, fi;    /* at the outer slopes, at the inner slopes (when two) */
    sweep_row_t *rows;            /* args.points rows with --sweep, else NULL */
} flutter_result_t;

static cJSON *num_or_null(int ok, double v)
{
    return ok ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

static const char *model_name(const aenl_sim_model_t *m)
{
    return m->type == AENL_SIM_AIRFOIL2DOF ? "airfoil2dof" : "section3dof";
}

static const char *speed_unit(const aenl_sim_model_t *m)
{
    return m->type == AENL_SIM_AIRFOIL2DOF ? "U*" : "m/s";
}

static const char *frequency_unit(const aenl_sim_model_t *m)
{
    return m->type == AENL_SIM_AIRFOIL2DOF ? "omega/omega_alpha" : "Hz";
}

/* --range VMIN:VMAX into a->vmin, a->vmax: 0, or -1 after printing what is wrong. */
static int parse_range(const char *range, flutter_args_t *a)
{
    char buf[128];
    char *colon = NULL;
    const size_t len = strlen(range);
    if (len < sizeof(buf))
    {
        memcpy(buf, range, len + 1u);
        colon = strchr(buf, ':');
    }
    if (colon == NULL)
    {
        aenl_cli_error(k_cmd, "--range: '%s' is not VMIN:VMAX", range);
        return -1;
    }
    *colon = '\0';
    if (aenl_cli_parse_double(k_cmd, "--range VMIN", buf, &a->vmin) != 0 ||
        aenl_cli_parse_double(k_cmd, "--range VMAX", colon + 1, &a->vmax) != 0)
    {
        return -1;
    }
    if (!(a->vmin > 0.0) || !(a->vmax > a->vmin))
    {
        aenl_cli_error(k_cmd, "--range: need 0 < VMIN < VMAX");
        return -1;
    }
    return 0;
}

/* 0 to go on, 1 after the help, -1 after printing what is wrong. --range is checked once the
 * whole line is read, after the check for a model file. */
static int parse_args(int argc, char **argv, flutter_args_t *a)
{
    const char *range = NULL;
    memset(a, 0, sizeof(*a));
    a->points = 25;
    for (int i = 1; i < argc; ++i)
    {
        const char *o = argv[i];
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0)
        {
            help();
            return 1;
        }
        if (strcmp(o, "--json") == 0)
        {
            a->json = 1;
        }
        else if (strcmp(o, "--sweep") == 0)
        {
            a->sweep = 1;
        }
        else if (strcmp(o, "--range") == 0)
        {
            if ((range = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return -1;
            }
        }
        else if (strcmp(o, "--points") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || aenl_cli_parse_long(k_cmd, "--points", v, 2, 100000, &a->points) != 0)
            {
                return -1;
            }
        }
        else if (aenl_cli_positional(k_cmd, o, &a->ini, "MODEL.ini") != 0)
        {
            return -1;
        }
    }
    if (a->ini == NULL)
    {
        aenl_cli_error(k_cmd, "no MODEL.ini given (aenl flutter --help)");
        return -1;
    }
    return range != NULL ? parse_range(range, a) : 0;
}

/* The model and its flutter speeds (outer slopes, and inner ones when a law has them); an exit
 * code: usage for a model that does not load, failure for an eigenvalue computation. */
static int compute_speeds(const flutter_args_t *a, flutter_result_t *r)
{
    aenl_err_t err;
    double inner[AENL_SIM_N_DOF];
    aenl_err_clear(&err);
    if (aenl_sim_load_ini(a->ini, &r->model, NULL, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    r->two = aenl_sim_slopes(&r->model, r->outer, inner);
    if (aenl_sim_flutter(&r->model, r->outer, a->vmin, a->vmax, &r->fo, &err) != AENL_OK ||
        (r->two && aenl_sim_flutter(&r->model, inner, a->vmin, a->vmax, &r->fi, &err) != AENL_OK))
    {
        aenl_cli_error(k_cmd, "%s: %s", a->ini, err.msg);
        return AENL_EXIT_FAIL;
    }
    return AENL_EXIT_OK;
}

/* The modes at a->points velocities into r->rows: over --range, or by default from a low speed
 * to 1.5 x the flutter speed (a fixed top when there is none). An exit code. */
static int compute_sweep(const flutter_args_t *a, flutter_result_t *r)
{
    const int airfoil = r->model.type == AENL_SIM_AIRFOIL2DOF;
    const double lo = a->vmin > 0.0 ? a->vmin : (airfoil ? 0.5 : 1.0);
    const double hi =
        a->vmax > 0.0 ? a->vmax : (r->fo.found ? 1.5 * r->fo.speed : (airfoil ? 10.0 : 40.0));
    aenl_err_t err;
    aenl_err_clear(&err);
    r->rows = calloc((size_t)a->points, sizeof(*r->rows));
    if (r->rows == NULL)
    {
        aenl_cli_error(k_cmd, "out of memory");
        return AENL_EXIT_FAIL;
    }
    for (int i = 0; i < (int)a->points; ++i)
    {
        sweep_row_t *row = &r->rows[i];
        row->v = lo + (hi - lo) * (double)i / (double)(a->points - 1);
        if (aenl_sim_modes(&r->model, row->v, r->outer, row->m, AENL_SIM_MAX_X, &row->n, &err) !=
            AENL_OK)
        {
            aenl_cli_error(k_cmd, "%s: %s", a->ini, err.msg);
            return AENL_EXIT_FAIL;
        }
    }
    return AENL_EXIT_OK;
}

/* The sweep as [{"velocity": v, "modes": [{"damping": d, "frequency": f}, ...]}, ...]. */
static cJSON *json_sweep(const sweep_row_t *rows, long points)
{
    cJSON *arr = cJSON_CreateArray();
    for (int i = 0; i < (int)points; ++i)
    {
        cJSON *r = cJSON_CreateObject(), *ms = cJSON_CreateArray();
        cJSON_AddNumberToObject(r, "velocity", rows[i].v);
        for (size_t k = 0; k < rows[i].n; ++k)
        {
            cJSON *m = cJSON_CreateObject();
            cJSON_AddNumberToObject(m, "damping", rows[i].m[k].damping);
            cJSON_AddNumberToObject(m, "frequency", rows[i].m[k].frequency);
            cJSON_AddItemToArray(ms, m);
        }
        cJSON_AddItemToObject(r, "modes", ms);
        cJSON_AddItemToArray(arr, r);
    }
    return arr;
}

/* An exit code: failure when the text cannot be built. */
static int print_json(const flutter_args_t *a, const flutter_result_t *r)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "schema", "aenl-flutter/1");
    cJSON_AddStringToObject(root, "aenl_version", AENL_VERSION);
    cJSON_AddStringToObject(root, "file", a->ini);
    cJSON_AddStringToObject(root, "model", model_name(&r->model));
    cJSON_AddItemToObject(root, "speed", num_or_null(r->fo.found, r->fo.speed));
    cJSON_AddItemToObject(root, "frequency", num_or_null(r->fo.found, r->fo.frequency));
    cJSON_AddStringToObject(root, "unit", speed_unit(&r->model));
    cJSON_AddStringToObject(root, "frequency_unit", frequency_unit(&r->model));
    if (r->two)
    {
        cJSON *in = cJSON_CreateObject();
        cJSON_AddItemToObject(in, "speed", num_or_null(r->fi.found, r->fi.speed));
        cJSON_AddItemToObject(in, "frequency", num_or_null(r->fi.found, r->fi.frequency));
        cJSON_AddItemToObject(root, "inner_slope", in);
    }
    if (r->rows != NULL)
    {
        cJSON_AddItemToObject(root, "sweep", json_sweep(r->rows, a->points));
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (text == NULL)
    {
        aenl_cli_error(k_cmd, "out of memory");
        return AENL_EXIT_FAIL;
    }
    printf("%s\n", text);
    cJSON_free(text);
    return AENL_EXIT_OK;
}

/* One line per velocity: damping and frequency of each mode, "nan" where a velocity has fewer
 * modes than the most any has. */
static void print_sweep(const sweep_row_t *rows, long points)
{
    size_t nmax = 0;
    for (int i = 0; i < (int)points; ++i)
    {
        nmax = rows[i].n > nmax ? rows[i].n : nmax;
    }
    printf("\n%12s", "velocity");
    for (size_t k = 0; k < nmax; ++k)
    {
        printf("  %9s%-2zu %9s%-2zu", "damping", k + 1, "freq", k + 1);
    }
    printf("\n");
    for (int i = 0; i < (int)points; ++i)
    {
        printf("%12.6g", rows[i].v);
        for (size_t k = 0; k < nmax; ++k)
        {
            if (k < rows[i].n)
            {
                printf("  %11.5g %11.5g", rows[i].m[k].damping, rows[i].m[k].frequency);
            }
            else
            {
                printf("  %11s %11s", "nan", "nan");
            }
        }
        printf("\n");
    }
}

static void print_text(const flutter_args_t *a, const flutter_result_t *r)
{
    const char *unit = speed_unit(&r->model), *funit = frequency_unit(&r->model);
    printf("%s: %s\n", a->ini, model_name(&r->model));
    if (r->fo.found)
    {
        printf("flutter speed %.9g %s, frequency %.6g %s (laws at their outer slope)\n",
               r->fo.speed, unit, r->fo.frequency, funit);
    }
    else
    {
        printf("no flutter in the search range (laws at their outer slope)\n");
    }
    if (r->two && r->fi.found)
    {
        printf("flutter speed %.9g %s, frequency %.6g %s (freeplay/hysteresis at the inner "
               "slope)\n",
               r->fi.speed, unit, r->fi.frequency, funit);
    }
    else if (r->two)
    {
        printf("no flutter in the search range (freeplay/hysteresis at the inner slope)\n");
    }
    if (r->rows != NULL)
    {
        print_sweep(r->rows, a->points);
    }
}

int aenl_cmd_flutter(int argc, char **argv)
{
    flutter_args_t a;
    const int pr = parse_args(argc, argv, &a);
    if (pr != 0)
    {
        return pr > 0 ? AENL_EXIT_OK : AENL_EXIT_USAGE;
    }
    flutter_result_t r;
    memset(&r, 0, sizeof(r));
    int rc = compute_speeds(&a, &r);
    if (rc == AENL_EXIT_OK && a.sweep)
    {
        rc = compute_sweep(&a, &r);
    }
    if (rc == AENL_EXIT_OK && a.json)
    {
        rc = print_json(&a, &r);
    }
    else if (rc == AENL_EXIT_OK)
    {
        print_text(&a, &r);
    }
    free(r.rows);
    return rc;
}
