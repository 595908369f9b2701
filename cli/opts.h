/*
 * opts.h — commands described once, as data. A subcommand declares its
 * options in static tables (name, short alias, kind, metavar, help line,
 * default, where the value goes or the callback that takes it) and its
 * positional arguments; one spec per command collects them with the prose of
 * its help. From that one description come the parser (cli_parse), the
 * `--help` text (cli_print_help), the manual page (cli_print_man) and the
 * bash completion (cli_print_completion): none of them can drift from the
 * others.
 *
 * Values land in a command-specific struct of parsed arguments ("args"): an
 * option names its field by offset and size (CLI_AT), so the tables stay
 * static const data that the generators can read without running a command.
 */
#ifndef BVOX_CLI_OPTS_H
#define BVOX_CLI_OPTS_H

#include "bvox.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* What an option's value is: it picks the built-in parser, the metavar's
 * completion (files for CLI_PATH, words for choices) and the man page. */
typedef enum cli_kind {
    CLI_FLAG,   /* no value: stores 1 (0 with CLI_NEGATE) into an int field */
    CLI_STR,    /* a word: stores the const char * */
    CLI_PATH,   /* a file or folder name: stores the const char * */
    CLI_INT,    /* an integer in lo..hi (both 0: any), one of choices if given */
    CLI_DOUBLE, /* a finite number, bounded by min/max as flags say */
    CLI_TRIPLE, /* "X,Y,Z": three finite numbers into a double[3], bounded like CLI_DOUBLE */
    CLI_CHOICE, /* one of choices: stores its index into an int field */
} cli_kind;

/* cli_opt.flags */
enum {
    CLI_NEGATE = 1 << 0,   /* CLI_FLAG stores 0 */
    CLI_MIN = 1 << 1,      /* value >= min */
    CLI_MIN_OPEN = 1 << 2, /* value > min */
    CLI_MAX = 1 << 3,      /* value <= max */
    CLI_MAX_OPEN = 1 << 4, /* value < max */
    CLI_REPEAT = 1 << 5,   /* may be given several times, each one counts (documentation) */
    CLI_DIR = 1 << 6,      /* CLI_PATH names a folder (completion) */
};

/* What a callback answers: the value is taken, or bad (the parser prints
 * the option's `bad` message with the value), or the callback has printed
 * its own usage message. */
enum { CLI_OPT_OK = 0, CLI_OPT_BAD = -1, CLI_OPT_FAILED = 1 };

struct cli_opt;
/* Takes an option's value (NULL for a flag). target is the args struct plus
 * the option's offset. */
typedef int (*cli_opt_fn)(const char *cmd, const struct cli_opt *opt, const char *value,
                          void *target);

typedef struct cli_opt {
    const char *name;    /* "--radius"; NULL ends a table */
    char alias;          /* 'o' for -o, or 0 */
    cli_kind kind;
    const char *metavar; /* "R"; NULL for a flag (choices: "a|b" by default) */
    const char *help;    /* one line, wrapped by the generators; "{formats}" is
                            replaced by the list of file formats */
    size_t offset, size; /* the field in the args struct (CLI_AT) */
    const char *def;     /* default: shown, and taken (parsed or given to fn)
                            before the command line */
    int flags;
    int64_t lo, hi;      /* CLI_INT bounds */
    double min, max;     /* CLI_DOUBLE / CLI_TRIPLE bounds (see flags) */
    const char *const *choices; /* NULL-terminated: CLI_CHOICE words, CLI_INT values */
    cli_opt_fn fn;       /* takes the value instead of the built-in parser */
    const char *bad;     /* usage message for a bad value, one %s: the value */
} cli_opt;

/* The field `member` of the args struct `type`. */
#define CLI_AT(type, member) .offset = offsetof(type, member), .size = sizeof(((type *)0)->member)

/* A titled list of options; several commands may share one (read options). */
typedef struct cli_group {
    const char *title; /* "Options", "Read options (...)" */
    const cli_opt *opts;
    const char *note;  /* text printed after the options, or NULL */
} cli_group;

/* A group used by a command, its fields at `base` inside the command's args. */
typedef struct cli_use {
    const cli_group *group;
    size_t base;
} cli_use;

/* A list filled by a positional argument that takes the rest (many): the
 * command allocates items with room for argc entries before cli_parse. */
typedef struct cli_list {
    const char **items;
    int n;
} cli_list;

typedef struct cli_pos {
    const char *name; /* "IN"; NULL ends the list */
    const char *help;
    size_t offset, size; /* a const char * field, or a cli_list one when many */
    int many;            /* takes every further positional argument */
} cli_pos;

/* Prose of a help text: a titled block printed as written ("Operations:"). */
typedef struct cli_section {
    const char *title;
    const char *text;
} cli_section;

#define CLI_MAX_USES 8

typedef struct cli_spec {
    const char *name;    /* "morph" */
    const char *summary; /* the line of `bvox --help` */
    const char *usage;   /* after "bvox NAME "; "\n" starts another usage line */
    const char *about;   /* the description, as written */
    const cli_pos *pos;  /* NULL or a list ended by a NULL name */
    const cli_section *sections; /* between the description and the options */
    cli_use uses[CLI_MAX_USES];  /* option groups in help order; ends with a NULL group */
    const char *notes;   /* after the options */
    const char *examples;
    const char *too_many; /* message for an extra positional (one %s), or NULL */
} cli_spec;

/* What cli_parse answers. */
enum { CLI_PARSED = 0, CLI_PARSE_HELP = 1, CLI_PARSE_ERROR = 2 };

/* Parses argv[1..argc-1] (argv[0] is the command's name) into args: the
 * defaults of the tables first, then each argument left to right; "--" ends
 * the options; --help/-h prints the help on stdout (CLI_PARSE_HELP). A wrong
 * command line prints one "bvox: CMD: ..." line (CLI_PARSE_ERROR). The
 * commands check what is required and what excludes what themselves. */
int cli_parse(const cli_spec *spec, int argc, char **argv, void *args);

/* The start of every command: parse, or return the exit code it ends with. */
#define CLI_PARSE_OR_RETURN(spec, argc, argv, args)                                            \
    do {                                                                                       \
        int cli_parse_r_ = cli_parse((spec), (argc), (argv), (args));                          \
        if (cli_parse_r_ != CLI_PARSED) return cli_parse_r_ == CLI_PARSE_HELP ? 0 : 2;         \
    } while (0)

/* The option of spec named arg ("--name", "--name=V", "-o"), or NULL; sets
 * *value to the text after '=' (else NULL) and *base to the group's base. */
const cli_opt *cli_find_option(const cli_spec *spec, const char *arg, const char **value,
                               size_t *base);

/* Iterates the options of spec in help order, each name once (the first
 * table that names an option owns it). Start with *use = *index = 0;
 * returns NULL at the end; *group_out (if not NULL) is the option's group. */
const cli_opt *cli_next_option(const cli_spec *spec, int *use, int *index,
                               const cli_group **group_out);

/* "R", "6|18|26", "above|below" or NULL for a flag. */
const char *cli_opt_metavar(const cli_opt *o, char *buf, size_t size);

/* The help line with "{formats}" expanded and " (default D)" appended. */
void cli_opt_help_text(const cli_opt *o, char *buf, size_t size);

/* Generators (opts_help.c, gen_man.c, gen_completion.c). */
void cli_print_help(FILE *f, const cli_spec *spec);
void cli_print_man(FILE *f, const cli_spec *spec);

/* The whole program, for `bvox help --man` and completion: the commands in
 * the order of `bvox --help`, and the global options. */
typedef struct cli_program {
    const cli_spec *const *commands;
    size_t ncommands;
    const cli_group *global;
} cli_program;
void cli_print_program_help(FILE *f, const cli_program *p);
void cli_print_program_man(FILE *f, const cli_program *p);
void cli_print_completion(FILE *f, const cli_program *p);

#endif
