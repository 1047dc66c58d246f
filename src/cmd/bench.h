/*
 * bench.h: `vkrt bench`: for each scene and acceleration structure, the build time and memory,
 * and primary and shadow rays per second timed on the GPU with timestamps. A program that
 * prints numbers; nothing here decides a test.
 */
#ifndef VKRT_BENCH_H
#define VKRT_BENCH_H

#include "cli.h"

/* Runs a bench command line (its scenes, each with every structure or --accel's); returns the
 * process exit code. */
int vkrt_cmd_bench(const vkrt_command_line *cl);

#endif
