/*
 * bench.h: `vkrt bench`: for each scene and acceleration structure, the build time and memory,
 * and primary and shadow rays per second timed on the GPU with timestamps. A program that
 * prints numbers; nothing here decides a test.
 */
#ifndef VKRT_BENCH_H
#define VKRT_BENCH_H

#include <stdio.h>

#include "cli.h"

/* Runs the benchmark the options describe; returns the process exit code. */
int vkrt_bench_run(const vkrt_bench_options *opts);

#endif
