/*
 * test_device_pool.c: the queue and the failures of src/device_pool.c, with workers that render
 * nothing: a frame is a file the worker creates (O_EXCL, so a frame written twice fails its
 * worker). Every frame is written exactly once, by some worker; a worker killed while it holds a
 * frame (SIGKILL, as a crashing driver would end it), one whose frame fails and one that cannot
 * start each lose nothing and are reported; when every worker fails the frames left are counted;
 * a stop hands out no more frames. Workers whose files are written later on threads of their own
 * (as vkrt's write pool does) hold several frames: a kill returns all of them, and a write that
 * fails on such a thread while the worker waits for a frame fails the worker without a hang.
 * Also the --devices forms and the device listing in a child.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
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
    uint32_t stop_after; /* the parent sets the stop flag after this many frames; 0: never */
    volatile sig_atomic_t stop;
    /* Files written 30 ms after the frame, each on a thread of its own; the worker kill_worker
     * kills itself on its third frame instead of its first, fail_deferred_worker's first
     * deferred write fails. */
    bool deferred;
    int fail_deferred_worker;
    uint32_t worker; /* in a worker: its index (each process has its own copy) */
    vkrt_pool_reporter *reporter;
    uint32_t frames_taken;
    pthread_mutex_t lock; /* in a worker: guards pending */
    pthread_cond_t none_pending;
    uint32_t pending; /* deferred writes not yet done */
} fake;

static bool fake_start(void *user, uint32_t worker, int device, vkrt_pool_reporter *reporter,
                       vkrt_pool_start *started, vkrt_error *err)
{
    fake *f = user;
    f->worker = worker;
    f->reporter = reporter;
    pthread_mutex_init(&f->lock, NULL);
    pthread_cond_init(&f->none_pending, NULL);
    if ((int)worker == f->no_start_worker)
        return vkrt_error_set(err, "device %d: no such luck", device);
    snprintf(started->device_name, sizeof started->device_name, "fake %d", device);
    snprintf(started->about, sizeof started->about, "about worker %u\n", worker);
    return true;
}

/* Writes frame's file and reports it; O_EXCL, so a frame written twice fails (except after a
 * kill with deferred writes: a file written but not yet reported is rightly written again). */
static bool write_frame(fake *f, uint32_t frame, vkrt_error *err)
{
    char path[600];
    snprintf(path, sizeof path, "%s/frame%02u", f->dir, frame);
    bool again_ok = f->deferred && f->kill_worker >= 0;
    int fd = open(path, O_WRONLY | O_CREAT | (again_ok ? O_TRUNC : O_EXCL), 0644);
    if (fd < 0)
        return vkrt_error_set(err, "frame %u written twice", frame);
    close(fd);
    vkrt_pool_report_written(f->reporter, frame,
                             &(vkrt_pool_frame){.gpu_seconds = 0.001, .rays = 100});
    return true;
}

typedef struct deferred_write {
    fake *f;
    uint32_t frame;
} deferred_write;

static void *deferred_main(void *arg)
{
    deferred_write *d = arg;
    fake *f = d->f;
    nanosleep(&(struct timespec){.tv_nsec = 30 * 1000 * 1000}, NULL);
    vkrt_error err = {{0}};
    if ((int)f->worker == f->fail_deferred_worker)
        vkrt_pool_report_failed(f->reporter,
                                &(vkrt_error){"frame: cannot write: No space left on device"});
    else if (!write_frame(f, d->frame, &err))
        vkrt_pool_report_failed(f->reporter, &err);
    pthread_mutex_lock(&f->lock);
    if (--f->pending == 0)
        pthread_cond_broadcast(&f->none_pending);
    pthread_mutex_unlock(&f->lock);
    free(d);
    return NULL;
}

static bool fake_render(void *user, uint32_t frame, vkrt_error *err)
{
    fake *f = user;
    /* A frame takes a little while, as a real one does: every worker gets frames. */
    nanosleep(&(struct timespec){.tv_nsec = 5 * 1000 * 1000}, NULL);
    ++f->frames_taken;
    if (f->every_worker_dies ||
        ((int)f->worker == f->kill_worker && f->frames_taken == (f->deferred ? 3 : 1)))
        raise(SIGKILL);
    if ((int)f->worker == f->fail_worker)
        return vkrt_error_set(err, "frame %u: the device was lost", frame);
    if (!f->deferred)
        return write_frame(f, frame, err);
    deferred_write *d = malloc(sizeof *d);
    pthread_t thread;
    if (!d)
        return vkrt_error_set(err, "out of memory");
    *d = (deferred_write){.f = f, .frame = frame};
    pthread_mutex_lock(&f->lock);
    ++f->pending;
    pthread_mutex_unlock(&f->lock);
    if (pthread_create(&thread, NULL, deferred_main, d) != 0)
        return vkrt_error_set(err, "no thread");
    pthread_detach(thread);
    return true;
}

/* Waits for the deferred writes, as the write pool's finish does. */
static bool fake_finish(void *user, bool ok, vkrt_error *err)
{
    (void)err;
    fake *f = user;
    pthread_mutex_lock(&f->lock);
    while (f->pending > 0)
        pthread_cond_wait(&f->none_pending, &f->lock);
    pthread_mutex_unlock(&f->lock);
    return ok;
}

static void fake_frame_done(void *user, uint32_t frame, uint32_t done, uint32_t worker)
{
    (void)frame;
    (void)worker;
    fake *f = user;
    if (f->stop_after && done >= f->stop_after)
        f->stop = 1;
}

/* A fake whose workers all behave. */
static fake fake_default(void)
{
    return (fake){
        .kill_worker = -1, .fail_worker = -1, .no_start_worker = -1, .fail_deferred_worker = -1};
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
        .finish = fake_finish,
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

/* Every frame is on disk once and reported once. */
static void expect_every_frame(temp_dir *t, const vkrt_pool_result *r)
{
    assert_int_equal(r->rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
    assert_int_equal(frames_reported(r), frame_count);
}

static void expect_no_failure(const vkrt_pool_result *r)
{
    for (uint32_t w = 0; w < r->worker_count; ++w)
        if (r->workers[w].failed)
            fail_msg("worker %u failed: %s", w, r->workers[w].failure);
}

static void every_frame_once(void **state)
{
    temp_dir *t = *state;
    fake f = fake_default();
    vkrt_pool_result r;
    run(t, &f, &r);
    expect_every_frame(t, &r);
    expect_no_failure(&r);
    for (uint32_t w = 0; w < 3; ++w) {
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
    fake f = fake_default();
    f.kill_worker = 1;
    vkrt_pool_result r;
    run(t, &f, &r);
    const vkrt_pool_worker *k = &r.workers[1];
    assert_true(k->failed);
    assert_non_null(strstr(k->failure, "killed by signal 9"));
    assert_true(k->lost_frame);
    assert_int_equal(k->frames, 0);
    assert_true(k->lost_frame_number >= 100 && k->lost_frame_number < 100 + frame_count);
    expect_every_frame(t, &r);
    assert_false(r.workers[0].failed || r.workers[2].failed);
}

static void failed_frame_goes_to_the_others(void **state)
{
    temp_dir *t = *state;
    fake f = fake_default();
    f.fail_worker = 0;
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
    fake f = fake_default();
    f.no_start_worker = 2;
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
    fake f = fake_default();
    f.every_worker_dies = true;
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
    fake f = fake_default();
    f.stop_after = 3;
    vkrt_pool_result r;
    run(t, &f, &r);
    assert_true(r.interrupted);
    /* The frames in flight when the stop came finish: at most one a worker after the third. */
    assert_true(r.rendered >= 3 && r.rendered <= 3 + 3);
    assert_int_equal(frames_on_disk(t), r.rendered);
    for (uint32_t w = 0; w < 3; ++w)
        assert_false(r.workers[w].failed);
}

static void deferred_writes_hold_several_frames(void **state)
{
    temp_dir *t = *state;
    fake f = fake_default();
    f.deferred = true;
    vkrt_pool_result r;
    run(t, &f, &r);
    expect_every_frame(t, &r);
    expect_no_failure(&r);
    /* A worker's time runs from its start to its last file: at least one deferred write's. */
    for (uint32_t w = 0; w < 3; ++w)
        assert_true(r.workers[w].seconds >= 0.03);
}

static void killed_worker_returns_every_held_frame(void **state)
{
    temp_dir *t = *state;
    fake f = fake_default();
    f.kill_worker = 1;
    f.deferred = true;
    vkrt_pool_result r;
    run(t, &f, &r);
    const vkrt_pool_worker *k = &r.workers[1];
    assert_true(k->failed);
    assert_non_null(strstr(k->failure, "killed by signal 9"));
    /* Its third frame and the two before, whose files were not written yet 30 ms on. */
    assert_true(k->lost_frame);
    assert_int_equal(k->lost_frames + k->frames, 3);
    assert_true(k->lost_frames >= 2);
    expect_every_frame(t, &r);
}

static void deferred_failure_fails_the_worker(void **state)
{
    temp_dir *t = *state;
    fake f = fake_default();
    f.fail_deferred_worker = 2;
    f.deferred = true;
    vkrt_pool_result r;
    run(t, &f, &r); /* alarm() below catches a hang */
    const vkrt_pool_worker *k = &r.workers[2];
    assert_true(k->failed);
    assert_false(k->failed_at_end);
    assert_string_equal(k->failure, "frame: cannot write: No space left on device");
    assert_true(k->lost_frame);
    assert_int_equal(k->frames, 0);
    assert_int_equal(r.rendered, frame_count);
    assert_int_equal(frames_on_disk(t), frame_count);
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
    assert_string_equal(text,
                        "0: first (discrete GPU, Vulkan 1.3.0)\n1: second (CPU, Vulkan 1.3.0)");
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
        temp_dir_test(deferred_writes_hold_several_frames),
        temp_dir_test(killed_worker_returns_every_held_frame),
        temp_dir_test(deferred_failure_fails_the_worker),
        cmocka_unit_test(devices_forms),
        cmocka_unit_test(listing_in_a_child),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
