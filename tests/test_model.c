/*
 * test_model.c: the scene model (src/scene/model.h) and the OBJ loader's part in it: an OBJ is
 * one mesh and one identity instance, an .mtl record keeps every field in the model's units, the
 * renderer's flattening of instances into world space matches a case computed by hand, and
 * materials.c gives each map its texture read as the map's sampler, transform and channel say,
 * and several files placed into one model keep their meshes once.
 */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <stb_image_write.h>

#include "../glsl/shared.h"
#include "scene/materials.h"
#include "scene/model.h"
#include "scene/model_place.h"
#include "scene/obj/mtl.h"
#include "scene/obj/obj_load.h"
#include "scene/scene.h"
#include "temp_dir.h"

static void assert_vec3_near(const float *got, double x, double y, double z)
{
    const double want[3] = {x, y, z};
    for (int k = 0; k < 3; ++k)
        if (fabs(got[k] - want[k]) > 1e-6)
            fail_msg("component %d: got %.9g, want %.9g", k, (double)got[k], want[k]);
}

static void obj_is_one_mesh_and_one_identity_instance(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 -1\nf 1 2 3 4\n";
    vkrt_model m;
    vkrt_error err = {{0}};
    assert_true(vkrt_obj_parse(text, strlen(text), "q.obj", NULL, &m, &err));
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.instance_count, 1);
    assert_int_equal(m.instances[0].mesh, 0);
    assert_memory_equal(m.instances[0].transform, vkrt_identity_transform,
                        sizeof vkrt_identity_transform);
    assert_int_equal(m.triangle_count, 2);
    assert_int_equal(m.meshes[0].triangle_count, 2);
    assert_null(m.meshes[0].tangents);
    assert_memory_equal(m.bounds_min, m.meshes[0].bounds_min, sizeof m.bounds_min);
    assert_memory_equal(m.bounds_max, m.meshes[0].bounds_max, sizeof m.bounds_max);
    assert_int_equal(m.light_count, 0);
    assert_int_equal(m.camera_count, 0);
    /* One identity instance: the world is the mesh's own arrays, not a copy. */
    vkrt_mesh world;
    bool copied = true;
    assert_true(vkrt_model_world(&m, &world, &copied, &err));
    assert_false(copied);
    assert_ptr_equal(world.positions, m.meshes[0].positions);
    assert_ptr_equal(world.material, m.meshes[0].material);
    vkrt_model_free(&m);
}

/* An .mtl record as the file says it, with mtl.h's defaults for what it leaves out. */
static vkrt_mtl plain_mtl(char *name)
{
    vkrt_mtl m = {.name = name, .kd = {0.8f, 0.8f, 0.8f}, .ni = 1, .d = 1, .illum = 2,
                  .tf = {1, 1, 1}, .pr = -1, .bump_multiplier = 1};
    return m;
}

static void mtl_record_maps_into_the_model(void **state)
{
    (void)state;
    vkrt_material out;
    /* illum 4 with Ni: the smooth dielectric of that index; Pr (the PBR extension) makes it
     * rough, with Pr as the roughness. */
    vkrt_mtl glass = plain_mtl("glass");
    glass.illum = 4;
    glass.ni = 1.33f;
    glass.tf[1] = 0.5f;
    assert_true(vkrt_mtl_to_material(&glass, &out));
    assert_int_equal(out.bsdf, VKRT_BSDF_DIELECTRIC);
    assert_float_equal(out.ior, 1.33f, 0);
    assert_vec3_near(out.transmission_filter, 1, 0.5, 1);
    assert_string_equal(out.name, "glass");
    assert_string_equal(out.file, "(.mtl)");
    vkrt_material_free_strings(&out);
    glass.pbr = true;
    glass.pr = 0.4f;
    assert_true(vkrt_mtl_to_material(&glass, &out));
    assert_int_equal(out.bsdf, VKRT_BSDF_ROUGH_DIELECTRIC);
    assert_float_equal(out.roughness, 0.4f, 0);
    vkrt_material_free_strings(&out);
    /* Ns without Pr: roughness sqrt(alpha), alpha = sqrt(2 / (Ns + 2)); Ns 98 gives
     * alpha = sqrt(0.02), roughness 0.02^(1/4). */
    vkrt_mtl phong = plain_mtl("phong");
    phong.ks[0] = phong.ks[1] = phong.ks[2] = 0.5f;
    phong.ns = 98;
    assert_true(vkrt_mtl_to_material(&phong, &out));
    assert_int_equal(out.bsdf, VKRT_BSDF_GLOSSY_PHONG);
    assert_float_equal(out.roughness, powf(0.02f, 0.25f), 1e-6);
    assert_float_equal(out.specular_exponent, 98, 0);
    vkrt_material_free_strings(&out);
    /* map_Kd: an sRGB colour texture with its line, repeat and bilinear; a diffuse family. */
    vkrt_mtl wood = plain_mtl("wood");
    wood.map_kd = "wood.png";
    wood.map_kd_line = 4;
    wood.mtl_path = "x.mtl";
    wood.pc = 2; /* the coat weight is Pc / 4 */
    assert_true(vkrt_mtl_to_material(&wood, &out));
    assert_int_equal(out.bsdf, VKRT_BSDF_DIFFUSE);
    assert_string_equal(out.maps[VKRT_MAP_BASE_COLOUR].path, "wood.png");
    assert_int_equal(out.maps[VKRT_MAP_BASE_COLOUR].line, 4);
    assert_int_equal(out.maps[VKRT_MAP_BASE_COLOUR].space, VKRT_TEXTURE_COLOUR);
    assert_int_equal(out.maps[VKRT_MAP_BASE_COLOUR].sampler.wrap_u, VKRT_WRAP_REPEAT);
    assert_int_equal(out.maps[VKRT_MAP_BASE_COLOUR].sampler.filter, VKRT_FILTER_LINEAR);
    assert_string_equal(out.file, "x.mtl");
    assert_float_equal(out.coat, 0.5f, 0);
    vkrt_material_free_strings(&out);
    /* Ke alone: the emitter family. */
    vkrt_mtl lamp = plain_mtl("lamp");
    memset(lamp.kd, 0, sizeof lamp.kd);
    lamp.ke[0] = 5;
    assert_true(vkrt_mtl_to_material(&lamp, &out));
    assert_int_equal(out.bsdf, VKRT_BSDF_EMITTER);
    assert_vec3_near(out.emission, 5, 0, 0);
    vkrt_material_free_strings(&out);
}

/* A one-triangle mesh placed twice: as it is, and scaled by 2 along y, moved by (5, 0, -1). The
 * corners go to (5, 0, -1), (6, 0, -1), (5, 2, -1); the normal (0, 1, 1) / sqrt 2 goes by the
 * inverse transpose diag(1, 1/2, 1) to (0, 1/2, 1), made unit: (0, 1, 2) / sqrt 5. */
static void instances_flatten_into_world_space(void **state)
{
    (void)state;
    vkrt_model m = {0};
    m.mesh_count = 1;
    m.meshes = calloc(1, sizeof *m.meshes);
    m.instance_count = 2;
    m.instances = calloc(2, sizeof *m.instances);
    assert_non_null(m.meshes);
    assert_non_null(m.instances);
    vkrt_mesh *mesh = &m.meshes[0];
    mesh->triangle_count = 1;
    mesh->positions = malloc(9 * sizeof(float));
    mesh->normals = malloc(9 * sizeof(float));
    mesh->texcoords = malloc(6 * sizeof(float));
    mesh->material = malloc(sizeof(int32_t));
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uv[6] = {0, 0, 1, 0, 0, 1};
    memcpy(mesh->positions, p, sizeof p);
    for (int c = 0; c < 3; ++c) {
        mesh->normals[3 * c] = 0;
        mesh->normals[3 * c + 1] = mesh->normals[3 * c + 2] = (float)M_SQRT1_2;
    }
    memcpy(mesh->texcoords, uv, sizeof uv);
    mesh->material[0] = -1;
    mesh->bounds_max[0] = mesh->bounds_max[1] = 1;
    memcpy(m.instances[0].transform, vkrt_identity_transform, sizeof vkrt_identity_transform);
    const float moved[12] = {1, 0, 0, 5, 0, 2, 0, 0, 0, 0, 1, -1};
    memcpy(m.instances[1].transform, moved, sizeof moved);
    vkrt_error err = {{0}};
    assert_true(vkrt_model_finish(&m, &err));
    assert_int_equal(m.triangle_count, 2);
    assert_vec3_near(m.bounds_min, 0, 0, -1);
    assert_vec3_near(m.bounds_max, 6, 2, 0);

    vkrt_mesh world;
    bool copied = false;
    assert_true(vkrt_model_world(&m, &world, &copied, &err));
    assert_true(copied);
    assert_int_equal(world.triangle_count, 2);
    assert_memory_equal(world.positions, p, sizeof p);
    assert_vec3_near(world.positions + 9, 5, 0, -1);
    assert_vec3_near(world.positions + 12, 6, 0, -1);
    assert_vec3_near(world.positions + 15, 5, 2, -1);
    for (int c = 0; c < 3; ++c) {
        assert_vec3_near(world.normals + 3 * c, 0, M_SQRT1_2, M_SQRT1_2);
        assert_vec3_near(world.normals + 9 + 3 * c, 0, 1 / sqrt(5), 2 / sqrt(5));
    }
    assert_memory_equal(world.texcoords, uv, sizeof uv);
    assert_memory_equal(world.texcoords + 6, uv, sizeof uv);
    assert_int_equal(world.material[0], -1);
    assert_int_equal(world.material[1], -1);
    assert_null(world.tangents);
    assert_vec3_near(world.bounds_min, 0, 0, -1);
    assert_vec3_near(world.bounds_max, 6, 2, 0);
    vkrt_mesh_free(&world);

    /* The materials are the mesh's, once; over the instances, one entry per world triangle. */
    vkrt_config cfg = {0};
    vkrt_scene_materials mats;
    assert_true(vkrt_scene_materials_resolve(&cfg, &m, NULL, &mats, &err));
    assert_int_equal(mats.triangle_count, 1);
    assert_int_equal(mats.mesh_first[0], 0);
    const uint32_t *per_world;
    uint32_t *owned;
    assert_true(vkrt_scene_materials_world(&mats, &m, &per_world, &owned, &err));
    assert_non_null(owned);
    assert_int_equal(per_world[0], mats.triangle_material[0]);
    assert_int_equal(per_world[1], mats.triangle_material[0]);
    free(owned);
    vkrt_scene_materials_free(&mats);

    /* An instance naming a mesh that is not there is refused. */
    m.instances[1].mesh = 3;
    assert_false(vkrt_model_finish(&m, &err));
    assert_non_null(strstr(err.msg, "instance 1 names mesh 3 of 1"));
    vkrt_model_free(&m);
}

/* A one-triangle model of one material; its maps are the caller's to fill. */
static void one_material_model(vkrt_model *m, vkrt_bsdf bsdf)
{
    memset(m, 0, sizeof *m);
    m->mesh_count = m->instance_count = m->material_count = 1;
    m->meshes = calloc(1, sizeof *m->meshes);
    m->instances = calloc(1, sizeof *m->instances);
    m->materials = calloc(1, sizeof *m->materials);
    assert_true(m->meshes && m->instances && m->materials);
    vkrt_material_defaults(&m->materials[0]);
    m->materials[0].bsdf = bsdf;
    m->materials[0].name = strdup("tiles");
    m->materials[0].file = strdup("scene.gltf");
    vkrt_mesh *mesh = &m->meshes[0];
    mesh->triangle_count = 1;
    mesh->positions = calloc(9, sizeof(float));
    mesh->material = calloc(1, sizeof(int32_t));
    memcpy(m->instances[0].transform, vkrt_identity_transform, sizeof vkrt_identity_transform);
    vkrt_error err = {{0}};
    assert_true(vkrt_model_finish(m, &err));
}

static void set_map(vkrt_material *mat, int map, const char *path, vkrt_texture_usage space)
{
    mat->maps[map].path = strdup(path);
    mat->maps[map].line = 7;
    mat->maps[map].space = space;
}

/* Each map reads its texture as its reference says: a glTF metallicRoughness image serves the
 * roughness (green) and the metallic (blue) maps as two entries sharing one image's texels, the
 * base colour is clamped, mirrored and nearest, the roughness map transformed; a map on a second
 * uv set is refused, naming the file and line. */
static void maps_read_their_textures_as_their_refs_say(void **state)
{
    temp_dir *fx = *state;
    unsigned char px[2 * 2 * 4];
    for (int i = 0; i < 16; i++)
        px[i] = (unsigned char)(i * 16 + 5);
    assert_true(stbi_write_png(temp_dir_path(fx, "mr.png"), 2, 2, 4, px, 8) != 0);
    char *path = strdup(fx->path);
    vkrt_model m;
    one_material_model(&m, VKRT_BSDF_PRINCIPLED);
    vkrt_material *mat = &m.materials[0];
    set_map(mat, VKRT_MAP_ROUGHNESS, path, VKRT_TEXTURE_DATA);
    set_map(mat, VKRT_MAP_METALLIC, path, VKRT_TEXTURE_DATA);
    set_map(mat, VKRT_MAP_BASE_COLOUR, path, VKRT_TEXTURE_COLOUR);
    mat->maps[VKRT_MAP_ROUGHNESS].channel = 1;
    mat->maps[VKRT_MAP_ROUGHNESS].uv_rotation = 0.5f;
    mat->maps[VKRT_MAP_METALLIC].channel = 2;
    mat->maps[VKRT_MAP_BASE_COLOUR].channel = 2; /* not a one-number map: reads its colour */
    mat->maps[VKRT_MAP_BASE_COLOUR].sampler =
        (vkrt_sampler){VKRT_WRAP_CLAMP, VKRT_WRAP_MIRROR, VKRT_FILTER_NEAREST};
    vkrt_config cfg = {0};
    vkrt_scene_materials mats;
    vkrt_error err = {{0}};
    assert_true(vkrt_scene_materials_resolve(&cfg, &m, NULL, &mats, &err));
    const vkrt_scene_material *sm = &mats.list[mats.triangle_material[0]];
    const vkrt_texture_info *base = &mats.textures.info[sm->textures[0]];
    const vkrt_texture_info *rough = &mats.textures.info[sm->textures[2]];
    const vkrt_texture_info *metal = &mats.textures.info[sm->textures[3]];
    /* The 2 x 2 images have one mipmap level each. */
    assert_int_equal(base->flags, VKRT_TEXTURE_SRGB | VKRT_TEXTURE_WRAP_U(VKRT_TEXTURE_CLAMP) |
                                      VKRT_TEXTURE_WRAP_V(VKRT_TEXTURE_MIRROR) |
                                      VKRT_TEXTURE_NEAREST | VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(rough->flags,
                     VKRT_TEXTURE_CHANNEL(1u) | VKRT_TEXTURE_TRANSFORM | VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(metal->flags, VKRT_TEXTURE_CHANNEL(2u) | VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(rough->offset, metal->offset); /* one image, one copy of its texels */
    assert_true(fabsf(rough->uv_matrix[0] - cosf(0.5f)) < 1e-6f);
    assert_true(fabsf(rough->uv_matrix[1] - sinf(0.5f)) < 1e-6f);
    /* Two images (colour and data) and the views the maps need on top of the data image: the
     * plain one, green transformed, blue. */
    assert_int_equal(mats.textures.texel_words, 2 * (4 + 1));
    vkrt_scene_materials_free(&mats);

    mat->maps[VKRT_MAP_METALLIC].uv_set = 1;
    assert_false(vkrt_scene_materials_resolve(&cfg, &m, NULL, &mats, &err));
    char want[1200];
    snprintf(want, sizeof want,
             "scene.gltf:7: texture '%s': reads texture coordinates 1; vkrt reads one set "
             "(TEXCOORD_0) only",
             path);
    assert_string_equal(err.msg, want);
    free(path);
    vkrt_model_free(&m);
}


/* Two files placed into one model (model_place.h): the second file's meshes, materials and
 * images move past the first's, its instances come once per placement with the placement applied
 * after the file's own transform, and its lights are placed with it. Checked against the numbers
 * written out by hand. */
static void files_are_placed_as_instances(void **state)
{
    (void)state;
    const char *a_text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const char *b_text = "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nf 1 2 3\nf 1 3 4\n";
    vkrt_model a, b, scene = {0};
    vkrt_error err = {{0}};
    assert_true(vkrt_obj_parse(a_text, strlen(a_text), "a.obj", NULL, &a, &err));
    assert_true(vkrt_obj_parse(b_text, strlen(b_text), "b.obj", NULL, &b, &err));
    /* Give each file a material and b an embedded image and a light, as a glTF would. */
    vkrt_model *files[2] = {&a, &b};
    for (int f = 0; f < 2; f++) {
        files[f]->materials = calloc(1, sizeof(vkrt_material));
        assert_non_null(files[f]->materials);
        vkrt_material_defaults(&files[f]->materials[0]);
        files[f]->material_count = 1;
        files[f]->meshes[0].material[0] = 0;
    }
    a.images = calloc(1, sizeof *a.images);
    b.images = calloc(1, sizeof *b.images);
    a.image_count = b.image_count = 1;
    b.materials[0].maps[VKRT_MAP_BASE_COLOUR].embedded = 0;
    b.lights = calloc(1, sizeof *b.lights);
    b.light_count = 1;
    b.lights[0].kind = VKRT_LIGHT_SPOT;
    b.lights[0].position[0] = 1.0f;
    b.lights[0].direction[2] = -1.0f;

    static const float identity[1][12] = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}};
    /* b twice: moved by (10, 0, 0), and turned 90 degrees about y (x -> -z, z -> x). */
    static const float twice[2][12] = {{1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0},
                                       {0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0}};
    assert_true(vkrt_model_place(&scene, &a, identity, 1, &err));
    assert_true(vkrt_model_place(&scene, &b, twice, 2, &err));
    assert_true(vkrt_model_finish(&scene, &err));
    assert_int_equal(a.mesh_count, 0); /* moved: src is left empty */
    assert_int_equal(scene.mesh_count, 2);
    assert_int_equal(scene.material_count, 2);
    assert_int_equal(scene.image_count, 2);
    assert_int_equal(scene.instance_count, 3);
    assert_int_equal(scene.instances[1].mesh, 1);
    assert_int_equal(scene.instances[2].mesh, 1);
    assert_int_equal(scene.triangle_count, 1 + 2 * 2);
    assert_int_equal(scene.meshes[1].material[0], 1);
    assert_int_equal(scene.meshes[1].material[1], -1);
    assert_int_equal(scene.materials[1].maps[VKRT_MAP_BASE_COLOUR].embedded, 1);
    assert_int_equal(scene.light_count, 2);
    assert_vec3_near(scene.lights[0].position, 11, 0, 0);
    assert_vec3_near(scene.lights[1].position, 0, 0, -1);
    assert_vec3_near(scene.lights[1].direction, -1, 0, 0);
    /* The world box: b's far corner (2 on each axis) at x 12, and turned to z -2 and x 2. */
    assert_vec3_near(scene.bounds_min, 0, 0, -2);
    assert_vec3_near(scene.bounds_max, 12, 2, 2);
    vkrt_model_free(&scene);
}

/* A scene's lights are its geometry file's, then scene.cfg's, in that order; where only one of
 * them gives lights the scene reads that array itself; the cameras are scene.cfg's. */
static void scene_lights_are_the_model_then_the_config(void **state)
{
    (void)state;
    vkrt_scene scene = {0};
    vkrt_error err = {{0}};
    scene.config.lights = calloc(2, sizeof *scene.config.lights);
    scene.config.cameras = calloc(1, sizeof *scene.config.cameras);
    assert_non_null(scene.config.lights);
    assert_non_null(scene.config.cameras);
    scene.config.light_count = 2;
    scene.config.camera_count = 1;
    scene.config.lights[0].kind = VKRT_LIGHT_DIRECTIONAL;
    scene.config.lights[1].kind = VKRT_LIGHT_AMBIENT;
    assert_true(vkrt_scene_compose(&scene, &err));
    assert_ptr_equal(scene.lights, scene.config.lights); /* no copy */
    assert_int_equal(scene.light_count, 2);
    assert_ptr_equal(scene.cameras, scene.config.cameras);
    assert_int_equal(scene.camera_count, 1);

    scene.model.lights = calloc(1, sizeof *scene.model.lights);
    assert_non_null(scene.model.lights);
    scene.model.light_count = 1;
    scene.model.lights[0].kind = VKRT_LIGHT_POINT;
    scene.model.lights[0].position[1] = 3.0f;
    assert_true(vkrt_scene_compose(&scene, &err));
    assert_int_equal(scene.light_count, 3);
    assert_int_equal(scene.lights[0].kind, VKRT_LIGHT_POINT);
    assert_true(scene.lights[0].position[1] == 3.0f);
    assert_int_equal(scene.lights[1].kind, VKRT_LIGHT_DIRECTIONAL);
    assert_int_equal(scene.lights[2].kind, VKRT_LIGHT_AMBIENT);
    vkrt_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(obj_is_one_mesh_and_one_identity_instance),
        cmocka_unit_test(mtl_record_maps_into_the_model),
        cmocka_unit_test(instances_flatten_into_world_space),
        temp_dir_test(maps_read_their_textures_as_their_refs_say),
        cmocka_unit_test(scene_lights_are_the_model_then_the_config),
        cmocka_unit_test(files_are_placed_as_instances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
