/*
 * emitters.h: the emissive triangles of a scene as one light, sampled by power.
 *
 * The path tracer picks an emissive triangle for next-event estimation with probability
 * power / total power, power = luminance(Ke) * area (luminance = 0.2126 R + 0.7152 G + 0.0722 B,
 * Rec. 709, as Mitsuba and pbrt weigh lights), through an alias table (Vose's method: one
 * uniform entry and one comparison per pick, whatever the count; glsl/shared.h, Emitter). An alias
 * table rather than a light tree: it costs O(1) per sample and nothing to build beyond a sort-free
 * pass, and the density it gives a point (luminance(Ke) / total power per unit area) needs no
 * lookup when a BSDF ray hits the emitter, which MIS asks for at every such hit.
 *
 * Pure CPU, no Vulkan.
 */
#ifndef VKRT_EMITTERS_H
#define VKRT_EMITTERS_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"

/* The alias table, in arrays that match the fields of Emitter in glsl/shared.h entry by entry.
 * Entry i is taken with probability 1/count; it yields triangle[i] with probability keep[i], else
 * entry alias[i]'s triangle. power[i] is triangle[i]'s own luminance(Ke) * area. */
typedef struct vkrt_emitters {
    uint32_t count;     /* emissive triangles of non-zero area, the table's entries */
    uint32_t *triangle; /* the triangle's index in the mesh's ORIGINAL order (the caller remaps it
                           to the acceleration structure's order before upload) */
    float *keep;        /* in [0, 1] */
    uint32_t *alias;    /* an entry index in [0, count) */
    float *power;       /* luminance(Ke) * area, > 0 (0 only where a vanishing triangle's
                           power underflows a float; the table itself is built in double) */
    double total_power; /* the sum of power over the entries */
} vkrt_emitters;

/* Builds the alias table over the emissive triangles of a mesh. positions holds 9 floats per
 * triangle (v0, v1, v2), triangle_material one index per triangle into material_ke, which holds 3
 * floats (Ke, linear RGB, >= 0) per material. A triangle emits when its material's
 * luminance(Ke) > 0 and its area (in double, from the float corners) is above zero: degenerate
 * triangles are skipped, since a point on them can never be hit. Entries are in triangle order.
 * No emitters gives an empty table (count 0, NULL arrays, total 0) and true.
 * Returns false with err set, and *out zeroed, when a material index is out of range, a Ke is
 * negative or not finite, a power overflows a float, or memory runs out. The caller frees *out
 * with vkrt_emitters_free. */
bool vkrt_emitters_build(const float *positions, uint32_t triangle_count,
                         const uint32_t *triangle_material, const float *material_ke,
                         uint32_t material_count, vkrt_emitters *out, vkrt_error *err);

/* Frees the arrays and zeroes *e. Safe on a zeroed struct and on NULL. */
void vkrt_emitters_free(vkrt_emitters *e);

#endif
