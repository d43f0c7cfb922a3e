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

static cJSON *num_or_null(int ok, double v)
{
    return ok ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

int aenl_cmd_flutter(int argc, char **argv)
{
    const char *ini = NULL, *range = NULL;
    int json = 0, sweep = 0, i, two;
    long points = 25;
    aenl_sim_model_t model;
    aenl_sim_flutter_t fo, fi;
    double outer[AENL_SIM_N_DOF], inner[AENL_SIM_N_DOF], vmin = 0.0, vmax = 0.0;
    aenl_err_t err;
    sweep_row_t *rows = NULL;
    const char *unit, *funit;
    aenl_err_clear(&err);
    memset(&fi, 0, sizeof(fi));
    for (i = 1; i < argc; ++i)
    {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(a, "--json") == 0)
        {
            json = 1;
        }
        else if (strcmp(a, "--sweep") == 0)
        {
            sweep = 1;
        }
        else if (strcmp(a, "--range") == 0)
        {
            if ((range = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--points") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || aenl_cli_parse_long(k_cmd, "--points", v, 2, 100000, &points) != 0)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (aenl_cli_positional(k_cmd, a, &ini, "MODEL.ini") != 0)
        {
            return AENL_EXIT_USAGE;
        }
    }
    if (ini == NULL)
    {
        aenl_cli_error(k_cmd, "no MODEL.ini given (aenl flutter --help)");
        return AENL_EXIT_USAGE;
    }
    if (range != NULL)
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
            return AENL_EXIT_USAGE;
        }
        *colon = '\0';
        if (aenl_cli_parse_double(k_cmd, "--range VMIN", buf, &vmin) != 0 ||
            aenl_cli_parse_double(k_cmd, "--range VMAX", colon + 1, &vmax) != 0)
        {
            return AENL_EXIT_USAGE;
        }
        if (!(vmin > 0.0) || !(vmax > vmin))
        {
            aenl_cli_error(k_cmd, "--range: need 0 < VMIN < VMAX");
            return AENL_EXIT_USAGE;
        }
    }
    if (aenl_sim_load_ini(ini, &model, NULL, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    two = aenl_sim_slopes(&model, outer, inner);
    if (aenl_sim_flutter(&model, outer, vmin, vmax, &fo, &err) != AENL_OK ||
        (two && aenl_sim_flutter(&model, inner, vmin, vmax, &fi, &err) != AENL_OK))
    {
        aenl_cli_error(k_cmd, "%s: %s", ini, err.msg);
        return AENL_EXIT_FAIL;
    }
    unit = model.type == AENL_SIM_AIRFOIL2DOF ? "U*" : "m/s";
    funit = model.type == AENL_SIM_AIRFOIL2DOF ? "omega/omega_alpha" : "Hz";
    if (sweep)
    {
        const double lo = vmin > 0.0 ? vmin : (model.type == AENL_SIM_AIRFOIL2DOF ? 0.5 : 1.0);
        const double hi =
            vmax > 0.0
                ? vmax
                : (fo.found ? 1.5 * fo.speed : (model.type == AENL_SIM_AIRFOIL2DOF ? 10.0 : 40.0));
        rows = calloc((size_t)points, sizeof(*rows));
        if (rows == NULL)
        {
            aenl_cli_error(k_cmd, "out of memory");
            return AENL_EXIT_FAIL;
        }
        for (i = 0; i < (int)points; ++i)
        {
            rows[i].v = lo + (hi - lo) * (double)i / (double)(points - 1);
            if (aenl_sim_modes(&model, rows[i].v, outer, rows[i].m, AENL_SIM_MAX_X, &rows[i].n,
                               &err) != AENL_OK)
            {
                free(rows);
                aenl_cli_error(k_cmd, "%s: %s", ini, err.msg);
                return AENL_EXIT_FAIL;
            }
        }
    }
    if (json)
    {
        cJSON *root = cJSON_CreateObject();
        char *text;
        cJSON_AddStringToObject(root, "file", ini);
        cJSON_AddStringToObject(root, "model",
                                model.type == AENL_SIM_AIRFOIL2DOF ? "airfoil2dof" : "section3dof");
        cJSON_AddItemToObject(root, "speed", num_or_null(fo.found, fo.speed));
        cJSON_AddItemToObject(root, "frequency", num_or_null(fo.found, fo.frequency));
        cJSON_AddStringToObject(root, "unit", unit);
        cJSON_AddStringToObject(root, "frequency_unit", funit);
        if (two)
        {
            cJSON *in = cJSON_CreateObject();
            cJSON_AddItemToObject(in, "speed", num_or_null(fi.found, fi.speed));
            cJSON_AddItemToObject(in, "frequency", num_or_null(fi.found, fi.frequency));
            cJSON_AddItemToObject(root, "inner_slope", in);
        }
        if (rows != NULL)
        {
            cJSON *arr = cJSON_CreateArray();
            for (i = 0; i < (int)points; ++i)
            {
                cJSON *r = cJSON_CreateObject(), *ms = cJSON_CreateArray();
                size_t k;
                cJSON_AddNumberToObject(r, "velocity", rows[i].v);
                for (k = 0; k < rows[i].n; ++k)
                {
                    cJSON *m = cJSON_CreateObject();
                    cJSON_AddNumberToObject(m, "damping", rows[i].m[k].damping);
                    cJSON_AddNumberToObject(m, "frequency", rows[i].m[k].frequency);
                    cJSON_AddItemToArray(ms, m);
                }
                cJSON_AddItemToObject(r, "modes", ms);
                cJSON_AddItemToArray(arr, r);
            }
            cJSON_AddItemToObject(root, "sweep", arr);
        }
        text = cJSON_Print(root);
        cJSON_Delete(root);
        if (text == NULL)
        {
            free(rows);
            aenl_cli_error(k_cmd, "out of memory");
            return AENL_EXIT_FAIL;
        }
        printf("%s\n", text);
        cJSON_free(text);
    }
    else
    {
        printf("%s: %s\n", ini, model.type == AENL_SIM_AIRFOIL2DOF ? "airfoil2dof" : "section3dof");
        if (fo.found)
        {
            printf("flutter speed %.9g %s, frequency %.6g %s (laws at their outer slope)\n",
                   fo.speed, unit, fo.frequency, funit);
        }
        else
        {
            printf("no flutter in the search range (laws at their outer slope)\n");
        }
        if (two)
        {
            if (fi.found)
            {
                printf("flutter speed %.9g %s, frequency %.6g %s (freeplay/hysteresis at the inner "
                       "slope)\n",
                       fi.speed, unit, fi.frequency, funit);
            }
            else
            {
                printf("no flutter in the search range (freeplay/hysteresis at the inner slope)\n");
            }
        }
        if (rows != NULL)
        {
            size_t k, nmax = 0;
            for (i = 0; i < (int)points; ++i)
            {
                nmax = rows[i].n > nmax ? rows[i].n : nmax;
            }
            printf("\n%12s", "velocity");
            for (k = 0; k < nmax; ++k)
            {
                printf("  %9s%-2zu %9s%-2zu", "damping", k + 1, "freq", k + 1);
            }
            printf("\n");
            for (i = 0; i < (int)points; ++i)
            {
                printf("%12.6g", rows[i].v);
                for (k = 0; k < nmax; ++k)
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
    }
    free(rows);
    return AENL_EXIT_OK;
}
