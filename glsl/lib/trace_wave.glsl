/*
 * trace_wave.glsl: the BVH walk of a whole dispatch with dynamic ray fetch (Aila and Laine,
 * "Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009, section 4): a lane whose ray
 * is done does not wait for the slowest ray of its subgroup; once half the subgroup is idle, the
 * idle lanes take the next rays of the dispatch from a counter (one atomic per subgroup) and
 * start them while the others go on. Each loop iteration is one step of every busy lane (a node
 * or a leaf), so lanes with short rays no longer idle through the long ones: the SIMD loss that
 * bench --stats measures for incoherent rays. For trace.comp (closest hits) and occlusion.comp
 * (any hit); rays are read and hits written as those kernels do. GPUs only: on a CPU device the
 * renderer keeps one ray per invocation (src/render/renderer.c says why). Needs bindings.glsl,
 * traverse.glsl, traversal_stats.glsl and the subgroup ballot and vote extensions.
 */
#ifndef VKRT_TRACE_WAVE_GLSL
#define VKRT_TRACE_WAVE_GLSL

/* Lanes fetch new rays once at least 1 / REFILL_SHARE of the subgroup is idle: fetching at every
 * idle lane would take one atomic per ray or two on one counter. */
const uint REFILL_SHARE = 2u;

void trace_wave(bool any_hit)
{
    uint count = dispatch_ray_count();
    bool busy_lane = false, exhausted = false;
    uint index = 0u, ref = NO_NODE;
    RayShear s = ray_shear_make(vec3(0.0), vec3(0.0, 0.0, 1.0));
    SlabRay b = slab_ray_make(vec3(0.0), vec3(1.0));
    float tmin = 0.0, tmax = 0.0;
    Hit hit = Hit(0.0, 0.0, 0.0, VKRT_NO_HIT);
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint iterations = 0u, busy = 0u, rays_done = 0u;
    while (true) {
        uvec4 idle = subgroupBallot(!busy_lane);
        uint idle_count = subgroupBallotBitCount(idle);
        if (!exhausted && idle_count * REFILL_SHARE >= gl_SubgroupSize) {
            uint base = 0u;
            if (subgroupElect())
                base = atomicAdd(trace_cursor[frame.wave.y], idle_count);
            base = subgroupBroadcastFirst(base);
            exhausted = base + idle_count >= count;
            if (!busy_lane) {
                index = base + subgroupBallotExclusiveBitCount(idle);
                if (index < count) {
                    Ray ray = load_ray(index);
                    tmax = ray.direction.w;
                    if ((ray.info.w & VKRT_RAY_DEAD) != 0u) {
                        hits[index] = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
                    } else {
                        s = ray_shear_make(ray.origin.xyz, ray.direction.xyz);
                        b = slab_ray_make(ray.origin.xyz, safe_inverse(ray.direction.xyz));
                        tmin = ray.origin.w;
                        hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
                        ref = 0u; /* the root */
                        top = 0;
                        busy_lane = true;
                    }
                }
            }
        }
        if (!subgroupAny(busy_lane)) {
            if (exhausted)
                break;
            continue;
        }
        /* The idle lanes wait here rather than `continue`: every lane reaches the ballot at the
         * top of the loop together, which its count of idle lanes relies on. */
        ++iterations;
        if (busy_lane) {
            ++busy;
            bool done = false;
            if ((ref & VKRT_BVH_LEAF) != 0u) {
                done = bvh_leaf(s, ref & 0x07FFFFFFu, ((ref >> 27) & 0xFu) + 1u, tmin, hit) && any_hit;
                ref = NO_NODE;
            } else {
                uint push;
                ref = bvh_pair_step(b, tmin, hit.t, any_hit, ref, push);
                if (push != NO_NODE)
                    stack[top++] = push;
            }
            if (!done && ref == NO_NODE) {
                if (top == 0)
                    done = true;
                else
                    ref = stack[--top];
            }
            if (done) {
                if (any_hit)
                    hits[index] = Hit(tmax, 0.0, 0.0, hit.triangle != VKRT_NO_HIT ? 0u : VKRT_NO_HIT);
                else
                    hits[index] = hit;
                busy_lane = false;
                ++rays_done;
            }
        }
    }
    record_traversal_work(rays_done, busy, iterations);
}

#endif
