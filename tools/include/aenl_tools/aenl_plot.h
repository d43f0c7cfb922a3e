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

#endif /* AENL_TOOLS_PLOT_H */
