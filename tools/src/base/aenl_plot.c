/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_plot.c
 * @brief gnuplot runner: fork/exec (no shell, so paths need no shell quoting).
 */
#define _POSIX_C_SOURCE 200809L

#include "aenl_tools/aenl_plot.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

static int file_exists(const char *p)
{
    struct stat sb;
    return stat(p, &sb) == 0 && S_ISREG(sb.st_mode);
}

static int on_path(const char *prog)
{
    const char *path = getenv("PATH");
    if (path == NULL)
    {
        return 0;
    }
    char buf[4096];
    const char *p = path;
    while (*p != '\0')
    {
        const char *colon = strchr(p, ':');
        const size_t len = colon ? (size_t)(colon - p) : strlen(p);
        if (len > 0 && len + strlen(prog) + 2 < sizeof(buf))
        {
            memcpy(buf, p, len);
            buf[len] = '/';
            memcpy(buf + len + 1, prog, strlen(prog) + 1u);
            if (access(buf, X_OK) == 0)
            {
                return 1;
            }
        }
        p += len;
        if (*p == ':')
        {
            p++;
        }
    }
    return 0;
}

int aenl_plot_available(void)
{
    return on_path("gnuplot");
}

aenl_status_t aenl_plot_script_path(const char *script, char *buf, size_t n, aenl_err_t *err)
{
    const char *env = getenv("AENL_PLOT_DIR");
    if (env != NULL && env[0] != '\0')
    {
        const int len = snprintf(buf, n, "%s/%s.gp", env, script);
        if (len > 0 && (size_t)len < n && file_exists(buf))
        {
            return AENL_OK;
        }
    }
    char rel[256];
    const int len = snprintf(rel, sizeof(rel), "plot/%s.gp", script);
    if (len < 0 || (size_t)len >= sizeof(rel))
    {
        aenl_err_set(err, "plot script name '%s' too long", script);
        return AENL_E_ARG;
    }
    return aenl_share_path(rel, buf, n, err);
}

/* The figure's format from the path's extension (any case): "png", "svg" or "pdf"; PNG for a
 * path without one ("-", a device); NULL for another extension. */
static const char *figure_format(const char *path)
{
    const char *base = strrchr(path, '/');
    base = base != NULL ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (dot == NULL || dot == base)
    {
        return "png";
    }
    static const char *const k_fmt[] = {"png", "svg", "pdf"};
    for (size_t i = 0; i < 3; ++i)
    {
        if (strlen(dot + 1) == 3 && tolower((unsigned char)dot[1]) == k_fmt[i][0] &&
            tolower((unsigned char)dot[2]) == k_fmt[i][1] &&
            tolower((unsigned char)dot[3]) == k_fmt[i][2])
        {
            return k_fmt[i];
        }
    }
    return NULL;
}

/* A value or name that would break out of its quotes in gnuplot's -e expression is refused. */
static aenl_status_t check_vars(const aenl_plot_var_t *vars, size_t n_vars, aenl_err_t *err)
{
    for (size_t i = 0; i < n_vars; ++i)
    {
        if (strpbrk(vars[i].value, "'\n\r") != NULL || strpbrk(vars[i].name, "'\"\n =;") != NULL)
        {
            aenl_err_set(err, "plot variable %s: value \"%s\" holds a quote or newline",
                         vars[i].name, vars[i].value);
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

/* The folder of the script gp into term_dir (n bytes): the scripts load their terminal
 * settings from beside themselves. */
static aenl_status_t script_dir(const char *gp, char *term_dir, size_t n, aenl_err_t *err)
{
    const char *slash = strrchr(gp, '/');
    const size_t dir_len = slash != NULL ? (size_t)(slash - gp) : 1u;
    if (dir_len >= n || strchr(gp, '\'') != NULL)
    {
        aenl_err_set(err, "plot script path %s: too long or holds a quote", gp);
        return AENL_E_ARG;
    }
    memcpy(term_dir, slash != NULL ? gp : ".", dir_len);
    term_dir[dir_len] = '\0';
    return AENL_OK;
}

/* Opens the figure's output and checks that gnuplot can be pointed at it. On failure nothing is
 * left open. */
static aenl_status_t open_figure(aenl_outfile_t *of, const char *out_path, aenl_err_t *err)
{
    aenl_status_t st = aenl_outfile_open(of, out_path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    /* gnuplot writes the temporary (or the device) itself; our handle only keeps it reserved. */
    if (fflush(of->fp) != 0)
    {
        aenl_outfile_abort(of);
        aenl_err_set(err, "%s: cannot write", out_path);
        return AENL_E_IO;
    }
    if (of->direct == 2 && of->fp == stderr)
    {
        aenl_outfile_abort(of);
        aenl_err_set(err, "%s: a figure cannot go to standard error", out_path);
        return AENL_E_ARG;
    }
    if (strchr(aenl_outfile_write_path(of), '\'') != NULL)
    {
        aenl_outfile_abort(of);
        aenl_err_set(err, "%s: a figure's path must not hold a quote", out_path);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* gnuplot's -e expression: the output, its format, the terminal folder and the variables, each
 * as a quoted string assignment. NULL when out of memory; the caller frees it. */
static char *plot_expression(const aenl_plot_var_t *vars, size_t n_vars, const char *gp_out,
                             const char *fmt, const char *term_dir)
{
    size_t cap = 64;
    for (size_t i = 0; i < n_vars; ++i)
    {
        cap += strlen(vars[i].name) + strlen(vars[i].value) + 8;
    }
    cap += strlen(gp_out) + strlen(term_dir) + 64;
    char *expr = malloc(cap);
    if (expr == NULL)
    {
        return NULL;
    }
    size_t pos = (size_t)snprintf(expr, cap, "out='%s';aenl_fmt='%s';aenl_term_dir='%s';", gp_out,
                                  fmt, term_dir);
    for (size_t i = 0; i < n_vars; ++i)
    {
        pos += (size_t)snprintf(expr + pos, cap - pos, "%s='%s';", vars[i].name, vars[i].value);
    }
    return expr;
}

/* Runs gnuplot -e expr gp with its messages (and, unless the figure goes to standard output,
 * its standard output) into logfd. 1 when it did not run or exit with status 0. */
static int run_gnuplot(char *expr, char *gp, int to_stdout, int logfd)
{
    const pid_t pid = fork();
    if (pid == 0)
    {
        dup2(logfd, STDERR_FILENO);
        if (!to_stdout)
        {
            dup2(logfd, STDOUT_FILENO);
        }
        char *argv[] = {"gnuplot", "-e", expr, gp, NULL};
        execvp("gnuplot", argv);
        _exit(127);
    }
    int status = -1;
    if (pid > 0)
    {
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        {
        }
    }
    return pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0;
}

/* Reads gnuplot's messages from logfd and closes it: any "error" line is a failure even with
 * exit status 0. tail (n bytes) receives the last line that names an error or a script line.
 * 1 when an error line was seen. */
static int read_gnuplot_log(int logfd, char *tail, size_t n)
{
    int failed = 0;
    FILE *lf = fdopen(logfd, "r");
    if (lf == NULL)
    {
        close(logfd);
        return 0;
    }
    rewind(lf);
    char line[400];
    while (fgets(line, sizeof(line), lf) != NULL)
    {
        if (strstr(line, "rror") != NULL || strstr(line, "line ") != NULL)
        {
            if (strstr(line, "rror") != NULL)
            {
                failed = 1;
            }
            (void)snprintf(tail, n, "%s", line);
        }
    }
    (void)fclose(lf); /* read-only */
    return failed;
}

/* gnuplot reports no error when its output cannot be written (a full disk leaves the file cut
 * short or empty), so the file itself is read. */
int aenl_plot_file_complete(const char *path, const char *fmt)
{
    static const unsigned char k_iend[12] = {0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
                                             0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};
    unsigned char tail[64];
    FILE *f = fopen(path, "rb");
    if (f == NULL)
    {
        return 0;
    }
    const long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1L;
    const size_t k =
        size <= 0 ? 0u : (size_t)(size < (long)sizeof(tail) ? size : (long)sizeof(tail));
    const size_t got =
        (k > 0u && fseek(f, size - (long)k, SEEK_SET) == 0) ? fread(tail, 1, k, f) : 0u;
    (void)fclose(f); /* read-only */
    if (k == 0u || got != k)
    {
        return 0;
    }
    if (strcmp(fmt, "png") == 0)
    {
        return got >= sizeof(k_iend) &&
               memcmp(tail + got - sizeof(k_iend), k_iend, sizeof(k_iend)) == 0;
    }
    const char *mark = strcmp(fmt, "svg") == 0 ? "</svg>" : "%%EOF";
    const size_t ml = strlen(mark);
    for (size_t i = 0; i + ml <= got; ++i)
    {
        if (memcmp(tail + i, mark, ml) == 0)
        {
            return 1;
        }
    }
    return 0;
}

/* Runs gnuplot on expr and the script gp, then commits the figure of, or aborts it when gnuplot
 * fails or leaves the file incomplete. Takes over of. */
static aenl_status_t plot_and_commit(aenl_outfile_t *of, char *expr, char *gp, const char *script,
                                     const char *out_path, const char *fmt, aenl_err_t *err)
{
    char logname[] = "/tmp/aenl_gnuplot_XXXXXX";
    const int logfd = mkstemp(logname);
    if (logfd < 0)
    {
        aenl_outfile_abort(of);
        aenl_err_set(err, "cannot create a temporary file for gnuplot's messages: %s",
                     strerror(errno));
        return AENL_E_IO;
    }
    int failed = run_gnuplot(expr, gp, of->direct == 2, logfd);
    char tail[400] = "";
    failed |= read_gnuplot_log(logfd, tail, sizeof(tail));
    unlink(logname);
    if (failed)
    {
        aenl_outfile_abort(of);
        tail[strcspn(tail, "\n")] = '\0';
        aenl_err_set(err, "gnuplot failed on %s.gp for %s: %s", script, out_path,
                     tail[0] ? tail : "no message");
        return AENL_E_IO;
    }
    if (of->tmp_path != NULL && !aenl_plot_file_complete(of->tmp_path, fmt))
    {
        aenl_outfile_abort(of);
        aenl_err_set(err,
                     "%s: cannot write the figure (the file gnuplot wrote is incomplete: a "
                     "full disk?)",
                     out_path);
        return AENL_E_IO;
    }
    return aenl_outfile_commit(of, err);
}

aenl_status_t aenl_plot_run(const char *script, const aenl_plot_var_t *vars, size_t n_vars,
                            const char *out_path, aenl_err_t *err)
{
    char gp[4096];
    aenl_status_t st = aenl_plot_script_path(script, gp, sizeof(gp), err);
    if (st != AENL_OK)
    {
        return st;
    }
    if (!aenl_plot_available())
    {
        aenl_err_set(err, "gnuplot not found on PATH (Debian: apt-get install gnuplot-nox)");
        return AENL_E_IO;
    }
    st = check_vars(vars, n_vars, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const char *fmt = figure_format(out_path);
    if (fmt == NULL)
    {
        aenl_err_set(err, "%s: a figure is written as .png, .svg or .pdf (from the extension)",
                     out_path);
        return AENL_E_ARG;
    }
    char term_dir[4096];
    st = script_dir(gp, term_dir, sizeof(term_dir), err);
    if (st != AENL_OK)
    {
        return st;
    }
    aenl_outfile_t of;
    st = open_figure(&of, out_path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    char *expr = plot_expression(vars, n_vars, aenl_outfile_write_path(&of), fmt, term_dir);
    if (expr == NULL)
    {
        aenl_outfile_abort(&of);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    st = plot_and_commit(&of, expr, gp, script, out_path, fmt, err);
    free(expr);
    return st;
}
