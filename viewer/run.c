/*
 * run.c — the three ways to run the viewer: in a window (SDL2, present.c),
 * replaying a script (through the window's event queue, so replayed input
 * takes the same path as real input; --offscreen: plain memory), and the
 * benchmark (a full turn rendered off screen, times per phase).
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int readback(void *ctx, uint8_t *rgb, int w, int h)
{
    return vw_window_read(ctx, rgb, w, h);
}

static int fail_status(const char *what)
{
    fprintf(stderr, "bvox: view: %s: %s\n", what, bvox_errmsg()[0] ? bvox_errmsg() : "failed");
    return 1;
}

static int draw(vw_state *s, vw_window *win)
{
    if (vw_render(s)) return fail_status("rendering");
    /* after a resize the window's texture follows the canvas */
    if (win && vw_window_resize(win, s->width, s->height)) {
        fprintf(stderr, "bvox: view: the window cannot show %dx%d\n", s->width, s->height);
        return 1;
    }
    if (win && vw_window_present(win, s->rgb, s->width, s->height)) {
        fprintf(stderr, "bvox: view: the window refused the frame\n");
        return 1;
    }
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int run_bench(vw_state *s, int frames)
{
    double t = vw_now();
    if (vw_render(s)) return fail_status("rendering");
    double first = (vw_now() - t) * 1e3, surface = s->times.surface;
    double *ph = bvox__mem_zalloc((size_t)frames * 5, sizeof *ph);
    if (!ph) return fail_status("memory");
    double *tot = ph, *cast = ph + frames, *code = ph + 2 * frames, *lut = ph + 3 * frames,
           *comp = ph + 4 * frames;
    const double up[3] = {0, 1, 0}; /* the screen's vertical: the object spins upright */
    double t0 = vw_now();
    for (int i = 0; i < frames; i++) {
        vw_rotate(s->R, up, 2 * 3.14159265358979323846 / frames);
        s->need_cast = 1;
        double a = vw_now();
        if (vw_render(s)) {
            free(ph);
            return fail_status("rendering");
        }
        tot[i] = (vw_now() - a) * 1e3;
        cast[i] = s->times.cast, code[i] = s->times.code, lut[i] = s->times.lut;
        comp[i] = s->times.compose;
        s->fps = 1e3 / tot[i];
    }
    double wall = vw_now() - t0;
    /* the same turn as a drag on a slow machine draws it: half-resolution
     * casts (and in the smooth mode, when its codes are slow, the gradient
     * mode's codes in their place) */
    s->coarse = 1;
    s->view_drag = 1;
    double c0 = vw_now();
    for (int i = 0; i < frames; i++) {
        vw_rotate(s->R, up, 2 * 3.14159265358979323846 / frames);
        s->need_cast = 1;
        if (vw_render(s)) {
            free(ph);
            return fail_status("rendering");
        }
    }
    double coarse_fps = frames / (vw_now() - c0);
    /* the same turn as a drag on this machine draws it: full-resolution
     * casts; in the smooth mode, when a smooth frame is slower than
     * drag_frame_ms, the gradient codes in its place until the release */
    s->coarse = 0;
    c0 = vw_now();
    for (int i = 0; i < frames; i++) {
        vw_rotate(s->R, up, 2 * 3.14159265358979323846 / frames);
        s->need_cast = 1;
        if (vw_render(s)) {
            free(ph);
            return fail_status("rendering");
        }
    }
    double drag_fps = frames / (vw_now() - c0);
    int drag_stand_in = s->fast_codes;
    s->view_drag = 0;
    s->need_cast = 1;
    /* a light change: a new table applied to the codes, nothing cast */
    int nl = 36;
    double *lt = bvox__mem_zalloc((size_t)nl, sizeof *lt);
    if (!lt) {
        free(ph);
        return fail_status("memory");
    }
    for (int i = 0; i < nl; i++) {
        s->light.azimuth = fmod(s->light.azimuth + 10, 360);
        double a = vw_now();
        vw_apply_lut(s);
        lt[i] = (vw_now() - a) * 1e3;
    }
    /* an edit: a brush ball removed under the centre of the +z view, the
     * surface rebuilt, the frame drawn (what a click in the window costs) */
    int ne = 10;
    double *et = bvox__mem_zalloc((size_t)ne, sizeof *et);
    if (!et) {
        free(lt);
        free(ph);
        return fail_status("memory");
    }
    vw_set_axis_view(s, BVOX_VIEW_POS_Z);
    if (vw_render(s)) {
        free(et), free(lt), free(ph);
        return fail_status("rendering");
    }
    int edits = 0;
    for (int i = 0; i < ne; i++) {
        double a = vw_now();
        int32_t hit[3];
        if (vw_pick(s, s->width / 2 + 4 * i, s->height / 2, hit)) {
            if (vw_brush(s, hit)) {
                free(et), free(lt), free(ph);
                return fail_status("brush");
            }
            edits++;
        }
        if (vw_render(s)) {
            free(et), free(lt), free(ph);
            return fail_status("rendering");
        }
        et[i] = (vw_now() - a) * 1e3;
    }
    double medit = median(et, ne);
    free(et);
    double fps = frames / wall, mt = median(tot, frames);
    double mc = median(cast, frames), mk = median(code, frames), ml = median(lut, frames),
           mp = median(comp, frames), mlight = median(lt, nl);
    printf("bench: %dx%dx%d voxels, %lld boundary voxels, %dx%d canvas, %s shading, %d threads\n",
           (int)s->dims.nx, (int)s->dims.ny, (int)s->dims.nz, (long long)bvox_surface_count(s->surf),
           s->width, s->height, vw_shade_name(s->shade), bvox_threads());
    printf("first frame %.1f ms (surface %.1f ms)\n", first, surface);
    printf("full turn: %d frames in %.3f s = %.1f fps (median frame %.2f ms = %.1f fps)\n", frames,
           wall, fps, mt, 1e3 / mt);
    printf("per frame (medians): cast %.2f ms, codes %.2f ms, table %.2f ms, overlay %.2f ms\n",
           mc, mk, ml, mp);
    printf("dragging at half resolution (when a full cast takes over %.0f ms): %.1f fps\n",
           s->coarse_ms, coarse_fps);
    printf("dragging at full resolution: %.1f fps%s\n", drag_fps,
           drag_stand_in ? " (smooth frames are slower than 60 Hz: gradient codes while turning)" : "");
    printf("light change (table only, no cast): median %.3f ms\n", mlight);
    printf("brush edit (r=%d ball, surface updated in its box, frame drawn): median %.1f ms; %d edits, "
           "undo journal %.1f KiB\n",
           s->brush_radius, medit, edits, bvox_journal_bytes(s->journal) / 1024.0);
    printf("{\"bench\":\"view\",\"nx\":%d,\"ny\":%d,\"nz\":%d,\"surface_voxels\":%lld,\"width\":%d,"
           "\"height\":%d,\"frames\":%d,\"fps\":%.2f,\"median_frame_ms\":%.3f,\"cast_ms\":%.3f,"
           "\"codes_ms\":%.3f,\"table_ms\":%.3f,\"overlay_ms\":%.3f,\"light_change_ms\":%.4f,"
           "\"surface_ms\":%.3f,\"coarse_fps\":%.2f,\"drag_fps\":%.2f,\"edit_ms\":%.3f,\"journal_bytes\":%zu,\"threads\":%d}\n",
           (int)s->dims.nx, (int)s->dims.ny, (int)s->dims.nz, (long long)bvox_surface_count(s->surf),
           s->width, s->height, frames, fps, mt, mc, mk, ml, mp, mlight, surface, coarse_fps, drag_fps, medit,
           bvox_journal_bytes(s->journal), bvox_threads());
    free(lt);
    free(ph);
    return 0;
}

/* Hand events to the state: through the window's queue when there is one. */
static int feed(vw_state *s, vw_window *win, const vw_event *ev, int n)
{
    for (int i = 0; i < n; i++) {
        if (win && ev[i].type == VW_EV_RESIZE) {
            /* a real resize: the window system is asked, and its answer
             * comes back as the event the viewer handles */
            vw_window_set_size(win, ev[i].x, ev[i].y);
            double end = vw_now() + 5;
            while (!(s->width == ev[i].x && s->height == ev[i].y) && vw_now() < end) {
                vw_event got[64];
                int k = vw_window_events(win, got, 64, 20);
                for (int j = 0; j < k; j++) vw_handle(s, &got[j]);
            }
            if (s->width != ev[i].x || s->height != ev[i].y) {
                fprintf(stderr, "bvox: view: the window did not become %dx%d (it is %dx%d)\n",
                        ev[i].x, ev[i].y, s->width, s->height);
                return 1;
            }
        } else if (win) {
            if (vw_window_push(win, &ev[i])) {
                fprintf(stderr, "bvox: view: the window refused an event\n");
                return 1;
            }
            vw_event got[64];
            int k = vw_window_events(win, got, 64, 0);
            for (int j = 0; j < k; j++) vw_handle(s, &got[j]);
        } else {
            vw_handle(s, &ev[i]);
        }
        if (draw(s, win)) return 1;
        if (s->quit) return 0;
    }
    return 0;
}

/* sc: the script, read and checked before any window opens */
static int run_script(vw_state *s, vw_window *win, const char *path, vw_script *script)
{
    vw_script sc = *script;
    int rc = draw(s, win);
    for (int i = 0; !rc && i < sc.n && !s->quit; i++) {
        const vw_cmd *c = &sc.cmds[i];
        vw_event ev[10016];
        int n;
        switch (c->type) {
        case VW_CMD_WAIT: {
            double end = vw_now() + c->amount / 1e3;
            do {
                if (win) {
                    vw_event got[64];
                    int k = vw_window_events(win, got, 64, 0);
                    for (int j = 0; j < k; j++) vw_handle(s, &got[j]);
                }
                rc = draw(s, win);
                vw_sleep_ms(10);
            } while (!rc && vw_now() < end);
            break;
        }
        case VW_CMD_SCREENSHOT:
            rc = draw(s, win);
            if (!rc && vw_screenshot(s, c->path)) rc = fail_status(c->path);
            break;
        case VW_CMD_SAVE:
            if (vw_save(s, c->path)) rc = fail_status(c->path);
            else rc = draw(s, win);
            break;
        default:
            n = vw_script_events(c, ev, (int)(sizeof ev / sizeof ev[0]));
            rc = feed(s, win, ev, n);
            break;
        }
        if (rc) fprintf(stderr, "bvox: view: script %s stopped at line %d\n", path, c->line);
    }
    vw_script_free(&sc);
    return rc;
}

static int run_window(vw_state *s, vw_window *win)
{
    s->fps = 0;
    int dirty = 1;
    while (!s->quit) {
        vw_event ev[256];
        int n = vw_window_events(win, ev, 256, dirty ? 0 : 30);
        for (int i = 0; i < n; i++) vw_handle(s, &ev[i]);
        if (n) dirty = 1;
        if (!dirty || s->quit) continue;
        /* the frame rate shown: how many frames with a new view (cast,
         * shading, present) this machine draws per second, smoothed; frames
         * that only re-apply the table are faster and not counted */
        int casting = s->need_cast || s->need_surface;
        double t0 = vw_now();
        if (draw(s, win)) return 1;
        double dt = vw_now() - t0;
        if (casting && dt > 0) s->fps = s->fps > 0 ? 0.7 * s->fps + 0.3 / dt : 1 / dt;
        /* keep drawing while a drag goes on (fps stays meaningful); else wait */
        dirty = s->drag_button != 0;
    }
    return 0;
}

int vw_run(const vw_run_opts *o, bvox_volume *model)
{
    int w = o->width ? o->width : 800, h = o->height ? o->height : 800;
    vw_state *s;
    bvox_status st = vw_open(model, w, h, &s);
    if (st) {
        fprintf(stderr, "bvox: view: cannot open the viewer (%s; canvas %dx%d must be 64..8192)\n",
                bvox_status_name(st), w, h);
        return 1;
    }
    if (o->output) s->save_path = o->output;
    if (o->shade) {
        int m = vw_shade_parse(o->shade);
        if (m < 0) {
            vw_close(s);
            fprintf(stderr, "bvox: view: unknown shading '%s'\n", o->shade);
            return 1;
        }
        s->shade = (vw_shade)m;
    }
    if (o->labels) {
        st = vw_set_labels(s, o->labels, o->lut);
        if (st) {
            vw_close(s);
            return fail_status("the label colours");
        }
    }
    if (o->bench) {
        int rc = run_bench(s, o->frames > 0 ? o->frames : 120);
        vw_close(s);
        return rc;
    }
    s->log = stdout;
    vw_script sc = {NULL, 0};
    if (o->script && vw_script_load(o->script, &sc)) {
        fprintf(stderr, "bvox: view: %s\n", vw_script_error());
        vw_close(s);
        return 1;
    }
    vw_window *win = NULL;
    if (!(o->script && o->offscreen)) {
        char err[256];
        if (!vw_window_open(&win, w, h, "bvox view", err, sizeof err)) {
            fprintf(stderr, "bvox: view: %s\n", err);
            vw_script_free(&sc);
            vw_close(s);
            return 1;
        }
        s->readback = readback;
        s->readback_ctx = win;
    }
    int rc = o->script ? run_script(s, win, o->script, &sc) : run_window(s, win);
    vw_window_close(win);
    vw_close(s);
    return rc;
}
