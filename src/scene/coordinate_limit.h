/*
 * coordinate_limit.h: the largest coordinate a scene may give a vertex, a camera or a light
 * (docs/scene-format.md, "Coordinates"). The OBJ pre-scan and the scene.cfg parser refuse
 * anything beyond it with file:line.
 *
 * Why 1e11: the kernels work in 32-bit floats, and the watertight test's scaled distance
 * (glsl/lib/intersect.glsl: edge functions, which are products of two sheared coordinates, times
 * a third) is of degree 3 in the coordinates. In a scene within +-X it can reach about 336 X^3
 * (sheared coordinates up to 4X, edge functions 32X^2, distances 3.5X, three terms), which
 * overflows float (3.4e38) past X = 1e12: the Cornell box scaled to +-7e12 lost its back wall. At
 * 1e11 that product stays 1000 times below the overflow. The kernels' other products are of
 * degree 2 (squared distances to lights, a normal's cross product) or are scaled first (a
 * normal's length, degree 4; the BVH's slab biases).
 */
#ifndef VKRT_COORDINATE_LIMIT_H
#define VKRT_COORDINATE_LIMIT_H

#define VKRT_COORDINATE_LIMIT 1e11
/* What a message says after "... is outside ". */
#define VKRT_COORDINATE_RANGE_TEXT                                                                 \
    "[-1e11, 1e11], the range vkrt's float arithmetic renders (docs/scene-format.md, Coordinates)"

#endif
