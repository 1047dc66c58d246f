/*
 * bvh_lanes.h: the 4-lane float vectors and boxes of the BVH builder (bvh.c, bvh_split.c).
 *
 * Internal to the builder, and all static inline: the hot loops (binning, partitioning) work on
 * whole boxes in these and keep them in registers, which they only do if the calls inline (boxes
 * spelled as float arrays went through memory lane by lane). SSE2 where the target has it (every
 * x86-64), plain arrays elsewhere or with BVH_SCALAR_LANES defined, which tests/meson.build does
 * to hold one against the other (tests/test_bvh_lanes.c). Both versions compute the same IEEE
 * operations per lane, min and max included (a < b ? a : b, as MINPS), so the tree does not
 * depend on which one is compiled.
 */
#ifndef VKRT_BVH_LANES_H
#define VKRT_BVH_LANES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define MINF(a, b) ((a) < (b) ? (a) : (b))
#define MAXF(a, b) ((a) > (b) ? (a) : (b))

/* ------------------------------------------------------------------------ lanes */

#if defined(__SSE2__) && !defined(BVH_SCALAR_LANES)
#include <emmintrin.h>
typedef __m128 vec4;
static inline vec4 v4_load(const void *p) { return _mm_loadu_ps(p); }
static inline void v4_store(float *p, vec4 a) { _mm_storeu_ps(p, a); }
static inline vec4 v4_set1(float x) { return _mm_set1_ps(x); }
static inline vec4 v4_set3(float x, float y, float z) { return _mm_setr_ps(x, y, z, 0.0f); }
static inline vec4 v4_min(vec4 a, vec4 b) { return _mm_min_ps(a, b); }
static inline vec4 v4_max(vec4 a, vec4 b) { return _mm_max_ps(a, b); }
static inline vec4 v4_add(vec4 a, vec4 b) { return _mm_add_ps(a, b); }
static inline vec4 v4_sub(vec4 a, vec4 b) { return _mm_sub_ps(a, b); }
static inline vec4 v4_mul(vec4 a, vec4 b) { return _mm_mul_ps(a, b); }
/* Lanes truncated to integers; the caller keeps them in [0, 2^31). */
static inline void v4_to_u32(vec4 a, uint32_t out[4]) { _mm_storeu_si128((__m128i *)out, _mm_cvttps_epi32(a)); }
/* Lanes 0..2 of a, lane 3 zero (+0). */
static inline vec4 v4_xyz(vec4 a) { return _mm_and_ps(a, _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0))); }
#else
typedef struct vec4 {
    float f[4];
} vec4;
static inline vec4 v4_load(const void *p) { vec4 r; memcpy(r.f, p, sizeof r.f); return r; }
static inline void v4_store(float *p, vec4 a) { memcpy(p, a.f, sizeof a.f); }
static inline vec4 v4_set1(float x) { return (vec4){ { x, x, x, x } }; }
static inline vec4 v4_set3(float x, float y, float z) { return (vec4){ { x, y, z, 0.0f } }; }
#define VEC4_LANEWISE(name, expr) \
    static inline vec4 name(vec4 a, vec4 b) \
    { \
        vec4 r; \
        for (int k = 0; k < 4; k++) \
            r.f[k] = expr; \
        return r; \
    }
VEC4_LANEWISE(v4_min, a.f[k] < b.f[k] ? a.f[k] : b.f[k])
VEC4_LANEWISE(v4_max, a.f[k] > b.f[k] ? a.f[k] : b.f[k])
VEC4_LANEWISE(v4_add, a.f[k] + b.f[k])
VEC4_LANEWISE(v4_sub, a.f[k] - b.f[k])
VEC4_LANEWISE(v4_mul, a.f[k] * b.f[k])
#undef VEC4_LANEWISE
static inline void v4_to_u32(vec4 a, uint32_t out[4])
{
    for (int k = 0; k < 4; k++)
        out[k] = (uint32_t)a.f[k];
}
static inline vec4 v4_xyz(vec4 a)
{
    a.f[3] = 0.0f;
    return a;
}
#endif

/* ------------------------------------------------------------------------ boxes and records */

/* A box in 4 lanes; lane 3 is padding whose value means nothing. */
typedef struct aabb {
    vec4 lo, hi;
} aabb;

/* One triangle's exact bounds and original index, 32 bytes; the build permutes these. In memory
 * lo's lane 3 is the index and hi's is zero; ref_load clears the index's lane. */
typedef struct prim_ref {
    float lo[3];
    uint32_t index;
    float hi[3];
    uint32_t pad;
} prim_ref;

_Static_assert(sizeof(prim_ref) == 32 && offsetof(prim_ref, hi) == 16, "prim_ref lanes");

/* A ref in lanes: its bounds and its centroid (lanes 0..2 meaningful). */
typedef struct ref_lanes {
    vec4 lo, hi, c;
} ref_lanes;

/* The empty box: +inf below, -inf above, so any grow replaces it. */
static inline void aabb_empty(aabb *b)
{
    b->lo = v4_set1(INFINITY);
    b->hi = v4_set1(-INFINITY);
}

/* b grown to hold the box [lo, hi]. */
static inline void aabb_grow_box(aabb *b, vec4 lo, vec4 hi)
{
    b->lo = v4_min(b->lo, lo);
    b->hi = v4_max(b->hi, hi);
}

static inline void aabb_grow_point(aabb *b, vec4 p)
{
    aabb_grow_box(b, p, p);
}

static inline void aabb_grow(aabb *b, const aabb *other)
{
    aabb_grow_box(b, other->lo, other->hi);
}

/* The box's lanes 0..2 into lo[3] and hi[3]. */
static inline void aabb_store(const aabb *b, float lo[3], float hi[3])
{
    float l[4], h[4];
    v4_store(l, b->lo);
    v4_store(h, b->hi);
    memcpy(lo, l, 3 * sizeof *lo);
    memcpy(hi, h, 3 * sizeof *hi);
}

/* Half the surface area; the SAH only uses ratios, so the factor 2 does not matter. */
static inline float aabb_half_area(const aabb *b)
{
    float d[4];
    v4_store(d, v4_sub(b->hi, b->lo));
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* A ref's bounds and centroid. Every centroid of the build comes from here (the centroid bounds,
 * the binning, the partitioning), so they agree bit for bit. Halving before adding keeps huge
 * coordinates from overflowing. lo's lane 3, the index, is cleared: read as a float, an index
 * below 2^23 is subnormal, and halving it (and one above, below 2^24) makes a subnormal. Without
 * flush-to-zero, some x86 cores finish a multiplication that makes a subnormal in a microcode
 * assist of over a hundred cycles (what VTune counts as "FP Assists"), which the centroid and the
 * binning would pay once or more per record and pass. */
static inline ref_lanes ref_load(const prim_ref *r)
{
    ref_lanes l;
    l.lo = v4_xyz(v4_load((const char *)r + offsetof(prim_ref, lo)));
    l.hi = v4_load((const char *)r + offsetof(prim_ref, hi));
    vec4 half = v4_set1(0.5f);
    l.c = v4_add(v4_mul(l.lo, half), v4_mul(l.hi, half));
    return l;
}

#endif
