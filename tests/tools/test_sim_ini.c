/* SPDX-License-Identifier: MIT */
/**
 * @file test_sim_ini.c
 * @brief Model INI loading (docs/simulate.md): the example files, every rejected input with a
 * message naming file, line and key; seeded measurement noise at the stated SNR, reproducibility,
 *        and the turbulence forcing.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "unity.h"

#include "aenl_tools/aenl_sim.h"

#define DEG      (3.14159265358979323846 / 180.0)
#define EXAMPLES AENL_SOURCE_DIR "/tools/examples/"

void setUp(void)
{
}

void tearDown(void)
{
}

static const char *write_tmp(const char *name, const char *text)
{
    static char path[512];
    FILE *fp;
    (void)snprintf(path, sizeof(path), "%s/%s", AENL_TEST_TMP_DIR, name);
    fp = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(fp);
    TEST_ASSERT_TRUE(fputs(text, fp) >= 0);
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
    return path;
}

static void expect_error(const char *name, const char *text, const char *needle1,
                         const char *needle2)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_err_t err;
    const char *path = write_tmp(name, text);
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_E_ARG, aenl_sim_load_ini(path, &m, &r, &err), name);
    TEST_MESSAGE(err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, needle1), err.msg);
    if (needle2 != NULL)
    {
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, needle2), err.msg);
    }
}

#define GOOD_MODEL "[model]\ntype = airfoil2dof\nustar = 5.5\n"

static void test_ini_examples_load_and_run(void)
{
    static const char *const names[] = {
        "paper_hysteresis_pitch.ini", "paper_flap_freeplay.ini",
        "paper_polynomial_pitch.ini", "validate_linear_u4.ini",
        "validate_freeplay_u55.ini",  "validate_cubic_u7.ini",
        "validate_hysteresis_u5.ini", "validate_conner_flap_u15.ini",
        "section3dof_turbulence.ini", "section3dof_two_freeplays.ini",
        "section3dof_raps.ini",       "section3dof_raps_base.ini",
        "section3dof_multisine.ini"};
    size_t i;
    for (i = 0; i < sizeof(names) / sizeof(names[0]); ++i)
    {
        char path[512];
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        aenl_sim_result_t res;
        aenl_err_t err;
        aenl_err_clear(&err);
        (void)snprintf(path, sizeof(path), "%s%s", EXAMPLES, names[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
        TEST_ASSERT_TRUE(res.n_samples > 500);
        aenl_sim_result_free(&res);
    }
}

static void test_ini_values_and_units(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_sim_load_ini(EXAMPLES "paper_flap_freeplay.ini", &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_SECTION3DOF, m.type);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_LAW_FREEPLAY, m.law[AENL_SIM_DOF_FLAP].kind);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 2.0 * DEG, m.law[AENL_SIM_DOF_FLAP].delta);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, -1.0 * DEG, m.law[AENL_SIM_DOF_FLAP].x_f);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 1.0 * DEG, m.x0[AENL_SIM_DOF_PITCH]);
    TEST_ASSERT_EQUAL_DOUBLE(15.0, m.section.velocity);
    TEST_ASSERT_EQUAL_DOUBLE(0.127, m.section.b); /* Conner default */
    TEST_ASSERT_EQUAL_DOUBLE(3.0, r.snr);
    TEST_ASSERT_EQUAL_UINT64(42, r.noise_seed);
    TEST_ASSERT_EQUAL_DOUBLE(1e-10, r.rtol);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_sim_load_ini(EXAMPLES "paper_polynomial_pitch.ini", &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_LAW_POLYNOMIAL, m.law[AENL_SIM_DOF_PITCH].kind);
    TEST_ASSERT_EQUAL_size_t(3, m.law[AENL_SIM_DOF_PITCH].n_coeffs);
    TEST_ASSERT_EQUAL_DOUBLE(3.0, m.law[AENL_SIM_DOF_PITCH].coeffs[2]);
    TEST_ASSERT_EQUAL_INT(1, m.airfoil.ic_forcing);
    /* Radians without the suffix; flutter analysis needs no [run]. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK,
        aenl_sim_load_ini(write_tmp("rad.ini", GOOD_MODEL "[pitch]\nlaw = freeplay\ndelta = 0.01\n"
                                                          "alpha_f = -0.005\n"),
                          &m, NULL, &err),
        err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(0.01, m.law[AENL_SIM_DOF_PITCH].delta);
    TEST_ASSERT_EQUAL_DOUBLE(-0.005, m.law[AENL_SIM_DOF_PITCH].x_f);
}

/* Write m and run with aenl_sim_write_ini to file `name` and load it back. */
static void write_and_load(const char *name, const aenl_sim_model_t *m, const aenl_sim_run_t *run,
                           aenl_sim_model_t *back, aenl_sim_run_t *rback)
{
    char path[512];
    aenl_err_t err;
    (void)snprintf(path, sizeof(path), "%s", write_tmp(name, ""));
    FILE *fp = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(fp);
    aenl_sim_write_ini(fp, m, run);
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, back, rback, &err), err.msg);
}

/* The writer and the reader agree: every field written comes back bit for bit (%.17g). */
static void test_ini_write_reads_back(void)
{
    for (int type = 0; type < 2; ++type)
    {
        aenl_sim_model_t m, back;
        aenl_sim_run_t run, rback;
        aenl_sim_model_default(&m, (aenl_sim_type_t)type);
        aenl_sim_run_default(&run, (aenl_sim_type_t)type);
        m.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
        m.law[AENL_SIM_DOF_PITCH].delta = 0.0123456789;
        m.law[AENL_SIM_DOF_PITCH].x_f = -0.00321;
        m.law[AENL_SIM_DOF_PITCH].preload = 0.001;
        m.law[AENL_SIM_DOF_PITCH].inner_stiffness = 0.25;
        m.law[AENL_SIM_DOF_PLUNGE].kind = AENL_SIM_LAW_POLYNOMIAL;
        m.law[AENL_SIM_DOF_PLUNGE].n_coeffs = 3;
        m.law[AENL_SIM_DOF_PLUNGE].coeffs[0] = 1.0;
        m.law[AENL_SIM_DOF_PLUNGE].coeffs[1] = -0.1;
        m.law[AENL_SIM_DOF_PLUNGE].coeffs[2] = 3.3;
        if (type == 1)
        {
            m.law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_HYSTERESIS;
            m.law[AENL_SIM_DOF_FLAP].delta = 0.02;
            m.law[AENL_SIM_DOF_FLAP].x_f = 0.005;
            m.law[AENL_SIM_DOF_FLAP].preload = 0.004;
        }
        m.x0[AENL_SIM_DOF_PITCH] = 0.0174;
        m.v0[AENL_SIM_DOF_PLUNGE] = -0.003;
        m.initial = type == 0 ? AENL_SIM_INITIAL_ESTIMATE : AENL_SIM_INITIAL_GIVEN;
        run.turbulence = 1;
        run.turb_intensity = 0.011;
        run.turb_length = type == 0 ? 2.5 : 0.3;
        run.turb_seed = 12345678901ull;
        run.turb_spectrum = type == 1 ? AENL_SIM_GUST_DRYDEN : AENL_SIM_GUST_FIRST_ORDER;
        run.snr = 3.25;
        run.noise_seed = 77u;
        run.duration = type == 0 ? 123.5 : 2.5;
        run.dt = type == 0 ? 0.25 : 0.002;
        write_and_load("written.ini", &m, &run, &back, &rback);
        TEST_ASSERT_EQUAL_INT(m.type, back.type);
        TEST_ASSERT_EQUAL_MEMORY(&m.law, &back.law, sizeof(m.law));
        TEST_ASSERT_EQUAL_MEMORY(m.x0, back.x0, sizeof(m.x0));
        TEST_ASSERT_EQUAL_MEMORY(m.v0, back.v0, sizeof(m.v0));
        TEST_ASSERT_EQUAL_INT(m.initial, back.initial);
        /* not said: not written, and read back as not said */
        m.initial = AENL_SIM_INITIAL_AUTO;
        write_and_load("written_auto.ini", &m, &run, &back, &rback);
        TEST_ASSERT_EQUAL_INT(AENL_SIM_INITIAL_AUTO, back.initial);
        if (type == 0)
        {
            TEST_ASSERT_EQUAL_MEMORY(&m.airfoil, &back.airfoil, sizeof(m.airfoil));
        }
        else
        {
            TEST_ASSERT_EQUAL_MEMORY(&m.section, &back.section, sizeof(m.section));
        }
        TEST_ASSERT_EQUAL_MEMORY(&run, &rback, sizeof(run));
    }
}

static void test_ini_kick_train(void)
{
    /* Values and units, then the writer's round trip. */
    const char *path = write_tmp("kicks.ini", "[model]\ntype = section3dof\nvelocity = 12\n"
                                              "[excitation]\ntype = kicks\nrate_deg = 20\n"
                                              "dof = flap\nevery = 1.5\nsign = alternate\n"
                                              "seed = 9\n[run]\nduration = 6\ndt = 0.005\n");
    aenl_sim_model_t m, back;
    aenl_sim_run_t r, rback;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(1, r.kicks);
    TEST_ASSERT_EQUAL_INT(0, r.turbulence);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_FLAP, r.kick_dof);
    TEST_ASSERT_EQUAL_DOUBLE(1.5, r.kick_every);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 20.0 * DEG, r.kick_rate);
    TEST_ASSERT_EQUAL_DOUBLE(r.kick_rate, r.kick_rate_max); /* rate_max defaults to rate */
    TEST_ASSERT_EQUAL_INT(AENL_SIM_KICK_ALTERNATE, r.kick_sign);
    TEST_ASSERT_EQUAL_UINT64(9u, r.kick_seed);
    r.kick_rate_max = 0.5;
    r.kick_sign = AENL_SIM_KICK_RANDOM;
    write_and_load("kicks_written.ini", &m, &r, &back, &rback);
    TEST_ASSERT_EQUAL_MEMORY(&r, &rback, sizeof(r));

    /* Rejected: the [excitation] section after GOOD_MODEL, the message's file:line and key. */
    static const struct
    {
        const char *name, *excitation, *where, *what;
    } bad[] = {
        {"kick_no_dof.ini", "type = kicks\nevery = 2\nrate = 1\n", ":4:", "'dof'"},
        {"kick_flap_2dof.ini", "type = kicks\ndof = flap\nevery = 2\nrate = 1\n",
         ":6:", "pitch or plunge"},
        {"kick_no_every.ini", "type = kicks\ndof = pitch\nrate = 1\n", ":4:", "'every'"},
        {"kick_plunge_deg.ini", "type = kicks\ndof = plunge\nevery = 2\nrate_deg = 1\n",
         ":8:", "rate_deg"},
        {"kick_turb_key.ini", "type = kicks\ndof = pitch\nevery = 2\nrate = 1\nintensity = 0.1\n",
         ":9:", "intensity"},
        {"turb_kick_key.ini", "type = turbulence\nintensity = 0.1\nevery = 2\n",
         ":7:", "type = kicks"},
        {"kick_every.ini", "type = kicks\ndof = pitch\nevery = 2.25\nrate = 1\n", "",
         "whole number"},
        {"kick_rate_max.ini", "type = kicks\ndof = pitch\nevery = 2\nrate = 1\nrate_max = 0.5\n",
         ":9:", "rate_max"},
        {"kick_sign.ini", "type = kicks\ndof = pitch\nevery = 2\nrate = 1\nsign = up\n",
         ":9:", "sign"},
    };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i)
    {
        char buf[512], where[64];
        (void)snprintf(buf, sizeof(buf),
                       GOOD_MODEL "[excitation]\n%s[run]\nduration = 6\ndt = 0.5\n",
                       bad[i].excitation);
        (void)snprintf(where, sizeof(where), "%s%s", bad[i].name, bad[i].where);
        expect_error(bad[i].name, buf, where, bad[i].what);
    }
}

static void test_ini_forced_excitation(void)
{
    /* Values and units of a sweep and a multisine, then the writer's round trip. */
    const char *path = write_tmp("sweep.ini", "[model]\ntype = section3dof\nvelocity = 12\n"
                                              "[excitation]\ntype = sweep\ndof = flap\n"
                                              "amplitude_deg = 0.5\nf_start = 1\nf_end = 20\n"
                                              "law = log\n[run]\nduration = 6\ndt = 0.005\n");
    aenl_sim_model_t m, back;
    aenl_sim_run_t r, rback;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_FORCE_SWEEP, r.force);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_FLAP, r.force_dof);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.5 * DEG, r.force_amp);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, r.force_f0);
    TEST_ASSERT_EQUAL_DOUBLE(20.0, r.force_f1);
    TEST_ASSERT_EQUAL_INT(1, r.force_log);
    write_and_load("sweep_written.ini", &m, &r, &back, &rback);
    TEST_ASSERT_EQUAL_MEMORY(&r, &rback, sizeof(r));

    path = write_tmp("multisine.ini", GOOD_MODEL "[excitation]\ntype = multisine\ndof = plunge\n"
                                                 "rms = 0.01\nf_min = 0.01\nf_max = 0.2\n"
                                                 "period = 200\nseed = 7\n"
                                                 "[run]\nduration = 400\ndt = 0.5\n");
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_FORCE_MULTISINE, r.force);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_PLUNGE, r.force_dof);
    TEST_ASSERT_EQUAL_DOUBLE(0.01, r.force_amp);
    TEST_ASSERT_EQUAL_DOUBLE(200.0, r.force_period);
    TEST_ASSERT_EQUAL_UINT64(7u, r.force_seed);
    write_and_load("multisine_written.ini", &m, &r, &back, &rback);
    TEST_ASSERT_EQUAL_MEMORY(&r, &rback, sizeof(r));

    /* Rejected: the [excitation] section after GOOD_MODEL (dt 0.5: Nyquist 1). */
    static const struct
    {
        const char *name, *excitation, *where, *what;
    } bad[] = {
        {"sweep_no_amp.ini", "type = sweep\ndof = pitch\nf_start = 0.1\nf_end = 0.2\n",
         ":4:", "'amplitude_deg'"},
        {"sweep_no_end.ini", "type = sweep\ndof = pitch\namplitude = 0.1\nf_start = 0.1\n",
         ":4:", "'f_end'"},
        {"sweep_nyquist.ini",
         "type = sweep\ndof = pitch\namplitude = 0.1\nf_start = 0.1\n"
         "f_end = 1.5\n",
         "", "Nyquist"},
        {"sweep_law.ini",
         "type = sweep\ndof = pitch\namplitude = 0.1\nf_start = 0.1\n"
         "f_end = 0.2\nlaw = cubic\n",
         ":10:", "law"},
        {"sweep_rms.ini",
         "type = sweep\ndof = pitch\namplitude = 0.1\nf_start = 0.1\n"
         "f_end = 0.2\nrms = 1\n",
         ":10:", "rms"},
        {"ms_plunge_deg.ini",
         "type = multisine\ndof = plunge\nrms_deg = 1\nf_min = 0.1\n"
         "f_max = 0.2\n",
         ":7:", "rms_deg"},
        {"ms_band.ini", "type = multisine\ndof = pitch\nrms = 0.1\nf_min = 0.3\nf_max = 0.2\n", "",
         "f_max"},
        {"ms_no_line.ini",
         "type = multisine\ndof = pitch\nrms = 0.1\nf_min = 0.101\n"
         "f_max = 0.102\n",
         "", "no line"},
        {"ms_lines.ini",
         "type = multisine\ndof = pitch\nrms = 0.1\nf_min = 0.001\n"
         "f_max = 0.9\nperiod = 2000\n",
         "", "lines"},
        {"ms_flap_2dof.ini",
         "type = multisine\ndof = flap\nrms = 0.1\nf_min = 0.1\n"
         "f_max = 0.2\n",
         ":6:", "pitch or plunge"},
    };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i)
    {
        char buf[512], where[64];
        (void)snprintf(buf, sizeof(buf),
                       GOOD_MODEL "[excitation]\n%s[run]\nduration = 20\ndt = 0.5\n",
                       bad[i].excitation);
        (void)snprintf(where, sizeof(where), "%s%s", bad[i].name, bad[i].where);
        expect_error(bad[i].name, buf, where, bad[i].what);
    }
}

static void test_ini_rejects_bad_files(void)
{
    const char *run = "[run]\nduration = 10\ndt = 0.5\n";
    char buf[512];
    expect_error("unknown_key.ini", GOOD_MODEL "mass_ratio = 3\n[run]\nduration = 10\ndt = 0.5\n",
                 "unknown_key.ini:4:", "mass_ratio");
    expect_error("unknown_section.ini", GOOD_MODEL "[runn]\nduration = 10\n",
                 "unknown_section.ini:4:", "[runn]");
    expect_error("empty_unknown_section.ini", GOOD_MODEL "[extra]\n[run]\nduration = 1\ndt = 0.5\n",
                 "empty_unknown_section.ini:4:", "[extra]");
    expect_error("missing_dt.ini", GOOD_MODEL "[run]\nduration = 10\n",
                 "missing_dt.ini:4:", "'dt'");
    expect_error("missing_run.ini", GOOD_MODEL, "missing_run.ini", "duration");
    expect_error("bad_estimate.ini",
                 GOOD_MODEL "[initial]\nestimate = maybe\n[run]\nduration = 10\ndt = 0.5\n",
                 "bad_estimate.ini:5:", "true or false");
    expect_error("missing_ustar.ini",
                 "[model]\ntype = airfoil2dof\n[run]\nduration = 1\ndt = 0.5\n",
                 "missing_ustar.ini:1:", "ustar");
    expect_error("missing_type.ini", "[model]\nustar = 3\n[run]\nduration = 1\ndt = 0.5\n",
                 "missing_type.ini:1:", "type");
    (void)snprintf(buf, sizeof(buf), GOOD_MODEL "[pitch]\nlaw = freeplay\nalpha_f_deg = 0\n%s",
                   run);
    expect_error("missing_delta.ini", buf, "missing_delta.ini:4:", "delta");
    (void)snprintf(buf, sizeof(buf), GOOD_MODEL "[pitch]\nlaw = polynomial\n%s", run);
    expect_error("missing_coeffs.ini", buf, "missing_coeffs.ini:4:", "coeffs");
    expect_error("negative_duration.ini", GOOD_MODEL "[run]\nduration = -5\ndt = 0.5\n",
                 "negative_duration.ini:5:", "duration");
    expect_error("zero_dt.ini", GOOD_MODEL "[run]\nduration = 5\ndt = 0\n", "zero_dt.ini:6:", "dt");
    expect_error("negative_dt.ini", GOOD_MODEL "[run]\nduration = 5\ndt = -0.1\n",
                 "negative_dt.ini:6:", "dt");
    expect_error("nan.ini",
                 "[model]\ntype = airfoil2dof\nustar = nan\n[run]\nduration = 5\ndt = 1\n",
                 "nan.ini:3:", "ustar");
    expect_error("inf.ini", GOOD_MODEL "mu = inf\n[run]\nduration = 5\ndt = 1\n",
                 "inf.ini:4:", "mu");
    expect_error("text.ini", GOOD_MODEL "[run]\nduration = ten\ndt = 1\n",
                 "text.ini:5:", "duration");
    expect_error("dup.ini", GOOD_MODEL "ustar = 4\n[run]\nduration = 5\ndt = 1\n",
                 "dup.ini:4:", "ustar");
    (void)snprintf(buf, sizeof(buf),
                   GOOD_MODEL "[pitch]\nlaw = freeplay\ndelta = 0.01\ndelta_deg = 1\n%s", run);
    expect_error("dup_deg.ini", buf, "dup_deg.ini:7:", "delta");
    (void)snprintf(buf, sizeof(buf), GOOD_MODEL "[flap]\nlaw = freeplay\ndelta_deg = 1\n%s", run);
    expect_error("flap_on_2dof.ini", buf, "flap_on_2dof.ini:4:", "[flap]");
    (void)snprintf(buf, sizeof(buf), GOOD_MODEL "[pitch]\nlaw = backlash\n%s", run);
    expect_error("bad_law.ini", buf, "bad_law.ini:5:", "law");
    (void)snprintf(buf, sizeof(buf), GOOD_MODEL "[plunge]\nlaw = freeplay\ndelta_deg = 1\n%s", run);
    expect_error("plunge_deg.ini", buf, "plunge_deg.ini:6:", "delta_deg");
    expect_error("dt_above_duration.ini", GOOD_MODEL "[run]\nduration = 1\ndt = 2\n",
                 "dt_above_duration.ini:6:", "dt");
    expect_error("syntax.ini", GOOD_MODEL "just words\n[run]\nduration = 1\ndt = 0.5\n",
                 "syntax.ini:4:", "syntax");
    expect_error("bad_seed.ini",
                 GOOD_MODEL "[run]\nduration = 1\ndt = 0.5\n[noise]\nsnr = 3\nseed = -1\n",
                 "bad_seed.ini:9:", "seed");
    expect_error("zero_snr.ini", GOOD_MODEL "[run]\nduration = 1\ndt = 0.5\n[noise]\nsnr = 0\n",
                 "zero_snr.ini:8:", "snr");
    expect_error("3dof_key.ini",
                 "[model]\ntype = section3dof\nvelocity = 10\nustar = 3\n"
                 "[run]\nduration = 1\ndt = 0.5\n",
                 "3dof_key.ini:4:", "ustar");
    expect_error("bad_spectrum.ini",
                 GOOD_MODEL "[excitation]\ntype = turbulence\nintensity = 0.01\n"
                            "spectrum = von_karman\n[run]\nduration = 1\ndt = 0.5\n",
                 "bad_spectrum.ini:7:", "spectrum");
    {
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        aenl_err_t err;
        aenl_err_clear(&err);
        TEST_ASSERT_EQUAL_INT(AENL_E_IO,
                              aenl_sim_load_ini(AENL_TEST_TMP_DIR "/absent.ini", &m, &r, &err));
        TEST_ASSERT_NOT_NULL(strstr(err.msg, "absent.ini"));
    }
}

static double stdev(const double *y, size_t n)
{
    double m = 0.0, v = 0.0;
    size_t k;
    for (k = 0; k < n; ++k)
    {
        m += y[k];
    }
    m /= (double)n;
    for (k = 0; k < n; ++k)
    {
        v += (y[k] - m) * (y[k] - m);
    }
    return sqrt(v / (double)n);
}

static void test_noise_has_the_stated_snr_and_is_reproducible(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t noisy, noisy2, clean;
    aenl_err_t err;
    size_t c, k, n;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_sim_load_ini(EXAMPLES "paper_flap_freeplay.ini", &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &noisy, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &noisy2, &err));
    r.snr = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &clean, &err));
    n = clean.n_samples;
    /* Same seed: the same bytes. */
    TEST_ASSERT_EQUAL_MEMORY(noisy.y, noisy2.y, n * noisy.n_channels * sizeof(double));
    for (c = 0; c < clean.n_channels; ++c)
    {
        double d[10001];
        const double *yc = clean.y + c * n, *yn = noisy.y + c * n;
        double snr;
        TEST_ASSERT_TRUE(n <= 10001);
        for (k = 0; k < n; ++k)
        {
            d[k] = yn[k] - yc[k];
        }
        snr = stdev(yc, n) / stdev(d, n);
        TEST_ASSERT_DOUBLE_WITHIN(0.1, 3.0, snr); /* 10^4 samples: ~1 % sampling error */
    }
    aenl_sim_result_free(&noisy);
    aenl_sim_result_free(&noisy2);
    aenl_sim_result_free(&clean);
}

static void test_turbulence_is_seeded_and_linear_in_intensity(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t a, b, c, z, off;
    aenl_err_t err;
    size_t k, n;
    double d = 0.0, s1, s2;
    aenl_err_clear(&err);
    /* Linear section below flutter, at rest, driven by the gust only. */
    aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
    m.section.velocity = 12.0;
    aenl_sim_run_default(&r, AENL_SIM_SECTION3DOF);
    r.duration = 10.0;
    r.dt = 2e-3;
    r.turbulence = 1;
    r.turb_intensity = 0.01;
    r.turb_seed = 5;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &a, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &b, &err));
    n = a.n_samples;
    TEST_ASSERT_EQUAL_MEMORY(a.y, b.y, n * a.n_channels * sizeof(double));
    r.turb_intensity = 0.02;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &c, &err));
    s1 = stdev(a.y + 2 * n, n);
    s2 = stdev(c.y + 2 * n, n);
    TEST_ASSERT_TRUE(s1 > 1e-5); /* the flap moves */
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 2.0, s2 / s1);
    /* Intensity 0 equals a run without turbulence. */
    r.turb_intensity = 0.0;
    m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &z, &err));
    r.turbulence = 0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &off, &err));
    for (k = 0; k < n * z.n_channels; ++k)
    {
        d = fmax(d, fabs(z.y[k] - off.y[k]));
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-10, 0.0, d);
    /* A different seed gives a different record. */
    r.turbulence = 1;
    r.turb_intensity = 0.01;
    r.turb_seed = 6;
    m.x0[AENL_SIM_DOF_PITCH] = 0.0;
    aenl_sim_result_free(&b);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &b, &err));
    TEST_ASSERT_TRUE(fabs(stdev(b.y + 2 * n, n) - s1) > 0.0);
    TEST_ASSERT_TRUE(memcmp(a.y, b.y, n * sizeof(double)) != 0);
    aenl_sim_result_free(&a);
    aenl_sim_result_free(&b);
    aenl_sim_result_free(&c);
    aenl_sim_result_free(&z);
    aenl_sim_result_free(&off);
}

static void test_simulate_rejects_bad_arguments(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t res;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_run_default(&r, AENL_SIM_AIRFOIL2DOF);
    r.duration = 10.0;
    r.dt = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &r, &res, &err));
    TEST_ASSERT_NULL(res.t);
    r.dt = 0.5;
    m.airfoil.mu = NAN;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &r, &res, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "mu"));
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
    m.law[AENL_SIM_DOF_PITCH].delta = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &r, &res, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, NULL, &res, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &r, NULL, &err));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ini_examples_load_and_run);
    RUN_TEST(test_ini_values_and_units);
    RUN_TEST(test_ini_rejects_bad_files);
    RUN_TEST(test_ini_kick_train);
    RUN_TEST(test_ini_forced_excitation);
    RUN_TEST(test_ini_write_reads_back);
    RUN_TEST(test_noise_has_the_stated_snr_and_is_reproducible);
    RUN_TEST(test_turbulence_is_seeded_and_linear_in_intensity);
    RUN_TEST(test_simulate_rejects_bad_arguments);
    return UNITY_END();
}
