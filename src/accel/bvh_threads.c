/* bvh_threads.c: bvh_threads_run (bvh_threads.h) on POSIX threads. */
#define _POSIX_C_SOURCE 200809L

#include "bvh_threads.h"

#include <pthread.h>
#include <stdbool.h>
#include <unistd.h>

uint32_t bvh_threads_default(void)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    return cores < 1                         ? 1
           : cores > BVH_DEFAULT_MAX_THREADS ? BVH_DEFAULT_MAX_THREADS
                                             : (uint32_t)cores;
}

void bvh_threads_run(uint32_t threads, void *(*fn)(void *), void *args, size_t arg_size)
{
    pthread_t tid[BVH_MAX_THREADS];
    bool started[BVH_MAX_THREADS] = {false};
    char *base = args;
    for (uint32_t t = 1; t < threads; t++)
        started[t] = pthread_create(&tid[t], NULL, fn, base + t * arg_size) == 0;
    fn(base);
    for (uint32_t t = 1; t < threads; t++) {
        if (started[t])
            pthread_join(tid[t], NULL);
        else
            fn(base + t * arg_size);
    }
}
