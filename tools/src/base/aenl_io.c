/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_io.c
 * @brief Host-only: first-cause error messages and output files that appear only when complete.
 *
 * An output file is written as ".<name>.tmp.<pid>.<counter>" in the folder of its final path
 * (same file system, so rename(2) is atomic) and renamed into place by aenl_outfile_commit().
 * Only a regular file, or a name that does not exist yet, is replaced that way: symbolic links
 * are followed and the file they name is written (the link stays), while a device, FIFO or
 * socket, and "-" (standard output), are opened and written as they are, never replaced.
 * Every open temporary is listed in a process-wide table; aenl_outfile_abort_all() (registered
 * with atexit on the first open) unlinks what is still listed. The table is not thread-safe: the
 * tools are single-threaded. abort_all only calls unlink() and rename(), so a signal handler may
 * call it.
 */
#define _POSIX_C_SOURCE 200809L

#include "aenl_tools/aenl_io.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- error messages ------------------------------------------------------------------------ */

void aenl_err_clear(aenl_err_t *err)
{
    if (err != NULL)
    {
        err->msg[0] = '\0';
    }
}

void aenl_err_set(aenl_err_t *err, const char *fmt, ...)
{
    va_list ap;
    if (err == NULL || fmt == NULL || err->msg[0] != '\0')
    {
        return; /* the first cause wins */
    }
    va_start(ap, fmt);
    (void)vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
}

/* ---- table of pending temporaries ---------------------------------------------------------- */

/* Pointers to the tmp_path strings of open outfiles (owned by the outfiles); a slot is NULL when
 * free. Not thread-safe (the tools are single-threaded). */
static char **g_pending;
static size_t g_pending_cap;
static volatile sig_atomic_t g_atexit_done;
static pid_t g_run_owner; /* the process of the current run (not a forked child) */
static unsigned long g_tmp_counter;

/* Room in *v (elem bytes each, *cap of them) for one more than n; 0 on success. */
static int grow(void **v, size_t *cap, size_t n, size_t elem)
{
    if (n < *cap)
    {
        return 0;
    }
    const size_t new_cap = (*cap == 0) ? 8 : 2 * *cap;
    void *g = realloc(*v, new_cap * elem);
    if (g == NULL)
    {
        return -1;
    }
    *v = g;
    *cap = new_cap;
    return 0;
}

static int pending_add(char *tmp_path)
{
    size_t i;
    for (i = 0; i < g_pending_cap; ++i)
    {
        if (g_pending[i] == NULL)
        {
            g_pending[i] = tmp_path;
            return 0;
        }
    }
    const size_t old_cap = g_pending_cap; /* every slot is taken */
    if (grow((void **)&g_pending, &g_pending_cap, old_cap, sizeof(*g_pending)) != 0)
    {
        return -1;
    }
    for (i = old_cap; i < g_pending_cap; ++i)
    {
        g_pending[i] = NULL;
    }
    g_pending[old_cap] = tmp_path;
    return 0;
}

static void pending_remove(const char *tmp_path)
{
    size_t i;
    for (i = 0; i < g_pending_cap; ++i)
    {
        if (g_pending[i] == tmp_path)
        {
            g_pending[i] = NULL;
            return;
        }
    }
}

static void journal_rollback(void);

void aenl_outfile_abort_all(void)
{
    size_t i;
    if (g_run_owner != 0 && getpid() != g_run_owner)
    {
        return; /* a forked child before its exec: the files are its parent's */
    }
    for (i = 0; i < g_pending_cap; ++i)
    {
        if (g_pending[i] != NULL)
        {
            (void)unlink(g_pending[i]);
            /* The string stays owned by its outfile; the slot is forgotten so a second call (a
             * signal, then exit) does nothing. Nothing is freed: not async-signal-safe. */
            g_pending[i] = NULL;
        }
    }
    journal_rollback();
}

static void pending_release_table(void)
{
    size_t i;
    for (i = 0; i < g_pending_cap; ++i)
    {
        if (g_pending[i] != NULL)
        {
            return; /* still in use */
        }
    }
    free(g_pending);
    g_pending = NULL;
    g_pending_cap = 0;
}

/* atexit handler: remove the temporaries, then release the (now empty) table. */
static void run_free(void);

static void outfile_at_exit(void)
{
    aenl_outfile_abort_all();
    pending_release_table();
    run_free();
}

/* ---- output files -------------------------------------------------------------------------- */

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = (char *)malloc(n);
    if (d != NULL)
    {
        memcpy(d, s, n);
    }
    return d;
}

/* "<dir>/.<base>.tmp.<pid>.<counter>" for path "<dir>/<base>" (dir may be empty). */
static char *make_tmp_name(const char *path, const char *kind, unsigned long counter)
{
    const char *slash = strrchr(path, '/');
    size_t dir_len = (slash != NULL) ? (size_t)(slash - path) + 1U : 0U;
    const char *base = path + dir_len;
    size_t need = strlen(path) + 64U;
    char *tmp = (char *)malloc(need);
    if (tmp == NULL)
    {
        return NULL;
    }
    memcpy(tmp, path, dir_len);
    (void)snprintf(tmp + dir_len, need - dir_len, ".%s.%s.%ld.%lu", base, kind, (long)getpid(),
                   counter);
    return tmp;
}

static void outfile_zero(aenl_outfile_t *of)
{
    of->fp = NULL;
    of->path = NULL;
    of->tmp_path = NULL;
    of->direct = 0;
}

/* ---- the run: its inputs, its outputs and what its outputs replaced ----------------------------
 * A run (aenl_outfile_run_begin) remembers every file it reads (aenl_input_note: device and
 * inode, so a hard or symbolic link to an input is the input) and every output it opens (its
 * folder's device and inode, and its name), so that no output replaces one of the
 * run's inputs or another of its outputs. A commit inside a run keeps the file it replaces as a
 * hard link ".<name>.bak.<pid>.<n>" beside it (or, where hard links fail, moves the file to that
 * name) and journals the replacement, so that when the run
 * fails, aenl_outfile_abort_all puts every replaced file back and removes every new one: a run
 * that fails leaves the user's files as they were. aenl_outfile_run_keep ends a run that
 * succeeded and removes the kept copies. The rollback only calls rename() and unlink(), so a
 * signal handler may run it. */

typedef struct
{
    dev_t dev;
    ino_t ino;
} file_id_t;

typedef struct
{
    char *target; /* the output's final path */
    char *backup; /* the file it replaced, under another name; NULL when none was kept */
    int existed;  /* a file was there before the commit */
    int moved;    /* backup is the replaced file renamed (no hard link could be made) */
} journal_t;

static int g_run;
static file_id_t *g_inputs;
static size_t g_n_inputs, g_inputs_cap;
static char **g_outputs; /* canonical paths of the run's outputs */
static size_t g_n_outputs, g_outputs_cap;
static journal_t *g_journal;
static size_t g_journal_len;                 /* entries whose strings the journal owns */
static volatile sig_atomic_t g_journal_live; /* the first entries not yet rolled back */
static size_t g_journal_cap;

/* 1 when the file of st is one the run has read. */
static int noted_input(const struct stat *st)
{
    for (size_t i = 0; i < g_n_inputs; ++i)
    {
        if (g_inputs[i].dev == st->st_dev && g_inputs[i].ino == st->st_ino)
        {
            return 1;
        }
    }
    return 0;
}

void aenl_input_note(const char *path)
{
    struct stat st;
    /* only inside a run: outside one a noted file may be deleted and its inode given to another */
    if (!g_run || path == NULL || strcmp(path, "-") == 0 || stat(path, &st) != 0 ||
        !S_ISREG(st.st_mode) || noted_input(&st))
    {
        return;
    }
    if (grow((void **)&g_inputs, &g_inputs_cap, g_n_inputs, sizeof(*g_inputs)) == 0)
    {
        g_inputs[g_n_inputs].dev = st.st_dev;
        g_inputs[g_n_inputs].ino = st.st_ino;
        g_n_inputs++;
    }
}

/* Inside a run, 1 when path names (through links) a file the run has read. */
static int is_input(const char *path)
{
    struct stat st;
    return g_run && g_n_inputs > 0 && stat(path, &st) == 0 && noted_input(&st);
}

/* final_path's identity as "device:inode of its folder/name" (malloc'd), the same for every
 * spelling of the path; NULL when the folder cannot be examined (opening the output fails on it
 * then) or memory is out. */
static char *canonical_path(const char *final_path)
{
    const char *slash = strrchr(final_path, '/');
    const char *base = (slash != NULL) ? slash + 1 : final_path;
    char dir[4096];
    struct stat st;
    if (slash == NULL)
    {
        (void)snprintf(dir, sizeof dir, ".");
    }
    else if (slash == final_path)
    {
        (void)snprintf(dir, sizeof dir, "/");
    }
    else
    {
        (void)snprintf(dir, sizeof dir, "%.*s", (int)(slash - final_path), final_path);
    }
    if (stat(dir, &st) != 0)
    {
        return NULL;
    }
    const size_t need = strlen(base) + 48U;
    char *out = (char *)malloc(need);
    if (out != NULL)
    {
        (void)snprintf(out, need, "%ju:%ju/%s", (uintmax_t)st.st_dev, (uintmax_t)st.st_ino, base);
    }
    return out;
}

/* Inside a run, AENL_E_ARG when final_path is one of the run's inputs or outputs; otherwise the
 * output is noted. path is the name the user gave (for the message). */
static aenl_status_t run_claim_output(const char *path, const char *final_path, aenl_err_t *err)
{
    if (is_input(final_path))
    {
        aenl_err_set(err, "%s: is an input of this run; write the output under another name", path);
        return AENL_E_ARG;
    }
    if (!g_run)
    {
        return AENL_OK;
    }
    char *canon = canonical_path(final_path);
    if (canon == NULL)
    {
        return AENL_OK;
    }
    for (size_t i = 0; i < g_n_outputs; ++i)
    {
        if (strcmp(g_outputs[i], canon) == 0)
        {
            free(canon);
            aenl_err_set(err, "%s: is already an output of this run; give each output its own name",
                         path);
            return AENL_E_ARG;
        }
    }
    if (grow((void **)&g_outputs, &g_outputs_cap, g_n_outputs, sizeof(*g_outputs)) != 0)
    {
        free(canon);
        aenl_err_set(err, "%s: out of memory", path);
        return AENL_E_IO;
    }
    g_outputs[g_n_outputs++] = canon;
    return AENL_OK;
}

/* Before a commit inside a run replaces target: room in the journal and, when a regular file is
 * there, a hard link to it beside it (kept until the run ends), or the file itself moved to that
 * name where no hard link can be made. Nonzero when memory is out. */
static int journal_prepare(const char *target, journal_t *j)
{
    struct stat st;
    j->target = NULL;
    j->backup = NULL;
    j->existed = 0;
    j->moved = 0;
    if (grow((void **)&g_journal, &g_journal_cap, g_journal_len, sizeof(*g_journal)) != 0)
    {
        return 1;
    }
    j->target = dup_str(target);
    if (j->target == NULL)
    {
        return 1;
    }
    if (lstat(target, &st) != 0)
    {
        return 0;
    }
    j->existed = 1;
    for (int attempt = 0; S_ISREG(st.st_mode) && attempt < 100; ++attempt)
    {
        j->backup = make_tmp_name(target, "bak", g_tmp_counter++);
        if (j->backup == NULL)
        {
            return 1;
        }
        if (link(target, j->backup) == 0)
        {
            break;
        }
        const int again = errno == EEXIST;
        /* a file system without hard links (FAT, some network ones): the file itself moves
         * aside, and the new one is renamed into the free name */
        if (!again && rename(target, j->backup) == 0)
        {
            j->moved = 1;
            break;
        }
        free(j->backup);
        j->backup = NULL;
        if (!again)
        {
            break;
        }
    }
    return 0;
}

/* Undo journal_prepare when the commit fails. */
static void journal_discard(journal_t *j)
{
    if (j->backup != NULL && j->moved)
    {
        (void)rename(j->backup, j->target);
    }
    else if (j->backup != NULL)
    {
        (void)unlink(j->backup);
    }
    free(j->backup);
    free(j->target);
    j->backup = NULL;
    j->target = NULL;
}

/* Put back what the run's commits replaced, newest first, and remove what they created. */
static void journal_rollback(void)
{
    for (size_t i = (size_t)g_journal_live; i > 0; --i)
    {
        const journal_t *j = &g_journal[i - 1U];
        if (j->backup != NULL)
        {
            (void)rename(j->backup, j->target);
        }
        else if (!j->existed)
        {
            (void)unlink(j->target);
        }
    }
    g_journal_live = 0; /* the strings stay allocated: freeing is not async-signal-safe */
}

/* The signals the command handles are held while the journal changes, so that the handler's
 * rollback never sees an entry half made or a table half freed. */
static void hold_signals(int hold, sigset_t *old)
{
    sigset_t set;
    if (hold)
    {
        (void)sigemptyset(&set);
        (void)sigaddset(&set, SIGINT);
        (void)sigaddset(&set, SIGTERM);
        (void)sigaddset(&set, SIGHUP);
        (void)sigprocmask(SIG_BLOCK, &set, old);
    }
    else
    {
        (void)sigprocmask(SIG_SETMASK, old, NULL);
    }
}

/* The run's tables freed; the kept copies of the entries not rolled back are removed (the run
 * succeeded: the entries are taken out of the rollback's reach first). */
static void run_free(void)
{
    sigset_t old;
    hold_signals(1, &old);
    const size_t live = (size_t)g_journal_live;
    g_journal_live = 0;
    for (size_t i = 0; i < g_journal_len; ++i)
    {
        if (i < live && g_journal[i].backup != NULL)
        {
            (void)unlink(g_journal[i].backup);
        }
        free(g_journal[i].target);
        free(g_journal[i].backup);
    }
    free(g_journal);
    g_journal = NULL;
    g_journal_len = 0;
    g_journal_cap = 0;
    for (size_t i = 0; i < g_n_outputs; ++i)
    {
        free(g_outputs[i]);
    }
    free((void *)g_outputs);
    g_outputs = NULL;
    g_n_outputs = 0;
    g_outputs_cap = 0;
    free(g_inputs);
    g_inputs = NULL;
    g_n_inputs = 0;
    g_inputs_cap = 0;
    hold_signals(0, &old);
}

void aenl_outfile_run_begin(void)
{
    journal_rollback(); /* a run left unended failed */
    run_free();         /* a run starts with nothing read and nothing written */
    g_run = 1;
    g_run_owner = getpid();
    if (!g_atexit_done && atexit(outfile_at_exit) == 0)
    {
        g_atexit_done = 1;
    }
}

void aenl_outfile_run_keep(void)
{
    run_free();
    g_run = 0;
    g_run_owner = 0;
}

/* The file a path names once symbolic links are followed (a dangling link names the file it
 * would create), in malloc'd memory. *st receives lstat's answer for that file and *exists
 * whether it exists. Links are followed one at a time because realpath() fails on a dangling
 * one, which a user may still expect to be written through. */
static char *resolve_target(const char *path, struct stat *st, int *exists, int *magic,
                            aenl_err_t *err)
{
    char *cur = dup_str(path);
    int hops;
    *magic = 0;
    for (hops = 0; cur != NULL && hops < 40; ++hops)
    {
        char link[4096];
        ssize_t n;
        char *next;
        if (lstat(cur, st) != 0)
        {
            if (errno == ENOENT)
            {
                *exists = 0;
                return cur;
            }
            aenl_err_set(err, "%s: cannot examine (%s)", path, strerror(errno));
            free(cur);
            return NULL;
        }
        if (!S_ISLNK(st->st_mode))
        {
            *exists = 1;
            return cur;
        }
        if (strncmp(cur, "/proc/", 6) == 0 || strncmp(cur, "/dev/fd/", 8) == 0)
        {
            /* A kernel's link to an open file (a pipe, a terminal, a redirected file): its text
             * is not a path to write beside; the link itself is opened as it is. */
            *magic = 1;
            return cur;
        }
        n = readlink(cur, link, sizeof link - 1U);
        if (n < 0)
        {
            aenl_err_set(err, "%s: cannot read the link (%s)", path, strerror(errno));
            free(cur);
            return NULL;
        }
        link[n] = '\0';
        if (link[0] == '/' || strrchr(cur, '/') == NULL)
        {
            next = dup_str(link);
        }
        else
        {
            /* A relative target is relative to the link's own folder. */
            size_t dir_len = (size_t)(strrchr(cur, '/') - cur) + 1U;
            next = (char *)malloc(dir_len + (size_t)n + 1U);
            if (next != NULL)
            {
                memcpy(next, cur, dir_len);
                memcpy(next + dir_len, link, (size_t)n + 1U);
            }
        }
        free(cur);
        cur = next;
    }
    if (cur == NULL)
    {
        aenl_err_set(err, "%s: out of memory", path);
        return NULL;
    }
    free(cur);
    aenl_err_set(err, "%s: too many levels of symbolic links", path);
    return NULL;
}

/* "-" and the usual names of standard output (and of standard error) are written through the
 * process's own stream, so a redirection's offset and append mode are kept. */
static int names_stdout(const char *path)
{
    return strcmp(path, "-") == 0 || strcmp(path, "/dev/stdout") == 0 ||
           strcmp(path, "/dev/fd/1") == 0 || strcmp(path, "/proc/self/fd/1") == 0;
}

static int names_stderr(const char *path)
{
    return strcmp(path, "/dev/stderr") == 0 || strcmp(path, "/dev/fd/2") == 0 ||
           strcmp(path, "/proc/self/fd/2") == 0;
}

/* Standard output or standard error: flushed at commit, never closed. */
static aenl_status_t open_stdout(aenl_outfile_t *of, FILE *stream, aenl_err_t *err)
{
    of->path = dup_str(stream == stderr ? "/dev/stderr" : "/dev/stdout");
    if (of->path == NULL)
    {
        aenl_err_set(err, "standard output: out of memory");
        return AENL_E_IO;
    }
    of->fp = stream;
    of->direct = 2;
    return AENL_OK;
}

/* A device, FIFO or socket, or a kernel link to an open file: opened and written as it is,
 * never replaced. Takes `target` (malloc'd). */
static aenl_status_t open_direct(aenl_outfile_t *of, const char *path, char *target,
                                 aenl_err_t *err)
{
    struct stat st;
    int fd;
    if (is_input(target))
    {
        free(target);
        aenl_err_set(err, "%s: is an input of this run; write the output under another name", path);
        return AENL_E_ARG;
    }
    /* Through a kernel link a regular file is truncated, as a shell's '>' would do. */
    const int trunc = (stat(target, &st) == 0 && S_ISREG(st.st_mode)) ? O_TRUNC : 0;
    fd = open(target, O_WRONLY | O_NOCTTY | trunc);
    if (fd < 0)
    {
        const int e = errno;
        free(target);
        aenl_err_set(err, "%s: cannot open for writing (%s)", path, strerror(e));
        return AENL_E_IO;
    }
    of->fp = fdopen(fd, "w");
    if (of->fp == NULL)
    {
        const int e = errno;
        (void)close(fd);
        free(target);
        aenl_err_set(err, "%s: cannot open a stream (%s)", path, strerror(e));
        return AENL_E_IO;
    }
    of->path = target;
    of->direct = 1;
    return AENL_OK;
}

aenl_status_t aenl_outfile_open(aenl_outfile_t *of, const char *path, aenl_err_t *err)
{
    int fd = -1;
    int attempt;
    int exists = 0;
    int magic = 0;
    char *tmp = NULL;
    char *final_path;
    struct stat st;
    size_t len;

    if (of == NULL)
    {
        aenl_err_set(err, "aenl_outfile_open: NULL outfile");
        return AENL_E_ARG;
    }
    outfile_zero(of);
    if (path == NULL || path[0] == '\0')
    {
        aenl_err_set(err, "output file: empty path");
        return AENL_E_ARG;
    }
    if (names_stdout(path) || names_stderr(path))
    {
        return open_stdout(of, names_stdout(path) ? stdout : stderr, err);
    }
    len = strlen(path);
    if (path[len - 1] == '/')
    {
        aenl_err_set(err, "%s: is a folder, not a file name", path);
        return AENL_E_ARG;
    }
    final_path = resolve_target(path, &st, &exists, &magic, err);
    if (final_path == NULL)
    {
        return AENL_E_IO;
    }
    if (magic)
    {
        return open_direct(of, path, final_path, err);
    }
    if (exists && S_ISDIR(st.st_mode))
    {
        free(final_path);
        aenl_err_set(err, "%s: is a folder, not a file name", path);
        return AENL_E_ARG;
    }
    if (exists && !S_ISREG(st.st_mode))
    {
        return open_direct(of, path, final_path, err);
    }
    const aenl_status_t claim = run_claim_output(path, final_path, err);
    if (claim != AENL_OK)
    {
        free(final_path);
        return claim;
    }
    if (exists && access(final_path, W_OK) != 0)
    {
        /* Replacing by rename would succeed in a writable folder; a shell's '>' would not. */
        const int e = errno;
        free(final_path);
        aenl_err_set(err, "%s: cannot write (%s)", path, strerror(e));
        return AENL_E_IO;
    }
    for (attempt = 0; attempt < 100; ++attempt)
    {
        tmp = make_tmp_name(final_path, "tmp", g_tmp_counter++);
        if (tmp == NULL)
        {
            break;
        }
        /* 0666 & ~umask: the final file gets ordinary permissions (mkstemp would give 0600). */
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0 || errno != EEXIST)
        {
            break;
        }
        free(tmp);
        tmp = NULL;
    }
    if (tmp == NULL)
    {
        free(final_path);
        aenl_err_set(err, "%s: cannot create a temporary file (out of memory or names exhausted)",
                     path);
        return AENL_E_IO;
    }
    if (fd < 0)
    {
        int e = errno;
        free(tmp);
        free(final_path);
        aenl_err_set(err, "%s: cannot create (%s)", path, strerror(e));
        return AENL_E_IO;
    }
    if (exists)
    {
        /* The replacement keeps the permissions the user gave the file it replaces. */
        (void)fchmod(fd, st.st_mode & 07777);
    }
    if (pending_add(tmp) != 0)
    {
        (void)close(fd);
        (void)unlink(tmp);
        free(tmp);
        free(final_path);
        aenl_err_set(err, "%s: out of memory", path);
        return AENL_E_IO;
    }
    if (!g_atexit_done)
    {
        if (atexit(outfile_at_exit) == 0)
        {
            g_atexit_done = 1;
        }
    }
    of->fp = fdopen(fd, "w");
    if (of->fp == NULL)
    {
        int e = errno;
        pending_remove(tmp);
        (void)close(fd);
        (void)unlink(tmp);
        free(tmp);
        free(final_path);
        aenl_err_set(err, "%s: cannot open a stream (%s)", path, strerror(e));
        return AENL_E_IO;
    }
    of->path = final_path;
    of->tmp_path = tmp;
    return AENL_OK;
}

const char *aenl_outfile_write_path(const aenl_outfile_t *of)
{
    if (of == NULL)
    {
        return NULL;
    }
    return (of->tmp_path != NULL) ? of->tmp_path : of->path;
}

/* Flush and close a direct output (standard output is flushed, not closed). */
static aenl_status_t commit_direct(aenl_outfile_t *of, aenl_err_t *err)
{
    int e = 0;
    if (fflush(of->fp) != 0)
    {
        e = errno;
    }
    else if (ferror(of->fp))
    {
        e = EIO;
    }
    if (of->direct == 1 && fclose(of->fp) != 0 && e == 0)
    {
        e = errno;
    }
    if (e != 0)
    {
        aenl_err_set(err, "%s: cannot write (%s)", of->path, strerror(e));
    }
    free(of->path);
    outfile_zero(of);
    return (e != 0) ? AENL_E_IO : AENL_OK;
}

aenl_status_t aenl_outfile_commit(aenl_outfile_t *of, aenl_err_t *err)
{
    int failed = 0;
    int e = 0;
    const char *what = "";
    if (of != NULL && of->direct != 0 && of->fp != NULL && of->path != NULL)
    {
        return commit_direct(of, err);
    }
    if (of == NULL || of->fp == NULL || of->tmp_path == NULL || of->path == NULL)
    {
        aenl_err_set(err, "aenl_outfile_commit: the output file is not open");
        aenl_outfile_abort(of);
        return AENL_E_ARG;
    }
    /* Every step is checked: a full disk shows up at fflush or fclose, not at fprintf. */
    if (fflush(of->fp) != 0)
    {
        failed = 1;
        e = errno;
        what = "write";
    }
    else if (ferror(of->fp))
    {
        failed = 1;
        e = EIO;
        what = "write";
    }
    if (fclose(of->fp) != 0 && !failed)
    {
        failed = 1;
        e = errno;
        what = "close";
    }
    of->fp = NULL;
    if (!failed && is_input(of->path))
    {
        /* an input read after the output was opened */
        aenl_err_set(err, "%s: is an input of this run; write the output under another name",
                     of->path);
        aenl_outfile_abort(of);
        return AENL_E_ARG;
    }
    journal_t j = {NULL, NULL, 0, 0};
    sigset_t held;
    hold_signals(1, &held);
    if (!failed && g_run && journal_prepare(of->path, &j) != 0)
    {
        failed = 1;
        e = ENOMEM;
        what = "keep the file it replaces";
    }
    if (!failed && rename(of->tmp_path, of->path) != 0)
    {
        failed = 1;
        e = errno;
        what = "rename into place";
    }
    if (failed)
    {
        journal_discard(&j);
        hold_signals(0, &held);
        aenl_err_set(err, "%s: cannot %s (%s)", of->path, what, strerror(e));
        aenl_outfile_abort(of); /* removes the temporary, frees, zeroes */
        return AENL_E_IO;
    }
    if (g_run)
    {
        g_journal[g_journal_len++] = j; /* journal_prepare made the room */
        g_journal_live = (sig_atomic_t)g_journal_len;
    }
    hold_signals(0, &held);
    pending_remove(of->tmp_path);
    free(of->tmp_path);
    free(of->path);
    outfile_zero(of);
    return AENL_OK;
}

void aenl_outfile_abort(aenl_outfile_t *of)
{
    if (of == NULL)
    {
        return;
    }
    if (of->fp != NULL && of->direct == 2)
    {
        (void)fflush(of->fp); /* standard output stays open */
    }
    else if (of->fp != NULL)
    {
        (void)fclose(of->fp);
    }
    if (of->tmp_path != NULL)
    {
        pending_remove(of->tmp_path);
        (void)unlink(of->tmp_path);
        free(of->tmp_path);
    }
    free(of->path);
    outfile_zero(of);
}

/* ---- aenl's own files ------------------------------------------------------------------------ */

#ifndef AENL_SHARE_DIR
#define AENL_SHARE_DIR "/usr/local/share/aenl"
#endif

/* BIN/../share/aenl for the running executable, or "" when /proc/self/exe cannot be read. */
static void share_beside_exe(char *buf, size_t n)
{
    char exe[4096];
    buf[0] = '\0';
    const ssize_t len = readlink("/proc/self/exe", exe, sizeof(exe) - 1u);
    if (len <= 0)
    {
        return;
    }
    exe[len] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash == NULL)
    {
        return;
    }
    *slash = '\0';
    const int w = snprintf(buf, n, "%s/../share/aenl", exe);
    if (w < 0 || (size_t)w >= n)
    {
        buf[0] = '\0';
    }
}

aenl_status_t aenl_share_path(const char *rel, char *buf, size_t n, aenl_err_t *err)
{
    char beside[4200];
    share_beside_exe(beside, sizeof(beside));
    const char *env = getenv("AENL_SHARE_DIR");
    const char *dirs[3] = {env, beside, AENL_SHARE_DIR};
    for (size_t i = 0; i < 3; ++i)
    {
        if (dirs[i] == NULL || dirs[i][0] == '\0')
        {
            continue;
        }
        struct stat sb;
        const int len = snprintf(buf, n, "%s/%s", dirs[i], rel);
        if (len > 0 && (size_t)len < n && stat(buf, &sb) == 0)
        {
            return AENL_OK;
        }
    }
    aenl_err_set(err, "%s not found (looked in $AENL_SHARE_DIR = '%s', '%s' and '%s')", rel,
                 env != NULL ? env : "", beside, AENL_SHARE_DIR);
    if (n > 0)
    {
        buf[0] = '\0';
    }
    return AENL_E_IO;
}
