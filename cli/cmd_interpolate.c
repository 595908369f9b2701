/*
 * cmd_interpolate.c — `bvox interpolate MASK --axis z [-o OUT] [--labels]`:
 * a mask annotated on some z slices only (every n-th, or irregular) gets the
 * slices between them by shape-based interpolation
 * (bvox_interpolate_slices). With --labels, MASK is a label volume: all
 * labels are interpolated at once (bvox_interpolate_labels: a slice holding
 * any label is annotated, and regions stay tiled), or with --separate each
 * on its own crop (bvox_labels_read; a voxel two labels both claim keeps the
 * lower label); the labels are written back as one label volume
 * (bvox_write_labels: NIfTI, NRRD, .seg.nrrd, MetaImage by OUT's suffix, in
 * the input's integer type, with the names and colours of --lut or of the
 * input's own segments).
 */
#include "args.h"
#include "cli.h"
#include "opts.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

typedef struct interpolate_args {
    const char *in, *out, *axis, *lut;
    int labels, separate;
    cli_read_args ra;
} interpolate_args;

#define A(member) CLI_AT(interpolate_args, member)

static const char *const axes[] = {"z", NULL};
static const cli_opt interpolate_opts[] = {
    {"--axis", 0, CLI_STR, "z", "the slicing axis (only z for now)", A(axis), .choices = axes},
    {"--output", 'o', CLI_PATH, "OUT",
     "write the filled volume (with --labels: a label volume, .nii, .nii.gz, .nrrd, .nhdr, "
     ".seg.nrrd, .mha or .mhd)",
     A(out)},
    {"--labels", 0, CLI_FLAG, NULL, "MASK is a label volume: all its labels filled together",
     A(labels)},
    /* labelio: each label on its own (the slices holding it), not all at once */
    {"--separate", 0, CLI_FLAG, NULL,
     "with --labels: interpolate each label on its own, between the slices that hold it "
     "(labels traced on different slices); a voxel two labels claim keeps the lower",
     A(separate)},
    /* labelio: names and colours of the segments of a .seg.nrrd output */
    {"--lut", 0, CLI_PATH, "FILE",
     "with --labels: label names and colours for a .seg.nrrd output (FreeSurfer, ITK-SNAP, "
     "Slicer or AAL table; default: the input's own segments)",
     A(lut)},
    {NULL},
};
static const cli_group interpolate_group = {"Options", interpolate_opts, NULL};
static const cli_pos interpolate_pos[] = {
    {"MASK", "the mask annotated on some slices", A(in)},
    {NULL},
};

const cli_spec cli_spec_interpolate = {
    .name = "interpolate",
    .summary = "fill unannotated slices of a mask (shape-based, per label)",
    .usage = "MASK --axis z [-o OUT] [--labels [--separate] [--lut FILE]] [options]",
    .about = "Fill the slices of MASK that were not annotated (those without a 1-voxel)\n"
             "between annotated ones by shape-based interpolation: signed distance maps of\n"
             "the two annotated slices around, blended linearly, as 'bvox reconstruct' does\n"
             "between sections. Annotated slices are kept unchanged.\n"
             "With --labels, MASK is a label volume: every label's and the background's\n"
             "distance maps are blended together and each voxel takes the label it lies\n"
             "deepest in, so neighbouring regions neither overlap nor part (a slice holding\n"
             "any label is annotated for all); --separate fills each label on its own.\n",
    .pos = interpolate_pos,
    .uses = {{&interpolate_group, 0}, CLI_USE_READ(interpolate_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox interpolate traced.nii.gz --axis z -o filled.nii.gz\n"
                "  bvox interpolate seg_every5.nii.gz --axis z --labels -o seg.nii.gz\n"
                "  bvox interpolate atlas5.nii.gz --labels --lut atlas.txt -o atlas.seg.nrrd\n",
};

/* The labels of set's crops into lab (nx*ny*nz, x fastest); lower labels
 * written last, so a voxel two crops both hold keeps the lower label. */
static void unsplit(const bvox_labelset *set, const bvox_label_object *o, const bvox_volume *v,
                    uint32_t *lab)
{
    bvox_dims d = set->dims, c = bvox_volume_dims(v);
    for (int32_t z = 0; z < c.nz; z++)
        for (int32_t y = 0; y < c.ny; y++)
            for (int32_t x = 0; x < c.nx; x++)
                if (bvox_volume_get(v, x, y, z))
                    lab[((size_t)(z + o->crop.z0) * d.ny + (size_t)(y + o->crop.y0)) * d.nx +
                        (size_t)(x + o->crop.x0)] = (uint32_t)o->label;
}

static int interpolate_labels(const char *in, const cli_read_args *ra, const char *lut,
                              bool separate, const char *out)
{
    bvox_labelset *set;
    bvox_label_table *table;
    if (cli_labels_load(in, ra, lut, BVOX_LABELS_MAX_DEFAULT, &set, &table)) return cli_fail();
    bvox_dims d = set->dims;
    size_t n = (size_t)d.nx * d.ny * d.nz;
    uint32_t *lab = calloc(n, sizeof *lab);
    bvox_volume *like = NULL;
    int rc = CLI_OK;
    int64_t before = 0, after = 0;
    if (!lab || bvox_volume_create(d, &like) || bvox_volume_set_geometry(like, &set->geometry)) {
        rc = cli_fail();
        goto done;
    }
    for (int64_t i = set->n - 1; i >= 0; i--) { /* lower labels written last: they win */
        const bvox_label_object *o = &set->objects[i];
        if (o->label < 0 || o->label > UINT32_MAX) {
            fprintf(stderr, "bvox: %s: label %lld does not fit a written label volume\n", in,
                    (long long)o->label);
            rc = CLI_FAIL;
            goto done;
        }
        before += o->count;
        if (!separate) { /* all labels at once, below */
            unsplit(set, o, o->volume, lab);
            continue;
        }
        bvox_volume *f;
        if (bvox_interpolate_slices(o->volume, NULL, &f)) {
            rc = cli_fail();
            goto done;
        }
        after += bvox_volume_count(f);
        unsplit(set, o, f, lab);
        bvox_volume_destroy(f);
    }
    if (!separate) {
        if (bvox_interpolate_labels(d, lab, NULL)) {
            rc = cli_fail();
            goto done;
        }
        for (size_t i = 0; i < n; i++) after += lab[i] != 0;
    }
    /* the input's integer type (an int16 atlas stays int16); floats holding
       integers get the smallest unsigned type */
    int dtype = set->dtype < BVOX_DT_F32 ? (int)set->dtype : -1;
    if (out && bvox_write_labels(out, like, lab, dtype, table)) {
        rc = cli_fail();
        goto done;
    }
    printf("%s: %lld labels, %lld voxels annotated, %lld after filling\n", out ? out : in,
           (long long)set->n, (long long)before, (long long)after);
done:
    free(lab);
    bvox_volume_destroy(like);
    bvox_labelset_destroy(set);
    bvox_label_table_destroy(table);
    return rc;
}

int cmd_interpolate(int argc, char **argv)
{
    const char *cmd = "interpolate";
    interpolate_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_interpolate, argc, argv, &a);
    const char *in = a.in, *out = a.out, *axis = a.axis;
    int labels = a.labels;
    cli_read_args ra = a.ra;
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    if (!in) return cli_usage_error(cmd, "missing the MASK to fill");
    if (axis && strcmp(axis, "z"))
        return cli_usage_error(cmd, "--axis: only z is supported, not '%s'", axis);
    if (a.lut && !labels) return cli_usage_error(cmd, "--lut goes with --labels");
    if (a.separate && !labels) return cli_usage_error(cmd, "--separate goes with --labels");
    if (labels) {
        if (ra.binarize_given)
            return cli_usage_error(cmd, "--labels interpolates every label: no --label/--threshold");
        const char *of = out ? bvox_format_for_path(out) : NULL;
        if (out && (!of || (strcmp(of, "nifti") && strcmp(of, "nrrd") && strcmp(of, "metaimage"))))
            return cli_usage_error(cmd,
                                   "-o: '%s': label volumes are written as .nii, .nii.gz, .nrrd, "
                                   ".nhdr, .seg.nrrd, .mha or .mhd",
                                   out);
        return interpolate_labels(in, &ra, a.lut, a.separate, out);
    }
    bvox_volume *vol = NULL, *f = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_status st = bvox_interpolate_slices(vol, NULL, &f);
    int64_t before = bvox_volume_count(vol);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    if (out && bvox_write(out, f, &wo)) {
        bvox_volume_destroy(f);
        return cli_fail();
    }
    printf("%s: %lld voxels annotated, %lld after filling\n", out ? out : in, (long long)before,
           (long long)bvox_volume_count(f));
    bvox_volume_destroy(f);
    return CLI_OK;
}
