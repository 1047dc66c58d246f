/*
 * write_pool.c: writer threads fed from a bounded queue of frame buffers (write_pool.h).
 *
 * Every buffer lives in a slot, which is in exactly one place at a time: free, held by the
 * render loop, queued, or being written. One mutex guards those places and one condition
 * variable says that any of them changed; the callbacks run under a second mutex of their own,
 * so a slow callback (a progress line, a pipe) never holds up the render loop's calls.
 */
#define _GNU_SOURCE /* sched_getaffinity: the cores this process may run on */
#include "write_pool.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_write.h"

/* The writer threads a process uses at most by default: turning a frame into PNG bytes takes one
 * core about as long as a fast GPU takes to render it (docs/architecture.md, "Writing frames"),
 * so 1-2 threads keep up; 4 leave room and bound the memory at 6 frames. */
enum { DEFAULT_MAX_THREADS = 4 };

/* Frames in flight besides those being written: the one being rendered and one waiting. */
enum { EXTRA_BUFFERS = 2 };

/* The AOVs a slot may hold, in VKRT_AOV_* bit order, and their floats a pixel. */
enum { AOV_KINDS = 4 };
static const uint32_t aov_floats[AOV_KINDS] = {3, 3, 1, 3};

typedef struct slot {
    float *rgb;
    float *aovs[AOV_KINDS]; /* albedo, normal, depth, position: those of desc.aovs, else NULL */
    vkrt_written_frame frame;
    char path[4096];
} slot;

struct vkrt_write_pool {
    vkrt_write_pool_desc desc;
    pthread_mutex_t lock;
    pthread_cond_t changed;
    pthread_mutex_t report_lock; /* serialises the callbacks */
    pthread_t threads[VKRT_WRITE_POOL_MAX_THREADS];
    uint32_t thread_count; /* started */
    slot *slots;
    uint32_t slot_count;
    uint32_t *free_slots; /* a stack of slot_count */
    uint32_t free_count;
    uint32_t *queue; /* a ring of slot_count */
    uint32_t queue_head, queue_count;
    int held;         /* the slot the render loop holds, -1 if none */
    uint32_t writing; /* slots being written */
    bool failed, stopping;
    vkrt_error failure;
};

bool vkrt_write_pool_threads(uint32_t sharers, uint32_t *threads, vkrt_error *err)
{
    const char *env = getenv("VKRT_WRITE_THREADS");
    if (env && *env) {
        char *end;
        errno = 0;
        unsigned long n = strtoul(env, &end, 10);
        if (errno || *end || *env < '0' || *env > '9' || n > VKRT_WRITE_POOL_MAX_THREADS)
            return vkrt_error_set(err,
                                  "VKRT_WRITE_THREADS=%s: give the number of writer "
                                  "threads, 0 to %d",
                                  env, VKRT_WRITE_POOL_MAX_THREADS);
        *threads = (uint32_t)n;
        return true;
    }
    /* The cores the process may use, not the machine's: a Slurm task or a taskset gets fewer. */
    cpu_set_t allowed;
    long cores = sched_getaffinity(0, sizeof allowed, &allowed) == 0
                     ? CPU_COUNT(&allowed)
                     : sysconf(_SC_NPROCESSORS_ONLN);
    long per_process = cores > 0 ? cores / (sharers ? sharers : 1) : 1;
    long n = per_process - 1;
    *threads = n < 1 ? 1 : n > DEFAULT_MAX_THREADS ? DEFAULT_MAX_THREADS : (uint32_t)n;
    return true;
}

/* Writes one slot's frame and reports it; returns whether the file was written. */
static bool write_slot(vkrt_write_pool *pool, slot *s, vkrt_error *err)
{
    const vkrt_write_pool_desc *d = &pool->desc;
    const float *written[AOV_KINDS];
    for (int k = 0; k < AOV_KINDS; ++k)
        written[k] = d->aovs_written & (1u << k) ? s->aovs[k] : NULL;
    vkrt_frame_image image = {.width = d->width, .height = d->height, .rgb = s->rgb,
                              .albedo = written[0], .normal = written[1], .depth = written[2],
                              .position = written[3], .guide_albedo = s->aovs[0],
                              .guide_normal = s->aovs[1]};
    bool ok = vkrt_image_write_layers(s->path, &image, &d->finish, err);
    if (ok && d->written) {
        pthread_mutex_lock(&pool->report_lock);
        d->written(d->user, &s->frame);
        pthread_mutex_unlock(&pool->report_lock);
    }
    return ok;
}

/* Records a failure (the first is kept) and tells the callback of the first. Called with
 * pool->lock held; unlocks it around the callback. */
static void record_failure(vkrt_write_pool *pool, const vkrt_error *err)
{
    if (pool->failed)
        return;
    pool->failed = true;
    pool->failure = *err;
    if (pool->desc.failed) {
        pthread_mutex_unlock(&pool->lock);
        pthread_mutex_lock(&pool->report_lock);
        pool->desc.failed(pool->desc.user, err);
        pthread_mutex_unlock(&pool->report_lock);
        pthread_mutex_lock(&pool->lock);
    }
}

static void *writer_main(void *arg)
{
    vkrt_write_pool *pool = arg;
    pthread_mutex_lock(&pool->lock);
    for (;;) {
        while (pool->queue_count == 0 && !pool->stopping)
            pthread_cond_wait(&pool->changed, &pool->lock);
        if (pool->queue_count == 0)
            break; /* stopping, and nothing left to write */
        uint32_t index = pool->queue[pool->queue_head];
        pool->queue_head = (pool->queue_head + 1) % pool->slot_count;
        --pool->queue_count;
        /* After a failure the run is over: queued frames are dropped, not written. */
        bool skip = pool->failed;
        ++pool->writing;
        pthread_mutex_unlock(&pool->lock);
        vkrt_error err = {{0}};
        bool ok = skip || write_slot(pool, &pool->slots[index], &err);
        pthread_mutex_lock(&pool->lock);
        if (!ok)
            record_failure(pool, &err);
        --pool->writing;
        pool->free_slots[pool->free_count++] = index;
        pthread_cond_broadcast(&pool->changed);
    }
    pthread_mutex_unlock(&pool->lock);
    return NULL;
}

/* Starts the writer threads with SIGINT and SIGTERM blocked (they inherit the mask), so a
 * Ctrl-C reaches the render loop's thread, which decides. */
static bool start_threads(vkrt_write_pool *pool, vkrt_error *err)
{
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &block, &old);
    int rc = 0;
    while (pool->thread_count < pool->desc.threads &&
           (rc = pthread_create(&pool->threads[pool->thread_count], NULL, writer_main, pool)) == 0)
        ++pool->thread_count;
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc != 0)
        return vkrt_error_set(err, "cannot start a thread to write images: %s", strerror(rc));
    return true;
}

bool vkrt_write_pool_create(vkrt_write_pool **out, const vkrt_write_pool_desc *desc,
                            vkrt_error *err)
{
    *out = NULL;
    if (desc->threads > VKRT_WRITE_POOL_MAX_THREADS)
        return vkrt_error_set(err, "%u writer threads: at most %d", desc->threads,
                              VKRT_WRITE_POOL_MAX_THREADS);
    vkrt_write_pool *pool = calloc(1, sizeof *pool);
    if (!pool)
        return vkrt_error_set(err, "out of memory");
    pthread_mutex_init(&pool->lock, NULL);
    pthread_cond_init(&pool->changed, NULL);
    pthread_mutex_init(&pool->report_lock, NULL);
    pool->desc = *desc;
    pool->held = -1;
    pool->slot_count = desc->threads ? desc->threads + EXTRA_BUFFERS : 1;
    pool->slots = calloc(pool->slot_count, sizeof *pool->slots);
    pool->free_slots = calloc(pool->slot_count, sizeof *pool->free_slots);
    pool->queue = calloc(pool->slot_count, sizeof *pool->queue);
    bool ok = pool->slots && pool->free_slots && pool->queue;
    size_t values = (size_t)desc->width * desc->height * 3;
    size_t pixels = (size_t)desc->width * desc->height;
    for (uint32_t i = 0; ok && i < pool->slot_count; ++i) {
        ok = (pool->slots[i].rgb = malloc(values * sizeof(float))) != NULL;
        for (uint32_t k = 0; ok && k < AOV_KINDS; ++k)
            if (desc->aovs & (1u << k))
                ok = (pool->slots[i].aovs[k] = malloc(pixels * aov_floats[k] * sizeof(float))) != NULL;
        pool->free_slots[pool->free_count++] = pool->slot_count - 1 - i;
    }
    if (!ok) {
        vkrt_write_pool_destroy(pool);
        return vkrt_error_set(err, "out of memory for %u frames of %ux%u to write",
                              desc->threads + EXTRA_BUFFERS, desc->width, desc->height);
    }
    if (!start_threads(pool, err)) {
        vkrt_write_pool_destroy(pool);
        return false;
    }
    *out = pool;
    return true;
}

float *vkrt_write_pool_buffer(vkrt_write_pool *pool, vkrt_error *err)
{
    pthread_mutex_lock(&pool->lock);
    while (pool->held < 0 && pool->free_count == 0 && !pool->failed)
        pthread_cond_wait(&pool->changed, &pool->lock);
    float *rgb = NULL;
    if (pool->failed)
        *err = pool->failure;
    else {
        if (pool->held < 0)
            pool->held = (int)pool->free_slots[--pool->free_count];
        rgb = pool->slots[pool->held].rgb;
    }
    pthread_mutex_unlock(&pool->lock);
    return rgb;
}

void vkrt_write_pool_aovs(vkrt_write_pool *pool, float *aovs[4])
{
    pthread_mutex_lock(&pool->lock);
    for (uint32_t k = 0; k < AOV_KINDS; ++k)
        aovs[k] = pool->held >= 0 ? pool->slots[pool->held].aovs[k] : NULL;
    pthread_mutex_unlock(&pool->lock);
}

bool vkrt_write_pool_submit(vkrt_write_pool *pool, const vkrt_written_frame *frame, vkrt_error *err)
{
    pthread_mutex_lock(&pool->lock);
    bool ok = false;
    if (pool->failed)
        *err = pool->failure;
    else if (pool->held < 0)
        vkrt_error_set(err, "%s: no buffer was taken for the frame", frame->path);
    else if (strlen(frame->path) >= sizeof pool->slots[0].path)
        vkrt_error_set(err, "%s: path too long", frame->path);
    else
        ok = true;
    if (!ok) {
        pthread_mutex_unlock(&pool->lock);
        return false;
    }
    uint32_t index = (uint32_t)pool->held;
    pool->held = -1;
    slot *s = &pool->slots[index];
    s->frame = *frame;
    snprintf(s->path, sizeof s->path, "%s", frame->path);
    s->frame.path = s->path;
    if (pool->thread_count == 0) {
        /* No threads: written here, now, as one frame at a time always was. */
        pthread_mutex_unlock(&pool->lock);
        ok = write_slot(pool, s, err);
        pthread_mutex_lock(&pool->lock);
        if (!ok)
            record_failure(pool, err);
        pool->free_slots[pool->free_count++] = index;
    } else {
        pool->queue[(pool->queue_head + pool->queue_count++) % pool->slot_count] = index;
        pthread_cond_broadcast(&pool->changed);
    }
    pthread_mutex_unlock(&pool->lock);
    return ok;
}

bool vkrt_write_pool_finish(vkrt_write_pool *pool, vkrt_error *err)
{
    pthread_mutex_lock(&pool->lock);
    while ((pool->queue_count > 0 || pool->writing > 0) && pool->thread_count > 0)
        pthread_cond_wait(&pool->changed, &pool->lock);
    bool ok = !pool->failed;
    if (!ok)
        *err = pool->failure;
    pthread_mutex_unlock(&pool->lock);
    return ok;
}

void vkrt_write_pool_destroy(vkrt_write_pool *pool)
{
    if (!pool)
        return;
    if (pool->thread_count > 0) {
        pthread_mutex_lock(&pool->lock);
        pool->stopping = true;
        pthread_cond_broadcast(&pool->changed);
        pthread_mutex_unlock(&pool->lock);
        for (uint32_t i = 0; i < pool->thread_count; ++i)
            pthread_join(pool->threads[i], NULL);
    }
    pthread_mutex_destroy(&pool->report_lock);
    pthread_cond_destroy(&pool->changed);
    pthread_mutex_destroy(&pool->lock);
    for (uint32_t i = 0; pool->slots && i < pool->slot_count; ++i) {
        free(pool->slots[i].rgb);
        for (uint32_t k = 0; k < AOV_KINDS; ++k)
            free(pool->slots[i].aovs[k]);
    }
    free(pool->slots);
    free(pool->free_slots);
    free(pool->queue);
    free(pool);
}
