/*
 * choose.c: the rule behind `accel auto` (see choose.h; measurements in docs/performance.md).
 *
 * Measured with `vkrt bench` on lavapipe and on an H100 (bench/results/): with the current
 * kernels the uniform grid traces primary rays as fast as the BVH or faster on the bunny, Sponza,
 * Sibenik and Lost Empire, and the BVH wins by 60x to 190x on the teapot-in-a-stadium scene,
 * where a few cells hold most of the triangles. What separates them is not the fullest cell alone
 * (Sibenik has a cell of 1545 triangles and still suits the grid: few rays pass through it) but
 * how much of the scene sits in crowded cells: there the grid tests every triangle of a cell for
 * each ray that crosses it, while a BVH keeps subdividing.
 */
#include "choose.h"

#include <stdio.h>

/* Below this, building and walking any structure costs more than testing every triangle: a ray
 * against 64 triangles is a few hundred instructions, about one traversal's overhead. */
static const uint32_t brute_force_limit = 64;

/* A cell is crowded when it holds more than this many times the mean of the occupied cells. */
static const double crowded_ratio = 16.0;

/* The scene is uneven when more than this share of all references lies in crowded cells. Measured
 * shares (docs/performance.md): the stadium 0.54; Sibenik 0.11, Sponza 0.085, the bunny, the
 * teapot and Lost Empire 0. */
static const double uneven_share = 0.25;

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
    uint64_t crowded_refs = 0;
    for (uint32_t cell = 0; cell < g->cell_count; ++cell) {
        uint32_t refs = g->cell_start[cell + 1] - g->cell_start[cell];
        if (refs > crowded_ratio * mean)
            crowded_refs += refs;
    }
    double share = g->ref_count ? (double)crowded_refs / g->ref_count : 0.0;
    c.kind = share > uneven_share ? VKRT_ACCEL_BVH : VKRT_ACCEL_GRID;
    snprintf(c.reason, sizeof c.reason,
             "%s: %.1f%% of the grid's references lie in cells holding over %.0fx the mean %.1f "
             "(limit %.0f%%): %s",
             share > uneven_share ? "uneven" : "even", 100 * share, crowded_ratio, mean,
             100 * uneven_share, share > uneven_share ? "BVH" : "grid");
    return c;
}
