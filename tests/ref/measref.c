/* measref.c — see measref.h: the slow, obvious references for measures. */
#include "measref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const int dirs13[13][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 0},  {1, -1, 0},
                                  {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}, {1, 1, 1},
                                  {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
static const int dir_class[13] = {0, 1, 2, 3, 3, 4, 4, 5, 5, 6, 6, 6, 6};

/* Number of conn-connected components of the cells equal to `value` in a
 * grid g (w*h*d bytes); with `outside` set, cells of value connected to the
 * grid border are not counted (flood filled from the border first). */
static int64_t flood_count(uint8_t *g, int w, int h, int d, uint8_t value, int conn, int outside)
{
    size_t n = (size_t)w * h * d, *queue = malloc(n * sizeof *queue);
    uint8_t *seen = calloc(n, 1);
    int64_t count = 0;
    for (int pass = outside ? 0 : 1; pass < 2; pass++)
        for (size_t i = 0; i < n; i++) {
            int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w % (size_t)h),
                z = (int)(i / ((size_t)w * h));
            int border = !x || !y || !z || x == w - 1 || y == h - 1 || z == d - 1;
            if (g[i] != value || seen[i] || (pass == 0 && !border)) continue;
            if (pass == 1) count++;
            size_t head = 0, tail = 0;
            queue[tail++] = i;
            seen[i] = 1;
            while (head < tail) {
                size_t p = queue[head++];
                int px = (int)(p % (size_t)w), py = (int)(p / (size_t)w % (size_t)h),
                    pz = (int)(p / ((size_t)w * h));
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int k = abs(dx) + abs(dy) + abs(dz);
                            if (!k || (conn == 6 && k > 1)) continue;
                            int qx = px + dx, qy = py + dy, qz = pz + dz;
                            if (qx < 0 || qy < 0 || qz < 0 || qx >= w || qy >= h || qz >= d) continue;
                            size_t q = ((size_t)qz * h + qy) * w + qx;
                            if (g[q] != value || seen[q]) continue;
                            seen[q] = 1;
                            queue[tail++] = q;
                        }
            }
        }
    free(queue);
    free(seen);
    return count;
}

void measref_compute(const voxref *r, const double sp[3], measref *o)
{
    memset(o, 0, sizeof *o);
    int nx = r->nx, ny = r->ny, nz = r->nz;
    long double s[3] = {0}, ss[3][3] = {{0}};
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                if (!voxref_get(r, x, y, z)) continue;
                o->count++;
                long double p[3] = {x, y, z};
                for (int i = 0; i < 3; i++) {
                    s[i] += p[i];
                    for (int j = 0; j < 3; j++) ss[i][j] += p[i] * p[j];
                }
            }
    /* transitions: every pair (p, p+d) with p or p+d inside and values differing */
    for (int z = -1; z <= nz; z++)
        for (int y = -1; y <= ny; y++)
            for (int x = -1; x <= nx; x++)
                for (int d = 0; d < 13; d++)
                    if (voxref_get(r, x, y, z) !=
                        voxref_get(r, x + dirs13[d][0], y + dirs13[d][1], z + dirs13[d][2]))
                        o->trans[dir_class[d]]++;
    for (int a = 0; a < 3; a++) o->faces[a] = o->trans[a];
    /* V - E + F - C of the closed cubes, each cell tested on its own */
    int64_t V = 0, E = 0, F = 0;
    for (int z = 0; z <= nz; z++)
        for (int y = 0; y <= ny; y++)
            for (int x = 0; x <= nx; x++) {
                int any = 0, ex = 0, ey = 0, ez = 0, fx = 0, fy = 0, fz = 0;
                for (int dz = -1; dz <= 0; dz++)
                    for (int dy = -1; dy <= 0; dy++)
                        for (int dx = -1; dx <= 0; dx++)
                            any |= voxref_get(r, x + dx, y + dy, z + dz);
                /* edge (x,y,z)-(x+1,y,z) touches voxels (x, y-1..y, z-1..z) */
                for (int a = -1; a <= 0; a++)
                    for (int b = -1; b <= 0; b++) {
                        ex |= voxref_get(r, x, y + a, z + b);
                        ey |= voxref_get(r, x + a, y, z + b);
                        ez |= voxref_get(r, x + a, y + b, z);
                    }
                /* face at x spanning y..y+1, z..z+1 touches (x-1|x, y, z) */
                for (int a = -1; a <= 0; a++) {
                    fx |= voxref_get(r, x + a, y, z);
                    fy |= voxref_get(r, x, y + a, z);
                    fz |= voxref_get(r, x, y, z + a);
                }
                V += any;
                E += ex + ey + ez;
                F += fx + fy + fz;
            }
    o->euler = V - E + F - o->count;
    if (o->count) {
        long double n = (long double)o->count;
        for (int i = 0; i < 3; i++) {
            o->centroid[i] = (double)(s[i] / n * sp[i]);
            for (int j = 0; j < 3; j++)
                o->cov[i * 3 + j] = (double)((ss[i][j] / n - s[i] / n * s[j] / n) * sp[i] * sp[j]);
        }
    }
    /* components of the object; cavities of the background padded by one */
    o->components = flood_count(r->v, nx, ny, nz, 1, 26, 0);
    voxref *pad = voxref_pad(r, (const int[3]){1, 1, 1}, (const int[3]){1, 1, 1});
    o->cavities = flood_count(pad->v, nx + 2, ny + 2, nz + 2, 0, 6, 1);
    o->cavities_26 = flood_count(pad->v, nx + 2, ny + 2, nz + 2, 0, 26, 1);
    voxref_destroy(pad);
}
