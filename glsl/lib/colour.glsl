/*
 * colour.glsl: what the kernels need to know of colour: the luminance that weighs lights, lobes
 * and emitters (the same weights as src/scene/emitters.c, so the alias table's powers and the
 * kernels' densities agree).
 */
#ifndef VKRT_COLOUR_GLSL
#define VKRT_COLOUR_GLSL

/* The relative luminance of linear Rec. 709 RGB (the weights of lights and lobes). */
float luminance(vec3 c)
{
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

#endif
