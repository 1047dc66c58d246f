/* materials.c: from usemtl names to shaders, parameters and textures (see materials.h). */
#define _POSIX_C_SOURCE 200809L
#include "materials.h"

#include "../../glsl/shared.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const vkrt_builtin_shaders[] = {
    "diffuse", "textured", "phong", "mirror", "glass", "emissive", "checker", "absorbing_glass",
    "roughconductor", "roughdielectric", "roughplastic", "pbr", "environment", NULL,
};

/* Parameter layout of the built-ins, which the .mtl mapping fills (glsl/lib/mtl.glsl). */
enum {
    PARAM_KD = 0,
    PARAM_TRANSPARENCY = 3,
    PARAM_KS = 4,
    PARAM_NS = 7,
    PARAM_KE = 8,
    PARAM_NI = 11,
    PARAM_TF = 12,
    PARAM_ILLUM = 15,
    PARAM_ROUGHNESS = 16,
    PARAM_METALLIC = 17,
    PARAM_COAT = 18,
    PARAM_COAT_ROUGHNESS = 19,
};
enum {
    SLOT_MAP_KD = 0,
    SLOT_MAP_D = 1,
    SLOT_MAP_PR = 2,
    SLOT_MAP_PM = 3,
    SLOT_DETAIL = VKRT_SLOT_DETAIL,     /* norm, or map_Bump */
    SLOT_MAP_KE = VKRT_SLOT_EMISSION,
    SLOT_MAP_PS = VKRT_SLOT_SHEEN,
};
/* A material file's number that is not one of the 20 above: the sheen (Material.maps.z). */
enum { NUMBER_SHEEN = 20 };

/* Below this roughness the GGX built-ins are smooth (glsl/lib/microfacet.glsl's
 * MICROFACET_SMOOTH_ALPHA is its square): a PBR glass this smooth is the plain glass. */
static const float smooth_roughness = 0.02f;

static const float default_albedo = 0.8f;

static bool is_builtin(const char *name)
{
    for (const char *const *b = vkrt_builtin_shaders; *b; ++b)
        if (strcmp(*b, name) == 0)
            return true;
    return false;
}

static char *read_text(const char *path, vkrt_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        vkrt_error_set(err, "cannot read '%s': %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 4096, len = 0;
    char *text = malloc(cap);
    size_t n;
    while (text && (n = fread(text + len, 1, cap - len - 1, f)) > 0) {
        len += n;
        if (len + 1 == cap) {
            char *grown = realloc(text, cap *= 2);
            if (!grown) {
                free(text);
                text = NULL;
                break;
            }
            text = grown;
        }
    }
    bool failed = ferror(f);
    fclose(f);
    if (!text || failed) {
        free(text);
        vkrt_error_set(err, "cannot read '%s'", path);
        return NULL;
    }
    text[len] = '\0';
    if (strlen(text) != len) {
        free(text);
        vkrt_error_set(err, "'%s' is not a text file (it holds a NUL byte)", path);
        return NULL;
    }
    return text;
}

/* Index of the shader (built-in name or user path) in out->shaders, adding it if new. */
static bool find_or_add_shader(vkrt_scene_materials *out, const char *builtin, const char *path,
                               const char *referrer, uint32_t *index, vkrt_error *err)
{
    for (uint32_t i = 0; i < out->shader_count; ++i) {
        const vkrt_shader_source *s = &out->shaders[i];
        if ((builtin && s->builtin && strcmp(builtin, s->builtin) == 0) ||
            (path && s->path && strcmp(path, s->path) == 0)) {
            *index = i;
            return true;
        }
    }
    vkrt_shader_source *grown =
        realloc(out->shaders, (out->shader_count + 1) * sizeof *out->shaders);
    if (!grown)
        return vkrt_error_set(err, "out of memory");
    out->shaders = grown;
    vkrt_shader_source *s = &out->shaders[out->shader_count];
    memset(s, 0, sizeof *s);
    s->referrer = strdup(referrer);
    if (!s->referrer)
        return vkrt_error_set(err, "out of memory");
    ++out->shader_count;
    if (builtin) {
        if (!is_builtin(builtin))
            return vkrt_error_set(err, "%s: no built-in shader '@%s' (see docs/materials.md)",
                                  referrer, builtin);
        s->builtin = strdup(builtin);
        if (!s->builtin)
            return vkrt_error_set(err, "out of memory");
    } else {
        s->path = strdup(path);
        if (!s->path)
            return vkrt_error_set(err, "out of memory");
        s->text = read_text(path, err);
        if (!s->text)
            return vkrt_error_prefix(err, "%s: shader", referrer);
    }
    *index = out->shader_count - 1;
    return true;
}

static bool any_nonzero(const float *v, int n)
{
    for (int i = 0; i < n; ++i)
        if (v[i] != 0.0f)
            return true;
    return false;
}

/* The material's emission: Ke, or 1 1 1 where a map_Ke comes without a Ke (the map is then the
 * emission itself, as a map replaces its number below). */
static void mtl_emission(const vkrt_mtl *m, float ke[3])
{
    for (int i = 0; i < 3; ++i)
        ke[i] = m->map_ke && !m->ke_given ? 1.0f : m->ke[i];
}

/* The built-in that renders an .mtl material as its illumination model says (docs/materials.md). */
static const char *mtl_builtin(const vkrt_mtl *m)
{
    float ke[3];
    mtl_emission(m, ke);
    if (m->illum == 4 || m->illum == 6 || m->illum == 7)
        return m->pbr && (m->pr < 0.0f || m->pr >= smooth_roughness) ? "roughdielectric" : "glass";
    if (m->illum == 3 || m->illum == 5)
        return "mirror";
    if (any_nonzero(ke, 3) && !any_nonzero(m->kd, 3) && !any_nonzero(m->ks, 3) && !m->map_kd)
        return "emissive";
    if (m->pbr)
        return "pbr";
    if (m->illum >= 2 && any_nonzero(m->ks, 3) && m->ns > 0.0f)
        return "phong";
    return m->map_kd ? "textured" : "diffuse";
}

float vkrt_ns_roughness(float ns)
{
    float alpha = sqrtf(2.0f / (fmaxf(ns, 0.0f) + 2.0f));
    return sqrtf(alpha);
}

static void mtl_params(const vkrt_mtl *m, float *p)
{
    memcpy(p + PARAM_KD, m->kd, sizeof m->kd);
    p[PARAM_TRANSPARENCY] = 1.0f - m->d;
    memcpy(p + PARAM_KS, m->ks, sizeof m->ks);
    p[PARAM_NS] = m->ns;
    mtl_emission(m, p + PARAM_KE);
    p[PARAM_NI] = m->ni;
    memcpy(p + PARAM_TF, m->tf, sizeof m->tf);
    p[PARAM_ILLUM] = (float)m->illum;
    /* A map replaces its number (Blender's exporter writes both, and its importer ignores the
     * number where a map is linked): the shader multiplies them, so the number becomes 1. */
    p[PARAM_ROUGHNESS] = m->map_pr ? 1.0f : m->pr >= 0.0f ? m->pr : vkrt_ns_roughness(m->ns);
    p[PARAM_METALLIC] = m->map_pm ? 1.0f : m->pm;
    /* Blender's importer reads Pc as Coat Weight Pc / 4 ("Clearcoat used to include an implicit
     * 0.25 factor": Principled v1's clearcoat lobe was a quarter of its number), Pcr as the coat's
     * roughness; number 18 is the weight. */
    p[PARAM_COAT] = fminf(fmaxf(0.25f * m->pc, 0.0f), 1.0f);
    p[PARAM_COAT_ROUGHNESS] = m->pcr;
}

/* The material's sheen weight clamped to [0, 1] (Blender's Sheen Weight's range), and
 * VKRT_MATERIAL_COAT and _SHEEN where its coat weight (number 18) or sheen is above 0: the
 * scene's shaders then compile the coat or the sheen (glsl/lib/microfacet.glsl). */
static void mark_layers(vkrt_scene_material *mat, float sheen)
{
    mat->sheen = fminf(fmaxf(sheen, 0.0f), 1.0f);
    if (mat->params[PARAM_COAT] > 0.0f)
        mat->maps |= VKRT_MATERIAL_COAT;
    if (mat->sheen > 0.0f)
        mat->maps |= VKRT_MATERIAL_SHEEN;
}

static bool add_texture(vkrt_scene_materials *out, vkrt_scene_material *mat, uint32_t slot,
                        const char *path, vkrt_texture_usage usage, const char *referrer,
                        vkrt_error *err)
{
    uint32_t index;
    if (!vkrt_texture_set_add(&out->textures, path, usage, referrer, &index, err))
        return false;
    mat->textures[slot] = index;
    if (slot + 1 > mat->texture_count)
        mat->texture_count = slot + 1;
    out->reads_texcoords = true;
    return true;
}

static bool init_material(vkrt_scene_material *mat, const char *name, const char *referrer,
                          vkrt_error *err)
{
    memset(mat, 0, sizeof *mat);
    for (uint32_t k = 0; k < VKRT_MATERIAL_TEXTURE_SLOTS; ++k)
        mat->textures[k] = VKRT_SCENE_NO_TEXTURE;
    mat->name = strdup(name);
    mat->referrer = strdup(referrer);
    if (!mat->name || !mat->referrer)
        return vkrt_error_set(err, "out of memory");
    return true;
}

/* A material of the material file: its shader, parameters and textures (sRGB colour maps). */
static bool from_definition(vkrt_scene_materials *out, vkrt_scene_material *mat,
                            const vkrt_material_file *file, const vkrt_material_def *def,
                            vkrt_error *err)
{
    char referrer[1200];
    snprintf(referrer, sizeof referrer, "%s:%d", file->path, def->line);
    if (!init_material(mat, def->name, referrer, err))
        return false;
    memcpy(mat->params, def->params, sizeof mat->params);
    mark_layers(mat, def->params[NUMBER_SHEEN]);
    char shader_referrer[1400];
    snprintf(shader_referrer, sizeof shader_referrer, "%s: material '%s'", referrer, def->name);
    bool builtin = def->shader[0] == '@';
    if (!find_or_add_shader(out, builtin ? def->shader + 1 : NULL, builtin ? NULL : def->shader,
                            shader_referrer, &mat->shader, err))
        return false;
    for (uint32_t k = 0; k < def->texture_count; ++k)
        if (!add_texture(out, mat, k, def->textures[k], VKRT_TEXTURE_COLOUR, referrer, err))
            return false;
    return true;
}

static bool from_mtl(vkrt_scene_materials *out, vkrt_scene_material *mat, const vkrt_mtl *m,
                     vkrt_error *err)
{
    const char *mtl = m->mtl_path ? m->mtl_path : "(.mtl)";
    if (!init_material(mat, m->name, mtl, err))
        return false;
    mtl_params(m, mat->params);
    /* Blender's importer reads Ps as Sheen Weight; a map replaces its number, as for Pr. */
    mark_layers(mat, m->map_ps ? 1.0f : m->ps);
    char shader_referrer[1200];
    snprintf(shader_referrer, sizeof shader_referrer, "%s: material '%s'", mtl, m->name);
    if (!find_or_add_shader(out, mtl_builtin(m), NULL, shader_referrer, &mat->shader, err))
        return false;
    /* Each map in its slot, named by its line for texture errors; roughness, metallic and sheen
     * maps are data, read as they are stored (no sRGB decoding). */
    const struct {
        const char *path;
        int line;
        uint32_t slot;
        vkrt_texture_usage usage;
    } maps[] = {
        {m->map_kd, m->map_kd_line, SLOT_MAP_KD, VKRT_TEXTURE_COLOUR},
        {m->map_d, m->map_d_line, SLOT_MAP_D, VKRT_TEXTURE_ALPHA},
        {m->map_pr, m->map_pr_line, SLOT_MAP_PR, VKRT_TEXTURE_DATA},
        {m->map_pm, m->map_pm_line, SLOT_MAP_PM, VKRT_TEXTURE_DATA},
        {m->map_ps, m->map_ps_line, SLOT_MAP_PS, VKRT_TEXTURE_DATA},
        /* Normal and height maps are data too; norm wins over a map_Bump of the same material. */
        {m->norm ? m->norm : m->map_bump, m->norm ? m->norm_line : m->map_bump_line, SLOT_DETAIL,
         VKRT_TEXTURE_DATA},
        {m->map_ke, m->map_ke_line, SLOT_MAP_KE, VKRT_TEXTURE_COLOUR},
    };
    for (size_t i = 0; i < sizeof maps / sizeof *maps; ++i) {
        char referrer[1200];
        snprintf(referrer, sizeof referrer, "%s:%d", mtl, maps[i].line);
        if (maps[i].path &&
            !add_texture(out, mat, maps[i].slot, maps[i].path, maps[i].usage, referrer, err))
            return false;
    }
    /* A map_Bump is a height map unless its image is a normal map (Blender writes its normal
     * maps as map_Bump): told apart by the image (vkrt_texture_is_normal_map). */
    uint32_t detail = mat->textures[SLOT_DETAIL];
    if (m->norm || (detail != VKRT_SCENE_NO_TEXTURE &&
                    vkrt_texture_is_normal_map(&out->textures, detail)))
        mat->maps |= VKRT_MATERIAL_NORMAL_MAP;
    else if (detail != VKRT_SCENE_NO_TEXTURE)
        mat->maps |= VKRT_MATERIAL_BUMP_MAP;
    if (m->map_ke)
        mat->maps |= VKRT_MATERIAL_EMISSION_MAP;
    mat->detail_multiplier = m->bump_multiplier;
    return true;
}

static bool default_material(vkrt_scene_materials *out, vkrt_scene_material *mat, vkrt_error *err)
{
    if (!init_material(mat, "(default)", "(default material: triangles without usemtl)", err))
        return false;
    for (int i = 0; i < 3; ++i)
        mat->params[PARAM_KD + i] = default_albedo;
    return find_or_add_shader(out, "diffuse", NULL, "(default material)", &mat->shader, err);
}

static bool environment_material(vkrt_scene_materials *out, vkrt_scene_material *mat,
                                 const vkrt_config *cfg, const vkrt_material_file *file,
                                 vkrt_error *err)
{
    const vkrt_material_def *def = file ? vkrt_material_file_find(file, "environment") : NULL;
    if (def)
        return from_definition(out, mat, file, def, err);
    if (!init_material(mat, "environment", cfg->path ? cfg->path : "(scene)", err))
        return false;
    memcpy(mat->params, cfg->environment, sizeof cfg->environment);
    return find_or_add_shader(out, "environment", NULL, "(environment)", &mat->shader, err);
}

bool vkrt_scene_materials_resolve(const vkrt_config *cfg, const vkrt_mesh *mesh,
                                  const vkrt_material_file *file, vkrt_scene_materials *out,
                                  vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    uint32_t mtl_count = mesh->material_count;
    /* used[i]: the list index of .mtl material i (mtl_count: the default), or UINT32_MAX. */
    uint32_t *used = malloc((mtl_count + 1) * sizeof *used);
    out->triangle_material = malloc((mesh->triangle_count ? mesh->triangle_count : 1) *
                                    sizeof *out->triangle_material);
    /* The used materials (at most every .mtl one and the default), the environment, and one
     * zeroed entry that free may visit after a failure part way. */
    out->list = calloc(mtl_count + 3, sizeof *out->list);
    if (!used || !out->triangle_material || !out->list) {
        free(used);
        vkrt_scene_materials_free(out);
        return vkrt_error_set(err, "out of memory for %u materials", mtl_count);
    }
    for (uint32_t i = 0; i <= mtl_count; ++i)
        used[i] = UINT32_MAX;
    bool ok = true;
    for (uint32_t t = 0; ok && t < mesh->triangle_count; ++t) {
        int32_t m = mesh->material[t];
        uint32_t key = m < 0 ? mtl_count : (uint32_t)m;
        if (used[key] == UINT32_MAX) {
            vkrt_scene_material *mat = &out->list[out->count];
            const vkrt_material_def *def =
                m >= 0 && file ? vkrt_material_file_find(file, mesh->materials[m].name) : NULL;
            if (def)
                ok = from_definition(out, mat, file, def, err);
            else if (m >= 0)
                ok = from_mtl(out, mat, &mesh->materials[m], err);
            else
                ok = default_material(out, mat, err);
            used[key] = out->count++;
        }
        out->triangle_material[t] = used[key];
    }
    if (ok) {
        out->environment = out->count;
        ok = environment_material(out, &out->list[out->count++], cfg, file, err);
    }
    free(used);
    if (!ok)
        vkrt_scene_materials_free(out);
    return ok;
}

void vkrt_scene_materials_free(vkrt_scene_materials *m)
{
    for (uint32_t i = 0; m->list && i < m->count + 1; ++i) {
        free(m->list[i].name);
        free(m->list[i].referrer);
    }
    free(m->list);
    free(m->triangle_material);
    for (uint32_t i = 0; i < m->shader_count; ++i) {
        free(m->shaders[i].builtin);
        free(m->shaders[i].path);
        free(m->shaders[i].text);
        free(m->shaders[i].referrer);
    }
    free(m->shaders);
    vkrt_texture_set_free(&m->textures);
    memset(m, 0, sizeof *m);
}
