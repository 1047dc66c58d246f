/*
 * display.comp: the viewer's last pass (src/view/display.c). Turns the renderer's image (a sum of
 * sample passes per pixel, vec4) into the 8-bit sRGB pixels of a window: the average, times
 * 2^exposure, through the tone curve (glsl/tone_curves.h; none: clamped), through the sRGB curve,
 * as a PNG of `vkrt render` gets them (src/output/finish.h). The pixels are packed in the byte
 * order of the swapchain's format, and copied into its image afterwards: a copy works on any
 * swapchain, where storage-image use is optional.
 *
 * One invocation per window pixel; the window may differ in size from the image (while a resize
 * is waiting for the renderer to follow), and then shows it scaled, nearest pixel.
 */
#include "shared.h"
#include "tone_curves.h"

layout(local_size_x_id = VKRT_SPEC_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = VKRT_DISPLAY_BINDING_IMAGE) readonly buffer ImageBuffer { vec4 image[]; };
layout(std430, set = 0, binding = VKRT_DISPLAY_BINDING_WINDOW) writeonly buffer WindowBuffer { uint window_pixels[]; };

layout(push_constant) uniform DisplayPush { DisplayParams display; };

float srgb_encode(float linear)
{
    return linear < 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

uint srgb8(float radiance)
{
    /* NaN becomes black, as in the PNG writer. */
    float clamped = isnan(radiance) ? 0.0 : clamp(radiance, 0.0, 1.0);
    return uint(srgb_encode(clamped) * 255.0 + 0.5);
}

/* The tone curves of src/output/tonemap.c, step for step, with the same constants. */
vec3 aces_fit(vec3 v)
{
    vec3 a = v * (v + VKRT_ACES_FIT_A) - VKRT_ACES_FIT_B;
    vec3 b = v * (VKRT_ACES_FIT_C * v + VKRT_ACES_FIT_D) + VKRT_ACES_FIT_E;
    return a / b;
}

vec3 aces(vec3 v)
{
    v = vec3(dot(vec3(VKRT_ACES_INPUT_ROW0), v), dot(vec3(VKRT_ACES_INPUT_ROW1), v),
             dot(vec3(VKRT_ACES_INPUT_ROW2), v));
    v = aces_fit(v);
    v = vec3(dot(vec3(VKRT_ACES_OUTPUT_ROW0), v), dot(vec3(VKRT_ACES_OUTPUT_ROW1), v),
             dot(vec3(VKRT_ACES_OUTPUT_ROW2), v));
    return clamp(v, 0.0, 1.0);
}

vec3 agx(vec3 v)
{
    v = vec3(dot(vec3(VKRT_AGX_INSET_ROW0), v), dot(vec3(VKRT_AGX_INSET_ROW1), v),
             dot(vec3(VKRT_AGX_INSET_ROW2), v));
    vec3 ev = clamp(log2(max(v, VKRT_AGX_LOG_FLOOR)), VKRT_AGX_MIN_EV, VKRT_AGX_MAX_EV);
    vec3 x = (ev - VKRT_AGX_MIN_EV) / (VKRT_AGX_MAX_EV - VKRT_AGX_MIN_EV);
    vec3 p = vec3(VKRT_AGX_POLY6);
    p = p * x + VKRT_AGX_POLY5;
    p = p * x + VKRT_AGX_POLY4;
    p = p * x + VKRT_AGX_POLY3;
    p = p * x + VKRT_AGX_POLY2;
    p = p * x + VKRT_AGX_POLY1;
    p = p * x + VKRT_AGX_POLY0;
    v = vec3(dot(vec3(VKRT_AGX_OUTSET_ROW0), p), dot(vec3(VKRT_AGX_OUTSET_ROW1), p),
             dot(vec3(VKRT_AGX_OUTSET_ROW2), p));
    return clamp(pow(max(v, 0.0), vec3(VKRT_AGX_DISPLAY_GAMMA)), 0.0, 1.0);
}

/* Exposed radiance through the tone curve; none leaves it to srgb8's clip. */
vec3 tone_curve(vec3 radiance)
{
    uint curve = display.curve.x;
    if (curve == VKRT_TONE_CURVE_NONE)
        return radiance;
    /* A NaN channel would reach every channel through the matrices: the pixel is black. */
    if (any(isnan(radiance)))
        return vec3(0.0);
    vec3 v = clamp(radiance, 0.0, VKRT_TONE_INPUT_MAX);
    return curve == VKRT_TONE_CURVE_ACES ? aces(v) : agx(v);
}

void main()
{
    /* gpu_dispatch folds more than 65535 workgroups into y. */
    uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x +
                 gl_LocalInvocationID.x;
    uint width = display.size.z, height = display.size.w;
    if (index >= width * height)
        return;
    uint x = index % width, y = index / width;
    uint ix = min(x * display.size.x / width, display.size.x - 1u);
    uint iy = min(y * display.size.y / height, display.size.y - 1u);
    vec4 sum = image[iy * display.size.x + ix];
    float per_sample = display.scale.w != 0.0 ? (sum.w > 0.0 ? 1.0 / sum.w : 0.0) : display.scale.x;
    vec3 radiance = tone_curve(sum.rgb * per_sample * display.scale.y);
    uvec3 c = uvec3(srgb8(radiance.r), srgb8(radiance.g), srgb8(radiance.b));
    if (display.scale.z != 0.0)
        c = c.bgr;
    window_pixels[index] = c.r | (c.g << 8) | (c.b << 16) | (255u << 24);
}
