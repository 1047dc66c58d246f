/*
 * surface.glsl: what a hit looks like to lights and materials, and the light geometry that the
 * light kernel (which traces the shadow rays) and the shading kernel (which uses them) share.
 */
#ifndef VKRT_SURFACE_GLSL
#define VKRT_SURFACE_GLSL

#include "bindings.glsl"
#include "instances.glsl"
#include "intersect.glsl"
#include "surface_maps.glsl"

const float PI = 3.14159265358979;

/* A hit as material shaders see it (docs/materials.md). Normals face the side the ray came from:
 * surfaces are two-sided, and front_face says which side was hit. */
struct Surface {
    vec3 position;
    vec3 normal;            /* shading normal (interpolated when the OBJ has normals, bent by a
                               normal or bump map: lib/surface_maps.glsl), unit */
    vec3 geometric_normal;  /* the triangle's plane normal, unit */
    vec3 incoming;          /* unit direction of the arriving ray, pointing into the surface */
    vec2 uv;                /* texture coordinates, (0, 0) when the OBJ has none */
    bool front_face;        /* true when the ray hit the side the triangle's winding faces */
    uint depth;             /* 0 for camera rays, +1 per bounce */
    vec3 importance;        /* the arriving ray's throughput to the pixel, for information */
    vec4 payload;           /* the arriving ray's payload */
    uint material;          /* index of the material (internal) */
    float magnitude;        /* scale of the triangle's rounding, for origin offsets (internal) */
    float texture_footprint;/* log2 of the ray cone's footprint on the surface in uv units, what
                               its textures are read at (texture_sample_footprint; internal) */
    float cone_width;       /* the arriving ray's cone: its width here, and the spread a ray */
    float cone_spread;      /* reflected here leaves with (surface_cast_cone; internal) */
};

/* The ray cone of ray at its hit of triangle tri (world space) at distance t, seen with geometric
 * normal ng (unit, facing the ray): its width there, and the spread a reflection leaves with
 * (Akenine-Moller et al., RTG 2019 section 20.3.4 and JCGT 2021): the arriving spread plus twice
 * the surface's spread angle beta, which a curved surface adds (a convex one widens the cone, a
 * concave one narrows it). beta = k w / |n.d| (JCGT 2021's arc-length form) for the triangle's
 * curvature k, estimated from its vertex normals (world space, on the side of ng; none: flat) as
 * the mean over its edges of (n_j - n_i).(p_j - p_i) / |p_j - p_i|^2, the normal's turn per unit
 * length along each edge. */
void surface_cone(Ray ray, float t, Triangle tri, vec3 ng, bool has_normals, TriangleNormals tn,
                  out float width, out float spread)
{
    width = ray_cone_width(ray) + ray_cone_spread(ray) * t;
    spread = ray_cone_spread(ray);
    if (!has_normals || width == 0.0)
        return;
    vec3 e01 = tri.v1.xyz - tri.v0.xyz, e12 = tri.v2.xyz - tri.v1.xyz,
         e20 = tri.v0.xyz - tri.v2.xyz;
    float side = dot(tn.n0.xyz + tn.n1.xyz + tn.n2.xyz, ng) < 0.0 ? -1.0 : 1.0;
    float k = (dot(tn.n1.xyz - tn.n0.xyz, e01) / dot(e01, e01) +
               dot(tn.n2.xyz - tn.n1.xyz, e12) / dot(e12, e12) +
               dot(tn.n0.xyz - tn.n2.xyz, e20) / dot(e20, e20)) * (side / 3.0);
    float cos_in = max(abs(dot(ray.direction.xyz, ng)), 1e-4);
    float beta = k * width / cos_in;
    if (!isnan(beta) && !isinf(beta))
        spread += 2.0 * beta;
}

/* Gives child, a ray cast from s, its cone: it starts as wide as the arriving cone is at s and
 * spreads by s's reflected spread (surface_cone), plus, for a sample of a lobe with solid-angle
 * pdf `pdf` (0: a delta lobe), the angle of a cone holding the solid angle 1 / pdf that one
 * sample stands for, 2 / sqrt(pi pdf): a rough bounce reads its next textures blurred as its
 * lobe blurs them, a mirror keeps the cone. Refraction is treated as reflection (RTG II's
 * refraction cones are not done). */
void surface_cast_cone(Surface s, inout Ray child, float pdf)
{
    float spread = s.cone_spread;
    if (pdf > 0.0)
        spread += 2.0 / sqrt(PI * pdf);
    ray_set_cone(child, s.cone_width, spread);
}

Surface surface_at(Ray ray, Hit hit)
{
    /* An instanced mesh's hit: its uploaded triangle, moved to world space, so that everything
     * below (position, normals, texture space, offsets) is as for a flat scene's. */
    uint instance = 0u;
    uint triangle = hit.triangle;
    if (INSTANCED) {
        instance = instance_of(hit.triangle);
        triangle = instance_triangle(instance, hit.triangle);
    }
    Triangle tri = triangle_at(triangle);
    if (INSTANCED) {
        vec4 m[3] = instances[instance].object_to_world;
        tri.v0.xyz = transform_point(m, tri.v0.xyz);
        tri.v1.xyz = transform_point(m, tri.v1.xyz);
        tri.v2.xyz = transform_point(m, tri.v2.xyz);
    }
    float w = 1.0 - hit.u - hit.v;
    Surface s;
    s.position = w * tri.v0.xyz + hit.u * tri.v1.xyz + hit.v * tri.v2.xyz;
    vec3 ng = triangle_normal(tri.v0.xyz, tri.v1.xyz, tri.v2.xyz);
    s.front_face = dot(ng, ray.direction.xyz) < 0.0;
    if (!s.front_face)
        ng = -ng;
    s.geometric_normal = ng;
    s.normal = ng;
    TriangleNormals tn = TriangleNormals(vec4(0.0), vec4(0.0), vec4(0.0));
    if (HAS_NORMALS) {
        tn = normals_at(triangle);
        /* An instance's vertex normals each in world space and unit, as flattening makes them
         * (vkrt_model_world), before they are interpolated. */
        if (INSTANCED) {
            tn.n0.xyz = instance_normal(instance, tn.n0.xyz);
            tn.n1.xyz = instance_normal(instance, tn.n1.xyz);
            tn.n2.xyz = instance_normal(instance, tn.n2.xyz);
        }
        vec3 ns = w * tn.n0.xyz + hit.u * tn.n1.xyz + hit.v * tn.n2.xyz;
        if (dot(ns, ns) > 0.0) {
            ns = normalize(ns);
            s.normal = dot(ns, ng) < 0.0 ? -ns : ns;
        }
    }
    s.uv = vec2(0.0);
    s.incoming = ray.direction.xyz;
    s.material = material_of(triangle);
    surface_cone(ray, hit.t, tri, ng, HAS_NORMALS, tn, s.cone_width, s.cone_spread);
    s.texture_footprint = TEXTURE_FULL_RESOLUTION;
    if (HAS_TEXCOORDS) {
        TriangleTexcoords tc = texcoords_at(triangle);
        s.uv = w * tc.uv01.xy + hit.u * tc.uv01.zw + hit.v * tc.uv2.xy;
        s.texture_footprint = texture_cone_footprint(
            s.cone_width, abs(dot(ray.direction.xyz, ng)), tri.v1.xyz - tri.v0.xyz,
            tri.v2.xyz - tri.v0.xyz, tc.uv01.zw - tc.uv01.xy, tc.uv2.xy - tc.uv01.xy);
        vec3 dpdu, dpdv;
        if ((SURFACE_MAPS & (VKRT_MATERIAL_NORMAL_MAP | VKRT_MATERIAL_BUMP_MAP)) != 0u &&
            (materials[s.material].info.y &
             (VKRT_MATERIAL_NORMAL_MAP | VKRT_MATERIAL_BUMP_MAP)) != 0u &&
            texture_space(tri, tc, dpdu, dpdv)) {
            /* The map's +z is on the side of the OBJ's normal (the winding's without one): map
             * there, then turn the result to the ray's side as the normals above. */
            float side = s.front_face ? 1.0 : -1.0;
            vec3 mapped = side * mapped_normal(s.material, side * s.normal, dpdu, dpdv, s.uv,
                                               s.texture_footprint);
            s.normal = guard_mapped_normal(mapped, ng, -s.incoming);
        }
    }
    s.depth = ray_depth(ray);
    s.importance = ray_throughput(ray);
    s.payload = ray.payload;
    s.magnitude = triangle_magnitude(tri.v0.xyz, tri.v1.xyz, tri.v2.xyz);
    return s;
}

/* A ray origin just off the surface on the side direction d leaves towards. */
vec3 surface_origin(Surface s, vec3 d)
{
    vec3 n = dot(d, s.geometric_normal) >= 0.0 ? s.geometric_normal : -s.geometric_normal;
    return offset_ray_origin(s.position, n, s.magnitude);
}

/* Light i seen from s: the unit direction to it, the distance (FAR for a directional light) and
 * the irradiance it would bring to a surface at s facing it, before shadowing; all measured from
 * s.position itself. False when it cannot light s at all: ambient, behind the surface (by either
 * normal: light must not leak to the back through an interpolated normal), or outside a spot's
 * cone. Spot lights fall off linearly in angle from beam (full) to cutoff (zero), as Mitsuba's. */
bool light_geometry(Surface s, uint i, out vec3 to_light, out float distance_to_light,
                    out vec3 irradiance)
{
    Light l = lights[i];
    to_light = vec3(0.0, 0.0, 1.0);
    distance_to_light = 0.0;
    irradiance = vec3(0.0);
    if (l.info.x == VKRT_LIGHT_KIND_AMBIENT)
        return false;
    if (l.info.x == VKRT_LIGHT_KIND_DIRECTIONAL) {
        to_light = -l.direction.xyz;
        distance_to_light = FAR;
        irradiance = l.colour.rgb;
    } else {
        vec3 d = l.position.xyz - s.position;
        float d2 = dot(d, d);
        distance_to_light = sqrt(d2);
        to_light = d / distance_to_light;
        irradiance = l.colour.rgb / d2;
        if (l.info.x == VKRT_LIGHT_KIND_SPOT) {
            float cos_angle = dot(-to_light, l.direction.xyz);
            if (cos_angle <= l.direction.w)
                return false;
            float angle = acos(clamp(cos_angle, -1.0, 1.0));
            float cutoff = l.position.w, beam = l.colour.w;
            if (angle > beam)
                irradiance *= (cutoff - angle) / (cutoff - beam);
        }
    }
    return dot(s.normal, to_light) > 0.0 && dot(s.geometric_normal, to_light) > 0.0 &&
           any(greaterThan(irradiance, vec3(0.0)));
}

/* The shadow ray towards light i from s: it starts just off the lit side of the surface and ends
 * at the light (a directional light: never). */
void shadow_ray(Surface s, uint i, vec3 to_light, out vec3 origin, out vec3 direction,
                out float tmax)
{
    origin = offset_ray_origin(s.position, s.geometric_normal, s.magnitude);
    Light l = lights[i];
    if (l.info.x == VKRT_LIGHT_KIND_DIRECTIONAL) {
        direction = to_light;
        tmax = FAR;
        return;
    }
    vec3 d = l.position.xyz - origin;
    tmax = length(d);
    direction = d / tmax;
}

#endif
