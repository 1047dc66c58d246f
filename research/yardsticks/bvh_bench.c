/*
 * bvh_bench.c: times the BVH build (src/accel/bvh.c) and its layout into the GPU's pairs
 * (bvh_pairs.c) on one OBJ, as vkrt bench's build_ms counts them, without a GPU. A benchmark:
 * it prints numbers and decides nothing.
 *   usage: bvh-bench FILE.obj [RUNS [THREADS [LEAF COST [BUDGET]]]]
 * RUNS default 5; THREADS 0: one per core; LEAF and COST the build's largest leaf and SAH node
 * cost (bvh_build_desc; 0: bvh.h's defaults; vkrt uses 2 and 0.5 on GPUs, src/render/tuning.c);
 * BUDGET the spatial splits' budget (bvh_build_desc.spatial_budget; 0, the default: none, and
 * `bvh-splits on` is 0.3).
 * Prints each run's milliseconds (the first builds into memory the process never touched, as a
 * render's one build does), split into the build and the layout, with the processor time all
 * threads spent (what the build costs in work: over wall time, how many cores it kept busy), and
 * the smallest, median and largest; and a hash of the last tree (nodes and triangle order), the
 * same for the same tree.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "accel/bvh.h"
#include "accel/bvh_pairs.h"
#include "scene/obj/obj_load.h"

enum { max_runs = 1000 };

static double clock_ms(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static double now_ms(void)
{
    return clock_ms(CLOCK_MONOTONIC);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* FNV-1a over the bytes of the nodes and the triangle order: two builds that print the same
 * hash made the same tree (a change meant to keep the tree is checked by it). */
static uint64_t tree_hash(const bvh *b)
{
    uint64_t h = 14695981039346656037ull;
    const unsigned char *parts[2] = {(const unsigned char *)b->nodes,
                                     (const unsigned char *)b->prim_order};
    size_t sizes[2] = {b->node_count * sizeof *b->nodes, b->prim_count * sizeof *b->prim_order};
    for (int p = 0; p < 2; ++p) {
        for (size_t i = 0; i < sizes[p]; ++i)
            h = (h ^ parts[p][i]) * 1099511628211ull;
    }
    return h;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 7 || argc == 5) {
        fprintf(stderr, "usage: bvh-bench FILE.obj [RUNS [THREADS [LEAF COST [BUDGET]]]]\n");
        return 2;
    }
    int runs = argc > 2 ? atoi(argv[2]) : 5, threads = argc > 3 ? atoi(argv[3]) : 0;
    int leaf = argc > 5 ? atoi(argv[4]) : 0;
    float cost = argc > 5 ? (float)atof(argv[5]) : 0.0f;
    float budget = argc > 6 ? (float)atof(argv[6]) : 0.0f;
    if (runs < 1 || runs > max_runs || threads < 0 || threads > 64 || leaf < 0 || leaf > 16 ||
        !(cost >= 0.0f && cost <= 100.0f)) {
        fprintf(stderr, "bvh-bench: RUNS 1..%d, THREADS 0..64, LEAF 0..16, COST 0..100\n",
                max_runs);
        return 2;
    }
    vkrt_model model = {0};
    vkrt_error err = {""};
    if (!vkrt_obj_load(argv[1], &model, &err)) {
        fprintf(stderr, "bvh-bench: %s\n", err.msg);
        return 1;
    }
    const vkrt_mesh mesh = model.meshes[0]; /* an OBJ is one mesh, one identity instance */
    double ms[max_runs];
    bvh_build_desc desc = {.threads = (uint32_t)threads, .max_leaf_size = (uint32_t)leaf,
                           .traversal_cost = cost, .spatial_budget = budget};
    bvh b = {0};
    for (int r = 0; r < runs; ++r) {
        double start = now_ms(), cpu_start = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        bvh_pairs pairs = {0};
        bool built = bvh_build(&b, mesh.positions, mesh.triangle_count, &desc, &err);
        double built_at = now_ms(), cpu_built = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        if (!built || !bvh_pairs_build(&b, &pairs, &err)) {
            fprintf(stderr, "bvh-bench: %s\n", err.msg);
            return 1;
        }
        ms[r] = now_ms() - start;
        printf("run %d: %.1f ms (build %.1f ms, processor %.1f ms; pairs %.1f ms)\n", r + 1, ms[r],
               built_at - start, cpu_built - cpu_start, ms[r] - (built_at - start));
        static const char *const stage_names[BVH_STAGE_COUNT] = {"refs", "top", "subtrees",
                                                                 "stitch", "finish"};
        printf("  stages, wall / processor ms:");
        for (int s = 0; s < BVH_STAGE_COUNT; ++s)
            printf(" %s %.1f / %.1f", stage_names[s], b.stages[s].wall_ms, b.stages[s].cpu_ms);
        printf("\n");
        bvh_pairs_free(&pairs);
        if (r + 1 < runs)
            bvh_free(&b);
    }
    printf("%s: %u triangles, %u references (%+.1f%%), %u nodes, SAH %.3f, tree hash %016llx\n",
           argv[1], mesh.triangle_count, b.prim_count,
           100.0 * ((double)b.prim_count - mesh.triangle_count) / mesh.triangle_count, b.node_count,
           (double)b.sah_cost, (unsigned long long)tree_hash(&b));
    qsort(ms, runs, sizeof *ms, compare_doubles);
    printf("build and pairs layout: min %.1f ms, median %.1f ms, max %.1f ms over %d runs\n", ms[0],
           ms[runs / 2], ms[runs - 1], runs);
    bvh_free(&b);
    vkrt_model_free(&model);
    return 0;
}
