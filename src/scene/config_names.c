/* config_names.c: the names scene.cfg and the command line give the structure, the integrator,
 * the BVH's splits and the tone curve (config.h). */
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "config.h"

static const vkrt_accel_kind all_accels[] = {VKRT_ACCEL_AUTO, VKRT_ACCEL_BRUTE, VKRT_ACCEL_GRID,
                                             VKRT_ACCEL_BVH, VKRT_ACCEL_KDTREE};
static const vkrt_integrator all_integrators[] = {VKRT_INTEGRATOR_AUTO, VKRT_INTEGRATOR_WHITTED,
                                                  VKRT_INTEGRATOR_PATH};
static const vkrt_bvh_splits all_splits[] = {VKRT_BVH_SPLITS_AUTO, VKRT_BVH_SPLITS_ON,
                                             VKRT_BVH_SPLITS_OFF};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Appends name to the list in out as item i of n: "a", "a, b", ..., "a, b or c". */
static void append_name(char *out, size_t size, size_t i, size_t n, const char *name)
{
    size_t used = strlen(out);
    const char *joint = i == 0 ? "" : i + 1 == n ? " or " : ", ";
    snprintf(out + used, used < size ? size - used : 0, "%s%s", joint, name);
}

const char *vkrt_accel_names(char out[VKRT_NAMES_BYTES])
{
    out[0] = '\0';
    for (size_t i = 0; i < COUNT(all_accels); i++)
        append_name(out, VKRT_NAMES_BYTES, i, COUNT(all_accels), vkrt_accel_name(all_accels[i]));
    return out;
}

const char *vkrt_integrator_names(char out[VKRT_NAMES_BYTES])
{
    out[0] = '\0';
    for (size_t i = 0; i < COUNT(all_integrators); i++)
        append_name(out, VKRT_NAMES_BYTES, i, COUNT(all_integrators),
                    vkrt_integrator_name(all_integrators[i]));
    return out;
}

const char *vkrt_bvh_splits_names(char out[VKRT_NAMES_BYTES])
{
    out[0] = '\0';
    for (size_t i = 0; i < COUNT(all_splits); i++)
        append_name(out, VKRT_NAMES_BYTES, i, COUNT(all_splits), vkrt_bvh_splits_name(all_splits[i]));
    return out;
}

const char *vkrt_accel_name(vkrt_accel_kind kind)
{
    switch (kind) {
    case VKRT_ACCEL_AUTO:
        return "auto";
    case VKRT_ACCEL_BRUTE:
        return "brute";
    case VKRT_ACCEL_GRID:
        return "grid";
    case VKRT_ACCEL_BVH:
        return "bvh";
    case VKRT_ACCEL_KDTREE:
        return "kdtree";
    }
    return "unknown";
}

bool vkrt_accel_parse(const char *name, vkrt_accel_kind *kind)
{
    if (!name)
        return false;
    for (size_t i = 0; i < COUNT(all_accels); i++) {
        if (strcmp(name, vkrt_accel_name(all_accels[i])) == 0) {
            if (kind)
                *kind = all_accels[i];
            return true;
        }
    }
    return false;
}

const char *vkrt_integrator_name(vkrt_integrator integrator)
{
    switch (integrator) {
    case VKRT_INTEGRATOR_AUTO:
        return "auto";
    case VKRT_INTEGRATOR_WHITTED:
        return "whitted";
    case VKRT_INTEGRATOR_PATH:
        return "path";
    }
    return "unknown";
}

bool vkrt_integrator_parse(const char *name, vkrt_integrator *integrator)
{
    if (!name)
        return false;
    for (size_t i = 0; i < COUNT(all_integrators); i++) {
        if (strcmp(name, vkrt_integrator_name(all_integrators[i])) == 0) {
            if (integrator)
                *integrator = all_integrators[i];
            return true;
        }
    }
    return false;
}

const char *vkrt_bvh_splits_name(vkrt_bvh_splits splits)
{
    switch (splits) {
    case VKRT_BVH_SPLITS_AUTO:
        return "auto";
    case VKRT_BVH_SPLITS_ON:
        return "on";
    case VKRT_BVH_SPLITS_OFF:
        return "off";
    }
    return "unknown";
}

bool vkrt_bvh_splits_parse(const char *name, vkrt_bvh_splits *splits)
{
    for (size_t i = 0; name && i < COUNT(all_splits); i++) {
        if (strcmp(name, vkrt_bvh_splits_name(all_splits[i])) == 0) {
            *splits = all_splits[i];
            return true;
        }
    }
    return false;
}

const char *vkrt_tonemap_name(vkrt_tonemap curve)
{
    switch (curve) {
    case VKRT_TONEMAP_NONE:
        return "none";
    case VKRT_TONEMAP_ACES:
        return "aces";
    case VKRT_TONEMAP_AGX:
        return "agx";
    }
    return "unknown";
}

bool vkrt_tonemap_parse(const char *name, vkrt_tonemap *curve)
{
    static const vkrt_tonemap all[] = {VKRT_TONEMAP_NONE, VKRT_TONEMAP_ACES, VKRT_TONEMAP_AGX};
    for (size_t i = 0; name && i < sizeof all / sizeof all[0]; i++) {
        if (strcmp(name, vkrt_tonemap_name(all[i])) == 0) {
            *curve = all[i];
            return true;
        }
    }
    return false;
}

bool vkrt_texture_filter_parse(const char *name, vkrt_texture_filter *filter)
{
    static const char *const names[] = {
        [VKRT_TEXTURE_FILTER_CONE] = "cone",
        [VKRT_TEXTURE_FILTER_BILINEAR] = "bilinear",
        [VKRT_TEXTURE_FILTER_NEAREST] = "nearest",
    };
    for (size_t i = 0; name && i < sizeof names / sizeof names[0]; i++)
        if (strcmp(name, names[i]) == 0) {
            *filter = (vkrt_texture_filter)i;
            return true;
        }
    return false;
}
