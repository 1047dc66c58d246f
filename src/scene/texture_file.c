/* texture_file.c: an image's file found as a Windows-made scene names it, and why stb_image
 * could not decode one (see texture_file.h). */
#define _DEFAULT_SOURCE
#include "texture_file.h"

#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <stb_image.h>

/* "<referrer>: texture '<path>': <reason>", the referrer left out when there is none. */
#define fail(err, referrer, path, ...) \
    vkrt_error_set_file(err, referrer, "texture", path, __VA_ARGS__)

/* ---------------------------------------------------------------------------------------------
 * Finding the file
 * ------------------------------------------------------------------------------------------- */

static bool is_regular_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static char *join(const char *folder, const char *name)
{
    size_t n = strlen(folder) + 1 + strlen(name) + 1;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%s/%s", folder, name);
    return out;
}

/* Looks for the one file in path's folder whose name equals path's file name ignoring case.
 * Returns 1 with the match in *found, 0 if none, or the number of matches when several
 * (their first two names in names), or -1 if out of memory. */
static int match_ignoring_case(const char *path, char **found, char names[2][256])
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    char *folder = slash ? strndup(path, (size_t)(slash - path)) : strdup(".");
    if (!folder)
        return -1;
    if (slash && slash == path) { /* "/name": the root folder */
        free(folder);
        folder = strdup("/");
        if (!folder)
            return -1;
    }
    DIR *d = *base ? opendir(folder) : NULL;
    int matches = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        if (strcasecmp(e->d_name, base) != 0)
            continue;
        char *candidate = join(folder, e->d_name);
        if (!candidate) {
            matches = -1;
            break;
        }
        if (!is_regular_file(candidate)) {
            free(candidate);
            continue;
        }
        if (matches < 2)
            snprintf(names[matches], sizeof names[0], "%s", e->d_name);
        if (matches == 0)
            *found = candidate;
        else
            free(candidate);
        matches++;
    }
    if (d)
        closedir(d);
    free(folder);
    if (matches != 1) {
        free(*found);
        *found = NULL;
    }
    return matches;
}

/* The file path names: as written, else with backslashes read as '/', else the unique file of its
 * folder whose name matches ignoring case (see texture.h). Returns a malloc'ed path in *found, or
 * false with err set. */
bool vkrt_texture_find_file(const char *path, const char *referrer, char **found, vkrt_error *err)
{
    *found = NULL;
    struct stat st;
    if (stat(path, &st) == 0) {
        if (!S_ISREG(st.st_mode))
            return fail(err, referrer, path, "not a regular file");
        *found = strdup(path);
        return *found ? true : fail(err, referrer, path, "out of memory");
    }
    int stat_errno = errno;
    if (stat_errno != ENOENT && stat_errno != ENOTDIR)
        return fail(err, referrer, path, "cannot open: %s", strerror(stat_errno));

    char *slashed = strdup(path);
    if (!slashed)
        return fail(err, referrer, path, "out of memory");
    for (char *c = slashed; *c; c++)
        if (*c == '\\')
            *c = '/';
    if (strcmp(slashed, path) != 0 && is_regular_file(slashed)) {
        *found = slashed;
        return true;
    }
    char names[2][256];
    int matches = match_ignoring_case(slashed, found, names);
    free(slashed);
    if (matches == 1)
        return true;
    if (matches < 0)
        return fail(err, referrer, path, "out of memory");
    if (matches > 1)
        return fail(err, referrer, path,
                    "not found, and %d files match its name ignoring case ('%s', '%s'%s)", matches,
                    names[0], names[1], matches > 2 ? ", ..." : "");
    return fail(err, referrer, path, "cannot open: %s", strerror(stat_errno));
}

/* ---------------------------------------------------------------------------------------------
 * Why a decode failed
 * ------------------------------------------------------------------------------------------- */

static uint32_t big_endian32(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | (uint32_t)b[3];
}

/* Whether f is a PNG that ends before its IEND chunk, said in why. stb_image reads past the end
 * of a file as zeros, so for a PNG cut short it reports a chunk of type "\0\0\0\0" as unknown:
 * an empty reason. Walking the chunk headers (length, type, data, CRC) finds where it ends. */
static bool png_cut_short(FILE *f, char *why, size_t size)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    struct stat st;
    unsigned char head[8];
    if (fstat(fileno(f), &st) != 0 || fseek(f, 0, SEEK_SET) != 0 || fread(head, 1, 8, f) != 8 ||
        memcmp(head, signature, 8) != 0)
        return false;
    unsigned long long file_size = (unsigned long long)st.st_size, at = 8;
    for (;;) { /* every chunk takes 12 bytes or more, so this ends */
        unsigned char chunk[8];
        if (at + 8 > file_size || fseek(f, (long)at, SEEK_SET) != 0 || fread(chunk, 1, 8, f) != 8) {
            snprintf(why, size,
                     "the PNG file is cut short: it ends at byte %llu, before its IEND chunk",
                     file_size);
            return true;
        }
        for (int i = 4; i < 8; i++)
            if (!((chunk[i] >= 'A' && chunk[i] <= 'Z') || (chunk[i] >= 'a' && chunk[i] <= 'z')))
                return false; /* not a chunk type: damaged rather than short */
        unsigned long long end = at + 12 + big_endian32(chunk);
        if (end > file_size) {
            snprintf(why, size,
                     "the PNG file is cut short: it has %llu bytes, but its %.4s chunk at byte "
                     "%llu runs to byte %llu",
                     file_size, (const char *)chunk + 4, at, end);
            return true;
        }
        if (memcmp(chunk + 4, "IEND", 4) == 0)
            return false;
        at = end;
    }
}

/* stb_image's reasons are short codes ("outofdata", "bad huffman code"); this says what they mean
 * for the user, and whether the code adds anything (a damaged file's code names what is damaged;
 * "outofdata" says no more than "cut short"). NULL for a reason that is empty or not printable. */
static const char *meaning_of(const char *reason, bool *show_code)
{
    *show_code = false;
    if (!reason || !*reason)
        return NULL;
    for (const char *c = reason; *c; c++)
        if (*c < 0x20 || *c > 0x7E)
            return NULL;
    static const struct {
        const char *code, *meaning;
        bool show_code;
    } known[] = {
        {"outofdata", "the image data stops before the image is complete (the file is cut short or damaged)", false},
        {"read past buffer", "the image data stops before the image is complete (the file is cut short or damaged)", false},
        {"not enough pixels", "the image data stops before the image is complete (the file is cut short or damaged)", false},
        {"too large", "stb_image cannot decode an image this large in this format", true},
        {"output buffer limit", "stb_image cannot decode an image this large in this format", true},
        {"outofmem", "out of memory", false},
        {"only 8-bit", "a format variant stb_image does not support", true},
        {"1/2/4/8/16-bit only", "a format variant stb_image does not support", true},
        {"unknown image type", "a format stb_image does not support", false},
    };
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (strcmp(reason, known[i].code) == 0) {
            *show_code = known[i].show_code;
            return known[i].meaning;
        }
    *show_code = true;
    if (strstr(reason, "not known"))
        return "a format variant stb_image does not support";
    return "the image data is damaged";
}

/* Why stb_image failed to decode f, in why: a PNG cut short, else stb_image's reason with its
 * meaning, else that it gave none. */
void vkrt_texture_decode_failure(FILE *f, char *why, size_t size)
{
    const char *reason = stbi_failure_reason(); /* before png_cut_short reads anything */
    bool show_code;
    const char *meaning = meaning_of(reason, &show_code);
    if (png_cut_short(f, why, size))
        return;
    if (meaning && !show_code)
        snprintf(why, size, "%s", meaning);
    else if (meaning)
        snprintf(why, size, "%s (stb_image: %s)", meaning, reason);
    else
        snprintf(why, size, "the file is damaged or cut short (stb_image gives no reason)");
}

