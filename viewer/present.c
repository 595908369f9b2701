/*
 * present.c — the only file that talks to SDL2: a resizable window with a
 * streaming RGB texture the canvas is copied into (made again at the new
 * size after a resize), SDL's events turned into vw_events (a resize, a
 * dropped file), scripted events pushed through SDL's own queue, and the
 * window's pixels read back for screenshots.
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <SDL.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct vw_window {
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    int w, h;
    char drop[4096]; /* the last dropped file's path (the event points here) */
};

int vw_have_sdl(void) { return 1; }

void vw_sleep_ms(int ms)
{
    struct timespec t = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

int vw_window_open(vw_window **out, int width, int height, const char *title, char *err,
                   size_t errlen)
{
    *out = NULL;
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        snprintf(err, errlen, "cannot open a window (is DISPLAY set? under a test: xvfb-run): %s",
                 SDL_GetError());
        SDL_Quit();
        return 0;
    }
    /* SDL falls back to its off-screen driver when there is no display: a
     * window nobody sees would wait for input for ever. Only when asked for
     * by name (SDL_VIDEODRIVER) is such a driver accepted. */
    const char *drv = SDL_GetCurrentVideoDriver(), *want = getenv("SDL_VIDEODRIVER");
    if (drv && (!strcmp(drv, "offscreen") || !strcmp(drv, "dummy") || !strcmp(drv, "evdev")) &&
        !(want && !strcmp(want, drv))) {
        snprintf(err, errlen, "cannot open a window: no display (DISPLAY is not set; under a "
                              "test use xvfb-run, or --script FILE --offscreen)");
        SDL_Quit();
        return 0;
    }
    vw_window *w = bvox__mem_zalloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "out of memory");
        SDL_Quit();
        return 0;
    }
    w->w = width, w->h = height;
    w->win = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, width, height,
                              SDL_WINDOW_SHOWN | SDL_WINDOW_RESIZABLE);
    if (w->win) {
        w->ren = SDL_CreateRenderer(w->win, -1, SDL_RENDERER_ACCELERATED);
        if (!w->ren) w->ren = SDL_CreateRenderer(w->win, -1, SDL_RENDERER_SOFTWARE);
    }
    if (w->ren)
        w->tex = SDL_CreateTexture(w->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, width,
                                   height);
    if (!w->tex) {
        snprintf(err, errlen, "cannot open a %dx%d window: %s", width, height, SDL_GetError());
        vw_window_close(w);
        return 0;
    }
    *out = w;
    return 1;
}

int vw_window_set_size(vw_window *w, int width, int height)
{
    SDL_SetWindowSize(w->win, width, height);
    return 0;
}

int vw_window_resize(vw_window *w, int width, int height)
{
    if (width == w->w && height == w->h) return 0;
    SDL_Texture *t = SDL_CreateTexture(w->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING,
                                       width, height);
    if (!t) return -1;
    SDL_DestroyTexture(w->tex);
    w->tex = t;
    w->w = width, w->h = height;
    return 0;
}

void vw_window_close(vw_window *w)
{
    if (!w) return;
    if (w->tex) SDL_DestroyTexture(w->tex);
    if (w->ren) SDL_DestroyRenderer(w->ren);
    if (w->win) SDL_DestroyWindow(w->win);
    free(w);
    SDL_Quit();
}

static int draw(vw_window *w, const uint8_t *rgb)
{
    if (rgb && SDL_UpdateTexture(w->tex, NULL, rgb, w->w * 3) != 0) return -1;
    if (SDL_RenderClear(w->ren) != 0) return -1;
    return SDL_RenderCopy(w->ren, w->tex, NULL, NULL) != 0 ? -1 : 0;
}

int vw_window_present(vw_window *w, const uint8_t *rgb, int width, int height)
{
    if (width != w->w || height != w->h || draw(w, rgb)) return -1;
    SDL_RenderPresent(w->ren);
    return 0;
}

int vw_window_read(vw_window *w, uint8_t *rgb, int width, int height)
{
    /* what the renderer puts in the window: the last texture drawn again,
     * read back before it is shown */
    if (width != w->w || height != w->h || draw(w, NULL)) return -1;
    int rc = SDL_RenderReadPixels(w->ren, NULL, SDL_PIXELFORMAT_RGB24, rgb, width * 3);
    SDL_RenderPresent(w->ren);
    return rc != 0 ? -1 : 0;
}

static unsigned mods_of(SDL_Keymod m)
{
    return (m & KMOD_SHIFT ? VW_MOD_SHIFT : 0u) | (m & KMOD_CTRL ? VW_MOD_CTRL : 0u) |
           (m & KMOD_ALT ? VW_MOD_ALT : 0u);
}

static const struct {
    SDL_Keycode sdl;
    int key;
} keymap[] = {
    {SDLK_UP, VW_KEY_UP},           {SDLK_DOWN, VW_KEY_DOWN},       {SDLK_LEFT, VW_KEY_LEFT},
    {SDLK_RIGHT, VW_KEY_RIGHT},     {SDLK_PAGEUP, VW_KEY_PAGEUP},   {SDLK_PAGEDOWN, VW_KEY_PAGEDOWN},
    {SDLK_HOME, VW_KEY_HOME},       {SDLK_END, VW_KEY_END},         {SDLK_DELETE, VW_KEY_DELETE},
    {SDLK_BACKSPACE, VW_KEY_BACKSPACE}, {SDLK_RETURN, VW_KEY_RETURN}, {SDLK_ESCAPE, VW_KEY_ESCAPE},
    {SDLK_TAB, VW_KEY_TAB},         {SDLK_KP_PLUS, '+'},            {SDLK_KP_MINUS, '-'},
    {SDLK_F1, VW_KEY_F1},           {SDLK_F2, VW_KEY_F1 + 1},       {SDLK_F3, VW_KEY_F1 + 2},
    {SDLK_F4, VW_KEY_F1 + 3},       {SDLK_F5, VW_KEY_F1 + 4},       {SDLK_F6, VW_KEY_F1 + 5},
    {SDLK_F7, VW_KEY_F1 + 6},       {SDLK_F8, VW_KEY_F1 + 7},       {SDLK_F9, VW_KEY_F1 + 8},
    {SDLK_F10, VW_KEY_F1 + 9},      {SDLK_F11, VW_KEY_F1 + 10},     {SDLK_F12, VW_KEY_F12},
};

static int key_of(SDL_Keycode k, unsigned *mods)
{
    for (size_t i = 0; i < sizeof keymap / sizeof keymap[0]; i++)
        if (keymap[i].sdl == k) return keymap[i].key;
    if (k > 32 && k < 127) {
        /* SDL reports the unshifted key: shift+/ is '?', shift+= is '+' */
        if (*mods & VW_MOD_SHIFT) {
            if (k == '/') return *mods &= ~(unsigned)VW_MOD_SHIFT, '?';
            if (k == '=') return *mods &= ~(unsigned)VW_MOD_SHIFT, '+';
        }
        return (int)k;
    }
    return -1;
}

static SDL_Keycode sdl_of(int key)
{
    for (size_t i = 0; i < sizeof keymap / sizeof keymap[0]; i++)
        if (keymap[i].key == key) return keymap[i].sdl;
    return (SDL_Keycode)key;
}

static SDL_Keymod sdl_mods(unsigned m)
{
    return (SDL_Keymod)((m & VW_MOD_SHIFT ? KMOD_LSHIFT : 0) | (m & VW_MOD_CTRL ? KMOD_LCTRL : 0) |
                        (m & VW_MOD_ALT ? KMOD_LALT : 0));
}

int vw_window_events(vw_window *w, vw_event *ev, int max, int timeout_ms)
{
    int n = 0;
    SDL_Event e;
    int got = timeout_ms > 0 ? SDL_WaitEventTimeout(&e, timeout_ms) : SDL_PollEvent(&e);
    while (got && n < max) {
        vw_event v;
        memset(&v, 0, sizeof v);
        int ok = 1;
        switch (e.type) {
        case SDL_QUIT: v.type = VW_EV_QUIT; break;
        case SDL_WINDOWEVENT:
            if (e.window.event == SDL_WINDOWEVENT_CLOSE) v.type = VW_EV_QUIT;
            else if (e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED)
                v.type = VW_EV_RESIZE, v.x = e.window.data1, v.y = e.window.data2;
            else if (e.window.event == SDL_WINDOWEVENT_EXPOSED || e.window.event == SDL_WINDOWEVENT_SHOWN ||
                     e.window.event == SDL_WINDOWEVENT_RESTORED)
                v.type = VW_EV_EXPOSE;
            else ok = 0;
            break;
        case SDL_KEYDOWN:
            v.type = VW_EV_KEY;
            v.mods = mods_of((SDL_Keymod)e.key.keysym.mod);
            v.key = key_of(e.key.keysym.sym, &v.mods);
            ok = v.key >= 0;
            break;
        case SDL_MOUSEBUTTONDOWN: case SDL_MOUSEBUTTONUP:
            v.type = e.type == SDL_MOUSEBUTTONDOWN ? VW_EV_DOWN : VW_EV_UP;
            v.button = e.button.button == SDL_BUTTON_LEFT     ? VW_BUTTON_LEFT
                       : e.button.button == SDL_BUTTON_MIDDLE ? VW_BUTTON_MIDDLE
                       : e.button.button == SDL_BUTTON_RIGHT  ? VW_BUTTON_RIGHT
                                                              : 0;
            v.x = e.button.x, v.y = e.button.y;
            v.mods = mods_of(SDL_GetModState());
            ok = v.button != 0;
            break;
        case SDL_MOUSEMOTION:
            v.type = VW_EV_MOTION;
            v.x = e.motion.x, v.y = e.motion.y;
            v.mods = mods_of(SDL_GetModState());
            break;
        case SDL_MOUSEWHEEL:
            v.type = VW_EV_WHEEL;
            v.wheel = e.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e.wheel.y : e.wheel.y;
            ok = v.wheel != 0;
            break;
        case SDL_DROPFILE:
            v.type = VW_EV_DROP;
            snprintf(w->drop, sizeof w->drop, "%s", e.drop.file ? e.drop.file : "");
            SDL_free(e.drop.file);
            v.path = w->drop;
            ok = w->drop[0] != 0;
            break;
        default: ok = 0; break;
        }
        if (ok) ev[n++] = v;
        got = n < max && SDL_PollEvent(&e);
    }
    return n;
}

int vw_window_push(vw_window *w, const vw_event *v)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    Uint32 id = SDL_GetWindowID(w->win);
    /* mouse events carry no modifiers in SDL: the keyboard state does */
    SDL_SetModState(sdl_mods(v->mods));
    switch (v->type) {
    case VW_EV_QUIT: e.type = SDL_QUIT; break;
    case VW_EV_KEY:
        e.type = SDL_KEYDOWN;
        e.key.windowID = id;
        e.key.state = SDL_PRESSED;
        e.key.keysym.sym = sdl_of(v->key);
        e.key.keysym.mod = (Uint16)sdl_mods(v->mods);
        break;
    case VW_EV_DOWN: case VW_EV_UP:
        e.type = v->type == VW_EV_DOWN ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP;
        e.button.windowID = id;
        e.button.state = v->type == VW_EV_DOWN ? SDL_PRESSED : SDL_RELEASED;
        e.button.button = (Uint8)(v->button == VW_BUTTON_LEFT     ? SDL_BUTTON_LEFT
                                  : v->button == VW_BUTTON_MIDDLE ? SDL_BUTTON_MIDDLE
                                                                  : SDL_BUTTON_RIGHT);
        e.button.clicks = 1;
        e.button.x = v->x, e.button.y = v->y;
        break;
    case VW_EV_MOTION:
        e.type = SDL_MOUSEMOTION;
        e.motion.windowID = id;
        e.motion.x = v->x, e.motion.y = v->y;
        break;
    case VW_EV_DROP:
        e.type = SDL_DROPFILE;
        e.drop.windowID = id;
        e.drop.file = SDL_strdup(v->path ? v->path : "");
        if (!e.drop.file) return -1;
        break;
    case VW_EV_RESIZE: /* what the window system says after SDL_SetWindowSize */
        e.type = SDL_WINDOWEVENT;
        e.window.windowID = id;
        e.window.event = SDL_WINDOWEVENT_SIZE_CHANGED;
        e.window.data1 = v->x, e.window.data2 = v->y;
        break;
    case VW_EV_EXPOSE:
        e.type = SDL_WINDOWEVENT;
        e.window.windowID = id;
        e.window.event = SDL_WINDOWEVENT_EXPOSED;
        break;
    case VW_EV_WHEEL:
        e.type = SDL_MOUSEWHEEL;
        e.wheel.windowID = id;
        e.wheel.y = v->wheel;
        e.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
        break;
    }
    return SDL_PushEvent(&e) == 1 ? 0 : -1;
}
