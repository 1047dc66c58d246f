/*
 * bvh_split.c: one node's split by the binned SAH (bvh_split.h), after Wald 2007.
 *
 * The node's centroids go into K bins per axis over its centroid bounds; one sweep per axis
 * gives the cost of the K - 1 planes between bins (A_left N_left + A_right N_right, one triangle
 * test costs 1), and the cheapest plane wins if it beats a leaf. The records themselves are then
 * partitioned in place (Hoare's scheme: only misplaced pairs move), not indices into them, so
 * binning reads memory sequentially. Boxes and centroids are 4-lane vectors (bvh_lanes.h).
 */
#include "bvh_split.h"

#include <math.h>
#include <string.h>

enum { ALWAYS_LEAF_PRIMS = BVH_SPLIT_ALWAYS_LEAF };

/* A small node gets at most max(count, SMALL_NODE_MIN_BINS) bins (a departure from Wald's fixed
 * count): with a few triangles most of 16 bins would be empty, yet clearing and sweeping them is
 * a fixed cost per node, and the bottom levels hold most nodes. count bins still separate the two
 * extreme centroids and give count - 1 candidate planes, as many as an exact sweep has. */
enum { SMALL_NODE_MIN_BINS = 4 };

/* The bins of a node with centroid bounds cb: nb per axis where the extent is usable (positive
 * and finite). Other axes get scale 0 and lo 0, so their refs all fall into bin 0 without a
 * branch (finite centroid times 0), and are not swept. */
static bvh_bin_map make_bin_map(const aabb *cb, uint32_t nb, bool active[3])
{
    float lo[4], hi[4], mlo[3], scale[3];
    v4_store(lo, cb->lo);
    v4_store(hi, cb->hi);
    for (int a = 0; a < 3; a++) {
        float extent = hi[a] - lo[a];
        scale[a] = (float)nb / extent;
        active[a] = extent > 0.0f && isfinite(extent) && isfinite(scale[a]);
        mlo[a] = active[a] ? lo[a] : 0.0f;
        scale[a] = active[a] ? scale[a] : 0.0f;
    }
    return (bvh_bin_map){.lo = v4_set3(mlo[0], mlo[1], mlo[2]),
                         .scale = v4_set3(scale[0], scale[1], scale[2]),
                         .last = v4_set1((float)(nb - 1))};
}

/* Bins the centroids of refs[begin, end) on all three axes. */
void bvh_split_bins_fill(bvh_split_scratch *s, const prim_ref *refs, uint32_t begin, uint32_t end,
                         const bvh_bin_split *b)
{
    const uint32_t nb = b->bins;
    const bvh_bin_map map =
        b->map; /* a copy: stores to s could alias *b, this stays in registers */
    for (int a = 0; a < 3; a++) {
        for (uint32_t k = 0; k < nb; k++)
            aabb_empty(&s->bins[a][k]);
        memset(s->counts[a], 0, nb * sizeof s->counts[a][0]);
    }
    for (uint32_t i = begin; i < end; i++) {
        ref_lanes l = ref_load(&refs[i]);
        uint32_t k[4];
        bvh_bins_of(&map, l.c, k);
        aabb_grow_box(&s->bins[0][k[0]], l.lo, l.hi);
        aabb_grow_box(&s->bins[1][k[1]], l.lo, l.hi);
        aabb_grow_box(&s->bins[2][k[2]], l.lo, l.hi);
        s->counts[0][k[0]]++;
        s->counts[1][k[1]]++;
        s->counts[2][k[2]]++;
    }
}

void bvh_split_bins_bounds(const bvh_split_scratch *s, const bvh_bin_split *b, uint32_t first,
                           uint32_t end, aabb *out)
{
    aabb_empty(out);
    for (uint32_t k = first; k < end; k++)
        aabb_grow(out, &s->bins[b->axis][k]);
}

/* Sweeps one axis's bins: right-to-left areas first, then left to right for the costs.
 * Strict < keeps the first of equal costs, so the choice is reproducible. An empty bin changes
 * neither side's box nor count, so the plane after it costs what the plane before it did: the
 * sweeps copy or skip it rather than compute the same area again (small nodes' bins are mostly
 * empty: a node of n triangles has n bins). */
static void sweep_axis(bvh_split_scratch *s, int a, bvh_bin_split *best)
{
    const uint32_t nb = best->bins;
    const aabb *bins = s->bins[a];
    const uint32_t *counts = s->counts[a];
    aabb acc;
    aabb_empty(&acc);
    uint32_t cnt = 0;
    for (uint32_t k = nb - 1; k > 0; k--) {
        if (counts[k] == 0 && k < nb - 1) {
            s->right_count[k] = s->right_count[k + 1];
            s->right_area[k] = s->right_area[k + 1];
            continue;
        }
        aabb_grow(&acc, &bins[k]);
        cnt += counts[k];
        s->right_count[k] = cnt;
        s->right_area[k] = cnt ? aabb_half_area(&acc) : 0.0f;
    }
    aabb_empty(&acc);
    cnt = 0;
    for (uint32_t k = 1; k < nb; k++) {
        if (counts[k - 1] == 0)
            continue;
        aabb_grow(&acc, &bins[k - 1]);
        cnt += counts[k - 1];
        if (s->right_count[k] == 0)
            continue;
        float cost = aabb_half_area(&acc) * (float)cnt + s->right_area[k] * (float)s->right_count[k];
        if (cost < best->cost) {
            best->cost = cost;
            best->axis = a;
            best->bin = k;
        }
    }
}

static uint32_t bin_count(const bvh_split_params *p, uint32_t count)
{
    return MINF(p->bins, MAXF(count, (uint32_t)SMALL_NODE_MIN_BINS));
}

void bvh_split_bins_init(const bvh_split_params *p, uint32_t count, const aabb *cbounds,
                         bvh_bin_split *b)
{
    uint32_t nb = bin_count(p, count);
    *b = (bvh_bin_split){.bins = nb, .axis = -1, .cost = INFINITY};
    b->map = make_bin_map(cbounds, nb, b->active);
}

/* Costs are compared unnormalised, times A_parent: split when
 * traversal_cost * A + A_l N_l + A_r N_r < N * A, which also behaves for a flat (A = 0) node. */
bvh_split_kind bvh_split_choose(const bvh_split_params *p, bvh_split_scratch *s, uint32_t count,
                                const aabb *bounds, bvh_bin_split *b)
{
    if (count <= ALWAYS_LEAF_PRIMS)
        return BVH_SPLIT_LEAF;
    for (int a = 0; a < 3; a++) {
        if (b->active[a])
            sweep_axis(s, a, b);
    }
    bool must_split = count > p->max_leaf;
    float area = aabb_half_area(bounds);
    bool worth = b->axis >= 0 && p->traversal_cost * area + b->cost < (float)count * area;
    if (b->axis >= 0 && (must_split || worth))
        return BVH_SPLIT_BINNED;
    return must_split ? BVH_SPLIT_MEDIAN : BVH_SPLIT_LEAF;
}

/* Partitions refs[begin, end) in place, Hoare's way (each ref is looked at once, and only pairs
 * on the wrong sides move): bins below split->bin go left. Collects the children's bounds on the
 * way, so they are exact. Returns the first index of the right side. */
static uint32_t partition_refs(prim_ref *refs, uint32_t begin, uint32_t end,
                               const bvh_bin_split *split, bvh_split_result *out)
{
    const int a = split->axis;
    const uint32_t left_bins = split->bin;
    aabb lb, lcb, rb, rcb; /* locals, not out->..[side]: they stay in registers */
    aabb_empty(&lb);
    aabb_empty(&lcb);
    aabb_empty(&rb);
    aabb_empty(&rcb);
    uint32_t i = begin, j = end; /* [begin, i) left, [j, end) right */
    for (;;) {
        ref_lanes li, lj;
        uint32_t k[4];
        for (; i < j; i++) { /* the first ref from the left that belongs right */
            li = ref_load(&refs[i]);
            bvh_bins_of(&split->map, li.c, k);
            if (k[a] >= left_bins)
                break;
            aabb_grow_box(&lb, li.lo, li.hi);
            aabb_grow_point(&lcb, li.c);
        }
        if (i == j)
            break;
        aabb_grow_box(&rb, li.lo, li.hi);
        aabb_grow_point(&rcb, li.c);
        for (j--; j > i; j--) { /* the first ref from the right that belongs left */
            lj = ref_load(&refs[j]);
            bvh_bins_of(&split->map, lj.c, k);
            if (k[a] < left_bins)
                break;
            aabb_grow_box(&rb, lj.lo, lj.hi);
            aabb_grow_point(&rcb, lj.c);
        }
        if (j == i)
            break; /* refs[i] belongs right and is the right side's first */
        aabb_grow_box(&lb, lj.lo, lj.hi);
        aabb_grow_point(&lcb, lj.c);
        prim_ref tmp = refs[i];
        refs[i] = refs[j];
        refs[j] = tmp;
        i++;
    }
    out->bounds[0] = lb;
    out->cbounds[0] = lcb;
    out->bounds[1] = rb;
    out->cbounds[1] = rcb;
    return i;
}

void bvh_split_range_bounds(const prim_ref *refs, uint32_t begin, uint32_t end, aabb *b,
                            aabb *cb)
{
    aabb_empty(b);
    aabb_empty(cb);
    for (uint32_t i = begin; i < end; i++) {
        ref_lanes l = ref_load(&refs[i]);
        aabb_grow_box(b, l.lo, l.hi);
        aabb_grow_point(cb, l.c);
    }
}

/* Splits the range in the middle of its order: the fallback when binning finds no split with
 * both sides non-empty (all centroids equal, or extents that overflow) and the node is too big
 * for a leaf. Halving the count makes the recursion terminate. */
void bvh_split_median(const prim_ref *refs, uint32_t begin, uint32_t end, bvh_split_result *out)
{
    out->split = true;
    out->spatial = false;
    out->mid = begin + (end - begin) / 2;
    out->right_end = end;
    bvh_split_range_bounds(refs, begin, out->mid, &out->bounds[0], &out->cbounds[0]);
    bvh_split_range_bounds(refs, out->mid, end, &out->bounds[1], &out->cbounds[1]);
}

/* bvh_split_node for a node of two records, without bins (half the nodes of a tree with leaves
 * of 2 hold two triangles). Its bins hold one record or none, so on an axis where the two fall
 * into different bins every plane between them has one record on each side and costs
 * A(r0) * 1 + A(r1) * 1, whichever axis it is: the sweep keeps the first such axis and the first
 * plane past the lower record's bin, which goes left. Same decision, same floats. */
static void split_pair(const bvh_split_params *p, prim_ref *refs, uint32_t begin,
                       const aabb *bounds, const aabb *cbounds, bvh_split_result *out)
{
    bool active[3];
    const bvh_bin_map map = make_bin_map(cbounds, bin_count(p, 2), active);
    ref_lanes l[2] = {ref_load(&refs[begin]), ref_load(&refs[begin + 1])};
    uint32_t k[2][4];
    bvh_bins_of(&map, l[0].c, k[0]);
    bvh_bins_of(&map, l[1].c, k[1]);
    int axis = -1;
    for (int a = 0; a < 3 && axis < 0; a++) {
        if (active[a] && k[0][a] != k[1][a])
            axis = a;
    }
    aabb box[2];
    for (int i = 0; i < 2; i++) {
        aabb_empty(&box[i]);
        aabb_grow_box(&box[i], l[i].lo, l[i].hi);
    }
    /* Both orders of the sum are the same float; a cost that is not below infinity (boxes too
     * large for float areas) never wins the sweep. */
    float cost = aabb_half_area(&box[0]) * 1.0f + aabb_half_area(&box[1]) * 1.0f;
    if (!(cost < INFINITY))
        axis = -1;
    bool must_split = 2 > p->max_leaf;
    float area = aabb_half_area(bounds);
    bool worth = axis >= 0 && p->traversal_cost * area + cost < 2.0f * area;
    out->split = false;
    out->spatial = false;
    out->right_end = begin + 2;
    if (axis >= 0 && (must_split || worth)) {
        int left = k[0][axis] < k[1][axis] ? 0 : 1; /* Hoare's partition swaps a pair in order */
        if (left == 1) {
            prim_ref tmp = refs[begin];
            refs[begin] = refs[begin + 1];
            refs[begin + 1] = tmp;
        }
        out->split = true;
        out->mid = begin + 1;
        for (int side = 0; side < 2; side++) {
            const ref_lanes *r = &l[side == 0 ? left : 1 - left];
            out->bounds[side] = box[side == 0 ? left : 1 - left];
            aabb_empty(&out->cbounds[side]);
            aabb_grow_point(&out->cbounds[side], r->c);
        }
    } else if (must_split) {
        bvh_split_median(refs, begin, begin + 2, out);
    }
}

void bvh_split_node(const bvh_split_params *p, bvh_split_scratch *s, prim_ref *refs,
                    uint32_t begin, uint32_t end, const aabb *bounds, const aabb *cbounds,
                    bvh_split_result *out)
{
    uint32_t count = end - begin;
    out->split = false;
    out->spatial = false;
    if (count <= ALWAYS_LEAF_PRIMS)
        return;
    if (count == 2) {
        split_pair(p, refs, begin, bounds, cbounds, out);
        return;
    }
    bvh_bin_split b;
    bvh_split_bins_init(p, count, cbounds, &b);
    bvh_split_bins_fill(s, refs, begin, end, &b);
    bvh_split_apply(p, refs, begin, end, bvh_split_choose(p, s, count, bounds, &b), &b, out);
}

void bvh_split_apply(const bvh_split_params *p, prim_ref *refs, uint32_t begin, uint32_t end,
                     bvh_split_kind kind, const bvh_bin_split *b, bvh_split_result *out)
{
    out->split = false;
    out->spatial = false;
    out->right_end = end;
    if (kind == BVH_SPLIT_BINNED) {
        out->mid = partition_refs(refs, begin, end, b, out);
        out->split = out->mid > begin && out->mid < end;
        if (out->split)
            return;
        kind = end - begin > p->max_leaf ? BVH_SPLIT_MEDIAN : BVH_SPLIT_LEAF;
    }
    if (kind == BVH_SPLIT_MEDIAN)
        bvh_split_median(refs, begin, end, out);
}
