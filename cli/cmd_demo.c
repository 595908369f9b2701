/*
 * cmd_demo.c — `bvox demo [-o DIR]`: the paper's system end to end on the
 * library's sample specimen (bvox_demo_run): the specimen cut into simulated
 * serial section images, the model reconstructed from them and compared
 * with the specimen. Prints what `bvox info` would print about the specimen,
 * then the reconstruction's numbers; with -o the sections, the specimen, the
 * model, the paper's four pictures of the model and a turntable GIF go into
 * DIR through the library's folder-output rules.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct demo_args {
    const char *dir;
    int json;
    int force;
} demo_args;

#define A(member) CLI_AT(demo_args, member)

static const cli_opt demo_opts[] = {
    {"--output", 'o', CLI_PATH, "DIR",
     "also write into DIR: the specimen (specimen.nii.gz, specimen.tif), the 70 simulated "
     "section images (section_0000.png ..), the reconstructed model (model.nii.gz), the "
     "paper's four pictures of it: picture1.png binary gradient and depth shaded, picture2.png "
     "depth shaded, zoomed x2 and high-pass filtered, picture3.png the same resliced along a "
     "plane, picture4.png the data set as stored in a frame buffer; beside them "
     "picture1_smooth.png and picture3_smooth.png, pictures 1 and 3 smooth-shaded (normals "
     "from the occupancy around each voxel); the paper's pre-image methods where it used "
     "them: picture1_preimage.png (picture 1 by a binary gradient operator over the "
     "pre-image), picture2_enlarged.png and picture3_enlarged.png (pictures 2 and 3 as a "
     "gradient over the pre-image enlarged x2 with Figure 5's averaging); and turntable.gif (DIR "
     "and its missing parents are created; a folder holding other files is refused)",
     A(dir), .flags = CLI_DIR},
    CLI_OPT_FORCE(demo_args, force),
    {"--json", 0, CLI_FLAG, NULL, "print the info as one JSON object", A(json)},
    {NULL},
};
static const cli_group demo_group = {"Options", demo_opts, NULL};

const cli_spec cli_spec_demo = {
    .name = "demo",
    .summary = "the paper's system end to end: cut, image, reconstruct the sample specimen",
    .usage = "[-o DIR] [options]",
    .about = "Build the built-in sample specimen: an embryo-like object (a body with a\n"
             "hole bored through it, a ring around it and a cap on top) of 256 x 256 x 128\n"
             "voxels of 10 x 10 x 25 um, as thick serial sections would give it, and print\n"
             "its info. Then run the paper's system on it: cut it into 70 sections 40 um\n"
             "apart, image each as a microscope would (uneven light, noise, three embedding\n"
             "markers, a random shift and turn per section), reconstruct the model from the\n"
             "images (`bvox reconstruct`: threshold, contours, marker alignment, shape-based\n"
             "interpolation) and print its Dice overlap and volume error against the specimen.\n",
    .uses = {{&demo_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox demo -o out && bvox view out/model.nii.gz\n",
};

/* The outermost missing folder above dir (what -o creates besides DIR
 * itself, which the library makes), or NULL if dir's parent exists. */
static char *first_missing_parent(const char *dir)
{
    char *p = strdup(dir);
    if (!p) return NULL;
    size_t n = strlen(p);
    while (n > 1 && p[n - 1] == '/') p[--n] = '\0';
    char *slash = strrchr(p, '/');
    if (!slash || slash == p) {
        free(p);
        return NULL;
    }
    *slash = '\0';
    struct stat sb;
    if (stat(p, &sb) == 0) {
        free(p);
        return NULL;
    }
    /* the outermost missing prefix of the parent */
    for (char *s = p + 1; *s; s++) {
        if (*s != '/') continue;
        *s = '\0';
        if (stat(p, &sb) != 0) return p;
        *s = '/';
    }
    return p;
}

/* Remove the empty folders from parent up to top (what this run made). */
static void remove_made(const char *dir, const char *top)
{
    char *p = strdup(dir);
    if (!p) return;
    size_t top_len = strlen(top);
    for (;;) {
        char *slash = strrchr(p, '/');
        if (!slash) break;
        *slash = '\0';
        if (strlen(p) < top_len || rmdir(p) != 0 || strlen(p) == top_len) break;
    }
    free(p);
}

static void print_text(const bvox_demo_report *r)
{
    printf("reconstruction: %d sections of %d x %d pixels (%g um, %g um apart, %d markers, "
           "%d not aligned by them)\n",
           (int)r->sections, (int)r->width, (int)r->height, r->pixel, r->section_spacing,
           (int)r->markers, (int)r->fallbacks);
    printf("dice: %.4f\n", r->dice);
    printf("volume error: %+.2f %% (%lld model voxels, %lld in the specimen)\n",
           r->volume_error_percent, (long long)r->model_voxels, (long long)r->specimen_voxels);
}

static void print_json(const bvox_info *info, const bvox_demo_report *r, const char *dir)
{
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_info_json_fields(&j, info, NULL, NULL);
    cli_json_io(&j, NULL, dir);
    cli_json_key(&j, "reconstruction");
    cli_json_begin_object(&j);
    cli_json_key(&j, "sections");
    cli_json_int(&j, r->sections);
    cli_json_key(&j, "dice");
    cli_json_double(&j, r->dice);
    cli_json_key(&j, "volume_error_percent");
    cli_json_double(&j, r->volume_error_percent);
    cli_json_key(&j, "section_spacing");
    cli_json_double(&j, r->section_spacing);
    cli_json_key(&j, "markers");
    cli_json_int(&j, r->markers);
    cli_json_key(&j, "fallbacks");
    cli_json_int(&j, r->fallbacks);
    cli_json_key(&j, "model_voxels");
    cli_json_int(&j, r->model_voxels);
    cli_json_end_object(&j);
    cli_json_end_object(&j);
    fputc('\n', stdout);
}

int cmd_demo(int argc, char **argv)
{
    const char *cmd = "demo";
    demo_args a = {0};
    CLI_PARSE_OR_RETURN(&cli_spec_demo, argc, argv, &a);
    if (a.dir && !*a.dir) return cli_usage_error(cmd, "-o needs a folder name");

    bvox_volume *vol = NULL;
    if (bvox_demo_specimen(&vol)) return cli_fail();
    bvox_info info;
    bvox_status st = bvox_info_compute(vol, &info);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();

    char *top = NULL;
    if (a.dir) {
        top = first_missing_parent(a.dir);
        if (top) {
            char *parent = strdup(a.dir);
            size_t n = parent ? strlen(parent) : 0;
            while (n > 1 && parent[n - 1] == '/') parent[--n] = '\0';
            char *slash = parent ? strrchr(parent, '/') : NULL;
            if (slash) *slash = '\0';
            int err = parent ? cli_make_dirs(parent) : ENOMEM;
            free(parent);
            if (err) {
                fprintf(stderr, "bvox: %s: cannot create the folder: %s\n", a.dir, strerror(err));
                remove_made(a.dir, top);
                free(top);
                return CLI_FAIL;
            }
        }
    }
    bvox_demo_opts o = bvox_demo_opts_default();
    o.dir = a.dir;
    o.force = a.force;
    bvox_demo_report r;
    st = bvox_demo_run(&o, &r);
    if (st && top) remove_made(a.dir, top);
    free(top);
    /* a failed demo prints only its error */
    if (st) return cli_fail();
    if (a.dir)
        fprintf(stderr,
                "wrote into %s: specimen.nii.gz, specimen.tif, section_0000.png .. "
                "section_%04d.png, model.nii.gz, picture1.png .. picture4.png, "
                "picture1_smooth.png, picture3_smooth.png, picture1_preimage.png, "
                "picture2_enlarged.png, picture3_enlarged.png, turntable.gif\n",
                a.dir, (int)r.sections - 1);
    if (a.json) print_json(&info, &r, a.dir);
    else {
        cli_print_info_text(stdout, &info, "(built-in specimen)", NULL);
        print_text(&r);
    }
    return CLI_OK;
}
