/* accel_instanced.c: the two-level BVH of an instanced scene (see accel_instanced.h). */
#include "accel_instanced.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"
#include "../accel/bvh.h"
#include "../clock.h"
#include "accel_cache.h"

_Static_assert(sizeof(Instance) % sizeof(uint32_t) == 0, "Instance records travel as words");

vkrt_instancing_counts vkrt_instancing_count(const vkrt_model *model)
{
    vkrt_instancing_counts c = {0};
    bool *used = calloc(model->mesh_count ? model->mesh_count : 1, sizeof *used);
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        uint32_t m = model->instances[i].mesh;
        if (m >= model->mesh_count)
            continue;
        c.instanced += model->meshes[m].triangle_count;
        /* Out of memory: count every instance's mesh as unique (instancing then looks cheap). */
        if (!used || !used[m])
            c.unique += model->meshes[m].triangle_count;
        if (used)
            used[m] = true;
    }
    free(used);
    return c;
}

bool vkrt_instancing_pays(const vkrt_model *model)
{
    vkrt_instancing_counts c = vkrt_instancing_count(model);
    return c.unique > 0 && c.instanced >= VKRT_INSTANCING_MIN_RATIO * c.unique;
}

void vkrt_unique_meshes_free(vkrt_unique_meshes *u)
{
    vkrt_mesh_free(&u->mesh);
    free(u->scene_material);
    free(u->mesh_base);
    memset(u, 0, sizeof *u);
}

bool vkrt_unique_meshes_make(const vkrt_model *model, const uint32_t *triangle_material,
                             const uint32_t *material_first, vkrt_unique_meshes *u,
                             vkrt_error *err)
{
    memset(u, 0, sizeof *u);
    uint32_t meshes = model->mesh_count;
    u->mesh_base = malloc((meshes ? meshes : 1) * sizeof *u->mesh_base);
    if (!u->mesh_base) {
        vkrt_unique_meshes_free(u);
        return vkrt_error_set(err, "out of memory");
    }
    for (uint32_t m = 0; m < meshes; ++m)
        u->mesh_base[m] = UINT32_MAX;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        uint32_t m = model->instances[i].mesh;
        if (m < meshes)
            u->mesh_base[m] = 0; /* used; numbered below */
    }
    uint64_t n = 0;
    bool normals = false, texcoords = false;
    for (uint32_t m = 0; m < meshes; ++m) {
        if (u->mesh_base[m] == UINT32_MAX)
            continue;
        u->mesh_base[m] = (uint32_t)n;
        n += model->meshes[m].triangle_count;
        normals = normals || model->meshes[m].normals;
        texcoords = texcoords || model->meshes[m].texcoords;
        if (n > BVH_LEAF_REF_MAX_FIRST + 1ull) {
            vkrt_unique_meshes_free(u);
            return vkrt_error_set(err,
                                  "the instanced meshes hold over %u triangles, more than the "
                                  "two-level BVH addresses",
                                  BVH_LEAF_REF_MAX_FIRST + 1u);
        }
    }
    vkrt_mesh *out = &u->mesh;
    size_t count = n ? (size_t)n : 1;
    out->triangle_count = (uint32_t)n;
    out->positions = malloc(count * 9 * sizeof(float));
    /* Zero normals where a mesh has none: the kernels then take the geometric normal. */
    out->normals = normals ? calloc(count, 9 * sizeof(float)) : NULL;
    out->texcoords = texcoords ? calloc(count, 6 * sizeof(float)) : NULL;
    u->scene_material = malloc(count * sizeof *u->scene_material);
    if (!out->positions || (normals && !out->normals) || (texcoords && !out->texcoords) ||
        !u->scene_material) {
        vkrt_unique_meshes_free(u);
        return vkrt_error_set(err, "out of memory for %llu unique triangles",
                              (unsigned long long)n);
    }
    for (uint32_t m = 0; m < meshes; ++m) {
        if (u->mesh_base[m] == UINT32_MAX)
            continue;
        const vkrt_mesh *mesh = &model->meshes[m];
        size_t base = u->mesh_base[m], k = mesh->triangle_count;
        memcpy(out->positions + 9 * base, mesh->positions, k * 9 * sizeof(float));
        if (mesh->normals)
            memcpy(out->normals + 9 * base, mesh->normals, k * 9 * sizeof(float));
        if (mesh->texcoords)
            memcpy(out->texcoords + 6 * base, mesh->texcoords, k * 6 * sizeof(float));
        memcpy(u->scene_material + base, triangle_material + material_first[m],
               k * sizeof *u->scene_material);
    }
    return true;
}

/* ------------------------------------------------------------------------ transforms */

/* The inverse of the affine map t (3x4 rows) into inv, in double; false when t is singular. */
static bool invert_affine(const float t[12], double inv[12])
{
    double cof[3][3];
    double det = vkrt_transform_cofactors(t, cof);
    if (!(fabs(det) > 0) || !isfinite(det))
        return false;
    /* inverse = adjugate / det, the adjugate the cofactors' transpose; then -inverse * offset. */
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            inv[4 * r + c] = cof[c][r] / det;
    for (int r = 0; r < 3; ++r)
        inv[4 * r + 3] = -(inv[4 * r] * t[3] + inv[4 * r + 1] * t[7] + inv[4 * r + 2] * t[11]);
    return true;
}

/* A world box that holds the mesh's box under t, padded by 2^-20 of its size and coordinates:
 * the kernels move the ray, not the triangles, so a hit's world point and the box planes are
 * rounded apart, and an unpadded box could cull a triangle that lies on its face. */
static void instance_box(const float t[12], const vkrt_mesh *mesh, float lo[3], float hi[3])
{
    double l[3] = {INFINITY, INFINITY, INFINITY}, h[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 8; ++c) {
        double p[3] = {c & 1 ? mesh->bounds_max[0] : mesh->bounds_min[0],
                       c & 2 ? mesh->bounds_max[1] : mesh->bounds_min[1],
                       c & 4 ? mesh->bounds_max[2] : mesh->bounds_min[2]};
        for (int r = 0; r < 3; ++r) {
            double x = t[4 * r] * p[0] + t[4 * r + 1] * p[1] + t[4 * r + 2] * p[2] + t[4 * r + 3];
            l[r] = fmin(l[r], x);
            h[r] = fmax(h[r], x);
        }
    }
    const double pad = 1.0 / 1048576.0;
    for (int r = 0; r < 3; ++r) {
        double margin = pad * (h[r] - l[r] + fmax(fabs(l[r]), fabs(h[r])));
        lo[r] = (float)(l[r] - margin);
        hi[r] = (float)(h[r] + margin);
        lo[r] = nextafterf(lo[r], -INFINITY);
        hi[r] = nextafterf(hi[r], INFINITY);
    }
}

/* ------------------------------------------------------------------------ the trees */

/* What the build holds while it runs. */
typedef struct two_level {
    uint32_t mesh_count;
    bvh *trees;               /* per model mesh; zeroed where no instance uses it */
    vkrt_bvh_layout *layouts; /* per model mesh */
    uint32_t *node_base;      /* per model mesh: its tree's first node in the node array */
    uint32_t *kept;           /* the model's instances that go in, in the model's order */
    Instance *records;        /* per kept instance, in the model's order */
    uint32_t kept_count;
    bvh top;
    vkrt_bvh_layout top_layout;
} two_level;

static void two_level_free(two_level *t)
{
    for (uint32_t m = 0; t->trees && m < t->mesh_count; ++m)
        bvh_free(&t->trees[m]);
    for (uint32_t m = 0; t->layouts && m < t->mesh_count; ++m)
        free(t->layouts[m].nodes);
    free(t->trees);
    free(t->layouts);
    free(t->node_base);
    free(t->kept);
    free(t->records);
    bvh_free(&t->top);
    free(t->top_layout.nodes);
    memset(t, 0, sizeof *t);
}

/* The child words of node i of a layout of width 2 or 4 and how many of them are children. (The
 * width is not the node's size: pairs and quads are both 64 bytes.) */
static uint32_t *child_words(const vkrt_bvh_layout *l, uint32_t width, uint32_t i, uint32_t *count)
{
    if (width == 2) {
        BvhPair *p = (BvhPair *)l->nodes + i;
        *count = 2;
        return &p->refs.x;
    }
    BvhQuad *q = (BvhQuad *)l->nodes + i;
    uint32_t meta;
    memcpy(&meta, &q->origin.w, sizeof meta);
    *count = meta >> 24;
    return &q->refs.x;
}

/* Moves a bottom-level tree's nodes to node_base and its triangles to triangle_base. */
static void relocate(vkrt_bvh_layout *l, uint32_t width, uint32_t node_base,
                     uint32_t triangle_base)
{
    for (uint32_t i = 0; i < l->count; ++i) {
        uint32_t count;
        uint32_t *ref = child_words(l, width, i, &count);
        for (uint32_t k = 0; k < count; ++k)
            ref[k] = (ref[k] & BVH_LEAF_REF) ? ref[k] + triangle_base : ref[k] + node_base;
    }
}

/* The bottom-level trees of the used meshes, laid out. */
static bool build_meshes(const vkrt_accel_desc *desc, const vkrt_model *model,
                         const vkrt_unique_meshes *u, two_level *t, uint32_t *stack,
                         vkrt_error *err)
{
    const bvh_build_desc build = {
        .max_leaf_size = desc->bvh_max_leaf,
        .traversal_cost = desc->bvh_traversal_cost,
    };
    *stack = 0;
    for (uint32_t m = 0; m < model->mesh_count; ++m) {
        uint32_t n = model->meshes[m].triangle_count;
        if (u->mesh_base[m] == UINT32_MAX || n == 0)
            continue;
        if (!bvh_build(&t->trees[m], u->mesh.positions + 9 * (size_t)u->mesh_base[m], n, &build,
                       err) ||
            !vkrt_bvh_lay_out(&t->trees[m], desc->bvh_width, &t->layouts[m], err))
            return false;
        *stack = t->layouts[m].stack > *stack ? t->layouts[m].stack : *stack;
    }
    return true;
}

/* The instances that go in (a used, non-empty mesh and an invertible transform), their records
 * but for info.z, and the top-level tree over their world boxes. */
static bool build_top(const vkrt_accel_desc *desc, const vkrt_model *model,
                      const vkrt_unique_meshes *u, two_level *t, vkrt_error *err)
{
    uint32_t n = model->instance_count;
    t->kept = malloc((n ? n : 1) * sizeof *t->kept);
    t->records = calloc(n ? n : 1, sizeof *t->records);
    float *boxes = malloc((n ? n : 1) * 9 * sizeof *boxes);
    if (!t->kept || !t->records || !boxes) {
        free(boxes);
        return vkrt_error_set(err, "out of memory for %u instances", n);
    }
    for (uint32_t i = 0; i < n; ++i) {
        const vkrt_instance *inst = &model->instances[i];
        const vkrt_mesh *mesh = &model->meshes[inst->mesh];
        double inv[12];
        if (mesh->triangle_count == 0 || !invert_affine(inst->transform, inv))
            continue;
        uint32_t k = t->kept_count++;
        t->kept[k] = i;
        Instance *rec = &t->records[k];
        float *from[3] = {&rec->object_to_world[0].x, &rec->object_to_world[1].x,
                          &rec->object_to_world[2].x};
        float *to[3] = {&rec->world_to_object[0].x, &rec->world_to_object[1].x,
                        &rec->world_to_object[2].x};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) {
                from[r][c] = inst->transform[4 * r + c];
                to[r][c] = (float)inv[4 * r + c];
            }
        rec->info = (uvec4){t->node_base[inst->mesh], u->mesh_base[inst->mesh], 0,
                            mesh->triangle_count};
        /* The box as a triangle (lo, hi, hi): the builder bounds it by lo and hi. */
        float *b = boxes + 9 * (size_t)k;
        instance_box(inst->transform, mesh, b, b + 3);
        memcpy(b + 6, b + 3, 3 * sizeof *b);
    }
    if (t->kept_count == 0) {
        free(boxes);
        return vkrt_error_set(err, "no instance has triangles and an invertible transform");
    }
    /* One instance per leaf: entering one costs a transform and a tree, far more than a
     * triangle test. */
    const bvh_build_desc top = {.max_leaf_size = 1};
    bool ok = bvh_build(&t->top, boxes, t->kept_count, &top, err) &&
              vkrt_bvh_lay_out(&t->top, desc->bvh_width, &t->top_layout, err);
    free(boxes);
    return ok;
}

/* The arrays of a finished build: nodes, Instance records in leaf order with their instanced
 * order, the triangle order over the unique meshes, the instance map. */
static bool gather(const vkrt_model *model, const vkrt_unique_meshes *u, two_level *t,
                   uint32_t total_nodes, vkrt_accel_arrays *a, vkrt_error *err)
{
    size_t node_size = t->top_layout.node_size;
    uint32_t n = t->kept_count, triangles = u->mesh.triangle_count;
    vkrt_instance_map *map = &a->instances;
    a->nodes = malloc((size_t)total_nodes * node_size);
    a->refs = malloc((size_t)n * sizeof(Instance));
    a->prim_order = malloc((triangles ? triangles : 1) * sizeof *a->prim_order);
    map->first = malloc(n * sizeof *map->first);
    map->mesh_base = malloc(n * sizeof *map->mesh_base);
    map->flat_first = malloc(n * sizeof *map->flat_first);
    uint64_t *flat = malloc((model->instance_count ? model->instance_count : 1) * sizeof *flat);
    if (!a->nodes || !a->refs || !a->prim_order || !map->first || !map->mesh_base ||
        !map->flat_first || !flat) {
        free(flat);
        return vkrt_error_set(err, "out of memory for the two-level BVH");
    }
    map->count = n;
    uint64_t at = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        flat[i] = at;
        at += model->meshes[model->instances[i].mesh].triangle_count;
    }
    memcpy(a->nodes, t->top_layout.nodes, t->top_layout.bytes);
    for (uint32_t m = 0; m < t->mesh_count; ++m)
        if (t->layouts[m].nodes)
            memcpy((char *)a->nodes + (size_t)t->node_base[m] * node_size, t->layouts[m].nodes,
                   t->layouts[m].bytes);
    /* Instances in the top-level tree's leaf order, numbered in the instanced order. */
    Instance *records = (Instance *)a->refs;
    uint64_t first = 0;
    for (uint32_t k = 0; k < n; ++k) {
        uint32_t from = t->top.prim_order[k];
        records[k] = t->records[from];
        records[k].info.z = (uint32_t)first;
        map->first[k] = (uint32_t)first;
        map->mesh_base[k] = records[k].info.y;
        map->flat_first[k] = flat[t->kept[from]];
        first += records[k].info.w;
    }
    free(flat);
    if (first >= VKRT_NO_HIT)
        return vkrt_error_set(err,
                              "%llu triangles over all instances: the two-level BVH numbers "
                              "hits in 32 bits",
                              (unsigned long long)first);
    a->ref_count = (size_t)n * sizeof(Instance) / sizeof(uint32_t);
    for (uint32_t m = 0; m < t->mesh_count; ++m) {
        if (!t->trees[m].prim_order)
            continue;
        uint32_t base = u->mesh_base[m];
        for (uint32_t i = 0; i < t->trees[m].prim_count; ++i)
            a->prim_order[base + i] = base + t->trees[m].prim_order[i];
    }
    /* Meshes no kept instance reaches are still uploaded; their triangles keep their place. */
    for (uint32_t m = 0; m < model->mesh_count; ++m)
        if (u->mesh_base[m] != UINT32_MAX && !t->trees[m].prim_order)
            for (uint32_t i = 0; i < model->meshes[m].triangle_count; ++i)
                a->prim_order[u->mesh_base[m] + i] = u->mesh_base[m] + i;
    a->info.dims.x = n;
    a->node_size = node_size;
    a->node_count = total_nodes;
    a->triangle_count = triangles;
    return true;
}

bool vkrt_accel_build_instanced(const vkrt_accel_desc *desc, const vkrt_model *model,
                                const vkrt_unique_meshes *u, vkrt_accel_arrays *a,
                                vkrt_error *err)
{
    memset(a, 0, sizeof *a);
    if (desc->bvh_width != 2 && desc->bvh_width != 4)
        return vkrt_error_set(err, "BVH width %u: the GPU layouts are 2 and 4 wide",
                              desc->bvh_width);
    double start = vkrt_clock_ms();
    two_level t = {.mesh_count = model->mesh_count};
    uint32_t meshes = model->mesh_count ? model->mesh_count : 1;
    t.trees = calloc(meshes, sizeof *t.trees);
    t.layouts = calloc(meshes, sizeof *t.layouts);
    t.node_base = calloc(meshes, sizeof *t.node_base);
    uint32_t mesh_stack = 0;
    bool ok = (t.trees && t.layouts && t.node_base) ||
              vkrt_error_set(err, "out of memory for %u meshes", model->mesh_count);
    ok = ok && build_meshes(desc, model, u, &t, &mesh_stack, err);
    /* The top level takes nodes from 0; the meshes' trees follow, each moved to its place. The
     * top level's size is known only after its build, which needs the meshes' roots: so the
     * meshes are numbered from 0 first and moved by the top level's size after. */
    uint64_t nodes = 0;
    for (uint32_t m = 0; ok && m < model->mesh_count; ++m) {
        t.node_base[m] = (uint32_t)nodes;
        nodes += t.layouts[m].count;
    }
    ok = ok && build_top(desc, model, u, &t, err);
    uint64_t total = nodes + t.top_layout.count;
    if (ok && total > 0x7FFFFFFFu)
        ok = vkrt_error_set(err, "two-level BVH of %llu nodes: the GPU walk holds at most 2^31",
                            (unsigned long long)total);
    if (ok) {
        uint32_t top = t.top_layout.count;
        for (uint32_t m = 0; m < model->mesh_count; ++m) {
            t.node_base[m] += top;
            if (t.layouts[m].nodes)
                relocate(&t.layouts[m], desc->bvh_width, t.node_base[m], u->mesh_base[m]);
        }
        for (uint32_t k = 0; k < t.kept_count; ++k)
            t.records[k].info.x += top;
    }
    /* The walk keeps the top level's entries below the instance's (glsl/lib/
     * traverse_instanced.glsl), and one for a top-level leaf's other instances. */
    uint32_t stack = t.top_layout.stack + mesh_stack + 1;
    if (ok && stack > VKRT_BVH_STACK_SIZE)
        ok = vkrt_error_set(err, "two-level BVH needs a traversal stack of %u entries, more than %u",
                            stack, VKRT_BVH_STACK_SIZE);
    ok = ok && gather(model, u, &t, (uint32_t)total, a, err);
    if (ok) {
        vkrt_accel_stats *s = &a->stats;
        vkrt_instancing_counts c = vkrt_instancing_count(model);
        uint32_t used = 0, leaves = 0, depth = 0;
        for (uint32_t m = 0; m < model->mesh_count; ++m) {
            used += t.trees[m].prim_order != NULL;
            leaves += t.trees[m].leaf_count;
            depth = t.layouts[m].depth > depth ? t.layouts[m].depth : depth;
        }
        s->kind = VKRT_ACCEL_BVH;
        snprintf(s->reason, sizeof s->reason,
                 "two-level BVH over %u instances of %u meshes: %llu triangles instanced, "
                 "%u unique",
                 t.kept_count, used, (unsigned long long)c.instanced, u->mesh.triangle_count);
        s->two_level = true;
        s->instances = t.kept_count;
        s->meshes = used;
        s->instanced_triangles = c.instanced;
        s->triangles = u->mesh.triangle_count;
        s->references = u->mesh.triangle_count;
        s->bytes = a->node_count * a->node_size + a->ref_count * sizeof(uint32_t);
        s->nodes = (uint32_t)a->node_count;
        s->leaves = leaves + t.top.leaf_count;
        s->triangles_per_leaf = leaves ? (double)u->mesh.triangle_count / leaves : 0;
        s->max_depth = t.top_layout.depth + 1 + depth;
        s->bvh_width = desc->bvh_width;
        s->sah_cost = t.top.sah_cost;
        s->bvh_max_leaf = desc->bvh_max_leaf ? desc->bvh_max_leaf : BVH_DEFAULT_MAX_LEAF;
        s->bvh_traversal_cost =
            desc->bvh_traversal_cost > 0 ? desc->bvh_traversal_cost : BVH_DEFAULT_TRAVERSAL_COST;
        s->build_ms = vkrt_clock_ms() - start;
    }
    two_level_free(&t);
    if (!ok)
        vkrt_accel_arrays_free(a);
    return ok;
}

bool vkrt_accel_gpu_create_instanced(vkrt_accel_gpu *a, gpu_context *ctx,
                                     const vkrt_accel_desc *desc, const vkrt_model *model,
                                     const vkrt_unique_meshes *u, vkrt_error *err)
{
    memset(a, 0, sizeof *a);
    /* The structure cache (accel_cache.h), as for a flat structure: try it, else build and
     * store. */
    vkrt_accel_cache_name name;
    vkrt_accel_arrays arr;
    bool cached = vkrt_accel_cache_name_of_instanced(desc, model, u, &name);
    if (!(cached && vkrt_accel_cache_load(&name, &arr))) {
        if (!vkrt_accel_build_instanced(desc, model, u, &arr, err))
            return false;
        if (cached)
            vkrt_accel_cache_store(&name, &arr);
    }
    bool ok = vkrt_accel_gpu_upload(a, ctx, &arr, err);
    vkrt_accel_arrays_free(&arr);
    return ok;
}
