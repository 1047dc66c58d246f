/*
 * traversal_stats.glsl: adds this subgroup's traversal work to counters.trace_* (glsl/shared.h
 * says what each means). One atomic per subgroup, after subgroup sums, so counting does not
 * serialise the kernel on one address. Needs GL_KHR_shader_subgroup_arithmetic and
 * GL_KHR_shader_subgroup_basic enabled by the kernel, and traverse_bvh.glsl included.
 */
#ifndef VKRT_TRAVERSAL_STATS_GLSL
#define VKRT_TRAVERSAL_STATS_GLSL

/* rays: the rays this lane traced; busy: the loop iterations in which it had work (a node or a
 * leaf); iterations: the iterations its subgroup's loop ran, which the subgroup spent whatever
 * each lane was doing. */
void record_traversal_work(uint rays, uint busy, uint iterations)
{
    if (!TRAVERSAL_STATS)
        return;
    uint ray_sum = subgroupAdd(rays);
    uint steps = subgroupAdd(traversal_steps);
    uint tests = subgroupAdd(traversal_tests);
    uint busy_sum = subgroupAdd(busy);
    uint widest = subgroupMax(iterations);
    if (subgroupElect()) {
        atomicAdd(counters.trace_rays, ray_sum);
        atomicAdd(counters.trace_steps, steps);
        atomicAdd(counters.trace_tests, tests);
        atomicAdd(counters.trace_busy, busy_sum);
        atomicAdd(counters.trace_widest, widest);
        atomicMax(counters.subgroup_size, gl_SubgroupSize);
    }
}

/* The same for one ray traced by bvh_traverse: each of its nodes and leaves is one iteration of
 * the walk's loop, and the subgroup ran as many as its busiest lane. */
void record_traversal_stats()
{
    record_traversal_work(1u, traversal_steps + traversal_leaves, traversal_steps + traversal_leaves);
}

#endif
