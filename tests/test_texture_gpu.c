/*
 * test_texture_gpu.c: glsl/lib/texture.glsl on the GPU agrees with its CPU reference
 * (vkrt_texture_sample and vkrt_texture_texel in src/scene/texture.c).
 *
 * test_texture.c checks the CPU reference against closed forms; this test closes the loop: a
 * small kernel includes the real texture.glsl, samples a hand-made texture set (sRGB, linear and
 * half-float textures, odd sizes, a 1x1; each also read clamped, mirrored, nearest, through a
 * KHR_texture_transform and by one channel) at several hundred uv (negative, past 1, on texel centres
 * and seams, huge, non-finite) and reads texels at wrapped integer coordinates; every result must
 * match the CPU's. Bilinear filtering is continuous, so a GPU that rounds a position differently
 * (fused multiply-add, another fract) moves the result by about that rounding only: a small
 * tolerance, not an exact match, is the right test. Nearest filtering is not continuous, but
 * its position is one multiplication of a wrapped coordinate, rounded alike on both sides.
 */
#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "scene/texture.h"

static const char KERNEL[] =
    "#include \"shared.h\"\n"
    "layout(local_size_x_id = 0) in;\n"
    "layout(std430, binding = 0) readonly buffer Infos { TextureInfo texture_infos[]; };\n"
    "layout(std430, binding = 1) readonly buffer Texels { uint texels[]; };\n"
    "uint texel_word(uint i) { return texels[i]; }\n"
    "layout(std430, binding = 2) readonly buffer Queries { uvec4 queries[]; };\n"
    "layout(std430, binding = 3) buffer Results { vec4 results[]; };\n"
    "layout(push_constant) uniform Push { uint count; };\n"
    "#include \"lib/texture.glsl\"\n"
    "void main() {\n"
    "  uint i = gl_GlobalInvocationID.x;\n"
    "  if (i >= count) return;\n"
    "  uvec4 q = queries[i];\n"
    "  results[i] = q.w == 0u ? texture_sample(q.x, uintBitsToFloat(q.yz))\n"
    "                         : texture_texel(q.x, int(q.y), int(q.z));\n"
    "}\n";

/* A query: texture x; w = 0: sample at uv = (y, z) as float bits; w = 1: texel (int y, int z). */
typedef struct query {
    uint32_t texture, a, b, kind;
} query;

static uint32_t rng_state = 12345u;

static uint32_t next_random(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state;
}

/* Uniform in [lo, hi). */
static float random_float(float lo, float hi)
{
    return lo + (hi - lo) * (float)(next_random() >> 8) / 16777216.0f;
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Appends a texture of w x h texels with the given flags and random texel words to the set. HALF
 * texels get halves between 1/1024 and 64 (exponents 5..20), so values stay finite and varied. */
static void add_random_texture(vkrt_texture_set *set, uint32_t w, uint32_t h, uint32_t flags)
{
    size_t words = (size_t)w * h * (flags & VKRT_TEXTURE_HALF ? 2 : 1);
    set->info = realloc(set->info, (set->count + 1) * sizeof *set->info);
    set->texels = realloc(set->texels, (set->texel_words + words) * sizeof *set->texels);
    assert_non_null(set->info);
    assert_non_null(set->texels);
    set->info[set->count] = (vkrt_texture_info){(uint32_t)set->texel_words, w, h, flags};
    for (size_t i = 0; i < words; i++) {
        uint32_t r = next_random();
        if (flags & VKRT_TEXTURE_HALF) {
            uint32_t lo = (5u + (r >> 3) % 16u) << 10 | (r >> 9 & 0x3FFu);
            uint32_t hi = (5u + (r >> 19) % 16u) << 10 | (next_random() >> 7 & 0x3FFu);
            r = lo | hi << 16;
        }
        set->texels[set->texel_words + i] = r;
    }
    set->texel_words += words;
    set->count++;
}

enum { IMAGES = 6, VIEWS = 5 };

/* Whether got lies within what the CPU gives at the corners of a small box about (u, v): for a
 * transformed entry, the GPU may round the transform's products and sums differently (a fused
 * multiply-add), which moves the position by a few units in the last place of the coordinates;
 * filtered, the value moves within the box's corners, and nearest may take the texel across an
 * edge the point lies on. The box is several times that rounding, and no wider. */
static bool within_rounding(const vkrt_texture_set *set, uint32_t tex, float u, float v, int k,
                            float got)
{
    if (!isfinite(u) || !isfinite(v))
        return false;
    double delta = 1e-6 * (4.0 + 2.0 * (fabs(u) + fabs(v)));
    float lo = INFINITY, hi = -INFINITY;
    for (int du = -1; du <= 1; du++)
        for (int dv = -1; dv <= 1; dv++) {
            float c[4];
            vkrt_texture_sample(set, tex, (float)(u + du * delta), (float)(v + dv * delta), c);
            lo = fminf(lo, c[k]);
            hi = fmaxf(hi, c[k]);
        }
    float tolerance = 2e-5f * fmaxf(1.0f, fabsf(got));
    return got >= lo - tolerance && got <= hi + tolerance;
}

/* Adds to each of the set's images the entries that read it through other samplers, transforms
 * and channels, as maps make them (vkrt_texture_set_view): every wrap mode on each axis, nearest
 * filtering, a rotating, scaling, mirroring and shifting transform, channel selection. */
static void add_views(vkrt_texture_set *set)
{
    static const uint32_t flags[VIEWS] = {
        VKRT_TEXTURE_WRAP_U(VKRT_TEXTURE_CLAMP) | VKRT_TEXTURE_WRAP_V(VKRT_TEXTURE_MIRROR),
        VKRT_TEXTURE_WRAP_U(VKRT_TEXTURE_MIRROR) | VKRT_TEXTURE_WRAP_V(VKRT_TEXTURE_CLAMP) |
            VKRT_TEXTURE_NEAREST | VKRT_TEXTURE_CHANNEL(2u),
        VKRT_TEXTURE_TRANSFORM,
        VKRT_TEXTURE_TRANSFORM | VKRT_TEXTURE_NEAREST | VKRT_TEXTURE_CHANNEL(1u) |
            VKRT_TEXTURE_WRAP_U(VKRT_TEXTURE_MIRROR) | VKRT_TEXTURE_WRAP_V(VKRT_TEXTURE_MIRROR),
        VKRT_TEXTURE_NEAREST | VKRT_TEXTURE_CHANNEL(3u),
    };
    uint32_t images = set->count;
    set->info = realloc(set->info, images * (1 + VIEWS) * sizeof *set->info);
    assert_non_null(set->info);
    float offset[2] = {0.3f, -2.1f}, scale[2] = {1.5f, -0.75f}, matrix[4], translation[2];
    assert_false(vkrt_texture_uv_transform(offset, scale, 0.7f, matrix, translation));
    for (uint32_t t = 0; t < images; t++)
        for (uint32_t k = 0; k < VIEWS; k++) {
            vkrt_texture_info view = set->info[t];
            view.flags |= flags[k];
            if (flags[k] & VKRT_TEXTURE_TRANSFORM) {
                memcpy(view.uv_matrix, matrix, sizeof matrix);
                memcpy(view.uv_offset, translation, sizeof translation);
            }
            set->info[set->count++] = view;
        }
}

static void gpu_matches_cpu_reference(void **state)
{
    (void)state;
    vkrt_texture_set set = {0};
    add_random_texture(&set, 5, 3, VKRT_TEXTURE_SRGB);
    add_random_texture(&set, 4, 4, 0);
    add_random_texture(&set, 3, 2, VKRT_TEXTURE_HALF);
    add_random_texture(&set, 1, 1, VKRT_TEXTURE_SRGB);
    add_random_texture(&set, 7, 1, VKRT_TEXTURE_SRGB);
    add_random_texture(&set, 2, 9, VKRT_TEXTURE_HALF);
    add_views(&set);

    enum { PER_TEXTURE = 400, MAX_QUERIES = IMAGES * (1 + VIEWS) * PER_TEXTURE };
    assert_int_equal(set.count, IMAGES * (1 + VIEWS));
    static query queries[MAX_QUERIES];
    uint32_t n = 0;
    for (uint32_t t = 0; t < set.count; t++) {
        const vkrt_texture_info *info = &set.info[t];
        float special[] = {0.0f,   1.0f,        -1.0f,    0.5f,     1e-7f,
                           -1e-7f, 0.99999994f, 1000.37f, -2048.75f};
        size_t ns = sizeof special / sizeof special[0];
        for (size_t i = 0; i < ns; i++)
            for (size_t j = 0; j < ns; j++)
                queries[n++] = (query){t, float_bits(special[i]), float_bits(special[j]), 0};
        /* texel centres and the seams between texels, one repeat away */
        for (uint32_t x = 0; x <= info->width && n < (t + 1) * PER_TEXTURE - 200; x++)
            for (uint32_t y = 0; y <= info->height && n < (t + 1) * PER_TEXTURE - 200; y++) {
                float u = ((float)x + 0.5f) / (float)info->width + 1.0f;
                float v = 1.0f - (float)y / (float)info->height - 2.0f;
                queries[n++] = (query){t, float_bits(u), float_bits(v), 0};
            }
        queries[n++] = (query){t, float_bits(NAN), float_bits(0.3f), 0};
        queries[n++] = (query){t, float_bits(0.3f), float_bits(INFINITY), 0};
        queries[n++] = (query){t, float_bits(-INFINITY), float_bits(NAN), 0};
        int32_t far[] = {INT32_MIN, INT32_MAX, -1, 0, (int32_t)info->width, -(int32_t)info->height};
        for (size_t i = 0; i < 6; i++)
            queries[n++] = (query){t, (uint32_t)far[i], (uint32_t)far[5 - i], 1};
        while (n < (t + 1) * PER_TEXTURE) {
            if (next_random() & 1)
                queries[n++] =
                    (query){t, float_bits(random_float(-3, 3)), float_bits(random_float(-3, 3)), 0};
            else
                queries[n++] = (query){t, (uint32_t)(int32_t)(next_random() % 101) - 50,
                                       (uint32_t)(int32_t)(next_random() % 101) - 50, 1};
        }
    }

    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer buffers[4];
    assert_true(gpu_buffer_create(&ctx, &buffers[0], set.count * sizeof *set.info, "infos", &err));
    assert_true(gpu_buffer_create(&ctx, &buffers[1], set.texel_words * 4, "texels", &err));
    assert_true(gpu_buffer_create(&ctx, &buffers[2], n * sizeof *queries, "queries", &err));
    assert_true(gpu_buffer_create(&ctx, &buffers[3], n * 4 * sizeof(float), "results", &err));
    assert_true(gpu_buffer_upload(&ctx, &buffers[0], set.info, set.count * sizeof *set.info, &err));
    assert_true(gpu_buffer_upload(&ctx, &buffers[1], set.texels, set.texel_words * 4, &err));
    assert_true(gpu_buffer_upload(&ctx, &buffers[2], queries, n * sizeof *queries, &err));
    assert_true(gpu_buffer_zero(&ctx, &buffers[3], &err));
    fixture_run_kernel(&ctx, KERNEL, buffers, 4, &n, sizeof n, n);
    float *results = malloc(n * 4 * sizeof *results);
    assert_non_null(results);
    assert_true(gpu_buffer_download(&ctx, &buffers[3], results, n * 4 * sizeof *results, &err));
    for (int i = 3; i >= 0; i--)
        gpu_buffer_destroy(&ctx, &buffers[i]);
    fixture_context_destroy(&ctx);

    double worst = 0;
    uint32_t nudged = 0;
    for (uint32_t i = 0; i < n; i++) {
        const query *q = &queries[i];
        float want[4];
        if (q->kind == 0)
            vkrt_texture_sample(&set, q->texture, bits_float(q->a), bits_float(q->b), want);
        else
            vkrt_texture_texel(&set, q->texture, (int32_t)q->a, (int32_t)q->b, want);
        bool transformed = q->kind == 0 && (set.info[q->texture].flags & VKRT_TEXTURE_TRANSFORM);
        for (int k = 0; k < 4; k++) {
            float got = results[4 * i + k];
            double error = fabs((double)got - want[k]) / fmax(1.0, fabs(want[k]));
            if (!(error <= 2e-5) && transformed &&
                within_rounding(&set, q->texture, bits_float(q->a), bits_float(q->b), k, got)) {
                nudged++;
                continue;
            }
            if (!(error <= 2e-5))
                fail_msg("texture %u, %s (%g, %g), channel %d: GPU %.9g, CPU %.9g", q->texture,
                         q->kind ? "texel" : "sample at",
                         q->kind ? (double)(int32_t)q->a : (double)bits_float(q->a),
                         q->kind ? (double)(int32_t)q->b : (double)bits_float(q->b), k, (double)got,
                         (double)want[k]);
            worst = fmax(worst, error);
        }
    }
    printf("%u queries over %u textures; largest GPU-CPU difference %.3g; %u components of "
           "transformed samples within the rounding of their position\n",
           n, set.count, worst, nudged);
    free(results);
    vkrt_texture_set_free(&set);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpu_matches_cpu_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
