/*
 * clock.h: the one clock vkrt times its own work with (builds, uploads, frames).
 */
#ifndef VKRT_CLOCK_H
#define VKRT_CLOCK_H

/* Milliseconds on a monotonic clock (CLOCK_MONOTONIC) from an unspecified start: only the
 * difference of two readings means anything; it never goes back when the wall clock is set. */
double vkrt_clock_ms(void);

/* Milliseconds of processor time the whole process has used, all its threads together
 * (CLOCK_PROCESS_CPUTIME_ID): over a stretch of wall time, how many cores were busy. */
double vkrt_clock_cpu_ms(void);

#endif
