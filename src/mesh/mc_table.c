/*
 * mc_table.c — the marching-cubes case table, generated at first use from
 * one rule instead of typed in (Lorensen and Cline's 15 classes plus a fixed
 * answer to the ambiguous face).
 *
 * Each of the 6 faces of a cell is walked counter-clockwise seen from
 * outside the cell; along the walk a side is an "entry" (0 -> 1) or an
 * "exit" (1 -> 0). Every entry is joined to the next exit: on an ambiguous
 * face (1s on one diagonal) that cuts off each 1-corner, i.e. the 1-voxels
 * are 6-connected and the 0-voxels 18-connected. The rule looks at the face
 * alone, so the two cells sharing a face draw the same segments (in opposite
 * directions): the contour is closed and every mesh edge lies on exactly two
 * triangles. A crossed cube edge lies on two faces: it starts one segment
 * and ends another, so the segments of a cell chain into loops; each loop
 * is triangulated as a fan from a vertex none of whose diagonals join two
 * points of one face (such a diagonal could be drawn by the neighbour cell
 * too), or around the loop's centre when no vertex qualifies. (With this
 * rule every loop of the 256 cases has such a vertex, at most 5 triangles
 * per case as in the classic table; the centre fallback is kept so that a
 * change of rule cannot silently break the manifold property.)
 */
#include "mesh_private.h"

#include <pthread.h>
#include <string.h>

static bvox__mc_case table[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

void bvox__mc_edge_corners(int e, int *c0, int *c1)
{
    int axis = e >> 2, s = e & 3, o1 = s & 1, o2 = s >> 1;
    int off[3];
    off[axis] = 0;
    off[axis == 0 ? 1 : 0] = o1;
    off[axis == 2 ? 1 : 2] = o2;
    *c0 = off[0] | off[1] << 1 | off[2] << 2;
    *c1 = *c0 | 1 << axis;
}

static int edge_of(int ca, int cb)
{
    int diff = ca ^ cb, axis = diff == 1 ? 0 : diff == 2 ? 1 : 2;
    int c = ca & ~diff;
    int off[3] = {c & 1, (c >> 1) & 1, (c >> 2) & 1};
    int o1 = off[axis == 0 ? 1 : 0], o2 = off[axis == 2 ? 1 : 2];
    return axis << 2 | o1 | o2 << 1;
}

/* Faces (bit axis*2+side) an edge lies on. */
static unsigned edge_faces(int e)
{
    int c0, c1;
    bvox__mc_edge_corners(e, &c0, &c1);
    int axis = e >> 2;
    unsigned f = 0;
    for (int a = 0; a < 3; a++)
        if (a != axis) f |= 1u << (a * 2 + ((c0 >> a) & 1));
    return f;
}

static void edge_mid(int e, double p[3])
{
    int c0, c1;
    bvox__mc_edge_corners(e, &c0, &c1);
    for (int a = 0; a < 3; a++) p[a] = 0.5 * (((c0 >> a) & 1) + ((c1 >> a) & 1));
}

static void build_case(int k, int flip)
{
    bvox__mc_case *c = &table[k];
    memset(c, 0, sizeof *c);
    memset(c->edge_loop, -1, sizeof c->edge_loop);
    int succ[12];
    for (int e = 0; e < 12; e++) succ[e] = -1;
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++) {
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            int corner[4];
            for (int i = 0; i < 4; i++) {
                int iu = uv[side ? i : (4 - i) % 4][0], iv = uv[side ? i : (4 - i) % 4][1];
                corner[i] = side << axis | iu << u | iv << v;
            }
            int val[4];
            for (int i = 0; i < 4; i++) val[i] = (k >> corner[i]) & 1;
            if (val[0] == val[2] && val[1] == val[3] && val[0] != val[1])
                c->diag_faces |= (uint8_t)(1u << (axis * 2 + side));
            for (int i = 0; i < 4; i++) {
                if (!(val[i] == 0 && val[(i + 1) & 3] == 1)) continue; /* entry */
                for (int j = 1; j < 4; j++) {
                    int s = (i + j) & 3;
                    if (val[s] == 1 && val[(s + 1) & 3] == 0) { /* next exit */
                        int a = edge_of(corner[i], corner[(i + 1) & 3]);
                        int b = edge_of(corner[s], corner[(s + 1) & 3]);
                        if (flip) succ[b] = a;
                        else succ[a] = b;
                        break;
                    }
                }
            }
        }
    for (int e = 0; e < 12; e++) {
        if (succ[e] < 0 || c->edge_loop[e] >= 0) continue;
        int L = c->nloops++;
        int x = e, n = 0;
        do {
            c->edge_loop[x] = (int8_t)L;
            c->loop[L][n++] = (uint8_t)x;
            x = succ[x];
        } while (x != e);
        c->loop_len[L] = (uint8_t)n;
    }
    for (int e = 0; e < 12; e++)
        if (c->edge_loop[e] >= 0) c->edges |= (uint16_t)(1u << e);
    for (int L = 0; L < c->nloops; L++) {
        int n = c->loop_len[L];
        const uint8_t *lp = c->loop[L];
        int start = -1;
        for (int s = 0; s < n && start < 0; s++) {
            int ok = 1;
            for (int j = 0; j < n && ok; j++) {
                if (j == s || j == (s + 1) % n || j == (s + n - 1) % n) continue;
                if (edge_faces(lp[s]) & edge_faces(lp[j])) ok = 0;
            }
            if (ok) start = s;
        }
        if (start >= 0) {
            for (int i = 1; i + 1 < n; i++) {
                uint8_t *t = c->tri[c->ntri++];
                t[0] = lp[start];
                t[1] = lp[(start + i) % n];
                t[2] = lp[(start + i + 1) % n];
            }
        } else {
            c->centres |= (uint8_t)(1u << L);
            for (int i = 0; i < n; i++) {
                uint8_t *t = c->tri[c->ntri++];
                t[0] = (uint8_t)(12 + L);
                t[1] = lp[i];
                t[2] = lp[(i + 1) % n];
            }
        }
    }
}

static void build(void)
{
    build_case(1, 0);
    /* case 1 (corner 0 alone): the triangle's normal must point away from
     * corner 0; if the walk gave the other orientation, flip every segment */
    double a[3], b[3], d[3];
    edge_mid(table[1].tri[0][0], a);
    edge_mid(table[1].tri[0][1], b);
    edge_mid(table[1].tri[0][2], d);
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                   u[0] * w[1] - u[1] * w[0]};
    int flip = (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]) < 0;
    for (int k = 0; k < 256; k++) build_case(k, flip);
}

const bvox__mc_case *bvox__mc_table(void)
{
    pthread_once(&once, build);
    return table;
}
