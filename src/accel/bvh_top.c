/*
 * bvh_top.c: a level of big nodes split by all build threads together (bvh_top.h).
 *
 * Each node's records are cut into chunks of CHUNK_PRIMS, and the chunks of all the level's
 * nodes are the threads' tasks, handed out by an atomic counter, in three passes:
 *  1. bin: each chunk is binned on its own (bvh_split_bins_fill); each node's chunks are then
 *     added up in order and its split chosen (bvh_split_choose), as bvh_split_node would;
 *  2. classify: each record's side goes into a byte of flags, and each chunk counts its left
 *     records and collects its two sides' centroid bounds;
 *  3. swap: a node's left child is [begin, mid) with mid = begin + its left records. Hoare's
 *     partition (bvh_split.c) swaps the k-th record of [begin, mid) that belongs right, counted
 *     from begin, with the k-th of [mid, end) that belongs left, counted from end, and nothing
 *     else; so each chunk of [begin, mid) swaps its misplaced records with the partners of their
 *     ranks, found from per-chunk counts, and the order is Hoare's.
 * The children's bounds are unions of bins (exact: min and max do not round, and records hold no
 * -0, bvh.c, so no order of combining them can tell the zeros apart), their centroid bounds
 * unions of the chunks'. The tree is therefore the serial build's, byte for byte.
 */
#include "bvh_top.h"
#include "bvh_threads.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Records per task: large enough that handing out a task (one atomic add) costs nothing next to
 * it, small enough that the root of a 10 M triangle scene gives hundreds of tasks for 16
 * threads. 512 KiB of records, about what one core's cache holds. */
enum { CHUNK_PRIMS = 1 << 14 };

typedef struct chunk {
    uint32_t node; /* index into the level's nodes */
    uint32_t begin, end;
    uint32_t left;        /* records that go left (classify) */
    uint32_t wrong_left;  /* in [begin, mid) but go right: Hoare's i side */
    uint32_t wrong_right; /* in [mid, end) but go left: Hoare's j side */
    uint32_t rank_left;   /* the node's wrong_left records before this chunk */
    uint32_t rank_right;  /* the node's wrong_right records after this chunk */
    aabb cbounds[2];      /* centroid bounds of its left and right records */
} chunk;

typedef struct node_state {
    bvh_split_kind kind;
    bvh_bin_split split;
    uint32_t first_chunk, chunk_count;
    uint32_t mid;
} node_state;

typedef struct top_ctx {
    const bvh_split_params *p;
    prim_ref *refs;
    const bvh_top_node *nodes;
    node_state *state;
    chunk *chunks;
    uint32_t chunk_count;
    aabb *chunk_bins;       /* chunk c, axis a, bin k: [(c * 3 + a) * p->bins + k] */
    uint32_t *chunk_counts; /* the same layout */
    uint8_t *flags;         /* flags[i - flag_base]: refs[i] goes left */
    uint32_t flag_base;
    atomic_uint next; /* the next task of the running pass */
} top_ctx;

typedef struct top_worker {
    top_ctx *ctx;
    bvh_split_scratch *scratch;
    void (*task)(top_ctx *, bvh_split_scratch *, uint32_t);
} top_worker;

static void *run_tasks(void *arg)
{
    top_worker *w = arg;
    for (;;) {
        uint32_t c = atomic_fetch_add(&w->ctx->next, 1);
        if (c >= w->ctx->chunk_count)
            return NULL;
        w->task(w->ctx, w->scratch, c);
    }
}

/* Runs task on every chunk with `threads` threads. */
static void run_pass(top_ctx *ctx, top_worker *workers, uint32_t threads,
                     void (*task)(top_ctx *, bvh_split_scratch *, uint32_t))
{
    atomic_store(&ctx->next, 0);
    for (uint32_t t = 0; t < threads; t++)
        workers[t].task = task;
    bvh_threads_run(threads, run_tasks, workers, sizeof *workers);
}

/* ------------------------------------------------------------------------ pass 1: bins */

static void bin_chunk(top_ctx *ctx, bvh_split_scratch *s, uint32_t c)
{
    const chunk *ch = &ctx->chunks[c];
    const bvh_bin_split *b = &ctx->state[ch->node].split;
    bvh_split_bins_fill(s, ctx->refs, ch->begin, ch->end, b);
    for (int a = 0; a < 3; a++) {
        size_t at = ((size_t)c * 3 + a) * ctx->p->bins;
        memcpy(&ctx->chunk_bins[at], s->bins[a], b->bins * sizeof s->bins[a][0]);
        memcpy(&ctx->chunk_counts[at], s->counts[a], b->bins * sizeof s->counts[a][0]);
    }
}

/* Adds node i's chunks' bins up in sum, chooses its split, and for a binned one sets the
 * children's bounds from the bins. */
static void choose_split(top_ctx *ctx, bvh_split_scratch *sum, uint32_t i, bvh_split_result *out)
{
    node_state *ns = &ctx->state[i];
    const bvh_top_node *n = &ctx->nodes[i];
    bvh_bin_split *b = &ns->split;
    bvh_split_bins_fill(sum, ctx->refs, 0, 0, b); /* clears them */
    for (uint32_t c = ns->first_chunk; c < ns->first_chunk + ns->chunk_count; c++) {
        for (int a = 0; a < 3; a++) {
            size_t at = ((size_t)c * 3 + a) * ctx->p->bins;
            for (uint32_t k = 0; k < b->bins; k++) {
                aabb_grow(&sum->bins[a][k], &ctx->chunk_bins[at + k]);
                sum->counts[a][k] += ctx->chunk_counts[at + k];
            }
        }
    }
    ns->kind = bvh_split_choose(ctx->p, sum, n->end - n->begin, &n->bounds, b);
    if (ns->kind == BVH_SPLIT_BINNED) {
        bvh_split_bins_bounds(sum, b, 0, b->bin, &out->bounds[0]);
        bvh_split_bins_bounds(sum, b, b->bin, b->bins, &out->bounds[1]);
    }
}

/* ------------------------------------------------------------------------ pass 2: sides */

static void classify_chunk(top_ctx *ctx, bvh_split_scratch *s, uint32_t c)
{
    (void)s;
    chunk *ch = &ctx->chunks[c];
    const node_state *ns = &ctx->state[ch->node];
    if (ns->kind != BVH_SPLIT_BINNED)
        return;
    uint8_t *flags = ctx->flags;
    const uint32_t base = ctx->flag_base;
    const bvh_bin_split split = ns->split; /* a copy: the byte stores could alias ns */
    aabb cb[2];
    aabb_empty(&cb[0]);
    aabb_empty(&cb[1]);
    uint32_t left = 0;
    const prim_ref *refs = ctx->refs;
    for (uint32_t i = ch->begin; i < ch->end; i++) {
        ref_lanes l = ref_load(&refs[i]);
        bool goes_left = bvh_split_goes_left(&split, l.c);
        flags[i - base] = goes_left;
        left += goes_left;
        aabb_grow_point(&cb[goes_left ? 0 : 1], l.c);
    }
    ch->left = left;
    ch->cbounds[0] = cb[0];
    ch->cbounds[1] = cb[1];
}

/* Node i's mid, children's centroid bounds, and each chunk's misplaced records and their ranks.
 * False if one side is empty (binning and classifying agree, so it cannot happen). */
static bool place_mid(top_ctx *ctx, uint32_t i, bvh_split_result *out)
{
    node_state *ns = &ctx->state[i];
    chunk *first = &ctx->chunks[ns->first_chunk];
    const uint8_t *flags = ctx->flags;
    const uint32_t base = ctx->flag_base;
    uint32_t left = 0;
    aabb_empty(&out->cbounds[0]);
    aabb_empty(&out->cbounds[1]);
    for (uint32_t c = 0; c < ns->chunk_count; c++) {
        left += first[c].left;
        aabb_grow(&out->cbounds[0], &first[c].cbounds[0]);
        aabb_grow(&out->cbounds[1], &first[c].cbounds[1]);
    }
    const bvh_top_node *n = &ctx->nodes[i];
    uint32_t mid = n->begin + left;
    if (mid == n->begin || mid == n->end)
        return false;
    ns->mid = mid;
    uint32_t rank = 0;
    for (uint32_t c = 0; c < ns->chunk_count; c++) {
        chunk *ch = &first[c];
        uint32_t split_at =
            MINF(MAXF(mid, ch->begin), ch->end); /* [begin, split_at) is left of mid */
        uint32_t right_of_left = 0;
        if (split_at == ch->end) {
            right_of_left = (ch->end - ch->begin) - ch->left;
        } else {
            for (uint32_t k = ch->begin; k < split_at; k++)
                right_of_left += !flags[k - base];
        }
        uint32_t left_in_left = (split_at - ch->begin) - right_of_left;
        ch->wrong_left = right_of_left;
        ch->wrong_right = ch->left - left_in_left;
        ch->rank_left = rank;
        rank += ch->wrong_left;
    }
    rank = 0;
    for (uint32_t c = ns->chunk_count; c-- > 0;) {
        first[c].rank_right = rank;
        rank += first[c].wrong_right;
    }
    return true;
}

/* ------------------------------------------------------------------------ pass 3: swaps */

/* The position of the record of [mid, end) that belongs left and has `rank` such records after
 * it in the node. */
static uint32_t find_wrong_right(const top_ctx *ctx, const node_state *ns, uint32_t rank)
{
    const chunk *first = &ctx->chunks[ns->first_chunk];
    const uint8_t *flags = ctx->flags;
    const uint32_t base = ctx->flag_base;
    uint32_t c = ns->chunk_count - 1;
    while (first[c].rank_right > rank || first[c].rank_right + first[c].wrong_right <= rank)
        c--;
    uint32_t skip = rank - first[c].rank_right;
    uint32_t j = first[c].end - 1;
    for (;; j--) {
        if (flags[j - base] && skip-- == 0)
            return j;
    }
}

static void swap_chunk(top_ctx *ctx, bvh_split_scratch *s, uint32_t c)
{
    (void)s;
    const chunk *ch = &ctx->chunks[c];
    const node_state *ns = &ctx->state[ch->node];
    if (ns->kind != BVH_SPLIT_BINNED || ch->wrong_left == 0)
        return;
    const uint8_t *flags = ctx->flags;
    const uint32_t base = ctx->flag_base;
    prim_ref *refs = ctx->refs;
    uint32_t j = find_wrong_right(ctx, ns, ch->rank_left);
    uint32_t end = MINF(ch->end, ns->mid);
    for (uint32_t i = ch->begin; i < end; i++) {
        if (flags[i - base])
            continue;
        while (!flags[j - base])
            j--;
        prim_ref tmp = refs[i];
        refs[i] = refs[j];
        refs[j] = tmp;
        j--;
    }
}

/* ------------------------------------------------------------------------ the level */

typedef struct top_mem {
    node_state *state;
    chunk *chunks;
    aabb *chunk_bins;
    uint32_t *chunk_counts;
    uint8_t *flags;
    bvh_split_scratch *scratch; /* one per thread, and the sum after them */
} top_mem;

static void free_top_mem(top_mem *m)
{
    free(m->state);
    free(m->chunks);
    free(m->chunk_bins);
    free(m->chunk_counts);
    free(m->flags);
    free(m->scratch);
}

bool bvh_top_split(const bvh_split_params *p, prim_ref *refs, const bvh_top_node *nodes,
                   uint32_t count, uint32_t threads, bvh_split_result *out)
{
    if (count == 0)
        return true;
    uint32_t chunk_count = 0, lo = UINT32_MAX, hi = 0;
    for (uint32_t i = 0; i < count; i++) {
        chunk_count += (nodes[i].end - nodes[i].begin + CHUNK_PRIMS - 1) / CHUNK_PRIMS;
        lo = MINF(lo, nodes[i].begin);
        hi = MAXF(hi, nodes[i].end);
    }
    size_t bins = (size_t)chunk_count * 3 * p->bins;
    top_mem m = {
        .state = malloc(count * sizeof *m.state),
        .chunks = malloc(chunk_count * sizeof *m.chunks),
        .chunk_bins = malloc(bins * sizeof *m.chunk_bins),
        .chunk_counts = malloc(bins * sizeof *m.chunk_counts),
        .flags = malloc(hi - lo),
        .scratch = malloc((threads + 1) * sizeof *m.scratch),
    };
    if (!m.state || !m.chunks || !m.chunk_bins || !m.chunk_counts || !m.flags || !m.scratch) {
        free_top_mem(&m);
        return false;
    }
    top_ctx ctx = {.p = p,
                   .refs = refs,
                   .nodes = nodes,
                   .state = m.state,
                   .chunks = m.chunks,
                   .chunk_count = chunk_count,
                   .chunk_bins = m.chunk_bins,
                   .chunk_counts = m.chunk_counts,
                   .flags = m.flags,
                   .flag_base = lo};
    top_worker workers[BVH_MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        workers[t] = (top_worker){.ctx = &ctx, .scratch = &m.scratch[t]};

    uint32_t c = 0;
    for (uint32_t i = 0; i < count; i++) {
        node_state *ns = &m.state[i];
        bvh_split_bins_init(p, nodes[i].end - nodes[i].begin, &nodes[i].cbounds, &ns->split);
        ns->first_chunk = c;
        for (uint32_t b = nodes[i].begin; b < nodes[i].end; b += CHUNK_PRIMS)
            m.chunks[c++] = (chunk){
                .node = i, .begin = b, .end = MINF(nodes[i].end, b + (uint32_t)CHUNK_PRIMS)};
        ns->chunk_count = c - ns->first_chunk;
    }

    run_pass(&ctx, workers, threads, bin_chunk);
    bvh_split_scratch *sum = &m.scratch[threads];
    for (uint32_t i = 0; i < count; i++) {
        out[i].split = false;
        out[i].spatial = false;
        choose_split(&ctx, sum, i, &out[i]);
    }
    run_pass(&ctx, workers, threads, classify_chunk);
    for (uint32_t i = 0; i < count; i++) {
        node_state *ns = &m.state[i];
        if (ns->kind == BVH_SPLIT_BINNED && !place_mid(&ctx, i, &out[i]))
            ns->kind =
                nodes[i].end - nodes[i].begin > p->max_leaf ? BVH_SPLIT_MEDIAN : BVH_SPLIT_LEAF;
    }
    run_pass(&ctx, workers, threads, swap_chunk);
    for (uint32_t i = 0; i < count; i++) {
        if (m.state[i].kind == BVH_SPLIT_BINNED) {
            out[i].split = true;
            out[i].mid = m.state[i].mid;
            out[i].right_end = nodes[i].end;
        } else if (m.state[i].kind == BVH_SPLIT_MEDIAN) {
            bvh_split_median(refs, nodes[i].begin, nodes[i].end, &out[i]);
        }
    }
    free_top_mem(&m);
    return true;
}
