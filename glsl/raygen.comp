/*
 * raygen.comp: the primary rays of one sample pass, and the pass's resets. A pass holds samples
 * image.z .. image.z + K - 1 of every pixel, K = counts.z / pixels (one, or several where the
 * image is small: src/render/tuning.c), ray index = sample offset * pixels + pixel order; with
 * --target-error, of the pixels adapt.comp listed, K = counts.z (see main).
 *
 * Sample s of N in a pixel lands in its own stratum. The path tracer takes its jitter from its
 * sampler (lib/sampler.glsl: dimensions 0-1 of depth 0, a (0,m,2)-net over the pixel's samples
 * that the rest of the path's dimensions are stratified along with). Whitted cuts the pixel's
 * square into rows x cols cells with rows the largest divisor of N not above sqrt(N) (so the
 * cells tile the square exactly for every N), and jitters the ray inside its cell. With N == 1
 * the ray goes through the pixel's centre, as the reference render expects.
 *
 * Consecutive invocations take the pixels of TILE x TILE tiles rather than of raster rows, so a
 * subgroup's rays (32 lanes: 8 x 4 pixels) leave the camera close together and walk the same
 * nodes; the ray carries its pixel (ray_pixel), so nothing downstream depends on the order.
 *
 * This kernel also resets what a pass starts from, instead of transfer commands before it (an
 * update and the barriers between transfer and compute, per pass): the image (and the AOVs of
 * --aov) at pass 0 and the wave table (wave 0 covers the primary rays, the others are empty until count and prepare fill
 * them).
 */
#include "lib/aov.glsl"
#include "lib/bindings.glsl"
#include "lib/rng.glsl"
#include "lib/sampler.glsl"
#include "lib/tiles.glsl"

/* Shirley and Chiu's concentric map of the unit square onto the unit disc: it keeps strata
 * (neighbouring points stay neighbours), so a stratified lens sample stays stratified. */
vec2 concentric_disk(vec2 u)
{
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0)
        return vec2(0.0);
    const float quarter_pi = 0.78539816339;
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = quarter_pi * (o.y / o.x);
    } else {
        r = o.y;
        theta = 2.0 * quarter_pi - quarter_pi * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

void reset_waves(uint rays)
{
    uint groups = (rays + WAVE_WORKGROUP_SIZE - 1u) / WAVE_WORKGROUP_SIZE;
    uint groups_x = min(groups, 65535u);
    waves[0] = WaveState(groups_x, (groups + groups_x - 1u) / groups_x, 1u, rays);
    for (uint depth = 1u; depth <= frame.wave.z + 1u; ++depth)
        waves[depth] = WaveState(0u, 0u, 0u, 0u);
}

void main()
{
    uint index = invocation_index();
    uint width = frame.image.x, height = frame.image.y, pixels = width * height;
    /* Adaptive sampling (TARGET_ERROR > 0): samples image.z .. + counts.z - 1 of the pixels
     * adapt.comp listed (in tile order), ray index = sample offset * listed + place in the list.
     * Every listed pixel has had the same samples, image.z, so sample indices stay consecutive
     * in each pixel and the sampler's strata hold for the samples it gets. */
    uint listed = TARGET_ERROR > 0.0 ? active_list.count : pixels;
    uint pass_rays = TARGET_ERROR > 0.0 ? listed * frame.counts.z : frame.counts.z;
    /* Before the check: a pass of no listed pixels (adapt_dispatch.comp still dispatches one
     * workgroup) must empty the wave table all the same. */
    /* The bins of order.comp, every depth's, start each pass empty. */
    if (MATERIAL_ORDER && gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u)
        for (uint i = gl_LocalInvocationIndex; i < order_bins_start(frame.wave.z + 1u);
             i += gl_WorkGroupSize.x)
            material_order[i] = 0u;
    if (index == 0u) {
        reset_waves(pass_rays);
        if (TARGET_ERROR > 0.0)
            counters.primary_rays += pass_rays;
    }
    if (index >= pass_rays)
        return;
    uint offset_in_pass = index / listed, place = index - offset_in_pass * listed;
    uint sample_index = frame.image.z + offset_in_pass, samples = frame.image.w;
    uvec2 p;
    if (TARGET_ERROR > 0.0) {
        uint listed_pixel = active_pixels[place];
        p = uvec2(listed_pixel % width, listed_pixel / width);
    } else {
        p = tile_pixel(place, width, height);
    }
    uint pixel = p.y * width + p.x;
    if (sample_index == 0u) {
        image[pixel] = vec4(0.0);
        if (AOVS != 0u)
            aov_clear(pixel);
    }

    uint seed = pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(frame.counts.w)));
    vec2 offset = vec2(0.5);
    Ray ray = ray_camera(pixel, seed, sample_index);
    /* --aov albedo or normal: the path owes them until it meets a surface that is not a delta
     * (lib/aov.glsl). */
    if ((AOVS & VKRT_AOV_SURFACE) != 0u)
        ray_mark_aov_pending(ray);
    if (samples > 1u && INTEGRATOR == VKRT_INTEGRATE_PATH) {
        offset = sampler_2d(ray, frame.counts.w, SAMPLER_DIM_PIXEL);
    } else if (samples > 1u) {
        uint rows = uint(sqrt(float(samples)));
        while (rows > 1u && samples % rows != 0u)
            --rows;
        uint cols = samples / rows;
        vec2 cell = vec2(float(sample_index % cols), float(sample_index / cols));
        vec2 jitter = vec2(rng_next(seed), rng_next(seed));
        offset = (cell + jitter) / vec2(float(cols), float(rows));
    }
    /* Image row 0 is the top of the picture: y grows downwards in pixels, upwards in camera. */
    float x = 2.0 * (float(p.x) + offset.x) / float(width) - 1.0;
    float y = 1.0 - 2.0 * (float(p.y) + offset.y) / float(height);
    vec3 through = frame.forward.xyz + x * frame.right.xyz + y * frame.up.xyz;
    vec3 origin = frame.eye.xyz, dir = normalize(through);
    if (frame.forward.w != 0.0) {
        /* Orthographic (pbrt's OrthographicCamera): parallel rays along the view axis, from the
         * pixel's point of the image plane through the eye; right and up span half the view in
         * scene units, so a scene unit covers width / (2 |right|) pixels at any distance. */
        origin = frame.eye.xyz + x * frame.right.xyz + y * frame.up.xyz;
        through = frame.forward.xyz;
        dir = frame.forward.xyz;
    }
    vec3 pinhole = origin;
    if (frame.right.w > 0.0) {
        /* A thin lens of radius right.w (Mitsuba's thinlens, pbrt's PerspectiveCamera and
         * OrthographicCamera): the ray leaves a point of the lens (centred on the pinhole ray's
         * origin) towards where the pinhole ray meets the plane in focus, at distance up.w along
         * the view axis (through has 1 along it). Whitted draws the lens point from a stream of
         * its own, not from the ray's, which its shaders use. */
        vec2 u = INTEGRATOR == VKRT_INTEGRATE_PATH
                     ? sampler_2d(ray, frame.counts.w, SAMPLER_DIM_LENS)
                     : vec2(rng_float(pcg_hash(ray_seed(ray) ^ 0x1B873593u)),
                            rng_float(pcg_hash(ray_seed(ray) ^ 0x68E31DA4u)));
        vec2 lens = frame.right.w * concentric_disk(u);
        origin += lens.x * normalize(frame.right.xyz) + lens.y * normalize(frame.up.xyz);
        dir = normalize(pinhole + frame.up.w * through - origin);
    }

    ray_set_segment(ray, origin, dir, 0.0, FAR);
    vec2 cone = ray_camera_cone(frame); /* texture filtering: the pixel's cone */
    ray_set_cone(ray, cone.x, cone.y);
    rays[index] = ray;
}
