/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_io.h
 * @brief Host-only: error messages and output files that appear only when complete.
 *
 * Host functions report failures as an aenl_status_t plus one human-readable message in an
 * aenl_err_t (what and where: "data.csv:12:3: not a number 'x1'"). Only `main` prints.
 * Every file the tools write goes through aenl_outfile_t: a regular file (or a new name) is
 * written under a temporary name in the same folder and renamed into place by
 * aenl_outfile_commit(), so a failure (or an exit before commit) never leaves a partial output
 * file behind. Symbolic links are followed (the file they name is replaced, the link kept); a
 * device, FIFO or socket, and "-" for standard output, are written directly and never replaced.
 */
#ifndef AENL_TOOLS_IO_H
#define AENL_TOOLS_IO_H

#include <stdio.h>

#include "aenl/aenl_types.h"

#if defined(__GNUC__)
#define AENL_PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define AENL_PRINTF_LIKE(f, a)
#endif

/** One error message; the first cause is kept (later aenl_err_set calls do not overwrite). */
typedef struct aenl_err
{
    char msg[768];
} aenl_err_t;

/** Empty the message. */
void aenl_err_clear(aenl_err_t *err);

/** Set the message (printf-style) unless one is already set. err may be NULL. */
void aenl_err_set(aenl_err_t *err, const char *fmt, ...) AENL_PRINTF_LIKE(2, 3);

/** An output file under construction. Fields are private. */
typedef struct aenl_outfile
{
    FILE *fp;       /**< write through this between open and commit */
    char *path;     /**< final path */
    char *tmp_path; /**< temporary path in the same folder (NULL when written directly) */
    int direct;     /**< 0 temporary and rename, 1 a device or FIFO written as it is, 2 stdout */
} aenl_outfile_t;

/**
 * @brief Open `path` for writing: a regular file or a new name gets a temporary twin in the same
 *        folder (symbolic links followed); a device, FIFO or socket is opened as it is; "-" is
 *        standard output. Fails with AENL_E_IO (message names the path) if the folder does not
 *        exist or is not writable, or the existing file is not writable; with AENL_E_ARG for a
 *        folder. The final path is not touched.
 */
aenl_status_t aenl_outfile_open(aenl_outfile_t *of, const char *path, aenl_err_t *err);

/** The path another process should write to (the temporary, or the target when direct). */
const char *aenl_outfile_write_path(const aenl_outfile_t *of);

/**
 * @brief Flush, close and rename into place. On any write error the temporary is removed and
 *        AENL_E_IO returned; the final path is then untouched.
 */
aenl_status_t aenl_outfile_commit(aenl_outfile_t *of, aenl_err_t *err);

/** Close and remove the temporary. Safe on a zeroed, aborted or committed outfile. */
void aenl_outfile_abort(aenl_outfile_t *of);

/**
 * Remove every temporary still open and, inside a run, put back every file the run's commits
 * replaced and remove every file they created (called at exit; also usable by a signal handler).
 */
void aenl_outfile_abort_all(void);

/**
 * @brief Begin a run (the `aenl` command: one per process). Inside a run an output may name
 *        neither a file the run has read (aenl_input_note) nor another of its outputs
 *        (AENL_E_ARG from aenl_outfile_open or aenl_outfile_commit), and each commit keeps the
 *        file it replaces until the run ends: aenl_outfile_run_keep when it succeeded, else
 *        aenl_outfile_abort_all (also at exit) restores them.
 */
void aenl_outfile_run_begin(void);

/** End a run that succeeded: its outputs stay, the files they replaced are removed. */
void aenl_outfile_run_keep(void);

/**
 * Note a file the run reads (a regular file; "-" and others, and any file outside a run, are
 * ignored), so that no output of the run replaces it: aenl_outfile_open and aenl_outfile_commit
 * refuse it (AENL_E_ARG).
 */
void aenl_input_note(const char *path);

/**
 * @brief The path of one of aenl's own files (`rel`: "plot/moments.gp", "examples/x.ini", a
 *        folder such as "source") in the first of these folders that holds it:
 *        $AENL_SHARE_DIR; share/aenl beside the executable's folder (BIN/../share/aenl, which
 *        is where `cmake --install` puts them, so an installed tree can be moved anywhere;
 *        the build tree has the same layout); the folder the build was configured to install
 *        to. AENL_E_IO with a message naming the folders searched when none holds it.
 */
aenl_status_t aenl_share_path(const char *rel, char *buf, size_t n, aenl_err_t *err);

#endif /* AENL_TOOLS_IO_H */
