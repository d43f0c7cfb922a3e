/* SPDX-License-Identifier: MIT */
/**
 * @file cli_channel.c
 * @brief Reading one channel of a CSV record for the subcommands.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_cli.h"

/* The time column's name given to this process's command (--time COL); NULL: known by its name.
 * One command runs per process, so the setting is the command's. */
static const char *g_time_column = NULL;

void aenl_cli_set_time_column(const char *name)
{
    g_time_column = name;
}

const char *aenl_cli_time_column(void)
{
    return g_time_column;
}

int aenl_cli_is_time_column(const char *name)
{
    return aenl_csv_is_time_column(name, g_time_column);
}

/* Notes on stderr go with a table; a JSON output's reader wants a quiet stderr on success. */
static int g_notes = 1;

void aenl_cli_set_notes(int on)
{
    g_notes = on;
}

void aenl_cli_no_time_text(const char *path, char *buf, size_t n)
{
    (void)snprintf(buf, n,
                   "%s has no time column (t, time, tau or timestamp, or the one --time names): "
                   "every column is a channel, and lags count samples",
                   path);
}

/* The run's notes, each once, printed by aenl_cli_flush_notes when the run succeeds: a run that
 * fails prints its one error message and nothing else. */
static char g_note_buf[8192];

void aenl_cli_note_no_time(const char *cmd, const char *path)
{
    if (!g_notes)
    {
        return;
    }
    char text[4096 + 256], line[4096 + 512];
    aenl_cli_no_time_text(path, text, sizeof(text));
    (void)snprintf(line, sizeof(line), "aenl %s: note: %s\n", cmd, text);
    const size_t used = strlen(g_note_buf);
    if (strstr(g_note_buf, line) == NULL && used + strlen(line) < sizeof(g_note_buf))
    {
        memcpy(g_note_buf + used, line, strlen(line) + 1u);
    }
}

void aenl_cli_flush_notes(int print)
{
    if (print)
    {
        fputs(g_note_buf, stderr);
    }
    g_note_buf[0] = '\0';
}

/* The column names of t, comma-separated, into buf (cut when too long). */
static void column_list(const aenl_table_t *t, char *buf, size_t cap)
{
    buf[0] = '\0';
    for (size_t i = 0; i < t->n_cols; ++i)
    {
        const size_t len = strlen(buf);
        if (len + strlen(t->names[i]) + 3 < cap)
        {
            (void)snprintf(buf + len, cap - len, "%s%s", i ? ", " : "", t->names[i]);
        }
    }
}

/* The names of the columns that are not time columns, comma-separated, into buf. */
static void channel_list(const aenl_table_t *t, char *buf, size_t cap)
{
    buf[0] = '\0';
    for (size_t i = 0; i < t->n_cols; ++i)
    {
        const size_t len = strlen(buf);
        if (!aenl_cli_is_time_column(t->names[i]) && len + strlen(t->names[i]) + 3 < cap)
        {
            (void)snprintf(buf + len, cap - len, "%s%s", len > 0 ? ", " : "", t->names[i]);
        }
    }
}

/* 0 when the record has the time column --time names (or none was named), else -1 after the
 * message; without any time column, a note on stderr says how the record is read. */
static int check_time_column(const char *cmd, const aenl_table_t *t, const char *path)
{
    if (g_time_column != NULL && aenl_table_find(t, g_time_column) < 0)
    {
        char names[512];
        column_list(t, names, sizeof(names));
        aenl_cli_error(cmd, "%s: --time: no column '%s' (columns: %s)", path, g_time_column, names);
        return -1;
    }
    size_t n_time = 0;
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        n_time += aenl_cli_is_time_column(t->names[c]) ? 1u : 0u;
    }
    if (n_time == 0)
    {
        aenl_cli_note_no_time(cmd, path);
    }
    return 0;
}

int aenl_cli_time_value_check(aenl_time_steps_t *s, double t, double t_prev, size_t row,
                              const char *path, const char *column, aenl_err_t *err)
{
    if (isnan(t))
    {
        aenl_err_set(err, "%s: column '%s', data row %zu: missing time value", path, column, row);
        return -1;
    }
    if (row > 1u && !(t > t_prev))
    {
        aenl_err_set(err,
                     "%s: column '%s', data row %zu: time %.10g does not increase (previous "
                     "%.10g)",
                     path, column, row, t, t_prev);
        return -1;
    }
    if (row > 1u && t - t_prev < DBL_MIN)
    {
        /* a step below the smallest normal number has no finite rate (1 / step) */
        aenl_err_set(err,
                     "%s: column '%s', data row %zu: time step %.6g is too small to compute "
                     "with; give the time column in a larger unit",
                     path, column, row, t - t_prev);
        return -1;
    }
    double step = 0.0;
    double ref = 0.0;
    if (!aenl_time_steps_take(s, t, &step, &ref))
    {
        aenl_err_set(err,
                     "%s: column '%s', data row %zu: time step %.6g where the record's step is "
                     "%.6g (%s): the samples are taken as equally spaced; cut the record there "
                     "or resample it",
                     path, column, row, step, ref,
                     step > AENL_TIME_GAP * ref ? "a gap" : "uneven steps");
        return -1;
    }
    return 0;
}

long aenl_cli_pick_channel(const char *cmd, const aenl_table_t *t, const char *path,
                           const char *channel)
{
    if (channel != NULL)
    {
        const long c = aenl_table_find(t, channel);
        if (c < 0 || aenl_cli_is_time_column(t->names[c]))
        {
            char names[512];
            channel_list(t, names, sizeof(names));
            aenl_cli_error(cmd, "%s: no channel '%s' (channels: %s%s)", path, channel, names,
                           c >= 0 ? "; it is the time column" : "");
            return -1;
        }
        return c;
    }
    long found = -1;
    size_t n_data = 0;
    for (size_t i = 0; i < t->n_cols; ++i)
    {
        if (!aenl_cli_is_time_column(t->names[i]))
        {
            n_data++;
            found = (long)i;
        }
    }
    if (n_data != 1)
    {
        aenl_cli_error(cmd, "%s: %zu data channels: name one with --channel", path, n_data);
        return -1;
    }
    return found;
}

int aenl_cli_check_record(const char *cmd, const aenl_table_t *t, const char *path, long col)
{
    if (check_time_column(cmd, t, path) != 0)
    {
        return -1;
    }
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        const double *v = aenl_table_col(t, c);
        if (aenl_cli_is_time_column(t->names[c]))
        {
            aenl_time_steps_t steps;
            memset(&steps, 0, sizeof(steps));
            for (size_t r = 0; r < t->n_rows; ++r)
            {
                aenl_err_t e;
                aenl_err_clear(&e);
                if (aenl_cli_time_value_check(&steps, v[r], r > 0 ? v[r - 1u] : 0.0, r + 1u, path,
                                              t->names[c], &e) != 0)
                {
                    aenl_cli_error(cmd, "%s", e.msg);
                    return -1;
                }
            }
        }
        else if (col < 0 || (size_t)col == c)
        {
            size_t n_finite = 0;
            for (size_t r = 0; r < t->n_rows; ++r)
            {
                n_finite += isnan(v[r]) ? 0u : 1u;
                if (fabs(v[r]) > AENL_CLI_MAX_ABS)
                {
                    aenl_cli_error(cmd,
                                   "%s: column '%s', data row %zu: value %g is too large "
                                   "(the limit is +-%g)",
                                   path, t->names[c], r + 1u, v[r], AENL_CLI_MAX_ABS);
                    return -1;
                }
            }
            if (n_finite == 0 && t->n_rows > 0)
            {
                aenl_cli_error(cmd, "%s, channel %s: no finite sample (%zu samples, all missing)",
                               path, t->names[c], t->n_rows);
                return -1;
            }
        }
    }
    return 0;
}

int aenl_cli_is_input(const size_t *in, size_t n_in, size_t col)
{
    for (size_t k = 0; k < n_in; ++k)
    {
        if (in[k] == col)
        {
            return 1;
        }
    }
    return 0;
}

int aenl_cli_record_channels(const char *cmd, const aenl_table_t *t, const char *path,
                             const size_t *in, size_t n_in, long only, size_t max,
                             const double **chan, const char **names, size_t *nz)
{
    const size_t n = t->n_rows;
    *nz = 0;
    for (size_t c = 0; c < t->n_cols; ++c)
    {
        if (aenl_cli_is_time_column(t->names[c]) || aenl_cli_is_input(in, n_in, c) ||
            (only >= 0 && (long)c != only))
        {
            continue;
        }
        if (*nz == max)
        {
            aenl_cli_error(cmd, "%s: more than %zu channels: name one with --channel", path, max);
            return -1;
        }
        chan[*nz] = t->data + c * n;
        names[(*nz)++] = t->names[c];
    }
    if (*nz == 0)
    {
        aenl_cli_error(cmd,
                       n_in > 0 ? "%s: no channel left to test (only time and inputs)"
                                : "%s: no data column (only the time column)",
                       path);
        return -1;
    }
    for (size_t j = 0; j < *nz; ++j)
    {
        double lo = HUGE_VAL;
        double hi = -HUGE_VAL;
        for (size_t k = 0; k < n; ++k)
        {
            lo = fmin(lo, chan[j][k]); /* fmin and fmax pass over a missing sample */
            hi = fmax(hi, chan[j][k]);
        }
        if (!(hi > lo)) /* nothing to test, whatever the record's length */
        {
            aenl_cli_error(cmd,
                           "%s, channel %s: constant signal (every sample is %g): nothing to "
                           "identify (name another channel with --channel)",
                           path, names[j], lo);
            return -1;
        }
    }
    return 0;
}
