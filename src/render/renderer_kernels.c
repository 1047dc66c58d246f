/*
 * renderer_kernels.c: the wave kernels compiled for one scene and device. Every kernel gets the
 * same specialization constants (glsl/shared.h's VKRT_SPEC_*): what the scene has (normals,
 * texture coordinates), which structure traversal walks and how (the tuning's choices), so each
 * choice is dead code elimination in the driver rather than a branch at run time. count.comp and
 * shade.comp include the material module generated from the materials the scene uses.
 */
#include <stdlib.h>
#include <string.h>

#include "../gpu/shader.h"
#include "kernel_sources.h"
#include "renderer_private.h"

/* What every wave kernel may use beyond core GLSL on this device: subgroup operations (count.comp
 * reserves ray slots with one atomic per subgroup with them, one per ray without; the trace
 * kernels' statistics need them, and are not built without). */
#define SUBGROUPS                                                                                  \
    "#extension GL_KHR_shader_subgroup_arithmetic : require\n"                                     \
    "#extension GL_KHR_shader_subgroup_ballot : require\n"                                         \
    "#extension GL_KHR_shader_subgroup_vote : require\n"                                           \
    "#define VKRT_SUBGROUPS 1\n"
/* A scene with an array split over several buffers reads it through device addresses
 * (lib/bindings.glsl); every other scene's kernels go without, as they were. */
#define SPLIT_ARRAYS                                                                               \
    "#extension GL_EXT_buffer_reference : require\n"                                               \
    "#extension GL_EXT_buffer_reference_uvec2 : require\n"                                         \
    "#define VKRT_SPLIT_ARRAYS 1\n"

static const char *kernel_preamble(const vkrt_renderer *r)
{
    if (r->split)
        return r->ctx->subgroup_arithmetic ? SUBGROUPS SPLIT_ARRAYS : SPLIT_ARRAYS;
    return r->ctx->subgroup_arithmetic ? SUBGROUPS : "";
}

typedef struct kernel_spec {
    uint32_t workgroup_size;
    const gpu_spec_constant *constants;
    uint32_t count;
} kernel_spec;

/* Compiles an embedded kernel (glsl/path) and makes its pipeline. */
static bool create_kernel(vkrt_renderer *r, gpu_pipeline *pipe, const char *path,
                          const kernel_spec *spec, vkrt_error *err)
{
    gpu_shader_sources sources = {
        .lookup = vkrt_kernel_source_lookup,
        .display_prefix = "glsl/",
        .preamble = kernel_preamble(r),
    };
    uint32_t *spirv;
    size_t words;
    if (!gpu_shader_compile(&sources, path, &spirv, &words, err))
        return false;
    bool ok = gpu_pipeline_create(r->ctx, pipe, &r->set, spirv, words, spec->workgroup_size,
                                  spec->constants, spec->count, path, err);
    free(spirv);
    return ok;
}

/* Compiles a kernel that includes the generated material module, and makes its pipeline. */
static bool create_material_kernel(vkrt_renderer *r, gpu_pipeline *pipe, const char *path,
                                   const vkrt_material_kernel *kernel,
                                   const vkrt_scene_materials *mats, const kernel_spec *spec,
                                   vkrt_error *err)
{
    uint32_t *spirv;
    size_t words;
    if (!vkrt_material_kernel_compile(kernel, mats, path, kernel_preamble(r), &spirv, &words, err))
        return false;
    bool ok = gpu_pipeline_create(r->ctx, pipe, &r->set, spirv, words, spec->workgroup_size,
                                  spec->constants, spec->count, path, err);
    free(spirv);
    return ok;
}

static uint32_t traverse_kind(vkrt_accel_kind kind)
{
    return kind == VKRT_ACCEL_BVH      ? VKRT_TRAVERSE_BVH
           : kind == VKRT_ACCEL_GRID   ? VKRT_TRAVERSE_GRID
           : kind == VKRT_ACCEL_KDTREE ? VKRT_TRAVERSE_KDTREE
                                       : VKRT_TRAVERSE_BRUTE;
}

bool renderer_create_kernels(vkrt_renderer *r, bool has_normals, bool has_texcoords,
                             bool traversal_stats, const vkrt_material_kernel *kernel,
                             const vkrt_scene_materials *mats, vkrt_error *err)
{
    uint32_t workgroup_size = r->tuning.workgroup_size;
    /* A float specialization constant travels as its 32 bits. */
    uint32_t clamp_bits, target_bits;
    memcpy(&clamp_bits, &r->clamp, sizeof clamp_bits);
    memcpy(&target_bits, &r->target_error, sizeof target_bits);
    const gpu_spec_constant constants[] = {
        {VKRT_SPEC_HAS_NORMALS, has_normals},
        {VKRT_SPEC_ACCEL_KIND, traverse_kind(r->accel.stats.kind)},
        {VKRT_SPEC_HAS_TEXCOORDS, has_texcoords},
        {VKRT_SPEC_WAVE_WORKGROUP, workgroup_size},
        {VKRT_SPEC_TRAVERSAL_STATS, traversal_stats},
        {VKRT_SPEC_BVH_WIDTH, r->accel.stats.bvh_width},
        {VKRT_SPEC_TEXEL_LOADS, r->texel_loads},
        {VKRT_SPEC_NESTED_WALK, r->tuning.nested_walk},
        {VKRT_SPEC_INTEGRATOR,
         r->integrator == VKRT_INTEGRATOR_PATH ? VKRT_INTEGRATE_PATH : VKRT_INTEGRATE_WHITTED},
        {VKRT_SPEC_LIGHT_SAMPLING, r->light_sampling},
        {VKRT_SPEC_HAS_CUTOUTS, r->has_cutouts},
        {VKRT_SPEC_EMITTER_LIGHT, r->emitter_light},
        {VKRT_SPEC_CLAMP, clamp_bits},
        {VKRT_SPEC_SURFACE_MAPS, r->surface_maps},
        {VKRT_SPEC_TARGET_ERROR, target_bits},
        /* How each array is split (0: one buffer); read only where r->split. */
        {VKRT_SPEC_SPLIT_TRIANGLES, renderer_split_shift(r, VKRT_SPLIT_TRIANGLES)},
        {VKRT_SPEC_SPLIT_NORMALS, renderer_split_shift(r, VKRT_SPLIT_NORMALS)},
        {VKRT_SPEC_SPLIT_TEXCOORDS, renderer_split_shift(r, VKRT_SPLIT_TEXCOORDS)},
        {VKRT_SPEC_SPLIT_TRIANGLE_MATERIAL, renderer_split_shift(r, VKRT_SPLIT_TRIANGLE_MATERIAL)},
        {VKRT_SPEC_SPLIT_NODES, renderer_split_shift(r, VKRT_SPLIT_NODES)},
        {VKRT_SPEC_SPLIT_REFS, renderer_split_shift(r, VKRT_SPLIT_REFS)},
        {VKRT_SPEC_SPLIT_TEXELS, renderer_split_shift(r, VKRT_SPLIT_TEXELS)},
        {VKRT_SPEC_MATERIAL_ORDER, r->material_order},
    };
    const uint32_t count = sizeof constants / sizeof *constants;
    const kernel_spec wave = {workgroup_size, constants, count};
    /* prepare.comp writes the next depth's indirect dispatch: one invocation. */
    const kernel_spec single = {1, constants, count};
    /* The light kernel: Whitted's shadow rays for the materials to read, or the path tracer's
     * next-event estimation, which evaluates the materials' BSDFs itself. */
    bool path = r->integrator == VKRT_INTEGRATOR_PATH;
    return create_kernel(r, &r->raygen, "raygen.comp", &wave, err) &&
           create_kernel(r, &r->trace, "trace.comp", &wave, err) &&
           (path ? create_material_kernel(r, &r->light, "nee.comp", kernel, mats, &wave, err)
                 : create_kernel(r, &r->light, "light.comp", &wave, err)) &&
           create_kernel(r, &r->occlusion, "occlusion.comp", &wave, err) &&
           create_kernel(r, &r->prepare, "prepare.comp", &single, err) &&
           create_material_kernel(r, &r->count, "count.comp", kernel, mats, &wave, err) &&
           create_material_kernel(r, &r->shade, "shade.comp", kernel, mats, &wave, err) &&
           (!r->material_order || create_kernel(r, &r->order, "order.comp", &wave, err)) &&
           /* Adaptive sampling's kernels only where there is a target error. */
           (r->target_error <= 0 ||
            (create_kernel(r, &r->adapt, "adapt.comp", &wave, err) &&
             create_kernel(r, &r->adapt_dispatch, "adapt_dispatch.comp", &single, err)));
}
