/*
 * environment: the built-in environment shader, a constant radiance (parameters 0-2; scene.cfg's
 * `environment` line fills them) for every ray that leaves the scene. An environment shader sees
 * only the ray's direction and payload.
 */
vec3 environment(vec3 direction, vec4 payload)
{
    return param3(0u);
}
