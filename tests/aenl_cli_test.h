/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_cli_test.h
 * @brief Running the built `aenl` command from a test: exit status, stdout and stderr captured.
 *        Needs AENL_CLI_PATH (the executable) and AENL_TEST_TMP_DIR (a writable folder).
 */
#ifndef AENL_CLI_TEST_H
#define AENL_CLI_TEST_H

#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "unity.h"

typedef struct
{
    int status;      /* exit status, or -1 when the process did not exit normally (a crash) */
    char out[65536]; /* stdout (truncated) */
    char err[8192];  /* stderr (truncated) */
    size_t n_out;    /* bytes on stdout (full count) */
    int err_lines;   /* lines on stderr */
} cli_result_t;

static inline size_t cli_slurp(const char *path, char *buf, size_t cap)
{
    size_t total = 0;
    FILE *f = fopen(path, "rb");
    buf[0] = '\0';
    if (f == NULL)
    {
        return 0;
    }
    for (;;)
    {
        char tmp[4096];
        const size_t got = fread(tmp, 1, sizeof(tmp), f);
        if (got == 0)
        {
            break;
        }
        if (total < cap - 1u)
        {
            const size_t room = cap - 1u - total;
            memcpy(buf + total, tmp, got < room ? got : room);
            buf[total + (got < room ? got : room)] = '\0';
        }
        total += got;
    }
    (void)fclose(f);
    return total;
}

/* Run AENL_CLI_PATH with argv (NULL-terminated, argv[0] is the subcommand), in dir `cwd`. */
static inline void cli_run(cli_result_t *r, const char *const *args)
{
    /* per process: the parts of a suite run side by side in the same folder */
    char out_path[512], err_path[512];
    const long self = (long)getpid();
    (void)snprintf(out_path, sizeof(out_path), "%s/cli_stdout.%ld.txt", AENL_TEST_TMP_DIR, self);
    (void)snprintf(err_path, sizeof(err_path), "%s/cli_stderr.%ld.txt", AENL_TEST_TMP_DIR, self);
    const char *argv[64];
    size_t n = 0;
    argv[n++] = AENL_CLI_PATH;
    while (args[n - 1u] != NULL && n < 63u)
    {
        argv[n] = args[n - 1u];
        n++;
    }
    argv[n] = NULL;
    (void)fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0)
    {
        const int fo = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int fe = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int fi = open("/dev/null", O_RDONLY);
        if (fo < 0 || fe < 0 || fi < 0 || chdir(AENL_TEST_TMP_DIR) != 0)
        {
            _exit(126);
        }
        dup2(fo, STDOUT_FILENO);
        dup2(fe, STDERR_FILENO);
        dup2(fi, STDIN_FILENO);
        execv(AENL_CLI_PATH, (char *const *)argv);
        _exit(127);
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR)
    {
    }
    r->status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    r->n_out = cli_slurp(out_path, r->out, sizeof(r->out));
    cli_slurp(err_path, r->err, sizeof(r->err));
    (void)unlink(out_path);
    (void)unlink(err_path);
    r->err_lines = 0;
    for (const char *p = r->err; *p; ++p)
    {
        r->err_lines += (*p == '\n');
    }
}

/* Write `text` to AENL_TEST_TMP_DIR/name and return the full path (static buffer per call slot). */
static inline const char *cli_file(const char *name, const char *text)
{
    static char paths[8][512];
    static int slot = 0;
    char *p = paths[slot++ % 8];
    (void)snprintf(p, 512, "%s/%s", AENL_TEST_TMP_DIR, name);
    FILE *f = fopen(p, "wb");
    if (f != NULL)
    {
        fputs(text, f);
        (void)fclose(f);
    }
    return p;
}

static inline int cli_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* No file in AENL_TEST_TMP_DIR whose name starts with `prefix` (catches temporaries too). */
static inline int cli_no_file_like(const char *prefix)
{
    char cmd[1024];
    (void)snprintf(cmd, sizeof(cmd), "ls -a '%s' | grep -q '^%s'", AENL_TEST_TMP_DIR, prefix);
    return system(cmd) != 0; /* NOLINT(cert-env33-c): test helper, fixed command */
}

/* The command is refused as bad input or usage: exit status 2, nothing on stdout, one line on
 * stderr, holding needle unless that is NULL. */
static inline void cli_expect_refused(const char *const *args, const char *needle)
{
    static cli_result_t r; /* 73 KB: not on the stack */
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, r.err_lines, r.err);
    TEST_ASSERT_EQUAL_size_t_MESSAGE(0, r.n_out, r.out);
    TEST_ASSERT_TRUE_MESSAGE(needle == NULL || strstr(r.err, needle) != NULL, r.err);
}

#endif /* AENL_CLI_TEST_H */
