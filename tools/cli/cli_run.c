/* SPDX-License-Identifier: MIT */
/**
 * @file cli_run.c
 * @brief Running a helper program that is installed beside `aenl` (the float32 benches).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "aenl_cli.h"

static const char *const k_cmd = "bench";

/* Run `name` (a program in aenl's own folder) with args, its output passed through. */
int aenl_bench_run_sibling(const char *name, char *const *args, int n_args)
{
    char self[1024];
    const ssize_t len = readlink("/proc/self/exe", self, sizeof(self) - 1u);
    char *slash = NULL;
    if (len > 0)
    {
        self[len] = '\0';
        slash = strrchr(self, '/');
    }
    char path[1200];
    if (slash == NULL || snprintf(path, sizeof(path), "%.*s/%s", (int)(slash - self), self, name) >=
                             (int)sizeof(path))
    {
        aenl_cli_error(k_cmd, "cannot locate %s next to aenl", name);
        return AENL_EXIT_FAIL;
    }
    char *argv2[8];
    int n = 0;
    argv2[n++] = path;
    for (int i = 0; i < n_args && n < 7; ++i)
    {
        argv2[n++] = args[i];
    }
    argv2[n] = NULL;
    (void)fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0)
    {
        execv(path, argv2);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid)
    {
        aenl_cli_error(k_cmd, "cannot run %s", path);
        return AENL_EXIT_FAIL;
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 2)
    {
        return AENL_EXIT_USAGE; /* the bench printed its usage */
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    {
        aenl_cli_error(k_cmd, "%s failed (%s)", path,
                       WIFEXITED(status) && WEXITSTATUS(status) == 127 ? "not found" : "status");
        return AENL_EXIT_FAIL;
    }
    return AENL_EXIT_OK;
}
