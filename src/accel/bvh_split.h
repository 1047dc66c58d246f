/*
 * bvh_split.h: one node's split decision in the BVH builder (bvh.c), by the binned surface area
 * heuristic of Wald, "On fast construction of SAH-based bounding volume hierarchies" (IEEE
 * Symposium on Interactive Ray Tracing 2007). Internal to the builder.
 *
 * The centroids of the node's triangle records are binned along the 3 axes over the node's
 * centroid bounds, the bins are swept for the cheapest split, and the records are partitioned in
 * place. The decision depends only on the records and the parameters, never on the thread that
 * makes it, which keeps the build deterministic.
 */
#ifndef VKRT_BVH_SPLIT_H
#define VKRT_BVH_SPLIT_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_lanes.h"

/* The most bins per axis a build may use: the scratch arrays are this long. */
enum { BVH_SPLIT_MAX_BINS = 256 };

/* A node this small is a leaf without looking at the SAH. */
enum { BVH_SPLIT_ALWAYS_LEAF = 1 };

/* The SAH settings of a build: bvh_build_desc's, defaults applied (bvh.h). */
typedef struct bvh_split_params {
    uint32_t max_leaf;    /* a node over this many triangles always splits */
    uint32_t bins;        /* per axis, at most BVH_SPLIT_MAX_BINS */
    float traversal_cost; /* of one node visit, in triangle tests */
} bvh_split_params;

/* Bins per axis in bvh_split_scratch's arrays beyond the most a build uses, so that an axis's
 * bins start 8 KiB + 64 bytes after the previous axis's rather than 8 KiB: binning updates bin k
 * of all three axes for most records, and x86 cores stall a load that lies a multiple of 4 KiB
 * from a store still in flight as if the two overlapped (4K aliasing). */
enum { BVH_SPLIT_BIN_PAD = 2 };

/* One thread's bins, about 40 KiB: one per thread, reused for every node it splits. The spatial
 * bins (bvh_spatial.h) count in counts the references that start in each bin and in exits those
 * that end there. */
typedef struct bvh_split_scratch {
    aabb bins[3][BVH_SPLIT_MAX_BINS + BVH_SPLIT_BIN_PAD];
    uint32_t counts[3][BVH_SPLIT_MAX_BINS];
    float right_area[BVH_SPLIT_MAX_BINS];
    uint32_t right_count[BVH_SPLIT_MAX_BINS];
    uint32_t exits[3][BVH_SPLIT_MAX_BINS];
} bvh_split_scratch;

/* What one node's split decision says. */
typedef struct bvh_split_result {
    bool split;
    uint32_t mid;          /* left child: [begin, mid), right child: [mid, right_end) */
    uint32_t right_end;    /* the node's end, or past it when a spatial split duplicated refs */
    bool spatial;          /* split by a plane (bvh_spatial.h), not by grouping whole refs */
    aabb bounds[2];        /* exact bounds of the children */
    aabb cbounds[2];       /* centroid bounds of the children */
} bvh_split_result;

/* How a node maps centroids to bins: bin = clamp((c - lo) * scale, 0, last), truncated, on all
 * three axes at once. Binning and partitioning both go through bvh_bins_of, so they agree on
 * every triangle's bin. The clamps keep the conversion defined even if rounding strays outside
 * [0, last] (a NaN lands in bin 0). */
typedef struct bvh_bin_map {
    vec4 lo, scale, last;
} bvh_bin_map;

static inline void bvh_bins_of(const bvh_bin_map *m, vec4 c, uint32_t k[4])
{
    vec4 f = v4_mul(v4_sub(c, m->lo), m->scale);
    f = v4_min(v4_max(f, v4_set1(0.0f)), m->last);
    v4_to_u32(f, k);
}

/* One node's binned split: its bins, and once chosen the plane (left side: bins [0, bin) of
 * axis). */
typedef struct bvh_bin_split {
    bvh_bin_map map;
    uint32_t bins;  /* per axis */
    bool active[3]; /* axes with a usable extent; the others are not swept */
    int axis;       /* -1: no split with both sides non-empty */
    uint32_t bin;
    float cost; /* A_left N_left + A_right N_right */
} bvh_bin_split;

/* What bvh_split_choose decides for a node. */
typedef enum bvh_split_kind {
    BVH_SPLIT_LEAF,   /* keep the node whole */
    BVH_SPLIT_BINNED, /* partition by the chosen plane */
    BVH_SPLIT_MEDIAN, /* too big for a leaf and no plane separates it: bvh_split_median */
} bvh_split_kind;

/* bvh_split_node in pieces, for one big node split by many threads (bvh_top.c): the bins of a
 * node of `count` triangles with centroid bounds cbounds; each thread fills a scratch from a
 * slice of the node's records (fill clears the scratch's first b->bins bins first); the slices'
 * bins are added up; then the choice. Bins hold exact unions (records hold no -0, bvh.c) and
 * counts, so the slices add up to the bins one pass over the whole range gives. */
void bvh_split_bins_init(const bvh_split_params *p, uint32_t count, const aabb *cbounds,
                         bvh_bin_split *b);
void bvh_split_bins_fill(bvh_split_scratch *s, const prim_ref *refs, uint32_t begin, uint32_t end,
                         const bvh_bin_split *b);

/* Sweeps the filled bins s of a node of `count` triangles and exact bounds `bounds`, sets the
 * plane in *b, and says what the node does (the same decision bvh_split_node makes). */
bvh_split_kind bvh_split_choose(const bvh_split_params *p, bvh_split_scratch *s, uint32_t count,
                                const aabb *bounds, bvh_bin_split *b);

/* Whether a centroid goes to the left child of a BVH_SPLIT_BINNED choice. */
static inline bool bvh_split_goes_left(const bvh_bin_split *b, vec4 c)
{
    uint32_t k[4];
    bvh_bins_of(&b->map, c, k);
    return k[b->axis] < b->bin;
}

/* The exact bounds of bins [first, end) of the chosen axis: a child's bounds, read from bins. */
void bvh_split_bins_bounds(const bvh_split_scratch *s, const bvh_bin_split *b, uint32_t first,
                           uint32_t end, aabb *out);

/* Splits refs[begin, end) in the middle of its order (BVH_SPLIT_MEDIAN), children's bounds
 * included. */
void bvh_split_median(const prim_ref *refs, uint32_t begin, uint32_t end, bvh_split_result *out);

/* Carries out bvh_split_choose's decision `kind` (b's plane for BVH_SPLIT_BINNED) on
 * refs[begin, end), as bvh_split_node does after choosing: out->split false for a leaf. */
void bvh_split_apply(const bvh_split_params *p, prim_ref *refs, uint32_t begin, uint32_t end,
                     bvh_split_kind kind, const bvh_bin_split *b, bvh_split_result *out);

/* The exact bounds and centroid bounds of refs[begin, end). */
void bvh_split_range_bounds(const prim_ref *refs, uint32_t begin, uint32_t end, aabb *b, aabb *cb);

/* Decides whether the node over refs[begin, end), with exact bounds `bounds` and centroid bounds
 * `cbounds`, is a leaf or splits, and on a split reorders refs[begin, end) so that its children
 * are [begin, out->mid) and [out->mid, end) (out->right_end = end), both non-empty, with their
 * bounds in *out. A node of more than p->max_leaf triangles always splits (in the middle of its
 * order when no binned split separates it); a leaf leaves the order of refs as it was. */
void bvh_split_node(const bvh_split_params *p, bvh_split_scratch *s, prim_ref *refs,
                    uint32_t begin, uint32_t end, const aabb *bounds, const aabb *cbounds,
                    bvh_split_result *out);

#endif
