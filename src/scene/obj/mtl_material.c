/* mtl_material.c: an .mtl material as the scene model's physically based record (see mtl.h). */
#define _POSIX_C_SOURCE 200809L
#include "mtl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Below this roughness the GGX built-ins are smooth (glsl/lib/microfacet.glsl's
 * MICROFACET_SMOOTH_ALPHA is its square): a PBR glass this smooth is the smooth dielectric. */
static const float smooth_roughness = 0.02f;

static bool any_nonzero(const float *v, int n)
{
    for (int i = 0; i < n; ++i)
        if (v[i] != 0.0f)
            return true;
    return false;
}

float vkrt_ns_roughness(float ns)
{
    float alpha = sqrtf(2.0f / (fmaxf(ns, 0.0f) + 2.0f));
    return sqrtf(alpha);
}

/* The family the illumination model and the fields describe (docs/materials.md's table): glass
 * for illum 4, 6 and 7 (rough where the PBR extension gives it a roughness), a mirror for 3 and 5,
 * an emitter where only Ke is given, the principled base where the PBR extension is used, Phong
 * where illum 2 or more has a highlight, else diffuse. emission is the resolved Ke. */
static vkrt_bsdf family_of(const vkrt_mtl *m, const float emission[3])
{
    if (m->illum == 4 || m->illum == 6 || m->illum == 7)
        return m->pbr && (m->pr < 0.0f || m->pr >= smooth_roughness) ? VKRT_BSDF_ROUGH_DIELECTRIC
                                                                      : VKRT_BSDF_DIELECTRIC;
    if (m->illum == 3 || m->illum == 5)
        return VKRT_BSDF_MIRROR;
    if (any_nonzero(emission, 3) && !any_nonzero(m->kd, 3) && !any_nonzero(m->ks, 3) && !m->map_kd)
        return VKRT_BSDF_EMITTER;
    if (m->pbr)
        return VKRT_BSDF_PRINCIPLED;
    if (m->illum >= 2 && any_nonzero(m->ks, 3) && m->ns > 0.0f)
        return VKRT_BSDF_GLOSSY_PHONG;
    return VKRT_BSDF_DIFFUSE;
}

/* A copy of s, or NULL for NULL; *failed set when memory runs out. */
static char *copy(const char *s, bool *failed)
{
    if (!s)
        return NULL;
    char *c = strdup(s);
    *failed = *failed || !c;
    return c;
}

static void set_map(vkrt_material *out, int k, const char *path, int line, bool *failed)
{
    out->maps[k].path = copy(path, failed);
    out->maps[k].line = line;
}

bool vkrt_mtl_to_material(const vkrt_mtl *m, vkrt_material *out)
{
    vkrt_material_defaults(out);
    memcpy(out->base_colour, m->kd, sizeof m->kd);
    out->opacity = m->d;
    memcpy(out->specular, m->ks, sizeof m->ks);
    out->specular_exponent = m->ns;
    /* A map_Ke without a Ke is the emission itself (Ke 1 1 1), as a map replaces its number. */
    for (int i = 0; i < 3; ++i)
        out->emission[i] = m->map_ke && !m->ke_given ? 1.0f : m->ke[i];
    out->ior = m->ni;
    memcpy(out->transmission_filter, m->tf, sizeof m->tf);
    /* A map replaces its number (Blender's exporter writes both, and its importer ignores the
     * number where a map is linked): the shader multiplies them, so the number becomes 1.
     * Without Pr the roughness comes from Ns (vkrt_ns_roughness). */
    out->roughness = m->map_pr ? 1.0f : m->pr >= 0.0f ? m->pr : vkrt_ns_roughness(m->ns);
    out->metallic = m->map_pm ? 1.0f : m->pm;
    /* Blender's importer reads Pc as Coat Weight Pc / 4 ("Clearcoat used to include an implicit
     * 0.25 factor": Principled v1's clearcoat lobe was a quarter of its number), Pcr as the coat's
     * roughness. */
    out->coat = fminf(fmaxf(0.25f * m->pc, 0.0f), 1.0f);
    out->coat_roughness = m->pcr;
    /* Blender's importer reads Ps as Sheen Weight; a map replaces its number, as for Pr. */
    out->sheen = m->map_ps ? 1.0f : m->ps;
    out->bsdf = family_of(m, out->emission);
    bool failed = false;
    out->name = copy(m->name, &failed);
    out->file = copy(m->mtl_path ? m->mtl_path : "(.mtl)", &failed);
    set_map(out, VKRT_MAP_BASE_COLOUR, m->map_kd, m->map_kd_line, &failed);
    set_map(out, VKRT_MAP_COVERAGE, m->map_d, m->map_d_line, &failed);
    set_map(out, VKRT_MAP_ROUGHNESS, m->map_pr, m->map_pr_line, &failed);
    set_map(out, VKRT_MAP_METALLIC, m->map_pm, m->map_pm_line, &failed);
    set_map(out, VKRT_MAP_SHEEN, m->map_ps, m->map_ps_line, &failed);
    /* norm is a normal map and wins over a map_Bump of the same material; a map_Bump is a height
     * map unless its image is a normal map (Blender writes its normal maps as map_Bump). */
    if (m->norm)
        set_map(out, VKRT_MAP_DETAIL, m->norm, m->norm_line, &failed);
    else
        set_map(out, VKRT_MAP_DETAIL, m->map_bump, m->map_bump_line, &failed);
    out->detail_kind = m->norm ? VKRT_DETAIL_NORMAL : VKRT_DETAIL_BY_IMAGE;
    out->detail_scale = m->bump_multiplier;
    set_map(out, VKRT_MAP_EMISSION, m->map_ke, m->map_ke_line, &failed);
    if (failed)
        vkrt_material_free_strings(out);
    return !failed;
}

void vkrt_mtl_free(vkrt_mtl *m)
{
    free(m->name);
    free(m->map_kd);
    free(m->map_d);
    free(m->map_pr);
    free(m->map_pm);
    free(m->map_ps);
    free(m->norm);
    free(m->map_bump);
    free(m->map_ke);
    free(m->mtl_path);
    memset(m, 0, sizeof *m);
}
