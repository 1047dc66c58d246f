/*
 * bvh_quads.h: the BVH re-laid for GPU traversal as a 4-wide tree of 64-byte nodes whose
 * children's boxes are quantized to 8 bits per plane (after Ylitie, Karras and Laine, "Efficient
 * Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017, with 4 children
 * instead of 8). The binary tree of bvh.h is collapsed: a node takes its two children, and the
 * inner child of largest surface area is replaced by its own two until there are 4 or only
 * leaves remain. One 64-byte fetch then tests 4 boxes instead of the 2 of bvh_pairs.h, which
 * halves the nodes a ray visits. It is the default on CPU devices, where a fetch costs more than
 * decoding the node; on GPUs the binary pairs are the default, since there the decoding and
 * sorting cost more than the fetches they save (`--bvh-width` chooses either).
 *
 * Quantization is conservative: the decoded box of a child, origin + q * scale evaluated in float
 * exactly as the kernel does, always contains the child's float box, so the slab test still
 * never culls a triangle the watertight test would hit.
 */
#ifndef VKRT_BVH_QUADS_H
#define VKRT_BVH_QUADS_H

#include <stdint.h>

#include "../error.h"
#include "bvh.h"

/* One node, 64 bytes (glsl/shared.h BvhQuad has the same bytes). Child k's box is
 * origin + byte k of lo/hi * scale per axis, scale = 2^(exponent - 127) (a float's exponent
 * field). meta: exponents of x, y, z in bits 0-7, 8-15, 16-23, the child count (1..4) in bits
 * 24-31. lo_hi: per axis a (lo, hi) pair of words, byte k of each for child k: x lo, x hi, y lo,
 * y hi, z lo, z hi, then two unused words. ref[k]: the child's node index, or its leaf reference (bvh.h). */
typedef struct bvh_quad {
    float origin[3];
    uint32_t meta;
    uint32_t lo_hi[8];
    uint32_t ref[4];
} bvh_quad;

/* What bvh_quads_build made. */
typedef struct bvh_quads {
    bvh_quad *nodes;          /* nodes[0] is the root; depth-first order */
    uint32_t node_count;
    uint32_t max_depth;       /* of the deepest node; the root has depth 0 */
    uint32_t max_stack;       /* the most entries the kernel's stack can need on any path */
} bvh_quads;

/* Collapses and quantizes b. Fails (err set, nothing allocated) on allocation failure or when a
 * leaf does not fit a reference (bvh_leaf_ref). */
bool bvh_quads_build(const bvh *b, bvh_quads *out, vkrt_error *err);

/* Child k's box as the kernel decodes it (float arithmetic), for tests. */
void bvh_quad_child_box(const bvh_quad *q, int k, float lo[3], float hi[3]);

/* Frees what bvh_quads_build allocated and zeroes *q. Safe on a zeroed struct. */
void bvh_quads_free(bvh_quads *q);

#endif
