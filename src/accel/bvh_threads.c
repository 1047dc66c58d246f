/* bvh_threads.c: bvh_threads_run (bvh_threads.h) on POSIX threads. */
#include "bvh_threads.h"

#include <pthread.h>
#include <stdbool.h>

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
