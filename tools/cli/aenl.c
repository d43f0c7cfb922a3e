/* SPDX-License-Identifier: MIT */
/**
 * @file aenl.c
 * @brief `aenl <subcommand>`: dispatch, usage, and the helpers every subcommand shares.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"

typedef struct
{
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} subcommand_t;

static const subcommand_t k_subcommands[] = {
    {"simulate", aenl_cmd_simulate, "simulate an aeroelastic model (INI) -> CSV"},
    {"flutter", aenl_cmd_flutter, "linear flutter speed and frequency of a model (INI)"},
    {"moments", aenl_cmd_moments, "conditional mean/variance curves of a channel -> CSV (+ plot)"},
    {"identify", aenl_cmd_identify, "classify each channel, name the nonlinear one (JSON, plots)"},
    {"fit", aenl_cmd_fit, "EM switching state-space identification"},
    {"diagnose", aenl_cmd_diagnose,
     "model vs measurement: name the missing effect, update the model"},
    {"plot", aenl_cmd_plot, "figures from the CSV outputs of the other subcommands"},
    {"demo", aenl_cmd_demo, "the worked examples end to end, with figures"},
    {"bench", aenl_cmd_bench, "performance figures against simple references"},
};

static void usage(FILE *fp)
{
    fprintf(fp, "usage: aenl <subcommand> [options]   (aenl <subcommand> --help for its options)\n"
                "       aenl --version\n\n"
                "Every subcommand takes --opt VALUE or --opt=VALUE; after --, every argument is\n"
                "a file name, even one that starts with '-'.\n\n");
    for (size_t i = 0; i < sizeof(k_subcommands) / sizeof(k_subcommands[0]); ++i)
    {
        fprintf(fp, "  %-10s %s\n", k_subcommands[i].name, k_subcommands[i].summary);
    }
}

void aenl_cli_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "aenl %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

int aenl_cli_exit(aenl_status_t st)
{
    return st == AENL_OK ? AENL_EXIT_OK : AENL_EXIT_USAGE;
}

int aenl_cli_parse_double(const char *cmd, const char *opt, const char *s, double *out)
{
    char *end = NULL;
    if (s == NULL || *s == '\0')
    {
        aenl_cli_error(cmd, "%s needs a number", opt);
        return -1;
    }
    const double v = aenl_strtod_decimal(s, &end);
    if (end == s || *end != '\0' || !isfinite(v))
    {
        aenl_cli_error(cmd, "%s: '%s' is not a finite number", opt, s);
        return -1;
    }
    *out = v;
    return 0;
}

int aenl_cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi,
                        long *out)
{
    char *end = NULL;
    if (s == NULL || *s == '\0')
    {
        aenl_cli_error(cmd, "%s needs a whole number", opt);
        return -1;
    }
    const long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi)
    {
        aenl_cli_error(cmd, "%s: '%s' is not a whole number in %ld..%ld", opt, s, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int aenl_cli_positional(const char *cmd, const char *arg, const char **slot, const char *what)
{
    if (arg[0] == '-' && arg[1] != '\0')
    {
        aenl_cli_error(cmd, "unknown option %s (aenl %s --help)", arg, cmd);
        return -1;
    }
    if (*slot != NULL)
    {
        aenl_cli_error(cmd, "one %s only (got '%s' and '%s')", what, *slot, arg);
        return -1;
    }
    *slot = arg;
    return 0;
}

const char *aenl_cli_value(const char *cmd, int argc, char **argv, int *i)
{
    if (*i + 1 >= argc)
    {
        aenl_cli_error(cmd, "option %s needs a value", argv[*i]);
        return NULL;
    }
    *i += 1;
    return argv[*i];
}

/* The arguments as every subcommand's parser reads them: "--opt=value" becomes "--opt" "value",
 * and after "--" an argument that starts with '-' becomes the same path written "./-name", so
 * no subcommand needs to know either convention. *out is NULL-terminated; the strings made
 * here are listed in *owned (free with free_args). Returns the new count, or -1 out of memory. */
static int normalise_args(int argc, char **argv, char ***out, char ***owned)
{
    char **v = (char **)calloc(2u * (size_t)argc + 1u, sizeof(char *));
    char **own = (char **)calloc(2u * (size_t)argc + 1u, sizeof(char *));
    if (v == NULL || own == NULL)
    {
        free((void *)v);
        free((void *)own);
        return -1;
    }
    int n = 0;
    int n_own = 0;
    int files_only = 0;
    for (int i = 0; i < argc; ++i)
    {
        const char *a = argv[i];
        const char *eq = strchr(a, '=');
        if (!files_only && i > 0 && strcmp(a, "--") == 0)
        {
            files_only = 1;
        }
        else if (!files_only && a[0] == '-' && a[1] == '-' && eq != NULL && eq > a + 2)
        {
            const size_t len = (size_t)(eq - a);
            char *opt = (char *)malloc(len + 1u);
            if (opt == NULL)
            {
                *out = v;
                *owned = own;
                return -1;
            }
            memcpy(opt, a, len);
            opt[len] = '\0';
            own[n_own++] = opt;
            v[n++] = opt;
            v[n++] = (char *)(eq + 1); /* points into argv, which outlives the run */
        }
        else if (files_only && a[0] == '-' && a[1] != '\0')
        {
            const size_t len = strlen(a);
            char *path = (char *)malloc(len + 3u);
            if (path == NULL)
            {
                *out = v;
                *owned = own;
                return -1;
            }
            path[0] = '.';
            path[1] = '/';
            memcpy(path + 2, a, len + 1u);
            own[n_own++] = path;
            v[n++] = path;
        }
        else
        {
            v[n++] = argv[i];
        }
    }
    *out = v;
    *owned = own;
    return n;
}

static void free_args(char **v, char **owned)
{
    for (size_t i = 0; owned != NULL && owned[i] != NULL; ++i)
    {
        free(owned[i]);
    }
    free((void *)owned);
    free((void *)v);
}

static void on_signal(int sig)
{
    /* abort_all only calls unlink(2) and rename(2), which are async-signal-safe (aenl_io.c). */
    aenl_outfile_abort_all(); /* NOLINT(bugprone-signal-handler,cert-sig30-c) */
    (void)signal(sig, SIG_DFL);
    (void)raise(sig);
}

int main(int argc, char **argv)
{
    if (argc < 2)
    {
        usage(stderr);
        return AENL_EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
        strcmp(argv[1], "help") == 0)
    {
        usage(stdout);
        return AENL_EXIT_OK;
    }
    if (strcmp(argv[1], "--version") == 0)
    {
        printf("aenl %s\n", AENL_VERSION);
        return AENL_EXIT_OK;
    }
    (void)signal(SIGINT, on_signal); /* best effort: temporaries are also removed at exit */
    (void)signal(SIGTERM, on_signal);
    (void)signal(SIGHUP, on_signal); /* the terminal closed */
    for (size_t i = 0; i < sizeof(k_subcommands) / sizeof(k_subcommands[0]); ++i)
    {
        if (strcmp(argv[1], k_subcommands[i].name) == 0)
        {
            char **args = NULL;
            char **owned = NULL;
            const int n_args = normalise_args(argc - 1, argv + 1, &args, &owned);
            if (n_args < 0)
            {
                free_args(args, owned);
                aenl_cli_error(argv[1], "out of memory");
                return AENL_EXIT_FAIL;
            }
            aenl_outfile_run_begin();
            int rc = k_subcommands[i].run(n_args, args);
            free_args(args, owned);
            if (fflush(stdout) != 0 && rc == AENL_EXIT_OK)
            {
                aenl_cli_error(argv[1], "writing to standard output failed");
                rc = AENL_EXIT_FAIL;
            }
            aenl_cli_flush_notes(rc == AENL_EXIT_OK);
            if (rc == AENL_EXIT_OK)
            {
                aenl_outfile_run_keep();
            }
            /* nothing half-written survives, and a failed run leaves the user's files as they
             * were, whatever the path out */
            aenl_outfile_abort_all();
            return rc;
        }
    }
    aenl_cli_error(argv[1], "unknown subcommand (aenl --help lists them)");
    return AENL_EXIT_USAGE;
}
