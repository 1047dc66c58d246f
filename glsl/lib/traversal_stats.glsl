/*
 * traversal_stats.glsl: adds this subgroup's traversal work to counters.trace_* (glsl/shared.h
 * says what each means). One atomic per subgroup, after subgroup sums, so counting does not
 * serialise the kernel on one address. Needs GL_KHR_shader_subgroup_arithmetic and
 * GL_KHR_shader_subgroup_basic enabled by the kernel, and traverse_bvh.glsl included.
 */
#ifndef VKRT_TRAVERSAL_STATS_GLSL
#define VKRT_TRAVERSAL_STATS_GLSL

void record_traversal_stats()
{
    if (!TRAVERSAL_STATS)
        return;
    uint rays = subgroupAdd(1u);
    uint steps = subgroupAdd(traversal_steps);
    uint tests = subgroupAdd(traversal_tests);
    uint widest = subgroupMax(traversal_steps + traversal_tests);
    if (subgroupElect()) {
        atomicAdd(counters.trace_rays, rays);
        atomicAdd(counters.trace_steps, steps);
        atomicAdd(counters.trace_tests, tests);
        atomicAdd(counters.trace_widest, widest);
        atomicMax(counters.subgroup_size, gl_SubgroupSize);
    }
}

#endif
