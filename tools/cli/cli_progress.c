/* SPDX-License-Identifier: MIT */
/**
 * @file cli_progress.c
 * @brief A progress bar on stderr for the long runs, drawn only when stderr is a terminal: a
 *        log file or a pipe gets nothing, and the bar is erased when the run ends, so that what
 *        stays on the screen is the run's own output.
 */
#define _POSIX_C_SOURCE 200809L /* fileno */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aenl_cli.h"
#include "aenl_tools/aenl_clock.h"

#define BAR_CELLS 24

void aenl_cli_bar_begin(aenl_cli_bar_t *b, const char *cmd, const char *what)
{
    memset(b, 0, sizeof(*b));
    b->cmd = cmd;
    b->what = what;
    b->on = isatty(fileno(stderr)) && getenv("AENL_NO_PROGRESS") == NULL;
    b->t0 = aenl_now_s();
    b->shown = -1;
    b->progress.fn = aenl_cli_bar_update;
    b->progress.ctx = b;
}

void aenl_cli_bar_update(void *ctx, size_t done, size_t total)
{
    aenl_cli_bar_t *b = (aenl_cli_bar_t *)ctx;
    if (!b->on || total == 0)
    {
        return;
    }
    const size_t d = done < total ? done : total;
    const long cells = (long)(d * BAR_CELLS / total);
    const double secs = aenl_now_s() - b->t0;
    if (cells == b->shown && d != total && secs - b->t_shown < 1.0)
    {
        return; /* redrawn when a cell fills, and once a second for the clock */
    }
    char bar[BAR_CELLS + 1];
    for (long i = 0; i < BAR_CELLS; ++i)
    {
        bar[i] = i < cells ? '#' : '.';
    }
    bar[BAR_CELLS] = '\0';
    fprintf(stderr, "\raenl %s: %s [%s] %zu/%zu  %.0f s ", b->cmd, b->what, bar, d, total, secs);
    (void)fflush(stderr);
    b->shown = cells;
    b->t_shown = secs;
    b->drawn = 1;
}

void aenl_cli_bar_end(aenl_cli_bar_t *b)
{
    if (b->drawn)
    {
        fprintf(stderr, "\r\033[K"); /* the line erased: the output that follows stands alone */
        (void)fflush(stderr);
    }
    b->drawn = 0;
}
