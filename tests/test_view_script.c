/*
 * test_view_script.c: the viewer's event scripts (src/view/script.c): every command, the
 * expansion of hold, drag and taps into primitive events, and messages that name the line.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "view/script.h"

/* A toy key table: letters are 100 + their index, "shift" 7, "escape" 9. */
static int toy_key(const char *name)
{
    if (name[0] >= 'a' && name[0] <= 'z' && !name[1])
        return 100 + name[0] - 'a';
    if (strcmp(name, "shift") == 0)
        return 7;
    if (strcmp(name, "escape") == 0)
        return 9;
    return -1;
}

static void parse_ok(const char *text, view_script *script)
{
    vkrt_error err = {{0}};
    bool ok = view_script_parse(text, strlen(text), "e.txt", toy_key, script, &err);
    if (!ok)
        fail_msg("%s", err.msg);
}

static void parse_fails(const char *text, const char *expected)
{
    view_script script = {(view_event *)1, 99};
    vkrt_error err = {{0}};
    assert_false(view_script_parse(text, strlen(text), "e.txt", toy_key, &script, &err));
    if (!strstr(err.msg, expected))
        fail_msg("message '%s' lacks '%s'", err.msg, expected);
    assert_null(script.events);
    assert_int_equal(script.count, 0);
}

static void test_every_command(void **state)
{
    (void)state;
    view_script s;
    parse_ok("# a comment\n"
             "\n"
             "key W down   # a key named in capitals\n"
             "key w up\n"
             "key shift\n"
             "button down\n"
             "move 3.5 -2\n"
             "button up\n"
             "scroll -2\n"
             "resize 200 100\n"
             "wait 7\n"
             "wait 0\n"
             "wait converged\n"
             "key escape\r\n",
             &s);
    const view_event expected[] = {
        {VIEW_EVENT_KEY_DOWN, 122, 0, 0, 0, 3},  {VIEW_EVENT_KEY_UP, 122, 0, 0, 0, 4},
        {VIEW_EVENT_KEY_DOWN, 7, 0, 0, 0, 5},    {VIEW_EVENT_KEY_UP, 7, 0, 0, 0, 5},
        {VIEW_EVENT_BUTTON_DOWN, 0, 0, 0, 0, 6}, {VIEW_EVENT_MOVE, 0, 3.5f, -2, 0, 7},
        {VIEW_EVENT_BUTTON_UP, 0, 0, 0, 0, 8},   {VIEW_EVENT_SCROLL, 0, 0, -2, 0, 9},
        {VIEW_EVENT_RESIZE, 0, 200, 100, 0, 10}, {VIEW_EVENT_WAIT, 0, 0, 0, 7, 11},
        {VIEW_EVENT_WAIT, 0, 0, 0, 0, 12},       {VIEW_EVENT_WAIT_CONVERGED, 0, 0, 0, 0, 13},
        {VIEW_EVENT_KEY_DOWN, 9, 0, 0, 0, 14},   {VIEW_EVENT_KEY_UP, 9, 0, 0, 0, 14},
    };
    assert_int_equal(s.count, sizeof expected / sizeof *expected);
    for (size_t i = 0; i < s.count; ++i) {
        assert_int_equal(s.events[i].kind, expected[i].kind);
        assert_int_equal(s.events[i].key, expected[i].key);
        assert_true(s.events[i].x == expected[i].x && s.events[i].y == expected[i].y);
        assert_int_equal(s.events[i].frames, expected[i].frames);
        assert_int_equal(s.events[i].line, expected[i].line);
    }
    view_script_free(&s);
    assert_null(s.events);
}

static void test_hold_and_drag_expand(void **state)
{
    (void)state;
    view_script s;
    parse_ok("hold d 5\ndrag 30 -12 4\n", &s);
    /* hold: down, wait 5, up */
    assert_true(s.count >= 3);
    assert_int_equal(s.events[0].kind, VIEW_EVENT_KEY_DOWN);
    assert_int_equal(s.events[0].key, 103);
    assert_int_equal(s.events[1].kind, VIEW_EVENT_WAIT);
    assert_int_equal(s.events[1].frames, 5);
    assert_int_equal(s.events[2].kind, VIEW_EVENT_KEY_UP);
    /* drag: button down, 4 x (move, wait 1), button up; the moves add up to the drag */
    assert_int_equal(s.count, 3 + 1 + 8 + 1);
    assert_int_equal(s.events[3].kind, VIEW_EVENT_BUTTON_DOWN);
    float dx = 0, dy = 0;
    for (size_t i = 4; i < 12; i += 2) {
        assert_int_equal(s.events[i].kind, VIEW_EVENT_MOVE);
        assert_int_equal(s.events[i + 1].kind, VIEW_EVENT_WAIT);
        assert_int_equal(s.events[i + 1].frames, 1);
        dx += s.events[i].x;
        dy += s.events[i].y;
    }
    assert_true(fabsf(dx - 30) < 1e-5f && fabsf(dy + 12) < 1e-5f);
    assert_int_equal(s.events[12].kind, VIEW_EVENT_BUTTON_UP);
    for (size_t i = 3; i < s.count; ++i)
        assert_int_equal(s.events[i].line, 2);
    view_script_free(&s);
}

static void test_empty_script(void **state)
{
    (void)state;
    view_script s;
    parse_ok("# nothing but a comment\n\n", &s);
    assert_int_equal(s.count, 0);
    view_script_free(&s);
}

static void test_mistakes_name_their_line(void **state)
{
    (void)state;
    parse_fails("wait 1\nfly 3\n", "e.txt:2: unknown command");
    parse_fails("key ctrl\n", "e.txt:1: unknown key 'ctrl'");
    parse_fails("key w sideways\n", "e.txt:1: key: down or up was expected; got 'sideways'");
    parse_fails("key\n", "e.txt:1: key takes: key NAME [down|up]");
    parse_fails("hold w\n", "e.txt:1: hold takes: hold NAME FRAMES");
    parse_fails("hold w 0\n", "e.txt:1: a frame count from 1");
    parse_fails("wait -3\n", "e.txt:1: a frame count from 0");
    parse_fails("wait soon\n", "got 'soon'");
    parse_fails("wait 1 2\n", "wait takes");
    parse_fails("move 1 nan\n", "e.txt:1: a finite number was expected; got 'nan'");
    parse_fails("drag 1 2 0\n", "a frame count from 1");
    parse_fails("button left\n", "button: down or up was expected");
    parse_fails("resize 0 10\n", "e.txt:1: a frame count from 1");
    parse_fails("resize 20000 10\n", "larger than 16384");
    parse_fails("scroll\n", "scroll takes: scroll CLICKS");
    static const char nul[] = "wait 1\nkey w\0\n";
    view_script script;
    vkrt_error err = {{0}};
    assert_false(view_script_parse(nul, sizeof nul - 1, "e.txt", toy_key, &script, &err));
    assert_non_null(strstr(err.msg, "e.txt:2: not a text line"));
}

static void test_load_names_the_file(void **state)
{
    (void)state;
    view_script s;
    vkrt_error err = {{0}};
    assert_false(view_script_load("/nonexistent/events.txt", toy_key, &s, &err));
    assert_non_null(strstr(err.msg, "/nonexistent/events.txt"));
    char path[] = "/tmp/vkrt-script-XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs("hold w 2\nkey escape\n", f);
    fclose(f);
    assert_true(view_script_load(path, toy_key, &s, &err));
    assert_int_equal(s.count, 5);
    view_script_free(&s);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_command),       cmocka_unit_test(test_hold_and_drag_expand),
        cmocka_unit_test(test_empty_script),        cmocka_unit_test(test_mistakes_name_their_line),
        cmocka_unit_test(test_load_names_the_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
