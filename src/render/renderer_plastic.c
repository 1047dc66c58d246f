/*
 * renderer_plastic.c: @roughplastic's coat tables (glsl/shared.h VKRT_BINDING_PLASTIC_TABLES,
 * src/scene/plastic_table.h), one per index and roughness of the scene's rough plastics, and
 * each such material's Material.maps.w pointing at its table. A material of one roughness gets
 * one row, made at exactly its roughness; one with a roughness map (map_Pr, texture slot 2) a
 * row every 1/32 of roughness from 0 to 1, between which the shader interpolates (within 2.5e-3
 * of T at any cosine, 1.5e-4 at cos 0.5). A smooth coat (roughness below 0.02, what the shader treats as
 * a delta mirror) and an index of 1 (no coat: the base is Lambertian) need none.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../accel/bvh_threads.h"
#include "../scene/plastic_table.h"
#include "renderer_private.h"

/* Rows of a table for a roughness map: every 1/32 of roughness from 0 to 1. */
enum { MAPPED_ROWS = 33 };

/* Below this roughness the coat is smooth (glsl/lib/microfacet.glsl, MICROFACET_SMOOTH_ALPHA
 * is its square). */
static const float smooth_roughness = 0.02f;

/* One table: its index, rows and last row's roughness, and where it starts in the floats. */
typedef struct plastic_key {
    float eta, roughness;
    uint32_t rows, offset;
} plastic_key;

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

/* The table material m needs, or false where it needs none. */
static bool plastic_key_of(const vkrt_scene_materials *mats, uint32_t m, plastic_key *key)
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
    bool mapped = mat->textures[2] != VKRT_SCENE_NO_TEXTURE;
    *key = (plastic_key){eta, mapped ? 1.0f : roughness, mapped ? MAPPED_ROWS : 1, 0};
    return true;
}

bool renderer_upload_plastic_tables(vkrt_renderer *r, const vkrt_scene_materials *mats,
                                    Material *materials, vkrt_error *err)
{
    plastic_key *keys = calloc(mats->count ? mats->count : 1, sizeof *keys);
    if (!keys)
        return vkrt_error_set(err, "out of memory");
    uint32_t key_count = 0, floats = 0, rows = 0;
    for (uint32_t m = 0; m < mats->count; ++m) {
        materials[m].maps.w = -1;
        plastic_key key;
        if (!plastic_key_of(mats, m, &key))
            continue;
        uint32_t k = 0;
        while (k < key_count && !(keys[k].eta == key.eta && keys[k].roughness == key.roughness &&
                                  keys[k].rows == key.rows))
            ++k;
        if (k == key_count) {
            key.offset = floats;
            keys[key_count++] = key;
            floats += VKRT_PLASTIC_HEADER_FLOATS + key.rows * VKRT_PLASTIC_ROW_FLOATS;
            rows += key.rows;
        }
        materials[m].maps.w = (float)keys[k].offset;
    }
    float *table = calloc(floats ? floats : 1, sizeof *table);
    plastic_job *jobs = calloc(rows ? rows : 1, sizeof *jobs);
    if (!table || !jobs) {
        free(keys);
        free(table);
        free(jobs);
        return vkrt_error_set(err, "out of memory for the plastic tables");
    }
    uint32_t job = 0;
    for (uint32_t k = 0; k < key_count; ++k) {
        float *t = table + keys[k].offset;
        uint32_t n = keys[k].rows;
        t[0] = (float)n;
        t[1] = n > 1 ? (float)(n - 1) / keys[k].roughness : 0.0f;
        for (uint32_t row = 0; row < n; ++row) {
            float roughness =
                n > 1 ? keys[k].roughness * (float)row / (float)(n - 1) : keys[k].roughness;
            jobs[job++] = (plastic_job){.alpha = roughness * roughness,
                                        .eta = keys[k].eta,
                                        .row = t + VKRT_PLASTIC_HEADER_FLOATS +
                                               row * VKRT_PLASTIC_ROW_FLOATS};
        }
    }
    /* About 10 ms of one core a row: the rows' cosines over the cores. */
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
    free(keys);
    free(table);
    free(jobs);
    return ok;
}
