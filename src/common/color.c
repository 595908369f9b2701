/*
 * color.c — colours from text: a short list of names (the CSS colours a
 * figure usually wants, with the CSS values, so "orange" is what a browser
 * shows) and hex #rrggbb or #rgb; and the default colour of a label.
 */
#include "common/color.h"

#include <ctype.h>
#include <math.h>
#include <string.h>
#include <strings.h>

static const struct {
    const char *name;
    uint8_t rgb[3];
} names[] = {
    {"black", {0, 0, 0}},        {"white", {255, 255, 255}},  {"gray", {128, 128, 128}},
    {"grey", {128, 128, 128}},   {"red", {255, 0, 0}},        {"green", {0, 128, 0}},
    {"lime", {0, 255, 0}},       {"blue", {0, 0, 255}},       {"yellow", {255, 255, 0}},
    {"cyan", {0, 255, 255}},     {"magenta", {255, 0, 255}},  {"orange", {255, 165, 0}},
    {"purple", {128, 0, 128}},   {"brown", {165, 42, 42}},    {"pink", {255, 192, 203}},
    {"gold", {255, 215, 0}},     {"navy", {0, 0, 128}},       {"teal", {0, 128, 128}},
};

const char *bvox__color_names(void)
{
    return "black, white, gray, red, green, lime, blue, yellow, cyan, magenta, orange, purple, "
           "brown, pink, gold, navy, teal";
}

static int hex(int c)
{
    return isdigit(c) ? c - '0' : isxdigit(c) ? tolower(c) - 'a' + 10 : -1;
}

int bvox__color_parse(const char *text, uint8_t rgb[3])
{
    if (!text) return -1;
    if (text[0] == '#') {
        size_t n = strlen(text + 1);
        if (n != 6 && n != 3) return -1;
        int v[6];
        for (size_t i = 0; i < n; i++)
            if ((v[i] = hex((unsigned char)text[1 + i])) < 0) return -1;
        for (int c = 0; c < 3; c++)
            rgb[c] = (uint8_t)(n == 6 ? v[2 * c] * 16 + v[2 * c + 1] : v[c] * 17);
        return 0;
    }
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcasecmp(text, names[i].name)) {
            memcpy(rgb, names[i].rgb, 3);
            return 0;
        }
    return -1;
}

/* A distinct hue per label: hue = label x the golden angle (137.5 degrees),
 * full saturation softened to 0.65, value 0.95; consecutive labels (often
 * neighbours in an atlas) land far apart on the colour wheel. */
void bvox__label_color(int64_t label, uint8_t rgb[3])
{
    double h = fmod((double)(label % 100000) * 137.50776405, 360.0) / 60.0;
    const double s = 0.65, v = 0.95;
    int i = (int)h;
    double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch (i % 6) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
    }
    rgb[0] = (uint8_t)(r * 255 + 0.5), rgb[1] = (uint8_t)(g * 255 + 0.5), rgb[2] = (uint8_t)(b * 255 + 0.5);
}
