/*
 * bvh_spatial.c: one node's split with spatial splits (bvh_spatial.h), after Stich, Friedrich and
 * Dietrich, HPG 2009.
 *
 * Spatial bins split the node's box into equal slabs along an axis. A reference counts as
 * entering the slab of its box's low end and leaving the slab of its high end; its triangle is
 * chopped at each slab plane in between, and each slab's box grows by the piece inside it only.
 * One sweep then gives the cost of every plane: A_left N_entered_left + A_right N_left_right.
 * References cross the children with their triangles clipped, so a child's box is the union of
 * clipped boxes, never larger than its part of the node. Which reference goes where is written
 * into prim_ref.pad while a split is applied, and cleared after.
 */
#include "bvh_spatial.h"

#include "bvh_threads.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Where a reference goes in a spatial split, kept in prim_ref.pad while it is applied. */
enum { TAG_NONE = 0, TAG_LEFT = 1, TAG_RIGHT = 2, TAG_BOTH = 3 };

typedef struct spatial_split {
    int axis;   /* -1: none */
    float pos;  /* the plane */
    float cost; /* A_left N_left + A_right N_right */
} spatial_split;

static bool box_valid(const aabb *b)
{
    float lo[4], hi[4];
    v4_store(lo, b->lo);
    v4_store(hi, b->hi);
    return lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2];
}

static aabb box_intersect(const aabb *a, const aabb *b)
{
    return (aabb){.lo = v4_max(a->lo, b->lo), .hi = v4_min(a->hi, b->hi)};
}

static void grow3(float lo[3], float hi[3], const float plo[3], const float phi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = MINF(lo[k], plo[k]);
        hi[k] = MAXF(hi[k], phi[k]);
    }
}

/* Where edge p-q crosses x[axis] = pos, as a box. Exact: computed in double and each other
 * coordinate widened by one float step each way (so the rounding to float never moves it
 * inwards), then kept within the edge's own extent. Else the float estimate binning needs. */
static void edge_crossing(const float *p, const float *q, int axis, float pos, bool exact,
                          float lo[3], float hi[3])
{
    double t = exact ? ((double)pos - p[axis]) / ((double)q[axis] - p[axis]) : 0.0;
    float tf = (pos - p[axis]) / (q[axis] - p[axis]);
    for (int b = 0; b < 3; b++) {
        if (b == axis) {
            lo[b] = hi[b] = pos;
        } else if (!exact) {
            lo[b] = hi[b] = p[b] + tf * (q[b] - p[b]);
        } else {
            float x = (float)(p[b] + t * ((double)q[b] - p[b]));
            lo[b] = MAXF(nextafterf(x, -INFINITY), MINF(p[b], q[b]));
            hi[b] = MINF(nextafterf(x, INFINITY), MAXF(p[b], q[b]));
        }
    }
}

/* bvh_clip_triangle, exact (conservative) or estimated (binning). */
static void clip_triangle(const float *v, const aabb *box, int axis, float pos, bool exact,
                          aabb *below, aabb *above)
{
    float blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    float alo[3] = {INFINITY, INFINITY, INFINITY}, ahi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++) {
        const float *p = v + 3 * i, *q = v + 3 * ((i + 1) % 3);
        if (p[axis] <= pos)
            grow3(blo, bhi, p, p);
        if (p[axis] >= pos)
            grow3(alo, ahi, p, p);
        if ((p[axis] < pos && q[axis] > pos) || (p[axis] > pos && q[axis] < pos)) {
            float lo[3], hi[3];
            edge_crossing(p, q, axis, pos, exact, lo, hi);
            grow3(blo, bhi, lo, hi);
            grow3(alo, ahi, lo, hi);
        }
    }
    /* + 0: -0 becomes +0, as in the builder's records (bvh.c), so that no union of clipped
     * boxes depends on the order it takes them in. */
    const vec4 zero = v4_set1(0.0f);
    aabb b = {v4_add(v4_set3(blo[0], blo[1], blo[2]), zero),
              v4_add(v4_set3(bhi[0], bhi[1], bhi[2]), zero)};
    aabb a = {v4_add(v4_set3(alo[0], alo[1], alo[2]), zero),
              v4_add(v4_set3(ahi[0], ahi[1], ahi[2]), zero)};
    *below = box_intersect(&b, box);
    *above = box_intersect(&a, box);
}

void bvh_clip_triangle(const float *v, const aabb *box, int axis, float pos, aabb *below,
                       aabb *above)
{
    clip_triangle(v, box, axis, pos, true, below, above);
}

static aabb ref_box(const prim_ref *r)
{
    ref_lanes l = ref_load(r);
    return (aabb){l.lo, l.hi};
}

static void set_ref_box(prim_ref *r, const aabb *b)
{
    aabb_store(b, r->lo, r->hi);
}

/* Clips reference r's triangle at the plane. */
static void clip_ref(const bvh_spatial_params *sp, const prim_ref *r, int axis, float pos,
                     aabb *below, aabb *above)
{
    aabb box = ref_box(r);
    bvh_clip_triangle(sp->positions + (size_t)r->index * 9, &box, axis, pos, below, above);
}

/* ------------------------------------------------------------------------ finding */

/* The planes of nb slabs over [lo, lo + extent]: plane k is slab k's low side. */
static float slab_plane(float lo, float extent, uint32_t k, uint32_t nb)
{
    return lo + extent * ((float)k / (float)nb);
}

/* Bins refs[begin, end) into nb slabs of axis a of bounds, chopping each triangle at the planes
 * its box crosses. s->counts holds the entries, s->exits the exits. */
static void fill_spatial_bins(const bvh_spatial_params *sp, bvh_split_scratch *s,
                              const prim_ref *refs, uint32_t begin, uint32_t end, int a, float lo,
                              float extent, uint32_t nb)
{
    aabb *bins = s->bins[a];
    for (uint32_t k = 0; k < nb; k++)
        aabb_empty(&bins[k]);
    memset(s->counts[a], 0, nb * sizeof s->counts[a][0]);
    memset(s->exits[a], 0, nb * sizeof s->exits[a][0]);
    float scale = (float)nb / extent, last = (float)(nb - 1);
    for (uint32_t i = begin; i < end; i++) {
        float f0 = (refs[i].lo[a] - lo) * scale, f1 = (refs[i].hi[a] - lo) * scale;
        uint32_t b0 = (uint32_t)MINF(MAXF(f0, 0.0f), last);
        uint32_t b1 = (uint32_t)MINF(MAXF(f1, 0.0f), last);
        s->counts[a][b0]++;
        s->exits[a][b1]++;
        aabb rest = ref_box(&refs[i]);
        const float *v = sp->positions + (size_t)refs[i].index * 9;
        for (uint32_t b = b0; b < b1 && box_valid(&rest); b++) {
            aabb piece;
            clip_triangle(v, &rest, a, slab_plane(lo, extent, b + 1, nb), false, &piece, &rest);
            if (box_valid(&piece))
                aabb_grow(&bins[b], &piece);
        }
        if (box_valid(&rest))
            aabb_grow(&bins[b1], &rest);
    }
}

/* Sweeps axis a's slabs for the cheapest plane; strict < keeps the first of equal costs. */
static void sweep_spatial(bvh_split_scratch *s, int a, float lo, float extent, uint32_t nb,
                          spatial_split *best)
{
    const aabb *bins = s->bins[a];
    aabb acc;
    aabb_empty(&acc);
    uint32_t cnt = 0;
    for (uint32_t k = nb - 1; k > 0; k--) {
        aabb_grow(&acc, &bins[k]);
        cnt += s->exits[a][k];
        s->right_count[k] = cnt;
        s->right_area[k] = box_valid(&acc) ? aabb_half_area(&acc) : INFINITY;
    }
    aabb_empty(&acc);
    cnt = 0;
    for (uint32_t k = 1; k < nb; k++) {
        aabb_grow(&acc, &bins[k - 1]);
        cnt += s->counts[a][k - 1];
        if (cnt == 0 || s->right_count[k] == 0 || !box_valid(&acc))
            continue;
        float cost =
            aabb_half_area(&acc) * (float)cnt + s->right_area[k] * (float)s->right_count[k];
        if (cost < best->cost)
            *best = (spatial_split){.axis = a, .pos = slab_plane(lo, extent, k, nb), .cost = cost};
    }
}

/* A node's spatial bins: nb slabs on each active axis over its box [lo, lo + extent]. */
typedef struct slabs {
    float lo[3], extent[3];
    bool active[3];
    uint32_t nb;
} slabs;

static slabs make_slabs(const aabb *bounds, uint32_t nb)
{
    slabs sl = {.nb = nb};
    float lo[4], hi[4];
    v4_store(lo, bounds->lo);
    v4_store(hi, bounds->hi);
    for (int a = 0; a < 3; a++) {
        sl.lo[a] = lo[a];
        sl.extent[a] = hi[a] - lo[a];
        sl.active[a] =
            sl.extent[a] > 0.0f && isfinite(sl.extent[a]) && isfinite((float)nb / sl.extent[a]);
    }
    return sl;
}

/* Bins refs[begin, end) on every active axis (each axis's bins cleared first). */
static void fill_slabs(const bvh_spatial_params *sp, bvh_split_scratch *s, const prim_ref *refs,
                       uint32_t begin, uint32_t end, const slabs *sl)
{
    for (int a = 0; a < 3; a++)
        if (sl->active[a])
            fill_spatial_bins(sp, s, refs, begin, end, a, sl->lo[a], sl->extent[a], sl->nb);
}

static spatial_split sweep_slabs(bvh_split_scratch *s, const slabs *sl)
{
    spatial_split best = {.axis = -1, .cost = INFINITY};
    for (int a = 0; a < 3; a++)
        if (sl->active[a])
            sweep_spatial(s, a, sl->lo[a], sl->extent[a], sl->nb, &best);
    return best;
}

/* ------------------------------------------------------------------------ applying */

static void swap_refs(prim_ref *refs, uint32_t i, uint32_t j)
{
    prim_ref t = refs[i];
    refs[i] = refs[j];
    refs[j] = t;
}

/* What tagging the references for a spatial split found. */
typedef struct spatial_tags {
    uint32_t left, right; /* references of each child, those in both counted twice */
    uint32_t both;        /* references in both children */
    float cost;           /* A_left N_left + A_right N_right of the children as tagged */
} spatial_tags;

/* Tags each ref of [begin, end) left, right or both for the plane, then unsplits (Stich et al.,
 * section 4.4): a reference crossing the plane goes whole to one side when that costs less than
 * two pieces, judged against the children as they stand. */
static spatial_tags tag_refs(const bvh_spatial_params *sp, prim_ref *refs, uint32_t begin,
                             uint32_t end, const spatial_split *split)
{
    const int a = split->axis;
    const float pos = split->pos;
    aabb lb, rb;
    aabb_empty(&lb);
    aabb_empty(&rb);
    uint32_t nl = 0, nr = 0;
    for (uint32_t i = begin; i < end; i++) {
        prim_ref *r = &refs[i];
        aabb box = ref_box(r), below, above;
        if (r->hi[a] <= pos) {
            r->pad = TAG_LEFT;
        } else if (r->lo[a] >= pos) {
            r->pad = TAG_RIGHT;
        } else {
            clip_ref(sp, r, a, pos, &below, &above);
            /* A box rounded outwards may cross a plane its triangle does not reach. */
            bool l = box_valid(&below), rr = box_valid(&above);
            r->pad = l && rr ? TAG_BOTH : l ? TAG_LEFT : TAG_RIGHT;
            if (r->pad == TAG_BOTH) {
                aabb_grow(&lb, &below);
                aabb_grow(&rb, &above);
                nl++;
                nr++;
                continue;
            }
        }
        aabb_grow(r->pad == TAG_LEFT ? &lb : &rb, &box);
        if (r->pad == TAG_LEFT)
            nl++;
        else
            nr++;
    }
    uint32_t both = 0;
    for (uint32_t i = begin; i < end; i++) {
        prim_ref *r = &refs[i];
        if (r->pad != TAG_BOTH)
            continue;
        aabb box = ref_box(r), l1 = lb, r2 = rb;
        aabb_grow(&l1, &box);
        aabb_grow(&r2, &box);
        float c_split = aabb_half_area(&lb) * nl + aabb_half_area(&rb) * nr;
        float c_left = aabb_half_area(&l1) * nl + aabb_half_area(&rb) * (nr - 1);
        float c_right = aabb_half_area(&lb) * (nl - 1) + aabb_half_area(&r2) * nr;
        if (c_left < c_split && c_left <= c_right) {
            r->pad = TAG_LEFT;
            lb = l1;
            nr--;
        } else if (c_right < c_split) {
            r->pad = TAG_RIGHT;
            rb = r2;
            nl--;
        } else {
            both++;
        }
    }
    return (spatial_tags){.left = nl,
                          .right = nr,
                          .both = both,
                          .cost = aabb_half_area(&lb) * nl + aabb_half_area(&rb) * nr};
}

/* Applies a spatial split; false (refs as they were) when a side would be empty, the duplicates
 * do not fit in [end, cap), or the children as unsplitting left them cost no less than
 * cost_limit (the binned estimate counted every crossing reference in both). */
static bool apply_spatial(const bvh_spatial_params *sp, prim_ref *refs, uint32_t begin,
                          uint32_t end, uint32_t cap, const spatial_split *split, float cost_limit,
                          bvh_split_result *out)
{
    spatial_tags tags = tag_refs(sp, refs, begin, end, split);
    uint32_t both = tags.both;
    if (tags.left == 0 || tags.right == 0 || both > cap - end || !(tags.cost < cost_limit)) {
        for (uint32_t i = begin; i < end; i++)
            refs[i].pad = TAG_NONE;
        return false;
    }
    /* Three ways: [begin, lo) left, [lo, hi) both, [hi, end) right (Dijkstra's flag). */
    uint32_t lo = begin, mid = begin, hi = end;
    while (mid < hi) {
        uint32_t tag = refs[mid].pad;
        if (tag == TAG_LEFT)
            swap_refs(refs, lo++, mid++);
        else if (tag == TAG_BOTH)
            mid++;
        else
            swap_refs(refs, mid, --hi);
    }
    memmove(refs + hi + both, refs + hi, (end - hi) * sizeof *refs);
    for (uint32_t k = 0; k < both; k++) {
        prim_ref *r = &refs[lo + k];
        aabb below, above;
        clip_ref(sp, r, split->axis, split->pos, &below, &above);
        refs[hi + k] = *r;
        set_ref_box(r, &below);
        set_ref_box(&refs[hi + k], &above);
    }
    uint32_t right_end = end + both;
    for (uint32_t i = begin; i < right_end; i++)
        refs[i].pad = TAG_NONE;
    out->split = true;
    out->spatial = true;
    out->mid = hi;
    out->right_end = right_end;
    bvh_split_range_bounds(refs, begin, hi, &out->bounds[0], &out->cbounds[0]);
    bvh_split_range_bounds(refs, hi, right_end, &out->bounds[1], &out->cbounds[1]);
    return true;
}

/* ------------------------------------------------------------------------ the decision */

/* Chooses the object split from filled object bins s as bvh_split_node would, and reads its
 * children's boxes from the bins before the spatial search reuses them. */
static bvh_split_kind choose_object(const bvh_split_params *p, bvh_split_scratch *s, uint32_t count,
                                    const aabb *bounds, bvh_bin_split *o, aabb child[2])
{
    bvh_split_kind kind = bvh_split_choose(p, s, count, bounds, o);
    if (o->axis >= 0) {
        bvh_split_bins_bounds(s, o, 0, o->bin, &child[0]);
        bvh_split_bins_bounds(s, o, o->bin, o->bins, &child[1]);
    }
    return kind;
}

/* Whether a node with room for duplicates should look for a spatial split: only where the object
 * split's children overlap by more than alpha of the root's area can one pay (Stich et al.,
 * section 4.5). No object split at all (all centroids equal) counts as overlapping. */
static bool worth_spatial(const bvh_spatial_params *sp, uint32_t end, uint32_t cap,
                          const bvh_bin_split *o, const aabb child[2])
{
    if (cap <= end)
        return false;
    if (o->axis < 0)
        return true;
    aabb overlap = box_intersect(&child[0], &child[1]);
    return box_valid(&overlap) && aabb_half_area(&overlap) > sp->alpha * sp->root_half_area;
}

/* Takes the spatial split when it is cheaper, else the object split's decision `kind`. A split
 * must cost less than the children a leaf would save (unless the node must split), and a
 * spatial one less than the object split too. */
static void decide(const bvh_split_params *p, const bvh_spatial_params *sp, prim_ref *refs,
                   uint32_t begin, uint32_t end, uint32_t cap, const aabb *bounds,
                   bvh_split_kind kind, const bvh_bin_split *o, const spatial_split *spatial,
                   bvh_split_result *out)
{
    uint32_t count = end - begin;
    float area = aabb_half_area(bounds), leaf_cost = (float)count * area;
    float limit =
        count > p->max_leaf ? o->cost : MINF(o->cost, leaf_cost - p->traversal_cost * area);
    if (spatial->axis >= 0 && spatial->cost < limit &&
        apply_spatial(sp, refs, begin, end, cap, spatial, limit, out))
        return;
    bvh_split_apply(p, refs, begin, end, kind, o, out);
}

void bvh_spatial_split_node(const bvh_split_params *p, const bvh_spatial_params *sp,
                            bvh_split_scratch *s, prim_ref *refs, uint32_t begin, uint32_t end,
                            uint32_t cap, const aabb *bounds, const aabb *cbounds,
                            bvh_split_result *out)
{
    uint32_t count = end - begin;
    out->split = false;
    out->spatial = false;
    out->right_end = end;
    if (count <= BVH_SPLIT_ALWAYS_LEAF)
        return;
    bvh_bin_split o;
    bvh_split_bins_init(p, count, cbounds, &o);
    bvh_split_bins_fill(s, refs, begin, end, &o);
    aabb child[2];
    bvh_split_kind kind = choose_object(p, s, count, bounds, &o, child);
    spatial_split spatial = {.axis = -1, .cost = INFINITY};
    if (worth_spatial(sp, end, cap, &o, child)) {
        slabs sl = make_slabs(bounds, o.bins);
        fill_slabs(sp, s, refs, begin, end, &sl);
        spatial = sweep_slabs(s, &sl);
    }
    decide(p, sp, refs, begin, end, cap, bounds, kind, &o, &spatial, out);
}

/* ------------------------------------------------------------------------ shared by threads */

/* References per task of the shared split: as bvh_top.c's chunks, a task costs one atomic add. */
enum { CHUNK_REFS = 1 << 14 };

/* One node's binning cut into chunks: each chunk binned alone into its own slots, the slots then
 * added up in chunk order. */
typedef struct shared_bins {
    const bvh_spatial_params *sp;
    const prim_ref *refs;
    uint32_t begin, end, chunks;
    const bvh_bin_split *object; /* the object pass: these bins */
    const slabs *slabs;          /* the spatial pass: these */
    aabb *bins;               /* chunk c, axis a, bin k: [(c * 3 + a) * BVH_SPLIT_MAX_BINS + k] */
    uint32_t *counts, *exits; /* the same layout */
    atomic_uint next;
} shared_bins;

/* The axes a pass bins: all three for the object bins, the active ones for the slabs. */
static bool axis_binned(const shared_bins *sb, int a)
{
    return sb->object || sb->slabs->active[a];
}

typedef struct shared_worker {
    shared_bins *sb;
    bvh_split_scratch *s;
} shared_worker;

static void *bin_chunks(void *arg)
{
    shared_worker *w = arg;
    shared_bins *sb = w->sb;
    bvh_split_scratch *s = w->s;
    for (;;) {
        uint32_t c = atomic_fetch_add(&sb->next, 1);
        if (c >= sb->chunks)
            return NULL;
        uint32_t b = sb->begin + c * (uint32_t)CHUNK_REFS, e = MINF(sb->end, b + CHUNK_REFS);
        uint32_t nb;
        if (sb->object) {
            nb = sb->object->bins;
            bvh_split_bins_fill(s, sb->refs, b, e, sb->object);
        } else {
            nb = sb->slabs->nb;
            fill_slabs(sb->sp, s, sb->refs, b, e, sb->slabs);
        }
        for (int a = 0; a < 3; a++) {
            if (!axis_binned(sb, a))
                continue;
            size_t at = ((size_t)c * 3 + a) * BVH_SPLIT_MAX_BINS;
            memcpy(&sb->bins[at], s->bins[a], nb * sizeof s->bins[a][0]);
            memcpy(&sb->counts[at], s->counts[a], nb * sizeof s->counts[a][0]);
            if (!sb->object) /* object bins count no exits */
                memcpy(&sb->exits[at], s->exits[a], nb * sizeof s->exits[a][0]);
        }
    }
}

/* Bins the node's chunks on `threads` threads and adds them up into sum (cleared first). Bins
 * are unions of boxes without -0 and counts, so the sum equals one pass over the whole range. */
static void bin_shared(shared_bins *sb, bvh_split_scratch *const *scratch, uint32_t threads,
                       uint32_t nb, bvh_split_scratch *sum)
{
    shared_worker workers[BVH_MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        workers[t] = (shared_worker){.sb = sb, .s = scratch[t]};
    atomic_store(&sb->next, 0);
    bvh_threads_run(threads, bin_chunks, workers, sizeof workers[0]);
    for (int a = 0; a < 3; a++) {
        if (!axis_binned(sb, a))
            continue;
        for (uint32_t k = 0; k < nb; k++)
            aabb_empty(&sum->bins[a][k]);
        memset(sum->counts[a], 0, nb * sizeof sum->counts[a][0]);
        memset(sum->exits[a], 0, nb * sizeof sum->exits[a][0]);
        for (uint32_t c = 0; c < sb->chunks; c++) {
            size_t at = ((size_t)c * 3 + a) * BVH_SPLIT_MAX_BINS;
            for (uint32_t k = 0; k < nb; k++) {
                aabb_grow(&sum->bins[a][k], &sb->bins[at + k]);
                sum->counts[a][k] += sb->counts[at + k];
                sum->exits[a][k] += sb->exits[at + k];
            }
        }
    }
}

bool bvh_spatial_split_shared(const bvh_split_params *p, const bvh_spatial_params *sp,
                              bvh_split_scratch *const *scratch, uint32_t threads, prim_ref *refs,
                              uint32_t begin, uint32_t end, uint32_t cap, const aabb *bounds,
                              const aabb *cbounds, bvh_split_result *out)
{
    uint32_t count = end - begin;
    if (count <= BVH_SPLIT_ALWAYS_LEAF || threads < 2) {
        bvh_spatial_split_node(p, sp, scratch[0], refs, begin, end, cap, bounds, cbounds, out);
        return true;
    }
    uint32_t chunks = (count + CHUNK_REFS - 1) / CHUNK_REFS;
    size_t slots = (size_t)chunks * 3 * BVH_SPLIT_MAX_BINS;
    shared_bins sb = {.sp = sp,
                      .refs = refs,
                      .begin = begin,
                      .end = end,
                      .chunks = chunks,
                      .bins = malloc(slots * sizeof *sb.bins),
                      .counts = calloc(slots, sizeof *sb.counts),
                      .exits = calloc(slots, sizeof *sb.exits)};
    bvh_split_scratch *sum = malloc(sizeof *sum);
    bool ok = sb.bins && sb.counts && sb.exits && sum;
    if (ok) {
        out->split = false;
        out->spatial = false;
        out->spatial = false;
        out->right_end = end;
        bvh_bin_split o;
        bvh_split_bins_init(p, count, cbounds, &o);
        sb.object = &o;
        bin_shared(&sb, scratch, threads, o.bins, sum);
        aabb child[2];
        bvh_split_kind kind = choose_object(p, sum, count, bounds, &o, child);
        spatial_split spatial = {.axis = -1, .cost = INFINITY};
        if (worth_spatial(sp, end, cap, &o, child)) {
            slabs sl = make_slabs(bounds, o.bins);
            sb.object = NULL;
            sb.slabs = &sl;
            bin_shared(&sb, scratch, threads, sl.nb, sum);
            spatial = sweep_slabs(sum, &sl);
        }
        decide(p, sp, refs, begin, end, cap, bounds, kind, &o, &spatial, out);
    }
    free(sb.bins);
    free(sb.counts);
    free(sb.exits);
    free(sum);
    return ok;
}
