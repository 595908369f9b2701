/*
 * cmd_demo.c — `bvox demo [-o DIR]`: build the library's sample specimen
 * (bvox_demo_specimen), print what `bvox info` would print about it, and with
 * -o write it into DIR as specimen.nii.gz and specimen.tif, with the paper's
 * four pictures of it (bvox_demo_pictures: picture1.png .. picture4.png).
 */
#include "args.h"
#include "cli.h"
#include "opts.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const outputs[] = {"specimen.nii.gz", "specimen.tif"};

typedef struct demo_args {
    const char *dir;
    int json;
} demo_args;

#define A(member) CLI_AT(demo_args, member)

static const cli_opt demo_opts[] = {
    {"--output", 'o', CLI_PATH, "DIR",
     "also write DIR/specimen.nii.gz and DIR/specimen.tif and the paper's four pictures of "
     "it: picture1.png binary gradient and depth shaded, picture2.png depth shaded, zoomed x2 "
     "and high-pass filtered, picture3.png the same resliced along a plane, picture4.png the "
     "data set as stored in a frame buffer (DIR is created if needed)",
     A(dir), .flags = CLI_DIR},
    {"--json", 0, CLI_FLAG, NULL, "print the info as one JSON object", A(json)},
    {NULL},
};
static const cli_group demo_group = {"Options", demo_opts, NULL};

const cli_spec cli_spec_demo = {
    .name = "demo",
    .summary = "build the sample specimen, print its info, optionally write it",
    .usage = "[-o DIR] [options]",
    .about = "Build the built-in sample specimen: an embryo-like object (a body with a\n"
             "hole bored through it, a ring around it and a cap on top) of 256 x 256 x 128\n"
             "voxels of 10 x 10 x 25 um, as thick serial sections would give it, and print\n"
             "its info.\n",
    .uses = {{&demo_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox demo -o out && bvox info out/specimen.nii.gz\n",
};

/* The outermost folder of dir that does not exist yet (what -o creates),
 * or NULL if dir exists; free it. */
static char *first_missing(const char *dir)
{
    char *p = strdup(dir);
    struct stat sb;
    for (char *s = p ? p + 1 : NULL; s; s++) {
        if (*s != '/' && *s != '\0') continue;
        char c = *s;
        *s = '\0';
        if (stat(p, &sb) != 0) return p;
        *s = c;
        if (!c) break;
    }
    free(p);
    return NULL;
}

/* After a failure: remove what this run wrote into the folders it created,
 * then those folders (from dir up to top), so a failed demo leaves nothing. */
static void undo_outputs(const char *dir, const char *top)
{
    static const char *const pictures[] = {"picture1.png", "picture2.png", "picture3.png",
                                           "picture4.png"};
    char path[4096];
    for (size_t k = 0; k < 2; k++)
        if (snprintf(path, sizeof path, "%s/%s", dir, outputs[k]) < (int)sizeof path)
            unlink(path);
    for (size_t k = 0; k < 4; k++)
        if (snprintf(path, sizeof path, "%s/%s", dir, pictures[k]) < (int)sizeof path)
            unlink(path);
    snprintf(path, sizeof path, "%s", dir);
    size_t top_len = strlen(top);
    for (;;) {
        size_t n = strlen(path);
        while (n > 1 && path[n - 1] == '/') path[--n] = '\0';
        if (n < top_len || rmdir(path) != 0 || n == top_len) break;
        char *slash = strrchr(path, '/');
        if (!slash) break;
        *slash = '\0';
    }
}

static int write_some(const char *dir, const bvox_volume *vol);

static int write_outputs(const char *dir, const bvox_volume *vol)
{
    char *top = first_missing(dir);
    int rc = write_some(dir, vol);
    if (rc != CLI_OK && top) undo_outputs(dir, top);
    free(top);
    return rc;
}

static int write_some(const char *dir, const bvox_volume *vol)
{
    int err = cli_make_dirs(dir);
    if (err) {
        fprintf(stderr, "bvox: %s: cannot create the folder: %s\n", dir, strerror(err));
        return CLI_FAIL;
    }
    for (size_t k = 0; k < sizeof outputs / sizeof outputs[0]; k++) {
        size_t n = strlen(dir) + strlen(outputs[k]) + 2;
        char *path = malloc(n);
        if (!path) {
            fprintf(stderr, "bvox: out of memory\n");
            return CLI_FAIL;
        }
        snprintf(path, n, "%s/%s", dir, outputs[k]);
        bvox_status st = bvox_write(path, vol, NULL);
        if (st) {
            free(path);
            return cli_fail();
        }
        fprintf(stderr, "wrote %s\n", path);
        free(path);
    }
    if (bvox_demo_pictures(vol, dir)) return cli_fail();
    fprintf(stderr, "wrote %s/picture1.png .. picture4.png\n", dir);
    return CLI_OK;
}

int cmd_demo(int argc, char **argv)
{
    const char *cmd = "demo";
    demo_args a = {0};
    CLI_PARSE_OR_RETURN(&cli_spec_demo, argc, argv, &a);
    const char *dir = a.dir;
    int json = a.json;
    if (dir && !*dir) return cli_usage_error(cmd, "-o needs a folder name");

    bvox_volume *vol = NULL;
    if (bvox_demo_specimen(&vol)) return cli_fail();
    bvox_info info;
    if (bvox_info_compute(vol, &info)) {
        bvox_volume_destroy(vol);
        return cli_fail();
    }
    /* Write first: a failed demo prints only its error. */
    int rc = dir ? write_outputs(dir, vol) : CLI_OK;
    bvox_volume_destroy(vol);
    if (rc != CLI_OK) return rc;
    if (json) cli_print_info_json_io(stdout, &info, NULL, NULL, NULL, dir);
    else cli_print_info_text(stdout, &info, "(built-in specimen)", NULL);
    return CLI_OK;
}
