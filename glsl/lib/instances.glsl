/*
 * instances.glsl: the instances of a two-level BVH (glsl/shared.h Instance) as shading sees them.
 *
 * Traversal reports a hit on an instanced mesh by its index in the instanced order (shared.h);
 * what reads per-triangle arrays (materials, normals, texture coordinates) needs the uploaded
 * triangle and what needs positions the instance's transform. Every function here is the
 * identity on scenes traced with one flat structure (INSTANCED false, a specialization constant:
 * the lookups are dead code there). Needs bindings.glsl.
 */
#ifndef VKRT_INSTANCES_GLSL
#define VKRT_INSTANCES_GLSL

#include "bindings.glsl"

const bool INSTANCED = ACCEL_KIND == VKRT_TRAVERSE_BVH_INSTANCED;

/* The instance whose triangles in the instanced order include hit triangle h: the last whose
 * first (info.z, ascending) is at most h. */
uint instance_of(uint h)
{
    uint lo = 0u, hi = grid.dims.x; /* the answer lies in [lo, hi) */
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (instances[mid].info.z <= h)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The uploaded triangle (the index of the per-triangle arrays) of hit triangle h of instance i. */
uint instance_triangle(uint i, uint h)
{
    return instances[i].info.y + (h - instances[i].info.z);
}

/* The uploaded triangle of a hit's triangle index, whatever the structure. */
uint hit_uploaded_triangle(uint h)
{
    if (!INSTANCED)
        return h;
    return instance_triangle(instance_of(h), h);
}

/* Point p and direction d through the 3x4 rows m. */
vec3 transform_point(vec4 m[3], vec3 p)
{
    return vec3(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w);
}

vec3 transform_vector(vec4 m[3], vec3 d)
{
    return vec3(dot(m[0].xyz, d), dot(m[1].xyz, d), dot(m[2].xyz, d));
}

/* A normal of instance i's mesh in world space: the transpose of world_to_object's 3x3 part
 * applied to it (the inverse transpose of object_to_world's), unit; zero stays zero (a mesh
 * without normals: the geometric normal is taken). */
vec3 instance_normal(uint i, vec3 n)
{
    vec4 m[3] = instances[i].world_to_object;
    vec3 w = m[0].xyz * n.x + m[1].xyz * n.y + m[2].xyz * n.z;
    return dot(w, w) > 0.0 ? normalize(w) : w;
}

#endif
