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
    for (size_t i = 0; i < n_vars; ++i)
    {
        if (strpbrk(vars[i].value, "'\n\r") != NULL || strpbrk(vars[i].name, "'\"\n =;") != NULL)
        {
            aenl_err_set(err, "plot variable %s: value \"%s\" holds a quote or newline",
                         vars[i].name, vars[i].value);
            return AENL_E_ARG;
        }
    }
    const char *fmt = figure_format(out_path);
    if (fmt == NULL)
    {
        aenl_err_set(err, "%s: a figure is written as .png, .svg or .pdf (from the extension)",
                     out_path);
        return AENL_E_ARG;
    }
    char term_dir[4096];
    const char *slash = strrchr(gp, '/');
    const size_t dir_len = slash != NULL ? (size_t)(slash - gp) : 1u;
    if (dir_len >= sizeof(term_dir) || strchr(gp, '\'') != NULL)
    {
        aenl_err_set(err, "plot script path %s: too long or holds a quote", gp);
        return AENL_E_ARG;
    }
    memcpy(term_dir, slash != NULL ? gp : ".", dir_len);
    term_dir[dir_len] = '\0';
    aenl_outfile_t of;
    st = aenl_outfile_open(&of, out_path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    /* gnuplot writes the temporary (or the device) itself; our handle only keeps it reserved. */
    if (fflush(of.fp) != 0)
    {
        aenl_outfile_abort(&of);
        aenl_err_set(err, "%s: cannot write", out_path);
        return AENL_E_IO;
    }

    size_t cap = 64;
    for (size_t i = 0; i < n_vars; ++i)
    {
        cap += strlen(vars[i].name) + strlen(vars[i].value) + 8;
    }
    const char *gp_out = aenl_outfile_write_path(&of);
    const int to_stdout = (of.direct == 2);
    if (to_stdout && of.fp == stderr)
    {
        aenl_outfile_abort(&of);
        aenl_err_set(err, "%s: a figure cannot go to standard error", out_path);
        return AENL_E_ARG;
    }
    if (strchr(gp_out, '\'') != NULL)
    {
        aenl_outfile_abort(&of);
        aenl_err_set(err, "%s: a figure's path must not hold a quote", out_path);
        return AENL_E_ARG;
    }
    cap += strlen(gp_out) + strlen(term_dir) + 64;
    char *expr = malloc(cap);
    if (expr == NULL)
    {
        aenl_outfile_abort(&of);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    size_t pos = (size_t)snprintf(expr, cap, "out='%s';aenl_fmt='%s';aenl_term_dir='%s';", gp_out,
                                  fmt, term_dir);
    for (size_t i = 0; i < n_vars; ++i)
    {
        pos += (size_t)snprintf(expr + pos, cap - pos, "%s='%s';", vars[i].name, vars[i].value);
    }

    char logname[] = "/tmp/aenl_gnuplot_XXXXXX";
    const int logfd = mkstemp(logname);
    if (logfd < 0)
    {
        free(expr);
        aenl_outfile_abort(&of);
        aenl_err_set(err, "cannot create a temporary file for gnuplot's messages: %s",
                     strerror(errno));
        return AENL_E_IO;
    }
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
    free(expr);
    /* Read gnuplot's messages: any "error" line is a failure even with exit status 0. */
    int failed = (pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0);
    char tail[400] = "";
    FILE *lf = fdopen(logfd, "r");
    if (lf != NULL)
    {
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
                (void)snprintf(tail, sizeof(tail), "%s", line);
            }
        }
        (void)fclose(lf); /* read-only */
    }
    else
    {
        close(logfd);
    }
    unlink(logname);
    if (failed)
    {
        aenl_outfile_abort(&of);
        tail[strcspn(tail, "\n")] = '\0';
        aenl_err_set(err, "gnuplot failed on %s.gp for %s: %s", script, out_path,
                     tail[0] ? tail : "no message");
        return AENL_E_IO;
    }
    return aenl_outfile_commit(&of, err);
}
