/*
 * adapt.comp: adaptive sampling (--target-error), after each sample pass: one invocation per
 * pixel, in raygen's tile order. A pixel the pass sampled folds its samples' luminance (what the
 * pass's kernels added to its slots, lib/pixel.glsl) into its statistics, one sample at a time
 * (lib/adaptive.glsl), clears the slots, and stores its sample count in image[pixel].w, by which
 * the image is divided (each pixel has its own count). It stays in the list for the next pass
 * while it has fewer than VKRT_ADAPTIVE_MIN_SAMPLES samples (VKRT_ADAPTIVE_MIN_DARK_SAMPLES while
 * none found light), or its estimated relative error is above TARGET_ERROR, and it has fewer than image.w (--spp, the cap). A pixel dropped from the list is
 * never sampled again in the frame: its statistics, and so its estimate, no longer change.
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

/* Whether pixel takes samples in the next pass; folds the last pass's samples first. */
bool next_pass_samples(uint pixel, uint pixels)
{
    uint done = frame.image.z, taken = frame.counts.z;
    if (done == 0u) {
        pixel_stats[pixel] = PixelStats(0.0, 0.0, 0u, 1u);
        for (uint k = 0u; k < taken; ++k)
            sample_luminance[k * pixels + pixel] = 0.0;
        return true;
    }
    PixelStats st = pixel_stats[pixel];
    if (st.listed == 0u)
        return false;
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
    st.listed = more ? 1u : 0u;
    pixel_stats[pixel] = st;
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
        listed = next_pass_samples(pixel, pixels);
    }
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
