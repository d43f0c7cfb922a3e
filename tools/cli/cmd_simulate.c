/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_simulate.c
 * @brief `aenl simulate MODEL.ini [-o out.csv]`: run a model INI (docs/simulate.md).
 */
#include <stdio.h>
#include <string.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_sim.h"

static const char *const k_cmd = "simulate";

static void help(void)
{
    printf("usage: aenl simulate MODEL.ini [-o out.csv] [--no-ic-forcing] [--rk4 H] [--info]\n\n"
           "Simulates the model of MODEL.ini (airfoil2dof or section3dof, see docs/simulate.md) "
           "with the\n"
           "event-located Dormand-Prince integrator and writes the CSV on the [run] grid:\n"
           "airfoil2dof -> t,alpha,xi (tau, rad, h/b); section3dof -> t,h,alpha,beta (s, m, rad,\n"
           "rad); a sweep or multisine ([excitation]) adds its force as a last column f_pitch,\n"
           "f_plunge or f_flap. Without -o the CSV goes to stdout; with -o the file appears only\n"
           "when complete.\n"
           "  --no-ic-forcing  drop the Wagner start-up terms f, g (airfoil2dof)\n"
           "  --rk4 H          naive fixed-step RK4 with step H instead (for comparisons)\n"
           "  --info           integrator counters on stderr (steps, events, sticking)\n");
}

int aenl_cmd_simulate(int argc, char **argv)
{
    const char *ini = NULL, *out = NULL;
    int no_ic = 0, info = 0, i;
    double rk4 = 0.0;
    aenl_sim_model_t model;
    aenl_sim_run_t run;
    aenl_sim_result_t res;
    aenl_err_t err;
    aenl_status_t st;
    aenl_err_clear(&err);
    for (i = 1; i < argc; ++i)
    {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
        {
            help();
            return AENL_EXIT_OK;
        }
        if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0)
        {
            if ((out = aenl_cli_value(k_cmd, argc, argv, &i)) == NULL)
            {
                return AENL_EXIT_USAGE;
            }
        }
        else if (strcmp(a, "--no-ic-forcing") == 0)
        {
            no_ic = 1;
        }
        else if (strcmp(a, "--info") == 0)
        {
            info = 1;
        }
        else if (strcmp(a, "--rk4") == 0)
        {
            const char *v = aenl_cli_value(k_cmd, argc, argv, &i);
            if (v == NULL || aenl_cli_parse_double(k_cmd, "--rk4", v, &rk4) != 0)
            {
                return AENL_EXIT_USAGE;
            }
            if (!(rk4 > 0.0))
            {
                aenl_cli_error(k_cmd, "--rk4: the step must be > 0");
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
        aenl_cli_error(k_cmd, "no MODEL.ini given (aenl simulate --help)");
        return AENL_EXIT_USAGE;
    }
    if (aenl_sim_load_ini(ini, &model, &run, &err) != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE;
    }
    if (no_ic)
    {
        model.airfoil.ic_forcing = 0;
    }
    st = (rk4 > 0.0) ? aenl_sim_simulate_rk4(&model, &run, rk4, &res, &err)
                     : aenl_sim_simulate(&model, &run, &res, &err);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s: %s", ini, err.msg);
        /* a motion the integrator cannot follow (it grows without bound, a law's force
         * overflows) is the model's, so the input's: only memory running out is not */
        return st == AENL_E_ARG || st == AENL_E_NUMERIC ? AENL_EXIT_USAGE : AENL_EXIT_FAIL;
    }
    st = aenl_sim_result_write_csv(&res, out, &err);
    if (st == AENL_OK && info)
    {
        fprintf(stderr,
                "aenl simulate: %zu samples; steps %lu (rejected %lu), rhs %lu, events %lu "
                "(grazing %lu), stuck %lu, unstick %lu\n",
                res.n_samples, res.info.n_steps, res.info.n_rejected, res.info.n_rhs,
                res.info.n_events, res.info.n_grazing, res.info.n_stuck, res.info.n_unstick);
    }
    aenl_sim_result_free(&res);
    if (st != AENL_OK)
    {
        aenl_cli_error(k_cmd, "%s", err.msg);
        return AENL_EXIT_USAGE; /* an unwritable output path, as in the other subcommands */
    }
    return AENL_EXIT_OK;
}
