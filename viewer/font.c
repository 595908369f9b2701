/*
 * font.c — a 5x7 bitmap font for the overlay and the help screen, drawn
 * straight into the RGB canvas. Built in (95 glyphs, 475 bytes) rather than
 * SDL2_ttf: no font file to find at run time, no extra package, the same
 * pixels on every machine (golden screenshots compare exactly), and it works
 * off screen where SDL is not even initialised. The glyphs are the library's
 * (src/common/font5x7.c, the classic 5x7 LCD set): 5 columns per glyph, bit 0
 * the top row; drawn here into the viewer's RGB canvas.
 */
#include "view.h"
#include "common/font5x7.h"


static void put(uint8_t *rgb, int w, int h, int x, int y, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    uint8_t *p = rgb + ((size_t)y * (size_t)w + (size_t)x) * 3;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

void vw_text(uint8_t *rgb, int w, int h, int x, int y, int scale, const char *text,
             const uint8_t color[3])
{
    int x0 = x;
    for (const unsigned char *t = (const unsigned char *)text; *t; t++) {
        if (*t == '\n') {
            x = x0;
            y += 9 * scale;
            continue;
        }
        const uint8_t *glyph = bvox__font_glyph(*t);
        for (int col = 0; col < 5; col++)
            for (int row = 0; row < 7; row++)
                if (glyph[col] >> row & 1)
                    for (int a = 0; a < scale; a++)
                        for (int b = 0; b < scale; b++)
                            put(rgb, w, h, x + col * scale + b, y + row * scale + a, color);
        x += 6 * scale;
    }
}

int vw_text_width(const char *text, int scale)
{
    int n = 0, best = 0;
    for (; *text; text++) {
        if (*text == '\n') n = 0;
        else n++;
        best = n > best ? n : best;
    }
    return best * 6 * scale;
}

void vw_fill_rect(uint8_t *rgb, int w, int h, vw_rect r, const uint8_t color[3], int alpha)
{
    int x0 = r.x < 0 ? 0 : r.x, y0 = r.y < 0 ? 0 : r.y;
    int x1 = r.x + r.w > w ? w : r.x + r.w, y1 = r.y + r.h > h ? h : r.y + r.h;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            uint8_t *p = rgb + ((size_t)y * (size_t)w + (size_t)x) * 3;
            for (int c = 0; c < 3; c++) p[c] = (uint8_t)((p[c] * (255 - alpha) + color[c] * alpha + 127) / 255);
        }
}
