/*
 * choose.h: which acceleration structure a scene needs (`accel auto`).
 *
 * The choice looks at the scene, not at a clock: the triangle count, and how unevenly the
 * triangles fill space, read off the uniform grid's occupancy (building it is O(n) and cheap).
 * Brute force for a handful of triangles; the grid when the triangles are spread evenly over its
 * cells; the BVH otherwise (the teapot-in-a-stadium case, where a few cells hold most of them).
 */
#ifndef VKRT_ACCEL_CHOOSE_H
#define VKRT_ACCEL_CHOOSE_H

#include <stdint.h>

#include "../scene/config.h"
#include "grid.h"

typedef struct accel_choice {
    vkrt_accel_kind kind;   /* never VKRT_ACCEL_AUTO */
    char reason[256];       /* one sentence for --verbose and the summary */
} accel_choice;

/* At or below this many triangles brute force is chosen without building anything. */
uint32_t accel_brute_force_limit(void);

/* Chooses for a scene of triangle_count triangles whose grid (built with the default density) is
 * g; g may be NULL when triangle_count <= accel_brute_force_limit(). */
accel_choice accel_choose(uint32_t triangle_count, const grid *g);

#endif
