/*
 * demo.c — the built-in sample specimen behind `bvox demo`: an "embryo"-like
 * object drawn from shapes, with the anisotropic voxels of a reconstruction
 * from thick serial sections (10 x 10 um pixels, 25 um sections).
 *
 * The parts are chosen so that the exact volume has a closed form, which the
 * CLI test (tests/cli/demo.sh) recomputes independently; keep the two in step:
 *  - body: spheroid, semi-axes R = 800, R = 800, c = 1100 um, centred in the
 *    volume, with a cylinder of radius r = 200 um bored through it along z.
 *    What is left is a scaled "napkin ring": 4/3 pi (R^2 - r^2)^(3/2) c / R.
 *  - ring: torus around the body (axis z, ring radius 1050, tube 120 um),
 *    clear of the body (1050 - 120 > 800): 2 pi^2 * 1050 * 120^2.
 *  - cap: cone standing on the body's top (base radius 300 um, height 350 um,
 *    base 50 um above the body): pi 300^2 350 / 3.
 * The hole is cut before ring and cap are added, so it only touches the body.
 */
#include "ops/demo.h"

bvox_status bvox__demo_draw(bvox_volume *v)
{
    /* The specimen's centre, fixed in the physical frame of the built-in
     * grid: voxel centres run from 0 to (n-1)*spacing. */
    const double cx = (DEMO_NX - 1) * DEMO_SXY / 2, cy = (DEMO_NY - 1) * DEMO_SXY / 2;
    const double cz = (DEMO_NZ - 1) * DEMO_SZ / 2;
    const bvox_shape body = {.kind = BVOX_SHAPE_ELLIPSOID,
                             .center = {cx, cy, cz},
                             .semi_axes = {800, 800, 1100}};
    /* Taller than the whole volume: bores right through the body. */
    const bvox_shape hole = {.kind = BVOX_SHAPE_CYLINDER,
                             .center = {cx, cy, cz},
                             .axis = {0, 0, 1},
                             .radius = 200,
                             .height = 4000};
    const bvox_shape ring = {.kind = BVOX_SHAPE_TORUS,
                             .center = {cx, cy, cz},
                             .axis = {0, 0, 1},
                             .radius = 1050,
                             .minor_radius = 120};
    const bvox_shape cap = {.kind = BVOX_SHAPE_CONE,
                            .center = {cx, cy, cz + 1100 + 50},
                            .axis = {0, 0, 1},
                            .radius = 300,
                            .height = 350};
    const struct {
        const bvox_shape *shape;
        bvox_csg_op op;
    } steps[] = {{&body, BVOX_CSG_UNION},
                 {&hole, BVOX_CSG_DIFFERENCE},
                 {&ring, BVOX_CSG_UNION},
                 {&cap, BVOX_CSG_UNION}};
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
        bvox_status st = bvox_shape_draw(v, steps[i].shape, steps[i].op);
        if (st) return st;
    }
    return BVOX_OK;
}

bvox_status bvox_demo_specimen(bvox_volume **out)
{
    *out = NULL;
    bvox_volume *v = NULL;
    bvox_status st = bvox_volume_create((bvox_dims){DEMO_NX, DEMO_NY, DEMO_NZ}, &v);
    if (st) return st;
    st = bvox_volume_set_spacing(v, DEMO_SXY, DEMO_SXY, DEMO_SZ, "um");
    if (!st) st = bvox__demo_draw(v);
    if (st) {
        bvox_volume_destroy(v);
        return st;
    }
    *out = v;
    return BVOX_OK;
}
