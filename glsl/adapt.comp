/*
 * adapt.comp: adaptive sampling (--target-error), after each sample pass: one invocation per
 * pixel, in raygen's tile order, twice (frame_adapt_step says which):
 *   VKRT_ADAPT_FOLD: a listed pixel folds its samples' luminance (what the pass's kernels added to
 *     its slots, lib/pixel.glsl) into its statistics, one sample at a time (lib/adaptive.glsl),
 *     clears the slots, and stores its sample count in image[pixel].w, by which the image is
 *     divided (each pixel has its own count). It is unconverged while below image.w (--spp, the
 *     cap) and with fewer than VKRT_ADAPTIVE_MIN_SAMPLES samples (VKRT_ADAPTIVE_MIN_DARK_SAMPLES
 *     while none found light), or an estimated relative error above TARGET_ERROR.
 *   VKRT_ADAPT_SELECT: a listed pixel stays listed for the next pass while it or one of its eight
 *     neighbours is unconverged. A pixel's variance, estimated from its first samples, misses the
 *     rare bright paths that light a dim face: on CornellBox-Original's short box such pixels
 *     stopped at 16 samples with most of their light unseen while a neighbour that had caught one
 *     such path sampled on. Keeping the neighbours of an unconverged pixel (Cycles dilates its
 *     unconverged pixels the same way, by one in x and in y) pools that evidence. A pixel
 *     dropped is not listed again, so every listed pixel has had the same samples (image.z) and
 *     raygen's sample indices stay consecutive in each pixel.
 * A neighbour reads a pixel's flags in the second pass while the pixel may clear its own, so
 * both go through atomics.
 *
 * Push constants: image.z is the samples each listed pixel has after the pass (0: the frame
 * starts, every pixel is listed with fresh statistics and cleared slots), counts.z the samples
 * the pass gave each (at the start: the most a pass gives, the slots to clear).
 *
 * The list is compacted as count.comp reserves ray slots: with subgroup operations one atomic per
 * subgroup, so a subgroup's pixels stay neighbours in the list and raygen's rays stay coherent.
 * adapt_dispatch.comp turns the list's length into raygen's indirect dispatch.
 */
#include "lib/bindings.glsl"
#include "lib/adaptive.glsl"
#include "lib/tiles.glsl"

/* Folds the last pass's samples of a listed pixel and judges it by its own estimate. */
void fold(uint pixel, uint pixels)
{
    uint taken = frame.counts.z;
    if (frame.image.z == 0u) {
        pixel_stats[pixel] = PixelStats(0.0, 0.0, 0u, VKRT_PIXEL_LISTED | VKRT_PIXEL_UNCONVERGED);
        for (uint k = 0u; k < taken; ++k)
            sample_luminance[k * pixels + pixel] = 0.0;
        return;
    }
    PixelStats st = pixel_stats[pixel];
    if ((st.listed & VKRT_PIXEL_LISTED) == 0u)
        return;
    for (uint k = 0u; k < taken; ++k) {
        uint slot = k * pixels + pixel;
        st.samples += 1u;
        adaptive_add(st.mean, st.m2, st.samples, sample_luminance[slot]);
        sample_luminance[slot] = 0.0;
    }
    image[pixel].w = float(st.samples);
    uint fewest = st.mean > 0.0 ? VKRT_ADAPTIVE_MIN_SAMPLES : VKRT_ADAPTIVE_MIN_DARK_SAMPLES;
    bool more = st.samples < frame.image.w &&
                (st.samples < fewest ||
                 adaptive_relative_error(st.mean, st.m2, st.samples) > TARGET_ERROR);
    st.listed = VKRT_PIXEL_LISTED | (more ? VKRT_PIXEL_UNCONVERGED : 0u);
    pixel_stats[pixel] = st;
}

/* Whether listed pixel (x, y) stays listed for the next pass (above); unlists it if not. */
bool select_pixel(uint pixel, uvec2 p, uint width, uint height)
{
    if ((atomicOr(pixel_stats[pixel].listed, 0u) & VKRT_PIXEL_LISTED) == 0u)
        return false;
    bool more = false;
    if (pixel_stats[pixel].samples < frame.image.w)
        for (uint y = p.y > 0u ? p.y - 1u : 0u; y <= min(p.y + 1u, height - 1u); ++y)
            for (uint x = p.x > 0u ? p.x - 1u : 0u; x <= min(p.x + 1u, width - 1u); ++x)
                more = more || (atomicOr(pixel_stats[y * width + x].listed, 0u) &
                                VKRT_PIXEL_UNCONVERGED) != 0u;
    if (!more)
        atomicAnd(pixel_stats[pixel].listed, ~VKRT_PIXEL_LISTED);
    return more;
}

void main()
{
    uint index = invocation_index();
    uint width = frame.image.x, height = frame.image.y, pixels = width * height;
    /* No early return: invocations past the image take part in the subgroup sums with 0. */
    uint pixel = 0u;
    bool listed = false;
    if (index < pixels) {
        uvec2 p = tile_pixel(index, width, height);
        pixel = p.y * width + p.x;
        if (frame_adapt_step(frame) == VKRT_ADAPT_FOLD)
            fold(pixel, pixels);
        else
            listed = select_pixel(pixel, p, width, height);
    }
    /* Only the second pass lists pixels (uniform control flow for the subgroup operations). */
    if (frame_adapt_step(frame) == VKRT_ADAPT_FOLD)
        return;
#ifdef VKRT_SUBGROUPS
    uint one = listed ? 1u : 0u;
    uint offset = subgroupExclusiveAdd(one);
    uint total = subgroupAdd(one);
    uint base = 0u;
    if (subgroupElect() && total > 0u)
        base = atomicAdd(active_list.appended, total);
    base = subgroupBroadcastFirst(base);
    if (listed)
        active_pixels[base + offset] = pixel;
#else
    if (listed)
        active_pixels[atomicAdd(active_list.appended, 1u)] = pixel;
#endif
}
