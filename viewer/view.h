/*
 * view.h — the viewer's core, free of SDL: the view state (camera, light,
 * shading, cut plane, layout, cursor, selection, primitive, brush), the
 * events it understands (keys and mouse in window pixels), the frame it
 * draws into an RGB canvas, the script language and the edit journal use.
 * present.c is the only file that talks to SDL2; everything here can be run
 * and tested off screen (tests/unit/test_view_*.c, --bench, --script).
 *
 * Frames: the camera is a rotation R with rows right, down, view in the
 * volume's axis-aligned physical frame (voxel (i, j, k) at (i sx, j sy,
 * k sz)), the convention of bvox_projection's matrix.
 */
#ifndef BVOX_VIEWER_VIEW_H
#define BVOX_VIEWER_VIEW_H

#include "bvox.h"

#include <stdint.h>
#include <stdio.h>

/* ---- keys: printable ASCII as itself (letters lower case), plus these ---- */
enum {
    VW_KEY_UP = 256, VW_KEY_DOWN, VW_KEY_LEFT, VW_KEY_RIGHT, VW_KEY_PAGEUP, VW_KEY_PAGEDOWN,
    VW_KEY_HOME, VW_KEY_END, VW_KEY_DELETE, VW_KEY_BACKSPACE, VW_KEY_RETURN, VW_KEY_ESCAPE,
    VW_KEY_TAB, VW_KEY_F1, /* F1..F12 consecutive */ VW_KEY_F12 = VW_KEY_F1 + 11,
    VW_KEY_MAX
};
enum { VW_MOD_SHIFT = 1, VW_MOD_CTRL = 2, VW_MOD_ALT = 4 };
enum { VW_BUTTON_LEFT = 1, VW_BUTTON_MIDDLE = 2, VW_BUTTON_RIGHT = 3 };

typedef enum vw_event_type {
    VW_EV_KEY, VW_EV_DOWN, VW_EV_UP, VW_EV_MOTION, VW_EV_WHEEL, VW_EV_QUIT,
    VW_EV_EXPOSE, /* the window must be drawn again (nothing changes) */
    VW_EV_RESIZE, /* the window's new size: x = width, y = height */
    VW_EV_DROP    /* a file dropped on the window: path */
} vw_event_type;
typedef struct vw_event {
    vw_event_type type;
    int key;        /* VW_EV_KEY */
    unsigned mods;  /* VW_MOD_* */
    int button;     /* VW_EV_DOWN/UP */
    int x, y;       /* pointer, canvas pixels */
    int wheel;      /* VW_EV_WHEEL: + zooms in */
    const char *path; /* VW_EV_DROP: valid until the next vw_window_events */
} vw_event;

/* Key names for scripts and the help: "a", "shift+a", "ctrl+z", "up",
 * "pageup", "f1", "space", "delete"... parse returns 0 on success. */
int vw_key_parse(const char *text, int *key, unsigned *mods);
const char *vw_key_name(int key); /* static buffer for printable keys */

/* The shading modes, in the order the s key cycles them: the library's
 * (the 3D pane is shaded by bvox_shade_codes_volume and
 * bvox_shade_table_build). Smooth (issue 18: normals from the occupancy
 * around the hit voxel, of the displayed volume) is coded per frame in the
 * gradient mode's 64 x 64 bins, so a light change still rebuilds only the
 * table. */
typedef enum vw_shade { VW_SHADE_DEPTH = BVOX_SHADE_DEPTH, VW_SHADE_BINARY = BVOX_SHADE_BINARY,
                        VW_SHADE_GRADIENT = BVOX_SHADE_GRADIENT,
                        VW_SHADE_COMBINED = BVOX_SHADE_BINARY_DEPTH,
                        VW_SHADE_SMOOTH = BVOX_SHADE_SMOOTH, VW_NSHADE } vw_shade;
/* The mode's short name ("depth", "binary", "gradient", "combined",
 * "smooth"), and back (-1 if unknown; the library's names are accepted too:
 * "binary+depth"). */
const char *vw_shade_name(vw_shade shade);
int vw_shade_parse(const char *name);
typedef enum vw_layout { VW_LAYOUT_3D, VW_LAYOUT_ORTHO, VW_LAYOUT_MOSAIC } vw_layout;
typedef enum vw_prim { VW_PRIM_NONE, VW_PRIM_SPHERE, VW_PRIM_BOX, VW_PRIM_CYLINDER, VW_NPRIM } vw_prim;
typedef enum vw_pane_kind { VW_PANE_3D, VW_PANE_XY, VW_PANE_XZ, VW_PANE_YZ, VW_PANE_MOSAIC } vw_pane_kind;

typedef struct vw_rect {
    int x, y, w, h;
} vw_rect;

/* Per-phase times of the last frames (milliseconds). */
typedef struct vw_times {
    double surface, cast, code, lut, compose, total;
} vw_times;

typedef struct vw_3d {
    /* the pane's pre-image, cropped to the pane */
    int w, h;
    int32_t *depth;   /* -1 background; pixel units of the cast */
    uint8_t *ncode;   /* the cast's code (normal | cue << 5) */
    uint16_t *code;   /* the shading codes (bvox_shade_codes) */
    /* the frame of the cast, shifted to the pane's pixel (0, 0) */
    double eye[9], origin[3], pixel, step;
    int32_t depth_range;
    int valid;
    int coarse;       /* cast at half resolution, pixels doubled */
} vw_3d;

/* A label volume shown in its table's colours (labels.c). */
typedef struct vw_labels vw_labels;

typedef struct vw_state {
    /* the model and what is displayed of it */
    bvox_volume *model;
    bvox_volume *cut_copy;  /* the model cut by the plane, or NULL */
    bvox_surface *surf;     /* of the displayed volume */
    bvox_journal *journal;
    double disp_center[3];  /* bbox centre of the displayed volume (the cast's centre) */
    int surf_of_cut;        /* surf was built from cut_copy */
    int dirty_state;        /* model edits since surf: 0 none, 1 inside dirty, 2 unknown */
    bvox_box dirty;
    bvox_dims dims;
    bvox_geometry geom;
    double sp[3];           /* spacing */
    double center[3];       /* the model's bbox centre at load (physical) */
    double radius;          /* half the bbox diagonal at load */
    int64_t count;          /* 1-voxels of the model */
    /* camera */
    double R[9];
    double zoom;            /* 1: the object's bounding sphere fits the pane */
    double pan[2];          /* pixels */
    int iso;                /* next isometric view */
    /* light and shading */
    bvox_light light;
    bvox_depth_shading depth;
    vw_shade shade;
    /* cut plane: m . p + e >= 0 kept when keep_above (p physical, axis frame) */
    int cut;
    double cut_n[3], cut_s;  /* unit normal, offset from centre along it */
    int keep_above;
    /* layout */
    vw_layout layout;
    int overlay, help;
    uint8_t planes;          /* mosaic bit planes */
    bvox_mosaic_display mosaic_display;
    bvox_image *mosaic;      /* cached */
    /* cursor, selection, brush, primitive */
    int32_t cursor[3];
    int sel_n;               /* corners set: 0, 1 or 2 */
    int32_t sel[2][3];
    int brush;               /* edit mode */
    int brush_add;
    int brush_radius;        /* voxels */
    vw_prim prim;
    int prim_size;           /* voxels */
    /* mouse */
    int drag_button, drag_mode, last_x, last_y, press_x, press_y, moved;
    int drag_axis;           /* ctrl+drag in a slice: the axis across it */
    int stroke;              /* a brush stroke is open in the journal */
    /* while the view is dragged, the 3D pane is cast at half resolution when
     * a full cast took longer than coarse_ms (0: never), at full resolution
     * again on release */
    int coarse;
    double coarse_ms, last_full_cast_ms;
    /* the same for the smooth mode's codes (a normal per hit voxel from its
     * neighbourhood: slower than the cast on a large view): while the view
     * is dragged they are made from the depth map (the gradient mode, the
     * same 64 x 64 bins and table) when the last smooth codes took longer
     * than coarse_ms, or when the last smooth frame (its full cast and its
     * codes) took longer than drag_frame_ms (a 60 Hz frame by default, so a
     * turn stays at 60 fps where smooth frames cannot), and the smooth ones
     * again on release */
    double drag_frame_ms;
    int view_drag;           /* a turn or pan drag is under way */
    int fast_codes;          /* the pane shows those stand-in codes */
    double last_smooth_ms;
    /* the smooth normals' moments across frames (made on first use; cleared
     * whenever the displayed volume's surface is rebuilt or updated) */
    bvox_normal_cache *normals;
    /* canvas */
    int width, height;
    uint8_t *rgb;            /* width*height*3 */
    vw_3d view3d;
    bvox_shade_table lut;    /* RGB of the pane's shading codes */
    /* dirty flags */
    int need_surface, need_cast, need_code, need_lut, need_mosaic;
    /* bookkeeping */
    int quit;
    double fps;              /* shown in the overlay; < 0: not shown */
    vw_times times;
    const char *save_path;   /* ctrl+s */
    int shot_seq;
    FILE *log;               /* edits and saves are reported here (may be NULL) */
    /* screenshots read what the window shows when set (else the canvas) */
    int (*readback)(void *ctx, uint8_t *rgb, int width, int height);
    void *readback_ctx;
    char status[160];        /* last message shown in the overlay */
    /* measuring: the ruler's points (g marks the cursor), the selection's
     * count of 1-voxels (cached for the box and the model it was made on) */
    int ruler_n;             /* points set: 0, 1 or 2 */
    int32_t ruler[2][3];
    int sel_count_ok;
    int32_t sel_counted[2][3];
    int64_t sel_count;
    vw_labels *labels;       /* NULL: a binary model in one colour */
} vw_state;

/* Open a viewer state on model (taken over: destroyed by vw_close) with a
 * canvas of width x height pixels. */
bvox_status vw_open(bvox_volume *model, int width, int height, vw_state **out);
void vw_close(vw_state *s);
/* Show another model (taken over; a dropped file): the view, light, shading
 * and layout stay, the rest (cut, selection, ruler, undo, labels) starts
 * afresh. On failure the old model stays and model is destroyed. */
bvox_status vw_replace_model(vw_state *s, bvox_volume *model);
/* A new canvas size (the window was resized; 64..8192 each): the panes are
 * laid out again and the 3D pane is cast at its new size. */
bvox_status vw_resize(vw_state *s, int width, int height);

/* ---- view_state.c: the state and its geometry (calls no other viewer file) ---- */
void vw_set_axis_view(vw_state *s, bvox_view view);
void vw_set_iso_view(vw_state *s, int corner); /* corner 0..7: signs of x, y, z */
/* Turn by a trackball drag from (x0, y0) to (x1, y1) in a pane of w x h. */
void vw_trackball(double R[9], double x0, double y0, double x1, double y1, int w, int h);
/* Rotate R by angle (radians) about the unit axis (in the frame of R's rows). */
void vw_rotate(double R[9], const double axis[3], double angle);
void vw_orthonormalize(double R[9]);
/* The cut plane as m . p + e (physical axis frame); world plane for bvox_cut_plane. */
void vw_cut_plane_local(const vw_state *s, double m[3], double *e);
void vw_cut_plane_world(const vw_state *s, double plane[4]);
/* Turn the cut plane's normal by angle (radians) about axis (physical frame). */
void vw_cut_tilt(vw_state *s, const double *axis, double angle);
/* The panes of the current layout. Returns their number. */
int vw_panes(const vw_state *s, vw_rect rects[4], vw_pane_kind kinds[4]);
/* The smallest voxel size (a step of one voxel in physical units). */
double vw_min_spacing(const vw_state *s);
/* The shape of the current primitive at the cursor. */
void vw_primitive_shape(const vw_state *s, bvox_shape *shape);
/* The canvas as an image (RGB, a copy). */
bvox_status vw_canvas_image(const vw_state *s, bvox_image **out);
/* Debug invariant of the state (a rotation for the camera, the cursor in
 * the volume, known modes, the pane's arrays together): asserted where the
 * event handler and the frame take and hand back the state; release builds
 * (NDEBUG) compile the asserts out. */
int vw_state_ok(const vw_state *s);
/* The help text: NULL-terminated lines. */
extern const char *const vw_help_lines[];

/* ---- input.c: events (on view_state.c, edits.c, frame.c) ---- */
/* Handle one event (the keys and mouse of the help screen). */
void vw_handle(vw_state *s, const vw_event *ev);

/* ---- frame.c: drawing (on view_state.c, font.c, pick.c) ---- */
/* Bring the canvas up to date (casts only what changed). */
bvox_status vw_render(vw_state *s);
/* Only the shading table and its application (a light change). */
void vw_apply_lut(vw_state *s);

/* ---- measure.c: the ruler, the selection's volume, the scale bar ---- */
/* The ruler's length (physical, between the voxel centres), or -1 without
 * two points. */
double vw_ruler_length(const vw_state *s);
/* The selection box (inclusive corners) as a half-open bvox_box; 0 if none. */
int vw_selection_box(const vw_state *s, bvox_box *box);
/* 1-voxels of the model inside the selection box and their volume
 * (physical, unit^3); cached until the box or the model changes. */
bvox_status vw_selection_volume(vw_state *s, int64_t *count, double *volume);
/* A round length (1, 2 or 5 times a power of ten) for a scale bar of at
 * most max_px pixels of units_per_px each, as long as possible; 0 if none. */
double vw_scale_bar_length(double units_per_px, int max_px);

/* ---- labels.c: a label volume's objects in their table's colours ---- */
/* The binary model of a label set: the union of its objects. */
bvox_status vw_labels_model(const bvox_labelset *set, bvox_volume **out);
/* Show s's model (made by vw_labels_model from set) in the colours of
 * table (NULL, or labels it lacks: a fixed palette); names from the table. */
bvox_status vw_set_labels(vw_state *s, const bvox_labelset *set, const bvox_label_table *table);
void vw_labels_free(vw_labels *l);
/* The label at voxel v (0: none), its name ("" if none) and colour. */
int64_t vw_label_at(const vw_state *s, const int32_t v[3], const char **name, uint8_t rgb[3]);
/* The label of the voxel each pixel of the 3D pane shows (after a cast). */
void vw_labels_pixels(vw_state *s);
/* Colour the 3D pane's object pixels (canvas rectangle r) by those labels
 * (a light change re-applies only this). */
void vw_labels_tint(vw_state *s, vw_rect r);

/* ---- pick.c: ray from a pixel of the 3D pane to the first 1-voxel ---- */
/* The ray of pane pixel (u, v) (pixel centres at integers) in the physical
 * axis frame: point p0 at the front of the view and unit direction dir. */
void vw_pixel_ray(const vw_3d *v, double u, double v_, double p0[3], double dir[3]);
/* First 1-voxel of vol met by the ray p0 + t dir (t >= 0), voxel boxes of the
 * spacing centred on index * spacing; 1 and *hit if one, else 0. */
int vw_pick_ray(const bvox_volume *vol, const double sp[3], const double p0[3],
                const double dir[3], int32_t hit[3]);
/* Pick under canvas pixel (x, y) of the 3D pane (or a slice pane). */
int vw_pick(vw_state *s, int x, int y, int32_t hit[3]);

/* ---- edits.c: journalled edits, undo/redo (on view_state.c) ---- */
bvox_status vw_brush(vw_state *s, const int32_t at[3]);
bvox_status vw_edit_box(vw_state *s, int keep);
bvox_status vw_apply_primitive(vw_state *s, bvox_csg_op op);
bvox_status vw_apply_cut(vw_state *s);
bvox_status vw_undo(vw_state *s, int redo);
/* After the model changed inside *changed (half-open; NULL: anywhere):
 * the count, and the surface (updated in that box only when no cut is
 * shown, else rebuilt) at the next frame. */
void vw_model_changed(vw_state *s, const bvox_box *changed);
bvox_status vw_save(vw_state *s, const char *path);
bvox_status vw_screenshot(vw_state *s, const char *path);

/* ---- font.c: a 5x7 bitmap font, cells of 6x9 pixels times scale ---- */
void vw_text(uint8_t *rgb, int w, int h, int x, int y, int scale, const char *text,
             const uint8_t color[3]);
int vw_text_width(const char *text, int scale);
void vw_fill_rect(uint8_t *rgb, int w, int h, vw_rect r, const uint8_t color[3], int alpha);

/* ---- script.c: the script language ---- */
typedef enum vw_cmd_type {
    VW_CMD_KEY, VW_CMD_DRAG, VW_CMD_CLICK, VW_CMD_MOVE, VW_CMD_WHEEL, VW_CMD_WAIT,
    VW_CMD_SCREENSHOT, VW_CMD_SAVE, VW_CMD_QUIT, VW_CMD_RESIZE, VW_CMD_DROP
} vw_cmd_type;
typedef struct vw_cmd {
    vw_cmd_type type;
    int line;
    int key;
    unsigned mods;
    int button;
    int x0, y0, x1, y1, steps;
    int amount;     /* wheel clicks, wait milliseconds */
    char *path;     /* screenshot, save, drop (owned) */
} vw_cmd;
typedef struct vw_script {
    vw_cmd *cmds;
    int n;
} vw_script;
/* Parse script text; on error returns BVOX_EINVAL and vw_script_error()
 * says "script line N: ..." (this thread's last error; nothing is printed). */
const char *vw_script_error(void);
bvox_status vw_script_parse(const char *text, vw_script *out);
bvox_status vw_script_load(const char *path, vw_script *out);
void vw_script_free(vw_script *sc);
/* The events of one command (a drag is a press, steps motions, a release);
 * at most max written, returns the count. */
int vw_script_events(const vw_cmd *c, vw_event *ev, int max);

/* ---- run.c: the entry point (cli/cmd_view.c) ---- */
typedef struct vw_run_opts {
    const char *script;   /* replay this file and exit */
    int bench;            /* render a full turn off screen, print the times */
    int frames;           /* bench: frames of the turn (0: 120) */
    int width, height;    /* canvas (0: 800 x 800) */
    const char *output;   /* ctrl+s saves here */
    int offscreen;        /* script without a window (plain memory) */
    const bvox_labelset *labels;     /* model made from it: show it in colours */
    const bvox_label_table *lut;     /* their names and colours (NULL: a palette) */
    const char *shade;    /* the shading mode to start in (vw_shade_parse; NULL: combined) */
} vw_run_opts;
/* Runs the viewer on model (taken over); prints errors ("bvox: ...") and
 * returns the exit code: 0, or 1 when something failed. */
int vw_run(const vw_run_opts *o, bvox_volume *model);

/* ---- present.c (SDL2) or present_none.c ---- */
typedef struct vw_window vw_window;
/* 0 and a message in err when no window can be opened (no SDL2 in this
 * build, no display). */
int vw_window_open(vw_window **out, int width, int height, const char *title, char *err,
                   size_t errlen);
void vw_window_close(vw_window *w);
/* Show the canvas; 0 on success. */
int vw_window_present(vw_window *w, const uint8_t *rgb, int width, int height);
/* Wait up to timeout_ms for events (0: poll); returns the number written. */
int vw_window_events(vw_window *w, vw_event *ev, int max, int timeout_ms);
/* Read back what the window shows (RGB, width*height*3); 0 on success. */
int vw_window_read(vw_window *w, uint8_t *rgb, int width, int height);
/* Push an event through the window system's queue (script mode), so that
 * replayed input travels the same path as real input (a drop as SDL's own
 * drop event); 0 on success. */
int vw_window_push(vw_window *w, const vw_event *ev);
/* Ask the window system for a new window size (script mode: the resize
 * comes back as a VW_EV_RESIZE event, as when the user drags a corner). */
int vw_window_set_size(vw_window *w, int width, int height);
/* Make the window show canvases of width x height (after a resize). */
int vw_window_resize(vw_window *w, int width, int height);
void vw_sleep_ms(int ms);
double vw_now(void);
/* 1 when built with SDL2. */
int vw_have_sdl(void);

#endif
