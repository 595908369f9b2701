/*
 * warn.c — warnings without printing: the library formats one line and hands
 * it to the calling thread's handler (the CLI prints "bvox: warning: ...",
 * Python turns it into warnings.warn). Thread-local so that two threads with
 * different callers never see each other's warnings and no lock is needed.
 */
#include "internal.h"

#include <stdarg.h>
#include <stdio.h>

static _Thread_local bvox_warning_fn handler;
static _Thread_local void *handler_user;
static _Thread_local uint64_t raised;

void bvox_set_warning_handler(bvox_warning_fn fn, void *user)
{
    handler = fn;
    handler_user = fn ? user : NULL;
}

uint64_t bvox_warning_count(void) { return raised; }

void bvox__warn(const char *fmt, ...)
{
    raised++;
    if (!handler) return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    handler(line, handler_user);
}
