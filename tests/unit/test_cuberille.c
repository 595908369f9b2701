/* test_cuberille.c — cuberille's plain-quad path (whole columns whose faces
 * have no diagonal side and no multi-sheet corner, emitted from ranks
 * without building polygons) against its general path
 * (bvox__mesh_cuberille_reference: every face through face_polygon): the
 * same vertices bit for bit and the same triangles in the same order, on
 * smooth objects with a few specks (mostly plain columns, some not), on
 * random volumes (mostly general), at awkward sizes, in a scaled, shifted
 * and mirrored frame, at 1 and 3 threads. test_mesh.c checks the meshes
 * themselves (manifold, exact volume, hand-computed cases). */
#include "harness.h"
#include "internal.h"
#include "mesh/mesh_private.h"

#include <string.h>

/* Balls and a box, plus specks (single voxels, which touch the objects
 * along edges and at corners: diagonal edges, multi-sheet corners). */
static bvox_volume *blobby(bvox_dims d, unsigned specks_per_mille)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create(d, &v) != BVOX_OK) return NULL;
    const double cx = d.nx * 0.45, cy = d.ny * 0.5, cz = d.nz * 0.55;
    const double r = 0.35 * (d.nx < d.ny ? (d.nx < d.nz ? d.nx : d.nz) : (d.ny < d.nz ? d.ny : d.nz));
    for (int32_t z = 0; z < d.nz; z++)
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++) {
                double dx = x - cx, dy = y - cy, dz = z - cz;
                int in = dx * dx + dy * dy + dz * dz <= r * r;
                double ex = x - 0.2 * d.nx, ey = y - 0.8 * d.ny, ez = z - 0.3 * d.nz;
                in |= ex * ex + 2 * ey * ey + ez * ez <= 0.1 * r * r;
                in |= x >= d.nx * 3 / 4 && y < d.ny / 3 && z >= 2 && z < d.nz - 2;
                if (harness_rand() % 1000 < specks_per_mille) in = !in;
                if (in) bvox_volume_set(v, x, y, z, 1);
            }
    return v;
}

static bvox_volume *random_volume(bvox_dims d, unsigned percent)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create(d, &v) != BVOX_OK) return NULL;
    for (int32_t z = 0; z < d.nz; z++)
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++)
                if (harness_rand() % 100 < percent) bvox_volume_set(v, x, y, z, 1);
    return v;
}

/* 0 if both paths give the same mesh, byte for byte. */
static int same_as_reference(const bvox_volume *v)
{
    bvox_mesh *a = NULL, *b = NULL;
    CHECK_OK(bvox_mesh_create(&a));
    CHECK_OK(bvox_mesh_create(&b));
    CHECK_OK(bvox__mesh_cuberille(v, a));
    CHECK_OK(bvox__mesh_cuberille_reference(v, b));
    CHECK_EQ(a->nvertices, b->nvertices);
    CHECK_EQ(a->ntriangles, b->ntriangles);
    /* (an empty mesh may have no arrays at all) */
    CHECK(!a->nvertices ||
          !memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double)));
    CHECK(!a->ntriangles ||
          !memcmp(a->triangles, b->triangles, (size_t)a->ntriangles * 3 * sizeof(int32_t)));
    bvox_mesh_destroy(a);
    bvox_mesh_destroy(b);
    return 0;
}

static const bvox_dims sizes[] = {{1, 1, 1},  {3, 2, 1},   {5, 7, 63},  {6, 5, 64},
                                  {9, 4, 65}, {13, 11, 130}, {40, 33, 70}, {31, 45, 128}};

TEST(plain_path_smooth_objects)
{
    for (int t = 0; t < 2; t++) {
        bvox_set_threads(t ? 3 : 1);
        for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
            for (unsigned sp = 0; sp <= 4; sp += 2) {
                bvox_volume *v = blobby(sizes[s], sp);
                CHECK(v);
                if (same_as_reference(v)) {
                    fprintf(stderr, "size %dx%dx%d, specks %u/1000\n", sizes[s].nx, sizes[s].ny,
                            sizes[s].nz, sp);
                    return 1;
                }
                bvox_volume_destroy(v);
            }
    }
    bvox_set_threads(0);
    return 0;
}

TEST(plain_path_random_volumes)
{
    static const unsigned dens[] = {1, 10, 50, 90, 99};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
        for (size_t d = 0; d < sizeof dens / sizeof *dens; d++) {
            bvox_volume *v = random_volume(sizes[s], dens[d]);
            CHECK(v);
            if (same_as_reference(v)) {
                fprintf(stderr, "size %dx%dx%d, %u %%\n", sizes[s].nx, sizes[s].ny, sizes[s].nz,
                        dens[d]);
                return 1;
            }
            bvox_volume_destroy(v);
        }
    return 0;
}

/* Positions come from a precomputed column term plus a z term: they must
 * still equal bvox__grid_world's to the bit in any frame. */
TEST(plain_path_geometry)
{
    bvox_volume *v = blobby((bvox_dims){24, 21, 67}, 1);
    CHECK(v);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.3;
    g.spacing[1] = 1.7;
    g.spacing[2] = 0.1;
    g.origin[0] = 10.125;
    g.origin[1] = -20.3;
    g.origin[2] = 1e5 / 3;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    CHECK(!same_as_reference(v));
    /* a rotated and mirrored frame (x reversed): faces flipped */
    const double dir[9] = {-0.6, 0.8, 0, 0.8, 0.6, 0, 0, 0, 1};
    memcpy(g.direction, dir, sizeof dir);
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    CHECK(!same_as_reference(v));
    bvox_volume_destroy(v);
    return 0;
}

/* Pass 1 looks up the case only of the cells bvox__grid_maybe_multi keeps:
 * it must keep every case with more than one sheet (and, to be worth it,
 * not many more). Each case in every bit position of the word. */
TEST(maybe_multi_covers_the_table)
{
    const bvox__mc_case *tab = bvox__mc_table();
    int multi = 0, kept = 0;
    for (unsigned k = 0; k < 256; k++) {
        for (unsigned bit = 0; bit < 64; bit += 21) {
            uint64_t c[8];
            for (int b = 0; b < 8; b++) c[b] = ((k >> b) & 1) ? 1ull << bit : 0;
            uint64_t m = bvox__grid_maybe_multi(c);
            CHECK(!(m & ~(1ull << bit)));
            if (tab[k].nloops > 1) CHECK(m);
            if (bit == 0) kept += m != 0;
        }
        multi += tab[k].nloops > 1;
    }
    CHECK(multi > 0);
    CHECK(kept < 2 * multi);
    return 0;
}
