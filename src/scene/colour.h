/*
 * colour.h: the luminance that weighs lights and emitters on the host: the weights of
 * glsl/lib/colour.glsl, so the emitters' alias table, the environment map's distribution and the
 * integrator's choice all agree with the kernels' densities. Header only: one line of arithmetic.
 */
#ifndef VKRT_COLOUR_H
#define VKRT_COLOUR_H

/* The relative luminance of linear Rec. 709 RGB, in double. */
static inline double vkrt_luminance(const float rgb[3])
{
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

#endif
