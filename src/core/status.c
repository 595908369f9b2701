/*
 * status.c — status names and the thread-local error message.
 * The library never prints; callers read bvox_errmsg() after a failure.
 */
#include "internal.h"

#include <stdio.h>
#include <string.h>

static _Thread_local char errmsg[1024];

const char *bvox_version(void) { return BVOX_VERSION; }

const char *bvox_status_name(bvox_status status)
{
    switch (status) {
    case BVOX_OK: return "BVOX_OK";
    case BVOX_EINVAL: return "BVOX_EINVAL";
    case BVOX_ENOMEM: return "BVOX_ENOMEM";
    case BVOX_EIO: return "BVOX_EIO";
    case BVOX_EFORMAT: return "BVOX_EFORMAT";
    case BVOX_ETOOBIG: return "BVOX_ETOOBIG";
    case BVOX_ENOTFOUND: return "BVOX_ENOTFOUND";
    case BVOX_EUNSUPPORTED: return "BVOX_EUNSUPPORTED";
    case BVOX_ECANCELED: return "BVOX_ECANCELED";
    }
    return "BVOX_E?";
}

const char *bvox_errmsg(void) { return errmsg; }

void bvox__clear_error(void) { errmsg[0] = '\0'; }

bvox_status bvox__fail(bvox_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(errmsg, sizeof errmsg, fmt, ap);
    va_end(ap);
    return status;
}

void bvox__error_prefix(const char *prefix)
{
    if (!prefix || !*prefix) return;
    size_t plen = strlen(prefix);
    /* Do not prefix twice (nested readers may both add the file name). */
    if (strncmp(errmsg, prefix, plen) == 0 && errmsg[plen] == ':') return;
    char tmp[sizeof errmsg + 256];
    snprintf(tmp, sizeof tmp, "%.200s: %s", prefix, errmsg);
    tmp[sizeof errmsg - 1] = '\0';
    memcpy(errmsg, tmp, sizeof errmsg);
}
