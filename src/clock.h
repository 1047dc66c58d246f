/*
 * clock.h: the one clock vkrt times its own work with (builds, uploads, frames).
 */
#ifndef VKRT_CLOCK_H
#define VKRT_CLOCK_H

/* Milliseconds on a monotonic clock (CLOCK_MONOTONIC) from an unspecified start: only the
 * difference of two readings means anything; it never goes back when the wall clock is set. */
double vkrt_clock_ms(void);

#endif
