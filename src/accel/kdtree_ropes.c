/*
 * kdtree_ropes.c: the ropes of kdtree_ropes.h, by Popov et al.'s recursive pass: a node passes
 * its six ropes to its children, each child's rope across the splitting plane being its sibling,
 * and every rope is first pushed down the subtree it points to while one child alone still covers
 * the node's face.
 */
#include "kdtree_ropes.h"

#include <stdlib.h>
#include <string.h>

typedef struct rope_pass {
    kdtree *t;
    kd_rope_leaf *leaves;
    uint32_t next;
} rope_pass;

/* Rope r across face f (2 axis + high) of the box lo..hi, pushed down to the smallest node that
 * covers the whole face: a node split on the face's axis offers the child next to the face; one
 * split on another axis, the child the face lies in, if it lies in one. */
static uint32_t push_down(const kdtree *t, uint32_t r, int f, const float lo[3], const float hi[3])
{
    int k = f / 2;
    bool high = f % 2 == 1;
    while (r != KD_NO_ROPE && t->nodes[r].axis != KD_LEAF) {
        const kd_node *n = &t->nodes[r];
        if ((int)n->axis == k)
            r = high ? n->a : n->b;
        else if (n->split >= hi[n->axis])
            r = n->a;
        else if (n->split <= lo[n->axis])
            r = n->b;
        else
            break;
    }
    return r;
}

static void rope_node(rope_pass *p, uint32_t node, const uint32_t ropes_in[6], const float lo[3],
                      const float hi[3])
{
    kd_node *n = &p->t->nodes[node];
    uint32_t ropes[6];
    for (int f = 0; f < 6; ++f)
        ropes[f] = push_down(p->t, ropes_in[f], f, lo, hi);
    if (n->axis == KD_LEAF) {
        kd_rope_leaf *leaf = &p->leaves[p->next];
        memcpy(leaf->lo, lo, sizeof leaf->lo);
        memcpy(leaf->hi, hi, sizeof leaf->hi);
        memcpy(leaf->rope, ropes, sizeof leaf->rope);
        uint32_t at = p->t->node_count + KD_ROPE_TEXELS * p->next++;
        memcpy(&n->split, &at, sizeof at);
        return;
    }
    int k = (int)n->axis;
    uint32_t left = n->a, right = n->b;
    float child_lo[3], child_hi[3];
    uint32_t child_ropes[6];
    /* Below the plane: across its high face on k, the sibling above. */
    memcpy(child_lo, lo, sizeof child_lo);
    memcpy(child_hi, hi, sizeof child_hi);
    child_hi[k] = n->split;
    memcpy(child_ropes, ropes, sizeof child_ropes);
    child_ropes[2 * k + 1] = right;
    rope_node(p, left, child_ropes, child_lo, child_hi);
    /* Above it: across its low face, the sibling below. */
    memcpy(child_hi, hi, sizeof child_hi);
    child_lo[k] = n->split;
    memcpy(child_ropes, ropes, sizeof child_ropes);
    child_ropes[2 * k] = left;
    rope_node(p, right, child_ropes, child_lo, child_hi);
}

kd_rope_leaf *kdtree_ropes_build(kdtree *t, vkrt_error *err)
{
    if ((uint64_t)t->node_count + (uint64_t)KD_ROPE_TEXELS * t->leaf_count >= KD_NO_ROPE) {
        vkrt_error_set(err, "kd-tree ropes: %u nodes and %u leaves do not fit 32-bit indices",
                       t->node_count, t->leaf_count);
        return NULL;
    }
    rope_pass p = {.t = t, .leaves = malloc((t->leaf_count ? t->leaf_count : 1) *
                                            sizeof(kd_rope_leaf))};
    if (!p.leaves) {
        vkrt_error_set(err, "kd-tree ropes: out of memory for %u leaves", t->leaf_count);
        return NULL;
    }
    const uint32_t none[6] = {KD_NO_ROPE, KD_NO_ROPE, KD_NO_ROPE,
                              KD_NO_ROPE, KD_NO_ROPE, KD_NO_ROPE};
    if (t->node_count)
        rope_node(&p, 0, none, t->lo, t->hi);
    return p.leaves;
}
