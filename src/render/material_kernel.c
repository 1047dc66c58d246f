/* material_kernel.c: generating and compiling the scene's shading code (see material_kernel.h). */
#define _POSIX_C_SOURCE 200809L
#include "material_kernel.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../gpu/shader.h"
#include "kernel_sources.h"

static const char generated_path[] = "generated/materials.glsl";

/* generated/light_stage.glsl, which light.comp includes first: for the path integrator the material
 * module and next-event estimation, which evaluates the materials' BSDFs; for Whitted a nee_at that
 * returns 0, the branch light.comp names but its INTEGRATOR constant never takes there. So the
 * Whitted light kernel carries neither the path tracer's light sampling nor the shaders' code
 * (its stage traces shadow rays and reads no material code), and no pipeline compiles them. */
static const char light_stage_path[] = "generated/light_stage.glsl";
static const char light_stage_for_path[] = "#include \"materials.glsl\"\n#include \"../lib/nee.glsl\"\n";
static const char light_stage_for_whitted[] = "uint nee_at(uint index)\n{\n    return 0u;\n}\n";

typedef struct text {
    char *data;
    size_t length, capacity;
    bool failed;
} text;

static void add(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void add(text *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    for (;;) {
        va_list args;
        va_start(args, fmt);
        int n = vsnprintf(t->data ? t->data + t->length : NULL,
                          t->data ? t->capacity - t->length : 0, fmt, args);
        va_end(args);
        if (n < 0) {
            t->failed = true;
            return;
        }
        if (t->data && t->length + (size_t)n < t->capacity) {
            t->length += (size_t)n;
            return;
        }
        size_t capacity = t->capacity ? t->capacity : 16384;
        while (capacity <= t->length + (size_t)n)
            capacity *= 2;
        char *grown = realloc(t->data, capacity);
        if (!grown) {
            t->failed = true;
            return;
        }
        t->data = grown;
        t->capacity = capacity;
    }
}

/* Does source name one of names[0 .. count - 1] as a whole token? */
static bool mentions(const char *source, const char *const *names, size_t count)
{
    for (size_t i = 0; i < count; ++i)
        for (const char *p = strstr(source, names[i]); p; p = strstr(p + 1, names[i])) {
            char after = p[strlen(names[i])];
            bool start = p == source || !(isalnum((unsigned char)p[-1]) || p[-1] == '_');
            if (start && !(isalnum((unsigned char)after) || after == '_'))
                return true;
        }
    return false;
}

/* Does source call one of the functions that read light samples? A token search: a mention in
 * a comment only costs shadow rays that are not needed, never a wrong picture. */
static bool reads_lights(const char *source)
{
    static const char *const names[] = {"light_sample", "diffuse_light"};
    return mentions(source, names, sizeof names / sizeof *names);
}

/* The shader's name as #line and messages give it: its file, or glsl/materials/NAME.glsl. */
static void shader_display(const vkrt_shader_source *s, char *display, size_t size)
{
    if (s->builtin)
        snprintf(display, size, "glsl/materials/%s.glsl", s->builtin);
    else
        snprintf(display, size, "%s", s->path);
}

/* The shader's display name and its text (malloc'd). */
static char *shader_text(const vkrt_shader_source *s, char *display, size_t size)
{
    shader_display(s, display, size);
    if (s->builtin)
        return vkrt_kernel_source_lookup(NULL, display + strlen("glsl/"));
    return strdup(s->text);
}

/* The line that opens every switch over the shaders: texture reads take the footprint of the
 * surface the material is called for (glsl/lib/texture.glsl, texture_footprint). */
#define FOOTPRINT "    texture_footprint = s.texture_footprint;\n"

/* Whitted's switches over the shaders: the rays a hit casts and its shading. For the path
 * integrator each is its default alone, as add_path_dispatch's are for Whitted: the kernels name
 * them whatever the integrator, but under path they are dead, and leaving the shaders' Whitted
 * code uncalled keeps it out of the kernels the driver compiles. */
static void add_whitted_dispatch(text *t, uint32_t shader_count, uint32_t environment_shader,
                                 bool path)
{
    if (path) {
        add(t, "uint material_count_rays(uint shader, Surface s)\n{\n    return 0u;\n}\n"
               "void material_shade(uint shader, Surface s)\n{\n}\n");
        return;
    }
    add(t, "uint material_count_rays(uint shader, Surface s)\n{\n%s    switch (shader) {\n",
        FOOTPRINT);
    for (uint32_t i = 0; i < shader_count; ++i)
        if (i != environment_shader)
            add(t, "    case %uu: return vkrt_count_rays_%u(s);\n", i, i);
    add(t, "    }\n    return 0u;\n}\n");
    add(t, "void material_shade(uint shader, Surface s)\n{\n%s    switch (shader) {\n", FOOTPRINT);
    for (uint32_t i = 0; i < shader_count; ++i)
        if (i != environment_shader)
            add(t, "    case %uu: vkrt_shade_%u(s); break;\n", i, i);
    add(t, "    }\n}\n");
}

/* The path integrator's switches over the shaders: emitted light, BSDF value and sample. Each
 * calls the shader's renamed function (vkrt_NAME_<shader>) with the same arguments. For Whitted
 * each is its default alone: the kernels name these functions whatever the integrator (the
 * INTEGRATOR specialization constant leaves the calls dead), but Whitted's shaders need not
 * define what they would call. */
static void add_path_dispatch(text *t, uint32_t shader_count, uint32_t environment_shader,
                              bool path, const bool *samples)
{
    static const struct {
        const char *signature, *prologue, *name, *arguments, *otherwise;
    } switches[] = {
        {"vec3 material_emitted(uint shader, Surface s)", "", "emitted", "s", "vec3(0.0)"},
        {"vec3 material_bsdf_eval(uint shader, Surface s, vec3 wi, out float pdf)",
         "    pdf = 0.0;\n", "bsdf_eval", "s, wi, pdf", "vec3(0.0)"},
        {"bool material_bsdf_sample(uint shader, Surface s, out BsdfSample b)",
         "    b.pdf = 0.0;\n", "bsdf_sample", "s, b", "false"},
    };
    for (size_t k = 0; k < sizeof switches / sizeof *switches; ++k) {
        /* Whitted with samples: bsdf_sample's switch over the shaders that define one. */
        bool sample_switch = !path && samples && k == 2;
        if (!path && !sample_switch) {
            add(t, "%s\n{\n%s    return %s;\n}\n", switches[k].signature, switches[k].prologue,
                switches[k].otherwise);
            continue;
        }
        add(t, "%s\n{\n%s%s    switch (shader) {\n", switches[k].signature, switches[k].prologue,
            FOOTPRINT);
        for (uint32_t i = 0; i < shader_count; ++i)
            if (i != environment_shader && (!sample_switch || samples[i]))
                add(t, "    case %uu: return vkrt_%s_%u(%s);\n", i, switches[k].name, i,
                    switches[k].arguments);
        add(t, "    }\n    return %s;\n}\n", switches[k].otherwise);
    }
}

bool vkrt_material_kernel_create(vkrt_material_kernel *k, const vkrt_scene_materials *materials,
                                 bool float_atomics, bool path, vkrt_error *err)
{
    return vkrt_material_kernel_create_sampling(k, materials, float_atomics, path, false, err);
}

bool vkrt_material_kernel_create_sampling(vkrt_material_kernel *k,
                                          const vkrt_scene_materials *materials,
                                          bool float_atomics, bool path, bool whitted_samples,
                                          vkrt_error *err)
{
    memset(k, 0, sizeof *k);
    k->shader_count = materials->shader_count;
    k->shader_uses_lights = calloc(materials->shader_count + 1, sizeof *k->shader_uses_lights);
    /* Per shader: it defines bsdf_sample (Whitted with samples only). */
    bool *samples = whitted_samples && !path ? calloc(materials->shader_count + 1, sizeof *samples)
                                             : NULL;
    if (!k->shader_uses_lights || (whitted_samples && !path && !samples)) {
        free(samples);
        vkrt_material_kernel_destroy(k);
        return vkrt_error_set(err, "out of memory");
    }
    text t = {0};
    add(&t, "/* Generated by src/render/material_kernel.c for this scene's %u shaders. */\n",
        materials->shader_count);
    if (float_atomics)
        add(&t, "#extension GL_EXT_shader_atomic_float : require\n#define VKRT_FLOAT_ATOMICS 1\n");
    add(&t, "#include \"../lib/material_api.glsl\"\n#include \"../lib/mtl.glsl\"\n"
            "#include \"../lib/microfacet.glsl\"\n");
    add(&t, "#define VKRT_ENVIRONMENT_MATERIAL %uu\n", materials->environment);
    uint32_t environment_shader = materials->list[materials->environment].shader;
    int line = 6;
    for (uint32_t i = 0; i < materials->shader_count; ++i) {
        char display[1200];
        char *source = shader_text(&materials->shaders[i], display, sizeof display);
        if (!source) {
            free(samples);
            free(t.data);
            vkrt_material_kernel_destroy(k);
            return vkrt_error_set(err, "%s: no built-in shader '%s'", materials->shaders[i].referrer,
                                  display);
        }
        if (strchr(display, '"')) {
            free(source);
            free(samples);
            free(t.data);
            vkrt_material_kernel_destroy(k);
            return vkrt_error_set(err, "%s: shader path '%s' has a '\"' in it",
                                  materials->shaders[i].referrer, display);
        }
        k->shader_uses_lights[i] = reads_lights(source);
        if (samples)
            samples[i] = mentions(source, (const char *const[]){"bsdf_sample"}, 1);
        const char *kind = i == environment_shader ? "environment" : NULL;
        if (kind)
            add(&t, "#define environment vkrt_environment_%u\n", i);
        else
            add(&t, "#define count_rays vkrt_count_rays_%u\n#define shade vkrt_shade_%u\n"
                    "#define emitted vkrt_emitted_%u\n#define bsdf_eval vkrt_bsdf_eval_%u\n"
                    "#define bsdf_sample vkrt_bsdf_sample_%u\n",
                i, i, i, i, i);
        add(&t, "#line 1 \"%s\"\n%s\n", display, source);
        free(source);
        add(&t, "#line %d \"glsl/%s\"\n", line, generated_path);
        if (kind)
            add(&t, "#undef environment\n");
        else
            add(&t, "#undef count_rays\n#undef shade\n#undef emitted\n#undef bsdf_eval\n"
                    "#undef bsdf_sample\n");
    }
    add_whitted_dispatch(&t, materials->shader_count, environment_shader, path);
    add_path_dispatch(&t, materials->shader_count, environment_shader, path, samples);
    free(samples);
    add(&t, "vec3 material_environment(vec3 direction, vec4 payload)\n{\n"
            "    return vkrt_environment_%u(direction, payload);\n}\n",
        environment_shader);
    if (t.failed) {
        free(t.data);
        vkrt_material_kernel_destroy(k);
        return vkrt_error_set(err, "out of memory generating the material kernel");
    }
    k->text = t.data;
    k->path = path;
    return true;
}

static char *lookup(void *user, const char *path)
{
    const vkrt_material_kernel *k = user;
    if (strcmp(path, generated_path) == 0)
        return strdup(k->text);
    if (strcmp(path, light_stage_path) == 0)
        return strdup(k->path ? light_stage_for_path : light_stage_for_whitted);
    return vkrt_kernel_source_lookup(NULL, path);
}

bool vkrt_material_kernel_compile(const vkrt_material_kernel *k,
                                  const vkrt_scene_materials *materials, const char *kernel,
                                  const char *preamble, uint32_t **spirv, size_t *words,
                                  vkrt_error *err)
{
    gpu_shader_sources sources = {
        .lookup = lookup, .user = (void *)k, .display_prefix = "glsl/", .preamble = preamble};
    if (gpu_shader_compile(&sources, kernel, spirv, words, err))
        return true;
    /* A shader that lacks an entry point (or gives it the wrong parameters) fails where the
     * generated switch calls it, under the renamed name: say which shader and what it lacks. */
    static const struct {
        const char *renamed, *wanted;
    } entries[] = {
        {"vkrt_count_rays_", "uint count_rays(Surface s)"},
        {"vkrt_shade_", "void shade(Surface s)"},
        {"vkrt_environment_", "vec3 environment(vec3 direction, vec4 payload)"},
        {"vkrt_emitted_", "vec3 emitted(Surface s), which the path integrator needs"},
        {"vkrt_bsdf_eval_",
         "vec3 bsdf_eval(Surface s, vec3 wi, out float pdf), which the path integrator needs"},
        {"vkrt_bsdf_sample_",
         "bool bsdf_sample(Surface s, out BsdfSample b), which the path integrator needs"},
    };
    for (size_t e = 0; e < sizeof entries / sizeof *entries; ++e) {
        const char *at = strstr(err->msg, entries[e].renamed);
        unsigned shader;
        if (at && sscanf(at + strlen(entries[e].renamed), "%u", &shader) == 1 &&
            shader < materials->shader_count) {
            const vkrt_shader_source *s = &materials->shaders[shader];
            char display[1200];
            shader_display(s, display, sizeof display);
            return vkrt_error_set(err, "%s: %s does not define %s (docs/materials.md)",
                                  s->referrer, display, entries[e].wanted);
        }
    }
    /* Blame the material whose shader the first error is in. */
    for (uint32_t i = 0; i < materials->shader_count; ++i) {
        const vkrt_shader_source *s = &materials->shaders[i];
        char display[1200];
        shader_display(s, display, sizeof display - 1);
        strcat(display, ":");
        if (strstr(err->msg, display))
            return vkrt_error_prefix(err, "%s: shader does not compile", s->referrer);
    }
    return vkrt_error_prefix(err, "%s", kernel);
}

void vkrt_material_kernel_destroy(vkrt_material_kernel *k)
{
    free(k->text);
    free(k->shader_uses_lights);
    memset(k, 0, sizeof *k);
}
