/*
 * bench_timing.h: how `vkrt bench` and the yardsticks it is held against time a trace on a GPU,
 * in one place so that every tracer is timed alike: a probe run sizes a warm-up worth warmup_ms
 * of device time (tuning.h: 300 ms on GPUs, none on CPU devices), then the warm-up and
 * BENCH_TIMED_RUNS runs go back to back in one submission, with GPU timestamps between them; the
 * median of the timed runs is kept, with the fastest and slowest. A probe taken while the clocks
 * were still low (after seconds of host work, such as decoding a scene's textures) undersizes the
 * warm-up, and the timed runs then catch the clocks mid-climb (a rate several times too low): so
 * the submission is repeated, sized from its own timed runs, until its warm-up itself lasted the
 * 300 ms.
 */
#ifndef VKRT_BENCH_TIMING_H
#define VKRT_BENCH_TIMING_H

#include <stdbool.h>
#include <stdint.h>

#include "error.h"
#include "render/tuning.h"

#define BENCH_TIMED_RUNS 11

/* A trace's GPU times: median, fastest and slowest of the timed runs. */
typedef struct bench_times {
    double median_ms, min_ms, max_ms;
} bench_times;

/* Runs the trace `repeats` times back to back in one submission, writing each run's GPU time
 * (repeats entries) to ms. */
typedef bool (*bench_trace_fn)(void *user, uint32_t repeats, double *ms, vkrt_error *err);

/* Times trace as above, after warmup_ms of warm-up (vkrt_tuning.warmup_ms, shared with the
 * renderer's profiles). Returns false with err set when a run fails or memory runs out. */
bool bench_time_trace(bench_trace_fn trace, void *user, double warmup_ms, bench_times *times,
                      vkrt_error *err);

#endif
