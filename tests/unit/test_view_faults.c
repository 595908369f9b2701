/*
 * test_view_faults.c — the out-of-memory sweep of test_alloc_faults.c over
 * the viewer's core (viewer/ allocates through the same seam): opening a
 * state, drawing every layout and shading, an edit with its undo, parsing
 * a script, and the desktop (a resize, the selection's volume, a dropped
 * model replacing the old one, a label volume in colours), each with allocation n failed for n = 1, 2, ... until
 * it succeeds. A failure must be a clean BVOX_ENOMEM that leaves nothing
 * allocated (ASan's leak check) and nothing budgeted.
 */
#include "harness.h"
#include "internal.h"
#include "view.h"

#include <string.h>

static bvox_volume *torus(void)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){30, 26, 70}, &v)) return NULL;
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_TORUS;
    s.center[0] = 15, s.center[1] = 13, s.center[2] = 35;
    s.axis[0] = 0.3, s.axis[1] = 1, s.axis[2] = 0.2;
    s.radius = 9, s.minor_radius = 3.5;
    if (bvox_shape_draw(v, &s, BVOX_CSG_UNION)) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

static int64_t torus_count;

/* Open, draw in every layout and shading, brush, undo, close. */
static bvox_status session(void)
{
    bvox_volume *v = torus();
    if (!v) return BVOX_ENOMEM;
    vw_state *s = (vw_state *)1;
    bvox_status st = vw_open(v, 160, 120, &s); /* v is the state's now, even on failure */
    if (st) return s == NULL ? st : (bvox_status)-1000;
    for (int layout = VW_LAYOUT_3D; layout <= VW_LAYOUT_MOSAIC && !st; layout++)
        for (int shade = 0; shade < VW_NSHADE && !st; shade++) {
            s->layout = (vw_layout)layout;
            s->shade = (vw_shade)shade;
            s->need_cast = 1;
            st = vw_render(s);
        }
    const int32_t at[3] = {15, 13, 35};
    if (!st) st = vw_brush(s, at);
    if (!st) st = vw_undo(s, 0);
    if (!st && bvox_volume_count(s->model) != torus_count) st = (bvox_status)-1000;
    vw_close(s);
    return st;
}

static bvox_status script(void)
{
    vw_script sc = {0};
    bvox_status st = vw_script_parse("key 5 shift+b\ndrag left 10 20 110 70 5 shift\n"
                                     "screenshot out/a.png\nsave model.nii.gz\nquit\n", &sc);
    if (st == BVOX_OK && sc.n != 6) st = (bvox_status)-1000; /* key 5, key shift+b, ... */
    vw_script_free(&sc);
    return st;
}

static int sweep(const char *what, bvox_status (*op)(void))
{
    size_t base = bvox_memory_in_use();
    for (long n = 1; n < 100000; n++) {
        bvox__alloc_fail_after(n);
        bvox_status st = op();
        int injected = bvox__alloc_fail_pending() == 0; /* allocation n was reached */
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK && injected) continue; /* absorbed: later ones still to test */
        if (bvox_memory_in_use() != base) {
            fprintf(stderr, "%s: allocation %ld failed left budgeted bytes\n", what, n);
            return 1;
        }
        if (st == BVOX_OK) {
            if (n == 1) fprintf(stderr, "%s: allocates nothing\n", what);
            return n == 1;
        }
        if (st != BVOX_ENOMEM || !injected) {
            fprintf(stderr, "%s: allocation %ld failed gave %s\n", what, n, bvox_status_name(st));
            return 1;
        }
    }
    return 1;
}

/* Resize, count the selection, replace the model, show labels. */
static bvox_status desktop(void)
{
    bvox_volume *v = torus();
    if (!v) return BVOX_ENOMEM;
    vw_state *s = NULL;
    bvox_status st = vw_open(v, 120, 100, &s);
    if (st) return st;
    st = vw_resize(s, 150, 90);
    if (!st) st = vw_render(s);
    s->sel_n = 2;
    s->sel[0][0] = 2, s->sel[0][1] = 3, s->sel[0][2] = 10;
    s->sel[1][0] = 20, s->sel[1][1] = 20, s->sel[1][2] = 60;
    int64_t count = 0;
    double vol;
    if (!st) st = vw_selection_volume(s, &count, &vol);
    if (!st && count <= 0) st = (bvox_status)-1000;
    bvox_volume *w = torus();
    if (!st) st = w ? vw_replace_model(s, w) : BVOX_ENOMEM; /* w is taken over either way */
    else bvox_volume_destroy(w);
    /* a label volume of two labels on the torus's grid */
    static uint8_t raw[30 * 26 * 70];
    for (size_t i = 0; i < sizeof raw; i++) raw[i] = (uint8_t)(i % 30 < 10 ? 0 : i % 30 < 20 ? 4 : 9);
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    o.raw_dims = (bvox_dims){30, 26, 70};
    o.raw_dtype = BVOX_DT_U8;
    bvox_labelset *set = NULL;
    bvox_volume *m = NULL;
    if (!st) st = bvox_labels_read_memory(raw, sizeof raw, "l.raw", &o, 0, &set);
    if (!st) st = vw_labels_model(set, &m);
    if (!st) st = vw_replace_model(s, m);
    if (!st) st = vw_set_labels(s, set, NULL);
    if (!st) st = vw_render(s);
    bvox_labelset_destroy(set);
    vw_close(s);
    return st;
}

TEST(desktop) { return sweep("desktop", desktop); }

TEST(session)
{
    bvox_volume *v = torus();
    CHECK(v != NULL);
    torus_count = bvox_volume_count(v);
    bvox_volume_destroy(v);
    CHECK(torus_count > 100);
    CHECK(sweep("session", session) == 0);
    return 0;
}

TEST(script) { return sweep("script", script); }
