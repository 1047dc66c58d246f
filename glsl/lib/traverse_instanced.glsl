/*
 * traverse_instanced.glsl: the two-level BVH of an instanced scene (glsl/shared.h Instance,
 * src/render/accel_instanced.c): a top-level tree over the instances' world boxes whose leaves
 * hold instances, and below each a bottom-level tree of its mesh in the mesh's own space, all in
 * one node array of the layout BVH_WIDTH says.
 *
 * One loop and one stack, as bvh_traverse_one_loop (lib/traverse_bvh.glsl), whose node steps and
 * leaf test it calls. At a top-level leaf the walk moves the ray into the first instance's space
 * (world_to_object; the direction is not normalised, so a distance t along it is the world ray's
 * t and the closest hit so far keeps culling), remembers the stack's height, and walks the mesh's
 * tree; when the stack is back at that height the instance is done and the world ray returns.
 * The leaf's other instances wait on the stack as a leaf of one fewer. The hit is reported in the
 * instanced order (shared.h), which shading maps back (lib/instances.glsl). The nested walk of
 * CPU devices is not offered here: instanced scenes walk this loop everywhere. Needs
 * traverse_bvh.glsl and instances.glsl included first.
 */
#ifndef VKRT_TRAVERSE_INSTANCED_GLSL
#define VKRT_TRAVERSE_INSTANCED_GLSL

/* No instance is being walked: the walk is in the top-level tree. */
const uint IN_TOP_LEVEL = 0xFFFFFFFFu;

Hit instanced_traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    uint hit_instance = 0u;
    SlabRay world = slab_ray_make(origin, dir);
    SlabRay b = world;
    RayShear s = ray_shear_make(origin, dir); /* replaced before any triangle is tested */
    uint instance = IN_TOP_LEVEL;
    int instance_floor = 0; /* the stack's height when the instance was entered */
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint ref = 0u; /* the top-level root */
    while (true) {
        if ((ref & VKRT_BVH_LEAF) != 0u && instance == IN_TOP_LEVEL) {
            /* A top-level leaf: its first instance now, the rest later. */
            uint first = ref & 0x07FFFFFFu, count = ((ref >> 27) & 0xFu) + 1u;
            if (count > 1u && top < BVH_STACK_SIZE)
                stack[top++] = VKRT_BVH_LEAF | ((count - 2u) << 27) | (first + 1u);
            vec4 m[3] = instances[first].world_to_object;
            vec3 o = transform_point(m, origin), d = transform_vector(m, dir);
            s = ray_shear_make(o, d);
            b = slab_ray_make(o, d);
            instance = first;
            instance_floor = top;
            ref = instances[first].info.x;
            continue;
        }
        if ((ref & VKRT_BVH_LEAF) != 0u) {
            if (bvh_leaf_ref(s, ref, tmin, hit)) {
                hit_instance = instance;
                if (any_hit)
                    break;
            }
            ref = NO_NODE;
        } else {
            /* The host refused structures whose two levels' stacks together exceed it. */
            BVH_ONE_LOOP_STEP(b, tmin, hit.t, any_hit, ref, stack, top);
        }
        if (ref == NO_NODE) {
            if (instance != IN_TOP_LEVEL && top == instance_floor) {
                instance = IN_TOP_LEVEL;
                b = world;
            }
            if (top == 0)
                break;
            ref = stack[--top];
        }
    }
    if (hit.triangle != VKRT_NO_HIT)
        hit.triangle = instances[hit_instance].info.z +
                       (hit.triangle - instances[hit_instance].info.y);
    return hit;
}

#endif
