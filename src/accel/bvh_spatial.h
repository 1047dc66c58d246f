/*
 * bvh_spatial.h: one node's split decision with spatial splits (an SBVH: Stich, Friedrich and
 * Dietrich, "Spatial Splits in Bounding Volume Hierarchies", HPG 2009). Internal to the builder
 * (bvh.c), which calls it instead of bvh_split_node when a build allows spatial splits.
 *
 * A node first looks for the binned object split (bvh_split.h). Where the two children's boxes of
 * that split overlap by more than alpha of the root's surface area, it also bins the node's
 * references along each axis by space: each reference's triangle is clipped to the bins it
 * crosses, so a long thin triangle adds only its own piece to each bin's box. The cheaper of the
 * two wins. A spatial split puts a reference that crosses its plane into both children, each
 * with its triangle's part on that side, unless putting it whole into one side costs less
 * (Stich's reference unsplitting). The duplicates are paid from the node's spare room: the
 * builder gives every node a range of refs with room past its end, shared out to the children in
 * proportion to their references, so the total stays within the build's budget and the decision
 * never depends on another node's (the build stays deterministic).
 */
#ifndef VKRT_BVH_SPATIAL_H
#define VKRT_BVH_SPATIAL_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_split.h"

/* What a spatial-split build knows beyond the SAH settings. */
typedef struct bvh_spatial_params {
    const float *positions; /* the triangles, 9 floats each, indexed by prim_ref.index */
    float root_half_area;   /* of the whole tree's box */
    float alpha;            /* try spatial splits where overlap / root area exceeds this */
} bvh_spatial_params;

/* Spatial splits are looked for only where the object split's children overlap by more than
 * this share of the root's surface area. Stich et al. use 1e-5; a larger share searches far fewer
 * nodes (the search clips every triangle at every slab plane it crosses), which keeps the build a
 * small multiple of the plain one's, for SAH costs within a few percent of 1e-5's. */
#ifndef BVH_SPATIAL_ALPHA /* a build may set it to measure another share */
#define BVH_SPATIAL_ALPHA 1e-2f
#endif

/* Decides the node over refs[begin, end), with room for duplicates up to cap (refs[end, cap) are
 * free), like bvh_split_node, with spatial splits as well. A spatial split writes the left
 * child to [begin, out->mid) and the right to [out->mid, out->right_end), right_end <= cap; the
 * children's bounds are exact unions of their references' (clipped) boxes. */
void bvh_spatial_split_node(const bvh_split_params *p, const bvh_spatial_params *sp,
                            bvh_split_scratch *s, prim_ref *refs, uint32_t begin, uint32_t end,
                            uint32_t cap, const aabb *bounds, const aabb *cbounds,
                            bvh_split_result *out);

/* bvh_spatial_split_node for one big node, its binning shared by `threads` threads (the top
 * levels of bvh.c): scratch holds one scratch per thread. The bins add up to what one thread's
 * pass gives, so the decision and the references are the same. False only when out of memory,
 * with refs and out untouched (the caller then splits the node alone). */
bool bvh_spatial_split_shared(const bvh_split_params *p, const bvh_spatial_params *sp,
                              bvh_split_scratch *const *scratch, uint32_t threads, prim_ref *refs,
                              uint32_t begin, uint32_t end, uint32_t cap, const aabb *bounds,
                              const aabb *cbounds, bvh_split_result *out);

/* Cuts the part of triangle v (9 floats) inside box at the plane x[axis] = pos into the boxes of
 * its parts below and above the plane, each within box. Conservative: each box contains the
 * exact part (plane crossings are rounded outwards). A side the triangle does not reach comes
 * back empty (lo > hi). */
void bvh_clip_triangle(const float *v, const aabb *box, int axis, float pos, aabb *below,
                       aabb *above);

#endif
