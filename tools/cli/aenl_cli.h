/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_cli.h
 * @brief The subcommands of the single `aenl` command. Each is a thin layer over the host library.
 *
 * Every subcommand returns the process exit status: 0 success, 2 bad input or usage (one message on
 * stderr through aenl_cli_error, nothing on stdout, no output file left), 1 an internal failure.
 */
#ifndef AENL_CLI_H
#define AENL_CLI_H

#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_io.h"
#include "aenl_tools/aenl_progress.h"

#define AENL_EXIT_OK    0
#define AENL_EXIT_FAIL  1
#define AENL_EXIT_USAGE 2

/** Print "aenl <cmd>: <message>\n" on stderr. */
void aenl_cli_error(const char *cmd, const char *fmt, ...) AENL_PRINTF_LIKE(2, 3);

/** Exit status for a host status: 0 for AENL_OK, 2 otherwise. */
int aenl_cli_exit(aenl_status_t st);

/** Parse a finite double; on failure print "<opt>: ..." and return -1. */
int aenl_cli_parse_double(const char *cmd, const char *opt, const char *s, double *out);
/** Parse a whole number in [lo, hi]; on failure print and return -1. */
int aenl_cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi,
                        long *out);
/**
 * @brief An argument no option of `cmd` took: "-x" is an unknown option; otherwise it fills *slot
 *        when that is still empty, and a second one is an error naming `what` ("data file").
 * @return 0, or -1 after printing the error.
 */
int aenl_cli_positional(const char *cmd, const char *arg, const char **slot, const char *what);
/** The value after option argv[*i] (advancing *i), or NULL after printing "needs a value". */
const char *aenl_cli_value(const char *cmd, int argc, char **argv, int *i);

/** The command's time column by name (--time COL); NULL (the default): known by its name. */
void aenl_cli_set_time_column(const char *name);
/** The name set by aenl_cli_set_time_column, or NULL. */
const char *aenl_cli_time_column(void);
/** Notes on stderr on (1, the default) or off (0: a JSON output, whose stderr stays quiet). */
void aenl_cli_set_notes(int on);
/** A progress bar on stderr (cli_progress.c), drawn only when stderr is a terminal (and
 *  $AENL_NO_PROGRESS is unset). Pass &bar.progress to a library function that reports. */
typedef struct aenl_cli_bar
{
    const char *cmd, *what;
    int on, drawn;
    long shown;               /* cells last drawn */
    double t0, t_shown;       /* start, and the time last drawn (s) */
    aenl_progress_t progress; /* reports to aenl_cli_bar_update */
} aenl_cli_bar_t;
void aenl_cli_bar_begin(aenl_cli_bar_t *b, const char *cmd, const char *what);
void aenl_cli_bar_update(void *ctx, size_t done, size_t total);
/** Erase the bar (when drawn). */
void aenl_cli_bar_end(aenl_cli_bar_t *b);

/** The note on stderr for a record without a time column (how it is read, how to name one). */
void aenl_cli_note_no_time(const char *cmd, const char *path);
/** The run's notes on stderr when print (the run succeeded), else dropped; either way emptied. */
void aenl_cli_flush_notes(int print);
/** That note's text (without the command's prefix) into buf, for a JSON output's notes. */
void aenl_cli_no_time_text(const char *path, char *buf, size_t n);
/** 1 for the record's time column: the one --time names, else aenl_csv_is_time_name's. */
int aenl_cli_is_time_column(const char *name);
/** Checks time value t of data row `row` (from 1; t_prev the row before's) of column `column`:
 *  present, increasing and on the record's even step (aenl_time_steps_take, s); 0, or -1 with
 *  the message naming the file, column and row in err. */
int aenl_cli_time_value_check(aenl_time_steps_t *s, double t, double t_prev, size_t row,
                              const char *path, const char *column, aenl_err_t *err);
/** Column of `channel` (or of the only non-time column when NULL); -1 after printing why. */
long aenl_cli_pick_channel(const char *cmd, const aenl_table_t *t, const char *path,
                           const char *channel);

/** 1 when column col is one of the n_in columns in[]. */
int aenl_cli_is_input(const size_t *in, size_t n_in, size_t col);
/**
 * The record's channels: every column but time and the inputs (in, n_in), or only column `only`
 * (when >= 0), into chan and names (*nz of them, at most max). Returns 0, or -1 after one message
 * (none left, more than max, a constant one).
 */
int aenl_cli_record_channels(const char *cmd, const aenl_table_t *t, const char *path,
                             const size_t *in, size_t n_in, long only, size_t max,
                             const double **chan, const char **names, size_t *nz);

/** Largest sample magnitude the subcommands take: squares (variances) stay far from overflow. */
#define AENL_CLI_MAX_ABS 1e120

/**
 * @brief Check a record before use: the column --time names exists (a note on stderr when the
 *        record has no time column at all), every time column (aenl_cli_is_time_column) holds
 * finite, strictly increasing, equally spaced values (within AENL_TIME_STEP_TOL), and column `col`
 * (all non-time columns when col < 0) holds at least one finite value and none beyond
 * +-AENL_CLI_MAX_ABS. On failure prints one message naming the file, the column and the data row,
 * and returns -1; else 0.
 */
int aenl_cli_check_record(const char *cmd, const aenl_table_t *t, const char *path, long col);

/* ---- figures (cli_figures.c) ---- */

/** Figures written so far and folders created (undone if a later step fails). */
typedef struct
{
    char **files;
    size_t n_files, cap_files;
    char *dirs[16];
    size_t n_dirs;
} aenl_cli_figs_t;

/** The run fails: undo every output it wrote (aenl_outfile_abort_all), then remove the folders
 *  it made (those left empty). */
void aenl_cli_figs_rollback(aenl_cli_figs_t *o);
/** Forget the lists (the files stay). */
void aenl_cli_figs_free(aenl_cli_figs_t *o);
/** Remember a figure written. */
aenl_status_t aenl_cli_figs_add(aenl_cli_figs_t *o, const char *path, aenl_err_t *err);
/** mkdir -p dir, remembering the folders made. */
aenl_status_t aenl_cli_figs_mkdir(aenl_cli_figs_t *o, const char *dir, aenl_err_t *err);
/* The figures' data files and names are the library's (aenl_plot.h). */

int aenl_cmd_moments(int argc, char **argv);
int aenl_cmd_simulate(int argc, char **argv);
int aenl_cmd_flutter(int argc, char **argv);
int aenl_cmd_plot(int argc, char **argv);
int aenl_cmd_demo(int argc, char **argv);
int aenl_cmd_bench(int argc, char **argv);
/** `aenl bench simulate` (tools/cli/bench_simulate.c). */
int aenl_bench_simulate(int argc, char **argv);
/** `aenl fit` (tools/cli/cmd_fit.c). */
int aenl_cmd_fit(int argc, char **argv);
/** `aenl bench fit` (tools/cli/bench_fit.c). */
int aenl_bench_fit(int argc, char **argv);
/** `aenl identify` (tools/cli/cmd_identify.c). */
int aenl_cmd_identify(int argc, char **argv);
/** What `aenl identify` by its default method was asked for. */
typedef struct
{
    const char *channel;      /**< only this channel, or NULL: all */
    const char *inputs;       /**< comma-separated column names, or NULL */
    int json;                 /**< JSON instead of the table */
    double level;             /**< family-wise level */
    size_t n_controls;        /**< linear controls tested */
    int impulsive;            /**< the record is driven by impulses */
    const char *plot_dir;     /**< the figures' folder, or NULL */
    const char *control_path; /**< a linear control's record is written here, or NULL */
} aenl_identify_test_req_t;

/** `aenl identify` by its default method, the likelihood-based test, on `path` as req asks
 *  (tools/cli/cmd_identify_test.c); the exit status. */
int aenl_identify_by_test(const char *path, const aenl_identify_test_req_t *req);
/** `aenl identify --method moments` on `path` (only `channel` when not NULL) with opts, against
 *  the baseline INI `model` when not NULL, as JSON when json, its figures in plot_dir when not
 *  NULL (tools/cli/cmd_identify.c); the exit status. */
int aenl_identify_by_moments(const char *path, const char *channel,
                             const aenl_identify_opts_t *opts, const char *model, int json,
                             const char *plot_dir);
/** `aenl diagnose` (tools/cli/cmd_diagnose.c). */
int aenl_cmd_diagnose(int argc, char **argv);
/** `aenl bench diagnose` (tools/cli/bench_diagnose.c). */
int aenl_bench_diagnose(int argc, char **argv);
/** `aenl bench identify` (tools/cli/bench_identify.c). */
int aenl_bench_identify(int argc, char **argv);
/** `aenl bench null`: the level of identify --method test on linear records (bench_null.c). */
int aenl_bench_null(int argc, char **argv);
/** Run `name`, a program in aenl's own folder, with args (tools/cli/cli_run.c). */
int aenl_bench_run_sibling(const char *name, char *const *args, int n_args);

#endif /* AENL_CLI_H */
