/* bvh_pairs.c: the 64-byte two-box layout of bvh_pairs.h from the 32-byte tree of bvh.h, written
 * by one thread per core (bvh_threads.h). */
#include "bvh_pairs.h"
#include "bvh_threads.h"

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

/* One thread's share of the records: the inner nodes among nodes[begin, end). */
typedef struct pairs_share {
    const bvh_node *nodes;
    bvh_pair *pairs;
    uint32_t begin, end;
    bool ok;
    vkrt_error err;
} pairs_share;

static void *write_records(void *arg)
{
    pairs_share *s = arg;
    const bvh_node *nodes = s->nodes;
    s->ok = true;
    for (uint32_t i = s->begin; s->ok && i < s->end; i++) {
        if (nodes[i].count > 0)
            continue;
        uint32_t first = nodes[i].left_first;
        bvh_pair *p = &s->pairs[record_of(&nodes[i])];
        p->unused[0] = p->unused[1] = 0;
        for (int k = 0; s->ok && k < 2; k++) {
            s->ok = set_child(p, k, &nodes[first + k], &s->err);
            if (nodes[first + k].count == 0)
                p->ref[k] = record_of(&nodes[first + k]);
        }
    }
    return NULL;
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
    /* Records are independent, so the nodes are cut into one range per thread. */
    uint32_t threads = bvh_threads_default();
    pairs_share shares[BVH_MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        shares[t] = (pairs_share){.nodes = nodes,
                                  .pairs = pairs,
                                  .begin = (uint32_t)((uint64_t)b->node_count * t / threads),
                                  .end = (uint32_t)((uint64_t)b->node_count * (t + 1) / threads)};
    if (ok)
        bvh_threads_run(threads, write_records, shares, sizeof shares[0]);
    for (uint32_t t = 0; ok && t < threads; t++) {
        ok = shares[t].ok;
        if (!ok && err)
            *err = shares[t].err;
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
