/* SPDX-License-Identifier: MIT */
/**
 * @file cli_figures.c
 * @brief The figures' folder a subcommand owns: the files written so far and the folders made
 *        on the way (both undone when a later step fails).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "aenl_cli.h"

void aenl_cli_figs_rollback(aenl_cli_figs_t *o)
{
    /* the run fails: every file it wrote goes, every file it replaced comes back (by name
     * alone, a figure the user had before the run would be deleted), then the folders it made */
    aenl_outfile_abort_all();
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
