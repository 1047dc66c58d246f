/* clock.c: monotonic milliseconds (see clock.h). */
#define _POSIX_C_SOURCE 200809L

#include "clock.h"

#include <time.h>

double vkrt_clock_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}
