/*
 * bvh.c: the CPU builder behind bvh.h, a binned surface area heuristic (SAH) BVH after Wald,
 * "On fast construction of SAH-based bounding volume hierarchies" (IEEE Symposium on Interactive
 * Ray Tracing 2007).
 *
 * How it works:
 *  1. Every triangle gets a reference record (its exact float bounding box and its index); the
 *     records are computed in parallel, one contiguous chunk per thread.
 *  2. Each node is split by bvh_split.c: the centroids of its records are binned along the 3
 *     axes, the bins are swept for the cheapest SAH split
 *     (traversal_cost + (A_left N_left + A_right N_right) / A_parent, one triangle test costs 1)
 *     and the record range is partitioned in place. Boxes and centroids are 4-lane vectors
 *     (bvh_lanes.h: SSE2 on x86-64), which halved the build: written as float arrays, every box
 *     update went through memory lane by lane.
 *     With spatial splits (desc->spatial_budget > 0) bvh_spatial.c decides instead: a node may
 *     also be cut by a plane, its triangles that cross it going to both children clipped. Every
 *     range of refs then has room past its end for duplicates (refs[end, cap)), shared out
 *     between the children in proportion to their refs, and a leaf's refs move down to follow
 *     the previous leaf's, so prim_order has no gaps.
 *  3. With more than one thread, the top levels (nodes over top_min triangles: a share of one
 *     thread's work, see TOP_JOBS_PER_THREAD) are split by all threads together, a level at a
 *     time (bvh_top.c: binning and partitioning in parallel, into the order the serial partition
 *     leaves; with spatial splits a node at a time, its bins filled by all threads,
 *     bvh_spatial_split_shared). Their children below top_min become the first jobs of the pool.
 *     The pool is desc->threads threads (the caller's thread included) sharing a
 *     stack of jobs. A job over more than SPAWN_MIN_PRIMS triangles splits its node and pushes
 *     its two children as new jobs; a smaller job builds its whole subtree alone, depth first,
 *     into its own slice of a scratch node array (the slice of a range [b, e) is nodes
 *     [2b, 2e), with spatial splits [2b, 2 cap), which never overlaps another job's, so no
 *     locking is needed).
 *  4. One serial pass over the jobs stitches them together in depth-first order, and the threads
 *     then copy the local jobs' nodes to where it put them. Every node's sibling pair
 *     is allocated when the node splits and the left subtree is laid out before the right one,
 *     both inside a job and across jobs, so the output is the same for any thread count and any
 *     scheduling: the build is deterministic.
 *
 * Node bounds are the exact unions of the triangles' float vertex coordinates (no padding; with
 * spatial splits, of their clipped parts' boxes, rounded outwards): the kernels must treat a ray
 * that touches a box face as entering it.
 */
#define _POSIX_C_SOURCE 200809L

#include "bvh.h"
#include "bvh_spatial.h"
#include "bvh_split.h"
#include "bvh_threads.h"
#include "bvh_top.h"
#include "../clock.h"

#include <math.h>
#include <stddef.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Defaults of bvh_build_desc's zero fields (bvh.h documents them). */
enum { DEFAULT_MAX_LEAF = BVH_DEFAULT_MAX_LEAF, DEFAULT_BINS = 16 };

#define DEFAULT_TRAVERSAL_COST BVH_DEFAULT_TRAVERSAL_COST

/* Limits on the descriptor: bins live in fixed per-thread arrays. */
enum { MIN_BINS = 2, MAX_BINS = BVH_SPLIT_MAX_BINS, MAX_THREADS = BVH_MAX_THREADS };

/* Jobs over more triangles than this split one node and hand both children back to the pool;
 * smaller ones build their subtree alone. Small enough that a 70k-triangle mesh yields dozens of
 * jobs for load balance, large enough that job overhead (a lock, a copy) stays negligible. */
enum { SPAWN_MIN_PRIMS = 2048 };

/* With more than one thread, nodes over top_min(n, threads) triangles are split by all threads
 * together (bvh_top.c), a level at a time, before the pool starts: a job then holds at most
 * 1 / TOP_JOBS_PER_THREAD of one thread's share, so the pool's jobs balance, and the top levels,
 * which a single thread would split in turn while the others wait, no longer run on one. Below
 * TOP_MIN_PRIMS, the chunks of bvh_top.c would be too few to share. */
enum { TOP_MIN_PRIMS = 1 << 15, TOP_JOBS_PER_THREAD = 8 };

/* bvh_node.count of an inner node (bvh.h). */
enum { INNER_NODE_COUNT = 0 };

/* A node still to be built: its place, its range of refs, its bounds. refs[end, cap) is its room
 * for the references spatial splits duplicate (none in a plain build: cap == end). */
typedef struct pending_node {
    uint32_t node;         /* index in the job's local node array */
    uint32_t begin, end, cap;
    uint32_t depth;
    aabb bounds, cbounds;
} pending_node;

enum job_kind { JOB_LOCAL, JOB_SPLIT };

typedef struct build_job {
    pending_node root;     /* root.node unused */
    enum job_kind kind;
    uint32_t child[2];     /* JOB_SPLIT: job indices of the children */
    uint32_t local_nodes;  /* JOB_LOCAL: node count in scratch_nodes[2 * root.begin ...] */
    uint32_t ref_count;    /* JOB_LOCAL: its leaves' refs, packed from refs[root.begin] on */
    uint32_t max_depth;    /* JOB_LOCAL: of its deepest leaf */
    uint32_t spatial_splits; /* JOB_LOCAL: in its subtree; JOB_SPLIT: 1 if its node's split was */
} build_job;

/* Read-only parameters and shared arrays of one build. */
typedef struct build_ctx {
    bvh_split_params sah;
    bool spatial;            /* spatial splits allowed (bvh_spatial.h) */
    bvh_spatial_params spatial_params;
    prim_ref *refs;          /* capacity: the triangles and the duplicates' budget */
    bvh_node *scratch_nodes; /* 2 * the refs' capacity: job slices */
} build_ctx;

/* Per-thread scratch: bins and the depth-first stack of a local build. */
typedef struct thread_scratch {
    bvh_split_scratch bins;
    pending_node *stack;   /* capacity: the refs' capacity (pending ranges are disjoint and non-empty) */
} thread_scratch;

/* The job pool: a LIFO stack of job indices guarded by one mutex. */
typedef struct job_pool {
    const build_ctx *ctx;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    build_job *jobs;       /* capacity 2 * refs' capacity - 1: jobs form a binary tree over ranges */
    uint32_t job_count;
    uint32_t *stack;
    uint32_t stack_len;
    uint32_t unfinished;   /* jobs queued or running; 0 ends the workers */
} job_pool;

typedef struct worker_arg {
    job_pool *pool;
    thread_scratch *scratch;
} worker_arg;

/* ------------------------------------------------------------------------ triangle records */

typedef struct ref_chunk {
    const float *positions;
    prim_ref *refs;
    uint32_t begin, end;
    aabb bounds, cbounds;
    uint32_t first_bad;    /* first triangle with a non-finite coordinate, or end */
} ref_chunk;

static void *make_refs(void *arg)
{
    ref_chunk *c = arg;
    aabb_empty(&c->bounds);
    aabb_empty(&c->cbounds);
    c->first_bad = c->end;
    for (uint32_t i = c->begin; i < c->end; i++) {
        const float *v = c->positions + (size_t)i * 9;
        prim_ref *r = &c->refs[i];
        bool finite = true;
        for (int a = 0; a < 3; a++) {
            finite = finite && isfinite(v[a]) && isfinite(v[3 + a]) && isfinite(v[6 + a]);
            /* + 0: -0 becomes +0, so that a min or max over records never depends on the order
             * it takes them in (of -0 and +0, MINPS keeps the later), which lets bvh_top.c
             * add bins up in any order and match the serial build's bounds bit for bit. */
            r->lo[a] = MINF(MINF(v[a], v[3 + a]), v[6 + a]) + 0.0f;
            r->hi[a] = MAXF(MAXF(v[a], v[3 + a]), v[6 + a]) + 0.0f;
        }
        if (!finite && c->first_bad == c->end)
            c->first_bad = i;
        r->index = i;
        r->pad = 0;
        ref_lanes l = ref_load(r);
        aabb_grow_box(&c->bounds, l.lo, l.hi);
        aabb_grow_point(&c->cbounds, l.c);
    }
    return NULL;
}

/* Fills refs in parallel and returns the root bounds; false if a coordinate is not finite. */
static bool build_refs(const float *positions, uint32_t n, uint32_t threads, prim_ref *refs,
                       aabb *bounds, aabb *cbounds, vkrt_error *err)
{
    ref_chunk chunks[MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++) {
        chunks[t] = (ref_chunk){ .positions = positions, .refs = refs,
                                 .begin = (uint32_t)((uint64_t)n * t / threads),
                                 .end = (uint32_t)((uint64_t)n * (t + 1) / threads) };
    }
    bvh_threads_run(threads, make_refs, chunks, sizeof chunks[0]);
    aabb_empty(bounds);
    aabb_empty(cbounds);
    for (uint32_t t = 0; t < threads; t++) {
        if (chunks[t].first_bad < chunks[t].end)
            return vkrt_error_set(err, "bvh: triangle %u has a non-finite vertex coordinate",
                                  chunks[t].first_bad);
        aabb_grow(bounds, &chunks[t].bounds);
        aabb_grow(cbounds, &chunks[t].cbounds);
    }
    return true;
}

/* ------------------------------------------------------------------------ building */

/* Leaf or split for one pending node (bvh_split.h, bvh_spatial.h); on a split its range is
 * partitioned. */
static void split_node(const build_ctx *ctx, thread_scratch *s, const pending_node *n,
                       bvh_split_result *out)
{
    if (ctx->spatial)
        bvh_spatial_split_node(&ctx->sah, &ctx->spatial_params, &s->bins, ctx->refs, n->begin,
                               n->end, n->cap, &n->bounds, &n->cbounds, out);
    else
        bvh_split_node(&ctx->sah, &s->bins, ctx->refs, n->begin, n->end, &n->bounds, &n->cbounds,
                       out);
}

static void set_node_bounds(bvh_node *node, const aabb *b)
{
    aabb_store(b, node->lo, node->hi);
}

/* The children of a split node. The room the parent has left past its children's refs is shared
 * in proportion to their refs (Embree shares a spatial-split budget the same way), the left's
 * part between the two: the right child's refs move up by it. */
static void child_pending(const build_ctx *ctx, const pending_node *parent,
                          const bvh_split_result *sr, pending_node child[2])
{
    uint32_t nl = sr->mid - parent->begin, nr = sr->right_end - sr->mid;
    uint32_t spare = parent->cap - sr->right_end;
    uint32_t left_spare = (uint32_t)((uint64_t)spare * nl / (nl + nr));
    if (left_spare > 0)
        memmove(ctx->refs + sr->mid + left_spare, ctx->refs + sr->mid, nr * sizeof *ctx->refs);
    for (int side = 0; side < 2; side++)
        child[side] = (pending_node){ .depth = parent->depth + 1, .bounds = sr->bounds[side],
                                      .cbounds = sr->cbounds[side] };
    child[0].begin = parent->begin;
    child[0].end = sr->mid;
    child[0].cap = sr->mid + left_spare;
    child[1].begin = sr->mid + left_spare;
    child[1].end = sr->right_end + left_spare;
    child[1].cap = parent->cap;
}

/* Builds a job's whole subtree depth first into its scratch slice: local node 0 is its root,
 * children pairs are allocated in the order nodes split, left subtree before right. Leaves are
 * made in the order of their ranges, so each leaf's refs move down to follow the previous
 * leaf's, closing the gaps of unused room (in a plain build there are none, and nothing moves). */
static void build_local(const build_ctx *ctx, thread_scratch *s, build_job *job)
{
    bvh_node *nodes = ctx->scratch_nodes + 2 * (size_t)job->root.begin;
    uint32_t used = 1, top = 0, max_depth = 0, packed = job->root.begin, spatial = 0;
    s->stack[top] = job->root;
    s->stack[top++].node = 0;
    while (top > 0) {
        pending_node n = s->stack[--top];
        bvh_node *node = &nodes[n.node];
        set_node_bounds(node, &n.bounds);
        bvh_split_result sr;
        split_node(ctx, s, &n, &sr);
        if (!sr.split) {
            uint32_t count = n.end - n.begin;
            if (packed != n.begin)
                memmove(ctx->refs + packed, ctx->refs + n.begin, count * sizeof *ctx->refs);
            node->left_first = packed;
            node->count = count;
            packed += count;
            max_depth = MAXF(max_depth, n.depth);
            continue;
        }
        node->left_first = used;
        node->count = INNER_NODE_COUNT;
        spatial += sr.spatial;
        pending_node child[2];
        child_pending(ctx, &n, &sr, child);
        child[0].node = used;
        child[1].node = used + 1;
        s->stack[top++] = child[1]; /* popped after the left one */
        s->stack[top++] = child[0];
        used += 2;
    }
    job->kind = JOB_LOCAL;
    job->local_nodes = used;
    job->max_depth = max_depth;
    job->ref_count = packed - job->root.begin;
    job->spatial_splits = spatial;
}

/* A new job over root's range, not yet queued; the caller holds pool->lock or runs alone. */
static uint32_t new_job(job_pool *pool, const pending_node *root)
{
    uint32_t j = pool->job_count++;
    pool->jobs[j] = (build_job){ .root = *root };
    return j;
}

/* Hands job j to the pool's threads; the same locking as new_job. */
static void queue_job(job_pool *pool, uint32_t j)
{
    pool->stack[pool->stack_len++] = j;
    pool->unfinished++;
}

static uint32_t push_job(job_pool *pool, const pending_node *root)
{
    uint32_t j = new_job(pool, root);
    queue_job(pool, j);
    return j;
}

static void run_job(job_pool *pool, thread_scratch *s, uint32_t j)
{
    const build_ctx *ctx = pool->ctx;
    build_job *job = &pool->jobs[j];
    if (job->root.end - job->root.begin > SPAWN_MIN_PRIMS) {
        bvh_split_result sr;
        split_node(ctx, s, &job->root, &sr);
        if (sr.split) {
            pending_node child[2];
            child_pending(ctx, &job->root, &sr, child);
            job->kind = JOB_SPLIT;
            job->spatial_splits = sr.spatial;
            pthread_mutex_lock(&pool->lock);
            job->child[0] = push_job(pool, &child[0]);
            job->child[1] = push_job(pool, &child[1]);
            pthread_cond_broadcast(&pool->wake);
            pthread_mutex_unlock(&pool->lock);
            return;
        }
    }
    build_local(ctx, s, job);
}

/* Splits a level of the top (jobs level[0, len)) with all threads: bvh_top.c's parallel binning
 * and partitioning, or with spatial splits one node after another, each node's binning shared
 * by the threads (bvh_spatial.h; applying a spatial split moves the right child's references,
 * which bvh_top.c's partition does not). False when out of memory: then a plain level is as
 * bvh_top_split left it, and a spatial node that failed comes back unsplit (split false) with
 * its references untouched; either way the pool splits what was not, to the same tree. */
static bool split_level(const build_ctx *ctx, thread_scratch **scratch, const job_pool *pool,
                        const uint32_t *level, uint32_t len, uint32_t threads,
                        bvh_top_node *nodes, bvh_split_result *split)
{
    if (ctx->spatial) {
        bvh_split_scratch *bins[MAX_THREADS];
        for (uint32_t t = 0; t < threads; t++)
            bins[t] = &scratch[t]->bins;
        for (uint32_t i = 0; i < len; i++) {
            const pending_node *r = &pool->jobs[level[i]].root;
            if (!bvh_spatial_split_shared(&ctx->sah, &ctx->spatial_params, bins, threads,
                                          ctx->refs, r->begin, r->end, r->cap, &r->bounds,
                                          &r->cbounds, &split[i]))
                split[i].split = false;
        }
        return true;
    }
    for (uint32_t i = 0; i < len; i++) {
        const pending_node *r = &pool->jobs[level[i]].root;
        nodes[i] = (bvh_top_node){
            .begin = r->begin, .end = r->end, .bounds = r->bounds, .cbounds = r->cbounds};
    }
    return bvh_top_split(&ctx->sah, ctx->refs, nodes, len, threads, split);
}

/* The top levels: the root job and then, level by level, every child over top_min triangles are
 * split by all threads together (bvh_top.c); smaller children are queued for the pool. If memory
 * for that runs out, a level's jobs are queued unsplit and the pool splits them, as it would
 * with one thread: the tree is the same either way. */
static void split_top(job_pool *pool, thread_scratch **scratch, uint32_t root_job,
                      uint32_t top_min, uint32_t threads)
{
    const build_ctx *ctx = pool->ctx;
    /* A level's nodes are disjoint and each holds over top_min references. */
    size_t cap = pool->jobs[root_job].root.cap / top_min + 1;
    uint32_t *level = malloc(cap * sizeof *level), *next = malloc(cap * sizeof *next);
    bvh_top_node *nodes = malloc(cap * sizeof *nodes);
    bvh_split_result *split = malloc(cap * sizeof *split);
    uint32_t level_len = 1;
    bool ok = level && next && nodes && split;
    if (ok)
        level[0] = root_job;
    else
        queue_job(pool, root_job);
    while (ok && level_len > 0) {
        ok = split_level(ctx, scratch, pool, level, level_len, threads, nodes, split);
        uint32_t next_len = 0;
        for (uint32_t i = 0; i < level_len; i++) {
            if (!ok || !split[i].split) {
                queue_job(pool, level[i]);
                continue;
            }
            pool->jobs[level[i]].kind = JOB_SPLIT;
            pool->jobs[level[i]].spatial_splits = split[i].spatial;
            pending_node child[2];
            child_pending(ctx, &pool->jobs[level[i]].root, &split[i], child);
            for (int side = 0; side < 2; side++) {
                uint32_t j = new_job(pool, &child[side]);
                pool->jobs[level[i]].child[side] = j;
                if (child[side].end - child[side].begin > top_min)
                    next[next_len++] = j;
                else
                    queue_job(pool, j);
            }
        }
        uint32_t *t = level;
        level = next;
        next = t;
        level_len = next_len;
    }
    free(level);
    free(next);
    free(nodes);
    free(split);
}

static void *worker(void *arg)
{
    worker_arg *w = arg;
    job_pool *pool = w->pool;
    pthread_mutex_lock(&pool->lock);
    for (;;) {
        while (pool->stack_len == 0 && pool->unfinished > 0)
            pthread_cond_wait(&pool->wake, &pool->lock);
        if (pool->stack_len == 0)
            break; /* nothing queued, nothing running: the build is done */
        uint32_t j = pool->stack[--pool->stack_len];
        pthread_mutex_unlock(&pool->lock);
        run_job(pool, w->scratch, j);
        pthread_mutex_lock(&pool->lock);
        if (--pool->unfinished == 0)
            pthread_cond_broadcast(&pool->wake);
    }
    pthread_mutex_unlock(&pool->lock);
    return NULL;
}

/* Runs the pool on `threads` threads, this one included; a thread that cannot start only
 * slows the build down. */
static void run_pool(job_pool *pool, thread_scratch **scratch, uint32_t threads)
{
    worker_arg args[MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        args[t] = (worker_arg){ .pool = pool, .scratch = scratch[t] };
    bvh_threads_run(threads, worker, args, sizeof args[0]);
}

/* ------------------------------------------------------------------------ stitching */

typedef struct stitch_item {
    uint32_t job, pos;
} stitch_item;

/* Where a local job's nodes go: its root to pos, its other nodes from base on; its refs to
 * prim_order from ref_base on. */
typedef struct local_place {
    uint32_t job, pos, base, ref_base;
} local_place;

/* Lays the job tree out depth first, left before right, as build_local does inside a job:
 * writes the split jobs' nodes and lists where every local job's nodes go, in output order.
 * Returns the node count; *place_count, the refs in leaves and the deepest leaf's depth come
 * back too. */
static uint32_t stitch(const job_pool *pool, bvh_node *out, stitch_item *stack,
                       local_place *places, uint32_t *place_count, uint32_t *ref_count,
                       uint32_t *max_depth)
{
    uint32_t used = 1, top = 0, refs = 0;
    *max_depth = 0;
    *place_count = 0;
    stack[top++] = (stitch_item){ 0, 0 };
    while (top > 0) {
        stitch_item it = stack[--top];
        const build_job *job = &pool->jobs[it.job];
        if (job->kind == JOB_LOCAL) {
            places[(*place_count)++] = (local_place){ it.job, it.pos, used, refs };
            used += job->local_nodes - 1;
            refs += job->ref_count;
            *max_depth = MAXF(*max_depth, job->max_depth);
            continue;
        }
        set_node_bounds(&out[it.pos], &job->root.bounds);
        out[it.pos].left_first = used;
        out[it.pos].count = INNER_NODE_COUNT;
        stack[top++] = (stitch_item){ job->child[1], used + 1 };
        stack[top++] = (stitch_item){ job->child[0], used };
        used += 2;
    }
    *ref_count = refs;
    return used;
}

/* One thread's share of the copy after stitch: places[begin, end). */
typedef struct copy_share {
    const build_ctx *ctx;
    const job_pool *pool;
    const local_place *places;
    uint32_t begin, end;
    bvh_node *out;
    uint32_t *prim_order;
} copy_share;

/* Copies local jobs' nodes to their places (child links and leaf ranges rebased) and their
 * triangles' original indices to prim_order; the jobs' places tile both arrays, so shares never
 * overlap. */
static void *copy_places(void *arg)
{
    const copy_share *c = arg;
    for (uint32_t p = c->begin; p < c->end; p++) {
        const local_place *pl = &c->places[p];
        const build_job *job = &c->pool->jobs[pl->job];
        const bvh_node *src = c->ctx->scratch_nodes + 2 * (size_t)job->root.begin;
        for (uint32_t i = 0; i < job->local_nodes; i++) { /* local node i >= 1 goes to base + i - 1 */
            bvh_node n = src[i];
            if (n.count == INNER_NODE_COUNT)
                n.left_first = pl->base + n.left_first - 1;
            else
                n.left_first = pl->ref_base + n.left_first - job->root.begin;
            c->out[i == 0 ? pl->pos : pl->base + i - 1] = n;
        }
        for (uint32_t i = 0; i < job->ref_count; i++)
            c->prim_order[pl->ref_base + i] = c->ctx->refs[job->root.begin + i].index;
    }
    return NULL;
}

/* Runs copy_places on `threads` threads, shares cut where the triangles covered so far cross a
 * multiple of n / threads (copying is proportional to a job's triangles). */
static void copy_all_places(const build_ctx *ctx, const job_pool *pool, const local_place *places,
                            uint32_t place_count, uint32_t n, uint32_t threads, bvh *out)
{
    copy_share shares[MAX_THREADS];
    uint32_t p = 0, covered = 0;
    for (uint32_t t = 0; t < threads; t++) {
        shares[t] = (copy_share){ .ctx = ctx, .pool = pool, .places = places, .begin = p,
                                  .out = out->nodes, .prim_order = out->prim_order };
        uint64_t target = (uint64_t)n * (t + 1) / threads;
        while (p < place_count && covered < target) {
            covered += pool->jobs[places[p++].job].ref_count;
        }
        shares[t].end = p;
    }
    bvh_threads_run(threads, copy_places, shares, sizeof shares[0]);
}

static double node_half_area(const bvh_node *n)
{
    double dx = (double)n->hi[0] - n->lo[0], dy = (double)n->hi[1] - n->lo[1];
    double dz = (double)n->hi[2] - n->lo[2];
    return dx * dy + dy * dz + dz * dx;
}

/* The tree's SAH cost is summed over blocks of this many nodes, blocks in parallel, and the
 * blocks' sums added in block order: the same float for any thread count. */
enum { SAH_BLOCK_NODES = 1 << 16 };

typedef struct sah_share {
    const bvh_node *nodes;
    uint32_t count, first_block, end_block; /* the tree's nodes; this share's blocks */
    double root_area, *block_sum;           /* in: the root's half area; out: a sum per block */
    float traversal_cost;
    uint32_t *block_leaves;                 /* out: the leaves per block */
} sah_share;

/* A tree whose root box has no area (all triangles on one line or point) weighs every node 1. */
static void *sum_sah_blocks(void *arg)
{
    const sah_share *s = arg;
    for (uint32_t k = s->first_block; k < s->end_block; k++) {
        uint32_t end = (uint32_t)MINF((uint64_t)s->count, (uint64_t)(k + 1) * SAH_BLOCK_NODES);
        double sum = 0.0;
        uint32_t leaves = 0;
        for (uint32_t i = k * SAH_BLOCK_NODES; i < end; i++) {
            const bvh_node *n = &s->nodes[i];
            double w = s->root_area > 0.0 ? node_half_area(n) / s->root_area : 1.0;
            if (n->count == INNER_NODE_COUNT) {
                sum += s->traversal_cost * w;
            } else {
                sum += n->count * w;
                leaves++;
            }
        }
        s->block_sum[k] = sum;
        s->block_leaves[k] = leaves;
    }
    return NULL;
}

/* The SAH cost of the finished tree and its leaf count; block_sum and block_leaves hold a
 * block's each. */
static float tree_sah(const bvh_node *nodes, uint32_t count, float traversal_cost, uint32_t threads,
                      double *block_sum, uint32_t *block_leaves, uint32_t *leaves)
{
    uint32_t blocks = (uint32_t)(((uint64_t)count + SAH_BLOCK_NODES - 1) / SAH_BLOCK_NODES);
    sah_share shares[MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        shares[t] = (sah_share){.nodes = nodes,
                                .count = count,
                                .root_area = node_half_area(&nodes[0]),
                                .traversal_cost = traversal_cost,
                                .first_block = (uint32_t)((uint64_t)blocks * t / threads),
                                .end_block = (uint32_t)((uint64_t)blocks * (t + 1) / threads),
                                .block_sum = block_sum,
                                .block_leaves = block_leaves};
    bvh_threads_run(threads, sum_sah_blocks, shares, sizeof shares[0]);
    double sum = 0.0;
    *leaves = 0;
    for (uint32_t k = 0; k < blocks; k++) {
        sum += block_sum[k];
        *leaves += block_leaves[k];
    }
    return (float)sum;
}

/* ------------------------------------------------------------------------ entry points */

/* Ends the stage that began at *mark: its wall-clock and processor time go to out->stages[s],
 * and *mark moves to now, where the next stage begins. */
static void end_stage(bvh *out, bvh_stage s, bvh_stage_time *mark)
{
    bvh_stage_time now = {vkrt_clock_ms(), vkrt_clock_cpu_ms()};
    out->stages[s] = (bvh_stage_time){now.wall_ms - mark->wall_ms, now.cpu_ms - mark->cpu_ms};
    *mark = now;
}

static bool read_desc(const bvh_build_desc *desc, build_ctx *ctx, uint32_t *threads,
                      vkrt_error *err)
{
    bvh_build_desc d = desc ? *desc : (bvh_build_desc){ 0 };
    ctx->sah.max_leaf = d.max_leaf_size ? d.max_leaf_size : DEFAULT_MAX_LEAF;
    ctx->sah.bins = d.bins ? d.bins : DEFAULT_BINS;
    ctx->sah.traversal_cost = d.traversal_cost != 0.0f ? d.traversal_cost : DEFAULT_TRAVERSAL_COST;
    ctx->spatial = d.spatial_budget > 0.0f;
    ctx->spatial_params = (bvh_spatial_params){ .alpha = BVH_SPATIAL_ALPHA };
    if (!(d.spatial_budget >= 0.0f && d.spatial_budget <= BVH_MAX_SPATIAL_BUDGET))
        return vkrt_error_set(err, "bvh: spatial_budget must be 0..%g, got %g",
                              (double)BVH_MAX_SPATIAL_BUDGET, (double)d.spatial_budget);
    /* 0: one per online core, at most 16 (bvh_threads.h). The tree is the same for any count. */
    *threads = d.threads ? d.threads : bvh_threads_default();
    if (ctx->sah.bins < MIN_BINS || ctx->sah.bins > MAX_BINS)
        return vkrt_error_set(err, "bvh: bins must be %d..%d, got %u", MIN_BINS, MAX_BINS,
                              ctx->sah.bins);
    if (*threads > MAX_THREADS)
        return vkrt_error_set(err, "bvh: threads must be 1..%d, got %u", MAX_THREADS, *threads);
    if (!(ctx->sah.traversal_cost > 0.0f) || !isfinite(ctx->sah.traversal_cost))
        return vkrt_error_set(err, "bvh: traversal_cost must be positive and finite, got %g",
                              (double)ctx->sah.traversal_cost);
    return true;
}

/* Everything a build allocates, freed together. */
typedef struct build_mem {
    prim_ref *refs;
    bvh_node *scratch_nodes;
    build_job *jobs;
    uint32_t *job_stack;
    stitch_item *stitch_stack;
    local_place *places;
    double *sah_block_sum;
    uint32_t *sah_block_leaves;
    thread_scratch *scratch[MAX_THREADS];
} build_mem;

static void free_mem(build_mem *m)
{
    free(m->refs);
    free(m->scratch_nodes);
    free(m->jobs);
    free(m->job_stack);
    free(m->stitch_stack);
    free(m->places);
    free(m->sah_block_sum);
    free(m->sah_block_leaves);
    for (int t = 0; t < MAX_THREADS; t++) {
        if (m->scratch[t])
            free(m->scratch[t]->stack);
        free(m->scratch[t]);
    }
}

/* n: the refs' capacity (the triangles and the duplicates' budget). */
static bool alloc_mem(build_mem *m, bvh *out, uint32_t n, uint32_t threads, vkrt_error *err)
{
    size_t max_nodes = 2 * (size_t)n - 1;
    m->refs = malloc(n * sizeof *m->refs);
    m->scratch_nodes = malloc(2 * (size_t)n * sizeof *m->scratch_nodes);
    m->jobs = malloc(max_nodes * sizeof *m->jobs);
    m->job_stack = malloc(max_nodes * sizeof *m->job_stack);
    m->stitch_stack = malloc(max_nodes * sizeof *m->stitch_stack);
    m->places = malloc(max_nodes * sizeof *m->places);
    size_t sah_blocks = max_nodes / SAH_BLOCK_NODES + 1;
    m->sah_block_sum = malloc(sah_blocks * sizeof *m->sah_block_sum);
    m->sah_block_leaves = malloc(sah_blocks * sizeof *m->sah_block_leaves);
    out->nodes = malloc(max_nodes * sizeof *out->nodes);
    out->prim_order = malloc(n * sizeof *out->prim_order);
    bool ok = m->refs && m->scratch_nodes && m->jobs && m->job_stack && m->stitch_stack &&
              m->places && m->sah_block_sum && m->sah_block_leaves && out->nodes && out->prim_order;
    for (uint32_t t = 0; ok && t < threads; t++) {
        m->scratch[t] = malloc(sizeof *m->scratch[t]);
        ok = m->scratch[t] && (m->scratch[t]->stack = malloc(n * sizeof(pending_node)));
    }
    return ok || vkrt_error_set(err, "bvh: out of memory for %u references", n);
}

bool bvh_build(bvh *out, const float *positions, uint32_t triangle_count,
               const bvh_build_desc *desc, vkrt_error *err)
{
    bvh_stage_time mark = {vkrt_clock_ms(), vkrt_clock_cpu_ms()};
    double t0 = mark.wall_ms;
    if (!out)
        return vkrt_error_set(err, "bvh: no output");
    memset(out, 0, sizeof *out);
    build_ctx ctx;
    uint32_t threads = 0;
    if (triangle_count == 0)
        return vkrt_error_set(err, "bvh: no triangles");
    if (!positions)
        return vkrt_error_set(err, "bvh: no positions for %u triangles", triangle_count);
    if (!read_desc(desc, &ctx, &threads, err))
        return false;
    /* The refs' capacity: the triangles and the duplicates spatial splits may add. */
    double capacity = floor((double)triangle_count *
                            (1.0 + (desc ? (double)desc->spatial_budget : 0.0)));
    if (capacity > UINT32_MAX / 2)
        return vkrt_error_set(err, "bvh: %u triangles%s, at most %u references", triangle_count,
                              ctx.spatial ? " with the spatial splits' budget" : "",
                              UINT32_MAX / 2);
    uint32_t cap = (uint32_t)capacity;

    build_mem m = { 0 };
    pending_node root = { .begin = 0, .end = triangle_count, .cap = cap };
    bool ok = alloc_mem(&m, out, cap, threads, err) &&
              build_refs(positions, triangle_count, threads, m.refs, &root.bounds,
                         &root.cbounds, err);
    if (!ok) {
        free_mem(&m);
        bvh_free(out);
        return false;
    }
    ctx.refs = m.refs;
    ctx.scratch_nodes = m.scratch_nodes;
    ctx.spatial_params.positions = positions;
    ctx.spatial_params.root_half_area = aabb_half_area(&root.bounds);
    end_stage(out, BVH_STAGE_REFS, &mark);

    job_pool pool = { .ctx = &ctx, .jobs = m.jobs, .stack = m.job_stack };
    pthread_mutex_init(&pool.lock, NULL);
    pthread_cond_init(&pool.wake, NULL);
    uint32_t top_min =
        MAXF((uint32_t)TOP_MIN_PRIMS, triangle_count / (threads * (uint32_t)TOP_JOBS_PER_THREAD));
    if (threads > 1 && triangle_count > top_min)
        split_top(&pool, m.scratch, new_job(&pool, &root), top_min, threads);
    else
        push_job(&pool, &root);
    end_stage(out, BVH_STAGE_TOP, &mark);
    run_pool(&pool, m.scratch, threads);
    pthread_cond_destroy(&pool.wake);
    pthread_mutex_destroy(&pool.lock);
    end_stage(out, BVH_STAGE_SUBTREES, &mark);

    uint32_t place_count;
    out->node_count = stitch(&pool, out->nodes, m.stitch_stack, m.places, &place_count,
                             &out->prim_count, &out->max_depth);
    out->triangle_count = triangle_count;
    for (uint32_t j = 0; j < pool.job_count; j++) /* every job is a node or a subtree of the tree */
        out->spatial_splits += pool.jobs[j].spatial_splits;
    copy_all_places(&ctx, &pool, m.places, place_count, out->prim_count, threads, out);
    end_stage(out, BVH_STAGE_STITCH, &mark);
    out->sah_cost = tree_sah(out->nodes, out->node_count, ctx.sah.traversal_cost, threads,
                             m.sah_block_sum, m.sah_block_leaves, &out->leaf_count);
    free_mem(&m);
    /* Shrinking cannot fail in practice; if it does, the larger block is still valid. */
    bvh_node *shrunk = realloc(out->nodes, out->node_count * sizeof *out->nodes);
    if (shrunk)
        out->nodes = shrunk;
    uint32_t *order = realloc(out->prim_order, out->prim_count * sizeof *out->prim_order);
    if (order)
        out->prim_order = order;
    end_stage(out, BVH_STAGE_FINISH, &mark);
    out->build_ms = mark.wall_ms - t0;
    return true;
}

void bvh_free(bvh *b)
{
    if (!b)
        return;
    free(b->nodes);
    free(b->prim_order);
    memset(b, 0, sizeof *b);
}

bool bvh_leaf_ref(const bvh_node *n, uint32_t *ref, vkrt_error *err)
{
    if (n->count == 0 || n->count > BVH_LEAF_REF_MAX_COUNT || n->left_first > BVH_LEAF_REF_MAX_FIRST)
        return vkrt_error_set(err, "BVH leaf of %u triangles at %u does not fit the GPU layout "
                                   "(1 to %u triangles, the first below %u)",
                              n->count, n->left_first, BVH_LEAF_REF_MAX_COUNT,
                              BVH_LEAF_REF_MAX_FIRST + 1);
    *ref = BVH_LEAF_REF | (n->count - 1) << 27 | n->left_first;
    return true;
}
