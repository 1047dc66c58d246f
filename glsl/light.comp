/*
 * light.comp: direct lighting at every hit, with shadow rays, and the Lambert (MTL Kd) shade.
 *
 * For a hit with albedo Kd and shading normal n, each light adds (Kd / pi) * E * cos(theta),
 * where E is the light's irradiance at normal incidence (directional: its colour; point:
 * I / d^2; spot: I * falloff / d^2), when a shadow ray (any hit, first hit ends it) finds the
 * way clear. Ambient lights add Kd * colour (a uniform, unoccluded environment of that radiance).
 * Rays that miss add the environment's radiance. The result, times the ray's importance, is
 * added to the ray's pixel: one ray per pixel per pass, so no atomics are needed yet.
 */
#include "lib/bindings.glsl"
#include "lib/traverse.glsl"

const float PI = 3.14159265358979;
const float FAR = 3.4e38;

shared uint workgroup_shadow_rays;

/* Irradiance at normal incidence from light l at point p, and the unit direction to it. */
vec3 light_irradiance(Light l, vec3 p, out vec3 to_light, out float distance_to_light)
{
    if (l.info.x == VKRT_LIGHT_KIND_DIRECTIONAL) {
        to_light = -l.direction.xyz;
        distance_to_light = FAR;
        return l.colour.rgb;
    }
    vec3 d = l.position.xyz - p;
    float d2 = dot(d, d);
    distance_to_light = sqrt(d2);
    to_light = d / distance_to_light;
    vec3 e = l.colour.rgb / d2;
    if (l.info.x == VKRT_LIGHT_KIND_SPOT) {
        float cos_angle = dot(-to_light, l.direction.xyz);
        if (cos_angle <= l.direction.w)
            return vec3(0.0);
        float angle = acos(clamp(cos_angle, -1.0, 1.0));
        float cutoff = l.position.w, beam = l.colour.w;
        if (angle > beam)
            e *= (cutoff - angle) / (cutoff - beam);
    }
    return e;
}

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        workgroup_shadow_rays = 0u;
    barrier();

    uint index = invocation_index();
    uint shadow_rays = 0u;
    if (index < frame.counts.z) {
        Ray ray = rays[index];
        Hit hit = hits[index];
        vec3 radiance = frame.environment.rgb;
        if (hit.triangle != VKRT_NO_HIT) {
            Triangle tri = triangles[hit.triangle];
            float w = 1.0 - hit.u - hit.v;
            vec3 p = w * tri.v0.xyz + hit.u * tri.v1.xyz + hit.v * tri.v2.xyz;
            vec3 ng = normalize(cross(tri.v1.xyz - tri.v0.xyz, tri.v2.xyz - tri.v0.xyz));
            /* Surfaces are two-sided: face the normal towards the viewer. */
            if (dot(ng, ray.direction.xyz) > 0.0)
                ng = -ng;
            vec3 ns = ng;
            if (HAS_NORMALS) {
                TriangleNormals tn = triangle_normals[hit.triangle];
                ns = normalize(w * tn.n0.xyz + hit.u * tn.n1.xyz + hit.v * tn.n2.xyz);
                if (dot(ns, ng) < 0.0)
                    ns = -ns;
            }
            vec3 kd = materials[triangle_material[hit.triangle]].diffuse.rgb;
            vec3 origin = offset_ray_origin(p, ng, triangle_magnitude(tri.v0.xyz, tri.v1.xyz, tri.v2.xyz));

            radiance = vec3(0.0);
            for (uint i = 0u; i < frame.counts.y; ++i) {
                Light l = lights[i];
                if (l.info.x == VKRT_LIGHT_KIND_AMBIENT) {
                    radiance += kd * l.colour.rgb;
                    continue;
                }
                vec3 to_light;
                float distance_to_light;
                vec3 e = light_irradiance(l, origin, to_light, distance_to_light);
                float cos_theta = dot(ns, to_light);
                /* The light must lie on the lit side of the surface itself, not only of the
                 * interpolated normal, or light would leak through to the back. */
                if (cos_theta <= 0.0 || dot(ng, to_light) <= 0.0 || all(equal(e, vec3(0.0))))
                    continue;
                ++shadow_rays;
                if (trace_any(origin, to_light, 0.0, distance_to_light))
                    continue;
                radiance += kd * (1.0 / PI) * e * cos_theta;
            }
        }
        uint pixel = ray.info.x;
        image[pixel] += vec4(ray.importance.rgb * radiance, 0.0);
    }
    atomicAdd(workgroup_shadow_rays, shadow_rays);
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        atomicAdd(counters.rays_traced, workgroup_shadow_rays);
}
