/* image_check.c: completeness checks of frames on disk (see image_check.h). */
#define _POSIX_C_SOURCE 200809L
#include "image_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <openexr.h>

#include "image_write.h"

static uint32_t big_endian32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static bool png_is_complete(const char *path, uint32_t width, uint32_t height)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    /* The IEND chunk: length 0, type, CRC; a PNG written to its end finishes with these bytes. */
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    unsigned char head[24], tail[12];
    bool ok = fread(head, 1, sizeof head, f) == sizeof head &&
              memcmp(head, signature, sizeof signature) == 0 && memcmp(head + 12, "IHDR", 4) == 0 &&
              big_endian32(head + 16) == width && big_endian32(head + 20) == height &&
              fseek(f, -(long)sizeof tail, SEEK_END) == 0 &&
              fread(tail, 1, sizeof tail, f) == sizeof tail && memcmp(tail, iend, sizeof iend) == 0;
    fclose(f);
    return ok;
}

static void quiet_exr_errors(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    (void)code;
    (void)msg;
}

static bool exr_is_complete(const char *path, uint32_t width, uint32_t height)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return false;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_exr_errors;
    exr_context_t ctxt;
    if (exr_start_read(&ctxt, path, &init) != EXR_ERR_SUCCESS)
        return false;
    exr_attr_box2i_t window;
    int32_t chunks = 0, lines_per_chunk = 0;
    bool ok = exr_get_data_window(ctxt, 0, &window) == EXR_ERR_SUCCESS &&
              (uint32_t)(window.max.x - window.min.x + 1) == width &&
              (uint32_t)(window.max.y - window.min.y + 1) == height &&
              exr_get_chunk_count(ctxt, 0, &chunks) == EXR_ERR_SUCCESS &&
              exr_get_scanlines_per_chunk(ctxt, 0, &lines_per_chunk) == EXR_ERR_SUCCESS &&
              lines_per_chunk > 0;
    for (int32_t c = 0; ok && c < chunks; ++c) {
        exr_chunk_info_t info;
        ok = exr_read_scanline_chunk_info(ctxt, 0, window.min.y + c * lines_per_chunk, &info) ==
                 EXR_ERR_SUCCESS &&
             info.data_offset + info.packed_size <= (uint64_t)st.st_size;
    }
    exr_finish(&ctxt);
    return ok;
}

bool vkrt_image_is_complete(const char *path, uint32_t width, uint32_t height)
{
    switch (vkrt_image_format_of(path)) {
    case VKRT_IMAGE_PNG:
        return png_is_complete(path, width, height);
    case VKRT_IMAGE_EXR:
        return exr_is_complete(path, width, height);
    default:
        return false;
    }
}
