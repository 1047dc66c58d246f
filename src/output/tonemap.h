/*
 * tonemap.h: the tone curves of 8-bit output (scene.cfg `tonemap`, --tonemap): linear radiance,
 * exposure already applied, to linear display values in [0, 1] that the sRGB encode then turns
 * into code values (finish.h runs it as a pass). The curves and their sources are in
 * glsl/tone_curves.h, whose constants glsl/display.comp uses too, so that the window shows what a
 * PNG holds.
 */
#ifndef VKRT_TONEMAP_H
#define VKRT_TONEMAP_H

#include <stddef.h>

#include "../scene/config.h"

/* One pixel through curve: out is in [0, 1] for every input, black when a channel of in is NaN
 * or when none is above 0, and grey inputs (r = g = b) give outputs that never fall as the grey
 * rises. in and out may be the same array. VKRT_TONEMAP_NONE copies in to out (the encode
 * clips). */
void tonemap_pixel(vkrt_tonemap curve, const float in[3], float out[3]);

/* tonemap_pixel on each of `pixels` RGB triples of rgb, in place. */
void tonemap_image(vkrt_tonemap curve, float *rgb, size_t pixels);

#endif
