/*
 * display.comp: the viewer's last pass (src/view/display.c). Turns the renderer's image (a sum of
 * sample passes per pixel, vec4) into the 8-bit sRGB pixels of a window: the average, times
 * 2^exposure, clamped, through the sRGB curve, as a PNG of `vkrt render` gets them. The pixels
 * are packed in the byte order of the swapchain's format, and copied into its image afterwards:
 * a copy works on any swapchain, where storage-image use is optional.
 *
 * One invocation per window pixel; the window may differ in size from the image (while a resize
 * is waiting for the renderer to follow), and then shows it scaled, nearest pixel.
 */
#include "shared.h"

layout(local_size_x_id = VKRT_SPEC_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = VKRT_DISPLAY_BINDING_IMAGE) readonly buffer ImageBuffer { vec4 image[]; };
layout(std430, set = 0, binding = VKRT_DISPLAY_BINDING_WINDOW) writeonly buffer WindowBuffer { uint window_pixels[]; };

layout(push_constant) uniform Display {
    uvec4 size;   /* image width, height; window width, height */
    vec4 scale;   /* x: 1 / passes, y: 2^exposure, z: 1 to store red in the third byte (BGRA),
                     w: 1 to divide by each pixel's own count, its w, instead of x (sampling to a
                     target error: glsl/adapt.comp) */
} display;

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
    vec3 radiance = sum.rgb * per_sample * display.scale.y;
    uvec3 c = uvec3(srgb8(radiance.r), srgb8(radiance.g), srgb8(radiance.b));
    if (display.scale.z != 0.0)
        c = c.bgr;
    window_pixels[index] = c.r | (c.g << 8) | (c.b << 16) | (255u << 24);
}
