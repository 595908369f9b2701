/*
 * present_none.c — stands in for present.c when SDL2 was not found at build
 * time: `bvox view` then says so and exits 1 (the benchmark and off-screen
 * scripts, which need no window, still work).
 */
#include "view.h"

#include <time.h>

struct vw_window {
    int unused;
};

int vw_have_sdl(void) { return 0; }

void vw_sleep_ms(int ms)
{
    struct timespec t = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

int vw_window_open(vw_window **out, int width, int height, const char *title, char *err,
                   size_t errlen)
{
    (void)width, (void)height, (void)title;
    *out = NULL;
    snprintf(err, errlen, "this bvox was built without SDL2, so it cannot open a window "
                          "(install libsdl2-dev and rebuild; --bench and --script --offscreen "
                          "work without it)");
    return 0;
}

void vw_window_close(vw_window *w) { (void)w; }
int vw_window_present(vw_window *w, const uint8_t *rgb, int width, int height)
{
    (void)w, (void)rgb, (void)width, (void)height;
    return -1;
}
int vw_window_events(vw_window *w, vw_event *ev, int max, int timeout_ms)
{
    (void)w, (void)ev, (void)max, (void)timeout_ms;
    return 0;
}
int vw_window_read(vw_window *w, uint8_t *rgb, int width, int height)
{
    (void)w, (void)rgb, (void)width, (void)height;
    return -1;
}
int vw_window_push(vw_window *w, const vw_event *ev)
{
    (void)w, (void)ev;
    return -1;
}
int vw_window_set_size(vw_window *w, int width, int height)
{
    (void)w, (void)width, (void)height;
    return -1;
}
int vw_window_resize(vw_window *w, int width, int height)
{
    (void)w, (void)width, (void)height;
    return -1;
}
