/*
 * pick.c — the ray of a 3D-pane pixel and the first 1-voxel on it, by a
 * voxel walk (Amanatides and Woo) through the grid. Voxel (i, j, k) is the
 * box of the spacing centred on (i sx, j sy, k sz), the boxes
 * bvox_surface_cast splats, so the voxel picked under a pixel is the one the
 * pixel shows (its centre ray's first box).
 */
#include "view.h"

#include <math.h>

void vw_pixel_ray(const vw_3d *v, double u, double v_, double p0[3], double dir[3])
{
    for (int a = 0; a < 3; a++) {
        p0[a] = v->origin[a] + (u * v->eye[a] + v_ * v->eye[3 + a]) * v->pixel;
        dir[a] = v->eye[6 + a];
    }
}

int vw_pick_ray(const bvox_volume *vol, const double sp[3], const double p0[3],
                const double dir[3], int32_t hit[3])
{
    bvox_dims d = bvox_volume_dims(vol);
    const int32_t n[3] = {d.nx, d.ny, d.nz};
    /* grid units: voxel i is [i, i+1) */
    double g0[3], gd[3], t0 = 0, t1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        g0[a] = p0[a] / sp[a] + 0.5;
        gd[a] = dir[a] / sp[a];
        if (fabs(gd[a]) < 1e-15) {
            if (g0[a] < 0 || g0[a] >= n[a]) return 0;
            gd[a] = 0;
            continue;
        }
        double ta = (0 - g0[a]) / gd[a], tb = (n[a] - g0[a]) / gd[a];
        if (ta > tb) { double x = ta; ta = tb; tb = x; }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
    }
    if (t0 > t1) return 0;
    int32_t c[3];
    int step[3];
    double tmax[3], tdelta[3];
    for (int a = 0; a < 3; a++) {
        double g = g0[a] + t0 * gd[a];
        int32_t i = (int32_t)floor(g);
        /* at the entry face, the voxel the ray goes into */
        if (gd[a] < 0 && g == floor(g)) i--;
        c[a] = i < 0 ? 0 : i >= n[a] ? n[a] - 1 : i;
        if (gd[a] > 0) {
            step[a] = 1;
            tmax[a] = (c[a] + 1 - g0[a]) / gd[a];
            tdelta[a] = 1 / gd[a];
        } else if (gd[a] < 0) {
            step[a] = -1;
            tmax[a] = (c[a] - g0[a]) / gd[a];
            tdelta[a] = -1 / gd[a];
        } else {
            step[a] = 0;
            tmax[a] = INFINITY;
            tdelta[a] = INFINITY;
        }
    }
    for (;;) {
        if (bvox_volume_get(vol, c[0], c[1], c[2])) {
            hit[0] = c[0], hit[1] = c[1], hit[2] = c[2];
            return 1;
        }
        int a = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
        if (tmax[a] > t1) return 0;
        c[a] += step[a];
        if (c[a] < 0 || c[a] >= n[a]) return 0;
        tmax[a] += tdelta[a];
    }
}
