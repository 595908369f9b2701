/*
 * fuzz_view_script.c — libFuzzer target for the viewer's script parser
 * (viewer/script.c): the input is a script file. A parse either fails
 * (BVOX_EINVAL with a message naming the line, no commands left) or gives
 * commands whose fields are in range; each command's events are expanded
 * into a bounded buffer; nothing leaks. Key names are parsed too.
 */
#include "view.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > (1u << 20)) return 0;
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    vw_script sc;
    bvox_status st = vw_script_parse(text, &sc);
    if (st == BVOX_OK) {
        for (int i = 0; i < sc.n; i++) {
            const vw_cmd *c = &sc.cmds[i];
            if (c->line < 1 || (c->type == VW_CMD_DRAG && (c->steps < 1 || c->steps > 10000))) abort();
            if ((c->type == VW_CMD_SCREENSHOT || c->type == VW_CMD_SAVE) && (!c->path || !*c->path)) abort();
            vw_event ev[64];
            int n = vw_script_events(c, ev, 64);
            if (n < 0 || n > 64) abort();
        }
        vw_script_free(&sc);
    } else if (sc.cmds || sc.n || !vw_script_error()[0]) {
        abort();
    }
    /* the same bytes as one key name */
    if (size < 64) {
        int key;
        unsigned mods;
        if (vw_key_parse(text, &key, &mods) == 0 && (key < 0 || key >= VW_KEY_MAX)) abort();
    }
    free(text);
    return 0;
}
