/* bvh_pairs.c: the 64-byte two-box layout of bvh_pairs.h from the 32-byte tree of bvh.h. */
#include "bvh_pairs.h"

#include <stdlib.h>

/* Writes child slot k of p from node n; inner nodes get their record index later. */
static void set_child(bvh_pair *p, int k, const bvh_node *n)
{
    p->x[2 * k] = n->lo[0];
    p->x[2 * k + 1] = n->hi[0];
    p->y[2 * k] = n->lo[1];
    p->y[2 * k + 1] = n->hi[1];
    p->z[2 * k] = n->lo[2];
    p->z[2 * k + 1] = n->hi[2];
    p->ref[k] = n->left_first;
    p->count[k] = n->count;
}

bool bvh_pairs_build(const bvh *b, bvh_pair **pairs, uint32_t *count, vkrt_error *err)
{
    const bvh_node *nodes = b->nodes;
    /* A binary tree of L leaves has L - 1 inner nodes; a lone leaf still needs one record. */
    uint32_t inner = b->node_count > 1 ? (b->node_count - 1) / 2 : 1;
    bvh_pair *out = malloc((size_t)inner * sizeof *out);
    /* Depth-first walk: each entry is an inner node of b and where its parent's slot is. */
    typedef struct pending { uint32_t node, parent, slot; } pending;
    pending *stack = malloc(((size_t)b->max_depth + 2) * 2 * sizeof *stack);
    if (!out || !stack) {
        free(out);
        free(stack);
        return vkrt_error_set(err, "out of memory for %u BVH pair records", inner);
    }
    if (nodes[0].count > 0) {
        /* The whole tree is one leaf: split it, both halves under the root's box. */
        bvh_node half = nodes[0];
        half.count = (nodes[0].count + 1) / 2;
        set_child(&out[0], 0, &half);
        if (nodes[0].count > half.count) {
            half.left_first += half.count;
            half.count = nodes[0].count - half.count;
        }
        /* A one-triangle leaf is in both slots: the second test of it finds no nearer hit. */
        set_child(&out[0], 1, &half);
        *pairs = out;
        *count = 1;
        free(stack);
        return true;
    }
    uint32_t used = 0, top = 0;
    stack[top++] = (pending){0, UINT32_MAX, 0};
    while (top > 0) {
        pending e = stack[--top];
        uint32_t me = used++;
        if (e.parent != UINT32_MAX)
            out[e.parent].ref[e.slot] = me;
        uint32_t first = nodes[e.node].left_first;
        set_child(&out[me], 0, &nodes[first]);
        set_child(&out[me], 1, &nodes[first + 1]);
        /* Push b before a, so a's subtree is laid out first, right after this record. */
        for (int k = 1; k >= 0; --k)
            if (nodes[first + k].count == 0)
                stack[top++] = (pending){first + k, me, (uint32_t)k};
    }
    free(stack);
    *pairs = out;
    *count = used;
    return true;
}
