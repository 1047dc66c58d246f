/*
 * test_write_pool.c: src/output/write_pool.c without a GPU. Frames of known pixels go through
 * pools of 0 to 4 threads: every file is written once, with the bytes vkrt_image_write gives the
 * same pixels on this thread (the one-frame-at-a-time path), the written callback hears of each
 * once, and the buffers in flight never pass threads + 2. A frame whose folder is a file fails:
 * the failed callback hears once, the next buffer() says which file, later frames are dropped
 * and no temporary file is left.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "output/image_write.h"
#include "output/write_pool.h"
#include "temp_dir.h"

enum { W = 37, H = 23, FRAMES = 12 };

/* What the callbacks saw; they never run at once (the pool's promise), so no lock here. */
typedef struct seen {
    uint32_t written[FRAMES];
    uint32_t failures;
    char failure[1024];
} seen;

static void on_written(void *user, const vkrt_written_frame *frame)
{
    seen *s = user;
    assert_true(frame->frame < FRAMES);
    assert_int_equal(frame->rays, 1000 + frame->frame); /* passed through */
    ++s->written[frame->frame];
}

static void on_failed(void *user, const vkrt_error *err)
{
    seen *s = user;
    ++s->failures;
    snprintf(s->failure, sizeof s->failure, "%s", err->msg);
}

/* Frame f's pixels: a ramp that differs from frame to frame. */
static void fill(float *rgb, uint32_t f)
{
    for (size_t i = 0; i < (size_t)W * H * 3; ++i)
        rgb[i] = (float)((i * 7 + f * 131) % 997) / 700.0f;
}

static char *read_file(const char *path, size_t *size)
{
    FILE *file = fopen(path, "rb");
    assert_non_null(file);
    fseek(file, 0, SEEK_END);
    *size = (size_t)ftell(file);
    rewind(file);
    char *data = malloc(*size + 1);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, *size, file), *size);
    fclose(file);
    return data;
}

static void same_file(const char *a, const char *b)
{
    size_t na, nb;
    char *da = read_file(a, &na), *db = read_file(b, &nb);
    if (na != nb || memcmp(da, db, na) != 0)
        fail_msg("%s and %s differ", a, b);
    free(da);
    free(db);
}

static uint32_t temporaries_in(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    uint32_t n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

static vkrt_write_pool *make_pool(uint32_t threads, seen *s)
{
    vkrt_write_pool_desc desc = {.threads = threads,
                                 .width = W,
                                 .height = H,
                                 .finish = {.exposure = 0.5f},
                                 .written = on_written,
                                 .failed = on_failed,
                                 .user = s};
    vkrt_write_pool *pool = NULL;
    vkrt_error err = {{0}};
    if (!vkrt_write_pool_create(&pool, &desc, &err))
        fail_msg("%s", err.msg);
    return pool;
}

static void every_frame_written_as_on_one_thread(void **state)
{
    temp_dir *t = *state;
    float *reference = malloc((size_t)W * H * 3 * sizeof *reference);
    assert_non_null(reference);
    vkrt_error err = {{0}};
    char path[600], expected[600];
    for (uint32_t f = 0; f < FRAMES; ++f) {
        snprintf(path, sizeof path, "%s/one%02u.png", t->dir, f);
        fill(reference, f);
        assert_true(vkrt_image_write(path, W, H, reference, 0.5f, &err));
    }
    for (uint32_t threads = 0; threads <= 4; ++threads) {
        seen s = {0};
        vkrt_write_pool *pool = make_pool(threads, &s);
        float *buffers[FRAMES];
        for (uint32_t f = 0; f < FRAMES; ++f) {
            float *rgb = vkrt_write_pool_buffer(pool, &err);
            assert_non_null(rgb);
            assert_ptr_equal(vkrt_write_pool_buffer(pool, &err), rgb); /* held until submitted */
            buffers[f] = rgb;
            fill(rgb, f);
            snprintf(path, sizeof path, "%s/t%u-%02u.png", t->dir, threads, f);
            vkrt_written_frame frame = {.frame = f, .path = path, .rays = 1000 + f};
            assert_true(vkrt_write_pool_submit(pool, &frame, &err));
        }
        assert_true(vkrt_write_pool_finish(pool, &err));
        /* Frames in flight: at most threads + 2 different buffers (1 without threads). */
        uint32_t distinct = 0;
        for (uint32_t f = 0; f < FRAMES; ++f) {
            uint32_t g = 0;
            while (g < f && buffers[g] != buffers[f])
                ++g;
            distinct += g == f;
        }
        assert_true(distinct <= (threads ? threads + 2 : 1));
        for (uint32_t f = 0; f < FRAMES; ++f) {
            assert_int_equal(s.written[f], 1);
            snprintf(path, sizeof path, "%s/t%u-%02u.png", t->dir, threads, f);
            snprintf(expected, sizeof expected, "%s/one%02u.png", t->dir, f);
            same_file(path, expected);
        }
        assert_int_equal(s.failures, 0);
        vkrt_write_pool_destroy(pool);
    }
    assert_int_equal(temporaries_in(t->dir), 0);
    free(reference);
}

static void a_failed_write_stops_the_pool(void **state)
{
    temp_dir *t = *state;
    /* Frame 3's folder is a file: its write fails (ENOTDIR). */
    char path[600];
    for (uint32_t f = 0; f < FRAMES; ++f) {
        snprintf(path, sizeof path, "%s/d%u", t->dir, f);
        FILE *file = f == 3 ? fopen(path, "w") : NULL;
        if (file)
            fclose(file);
        else
            assert_int_equal(mkdir(path, 0777), 0);
    }
    for (uint32_t threads = 0; threads <= 3; threads += 3) {
        seen s = {0};
        vkrt_write_pool *pool = make_pool(threads, &s);
        vkrt_error err = {{0}};
        bool ok = true;
        uint32_t f = 0;
        for (; ok && f < FRAMES; ++f) {
            float *rgb = vkrt_write_pool_buffer(pool, &err);
            if (!rgb)
                break;
            fill(rgb, f);
            snprintf(path, sizeof path, "%s/d%u/t%u.png", t->dir, f, threads);
            vkrt_written_frame frame = {.frame = f, .path = path, .rays = 1000 + f};
            ok = vkrt_write_pool_submit(pool, &frame, &err);
        }
        if (ok) /* the loop ran out of frames before it heard: finish says it */
            assert_false(vkrt_write_pool_finish(pool, &err));
        snprintf(path, sizeof path, "%s/d3/t%u.png: cannot write: Not a directory", t->dir,
                 threads);
        assert_string_equal(err.msg, path);
        assert_int_equal(s.failures, 1);
        assert_string_equal(s.failure, path);
        assert_int_equal(s.written[3], 0);
        /* The frames before were written; with threads, at most threads + 2 after it were in
         * flight when it failed, and those not yet started are dropped. */
        for (uint32_t g = 0; g < 3; ++g)
            assert_int_equal(s.written[g], 1);
        if (threads == 0)
            assert_int_equal(f, 4); /* stopped right at the frame that failed */
        vkrt_write_pool_destroy(pool);
        for (uint32_t g = 0; g < FRAMES; ++g) {
            snprintf(path, sizeof path, "%s/d%u", t->dir, g);
            if (g != 3)
                assert_int_equal(temporaries_in(path), 0);
        }
    }
}

static void threads_from_the_environment(void **state)
{
    (void)state;
    uint32_t threads = 99;
    vkrt_error err = {{0}};
    setenv("VKRT_WRITE_THREADS", "3", 1);
    assert_true(vkrt_write_pool_threads(1, &threads, &err));
    assert_int_equal(threads, 3);
    static const char *const bad[] = {"many", "-1", "17", "2x", " 2"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        setenv("VKRT_WRITE_THREADS", bad[i], 1);
        assert_false(vkrt_write_pool_threads(1, &threads, &err));
        assert_non_null(strstr(err.msg, "give the number of writer threads, 0 to 16"));
    }
    unsetenv("VKRT_WRITE_THREADS");
    assert_true(vkrt_write_pool_threads(1, &threads, &err));
    assert_true(threads >= 1 && threads <= 4);
    assert_true(vkrt_write_pool_threads(1000, &threads, &err));
    assert_int_equal(threads, 1); /* many sharers: still one */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(every_frame_written_as_on_one_thread),
        temp_dir_test(a_failed_write_stops_the_pool),
        cmocka_unit_test(threads_from_the_environment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
