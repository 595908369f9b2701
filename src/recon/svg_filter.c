/*
 * svg_filter.c — which SVG elements are a section's outlines. A drawing made
 * in an editor holds more than the tracing: a full-canvas background <rect>,
 * hidden layers, guides. Read blindly, the background alone fills 90 % of
 * the model. The rules (the reader applies them, and warns with counts):
 *   - hidden: display="none", visibility="hidden"/"collapse", or the same in
 *     a style="..." attribute, on the element or any ancestor <g>;
 *   - background: a <rect> covering the whole canvas (the viewBox, else
 *     width x height), or sized 100% x 100%;
 *   - selection (--svg-select): a comma-separated list of id:NAME,
 *     class:NAME, layer:NAME (Inkscape's inkscape:label, or a <g id>), or a
 *     bare NAME matching any of them; an element is read when it or an
 *     ancestor matches.
 */
#include "contour_internal.h"

#include <string.h>
#include <strings.h>

/* Does the attribute's value, as a whitespace-separated word list (class),
 * or as a whole (id, label), equal word? */
static int attr_has_word(const bvox__xml *x, const char *name, const char *word, size_t wlen,
                         int as_list)
{
    const bvox__xml_attr *a = bvox__xml_attr_get(x, name);
    if (!a) return 0;
    if (!as_list) return a->vlen == wlen && !memcmp(a->value, word, wlen);
    size_t i = 0;
    while (i < a->vlen) {
        while (i < a->vlen && (a->value[i] == ' ' || a->value[i] == '\t')) i++;
        size_t j = i;
        while (j < a->vlen && a->value[j] != ' ' && a->value[j] != '\t') j++;
        if (j - i == wlen && !memcmp(a->value + i, word, wlen)) return 1;
        i = j;
    }
    return 0;
}

/* "display: none" inside a style attribute, spaces and case ignored. */
static int style_says(const bvox__xml *x, const char *prop, const char *value)
{
    const bvox__xml_attr *a = bvox__xml_attr_get(x, "style");
    if (!a) return 0;
    size_t plen = strlen(prop), vlen = strlen(value);
    for (size_t i = 0; i + plen <= a->vlen; i++) {
        if (strncasecmp(a->value + i, prop, plen)) continue;
        if (i > 0 && a->value[i - 1] != ';' && a->value[i - 1] != ' ') continue;
        size_t k = i + plen;
        while (k < a->vlen && a->value[k] == ' ') k++;
        if (k >= a->vlen || a->value[k] != ':') continue;
        k++;
        while (k < a->vlen && a->value[k] == ' ') k++;
        if (k + vlen <= a->vlen && !strncasecmp(a->value + k, value, vlen)) return 1;
    }
    return 0;
}

static int attr_is(const bvox__xml *x, const char *name, const char *value)
{
    const bvox__xml_attr *a = bvox__xml_attr_get(x, name);
    return a && a->vlen == strlen(value) && !strncasecmp(a->value, value, a->vlen);
}

int bvox__svg_hides(const bvox__xml *x)
{
    return attr_is(x, "display", "none") || attr_is(x, "visibility", "hidden") ||
           attr_is(x, "visibility", "collapse") || style_says(x, "display", "none") ||
           style_says(x, "visibility", "hidden") || style_says(x, "visibility", "collapse");
}

int bvox__svg_selected(const bvox__xml *x, const char *select)
{
    const char *p = select;
    while (*p) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        const char *word = p;
        int kind = 0; /* 0 any, 1 id, 2 class, 3 layer */
        if (len > 3 && !strncmp(p, "id:", 3)) kind = 1, word += 3;
        else if (len > 6 && !strncmp(p, "class:", 6)) kind = 2, word += 6;
        else if (len > 6 && !strncmp(p, "layer:", 6)) kind = 3, word += 6;
        size_t wlen = len - (size_t)(word - p);
        if (wlen && (kind == 0 || kind == 1) && attr_has_word(x, "id", word, wlen, 0)) return 1;
        if (wlen && (kind == 0 || kind == 2) && attr_has_word(x, "class", word, wlen, 1)) return 1;
        if (wlen && (kind == 0 || kind == 3) && bvox__xml_is(x, "g") &&
            (attr_has_word(x, "inkscape:label", word, wlen, 0) ||
             (kind == 3 && attr_has_word(x, "id", word, wlen, 0))))
            return 1;
        p += len;
        if (*p == ',') p++;
    }
    return 0;
}

int bvox__svg_covers_canvas(const bvox_point2 corner[4], const double canvas[4])
{
    double x0 = corner[0].x, x1 = x0, y0 = corner[0].y, y1 = y0;
    for (int i = 1; i < 4; i++) {
        x0 = corner[i].x < x0 ? corner[i].x : x0;
        x1 = corner[i].x > x1 ? corner[i].x : x1;
        y0 = corner[i].y < y0 ? corner[i].y : y0;
        y1 = corner[i].y > y1 ? corner[i].y : y1;
    }
    /* within half a pixel, or 0.5 % of the canvas, of every edge or beyond */
    double tx = canvas[2] * 0.005 > 0.5 ? canvas[2] * 0.005 : 0.5;
    double ty = canvas[3] * 0.005 > 0.5 ? canvas[3] * 0.005 : 0.5;
    return canvas[2] > 0 && canvas[3] > 0 && x0 <= canvas[0] + tx && y0 <= canvas[1] + ty &&
           x1 >= canvas[0] + canvas[2] - tx && y1 >= canvas[1] + canvas[3] - ty;
}
