/* config_names.c: the names scene.cfg and the command line give the structure, the integrator,
 * the BVH's splits and the tone curve (config.h). */
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "config.h"

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
    static const vkrt_accel_kind all[] = {VKRT_ACCEL_AUTO, VKRT_ACCEL_BRUTE, VKRT_ACCEL_GRID,
                                          VKRT_ACCEL_BVH, VKRT_ACCEL_KDTREE};
    if (!name)
        return false;
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        if (strcmp(name, vkrt_accel_name(all[i])) == 0) {
            if (kind)
                *kind = all[i];
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
    static const vkrt_integrator all[] = {VKRT_INTEGRATOR_AUTO, VKRT_INTEGRATOR_WHITTED,
                                          VKRT_INTEGRATOR_PATH};
    if (!name)
        return false;
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        if (strcmp(name, vkrt_integrator_name(all[i])) == 0) {
            if (integrator)
                *integrator = all[i];
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
    static const vkrt_bvh_splits all[] = {VKRT_BVH_SPLITS_AUTO, VKRT_BVH_SPLITS_ON,
                                          VKRT_BVH_SPLITS_OFF};
    for (size_t i = 0; name && i < sizeof all / sizeof all[0]; i++) {
        if (strcmp(name, vkrt_bvh_splits_name(all[i])) == 0) {
            *splits = all[i];
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
