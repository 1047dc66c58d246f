/*
 * microfacet.glsl: GGX microfacet BSDFs, for the built-in rough materials (roughconductor,
 * roughdielectric, roughplastic, pbr). Included by the generated material module after
 * material_api.glsl; glslang drops what a scene's shaders do not call.
 *
 * The model, in one place so that the four built-ins cannot drift apart:
 * - Normal distribution: GGX (Trowbridge-Reitz), isotropic, alpha = roughness^2 (the .mtl's Pr and
 *   Blender's roughness are "perceptual": alpha is its square, as in Disney's and Blender's
 *   Principled BSDF). Mitsuba's `alpha` is our alpha.
 * - Masking-shadowing: Smith's separable form G = G1(wo) G1(wi), as Mitsuba 3's
 *   MicrofacetDistribution::G, so that our lobes and Mitsuba's are the same function.
 * - Sampling: the distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of
 *   Visible Normals", JCGT 7(4)), whose pdf for a reflected direction is G1(wo) D / (4 cos_o):
 *   the sample weight f cos / pdf is then F G1(wi), never larger than F.
 * - Reflection and refraction through rough dielectrics: Walter, Marschner, Li and Torrance 2007,
 *   "Microfacet Models for Refraction through Rough Surfaces" (eq. 21 for the BTDF, 17 for the
 *   refracted half-vector's Jacobian), carrying radiance (the 1 / eta^2 of the smooth glass).
 * - The plastic's base (@roughplastic) under its rough coat: Mitsuba 3's roughplastic, from
 *   tables of the coat's transmittance and internal reflectance the host makes at scene load
 *   ("The rough coat's tables", below; src/scene/plastic_table.h).
 * Directions in the local frame have z along the shading normal, which faces the arriving ray.
 * Single scattering: light that would bounce between microfacets is lost, a few percent at
 * roughness 0.5 and more at 1 (tests/test_microfacet.c measures how much).
 */
#ifndef VKRT_MICROFACET_GLSL
#define VKRT_MICROFACET_GLSL

/* Below this alpha (roughness 0.02) a lobe is a delta lobe: D's peak, 1 / (pi alpha^2), passes
 * 2e6 there and the half-vector of two float directions is no longer precise enough to evaluate
 * it; a lobe that narrow is a mirror to every picture anyway. */
const float MICROFACET_SMOOTH_ALPHA = 4e-4;

/* ---- The distribution ------------------------------------------------------------------------ */

/* GGX's alpha from a perceptual roughness in [0, 1]. */
float ggx_alpha(float roughness)
{
    float r = clamp(roughness, 0.0, 1.0);
    return r * r;
}

/* GGX normal distribution D(m) of a local microfacet normal m. */
float ggx_d(vec3 m, float alpha)
{
    if (m.z <= 0.0)
        return 0.0;
    float a2 = alpha * alpha;
    float t = m.z * m.z * (a2 - 1.0) + 1.0;
    return a2 / (PI * t * t);
}

/* Smith's Lambda for GGX: G1 = 1 / (1 + Lambda). */
float ggx_lambda(vec3 w, float alpha)
{
    float c2 = w.z * w.z;
    float tan2 = max(1.0 - c2, 0.0) / max(c2, 1e-12);
    return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

/* Smith's masking of direction w by microfacets of normal m: 0 where w sees m's back. */
float ggx_g1(vec3 w, vec3 m, float alpha)
{
    if (dot(w, m) * w.z <= 0.0)
        return 0.0;
    return 1.0 / (1.0 + ggx_lambda(w, alpha));
}

/* A microfacet normal drawn from the normals visible from o (o.z > 0), density
 * G1(o) max(0, o.m) D(m) / o.z: Heitz 2018, listing 1 (stretch, sample a projected disk warped
 * towards the visible half, unstretch). */
vec3 ggx_sample_visible(vec3 o, float alpha, float u1, float u2)
{
    vec3 vh = normalize(vec3(alpha * o.x, alpha * o.y, o.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u1), phi = 2.0 * PI * u2;
    float p1 = r * cos(phi), p2 = r * sin(phi);
    float h = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - h) * sqrt(max(1.0 - p1 * p1, 0.0)) + h * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-6)));
}

/* Density of ggx_sample_visible drawing m, seen from o. */
float ggx_visible_pdf(vec3 o, vec3 m, float alpha)
{
    return ggx_g1(o, m, alpha) * max(dot(o, m), 0.0) * ggx_d(m, alpha) / o.z;
}

/* Schlick's Fresnel approximation with normal-incidence reflectance f0 (conductors: f0 is the
 * specular colour; Mitsuba's conductor takes a complex index instead, see docs/materials.md). */
vec3 fresnel_schlick(vec3 f0, float cos_i)
{
    float c = clamp(1.0 - cos_i, 0.0, 1.0);
    float c2 = c * c;
    return f0 + (vec3(1.0) - f0) * (c2 * c2 * c);
}

/* The hemispherical average of fresnel_dielectric for light arriving from outside,
 * 2 int_0^1 F(mu) mu dmu, by 8-point Gauss-Legendre in mu, the nodes symmetric about 1/2: F is
 * smooth in mu when eta > 1, and the rule is within 2e-5 of the integral for eta in [1.01, 3.5].
 * A midpoint rule in u = mu^2 is less accurate (sqrt(u) is not smooth at 0) for many more Fresnel
 * terms, which every evaluation of a plastic pays (docs/performance.md). */
float fresnel_diffuse_reflectance(float eta)
{
    const float offset[4] = float[4](0.091717321, 0.262766205, 0.398333239, 0.480144928);
    const float weight[4] = float[4](0.181341892, 0.156853323, 0.111190517, 0.050614268);
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        float lo = 0.5 - offset[k], hi = 0.5 + offset[k];
        sum += weight[k] * (lo * fresnel_dielectric(lo, eta) + hi * fresnel_dielectric(hi, eta));
    }
    return 2.0 * sum;
}

/* ---- The local frame ------------------------------------------------------------------------- */

/* An orthonormal frame about the shading normal, as cosine_direction builds it. */
mat3 microfacet_frame(vec3 n)
{
    vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0.0, 1.0, 0.0))
                                      : cross(n, vec3(1.0, 0.0, 0.0)));
    return mat3(t, cross(n, t), n);
}

/* World to local is the transpose of the frame's columns. */
vec3 to_local(mat3 f, vec3 v)
{
    return vec3(dot(v, f[0]), dot(v, f[1]), dot(v, f[2]));
}

/* ---- A rough material: which lobes, with which numbers -------------------------------------- */

/* The built-ins describe themselves in this struct; the functions below evaluate, sample and
 * Whitted-shade any of them. A mixture: `metallic` of a conductor of colour f0, the rest a
 * plastic (a GGX dielectric coat of index eta and colour specular over a Lambertian diffuse,
 * with a sheen of weight `sheen` beside it), unless `dielectric` (a rough glass boundary of
 * index eta, transmission tinted by tint). */
struct RoughMaterial {
    vec3 diffuse;   /* the plastic's Lambertian albedo under the coat */
    vec3 specular;  /* the plastic coat's reflectance scale (1: a plain dielectric coat) */
    vec3 f0;        /* the conductor's normal-incidence reflectance (Schlick) */
    vec3 tint;      /* the dielectric's transmission filter */
    float metallic; /* the conductor's share, in [0, 1] */
    float eta;      /* n_transmitted / n_incident of the coat or glass at this hit */
    float alpha;    /* GGX alpha of every lobe */
    bool dielectric;
    float sheen;    /* the plastic's sheen weight, in [0, 1] (the .mtl's Ps; "The sheen", below) */
    uint table;      /* where the plastic's coat table row at its roughness starts
                        (@roughplastic: plastic_find_row, "The rough coat's tables", below), or
                        PLASTIC_NO_TABLE: the smooth coat's Fresnel layering (@pbr, no coat, or
                        a smooth coat) */
    float table_mix; /* the share of the next row (a roughness map's rows); 0: this row alone */
};

/* Whether the material has a delta (smooth) specular lobe instead of a GGX one. */
bool rough_is_smooth(RoughMaterial m)
{
    return m.alpha < MICROFACET_SMOOTH_ALPHA;
}

/* ---- The rough coat's tables ---------------------------------------------------------------- */

/* @roughplastic follows Mitsuba 3's `roughplastic` (nonlinear false): its base sees the rough
 * coat's transmittance T(cos), what the GGX dielectric's visible microfacets refract in and the
 * refracted light's masking lets through, and 1 / (1 - Ri), Ri the coat's reflectance from inside
 * averaged as Mitsuba averages it. Both come from tables made on the host at scene load for the
 * indices and roughnesses the scene's rough plastics use (src/scene/plastic_table.h, layout in
 * glsl/shared.h), interpolated linearly in the cosine over Mitsuba's 64 cosines, as Mitsuba
 * does, and between rows of roughness where a map varies it. */
layout(std430, set = 0, binding = VKRT_BINDING_PLASTIC_TABLES) readonly buffer PlasticTableBuffer {
    float plastic_tables[];
};
const uint PLASTIC_NO_TABLE = 0xFFFFFFFFu;

/* Of the table row at `row`: T at cos_t, linear between the cosines as Mitsuba's lerp_gather;
 * or, where cos_t < 0, Ri. */
float plastic_row_value(uint row, float cos_t)
{
    if (cos_t < 0.0)
        return plastic_tables[row];
    float x = min(cos_t, 1.0) * float(VKRT_PLASTIC_COSINES - 1);
    uint k = min(uint(x), uint(VKRT_PLASTIC_COSINES - 2));
    return mix(plastic_tables[row + 1u + k], plastic_tables[row + 2u + k], x - float(k));
}

/* Finds m's rows in the table of the material being shaded (Material.maps.w) at m's roughness:
 * the row about it below, and the next one's share (a table of one row is the material's own
 * roughness). Once per material, so that the lobes read the header once. A smooth coat (below
 * roughness 0.02, which a roughness map may reach) has none: Mitsuba's smooth `plastic` is its
 * limit, the Fresnel layering below. */
void plastic_find_row(inout RoughMaterial m)
{
    float start = materials[vkrt_material].maps.w;
    m.table = PLASTIC_NO_TABLE;
    m.table_mix = 0.0;
    if (start < 0.0 || rough_is_smooth(m))
        return;
    uint table = uint(start), rows = uint(plastic_tables[table]);
    float x = clamp(sqrt(m.alpha) * plastic_tables[table + 1u], 0.0, float(rows - 1u));
    uint r0 = rows > 1u ? min(uint(x), rows - 2u) : 0u;
    m.table = table + uint(VKRT_PLASTIC_HEADER_FLOATS) + r0 * uint(VKRT_PLASTIC_ROW_FLOATS);
    m.table_mix = x - float(r0);
}

/* T at cos_t (or Ri where cos_t < 0) at m's roughness: its row, mixed with the next. */
float plastic_table_value(RoughMaterial m, float cos_t)
{
    float v = plastic_row_value(m.table, cos_t);
    if (m.table_mix > 0.0)
        v = mix(v, plastic_row_value(m.table + uint(VKRT_PLASTIC_ROW_FLOATS), cos_t), m.table_mix);
    return v;
}

/* Whether the base sees the rough coat's tables (a rough @roughplastic). */
bool plastic_tabulated(RoughMaterial m)
{
    return m.table != PLASTIC_NO_TABLE;
}

/* What the coat lets into the base from the direction at cos_t: the rough coat's T, or the
 * smooth coat's 1 - F. */
float plastic_transmittance(RoughMaterial m, float cos_t)
{
    if (plastic_tabulated(m))
        return plastic_table_value(m, max(cos_t, 0.0));
    return 1.0 - fresnel_dielectric(cos_t, m.eta);
}

/* ---- The sheen ------------------------------------------------------------------------------ */

/* The .mtl's Ps (docs/materials.md, "The sheen"): the Disney sheen (Burley 2012, "Physically
 * Based Shading at Disney", section 5.3), as Blender 3's Principled BSDF and Mitsuba 3's
 * `principled` have it: f = sheen (1 - i.h)^5, untinted (white: Blender 4's default Sheen Tint,
 * Mitsuba's sheen_tint 0), no 1 / pi, added to the non-metal share beside its diffuse base (and
 * so under a clear coat). A grazing term: near 0 where i and o are near the normal, 1 where they
 * are grazing and on opposite sides (light from behind the surface's rim). Sampled with the
 * diffuse base's cosine lobe, as Mitsuba samples it. Not energy-conserving on its own (it adds
 * to the base, as Disney's does): its albedo is at most 0.088 per unit weight, at grazing view.
 * A scene whose materials have no sheen compiles none of it (VKRT_MATERIAL_SHEEN in
 * SURFACE_MAPS). */
bool sheen_present(RoughMaterial m)
{
    return (SURFACE_MAPS & VKRT_MATERIAL_SHEEN) != 0u && m.sheen > 0.0;
}

/* f cos of the sheen for the local o (o.z > 0) and i (i.z > 0). */
float sheen_lobe(RoughMaterial m, vec3 o, vec3 i)
{
    if (!sheen_present(m))
        return 0.0;
    float c = clamp(1.0 - dot(i, normalize(o + i)), 0.0, 1.0);
    float c2 = c * c;
    return m.sheen * c2 * c2 * c * i.z;
}

/* The sheen's directional albedo at the viewing cosine cos_o, int sheen_lobe di: a quartic in
 * 1 - cos_o fitted to the integral (within 2.5e-5 per unit weight; tests/test_sheen.c holds it to
 * the integral). For the sampling probabilities and Whitted's ambient light. */
float sheen_albedo(RoughMaterial m, float cos_o)
{
    if (!sheen_present(m))
        return 0.0;
    float x = 1.0 - clamp(cos_o, 0.0, 1.0);
    return m.sheen * (2.588e-4 + x * (6.3485e-3 + x * (2.92702e-2 + x * (2.44559e-2 + x * 2.81456e-2))));
}

/* The plastic's diffuse lobe (f cos): Mitsuba's `plastic` and `roughplastic` (nonlinear false),
 * kd / (pi eta^2 (1 - Ri)) T(cos_i) T(cos_o) cos_i with the coat's transmittance T both ways and
 * 1 / (1 - Ri) for the light the coat reflects back down (internally) until it comes out.
 * Through a rough coat T and Ri are the tables' (above), and a white base returns less than the
 * coat lets in: Mitsuba's model loses the coat's single scattering on every crossing (Kd 1, Ni
 * 1.5, cos 0.5: albedo 0.982, 0.966, 0.725, 0.260 at roughness 0.05, 0.2, 0.5, 1). Through a
 * smooth coat (and for @pbr's base at any roughness) T = 1 - F and 1 - Ri = (1 - Fdr) / eta^2,
 * Fdr the coat's hemispherical average reflectance from outside: then the lobe's albedo for
 * kd = 1 is exactly 1 - F(cos_o), what the coat lets in. */
vec3 plastic_diffuse(RoughMaterial m, vec3 o, vec3 i)
{
    float through = plastic_transmittance(m, o.z) * plastic_transmittance(m, i.z);
    float inside = plastic_tabulated(m)
                       ? m.eta * m.eta * (1.0 - plastic_table_value(m, -1.0))
                       : 1.0 - fresnel_diffuse_reflectance(m.eta);
    return m.diffuse * (through * i.z / (PI * inside));
}

/* Probability that the plastic samples its coat rather than its diffuse base (and the sheen,
 * which shares the base's cosine sampling): what the coat does not let through at the viewing
 * angle against what it does, each by luminance, and the sheen's albedo (Mitsuba's choice,
 * luminance for its channel mean). */
float plastic_coat_probability(RoughMaterial m, vec3 o)
{
    float t = plastic_transmittance(m, o.z);
    float ws = luminance(m.specular) * (1.0 - t);
    float wd = luminance(m.diffuse) * t + sheen_albedo(m, o.z);
    return ws + wd > 0.0 ? ws / (ws + wd) : 1.0;
}

/* The reflectance of the mixture's specular lobes at a microfacet seen at cos_h: the conductor's
 * Schlick share and the plastic coat's dielectric Fresnel share. */
vec3 rough_specular_fresnel(RoughMaterial m, float cos_h)
{
    return m.metallic * fresnel_schlick(m.f0, cos_h) +
           (1.0 - m.metallic) * m.specular * fresnel_dielectric(cos_h, m.eta);
}

/* f cos and pdf of a rough dielectric boundary for the local directions o (o.z > 0) and i. */
vec3 rough_dielectric_lobe(RoughMaterial m, vec3 o, vec3 i, out float pdf)
{
    pdf = 0.0;
    bool reflected = i.z > 0.0;
    vec3 h = reflected ? o + i : o + m.eta * i;
    if (i.z == 0.0 || dot(h, h) == 0.0)
        return vec3(0.0);
    h = normalize(h);
    if (h.z < 0.0)
        h = -h;
    float oh = dot(o, h), ih = dot(i, h);
    if (oh <= 0.0 || (reflected ? ih <= 0.0 : ih >= 0.0))
        return vec3(0.0);
    float f = fresnel_dielectric(oh, m.eta);
    float d = ggx_d(h, m.alpha), g = ggx_g1(o, h, m.alpha) * ggx_g1(i, h, m.alpha);
    float visible = ggx_visible_pdf(o, h, m.alpha);
    if (reflected) {
        pdf = f * visible / (4.0 * oh);
        return vec3(f * d * g / (4.0 * o.z));
    }
    /* Walter's eq. 21 times |cos_i|, radiance carried (no eta^2 in the numerator), and eq. 17's
     * Jacobian of the refracted half-vector for the pdf. */
    float denom = oh + m.eta * ih;
    pdf = (1.0 - f) * visible * m.eta * m.eta * abs(ih) / (denom * denom);
    return m.tint * ((1.0 - f) * d * g * oh * abs(ih) / (o.z * denom * denom));
}

/* f cos and pdf of the reflecting mixture (conductor and plastic) for o (o.z > 0), i (i.z > 0). */
vec3 rough_reflection_lobes(RoughMaterial m, vec3 o, vec3 i, out float pdf)
{
    float coat = plastic_coat_probability(m, o);
    vec3 plastic = plastic_diffuse(m, o, i);
    float pdf_diffuse = i.z / PI;
    /* The probability of choosing the specular lobes over the diffuse one. */
    float p_specular = m.metallic + (1.0 - m.metallic) * coat;
    pdf = (1.0 - p_specular) * pdf_diffuse;
    vec3 f = (1.0 - m.metallic) * (plastic + sheen_lobe(m, o, i));
    if (rough_is_smooth(m))
        return f;
    vec3 h = normalize(o + i);
    float d = ggx_d(h, m.alpha), g = ggx_g1(o, h, m.alpha) * ggx_g1(i, h, m.alpha);
    pdf += p_specular * ggx_visible_pdf(o, h, m.alpha) / (4.0 * dot(o, h));
    return f + rough_specular_fresnel(m, dot(i, h)) * (d * g / (4.0 * o.z));
}

/* ---- The clear coat ------------------------------------------------------------------------ */

/* A clear coat over any of the above: Blender's Principled BSDF's coat (the .mtl's Pc and Pcr,
 * docs/materials.md), a GGX dielectric of index COAT_ETA whose reflection is `weight` times
 * F(i.h) D G / (4 cos_o), with its own roughness, sampled by visible normals as the other lobes.
 * The base beneath sees the coat's smooth-surface Fresnel transmission both ways,
 * (1 - w F(cos_o)) (1 - w F(cos_i)), and for the opaque bases the 1 / (1 - w Fdr) that counts the
 * light the coat reflects back down until it comes out: Kulla and Conty's reciprocal albedo
 * scaling (2017, "Revisiting Physically Based Shading at Imageworks") with the smooth coat's
 * Fresnel for the coat's albedo, the plastic's own layering (plastic_diffuse) again. Over a white
 * Lambertian base it conserves energy exactly but for the rough coat's single-scattering loss;
 * over other bases it loses or gains a few percent (tests/test_coat.c prints how much).
 * Over glass (a dielectric base) the coat is on the front face, the side the winding faces: light
 * the glass reflects there crosses the coat twice, light it lets through once, and nothing comes
 * back down (there is no base under a see-through solid to return it); from inside, light
 * leaving through the surface crosses the coat once, and the coat reflects nothing.
 * A scene whose materials have no coat compiles none of this (VKRT_MATERIAL_COAT in
 * SURFACE_MAPS). */
const float COAT_ETA = 1.5;
/* fresnel_diffuse_reflectance(COAT_ETA), 2 int_0^1 F(mu) mu dmu, precomputed. */
const float COAT_FDR = 0.09177796;

struct Coat {
    float weight; /* in [0, 1]: Blender's Coat Weight (number 18); 0: no coat */
    float alpha;  /* GGX alpha of its roughness (number 19) */
};

/* The coat of a rough built-in: numbers 18 and 19 of its material. */
Coat rough_coat()
{
    if ((SURFACE_MAPS & VKRT_MATERIAL_COAT) == 0u)
        return Coat(0.0, 0.0);
    return Coat(clamp(param(18u), 0.0, 1.0), ggx_alpha(param(19u)));
}

/* Whether the coat is there; constant false in a scene without one. */
bool coat_present(Coat c)
{
    return (SURFACE_MAPS & VKRT_MATERIAL_COAT) != 0u && c.weight > 0.0;
}

/* What the coat lets through at the cosine c to its normal: 1 - w F(c). */
float coat_transmission(Coat c, float cos_t)
{
    return 1.0 - c.weight * fresnel_dielectric(abs(cos_t), COAT_ETA);
}

/* The factor on the base's f cos for o (o.z > 0) and i, on the given side of the surface. */
float coat_base_scale(RoughMaterial m, Coat c, vec3 o, vec3 i, bool front)
{
    if (!m.dielectric)
        return coat_transmission(c, o.z) * coat_transmission(c, i.z) / (1.0 - c.weight * COAT_FDR);
    if (!front)
        return i.z < 0.0 ? coat_transmission(c, i.z) : 1.0;
    return i.z > 0.0 ? coat_transmission(c, o.z) * coat_transmission(c, i.z)
                     : coat_transmission(c, o.z);
}

/* Probability of sampling the coat rather than the base: the coat's reflectance at o against
 * what it lets through times a guess of the base's albedo (the reflecting mixture's Fresnel
 * shares by luminance; glass reflects or transmits everything). */
float coat_probability(RoughMaterial m, Coat c, vec3 o)
{
    float r = c.weight * fresnel_dielectric(o.z, COAT_ETA);
    float fb = fresnel_dielectric(o.z, m.eta);
    float base = m.dielectric ? 1.0
                              : m.metallic * luminance(fresnel_schlick(m.f0, o.z)) +
                                    (1.0 - m.metallic) * (luminance(m.specular) * fb +
                                                          luminance(m.diffuse) * (1.0 - fb) +
                                                          sheen_albedo(m, o.z));
    float t = (1.0 - r) * base;
    return r + t > 0.0 ? r / (r + t) : 1.0;
}

/* f cos of the coat's GGX reflection for o and i (nothing below the surface, or where the coat
 * is smooth: a delta lobe, which rough_sample draws), and the density with which rough_sample's
 * coat branch draws i: reflected about a visible normal, it may point below the surface, where a
 * glass base lets light through, so the density is counted there too (a balance of the
 * strategies that left it out would weigh those directions too much). */
vec3 coat_lobe(Coat c, vec3 o, vec3 i, bool above, out float pdf)
{
    pdf = 0.0;
    vec3 h = o + i;
    if (c.alpha < MICROFACET_SMOOTH_ALPHA || dot(h, h) == 0.0)
        return vec3(0.0);
    h = normalize(h);
    float oh = dot(o, h);
    if (oh <= 0.0)
        return vec3(0.0);
    pdf = ggx_visible_pdf(o, h, c.alpha) / (4.0 * oh);
    if (i.z <= 0.0 || !above)
        return vec3(0.0);
    float d = ggx_d(h, c.alpha), g = ggx_g1(o, h, c.alpha) * ggx_g1(i, h, c.alpha);
    return vec3(c.weight * fresnel_dielectric(dot(i, h), COAT_ETA) * d * g / (4.0 * o.z));
}

/* ---- What the built-ins call ----------------------------------------------------------------- */

/* The base's f cos and pdf (rough_eval without the coat) for the local o (o.z > 0) and i; above
 * says on which side of the geometric surface i leaves. */
vec3 rough_base_eval(RoughMaterial m, vec3 o, vec3 i, bool above, out float pdf)
{
    pdf = 0.0;
    if (m.dielectric) {
        if (rough_is_smooth(m) || above != (i.z > 0.0))
            return vec3(0.0);
        return rough_dielectric_lobe(m, o, i, pdf);
    }
    if (i.z <= 0.0 || !above)
        return vec3(0.0);
    return rough_reflection_lobes(m, o, i, pdf);
}

/* bsdf_eval of a rough material under its coat: f cos for the world direction wi, and the pdf
 * of rough_sample choosing it. Delta lobes (roughness below 0.02) are left out, as bsdf_eval
 * must. */
vec3 rough_eval(Surface s, RoughMaterial m, Coat c, vec3 wi, out float pdf)
{
    pdf = 0.0;
    mat3 frame = microfacet_frame(s.normal);
    vec3 o = to_local(frame, -s.incoming), i = to_local(frame, wi);
    if (o.z <= 0.0)
        return vec3(0.0);
    /* The geometric surface decides the side: no light through it by a bent shading normal. */
    bool above = dot(wi, s.geometric_normal) > 0.0;
    vec3 f = rough_base_eval(m, o, i, above, pdf);
    if (!coat_present(c))
        return f;
    bool front = !m.dielectric || s.front_face;
    float pc = front ? coat_probability(m, c, o) : 0.0;
    f *= coat_base_scale(m, c, o, i, front);
    pdf *= 1.0 - pc;
    if (pc > 0.0) {
        float pdf_coat;
        f += coat_lobe(c, o, i, above, pdf_coat);
        pdf += pc * pdf_coat;
    }
    return f;
}

/* bsdf_sample of a rough material: the coat's visible normal with coat_probability, or else the
 * base's: a visible normal, then reflection or (dielectric) refraction chosen by its Fresnel
 * reflectance; for the reflecting mixture first one of the conductor, the plastic's coat and the
 * diffuse base. The weight is rough_eval's value over its pdf, so that sampling and evaluation
 * cannot disagree; delta lobes weigh their value over the probability of choosing them. */
bool rough_sample(Surface s, RoughMaterial m, Coat c, out BsdfSample b)
{
    b.delta = false;
    b.pdf = 0.0;
    b.weight = vec3(0.0);
    b.direction = reflect(s.incoming, s.normal);
    mat3 frame = microfacet_frame(s.normal);
    vec3 o = to_local(frame, -s.incoming);
    /* With a coat, first the coat (probability pc) or the base; the base's delta lobes then
     * weigh what comes out through the coat over the probability of sampling the base. */
    bool coated = coat_present(c);
    bool front = !m.dielectric || s.front_face;
    float pc = 0.0;
    if (coated) {
        if (o.z <= 0.0)
            return false;
        pc = front ? coat_probability(m, c, o) : 0.0;
    }
    vec3 i = vec3(0.0);
    if (coated && random() < pc) {
        if (c.alpha < MICROFACET_SMOOTH_ALPHA) {
            /* The smooth coat's delta mirror, Fresnel at the normal. */
            b.delta = true;
            b.weight = vec3(c.weight * fresnel_dielectric(o.z, COAT_ETA) / pc);
            return dot(b.direction, s.geometric_normal) > 0.0;
        }
        i = reflect(-o, ggx_sample_visible(o, c.alpha, random(), random()));
    } else if (m.dielectric && rough_is_smooth(m)) {
        if (!dielectric_sample(s, m.eta, b))
            b.weight *= m.tint;
        if (coated)
            b.weight *= coat_base_scale(m, c, o, to_local(frame, b.direction), front) / (1.0 - pc);
        return true;
    } else {
        if (o.z <= 0.0)
            return false;
        if (m.dielectric) {
            vec3 h = ggx_sample_visible(o, m.alpha, random(), random());
            float oh = dot(o, h);
            if (random() < fresnel_dielectric(oh, m.eta))
                i = reflect(-o, h);
            else
                i = refract(-o, h, 1.0 / m.eta);
        } else {
            float p_specular = m.metallic + (1.0 - m.metallic) * plastic_coat_probability(m, o);
            float u = random();
            if (u >= p_specular) {
                b.direction = cosine_direction(s.normal, random(), random());
                i = to_local(frame, b.direction);
            } else if (rough_is_smooth(m)) {
                /* The delta mirror of the smooth coat or metal, Fresnel at the normal. */
                b.delta = true;
                b.weight = rough_specular_fresnel(m, o.z) / p_specular;
                if (coated)
                    b.weight *= coat_base_scale(m, c, o, vec3(-o.xy, o.z), front) / (1.0 - pc);
                return dot(b.direction, s.geometric_normal) > 0.0;
            } else {
                i = reflect(-o, ggx_sample_visible(o, m.alpha, random(), random()));
            }
        }
    }
    if (dot(i, i) == 0.0)
        return false;
    b.direction = normalize(frame * i);
    vec3 f = rough_eval(s, m, c, b.direction, b.pdf);
    if (!(b.pdf > 0.0))
        return false;
    b.weight = f / b.pdf;
    return true;
}

/* Whitted's shading of a rough material (Cook's distributed ray tracing: the glossy reflection is
 * one ray sampled from the BSDF per hit, converging with the pixel's samples): the scene's lights
 * through the whole BSDF (highlights and diffuse; point lights are never hit by a ray, so nothing
 * is counted twice), the ambient light on the diffuse base (through the coat), and one ray from
 * the specular lobes (a glossy reflection from the coat or the base, or reflection or refraction
 * through the glass). The diffuse base (and the sheen beside it, which sees the ambient light
 * through its albedo) casts no ray, as diffuse surfaces do not in Whitted's model. Everything is
 * scaled by coverage (the covered part of a cut-out; 1 for a solid surface). */
void rough_whitted_shade(Surface s, RoughMaterial m, Coat c, float coverage)
{
    float cos_o = dot(-s.incoming, s.normal);
    vec3 sum = (1.0 - m.metallic) * (m.diffuse + sheen_albedo(m, cos_o)) * ambient_light();
    if (coat_present(c))
        sum *= coat_transmission(c, cos_o);
    if (m.dielectric)
        sum = vec3(0.0);
    for (uint k = 0u; k < light_count(); ++k) {
        vec3 to_light, irradiance;
        float pdf;
        if (light_sample(s, k, to_light, irradiance))
            sum += rough_eval(s, m, c, to_light, pdf) * irradiance;
    }
    add_radiance(coverage * sum);
    BsdfSample b;
    if (m.dielectric) {
        if (rough_sample(s, m, c, b))
            cast_ray(s, b.direction, coverage * b.weight);
        return;
    }
    RoughMaterial specular_only = m;
    specular_only.diffuse = vec3(0.0);
    specular_only.sheen = 0.0;
    if (rough_sample(s, specular_only, c, b))
        cast_ray(s, b.direction, coverage * b.weight);
}

/* The five entry points of a rough built-in whose RoughMaterial comes from material(s), under the
 * coat of numbers 18 and 19 (rough_coat): one glossy ray per hit and the lights for Whitted
 * (rough_whitted_shade), Ke from the front face and the GGX lobes for path, all cut out by
 * coverage (d, map_d: mtl.glsl) as the .mtl built-ins are. A macro, so that the names it defines
 * are the ones the generated module renames for the shader that expands it (count_rays is
 * #defined to vkrt_count_rays_N there). */
#define ROUGH_BUILTIN(material)                                                                   \
    uint count_rays(Surface s) { return 1u + mtl_see_through_count(s); }                           \
    void shade(Surface s)                                                                          \
    {                                                                                              \
        float coverage = mtl_see_through(s);                                                       \
        rough_whitted_shade(s, material(s), rough_coat(), coverage);                               \
        add_radiance(coverage * mtl_emission(s));                                                  \
    }                                                                                              \
    vec3 emitted(Surface s) { return mtl_coverage(s) * mtl_emitted(s); }                           \
    vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)                                              \
    {                                                                                              \
        float coverage = mtl_coverage(s);                                                          \
        vec3 f = rough_eval(s, material(s), rough_coat(), wi, pdf);                                \
        pdf *= coverage;                                                                           \
        return coverage * f;                                                                       \
    }                                                                                              \
    bool bsdf_sample(Surface s, out BsdfSample b)                                                  \
    {                                                                                              \
        if (mtl_pass_through(s, b))                                                                \
            return true;                                                                           \
        bool ok = rough_sample(s, material(s), rough_coat(), b);                                   \
        b.pdf *= mtl_coverage(s);                                                                  \
        return ok;                                                                                 \
    }

#endif
