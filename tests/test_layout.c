/*
 * test_layout.c: the structs of glsl/shared.h have the same layout in C and in the kernels.
 *
 * A kernel writes a distinct value into every field of every shared struct, inside one std430
 * block (and into the second element of arrays, to check strides); the host reads the block back
 * through the C structs and checks that each field holds its value. A second kernel copies its
 * push constants (FrameParams) into a buffer, which must match what the host pushed byte for
 * byte. Any disagreement of offsets, sizes or alignment shows up as a wrong value. A third kernel
 * makes rays with glsl/lib/ray_record.glsl's constructors, and the host reads every packed lane
 * back through the same file's accessors, compiled as C.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "../glsl/lib/ray_record.glsl"
#include "../glsl/lib/rng.glsl"
#include "gpu/array.h"
#include "gpu_fixture.h"

typedef struct Probe {
    Ray ray;
    Hit hit;
    Triangle triangle;
    TriangleNormals normals;
    Material material;
    Light light;
    FrameParams params;
    Counters counters;
    BvhQuad node;
    BvhPair pair;
    GridInfo grid;
    TriangleTexcoords texcoords;
    WaveState wave;
    TextureInfo texture;
    Hit hit_pair[2];
    Ray ray_pair[2];
    Material material_pair[2];
    LightInfo light_info;
    Emitter emitter_pair[2];
    KdNode kd_pair[2];
    PixelStats pixel_stats_pair[2];
    ActivePixels active_pixels;
} Probe;

typedef enum { F32, U32, VEC4, UVEC4 } field_type;

typedef struct field {
    const char *glsl;   /* the field as the kernel names it */
    size_t offset;      /* where C puts it */
    field_type type;
} field;

#define FIELD(member, path, type) {#member "." #path, offsetof(Probe, member) + offsetof(__typeof__(((Probe *)0)->member), path), type}

static const field fields[] = {
    FIELD(ray, origin, VEC4), FIELD(ray, direction, VEC4), FIELD(ray, importance, VEC4),
    FIELD(ray, info, UVEC4), FIELD(ray, payload, VEC4),
    FIELD(hit, t, F32), FIELD(hit, u, F32), FIELD(hit, v, F32), FIELD(hit, triangle, U32),
    FIELD(triangle, v0, VEC4), FIELD(triangle, v1, VEC4), FIELD(triangle, v2, VEC4),
    FIELD(normals, n0, VEC4), FIELD(normals, n1, VEC4), FIELD(normals, n2, VEC4),
    FIELD(material, params[0], VEC4), FIELD(material, params[4], VEC4),
    FIELD(material, textures[0], UVEC4), FIELD(material, textures[1], UVEC4),
    FIELD(material, info, UVEC4), FIELD(material, maps, VEC4),
    FIELD(light, position, VEC4), FIELD(light, direction, VEC4), FIELD(light, colour, VEC4),
    FIELD(light, info, UVEC4),
    FIELD(params, eye, VEC4), FIELD(params, right, VEC4), FIELD(params, up, VEC4),
    FIELD(params, forward, VEC4), FIELD(params, image, UVEC4),
    FIELD(params, counts, UVEC4), FIELD(params, stage, UVEC4), FIELD(params, wave, UVEC4),
    FIELD(counters, shadow_rays, U32), FIELD(counters, secondary_rays, U32),
    FIELD(counters, max_wave, U32), FIELD(counters, overcast, U32),
    FIELD(counters, overcast_material, U32), FIELD(counters, nonfinite, U32),
    FIELD(counters, overcount, U32), FIELD(counters, trace_rays, U32),
    FIELD(counters, trace_steps, U32), FIELD(counters, trace_tests, U32),
    FIELD(counters, trace_busy, U32), FIELD(counters, trace_widest, U32),
    FIELD(counters, subgroup_size, U32), FIELD(counters, active_pixels, U32),
    FIELD(counters, primary_rays, U32), FIELD(counters, pad, U32),
    FIELD(pixel_stats_pair[0], mean, F32), FIELD(pixel_stats_pair[0], m2, F32),
    FIELD(pixel_stats_pair[1], samples, U32), FIELD(pixel_stats_pair[1], listed, U32),
    FIELD(active_pixels, groups_x, U32), FIELD(active_pixels, groups_y, U32),
    FIELD(active_pixels, groups_z, U32), FIELD(active_pixels, count, U32),
    FIELD(active_pixels, appended, U32), FIELD(active_pixels, pad2, U32),
    FIELD(texcoords, uv01, VEC4), FIELD(texcoords, uv2, VEC4),
    FIELD(wave, groups_x, U32), FIELD(wave, groups_y, U32), FIELD(wave, groups_z, U32),
    FIELD(wave, ray_count, U32),
    FIELD(texture, offset, U32), FIELD(texture, width, U32), FIELD(texture, height, U32),
    FIELD(texture, flags, U32), FIELD(texture, uv_matrix, VEC4), FIELD(texture, uv_offset, VEC4),
    FIELD(node, origin, VEC4), FIELD(node, planes, UVEC4), FIELD(node, planes_z, UVEC4),
    FIELD(node, refs, UVEC4),
    FIELD(pair, x, VEC4), FIELD(pair, y, VEC4), FIELD(pair, z, VEC4), FIELD(pair, refs, UVEC4),
    FIELD(light_info, emitter_count, U32), FIELD(light_info, emitter_power, F32),
    FIELD(light_info, environment_width, U32), FIELD(light_info, environment_height, U32),
    FIELD(light_info, environment_scale, F32), FIELD(light_info, environment_rotate, F32),
    FIELD(light_info, environment_pixels, U32), FIELD(light_info, environment_integral, F32),
    FIELD(light_info, environment_sampled, U32), FIELD(light_info, pad2, U32),
    FIELD(emitter_pair[0], triangle, U32), FIELD(emitter_pair[0], keep, F32),
    FIELD(emitter_pair[1], alias, U32), FIELD(emitter_pair[1], power, F32),
    FIELD(kd_pair[0], split, F32), FIELD(kd_pair[0], axis, U32), FIELD(kd_pair[1], a, U32),
    FIELD(kd_pair[1], b, U32),
    FIELD(grid, lo, VEC4), FIELD(grid, hi, VEC4), FIELD(grid, cell_size, VEC4), FIELD(grid, dims, UVEC4),
    {"hit_pair[1].triangle", offsetof(Probe, hit_pair) + sizeof(Hit) + offsetof(Hit, triangle), U32},
    {"hit_pair[1].t", offsetof(Probe, hit_pair) + sizeof(Hit) + offsetof(Hit, t), F32},
    {"ray_pair[1].info", offsetof(Probe, ray_pair) + sizeof(Ray) + offsetof(Ray, info), UVEC4},
    {"ray_pair[1].origin", offsetof(Probe, ray_pair) + sizeof(Ray) + offsetof(Ray, origin), VEC4},
    {"ray_pair[1].payload", offsetof(Probe, ray_pair) + sizeof(Ray) + offsetof(Ray, payload), VEC4},
    {"material_pair[1].info", offsetof(Probe, material_pair) + sizeof(Material) + offsetof(Material, info), UVEC4},
    {"material_pair[1].maps", offsetof(Probe, material_pair) + sizeof(Material) + offsetof(Material, maps), VEC4},
    {"material_pair[1].params[1]", offsetof(Probe, material_pair) + sizeof(Material) + offsetof(Material, params[1]), VEC4},
};
static const size_t field_count = sizeof fields / sizeof *fields;

/* Field k's components get the values 4k+1 .. 4k+4: distinct everywhere, exact as floats. */
static char *probe_kernel(void)
{
    size_t cap = 16384, used = 0;
    char *src = malloc(cap);
    used += (size_t)snprintf(src + used, cap - used,
                             "#include \"shared.h\"\n"
                             "layout(local_size_x_id = 0) in;\n"
                             "layout(std430, binding = 0) buffer Out {\n"
                             "  Ray ray; Hit hit; Triangle triangle; TriangleNormals normals;\n"
                             "  Material material; Light light; FrameParams params;\n"
                             "  Counters counters; BvhQuad node; BvhPair pair; GridInfo grid;\n"
                             "  TriangleTexcoords texcoords; WaveState wave; TextureInfo texture;\n"
                             "  Hit hit_pair[2]; Ray ray_pair[2]; Material material_pair[2];\n"
                             "  LightInfo light_info; Emitter emitter_pair[2];\n"
                             "  KdNode kd_pair[2];\n"
                             "  PixelStats pixel_stats_pair[2]; ActivePixels active_pixels;\n"
                             "};\n"
                             "void main() {\n"
                             "  if (gl_GlobalInvocationID.x != 0u) return;\n");
    for (size_t k = 0; k < field_count; ++k) {
        unsigned b = 4 * (unsigned)k;
        const char *f = fields[k].glsl;
        switch (fields[k].type) {
        case F32: used += (size_t)snprintf(src + used, cap - used, "  %s = %u.0;\n", f, b + 1); break;
        case U32: used += (size_t)snprintf(src + used, cap - used, "  %s = %uu;\n", f, b + 1); break;
        case VEC4:
            used += (size_t)snprintf(src + used, cap - used, "  %s = vec4(%u, %u, %u, %u);\n", f,
                                     b + 1, b + 2, b + 3, b + 4);
            break;
        case UVEC4:
            used += (size_t)snprintf(src + used, cap - used, "  %s = uvec4(%uu, %uu, %uu, %uu);\n",
                                     f, b + 1, b + 2, b + 3, b + 4);
            break;
        }
    }
    snprintf(src + used, cap - used, "}\n");
    return src;
}

static void test_buffer_layout(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer buf;
    assert_true(gpu_buffer_create(&ctx, &buf, sizeof(Probe), "probe", &err));
    assert_true(gpu_buffer_zero(&ctx, &buf, &err));
    char *src = probe_kernel();
    fixture_run_kernel(&ctx, src, &buf, 1, NULL, 0, 1);
    free(src);
    Probe probe;
    assert_true(gpu_buffer_download(&ctx, &buf, &probe, sizeof probe, &err));
    const unsigned char *bytes = (const unsigned char *)&probe;
    for (size_t k = 0; k < field_count; ++k) {
        int components = fields[k].type == VEC4 || fields[k].type == UVEC4 ? 4 : 1;
        bool is_float = fields[k].type == F32 || fields[k].type == VEC4;
        for (int c = 0; c < components; ++c) {
            unsigned expected = 4 * (unsigned)k + 1 + (unsigned)c;
            const unsigned char *at = bytes + fields[k].offset + 4 * (size_t)c;
            if (is_float) {
                float value;
                memcpy(&value, at, 4);
                if (value != (float)expected)
                    fail_msg("%s[%d]: C reads %g, the kernel wrote %u", fields[k].glsl, c,
                             value, expected);
            } else {
                uint32_t value;
                memcpy(&value, at, 4);
                if (value != expected)
                    fail_msg("%s[%d]: C reads %u, the kernel wrote %u", fields[k].glsl, c,
                             value, expected);
            }
        }
    }
    gpu_buffer_destroy(&ctx, &buf);
    fixture_context_destroy(&ctx);
}

static void test_push_constant_layout(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    FrameParams pushed;
    float *words = (float *)&pushed;
    for (size_t i = 0; i < sizeof pushed / 4; ++i)
        words[i] = (float)(i + 1);
    /* The uvec4 members hold integers, not float bit patterns: set them as such. */
    pushed.image = (uvec4){101, 102, 103, 104};
    pushed.counts = (uvec4){201, 202, 203, 204};
    pushed.stage = (uvec4){301, 302, 303, 304};
    pushed.wave = (uvec4){401, 402, 403, 404};
    gpu_buffer buf;
    assert_true(gpu_buffer_create(&ctx, &buf, sizeof(FrameParams), "params", &err));
    assert_true(gpu_buffer_zero(&ctx, &buf, &err));
    fixture_run_kernel(&ctx,
                       "#include \"shared.h\"\n"
                       "layout(local_size_x_id = 0) in;\n"
                       "layout(push_constant) uniform Push { FrameParams frame; };\n"
                       "layout(std430, binding = 0) buffer Out { FrameParams copy; };\n"
                       "void main() { if (gl_GlobalInvocationID.x == 0u) copy = frame; }\n",
                       &buf, 1, &pushed, sizeof pushed, 1);
    FrameParams copied;
    assert_true(gpu_buffer_download(&ctx, &buf, &copied, sizeof copied, &err));
    assert_memory_equal(&pushed, &copied, sizeof pushed);
    gpu_buffer_destroy(&ctx, &buf);
    fixture_context_destroy(&ctx);
}

/* Rays made by the kernels' constructors read back through the accessors, compiled as C: each
 * lane holds what its name says. */
static void test_ray_record(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer buf;
    Ray made[4];
    assert_true(gpu_buffer_create(&ctx, &buf, sizeof made, "rays", &err));
    assert_true(gpu_buffer_zero(&ctx, &buf, &err));
    fixture_run_kernel(&ctx,
                       "#include \"lib/ray_record.glsl\"\n"
                       "layout(local_size_x_id = 0) in;\n"
                       "layout(std430, binding = 0) buffer Out { Ray made[4]; };\n"
                       "void main()\n{\n"
                       "    if (gl_GlobalInvocationID.x != 0u) return;\n"
                       "    Ray camera = ray_camera(7u, 8u, 9u);\n"
                       "    ray_set_segment(camera, vec3(1.0), vec3(0.0, 0.0, 1.0), 0.5, 4.0);\n"
                       "    made[0] = camera;\n"
                       "    made[1] = ray_cast(camera, 2u, vec3(0.0), vec3(0.0, 1.0, 0.0),\n"
                       "                       vec3(0.25), 0.75, vec4(0.0));\n"
                       "    made[2] = ray_dead(made[1]);\n"
                       "    Ray killed = made[1];\n"
                       "    ray_kill(killed);\n"
                       "    made[3] = killed;\n"
                       "}\n",
                       &buf, 1, NULL, 0, 1);
    assert_true(gpu_buffer_download(&ctx, &buf, made, sizeof made, &err));
    gpu_buffer_destroy(&ctx, &buf);
    fixture_context_destroy(&ctx);

    assert_int_equal(ray_pixel(made[0]), 7);
    assert_int_equal(ray_seed(made[0]), 8);
    assert_int_equal(ray_sample(made[0]), 9);
    assert_int_equal(ray_depth(made[0]), 0);
    assert_false(ray_is_dead(made[0]));
    assert_true(ray_tmin(made[0]) == 0.5f && ray_tmax(made[0]) == 4.0f);
    assert_true(ray_bsdf_pdf(made[0]) == 0.0f);

    assert_int_equal(ray_pixel(made[1]), 7);
    assert_int_equal(ray_seed(made[1]), rng_child_seed(8, 2));
    assert_int_equal(ray_sample(made[1]), 9);
    assert_int_equal(ray_depth(made[1]), 1);
    assert_false(ray_is_dead(made[1]));
    assert_true(ray_bsdf_pdf(made[1]) == 0.75f && made[1].importance.x == 0.25f);
    assert_true(ray_tmin(made[1]) == 0.0f && ray_tmax(made[1]) == 3.4e38f);

    assert_true(ray_is_dead(made[2]));
    assert_int_equal(ray_pixel(made[2]), 7);
    assert_int_equal(ray_depth(made[2]), 2);
    assert_true(ray_tmax(made[2]) < 0.0f);

    assert_true(ray_is_dead(made[3]));
    assert_int_equal(ray_sample(made[3]), 9);
    assert_int_equal(ray_depth(made[3]), 1);

    /* FrameParams.stage: each setter writes what its getter reads. */
    FrameParams f = {0};
    frame_set_brute_range(&f, 11, 12, true);
    frame_set_light_words(&f, 13);
    assert_int_equal(frame_brute_first(f), 11);
    assert_int_equal(frame_brute_end(f), 12);
    assert_true(frame_brute_merges(f));
    assert_int_equal(frame_light_words(f), 13);
    frame_set_order_step(&f, VKRT_ORDER_PLACE);
    assert_int_equal(frame_order_step(f), VKRT_ORDER_PLACE);
    frame_set_adapt_step(&f, VKRT_ADAPT_SELECT);
    assert_int_equal(frame_adapt_step(f), VKRT_ADAPT_SELECT);
    assert_int_equal(frame_light_words(f), 13);
}

/* The host-side sizes the kernels rely on (std430 strides of arrays of these structs). */
static void test_sizes(void **state)
{
    (void)state;
    assert_int_equal(sizeof(Ray), 80);
    assert_int_equal(sizeof(Hit), 16);
    assert_int_equal(sizeof(Triangle), 48);
    assert_int_equal(sizeof(TriangleNormals), 48);
    assert_int_equal(sizeof(Material), 144);
    assert_int_equal(sizeof(TriangleTexcoords), 32);
    assert_int_equal(sizeof(WaveState), 16);
    assert_int_equal(sizeof(TextureInfo), 48);
    assert_int_equal(sizeof(Light), 64);
    assert_int_equal(sizeof(FrameParams), 128);
    assert_true(sizeof(FrameParams) <= 128); /* the push constant size every device offers */
    assert_int_equal(sizeof(Counters), 64);
    assert_int_equal(sizeof(BvhQuad), 64);
    assert_int_equal(sizeof(BvhPair), 64);
    assert_int_equal(sizeof(GridInfo), 64);
    assert_int_equal(sizeof(Instance), 112);
    assert_int_equal(sizeof(LightInfo), 48);
    assert_int_equal(sizeof(Emitter), 16);
    assert_int_equal(sizeof(KdNode), 16);
}

/* A buffer past one storage buffer's range (a scene too big for it) is refused with a message
 * that names it, its size and the device's limit that binds, and nothing is left allocated. */
static void test_buffer_over_the_limit(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer buf;
    size_t too_big = (size_t)ctx.properties.limits.maxStorageBufferRange + 16;
    assert_false(gpu_buffer_create(&ctx, &buf, too_big, "triangles", &err));
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "triangles needs"));
    /* The message names the smaller of the two limits (some drivers allocate less than one
     * storage buffer may address). */
    bool by_allocation = ctx.max_allocation < ctx.properties.limits.maxStorageBufferRange;
    assert_non_null(strstr(err.msg, by_allocation ? "maxMemoryAllocationSize"
                                                  : "maxStorageBufferRange"));
    assert_null(buf.buffer);
    fixture_context_destroy(&ctx);
}

/* An array past ctx->split_bytes is split into chunks of a power of two of elements, each holding
 * its elements in order (read back chunk by chunk against the data); one past 64 chunks is
 * refused with its size; one that fits is one buffer, shift 0. */
static void test_split_array(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    enum { count = 1000 };
    uint32_t data[count], back[count];
    for (uint32_t i = 0; i < count; ++i)
        data[i] = i * 2654435761u;
    gpu_array a;
    assert_true(gpu_array_create_from(&ctx, &a, data, sizeof *data, count, "words", &err));
    assert_int_equal(a.chunk_count, 1);
    assert_int_equal(a.shift, 0);
    gpu_array_destroy(&ctx, &a);
    if (!ctx.device_addresses) {
        fixture_context_destroy(&ctx);
        skip();
    }
    ctx.split_bytes = 1000; /* 250 words: chunks of 128 */
    assert_true(gpu_array_create_from(&ctx, &a, data, sizeof *data, count, "words", &err));
    assert_int_equal(a.shift, 7);
    assert_int_equal(a.chunk_count, 8);
    for (uint32_t c = 0; c < a.chunk_count; ++c) {
        size_t first = (size_t)c << a.shift, n = count - first < 128 ? count - first : 128;
        assert_int_equal(a.chunks[c].size, n * sizeof *data);
        assert_true(gpu_buffer_download(&ctx, &a.chunks[c], back + first, n * sizeof *data, &err));
    }
    assert_memory_equal(back, data, sizeof data);
    gpu_array_destroy(&ctx, &a);
    assert_int_equal(ctx.memory_used, 0);
    ctx.split_bytes = 40; /* chunks of 8 words: 125 of them */
    assert_false(gpu_array_create_from(&ctx, &a, data, sizeof *data, count, "words", &err));
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "its words take 4000 bytes (1000 x 4 bytes), more than 64 "
                                    "buffers of 32 bytes hold"));
    assert_int_equal(ctx.memory_used, 0);
    fixture_context_destroy(&ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sizes),
        cmocka_unit_test(test_buffer_over_the_limit),
        cmocka_unit_test(test_split_array),
        cmocka_unit_test(test_buffer_layout),
        cmocka_unit_test(test_push_constant_layout),
        cmocka_unit_test(test_ray_record),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
