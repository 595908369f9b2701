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

#include <stdio.h>
#include <string.h>

static int describe(const bvox_volume *vol, bool gzip, const char *data_file, char *buf,
                    size_t cap)
{
    bvox_geometry g = *bvox_volume_geometry(vol);
    bvox__geometry_flip_lps(&g);
    bvox_dims d = bvox_volume_dims(vol);
    char dirs[3][96];
    for (int a = 0; a < 3; a++) /* axis a: column a of direction, scaled by its spacing */
        snprintf(dirs[a], sizeof dirs[a], "(%.17g,%.17g,%.17g)",
                 g.direction[0 * 3 + a] * g.spacing[a], g.direction[1 * 3 + a] * g.spacing[a],
                 g.direction[2 * 3 + a] * g.spacing[a]);
    char units[80] = "";
    /* a quote or newline in the unit would break the header: leave it out */
    if (g.unit[0] && !strpbrk(g.unit, "\"\n\r\\"))
        snprintf(units, sizeof units, "space units: \"%s\" \"%s\" \"%s\"\n", g.unit, g.unit,
                 g.unit);
    char file_line[600] = "";
    if (data_file) snprintf(file_line, sizeof file_line, "data file: %s\n", data_file);
    return snprintf(buf, cap,
                    "NRRD0004\n"
                    "# Complete NRRD file format specification at:\n"
                    "# http://teem.sourceforge.net/nrrd/format.html\n"
                    "# written by bvox\n"
                    "type: uint8\ndimension: 3\nspace: left-posterior-superior\n"
                    "sizes: %ld %ld %ld\nspace directions: %s %s %s\n"
                    "kinds: domain domain domain\nendian: little\nencoding: %s\n"
                    "space origin: (%.17g,%.17g,%.17g)\n%s%s\n",
                    (long)d.nx, (long)d.ny, (long)d.nz, dirs[0], dirs[1], dirs[2],
                    gzip ? "gzip" : "raw", g.origin[0], g.origin[1], g.origin[2], units,
                    file_line);
}

bvox_status bvox__nrrd_write(const char *path, const bvox_volume *vol,
                             const bvox_write_opts *opts)
{
    (void)opts;
    char hdr[2048];
    if (!bvox__ends_with_ci(path, ".nhdr")) {
        int n = describe(vol, true, NULL, hdr, sizeof hdr);
        return bvox__write_byte_slices(path, vol, 1 | BVOX__SINK_PLAIN_HEADER, hdr, (size_t)n);
    }
    char data_path[4096];
    const char *base;
    bvox_status st = bvox__detached_name(path, 5, ".raw", data_path, sizeof data_path, &base);
    if (st) return st;
    int n = describe(vol, false, base, hdr, sizeof hdr);
    return bvox__write_detached(path, data_path, vol, 0, hdr, (size_t)n);
}
