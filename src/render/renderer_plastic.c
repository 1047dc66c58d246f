/*
 * renderer_plastic.c: @roughplastic's coat tables (glsl/shared.h VKRT_BINDING_PLASTIC_TABLES,
 * src/scene/plastic_table.h), one per index and roughness of the scene's rough plastics, and
 * each such material's Material.maps.w pointing at its table. A material of one roughness gets
 * one row, made at exactly its roughness; one with a roughness map (map_Pr, texture slot 2) a
 * "mapped" table of a row every 1/32 of roughness from 0 to 1, between which the shader
 * interpolates (within 2.5e-3 of T at any cosine, 1.5e-4 at cos 0.5). Where one index has more
 * plain roughnesses than that, they share one table of as many rows from 0 to the largest of
 * them instead of a row each (the shader finds a row by the table's header, rows and scale, so a
 * plain roughness reads it as a map's would): a row takes milliseconds of one core, and a scene
 * of hundreds of plastics of distinct roughness would otherwise wait seconds at start-up. An
 * index then takes at most 66 rows (a map's 33 and 33 plain); distinct indices each take their
 * own. A smooth coat (roughness below 0.02, what the shader treats as a delta mirror) and an
 * index of 1 (no coat: the base is Lambertian) need none.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../accel/bvh_threads.h"
#include "../scene/plastic_table.h"
#include "renderer_private.h"

/* Rows of a mapped table (every 1/32 of roughness from 0 to 1), and of a shared one. */
enum { MAPPED_ROWS = 33 };

/* Below this roughness the coat is smooth (glsl/lib/microfacet.glsl, MICROFACET_SMOOTH_ALPHA
 * is its square). */
static const float smooth_roughness = 0.02f;

/* One row to fill: its coat, where it goes, and its cosines' shares of Ri. */
typedef struct plastic_job {
    float alpha, eta;
    float *row;
    double internal[VKRT_PLASTIC_COSINES];
} plastic_job;

/* A thread's share of the rows' cosines: entries first, first + step, ... of rows x cosines. */
typedef struct plastic_share {
    plastic_job *jobs;
    uint32_t first, step, count;
} plastic_share;

static void *fill_entries(void *arg)
{
    const plastic_share *s = arg;
    for (uint32_t e = s->first; e < s->count; e += s->step) {
        plastic_job *j = &s->jobs[e / VKRT_PLASTIC_COSINES];
        int k = (int)(e % VKRT_PLASTIC_COSINES);
        vkrt_plastic_entry(j->alpha, j->eta, k, j->row, &j->internal[k]);
    }
    return NULL;
}

/* What material m's coat needs of the tables: its index, its roughness (unused where mapped)
 * and whether a roughness map varies it. */
typedef struct plastic_need {
    float eta, roughness;
    bool mapped;
    uint32_t material;
} plastic_need;

/* The need of material m, or false where it needs no table. */
static bool plastic_need_of(const vkrt_scene_materials *mats, uint32_t m, plastic_need *need)
{
    const vkrt_scene_material *mat = &mats->list[m];
    const char *builtin = mats->shaders[mat->shader].builtin;
    if (!builtin || strcmp(builtin, "roughplastic") != 0)
        return false;
    /* As glsl/materials/roughplastic.glsl reads them: Ni (0: 1.5), roughness clamped to [0, 1]
     * (times map_Pr's red, in [0, 1], where there is one). */
    float eta = mat->params[11] > 0 ? mat->params[11] : 1.5f;
    float roughness = fminf(fmaxf(mat->params[16], 0.0f), 1.0f);
    if (eta == 1.0f || roughness < smooth_roughness)
        return false;
    *need = (plastic_need){eta, roughness, mat->textures[2] != VKRT_SCENE_NO_TEXTURE, m};
    return true;
}

/* Sorts the needs by index, the mapped first, then by roughness: each index's tables in one
 * run, equal roughnesses side by side (a sort, so that 100k materials cost no more than that). */
static int need_order(const void *a, const void *b)
{
    const plastic_need *x = a, *y = b;
    if (x->eta != y->eta)
        return x->eta < y->eta ? -1 : 1;
    if (x->mapped != y->mapped)
        return x->mapped ? -1 : 1;
    if (x->roughness != y->roughness)
        return x->roughness < y->roughness ? -1 : 1;
    return (x->material > y->material) - (x->material < y->material);
}

/* Appends a table of `rows` rows, the last at roughness, and returns where it starts. */
static uint32_t add_table(renderer_plastic_layout *layout, float eta, float roughness,
                          uint32_t rows)
{
    uint32_t offset = layout->floats;
    layout->tables[layout->count++] = (renderer_plastic_table){eta, roughness, rows, offset};
    layout->floats += VKRT_PLASTIC_HEADER_FLOATS + rows * VKRT_PLASTIC_ROW_FLOATS;
    layout->rows += rows;
    return offset;
}

/* Whether sorted need[i] is a plain roughness that the needs before it do not have. */
static bool new_plain_roughness(const plastic_need *need, uint32_t i)
{
    return !need[i].mapped &&
           (i == 0 || need[i - 1].mapped || need[i].roughness != need[i - 1].roughness);
}

/* Lays out the tables of the needs of one index, need[0..n), sorted: a mapped table where one is
 * mapped; a row at each plain roughness while there are at most as many as the mapped table has
 * rows, else one table of as many rows for them all, from 0 to the largest (the closer the
 * rows, the closer its interpolation to the exact rows). */
static void lay_out_index(renderer_plastic_layout *layout, const plastic_need *need, uint32_t n,
                          Material *materials)
{
    uint32_t distinct = 0;
    for (uint32_t i = 0; i < n; ++i)
        distinct += new_plain_roughness(need, i);
    bool fold = distinct > MAPPED_ROWS;
    uint32_t mapped = 0, folded = 0, exact = 0;
    if (need[0].mapped)
        mapped = add_table(layout, need[0].eta, 1.0f, MAPPED_ROWS);
    if (fold)
        folded = add_table(layout, need[0].eta, need[n - 1].roughness, MAPPED_ROWS);
    for (uint32_t i = 0; i < n; ++i) {
        if (!fold && new_plain_roughness(need, i))
            exact = add_table(layout, need[i].eta, need[i].roughness, 1);
        uint32_t plain = fold ? folded : exact;
        materials[need[i].material].maps.w = (float)(need[i].mapped ? mapped : plain);
    }
}

bool renderer_plastic_layout_make(const vkrt_scene_materials *mats, Material *materials,
                                  renderer_plastic_layout *layout, vkrt_error *err)
{
    *layout = (renderer_plastic_layout){0};
    size_t size = mats->count ? mats->count : 1;
    plastic_need *needs = calloc(size, sizeof *needs);
    layout->tables = calloc(size, sizeof *layout->tables);
    if (!needs || !layout->tables) {
        free(needs);
        renderer_plastic_layout_free(layout);
        return vkrt_error_set(err, "out of memory for the plastic tables");
    }
    uint32_t n = 0;
    for (uint32_t m = 0; m < mats->count; ++m) {
        materials[m].maps.w = -1;
        n += plastic_need_of(mats, m, &needs[n]);
    }
    qsort(needs, n, sizeof *needs, need_order);
    for (uint32_t i = 0, end; i < n; i = end) {
        for (end = i + 1; end < n && needs[end].eta == needs[i].eta; ++end)
            ;
        lay_out_index(layout, needs + i, end - i, materials);
    }
    free(needs);
    return true;
}

void renderer_plastic_layout_free(renderer_plastic_layout *layout)
{
    free(layout->tables);
    *layout = (renderer_plastic_layout){0};
}

bool renderer_upload_plastic_tables(vkrt_renderer *r, const vkrt_scene_materials *mats,
                                    Material *materials, vkrt_error *err)
{
    renderer_plastic_layout layout;
    if (!renderer_plastic_layout_make(mats, materials, &layout, err))
        return false;
    uint32_t floats = layout.floats, rows = layout.rows;
    float *table = calloc(floats ? floats : 1, sizeof *table);
    plastic_job *jobs = calloc(rows ? rows : 1, sizeof *jobs);
    if (!table || !jobs) {
        renderer_plastic_layout_free(&layout);
        free(table);
        free(jobs);
        return vkrt_error_set(err, "out of memory for the plastic tables");
    }
    uint32_t job = 0;
    for (uint32_t k = 0; k < layout.count; ++k) {
        const renderer_plastic_table *key = &layout.tables[k];
        float *t = table + key->offset;
        uint32_t n = key->rows;
        t[0] = (float)n;
        t[1] = n > 1 ? (float)(n - 1) / key->roughness : 0.0f;
        for (uint32_t row = 0; row < n; ++row) {
            float roughness = n > 1 ? key->roughness * (float)row / (float)(n - 1) : key->roughness;
            jobs[job++] = (plastic_job){.alpha = roughness * roughness,
                                        .eta = key->eta,
                                        .row = t + VKRT_PLASTIC_HEADER_FLOATS +
                                               row * VKRT_PLASTIC_ROW_FLOATS};
        }
    }
    renderer_plastic_layout_free(&layout);
    /* Milliseconds of one core a row: the rows' cosines over the cores. */
    uint32_t entries = rows * VKRT_PLASTIC_COSINES, threads = bvh_threads_default();
    if (threads > entries)
        threads = entries > 0 ? entries : 1;
    plastic_share shares[BVH_MAX_THREADS];
    for (uint32_t t = 0; t < threads; ++t)
        shares[t] = (plastic_share){jobs, t, threads, entries};
    if (entries)
        bvh_threads_run(threads, fill_entries, shares, sizeof shares[0]);
    for (uint32_t j = 0; j < rows; ++j)
        vkrt_plastic_finish(jobs[j].row, jobs[j].internal);
    bool ok = floats ? gpu_buffer_create_from(r->ctx, &r->plastic_tables, table,
                                              floats * sizeof *table, "plastic tables", err)
                     : gpu_buffer_create(r->ctx, &r->plastic_tables, 0, "plastic tables", err);
    free(table);
    free(jobs);
    return ok;
}
