/* bench_timing.c: the warm-up and median of bench_timing.h. */
#include "bench_timing.h"

#include <stdlib.h>

#include "render/tuning.h"

/* Warm-up runs at least (the probe's own time may be noise); at most VKRT_WARMUP_MAX_RUNS (a
 * trace of microseconds would otherwise ask for hundreds of thousands). */
enum { min_warmup_runs = 2, max_attempts = 5 };

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

bool bench_time_trace(bench_trace_fn trace, void *user, double warmup_ms, bench_times *times,
                      vkrt_error *err)
{
    double probe;
    if (!trace(user, 1, &probe, err))
        return false;
    for (int attempt = 0;; ++attempt) {
        uint32_t warmup = vkrt_warmup_runs(warmup_ms, probe, min_warmup_runs);
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
        if (warmed >= 0.9 * warmup_ms || warmup == VKRT_WARMUP_MAX_RUNS ||
            attempt + 1 == max_attempts)
            return true;
    }
}
