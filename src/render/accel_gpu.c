/* accel_gpu.c: build, choose and upload the acceleration structure (see accel_gpu.h). */
#include "accel_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"
#include "../accel/bvh.h"
#include "../accel/bvh_pairs.h"
#include "../accel/bvh_quads.h"
#include "../accel/kdtree.h"
#include "../clock.h"
#include "accel_cache.h"

_Static_assert(sizeof(bvh_quad) == sizeof(BvhQuad), "bvh_quad and BvhQuad must be the same bytes");
_Static_assert(sizeof(bvh_pair) == sizeof(BvhPair), "bvh_pair and BvhPair must be the same bytes");
_Static_assert(BVH_LEAF_REF == VKRT_BVH_LEAF, "one leaf flag");
_Static_assert(sizeof(kd_node) == sizeof(KdNode), "kd_node and KdNode must be the same bytes");
_Static_assert(KD_LEAF == VKRT_KD_LEAF, "one kd-tree leaf mark");
_Static_assert(KDTREE_MAX_DEPTH == VKRT_KD_STACK_SIZE,
               "the kd-tree's stack holds its deepest path");

/* The grid's arrays, taken from g (which is left empty). */
static void grid_arrays(grid *g, vkrt_accel_arrays *out)
{
    out->info = (GridInfo){
        .lo = {g->lo[0], g->lo[1], g->lo[2], 0},
        .hi = {g->hi[0], g->hi[1], g->hi[2], 0},
        .cell_size = {g->cell_size[0], g->cell_size[1], g->cell_size[2], 0},
        .dims = {g->dims[0], g->dims[1], g->dims[2], g->cell_count},
    };
    vkrt_accel_stats *s = &out->stats;
    s->bytes = sizeof out->info + ((size_t)g->cell_count + 1) * sizeof(uint32_t) +
               (size_t)g->ref_count * sizeof(uint32_t);
    s->nodes = g->cell_count;
    s->leaves = g->occupied_cells;
    s->triangles_per_leaf = g->occupied_cells ? (double)g->ref_count / g->occupied_cells : 0;
    memcpy(s->grid_dims, g->dims, sizeof s->grid_dims);
    s->max_cell_refs = g->max_cell_refs;
    s->build_ms = g->build_ms;
    out->nodes = g->cell_start;
    out->node_size = sizeof(uint32_t);
    out->node_count = (size_t)g->cell_count + 1;
    out->refs = g->refs;
    out->ref_count = g->ref_count;
    g->cell_start = NULL;
    g->refs = NULL;
    grid_free(g);
}

bool vkrt_bvh_lay_out(const bvh *b, uint32_t width, vkrt_bvh_layout *out, vkrt_error *err)
{
    if (width == 2) {
        bvh_pairs p;
        if (!bvh_pairs_build(b, &p, err))
            return false;
        /* One push per level at most: the far child of a node whose two children were hit. */
        *out = (vkrt_bvh_layout){p.nodes, p.node_count, b->max_depth, b->max_depth,
                                 p.node_count * sizeof *p.nodes, sizeof *p.nodes};
        return true;
    }
    bvh_quads q;
    if (!bvh_quads_build(b, &q, err))
        return false;
    *out = (vkrt_bvh_layout){q.nodes, q.node_count, q.max_depth, q.max_stack,
                             q.node_count * sizeof *q.nodes, sizeof *q.nodes};
    return true;
}

/* Spatial splits may add up to this share of the triangles as duplicates (with Stich's overlap
 * threshold, 1e-5): a larger budget buys little more SAH cost for many more duplicates
 * (docs/performance.md). */
static const float spatial_budget = 0.3f;

/* bvh-splits auto keeps the spatial splits' tree when its SAH cost is at least this share below
 * the plain tree's. The traversal work of primary, shadow and diffuse rays (`vkrt bench --stats`)
 * follows the SAH's change in sign but only within a few points in size, so a smaller gain does
 * not say which tree traces faster (docs/performance.md has the measurements). */
static const float spatial_margin = 0.05f;

/* Above this many triangles auto builds the plain tree alone: building both costs several times
 * one plain build, seconds at this size. */
static const uint32_t spatial_auto_limit = 2000000;

/* Builds the binary tree as desc->bvh_splits says and says why in why. */
static bool build_tree(const vkrt_accel_desc *desc, const bvh_build_desc *build,
                       const float *positions, uint32_t n, bvh *out, char *why, size_t why_size,
                       vkrt_error *err)
{
    bvh_build_desc spatial = *build;
    spatial.spatial_budget =
        desc->bvh_spatial_budget > 0 ? desc->bvh_spatial_budget : spatial_budget;
    if (desc->bvh_splits == VKRT_BVH_SPLITS_OFF) {
        snprintf(why, why_size, "no spatial splits (asked for)");
        return bvh_build(out, positions, n, build, err);
    }
    if (desc->bvh_splits == VKRT_BVH_SPLITS_ON) {
        if (!bvh_build(out, positions, n, &spatial, err))
            return false;
        snprintf(why, why_size, "spatial splits (asked for): +%.1f%% references",
                 100.0 * (out->prim_count - n) / n);
        return true;
    }
    if (n > spatial_auto_limit) {
        snprintf(why, why_size, "no spatial splits: over %u triangles", spatial_auto_limit);
        return bvh_build(out, positions, n, build, err);
    }
    /* The split tree first: where no node took a spatial split it is the plain tree itself
     * (bvh.h), and the plain build is not needed. */
    if (!bvh_build(out, positions, n, &spatial, err))
        return false;
    if (out->spatial_splits == 0) {
        snprintf(why, why_size, "no spatial splits: none pays");
        return true;
    }
    bvh plain;
    if (!bvh_build(&plain, positions, n, build, err)) {
        bvh_free(out);
        return false;
    }
    bool keep = out->sah_cost < (1.0f - spatial_margin) * plain.sah_cost;
    int used =
        snprintf(why, why_size, "%sspatial splits: SAH cost %.1f -> %.1f, +%.1f%% references",
                 keep ? "" : "no ", (double)plain.sah_cost, (double)out->sah_cost,
                 100.0 * (out->prim_count - n) / n);
    if (!keep && used > 0 && (size_t)used < why_size)
        snprintf(why + used, why_size - used, ", not %.0f%% lower", 100.0 * spatial_margin);
    double both_ms = plain.build_ms + out->build_ms;
    if (!keep) {
        bvh_free(out);
        *out = plain;
    } else {
        bvh_free(&plain);
    }
    out->build_ms = both_ms;
    return true;
}

/* The tree of a BVH as desc asks (width, leaves, node cost, spatial splits), its reason appended
 * to the stats' reason; build gets the settings the stats report. */
static bool make_bvh(vkrt_accel_arrays *a, const vkrt_accel_desc *desc, const float *positions,
                     uint32_t n, bvh *b, bvh_build_desc *build, vkrt_error *err)
{
    if (desc->bvh_max_leaf > BVH_LEAF_REF_MAX_COUNT)
        return vkrt_error_set(err, "BVH leaves of %u triangles: the GPU layouts hold at most %u",
                              desc->bvh_max_leaf, BVH_LEAF_REF_MAX_COUNT);
    if (desc->bvh_width != 2 && desc->bvh_width != 4)
        return vkrt_error_set(err, "BVH width %u: the GPU layouts are 2 and 4 wide",
                              desc->bvh_width);
    *build = (bvh_build_desc){
        .max_leaf_size = desc->bvh_max_leaf,
        .traversal_cost = desc->bvh_traversal_cost,
    };
    char why[160];
    if (!build_tree(desc, build, positions, n, b, why, sizeof why, err))
        return false;
    size_t used = strlen(a->stats.reason);
    snprintf(a->stats.reason + used, sizeof a->stats.reason - used, "; %s", why);
    return true;
}

/* Lays b out in the GPU's nodes, into a's arrays; b is freed either way. */
static bool bvh_arrays(vkrt_accel_arrays *a, const vkrt_accel_desc *desc,
                       const bvh_build_desc *build, bvh *b, vkrt_error *err)
{
    uint32_t width = desc->bvh_width;
    double start = vkrt_clock_ms();
    vkrt_bvh_layout g = {0};
    bool ok = vkrt_bvh_lay_out(b, width, &g, err);
    double layout_ms = vkrt_clock_ms() - start;
    /* glsl/lib/traverse_bvh.glsl's stack; a tree needing more would lose subtrees. */
    if (ok && g.stack > VKRT_BVH_STACK_SIZE)
        ok = vkrt_error_set(err, "BVH needs a traversal stack of %u entries, more than %u",
                            g.stack, VKRT_BVH_STACK_SIZE);
    if (ok) {
        a->nodes = g.nodes;
        a->node_size = g.node_size;
        a->node_count = g.count;
        g.nodes = NULL;
        vkrt_accel_stats *s = &a->stats;
        s->bytes = g.bytes;
        s->nodes = g.count;
        s->leaves = b->leaf_count;
        s->triangles_per_leaf = b->leaf_count ? (double)b->prim_count / b->leaf_count : 0;
        s->references = b->prim_count;
        s->max_depth = g.depth;
        s->bvh_width = width;
        s->sah_cost = b->sah_cost;
        s->bvh_max_leaf = build->max_leaf_size ? build->max_leaf_size : BVH_DEFAULT_MAX_LEAF;
        s->bvh_traversal_cost =
            build->traversal_cost > 0 ? build->traversal_cost : BVH_DEFAULT_TRAVERSAL_COST;
        /* The binary build and its layout into the GPU's nodes. */
        s->build_ms = b->build_ms + layout_ms;
        a->prim_order = b->prim_order;
        a->triangle_count = b->prim_count;
        b->prim_order = NULL;
    }
    free(g.nodes);
    bvh_free(b);
    return ok;
}

/* The kd-tree with desc's traversal cost (the ratio to a triangle test) in *ratio. */
static bool make_kdtree(const vkrt_accel_desc *desc, const float *positions, uint32_t n,
                        kdtree *t, float *ratio, vkrt_error *err)
{
    *ratio = desc->kd_traversal_cost > 0
                 ? desc->kd_traversal_cost
                 : KDTREE_DEFAULT_TRAVERSAL_COST / KDTREE_DEFAULT_INTERSECTION_COST;
    const kdtree_build_desc build = {
        .traversal_cost = *ratio * KDTREE_DEFAULT_INTERSECTION_COST,
    };
    return kdtree_build(t, positions, n, &build, err);
}

/* t's arrays, taken into a; its root box goes in the grid frame's lo and hi
 * (glsl/lib/traverse_kdtree.glsl). t is freed either way. */
static bool kdtree_arrays(vkrt_accel_arrays *a, kdtree *t, float ratio, vkrt_error *err)
{
    /* The walk's stack marks its entries in the top bit (glsl/lib/traverse_kdtree.glsl). */
    if (t->node_count > 0x7FFFFFFFu) {
        vkrt_error_set(err, "kd-tree of %u nodes: the GPU walk holds at most 2^31", t->node_count);
        kdtree_free(t);
        return false;
    }
    a->info = (GridInfo){.lo = {t->lo[0], t->lo[1], t->lo[2], 0},
                         .hi = {t->hi[0], t->hi[1], t->hi[2], 0}};
    size_t node_bytes = (size_t)t->node_count * sizeof *t->nodes;
    size_t ref_bytes = (size_t)t->ref_count * sizeof *t->refs;
    {
        vkrt_accel_stats *s = &a->stats;
        s->bytes = sizeof a->info + node_bytes + ref_bytes;
        s->nodes = t->node_count;
        s->leaves = t->leaf_count;
        s->empty_leaves = t->empty_leaves;
        s->references = t->ref_count;
        uint32_t full = t->leaf_count - t->empty_leaves;
        s->triangles_per_leaf = full ? (double)t->ref_count / full : 0;
        s->max_depth = t->max_depth;
        s->sah_cost = t->sah_cost;
        s->kd_traversal_cost = ratio;
        s->build_ms = t->build_ms;
    }
    a->nodes = t->nodes;
    a->node_size = sizeof *t->nodes;
    a->node_count = t->node_count;
    a->refs = t->refs;
    a->ref_count = t->ref_count;
    t->nodes = NULL;
    t->refs = NULL;
    kdtree_free(t);
    return true;
}

static bool build_kdtree(vkrt_accel_arrays *a, const vkrt_accel_desc *desc,
                         const float *positions, uint32_t n, vkrt_error *err)
{
    kdtree t;
    float ratio;
    return make_kdtree(desc, positions, n, &t, &ratio, err) && kdtree_arrays(a, &t, ratio, err);
}

/* The BVH; with `auto` on a GPU, held against the kd-tree where the BVH's SAH cost says its boxes
 * overlap badly (accel_kdtree_worth_trying), and the kd-tree taken if it is much cheaper. */
static bool build_bvh(vkrt_accel_arrays *a, const vkrt_accel_desc *desc, const float *positions,
                      uint32_t n, bool weigh_kdtree, vkrt_error *err)
{
    bvh b;
    bvh_build_desc build;
    if (!make_bvh(a, desc, positions, n, &b, &build, err))
        return false;
    if (!weigh_kdtree || !accel_kdtree_worth_trying(n, b.sah_cost))
        return bvh_arrays(a, desc, &build, &b, err);
    kdtree t;
    float ratio;
    if (!make_kdtree(desc, positions, n, &t, &ratio, err)) {
        bvh_free(&b);
        return false;
    }
    vkrt_accel_stats *s = &a->stats;
    /* The time of the tree not kept, added to the kept one's below. */
    double other_ms = 0;
    bool kd = accel_kdtree_wins(t.sah_cost, b.sah_cost);
    if (kd) {
        /* The GPU rule's sentence says the BVH: the kd-tree's own replaces it. */
        snprintf(s->reason, sizeof s->reason,
                 "kd-tree (the BVH's SAH cost %.1f is high for %u triangles, its boxes overlap; "
                 "the kd-tree's %.1f is under %.1f of it)",
                 (double)b.sah_cost, n, (double)t.sah_cost, accel_kdtree_cost_share());
    } else {
        size_t used = strlen(s->reason);
        snprintf(s->reason + used, sizeof s->reason - used,
                 "; its SAH cost %.1f is high for %u triangles, but the kd-tree's %.1f is not "
                 "under %.1f of it",
                 (double)b.sah_cost, n, (double)t.sah_cost, accel_kdtree_cost_share());
    }
    bool ok;
    if (kd) {
        other_ms = b.build_ms;
        bvh_free(&b);
        s->kind = VKRT_ACCEL_KDTREE;
        ok = kdtree_arrays(a, &t, ratio, err);
    } else {
        other_ms = t.build_ms;
        kdtree_free(&t);
        ok = bvh_arrays(a, desc, &build, &b, err);
    }
    s->build_ms += other_ms;
    return ok;
}

/* Which structures compete is the tuning's (tuning.c). */
static accel_device choice_device(const vkrt_accel_desc *desc)
{
    return desc->grid_competes     ? ACCEL_DEVICE_CPU_STORAGE
           : desc->kdtree_competes ? ACCEL_DEVICE_CPU_TEXELS
                                   : ACCEL_DEVICE_GPU;
}

vkrt_accel_kind vkrt_accel_gpu_predict(const vkrt_accel_desc *desc, uint32_t triangle_count)
{
    if (desc->kind != VKRT_ACCEL_AUTO)
        return desc->kind;
    accel_device device = choice_device(desc);
    if (accel_choice_needs_grid(triangle_count, device))
        return VKRT_ACCEL_AUTO;
    return accel_choose(triangle_count, device, NULL).kind;
}

bool vkrt_accel_build(const vkrt_accel_desc *desc, const float *positions,
                      uint32_t triangle_count, vkrt_accel_arrays *a, vkrt_error *err)
{
    vkrt_accel_kind kind = desc->kind;
    float grid_density = desc->grid_density;
    grid_build_desc grid_desc = {.density = grid_density};
    memset(a, 0, sizeof *a);
    a->triangle_count = triangle_count;
    vkrt_accel_stats *s = &a->stats;
    s->triangles = triangle_count;
    grid g = {0};
    bool have_grid = false;
    snprintf(s->reason, sizeof s->reason, "asked for");
    accel_device device = choice_device(desc);
    if (kind == VKRT_ACCEL_AUTO) {
        double start = vkrt_clock_ms();
        if (accel_choice_needs_grid(triangle_count, device)) {
            /* The rule's thresholds were measured at the default density. */
            if (!grid_build(&g, positions, triangle_count, NULL, err))
                return false;
            have_grid = true;
        }
        accel_choice c = accel_choose(triangle_count, device, have_grid ? &g : NULL);
        kind = c.kind;
        snprintf(s->reason, sizeof s->reason, "%s", c.reason);
        s->choose_ms = vkrt_clock_ms() - start;
    }
    s->kind = kind;
    bool ok = true;
    if (kind == VKRT_ACCEL_GRID) {
        if (have_grid && grid_density > 0) {
            grid_free(&g);
            have_grid = false;
        }
        ok = have_grid || grid_build(&g, positions, triangle_count, &grid_desc, err);
        if (ok)
            grid_arrays(&g, a);
    } else if (kind == VKRT_ACCEL_BVH) {
        ok = build_bvh(a, desc, positions, triangle_count,
                       desc->kind == VKRT_ACCEL_AUTO && device == ACCEL_DEVICE_GPU, err);
    } else if (kind == VKRT_ACCEL_KDTREE) {
        ok = build_kdtree(a, desc, positions, triangle_count, err);
    }
    grid_free(&g);
    if (!ok)
        vkrt_accel_arrays_free(a);
    return ok;
}

/* The names of a kind's three buffers, in messages. */
static void buffer_names(vkrt_accel_kind kind, const char *names[3])
{
    names[0] = kind == VKRT_ACCEL_KDTREE ? "kd-tree box" : "grid frame";
    names[1] = kind == VKRT_ACCEL_GRID     ? "grid cells"
               : kind == VKRT_ACCEL_KDTREE ? "kd-tree nodes"
                                           : "BVH nodes";
    names[2] = kind == VKRT_ACCEL_KDTREE ? "kd-tree references" : "grid references";
}

bool vkrt_accel_gpu_upload(vkrt_accel_gpu *a, gpu_context *ctx, vkrt_accel_arrays *arr,
                           vkrt_error *err)
{
    memset(a, 0, sizeof *a);
    const char *names[3];
    buffer_names(arr->stats.kind, names);
    /* A brute-force walk reads no nodes; the binding keeps a minimal buffer. */
    size_t node_size = arr->node_size ? arr->node_size : sizeof(BvhPair);
    bool ok =
        gpu_buffer_create_from(ctx, &a->info, &arr->info, sizeof arr->info, names[0], err) &&
        (arr->node_count
             ? gpu_array_create_from(ctx, &a->nodes, arr->nodes, node_size, arr->node_count,
                                     names[1], err)
             : gpu_array_create(ctx, &a->nodes, node_size, 0, names[1], err)) &&
        (arr->ref_count ? gpu_array_create_from(ctx, &a->refs, arr->refs, sizeof *arr->refs,
                                                arr->ref_count, names[2], err)
                        : gpu_array_create(ctx, &a->refs, sizeof(uint32_t), 0, names[2], err));
    a->stats = arr->stats;
    a->triangle_count = arr->triangle_count;
    a->prim_order = arr->prim_order;
    arr->prim_order = NULL;
    a->instances = arr->instances;
    memset(&arr->instances, 0, sizeof arr->instances);
    if (!ok)
        vkrt_accel_gpu_destroy(a, ctx);
    return ok;
}

bool vkrt_accel_gpu_create(vkrt_accel_gpu *a, gpu_context *ctx, const vkrt_accel_desc *desc,
                           const float *positions, uint32_t triangle_count, vkrt_error *err)
{
    memset(a, 0, sizeof *a);
    /* The structure cache (accel_cache.h): try it, else build and store. */
    vkrt_accel_cache_name name;
    vkrt_accel_arrays arr;
    bool cached = desc->kind != VKRT_ACCEL_BRUTE &&
                  vkrt_accel_cache_name_of(desc, positions, triangle_count, &name);
    if (!(cached && vkrt_accel_cache_load(&name, &arr))) {
        if (!vkrt_accel_build(desc, positions, triangle_count, &arr, err))
            return false;
        if (cached && arr.stats.kind != VKRT_ACCEL_BRUTE)
            vkrt_accel_cache_store(&name, &arr);
    }
    bool ok = vkrt_accel_gpu_upload(a, ctx, &arr, err);
    vkrt_accel_arrays_free(&arr);
    return ok;
}

void vkrt_accel_arrays_free(vkrt_accel_arrays *a)
{
    free(a->nodes);
    free(a->refs);
    free(a->prim_order);
    vkrt_instance_map_free(&a->instances);
    memset(a, 0, sizeof *a);
}

void vkrt_instance_map_free(vkrt_instance_map *m)
{
    free(m->first);
    free(m->mesh_base);
    free(m->flat_first);
    memset(m, 0, sizeof *m);
}

void vkrt_accel_gpu_destroy(vkrt_accel_gpu *a, gpu_context *ctx)
{
    gpu_array_destroy(ctx, &a->refs);
    gpu_array_destroy(ctx, &a->nodes);
    gpu_buffer_destroy(ctx, &a->info);
    free(a->prim_order);
    vkrt_instance_map_free(&a->instances);
    memset(a, 0, sizeof *a);
}

uint32_t vkrt_accel_original_triangle(const vkrt_accel_gpu *a, uint32_t i)
{
    return a->prim_order && i < a->triangle_count ? a->prim_order[i] : i;
}

uint64_t vkrt_accel_original_hit(const vkrt_accel_gpu *a, uint32_t hit_triangle)
{
    const vkrt_instance_map *m = &a->instances;
    if (m->count == 0)
        return vkrt_accel_original_triangle(a, hit_triangle);
    /* The last instance whose first triangle is at most the hit's. */
    uint32_t lo = 0, hi = m->count;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (m->first[mid] <= hit_triangle)
            lo = mid;
        else
            hi = mid;
    }
    uint32_t uploaded = m->mesh_base[lo] + (hit_triangle - m->first[lo]);
    uint32_t in_mesh = vkrt_accel_original_triangle(a, uploaded) - m->mesh_base[lo];
    return m->flat_first[lo] + in_mesh;
}
