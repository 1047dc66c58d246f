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

/* The record of inner node `node`: bvh.h lays the children of the k-th inner node in depth-first
 * order (left before right) at nodes 2k + 1 and 2k + 2, and a depth-first walk makes that node
 * the k-th record. So one pass in node order writes every record where the walk would, with no
 * stack, and reads the nodes in the order they lie. */
static uint32_t record_of(const bvh_node *node)
{
    return (node->left_first - 1) / 2;
}

bool bvh_pairs_build(const bvh *b, bvh_pairs *out, vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    const bvh_node *nodes = b->nodes;
    /* A binary tree of L leaves has L - 1 inner nodes; a lone leaf still needs one record. */
    uint32_t inner = b->node_count > 1 ? (b->node_count - 1) / 2 : 1;
    bvh_pair *pairs = malloc(inner * sizeof *pairs);
    if (!pairs)
        return vkrt_error_set(err, "out of memory for %u BVH pair records", inner);
    bool ok = true;
    if (nodes[0].count > 0) {
        pairs[0] = (bvh_pair){.ref = {0}};
        ok = set_child(&pairs[0], 0, &nodes[0], err) && set_child(&pairs[0], 1, &nodes[0], err);
    }
    for (uint32_t i = 0; ok && i < b->node_count; i++) {
        if (nodes[i].count > 0)
            continue;
        uint32_t first = nodes[i].left_first;
        bvh_pair *p = &pairs[record_of(&nodes[i])];
        p->unused[0] = p->unused[1] = 0;
        for (int k = 0; ok && k < 2; k++) {
            ok = set_child(p, k, &nodes[first + k], err);
            if (nodes[first + k].count == 0)
                p->ref[k] = record_of(&nodes[first + k]);
        }
    }
    if (!ok) {
        free(pairs);
        return false;
    }
    out->nodes = pairs;
    out->node_count = inner;
    return true;
}

void bvh_pairs_free(bvh_pairs *p)
{
    free(p->nodes);
    memset(p, 0, sizeof *p);
}
