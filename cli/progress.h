/*
 * progress.h — the progress line on a terminal and Ctrl-C as a clean cancel
 * (progress.c).
 */
#ifndef BVOX_CLI_PROGRESS_H
#define BVOX_CLI_PROGRESS_H

/* Set the library's progress callback for the command; draw_line: draw the
 * line (stderr is a terminal, no --json, no --quiet). Takes SIGINT. */
void cli_progress_install(int draw_line);
/* Erase the line if one is shown (before a message or at the end). */
void cli_progress_clear(void);
/* Whether Ctrl-C was pressed (the work was then canceled). */
int cli_interrupted(void);

#endif
