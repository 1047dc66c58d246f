/*
 * kdtree.c: the CPU builder behind kdtree.h, Wald and Havran's O(N log N) SAH kd-tree (2006,
 * their section 4; the seed thesis's Algorithms 3 and 4).
 *
 * How it works:
 *  1. Each triangle's box gives two events per axis, a start at its low side and an end at its
 *     high side, or one planar event where the box is flat on that axis (a triangle in a plane
 *     of the axis). Each axis's events are sorted once, by position and, at one position, ends
 *     before planar events before starts.
 *  2. A node's best plane is found by one sweep over each axis's events, counting the triangles
 *     left of (N_L), in (N_P) and right of (N_R) each candidate position. The SAH of a plane
 *     places the planar triangles with the side that costs less:
 *        C = lambda (K_T + K_I (P_L N_L + P_R N_R)),  P = area(child) / area(node),
 *     lambda the empty-space bonus when one side holds nothing, 1 otherwise. A node stays a leaf
 *     when no plane costs less than testing its triangles, K_I N, or at the depth limit.
 *  3. Classify and splice: one pass over the chosen axis's events marks each triangle left only,
 *     right only or both. The events of one-sided triangles keep their order in the child's
 *     lists; a triangle on both sides is clipped to each child's box, its new events sorted
 *     (there are few of those: O(sqrt N) per node for reasonable scenes, the paper argues) and
 *     merged in. No list is sorted again, so a level costs O(N) and the build O(N log N).
 *  4. Perfect splits: the events come from the triangle clipped to the node's box (in double,
 *     rounded outward to float), not from its whole box, so a plane is tried exactly where the
 *     triangle's part in the node ends.
 *  5. Subtrees of large nodes are built into arrays of their own, which are then appended in
 *     depth-first order; which of them get a thread depends only on how many are running, so
 *     the tree and its layout are the same for any thread count. Any large node may spawn, not
 *     just the top levels': long thin triangles (tools/sliver_cylinder.py) put nearly all the
 *     work under one child of the root's first splits, which cut off empty space.
 *
 * Planes at a node's own face are allowed only to cut off a flat cell holding the triangles in
 * that face (the side that keeps the node's whole box would otherwise keep all its triangles and
 * the split would never end).
 */
#define _POSIX_C_SOURCE 200809L

#include "kdtree.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../clock.h"

/* Event types, in their order at one position: a triangle that ends at p is left of a plane at p,
 * one that starts at p right of it, so sweeping in this order counts each correctly. */
enum { EVENT_END = 0, EVENT_PLANAR = 1, EVENT_START = 2 };

/* Which side of the chosen plane a triangle goes to. */
enum { SIDE_BOTH = 0, SIDE_LEFT = 1, SIDE_RIGHT = 2 };

/* Nodes of at least this many triangles build their two subtrees apart, the left in a thread when
 * one is free: a thread start costs about what a few thousand triangles' events do. */
enum { SPAWN_MIN_TRIANGLES = 4096, DEFAULT_MAX_THREADS = 16 };

typedef struct box {
    float lo[3], hi[3];
} box;

/* An event: a position on one axis (the list says which), the triangle, and its type in the two
 * low bits (the triangle in the rest: up to 2^30 triangles). */
typedef struct event {
    float pos;
    uint32_t tri_type;
} event;

typedef struct event_list {
    event *e;
    size_t n;
} event_list;

static uint32_t event_type(event e)
{
    return e.tri_type & 3u;
}
static uint32_t event_tri(event e)
{
    return e.tri_type >> 2;
}

static bool event_before(event a, event b)
{
    return a.pos < b.pos || (a.pos == b.pos && event_type(a) < event_type(b));
}

static int event_compare(const void *pa, const void *pb)
{
    event a = *(const event *)pa, b = *(const event *)pb;
    return event_before(a, b) ? -1 : event_before(b, a) ? 1 : 0;
}

static float box_area(const box *b)
{
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    return 2.0f * (dx * dy + dy * dz + dz * dx);
}

/* The float below x or x itself when x is exact; above likewise: a double rounded outward. */
static float round_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float round_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* The box of the part of triangle v (9 floats) inside b, or false when there is none. The
 * polygon is clipped to b's six planes (Sutherland and Hodgman) in double, and its box rounded
 * outward and clamped to b: it contains the exact part, so no leaf misses a triangle that enters
 * its cell. A vertex, or a clipped point's coordinate on the clipping axis, is exact and stays so:
 * a triangle in a plane of an axis keeps a flat box there, and its planar event. */
static bool clipped_box(const float *v, const box *b, box *out)
{
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        float lo = fminf(v[k], fminf(v[3 + k], v[6 + k]));
        float hi = fmaxf(v[k], fmaxf(v[3 + k], v[6 + k]));
        inside = inside && lo >= b->lo[k] && hi <= b->hi[k];
        out->lo[k] = lo;
        out->hi[k] = hi;
    }
    if (inside)
        return true;
    /* Each of the six planes adds at most one vertex. */
    double poly[2][9][3];
    int n = 3, cur = 0;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            poly[0][i][k] = v[3 * i + k];
    for (int plane = 0; plane < 6 && n > 0; ++plane) {
        int k = plane / 2;
        bool keep_above = plane % 2 == 0;
        double at = keep_above ? b->lo[k] : b->hi[k];
        const double(*in)[3] = poly[cur];
        double(*res)[3] = poly[1 - cur];
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const double *p = in[i], *q = in[(i + 1) % n];
            bool p_in = keep_above ? p[k] >= at : p[k] <= at;
            bool q_in = keep_above ? q[k] >= at : q[k] <= at;
            if (p_in)
                memcpy(res[m++], p, sizeof(double[3]));
            if (p_in != q_in) {
                double s = (at - p[k]) / (q[k] - p[k]);
                for (int j = 0; j < 3; ++j)
                    res[m][j] = p[j] + s * (q[j] - p[j]);
                res[m++][k] = at;
            }
        }
        n = m;
        cur = 1 - cur;
    }
    if (n == 0)
        return false;
    for (int k = 0; k < 3; ++k) {
        double lo = poly[cur][0][k], hi = lo;
        for (int i = 1; i < n; ++i) {
            lo = fmin(lo, poly[cur][i][k]);
            hi = fmax(hi, poly[cur][i][k]);
        }
        out->lo[k] = fmaxf(round_down(lo), b->lo[k]);
        out->hi[k] = fminf(round_up(hi), b->hi[k]);
    }
    return true;
}

/* Appends triangle tri's events for its clipped box c to the three lists (room is there). */
static void add_events(event_list ev[3], uint32_t tri, const box *c)
{
    for (int k = 0; k < 3; ++k) {
        if (c->lo[k] == c->hi[k]) {
            ev[k].e[ev[k].n++] = (event){c->lo[k], tri << 2 | EVENT_PLANAR};
        } else {
            ev[k].e[ev[k].n++] = (event){c->lo[k], tri << 2 | EVENT_START};
            ev[k].e[ev[k].n++] = (event){c->hi[k], tri << 2 | EVENT_END};
        }
    }
}

/* A plane and what it costs. */
typedef struct plane {
    float cost;
    float pos;
    int axis;
    bool planar_left; /* the triangles in the plane go left */
} plane;

/* One build's parameters, shared read-only by its threads. */
typedef struct build_params {
    const float *positions;
    uint32_t triangle_count;
    float traversal_cost, intersection_cost, empty_bonus;
    uint32_t max_depth;
    float root_area;
    uint32_t max_threads;     /* threads at once, this one included */
    atomic_uint *running;     /* threads started and not yet joined */
} build_params;

/* One builder's output: the whole tree's, or a subtree's built by a thread of its own. */
typedef struct builder {
    const build_params *p;
    uint8_t *side; /* per triangle, SIDE_*: only the current node's entries mean anything */
    kd_node *nodes;
    uint32_t node_count, node_cap;
    uint32_t *refs;
    uint32_t ref_count, ref_cap;
    uint32_t leaf_count, empty_leaves, max_depth;
    double sah;  /* sum of the nodes' cost terms, relative to the root's area */
    bool failed; /* out of memory */
} builder;

static uint32_t push_node(builder *b)
{
    if (b->node_count == b->node_cap) {
        uint32_t cap = b->node_cap ? 2 * b->node_cap : 1024;
        kd_node *grown = realloc(b->nodes, cap * sizeof *grown);
        if (!grown) {
            b->failed = true;
            return 0;
        }
        b->nodes = grown;
        b->node_cap = cap;
    }
    b->nodes[b->node_count] = (kd_node){0};
    return b->node_count++;
}

static bool reserve_refs(builder *b, uint32_t more)
{
    if (b->ref_count + (uint64_t)more <= b->ref_cap)
        return true;
    uint64_t cap = b->ref_cap ? b->ref_cap : 1024;
    while (cap < b->ref_count + (uint64_t)more)
        cap *= 2;
    uint32_t *grown = cap <= UINT32_MAX ? realloc(b->refs, cap * sizeof *grown) : NULL;
    if (!grown)
        return false;
    b->refs = grown;
    b->ref_cap = (uint32_t)cap;
    return true;
}

/* The SAH of a split into children of area fractions pl, pr holding nl, nr triangles. */
static float split_cost(const build_params *p, float pl, float pr, uint32_t nl, uint32_t nr)
{
    float c = p->traversal_cost + p->intersection_cost * (pl * (float)nl + pr * (float)nr);
    return nl == 0 || nr == 0 ? p->empty_bonus * c : c;
}

/* The cheapest plane of node v holding n triangles, by one sweep per axis (step 2 above); its
 * cost is INFINITY when no plane is allowed. */
static plane find_plane(const build_params *p, const box *v, uint32_t n, const event_list ev[3])
{
    plane best = {.cost = INFINITY};
    float area = box_area(v);
    for (int k = 0; k < 3; ++k) {
        if (v->lo[k] == v->hi[k])
            continue;
        uint32_t nl = 0, nr = n;
        const event *e = ev[k].e;
        size_t count = ev[k].n;
        for (size_t i = 0; i < count;) {
            float pos = e[i].pos;
            uint32_t ends = 0, planars = 0, starts = 0;
            while (i < count && e[i].pos == pos && event_type(e[i]) == EVENT_END)
                ++ends, ++i;
            while (i < count && e[i].pos == pos && event_type(e[i]) == EVENT_PLANAR)
                ++planars, ++i;
            while (i < count && e[i].pos == pos && event_type(e[i]) == EVENT_START)
                ++starts, ++i;
            nr -= planars + ends;
            box l = *v, r = *v;
            l.hi[k] = pos;
            r.lo[k] = pos;
            float pl = box_area(&l) / area, pr = box_area(&r) / area;
            float cost_left = split_cost(p, pl, pr, nl + planars, nr);
            float cost_right = split_cost(p, pl, pr, nl, nr + planars);
            bool left = cost_left < cost_right;
            /* At a face, only the flat cell of the triangles in it (see the top). */
            if (pos <= v->lo[k])
                left = true;
            if (pos >= v->hi[k])
                left = false;
            bool allowed = (pos > v->lo[k] && pos < v->hi[k]) || planars > 0;
            float cost = left ? cost_left : cost_right;
            if (allowed && cost < best.cost)
                best = (plane){cost, pos, k, left};
            nl += starts + planars;
        }
    }
    return best;
}

/* The child's events on one axis: the parent's events of triangles marked `want`, in order,
 * merged with the (sorted) events of the triangles clipped to the child. */
static bool splice(const event_list *parent, const uint8_t *side, uint8_t want,
                   const event_list *clipped, event_list *out)
{
    size_t kept = 0;
    for (size_t i = 0; i < parent->n; ++i)
        kept += side[event_tri(parent->e[i])] == want;
    out->n = 0;
    out->e = malloc((kept + clipped->n + 1) * sizeof *out->e);
    if (!out->e)
        return false;
    size_t i = 0, j = 0;
    while (true) {
        while (i < parent->n && side[event_tri(parent->e[i])] != want)
            ++i;
        bool have_parent = i < parent->n, have_clipped = j < clipped->n;
        if (!have_parent && !have_clipped)
            break;
        if (have_parent && (!have_clipped || !event_before(clipped->e[j], parent->e[i])))
            out->e[out->n++] = parent->e[i++];
        else
            out->e[out->n++] = clipped->e[j++];
    }
    return true;
}

static void free_lists(event_list ev[3])
{
    for (int k = 0; k < 3; ++k) {
        free(ev[k].e);
        ev[k] = (event_list){0};
    }
}

static void make_leaf(builder *b, uint32_t node, const box *v, uint32_t n, const event_list ev[3],
                      uint32_t depth)
{
    if (!reserve_refs(b, n)) {
        b->failed = true;
        return;
    }
    kd_node *leaf = &b->nodes[node];
    *leaf = (kd_node){.axis = KD_LEAF, .a = b->ref_count, .b = n};
    /* Each triangle of the node has one start or one planar event on every axis. */
    for (size_t i = 0; i < ev[0].n; ++i)
        if (event_type(ev[0].e[i]) != EVENT_END)
            b->refs[b->ref_count++] = event_tri(ev[0].e[i]);
    ++b->leaf_count;
    b->empty_leaves += n == 0;
    if (depth > b->max_depth)
        b->max_depth = depth;
    b->sah += (double)n * box_area(v) / b->p->root_area;
}

static void build_node(builder *b, uint32_t node, const box *v, uint32_t n, event_list ev[3],
                       uint32_t depth);

/* A subtree built into a builder of its own (by a thread, or in this one). */
typedef struct subtree {
    builder b;
    box v;
    uint32_t n;
    event_list ev[3];
    uint32_t depth;
} subtree;

static void *build_subtree(void *arg)
{
    subtree *s = arg;
    uint32_t root = push_node(&s->b);
    if (!s->b.failed)
        build_node(&s->b, root, &s->v, s->n, s->ev, s->depth);
    else
        free_lists(s->ev);
    return NULL;
}

/* Appends subtree s's nodes and references to b's; returns the index of its root. */
static uint32_t append_subtree(builder *b, builder *s)
{
    uint32_t node_base = b->node_count;
    if (b->node_count + (uint64_t)s->node_count > UINT32_MAX || !reserve_refs(b, s->ref_count)) {
        b->failed = true;
        return 0;
    }
    if (b->node_cap < b->node_count + s->node_count) {
        kd_node *grown = realloc(b->nodes, (b->node_count + s->node_count) * sizeof *grown);
        if (!grown) {
            b->failed = true;
            return 0;
        }
        b->nodes = grown;
        b->node_cap = b->node_count + s->node_count;
    }
    for (uint32_t i = 0; i < s->node_count; ++i) {
        kd_node nd = s->nodes[i];
        if (nd.axis == KD_LEAF) {
            nd.a += b->ref_count;
        } else {
            nd.a += node_base;
            nd.b += node_base;
        }
        b->nodes[b->node_count++] = nd;
    }
    /* A subtree of empty leaves has no reference array at all (and memcpy's pointers must not be
     * null even for zero bytes). */
    if (s->ref_count)
        memcpy(b->refs + b->ref_count, s->refs, s->ref_count * sizeof *s->refs);
    b->ref_count += s->ref_count;
    b->leaf_count += s->leaf_count;
    b->empty_leaves += s->empty_leaves;
    b->max_depth = s->max_depth > b->max_depth ? s->max_depth : b->max_depth;
    b->sah += s->sah;
    b->failed = b->failed || s->failed;
    return node_base;
}

static void builder_free(builder *b)
{
    free(b->side);
    free(b->nodes);
    free(b->refs);
    memset(b, 0, sizeof *b);
}

/* Whether another thread may start: the first thread and those running stay within max_threads. */
static bool take_thread(const build_params *p)
{
    unsigned n = atomic_load(p->running);
    while (n + 1 < p->max_threads)
        if (atomic_compare_exchange_weak(p->running, &n, n + 1))
            return true;
    return false;
}

/* Builds both children: in subtrees of their own (the left in a thread when there are threads)
 * for large nodes of the top levels, else depth first in b. */
static void build_children(builder *b, uint32_t node, const box child[2], const uint32_t count[2],
                           event_list lists[2][3], uint32_t depth)
{
    const build_params *p = b->p;
    bool spawn = count[0] + count[1] >= SPAWN_MIN_TRIANGLES;
    if (!spawn) {
        uint32_t left = push_node(b);
        if (!b->failed)
            build_node(b, left, &child[0], count[0], lists[0], depth + 1);
        else
            free_lists(lists[0]);
        uint32_t right = push_node(b);
        if (!b->failed)
            build_node(b, right, &child[1], count[1], lists[1], depth + 1);
        else
            free_lists(lists[1]);
        b->nodes[node].a = left;
        b->nodes[node].b = right;
        return;
    }
    subtree s[2];
    for (int c = 0; c < 2; ++c) {
        s[c] = (subtree){.b = {.p = p}, .v = child[c], .n = count[c], .depth = depth + 1};
        memcpy(s[c].ev, lists[c], sizeof s[c].ev);
        /* The right subtree runs in this thread, and can use this builder's side marks. */
        s[c].b.side = c == 1 ? b->side : calloc(p->triangle_count, 1);
        s[c].b.failed = !s[c].b.side;
    }
    pthread_t thread;
    bool started = take_thread(p);
    if (started && pthread_create(&thread, NULL, build_subtree, &s[0]) != 0) {
        atomic_fetch_sub(p->running, 1);
        started = false;
    }
    if (!started)
        build_subtree(&s[0]);
    build_subtree(&s[1]);
    if (started) {
        pthread_join(thread, NULL);
        atomic_fetch_sub(p->running, 1);
    }
    s[1].b.side = NULL;
    uint32_t left = append_subtree(b, &s[0].b);
    uint32_t right = append_subtree(b, &s[1].b);
    builder_free(&s[0].b);
    builder_free(&s[1].b);
    if (!b->failed) {
        b->nodes[node].a = left;
        b->nodes[node].b = right;
    }
}

/* Builds the subtree of node (already pushed) over box v and its n triangles' events ev, which it
 * frees. */
static void build_node(builder *b, uint32_t node, const box *v, uint32_t n, event_list ev[3],
                       uint32_t depth)
{
    const build_params *p = b->p;
    float area = box_area(v);
    plane best = {.cost = INFINITY};
    if (n > 0 && depth < p->max_depth && area > 0)
        best = find_plane(p, v, n, ev);
    if (!(best.cost < p->intersection_cost * (float)n)) {
        make_leaf(b, node, v, n, ev, depth);
        free_lists(ev);
        return;
    }
    b->nodes[node] = (kd_node){.split = best.pos, .axis = (uint32_t)best.axis};
    b->sah += p->traversal_cost / p->intersection_cost * area / p->root_area;

    /* Classify (step 3): every triangle of the node both, then the chosen axis's events say
     * which lie on one side only. */
    uint8_t *side = b->side;
    for (size_t i = 0; i < ev[0].n; ++i)
        side[event_tri(ev[0].e[i])] = SIDE_BOTH;
    const event_list *axis = &ev[best.axis];
    for (size_t i = 0; i < axis->n; ++i) {
        event e = axis->e[i];
        uint32_t type = event_type(e);
        if (type == EVENT_END && e.pos <= best.pos)
            side[event_tri(e)] = SIDE_LEFT;
        else if (type == EVENT_START && e.pos >= best.pos)
            side[event_tri(e)] = SIDE_RIGHT;
        else if (type == EVENT_PLANAR)
            side[event_tri(e)] = e.pos < best.pos || (e.pos == best.pos && best.planar_left)
                                     ? SIDE_LEFT
                                     : SIDE_RIGHT;
    }
    box child[2] = {*v, *v};
    child[0].hi[best.axis] = best.pos;
    child[1].lo[best.axis] = best.pos;

    /* The triangles on both sides, clipped to each child; their events sorted. */
    uint32_t both = 0, count[2] = {0, 0};
    for (size_t i = 0; i < ev[0].n; ++i) {
        if (event_type(ev[0].e[i]) == EVENT_END)
            continue;
        uint8_t s = side[event_tri(ev[0].e[i])];
        both += s == SIDE_BOTH;
        count[0] += s == SIDE_LEFT;
        count[1] += s == SIDE_RIGHT;
    }
    event_list clipped[2][3] = {{{0}}};
    bool ok = true;
    for (int c = 0; c < 2; ++c)
        for (int k = 0; k < 3; ++k) {
            clipped[c][k].e = malloc((2 * (size_t)both + 1) * sizeof(event));
            ok = ok && clipped[c][k].e;
        }
    for (size_t i = 0; ok && i < ev[0].n; ++i) {
        event e = ev[0].e[i];
        if (event_type(e) == EVENT_END || side[event_tri(e)] != SIDE_BOTH)
            continue;
        uint32_t tri = event_tri(e);
        for (int c = 0; c < 2; ++c) {
            box cb;
            if (clipped_box(p->positions + 9 * (size_t)tri, &child[c], &cb)) {
                add_events(clipped[c], tri, &cb);
                ++count[c];
            }
        }
    }
    event_list lists[2][3] = {{{0}}};
    for (int c = 0; c < 2; ++c)
        for (int k = 0; k < 3; ++k) {
            if (!ok)
                break;
            qsort(clipped[c][k].e, clipped[c][k].n, sizeof(event), event_compare);
            ok =
                splice(&ev[k], side, c == 0 ? SIDE_LEFT : SIDE_RIGHT, &clipped[c][k], &lists[c][k]);
        }
    for (int c = 0; c < 2; ++c)
        free_lists(clipped[c]);
    free_lists(ev);
    if (!ok) {
        b->failed = true;
        free_lists(lists[0]);
        free_lists(lists[1]);
        return;
    }
    build_children(b, node, child, count, lists, depth);
}

static uint32_t default_threads(void)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores < 1)
        return 1;
    return cores > DEFAULT_MAX_THREADS ? DEFAULT_MAX_THREADS : (uint32_t)cores;
}

bool kdtree_build(kdtree *out, const float *positions, uint32_t n, const kdtree_build_desc *desc,
                  vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    double start = vkrt_clock_ms();
    atomic_uint running = 0;
    kdtree_build_desc d = desc ? *desc : (kdtree_build_desc){0};
    if (n > (UINT32_MAX >> 2))
        return vkrt_error_set(err, "kd-tree: %u triangles, at most %u", n, UINT32_MAX >> 2);
    build_params p = {
        .positions = positions,
        .triangle_count = n,
        .traversal_cost = d.traversal_cost > 0 ? d.traversal_cost : KDTREE_DEFAULT_TRAVERSAL_COST,
        .intersection_cost =
            d.intersection_cost > 0 ? d.intersection_cost : KDTREE_DEFAULT_INTERSECTION_COST,
        .empty_bonus = d.empty_bonus > 0 ? d.empty_bonus : KDTREE_DEFAULT_EMPTY_BONUS,
        .max_threads = d.threads ? d.threads : default_threads(),
        .running = &running,
    };
    uint32_t havran = (uint32_t)lrint(8.0 + 1.3 * log2(n > 1 ? (double)n : 1.0));
    p.max_depth = d.max_depth ? d.max_depth : havran;
    if (p.max_depth > KDTREE_MAX_DEPTH)
        p.max_depth = KDTREE_MAX_DEPTH;

    box root = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (size_t i = 0; i < 3 * (size_t)n; ++i)
        for (int k = 0; k < 3; ++k) {
            root.lo[k] = fminf(root.lo[k], positions[3 * i + k]);
            root.hi[k] = fmaxf(root.hi[k], positions[3 * i + k]);
        }
    if (n == 0)
        root = (box){{0, 0, 0}, {0, 0, 0}};
    p.root_area = box_area(&root) > 0 ? box_area(&root) : 1.0f;

    builder b = {.p = &p, .side = calloc(n ? n : 1, 1)};
    event_list ev[3] = {{0}};
    bool ok = b.side != NULL;
    for (int k = 0; ok && k < 3; ++k) {
        ev[k].e = malloc((2 * (size_t)n + 1) * sizeof(event));
        ok = ev[k].e != NULL;
    }
    if (!ok) {
        free_lists(ev);
        builder_free(&b);
        return vkrt_error_set(err, "kd-tree: out of memory for %u triangles' events", n);
    }
    for (uint32_t t = 0; t < n; ++t) {
        box c;
        clipped_box(positions + 9 * (size_t)t, &root, &c);
        add_events(ev, t, &c);
    }
    for (int k = 0; k < 3; ++k)
        qsort(ev[k].e, ev[k].n, sizeof(event), event_compare);
    uint32_t root_node = push_node(&b);
    if (!b.failed)
        build_node(&b, root_node, &root, n, ev, 0);
    else
        free_lists(ev);
    if (b.failed) {
        builder_free(&b);
        return vkrt_error_set(err, "kd-tree: out of memory building over %u triangles", n);
    }
    *out = (kdtree){
        .nodes = b.nodes,
        .node_count = b.node_count,
        .refs = b.refs,
        .ref_count = b.ref_count,
        .leaf_count = b.leaf_count,
        .empty_leaves = b.empty_leaves,
        .max_depth = b.max_depth,
        .sah_cost = (float)b.sah,
    };
    memcpy(out->lo, root.lo, sizeof root.lo);
    memcpy(out->hi, root.hi, sizeof root.hi);
    free(b.side);
    out->build_ms = vkrt_clock_ms() - start;
    return true;
}

void kdtree_free(kdtree *t)
{
    free(t->nodes);
    free(t->refs);
    memset(t, 0, sizeof *t);
}
