/*
 * tiff_write.c — the TIFF stack writer, ImageJ/Fiji's way (the reader is
 * tiff.c).
 *
 * It does not use libtiff: ImageJ reads a stack whose description says
 * "images=N" as N images stored contiguously after the first IFD's strip
 * offset, ignoring the other IFDs, and libtiff interleaves pixel data and
 * IFDs. So the file is laid out as ImageJ writes it — header, IFD 0, its
 * values, all pixel data back to back (8-bit 0/255, ImageJ's binary mask
 * convention, uncompressed, one strip per page), then IFDs 1..N-1 — and
 * streamed through the sink (temporary file, renamed on success). Every page
 * still has a complete IFD, so libtiff, tifffile and Bio-Formats read it too.
 * The description carries unit (um as "micron"), spacing (z) and a non-zero
 * origin as ImageJ's xorigin/yorigin/zorigin (in pixels); XResolution and
 * YResolution are 1/sx and 1/sy pixels per unit, ResolutionUnit none. Classic
 * TIFF caps the file at 4 GiB: beyond it the write fails with ETOOBIG.
 */
#include "io.h"
#include "common/names.h"

#include <math.h>
#include <string.h>

enum { T_ASCII = 2, T_SHORT = 3, T_LONG = 4, T_RATIONAL = 5 };
#define IFD0_ENTRIES 14
#define IFDN_ENTRIES 13
#define IFD_BYTES(n) (2 + 12 * (n) + 4)

static void put16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static void put32(uint8_t *p, uint32_t v)
{
    put16(p, v & 0xffff);
    put16(p + 2, v >> 16);
}
static uint8_t *entry(uint8_t *p, uint16_t tag, uint16_t type, uint32_t count, uint32_t value)
{
    put16(p, tag);
    put16(p + 2, type);
    put32(p + 4, count);
    put32(p + 8, 0);
    if (type == T_SHORT) put16(p + 8, value); /* left-justified in the value field */
    else put32(p + 8, value);
    return p + 12;
}

/* One IFD (the first has the description). Entries in ascending tag order. */
static void build_ifd(uint8_t *p, const bvox_volume *v, uint32_t data_off, uint32_t next,
                      uint32_t res_off, uint32_t desc_off, uint32_t desc_len)
{
    uint32_t page = (uint32_t)v->nx * (uint32_t)v->ny;
    put16(p, desc_len ? IFD0_ENTRIES : IFDN_ENTRIES);
    uint8_t *e = p + 2;
    e = entry(e, 254, T_LONG, 1, 0);               /* NewSubfileType: a page */
    e = entry(e, 256, T_LONG, 1, (uint32_t)v->nx); /* ImageWidth */
    e = entry(e, 257, T_LONG, 1, (uint32_t)v->ny); /* ImageLength */
    e = entry(e, 258, T_SHORT, 1, 8);              /* BitsPerSample */
    e = entry(e, 259, T_SHORT, 1, 1);              /* Compression: none */
    e = entry(e, 262, T_SHORT, 1, 1);              /* Photometric: MinIsBlack */
    if (desc_len) e = entry(e, 270, T_ASCII, desc_len, desc_off);
    e = entry(e, 273, T_LONG, 1, data_off);        /* StripOffsets */
    e = entry(e, 277, T_SHORT, 1, 1);              /* SamplesPerPixel */
    e = entry(e, 278, T_LONG, 1, (uint32_t)v->ny); /* RowsPerStrip: one strip */
    e = entry(e, 279, T_LONG, 1, page);            /* StripByteCounts */
    e = entry(e, 282, T_RATIONAL, 1, res_off);     /* XResolution */
    e = entry(e, 283, T_RATIONAL, 1, res_off + 8); /* YResolution */
    e = entry(e, 296, T_SHORT, 1, 1);              /* ResolutionUnit: none */
    put32(e, next);
}

/* v as num/den with the largest denominator that keeps num in 32 bits. */
static void put_rational(uint8_t *p, double v)
{
    double den = fmin(4294967295.0, floor(4294967295.0 / fmax(v, 1.0)));
    double num = fmin(4294967295.0, fmax(1.0, floor(v * den + 0.5)));
    put32(p, (uint32_t)num);
    put32(p + 4, (uint32_t)den);
}

static int imagej_description(const bvox_volume *v, char *buf, size_t cap)
{
    const bvox_geometry *g = &v->geom;
    const char *unit = g->unit;
    if (!strcmp(unit, "um") || !strcmp(unit, "\xc2\xb5m")) unit = "micron";
    for (const char *p = unit; *p; p++)
        if (*p < 0x21 || *p > 0x7e || *p == '=') unit = ""; /* ImageJ wants ASCII */
    int n = snprintf(buf, cap, "ImageJ=1.11a\n");
    if (v->nz > 1) n += snprintf(buf + n, cap - n, "images=%d\nslices=%d\n", v->nz, v->nz);
    if (*unit) n += snprintf(buf + n, cap - n, "unit=%s\n", unit);
    if (v->nz > 1) n += snprintf(buf + n, cap - n, "spacing=%.15g\nloop=false\n", g->spacing[2]);
    static const char *const key[3] = {"xorigin", "yorigin", "zorigin"};
    for (int a = 0; a < 3; a++) /* ImageJ's origin is in pixels, of the opposite sign */
        if (g->origin[a] != 0)
            n += snprintf(buf + n, cap - n, "%s=%.15g\n", key[a], -g->origin[a] / g->spacing[a]);
    return n;
}

bvox_status bvox__tiff_write(const char *path, const bvox_volume *v, const bvox_write_opts *opts)
{
    (void)opts;
    char desc[2048];
    /* NAME.ome.tif: OME-XML (Bio-Formats, napari, QuPath read its physical
     * sizes); otherwise ImageJ's description */
    size_t plen = strlen(path);
    int ome = (plen > 8 && bvox__ends_with_ci(path, ".ome.tif")) ||
              (plen > 9 && bvox__ends_with_ci(path, ".ome.tiff"));
    int dl = ome ? bvox__ome_describe(v, desc, sizeof desc) : imagej_description(v, desc, sizeof desc);
    if (dl < 0 || (size_t)dl >= sizeof desc)
        return bvox__fail(BVOX_EINVAL, "%s: cannot format the TIFF description", path);
    uint32_t desc_len = (uint32_t)dl + 1;
    const uint64_t page = (uint64_t)v->nx * (uint64_t)v->ny, nz = (uint64_t)v->nz;
    const uint64_t res_off = 8 + IFD_BYTES(IFD0_ENTRIES), desc_off = res_off + 16;
    const uint64_t data_off = (desc_off + desc_len + 1) & ~1ull;
    const uint64_t data_end = data_off + page * nz, ifd1 = (data_end + 1) & ~1ull;
    const uint64_t total = ifd1 + (nz - 1) * IFD_BYTES(IFDN_ENTRIES);
    if (total > UINT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "%s: the TIFF stack would need %llu bytes, over the "
                          "4 GiB of classic TIFF (write NIfTI instead)",
                          path, (unsigned long long)total);

    uint8_t head[8 + IFD_BYTES(IFD0_ENTRIES) + 16 + sizeof desc + 2];
    memset(head, 0, sizeof head);
    memcpy(head, "II*\0", 4);
    put32(head + 4, 8);
    build_ifd(head + 8, v, (uint32_t)data_off, nz > 1 ? (uint32_t)ifd1 : 0, (uint32_t)res_off,
              (uint32_t)desc_off, desc_len);
    put_rational(head + res_off, 1.0 / v->geom.spacing[0]);
    put_rational(head + res_off + 8, 1.0 / v->geom.spacing[1]);
    memcpy(head + desc_off, desc, desc_len);

    size_t nslab = nz < 64 ? (size_t)nz : 64, slab_bytes = nslab * (size_t)page;
    bvox_status st;
    uint8_t *slab = bvox__alloc(slab_bytes, false, "TIFF slices", &st);
    if (!slab) return st;
    bvox__sink sink;
    st = bvox__sink_open(path, 0, &sink);
    if (st) {
        bvox__free(slab, slab_bytes);
        return st;
    }
    st = bvox__sink_write(&sink, head, (size_t)data_off);
    for (int32_t z0 = 0; z0 < v->nz && !st; z0 += 64) {
        int32_t n = v->nz - z0 < 64 ? v->nz - z0 : 64;
        bvox__unpack_slices(v, z0, n, 255, slab);
        st = bvox__sink_write(&sink, slab, (size_t)n * (size_t)page);
        if (!st) st = bvox__progress_steps(z0 + n, v->nz);
    }
    if (!st && ifd1 > data_end) st = bvox__sink_write(&sink, "", 1);
    /* IFDs 1..nz-1, written 64 at a time. */
    size_t per = IFD_BYTES(IFDN_ENTRIES), used = 0;
    uint8_t ifdbuf[64 * IFD_BYTES(IFDN_ENTRIES)];
    for (uint64_t z = 1; z < nz && !st; z++) {
        uint64_t off = ifd1 + (z - 1) * per;
        build_ifd(ifdbuf + used, v, (uint32_t)(data_off + z * page),
                  z + 1 < nz ? (uint32_t)(off + per) : 0, (uint32_t)res_off, 0, 0);
        used += per;
        if (used == sizeof ifdbuf || z + 1 == nz) {
            st = bvox__sink_write(&sink, ifdbuf, used);
            used = 0;
        }
    }
    bvox__free(slab, slab_bytes);
    if (st) {
        bvox__sink_abort(&sink);
        return st;
    }
    return bvox__sink_commit(&sink);
}
