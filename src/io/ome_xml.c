/*
 * ome_xml.c — the OME-XML an OME-TIFF carries in its first ImageDescription:
 * read the voxel size (Pixels PhysicalSizeX/Y/Z and their units, microns
 * when no unit is given, as the OME schema says) and write a minimal valid
 * document for `.ome.tif` output. Only the <Pixels> attributes matter to
 * bvox, so a full XML parser is not needed: attributes are found by name
 * inside the first <Pixels ...> tag (OME-XML has no entities in numbers and
 * units; "&#181;m" and "&#xB5;m" are decoded).
 */
#include "io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The value of attribute `name` inside tag [tag, end), copied to out. */
static int attr(const char *tag, const char *end, const char *name, char *out, size_t cap)
{
    size_t n = strlen(name);
    for (const char *p = tag; p + n + 2 < end; p++) {
        if (memcmp(p, name, n) || p[n] != '=' || (p[n + 1] != '"' && p[n + 1] != '\'')) continue;
        if (p > tag && p[-1] != ' ' && p[-1] != '\t' && p[-1] != '\n' && p[-1] != '\r') continue;
        char q = p[n + 1];
        const char *v = p + n + 2, *e = memchr(v, q, (size_t)(end - v));
        if (!e || (size_t)(e - v) >= cap) return 0;
        memcpy(out, v, (size_t)(e - v));
        out[e - v] = '\0';
        return 1;
    }
    return 0;
}

/* OME length units to bvox's names and their size in metres. */
static const struct {
    const char *ome, *unit;
    double metres;
} units[] = {
    {"\xc2\xb5m", "um", 1e-6}, {"&#181;m", "um", 1e-6}, {"&#xB5;m", "um", 1e-6},
    {"um", "um", 1e-6},        {"nm", "nm", 1e-9},      {"mm", "mm", 1e-3},
    {"cm", "cm", 1e-2},        {"m", "m", 1.0},         {"pm", "pm", 1e-12},
};

static int unit_index(const char *ome)
{
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
        if (!strcmp(ome, units[i].ome)) return (int)i;
    return -1;
}

int bvox__ome_parse(const char *desc, double spacing[3], char unit[16], bool have[3])
{
    have[0] = have[1] = have[2] = false;
    if (!desc || !strstr(desc, "<OME")) return 0;
    const char *tag = strstr(desc, "<Pixels");
    if (!tag) return 0;
    const char *end = strchr(tag, '>');
    if (!end) return 0;
    static const char *const size_key[3] = {"PhysicalSizeX", "PhysicalSizeY", "PhysicalSizeZ"};
    static const char *const unit_key[3] = {"PhysicalSizeXUnit", "PhysicalSizeYUnit",
                                            "PhysicalSizeZUnit"};
    double metres[3] = {0, 0, 0};
    int first = -1;
    for (int a = 0; a < 3; a++) {
        char v[64], u[32];
        if (!attr(tag, end, size_key[a], v, sizeof v)) continue;
        char *e;
        double s = strtod(v, &e);
        if (e == v || !(s > 0) || !isfinite(s)) continue;
        int k = attr(tag, end, unit_key[a], u, sizeof u) ? unit_index(u) : unit_index("um");
        if (k < 0) continue; /* a unit bvox cannot convert: not used */
        metres[a] = s * units[k].metres;
        if (first < 0) first = k;
        have[a] = true;
    }
    if (first < 0) return 1;
    /* every axis in the first axis's unit (OME allows one per axis) */
    strcpy(unit, units[first].unit);
    for (int a = 0; a < 3; a++)
        if (have[a]) spacing[a] = metres[a] / units[first].metres;
    return 1;
}

int bvox__ome_describe(const bvox_volume *v, char *buf, size_t cap)
{
    const bvox_geometry *g = bvox_volume_geometry(v);
    bvox_dims d = bvox_volume_dims(v);
    const char *ome_unit = NULL;
    for (size_t i = 0; i < sizeof units / sizeof units[0] && g->unit[0]; i++)
        if (!strcmp(g->unit, units[i].unit)) {
            ome_unit = i < 4 ? "\xc2\xb5m" : units[i].ome;
            break;
        }
    if (!strcmp(g->unit, "\xc2\xb5m")) ome_unit = "\xc2\xb5m";
    char phys[400] = "";
    if (ome_unit) /* no unit: no physical size (OME would read it as microns) */
        snprintf(phys, sizeof phys,
                 " PhysicalSizeX=\"%.15g\" PhysicalSizeXUnit=\"%s\" PhysicalSizeY=\"%.15g\""
                 " PhysicalSizeYUnit=\"%s\" PhysicalSizeZ=\"%.15g\" PhysicalSizeZUnit=\"%s\"",
                 g->spacing[0], ome_unit, g->spacing[1], ome_unit, g->spacing[2], ome_unit);
    return snprintf(
        buf, cap,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<OME xmlns=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\" "
        "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
        "xsi:schemaLocation=\"http://www.openmicroscopy.org/Schemas/OME/2016-06 "
        "http://www.openmicroscopy.org/Schemas/OME/2016-06/ome.xsd\" Creator=\"bvox %s\">"
        "<Image ID=\"Image:0\" Name=\"mask\"><Pixels ID=\"Pixels:0\" DimensionOrder=\"XYZCT\" "
        "Type=\"uint8\" SizeX=\"%d\" SizeY=\"%d\" SizeZ=\"%d\" SizeC=\"1\" SizeT=\"1\"%s>"
        "<Channel ID=\"Channel:0:0\" SamplesPerPixel=\"1\"/>"
        "<TiffData IFD=\"0\" PlaneCount=\"%d\"/></Pixels></Image></OME>",
        BVOX_VERSION, (int)d.nx, (int)d.ny, (int)d.nz, phys, (int)d.nz);
}
