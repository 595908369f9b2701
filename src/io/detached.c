/*
 * detached.c — what the formats with a header and a separate data file
 * (NRRD's .nhdr, MetaImage's .mhd) share: the data file is named relative to
 * the header's folder, and both describe positions in the LPS frame of ITK
 * and 3D Slicer, which bvox turns into its own RAS frame (NIfTI's) and back.
 */
#include "io.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

bvox_status bvox__read_beside(const char *header_path, const char *file, bvox__bytes *out)
{
    char path[4096];
    const char *slash = strrchr(header_path, '/');
    int dir = slash && file[0] != '/' ? (int)(slash - header_path + 1) : 0;
    if (snprintf(path, sizeof path, "%.*s%s", dir, header_path, file) >= (int)sizeof path)
        return bvox__fail(BVOX_EINVAL, "%s: data file name '%s' is too long", header_path, file);
    return bvox__read_file(path, out);
}

void bvox__geometry_flip_lps(bvox_geometry *g)
{
    /* LPS <-> RAS: the first two world axes change sign (its own inverse);
     * + 0.0 turns -0 into 0, so headers do not show "-0" */
    for (int r = 0; r < 2; r++) {
        g->origin[r] = -g->origin[r] + 0.0;
        for (int c = 0; c < 3; c++) g->direction[r * 3 + c] = -g->direction[r * 3 + c] + 0.0;
    }
}

bvox_status bvox__detached_name(const char *path, size_t strip, const char *ext, char *out,
                                size_t cap, const char **base)
{
    size_t len = strlen(path);
    if (len < strip || len - strip + strlen(ext) >= cap)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", path);
    snprintf(out, cap, "%.*s%s", (int)(len - strip), path, ext);
    const char *slash = strrchr(out, '/');
    *base = slash ? slash + 1 : out;
    if (strlen(*base) > 400) return bvox__fail(BVOX_EINVAL, "%s: file name too long", path);
    return BVOX_OK;
}

bvox_status bvox__write_detached(const char *path, const char *data_path, const bvox_volume *vol,
                                 int gz, const char *header, size_t header_size)
{
    /* the data first, so that the header never names a missing file */
    bvox_status st = bvox__write_byte_slices(data_path, vol, gz, NULL, 0);
    if (st) return st;
    return bvox__write_header_after(path, data_path, header, header_size);
}

bvox_status bvox__write_header_after(const char *path, const char *data_path, const char *header,
                                     size_t header_size)
{
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, 0, &s);
    if (!st) st = bvox__sink_write(&s, header, header_size);
    if (!st) st = bvox__sink_commit(&s);
    else bvox__sink_abort(&s);
    if (st) unlink(data_path);
    return st;
}
