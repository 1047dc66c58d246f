/*
 * ray_record.glsl: the one place that reads and writes the packed lanes of glsl/shared.h's Ray
 * and FrameParams, each lane under the name of its one meaning. Every kernel goes through these
 * functions rather than through .w or .info, so that a lane that moves moves here only, and a
 * reader never has to know that a pdf travels in importance.w.
 *
 * Compiled as GLSL by the kernels and as C by the host (src/render) and tests/test_layout.c:
 * everything outside the VKRT_GLSL block is plain C and GLSL at once, so both sides use the same
 * names. The C-only block holds the setters of FrameParams' per-kernel lanes, which only the host
 * writes.
 */
#ifndef VKRT_RAY_RECORD_GLSL
#define VKRT_RAY_RECORD_GLSL

#include "../shared.h"

#ifdef VKRT_GLSL
#define VKRT_ACCESSOR
#else
#include <stdbool.h>
#include <string.h>
#define VKRT_ACCESSOR static inline
#endif

/* One accessor per lane: `Type name(Record record)` returns record.lane. */
#define VKRT_LANE(Type, name, Record, lane)                                                    \
    VKRT_ACCESSOR Type name(Record record)                                                     \
    {                                                                                          \
        return record.lane;                                                                    \
    }

/* ---- Ray ------------------------------------------------------------------------------------ */

/* ray_pixel: the pixel the ray adds its light to.
 * ray_seed: the state of the ray's hash stream (lib/rng.glsl), which Whitted's shaders and the
 *     path tracer past its sampler's dimensions draw from.
 * ray_depth: how many bounces the ray is from the camera (0: a camera ray).
 * ray_sample: the ray's sample index in its pixel over all the passes of a frame, what the path
 *     tracer's sampler (lib/sampler.glsl) draws its numbers by.
 * ray_tmin, ray_tmax: the segment of the ray that counts: hits at t in (tmin, tmax).
 * ray_bsdf_pdf: the solid-angle pdf of the BSDF sample that cast the ray, which the light it finds
 *     is weighed by against light sampling (lib/path.glsl); 0 where no light sample could have
 *     found that light: camera rays, delta lobes, and every ray of Whitted's integrator. */
VKRT_LANE(uint, ray_pixel, Ray, info.x)
VKRT_LANE(uint, ray_seed, Ray, info.y)
VKRT_LANE(uint, ray_sample, Ray, info.w >> VKRT_RAY_SAMPLE_SHIFT)
VKRT_LANE(float, ray_tmin, Ray, origin.w)
VKRT_LANE(float, ray_tmax, Ray, direction.w)
VKRT_LANE(float, ray_bsdf_pdf, Ray, importance.w)

/* ray_cone: the ray's cone for texture filtering (Akenine-Moller et al., "Texture Level of Detail
 * Strategies for Real-Time Ray Tracing", Ray Tracing Gems 2019, and "Improved Shader and Texture
 * Level of Detail Using Ray Cones", JCGT 2021): (width at the origin, spread angle in radians),
 * so that the cone is width + spread * t wide at distance t. Each is kept as the top 16 bits of
 * its float, rounded (bfloat16: the float's range, 8 bits of precision, a 0.6% error at most,
 * 0.01 of a mipmap level), since only the logarithm of the width matters. Zero for rays that carry
 * no cone (shadow rays, probes, the host's rays): textures are then read at full resolution. */
VKRT_ACCESSOR uint ray_cone_half(float f)
{
#ifdef VKRT_GLSL
    uint bits = floatBitsToUint(f);
#else
    uint bits;
    memcpy(&bits, &f, sizeof bits);
#endif
    /* Round to nearest: add half of the dropped part. A NaN stays a NaN, +-inf stays itself. */
    if ((bits & 0x7F800000u) != 0x7F800000u)
        bits += 0x7FFFu + ((bits >> 16) & 1u);
    return bits >> 16;
}

VKRT_ACCESSOR float ray_cone_float(uint half_bits)
{
    uint bits = half_bits << 16;
#ifdef VKRT_GLSL
    return uintBitsToFloat(bits);
#else
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
#endif
}

VKRT_ACCESSOR uint ray_cone_pack(float width, float spread)
{
    return ray_cone_half(width) | ray_cone_half(spread) << 16;
}

VKRT_ACCESSOR float ray_cone_width(Ray ray)
{
    return ray_cone_float(ray.info.z & 0xFFFFu);
}

VKRT_ACCESSOR float ray_cone_spread(Ray ray)
{
    return ray_cone_float(ray.info.z >> 16);
}

VKRT_ACCESSOR uint ray_depth(Ray ray)
{
    return (ray.info.w >> VKRT_RAY_DEPTH_SHIFT) & VKRT_RAY_DEPTH_MASK;
}

/* Whether the slot holds no ray (VKRT_RAY_DEAD in info.w): traced by nobody, shaded by nobody. */
VKRT_ACCESSOR bool ray_is_dead(Ray ray)
{
    return (ray.info.w & VKRT_RAY_DEAD) != 0u;
}

/* Whether the ray's path still owes its pixel the albedo and normal of its first non-delta hit
 * (VKRT_RAY_AOV_PENDING; lib/aov.glsl). Never set without --aov albedo or normal. */
VKRT_ACCESSOR bool ray_aov_pending(Ray ray)
{
    return (ray.info.w & VKRT_RAY_AOV_PENDING) != 0u;
}

/* ---- FrameParams.stage: one kernel's arguments for one dispatch ------------------------------ */

/* frame_brute_first, frame_brute_end: brute-force trace (lib/traverse_brute.glsl, trace.comp,
 *     occlusion.comp) tests triangles first .. end - 1 in this dispatch.
 * frame_order_step: order.comp's step, VKRT_ORDER_COUNT or VKRT_ORDER_PLACE.
 * frame_adapt_step: adapt.comp's step, VKRT_ADAPT_FOLD or VKRT_ADAPT_SELECT.
 * frame_light_words: the words of light visibility bits per ray, the same for every dispatch of a
 *     frame: bit i % 32 of word i / 32 is light i's (light.comp writes them, light_sample reads
 *     them). */
VKRT_LANE(uint, frame_brute_first, FrameParams, stage.x)
VKRT_LANE(uint, frame_brute_end, FrameParams, stage.y)
VKRT_LANE(uint, frame_order_step, FrameParams, stage.x)
VKRT_LANE(uint, frame_adapt_step, FrameParams, stage.x)
VKRT_LANE(uint, frame_light_words, FrameParams, stage.w)
#undef VKRT_LANE

/* Brute-force trace: whether this dispatch merges with the hits of the dispatches before it. */
VKRT_ACCESSOR bool frame_brute_merges(FrameParams f)
{
    return f.stage.z != 0u;
}

#ifdef VKRT_GLSL
#include "rng.glsl"

/* The farthest a ray reaches: a ray without an end of its own ends here. */
const float FAR = 3.4e38;

/* The light the ray carries back to its pixel per unit of what it finds (importance.rgb). */
vec3 ray_throughput(Ray ray)
{
    return ray.importance.rgb;
}

/* Camera ray number `sample_index` of pixel, with the hash stream at seed: depth 0, throughput
 * 1, no BSDF pdf, no payload, and no segment yet (ray_set_segment gives it one). */
Ray ray_camera(uint pixel, uint seed, uint sample_index)
{
    Ray ray;
    ray.origin = vec4(0.0);
    ray.direction = vec4(0.0);
    ray.importance = vec4(1.0, 1.0, 1.0, 0.0);
    ray.info = uvec4(pixel, seed, 0u, sample_index << VKRT_RAY_SAMPLE_SHIFT);
    ray.payload = vec4(0.0);
    return ray;
}

/* Gives the ray the cone (width at its origin, spread angle): ray_cone. */
void ray_set_cone(inout Ray ray, float width, float spread)
{
    ray.info.z = ray_cone_pack(width, spread);
}

/* The cone of a camera ray of frame f (RTG 2019, eq. 20.30): a pinhole's rays start as a point
 * and spread by one pixel's angle, atan(2 tan(fov / 2) / height), about 2 |up| / height since
 * up is scaled by tan(fov / 2); an orthographic camera's are a pixel wide and do not spread. The
 * thin lens is left out, as the papers leave it. */
vec2 ray_camera_cone(FrameParams f)
{
    float pixel = 2.0 * length(f.up.xyz) / float(f.image.y);
    return f.forward.w != 0.0 ? vec2(pixel, 0.0) : vec2(0.0, atan(pixel));
}

/* Points the ray from origin along direction (unit length) over (tmin, tmax). */
void ray_set_segment(inout Ray ray, vec3 origin, vec3 direction, float tmin, float tmax)
{
    ray.origin = vec4(origin, tmin);
    ray.direction = vec4(direction, tmax);
}

/* Ray k of those a hit of parent casts: the parent's pixel and sample, one bounce deeper, the
 * parent stream's child k (rng_child_seed), from origin along direction (unit length) to FAR. */
Ray ray_cast(Ray parent, uint k, vec3 origin, vec3 direction, vec3 throughput, float bsdf_pdf,
             vec4 payload)
{
    Ray child;
    child.origin = vec4(origin, 0.0);
    child.direction = vec4(direction, FAR);
    child.importance = vec4(throughput, bsdf_pdf);
    child.info = uvec4(ray_pixel(parent), rng_child_seed(ray_seed(parent), k), 0u,
                       (parent.info.w & ~VKRT_RAY_FLAGS) |
                           (ray_depth(parent) + 1u) << VKRT_RAY_DEPTH_SHIFT);
    child.payload = payload;
    return child;
}

/* A slot a hit of parent reserved and did not fill: dead, with an empty segment (tmax -1). */
Ray ray_dead(Ray parent)
{
    Ray dead;
    dead.origin = vec4(0.0);
    dead.direction = vec4(0.0, 0.0, 1.0, -1.0);
    dead.importance = vec4(0.0);
    dead.info = uvec4(ray_pixel(parent), 0u, 0u,
                      (parent.info.w & ~VKRT_RAY_FLAGS) |
                          (ray_depth(parent) + 1u) << VKRT_RAY_DEPTH_SHIFT | VKRT_RAY_DEAD);
    dead.payload = vec4(0.0);
    return dead;
}

/* A ray that is neither traced nor stored, only asked what the point at tmax looks like from
 * origin (surface_at): depth 0, no throughput, no pixel, no payload. */
Ray ray_probe(vec3 origin, vec3 direction, float tmax)
{
    Ray ray;
    ray.origin = vec4(origin, 0.0);
    ray.direction = vec4(direction, tmax);
    ray.importance = vec4(0.0);
    ray.info = uvec4(0u);
    ray.payload = vec4(0.0);
    return ray;
}

/* Marks the ray dead: it stays in its slot, but nobody traces or shades it. */
void ray_kill(inout Ray ray)
{
    ray.info.w |= VKRT_RAY_DEAD;
}

/* Marks the ray as carrying its path's AOVs on (ray_aov_pending): a camera ray, or the ray a
 * delta bounce cast. ray_cast clears the mark, so a child carries it only where this sets it. */
void ray_mark_aov_pending(inout Ray ray)
{
    ray.info.w |= VKRT_RAY_AOV_PENDING;
}
#else
/* The host's side of FrameParams.stage: each setter writes the lanes its getter above reads. */
static inline void frame_set_brute_range(FrameParams *f, uint first, uint end, bool merge)
{
    f->stage.x = first;
    f->stage.y = end;
    f->stage.z = merge ? 1u : 0u;
}

static inline void frame_set_order_step(FrameParams *f, uint step)
{
    f->stage.x = step;
}

static inline void frame_set_adapt_step(FrameParams *f, uint step)
{
    f->stage.x = step;
}

static inline void frame_set_light_words(FrameParams *f, uint words)
{
    f->stage.w = words;
}
#endif

#endif
