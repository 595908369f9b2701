/*
 * main.c — the `bvox` command: a table of subcommands {run, spec} from which
 * dispatch, `bvox --help`, `bvox help CMD`, the manual pages (`bvox help
 * --man [CMD]`) and the bash completion (`bvox help --bash-completion`) are
 * all derived, plus --version. Each subcommand lives in its own cmd_<name>.c and is a thin
 * wrapper over one library call.
 */
#include "cli.h"
#include "opts.h"
#include "progress.h"

#include <string.h>
#include <unistd.h>

static const cli_command commands[] = {
    {cmd_info, &cli_spec_info},
    {cmd_convert, &cli_spec_convert},
    {cmd_demo, &cli_spec_demo},
    {cmd_morph, &cli_spec_morph},
    {cmd_components, &cli_spec_components},
    {cmd_measure, &cli_spec_measure},
    {cmd_labels, &cli_spec_labels},
    {cmd_interpolate, &cli_spec_interpolate},
    {cmd_edit, &cli_spec_edit},
    {cmd_cut, &cli_spec_cut},
    {cmd_csg, &cli_spec_csg},
    {cmd_shape, &cli_spec_shape},
    {cmd_render, &cli_spec_render},
    {cmd_mosaic, &cli_spec_mosaic},
    {cmd_image, &cli_spec_image},
    {cmd_reconstruct, &cli_spec_reconstruct},
    {cmd_view, &cli_spec_view},
    {cmd_mesh, &cli_spec_mesh},
    {cmd_voxelize, &cli_spec_voxelize},
    {cmd_meshinfo, &cli_spec_meshinfo},
    {cmd_contours, &cli_spec_contours},
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

static const cli_spec *const specs[] = {
    &cli_spec_info,
    &cli_spec_convert,
    &cli_spec_demo,
    &cli_spec_morph,
    &cli_spec_components,
    &cli_spec_measure,
    &cli_spec_labels,
    &cli_spec_interpolate,
    &cli_spec_edit,
    &cli_spec_cut,
    &cli_spec_csg,
    &cli_spec_shape,
    &cli_spec_render,
    &cli_spec_mosaic,
    &cli_spec_image,
    &cli_spec_reconstruct,
    &cli_spec_view,
    &cli_spec_mesh,
    &cli_spec_voxelize,
    &cli_spec_meshinfo,
    &cli_spec_contours,
};

static const cli_opt global_opts[] = {
    {"--help", 'h', CLI_FLAG, NULL, "show this help ('bvox COMMAND --help' for a command)",
     .offset = 0},
    {"--version", 'V', CLI_FLAG, NULL, "show the version and the SIMD level in use", .offset = 0},
    /* taken out of the line by take_quiet before any command parses it */
    {"--quiet", 0, CLI_FLAG, NULL, "no warnings on stderr (errors are still printed)",
     .offset = 0},
    {NULL},
};
static const cli_group global_group = {"Global options", global_opts, NULL};
static const cli_program program = {specs, sizeof specs / sizeof specs[0], &global_group};

_Static_assert(sizeof specs / sizeof specs[0] == NCOMMANDS, "one spec per command");

static const cli_command *find(const char *name)
{
    for (size_t i = 0; i < NCOMMANDS; i++)
        if (!strcmp(commands[i].spec->name, name)) return &commands[i];
    return NULL;
}

static void help(FILE *f) { cli_print_program_help(f, &program); }

/* `bvox help [COMMAND]`, `bvox help --man [COMMAND]` (a roff manual page:
 * bvox(1) or bvox-COMMAND(1)), `bvox help --bash-completion`. */
static int help_command(int argc, char **argv)
{
    if (argc < 3) {
        help(stdout);
        return CLI_OK;
    }
    const char *what = argv[2];
    if (!strcmp(what, "--bash-completion")) {
        if (argc > 3) return cli_usage_error(NULL, "help --bash-completion takes no argument");
        cli_print_completion(stdout, &program);
        return CLI_OK;
    }
    if (!strcmp(what, "--man")) {
        if (argc > 4) return cli_usage_error(NULL, "help --man takes one COMMAND at most");
        if (argc == 3) {
            cli_print_program_man(stdout, &program);
            return CLI_OK;
        }
        const cli_command *c = find(argv[3]);
        if (!c) return cli_usage_error(NULL, "unknown command '%s'", argv[3]);
        cli_print_man(stdout, c->spec);
        return CLI_OK;
    }
    const cli_command *c = find(what);
    if (!c) {
        if (what[0] == '-') return cli_usage_error(NULL, "help: unknown option '%s'", what);
        return cli_usage_error(NULL, "unknown command '%s'", what);
    }
    char *sub[] = {argv[2], "--help", NULL};
    return c->run(2, sub);
}

/* Library warnings: one line each on stderr, "bvox: warning: ...". */
static void print_warning(const char *message, void *user)
{
    (void)user;
    cli_progress_clear();
    fprintf(stderr, "bvox: warning: %s\n", message);
}

/* --quiet is global: accepted anywhere on the line, removed before the
 * command sees its arguments. Returns the new argc. */
static int take_quiet(int argc, char **argv, int *quiet)
{
    int n = 0;
    for (int i = 0; i < argc; i++) {
        if (i > 0 && !strcmp(argv[i], "--")) { /* operands from here on */
            while (i < argc) argv[n++] = argv[i++];
            break;
        }
        if (i > 0 && !strcmp(argv[i], "--quiet")) {
            *quiet = 1;
            continue;
        }
        argv[n++] = argv[i];
    }
    argv[n] = NULL;
    return n;
}

int cli_quiet;

/* --json anywhere before "--": the output is for a script, no progress line. */
static int wants_json(int argc, char **argv)
{
    for (int i = 1; i < argc && strcmp(argv[i], "--"); i++)
        if (!strcmp(argv[i], "--json")) return 1;
    return 0;
}

static void version(void)
{
    bvox_simd level = bvox_simd_active();
    printf("bvox %s (simd: %s, threads: %d)\n", bvox_version(), bvox_simd_name(level),
           bvox_threads());
}

int main(int argc, char **argv)
{
    argc = take_quiet(argc, argv, &cli_quiet);
    if (!cli_quiet) bvox_set_warning_handler(print_warning, NULL);
    if (argc < 2) {
        help(stderr);
        return CLI_USAGE;
    }
    const char *name = argv[1];
    if (!strcmp(name, "--help") || !strcmp(name, "-h")) {
        help(stdout);
        return CLI_OK;
    }
    if (!strcmp(name, "--version") || !strcmp(name, "-V")) {
        version();
        return CLI_OK;
    }
    if (!strcmp(name, "help")) return help_command(argc, argv);
    const cli_command *c = find(name);
    if (!c) {
        if (name[0] == '-') return cli_usage_error(NULL, "unknown option '%s'", name);
        return cli_usage_error(NULL, "unknown command '%s'", name);
    }
    /* The progress line (a terminal, no --json, no --quiet; reconstruct
     * draws its own step line) and Ctrl-C as a clean cancel, installed
     * first so that the cleanup below leaves SIGINT to it. */
    if (c->run != cmd_view)
        cli_progress_install(isatty(2) && !cli_quiet && !wants_json(argc, argv) &&
                             c->run != cmd_reconstruct);
    /* Ctrl-C, SIGTERM or SIGHUP during a write removes its temporary files.
     * Not for the viewer, whose window library turns Ctrl-C into a quit. */
    if (c->run != cmd_view && bvox_cleanup_on_signals()) return cli_fail();
    int rc = c->run(argc - 1, argv + 1);
    cli_progress_clear();
    if (rc != CLI_OK && cli_interrupted()) return 130; /* as a death by SIGINT reads */
    /* A full disk or closed pipe on stdout is a failure too. */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        if (rc == CLI_OK) fprintf(stderr, "bvox: error writing the output\n");
        return rc == CLI_OK ? CLI_FAIL : rc;
    }
    return rc;
}
