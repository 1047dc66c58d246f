/* materials.c: from the model's material records to shaders, parameters and textures (see
 * materials.h). */
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

/* Parameter layout of the built-ins, which a model record fills (glsl/lib/mtl.glsl). */
enum {
    PARAM_KD = 0, PARAM_TRANSPARENCY = 3, PARAM_KS = 4, PARAM_NS = 7, PARAM_KE = 8, PARAM_NI = 11,
    PARAM_TF = 12, PARAM_FAMILY = 15, PARAM_ROUGHNESS = 16, PARAM_METALLIC = 17, PARAM_COAT = 18,
    PARAM_COAT_ROUGHNESS = 19,
};
/* The texture slot of each of a record's maps (VKRT_MAP_*), as the built-ins read them. */
static const uint32_t slot_of_map[VKRT_MAP_COUNT] = {
    [VKRT_MAP_BASE_COLOUR] = 0, [VKRT_MAP_COVERAGE] = 1,           [VKRT_MAP_ROUGHNESS] = 2,
    [VKRT_MAP_METALLIC] = 3,    [VKRT_MAP_SHEEN] = VKRT_SLOT_SHEEN, [VKRT_MAP_DETAIL] = VKRT_SLOT_DETAIL,
    [VKRT_MAP_EMISSION] = VKRT_SLOT_EMISSION,
};
/* A material file's number that is not one of the 20 above: the sheen (Material.maps.z). */
enum { NUMBER_SHEEN = 20 };

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

/* The built-in that renders a family (docs/materials.md): the diffuse family with a colour map
 * is the textured diffuse. */
static const char *builtin_of(const vkrt_material *m)
{
    switch (m->bsdf) {
    case VKRT_BSDF_GLOSSY_PHONG: return "phong";
    case VKRT_BSDF_MIRROR: return "mirror";
    case VKRT_BSDF_DIELECTRIC: return "glass";
    case VKRT_BSDF_ROUGH_DIELECTRIC: return "roughdielectric";
    case VKRT_BSDF_PRINCIPLED: return "pbr";
    case VKRT_BSDF_EMITTER: return "emissive";
    case VKRT_BSDF_DIFFUSE: break;
    }
    return m->maps[VKRT_MAP_BASE_COLOUR].path ? "textured" : "diffuse";
}

/* The record's numbers in the built-ins' parameter layout (glsl/lib/mtl.glsl). */
static void record_params(const vkrt_material *m, float *p)
{
    memcpy(p + PARAM_KD, m->base_colour, sizeof m->base_colour);
    p[PARAM_TRANSPARENCY] = 1.0f - m->opacity;
    memcpy(p + PARAM_KS, m->specular, sizeof m->specular);
    p[PARAM_NS] = m->specular_exponent;
    memcpy(p + PARAM_KE, m->emission, sizeof m->emission);
    p[PARAM_NI] = m->ior;
    memcpy(p + PARAM_TF, m->transmission_filter, sizeof m->transmission_filter);
    p[PARAM_FAMILY] = (float)m->bsdf;
    p[PARAM_ROUGHNESS] = m->roughness;
    p[PARAM_METALLIC] = m->metallic;
    p[PARAM_COAT] = m->coat;
    p[PARAM_COAT_ROUGHNESS] = m->coat_roughness;
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

/* Puts the texture into slot: the file at path, or with an image (not NULL) that image's bytes,
 * path then its name. */
static bool add_texture(vkrt_scene_materials *out, vkrt_scene_material *mat, uint32_t slot,
                        const char *path, const vkrt_image_blob *image, vkrt_texture_usage usage,
                        const char *referrer, vkrt_error *err)
{
    uint32_t index;
    bool added = image ? vkrt_texture_set_add_memory(&out->textures, image->bytes, image->size,
                                                     path, usage, referrer, &index, err)
                       : vkrt_texture_set_add(&out->textures, path, usage, referrer, &index, err);
    if (!added)
        return false;
    mat->textures[slot] = index;
    if (slot + 1 > mat->texture_count)
        mat->texture_count = slot + 1;
    out->reads_texcoords = true;
    return true;
}

/* The TextureInfo flag of a wrap mode. */
static uint32_t wrap_flag(vkrt_wrap wrap)
{
    return wrap == VKRT_WRAP_CLAMP    ? VKRT_TEXTURE_CLAMP
           : wrap == VKRT_WRAP_MIRROR ? VKRT_TEXTURE_MIRROR
                                      : VKRT_TEXTURE_REPEAT;
}

/* Makes the texture in slot read as map (the record's map number map_index) says: its sampler,
 * its uv transform and, for the maps the built-ins read as one number, its channel (a view of
 * the image, texture.h). A map read as repeating, bilinear, untransformed red keeps the image's
 * own entry. */
static bool read_as_map(vkrt_scene_materials *out, vkrt_scene_material *mat, uint32_t slot,
                        const vkrt_texture_ref *t, int map_index, const char *referrer,
                        vkrt_error *err)
{
    bool one_number = map_index == VKRT_MAP_ROUGHNESS || map_index == VKRT_MAP_METALLIC ||
                      map_index == VKRT_MAP_SHEEN;
    if (one_number && t->channel > 3)
        return vkrt_error_set(err, "%s: texture '%s': channel %u; a map has channels 0 to 3",
                              referrer, t->path, t->channel);
    uint32_t flags = VKRT_TEXTURE_WRAP_U(wrap_flag(t->sampler.wrap_u)) |
                     VKRT_TEXTURE_WRAP_V(wrap_flag(t->sampler.wrap_v)) |
                     (t->sampler.filter == VKRT_FILTER_NEAREST ? VKRT_TEXTURE_NEAREST : 0u) |
                     (one_number ? VKRT_TEXTURE_CHANNEL(t->channel) : 0u);
    float matrix[4], offset[2];
    if (!vkrt_texture_uv_transform(t->uv_offset, t->uv_scale, t->uv_rotation, matrix, offset))
        flags |= VKRT_TEXTURE_TRANSFORM;
    if (!vkrt_texture_set_view(&out->textures, mat->textures[slot], flags, matrix, offset,
                               &mat->textures[slot], err))
        return vkrt_error_prefix(err, "%s: texture '%s'", referrer, t->path);
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
        if (!add_texture(out, mat, k, def->textures[k], NULL, VKRT_TEXTURE_COLOUR, referrer, err))
            return false;
    return true;
}

static bool from_record(vkrt_scene_materials *out, vkrt_scene_material *mat,
                        const vkrt_model *model, const vkrt_material *m, vkrt_error *err)
{
    if (!init_material(mat, m->name, m->file, err))
        return false;
    record_params(m, mat->params);
    mark_layers(mat, m->sheen);
    char shader_referrer[1200];
    snprintf(shader_referrer, sizeof shader_referrer, "%s: material '%s'", m->file, m->name);
    if (!find_or_add_shader(out, builtin_of(m), NULL, shader_referrer, &mat->shader, err))
        return false;
    /* Each map in its slot, named by its line for texture errors, in the colour space the record
     * gives it. */
    for (int k = 0; k < VKRT_MAP_COUNT; ++k) {
        const vkrt_texture_ref *t = &m->maps[k];
        if (!t->path)
            continue;
        char referrer[1200];
        snprintf(referrer, sizeof referrer, "%s:%d", m->file, t->line);
        if (t->uv_set != 0)
            return vkrt_error_set(err,
                                  "%s: texture '%s': reads texture coordinates %u; vkrt reads "
                                  "one set (TEXCOORD_0) only",
                                  referrer, t->path, t->uv_set);
        if (t->embedded >= 0 && (uint32_t)t->embedded >= model->image_count)
            return vkrt_error_set(err, "%s: texture '%s': embedded image %d of %u", referrer,
                                  t->path, t->embedded, model->image_count);
        const vkrt_image_blob *image = t->embedded >= 0 ? &model->images[t->embedded] : NULL;
        if (!add_texture(out, mat, slot_of_map[k], t->path, image, t->space, referrer, err) ||
            !read_as_map(out, mat, slot_of_map[k], t, k, referrer, err))
            return false;
    }
    uint32_t detail = mat->textures[VKRT_SLOT_DETAIL];
    if (detail != VKRT_SCENE_NO_TEXTURE &&
        (m->detail_kind == VKRT_DETAIL_NORMAL ||
         (m->detail_kind == VKRT_DETAIL_BY_IMAGE &&
          vkrt_texture_is_normal_map(&out->textures, detail))))
        mat->maps |= VKRT_MATERIAL_NORMAL_MAP;
    else if (detail != VKRT_SCENE_NO_TEXTURE)
        mat->maps |= VKRT_MATERIAL_BUMP_MAP;
    if (m->maps[VKRT_MAP_EMISSION].path)
        mat->maps |= VKRT_MATERIAL_EMISSION_MAP;
    mat->detail_multiplier = m->detail_scale;
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

/* The material file's `environment` entry, which takes the place of scene.cfg's colour; NULL
 * where there is none. */
static const vkrt_material_def *file_environment(const vkrt_material_file *file)
{
    return file ? vkrt_material_file_find(file, "environment") : NULL;
}

bool vkrt_scene_materials_update_environment(vkrt_scene_materials *m, const vkrt_config *cfg,
                                             const vkrt_material_file *file)
{
    if (file_environment(file))
        return false;
    memcpy(m->list[m->environment].params, cfg->environment, sizeof cfg->environment);
    return true;
}

static bool environment_material(vkrt_scene_materials *out, vkrt_scene_material *mat,
                                 const vkrt_config *cfg, const vkrt_material_file *file,
                                 vkrt_error *err)
{
    const vkrt_material_def *def = file_environment(file);
    if (def)
        return from_definition(out, mat, file, def, err);
    if (!init_material(mat, "environment", cfg->path ? cfg->path : "(scene)", err))
        return false;
    memcpy(mat->params, cfg->environment, sizeof cfg->environment);
    return find_or_add_shader(out, "environment", NULL, "(environment)", &mat->shader, err);
}

/* The list index of the material triangle index m names (-1: the default), resolving it into
 * out on first use; used[i] caches record i's (used[count]: the default's), UINT32_MAX before. */
static bool material_for(vkrt_scene_materials *out, const vkrt_model *model,
                         const vkrt_material_file *file, int32_t m, uint32_t *used,
                         uint32_t *index, vkrt_error *err)
{
    if (m >= (int32_t)model->material_count)
        return vkrt_error_set(err, "a triangle names material %d of %u", m,
                              model->material_count);
    uint32_t key = m < 0 ? model->material_count : (uint32_t)m;
    if (used[key] == UINT32_MAX) {
        vkrt_scene_material *mat = &out->list[out->count];
        const vkrt_material *record = m >= 0 ? &model->materials[m] : NULL;
        /* The user-shader escape hatch: a material the material file names by the record's. */
        const vkrt_material_def *def =
            record && file ? vkrt_material_file_find(file, record->name) : NULL;
        bool ok = def      ? from_definition(out, mat, file, def, err)
                  : record ? from_record(out, mat, model, record, err)
                           : default_material(out, mat, err);
        used[key] = out->count++;
        if (!ok)
            return false;
    }
    *index = used[key];
    return true;
}

/* The images the used materials will add, as material_for will add them (a material file's
 * definition taking a record's place), decoded ahead on every core (texture.h). Which records
 * are used comes from the meshes the instances place; a record named out of range is left to
 * material_for to refuse. */
static void decode_textures_ahead(vkrt_scene_materials *out, const vkrt_model *model,
                                  const vkrt_material_file *file)
{
    bool *mesh_used = calloc(model->mesh_count ? model->mesh_count : 1, sizeof *mesh_used);
    bool *used = calloc(model->material_count ? model->material_count : 1, sizeof *used);
    vkrt_texture_source *sources = NULL;
    uint32_t count = 0, room = 0;
    for (uint32_t i = 0; mesh_used && i < model->instance_count; ++i)
        if (model->instances[i].mesh < model->mesh_count)
            mesh_used[model->instances[i].mesh] = true;
    for (uint32_t i = 0; mesh_used && used && i < model->mesh_count; ++i)
        for (uint32_t k = 0; mesh_used[i] && k < model->meshes[i].triangle_count; ++k) {
            int32_t m = model->meshes[i].material[k];
            if (m >= 0 && (uint32_t)m < model->material_count)
                used[m] = true;
        }
    for (uint32_t i = 0; mesh_used && used && i < model->material_count; ++i) {
        if (!used[i])
            continue;
        const vkrt_material *m = &model->materials[i];
        const vkrt_material_def *def = file ? vkrt_material_file_find(file, m->name) : NULL;
        uint32_t n = def ? def->texture_count : VKRT_MAP_COUNT;
        if (count + n > room) {
            room = 2 * (count + n);
            vkrt_texture_source *grown = realloc(sources, room * sizeof *sources);
            if (!grown)
                break;
            sources = grown;
        }
        for (uint32_t k = 0; k < n; ++k) {
            const vkrt_texture_ref *t = def ? NULL : &m->maps[k];
            if (t && !t->path)
                continue;
            bool embedded = t && t->embedded >= 0 && (uint32_t)t->embedded < model->image_count;
            sources[count++] = (vkrt_texture_source){
                .path = def ? def->textures[k] : t->path,
                .bytes = embedded ? model->images[t->embedded].bytes : NULL,
                .size = embedded ? model->images[t->embedded].size : 0,
                .usage = def ? VKRT_TEXTURE_COLOUR : t->space,
            };
        }
    }
    vkrt_texture_set_decode_ahead(&out->textures, sources, count);
    free(sources);
    free(used);
    free(mesh_used);
}

/* Numbers the meshes instances use in the order of their first instances into mesh_first
 * (UINT32_MAX for the others), their triangles' count into *count; false where an instance names
 * a mesh that is not there or the meshes hold more than 32-bit indices address. */
static bool number_meshes(const vkrt_model *model, uint32_t *mesh_first, uint32_t *count,
                          vkrt_error *err)
{
    for (uint32_t m = 0; m < model->mesh_count; ++m)
        mesh_first[m] = UINT32_MAX;
    uint64_t n = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        uint32_t m = model->instances[i].mesh;
        if (m >= model->mesh_count)
            return vkrt_error_set(err, "instance %u names mesh %u of %u", i, m,
                                  model->mesh_count);
        if (mesh_first[m] != UINT32_MAX)
            continue;
        mesh_first[m] = (uint32_t)n;
        n += model->meshes[m].triangle_count;
        if (n >= UINT32_MAX)
            return vkrt_error_set(err, "the instanced meshes hold %llu triangles or more, over "
                                       "32-bit indices",
                                  (unsigned long long)n);
    }
    *count = (uint32_t)n;
    return true;
}

bool vkrt_scene_materials_resolve(const vkrt_config *cfg, const vkrt_model *model,
                                  const vkrt_material_file *file, vkrt_scene_materials *out,
                                  vkrt_error *err)
{
    memset(out, 0, sizeof *out);
    uint32_t count = model->material_count;
    uint32_t *used = malloc((count + 1) * sizeof *used);
    out->mesh_first = malloc((model->mesh_count ? model->mesh_count : 1) *
                             sizeof *out->mesh_first);
    /* The used materials (at most every record and the default), the environment, and one
     * zeroed entry that free may visit after a failure part way. */
    out->list = calloc(count + 3, sizeof *out->list);
    if (!used || !out->mesh_first || !out->list) {
        free(used);
        vkrt_scene_materials_free(out);
        return vkrt_error_set(err, "out of memory for %u materials", count);
    }
    bool ok = number_meshes(model, out->mesh_first, &out->triangle_count, err);
    if (ok) {
        out->triangle_material = malloc((out->triangle_count ? out->triangle_count : 1) *
                                        sizeof *out->triangle_material);
        if (!out->triangle_material)
            ok = vkrt_error_set(err, "out of memory for %u triangles' materials",
                                out->triangle_count);
    }
    for (uint32_t i = 0; i <= count; ++i)
        used[i] = UINT32_MAX;
    if (ok)
        decode_textures_ahead(out, model, file);
    /* Mesh after mesh as their first instances come: the materials are then listed in the order
     * the instanced triangles first use them. */
    size_t t = 0;
    for (uint32_t i = 0; ok && i < model->instance_count; ++i) {
        uint32_t m = model->instances[i].mesh;
        if (out->mesh_first[m] != t)
            continue; /* resolved at an earlier instance (an empty mesh may come again: no-op) */
        const vkrt_mesh *mesh = &model->meshes[m];
        for (uint32_t k = 0; ok && k < mesh->triangle_count; ++k, ++t)
            ok = material_for(out, model, file, mesh->material[k], used,
                              &out->triangle_material[t], err);
    }
    if (ok) {
        out->environment = out->count;
        ok = environment_material(out, &out->list[out->count++], cfg, file, err);
    }
    if (ok)
        vkrt_texture_set_filter(&out->textures, cfg->texture_filter);
    free(used);
    if (!ok)
        vkrt_scene_materials_free(out);
    return ok;
}

bool vkrt_scene_materials_world(const vkrt_scene_materials *m, const vkrt_model *model,
                                const uint32_t **world, uint32_t **owned, vkrt_error *err)
{
    *world = m->triangle_material;
    *owned = NULL;
    if (model->triangle_count == m->triangle_count)
        return true; /* no mesh is placed twice: the orders are the same */
    *owned = malloc((model->triangle_count ? model->triangle_count : 1) * sizeof **owned);
    if (!*owned)
        return vkrt_error_set(err, "out of memory for %u triangles' materials",
                              model->triangle_count);
    size_t t = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        uint32_t mesh = model->instances[i].mesh, k = model->meshes[mesh].triangle_count;
        if (t + k > model->triangle_count) {
            free(*owned);
            *owned = NULL;
            return vkrt_error_set(err, "the model's triangle count is not its instances' "
                                       "(vkrt_model_finish sets it)");
        }
        memcpy(*owned + t, m->triangle_material + m->mesh_first[mesh], k * sizeof **owned);
        t += k;
    }
    *world = *owned;
    return true;
}

void vkrt_scene_materials_free(vkrt_scene_materials *m)
{
    for (uint32_t i = 0; m->list && i < m->count + 1; ++i) {
        free(m->list[i].name);
        free(m->list[i].referrer);
    }
    free(m->list);
    free(m->triangle_material);
    free(m->mesh_first);
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
