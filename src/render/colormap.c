/*
 * colormap.c — colour maps for 8-bit gray images (a 256-entry RGB table,
 * the frame grabber's colour output LUTs). Formulas follow MATLAB's maps:
 * hot rises through red, yellow to white in thirds; bone is 7/8 gray plus
 * 1/8 hot with the channels reversed (a blue-white tint for anatomy); copper
 * and cool are linear ramps.
 */
#include "render.h"

#include <string.h>
#include <strings.h>

static const char *const names[] = {"gray", "bone", "hot", "copper", "cool"};
#define NMAPS (int)(sizeof names / sizeof names[0])

const char *bvox_colormap_name(bvox_colormap map)
{
    return (unsigned)map < (unsigned)NMAPS ? names[map] : "unknown";
}

int bvox_colormap_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < NMAPS; i++)
        if (!strcasecmp(name, names[i])) return i;
    if (!strcasecmp(name, "grey")) return BVOX_CMAP_GRAY;
    return -1;
}

static double clamp01(double v) { return v < 0 ? 0 : v > 1 ? 1 : v; }

static void map_rgb(bvox_colormap map, double t, double rgb[3])
{
    switch (map) {
    case BVOX_CMAP_HOT:
        rgb[0] = clamp01(3 * t), rgb[1] = clamp01(3 * t - 1), rgb[2] = clamp01(3 * t - 2);
        break;
    case BVOX_CMAP_BONE:
        rgb[0] = (7 * t + clamp01(3 * t - 2)) / 8;
        rgb[1] = (7 * t + clamp01(3 * t - 1)) / 8;
        rgb[2] = (7 * t + clamp01(3 * t)) / 8;
        break;
    case BVOX_CMAP_COPPER:
        rgb[0] = clamp01(1.25 * t), rgb[1] = 0.7812 * t, rgb[2] = 0.4975 * t;
        break;
    case BVOX_CMAP_COOL:
        rgb[0] = t, rgb[1] = 1 - t, rgb[2] = 1;
        break;
    default:
        rgb[0] = rgb[1] = rgb[2] = t;
    }
}

bvox_status bvox_image_colormap(const bvox_image *in, bvox_colormap map, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(in, "colour map");
    if (st) return st;
    if ((unsigned)map >= (unsigned)NMAPS)
        return bvox__fail(BVOX_EINVAL, "unknown colour map %d", (int)map);
    if (in->channels != 1 || in->bits != 8)
        return bvox__fail(BVOX_EINVAL, "colour map: the image must be 8-bit gray");
    uint8_t table[256][3];
    for (int v = 0; v < 256; v++) {
        double rgb[3];
        map_rgb(map, v / 255.0, rgb);
        for (int c = 0; c < 3; c++) table[v][c] = (uint8_t)(rgb[c] * 255 + 0.5);
    }
    st = bvox_image_create(in->width, in->height, 3, 8, out);
    if (st) return st;
    size_t n = (size_t)in->width * (size_t)in->height;
    for (size_t i = 0; i < n; i++) memcpy((*out)->pixels + 3 * i, table[in->pixels[i]], 3);
    return BVOX_OK;
}
