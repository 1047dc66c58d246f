/*
 * choose.c: the rule behind `accel auto` (see choose.h; measurements in research/journal.md and
 * research/results/).
 *
 * Measured with `vkrt bench`: on the H100 the BVH traced primary and shadow rays 1.2 to 2.1 times
 * faster than the grid on the bunny, Sponza, Sibenik, Lost Empire and the teapot, and 190 times
 * faster on the teapot-in-a-stadium scene. On lavapipe, per primary-plus-shadow ray, the two
 * were within 3% of each other on the bunny, Sponza and Lost Empire, the BVH 14% ahead on
 * Sibenik and the grid 29% on the teapot; the grid built two to three times faster, and the BVH
 * was again about 100 times faster in the stadium. Those lavapipe figures are of traversal reading
 * storage buffers; reading triangles and nodes through texel buffers (vkrt_loads, lavapipe's
 * default since) made the BVH 1.5 to 3.9 times faster than the grid on every scene in that
 * session's measurement, so the grid is weighed only on a CPU device that reads storage buffers
 * (on texel loads the kd-tree is taken instead, below; a quiet 2026-12-02 table,
 * research/results/kdtree-lavapipe-quiet/, has the grid level with the BVH on some scenes and
 * behind the kd-tree on all but the smallest). What separates the
 * stadium is how much of the scene sits in crowded cells: there the grid tests every triangle of
 * a cell for each ray that crosses it, while a BVH keeps subdividing.
 *
 * On GPUs the kd-tree (accel kdtree, docs/kdtree.md) lost to the BVH on every public scene at
 * 1080p on the H200 (research/results/h200-1203/kd: 0.41-0.94x its rays per second, every scene
 * and kind of ray of bunny, Sponza, Sibenik, Lost Empire, CornellBox-Original, the teapot and the
 * Mori knob) and builds 1.2 to 4 times slower, so it is built only where the BVH's own SAH cost
 * says the BVH is bad: the slivers (tools/sliver_cylinder.py, 96k long thin triangles), whose
 * overlapping boxes gave a BVH of SAH cost 95.0, 5.7 per doubling of the triangle count, where
 * the public scenes' trees cost 0.3 to 2.1 per doubling (10.1 M triangles of tiled Lost Empire:
 * 2.6). There the kd-tree, which clips triangles to its cells, cost 26.0 and traced 3.1 to 3.8
 * times the BVH's rays (3.0 to 6.2 times the driver's ray tracing pipeline, where the BVH was at
 * 0.99 to 1.65). The kd-tree's SAH cost was 1.6 to 2.7 times the BVH's on the public scenes and
 * 0.27 times on the slivers; it is taken when below half.
 * On lavapipe reading texel buffers (its default) the
 * kd-tree mostly wins: at 480x270 on a quiet machine (research/results/kdtree-lavapipe-quiet/) the kd-tree
 * traced 1.1 to 2.4 times the BVH's rays per second in 25 of the 27 scene and ray kinds of the
 * nine scenes measured (Cornell boxes, teapot, bunny, Sponza, Sibenik, Lost Empire, the teapot
 * in a stadium; the bunny's shadow and diffuse rays 0.83-0.85x, and 1.57x and 0.95x in a second
 * round). Its build is the price: the bunny's 499 ms against 78, Lost Empire's (225k triangles)
 * 228 against 173, and it runs mostly on one core; past kdtree_limit, the largest scene measured,
 * the BVH's parallel build is taken instead.
 */
#include "choose.h"

#include <math.h>
#include <stdio.h>

/* On a CPU device, below this, building and walking any structure costs about what testing
 * every triangle does: a ray against 64 triangles is a few hundred instructions, about one
 * traversal's overhead (lavapipe's whole frames of the 36-triangle CornellBox-Original: brute
 * force 98 ms, BVH 100, grid 72; docs/speed-vs-accuracy/rays-vs-triangles.csv). Not on GPUs: on
 * the H200 the BVH traced that box's camera rays at 31,700 million a second against brute
 * force's 9,600 and the driver's 12,800 (research/results/h200-1203/auto-vs-driver/, h200-1202b),
 * and won whole frames of the 30- and 36-triangle boxes on the H100 and the H200 (the scaling
 * charts): there even a handful of triangles gets the BVH. */
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

/* The scene is uneven when more than this share of all references lies in crowded cells.
 * Measured shares at the default density: the stadium 0.5; Sibenik 0.11, Sponza 0.085, the bunny,
 * the teapot and Lost Empire about 0. */
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
