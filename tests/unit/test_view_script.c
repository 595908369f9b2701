/* test_view_script.c — the viewer's script language (viewer/script.c): every
 * command parsed into its fields, key names with modifiers, comments and
 * blank lines, the events a drag or click becomes (press, evenly spaced
 * motions ending on the target, release), and errors naming the line. */
#include "harness.h"
#include "view.h"

#include <stdlib.h>
#include <string.h>

TEST(parse_all_commands)
{
    const char *text = "# a demo\n"
                       "\n"
                       "key 5 shift+b ctrl+z pageup F12 A\n"
                       "drag left 10 20 110 70 5 shift   # light\n"
                       "drag right 0 0 -4 8\n"
                       "click middle 3 4 ctrl\n"
                       "move 7 9\n"
                       "wheel -2 40 50\n"
                       "wait 250\n"
                       "screenshot out/a.png\n"
                       "save model.nii.gz\n"
                       "quit\n";
    vw_script sc;
    CHECK_OK(vw_script_parse(text, &sc));
    CHECK_EQ(sc.n, 15);
    const vw_cmd *c = sc.cmds;
    CHECK_EQ(c[0].type, VW_CMD_KEY);
    CHECK_EQ(c[0].key, '5');
    CHECK_EQ(c[0].mods, 0);
    CHECK_EQ(c[0].line, 3);
    CHECK_EQ(c[1].key, 'b');
    CHECK_EQ(c[1].mods, VW_MOD_SHIFT);
    CHECK_EQ(c[2].key, 'z');
    CHECK_EQ(c[2].mods, VW_MOD_CTRL);
    CHECK_EQ(c[3].key, VW_KEY_PAGEUP);
    CHECK_EQ(c[4].key, VW_KEY_F12);
    CHECK_EQ(c[5].key, 'a'); /* a capital is shift + the letter */
    CHECK_EQ(c[5].mods, VW_MOD_SHIFT);
    CHECK_EQ(c[6].type, VW_CMD_DRAG);
    CHECK_EQ(c[6].button, VW_BUTTON_LEFT);
    CHECK(c[6].x0 == 10 && c[6].y0 == 20 && c[6].x1 == 110 && c[6].y1 == 70);
    CHECK_EQ(c[6].steps, 5);
    CHECK_EQ(c[6].mods, VW_MOD_SHIFT);
    CHECK_EQ(c[7].steps, 10); /* the default */
    CHECK_EQ(c[7].button, VW_BUTTON_RIGHT);
    CHECK_EQ(c[7].x1, -4);
    CHECK_EQ(c[8].type, VW_CMD_CLICK);
    CHECK_EQ(c[8].button, VW_BUTTON_MIDDLE);
    CHECK_EQ(c[8].mods, VW_MOD_CTRL);
    CHECK_EQ(c[9].type, VW_CMD_MOVE);
    CHECK_EQ(c[10].type, VW_CMD_WHEEL);
    CHECK_EQ(c[10].amount, -2);
    CHECK_EQ(c[11].type, VW_CMD_WAIT);
    CHECK_EQ(c[11].amount, 250);
    CHECK_EQ(c[12].type, VW_CMD_SCREENSHOT);
    CHECK(!strcmp(c[12].path, "out/a.png"));
    CHECK_EQ(c[13].type, VW_CMD_SAVE);
    CHECK(!strcmp(c[13].path, "model.nii.gz"));
    CHECK_EQ(c[14].type, VW_CMD_QUIT);
    CHECK_EQ(c[14].line, 12);
    vw_script_free(&sc);
    CHECK_OK(vw_script_parse("", &sc));
    CHECK_EQ(sc.n, 0);
    vw_script_free(&sc);
    return 0;
}

TEST(drag_events)
{
    vw_cmd c;
    memset(&c, 0, sizeof c);
    c.type = VW_CMD_DRAG;
    c.button = VW_BUTTON_LEFT;
    c.x0 = 10, c.y0 = 20, c.x1 = 110, c.y1 = 70, c.steps = 4;
    c.mods = VW_MOD_SHIFT;
    vw_event ev[16];
    int n = vw_script_events(&c, ev, 16);
    CHECK_EQ(n, 1 + 1 + 4 + 1); /* move there, press, 4 motions, release */
    CHECK_EQ(ev[0].type, VW_EV_MOTION);
    CHECK_EQ(ev[1].type, VW_EV_DOWN);
    CHECK(ev[1].x == 10 && ev[1].y == 20 && ev[1].button == VW_BUTTON_LEFT);
    for (int i = 1; i <= 4; i++) {
        CHECK_EQ(ev[1 + i].type, VW_EV_MOTION);
        CHECK_EQ(ev[1 + i].x, 10 + 25 * i);
        CHECK_EQ(ev[1 + i].y, 20 + (50 * i) / 4);
        CHECK_EQ(ev[1 + i].mods, VW_MOD_SHIFT);
    }
    CHECK_EQ(ev[6].type, VW_EV_UP);
    CHECK(ev[6].x == 110 && ev[6].y == 70);
    /* never more than asked */
    CHECK_EQ(vw_script_events(&c, ev, 3), 3);
    c.type = VW_CMD_CLICK;
    n = vw_script_events(&c, ev, 16);
    CHECK_EQ(n, 3);
    CHECK(ev[1].type == VW_EV_DOWN && ev[2].type == VW_EV_UP && ev[2].x == 10);
    return 0;
}

TEST(key_names)
{
    int k;
    unsigned m;
    CHECK_EQ(vw_key_parse("ctrl+shift+z", &k, &m), 0);
    CHECK(k == 'z' && m == (VW_MOD_CTRL | VW_MOD_SHIFT));
    CHECK_EQ(vw_key_parse("?", &k, &m), 0);
    CHECK(k == '?' && m == 0);
    CHECK_EQ(vw_key_parse("comma", &k, &m), 0);
    CHECK_EQ(k, ',');
    CHECK_EQ(vw_key_parse("Delete", &k, &m), 0);
    CHECK_EQ(k, VW_KEY_DELETE);
    CHECK_EQ(vw_key_parse("f13", &k, &m), -1);
    CHECK_EQ(vw_key_parse("ctrl+", &k, &m), -1);
    CHECK_EQ(vw_key_parse("nosuchkey", &k, &m), -1);
    /* names round-trip */
    int keys[] = {'a', '5', '[', VW_KEY_UP, VW_KEY_PAGEDOWN, VW_KEY_F1 + 4, VW_KEY_ESCAPE, ','};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        char name[32];
        snprintf(name, sizeof name, "%s", vw_key_name(keys[i]));
        CHECK_EQ(vw_key_parse(name, &k, &m), 0);
        CHECK_EQ(k, keys[i]);
    }
    return 0;
}

TEST(errors_name_the_line)
{
    static const char *const bad[] = {
        "key\n",                       /* no key */
        "# ok\nkey nosuch\n",          /* unknown key */
        "drag left 1 2 3\n",           /* missing coordinates */
        "drag up 1 2 3 4\n",           /* bad button */
        "drag left 1 2 3 4 0\n",       /* zero steps */
        "drag left 1 2 3 4 5 meta\n",  /* bad modifier */
        "click left x 2\n",            /* not a number */
        "wheel\n",
        "wait -1\n",
        "screenshot\n",
        "save a b\n",
        "jump 1 2\n",                  /* unknown command */
        "quit now\n",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        vw_script sc;
        CHECK_STATUS(vw_script_parse(bad[i], &sc), BVOX_EINVAL);
        CHECK(sc.cmds == NULL && sc.n == 0);
    }
    vw_script sc0;
    CHECK_STATUS(vw_script_parse("key 5\n\ndrag left 1 2\n", &sc0), BVOX_EINVAL);
    CHECK(strstr(vw_script_error(), "script line 3: drag") != NULL);
    /* a long line is refused, not truncated */
    char *longline = malloc(10000);
    CHECK(longline);
    memset(longline, 'a', 9999);
    longline[9999] = 0;
    vw_script sc;
    CHECK_STATUS(vw_script_parse(longline, &sc), BVOX_EINVAL);
    free(longline);
    CHECK_STATUS(vw_script_load(harness_path("missing.txt"), &sc), BVOX_ENOTFOUND);
    return 0;
}
