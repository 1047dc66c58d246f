/*
 * cycles_compare.c: holds vkrt renders against a Cycles reference (tools/blender_scenes.py), for
 * tests/test_gltf_blender.sh.
 *
 *   cycles_compare iou CYCLES.png BLACK.png WHITE.png MIN_IOU MAX_WRONG
 *     The silhouette. Cycles' is its PNG's alpha (film transparent: the share of the pixel that
 *     geometry covers). vkrt's comes from two renders that differ only in the environment, 0 and
 *     1, with max-depth 0 and the Whitted integrator, so that no ray but a camera ray that misses
 *     sees it: a pixel's coverage is 1 - (WHITE - BLACK), the mean over its channels of the
 *     linear values (the PNGs decoded from sRGB), clamped to [0, 1].
 *     BLACK "-" is an image of zeros: WHITE alone where nothing lit is seen (no lights, no
 *     emission: every surface renders 0).
 *     Prints the soft IoU, sum(min(a, b)) / sum(max(a, b)) over the pixels (1 for identical
 *     masks, the plain IoU for binary ones), and the pixels whose coverage differs by more than
 *     half ("wrong"); exits 0 when the IoU is at least MIN_IOU and at most MAX_WRONG pixels are
 *     wrong. The count is what finds a small object out of place in a large silhouette: the IoU
 *     of a whole picture hardly moves for it (an edge pixel's coverage, from 16 samples or so,
 *     is within about 1/8 of the truth, never wrong by half).
 *   cycles_compare mean CYCLES.exr VKRT.exr MAX_RELATIVE
 *     The image means of R, G and B (linear radiance; Cycles' EXR is premultiplied, so its empty
 *     pixels are 0 as vkrt's black environment is). Prints both and their ratio; exits 0 when
 *     every channel's mean is within MAX_RELATIVE of Cycles' (relative to Cycles').
 * Both exit 1 on a failed check and 2 on bad arguments or unreadable files (the message says
 * which); the images must have the same size.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "scene/envmap.h"

static int usage(void)
{
    fprintf(stderr, "usage: cycles_compare iou CYCLES.png BLACK.png WHITE.png MIN_IOU MAX_WRONG\n"
                    "       cycles_compare mean CYCLES.exr VKRT.exr MAX_RELATIVE\n");
    return 2;
}

/* An 8-bit sRGB-encoded value as linear, in [0, 1] (the sRGB curve's inverse). */
static double srgb_to_linear(unsigned char value)
{
    double c = value / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static int compare_silhouettes(const char *cycles_path, const char *black_path,
                               const char *white_path, double min_iou, long max_wrong)
{
    int w[3], h[3], channels;
    unsigned char *cycles = stbi_load(cycles_path, &w[0], &h[0], &channels, 4);
    unsigned char *white = stbi_load(white_path, &w[2], &h[2], &channels, 3);
    unsigned char *black = NULL;
    if (strcmp(black_path, "-") != 0) {
        black = stbi_load(black_path, &w[1], &h[1], &channels, 3);
    } else if (white) {
        w[1] = w[2], h[1] = h[2];
        black = calloc((size_t)w[2] * h[2], 3);
    }
    int status = 2;
    if (!cycles || !black || !white) {
        fprintf(stderr, "cycles_compare: cannot read %s\n",
                !cycles ? cycles_path : !black ? black_path : white_path);
    } else if (w[1] != w[0] || h[1] != h[0] || w[2] != w[0] || h[2] != h[0]) {
        fprintf(stderr, "cycles_compare: sizes differ: %dx%d, %dx%d and %dx%d\n", w[0], h[0], w[1],
                h[1], w[2], h[2]);
    } else {
        size_t pixels = (size_t)w[0] * h[0], differing = 0;
        double intersection = 0, union_ = 0, covered_cycles = 0, covered_vkrt = 0;
        for (size_t i = 0; i < pixels; ++i) {
            double a = cycles[4 * i + 3] / 255.0, seen = 0;
            for (int c = 0; c < 3; ++c)
                seen += srgb_to_linear(white[3 * i + c]) - srgb_to_linear(black[3 * i + c]);
            double b = fmin(fmax(1.0 - seen / 3.0, 0.0), 1.0);
            intersection += fmin(a, b);
            union_ += fmax(a, b);
            covered_cycles += a;
            covered_vkrt += b;
            differing += fabs(a - b) > 0.5;
        }
        double iou = union_ > 0 ? intersection / union_ : 1.0;
        printf("silhouette IoU %.4f (at least %.4f); covered: Cycles %.1f, vkrt %.1f of %zu "
               "pixels; %zu wrong by more than half (at most %ld)\n",
               iou, min_iou, covered_cycles, covered_vkrt, pixels, differing, max_wrong);
        status = iou >= min_iou && differing <= (size_t)max_wrong ? 0 : 1;
    }
    stbi_image_free(cycles);
    if (strcmp(black_path, "-") != 0)
        stbi_image_free(black);
    else
        free(black);
    stbi_image_free(white);
    return status;
}

static int compare_means(const char *cycles_path, const char *vkrt_path, double max_relative)
{
    vkrt_envmap_image cycles = {0}, vkrt = {0};
    vkrt_error err;
    int status = 2;
    if (!vkrt_envmap_load(cycles_path, NULL, &cycles, &err) ||
        !vkrt_envmap_load(vkrt_path, NULL, &vkrt, &err)) {
        fprintf(stderr, "cycles_compare: %s\n", err.msg);
    } else if (cycles.width != vkrt.width || cycles.height != vkrt.height) {
        fprintf(stderr, "cycles_compare: sizes differ: %ux%u and %ux%u\n", cycles.width,
                cycles.height, vkrt.width, vkrt.height);
    } else {
        size_t pixels = (size_t)cycles.width * cycles.height;
        double sums[2][3] = {{0}};
        for (size_t i = 0; i < pixels; ++i) {
            for (int c = 0; c < 3; ++c) {
                sums[0][c] += cycles.rgb[3 * i + c];
                sums[1][c] += vkrt.rgb[3 * i + c];
            }
        }
        status = 0;
        printf("means (R G B): Cycles");
        for (int c = 0; c < 3; ++c)
            printf(" %.5f", sums[0][c] / pixels);
        printf(", vkrt");
        for (int c = 0; c < 3; ++c)
            printf(" %.5f", sums[1][c] / pixels);
        printf(", vkrt / Cycles");
        for (int c = 0; c < 3; ++c) {
            double ratio = sums[0][c] > 0 ? sums[1][c] / sums[0][c] : (sums[1][c] > 0 ? INFINITY : 1);
            printf(" %.4f", ratio);
            if (!(fabs(ratio - 1.0) <= max_relative))
                status = 1;
        }
        printf(" (within %.3f)\n", max_relative);
    }
    vkrt_envmap_image_free(&cycles);
    vkrt_envmap_image_free(&vkrt);
    return status;
}

int main(int argc, char **argv)
{
    if (argc == 7 && strcmp(argv[1], "iou") == 0)
        return compare_silhouettes(argv[2], argv[3], argv[4], atof(argv[5]), atol(argv[6]));
    if (argc == 5 && strcmp(argv[1], "mean") == 0)
        return compare_means(argv[2], argv[3], atof(argv[4]));
    return usage();
}
