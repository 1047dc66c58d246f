/*
 * profile.c: GPU timestamps of a frame's dispatches and their medians (see profile.h).
 */
#include "profile.h"

#include <stdlib.h>
#include <string.h>

bool profile_recorder_create(gpu_context *ctx, profile_recorder *p, uint32_t marks,
                             uint32_t frames, vkrt_error *err)
{
    memset(p, 0, sizeof *p);
    p->marks = calloc(marks, sizeof *p->marks);
    p->frame_end = calloc(frames, sizeof *p->frame_end);
    p->capacity = marks;
    if (!p->marks || !p->frame_end) {
        profile_recorder_destroy(ctx, p);
        return vkrt_error_set(err, "out of memory for a profile");
    }
    if (!gpu_timer_create(ctx, &p->timer, marks + 1, err)) {
        profile_recorder_destroy(ctx, p);
        return false;
    }
    return true;
}

void profile_recorder_destroy(gpu_context *ctx, profile_recorder *p)
{
    gpu_timer_destroy(ctx, &p->timer);
    free(p->marks);
    free(p->frame_end);
    memset(p, 0, sizeof *p);
}

void profile_recorder_begin(VkCommandBuffer cmd, profile_recorder *p)
{
    gpu_timer_reset(cmd, &p->timer);
    gpu_timer_write(cmd, &p->timer, 0);
}

void profile_recorder_mark(VkCommandBuffer cmd, profile_recorder *p, uint32_t depth,
                           uint32_t kernel)
{
    if (!p)
        return;
    /* Past the room the query pool has, a timestamp would be written out of bounds (on some
     * devices, a hung device): the read below reports it instead. */
    if (p->count >= p->capacity) {
        p->overflow = true;
        return;
    }
    p->marks[p->count] = (profile_mark){
        p->frame, (uint8_t)(depth < VKRT_PROFILE_DEPTHS ? depth : VKRT_PROFILE_DEPTHS - 1),
        (uint8_t)kernel};
    gpu_timer_write(cmd, &p->timer, ++p->count);
}

void profile_recorder_end_frame(profile_recorder *p)
{
    p->frame_end[p->frame++] = p->count;
}

static int compare_ms(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of n values (sorted in place): the middle one, or the mean of the middle two. */
static double median_ms(double *values, uint32_t n)
{
    qsort(values, n, sizeof *values, compare_ms);
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

bool profile_recorder_read(gpu_context *ctx, profile_recorder *p, vkrt_frame_profile *out,
                           vkrt_error *err)
{
    uint32_t frames = p->frame;
    size_t cells = (size_t)VKRT_PROFILE_DEPTHS * VKRT_KERNEL_KINDS;
    double *per_frame = calloc(cells * frames, sizeof *per_frame);
    double *values = calloc(frames, sizeof *values);
    bool ok = per_frame && values;
    if (!ok)
        vkrt_error_set(err, "out of memory for a profile");
    if (ok && p->overflow)
        ok = vkrt_error_set(err, "profile: more dispatches than the %u timestamps made room for",
                            p->capacity);
    memset(out->kernel_ms, 0, sizeof out->kernel_ms);
    for (uint32_t i = 0; ok && i < p->count; ++i) {
        double ms;
        if (!(ok = gpu_timer_ms(ctx, &p->timer, i, i + 1, &ms, err)))
            break;
        const profile_mark *m = &p->marks[i];
        per_frame[m->frame * cells + (size_t)m->depth * VKRT_KERNEL_KINDS + m->kernel] += ms;
    }
    for (size_t c = 0; ok && c < cells; ++c) {
        for (uint32_t f = 0; f < frames; ++f)
            values[f] = per_frame[f * cells + c];
        out->kernel_ms[c / VKRT_KERNEL_KINDS][c % VKRT_KERNEL_KINDS] = median_ms(values, frames);
    }
    for (uint32_t f = 0; ok && f < frames; ++f)
        ok = gpu_timer_ms(ctx, &p->timer, f ? p->frame_end[f - 1] : 0, p->frame_end[f],
                          &values[f], err);
    if (ok) {
        out->frame_ms = median_ms(values, frames);
        out->profiled = true;
        out->frames = frames;
    }
    free(per_frame);
    free(values);
    return ok;
}

void vkrt_frame_profile_print(FILE *out, const vkrt_frame_profile *p)
{
    static const char *const names[VKRT_KERNEL_KINDS] = {"raygen", "trace",   "order", "light",
                                                          "count",  "prepare", "shade"};
    fprintf(out, "vkrt: profile (GPU ms, summed over sample passes; median of %u frame%s back to "
                 "back after %u warm-up frame%s)\n  depth",
            p->frames, p->frames == 1 ? "" : "s", p->warmups, p->warmups == 1 ? "" : "s");
    for (int k = 0; k < VKRT_KERNEL_KINDS; ++k)
        fprintf(out, " %9s", names[k]);
    fprintf(out, "\n");
    double total[VKRT_KERNEL_KINDS] = {0};
    for (int d = 0; d < VKRT_PROFILE_DEPTHS; ++d) {
        double row = 0;
        for (int k = 0; k < VKRT_KERNEL_KINDS; ++k)
            row += p->kernel_ms[d][k];
        if (row == 0)
            continue;
        fprintf(out, "  %5d", d);
        for (int k = 0; k < VKRT_KERNEL_KINDS; ++k) {
            fprintf(out, " %9.3f", p->kernel_ms[d][k]);
            total[k] += p->kernel_ms[d][k];
        }
        fprintf(out, "\n");
    }
    double sum = 0;
    fprintf(out, "  total");
    for (int k = 0; k < VKRT_KERNEL_KINDS; ++k) {
        fprintf(out, " %9.3f", total[k]);
        sum += total[k];
    }
    /* The light kernel is mostly its shadow rays' traversal. */
    double tracing = total[VKRT_KERNEL_TRACE] + total[VKRT_KERNEL_LIGHT];
    fprintf(out, "\n  frame %.3f ms (kernels %.3f); trace + light %.3f ms: the frame costs %.2fx "
                 "its tracing (frame / (trace + light))\n",
            p->frame_ms, sum, tracing, tracing > 0 ? p->frame_ms / tracing : 0.0);
}
