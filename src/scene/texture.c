/*
 * texture.c: decoding images into the texel buffer (see texture.h), and the CPU reference of the
 * kernels' sampling (glsl/lib/texture.glsl).
 *
 * stb_image's implementation comes from Debian's libstb (dependency('stb') links -lstb), so no
 * file of vkrt defines STB_IMAGE_IMPLEMENTATION: a second copy would clash with the library's.
 *
 * A texture is checked as far as possible before it is decoded: the header gives the size, so an
 * absurd image or one that would overflow the buffer is refused without allocating for it. It is
 * then decoded straight into room reserved at the end of the texel array, and only counted (count,
 * texel_words) once everything has succeeded: a failed add leaves the set's contents as they were
 * and gives the room back (the arrays may have moved).
 */
#define _XOPEN_SOURCE 700 /* realpath, strdup */

#include "texture.h"
#include "texture_file.h"
#include "texture_levels.h"

#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <pthread.h>
#include <stdatomic.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb_image.h>

#include "../../glsl/shared.h"

static_assert(sizeof(vkrt_texture_info) == sizeof(TextureInfo),
              "vkrt_texture_info must match TextureInfo");
#define SAME_FIELD(f)                                                                          \
    static_assert(offsetof(vkrt_texture_info, f) == offsetof(TextureInfo, f), "TextureInfo." #f)
SAME_FIELD(offset); SAME_FIELD(width); SAME_FIELD(height); SAME_FIELD(flags);
SAME_FIELD(uv_matrix); SAME_FIELD(uv_offset);
#undef SAME_FIELD

/* The flags that say how a map reads its image rather than what the image is. */
#define VIEW_FLAGS                                                                                \
    (VKRT_TEXTURE_WRAP_U(3u) | VKRT_TEXTURE_WRAP_V(3u) | VKRT_TEXTURE_NEAREST |                 \
     VKRT_TEXTURE_TRANSFORM | VKRT_TEXTURE_CHANNEL(3u))

/* Offsets into the texel buffer are 32-bit uints on the GPU. */
#define MAX_TEXEL_WORDS ((size_t)UINT32_MAX)

#define MIB (1024.0 * 1024.0)

/* ---------------------------------------------------------------------------------------------
 * Messages
 * ------------------------------------------------------------------------------------------- */

/* "<referrer>: texture '<path>': <reason>", the referrer left out when there is none. */
#define fail(err, referrer, path, ...) \
    vkrt_error_set_file(err, referrer, "texture", path, __VA_ARGS__)

/* ---------------------------------------------------------------------------------------------
 * Texel formats
 * ------------------------------------------------------------------------------------------- */

/* 8-bit RGBA (as stbi_load returns with 4 channels) into one uint per texel, r in the low byte
 * (what unpackUnorm4x8 reads). For coverage, the chosen channel goes to all four. */
/* Whether every texel of decoded RGBA pixels (floats when hdr, else bytes) has full alpha. */
static bool opaque(const void *pixels, size_t texels, bool hdr)
{
    for (size_t i = 0; i < texels; i++)
        if (hdr ? ((const float *)pixels)[4 * i + 3] != 1.0f
                : ((const unsigned char *)pixels)[4 * i + 3] != 255)
            return false;
    return true;
}

static void pack_rgba8(const unsigned char *px, size_t texels, int alpha_channel, uint32_t *out)
{
    for (size_t i = 0; i < texels; i++, px += 4) {
        if (alpha_channel >= 0)
            out[i] = px[alpha_channel] * 0x01010101u;
        else
            out[i] = (uint32_t)px[0] | (uint32_t)px[1] << 8 | (uint32_t)px[2] << 16 |
                     (uint32_t)px[3] << 24;
    }
}

/* Float RGBA into two uints per texel: r, g in the first (low, high half) and b, a in the second,
 * what unpackHalf2x16 reads. */
static void pack_rgba16f(const float *px, size_t texels, int alpha_channel, uint32_t *out)
{
    for (size_t i = 0; i < texels; i++, px += 4) {
        uint32_t c[4];
        for (int k = 0; k < 4; k++)
            c[k] = vkrt_half_from_float(px[alpha_channel >= 0 ? alpha_channel : k]);
        out[2 * i] = c[0] | c[1] << 16;
        out[2 * i + 1] = c[2] | c[3] << 16;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Adding a texture
 * ------------------------------------------------------------------------------------------- */

static bool reserve(void **array, size_t count, size_t size)
{
    void *p = realloc(*array, count * size);
    if (!p)
        return false;
    *array = p;
    return true;
}

/* Grows every array of the set for one more texture of word_count texel words. What the set
 * holds is unchanged whether or not it succeeds; only its arrays may have grown. */
static bool reserve_one_more(vkrt_texture_set *set, size_t word_count)
{
    size_t n = (size_t)set->count + 1;
    return reserve((void **)&set->info, n, sizeof *set->info) &&
           reserve((void **)&set->paths, n, sizeof *set->paths) &&
           reserve((void **)&set->usages, n, sizeof *set->usages) &&
           reserve((void **)&set->texels, set->texel_words + word_count, sizeof *set->texels);
}

/* After a failed decode: hands back the texel room reserved for it (a refused 16384 x 16384 image
 * would otherwise keep 1 GiB), so a failed add leaves no more memory held than before. */
static void give_back_room(vkrt_texture_set *set)
{
    if (set->texel_words == 0) {
        free(set->texels);
        set->texels = NULL;
        return;
    }
    uint32_t *p = realloc(set->texels, set->texel_words * sizeof *p);
    if (p)
        set->texels = p;
}

/* The set's flags of a w x h image: HDR images are linear already; 8-bit colour maps are
 * sRGB-encoded; every image has its mipmap levels (texture_levels.h). */
static uint32_t image_flags(bool hdr, vkrt_texture_usage usage, int w, int h)
{
    return (hdr ? VKRT_TEXTURE_HALF : usage == VKRT_TEXTURE_COLOUR ? VKRT_TEXTURE_SRGB : 0u) |
           VKRT_TEXTURE_LEVELS(vkrt_texture_level_count((uint32_t)w, (uint32_t)h));
}

/* Checks a w x h image (hdr: two words a texel) against the limits and what the set holds
 * already; its texel words in *words. */
static bool check_size(const vkrt_texture_set *set, int w, int h, bool hdr, const char *referrer,
                       const char *path, size_t *words, vkrt_error *err)
{
    uint32_t max = VKRT_TEXTURE_MAX_SIZE;
    if (w <= 0 || h <= 0 || (uint32_t)w > max || (uint32_t)h > max)
        return fail(err, referrer, path,
                    "image is %dx%d; textures must be 1 to %u texels wide and tall", w, h, max);
    *words = vkrt_texture_words_with_levels((uint32_t)w, (uint32_t)h, hdr ? 2 : 1);
    if (*words > MAX_TEXEL_WORDS - set->texel_words)
        return fail(err, referrer, path,
                    "the textures would pass the 16 GiB that 32-bit texel offsets address");
    size_t total_bytes = (set->texel_words + *words) * sizeof(uint32_t);
    if (set->max_texel_bytes && total_bytes > set->max_texel_bytes)
        return fail(err, referrer, path,
                    "this %dx%d texture takes %.1f MiB; with the %u textures before it the "
                    "textures would take %.1f MiB, over the limit of %.1f MiB",
                    w, h, (double)*words * sizeof(uint32_t) / MIB, set->count,
                    (double)total_bytes / MIB, (double)set->max_texel_bytes / MIB);
    return true;
}

/* Decodes the open image f, whose header said w x h with channels channels (hdr: a Radiance
 * image), into out (its texel words) for usage. False when stb_image fails or gives another size;
 * *size_differs then tells the two apart (stbi_failure_reason says why for the first). */
static bool decode_pixels(FILE *f, int w, int h, int channels, bool hdr, vkrt_texture_usage usage,
                          uint32_t *out, bool *size_differs, int *decoded_w, int *decoded_h)
{
    int dw = 0, dh = 0, dc = 0;
    void *pixels = hdr ? (void *)stbi_loadf_from_file(f, &dw, &dh, &dc, 4)
                       : (void *)stbi_load_from_file(f, &dw, &dh, &dc, 4);
    *size_differs = pixels && (dw != w || dh != h);
    *decoded_w = dw;
    *decoded_h = dh;
    if (!pixels || *size_differs) {
        stbi_image_free(pixels);
        return false;
    }
    size_t texels = (size_t)w * (size_t)h;
    /* Coverage reads alpha when the image has an alpha channel that says something (grey+alpha
     * or RGBA, not opaque everywhere), else its first channel: masks are made both ways, and
     * Lost Empire's lost_empire-Alpha.png is an RGBA image whose alpha is 255 throughout, its
     * coverage in the grey of its colour channels (read as alpha it would cover every leaf). */
    int alpha_channel = -1;
    if (usage == VKRT_TEXTURE_ALPHA)
        alpha_channel = (channels == 2 || channels == 4) && !opaque(pixels, texels, hdr) ? 3 : 0;
    if (hdr)
        pack_rgba16f(pixels, texels, alpha_channel, out);
    else
        pack_rgba8(pixels, texels, alpha_channel, out);
    stbi_image_free(pixels);
    return vkrt_texture_build_levels(out, (uint32_t)w, (uint32_t)h, image_flags(hdr, usage, w, h));
}

/* Reads the header of the open image f and checks its size against the limits and the set, then
 * decodes it into the texels past set->texel_words, filling *info and *word_count. The set's count
 * and texel_words are left for the caller to advance. */
static bool decode(vkrt_texture_set *set, FILE *f, vkrt_texture_usage usage, const char *referrer,
                   const char *path, vkrt_texture_info *info, size_t *word_count, vkrt_error *err)
{
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_file(f, &w, &h, &channels))
        return fail(err, referrer, path,
                    "not an image vkrt can read (stb_image: %s); use PNG, JPEG, TGA or HDR",
                    stbi_failure_reason());
    bool hdr = stbi_is_hdr_from_file(f) != 0;
    size_t words = 0;
    if (!check_size(set, w, h, hdr, referrer, path, &words, err))
        return false;
    if (!reserve_one_more(set, words))
        return fail(err, referrer, path, "out of memory for %dx%d texels", w, h);
    bool size_differs;
    int dw, dh;
    if (!decode_pixels(f, w, h, channels, hdr, usage, set->texels + set->texel_words,
                       &size_differs, &dw, &dh)) {
        if (size_differs)
            return fail(err, referrer, path, "decoded %dx%d, but its header says %dx%d", dw, dh,
                        w, h);
        char why[300];
        vkrt_texture_decode_failure(f, why, sizeof why);
        return fail(err, referrer, path, "cannot decode the image: %s", why);
    }
    *info = (vkrt_texture_info){
        .offset = (uint32_t)set->texel_words,
        .width = (uint32_t)w,
        .height = (uint32_t)h,
        .flags = image_flags(hdr, usage, w, h),
    };
    *word_count = words;
    return true;
}

/* Whether the set holds a texture of key (a canonical path or an embedded image's name) for
 * usage, read plainly (not a view, texture.h), its index then in *index. */
static bool find_added(const vkrt_texture_set *set, const char *key, vkrt_texture_usage usage,
                       uint32_t *index)
{
    for (uint32_t i = 0; i < set->count; i++)
        if (set->usages[i] == (uint32_t)usage && !(set->info[i].flags & VIEW_FLAGS) &&
            strcmp(set->paths[i], key) == 0) {
            *index = i;
            return true;
        }
    return false;
}

/* ---------------------------------------------------------------------------------------------
 * Decoding ahead, on every core
 * ------------------------------------------------------------------------------------------- */

/* An image decoded ahead: its texels wait in the set for the add that asks for it. */
struct vkrt_texture_ahead {
    char *key; /* as the set's paths: the canonical path or the embedded image's name */
    vkrt_texture_usage usage;
    int width, height, channels;
    bool hdr;
    size_t words;
    uint32_t *texels;  /* NULL: not decoded (it failed; the add decodes and says why) */
    const void *bytes; /* the embedded image's bytes, or NULL: the file key; only while */
    size_t size;       /* vkrt_texture_set_decode_ahead runs */
};

/* Most threads decoding at once. */
#define AHEAD_MAX_THREADS 32

typedef struct ahead_job {
    struct vkrt_texture_ahead *entries;
    uint32_t count;
    atomic_uint next;
} ahead_job;

static FILE *open_source(const struct vkrt_texture_ahead *a)
{
    return a->bytes ? fmemopen((void *)a->bytes, a->size, "rb") : fopen(a->key, "rb");
}

/* Decodes the job's entries, taking the next undecoded one until none is left. */
static void *decode_entries(void *arg)
{
    ahead_job *job = arg;
    for (uint32_t i; (i = atomic_fetch_add(&job->next, 1u)) < job->count;) {
        struct vkrt_texture_ahead *a = &job->entries[i];
        FILE *f = open_source(a);
        a->texels = f ? malloc(a->words * sizeof *a->texels) : NULL;
        bool size_differs;
        int dw, dh;
        if (a->texels && !decode_pixels(f, a->width, a->height, a->channels, a->hdr, a->usage,
                                        a->texels, &size_differs, &dw, &dh)) {
            free(a->texels);
            a->texels = NULL;
        }
        if (f)
            fclose(f);
    }
    return NULL;
}

/* Threads for decoding ahead: $VKRT_TEXTURE_THREADS when set (0 or 1: none ahead, every image
 * decoded by its add), else one per online core, at most AHEAD_MAX_THREADS. */
static uint32_t ahead_threads(void)
{
    const char *env = getenv("VKRT_TEXTURE_THREADS");
    long n = env && *env ? strtol(env, NULL, 10) : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1u : n > AHEAD_MAX_THREADS ? AHEAD_MAX_THREADS : (uint32_t)n;
}

/* Whether entries[0 .. count) or the set already has key for usage. */
static bool queued(const vkrt_texture_set *set, const struct vkrt_texture_ahead *entries,
                   uint32_t count, const char *key, vkrt_texture_usage usage)
{
    for (uint32_t i = 0; i < count; i++)
        if (entries[i].usage == usage && strcmp(entries[i].key, key) == 0)
            return true;
    for (uint32_t i = 0; i < set->ahead_count; i++)
        if (set->ahead[i].key && set->ahead[i].usage == usage &&
            strcmp(set->ahead[i].key, key) == 0)
            return true;
    uint32_t index;
    return find_added(set, key, usage, &index);
}

/* The key under which the add of source will look the image up, as vkrt_texture_set_add and
 * _add_memory make it; NULL where that add will fail before decoding (it then says why). */
static char *key_of(const vkrt_texture_source *source)
{
    if (source->bytes) {
        if (source->size == 0)
            return NULL;
        return strdup(source->path && *source->path ? source->path : "(embedded image)");
    }
    char *found = NULL;
    vkrt_error ignored;
    if (!source->path || !*source->path || !vkrt_texture_find_file(source->path, NULL, &found, &ignored))
        return NULL;
    char *canonical = realpath(found, NULL);
    if (!canonical)
        return found;
    free(found);
    return canonical;
}

/* Fills a with the size source's header gives, checked against the limits; false where the
 * image is not one to decode ahead (its add will say why). */
static bool read_header(struct vkrt_texture_ahead *a)
{
    FILE *f = open_source(a);
    bool ok = f && stbi_info_from_file(f, &a->width, &a->height, &a->channels);
    if (ok) {
        a->hdr = stbi_is_hdr_from_file(f) != 0;
        ok = a->width > 0 && a->height > 0 && (uint32_t)a->width <= VKRT_TEXTURE_MAX_SIZE &&
             (uint32_t)a->height <= VKRT_TEXTURE_MAX_SIZE;
        a->words = ok ? vkrt_texture_words_with_levels((uint32_t)a->width, (uint32_t)a->height,
                                                       a->hdr ? 2 : 1)
                      : 0;
    }
    if (f)
        fclose(f);
    return ok;
}

void vkrt_texture_set_decode_ahead(vkrt_texture_set *set, const vkrt_texture_source *sources,
                                   uint32_t count)
{
    uint32_t threads = ahead_threads();
    if (!set || !sources || count == 0 || threads < 2 || set->ahead_count > UINT32_MAX - count)
        return;
    struct vkrt_texture_ahead *entries =
        realloc(set->ahead, (set->ahead_count + (size_t)count) * sizeof *entries);
    if (!entries)
        return;
    set->ahead = entries;
    struct vkrt_texture_ahead *fresh = entries + set->ahead_count;
    /* The texels of the set and of what waits, against the limit the adds will check. */
    size_t words = set->texel_words;
    for (uint32_t i = 0; i < set->ahead_count; i++)
        words += entries[i].texels ? entries[i].words : 0;
    size_t limit = set->max_texel_bytes ? set->max_texel_bytes / sizeof(uint32_t) : MAX_TEXEL_WORDS;
    uint32_t n = 0;
    for (uint32_t i = 0; i < count; i++) {
        const vkrt_texture_source *s = &sources[i];
        if (s->usage != VKRT_TEXTURE_COLOUR && s->usage != VKRT_TEXTURE_DATA &&
            s->usage != VKRT_TEXTURE_ALPHA)
            continue;
        char *key = key_of(s);
        if (!key || queued(set, fresh, n, key, s->usage)) {
            free(key);
            continue;
        }
        fresh[n] = (struct vkrt_texture_ahead){
            .key = key, .usage = s->usage, .bytes = s->bytes, .size = s->size};
        if (!read_header(&fresh[n]) || fresh[n].words > limit - (words < limit ? words : limit)) {
            free(key); /* past the limit: its add fails, and no texels are spent on it */
            continue;
        }
        words += fresh[n++].words;
    }
    ahead_job job = {.entries = fresh, .count = n};
    atomic_init(&job.next, 0u);
    threads = threads > n ? n : threads;
    pthread_t ids[AHEAD_MAX_THREADS];
    bool started[AHEAD_MAX_THREADS] = {false};
    for (uint32_t t = 1; t < threads; t++)
        started[t] = pthread_create(&ids[t], NULL, decode_entries, &job) == 0;
    decode_entries(&job);
    for (uint32_t t = 1; t < threads; t++)
        if (started[t])
            pthread_join(ids[t], NULL);
    for (uint32_t i = 0; i < n; i++)
        fresh[i].bytes = NULL;
    set->ahead_count += n;
}

/* When key's image for usage was decoded ahead: appends it to the set as an add would have
 * (same checks and messages), index in *index, and returns 1, or -1 with err set when it does not
 * fit (the set as it was); 0 when it was not decoded ahead, for the caller to decode. */
static int append_ahead(vkrt_texture_set *set, const char *key, vkrt_texture_usage usage,
                        const char *referrer, const char *path, uint32_t *index, vkrt_error *err)
{
    for (uint32_t i = 0; i < set->ahead_count; i++) {
        struct vkrt_texture_ahead *a = &set->ahead[i];
        if (!a->texels || a->usage != usage || strcmp(a->key, key) != 0)
            continue;
        size_t words = 0;
        if (!check_size(set, a->width, a->height, a->hdr, referrer, path, &words, err))
            return -1;
        if (!reserve_one_more(set, words)) {
            give_back_room(set);
            fail(err, referrer, path, "out of memory for %dx%d texels", a->width, a->height);
            return -1;
        }
        memcpy(set->texels + set->texel_words, a->texels, words * sizeof *a->texels);
        free(a->texels);
        a->texels = NULL;
        set->info[set->count] = (vkrt_texture_info){
            .offset = (uint32_t)set->texel_words,
            .width = (uint32_t)a->width,
            .height = (uint32_t)a->height,
            .flags = image_flags(a->hdr, usage, a->width, a->height),
        };
        set->paths[set->count] = a->key; /* the set's now */
        a->key = NULL;
        set->usages[set->count] = (uint32_t)usage;
        set->texel_words += words;
        *index = set->count++;
        return 1;
    }
    return 0;
}

/* Decodes the open image f and appends it to the set under key (which the set then owns); on
 * failure the set is as it was and key is the caller's. path names the image in messages. */
static bool decode_and_append(vkrt_texture_set *set, FILE *f, vkrt_texture_usage usage,
                              const char *referrer, const char *path, char *key, uint32_t *index,
                              vkrt_error *err)
{
    vkrt_texture_info info;
    size_t words = 0;
    if (!decode(set, f, usage, referrer, path, &info, &words, err)) {
        give_back_room(set);
        return false;
    }
    set->info[set->count] = info;
    set->paths[set->count] = key;
    set->usages[set->count] = (uint32_t)usage;
    set->texel_words += words;
    *index = set->count++;
    return true;
}

bool vkrt_texture_set_add(vkrt_texture_set *set, const char *path, vkrt_texture_usage usage,
                          const char *referrer, uint32_t *index, vkrt_error *err)
{
    if (!path)
        path = "(null)";
    if (!set || !index)
        return fail(err, referrer, path, "no texture set to add to");
    if (usage != VKRT_TEXTURE_COLOUR && usage != VKRT_TEXTURE_DATA && usage != VKRT_TEXTURE_ALPHA)
        return fail(err, referrer, path, "unknown usage %d", (int)usage);
    if (!*path)
        return fail(err, referrer, path, "empty file name");
    if (set->count == UINT32_MAX)
        return fail(err, referrer, path, "too many textures");

    char *found = NULL;
    if (!vkrt_texture_find_file(path, referrer, &found, err))
        return false;
    /* One file reached by two spellings ("a/../t.png", "t.png", "T.PNG") is one texture. */
    char *canonical = realpath(found, NULL);
    if (!canonical) {
        canonical = found;
        found = NULL;
    }
    int ahead = find_added(set, canonical, usage, index)
                    ? 1
                    : append_ahead(set, canonical, usage, referrer, path, index, err);
    if (ahead != 0) {
        free(found);
        free(canonical);
        return ahead > 0;
    }

    FILE *f = fopen(found ? found : canonical, "rb");
    struct stat st;
    bool ok = false;
    if (!f)
        fail(err, referrer, path, "cannot open: %s", strerror(errno));
    else if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode))
        fail(err, referrer, path, "not a regular file");
    else if (st.st_size == 0)
        fail(err, referrer, path, "the file is empty");
    else
        ok = decode_and_append(set, f, usage, referrer, path, canonical, index, err);
    if (f)
        fclose(f);
    free(found);
    if (!ok)
        free(canonical);
    return ok;
}

bool vkrt_texture_set_add_memory(vkrt_texture_set *set, const void *bytes, size_t size,
                                 const char *name, vkrt_texture_usage usage,
                                 const char *referrer, uint32_t *index, vkrt_error *err)
{
    if (!name || !*name)
        name = "(embedded image)";
    if (!set || !index)
        return fail(err, referrer, name, "no texture set to add to");
    if (usage != VKRT_TEXTURE_COLOUR && usage != VKRT_TEXTURE_DATA && usage != VKRT_TEXTURE_ALPHA)
        return fail(err, referrer, name, "unknown usage %d", (int)usage);
    if (set->count == UINT32_MAX)
        return fail(err, referrer, name, "too many textures");
    if (find_added(set, name, usage, index))
        return true;
    int ahead = append_ahead(set, name, usage, referrer, name, index, err);
    if (ahead != 0)
        return ahead > 0;
    if (!bytes || size == 0)
        return fail(err, referrer, name, "the image is empty");
    char *key = strdup(name);
    /* stb_image's _from_file readers and the failure diagnosis read a FILE: the bytes as one. */
    FILE *f = key ? fmemopen((void *)bytes, size, "rb") : NULL;
    bool ok = false;
    if (!key)
        fail(err, referrer, name, "out of memory");
    else if (!f)
        fail(err, referrer, name, "cannot read the image's bytes: %s", strerror(errno));
    else
        ok = decode_and_append(set, f, usage, referrer, name, key, index, err);
    if (f)
        fclose(f);
    if (!ok)
        free(key);
    return ok;
}

bool vkrt_texture_set_view(vkrt_texture_set *set, uint32_t base, uint32_t view_flags,
                           const float uv_matrix[4], const float uv_offset[2], uint32_t *index,
                           vkrt_error *err)
{
    if (!set || base >= set->count || (set->info[base].flags & VIEW_FLAGS) ||
        (view_flags & ~VIEW_FLAGS))
        return vkrt_error_set(err, "texture view of texture %u (flags 0x%x) is not one of the set's "
                                   "images read another way", base, view_flags);
    if (!view_flags) {
        *index = base;
        return true;
    }
    vkrt_texture_info view = set->info[base];
    view.flags |= view_flags;
    if (view_flags & VKRT_TEXTURE_TRANSFORM) {
        memcpy(view.uv_matrix, uv_matrix, sizeof view.uv_matrix);
        view.uv_offset[0] = uv_offset[0];
        view.uv_offset[1] = uv_offset[1];
    }
    for (uint32_t i = 0; i < set->count; i++)
        if (memcmp(&set->info[i], &view, sizeof view) == 0) {
            *index = i;
            return true;
        }
    if (set->count == UINT32_MAX)
        return vkrt_error_set(err, "too many textures");
    /* reserve_one_more grows info, paths and usages by one and the texels by nothing. */
    char *path = strdup(set->paths[base]);
    if (!path || !reserve_one_more(set, 0)) {
        free(path);
        return vkrt_error_set(err, "out of memory for a texture view");
    }
    set->info[set->count] = view;
    set->paths[set->count] = path;
    set->usages[set->count] = set->usages[base];
    *index = set->count++;
    return true;
}

bool vkrt_texture_uv_transform(const float offset[2], const float scale[2], float rotation,
                               float uv_matrix[4], float uv_offset[2])
{
    float c = cosf(rotation), s = sinf(rotation);
    uv_matrix[0] = c * scale[0];
    uv_matrix[1] = s * scale[1];
    uv_matrix[2] = -s * scale[0];
    uv_matrix[3] = c * scale[1];
    uv_offset[0] = offset[0];
    uv_offset[1] = offset[1];
    return offset[0] == 0.0f && offset[1] == 0.0f && scale[0] == 1.0f && scale[1] == 1.0f &&
           rotation == 0.0f;
}

void vkrt_texture_set_filter(vkrt_texture_set *set, vkrt_texture_filter filter)
{
    for (uint32_t i = 0; filter != VKRT_TEXTURE_FILTER_CONE && i < set->count; i++) {
        set->info[i].flags &= ~VKRT_TEXTURE_LEVELS(15u);
        if (filter == VKRT_TEXTURE_FILTER_NEAREST)
            set->info[i].flags |= VKRT_TEXTURE_NEAREST;
    }
}

void vkrt_texture_set_free(vkrt_texture_set *set)
{
    if (!set)
        return;
    for (uint32_t i = 0; set->paths && i < set->count; i++)
        free(set->paths[i]);
    free(set->paths);
    free(set->info);
    free(set->usages);
    free(set->texels);
    for (uint32_t i = 0; set->ahead && i < set->ahead_count; i++) {
        free(set->ahead[i].key);
        free(set->ahead[i].texels);
    }
    free(set->ahead);
    size_t limit = set->max_texel_bytes;
    memset(set, 0, sizeof *set);
    set->max_texel_bytes = limit;
}

/* ---------------------------------------------------------------------------------------------
 * Sampling: the same steps as glsl/lib/texture.glsl, in float
 * ------------------------------------------------------------------------------------------- */

/* The exact sRGB decoding curve (IEC 61966-2-1), not a 2.2 power. */
static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

/* i modulo n for any int i; unsigned, as in the GLSL, where % of negative ints is undefined. */
static uint32_t wrap(int i, uint32_t n)
{
    uint32_t a = i < 0 ? 0u - (uint32_t)i : (uint32_t)i;
    uint32_t r = a % n;
    return i < 0 && r ? n - r : r;
}

/* Texel index i of n under a wrap mode: texture_wrap_mode. */
static uint32_t wrap_mode(int i, uint32_t n, uint32_t mode)
{
    if (mode == VKRT_TEXTURE_CLAMP)
        return i < 0 ? 0u : (uint32_t)i >= n ? n - 1u : (uint32_t)i;
    if (mode == VKRT_TEXTURE_MIRROR) {
        uint32_t m = wrap(i, 2u * n);
        return m < n ? m : 2u * n - 1u - m;
    }
    return wrap(i, n);
}

void vkrt_texture_texel(const vkrt_texture_set *set, uint32_t index, int x, int y, float rgba[4])
{
    if (!set || index >= set->count) {
        rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0f;
        return;
    }
    const vkrt_texture_info *info = &set->info[index];
    uint32_t wrap_u = info->flags >> 2 & 3u, wrap_v = info->flags >> 4 & 3u;
    uint32_t i = (wrap_u | wrap_v) == VKRT_TEXTURE_REPEAT
                     ? wrap(y, info->height) * info->width + wrap(x, info->width)
                     : wrap_mode(y, info->height, wrap_v) * info->width +
                           wrap_mode(x, info->width, wrap_u);
    if (info->flags & VKRT_TEXTURE_HALF) {
        const uint32_t *t = &set->texels[info->offset + 2u * i];
        rgba[0] = vkrt_half_to_float(t[0] & 0xFFFFu);
        rgba[1] = vkrt_half_to_float(t[0] >> 16);
        rgba[2] = vkrt_half_to_float(t[1] & 0xFFFFu);
        rgba[3] = vkrt_half_to_float(t[1] >> 16);
        return;
    }
    uint32_t t = set->texels[info->offset + i];
    for (int k = 0; k < 4; k++)
        rgba[k] = (float)((t >> (8 * k)) & 0xFFu) / 255.0f;
    if (info->flags & VKRT_TEXTURE_SRGB)
        for (int k = 0; k < 3; k++)
            rgba[k] = srgb_to_linear(rgba[k]);
}

/* GLSL's mix. */
static float mix(float a, float b, float t)
{
    return a * (1.0f - t) + b * t;
}

/* An image coordinate folded into the span its wrap mode repeats: texture_fold. */
static float fold(float c, uint32_t mode)
{
    if (mode == VKRT_TEXTURE_CLAMP)
        return fminf(fmaxf(c, 0.0f), 1.0f);
    if (mode == VKRT_TEXTURE_MIRROR)
        return c - 2.0f * floorf(c * 0.5f);
    return c - floorf(c);
}

void vkrt_texture_sample(const vkrt_texture_set *set, uint32_t index, float u, float v,
                         float rgba[4])
{
    if (!set || index >= set->count) {
        rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0f;
        return;
    }
    const vkrt_texture_info *info = &set->info[index];
    if (!isfinite(u))
        u = 0.0f;
    if (!isfinite(v))
        v = 0.0f;
    /* Image coordinates: s from the left, t down from the top row (OBJ's v = 0 is the bottom). */
    float s = u, t = 1.0f - v;
    if (info->flags & VKRT_TEXTURE_TRANSFORM) {
        const float *m = info->uv_matrix;
        float s2 = m[0] * s + m[1] * t + info->uv_offset[0];
        float t2 = m[2] * s + m[3] * t + info->uv_offset[1];
        s = isfinite(s2) ? s2 : 0.0f;
        t = isfinite(t2) ? t2 : 0.0f;
    }
    /* Wrap first, so a large coordinate keeps its precision; texel k covers [k, k + 1) with its
     * centre at k + 0.5. */
    uint32_t wrap_u = info->flags >> 2 & 3u, wrap_v = info->flags >> 4 & 3u;
    float ws = fold(s, wrap_u), wt = fold(t, wrap_v);
    float c[4];
    if (info->flags & VKRT_TEXTURE_NEAREST) {
        vkrt_texture_texel(set, index, (int)floorf(ws * (float)info->width),
                           (int)floorf(wt * (float)info->height), c);
    } else {
        float x = ws * (float)info->width - 0.5f, y = wt * (float)info->height - 0.5f;
        float x0 = floorf(x), y0 = floorf(y);
        float fx = x - x0, fy = y - y0;
        int ix = (int)x0, iy = (int)y0;
        float t00[4], t10[4], t01[4], t11[4];
        vkrt_texture_texel(set, index, ix, iy, t00);
        vkrt_texture_texel(set, index, ix + 1, iy, t10);
        vkrt_texture_texel(set, index, ix, iy + 1, t01);
        vkrt_texture_texel(set, index, ix + 1, iy + 1, t11);
        for (int k = 0; k < 4; k++)
            c[k] = mix(mix(t00[k], t10[k], fx), mix(t01[k], t11[k], fx), fy);
    }
    uint32_t channel = info->flags >> 8 & 3u;
    for (int k = 0; k < 4; k++)
        rgba[k] = c[channel ? channel : (uint32_t)k];
}

void vkrt_texture_mean(const vkrt_texture_set *set, uint32_t index, float rgba[4])
{
    double sum[4] = {0, 0, 0, 0};
    rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0f;
    if (!set || index >= set->count)
        return;
    const vkrt_texture_info *info = &set->info[index];
    for (uint32_t y = 0; y < info->height; y++)
        for (uint32_t x = 0; x < info->width; x++) {
            float t[4];
            vkrt_texture_texel(set, index, (int)x, (int)y, t);
            for (int k = 0; k < 4; k++)
                sum[k] += t[k];
        }
    double texels = (double)info->width * info->height;
    for (int k = 0; k < 4; k++)
        rgba[k] = (float)(sum[k] / texels);
}

bool vkrt_texture_is_normal_map(const vkrt_texture_set *set, uint32_t index)
{
    float mean[4];
    vkrt_texture_mean(set, index, mean);
    /* A tangent-space normal map averages to about (0.5, 0.5, 1): the normal mostly unbent, its
     * blue above its red and green. A height map is grey (r = g = b), and a colour image used as
     * one (dabrovic-sponza's) is not this blue. */
    float red_green = fmaxf(mean[0], mean[1]);
    return fabsf(mean[0] - 0.5f) < 0.25f && fabsf(mean[1] - 0.5f) < 0.25f && mean[2] > 0.8f &&
           mean[2] > red_green + 0.2f;
}
