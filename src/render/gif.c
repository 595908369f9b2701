/*
 * gif.c — animated GIF output (giflib) for turntables: the encoder writes
 * through an output callback straight into a bvox__sink (temporary file,
 * renamed on commit), one frame at a time.
 *
 * The file: GIF89a, a global gray palette when the first frame is gray,
 * the NETSCAPE2.0 application block that makes viewers loop forever, then per
 * frame a graphics control block (the delay) and the image. RGB frames get
 * their own 256-colour palette from giflib's median cut (GifQuantizeBuffer),
 * since a cut face tint or an anaglyph has more than 256 colours.
 */
#include "gif.h"
#include "io/io.h"

#include <gif_lib.h>
#include <stdlib.h>
#include <string.h>

struct bvox__gif {
    bvox__sink sink;
    GifFileType *gif;
    int32_t w, h;
    int delay;
    long frames;
    int has_global_gray;
    char *path;
};

static int out_fn(GifFileType *gif, const GifByteType *data, int len)
{
    bvox__gif *g = gif->UserData;
    return bvox__sink_write(&g->sink, data, (size_t)len) == BVOX_OK ? len : 0;
}

static bvox_status gif_fail(bvox__gif *g, int err, const char *what)
{
    const char *msg = GifErrorString(err);
    return bvox__fail(err == E_GIF_ERR_NOT_ENOUGH_MEM ? BVOX_ENOMEM : BVOX_EIO, "%s: %s: %s",
                      g->path, what, msg ? msg : "giflib error");
}

static ColorMapObject *gray_map(void)
{
    GifColorType c[256];
    for (int i = 0; i < 256; i++) c[i].Red = c[i].Green = c[i].Blue = (GifByteType)i;
    return GifMakeMapObject(256, c);
}

bvox_status bvox__gif_open(const char *path, int32_t width, int32_t height, int delay_cs,
                           bvox__gif **out)
{
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "GIF: no output path");
    if (width < 1 || height < 1 || width > 65535 || height > 65535)
        return bvox__fail(BVOX_EINVAL, "%s: a GIF frame is 1..65535 pixels a side, not %d x %d",
                          path, (int)width, (int)height);
    if (delay_cs < 0 || delay_cs > 65535)
        return bvox__fail(BVOX_EINVAL, "%s: frame delay %d out of range", path, delay_cs);
    bvox__gif *g = bvox__mem_zalloc(1, sizeof *g);
    char *p = g ? bvox__mem_strdup(path) : NULL;
    if (!p) {
        free(g);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    g->path = p;
    g->w = width, g->h = height, g->delay = delay_cs;
    bvox_status st = bvox__sink_open(path, 0, &g->sink);
    if (st) {
        free(g->path);
        free(g);
        return st;
    }
    int err = 0;
    g->gif = EGifOpen(g, out_fn, &err);
    if (!g->gif) {
        st = gif_fail(g, err, "cannot start the encoder");
        bvox__gif_abort(g);
        return st;
    }
    EGifSetGifVersion(g->gif, true); /* extensions need GIF89a */
    *out = g;
    return BVOX_OK;
}

static bvox_status start(bvox__gif *g, int gray)
{
    ColorMapObject *map = gray ? gray_map() : NULL;
    if (gray && !map) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int ok = EGifPutScreenDesc(g->gif, g->w, g->h, 8, 0, map) == GIF_OK;
    GifFreeMapObject(map);
    static const GifByteType loop[3] = {1, 0, 0}; /* sub-block 1: repeat 0 = forever */
    ok = ok && EGifPutExtensionLeader(g->gif, APPLICATION_EXT_FUNC_CODE) == GIF_OK &&
         EGifPutExtensionBlock(g->gif, 11, "NETSCAPE2.0") == GIF_OK &&
         EGifPutExtensionBlock(g->gif, 3, loop) == GIF_OK &&
         EGifPutExtensionTrailer(g->gif) == GIF_OK;
    if (!ok) return gif_fail(g, g->gif->Error, "cannot write the header");
    g->has_global_gray = gray;
    return BVOX_OK;
}

/* The frame's indices (into idx) and, for RGB, its palette (*map). */
static bvox_status index_frame(bvox__gif *g, const bvox_image *f, uint8_t *idx,
                               ColorMapObject **map)
{
    const size_t n = (size_t)g->w * (size_t)g->h;
    *map = NULL;
    if (f->channels == 1) {
        memcpy(idx, f->pixels, n);
        if (!g->has_global_gray && !(*map = gray_map()))
            return bvox__fail(BVOX_ENOMEM, "out of memory");
        return BVOX_OK;
    }
    bvox_status st;
    uint8_t *planes = bvox__alloc(3 * n, false, "GIF colour planes", &st);
    if (!planes) return st;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) planes[c * n + i] = f->pixels[3 * i + (size_t)c];
    GifColorType colors[256];
    int size = 256;
    memset(colors, 0, sizeof colors);
    int ok = GifQuantizeBuffer((unsigned)g->w, (unsigned)g->h, &size, planes, planes + n,
                               planes + 2 * n, idx, colors) == GIF_OK;
    bvox__free(planes, 3 * n);
    if (!ok) return bvox__fail(BVOX_ENOMEM, "%s: cannot make a palette", g->path);
    if (!(*map = GifMakeMapObject(256, colors))) return bvox__fail(BVOX_ENOMEM, "out of memory");
    return BVOX_OK;
}

bvox_status bvox__gif_add(bvox__gif *g, const bvox_image *frame)
{
    bvox_status st = bvox__image_check(frame, "GIF frame");
    if (st) return st;
    if (frame->bits != 8 || frame->width != g->w || frame->height != g->h)
        return bvox__fail(BVOX_EINVAL, "%s: frame %ld is not %d x %d, 8 bits", g->path,
                          g->frames, (int)g->w, (int)g->h);
    if (!g->frames && (st = start(g, frame->channels == 1))) return st;
    const size_t n = (size_t)g->w * (size_t)g->h;
    uint8_t *idx = bvox__alloc(n, false, "GIF frame", &st);
    if (!idx) return st;
    ColorMapObject *map = NULL;
    st = index_frame(g, frame, idx, &map);
    if (!st) {
        GraphicsControlBlock gcb = {DISPOSE_DO_NOT, false, g->delay, NO_TRANSPARENT_COLOR};
        GifByteType ext[4];
        EGifGCBToExtension(&gcb, ext);
        int ok = EGifPutExtension(g->gif, GRAPHICS_EXT_FUNC_CODE, 4, ext) == GIF_OK &&
                 EGifPutImageDesc(g->gif, 0, 0, g->w, g->h, false, map) == GIF_OK;
        for (int32_t y = 0; ok && y < g->h; y++)
            ok = EGifPutLine(g->gif, idx + (size_t)y * (size_t)g->w, g->w) == GIF_OK;
        if (!ok) st = gif_fail(g, g->gif->Error, "cannot write a frame");
        else g->frames++;
    }
    GifFreeMapObject(map);
    bvox__free(idx, n);
    return st;
}

bvox_status bvox__gif_commit(bvox__gif *g)
{
    if (!g) return bvox__fail(BVOX_EINVAL, "GIF: no writer");
    if (!g->frames) {
        bvox__gif_abort(g);
        return bvox__fail(BVOX_EINVAL, "GIF: no frames to write");
    }
    int err = 0;
    int ok = EGifCloseFile(g->gif, &err) == GIF_OK;
    g->gif = NULL;
    bvox_status st = ok ? BVOX_OK : gif_fail(g, err, "cannot finish the file");
    if (st) bvox__sink_abort(&g->sink);
    else st = bvox__sink_commit(&g->sink);
    free(g->path);
    free(g);
    return st;
}

void bvox__gif_abort(bvox__gif *g)
{
    if (!g) return;
    if (g->gif) EGifCloseFile(g->gif, NULL);
    bvox__sink_abort(&g->sink);
    free(g->path);
    free(g);
}
