/*
 * shader.c: include expansion and glslang compilation (see shader.h).
 *
 * glslang 12's C interface has no include callback, so includes are expanded here, before the
 * text reaches glslang. GL_GOOGLE_cpp_style_line_directive lets `#line N "file"` carry file
 * names into glslang's messages.
 */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include "shader.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>

#include "spirv_cache.h"

/* Deep enough for any real include chain; stops an include cycle without guards. */
static const int max_include_depth = 16;

typedef struct text_buffer {
    char *data;
    size_t length, capacity;
} text_buffer;

static bool text_append(text_buffer *t, const char *s, size_t n)
{
    if (t->length + n + 1 > t->capacity) {
        size_t capacity = t->capacity ? t->capacity : 4096;
        while (t->length + n + 1 > capacity)
            capacity *= 2;
        char *grown = realloc(t->data, capacity);
        if (!grown)
            return false;
        t->data = grown;
        t->capacity = capacity;
    }
    memcpy(t->data + t->length, s, n);
    t->length += n;
    t->data[t->length] = '\0';
    return true;
}

static bool text_printf(text_buffer *t, const char *fmt, const char *a, int n)
{
    char line[1200];
    int len = snprintf(line, sizeof line, fmt, n, a);
    return len > 0 && (size_t)len < sizeof line && text_append(t, line, (size_t)len);
}

/* Joins the folder of `from` with `name` and removes "." and ".." parts. False if the result
 * would leave the source tree. */
static bool resolve_include(const char *from, const char *name, char *out, size_t out_size)
{
    char joined[1024];
    const char *slash = strrchr(from, '/');
    int folder = slash ? (int)(slash - from + 1) : 0;
    if (snprintf(joined, sizeof joined, "%.*s%s", folder, from, name) >= (int)sizeof joined)
        return false;
    char *parts[64], *rest;
    int count = 0;
    /* strtok_r: kernels are expanded on several threads at once (render/renderer_kernels.c). */
    for (char *part = strtok_r(joined, "/", &rest); part; part = strtok_r(NULL, "/", &rest)) {
        if (strcmp(part, ".") == 0)
            continue;
        if (strcmp(part, "..") == 0) {
            if (count == 0)
                return false;
            --count;
            continue;
        }
        if (count == 64)
            return false;
        parts[count++] = part;
    }
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < count; ++i) {
        int n = snprintf(out + used, out_size - used, "%s%s", i ? "/" : "", parts[i]);
        if (n < 0 || (size_t)n >= out_size - used)
            return false;
        used += (size_t)n;
    }
    return count > 0;
}

/* If line is `#include "name"`, copies name into out and returns true. */
static bool parse_include(const char *line, size_t length, char *out, size_t out_size)
{
    const char *p = line, *end = line + length;
    while (p < end && isspace((unsigned char)*p))
        ++p;
    if (p == end || *p != '#')
        return false;
    ++p;
    while (p < end && isspace((unsigned char)*p))
        ++p;
    if ((size_t)(end - p) < 7 || strncmp(p, "include", 7) != 0)
        return false;
    p += 7;
    while (p < end && isspace((unsigned char)*p))
        ++p;
    if (p == end || *p != '"')
        return false;
    const char *close = memchr(p + 1, '"', (size_t)(end - p - 1));
    if (!close || (size_t)(close - p - 1) >= out_size)
        return false;
    memcpy(out, p + 1, (size_t)(close - p - 1));
    out[close - p - 1] = '\0';
    return true;
}

static bool expand(const gpu_shader_sources *sources, const char *path, int depth,
                   text_buffer *out, vkrt_error *err)
{
    const char *prefix = sources->display_prefix ? sources->display_prefix : "";
    if (depth > max_include_depth)
        return vkrt_error_set(err, "%s%s: includes nest deeper than %d (a cycle?)", prefix, path,
                              max_include_depth);
    char *source = sources->lookup(sources->user, path);
    if (!source)
        return vkrt_error_set(err, "%s%s: no such shader source", prefix, path);
    char display[1100];
    snprintf(display, sizeof display, "%s%s", prefix, path);
    bool ok = text_printf(out, "#line %d \"%s\"\n", display, 1);
    int line_number = 1;
    for (const char *line = source; ok && *line; ++line_number) {
        const char *newline = strchr(line, '\n');
        size_t length = newline ? (size_t)(newline - line) : strlen(line);
        char name[512], resolved[1024];
        if (parse_include(line, length, name, sizeof name)) {
            if (!resolve_include(path, name, resolved, sizeof resolved)) {
                vkrt_error_set(err, "%s:%d: cannot resolve include \"%s\"", display, line_number,
                               name);
                ok = false;
                break;
            }
            if (!expand(sources, resolved, depth + 1, out, err)) {
                if (strstr(err->msg, "no such shader source") && depth >= 0)
                    vkrt_error_set(err, "%s:%d: included file \"%s\" not found", display,
                                   line_number, name);
                ok = false;
                break;
            }
            ok = text_printf(out, "#line %d \"%s\"\n", display, line_number + 1);
        } else {
            ok = text_append(out, line, length) && text_append(out, "\n", 1);
        }
        line = newline ? newline + 1 : line + length;
    }
    free(source);
    if (!ok && err && err->msg[0] == '\0')
        vkrt_error_set(err, "out of memory expanding %s", display);
    return ok;
}

bool gpu_shader_expand(const gpu_shader_sources *sources, const char *path, char **text,
                       vkrt_error *err)
{
    text_buffer out = {0};
    if (err)
        err->msg[0] = '\0';
    if (!expand(sources, path, 0, &out, err)) {
        free(out.data);
        *text = NULL;
        return false;
    }
    *text = out.data;
    return true;
}

/* Keeps the first few "ERROR: " lines of a glslang log, without the prefix, joined by "; ". */
static void first_errors(const char *log, char *out, size_t out_size)
{
    static const int max_errors = 3;
    int found = 0;
    size_t used = 0;
    out[0] = '\0';
    for (const char *line = log; line && *line && found < max_errors;) {
        const char *newline = strchr(line, '\n');
        size_t length = newline ? (size_t)(newline - line) : strlen(line);
        /* The summary line ("ERROR: 1 compilation errors.") says nothing: skip it. Searched in
         * a copy of this line alone, or a later line's summary would hide this one. */
        char text[512];
        snprintf(text, sizeof text, "%.*s", (int)length, line);
        if (length > 7 && strncmp(line, "ERROR: ", 7) == 0 && !strstr(text, "compilation error")) {
            int n = snprintf(out + used, out_size - used, "%s%.*s", found ? "; " : "",
                             (int)(length - 7), line + 7);
            if (n < 0 || (size_t)n >= out_size - used)
                break;
            used += (size_t)n;
            ++found;
        }
        line = newline ? newline + 1 : NULL;
    }
    if (!found)
        snprintf(out, out_size, "%s", log && *log ? log : "unknown glslang error");
}

bool gpu_shader_compile(const gpu_shader_sources *sources, const char *path, uint32_t **spirv,
                        size_t *word_count, vkrt_error *err)
{
    return gpu_shader_compile_stage(sources, path, GPU_SHADER_COMPUTE, spirv, word_count, err);
}

bool gpu_shader_compile_stage(const gpu_shader_sources *sources, const char *path,
                              gpu_shader_stage stage, uint32_t **spirv, size_t *word_count,
                              vkrt_error *err)
{
    static const glslang_stage_t glslang_stages[] = {
        [GPU_SHADER_COMPUTE] = GLSLANG_STAGE_COMPUTE,
        [GPU_SHADER_RAYGEN] = GLSLANG_STAGE_RAYGEN,
        [GPU_SHADER_MISS] = GLSLANG_STAGE_MISS,
        [GPU_SHADER_CLOSEST_HIT] = GLSLANG_STAGE_CLOSESTHIT,
    };
    *spirv = NULL;
    *word_count = 0;
    if ((unsigned)stage >= sizeof glslang_stages / sizeof *glslang_stages)
        return vkrt_error_set(err, "%s: unknown shader stage %d", path, (int)stage);
    glslang_stage_t glslang_stage = glslang_stages[stage];
    /* GL_EXT_ray_tracing's SPIR-V (SPV_KHR_ray_tracing) needs SPIR-V 1.4; compute stays at 1.3,
     * what every Vulkan 1.1 device takes. */
    glslang_target_language_version_t spirv_version =
        stage == GPU_SHADER_COMPUTE ? GLSLANG_TARGET_SPV_1_3 : GLSLANG_TARGET_SPV_1_4;
    char *body;
    if (!gpu_shader_expand(sources, path, &body, err))
        return false;
    static const char header[] = "#version 460\n"
                                 "#extension GL_GOOGLE_cpp_style_line_directive : require\n"
                                 "#define VKRT_GLSL 1\n";
    text_buffer code = {0};
    const char *preamble = sources->preamble ? sources->preamble : "";
    bool ok = text_append(&code, header, sizeof header - 1) &&
              text_append(&code, preamble, strlen(preamble)) &&
              text_append(&code, body, strlen(body));
    free(body);
    if (!ok) {
        free(code.data);
        return vkrt_error_set(err, "out of memory compiling %s", path);
    }

    /* A kernel compiled before from the same text is on disk (spirv_cache.h). */
    gpu_spirv_key key = gpu_spirv_key_of(code.data, (uint32_t)stage << 16 | (uint32_t)spirv_version);
    if (gpu_spirv_cache_load(&key, spirv, word_count)) {
        free(code.data);
        return true;
    }

    glslang_input_t input = {
        .language = GLSLANG_SOURCE_GLSL,
        .stage = glslang_stage,
        .client = GLSLANG_CLIENT_VULKAN,
        .client_version = GLSLANG_TARGET_VULKAN_1_1,
        .target_language = GLSLANG_TARGET_SPV,
        .target_language_version = spirv_version,
        .code = code.data,
        .default_version = 460,
        .default_profile = GLSLANG_NO_PROFILE,
        .messages = GLSLANG_MSG_DEFAULT_BIT | GLSLANG_MSG_SPV_RULES_BIT |
                    GLSLANG_MSG_VULKAN_RULES_BIT,
        .resource = glslang_default_resource(),
    };
    /* Reference counted inside glslang, so pairing it with finalize per compile is safe. */
    glslang_initialize_process();
    glslang_shader_t *shader = glslang_shader_create(&input);
    glslang_program_t *program = NULL;
    char errors[900];
    ok = false;
    if (!shader) {
        vkrt_error_set(err, "glslang could not create a shader for %s", path);
        goto done;
    }
    if (!glslang_shader_preprocess(shader, &input) || !glslang_shader_parse(shader, &input)) {
        first_errors(glslang_shader_get_info_log(shader), errors, sizeof errors);
        vkrt_error_set(err, "%s", errors);
        goto done;
    }
    program = glslang_program_create();
    glslang_program_add_shader(program, shader);
    if (!glslang_program_link(program, GLSLANG_MSG_SPV_RULES_BIT | GLSLANG_MSG_VULKAN_RULES_BIT)) {
        first_errors(glslang_program_get_info_log(program), errors, sizeof errors);
        vkrt_error_set(err, "%s: link: %s", path, errors);
        goto done;
    }
    glslang_program_SPIRV_generate(program, glslang_stage);
    size_t words = glslang_program_SPIRV_get_size(program);
    *spirv = malloc(words * sizeof **spirv);
    if (!*spirv) {
        vkrt_error_set(err, "out of memory compiling %s", path);
        goto done;
    }
    glslang_program_SPIRV_get(program, *spirv);
    *word_count = words;
    gpu_spirv_cache_count_compiled();
    gpu_spirv_cache_store(&key, *spirv, words);
    ok = true;
done:
    if (program)
        glslang_program_delete(program);
    if (shader)
        glslang_shader_delete(shader);
    glslang_finalize_process();
    free(code.data);
    return ok;
}
