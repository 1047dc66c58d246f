/* clock.c: monotonic milliseconds (see clock.h). */
#define _POSIX_C_SOURCE 200809L

#include "clock.h"

#include <time.h>

static double clock_read_ms(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

double vkrt_clock_ms(void)
{
    return clock_read_ms(CLOCK_MONOTONIC);
}

double vkrt_clock_cpu_ms(void)
{
    return clock_read_ms(CLOCK_PROCESS_CPUTIME_ID);
}
