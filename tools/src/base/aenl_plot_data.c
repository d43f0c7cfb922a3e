/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_plot_data.c
 * @brief What the library's figures share: gnuplot's temporary data files, numbers and labels as
 *        gnuplot reads them, figure names made from record and channel names.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aenl_tools/aenl_plot.h"

/* A temporary data file for gnuplot: /tmp/aenl_identify_XXXXXX, opened for writing. */
FILE *aenl_plot_tmp_open(char path[64], aenl_err_t *err)
{
    (void)snprintf(path, 64, "/tmp/aenl_identify_XXXXXX");
    const int fd = mkstemp(path);
    FILE *f = (fd >= 0) ? fdopen(fd, "w") : NULL;
    if (f == NULL)
    {
        if (fd >= 0)
        {
            (void)close(fd);
            (void)remove(path);
        }
        path[0] = '\0';
        aenl_err_set(err, "cannot create a temporary file in /tmp");
    }
    return f;
}

aenl_status_t aenl_plot_tmp_close(FILE *f, const char *path, aenl_err_t *err)
{
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad)
    {
        aenl_err_set(err, "cannot write the temporary file %s", path);
        return AENL_E_IO;
    }
    return AENL_OK;
}

void aenl_plot_put_num(FILE *f, double v, const char *sep)
{
    if (isfinite(v))
    {
        fprintf(f, "%.10g%s", v, sep);
    }
    else
    {
        fprintf(f, "nan%s", sep);
    }
}

aenl_status_t aenl_plot_ts_files(aenl_plot_ts_row_fn row, const void *ctx, size_t n_bins,
                                 size_t n_det, char env[64], char det[64], aenl_err_t *err)
{
    FILE *f = aenl_plot_tmp_open(env, err);
    if (f == NULL)
    {
        return AENL_E_IO;
    }
    double t = 0.0;
    double lo = 0.0;
    double hi = 0.0;
    fprintf(f, "t,lo,hi\n");
    for (size_t b = 0; b < n_bins; ++b)
    {
        row(ctx, 0, b, &t, &lo, &hi);
        aenl_plot_put_num(f, t, ",");
        aenl_plot_put_num(f, lo <= hi ? lo : (double)NAN, ",");
        aenl_plot_put_num(f, lo <= hi ? hi : (double)NAN, "\n");
    }
    aenl_status_t st = aenl_plot_tmp_close(f, env, err);
    f = st == AENL_OK ? aenl_plot_tmp_open(det, err) : NULL;
    if (f == NULL)
    {
        (void)remove(env);
        return st == AENL_OK ? AENL_E_IO : st;
    }
    fprintf(f, "t,x\n");
    for (size_t k = 0; k < n_det; ++k)
    {
        row(ctx, 1, k, &t, &lo, &hi);
        aenl_plot_put_num(f, t, ",");
        aenl_plot_put_num(f, lo, "\n");
    }
    st = aenl_plot_tmp_close(f, det, err);
    if (st != AENL_OK)
    {
        (void)remove(env);
        (void)remove(det);
    }
    return st;
}

/* Channel name as a file-name piece: letters, digits, '-', '_' and '.' kept, others '_'. */
void aenl_plot_file_piece(const char *s, char *out, size_t n)
{
    size_t k = 0;
    for (; *s != '\0' && k + 1u < n; ++s)
    {
        const char c = *s;
        const int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '-' || c == '_' || c == '.';
        out[k++] = c;
        if (!ok)
        {
            out[k - 1u] = '_';
        }
    }
    out[k] = '\0';
}

/* A title or label gnuplot can take (no quote, no newline). */
void aenl_plot_text(char *s)
{
    for (; *s != '\0'; ++s)
    {
        *s = (char)((*s == '\'' || *s == '\n' || *s == '\r') ? ' ' : *s);
    }
}

/* Stem of the data file's name (no folder, no extension) as a file-name piece. */
void aenl_plot_data_stem(const char *path, char *out, size_t n)
{
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    char buf[256];
    (void)snprintf(buf, sizeof(buf), "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot != NULL && dot != buf)
    {
        *dot = '\0';
    }
    aenl_plot_file_piece(buf, out, n);
}
