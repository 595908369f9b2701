/*
 * progress.c — the command's progress line and its Ctrl-C.
 *
 * The library reports long work through the thread's progress callback
 * (bvox_set_progress). On a terminal, once a command has run for about a
 * second, one line on stderr is rewritten in place ("bvox: dilate  42%") and
 * erased when a library call ends (before the command prints its result) or
 * when it prints a message; never in a pipe or a
 * log, never with --json (a script reads those) or --quiet.
 * BVOX_PROGRESS_DELAY=S changes the second (0: at once).
 *
 * Ctrl-C: the first one asks the library to stop at its next check (the
 * callback returns non-zero): the call frees what it holds, its temporary
 * output is removed and nothing half-written is left; the command then exits
 * with 130, as a shell reports a death by SIGINT. A second Ctrl-C does not
 * wait: the library's temporary files are removed and the process dies of
 * the signal.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "progress.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static volatile sig_atomic_t interrupts;
static int draw, drawn;
static double t_start, t_drawn, delay = 1.0;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static void on_interrupt(int sig)
{
    if (interrupts++ == 0) return; /* the callback stops the work */
    bvox_remove_temp_files();      /* async-signal-safe */
    signal(sig, SIG_DFL);
    raise(sig);
}

static int on_progress(double fraction, const char *stage, void *user)
{
    (void)user;
    if (interrupts) return 1;
    if (!draw) return 0;
    if (fraction >= 1) { /* a call is done: erased before the command prints its result */
        cli_progress_clear();
        return 0;
    }
    double t = now_s();
    if (t - t_start < delay || (drawn && t - t_drawn < 0.1)) return 0;
    fprintf(stderr, "\r\033[Kbvox: %s %3d%%", stage, (int)(fraction * 100));
    fflush(stderr);
    drawn = 1;
    t_drawn = t;
    return 0;
}

void cli_progress_install(int draw_line)
{
    draw = draw_line;
    t_start = now_s();
    /* BVOX_PROGRESS_DELAY: seconds of work before the line shows (default 1;
     * the tests set 0) */
    const char *env = getenv("BVOX_PROGRESS_DELAY");
    if (env && *env) delay = atof(env);
    bvox_set_progress(on_progress, NULL);
    /* Installed before bvox_cleanup_on_signals, which then leaves SIGINT to
     * this handler (and keeps its own for SIGTERM and SIGHUP). */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    struct sigaction old;
    if (sigaction(SIGINT, NULL, &old) == 0 && old.sa_handler == SIG_DFL)
        sigaction(SIGINT, &sa, NULL);
}

void cli_progress_clear(void)
{
    if (!drawn) return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    drawn = 0;
}

int cli_interrupted(void) { return interrupts != 0; }
