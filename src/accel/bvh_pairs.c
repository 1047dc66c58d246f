/* bvh_pairs.c: the 64-byte two-box layout of bvh_pairs.h from the 32-byte tree of bvh.h. */
#include "bvh_pairs.h"

#include <stdlib.h>
#include <string.h>

/* Writes child slot k of p from node n: its box, and for a leaf its reference (an inner child
 * gets its record index when that record is made). */
static bool set_child(bvh_pair *p, int k, const bvh_node *n, vkrt_error *err)
{
    p->x[2 * k] = n->lo[0];
    p->x[2 * k + 1] = n->hi[0];
    p->y[2 * k] = n->lo[1];
    p->y[2 * k + 1] = n->hi[1];
    p->z[2 * k] = n->lo[2];
    p->z[2 * k + 1] = n->hi[2];
    p->ref[k] = 0;
    return n->count == 0 || bvh_leaf_ref(n, &p->ref[k], err);
}

bool bvh_pairs_build(const bvh *b, bvh_pairs *out, vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    const bvh_node *nodes = b->nodes;
    /* A binary tree of L leaves has L - 1 inner nodes; a lone leaf still needs one record. */
    uint32_t inner = b->node_count > 1 ? (b->node_count - 1) / 2 : 1;
    bvh_pair *pairs = calloc(inner, sizeof *pairs);
    /* Depth first: at most one pending sibling per level, plus the two just pushed. */
    typedef struct pending { uint32_t node, parent, slot; } pending;
    pending *pending_nodes = malloc(((size_t)b->max_depth + 2) * sizeof *pending_nodes);
    bool ok = pairs && pending_nodes;
    if (!ok)
        vkrt_error_set(err, "out of memory for %u BVH pair records", inner);
    uint32_t used = 0, top = 0;
    if (ok && nodes[0].count > 0) {
        ok = set_child(&pairs[0], 0, &nodes[0], err) && set_child(&pairs[0], 1, &nodes[0], err);
        used = 1;
    } else if (ok) {
        pending_nodes[top++] = (pending){0, UINT32_MAX, 0};
    }
    while (ok && top > 0) {
        pending e = pending_nodes[--top];
        uint32_t me = used++;
        if (e.parent != UINT32_MAX)
            pairs[e.parent].ref[e.slot] = me;
        uint32_t first = nodes[e.node].left_first;
        ok = set_child(&pairs[me], 0, &nodes[first], err) &&
             set_child(&pairs[me], 1, &nodes[first + 1], err);
        /* Push b before a, so a's subtree is laid out first, right after this record. */
        for (int k = 1; ok && k >= 0; --k)
            if (nodes[first + k].count == 0)
                pending_nodes[top++] = (pending){first + (uint32_t)k, me, (uint32_t)k};
    }
    free(pending_nodes);
    if (!ok) {
        free(pairs);
        return false;
    }
    out->nodes = pairs;
    out->node_count = used;
    return true;
}

void bvh_pairs_free(bvh_pairs *p)
{
    free(p->nodes);
    memset(p, 0, sizeof *p);
}
