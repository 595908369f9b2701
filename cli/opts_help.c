/*
 * opts_help.c — the `--help` text of a command and of `bvox` itself, made
 * from the tables of opts.h: usage lines, the description and sections as
 * written, then every option group with its lines wrapped to 79 columns
 * (the label in the first 24), the notes and the examples. --help/-h is the
 * parser's own, so its line closes the first group of every command.
 */
#include "opts.h"

#include <string.h>

enum { LABEL_COLS = 24, WIDTH = 79 };

static const cli_opt help_opt = {"--help", 'h', CLI_FLAG, NULL, "show this help", .offset = 0};

/* Words of text from column col on, wrapped at WIDTH with an indent of
 * LABEL_COLS. */
static void wrap(FILE *f, const char *text, int col)
{
    const char *p = text;
    int first = 1;
    while (*p) {
        while (*p == ' ') p++;
        size_t n = strcspn(p, " ");
        if (!n) break;
        if (!first && col + 1 + (int)n > WIDTH) {
            fprintf(f, "\n%*s", LABEL_COLS, "");
            col = LABEL_COLS;
        } else if (!first) {
            fputc(' ', f);
            col++;
        }
        fprintf(f, "%.*s", (int)n, p);
        col += (int)n;
        p += n;
        first = 0;
    }
    fputc('\n', f);
}

static void print_option(FILE *f, const cli_opt *o)
{
    char label[200], meta[200], text[1200];
    const char *m = cli_opt_metavar(o, meta, sizeof meta);
    char shortname[8] = "";
    if (o->alias) snprintf(shortname, sizeof shortname, "-%c, ", o->alias);
    int n = snprintf(label, sizeof label, "%s%s%s%s", shortname, o->name, m ? " " : "",
                     m ? m : "");
    cli_opt_help_text(o, text, sizeof text);
    if (n <= LABEL_COLS - 3) {
        fprintf(f, "  %-*s", LABEL_COLS - 2, label);
        wrap(f, text, LABEL_COLS);
    } else {
        fprintf(f, "  %s\n%*s", label, LABEL_COLS, "");
        wrap(f, text, LABEL_COLS);
    }
}

static void close_group(FILE *f, const cli_spec *s, int use, int home)
{
    if (use == home) print_option(f, &help_opt);
    if (s->uses[use].group && s->uses[use].group->note) fputs(s->uses[use].group->note, f);
}

void cli_print_help(FILE *f, const cli_spec *s)
{
    const char *u = s->usage;
    for (int line = 0; u; line++) {
        const char *nl = strchr(u, '\n');
        fprintf(f, "%s bvox %s %.*s\n", line ? "      " : "Usage:", s->name,
                (int)(nl ? nl - u : (long)strlen(u)), u);
        u = nl ? nl + 1 : NULL;
    }
    if (s->about) fprintf(f, "\n%s", s->about);
    for (const cli_section *sec = s->sections; sec && sec->title; sec++)
        fprintf(f, "\n%s:\n%s", sec->title, sec->text);
    /* The --help line closes the group called "Options" (else the first). */
    int home = 0;
    for (int k = 0; k < CLI_MAX_USES && s->uses[k].group; k++)
        if (!strcmp(s->uses[k].group->title, "Options")) {
            home = k;
            break;
        }
    int use = 0, index = 0, last = -1;
    const cli_group *g = NULL;
    const cli_opt *o;
    while ((o = cli_next_option(s, &use, &index, &g))) {
        if (use != last) {
            if (last >= 0) close_group(f, s, last, home);
            fprintf(f, "\n%s:\n", g->title);
            last = use;
        }
        print_option(f, o);
    }
    if (last < 0) fputs("\nOptions:\n", f);
    close_group(f, s, last < 0 ? home : last, home);
    if (s->notes) fprintf(f, "\n%s", s->notes);
    if (s->examples)
        fprintf(f, "\nExample%s:\n%s", strchr(s->examples, '\n') != strrchr(s->examples, '\n')
                                           ? "s" : "", s->examples);
}

void cli_print_program_help(FILE *f, const cli_program *p)
{
    fputs("Usage: bvox COMMAND [options]\n"
          "\n"
          "Binary voxel models: read, measure, convert.\n"
          "\n"
          "Commands:\n",
          f);
    for (size_t i = 0; i < p->ncommands; i++)
        fprintf(f, "  %-10s %s\n", p->commands[i]->name, p->commands[i]->summary);
    fprintf(f, "\n%s:\n", p->global->title);
    for (const cli_opt *o = p->global->opts; o->name; o++) print_option(f, o);
    fprintf(f, "\n"
               "Formats: %s\n"
               "Exit status: 0 success, 1 failure, 2 wrong command line.\n",
            bvox_format_list());
}
