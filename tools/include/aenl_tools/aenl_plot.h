/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_plot.h
 * @brief Host-only: run a checked-in gnuplot script (tools/plot/NAME.gp) to make a figure.
 *
 * The script reads its inputs from gnuplot variables given as name=value pairs (strings are quoted
 * for it) and writes to the variable `out`. The figure is produced under a temporary name and
 * renamed into place only when gnuplot succeeds (aenl_outfile_t), so no partial figure is left.
 * Scripts are looked up in $AENL_PLOT_DIR, the source tree, then the installed share folder.
 */
#ifndef AENL_TOOLS_PLOT_H
#define AENL_TOOLS_PLOT_H

#include <stddef.h>
#include <stdio.h>

#include "aenl_tools/aenl_io.h"

/** One gnuplot variable: `value` is passed as a string literal. */
typedef struct aenl_plot_var
{
    const char *name;
    const char *value;
} aenl_plot_var_t;

/** 1 when a gnuplot executable is on PATH. */
int aenl_plot_available(void);

/**
 * 1 when the figure file at path ends as a whole file of its format does ("png": the IEND
 * chunk; "svg": the closing tag; "pdf": the end-of-file marker), 0 when it is empty, cut short
 * or unreadable. aenl_plot_run checks every figure so before it replaces anything.
 */
int aenl_plot_file_complete(const char *path, const char *fmt);

/**
 * @brief Run the gnuplot script plot/`script`.gp (aenl_share_path) with the given variables,
 *        writing the figure to `out_path` as PNG, SVG or PDF after its extension (.png, .svg,
 *        .pdf, any case; PNG for a path without one, such as "-" or a device).
 * @return AENL_OK; AENL_E_ARG for a value gnuplot could not take (a quote or newline in it), an
 *         unknown script or another extension; AENL_E_IO when gnuplot is missing or fails (message
 * has its stderr tail).
 */
aenl_status_t aenl_plot_run(const char *script, const aenl_plot_var_t *vars, size_t n_vars,
                            const char *out_path, aenl_err_t *err);

/** Path of plot/`script`.gp into buf (size n): $AENL_PLOT_DIR first, then aenl_share_path. */
aenl_status_t aenl_plot_script_path(const char *script, char *buf, size_t n, aenl_err_t *err);

/* ---- what figures' data share ---- */

/**
 * Called with each figure a library figure function has written (its path), so that the caller
 * can list it and remove it again on a later failure; a status other than AENL_OK removes that
 * figure and stops the drawing with that status (err set).
 */
typedef aenl_status_t (*aenl_plot_done_fn)(void *ctx, const char *path, aenl_err_t *err);

/**
 * The record a figure is drawn from, as plain data: its file (titles carry its base name, figure
 * names its stem), its sample count, and its time column (NULL: the axis is the sample index)
 * with that column's name.
 */
typedef struct aenl_plot_record
{
    const char *path;
    size_t n;
    const double *time;
    const char *time_name;
} aenl_plot_record_t;

/** A temporary data file for gnuplot (/tmp/aenl_identify_XXXXXX) opened for writing; NULL and
 *  err set when it cannot be made. */
FILE *aenl_plot_tmp_open(char path[64], aenl_err_t *err);
/** Close a temporary data file; AENL_E_IO when a write failed. */
aenl_status_t aenl_plot_tmp_close(FILE *f, const char *path, aenl_err_t *err);
/** One row of a time-series figure's data: bin k (detail 0: its time and the bin's lo and hi,
 *  lo > hi for an empty bin) or sample k shown at full rate (detail 1: its time in t, value in
 *  lo). */
typedef void (*aenl_plot_ts_row_fn)(const void *ctx, int detail, size_t k, double *t, double *lo,
                                    double *hi);
/** The time-series figure's two temporary data files: env (t,lo,hi over n_bins bins) and det
 *  (t,x over n_det samples), from row(). On failure neither file is left and err is set. */
aenl_status_t aenl_plot_ts_files(aenl_plot_ts_row_fn row, const void *ctx, size_t n_bins,
                                 size_t n_det, char env[64], char det[64], aenl_err_t *err);
/** v as gnuplot reads it ("nan" when not finite), then sep. */
void aenl_plot_put_num(FILE *f, double v, const char *sep);
/** A name as a file-name piece: letters, digits, '-', '_' and '.' kept, others '_'. */
void aenl_plot_file_piece(const char *s, char *out, size_t n);
/** A title or label gnuplot can take (no quote, no newline), in place. */
void aenl_plot_text(char *s);
/** The data file's name without folder and extension, as a file-name piece. */
void aenl_plot_data_stem(const char *path, char *out, size_t n);

#endif /* AENL_TOOLS_PLOT_H */
