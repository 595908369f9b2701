/*
 * nrrd_write.c — binary volumes written as NRRD (beside the reader, nrrd.c):
 * uint8 samples 0/1, the geometry as "space directions" and "space origin"
 * in left-posterior-superior space (3D Slicer's and ITK's frame; bvox keeps
 * RAS, so x and y change sign on the way out, as they do on the way in) and
 * the unit as "space units".
 *  - `.nrrd`: header and gzip-encoded data in one file;
 *  - `.nhdr`: the header, with "data file: BASE.raw" written beside it first
 *    (raw encoding), so that the header never names a missing file.
 */
#include "io.h"
#include "common/names.h"
#include "common/strbuf.h"

#include <stdio.h>
#include <string.h>

void bvox__nrrd_describe(const bvox_volume *vol, const char *type, bool gzip,
                         const char *data_file, bvox__strbuf *sb)
{
    bvox_geometry g = *bvox_volume_geometry(vol);
    bvox__geometry_flip_lps(&g);
    bvox_dims d = bvox_volume_dims(vol);
    char dirs[3][96];
    for (int a = 0; a < 3; a++) /* axis a: column a of direction, scaled by its spacing */
        snprintf(dirs[a], sizeof dirs[a], "(%.17g,%.17g,%.17g)",
                 g.direction[0 * 3 + a] * g.spacing[a], g.direction[1 * 3 + a] * g.spacing[a],
                 g.direction[2 * 3 + a] * g.spacing[a]);
    bvox__sb_printf(sb,
                    "NRRD0004\n"
                    "# Complete NRRD file format specification at:\n"
                    "# http://teem.sourceforge.net/nrrd/format.html\n"
                    "# written by bvox\n"
                    "type: %s\ndimension: 3\nspace: left-posterior-superior\n"
                    "sizes: %ld %ld %ld\nspace directions: %s %s %s\n"
                    "kinds: domain domain domain\nendian: little\nencoding: %s\n"
                    "space origin: (%.17g,%.17g,%.17g)\n",
                    type, (long)d.nx, (long)d.ny, (long)d.nz, dirs[0], dirs[1], dirs[2],
                    gzip ? "gzip" : "raw", g.origin[0], g.origin[1], g.origin[2]);
    /* a quote or newline in the unit would break the header: leave it out */
    if (g.unit[0] && !strpbrk(g.unit, "\"\n\r\\"))
        bvox__sb_printf(sb, "space units: \"%s\" \"%s\" \"%s\"\n", g.unit, g.unit, g.unit);
    if (data_file) bvox__sb_printf(sb, "data file: %s\n", data_file);
}

/* The binary volume's header, ended by its blank line. */
static bvox_status describe(const bvox_volume *vol, bool gzip, const char *data_file,
                            bvox__strbuf *sb)
{
    bvox__nrrd_describe(vol, "uint8", gzip, data_file, sb);
    bvox__sb_puts(sb, "\n");
    if (!sb->failed) return BVOX_OK;
    bvox__sb_free(sb);
    return bvox__fail(BVOX_ENOMEM, "NRRD header: out of memory");
}

bvox_status bvox__nrrd_write(const char *path, const bvox_volume *vol,
                             const bvox_write_opts *opts)
{
    (void)opts;
    bvox__strbuf hdr = {0};
    bvox_status st;
    if (!bvox__ends_with_ci(path, ".nhdr")) {
        if ((st = describe(vol, true, NULL, &hdr))) return st;
        st = bvox__write_byte_slices(path, vol, 1 | BVOX__SINK_PLAIN_HEADER, hdr.data, hdr.len);
        bvox__sb_free(&hdr);
        return st;
    }
    char data_path[4096];
    const char *base;
    st = bvox__detached_name(path, 5, ".raw", data_path, sizeof data_path, &base);
    if (st) return st;
    if ((st = describe(vol, false, base, &hdr))) return st;
    st = bvox__write_detached(path, data_path, vol, 0, hdr.data, hdr.len);
    bvox__sb_free(&hdr);
    return st;
}
