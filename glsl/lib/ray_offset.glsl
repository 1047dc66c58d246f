/*
 * ray_offset.glsl: how far a ray that leaves a surface starts from it (lib/intersect.glsl says why
 * these numbers: an absolute error of about 5 ULPs of the point's largest coordinate, and the
 * intersection test's own error of ULPs of the triangle's size).
 *
 * Written to compile as C as well as GLSL (only scalars, no built-ins), so that src/bench_rays.c
 * offsets the shadow and bounce rays it makes on the CPU exactly as the kernels do.
 */
#ifndef VKRT_RAY_OFFSET_GLSL
#define VKRT_RAY_OFFSET_GLSL

#define OFFSET_ULPS_OF_SIZE 256.0
#define OFFSET_ULPS_OF_POSITION 8.0
/* Near the origin, where ULPs vanish, the offset is this absolute step at least. */
#define OFFSET_MIN_STEP (1.0 / 65536.0)
#define OFFSET_ULP_OF_ONE (1.0 / 8388608.0) /* 2^-23 */

/* The scale of a triangle's rounding errors, from its largest absolute coordinate and its size
 * (the largest side of its bounding box): the size, or the coordinate if that is less (a triangle
 * across the origin, at least half its size), or the coordinate scaled from
 * OFFSET_ULPS_OF_POSITION to OFFSET_ULPS_OF_SIZE ULPs if that is more. No point of the triangle is
 * further from the origin than that coordinate, so it bounds the hit point's rounding too. The
 * larger of the two, not their sum: each is at least 1.5 times the error it covers. Never more
 * than the largest coordinate: a longer offset only moves origins further than they need (a
 * shadow ray to an emitter, which stops short of it by 1e-4 of its length, could overshoot). */
float ray_offset_magnitude(float largest, float size)
{
    float bounded = size < largest ? size : largest;
    float of_position = (OFFSET_ULPS_OF_POSITION / OFFSET_ULPS_OF_SIZE) * largest;
    return bounded > of_position ? bounded : of_position;
}

/* The distance a ray's origin moves off a triangle of that magnitude, along its normal. */
float ray_offset_distance(float magnitude)
{
    float step = OFFSET_ULPS_OF_SIZE * OFFSET_ULP_OF_ONE * magnitude;
    return step > OFFSET_MIN_STEP ? step : OFFSET_MIN_STEP;
}

#endif
