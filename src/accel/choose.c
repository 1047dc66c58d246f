/*
 * choose.c: the rule behind `accel auto` (see choose.h).
 *
 * The rule is a pure function of the triangle count, the kind of device and, on a CPU device
 * reading storage buffers, the grid's occupancy: the same scene on the same kind of device always
 * gets the same structure, and no clock is read. Each branch takes the structure that traced
 * fastest on that kind of device in `vkrt bench`'s measurements (docs/performance.md,
 * docs/kdtree.md): brute force where a structure cannot pay for itself (a CPU device and a handful
 * of triangles; never on a GPU), the kd-tree on CPU devices reading texel buffers up to the size
 * where its mostly serial build outweighs its faster walks, the grid on CPU devices reading
 * storage buffers unless much of the scene sits in a few crowded cells (where the grid tests every
 * triangle of a cell for each ray crossing it while a BVH keeps subdividing), and the BVH
 * everywhere else. On a GPU the kd-tree, which clips triangles to its cells, is built as well
 * only when the BVH's SAH cost is far above the norm for its triangle count (overlapping boxes of
 * long thin triangles), and taken only when its own SAH cost is well below the BVH's.
 */
#include "choose.h"

#include <math.h>
#include <stdio.h>

/* On a CPU device, below this, building and walking any structure costs about what testing
 * every triangle does: a ray against 64 triangles is a few hundred instructions, about one
 * traversal's overhead. Not on GPUs, where the BVH outran brute force even on a box of 30
 * triangles: there even a handful of triangles gets the BVH. */
static const uint32_t brute_force_limit = 64;

/* Up to this many triangles a CPU device reading texel buffers gets the kd-tree (above). */
static const uint32_t kdtree_limit = 250000;

/* On a GPU, the kd-tree is built as well when the BVH's SAH cost per doubling of the triangle
 * count is above this (above) and the scene within kdtree_limit (its build runs mostly on one
 * core). */
static const double bvh_cost_per_doubling_limit = 3.5;

/* ... and taken when its SAH cost is below this share of the BVH's. */
static const double kdtree_cost_share = 0.5;

/* A cell is crowded when it holds more than this many times the mean of the occupied cells. */
static const double crowded_ratio = 16.0;

/* The scene is uneven when more than this share of all references lies in crowded cells: well
 * above the evenly filled scenes' shares and well below the teapot in a stadium's. */
static const double uneven_share = 0.25;

uint32_t accel_brute_force_limit(void)
{
    return brute_force_limit;
}

uint32_t accel_kdtree_limit(void)
{
    return kdtree_limit;
}

bool accel_kdtree_worth_trying(uint32_t triangle_count, float bvh_sah_cost)
{
    if (triangle_count > kdtree_limit || triangle_count <= brute_force_limit)
        return false;
    return bvh_sah_cost > bvh_cost_per_doubling_limit * log2((double)triangle_count);
}

bool accel_kdtree_wins(float kdtree_sah_cost, float bvh_sah_cost)
{
    return kdtree_sah_cost < kdtree_cost_share * bvh_sah_cost;
}

double accel_kdtree_cost_share(void)
{
    return kdtree_cost_share;
}

bool accel_choice_needs_grid(uint32_t triangle_count, accel_device device)
{
    return device == ACCEL_DEVICE_CPU_STORAGE && triangle_count > brute_force_limit;
}

accel_choice accel_choose(uint32_t triangle_count, accel_device device, const grid *g)
{
    accel_choice c = {0};
    if (triangle_count == 0 || (device != ACCEL_DEVICE_GPU && triangle_count <= brute_force_limit)) {
        c.kind = VKRT_ACCEL_BRUTE;
        snprintf(c.reason, sizeof c.reason, "%u triangles (at most %u, on a CPU device): brute force",
                 triangle_count, brute_force_limit);
        return c;
    }
    if (device == ACCEL_DEVICE_CPU_TEXELS && triangle_count <= kdtree_limit) {
        c.kind = VKRT_ACCEL_KDTREE;
        snprintf(c.reason, sizeof c.reason,
                 "%u triangles (at most %u) on a CPU device reading texel buffers: kd-tree (it "
                 "outran the BVH there on every scene measured but the bunny)",
                 triangle_count, kdtree_limit);
        return c;
    }
    if (device != ACCEL_DEVICE_CPU_STORAGE || !g) {
        c.kind = VKRT_ACCEL_BVH;
        snprintf(c.reason, sizeof c.reason,
                 "%u triangles: BVH (it outran the grid on every scene measured, on GPUs and on "
                 "CPU devices with texel loads, and the kd-tree on every public scene)",
                 triangle_count);
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
    bool uneven = share > uneven_share;
    c.kind = uneven ? VKRT_ACCEL_BVH : VKRT_ACCEL_GRID;
    snprintf(c.reason, sizeof c.reason,
             "%s: %.1f%% of the grid's references lie in cells holding over %.0fx the mean %.1f "
             "(limit %.0f%%), on a CPU device: %s",
             uneven ? "uneven" : "even", 100 * share, crowded_ratio, mean, 100 * uneven_share,
             uneven ? "BVH" : "grid");
    return c;
}
