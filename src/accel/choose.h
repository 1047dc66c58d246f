/*
 * choose.h: which acceleration structure a scene needs (`accel auto`).
 *
 * The choice looks at the scene and the kind of device, not at a clock. Brute force for a handful
 * of triangles on a CPU device. Above that, how unevenly the triangles fill space, read off the
 * uniform grid's occupancy (O(n) to build): a scene with much of its geometry in a few crowded
 * cells (the teapot in a stadium) gets the BVH. An evenly spread scene gets the grid on a CPU
 * device whose traversal reads storage buffers, where the grid traces about as fast as the BVH
 * and builds faster. A CPU device reading texel buffers gets the kd-tree, up to a size past which
 * its slower build would eat the gain. A GPU gets the BVH, and a BVH whose SAH cost is far above
 * its triangle count's norm is weighed against the kd-tree. choose.c says why each branch.
 */
#ifndef VKRT_ACCEL_CHOOSE_H
#define VKRT_ACCEL_CHOOSE_H

#include <stdbool.h>
#include <stdint.h>

#include "../scene/config.h"
#include "grid.h"

/* The kind of device the structure is for, as far as the choice is concerned: a GPU; a CPU device
 * (a software Vulkan driver) whose traversal reads texel buffers (its default); a CPU device
 * reading storage buffers (`--loads storage`). */
typedef enum accel_device {
    ACCEL_DEVICE_GPU,
    ACCEL_DEVICE_CPU_TEXELS,
    ACCEL_DEVICE_CPU_STORAGE,
} accel_device;

typedef struct accel_choice {
    vkrt_accel_kind kind;   /* never VKRT_ACCEL_AUTO */
    char reason[256];       /* one sentence for --verbose and the summary */
} accel_choice;

/* At or below this many triangles brute force is chosen without building anything. */
uint32_t accel_brute_force_limit(void);

/* Up to this many triangles a CPU device reading texel buffers gets the kd-tree. */
uint32_t accel_kdtree_limit(void);

/* On a GPU, after `auto` chose the BVH: whether its SAH cost is so high for triangle_count
 * triangles (overlapping boxes of long thin triangles) that the kd-tree is worth building too. */
bool accel_kdtree_worth_trying(uint32_t triangle_count, float bvh_sah_cost);

/* Whether the kd-tree of that SAH cost replaces the BVH of this one. */
bool accel_kdtree_wins(float kdtree_sah_cost, float bvh_sah_cost);
/* The share of the BVH's SAH cost the kd-tree's must be under to win (for the reason's words). */
double accel_kdtree_cost_share(void);

/* True when the choice for this scene and device needs the grid's statistics: above the brute
 * force limit on a CPU device reading storage buffers. (Elsewhere the grid loses either way, so
 * no grid is built.) */
bool accel_choice_needs_grid(uint32_t triangle_count, accel_device device);

/* Chooses for a scene of triangle_count triangles on a device of that kind. g is the scene's grid
 * at the default density when accel_choice_needs_grid said so, else NULL. */
accel_choice accel_choose(uint32_t triangle_count, accel_device device, const grid *g);

#endif
