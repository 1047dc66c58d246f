/*
 * one_mesh.h: test helpers between a mesh and the scene model (src/scene/model.h): a mesh made
 * in a test wrapped as a model of one identity instance, and an OBJ's one mesh.
 */
#ifndef VKRT_TEST_ONE_MESH_H
#define VKRT_TEST_ONE_MESH_H

#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene/model.h"
#include "scene/obj/obj_load.h"

/* model becomes mesh (whose arrays it now owns) as one identity instance, without materials. */
static inline void one_mesh_model(vkrt_model *model, vkrt_mesh mesh)
{
    memset(model, 0, sizeof *model);
    model->meshes = calloc(1, sizeof *model->meshes);
    model->instances = calloc(1, sizeof *model->instances);
    assert_non_null(model->meshes);
    assert_non_null(model->instances);
    model->meshes[0] = mesh;
    model->mesh_count = model->instance_count = 1;
    memcpy(model->instances[0].transform, vkrt_identity_transform,
           sizeof vkrt_identity_transform);
    vkrt_error err = {{0}};
    if (!vkrt_model_finish(model, &err))
        fail_msg("%s", err.msg);
}

/* The OBJ at path loaded into model; false (a skip) with err set when it fails. The one mesh is
 * model->meshes[0]. */
static inline bool one_mesh_load(const char *path, vkrt_model *model, vkrt_error *err)
{
    if (!vkrt_obj_load(path, model, err))
        return false;
    assert_int_equal(model->mesh_count, 1);
    return true;
}

#endif
