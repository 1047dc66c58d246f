/* bench_timing.c: the warm-up and median of bench_timing.h. */
#include "bench_timing.h"

#include <math.h>
#include <stdlib.h>

/* Warm-up runs at least (the probe's own time may be noise) and at most (a trace of
 * microseconds would otherwise ask for hundreds of thousands). */
enum { min_warmup_runs = 2, max_warmup_runs = 4000, max_attempts = 5 };

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

bool bench_time_trace(bench_trace_fn trace, void *user, bench_times *times, vkrt_error *err)
{
    double probe;
    if (!trace(user, 1, &probe, err))
        return false;
    for (int attempt = 0;; ++attempt) {
        double runs = probe > 0 ? ceil(BENCH_WARMUP_MS / probe) : 1;
        uint32_t warmup = runs < min_warmup_runs   ? min_warmup_runs
                          : runs > max_warmup_runs ? max_warmup_runs
                                                   : (uint32_t)runs;
        double *ms = malloc((warmup + BENCH_TIMED_RUNS) * sizeof *ms);
        if (!ms)
            return vkrt_error_set(err, "out of memory");
        if (!trace(user, warmup + BENCH_TIMED_RUNS, ms, err)) {
            free(ms);
            return false;
        }
        double warmed = 0;
        for (uint32_t i = 0; i < warmup; ++i)
            warmed += ms[i];
        double *timed = ms + warmup;
        qsort(timed, BENCH_TIMED_RUNS, sizeof *timed, compare_doubles);
        *times = (bench_times){timed[BENCH_TIMED_RUNS / 2], timed[0], timed[BENCH_TIMED_RUNS - 1]};
        free(ms);
        probe = times->median_ms;
        if (warmed >= 0.9 * BENCH_WARMUP_MS || warmup == max_warmup_runs ||
            attempt + 1 == max_attempts)
            return true;
    }
}
