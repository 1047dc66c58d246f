/*
 * trace.comp: closest hit of every ray in the wavefront.
 *
 * The traversal is included from lib/; which structure it walks is the renderer's choice
 * (brute force for now).
 */
#include "lib/bindings.glsl"
#include "lib/intersect.glsl"
#include "lib/traverse_brute.glsl"

void main()
{
    uint index = invocation_index();
    if (index >= frame.counts.z)
        return;
    Ray ray = rays[index];
    hits[index] = trace_closest(ray.origin.xyz, ray.direction.xyz, ray.origin.w, ray.direction.w);
}
