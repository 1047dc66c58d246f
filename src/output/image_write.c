/*
 * image_write.c: writes rendered frames, finished by finish.h, as PNG (8-bit sRGB, png_encode.h) or
 * EXR (32-bit float linear RGB, via OpenEXRCore), with their AOVs (layers of the EXR, or files
 * beside the PNG), and expands frame-number patterns in output paths.
 *
 * Both formats go through the same temporary-file discipline: the bytes are written to
 * "<path>.tmp-<host>-<pid>" (temporary.h) beside the target (same folder, so rename() is atomic), and only a
 * complete, closed file is renamed onto path. Any failure unlinks the temporary file, so a
 * failed or interrupted write never leaves a truncated image or clobbers an older one.
 */
#define _POSIX_C_SOURCE 200809L

#include "image_write.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <openexr.h>

#include "png_encode.h"
#include "temporary.h"

/* ---------------------------------------------------------------------------------------------
 * Format detection
 * ------------------------------------------------------------------------------------------- */

static bool ends_with_ignoring_case(const char *text, const char *suffix)
{
    size_t text_len = strlen(text), suffix_len = strlen(suffix);
    if (text_len < suffix_len)
        return false;
    const char *tail = text + text_len - suffix_len;
    for (size_t i = 0; i < suffix_len; i++) {
        if (tolower((unsigned char)tail[i]) != tolower((unsigned char)suffix[i]))
            return false;
    }
    return true;
}

vkrt_image_format vkrt_image_format_of(const char *path)
{
    if (!path)
        return VKRT_IMAGE_UNKNOWN;
    if (ends_with_ignoring_case(path, ".png"))
        return VKRT_IMAGE_PNG;
    if (ends_with_ignoring_case(path, ".exr"))
        return VKRT_IMAGE_EXR;
    return VKRT_IMAGE_UNKNOWN;
}

/* ---------------------------------------------------------------------------------------------
 * Temporary file beside the target
 * ------------------------------------------------------------------------------------------- */

typedef struct temp_file {
    const char *target_path; /* the final name, used in every error message */
    char *temp_path;         /* "<target>.tmp-<host>-<pid>", heap-allocated */
    int fd;                  /* -1 once closed */
} temp_file;

static bool temp_file_open(temp_file *tf, const char *target_path, vkrt_error *err)
{
    tf->target_path = target_path;
    tf->fd = -1;
    /* The host (at most 255 characters) and the pid (at most 20), ".tmp-", '-' and NUL. */
    size_t size = strlen(target_path) + 300;
    tf->temp_path = malloc(size);
    if (!tf->temp_path)
        return vkrt_error_set(err, "%s: cannot write: out of memory", target_path);
    vkrt_temporary_name(tf->temp_path, size, target_path);

    /* O_TRUNC rather than O_EXCL: a leftover from an earlier crashed run with the same pid is
     * ours to overwrite. 0666 lets the umask decide, like any other file the user creates. */
    tf->fd = open(tf->temp_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (tf->fd < 0) {
        int saved = errno;
        free(tf->temp_path);
        tf->temp_path = NULL;
        return vkrt_error_set(err, "%s: cannot write: %s", target_path, strerror(saved));
    }
    return true;
}

/* write_all's offset for "where the file position is" (the PNG stream writes in order). */
#define AT_FILE_POSITION ((off_t)-1)

/* Writes all of data, retrying short writes and EINTR: at the file position when offset is
 * AT_FILE_POSITION, else at that absolute offset (OpenEXRCore seeks back to fill the offset
 * table). Returns 0 or the errno of the failure. */
static int write_all(int fd, const void *data, size_t size, off_t offset)
{
    const unsigned char *bytes = data;
    while (size > 0) {
        ssize_t n =
            offset == AT_FILE_POSITION ? write(fd, bytes, size) : pwrite(fd, bytes, size, offset);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return errno;
        }
        if (n == 0)
            return EIO;
        bytes += n;
        size -= (size_t)n;
        if (offset != AT_FILE_POSITION)
            offset += n;
    }
    return 0;
}

/* Throws the temporary file away; used on every failure path, so it never reports. */
static void temp_file_discard(temp_file *tf)
{
    if (tf->fd >= 0)
        close(tf->fd);
    tf->fd = -1;
    if (tf->temp_path)
        unlink(tf->temp_path);
    free(tf->temp_path);
    tf->temp_path = NULL;
}

/* Closes the complete file and renames it onto the target. close() is checked because NFS
 * and friends report delayed write errors there; on any failure the temp file is removed. */
static bool temp_file_commit(temp_file *tf, vkrt_error *err)
{
    int fd = tf->fd;
    tf->fd = -1;
    if (close(fd) != 0) {
        int saved = errno;
        temp_file_discard(tf);
        return vkrt_error_set(err, "%s: cannot write: %s", tf->target_path, strerror(saved));
    }
    if (rename(tf->temp_path, tf->target_path) != 0) {
        int saved = errno;
        temp_file_discard(tf);
        return vkrt_error_set(err, "%s: cannot write: %s", tf->target_path, strerror(saved));
    }
    free(tf->temp_path);
    tf->temp_path = NULL;
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * PNG
 * ------------------------------------------------------------------------------------------- */

static bool png_size_fits(uint32_t width, uint32_t height)
{
    return width <= (uint32_t)INT32_MAX && height <= (uint32_t)INT32_MAX; /* PNG's limits */
}

/* Where the PNG encoder's bytes go: straight into the temp file, keeping the errno of a failed
 * write for the message. */
typedef struct png_file_sink {
    int fd;
    int error;
} png_file_sink;

static bool png_file_sink_write(void *context, const void *data, size_t size)
{
    png_file_sink *sink = context;
    sink->error = write_all(sink->fd, data, size, AT_FILE_POSITION);
    return sink->error == 0;
}

/* Encodes 8-bit RGB (size already checked) into path through a temporary file. */
static bool write_png8(const char *path, uint32_t width, uint32_t height, const uint8_t *srgb8,
                       vkrt_error *err)
{
    temp_file tf;
    if (!temp_file_open(&tf, path, err))
        return false;
    png_file_sink sink = {.fd = tf.fd, .error = 0};
    png_encode_result result = png_encode_rgb8(srgb8, width, height, png_file_sink_write, &sink);
    if (result != PNG_ENCODE_OK) {
        temp_file_discard(&tf);
        return result == PNG_ENCODE_SINK_FAILED
                   ? vkrt_error_set(err, "%s: cannot write: %s", path, strerror(sink.error))
               : result == PNG_ENCODE_NO_MEMORY
                   ? vkrt_error_set(err, "%s: cannot write: out of memory", path)
                   : vkrt_error_set(err, "%s: cannot write: the PNG encoder failed", path);
    }
    return temp_file_commit(&tf, err);
}

/* The albedo and normal the finish stage's denoiser is guided by: those written, else the
 * guides alone. */
static const float *guide_albedo(const vkrt_frame_image *frame)
{
    return frame->albedo ? frame->albedo : frame->guide_albedo;
}

static const float *guide_normal(const vkrt_frame_image *frame)
{
    return frame->normal ? frame->normal : frame->guide_normal;
}

/* frame's beauty as an 8-bit PNG, through the finish stage (which may denoise it with the
 * frame's albedo and normal). */
static bool write_png(const char *path, const vkrt_frame_image *frame,
                      const vkrt_finish_desc *finish, vkrt_error *err)
{
    uint32_t width = frame->width, height = frame->height;
    if (!png_size_fits(width, height))
        return vkrt_error_set(err, "%s: image %" PRIu32 "x%" PRIu32 " is too large for PNG",
                              path, width, height);

    size_t value_count = (size_t)width * height * 3;
    uint8_t *srgb8 = malloc(value_count);
    if (!srgb8)
        return vkrt_error_set(err, "%s: cannot write: out of memory", path);
    vkrt_finish_frame finishing = {.width = width, .height = height, .rgb = frame->rgb,
                                   .albedo = guide_albedo(frame), .normal = guide_normal(frame)};
    bool ok = vkrt_finish_srgb8(finish, &finishing, srgb8, err);
    if (!ok)
        vkrt_error_prefix(err, "%s: cannot write", path);
    ok = ok && write_png8(path, width, height, srgb8, err);
    free(srgb8);
    return ok;
}

/* ---------------------------------------------------------------------------------------------
 * EXR
 * ------------------------------------------------------------------------------------------- */

/* State shared with OpenEXRCore's callbacks through the context's user_data (no globals). */
typedef struct exr_stream {
    int fd;
    int write_errno;      /* errno of the first failed write, 0 if none */
    char library_msg[256]; /* the library's most recent detailed message, "" if none */
} exr_stream;

static int64_t exr_stream_write(exr_const_context_t ctxt, void *userdata, const void *buffer,
                                uint64_t size, uint64_t offset,
                                exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb; /* we keep errno ourselves, so the message can say what really went wrong */
    exr_stream *stream = userdata;
    if (size > (uint64_t)SSIZE_MAX || offset > (uint64_t)INT64_MAX) {
        stream->write_errno = EFBIG;
        return -1;
    }
    int error = write_all(stream->fd, buffer, (size_t)size, (off_t)offset);
    if (error != 0) {
        if (stream->write_errno == 0)
            stream->write_errno = error;
        return -1;
    }
    return (int64_t)size;
}

/* Replaces the library's default handler, which prints to stderr: library code must not
 * print, so the message is kept and becomes part of the returned error. */
static void exr_keep_error_message(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)code;
    void *userdata = NULL;
    if (!ctxt || exr_get_user_data(ctxt, &userdata) != EXR_ERR_SUCCESS || !userdata)
        return;
    exr_stream *stream = userdata;
    snprintf(stream->library_msg, sizeof stream->library_msg, "%s", msg ? msg : "");
}

/* Turns a failed OpenEXRCore call into "path: cannot write: why", preferring the errno of a
 * failed write, then the library's detailed text, then its generic text for the code. */
static bool exr_failure(const char *path, const exr_stream *stream, exr_result_t rv,
                        vkrt_error *err)
{
    if (stream->write_errno != 0)
        return vkrt_error_set(err, "%s: cannot write: %s", path, strerror(stream->write_errno));
    if (stream->library_msg[0] != '\0')
        return vkrt_error_set(err, "%s: cannot write EXR: %s", path, stream->library_msg);
    return vkrt_error_set(err, "%s: cannot write EXR: %s", path,
                          exr_get_default_error_message(rv));
}

/* One float channel of the EXR, read from the caller's buffers: its value at pixel i is
 * first[i * stride] (the top row first). */
typedef struct exr_source {
    const char *name;
    const float *first;
    int32_t stride; /* floats from one pixel's value to the next's */
} exr_source;

/* Declares the single scanline part with the given float channels (OpenEXRCore keeps them in the
 * sorted order EXR requires), data and display window 0..w-1 x 0..h-1, increasing y (top row
 * first, as ours). */
static exr_result_t exr_define_part(exr_context_t ctxt, uint32_t width, uint32_t height,
                                    const exr_source *sources, size_t count)
{
    int part_index = 0;
    exr_result_t rv = exr_add_part(ctxt, "rgb", EXR_STORAGE_SCANLINE, &part_index);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    rv = exr_initialize_required_attr_simple(ctxt, part_index, (int32_t)width, (int32_t)height,
                                             EXR_COMPRESSION_ZIP);
    for (size_t c = 0; c < count && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(ctxt, part_index, sources[c].name, EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    return rv;
}

/* The source of a channel by name, or NULL for a name we did not add. */
static const exr_source *exr_source_of(const char *name, const exr_source *sources, size_t count)
{
    for (size_t c = 0; c < count; c++)
        if (strcmp(name, sources[c].name) == 0)
            return &sources[c];
    return NULL;
}

/* Compresses and writes the chunk that starts at row y, reading straight from the caller's
 * buffers through strides (no copy). */
static exr_result_t exr_encode_chunk(exr_context_t ctxt, int32_t y, uint32_t width,
                                     const exr_source *sources, size_t count)
{
    exr_chunk_info_t chunk;
    exr_result_t rv = exr_write_scanline_chunk_info(ctxt, 0, y, &chunk);
    if (rv != EXR_ERR_SUCCESS)
        return rv;

    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    rv = exr_encoding_initialize(ctxt, 0, &chunk, &encoder);
    for (int16_t c = 0; c < encoder.channel_count && rv == EXR_ERR_SUCCESS; c++) {
        exr_coding_channel_info_t *channel = &encoder.channels[c];
        const exr_source *source = exr_source_of(channel->channel_name, sources, count);
        if (!source) {
            rv = EXR_ERR_INVALID_ARGUMENT;
            break;
        }
        size_t first_row = (size_t)chunk.start_y * width * (size_t)source->stride;
        channel->encode_from_ptr = (const uint8_t *)(source->first + first_row);
        channel->user_data_type = EXR_PIXEL_FLOAT;
        channel->user_bytes_per_element = (int16_t)sizeof(float);
        channel->user_pixel_stride = (int32_t)(source->stride * sizeof(float));
        channel->user_line_stride = (int32_t)(width * source->stride * sizeof(float));
    }
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_encoding_choose_default_routines(ctxt, 0, &encoder);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_encoding_run(ctxt, 0, &encoder);
    /* destroy is safe on a pipeline that initialize left zeroed or half-filled */
    exr_result_t destroy_rv = exr_encoding_destroy(ctxt, &encoder);
    return rv != EXR_ERR_SUCCESS ? rv : destroy_rv;
}

static exr_result_t exr_write_all_chunks(exr_context_t ctxt, uint32_t width, uint32_t height,
                                         const exr_source *sources, size_t count)
{
    int32_t lines_per_chunk = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines_per_chunk);
    if (rv == EXR_ERR_SUCCESS && lines_per_chunk <= 0)
        rv = EXR_ERR_INVALID_ARGUMENT;
    for (int64_t y = 0; y < (int64_t)height && rv == EXR_ERR_SUCCESS; y += lines_per_chunk)
        rv = exr_encode_chunk(ctxt, (int32_t)y, width, sources, count);
    return rv;
}

static bool exr_size_fits(uint32_t width, uint32_t height)
{
    /* EXR windows are int32, and the encoder's line stride (width * 12 bytes) is int32 too. */
    return height <= (uint32_t)INT32_MAX && (uint64_t)width * 3 * sizeof(float) <= INT32_MAX;
}

static bool write_exr(const char *path, uint32_t width, uint32_t height,
                      const exr_source *sources, size_t count, vkrt_error *err)
{
    if (!exr_size_fits(width, height))
        return vkrt_error_set(err, "%s: image %" PRIu32 "x%" PRIu32 " is too large for EXR",
                              path, width, height);

    temp_file tf;
    if (!temp_file_open(&tf, path, err))
        return false;

    /* A custom write function on our own descriptor, rather than the library's file mode,
     * so both formats share one temp-and-rename path and a failed write reports its errno. */
    exr_stream stream = {.fd = tf.fd, .write_errno = 0, .library_msg = ""};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &stream;
    init.write_fn = exr_stream_write;
    init.error_handler_fn = exr_keep_error_message;

    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_define_part(ctxt, width, height, sources, count);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_all_chunks(ctxt, width, height, sources, count);
    /* exr_finish writes the chunk offset table, so its result matters even after success. */
    if (ctxt) {
        exr_result_t finish_rv = exr_finish(&ctxt);
        if (rv == EXR_ERR_SUCCESS)
            rv = finish_rv;
    }

    if (rv != EXR_ERR_SUCCESS || stream.write_errno != 0) {
        temp_file_discard(&tf);
        return exr_failure(path, &stream, rv, err);
    }
    return temp_file_commit(&tf, err);
}

/* ---------------------------------------------------------------------------------------------
 * Entry point
 * ------------------------------------------------------------------------------------------- */

/* ---------------------------------------------------------------------------------------------
 * AOVs (--aov): layers of the EXR, or files beside the PNG
 * ------------------------------------------------------------------------------------------- */

/* Appends a layer's channels (names, NULL-terminated): channel k at values + k, values holding
 * as many floats a pixel as there are names. */
static void add_layer(exr_source *sources, size_t *count, const char *const *names,
                      const float *values)
{
    int32_t stride = 0;
    while (names[stride])
        ++stride;
    for (int32_t k = 0; k < stride; ++k)
        sources[(*count)++] = (exr_source){names[k], values + k, stride};
}

/* The channel names of each layer, as Nuke names a layer's channels (layer.channel) and as
 * Blender reads passes of a layer without a name (pass.channel, beside R, G, B, its Combined). */
static const char *const beauty_channels[] = {"R", "G", "B", NULL};
static const char *const albedo_channels[] = {"albedo.R", "albedo.G", "albedo.B", NULL};
static const char *const normal_channels[] = {"normal.X", "normal.Y", "normal.Z", NULL};
static const char *const depth_channels[] = {"depth.Z", NULL};
static const char *const position_channels[] = {"position.X", "position.Y", "position.Z", NULL};
/* The radiance rendered, kept beside a denoised beauty (--denoise). */
static const char *const noisy_channels[] = {"noisy.R", "noisy.G", "noisy.B", NULL};

enum { MAX_CHANNELS = 16 };

/* The channels of frame's EXR: the beauty (rgb: the finished radiance), the radiance rendered
 * where the finish stage denoised it (noisy), and every AOV the frame has. */
static size_t frame_channels(const vkrt_frame_image *frame, const float *rgb, const float *noisy,
                             exr_source sources[MAX_CHANNELS])
{
    size_t count = 0;
    add_layer(sources, &count, beauty_channels, rgb);
    if (noisy)
        add_layer(sources, &count, noisy_channels, noisy);
    if (frame->albedo)
        add_layer(sources, &count, albedo_channels, frame->albedo);
    if (frame->normal)
        add_layer(sources, &count, normal_channels, frame->normal);
    if (frame->depth)
        add_layer(sources, &count, depth_channels, frame->depth);
    if (frame->position)
        add_layer(sources, &count, position_channels, frame->position);
    return count;
}

/* Where AOV `name` of the image at path goes beside it: path without its extension, then
 * ".name.extension" ("shot.png" -> "shot.albedo.png"). */
static bool beside_path(char *out, size_t size, const char *path, const char *name,
                        const char *extension, vkrt_error *err)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - path) : strlen(path);
    int n = snprintf(out, size, "%.*s.%s.%s", (int)stem, path, name, extension);
    if (n < 0 || (size_t)n >= size)
        return vkrt_error_set(err, "%s: the path of its %s image is too long", path, name);
    return true;
}

/* A unit-range vector a pixel as 8-bit codes, 0.5 v + 0.5 (a normal map's convention: -1 is 0,
 * +1 is 255, 0 is 128), no transfer curve. */
static void vectors_to_codes(const float *v, size_t count, uint8_t *codes)
{
    for (size_t i = 0; i < count; ++i) {
        /* In double: the nearest code to the exact value, also where it is near a half. */
        double x = 0.5 * v[i] + 0.5;
        x = x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0; /* NaN to 0 too */
        codes[i] = (uint8_t)lrint(255.0 * x);
    }
}

/* The AOVs of frame as files beside the 8-bit picture at path: albedo as an sRGB PNG (a colour,
 * encoded as the beauty is but without its exposure), normal as a PNG of 0.5 n + 0.5, depth and
 * position as float EXRs (no 8-bit range holds distances), their channels named as in a
 * frame's EXR. */
static bool write_aovs_beside(const char *path, const vkrt_frame_image *frame, vkrt_error *err)
{
    uint32_t w = frame->width, h = frame->height;
    size_t values = (size_t)w * h * 3;
    char beside[4096];
    uint8_t *codes = frame->albedo || frame->normal ? malloc(values) : NULL;
    if ((frame->albedo || frame->normal) && !codes)
        return vkrt_error_set(err, "%s: cannot write its AOVs: out of memory", path);
    bool ok = true;
    if (ok && frame->albedo)
        ok = beside_path(beside, sizeof beside, path, "albedo", "png", err) &&
             vkrt_finish_srgb8(&(vkrt_finish_desc){0},
                               &(vkrt_finish_frame){.width = w, .height = h, .rgb = frame->albedo},
                               codes, err) &&
             write_png8(beside, w, h, codes, err);
    if (ok && frame->normal) {
        vectors_to_codes(frame->normal, values, codes);
        ok = beside_path(beside, sizeof beside, path, "normal", "png", err) &&
             write_png8(beside, w, h, codes, err);
    }
    free(codes);
    struct {
        const char *name;
        const float *values;
        const char *const *channels;
    } floats[] = {{"depth", frame->depth, depth_channels},
                  {"position", frame->position, position_channels}};
    for (size_t k = 0; ok && k < sizeof floats / sizeof *floats; ++k) {
        if (!floats[k].values)
            continue;
        exr_source sources[MAX_CHANNELS];
        size_t count = 0;
        add_layer(sources, &count, floats[k].channels, floats[k].values);
        ok = beside_path(beside, sizeof beside, path, floats[k].name, "exr", err) &&
             write_exr(beside, w, h, sources, count, err);
    }
    return ok;
}

/* ---------------------------------------------------------------------------------------------
 * Entry point
 * ------------------------------------------------------------------------------------------- */

bool vkrt_image_write_layers(const char *path, const vkrt_frame_image *frame,
                             const vkrt_finish_desc *finish, vkrt_error *err)
{
    uint32_t width = frame->width, height = frame->height;
    if (!path || path[0] == '\0')
        return vkrt_error_set(err, "cannot write image: empty output path");
    if (width == 0 || height == 0 || !frame->rgb)
        return vkrt_error_set(err, "%s: cannot write an empty image (%" PRIu32 "x%" PRIu32 ")",
                              path, width, height);
    if ((uint64_t)width * height > SIZE_MAX / (3 * sizeof(float)))
        return vkrt_error_set(err, "%s: image %" PRIu32 "x%" PRIu32 " is too large", path,
                              width, height);

    float *scratch = NULL;
    const float *linear;
    bool ok;
    switch (vkrt_image_format_of(path)) {
    case VKRT_IMAGE_PNG:
        /* The AOVs first: a complete beauty (what --resume checks) has them complete beside. */
        return write_aovs_beside(path, frame, err) &&
               write_png(path, frame, finish, err);
    case VKRT_IMAGE_EXR:
        linear = vkrt_finish_linear(finish,
                                    &(vkrt_finish_frame){.width = width, .height = height,
                                                         .rgb = frame->rgb,
                                                         .albedo = guide_albedo(frame),
                                                         .normal = guide_normal(frame)},
                                    &scratch, err);
        if (!linear)
            return vkrt_error_prefix(err, "%s: cannot write", path);
        exr_source sources[MAX_CHANNELS];
        /* Denoised: the beauty is the denoiser's, and the radiance rendered stays beside it. */
        size_t count = frame_channels(frame, linear, finish->denoiser ? frame->rgb : NULL, sources);
        ok = write_exr(path, width, height, sources, count, err);
        free(scratch);
        return ok;
    case VKRT_IMAGE_UNKNOWN:
    default:
        return vkrt_error_set(err, "%s: unknown image format (use .png or .exr)", path);
    }
}

bool vkrt_image_write_frame(const char *path, uint32_t width, uint32_t height, const float *rgb,
                            const vkrt_finish_desc *finish, vkrt_error *err)
{
    vkrt_frame_image frame = {.width = width, .height = height, .rgb = rgb};
    return vkrt_image_write_layers(path, &frame, finish, err);
}

bool vkrt_image_write(const char *path, uint32_t width, uint32_t height, const float *rgb,
                      float exposure, vkrt_error *err)
{
    return vkrt_image_write_frame(path, width, height, rgb,
                                  &(vkrt_finish_desc){.exposure = exposure}, err);
}

bool vkrt_image_write_png8(const char *path, uint32_t width, uint32_t height, const uint8_t *rgb,
                           vkrt_error *err)
{
    if (!path || path[0] == '\0')
        return vkrt_error_set(err, "cannot write image: empty output path");
    if (width == 0 || height == 0 || !rgb)
        return vkrt_error_set(err, "%s: cannot write an empty image (%" PRIu32 "x%" PRIu32 ")",
                              path, width, height);
    if (vkrt_image_format_of(path) != VKRT_IMAGE_PNG)
        return vkrt_error_set(err, "%s: 8-bit pixels are written as PNG only", path);
    if (!png_size_fits(width, height))
        return vkrt_error_set(err, "%s: image %" PRIu32 "x%" PRIu32 " is too large for PNG",
                              path, width, height);
    return write_png8(path, width, height, rgb, err);
}

/* ---------------------------------------------------------------------------------------------
 * Frame patterns
 *
 * The pattern is user input, so it is parsed here and never handed to printf: only "%%" and
 * one integer conversion "%d", "%Nd" or "%0Nd" (N of one or two digits) are accepted.
 * ------------------------------------------------------------------------------------------- */

typedef struct frame_conversion {
    size_t length;   /* characters the conversion spans in the pattern, '%' to 'd' */
    bool zero_pad;   /* "%0Nd" */
    int width;       /* N, 0 if absent */
} frame_conversion;

/* Parses the conversion that starts at the '%' at text[0]. Returns false if it is not one we
 * accept; "%%" is handled by the caller. */
static bool parse_frame_conversion(const char *text, frame_conversion *conv)
{
    size_t i = 1;
    conv->zero_pad = text[i] == '0';
    if (conv->zero_pad)
        i++;
    conv->width = 0;
    int digits = 0;
    while (isdigit((unsigned char)text[i]) && digits < 2) {
        conv->width = conv->width * 10 + (text[i] - '0');
        i++;
        digits++;
    }
    if (text[i] != 'd')
        return false;
    if (conv->zero_pad && digits == 0)
        return false; /* "%0d" is legal printf but almost certainly a typo for "%04d" */
    conv->length = i + 1;
    return true;
}

/* Shortens an offending conversion for an error message: "%" plus up to 3 more characters. */
static int conversion_excerpt_length(const char *text)
{
    int n = 1;
    while (n < 4 && text[n] != '\0')
        n++;
    return n;
}

bool vkrt_frame_pattern_has_number(const char *pattern)
{
    if (!pattern)
        return false;
    for (size_t i = 0; pattern[i] != '\0'; i++) {
        if (pattern[i] != '%')
            continue;
        if (pattern[i + 1] == '%') {
            i++;
            continue;
        }
        frame_conversion conv;
        if (parse_frame_conversion(pattern + i, &conv))
            return true;
    }
    return false;
}

/* Appends text of length n to out at *used, failing if it (plus the NUL) would not fit. */
static bool append(char *out, size_t out_size, size_t *used, const char *text, size_t n)
{
    if (n >= out_size - *used)
        return false;
    memcpy(out + *used, text, n);
    *used += n;
    out[*used] = '\0';
    return true;
}

static size_t format_frame_number(char *buf, size_t buf_size, const frame_conversion *conv,
                                  uint32_t frame)
{
    /* The format string here is ours, never the user's. */
    int n = conv->zero_pad ? snprintf(buf, buf_size, "%0*lu", conv->width, (unsigned long)frame)
                           : snprintf(buf, buf_size, "%*lu", conv->width, (unsigned long)frame);
    return n < 0 ? 0 : (size_t)n;
}

bool vkrt_frame_path(char *out, size_t out_size, const char *pattern, uint32_t frame,
                     vkrt_error *err)
{
    if (!out || out_size == 0 || !pattern)
        return vkrt_error_set(err, "frame pattern: no pattern or output buffer");
    out[0] = '\0';
    size_t used = 0;
    bool number_done = false;

    for (size_t i = 0; pattern[i] != '\0';) {
        bool fits;
        if (pattern[i] != '%') {
            size_t run = strcspn(pattern + i, "%");
            fits = append(out, out_size, &used, pattern + i, run);
            i += run;
        } else if (pattern[i + 1] == '%') {
            fits = append(out, out_size, &used, "%", 1);
            i += 2;
        } else {
            frame_conversion conv;
            if (!parse_frame_conversion(pattern + i, &conv))
                return vkrt_error_set(err,
                                      "frame pattern \"%s\": unsupported conversion \"%.*s\" "
                                      "(use %%d, %%04d or %%%% for a literal %%)",
                                      pattern, conversion_excerpt_length(pattern + i),
                                      pattern + i);
            if (number_done)
                return vkrt_error_set(err, "frame pattern \"%s\": more than one frame number",
                                      pattern);
            char number[128];
            size_t n = format_frame_number(number, sizeof number, &conv, frame);
            fits = append(out, out_size, &used, number, n);
            number_done = true;
            i += conv.length;
        }
        if (!fits) {
            out[0] = '\0';
            return vkrt_error_set(err, "frame pattern \"%s\": path for frame %" PRIu32
                                       " is longer than %zu characters",
                                  pattern, frame, out_size - 1);
        }
    }
    return true;
}
