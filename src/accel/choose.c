/* choose.c: the rule behind `accel auto` (see choose.h and docs/performance.md). */
#include "choose.h"

#include <stdio.h>

/* Below this, building and walking any structure costs more than testing every triangle: a ray
 * against 64 triangles is a few hundred instructions, about one BVH traversal's overhead. */
static const uint32_t brute_force_limit = 64;

/* The grid is "even" when its fullest cell holds at most this many times the mean references of
 * the occupied cells. A grid's cost per ray grows with the triangles in the cells it crosses; a
 * cell far above the mean (a dense object inside a sparse scene) makes every ray through it slow,
 * which a BVH, adapting to the density, avoids. */
static const double uneven_ratio = 16.0;

/* Even a uniform-looking grid is slow when the mean occupied cell is crowded. */
static const double crowded_cell_refs = 8.0;

uint32_t accel_brute_force_limit(void)
{
    return brute_force_limit;
}

accel_choice accel_choose(uint32_t triangle_count, const grid *g)
{
    accel_choice c = {0};
    if (triangle_count <= brute_force_limit || !g) {
        c.kind = VKRT_ACCEL_BRUTE;
        snprintf(c.reason, sizeof c.reason, "%u triangles (at most %u): brute force", triangle_count,
                 brute_force_limit);
        return c;
    }
    double mean = g->occupied_cells ? (double)g->ref_count / g->occupied_cells : 0.0;
    double ratio = mean > 0 ? g->max_cell_refs / mean : 0.0;
    if (ratio > uneven_ratio) {
        c.kind = VKRT_ACCEL_BVH;
        snprintf(c.reason, sizeof c.reason,
                 "uneven: the fullest grid cell holds %u triangles, %.0fx the mean %.1f of occupied "
                 "cells (limit %.0fx): BVH",
                 g->max_cell_refs, ratio, mean, uneven_ratio);
    } else if (mean > crowded_cell_refs) {
        c.kind = VKRT_ACCEL_BVH;
        snprintf(c.reason, sizeof c.reason,
                 "crowded: occupied grid cells hold %.1f triangles on average (limit %.0f): BVH",
                 mean, crowded_cell_refs);
    } else {
        c.kind = VKRT_ACCEL_GRID;
        snprintf(c.reason, sizeof c.reason,
                 "even: the fullest grid cell holds %u triangles, %.1fx the mean %.1f of occupied "
                 "cells: grid",
                 g->max_cell_refs, ratio, mean);
    }
    return c;
}
