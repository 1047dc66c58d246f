/*
 * bvh_threads.h: runs one function on several threads at once and waits for all of them; the
 * BVH builder's stages (bvh.c, bvh_top.c) each run this way. Internal to the builder.
 */
#ifndef VKRT_BVH_THREADS_H
#define VKRT_BVH_THREADS_H

#include <stddef.h>
#include <stdint.h>

/* The most threads a build may use. */
enum { BVH_MAX_THREADS = 64 };

/* Threads when a caller does not say: one per online core, at most BVH_DEFAULT_MAX_THREADS. */
enum { BVH_DEFAULT_MAX_THREADS = 16 };
uint32_t bvh_threads_default(void);

/* Calls fn(args + t * arg_size) for t = 0 .. threads - 1, each on its own thread (t = 0 on the
 * caller's), and returns when all have returned. A thread that cannot start costs speed, not
 * correctness: its call runs on the caller's thread afterwards, so fn must not wait for the
 * others. threads is 1 .. BVH_MAX_THREADS. */
void bvh_threads_run(uint32_t threads, void *(*fn)(void *), void *args, size_t arg_size);

#endif
