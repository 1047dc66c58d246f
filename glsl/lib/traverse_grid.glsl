/*
 * traverse_grid.glsl: 3D-DDA through the compact uniform grid (src/accel/grid.c builds it).
 *
 * Amanatides and Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing" (1987), the seed
 * thesis's Algorithm 2. A triangle may span several cells and be hit outside the cell being
 * visited; such a hit is kept as a candidate, and the walk ends only when the closest candidate
 * lies within the current cell's extent along the ray: no later cell can hold a closer hit then.
 * Direction components of 0 never step along their axis. Needs bindings.glsl, intersect.glsl and
 * traverse_bvh.glsl (for safe_inverse and slab_interval) included first. On devices whose loops
 * end after 65535 iterations per invocation (traverse_brute.glsl), a ray crossing cells of more
 * than that many references in all would lose hits; the grid is chosen only for even scenes.
 */
#ifndef VKRT_TRAVERSE_GRID_GLSL
#define VKRT_TRAVERSE_GRID_GLSL

/* Tests the triangles grid_refs[first .. end - 1] (a grid cell's, or a kd-tree leaf's), keeping
 * the closest hit in hit; returns true when the ray is done: any_hit and one was found. */
bool test_references(RayShear s, uint first, uint end, float tmin, bool any_hit, inout Hit hit)
{
    for (uint r = first; r < end; ++r) {
        uint i = ref_at(r);
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v) &&
            cutout_keeps(i, u, v)) {
            hit = Hit(t, u, v, i);
            if (any_hit)
                return true;
        }
    }
    return false;
}

Hit grid_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    const float inf = uintBitsToFloat(0x7f800000u);
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 origin = s.origin;
    vec3 inv_dir = safe_inverse(dir);
    vec2 span = slab_interval(grid.lo.xyz, grid.hi.xyz, origin, inv_dir, tmin, tmax);
    float t_enter = span.x, t_exit = span.y;
    if (t_enter > t_exit)
        return hit;

    ivec3 dims = ivec3(grid.dims.xyz);
    vec3 entry = origin + dir * t_enter;
    ivec3 cell = clamp(ivec3(floor((entry - grid.lo.xyz) / grid.cell_size.xyz)), ivec3(0), dims - 1);
    ivec3 step = ivec3(sign(dir));
    /* Distance along the ray to the next cell boundary on each axis, and between boundaries. */
    vec3 next_boundary = grid.lo.xyz + vec3(cell + max(step, ivec3(0))) * grid.cell_size.xyz;
    vec3 t_next = vec3(step.x != 0 ? (next_boundary.x - origin.x) * inv_dir.x : inf,
                       step.y != 0 ? (next_boundary.y - origin.y) * inv_dir.y : inf,
                       step.z != 0 ? (next_boundary.z - origin.z) * inv_dir.z : inf);
    vec3 t_delta = vec3(step.x != 0 ? grid.cell_size.x * abs(inv_dir.x) : inf,
                        step.y != 0 ? grid.cell_size.y * abs(inv_dir.y) : inf,
                        step.z != 0 ? grid.cell_size.z * abs(inv_dir.z) : inf);

    while (true) {
        uint index = uint(cell.x) + grid.dims.x * (uint(cell.y) + grid.dims.y * uint(cell.z));
        if (test_references(s, cell_start_at(index), cell_start_at(index + 1u), tmin, any_hit,
                            hit))
            return hit;
        float cell_exit = min(t_next.x, min(t_next.y, t_next.z));
        if (hit.triangle != VKRT_NO_HIT && hit.t <= cell_exit)
            break;
        if (cell_exit >= t_exit)
            break;
        /* Step along the axis whose boundary comes first. */
        if (t_next.x <= t_next.y && t_next.x <= t_next.z) {
            cell.x += step.x;
            if (cell.x < 0 || cell.x >= dims.x)
                break;
            t_next.x += t_delta.x;
        } else if (t_next.y <= t_next.z) {
            cell.y += step.y;
            if (cell.y < 0 || cell.y >= dims.y)
                break;
            t_next.y += t_delta.y;
        } else {
            cell.z += step.z;
            if (cell.z < 0 || cell.z >= dims.z)
                break;
            t_next.z += t_delta.z;
        }
    }
    return hit;
}

#endif
