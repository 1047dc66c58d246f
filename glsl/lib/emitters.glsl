/*
 * emitters.glsl: points on the emissive triangles, drawn from the alias table over them
 * (glsl/shared.h LightInfo and Emitter, src/scene/emitters.h), for both integrators: the path
 * tracer's next-event estimation (nee.comp, with its MIS weights in lib/path.glsl) and Whitted's
 * emitter light below.
 *
 * Whitted's emitter light: where the scene has emissive triangles (EMITTER_LIGHT, set by the host
 * only then, so other scenes compile none of it), every hit sees one more light after the
 * scene's, index frame.counts.y: one point drawn on the emitters per hit and sample pass, as
 * Cook's distributed ray tracing samples an area light, so its soft shadows converge with the
 * samples per pixel. It is a light like the others to the materials (light_count(),
 * light_sample() in lib/material_api.glsl) and to the light kernel, which traces its shadow ray
 * and keeps its visibility bit. Its "irradiance on a surface facing it" is the one-sample
 * estimate Le / pdf, pdf the point's density in solid angle at the hit (Le cos_light /
 * (pdf_area dist^2)): what a material makes of irradiance * cos(theta) is then an unbiased
 * estimate of the direct light from the emitters. The light kernel and the shading kernel draw the
 * same point: both hash the ray's seed with the key of emitter_light_stream.
 */
#ifndef VKRT_EMITTERS_GLSL
#define VKRT_EMITTERS_GLSL

#include "bindings.glsl"
#include "colour.glsl"
#include "rng.glsl"
#include "surface.glsl"

/* The solid-angle density with which a light sample from distance `dist` finds a point of an
 * emissive triangle of material m seen at cosine cos_light: the triangle was chosen in
 * proportion to its power and the point uniformly on it, so the density per area is
 * luminance(Ke) / total power (glsl/shared.h LightInfo), Ke times the mean of a map_Ke
 * (Material.maps.x: the host weighed the table by the same number). */
float emitter_pdf(uint m, float dist, float cos_light)
{
    if (light_info.emitter_count == 0u || cos_light <= 0.0)
        return 0.0;
    return materials[m].maps.x / light_info.emitter_power * dist * dist / cos_light;
}

/* A point on an emissive triangle for the vertex at s: the alias table picks the triangle, u.yz
 * a point on it uniformly. Fills the surface of the light there (as seen along the sample's
 * direction), the unit direction to it, the distance and the solid-angle pdf; false when the
 * triangle turns its back to s. */
bool sample_emitter(Surface s, vec3 u, out Surface light, out vec3 wi, out float dist,
                    out float pdf)
{
    uint n = light_info.emitter_count;
    float x = u.x * float(n);
    uint i = min(uint(x), n - 1u);
    if (x - float(i) >= emitters[i].keep)
        i = emitters[i].alias;
    uint tri = emitters[i].triangle;
    Triangle t = triangle_at(tri);
    /* Uniform on the triangle (pbrt's square-root mapping): barycentrics of v1 and v2. */
    float r = sqrt(u.y);
    float b1 = r * (1.0 - u.z), b2 = r * u.z;
    vec3 p = (1.0 - b1 - b2) * t.v0.xyz + b1 * t.v1.xyz + b2 * t.v2.xyz;
    vec3 d = p - s.position;
    dist = length(d);
    wi = d / dist;
    vec3 ng = triangle_normal(t.v0.xyz, t.v1.xyz, t.v2.xyz);
    float cos_light = -dot(wi, ng);
    Ray towards = ray_probe(s.position, wi, dist);
    light = surface_at(towards, Hit(dist, b1, b2, tri));
    pdf = emitter_pdf(light.material, dist, cos_light);
    return pdf > 0.0 && dist > 0.0;
}

/* ---- Whitted's emitter light ---------------------------------------------------------------- */

/* The lights a Whitted hit sees: the scene's, and the emitter light after them where there is
 * one. */
uint whitted_light_count()
{
    return frame.counts.y + (EMITTER_LIGHT ? 1u : 0u);
}

/* The random stream of the emitter light's point for the ray whose seed is seed: apart from the
 * material's own (random(), the seed itself) and the path tracer's light stream. */
uint emitter_light_stream(uint seed)
{
    return pcg_hash(seed ^ 0x5BD1E995u);
}

/* Light i of whitted_light_count() at s (seed: the arriving ray's), as light_geometry gives a
 * scene light: the unit direction to it and the irradiance it brings to a surface facing it,
 * and the shadow ray that decides whether it is seen (from just off the lit side of s to just
 * short of the light: a point on an emitter ends a relative 1e-4 short of it, far above the
 * rounding of its length, so it does not find the emitter's own triangle). False when it cannot
 * light s: as light_geometry says, or an emitter point on a triangle's back face. */
bool whitted_light(Surface s, uint seed, uint i, out vec3 to_light, out vec3 irradiance,
                   out vec3 origin, out vec3 direction, out float tmax)
{
    origin = s.position;
    direction = vec3(0.0, 0.0, 1.0);
    tmax = 0.0;
    if (!EMITTER_LIGHT || i < frame.counts.y) {
        float distance_to_light;
        if (!light_geometry(s, i, to_light, distance_to_light, irradiance))
            return false;
        shadow_ray(s, i, to_light, origin, direction, tmax);
        return true;
    }
    uint rng = emitter_light_stream(seed);
    vec3 u = vec3(rng_next(rng), rng_next(rng), rng_next(rng));
    Surface light;
    float dist, pdf;
    irradiance = vec3(0.0);
    if (!sample_emitter(s, u, light, to_light, dist, pdf))
        return false;
    /* A sample is only drawn on a front face (pdf > 0), and Ke (times map_Ke) is what the front
     * emits (mtl_emitted). */
    irradiance = surface_emission(light.material, light.uv) / pdf;
    if (!(dot(s.normal, to_light) > 0.0 && dot(s.geometric_normal, to_light) > 0.0 &&
          any(greaterThan(irradiance, vec3(0.0)))))
        return false;
    origin = offset_ray_origin(s.position, s.geometric_normal, s.magnitude);
    vec3 d = light.position - origin;
    float len = length(d);
    direction = d / len;
    tmax = len * (1.0 - 1e-4);
    return len > 0.0;
}

#endif
