/*
 * raygen.comp: one primary ray per pixel for one sample pass.
 *
 * Sample s of N in a pixel lands in its own stratum: the pixel's square is cut into rows x cols
 * cells with rows the largest divisor of N not above sqrt(N) (so the cells tile the square
 * exactly for every N), and the ray is jittered inside its cell. With N == 1 the ray goes through
 * the pixel's centre, as the reference render expects.
 */
#include "lib/bindings.glsl"
#include "lib/rng.glsl"

void main()
{
    uint index = invocation_index();
    uint width = frame.image.x, height = frame.image.y;
    if (index >= width * height)
        return;
    uint sample_index = frame.image.z, samples = frame.image.w;
    uint px = index % width, py = index / width;

    uint seed = pcg_hash(index ^ pcg_hash(sample_index ^ pcg_hash(frame.counts.w)));
    vec2 offset = vec2(0.5);
    if (samples > 1u) {
        uint rows = uint(sqrt(float(samples)));
        while (rows > 1u && samples % rows != 0u)
            --rows;
        uint cols = samples / rows;
        vec2 cell = vec2(float(sample_index % cols), float(sample_index / cols));
        vec2 jitter = vec2(rng_next(seed), rng_next(seed));
        offset = (cell + jitter) / vec2(float(cols), float(rows));
    }
    /* Image row 0 is the top of the picture: y grows downwards in pixels, upwards in camera. */
    float x = 2.0 * (float(px) + offset.x) / float(width) - 1.0;
    float y = 1.0 - 2.0 * (float(py) + offset.y) / float(height);
    vec3 dir = normalize(frame.forward.xyz + x * frame.right.xyz + y * frame.up.xyz);

    Ray ray;
    ray.origin = vec4(frame.eye.xyz, 0.0);
    ray.direction = vec4(dir, 3.4e38);
    ray.importance = vec4(1.0, 1.0, 1.0, 0.0);
    ray.info = uvec4(index, seed, 0u, 0u);
    ray.payload = vec4(0.0);
    rays[index] = ray;
}
