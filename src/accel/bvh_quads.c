/* bvh_quads.c: the collapsed, quantized 4-wide layout of bvh_quads.h from the tree of bvh.h. */
#include "bvh_quads.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Quantized planes may move one step outward after rounding (quantize_axis), so the grid spans
 * the node's box in this many steps, leaving a step of room at each end of the 0..255 range. */
enum { GRID_STEPS = 253 };

/* The float exponent field of the smallest power of two s with extent <= GRID_STEPS * s; at
 * least 1 (2^-126, so q * s stays a normal float and exact). */
static uint32_t grid_exponent(float extent)
{
    if (!(extent > 0.0f))
        return 1;
    int e;
    frexp((double)extent / GRID_STEPS, &e); /* extent / steps = m 2^e, 0.5 <= m < 1 */
    int biased = e + 127;
    return biased < 1 ? 1 : biased > 254 ? 254 : (uint32_t)biased;
}

static float exponent_scale(uint32_t e)
{
    uint32_t bits = e << 23;
    float s;
    memcpy(&s, &bits, sizeof s);
    return s;
}

/* What the kernel computes for plane q: q * scale is exact (8 bits times a power of two), so the
 * one rounding is the add's, with or without a fused multiply-add. */
static float decode(float origin, uint32_t q, float scale)
{
    return origin + (float)q * scale;
}

/* Child planes lo, hi as bytes in the grid (origin, scale), rounded outward so the decoded box
 * holds [lo, hi]: rounding of the add is monotonic, so a plane whose exact value lies outside
 * the float bound decodes outside it too; the loops catch what floor and ceil in double missed. */
static void quantize_axis(float origin, float scale, float lo, float hi, uint32_t *qlo,
                          uint32_t *qhi)
{
    double l = floor(((double)lo - origin) / scale), h = ceil(((double)hi - origin) / scale);
    uint32_t a = l < 0 ? 0 : l > 255 ? 255 : (uint32_t)l;
    uint32_t b = h < 0 ? 0 : h > 255 ? 255 : (uint32_t)h;
    while (a > 0 && decode(origin, a, scale) > lo)
        --a;
    while (b < 255 && decode(origin, b, scale) < hi)
        ++b;
    *qlo = a;
    *qhi = b;
}

static float half_area(const bvh_node *n)
{
    float d[3] = {n->hi[0] - n->lo[0], n->hi[1] - n->lo[1], n->hi[2] - n->lo[2]};
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* The binary nodes that become the children of the quad made for binary node `node`, in the
 * tree's order (so their triangle ranges stay in order): its two children, then repeatedly the
 * inner one of largest area replaced by its two. Returns how many (2..4), or 1 for a leaf root. */
static int collapse(const bvh *b, uint32_t node, uint32_t kids[4])
{
    const bvh_node *nodes = b->nodes;
    if (nodes[node].count > 0) {
        kids[0] = node;
        return 1;
    }
    int n = 2;
    kids[0] = nodes[node].left_first;
    kids[1] = nodes[node].left_first + 1;
    while (n < 4) {
        int best = -1;
        float best_area = -1.0f;
        for (int i = 0; i < n; ++i)
            if (nodes[kids[i]].count == 0 && half_area(&nodes[kids[i]]) > best_area) {
                best = i;
                best_area = half_area(&nodes[kids[i]]);
            }
        if (best < 0)
            break;
        uint32_t first = nodes[kids[best]].left_first;
        memmove(&kids[best + 2], &kids[best + 1], (size_t)(n - best - 1) * sizeof *kids);
        kids[best] = first;
        kids[best + 1] = first + 1;
        ++n;
    }
    return n;
}

/* Fills q's grid and child boxes from the binary nodes kids (count of them), under box. */
static void quantize_node(bvh_quad *q, const bvh_node *nodes, const uint32_t *kids, int count)
{
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = nodes[kids[0]].lo[a];
        hi[a] = nodes[kids[0]].hi[a];
        for (int k = 1; k < count; ++k) {
            lo[a] = fminf(lo[a], nodes[kids[k]].lo[a]);
            hi[a] = fmaxf(hi[a], nodes[kids[k]].hi[a]);
        }
    }
    memset(q, 0, sizeof *q);
    uint32_t exps[3];
    for (int a = 0; a < 3; ++a) {
        q->origin[a] = lo[a];
        /* The extent is rounded up, so the grid reaches hi even when hi - lo rounds down. */
        exps[a] = grid_exponent(nextafterf(hi[a] - lo[a], INFINITY));
        float scale = exponent_scale(exps[a]);
        for (int k = 0; k < count; ++k) {
            uint32_t ql, qh;
            quantize_axis(lo[a], scale, nodes[kids[k]].lo[a], nodes[kids[k]].hi[a], &ql, &qh);
            q->lo_hi[2 * a] |= ql << (8 * k);
            q->lo_hi[2 * a + 1] |= qh << (8 * k);
        }
    }
    q->meta = exps[0] | exps[1] << 8 | exps[2] << 16 | (uint32_t)count << 24;
}

void bvh_quad_child_box(const bvh_quad *q, int k, float lo[3], float hi[3])
{
    for (int a = 0; a < 3; ++a) {
        float scale = exponent_scale((q->meta >> (8 * a)) & 0xFFu);
        lo[a] = decode(q->origin[a], (q->lo_hi[2 * a] >> (8 * k)) & 0xFFu, scale);
        hi[a] = decode(q->origin[a], (q->lo_hi[2 * a + 1] >> (8 * k)) & 0xFFu, scale);
    }
}

bool bvh_quads_build(const bvh *b, bvh_quads *out, vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    /* Every quad but the root replaces at least one binary inner node: no more quads than those. */
    uint32_t cap = b->node_count > 1 ? (b->node_count - 1) / 2 : 1;
    typedef struct pending { uint32_t node, parent, slot, depth, stack; } pending;
    /* Depth first: at most 3 pending siblings per level of the binary tree's depth. */
    size_t pending_cap = 3 * ((size_t)b->max_depth + 2);
    bvh_quad *nodes = malloc((size_t)cap * sizeof *nodes);
    pending *pending_nodes = malloc(pending_cap * sizeof *pending_nodes);
    if (!nodes || !pending_nodes) {
        free(nodes);
        free(pending_nodes);
        return vkrt_error_set(err, "out of memory for %u BVH nodes", cap);
    }
    uint32_t used = 0, top = 0;
    pending_nodes[top++] = (pending){0, UINT32_MAX, 0, 0, 0};
    bool ok = true;
    while (ok && top > 0) {
        pending e = pending_nodes[--top];
        uint32_t me = used++;
        if (e.parent != UINT32_MAX)
            nodes[e.parent].ref[e.slot] = me;
        out->max_depth = e.depth > out->max_depth ? e.depth : out->max_depth;
        uint32_t kids[4];
        int count = collapse(b, e.node, kids);
        quantize_node(&nodes[me], b->nodes, kids, count);
        /* The kernel visits the nearest child hit next and pushes the others, leaves too. */
        uint32_t stack = e.stack + (uint32_t)count - 1;
        out->max_stack = stack > out->max_stack ? stack : out->max_stack;
        for (int k = count - 1; k >= 0; --k) {
            const bvh_node *c = &b->nodes[kids[k]];
            if (c->count == 0) {
                pending_nodes[top++] = (pending){kids[k], me, (uint32_t)k, e.depth + 1, stack};
                continue;
            }
            if (!bvh_leaf_ref(c, &nodes[me].ref[k], err)) {
                ok = false;
                break;
            }
        }
    }
    free(pending_nodes);
    if (!ok) {
        free(nodes);
        return false;
    }
    out->nodes = nodes;
    out->node_count = used;
    return true;
}

void bvh_quads_free(bvh_quads *q)
{
    free(q->nodes);
    memset(q, 0, sizeof *q);
}
