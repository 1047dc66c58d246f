/*
 * walk_profile.c: how long each of vkrt bench's rays walks the GPU's BVH, counted on the CPU, to
 * see where a dispatch's time goes when it is too small to fill the GPU for long. A profile: it
 * prints numbers and decides nothing.
 *   usage: walk-profile SCENE.cfg [WIDTH HEIGHT [LEAF COST [HEATMAP.png]]]
 * It builds the tree vkrt builds for a GPU (leaves of at most LEAF triangles, node cost COST:
 * default 2 and 0.5, src/render/accel_gpu.c), lays it out as pairs (bvh_pairs.c) and walks the
 * bench's primary rays, then its shadow and diffuse rays from those hits (src/bench_rays.c),
 * exactly as glsl/lib/traverse_bvh.glsl's pairs walk does: the same child order, one loop
 * iteration per node or leaf. The triangle test is Moller-Trumbore in double, not the kernel's
 * watertight one, so a ray through an edge may count a hit the GPU misses or the reverse; the
 * counts it prints beside the GPU's (`vkrt bench --stats`) say how close it came.
 *
 * For each ray kind it prints the loop iterations per ray (mean and percentiles) and per
 * subgroup of 32 consecutive rays, which runs as many iterations as its busiest lane; and what a
 * GPU that holds SLOTS subgroups at once would take to run the subgroups in dispatch order, each
 * taking its busiest lane's iterations, against the perfectly balanced sum / SLOTS: the share of
 * the dispatch that is its tail, and the same in reverse order and longest first. For shadow
 * rays also what the 4-wide tree of bvh_quads.h would take, the pairs walk if lanes that are
 * done took subtrees from the stacks of lanes that are not, and each ray's walk split over 2 or 4
 * lanes, one per subtree of the root's children or grandchildren (split_walks). With HEATMAP.png,
 * an image of the shadow rays' iterations per pixel (black: no shadow ray; brighter: longer
 * walks, the longest white).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "../../glsl/shared.h"
#include "accel/bvh.h"
#include "accel/bvh_pairs.h"
#include "accel/bvh_quads.h"
#include "bench_rays.h"
#include "scene/scene.h"

enum { subgroup = 32, stack_size = 64 };

/* The tree as the kernel reads it: pairs and triangles in BVH order. */
typedef struct walk_tree {
    const bvh_pair *pairs;
    const float *positions; /* 9 floats per triangle, BVH order */
    const uint32_t *prim_order;
} walk_tree;

typedef struct walk_count {
    uint32_t iterations; /* nodes plus leaves: the kernel's loop iterations */
    uint32_t nodes, tests;
} walk_count;

/* The ray's origin, direction and the kernel's safe inverse of it (traverse_bvh.glsl). */
static void ray_frame(const Ray *ray, double o[3], double d[3], double inv[3])
{
    o[0] = ray->origin.x, o[1] = ray->origin.y, o[2] = ray->origin.z;
    d[0] = ray->direction.x, d[1] = ray->direction.y, d[2] = ray->direction.z;
    for (int a = 0; a < 3; ++a)
        inv[a] = 1.0 / (fabs(d[a]) < 1e-30 ? (d[a] < 0 ? -1e-30 : 1e-30) : d[a]);
}

static bool triangle_hit(const float *p, const double o[3], const double d[3], double tmin,
                         double tmax, double *t_out, double *u_out, double *v_out)
{
    double e1[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]};
    double e2[3] = {p[6] - p[0], p[7] - p[1], p[8] - p[2]};
    double q[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
    if (det == 0.0)
        return false;
    double s[3] = {o[0] - p[0], o[1] - p[1], o[2] - p[2]};
    double u = (s[0] * q[0] + s[1] * q[1] + s[2] * q[2]) / det;
    if (u < 0.0 || u > 1.0)
        return false;
    double r[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                   s[0] * e1[1] - s[1] * e1[0]};
    double v = (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / det;
    if (v < 0.0 || u + v > 1.0)
        return false;
    double t = (e2[0] * r[0] + e2[1] * r[1] + e2[2] * r[2]) / det;
    if (!(t > tmin && t < tmax))
        return false;
    *t_out = t;
    *u_out = u;
    *v_out = v;
    return true;
}

/* One slab test of a child box of a pair: its entry distance, or INFINITY when missed. */
static double box_entry(const bvh_pair *n, int k, const double o[3], const double inv[3],
                        double tmin, double tmax)
{
    const float *planes[3] = {n->x, n->y, n->z};
    double enter = tmin, leave = tmax;
    for (int a = 0; a < 3; ++a) {
        double t0 = (planes[a][2 * k] - o[a]) * inv[a], t1 = (planes[a][2 * k + 1] - o[a]) * inv[a];
        enter = fmax(enter, fmin(t0, t1));
        leave = fmin(leave, fmax(t0, t1));
    }
    return enter <= leave * 1.0000004 ? enter : INFINITY;
}

/* traverse_bvh.glsl's one-loop pairs walk from `start` (the root is 0; VKRT_NO_HIT: nothing to
 * walk), counting; fills hit (triangle in scene order). */
static walk_count walk_from(const walk_tree *tree, const Ray *ray, bool any_hit, uint32_t start,
                            Hit *hit)
{
    walk_count c = {0};
    *hit = (Hit){ray->direction.w, 0, 0, VKRT_NO_HIT};
    if (start == VKRT_NO_HIT)
        return c;
    double o[3], d[3], inv[3];
    ray_frame(ray, o, d, inv);
    double tmin = ray->origin.w, best = ray->direction.w, bu = 0, bv = 0;
    uint32_t found = VKRT_NO_HIT, stack[stack_size];
    int top = 0;
    uint32_t ref = start;
    for (;;) {
        ++c.iterations;
        if (ref & BVH_LEAF_REF) {
            uint32_t first = ref & BVH_LEAF_REF_MAX_FIRST, count = ((ref >> 27) & 0xFu) + 1u;
            c.tests += count;
            bool any = false;
            for (uint32_t i = first; i < first + count; ++i) {
                double t, u, v;
                if (triangle_hit(tree->positions + 9 * (size_t)i, o, d, tmin, best, &t, &u, &v)) {
                    best = t, bu = u, bv = v, found = i, any = true;
                }
            }
            if (any && any_hit)
                break;
            ref = VKRT_NO_HIT;
        } else {
            const bvh_pair *n = &tree->pairs[ref];
            ++c.nodes;
            double a_in = box_entry(n, 0, o, inv, tmin, best);
            double b_in = box_entry(n, 1, o, inv, tmin, best);
            bool hit_a = a_in != INFINITY, hit_b = b_in != INFINITY;
            if (hit_a && hit_b) {
                bool a_first = any_hit || a_in <= b_in;
                if (top < stack_size)
                    stack[top++] = a_first ? n->ref[1] : n->ref[0];
                ref = a_first ? n->ref[0] : n->ref[1];
            } else {
                ref = hit_a ? n->ref[0] : hit_b ? n->ref[1] : VKRT_NO_HIT;
            }
        }
        if (ref == VKRT_NO_HIT) {
            if (top == 0)
                break;
            ref = stack[--top];
        }
    }
    *hit = (Hit){(float)best, (float)bu, (float)bv,
                     found == VKRT_NO_HIT ? VKRT_NO_HIT : tree->prim_order[found]};
    return c;
}

static walk_count walk(const walk_tree *tree, const Ray *ray, bool any_hit, Hit *hit)
{
    return walk_from(tree, ray, any_hit, 0, hit);
}

/* Where part `part` of `parts` (1, 2 or 4) of a split shadow walk starts: the root, one of its
 * children, or one of its grandchildren; VKRT_NO_HIT when that part has nothing (a leaf met
 * above its level belongs to the part whose lower bit is 0). */
static uint32_t part_start(const walk_tree *tree, uint32_t part, uint32_t parts)
{
    uint32_t ref = 0;
    for (uint32_t level = parts; level > 1; level /= 2) {
        uint32_t bit = (part / (level / 2)) & 1u;
        if (ref & BVH_LEAF_REF)
            return part % level ? VKRT_NO_HIT : ref;
        ref = tree->pairs[ref].ref[bit];
    }
    return ref;
}


/* One lane of a subgroup in the lockstep simulation of sharing: the ray it works for, the node it
 * visits next and its stack of subtrees still to visit (entries [base, top)). */
typedef struct share_lane {
    uint32_t ray, ref, base, top;
    uint32_t stack[stack_size];
} share_lane;

/* One step of lane l (a node or a leaf) of the walk for any hit; returns true when it hit. */
static bool share_step(const walk_tree *tree, const Ray *ray, share_lane *l)
{
    double o[3], d[3], inv[3];
    ray_frame(ray, o, d, inv);
    double tmin = ray->origin.w, tmax = ray->direction.w;
    uint32_t ref = l->ref;
    if (ref & BVH_LEAF_REF) {
        uint32_t first = ref & BVH_LEAF_REF_MAX_FIRST, count = ((ref >> 27) & 0xFu) + 1u;
        for (uint32_t i = first; i < first + count; ++i) {
            double t, u, v;
            if (triangle_hit(tree->positions + 9 * (size_t)i, o, d, tmin, tmax, &t, &u, &v))
                return true;
        }
        ref = VKRT_NO_HIT;
    } else {
        const bvh_pair *n = &tree->pairs[ref];
        double a_in = box_entry(n, 0, o, inv, tmin, tmax);
        double b_in = box_entry(n, 1, o, inv, tmin, tmax);
        bool hit_a = a_in != INFINITY, hit_b = b_in != INFINITY;
        if (hit_a && hit_b && l->top < stack_size)
            l->stack[l->top++] = n->ref[1];
        ref = hit_a ? n->ref[0] : hit_b ? n->ref[1] : VKRT_NO_HIT;
    }
    if (ref == VKRT_NO_HIT && l->top > l->base)
        ref = l->stack[--l->top];
    l->ref = ref;
    return false;
}

/* The loop iterations subgroup g of the any-hit rays[first, first + lanes) runs when lanes that
 * are done take the subtree nearest the root (the bottom of the stack) of a lane that has one,
 * between every two steps: how the idle lanes of a subgroup could help its longest walks. */
static uint32_t shared_subgroup(const walk_tree *tree, const Ray *rays, uint32_t first,
                                uint32_t lanes)
{
    share_lane lane[subgroup];
    bool blocked[subgroup] = {false};
    for (uint32_t i = 0; i < lanes; ++i)
        lane[i] = (share_lane){.ray = i, .ref = 0};
    uint32_t iterations = 0;
    for (;;) {
        bool any = false;
        for (uint32_t i = 0; i < lanes; ++i) {
            share_lane *l = &lane[i];
            if (l->ref == VKRT_NO_HIT || blocked[l->ray])
                continue;
            any = true;
            if (share_step(tree, &rays[first + l->ray], l))
                blocked[l->ray] = true;
        }
        if (!any)
            break;
        ++iterations;
        /* Idle lanes, in lane order, take from donors, in lane order. */
        uint32_t donor = 0;
        for (uint32_t i = 0; i < lanes; ++i) {
            share_lane *l = &lane[i];
            if (l->ref != VKRT_NO_HIT && !blocked[l->ray])
                continue;
            while (donor < lanes && !(lane[donor].top > lane[donor].base &&
                                      lane[donor].ref != VKRT_NO_HIT && !blocked[lane[donor].ray]))
                ++donor;
            if (donor == lanes)
                break;
            share_lane *d = &lane[donor++];
            l->ray = d->ray;
            l->ref = d->stack[d->base++];
            l->base = l->top = 0;
        }
    }
    return iterations;
}

/* The 4-wide walk for any hit over bvh_quads.h's nodes (their decoded boxes), children in
 * slot order: the iterations it takes. */
static uint32_t walk_quads_any(const bvh_quads *quads, const float *positions, const Ray *ray)
{
    double o[3], d[3], inv[3];
    ray_frame(ray, o, d, inv);
    double tmin = ray->origin.w, tmax = ray->direction.w;
    uint32_t stack[stack_size], ref = 0, iterations = 0;
    int top = 0;
    for (;;) {
        ++iterations;
        if (ref & BVH_LEAF_REF) {
            uint32_t first = ref & BVH_LEAF_REF_MAX_FIRST, count = ((ref >> 27) & 0xFu) + 1u;
            for (uint32_t i = first; i < first + count; ++i) {
                double t, u, v;
                if (triangle_hit(positions + 9 * (size_t)i, o, d, tmin, tmax, &t, &u, &v))
                    return iterations;
            }
            ref = VKRT_NO_HIT;
        } else {
            const bvh_quad *n = &quads->nodes[ref];
            uint32_t children = n->meta >> 24, next = VKRT_NO_HIT;
            for (uint32_t k = 0; k < children; ++k) {
                float lo[3], hi[3];
                bvh_quad_child_box(n, (int)k, lo, hi);
                double enter = tmin, leave = tmax;
                for (int a = 0; a < 3; ++a) {
                    double t0 = (lo[a] - o[a]) * inv[a], t1 = (hi[a] - o[a]) * inv[a];
                    enter = fmax(enter, fmin(t0, t1));
                    leave = fmin(leave, fmax(t0, t1));
                }
                if (enter > leave * 1.0000004)
                    continue;
                if (next == VKRT_NO_HIT)
                    next = n->ref[k];
                else if (top < stack_size)
                    stack[top++] = n->ref[k];
            }
            ref = next;
        }
        if (ref == VKRT_NO_HIT) {
            if (top == 0)
                return iterations;
            ref = stack[--top];
        }
    }
}

static int compare_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* The makespan of the subgroups in dispatch order on `slots` slots, each taking its cost, a new
 * one starting on the slot that frees first (a binary heap of finishing times). */
static double schedule(const uint32_t *cost, uint32_t count, uint32_t slots)
{
    double *heap = calloc(slots, sizeof *heap), end = 0.0;
    if (!heap)
        return -1.0;
    for (uint32_t i = 0; i < count; ++i) {
        double t = heap[0] + cost[i];
        end = t > end ? t : end;
        /* The root's slot takes subgroup i: sift its new finishing time down. */
        uint32_t k = 0;
        for (;;) {
            uint32_t l = 2 * k + 1, r = l + 1, m = l;
            if (l >= slots)
                break;
            if (r < slots && heap[r] < heap[l])
                m = r;
            if (heap[m] >= t)
                break;
            heap[k] = heap[m];
            k = m;
        }
        heap[k] = t;
    }
    free(heap);
    return end;
}

static void reverse(uint32_t *v, uint32_t count)
{
    for (uint32_t i = 0; i < count / 2; ++i) {
        uint32_t t = v[i];
        v[i] = v[count - 1 - i];
        v[count - 1 - i] = t;
    }
}

static void report(const char *kind, const walk_count *c, uint32_t count, uint32_t slots)
{
    if (count == 0) {
        printf("%s: no rays\n", kind);
        return;
    }
    uint32_t *it = malloc(count * sizeof *it);
    uint32_t groups = (count + subgroup - 1) / subgroup;
    uint32_t *widest = calloc(groups, sizeof *widest);
    if (!it || !widest) {
        fprintf(stderr, "walk-profile: out of memory\n");
        exit(1);
    }
    double nodes = 0, tests = 0, busy = 0, ran = 0;
    for (uint32_t i = 0; i < count; ++i) {
        it[i] = c[i].iterations;
        nodes += c[i].nodes;
        tests += c[i].tests;
        busy += c[i].iterations;
        if (c[i].iterations > widest[i / subgroup])
            widest[i / subgroup] = c[i].iterations;
    }
    double longest_group = 0;
    uint32_t longest_at = 0;
    for (uint32_t g = 0; g < groups; ++g) {
        ran += (double)widest[g] * subgroup;
        if (widest[g] > longest_group)
            longest_group = widest[g], longest_at = g;
    }
    double balanced = ran / subgroup / slots;
    double span = schedule(widest, groups, slots);
    /* The same subgroups in reverse, and longest first (the best order for a list schedule). */
    reverse(widest, groups);
    double reversed = schedule(widest, groups, slots);
    qsort(widest, groups, sizeof *widest, compare_u32);
    reverse(widest, groups);
    double longest_first = schedule(widest, groups, slots);
    qsort(it, count, sizeof *it, compare_u32);
    printf("%s: %u rays, %.1f nodes, %.1f triangles, %.1f iterations per ray, SIMD %.0f%%\n", kind,
           count, nodes / count, tests / count, busy / count, 100.0 * busy / ran);
    printf("  iterations per ray: median %u, 90%% %u, 99%% %u, 99.9%% %u, longest %u\n",
           it[count / 2], it[(uint32_t)(count * 0.9)], it[(uint32_t)(count * 0.99)],
           it[(uint32_t)(count * 0.999)], it[count - 1]);
    qsort(widest, groups, sizeof *widest, compare_u32);
    printf("  per subgroup (its busiest lane): median %u, 99%% %u, longest %.0f (subgroup %u of "
           "%u)\n",
           widest[groups / 2], widest[(uint32_t)(groups * 0.99)], longest_group, longest_at,
           groups);
    printf("  on %u subgroup slots in dispatch order: %.0f iterations, balanced %.0f: %.2fx, "
           "the longest subgroup alone %.0f%% of it\n",
           slots, span, balanced, span / balanced, 100.0 * longest_group / span);
    printf("  the same subgroups in reverse order %.0f, longest first %.0f\n", reversed,
           longest_first);
    free(it);
    free(widest);
}

/* The shadow rays' walks split into `parts` lanes each, lane k walking the subtree of
 * part_start(k): the subgroups' costs on `slots` slots when a ray's parts are neighbours (ray
 * major) and when each part takes its own run of the dispatch (part major), in order and in
 * reverse. */
static void split_walks(const walk_tree *w, const Ray *rays, uint32_t n, uint32_t parts,
                        uint32_t slots)
{
    uint32_t tasks = n * parts, groups = (tasks + subgroup - 1) / subgroup;
    uint32_t *it = malloc(tasks * sizeof *it), *cost = malloc(groups * sizeof *cost);
    if (!it || !cost) {
        fprintf(stderr, "walk-profile: out of memory\n");
        exit(1);
    }
    double iterations = 0;
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t k = 0; k < parts; ++k) {
            Hit h;
            it[i * parts + k] = walk_from(w, &rays[i], true, part_start(w, k, parts), &h).iterations;
            iterations += it[i * parts + k];
        }
    }
    for (int major = 0; major < 2; ++major) {
        memset(cost, 0, groups * sizeof *cost);
        uint32_t longest = 0;
        for (uint32_t t = 0; t < tasks; ++t) {
            /* Task t of the dispatch: ray major, or part major. */
            uint32_t i = major ? t / parts : (t % n) * parts + t / n;
            uint32_t g = t / subgroup;
            cost[g] = it[i] > cost[g] ? it[i] : cost[g];
            longest = cost[g] > longest ? cost[g] : longest;
        }
        double span = schedule(cost, groups, slots);
        reverse(cost, groups);
        printf("  split in %u, %s: %.1f iterations per ray, longest subgroup %u; on %u slots %.0f, "
               "reversed %.0f\n", parts, major ? "ray major" : "part major", iterations / n,
               longest, slots, span, schedule(cost, groups, slots));
    }
    free(cost);
    free(it);
}

/* What two other walks of the same shadow rays would take, in loop iterations, per subgroup and
 * on `slots` slots in dispatch order: the 4-wide tree of bvh_quads.h (its decoded boxes), and the
 * pairs with idle lanes taking subtrees from busy ones (shared_subgroup). */
static void shadow_alternatives(const walk_tree *w, const bvh *tree, const Ray *rays, uint32_t n,
                                uint32_t slots)
{
    uint32_t groups = (n + subgroup - 1) / subgroup;
    uint32_t *cost = calloc(groups, sizeof *cost);
    bvh_quads quads = {0};
    vkrt_error err = {""};
    if (!cost || !bvh_quads_build(tree, &quads, &err)) {
        fprintf(stderr, "walk-profile: %s\n", cost ? err.msg : "out of memory");
        free(cost);
        return;
    }
    double iterations = 0, longest = 0;
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t it = walk_quads_any(&quads, w->positions, &rays[i]);
        iterations += it;
        cost[i / subgroup] = it > cost[i / subgroup] ? it : cost[i / subgroup];
    }
    for (uint32_t g = 0; g < groups; ++g)
        longest = cost[g] > longest ? cost[g] : longest;
    printf("  4-wide (bvh_quads.h boxes): %.1f iterations per ray, longest subgroup %.0f; on %u "
           "slots %.0f\n", iterations / n, longest, slots, schedule(cost, groups, slots));
    bvh_quads_free(&quads);
    iterations = longest = 0;
    for (uint32_t g = 0; g < groups; ++g) {
        uint32_t lanes = n - g * subgroup < subgroup ? n - g * subgroup : subgroup;
        cost[g] = shared_subgroup(w, rays, g * subgroup, lanes);
        iterations += cost[g];
        longest = cost[g] > longest ? cost[g] : longest;
    }
    printf("  pairs, idle lanes taking subtrees: %.1f iterations per subgroup, longest %.0f; on %u "
           "slots %.0f\n", iterations / groups, longest, slots, schedule(cost, groups, slots));
    free(cost);
    for (uint32_t parts = 2; parts <= 4; parts *= 2)
        split_walks(w, rays, n, parts, slots);
}

/* walk-profile's HEATMAP.png: shadow ray i's iterations at the pixel of the primary
 * ray it comes from (its info.x, bench_shadow_rays). */
static void write_heatmap(const char *path, const walk_count *counts, const Ray *shadow, uint32_t n,
                          const Ray *primary, uint32_t width, uint32_t height)
{
    uint32_t longest = 1;
    for (uint32_t i = 0; i < n; ++i)
        longest = counts[i].iterations > longest ? counts[i].iterations : longest;
    unsigned char *img = calloc((size_t)width * height, 1);
    for (uint32_t i = 0; img && i < n; ++i) {
        double f = (double)counts[i].iterations / longest;
        img[primary[shadow[i].info.x].info.x] = (unsigned char)(40 + 215 * f);
    }
    if (!img || !stbi_write_png(path, (int)width, (int)height, 1, img, (int)width))
        fprintf(stderr, "walk-profile: could not write %s\n", path);
    free(img);
}

int main(int argc, char **argv)
{
    if (argc != 2 && argc != 4 && argc != 6 && argc != 7) {
        fprintf(stderr, "usage: walk-profile SCENE.cfg [WIDTH HEIGHT [LEAF COST [HEATMAP.png]]]\n");
        return 2;
    }
    uint32_t width = argc > 2 ? (uint32_t)atoi(argv[2]) : 1920;
    uint32_t height = argc > 3 ? (uint32_t)atoi(argv[3]) : 1080;
    uint32_t leaf = argc > 5 ? (uint32_t)atoi(argv[4]) : 2;
    float cost = argc > 5 ? (float)atof(argv[5]) : 0.5f;
    const char *heatmap = argc > 6 ? argv[6] : NULL;
    if (width < 1 || width > 8192 || height < 1 || height > 8192 || leaf < 1 || leaf > 16 ||
        !(cost > 0.0f && cost <= 100.0f)) {
        fprintf(stderr, "walk-profile: WIDTH, HEIGHT 1..8192, LEAF 1..16, COST in (0, 100]\n");
        return 2;
    }
    vkrt_scene scene = {0};
    vkrt_error err = {""};
    bvh tree = {0};
    bvh_pairs pairs = {0};
    bvh_build_desc desc = {.max_leaf_size = leaf, .traversal_cost = cost};
    if (!vkrt_scene_load_geometry(argv[1], &scene, &err) ||
        !bvh_build(&tree, scene.model.meshes[0].positions, scene.model.meshes[0].triangle_count, &desc, &err) ||
        !bvh_pairs_build(&tree, &pairs, &err)) {
        fprintf(stderr, "walk-profile: %s\n", err.msg);
        return 1;
    }
    uint32_t pixels = width * height;
    float *positions = malloc(tree.prim_count * 9 * sizeof *positions);
    Ray *primary = malloc(pixels * sizeof *primary);
    Ray *secondary = malloc(pixels * sizeof *secondary);
    Hit *hits = malloc(pixels * sizeof *hits), *scratch = malloc(pixels * sizeof *scratch);
    walk_count *counts = malloc(pixels * sizeof *counts);
    if (!positions || !primary || !secondary || !hits || !scratch || !counts) {
        fprintf(stderr, "walk-profile: out of memory\n");
        return 1;
    }
    for (uint32_t i = 0; i < tree.prim_count; ++i)
        memcpy(positions + 9 * (size_t)i, scene.model.meshes[0].positions + 9 * (size_t)tree.prim_order[i],
               9 * sizeof *positions);
    walk_tree w = {pairs.nodes, positions, tree.prim_order};
    /* 132 multiprocessors of an H100 or H200, 48 subgroups each at 40 registers per lane. */
    const uint32_t slots = 132 * 48;
    printf("%s at %ux%u, leaves <= %u, node cost %.2f: %u pair records\n", argv[1], width, height,
           leaf, (double)cost, pairs.node_count);

    bench_primary_rays(&scene.cameras[0], width, height, primary);
    uint32_t hit_count = 0;
    for (uint32_t i = 0; i < pixels; ++i) {
        counts[i] = walk(&w, &primary[i], false, &hits[i]);
        hit_count += hits[i].triangle != VKRT_NO_HIT;
    }
    report("primary", counts, pixels, slots);
    printf("  hits %u\n", hit_count);

    uint32_t n = bench_shadow_rays(&scene, primary, hits, pixels, secondary);
    uint32_t blocked = 0;
    for (uint32_t i = 0; i < n; ++i) {
        counts[i] = walk(&w, &secondary[i], true, &scratch[i]);
        blocked += scratch[i].triangle != VKRT_NO_HIT;
    }
    report("shadow", counts, n, slots);
    printf("  blocked %u\n", blocked);
    shadow_alternatives(&w, &tree, secondary, n, slots);
    if (heatmap)
        write_heatmap(heatmap, counts, secondary, n, primary, width, height);

    n = bench_diffuse_rays(&scene, primary, hits, pixels, secondary);
    for (uint32_t i = 0; i < n; ++i)
        counts[i] = walk(&w, &secondary[i], false, &scratch[i]);
    report("diffuse", counts, n, slots);

    free(counts);
    free(scratch);
    free(hits);
    free(secondary);
    free(primary);
    free(positions);
    bvh_pairs_free(&pairs);
    bvh_free(&tree);
    vkrt_scene_free(&scene);
    return 0;
}
