/*
 * envmap.c: environment maps: reading them, building their sampling distribution, and the CPU
 * mirror of the GPU's sampling (see envmap.h for the convention and the buffer layout).
 *
 * The distribution follows pbrt's Distribution2D (Pharr, Jakob, Humphreys, Physically Based
 * Rendering, 3rd ed., 13.6.7 and 14.2.4): a piecewise-constant density over the map's texels in
 * uv, built from luminance * sin(theta) so that the sin(theta) of the equirectangular Jacobian
 * cancels, sampled by inverting a marginal CDF over rows and a conditional CDF in the row. The
 * luminance of a texel is the mean of the bilinear lookup over it, not the texel's own value: a
 * black texel beside a bright one still receives light from the lookup, and a density of zero
 * there would make the light-sampling estimator miss it (bias). The mean is positive exactly where
 * the lookup is non-zero, and it follows the radiance more closely than the largest neighbour
 * would, which would spend samples on the dim edges of a small sun. The
 * sums are taken in double and stored as float, and every positive weight keeps a positive CDF
 * step even when it is below a float's resolution next to 1 (see cdf_build).
 */
#define _XOPEN_SOURCE 700 /* strcasecmp */

#include "envmap.h"
#include "texture.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <openexr.h>
#include <stb_image.h>

#include "../../glsl/shared.h"
#include "colour.h"
#include "radiance_hdr.h"
#include "texture_file.h"

#define PI_D 3.14159265358979323846
#define PI_F 3.14159265358979323846f

/* The largest float below 1: uniform numbers are clamped to it, so a CDF walk never runs off the
 * end of a table (whose last value is exactly 1). */
#define ONE_MINUS_EPSILON 0x1.fffffep-1f

/* ---------------------------------------------------------------------------------------------
 * Messages
 * ------------------------------------------------------------------------------------------- */

/* "<referrer>: environment-map '<path>': <reason>", the referrer left out when there is none. */
#define fail(err, referrer, path, ...) \
    vkrt_error_set_file(err, referrer, "environment-map", path, __VA_ARGS__)

/* ---------------------------------------------------------------------------------------------
 * Reading
 * ------------------------------------------------------------------------------------------- */

/* A channel as the map keeps it: NaN and negative values carry no light; values past what the
 * GPU's half floats hold are clamped here, so that the distribution sees what the kernels see. */
static float sanitise(float c)
{
    if (!(c > 0.0f))
        return 0.0f;
    return c < VKRT_ENVMAP_MAX_RADIANCE ? c : VKRT_ENVMAP_MAX_RADIANCE;
}

/* The exact sRGB decoding curve, as texture_srgb_to_linear in glsl/lib/texture.glsl. */
static float srgb_to_linear(float c)
{
    return c > 0.04045f ? powf((c + 0.055f) / 1.055f, 2.4f) : c / 12.92f;
}

static bool size_ok(int64_t w, int64_t h)
{
    return w > 0 && h > 0 && w <= VKRT_TEXTURE_MAX_SIZE && h <= VKRT_TEXTURE_MAX_SIZE;
}

/* The rest of f, from where it stands, in *bytes (malloc'd) and *size; false when out of memory
 * or a read fails. Read in doubling chunks: the file may be a pipe. */
static bool read_rest(FILE *f, unsigned char **bytes, size_t *size)
{
    size_t used = 0, cap = 0;
    unsigned char *buf = NULL;
    for (;;) {
        if (used == cap) {
            size_t grown_cap = cap ? 2 * cap : (size_t)1 << 16;
            unsigned char *grown = grown_cap > cap ? realloc(buf, grown_cap) : NULL;
            if (!grown) {
                free(buf);
                return false;
            }
            buf = grown;
            cap = grown_cap;
        }
        size_t n = fread(buf + used, 1, cap - used, f);
        used += n;
        if (n == 0)
            break;
    }
    if (ferror(f)) {
        free(buf);
        return false;
    }
    *bytes = buf;
    *size = used;
    return true;
}

/* A Radiance .hdr through radiance_hdr.c: the header, the size limits, the pixel data's
 * coverage (before anything is allocated for the pixels), then the decode. f is at its start. */
static bool load_radiance(FILE *f, const char *path, const char *referrer,
                          vkrt_envmap_image *image, vkrt_error *err)
{
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!read_rest(f, &bytes, &size))
        return fail(err, referrer, path, "cannot read: %s", ferror(f) ? strerror(errno)
                                                                       : "out of memory");
    char why[300];
    vkrt_radiance_info info;
    bool ok = vkrt_radiance_header(bytes, size, &info, why, sizeof why);
    if (ok && !size_ok(info.width, info.height)) {
        snprintf(why, sizeof why, "image is %ux%u; maps must be 1 to %u pixels wide and tall",
                 info.width, info.height, VKRT_TEXTURE_MAX_SIZE);
        ok = false;
    }
    ok = ok && vkrt_radiance_check(bytes, size, &info, why, sizeof why);
    float *rgb = ok ? malloc((size_t)info.width * info.height * 3 * sizeof *rgb) : NULL;
    if (ok && (!rgb || !vkrt_radiance_decode(bytes, size, &info, 3, rgb))) {
        snprintf(why, sizeof why, "out of memory for %ux%u pixels", info.width, info.height);
        ok = false;
    }
    free(bytes);
    if (!ok) {
        free(rgb);
        return fail(err, referrer, path, "%s", why);
    }
    size_t n = (size_t)info.width * info.height * 3;
    for (size_t i = 0; i < n; i++)
        rgb[i] = sanitise(rgb[i]);
    *image = (vkrt_envmap_image){.width = info.width, .height = info.height, .rgb = rgb};
    return true;
}

static bool load_stb(const char *path, const char *referrer, vkrt_envmap_image *image,
                     vkrt_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return fail(err, referrer, path, "cannot open: %s", strerror(errno));
    /* Radiance files, whatever their name, go to our reader; the rest to stb_image. */
    unsigned char magic[2] = {0, 0};
    size_t got = fread(magic, 1, sizeof magic, f);
    if (fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return fail(err, referrer, path, "cannot read: %s", strerror(errno));
    }
    if (vkrt_radiance_is(magic, got)) {
        bool ok = load_radiance(f, path, referrer, image, err);
        fclose(f);
        return ok;
    }
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_file(f, &w, &h, &channels)) {
        fclose(f);
        return fail(err, referrer, path,
                    "not an image vkrt can read (stb_image: %s); use EXR, HDR, PNG or JPEG",
                    stbi_failure_reason());
    }
    if (!size_ok(w, h)) {
        fclose(f);
        return fail(err, referrer, path,
                    "image is %dx%d; maps must be 1 to %u pixels wide and tall", w, h,
                    VKRT_TEXTURE_MAX_SIZE);
    }
    int dw = 0, dh = 0, dc = 0;
    unsigned char *pixels = stbi_load_from_file(f, &dw, &dh, &dc, 3);
    if (!pixels) {
        char why[300];
        vkrt_texture_decode_failure(f, why, sizeof why);
        fclose(f);
        return fail(err, referrer, path, "cannot decode the image: %s", why);
    }
    fclose(f);
    if (dw != w || dh != h) {
        stbi_image_free(pixels);
        return fail(err, referrer, path, "decoded %dx%d, but its header says %dx%d", dw, dh, w, h);
    }
    size_t n = (size_t)w * (size_t)h * 3;
    float *rgb = malloc(n * sizeof *rgb);
    if (!rgb) {
        stbi_image_free(pixels);
        return fail(err, referrer, path, "out of memory for %dx%d pixels", w, h);
    }
    /* 8-bit images are sRGB-encoded, like colour textures. */
    for (size_t i = 0; i < n; i++)
        rgb[i] = sanitise(srgb_to_linear(pixels[i] / 255.0f));
    stbi_image_free(pixels);
    *image = (vkrt_envmap_image){.width = (uint32_t)w, .height = (uint32_t)h, .rgb = rgb};
    return true;
}

/* OpenEXRCore keeps its last error message here, so the report can quote it. */
static void exr_keep_message(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)code;
    void *user = NULL;
    if (ctxt && exr_get_user_data(ctxt, &user) == EXR_ERR_SUCCESS && user)
        snprintf(user, 256, "%s", msg);
}

/* Decodes one chunk (a block of scanlines, or a tile) into the image, whose pixel (0, 0) is the
 * data window's corner; x0, y0 is the chunk's first pixel relative to that corner. channel[k] is
 * the part's channel for R, G, B (a grey map names Y three times; -1: none). */
static exr_result_t exr_decode_chunk(exr_context_t ctxt, const exr_chunk_info_t *chunk, int32_t x0,
                                     int32_t y0, const int channel[3], vkrt_envmap_image *image)
{
    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    exr_result_t rv = exr_decoding_initialize(ctxt, 0, chunk, &decoder);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    if (x0 < 0 || y0 < 0 || chunk->width < 0 || chunk->height < 0 ||
        (uint32_t)x0 + (uint32_t)chunk->width > image->width ||
        (uint32_t)y0 + (uint32_t)chunk->height > image->height) {
        exr_decoding_destroy(ctxt, &decoder);
        return EXR_ERR_CORRUPT_CHUNK;
    }
    float *corner = image->rgb + ((size_t)y0 * image->width + (size_t)x0) * 3;
    for (int16_t c = 0; c < decoder.channel_count; c++) {
        exr_coding_channel_info_t *ch = &decoder.channels[c];
        ch->decode_to_ptr = NULL; /* channels vkrt does not read are skipped */
        for (int k = 0; k < 3; k++) {
            if (channel[k] != c)
                continue;
            /* A grey map writes its one channel to R; G and B are copied from it afterwards. */
            ch->decode_to_ptr = (uint8_t *)(corner + k);
            ch->user_pixel_stride = 3 * (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)(image->width * 3 * sizeof(float));
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = sizeof(float);
            break;
        }
    }
    rv = exr_decoding_choose_default_routines(ctxt, 0, &decoder);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_decoding_run(ctxt, 0, &decoder);
    exr_result_t destroy_rv = exr_decoding_destroy(ctxt, &decoder);
    return rv != EXR_ERR_SUCCESS ? rv : destroy_rv;
}

/* Every chunk of part 0 at full resolution, scanline blocks or tiles (level 0 of a mipmapped
 * file). */
static exr_result_t exr_decode_all(exr_context_t ctxt, exr_storage_t storage,
                                   const exr_attr_box2i_t *window, const int channel[3],
                                   vkrt_envmap_image *image)
{
    exr_result_t rv = EXR_ERR_SUCCESS;
    if (storage == EXR_STORAGE_SCANLINE) {
        int32_t lines = 0;
        rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
        if (rv == EXR_ERR_SUCCESS && lines <= 0)
            rv = EXR_ERR_CORRUPT_CHUNK;
        for (int64_t y = window->min.y; y <= window->max.y && rv == EXR_ERR_SUCCESS; y += lines) {
            exr_chunk_info_t chunk;
            rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &chunk);
            if (rv == EXR_ERR_SUCCESS)
                rv = exr_decode_chunk(ctxt, &chunk, 0, chunk.start_y - window->min.y, channel,
                                      image);
        }
        return rv;
    }
    int32_t tile_w = 0, tile_h = 0;
    rv = exr_get_tile_sizes(ctxt, 0, 0, 0, &tile_w, &tile_h);
    if (rv == EXR_ERR_SUCCESS && (tile_w <= 0 || tile_h <= 0))
        rv = EXR_ERR_CORRUPT_CHUNK;
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    int32_t tiles_x = (int32_t)((image->width + (uint32_t)tile_w - 1) / (uint32_t)tile_w);
    int32_t tiles_y = (int32_t)((image->height + (uint32_t)tile_h - 1) / (uint32_t)tile_h);
    for (int32_t ty = 0; ty < tiles_y && rv == EXR_ERR_SUCCESS; ty++) {
        for (int32_t tx = 0; tx < tiles_x && rv == EXR_ERR_SUCCESS; tx++) {
            exr_chunk_info_t chunk;
            rv = exr_read_tile_chunk_info(ctxt, 0, tx, ty, 0, 0, &chunk);
            if (rv == EXR_ERR_SUCCESS)
                rv = exr_decode_chunk(ctxt, &chunk, tx * tile_w, ty * tile_h, channel, image);
        }
    }
    return rv;
}

/* Finds the R, G and B channels (or Y, for a grey map) of part 0; false if there are none, or
 * they are subsampled. */
static bool exr_find_channels(const exr_attr_chlist_t *list, int channel[3], bool *grey, char *why,
                              size_t why_size)
{
    static const char *const names[3] = {"R", "G", "B"};
    int y = -1;
    channel[0] = channel[1] = channel[2] = -1;
    for (int c = 0; c < list->num_channels; c++) {
        const exr_attr_chlist_entry_t *e = &list->entries[c];
        for (int k = 0; k < 3; k++)
            if (strcmp(e->name.str, names[k]) == 0)
                channel[k] = c;
        if (strcmp(e->name.str, "Y") == 0)
            y = c;
        bool wanted = !strcmp(e->name.str, "R") || !strcmp(e->name.str, "G") ||
                      !strcmp(e->name.str, "B") || !strcmp(e->name.str, "Y");
        if (wanted && (e->x_sampling != 1 || e->y_sampling != 1)) {
            snprintf(why, why_size, "channel %s is subsampled, which vkrt does not read",
                     e->name.str);
            return false;
        }
    }
    *grey = false;
    if (channel[0] >= 0 && channel[1] >= 0 && channel[2] >= 0)
        return true;
    if (y >= 0) {
        *grey = true;
        channel[0] = y;
        channel[1] = channel[2] = -1;
        return true;
    }
    snprintf(why, why_size, "no R, G and B channels (nor Y) in its first part");
    return false;
}

static bool load_exr(const char *path, const char *referrer, vkrt_envmap_image *image,
                     vkrt_error *err)
{
    char library_msg[256] = "";
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = library_msg;
    init.error_handler_fn = exr_keep_message;
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctxt);
        return fail(err, referrer, path, "cannot read it as OpenEXR: %s",
                    library_msg[0] ? library_msg : exr_get_default_error_message(rv));
    }
    char why[200] = "";
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    exr_attr_box2i_t window;
    memset(&window, 0, sizeof window);
    const exr_attr_chlist_t *list = NULL;
    int channel[3];
    bool grey = false;
    rv = exr_get_storage(ctxt, 0, &storage);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_data_window(ctxt, 0, &window);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_channels(ctxt, 0, &list);
    if (rv == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        snprintf(why, sizeof why, "a deep image, not a colour map");
    if (rv == EXR_ERR_SUCCESS && !why[0])
        exr_find_channels(list, channel, &grey, why, sizeof why);
    int64_t w = (int64_t)window.max.x - window.min.x + 1;
    int64_t h = (int64_t)window.max.y - window.min.y + 1;
    if (rv == EXR_ERR_SUCCESS && !why[0] && !size_ok(w, h))
        snprintf(why, sizeof why, "image is %lldx%lld; maps must be 1 to %u pixels wide and tall",
                 (long long)w, (long long)h, VKRT_TEXTURE_MAX_SIZE);
    if (rv != EXR_ERR_SUCCESS || why[0]) {
        exr_finish(&ctxt);
        if (why[0])
            return fail(err, referrer, path, "%s", why);
        return fail(err, referrer, path, "cannot read its header: %s",
                    library_msg[0] ? library_msg : exr_get_default_error_message(rv));
    }

    image->width = (uint32_t)w;
    image->height = (uint32_t)h;
    /* Zeroed: pixels a damaged file leaves out stay black rather than garbage. */
    image->rgb = calloc((size_t)w * (size_t)h * 3, sizeof *image->rgb);
    if (!image->rgb) {
        exr_finish(&ctxt);
        memset(image, 0, sizeof *image);
        return fail(err, referrer, path, "out of memory for %lldx%lld pixels", (long long)w,
                    (long long)h);
    }
    rv = exr_decode_all(ctxt, storage, &window, channel, image);
    exr_finish(&ctxt);
    if (rv != EXR_ERR_SUCCESS) {
        vkrt_envmap_image_free(image);
        return fail(err, referrer, path, "cannot decode its pixels: %s",
                    library_msg[0] ? library_msg : exr_get_default_error_message(rv));
    }
    size_t n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < n; i++) {
        float *p = image->rgb + 3 * i;
        if (grey)
            p[1] = p[2] = p[0];
        for (int k = 0; k < 3; k++)
            p[k] = sanitise(p[k]);
    }
    return true;
}

bool vkrt_envmap_load(const char *path, const char *referrer, vkrt_envmap_image *image,
                      vkrt_error *err)
{
    if (!image)
        return vkrt_error_set(err, "environment-map: no image to fill");
    memset(image, 0, sizeof *image);
    if (!path)
        return vkrt_error_set(err, "environment-map: no path given");
    size_t len = strlen(path);
    if (len >= 4 && strcasecmp(path + len - 4, ".exr") == 0) {
        /* OpenEXRCore's message for a missing file is vague: say it plainly first. */
        FILE *f = fopen(path, "rb");
        if (!f)
            return fail(err, referrer, path, "cannot open: %s", strerror(errno));
        fclose(f);
        return load_exr(path, referrer, image, err);
    }
    return load_stb(path, referrer, image, err);
}

void vkrt_envmap_image_free(vkrt_envmap_image *image)
{
    if (!image)
        return;
    free(image->rgb);
    memset(image, 0, sizeof *image);
}

/* ---------------------------------------------------------------------------------------------
 * The distribution
 * ------------------------------------------------------------------------------------------- */

size_t vkrt_envmap_distribution_floats(uint32_t width, uint32_t height)
{
    return ((size_t)height + 1) + (size_t)height * ((size_t)width + 1);
}

/* Writes the CDF of n weights (>= 0, finite) to cdf[0..n] and returns their sum. cdf[0] = 0,
 * cdf[n] = 1, non-decreasing; a zero weight has a zero step and a positive weight a positive one,
 * however small against the total (the step is widened to one float ulp where rounding would
 * close it, and the ulps are taken back from the steps before the end if that overshoots 1).
 * All zero: the uniform CDF, and 0 returned. */
static double cdf_build(const double *w, uint32_t n, float *cdf)
{
    double total = 0.0;
    for (uint32_t i = 0; i < n; i++)
        total += w[i];
    cdf[0] = 0.0f;
    if (!(total > 0.0)) {
        for (uint32_t i = 1; i <= n; i++)
            cdf[i] = (float)((double)i / n);
        return 0.0;
    }
    double sum = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        sum += w[i];
        float c = (float)(sum / total);
        if (w[i] > 0.0 && c <= cdf[i])
            c = nextafterf(cdf[i], 2.0f);
        else if (!(w[i] > 0.0))
            c = cdf[i];
        cdf[i + 1] = c;
    }
    /* The last positive weight brings sum to total exactly (the same additions in the same
     * order), so cdf[n] is 1, or above it where widened steps pile up at the end. */
    if (cdf[n] != 1.0f) {
        cdf[n] = 1.0f;
        for (uint32_t i = n - 1; i > 0; i--) {
            float limit = w[i] > 0.0 ? nextafterf(cdf[i + 1], 0.0f) : cdf[i + 1];
            if (cdf[i] <= limit)
                break;
            cdf[i] = limit;
        }
    }
    return total;
}


/* The bilinear lookup (linear between texel centres, wrapping across) integrated over
 * each texel of one row, across only: over [x, x + 1] it weighs texels x - 1, x, x + 1 by 1/8,
 * 3/4, 1/8. Applied across and then down, it gives the mean luminance the lookup returns over the
 * texel, which is positive exactly where the lookup is non-zero somewhere in the texel. */
static void row_filter(const float *rgb, uint32_t width, uint32_t y, double *out)
{
    const float *row = rgb + (size_t)y * width * 3;
    for (uint32_t x = 0; x < width; x++) {
        uint32_t left = x == 0 ? width - 1 : x - 1;
        uint32_t right = x + 1 == width ? 0 : x + 1;
        out[x] = 0.75 * vkrt_luminance(row + 3 * (size_t)x) +
                 0.125 * (vkrt_luminance(row + 3 * (size_t)left) +
                          vkrt_luminance(row + 3 * (size_t)right));
    }
}

bool vkrt_envmap_distribution_build(const float *rgb, uint32_t width, uint32_t height,
                                    vkrt_envmap_distribution *dist, vkrt_error *err)
{
    if (!dist)
        return vkrt_error_set(err, "environment-map: no distribution to fill");
    memset(dist, 0, sizeof *dist);
    if (!rgb || !size_ok(width, height))
        return vkrt_error_set(err,
                              "environment-map: a %ux%u map cannot be sampled (1 to %u "
                              "pixels wide and tall)",
                              width, height, VKRT_TEXTURE_MAX_SIZE);
    size_t count = vkrt_envmap_distribution_floats(width, height);
    float *data = malloc(count * sizeof *data);
    /* Three rows filtered across (the row above, this one, the one below) and a row of weights;
     * the marginal's weights, one per row. */
    double *rows = malloc((size_t)width * 4 * sizeof *rows);
    double *row_weight = malloc((size_t)height * sizeof *row_weight);
    if (!data || !rows || !row_weight) {
        free(data);
        free(rows);
        free(row_weight);
        return vkrt_error_set(err,
                              "environment-map: out of memory for the distribution of a "
                              "%ux%u map",
                              width, height);
    }
    double *above = rows, *here = rows + width, *below = rows + 2 * (size_t)width;
    double *weight = rows + 3 * (size_t)width;
    /* The bilinear lookup clamps vertically (glsl/lib/environment.glsl), so the top row's
     * neighbour above is itself, as is the bottom row's below. */
    row_filter(rgb, width, 0, above);
    row_filter(rgb, width, 0, here);
    for (uint32_t y = 0; y < height; y++) {
        row_filter(rgb, width, y + 1 == height ? y : y + 1, below);
        /* The mean of sin(theta) over the row, the solid angle per unit uv area: positive in
         * every row, the top and bottom ones too. */
        double theta0 = PI_D * y / height, theta1 = PI_D * (y + 1) / height;
        double sin_theta = (cos(theta0) - cos(theta1)) / (theta1 - theta0);
        for (uint32_t x = 0; x < width; x++)
            weight[x] = sin_theta * (0.75 * here[x] + 0.125 * (above[x] + below[x]));
        row_weight[y] = cdf_build(weight, width, data + (height + 1) + (size_t)y * (width + 1));
        double *spare = above;
        above = here;
        here = below;
        below = spare;
    }
    dist->weight_sum = cdf_build(row_weight, height, data);
    dist->width = width;
    dist->height = height;
    dist->data = data;
    dist->float_count = count;
    free(rows);
    free(row_weight);
    return true;
}

void vkrt_envmap_distribution_free(vkrt_envmap_distribution *dist)
{
    if (!dist)
        return;
    free(dist->data);
    memset(dist, 0, sizeof *dist);
}

void vkrt_envmap_light_info(const vkrt_envmap_distribution *dist, float scale, float rotate_degrees,
                            LightInfo *info)
{
    info->environment_width = dist->width;
    info->environment_height = dist->height;
    info->environment_scale = scale;
    /* Reduced first, so that a rotation of many turns keeps its precision. */
    info->environment_rotate = (float)(fmod((double)rotate_degrees, 360.0) * PI_D / 180.0);
    info->environment_integral = (float)dist->weight_sum;
    info->environment_sampled = dist->weight_sum > 0.0 && scale > 0.0f ? 1u : 0u;
}

/* ---------------------------------------------------------------------------------------------
 * The CPU mirror of glsl/lib/envmap.glsl
 * ------------------------------------------------------------------------------------------- */

void vkrt_envmap_direction(float u, float v, float rotate, float dir[3])
{
    float phi = 2.0f * PI_F * u - rotate;
    float theta = PI_F * (1.0f - v);
    float sin_theta = sinf(theta);
    dir[0] = sinf(phi) * sin_theta;
    dir[1] = cosf(theta);
    dir[2] = -cosf(phi) * sin_theta;
}

void vkrt_envmap_uv(const float dir[3], float rotate, float uv[2])
{
    /* Straight up or down, every u is the same direction: take 0 (atan2(0, 0) in GLSL is
     * undefined). */
    float phi = (dir[0] == 0.0f && dir[2] == 0.0f) ? 0.0f : atan2f(dir[0], -dir[2]);
    float u = (phi + rotate) * (1.0f / (2.0f * PI_F));
    float y = fminf(fmaxf(dir[1], -1.0f), 1.0f);
    uv[0] = u - floorf(u);
    uv[1] = 1.0f - acosf(y) * (1.0f / PI_F);
}

/* The largest i in [0, n) with cdf[i] <= x, for cdf[0] = 0 <= x < 1 = cdf[n]: the segment
 * [cdf[i], cdf[i + 1]) that holds x, which has a positive width (zero-width segments of zero
 * weights are passed over, since x < cdf[i + 1]). */
static uint32_t cdf_find(const float *cdf, uint32_t n, float x)
{
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        uint32_t mid = (lo + hi + 1) / 2;
        if (cdf[mid] <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void vkrt_envmap_sample(const float *data, uint32_t width, uint32_t height, float u1, float u2,
                        float uv[2], float *pdf_uv)
{
    u1 = fminf(fmaxf(u1, 0.0f), ONE_MINUS_EPSILON);
    u2 = fminf(fmaxf(u2, 0.0f), ONE_MINUS_EPSILON);
    const float *marginal = data;
    uint32_t y = cdf_find(marginal, height, u1);
    float row_p = marginal[y + 1] - marginal[y];
    float fy = fminf((u1 - marginal[y]) / row_p, ONE_MINUS_EPSILON);

    const float *conditional = data + (height + 1) + (size_t)y * (width + 1);
    uint32_t x = cdf_find(conditional, width, u2);
    float texel_p = conditional[x + 1] - conditional[x];
    float fx = fminf((u2 - conditional[x]) / texel_p, ONE_MINUS_EPSILON);

    *pdf_uv = row_p * (float)height * texel_p * (float)width;
    uv[0] = ((float)x + fx) / (float)width;
    uv[1] = 1.0f - ((float)y + fy) / (float)height;
}

float vkrt_envmap_pdf_uv(const float *data, uint32_t width, uint32_t height, float u, float v)
{
    u -= floorf(u);
    float t = fminf(fmaxf(1.0f - v, 0.0f), 1.0f); /* theta / pi: rows are stored from the top */
    uint32_t x = (uint32_t)fminf(u * (float)width, (float)(width - 1));
    uint32_t y = (uint32_t)fminf(t * (float)height, (float)(height - 1));
    const float *marginal = data;
    const float *conditional = data + (height + 1) + (size_t)y * (width + 1);
    return (marginal[y + 1] - marginal[y]) * (float)height * (conditional[x + 1] - conditional[x]) *
           (float)width;
}

float vkrt_envmap_pdf(const float *data, uint32_t width, uint32_t height, float rotate,
                      const float dir[3])
{
    float sin_theta = sqrtf(dir[0] * dir[0] + dir[2] * dir[2]);
    if (!(sin_theta > 0.0f))
        return 0.0f;
    float uv[2];
    vkrt_envmap_uv(dir, rotate, uv);
    return vkrt_envmap_pdf_uv(data, width, height, uv[0], uv[1]) / (2.0f * PI_F * PI_F * sin_theta);
}
