/*
 * material_api.glsl: the functions material shaders call (docs/materials.md documents them), and
 * the per-invocation state behind them. Included by the generated material module, which the
 * count and shade kernels include; a shader never includes anything itself.
 *
 * The state lives in globals rather than in parameters so that the API stays small: a shader
 * writes add_radiance(c) and cast_ray(s, d, w), and the kernel knows which ray, pixel, material
 * and slots those belong to.
 */
#ifndef VKRT_MATERIAL_API_GLSL
#define VKRT_MATERIAL_API_GLSL

#include "bindings.glsl"
#include "colour.glsl"
#include "emitters.glsl"
#include "rng.glsl"
#include "sampler.glsl"
#include "surface.glsl"
#include "texture.glsl"

/* Which material is being shaded (index into materials[]), and the ray that hit it. */
uint vkrt_material;
uint vkrt_ray_index;
Ray vkrt_ray;
uint vkrt_rng;
/* The path tracer's next dimension of the ray's BSDF block (random() below); the kernels set it. */
uint vkrt_dimension;
/* Radiance the shader added, towards the arriving ray; the kernel weights it by importance. */
vec3 vkrt_radiance;
/* The slots reserved for this hit's rays: [vkrt_cast_first, + vkrt_cast_reserved). */
bool vkrt_casting;
uint vkrt_cast_first;
uint vkrt_cast_reserved;
uint vkrt_cast_done;

/* ---- Parameters and textures of the material ---------------------------------------------- */

/* Numeric parameter i (0..15) of the material file's line, or of the .mtl mapping. */
float param(uint i)
{
    return i < VKRT_MATERIAL_PARAMS ? materials[vkrt_material].params[i >> 2u][i & 3u] : 0.0;
}

vec3 param3(uint i)
{
    return vec3(param(i), param(i + 1u), param(i + 2u));
}

bool has_texture(uint slot)
{
    return slot < VKRT_MATERIAL_TEXTURES &&
           materials[vkrt_material].textures[slot >> 2u][slot & 3u] != VKRT_NO_TEXTURE;
}

/* Texture slot (0..7) of the material at uv, bilinear with wrap-around, linear RGBA (colour maps
 * are decoded from sRGB); vec4(1) when the slot has no texture, so a missing map multiplies away. */
vec4 material_texture(uint slot, vec2 uv)
{
    if (!has_texture(slot))
        return vec4(1.0);
    return texture_sample(materials[vkrt_material].textures[slot >> 2u][slot & 3u], uv);
}

/* ---- Random numbers ------------------------------------------------------------------------ */

/* Uniform in [0, 1). count_rays and shade of one hit see the same sequence, so a shader may decide
 * at random how many rays to cast if it draws the same numbers in the same order in both. In the
 * path tracer the calls of one hit take the consecutive dimensions of the ray's BSDF block of the
 * sampler (lib/sampler.glsl), each stratified over the pixel's samples; past the block, and in
 * Whitted, they walk the ray's hash stream. */
float random()
{
    if (INTEGRATOR == VKRT_INTEGRATE_PATH && vkrt_dimension < SAMPLER_BSDF_DIMS)
        return sampler_1d(vkrt_ray, frame.counts.w, SAMPLER_DIM_BSDF + vkrt_dimension++);
    vkrt_rng = pcg_hash(vkrt_rng);
    return rng_float(vkrt_rng);
}

/* Two numbers for one 2D choice (a direction, a point): in the path tracer a pair of the BSDF
 * block that starts at an even dimension, so that the points of a pixel's samples are stratified
 * in 2D and not only along each axis (one random() before it skips a dimension to get there). */
vec2 random2()
{
    if (INTEGRATOR == VKRT_INTEGRATE_PATH)
        vkrt_dimension += vkrt_dimension & 1u;
    float u = random();
    return vec2(u, random());
}

/* ---- Lights ---------------------------------------------------------------------------------- */

/* The scene's lights and, where it has emissive triangles, one more: a point drawn on them for
 * this hit (lib/emitters.glsl). */
uint light_count()
{
    return whitted_light_count();
}

/* Light i at s: true when it reaches s (in front of the surface and not shadowed), with the unit
 * direction towards it and the irradiance it brings to a surface facing it (multiply by
 * dot(s.normal, to_light) for the irradiance on s). Ambient lights are never sampled here: see
 * ambient_light. The shadow ray was traced by the light kernel; this reads its answer. */
bool light_sample(Surface s, uint i, out vec3 to_light, out vec3 irradiance)
{
    vec3 origin, direction;
    float tmax;
    if (!whitted_light(s, ray_seed(vkrt_ray), i, to_light, irradiance, origin, direction, tmax))
        return false;
    uint word = light_visibility[vkrt_ray_index * frame_light_words(frame) + (i >> 5u)];
    return (word & (1u << (i & 31u))) != 0u;
}

/* The summed radiance of the ambient lights: light arriving from every direction, unshadowed. */
vec3 ambient_light()
{
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < frame.counts.y; ++i)
        if (lights[i].info.x == VKRT_LIGHT_KIND_AMBIENT)
            sum += lights[i].colour.rgb;
    return sum;
}

/* Radiance a Lambertian surface of the given albedo reflects towards the viewer under all the
 * lights: sum of (albedo / pi) * E * cos(theta) over visible lights, plus albedo * ambient. */
vec3 diffuse_light(Surface s, vec3 albedo)
{
    vec3 sum = albedo * ambient_light();
    for (uint i = 0u; i < light_count(); ++i) {
        vec3 to_light, irradiance;
        if (light_sample(s, i, to_light, irradiance))
            sum += albedo * (1.0 / PI) * irradiance * dot(s.normal, to_light);
    }
    return sum;
}

/* ---- Output ---------------------------------------------------------------------------------- */

/* Adds radiance leaving the surface towards the arriving ray (the kernel weights it by the ray's
 * importance and adds it to the pixel). */
void add_radiance(vec3 radiance)
{
    vkrt_radiance += radiance;
}

/* Casts a ray from s in direction (unit length) carrying weight times the arriving ray's
 * importance, and payload. A hit may cast exactly as many rays as its count_rays returned; more
 * are not traced and are reported as an error of the material. */
void cast_ray_payload(Surface s, vec3 direction, vec3 weight, vec4 payload)
{
    if (!vkrt_casting)
        return;
    if (vkrt_cast_done >= vkrt_cast_reserved) {
        /* The last depth reserves nothing on purpose: there the casts are simply the end. */
        if (frame.wave.y < frame.wave.z) {
            atomicAdd(counters.overcast, 1u);
            atomicExchange(counters.overcast_material, vkrt_material + 1u);
        }
        return;
    }
    uint k = vkrt_cast_done++;
    uint slot = vkrt_cast_first + k;
    if (slot >= frame.wave.w)
        return; /* past the buffers: the host sees the wave's size, grows them, renders again */
    /* Whitted's rays carry no BSDF pdf: what they find is counted in full. */
    vec3 throughput = ray_throughput(vkrt_ray) * weight;
    Ray child = ray_cast(vkrt_ray, k, surface_origin(s, direction), direction, throughput, 0.0,
                         payload);
    surface_cast_cone(s, child, 0.0);
    float strongest = max(throughput.r, max(throughput.g, throughput.b));
    if (!(strongest >= frame.eye.w))
        ray_kill(child);
    store_child_ray(slot, child);
}

void cast_ray(Surface s, vec3 direction, vec3 weight)
{
    cast_ray_payload(s, direction, weight, vkrt_ray.payload);
}

/* ---- Helpers ------------------------------------------------------------------------------- */

/* Fresnel reflectance of an unpolarised ray meeting a dielectric boundary at cos_i (cosine of the
 * angle to the normal, >= 0), eta = n_transmitted / n_incident. 1 under total internal reflection. */
float fresnel_dielectric(float cos_i, float eta)
{
    float sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1.0)
        return 1.0;
    float cos_t = sqrt(1.0 - sin_t2);
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/* ---- The path tracer's side of a material (docs/materials.md, "Materials for path") -------- */

/* What bsdf_sample returns: the direction it chose, the weight f * |cos| / pdf a path carries on
 * with, the pdf of the direction (solid angle; for MIS against light sampling), and whether it
 * came from a delta lobe (a perfect mirror or glass: no light sample can find it, pdf unused). */
struct BsdfSample {
    vec3 direction;
    vec3 weight;
    float pdf;
    bool delta;
};

/* The payload of the ray bsdf_sample casts: the arriving ray's unless the material sets another
 * (the path tracer's cast_ray_payload). */
vec4 vkrt_child_payload;

void set_payload(vec4 payload)
{
    vkrt_child_payload = payload;
}

/* The emission of the built-in materials at s: Ke (parameters 8-10) times the .mtl's map_Ke where
 * there is one (lib/surface_maps.glsl). Whitted's shaders add it on either side. */
vec3 mtl_emission(Surface s)
{
    return surface_emission(vkrt_material, s.uv);
}

/* Emitted radiance of the built-in materials for path: mtl_emission from the front face only (the
 * side the triangle's counter-clockwise winding faces), as Mitsuba's and pbrt's area lights. */
vec3 mtl_emitted(Surface s)
{
    return s.front_face ? mtl_emission(s) : vec3(0.0);
}

/* A unit vector with cosine-weighted density about n (for diffuse bounces). */
vec3 cosine_direction(vec3 n, float u1, float u2)
{
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 b = cross(n, t);
    return normalize(r * cos(phi) * t + r * sin(phi) * b + sqrt(max(0.0, 1.0 - u1)) * n);
}

/* The Lambertian lobe of albedo: f * cos for wi (0 below the surface), and its cosine pdf. */
vec3 lambert_eval(Surface s, vec3 albedo, vec3 wi, out float pdf)
{
    float c = dot(wi, s.normal);
    /* Light may not come through the surface by way of a bent shading normal either. */
    if (c <= 0.0 || dot(wi, s.geometric_normal) <= 0.0) {
        pdf = 0.0;
        return vec3(0.0);
    }
    pdf = c / PI;
    return albedo * (c / PI);
}

/* A cosine-distributed direction about the shading normal; weight albedo (f cos / pdf). False
 * (nothing to continue with) where the direction would go below the geometric surface. */
bool lambert_sample(Surface s, vec3 albedo, out BsdfSample b)
{
    vec2 u = random2();
    b.direction = cosine_direction(s.normal, u.x, u.y);
    float c = dot(b.direction, s.normal);
    b.pdf = c / PI;
    b.weight = albedo;
    b.delta = false;
    return c > 0.0 && dot(b.direction, s.geometric_normal) > 0.0;
}

/* A smooth dielectric boundary of eta = n_transmitted / n_incident: reflection or refraction,
 * one chosen with the Fresnel reflectance as its probability (both delta lobes), the refracted
 * radiance scaled by 1 / eta^2 (radiance, not importance, is carried: pbrt's Radiance mode,
 * Mitsuba's dielectric). True when it reflected. */
bool dielectric_sample(Surface s, float eta, out BsdfSample b)
{
    float cos_i = max(-dot(s.incoming, s.normal), 0.0);
    b.pdf = 0.0;
    b.delta = true;
    if (random() < fresnel_dielectric(cos_i, eta)) {
        b.direction = reflect(s.incoming, s.normal);
        b.weight = vec3(1.0);
        return true;
    }
    b.direction = normalize(refract(s.incoming, s.normal, 1.0 / eta));
    b.weight = vec3(1.0 / (eta * eta));
    return false;
}

/* A black surface: nothing reflected. */
vec3 black_eval(out float pdf)
{
    pdf = 0.0;
    return vec3(0.0);
}

#endif
