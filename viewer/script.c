/*
 * script.c — the script language of `bvox view MODEL --script FILE` and the
 * key names it shares with the help. One command per line, '#' starts a
 * comment, coordinates are canvas pixels (0,0 top left):
 *
 *   key NAME...                 press keys: a, shift+a, ctrl+z, up, pageup, f1,
 *                               space, delete, escape, comma, ...
 *   drag BUTTON X0 Y0 X1 Y1 [STEPS] [MODS]   press at (X0, Y0), move in STEPS
 *                               steps (default 10) to (X1, Y1), release;
 *                               BUTTON left|middle|right, MODS shift, ctrl,
 *                               shift+ctrl
 *   click BUTTON X Y [MODS]     press and release
 *   move X Y                    the pointer, no button
 *   wheel N [X Y]               N clicks, positive zooms in
 *   wait MS                     let MS milliseconds pass (frames keep coming)
 *   screenshot PATH             write what the window shows as a PNG
 *   save PATH                   write the model (format from the extension)
 *   resize W H                  the window becomes W x H (64..8192), as when
 *                               its corner is dragged
 *   drop PATH                   a file dropped on the window (SDL's drop event)
 *   quit                        stop here (the end of the file does too)
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const struct {
    const char *name;
    int key;
} named[] = {
    {"up", VW_KEY_UP},         {"down", VW_KEY_DOWN},       {"left", VW_KEY_LEFT},
    {"right", VW_KEY_RIGHT},   {"pageup", VW_KEY_PAGEUP},   {"pagedown", VW_KEY_PAGEDOWN},
    {"home", VW_KEY_HOME},     {"end", VW_KEY_END},         {"delete", VW_KEY_DELETE},
    {"backspace", VW_KEY_BACKSPACE}, {"return", VW_KEY_RETURN}, {"enter", VW_KEY_RETURN},
    {"escape", VW_KEY_ESCAPE}, {"esc", VW_KEY_ESCAPE},      {"tab", VW_KEY_TAB},
    {"space", ' '},            {"comma", ','},              {"period", '.'},
    {"plus", '+'},             {"minus", '-'},              {"hash", '#'},
};

int vw_key_parse(const char *text, int *key, unsigned *mods)
{
    *mods = 0;
    for (;;) {
        if (!strncasecmp(text, "shift+", 6)) *mods |= VW_MOD_SHIFT, text += 6;
        else if (!strncasecmp(text, "ctrl+", 5)) *mods |= VW_MOD_CTRL, text += 5;
        else if (!strncasecmp(text, "alt+", 4)) *mods |= VW_MOD_ALT, text += 4;
        else break;
    }
    if (!*text) return -1;
    if (!text[1]) {
        unsigned char c = (unsigned char)*text;
        if (c < 33 || c > 126) return -1;
        if (isupper(c)) *mods |= VW_MOD_SHIFT, c = (unsigned char)tolower(c);
        *key = c;
        return 0;
    }
    for (size_t i = 0; i < sizeof named / sizeof named[0]; i++)
        if (!strcasecmp(text, named[i].name)) {
            *key = named[i].key;
            return 0;
        }
    if ((text[0] == 'f' || text[0] == 'F') && isdigit((unsigned char)text[1])) {
        char *end;
        long n = strtol(text + 1, &end, 10);
        if (!*end && n >= 1 && n <= 12) {
            *key = VW_KEY_F1 + (int)n - 1;
            return 0;
        }
    }
    return -1;
}

const char *vw_key_name(int key)
{
    static char buf[8];
    for (size_t i = 0; i < sizeof named / sizeof named[0]; i++)
        if (named[i].key == key) return named[i].name;
    if (key >= VW_KEY_F1 && key <= VW_KEY_F12) {
        snprintf(buf, sizeof buf, "f%d", key - VW_KEY_F1 + 1);
        return buf;
    }
    if (key > 32 && key < 127) {
        buf[0] = (char)key, buf[1] = 0;
        return buf;
    }
    return "?";
}

static _Thread_local char errbuf[256];

const char *vw_script_error(void) { return errbuf; }

static bvox_status fail(int line, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    /* the library's message buffer is not ours: the caller prints this one */
    if (line > 0) snprintf(errbuf, sizeof errbuf, "script line %d: %s", line, msg);
    else snprintf(errbuf, sizeof errbuf, "%s", msg);
    return BVOX_EINVAL;
}

static int parse_int(const char *t, int lo, int hi, int *out)
{
    if (!t) return -1;
    char *end;
    errno = 0;
    long v = strtol(t, &end, 10);
    if (errno || *end || end == t || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_button(const char *t, int *b)
{
    if (!t) return -1;
    if (!strcasecmp(t, "left")) *b = VW_BUTTON_LEFT;
    else if (!strcasecmp(t, "middle")) *b = VW_BUTTON_MIDDLE;
    else if (!strcasecmp(t, "right")) *b = VW_BUTTON_RIGHT;
    else return -1;
    return 0;
}

static int parse_mods(const char *t, unsigned *mods)
{
    *mods = 0;
    if (!t) return 0;
    char buf[64];
    snprintf(buf, sizeof buf, "%s", t);
    for (char *p = strtok(buf, "+"); p; p = strtok(NULL, "+")) {
        if (!strcasecmp(p, "shift")) *mods |= VW_MOD_SHIFT;
        else if (!strcasecmp(p, "ctrl")) *mods |= VW_MOD_CTRL;
        else if (!strcasecmp(p, "alt")) *mods |= VW_MOD_ALT;
        else return -1;
    }
    return 0;
}

static bvox_status push(vw_script *sc, int *cap, const vw_cmd *c)
{
    if (sc->n == *cap) {
        int ncap = *cap ? *cap * 2 : 32;
        vw_cmd *n = bvox__mem_resize(sc->cmds, (size_t)ncap * sizeof *n);
        if (!n) return BVOX_ENOMEM;
        sc->cmds = n;
        *cap = ncap;
    }
    sc->cmds[sc->n++] = *c;
    return BVOX_OK;
}

enum { MAX_TOKENS = 64, MAX_LINE = 4096 };

static bvox_status parse_line(char *line, int lineno, vw_script *sc, int *cap)
{
    char *tok[MAX_TOKENS + 1];
    int n = 0;
    char *hash = strchr(line, '#');
    if (hash) *hash = 0;
    for (char *p = strtok(line, " \t\r\n"); p; p = strtok(NULL, " \t\r\n")) {
        if (n == MAX_TOKENS) return fail(lineno, "too many words");
        tok[n++] = p;
    }
    tok[n] = NULL;
    if (!n) return BVOX_OK;
    vw_cmd c;
    memset(&c, 0, sizeof c);
    c.line = lineno;
    const char *cmd = tok[0];
    const int W = 1 << 20;
    if (!strcmp(cmd, "key")) {
        if (n < 2) return fail(lineno, "key: which key?");
        for (int i = 1; i < n; i++) {
            c.type = VW_CMD_KEY;
            if (vw_key_parse(tok[i], &c.key, &c.mods)) return fail(lineno, "unknown key '%s'", tok[i]);
            if (push(sc, cap, &c)) return BVOX_ENOMEM;
        }
        return BVOX_OK;
    }
    if (!strcmp(cmd, "drag")) {
        c.type = VW_CMD_DRAG;
        c.steps = 10;
        if (n < 6 || n > 8 || parse_button(tok[1], &c.button) || parse_int(tok[2], -W, W, &c.x0) ||
            parse_int(tok[3], -W, W, &c.y0) || parse_int(tok[4], -W, W, &c.x1) ||
            parse_int(tok[5], -W, W, &c.y1))
            return fail(lineno, "drag BUTTON X0 Y0 X1 Y1 [STEPS] [MODS]");
        int k = 6;
        if (k < n && isdigit((unsigned char)tok[k][0])) {
            if (parse_int(tok[k], 1, 10000, &c.steps)) return fail(lineno, "drag: STEPS is 1..10000");
            k++;
        }
        if (k < n && (parse_mods(tok[k], &c.mods) || k + 1 < n))
            return fail(lineno, "drag: MODS is shift, ctrl, alt or a '+' list of them");
    } else if (!strcmp(cmd, "click")) {
        c.type = VW_CMD_CLICK;
        if (n < 4 || n > 5 || parse_button(tok[1], &c.button) || parse_int(tok[2], -W, W, &c.x0) ||
            parse_int(tok[3], -W, W, &c.y0) || (n == 5 && parse_mods(tok[4], &c.mods)))
            return fail(lineno, "click BUTTON X Y [MODS]");
    } else if (!strcmp(cmd, "move")) {
        c.type = VW_CMD_MOVE;
        if (n != 3 || parse_int(tok[1], -W, W, &c.x0) || parse_int(tok[2], -W, W, &c.y0))
            return fail(lineno, "move X Y");
    } else if (!strcmp(cmd, "wheel")) {
        c.type = VW_CMD_WHEEL;
        if ((n != 2 && n != 4) || parse_int(tok[1], -1000, 1000, &c.amount) ||
            (n == 4 && (parse_int(tok[2], -W, W, &c.x0) || parse_int(tok[3], -W, W, &c.y0))))
            return fail(lineno, "wheel N [X Y]");
    } else if (!strcmp(cmd, "wait")) {
        c.type = VW_CMD_WAIT;
        if (n != 2 || parse_int(tok[1], 0, 600000, &c.amount)) return fail(lineno, "wait MS (0..600000)");
    } else if (!strcmp(cmd, "resize")) {
        c.type = VW_CMD_RESIZE;
        if (n != 3 || parse_int(tok[1], 64, 8192, &c.x0) || parse_int(tok[2], 64, 8192, &c.y0))
            return fail(lineno, "resize W H (64..8192 each)");
    } else if (!strcmp(cmd, "screenshot") || !strcmp(cmd, "save") || !strcmp(cmd, "drop")) {
        c.type = cmd[0] == 'd' ? VW_CMD_DROP : cmd[1] == 'c' ? VW_CMD_SCREENSHOT : VW_CMD_SAVE;
        if (n != 2) return fail(lineno, "%s PATH (one word)", cmd);
        c.path = bvox__mem_strdup(tok[1]);
        if (!c.path) return fail(lineno, "out of memory"), BVOX_ENOMEM;
    } else if (!strcmp(cmd, "quit")) {
        if (n != 1) return fail(lineno, "quit takes nothing");
        c.type = VW_CMD_QUIT;
    } else {
        return fail(lineno, "unknown command '%s' (key, drag, click, move, wheel, wait, "
                            "screenshot, save, resize, drop, quit)", cmd);
    }
    if (push(sc, cap, &c)) {
        free(c.path);
        return BVOX_ENOMEM;
    }
    return BVOX_OK;
}

bvox_status vw_script_parse(const char *text, vw_script *out)
{
    out->cmds = NULL;
    out->n = 0;
    int cap = 0, lineno = 0;
    const char *p = text;
    errbuf[0] = 0;
    while (*p) {
        lineno++;
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len >= MAX_LINE) {
            vw_script_free(out);
            return fail(lineno, "line longer than %d bytes", MAX_LINE - 1);
        }
        char line[MAX_LINE];
        memcpy(line, p, len);
        line[len] = 0;
        bvox_status st = parse_line(line, lineno, out, &cap);
        if (st) {
            vw_script_free(out);
            return st;
        }
        p += len + (e ? 1 : 0);
    }
    return BVOX_OK;
}

bvox_status vw_script_load(const char *path, vw_script *out)
{
    out->cmds = NULL;
    out->n = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        fail(0, "cannot open script %.100s: %s", path, strerror(errno));
        return BVOX_ENOTFOUND;
    }
    size_t cap = 4096, n = 0;
    char *buf = bvox__mem_alloc(cap);
    for (;;) {
        if (!buf) break;
        if (n + 1 >= cap) {
            if (cap >= ((size_t)16 << 20)) { /* 16 MiB of script is a mistake */
                free(buf);
                buf = NULL;
                break;
            }
            char *nb = bvox__mem_resize(buf, cap * 2);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        if (!got) break;
        n += got;
    }
    fclose(f);
    if (!buf) {
        fail(0, "script %.100s is too large (or out of memory)", path);
        return BVOX_ETOOBIG;
    }
    buf[n] = 0;
    if (memchr(buf, 0, n)) {
        free(buf);
        fail(0, "script %.100s is not text", path);
        return BVOX_EFORMAT;
    }
    bvox_status st = vw_script_parse(buf, out);
    free(buf);
    return st;
}

void vw_script_free(vw_script *sc)
{
    for (int i = 0; i < sc->n; i++) free(sc->cmds[i].path);
    free(sc->cmds);
    sc->cmds = NULL;
    sc->n = 0;
}

int vw_script_events(const vw_cmd *c, vw_event *ev, int max)
{
    int n = 0;
#define ADD(...)                                                                          \
    do {                                                                                  \
        if (n < max) ev[n++] = (vw_event){__VA_ARGS__};                                   \
    } while (0)
    switch (c->type) {
    case VW_CMD_KEY: ADD(.type = VW_EV_KEY, .key = c->key, .mods = c->mods); break;
    case VW_CMD_CLICK:
        ADD(.type = VW_EV_MOTION, .mods = c->mods, .x = c->x0, .y = c->y0);
        ADD(.type = VW_EV_DOWN, .mods = c->mods, .button = c->button, .x = c->x0, .y = c->y0);
        ADD(.type = VW_EV_UP, .mods = c->mods, .button = c->button, .x = c->x0, .y = c->y0);
        break;
    case VW_CMD_DRAG:
        ADD(.type = VW_EV_MOTION, .mods = c->mods, .x = c->x0, .y = c->y0);
        ADD(.type = VW_EV_DOWN, .mods = c->mods, .button = c->button, .x = c->x0, .y = c->y0);
        for (int i = 1; i <= c->steps; i++) {
            int x = c->x0 + (int)((long)(c->x1 - c->x0) * i / c->steps);
            int y = c->y0 + (int)((long)(c->y1 - c->y0) * i / c->steps);
            ADD(.type = VW_EV_MOTION, .mods = c->mods, .button = c->button, .x = x, .y = y);
        }
        ADD(.type = VW_EV_UP, .mods = c->mods, .button = c->button, .x = c->x1, .y = c->y1);
        break;
    case VW_CMD_MOVE: ADD(.type = VW_EV_MOTION, .x = c->x0, .y = c->y0); break;
    case VW_CMD_WHEEL: ADD(.type = VW_EV_WHEEL, .wheel = c->amount, .x = c->x0, .y = c->y0); break;
    case VW_CMD_QUIT: ADD(.type = VW_EV_QUIT); break;
    case VW_CMD_RESIZE: ADD(.type = VW_EV_RESIZE, .x = c->x0, .y = c->y0); break;
    case VW_CMD_DROP: ADD(.type = VW_EV_DROP, .path = c->path); break;
    default: break;
    }
#undef ADD
    return n;
}
