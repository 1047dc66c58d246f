/*
 * test_device_pool.c: the queue and the failures of src/device_pool.c, with workers that render
 * nothing: a frame is a file the worker creates (O_EXCL, so a frame written twice fails its
 * worker). Every frame is written exactly once, by some worker; a worker killed while it holds a
 * frame (SIGKILL, as a crashing driver would end it), one whose frame fails and one that cannot
 * start each lose nothing and are reported; when every worker fails the frames left are counted;
 * a stop hands out no more frames. Also the --devices forms and the device listing in a child.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "device_pool.h"
#include "temp_dir.h"

enum { frame_count = 24 };

/* How each worker behaves: a worker of index `kill_worker` kills itself on its first frame, of
 * `fail_worker` reports an error on it, of `no_start_worker` fails to start; -1: none. */
typedef struct fake {
    const char *dir;
    int kill_worker, fail_worker, no_start_worker;
    bool every_worker_dies;
    uint32_t stop_after;      /* the parent sets the stop flag after this many frames; 0: never */
    volatile sig_atomic_t stop;
    uint32_t worker;          /* in a worker: its index (each process has its own copy) */
} fake;

static bool fake_start(void *user, uint32_t worker, int device, vkrt_pool_start *started,
                       vkrt_error *err)
{
    fake *f = user;
    f->worker = worker;
    if ((int)worker == f->no_start_worker)
        return vkrt_error_set(err, "device %d: no such luck", device);
    snprintf(started->device_name, sizeof started->device_name, "fake %d", device);
    snprintf(started->about, sizeof started->about, "about worker %u\n", worker);
    return true;
}

static bool fake_render(void *user, uint32_t frame, vkrt_pool_frame *result, vkrt_error *err)
{
    fake *f = user;
    /* A frame takes a little while, as a real one does: every worker gets frames. */
    nanosleep(&(struct timespec){.tv_nsec = 5 * 1000 * 1000}, NULL);
    if (f->every_worker_dies || (int)f->worker == f->kill_worker)
        raise(SIGKILL);
    if ((int)f->worker == f->fail_worker)
        return vkrt_error_set(err, "frame %u: the device was lost", frame);
    char path[600];
    snprintf(path, sizeof path, "%s/frame%02u", f->dir, frame);
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0)
        return vkrt_error_set(err, "frame %u written twice", frame);
    close(fd);
    result->gpu_seconds = 0.001;
    result->rays = 100;
    return true;
}

static void fake_frame_done(void *user, uint32_t frame, uint32_t done, uint32_t worker)
{
    (void)frame;
    (void)worker;
    fake *f = user;
    if (f->stop_after && done >= f->stop_after)
        f->stop = 1;
}

/* Runs 3 workers over frame_count frames (numbered 100, 101, ...: not the queue's indices). */
static void run(temp_dir *t, fake *f, vkrt_pool_result *r)
{
    static const int devices[] = {0, 0, 1};
    uint32_t frames[frame_count];
    for (uint32_t i = 0; i < frame_count; ++i)
        frames[i] = 100 + i;
    f->dir = t->dir;
    vkrt_device_pool_desc desc = {
        .devices = devices,
        .worker_count = 3,
        .frames = frames,
        .frame_count = frame_count,
        .user = f,
        .start = fake_start,
        .render = fake_render,
        .frame_done = fake_frame_done,
        .stop = &f->stop,
    };
    vkrt_error err = {{0}};
    if (!vkrt_device_pool_run(&desc, r, &err))
        fail_msg("%s", err.msg);
}

static uint32_t frames_on_disk(temp_dir *t)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < frame_count; ++i) {
        char name[16];
        snprintf(name, sizeof name, "frame%02u", 100 + i);
        n += access(temp_dir_path(t, name), F_OK) == 0;
    }
    return n;
}

static uint32_t frames_reported(const vkrt_pool_result *r)
{
    uint32_t n = 0;
    for (uint32_t w = 0; w < r->worker_count; ++w)
        n += r->workers[w].frames;
    return n;
}

static void every_frame_once(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = -1, .fail_worker = -1, .no_start_worker = -1};
    vkrt_pool_result r;
    run(t, &f, &r);
    assert_int_equal(r.rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
    assert_int_equal(frames_reported(&r), frame_count);
    for (uint32_t w = 0; w < 3; ++w) {
        if (r.workers[w].failed)
            fail_msg("worker %u failed: %s", w, r.workers[w].failure);
        assert_true(r.workers[w].frames > 0);
        assert_int_equal(r.workers[w].rays, 100 * r.workers[w].frames);
    }
    assert_string_equal(r.workers[2].device_name, "fake 1");
    assert_non_null(strstr(r.about, "about worker"));
    assert_false(r.interrupted);
}

static void killed_worker_loses_nothing(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = 1, .fail_worker = -1, .no_start_worker = -1};
    vkrt_pool_result r;
    run(t, &f, &r);
    const vkrt_pool_worker *k = &r.workers[1];
    assert_true(k->failed);
    assert_non_null(strstr(k->failure, "killed by signal 9"));
    assert_true(k->lost_frame);
    assert_int_equal(k->frames, 0);
    assert_true(k->lost_frame_number >= 100 && k->lost_frame_number < 100 + frame_count);
    assert_int_equal(r.rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
    assert_int_equal(frames_reported(&r), frame_count);
    assert_false(r.workers[0].failed || r.workers[2].failed);
}

static void failed_frame_goes_to_the_others(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = -1, .fail_worker = 0, .no_start_worker = -1};
    vkrt_pool_result r;
    run(t, &f, &r);
    const vkrt_pool_worker *k = &r.workers[0];
    assert_true(k->failed);
    assert_false(k->failed_at_end);
    assert_non_null(strstr(k->failure, "the device was lost"));
    assert_true(k->lost_frame);
    assert_int_equal(r.rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
}

static void worker_that_cannot_start(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = -1, .fail_worker = -1, .no_start_worker = 2};
    vkrt_pool_result r;
    run(t, &f, &r);
    const vkrt_pool_worker *k = &r.workers[2];
    assert_true(k->failed);
    assert_string_equal(k->failure, "device 1: no such luck");
    assert_string_equal(k->device_name, "");
    assert_false(k->lost_frame);
    assert_int_equal(r.rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
}

static void every_worker_dies(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = -1, .fail_worker = -1, .no_start_worker = -1,
              .every_worker_dies = true};
    vkrt_pool_result r;
    run(t, &f, &r);
    assert_int_equal(r.rendered, 0);
    assert_int_equal(frames_on_disk(t), 0);
    for (uint32_t w = 0; w < 3; ++w)
        assert_true(r.workers[w].failed && r.workers[w].lost_frame);
}

static void stop_hands_out_no_more(void **state)
{
    temp_dir *t = *state;
    fake f = {.kill_worker = -1, .fail_worker = -1, .no_start_worker = -1, .stop_after = 3};
    vkrt_pool_result r;
    run(t, &f, &r);
    assert_true(r.interrupted);
    /* The frames in flight when the stop came finish: at most one a worker after the third. */
    assert_true(r.rendered >= 3 && r.rendered <= 3 + 3);
    assert_int_equal(frames_on_disk(t), r.rendered);
    for (uint32_t w = 0; w < 3; ++w)
        assert_false(r.workers[w].failed);
}

static void devices_forms(void **state)
{
    (void)state;
    int d[VKRT_POOL_MAX_WORKERS];
    uint32_t n;
    vkrt_error err = {{0}};
    assert_true(vkrt_devices_spec_parse("all", 3, "", d, &n, &err));
    assert_int_equal(n, 3);
    assert_int_equal(d[2], 2);
    assert_true(vkrt_devices_spec_parse("2,0,0", 3, "", d, &n, &err));
    assert_int_equal(n, 3);
    assert_int_equal(d[0], 2);
    assert_int_equal(d[2], 0);
    assert_false(vkrt_devices_spec_parse("0,3", 3, "0: a\n1: b\n2: c", d, &n, &err));
    assert_string_equal(err.msg, "--devices 0,3: there is no device 3; the 3 devices:\n"
                                 "0: a\n1: b\n2: c");
    assert_false(vkrt_devices_spec_parse("all", 0, "", d, &n, &err));
    const char *bad[] = {"", "x", "0,", ",0", "0,,1", "-1", "1.5", "0 1", "1001", "al"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i)
        if (vkrt_devices_spec_check(bad[i], &err))
            fail_msg("--devices '%s' was taken", bad[i]);
    assert_true(vkrt_devices_spec_check("all", &err));
    assert_true(vkrt_devices_spec_check("0,1,0", &err));
}

static bool list_two(FILE *out, vkrt_error *err)
{
    (void)err;
    fputs("0: first (discrete GPU, Vulkan 1.3.0)\n1: second (CPU, Vulkan 1.3.0)\n", out);
    return true;
}

static bool list_fails(FILE *out, vkrt_error *err)
{
    (void)out;
    return vkrt_error_set(err, "no Vulkan driver");
}

static void listing_in_a_child(void **state)
{
    (void)state;
    char text[256];
    uint32_t count = 0;
    vkrt_error err = {{0}};
    assert_true(vkrt_device_pool_list(list_two, text, sizeof text, &count, &err));
    assert_int_equal(count, 2);
    assert_string_equal(text, "0: first (discrete GPU, Vulkan 1.3.0)\n1: second (CPU, Vulkan 1.3.0)");
    assert_false(vkrt_device_pool_list(list_fails, text, sizeof text, &count, &err));
    assert_non_null(strstr(err.msg, "no Vulkan driver"));
}

int main(void)
{
    /* A lost frame the queue never hands out again leaves the workers waiting for ever. */
    alarm(120);
    const struct CMUnitTest tests[] = {
        temp_dir_test(every_frame_once),
        temp_dir_test(killed_worker_loses_nothing),
        temp_dir_test(failed_frame_goes_to_the_others),
        temp_dir_test(worker_that_cannot_start),
        temp_dir_test(every_worker_dies),
        temp_dir_test(stop_hands_out_no_more),
        cmocka_unit_test(devices_forms),
        cmocka_unit_test(listing_in_a_child),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
