/* SPDX-License-Identifier: MIT */
/**
 * @file cli_figures.c
 * @brief What the subcommands' figures share: the files written so far (removed again when a
 *        later one fails), folders made on the way, gnuplot's temporary data files, numbers and
 *        labels as gnuplot reads them.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "aenl_cli.h"

void aenl_cli_figs_rollback(aenl_cli_figs_t *o)
{
    for (size_t i = 0; i < o->n_files; ++i)
    {
        (void)remove(o->files[i]);
    }
    for (size_t i = o->n_dirs; i > 0; --i)
    {
        (void)rmdir(o->dirs[i - 1u]); /* only if still empty */
    }
}

void aenl_cli_figs_free(aenl_cli_figs_t *o)
{
    for (size_t i = 0; i < o->n_files; ++i)
    {
        free(o->files[i]);
    }
    free((void *)o->files);
    for (size_t i = 0; i < o->n_dirs; ++i)
    {
        free(o->dirs[i]);
    }
    memset(o, 0, sizeof(*o));
}

static char *dup_str(const char *s)
{
    const size_t n = strlen(s) + 1u;
    char *d = malloc(n);
    if (d != NULL)
    {
        memcpy(d, s, n);
    }
    return d;
}

aenl_status_t aenl_cli_figs_add(aenl_cli_figs_t *o, const char *path, aenl_err_t *err)
{
    if (o->n_files == o->cap_files)
    {
        const size_t cap = o->cap_files ? 2u * o->cap_files : 8u;
        char **f = (char **)realloc((void *)o->files, cap * sizeof(*f));
        if (f == NULL)
        {
            aenl_err_set(err, "out of memory");
            return AENL_E_IO;
        }
        o->files = f;
        o->cap_files = cap;
    }
    if ((o->files[o->n_files] = dup_str(path)) == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    o->n_files++;
    return AENL_OK;
}

/* mkdir -p DIR, remembering what was created. */
aenl_status_t aenl_cli_figs_mkdir(aenl_cli_figs_t *o, const char *dir, aenl_err_t *err)
{
    char buf[4096];
    const size_t len = strlen(dir);
    if (len + 1u > sizeof(buf))
    {
        aenl_err_set(err, "--plot: folder name too long");
        return AENL_E_ARG;
    }
    memcpy(buf, dir, len + 1u);
    for (size_t i = 1; i <= len; ++i)
    {
        if (buf[i] != '/' && buf[i] != '\0')
        {
            continue;
        }
        const char keep = buf[i];
        buf[i] = '\0';
        struct stat sb;
        if (stat(buf, &sb) == 0)
        {
            if (!S_ISDIR(sb.st_mode))
            {
                aenl_err_set(err, "--plot: %s exists and is not a folder", buf);
                return AENL_E_IO;
            }
        }
        else if (mkdir(buf, 0777) != 0)
        {
            aenl_err_set(err, "--plot: cannot create folder %s (%s)", buf, strerror(errno));
            return AENL_E_IO;
        }
        else if (o->n_dirs < sizeof(o->dirs) / sizeof(o->dirs[0]))
        {
            o->dirs[o->n_dirs] = dup_str(buf);
            o->n_dirs += (o->dirs[o->n_dirs] != NULL) ? 1u : 0u;
        }
        buf[i] = keep;
    }
    return AENL_OK;
}

/* A temporary data file for gnuplot: /tmp/aenl_identify_XXXXXX, opened for writing. */
FILE *aenl_cli_tmp_open(char path[64], aenl_err_t *err)
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

aenl_status_t aenl_cli_tmp_close(FILE *f, const char *path, aenl_err_t *err)
{
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad)
    {
        aenl_err_set(err, "cannot write the temporary file %s", path);
        return AENL_E_IO;
    }
    return AENL_OK;
}

void aenl_cli_put_num(FILE *f, double v, const char *sep)
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

aenl_status_t aenl_cli_ts_files(aenl_cli_ts_row_fn row, const void *ctx, size_t n_bins,
                                size_t n_det, char env[64], char det[64], aenl_err_t *err)
{
    FILE *f = aenl_cli_tmp_open(env, err);
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
        aenl_cli_put_num(f, t, ",");
        aenl_cli_put_num(f, lo <= hi ? lo : (double)NAN, ",");
        aenl_cli_put_num(f, lo <= hi ? hi : (double)NAN, "\n");
    }
    aenl_status_t st = aenl_cli_tmp_close(f, env, err);
    f = st == AENL_OK ? aenl_cli_tmp_open(det, err) : NULL;
    if (f == NULL)
    {
        (void)remove(env);
        return st == AENL_OK ? AENL_E_IO : st;
    }
    fprintf(f, "t,x\n");
    for (size_t k = 0; k < n_det; ++k)
    {
        row(ctx, 1, k, &t, &lo, &hi);
        aenl_cli_put_num(f, t, ",");
        aenl_cli_put_num(f, lo, "\n");
    }
    st = aenl_cli_tmp_close(f, det, err);
    if (st != AENL_OK)
    {
        (void)remove(env);
        (void)remove(det);
    }
    return st;
}

/* Channel name as a file-name piece: letters, digits, '-', '_' and '.' kept, others '_'. */
void aenl_cli_file_piece(const char *s, char *out, size_t n)
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
void aenl_cli_plot_text(char *s)
{
    for (; *s != '\0'; ++s)
    {
        *s = (char)((*s == '\'' || *s == '\n' || *s == '\r') ? ' ' : *s);
    }
}

/* Stem of the data file's name (no folder, no extension) as a file-name piece. */
void aenl_cli_data_stem(const char *path, char *out, size_t n)
{
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    char buf[256];
    (void)snprintf(buf, sizeof(buf), "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot != NULL && dot != buf)
    {
        *dot = '\0';
    }
    aenl_cli_file_piece(buf, out, n);
}
