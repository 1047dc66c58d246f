/*
 * test_spirv_cache.c: compiled kernels kept on disk (src/gpu/spirv_cache.h), through the path
 * every kernel takes (gpu_shader_compile). No device needed.
 *
 * What must hold: a second compile of the same text gives the same words as glslang did and
 * comes from the cache, not from glslang (a file planted under the key is what comes back); a
 * changed text is another kernel; a damaged or truncated file is a miss and is written anew; an
 * unusable directory or VKRT_CACHE_DIR="" only means compiling every time.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "gpu/pipeline.h"
#include "gpu/shader.h"
#include "gpu/spirv_cache.h"
#include "temp_dir.h"

/* The one source this test compiles; `value` changes its text. */
static int value = 1;

static char *lookup(void *user, const char *path)
{
    (void)user;
    if (strcmp(path, "k.comp") != 0)
        return NULL;
    char *text = malloc(256);
    snprintf(text, 256,
             "layout(local_size_x = 1) in;\n"
             "layout(std430, binding = 0) buffer B { uint data[]; };\n"
             "void main() { data[gl_GlobalInvocationID.x] = %du; }\n",
             value);
    return text;
}

static const gpu_shader_sources sources = {.lookup = lookup};

static void compile(uint32_t **words, size_t *count)
{
    vkrt_error err = {{0}};
    bool ok = gpu_shader_compile(&sources, "k.comp", words, count, &err);
    if (!ok)
        print_error("compile failed: %s\n", err.msg);
    assert_true(ok);
    assert_true(*count > 5);
}

/* The number of files in dir (0 if it does not exist). */
static int files_in(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

/* The one .spv file in dir, into path. */
static void the_file(const char *dir, char *path, size_t size)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    path[0] = '\0';
    for (struct dirent *e; (e = readdir(d));)
        if (strstr(e->d_name, ".spv"))
            snprintf(path, size, "%s/%s", dir, e->d_name);
    closedir(d);
    assert_true(path[0] != '\0');
}

static void counts(uint32_t *loaded, uint32_t *compiled)
{
    uint32_t stored;
    gpu_spirv_cache_counts(loaded, compiled, &stored);
}

static void hit_gives_the_same_words_without_glslang(void **state)
{
    temp_dir *fx = *state;
    char dir[600];
    snprintf(dir, sizeof dir, "%s/nested/cache", fx->dir); /* made on the first store */
    setenv("VKRT_CACHE_DIR", dir, 1);
    value = 1;
    uint32_t loaded0, compiled0, loaded, compiled;
    counts(&loaded0, &compiled0);

    uint32_t *first, *second;
    size_t n1, n2;
    compile(&first, &n1);
    counts(&loaded, &compiled);
    assert_int_equal(compiled, compiled0 + 1);
    assert_int_equal(loaded, loaded0);
    assert_int_equal(files_in(dir), 1);

    compile(&second, &n2);
    counts(&loaded, &compiled);
    assert_int_equal(compiled, compiled0 + 1);
    assert_int_equal(loaded, loaded0 + 1);
    assert_int_equal(n1, n2);
    assert_memory_equal(first, second, n1 * sizeof *first);
    free(second);

    /* The words come from the file: store other words under the same key (read from the file's
     * header) through the module's own writer, and they are what the next compile returns. */
    char path[800];
    the_file(dir, path, sizeof path);
    uint32_t *planted = malloc(n1 * sizeof *planted);
    memcpy(planted, first, n1 * sizeof *planted);
    planted[3] ^= 0x5A5A5A5Au; /* the bound: an ignorable header word here, but different */
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    uint64_t header[4];
    assert_int_equal(fread(header, sizeof header, 1, f), 1);
    fclose(f);
    gpu_spirv_key key = {{header[1], header[2]}};
    gpu_spirv_cache_store(&key, planted, n1);
    compile(&second, &n2);
    assert_int_equal(second[3], planted[3]);
    free(second);
    free(planted);

    /* Another text is another kernel, with a file of its own. */
    value = 2;
    compile(&second, &n2);
    assert_int_equal(files_in(dir), 2);
    free(second);
    free(first);
}

static void damaged_files_are_misses(void **state)
{
    temp_dir *fx = *state;
    setenv("VKRT_CACHE_DIR", fx->dir, 1);
    value = 3;
    uint32_t *good, *again;
    size_t n, m;
    compile(&good, &n);
    char path[800];
    the_file(fx->dir, path, sizeof path);

    /* Cut short, then one byte of the module flipped, then not a cache file at all: each time
     * the kernel is compiled again, the same as glslang makes it, and the file written anew. */
    for (int damage = 0; damage < 3; ++damage) {
        FILE *f = fopen(path, "r+b");
        assert_non_null(f);
        if (damage == 0) {
            fclose(f);
            assert_int_equal(truncate(path, 40 + 4 * (long)n / 2), 0);
        } else if (damage == 1) {
            fseek(f, 32 + 4 * 7, SEEK_SET);
            int c = fgetc(f);
            fseek(f, 32 + 4 * 7, SEEK_SET);
            fputc(c ^ 0x10, f);
            fclose(f);
        } else {
            fputs("not a kernel", f);
            fclose(f);
        }
        uint32_t loaded0, compiled0, loaded, compiled;
        counts(&loaded0, &compiled0);
        compile(&again, &m);
        counts(&loaded, &compiled);
        assert_int_equal(compiled, compiled0 + 1);
        assert_int_equal(loaded, loaded0);
        assert_int_equal(m, n);
        assert_memory_equal(again, good, n * sizeof *good);
        free(again);
        compile(&again, &m); /* the rewritten file is whole again */
        counts(&loaded, &compiled);
        assert_int_equal(loaded, loaded0 + 1);
        free(again);
    }
    free(good);
}

static void no_cache_still_compiles(void **state)
{
    temp_dir *fx = *state;
    value = 4;
    uint32_t *words;
    size_t n;
    /* A directory that cannot be made: under a regular file. */
    const char *file = temp_dir_write(fx, "plain", "x", 1);
    char dir[600];
    snprintf(dir, sizeof dir, "%s/cache", file);
    setenv("VKRT_CACHE_DIR", dir, 1);
    uint32_t loaded, compiled, stored, stored_before;
    gpu_spirv_cache_counts(&loaded, &compiled, &stored_before);
    compile(&words, &n);
    /* Nothing was stored, and nothing says so (--verbose reports these counts). */
    gpu_spirv_cache_counts(&loaded, &compiled, &stored);
    assert_int_equal(stored, stored_before);
    gpu_spirv_key key = gpu_spirv_key_of("k", 1);
    assert_false(gpu_spirv_cache_store(&key, words, n));
    assert_false(gpu_spirv_cache_store_bytes(&key, words, n * sizeof *words));
    /* The cache directory is a file itself. */
    setenv("VKRT_CACHE_DIR", file, 1);
    assert_false(gpu_spirv_cache_store(&key, words, n));
    assert_false(gpu_spirv_cache_store_bytes(&key, words, n * sizeof *words));
    free(words);
    /* Switched off. */
    setenv("VKRT_CACHE_DIR", "", 1);
    char out[64];
    assert_false(gpu_spirv_cache_dir(out, sizeof out));
    compile(&words, &n);
    free(words);
    assert_int_equal(files_in(fx->dir), 1); /* only "plain" */
}

/* Without VKRT_CACHE_DIR: XDG_CACHE_HOME/vkrt, else HOME/.cache/vkrt. */
static void the_directory_follows_xdg(void **state)
{
    (void)state;
    char dir[256];
    unsetenv("VKRT_CACHE_DIR");
    setenv("XDG_CACHE_HOME", "/x/cache", 1);
    assert_true(gpu_spirv_cache_dir(dir, sizeof dir));
    assert_string_equal(dir, "/x/cache/vkrt");
    unsetenv("XDG_CACHE_HOME");
    setenv("HOME", "/home/u", 1);
    assert_true(gpu_spirv_cache_dir(dir, sizeof dir));
    assert_string_equal(dir, "/home/u/.cache/vkrt");
}

/* The driver's pipeline cache data (pipeline.c): kept whole and handed back only when whole;
 * the Vulkan header is checked against the device before the driver sees the data. */
static void pipeline_cache_entries_are_checked(void **state)
{
    temp_dir *fx = *state;
    setenv("VKRT_CACHE_DIR", fx->dir, 1);
    VkPhysicalDeviceProperties props = {.vendorID = 0x10DE, .deviceID = 0x2335};
    for (unsigned i = 0; i < VK_UUID_SIZE; ++i)
        props.pipelineCacheUUID[i] = (uint8_t)(3 * i + 1);
    unsigned char data[100];
    for (size_t i = 0; i < sizeof data; ++i)
        data[i] = (unsigned char)(i * 7);
    VkPipelineCacheHeaderVersionOne h = {.headerSize = 32,
                                         .headerVersion = VK_PIPELINE_CACHE_HEADER_VERSION_ONE,
                                         .vendorID = props.vendorID,
                                         .deviceID = props.deviceID};
    memcpy(h.pipelineCacheUUID, props.pipelineCacheUUID, VK_UUID_SIZE);
    memcpy(data, &h, sizeof h);
    assert_true(gpu_pipeline_cache_header_ok(data, sizeof data, &props));
    assert_false(gpu_pipeline_cache_header_ok(data, 31, &props)); /* shorter than a header */
    props.driverVersion++; /* not in the header: the key has it */
    assert_true(gpu_pipeline_cache_header_ok(data, sizeof data, &props));
    props.pipelineCacheUUID[5] ^= 1; /* another driver build */
    assert_false(gpu_pipeline_cache_header_ok(data, sizeof data, &props));
    props.pipelineCacheUUID[5] ^= 1;
    props.deviceID++;
    assert_false(gpu_pipeline_cache_header_ok(data, sizeof data, &props));
    props.deviceID--;
    data[4] = 2; /* header version */
    assert_false(gpu_pipeline_cache_header_ok(data, sizeof data, &props));
    data[4] = 1;

    gpu_spirv_key key = gpu_spirv_key_of_bytes("a pipeline", 10);
    gpu_spirv_cache_store_bytes(&key, data, sizeof data);
    void *back;
    size_t size;
    assert_true(gpu_spirv_cache_load_bytes(&key, &back, &size));
    assert_int_equal(size, sizeof data);
    assert_memory_equal(back, data, sizeof data);
    free(back);
    gpu_spirv_key other = gpu_spirv_key_of_bytes("a pipeline!", 11);
    assert_false(gpu_spirv_cache_load_bytes(&other, &back, &size));
    char path[800];
    snprintf(path, sizeof path, "%s/%016llx%016llx.vkpc", fx->dir, (unsigned long long)key.h[0],
             (unsigned long long)key.h[1]);
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    fseek(f, 32 + 50, SEEK_SET); /* one byte of the data flipped */
    fputc(data[50] ^ 0x40, f);
    fclose(f);
    assert_false(gpu_spirv_cache_load_bytes(&key, &back, &size));
    assert_null(back);
    gpu_spirv_cache_store_bytes(&key, data, sizeof data);
    assert_int_equal(truncate(path, 32 + 60), 0); /* cut short */
    assert_false(gpu_spirv_cache_load_bytes(&key, &back, &size));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(hit_gives_the_same_words_without_glslang),
        temp_dir_test(damaged_files_are_misses),
        temp_dir_test(no_cache_still_compiles),
        cmocka_unit_test(the_directory_follows_xdg),
        temp_dir_test(pipeline_cache_entries_are_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
