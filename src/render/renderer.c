/*
 * renderer.c: creating and destroying the renderer (see renderer.h), and what its users may read
 * of it. Creation runs in the order data flows: the structure (its triangle order decides every
 * upload's order), the material kernel's plan, the uploads, the frame's buffers, the kernels.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_private.h"
#include "accel_instanced.h"
#include "render_desc.h"
#include "../clock.h"
#include "../scene/colour.h"

/* Timed frames of a profile unless the description asks for another number. */
static const uint32_t default_profile_repeat = 11;

/* A scene assembled in memory (tests, bench) may come without resolved materials: then every
 * triangle is the default diffuse, resolved into own. */
static bool default_materials(const vkrt_scene *scene, vkrt_scene_materials *own,
                              vkrt_error *err)
{
    vkrt_model plain = scene->model;
    plain.material_count = 0;
    plain.materials = NULL;
    vkrt_mesh *meshes = calloc(plain.mesh_count ? plain.mesh_count : 1, sizeof *meshes);
    bool ok = meshes != NULL;
    for (uint32_t m = 0; ok && m < plain.mesh_count; ++m) {
        meshes[m] = scene->model.meshes[m];
        uint32_t n = meshes[m].triangle_count;
        int32_t *none = malloc((n ? n : 1) * sizeof *none);
        ok = none != NULL;
        for (uint32_t i = 0; ok && i < n; ++i)
            none[i] = -1;
        meshes[m].material = none;
    }
    plain.meshes = meshes;
    ok = ok && vkrt_scene_materials_resolve(&scene->config, &plain, NULL, own, err);
    for (uint32_t m = 0; meshes && m < plain.mesh_count; ++m)
        free(meshes[m].material);
    free(meshes);
    if (!ok && err && !err->msg[0])
        vkrt_error_set(err, "out of memory");
    return ok;
}

/* The name of the first material that emits light as an area light (renderer_material_ke), or
 * NULL when none does. */
static const char *first_emitter(const vkrt_scene_materials *mats)
{
    for (uint32_t i = 0; i < mats->count; ++i) {
        float ke[3];
        renderer_material_ke(mats, i, ke);
        if (vkrt_luminance(ke) > 0)
            return mats->list[i].name;
    }
    return NULL;
}

/* The integrator: asked for (desc, else the scene's `integrator`), or chosen from the scene's
 * lights. Light from geometry or from an environment map needs the path tracer; a scene lit by
 * point, spot and directional lights alone keeps Whitted's picture (and its speed). */
/* How many different shaders the materials that triangles can have use (the environment's
 * apart). */
static uint32_t surface_shaders(const vkrt_scene_materials *mats)
{
    bool *seen = calloc(mats->shader_count ? mats->shader_count : 1, sizeof *seen);
    uint32_t count = 0;
    for (uint32_t i = 0; seen && i < mats->count; ++i) {
        uint32_t shader = mats->list[i].shader;
        if (i == mats->environment || shader >= mats->shader_count || seen[shader])
            continue;
        seen[shader] = true;
        ++count;
    }
    bool counted = seen != NULL;
    free(seen);
    /* Out of memory: count two, so that the grouping stays on (it is only faster, or the same). */
    return counted ? count : 2;
}

static void choose_integrator(vkrt_renderer *r, const vkrt_render_desc *desc,
                              const vkrt_scene *scene, const vkrt_scene_materials *mats)
{
    vkrt_integrator asked = desc->integrator;
    if (asked != VKRT_INTEGRATOR_AUTO) {
        r->integrator = asked;
        snprintf(r->integrator_reason, sizeof r->integrator_reason, "asked for");
        return;
    }
    const char *emitter = first_emitter(mats);
    if (emitter) {
        r->integrator = VKRT_INTEGRATOR_PATH;
        snprintf(r->integrator_reason, sizeof r->integrator_reason,
                 "material '%s' emits light (Ke): path", emitter);
    } else if (scene->config.environment_map) {
        r->integrator = VKRT_INTEGRATOR_PATH;
        snprintf(r->integrator_reason, sizeof r->integrator_reason,
                 "an environment map lights the scene: path");
    } else if (scene->light_count == 0 && (scene->config.environment[0] > 0.0f ||
                                           scene->config.environment[1] > 0.0f ||
                                           scene->config.environment[2] > 0.0f)) {
        /* Whitted would light nothing: the sky is the scene's only light. */
        r->integrator = VKRT_INTEGRATOR_PATH;
        snprintf(r->integrator_reason, sizeof r->integrator_reason,
                 "no light but the environment's: path");
    } else {
        r->integrator = VKRT_INTEGRATOR_WHITTED;
        snprintf(r->integrator_reason, sizeof r->integrator_reason,
                 "no emissive material and no environment map: whitted");
    }
}

/* Whether the instances go under a two-level BVH (vkrt_instancing), into r->two_level; false
 * with err set where it was asked for and cannot be. */
static bool choose_two_level(vkrt_renderer *r, const vkrt_render_desc *desc,
                             const vkrt_scene *scene, const vkrt_scene_materials *mats,
                             vkrt_error *err)
{
    r->two_level = false;
    if (desc->instancing == VKRT_INSTANCING_FLAT)
        return true;
    const char *emitter = first_emitter(mats);
    bool bvh = desc->accel == VKRT_ACCEL_AUTO || desc->accel == VKRT_ACCEL_BVH;
    if (desc->instancing == VKRT_INSTANCING_TWO_LEVEL) {
        if (emitter)
            return vkrt_error_set(err,
                                  "the two-level BVH takes no emissive triangles (material '%s' "
                                  "emits light): light sampling reads them in world space",
                                  emitter);
        if (!bvh)
            return vkrt_error_set(err, "the two-level structure is a BVH, not a %s",
                                  vkrt_accel_name(desc->accel));
        r->two_level = true;
        return true;
    }
    /* Emissive triangles are sampled from a world-space list: such scenes are flattened. */
    if (emitter || !bvh)
        return true;
    vkrt_instancing_counts c = vkrt_instancing_count(&scene->model);
    /* What a flattened triangle takes on the device at least: its positions and material, and
     * its share of the nodes (about a 64-byte record per two triangles). */
    double flat_bytes = (double)c.instanced * (sizeof(Triangle) + sizeof(uint32_t) + 32.0);
    r->two_level = vkrt_instancing_pays(&scene->model) ||
                   flat_bytes > (double)r->ctx->memory_limit ||
                   c.instanced > VKRT_MODEL_FLAT_MAX_TRIANGLES;
    return true;
}

/* Adds the ms since *at to *into and restarts *at; true, to sit in a chain of && steps. */
static bool lap(double *at, double *into)
{
    double now = vkrt_clock_ms();
    *into += now - *at;
    *at = now;
    return true;
}

/* The image's rays must fit one ray buffer the device allows. */
static bool size_ray_buffers(vkrt_renderer *r, const vkrt_render_desc *desc, vkrt_error *err)
{
    uint64_t pixels = (uint64_t)r->width * r->height;
    r->max_capacity = renderer_max_ray_capacity(r);
    if (pixels > r->max_capacity)
        return vkrt_error_set(err,
                              "%ux%u needs %llu rays per buffer (%.0f MiB each); %s allows at "
                              "most %u: render a smaller image",
                              r->width, r->height, (unsigned long long)pixels,
                              pixels * sizeof(Ray) / 1048576.0, r->ctx->properties.deviceName,
                              r->max_capacity);
    /* Several samples of each pixel in one pass where the image is small (tuning.c, wave_rays),
     * as many as fit the buffers the device allows. */
    uint64_t batch = r->tuning.wave_rays / pixels;
    batch = batch < 1 ? 1 : batch > r->samples ? r->samples : batch;
    while (batch > 1 && pixels * batch > r->max_capacity)
        --batch;
    /* Sampling to a target error decides after each pass which pixels take more: a pass gives
     * at most VKRT_ADAPTIVE_MIN_SAMPLES, so a pixel stops within that many of its target. */
    if (r->target_error > 0 && batch > VKRT_ADAPTIVE_MIN_SAMPLES)
        batch = VKRT_ADAPTIVE_MIN_SAMPLES;
    /* Motion blur gives each pass its own time (renderer_frame.c): one sample a pass. */
    if (r->shutter > 0)
        batch = 1;
    r->batch = (uint32_t)batch;
    uint64_t rays = pixels * batch;
    r->capacity = desc->ray_capacity > rays ? desc->ray_capacity : (uint32_t)rays;
    if (r->capacity > r->max_capacity)
        r->capacity = r->max_capacity;
    return true;
}

bool vkrt_renderer_create(vkrt_renderer **out, gpu_context *ctx, const vkrt_scene *scene,
                          const vkrt_render_desc *desc, vkrt_error *err)
{
    *out = NULL;
    /* The scene's settings where desc leaves them zero, as the commands resolve theirs. */
    vkrt_render_desc completed = vkrt_render_desc_complete(desc, &scene->config);
    desc = &completed;
    if (!(desc->clamp >= 0 && isfinite(desc->clamp)))
        return vkrt_error_set(err, "clamp %g is not a positive number (0: no clamp)",
                              (double)desc->clamp);
    if (!(desc->target_error >= 0 && isfinite(desc->target_error)))
        return vkrt_error_set(err, "target error %g is not a positive number (0: none)",
                              (double)desc->target_error);
    vkrt_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return vkrt_error_set(err, "out of memory");
    r->ctx = ctx;
    r->tuning = vkrt_tuning_for(ctx, &desc->tuning);
    r->width = desc->width;
    r->height = desc->height;
    r->samples = desc->samples ? desc->samples : 1;
    r->max_depth = desc->max_depth;
    r->min_importance = desc->min_importance > 0 ? desc->min_importance
                                                 : r->tuning.min_importance;
    r->profile = desc->profile;
    r->profile_repeat = desc->profile_repeat ? desc->profile_repeat : default_profile_repeat;
    r->triangle_count = scene->model.triangle_count;

    const vkrt_scene_materials *mats = &scene->materials;
    vkrt_scene_materials own = {0};
    vkrt_material_kernel kernel = {0};
    bool ok = true;
    if (!mats->list) {
        ok = default_materials(scene, &own, err);
        mats = &own;
    }
    if (ok)
        choose_integrator(r, desc, scene, mats);
    /* Whitted's jitter cells are laid out for a fixed number of samples (raygen.comp): a pixel
     * that stopped early would have sampled part of its square only. */
    if (ok && desc->target_error > 0 && r->integrator != VKRT_INTEGRATOR_PATH)
        ok = vkrt_error_set(err,
                            "a target error needs the path integrator (this scene renders "
                            "with whitted: %s); add --integrator path",
                            r->integrator_reason);
    r->target_error = desc->target_error;
    /* Whitted sees the emissive triangles as one more light after the scene's, with a visibility
     * bit of its own (lib/emitters.glsl). */
    r->emitter_light = ok && r->integrator == VKRT_INTEGRATOR_WHITTED && first_emitter(mats);
    r->light_words = (scene->light_count + r->emitter_light + 31) / 32;
    r->clamp = desc->clamp;
    r->aovs = desc->aovs & VKRT_AOV_ALL;
    r->seed = desc->seed;
    r->shutter = desc->shutter;
    /* The path tracer's last wave only looks for the light its BSDF samples find (nee.comp skips
     * it): so light sampling and BSDF sampling both reach paths of max-depth + 2 segments, the
     * same paths, and max-depth 0 is direct light, as in Whitted (Mitsuba's max_depth is ours
     * + 2). */
    if (r->integrator == VKRT_INTEGRATOR_PATH)
        r->max_depth += 1;
    r->light_sampling = desc->light_sampling;
    /* Grouping hits by shader pays only where hits of different shaders can share a subgroup. */
    r->material_order = r->tuning.material_order && ok && surface_shaders(mats) > 1 &&
                        r->max_depth >= VKRT_ORDER_FIRST_DEPTH;
    const vkrt_tuning *t = &r->tuning;
    const vkrt_accel_desc accel = {
        .kind = desc->accel,
        .bvh_splits = desc->bvh_splits,
        .grid_density = t->grid_density,
        .bvh_width = t->bvh_width,
        .bvh_max_leaf = t->bvh_max_leaf,
        .bvh_traversal_cost = t->bvh_traversal_cost,
        .bvh_spatial_budget = t->bvh_spatial_budget,
        .kd_traversal_cost = t->kd_traversal_cost,
        .grid_competes = t->grid_competes,
        .kdtree_competes = t->kdtree_competes,
        .source = scene->config.geometry_count == 1 ? scene->config.geometries[0].path
                                                       : scene->config.path,
    };
    /* The instances' triangles in world space: the mesh's own arrays for one identity instance,
     * else a copy made here and dropped once uploaded. Under a two-level BVH, the meshes that
     * instances use, each once in its own space, with their materials (accel_instanced.h). */
    vkrt_mesh world = {0};
    bool world_copied = false;
    vkrt_unique_meshes unique = {0};
    vkrt_scene_materials uploaded_mats;
    uint32_t *world_materials = NULL;
    ok = ok && choose_two_level(r, desc, scene, mats, err);
    if (ok && r->two_level) {
        ok = vkrt_unique_meshes_make(&scene->model, mats->triangle_material, mats->mesh_first,
                                     &unique, err);
        world = unique.mesh;
        uploaded_mats = *mats;
        uploaded_mats.triangle_material = unique.scene_material;
        mats = &uploaded_mats;
    } else if (ok) {
        const uint32_t *per_world = NULL;
        ok = vkrt_model_world(&scene->model, &world, &world_copied, err) &&
             vkrt_scene_materials_world(mats, &scene->model, &per_world, &world_materials, err);
        uploaded_mats = *mats;
        uploaded_mats.triangle_material = (uint32_t *)per_world;
        mats = &uploaded_mats;
    }
    bool has_texcoords = mats->reads_texcoords && world.texcoords;
    bool has_normals = world.normals != NULL;
    vkrt_renderer_startup *times = &r->startup;
    double at = vkrt_clock_ms();
    /* The kernels compile on threads while the structure is built and the data uploaded, for
     * the layout predicted now (renderer_kernels.c); where it cannot be told, after the build. */
    renderer_data_layout layout;
    renderer_kernel_plan plan;
    ok = ok && size_ray_buffers(r, desc, err) &&
         gpu_storage_set_create_texels(ctx, &r->set, VKRT_STORAGE_BINDINGS, VKRT_TEXEL_BINDINGS,
                                       sizeof(FrameParams), err) &&
         vkrt_material_kernel_create_sampling(&kernel, mats, ctx->float_atomics,
                                              r->integrator == VKRT_INTEGRATOR_PATH,
                                              (r->aovs & VKRT_AOV_SURFACE) != 0, err) &&
         renderer_scan_materials(r, mats, err);
    if (ok && renderer_data_layout_predict(r, &accel, &world, mats, &layout)) {
        renderer_kernel_plan_make(r, &layout, has_normals, has_texcoords, desc->traversal_stats,
                                  &plan);
        ok = renderer_kernels_start(r, &plan, &kernel, mats, err);
    }
    bool early = r->kernels != NULL, predicted = false;
    ok = ok && lap(&at, &times->materials_ms) &&
         (r->two_level ? vkrt_accel_gpu_create_instanced(&r->accel, ctx, &accel, &scene->model,
                                                         &unique, err)
                       : vkrt_accel_gpu_create(&r->accel, ctx, &accel, world.positions,
                                               world.triangle_count, err)) &&
         lap(&at, &times->structure_ms) && renderer_upload_geometry(r, &world, mats, err) &&
         renderer_create_texel_views(r, err) && lap(&at, &times->geometry_ms) &&
         renderer_upload_materials(r, mats, &kernel, err) && lap(&at, &times->materials_ms) &&
         renderer_upload_lights(r, scene->lights, scene->light_count, err) &&
         renderer_upload_light_sampling(r, scene, &world, mats, err) &&
         lap(&at, &times->lights_ms) &&
         renderer_upload_split_addresses(r, err) && renderer_create_frame_buffers(r, err) &&
         lap(&at, &times->buffers_ms);
    if (ok) {
        renderer_data_layout_of(r, &layout);
        renderer_kernel_plan_make(r, &layout, has_normals, has_texcoords, desc->traversal_stats,
                                  &plan);
        if (!r->kernels)
            ok = renderer_kernels_start(r, &plan, &kernel, mats, err);
        ok = ok && renderer_kernels_finish(r, &plan, &predicted, err) &&
             lap(&at, &times->kernels_ms);
        times->kernels_recompiled = !early || !predicted;
    }
    /* The compiles read kernel and mats: joined before they go. */
    renderer_kernels_abandon(r);
    vkrt_material_kernel_destroy(&kernel);
    vkrt_scene_materials_free(&own);
    if (world_copied)
        vkrt_mesh_free(&world);
    vkrt_unique_meshes_free(&unique);
    free(world_materials);
    if (!ok) {
        vkrt_renderer_destroy(r);
        return false;
    }
    renderer_bind_all(r);
    *out = r;
    return true;
}

const vkrt_renderer_startup *vkrt_renderer_startup_times(const vkrt_renderer *r)
{
    return &r->startup;
}

vkrt_integrator vkrt_renderer_integrator(const vkrt_renderer *r, const char **reason)
{
    if (reason)
        *reason = r->integrator_reason;
    return r->integrator;
}

bool vkrt_renderer_per_pixel_counts(const vkrt_renderer *r)
{
    return r->target_error > 0;
}

const gpu_buffer *vkrt_renderer_image(const vkrt_renderer *r)
{
    return &r->image;
}

const vkrt_accel_stats *vkrt_renderer_accel_stats(const vkrt_renderer *r)
{
    return &r->accel.stats;
}

vkrt_renderer_memory vkrt_renderer_memory_use(const vkrt_renderer *r)
{
    vkrt_renderer_memory m = {
        .triangles = gpu_array_device_bytes(&r->triangles) + gpu_array_device_bytes(&r->normals) +
                     gpu_array_device_bytes(&r->texcoords) +
                     gpu_array_device_bytes(&r->triangle_material),
        .nodes = r->accel.info.device_bytes + gpu_array_device_bytes(&r->accel.nodes) +
                 gpu_array_device_bytes(&r->accel.refs),
        .textures = r->texture_infos.device_bytes + gpu_array_device_bytes(&r->texels),
        .rays = r->rays.device_bytes + r->rays_b.device_bytes + r->hits.device_bytes +
                r->visibility.device_bytes + r->slots.device_bytes,
        .image = r->image.device_bytes + r->aov_planes.device_bytes,
        .other = r->materials.device_bytes + r->lights.device_bytes + r->counters.device_bytes +
                 r->waves.device_bytes + r->emitters.device_bytes + r->environment.device_bytes +
                 r->plastic_tables.device_bytes + r->split_addresses.device_bytes,
    };
    m.total = m.triangles + m.nodes + m.textures + m.rays + m.image + m.other;
    return m;
}

const vkrt_tuning *vkrt_renderer_tuning(const vkrt_renderer *r)
{
    return &r->tuning;
}

bool vkrt_renderer_texel_loads(const vkrt_renderer *r)
{
    return r->texel_loads;
}

void vkrt_renderer_destroy(vkrt_renderer *r)
{
    if (!r)
        return;
    renderer_kernels_abandon(r);
    free(r->material_cutouts);
    gpu_pipeline *pipelines[] = {&r->order,     &r->adapt_dispatch, &r->adapt, &r->shade,
                                 &r->prepare,   &r->count,
                                 &r->occlusion,      &r->light, &r->trace, &r->raygen};
    for (size_t i = 0; i < sizeof pipelines / sizeof *pipelines; ++i)
        gpu_pipeline_destroy(r->ctx, pipelines[i]);
    /* The views before the buffers they look into. */
    gpu_buffer_view_destroy(r->ctx, &r->triangle_view);
    gpu_buffer_view_destroy(r->ctx, &r->node_view);
    renderer_destroy_ray_buffers(r);
    renderer_adaptive_destroy_buffers(r);
    gpu_buffer *buffers[] = {&r->aov_planes,      &r->split_addresses, &r->counters,      &r->image,
                             &r->waves,           &r->lights,        &r->materials,
                             &r->texture_infos,   &r->emitters,      &r->environment,
                             &r->plastic_tables};
    for (size_t i = 0; i < sizeof buffers / sizeof *buffers; ++i)
        gpu_buffer_destroy(r->ctx, buffers[i]);
    gpu_array *arrays[] = {&r->triangle_material, &r->normals, &r->texcoords, &r->triangles,
                           &r->texels};
    for (size_t i = 0; i < sizeof arrays / sizeof *arrays; ++i)
        gpu_array_destroy(r->ctx, arrays[i]);
    vkrt_accel_gpu_destroy(&r->accel, r->ctx);
    free(r->light_kinds);
    for (uint32_t i = 0; r->material_names && i < r->material_count; ++i)
        free(r->material_names[i]);
    free(r->material_names);
    gpu_storage_set_destroy(r->ctx, &r->set);
    free(r);
}
