/*
 * test_scene_materials.c: the clear coat's way from the .mtl and the material file to the
 * shaders' numbers (src/scene/materials.c): Pc as Blender's importer reads it (Coat Weight =
 * Pc / 4, clamped to 1; number 18), Pcr as number 19, the built-in a coated .mtl material maps
 * to, and the VKRT_MATERIAL_COAT flag, set exactly where a material has a coat: a scene without
 * one compiles no coat (the flag is or-ed into the SURFACE_MAPS specialization constant).
 * The same for the sheen: Ps as Blender's importer reads it (Sheen Weight, clamped to [0, 1]),
 * map_Ps in texture slot 6 replacing its number, a material file's number 20, the built-in a
 * sheen makes (pbr; glass stays glass), VKRT_MATERIAL_SHEEN exactly where there is a sheen, and
 * a missing map_Ps reported at its .mtl line.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "scene/scene.h"
#include "temp_dir.h"

/* The material called name in the loaded scene (fails the test where there is none). */
static const vkrt_scene_material *find(const vkrt_scene *scene, const char *name)
{
    for (uint32_t i = 0; i < scene->materials.count; ++i)
        if (strcmp(scene->materials.list[i].name, name) == 0)
            return &scene->materials.list[i];
    fail_msg("no material '%s'", name);
    return NULL;
}

static const char *builtin_of(const vkrt_scene *scene, const vkrt_scene_material *m)
{
    const char *b = scene->materials.shaders[m->shader].builtin;
    return b ? b : "(none)";
}

static bool coated(const vkrt_scene_material *m)
{
    return (m->maps & VKRT_MATERIAL_COAT) != 0;
}

static bool sheened(const vkrt_scene_material *m)
{
    return (m->maps & VKRT_MATERIAL_SHEEN) != 0;
}

/* Writes scene.cfg over m.obj (one triangle per name, with its usemtl) and m.mat; loads it. */
static bool load_triangles(temp_dir *fx, const char *const *names, size_t count, vkrt_scene *scene,
                           vkrt_error *err)
{
    char obj[1024] = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (size_t i = 0; i < count; ++i) {
        strcat(obj, "usemtl ");
        strcat(obj, names[i]);
        strcat(obj, "\nf 1 2 3\n");
    }
    temp_dir_write_text(fx, "m.obj", obj);
    const char *cfg = temp_dir_write_text(fx, "scene.cfg",
                                          "geometry m.obj\nmaterials m.mat\n"
                                          "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 40\n");
    return vkrt_scene_load(cfg, scene, err);
}

static void sheen_numbers_and_flag(void **state)
{
    temp_dir *fx = *state;
    /* A 1 x 1 uncompressed true-colour TGA (stb_image reads it): the sheen map. */
    static const unsigned char tga[18 + 3] = {0, 0, 2, 0, 0, 0,  0, 0,  0,   0,  0,
                                              0, 1, 0, 1, 0, 24, 0, 64, 128, 192};
    temp_dir_write(fx, "sheen.tga", tga, sizeof tga);
    temp_dir_write_text(fx, "m.mtl",
                        "newmtl velvet\nKd 0.3 0 0\nPs 0.75\n"                 /* Ps alone: pbr */
                        "newmtl satin\nKd 0.3 0 0\nPm 0.5\nPs 3\n"             /* clamped to 1 */
                        "newmtl cloth\nKd 0.3 0 0\nPs 0.2\nmap_Ps sheen.tga\n" /* map wins */
                        "newmtl bottle\nNi 1.5\nillum 7\nPs 1\n"               /* glass: no sheen */
                        "newmtl plain\nKd 0.5 0.5 0.5\nPs 0\n"                 /* no sheen */
                        "newmtl file_sheen\nnewmtl file_bare\n");
    temp_dir_write_text(fx, "m.mat",
                        "file_sheen 0 @roughplastic 0.3 0 0 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  "
                        "0 0  0.4\n"
                        "file_bare 0 @roughplastic 0.3 0 0 0  0 0 0 0  0 0 0  1\n");
    const char *names[] = {"velvet", "satin",      "cloth",    "bottle",
                           "plain",  "file_sheen", "file_bare"};
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!load_triangles(fx, names, sizeof names / sizeof *names, &scene, &err))
        fail_msg("load: %s", err.msg);
    const vkrt_scene_material *velvet = find(&scene, "velvet");
    assert_string_equal(builtin_of(&scene, velvet), "pbr");
    assert_float_equal(velvet->sheen, 0.75f, 1e-6);
    assert_true(sheened(velvet));
    assert_int_equal(velvet->textures[VKRT_SLOT_SHEEN], VKRT_SCENE_NO_TEXTURE);
    assert_float_equal(find(&scene, "satin")->sheen, 1.0f, 1e-6);
    const vkrt_scene_material *cloth = find(&scene, "cloth");
    assert_float_equal(cloth->sheen, 1.0f, 1e-6); /* the map replaces the number */
    assert_int_not_equal(cloth->textures[VKRT_SLOT_SHEEN], VKRT_SCENE_NO_TEXTURE);
    assert_true(sheened(cloth));
    assert_string_equal(builtin_of(&scene, find(&scene, "bottle")), "glass");
    const vkrt_scene_material *plain = find(&scene, "plain");
    assert_string_equal(builtin_of(&scene, plain), "diffuse");
    assert_false(sheened(plain));
    const vkrt_scene_material *file_sheen = find(&scene, "file_sheen");
    assert_float_equal(file_sheen->sheen, 0.4f, 1e-6);
    assert_true(sheened(file_sheen));
    assert_false(sheened(find(&scene, "file_bare")));
    assert_false(coated(velvet) || coated(file_sheen));
    vkrt_scene_free(&scene);

    /* A map_Ps that is not there: the error names the .mtl's line. */
    temp_dir_write_text(fx, "m.mtl", "newmtl velvet\nKd 0.3 0 0\nmap_Ps gone.png\n");
    const char *velvet_only[] = {"velvet"};
    assert_false(load_triangles(fx, velvet_only, 1, &scene, &err));
    assert_non_null(strstr(err.msg, "m.mtl:3: texture '"));
    assert_non_null(strstr(err.msg, "gone.png': cannot open"));
}

static void coat_numbers_and_flag(void **state)
{
    temp_dir *fx = *state;
    temp_dir_write_text(fx, "m.mtl",
                        "newmtl varnish\nKd 0.5 0.5 0.5\nPc 2\nPcr 0.3\n"      /* Pc alone: pbr */
                        "newmtl lacquer\nKd 0.5 0.5 0.5\nPm 1\nPr 0.2\nPc 9\n" /* clamped to 1 */
                        "newmtl bottle\nNi 1.5\nillum 7\nPc 4\nPcr 0.1\n"      /* rough glass */
                        "newmtl plain\nKd 0.5 0.5 0.5\nPc 0\nPcr 0.5\n"        /* no coat */
                        "newmtl file_coat\nnewmtl file_bare\n");
    temp_dir_write_text(fx, "m.mat",
                        "file_coat 0 @roughconductor 0 0 0 0  1 1 1 0  0 0 0  0  0 0 0  0  0.4  0  "
                        "0.5 0.2\n"
                        "file_bare 0 @roughconductor 0 0 0 0  1 1 1 0  0 0 0  0  0 0 0  0  0.4\n");
    const char *names[] = {"varnish", "lacquer", "bottle", "plain", "file_coat", "file_bare"};
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!load_triangles(fx, names, sizeof names / sizeof *names, &scene, &err))
        fail_msg("load: %s", err.msg);

    const vkrt_scene_material *varnish = find(&scene, "varnish");
    assert_string_equal(builtin_of(&scene, varnish), "pbr");
    assert_float_equal(varnish->params[18], 0.5f, 1e-6);
    assert_float_equal(varnish->params[19], 0.3f, 1e-6);
    assert_true(coated(varnish));
    const vkrt_scene_material *lacquer = find(&scene, "lacquer");
    assert_float_equal(lacquer->params[18], 1.0f, 1e-6);
    assert_true(coated(lacquer));
    const vkrt_scene_material *bottle = find(&scene, "bottle");
    assert_string_equal(builtin_of(&scene, bottle), "roughdielectric");
    assert_float_equal(bottle->params[18], 1.0f, 1e-6);
    assert_true(coated(bottle));
    const vkrt_scene_material *plain = find(&scene, "plain");
    assert_string_equal(builtin_of(&scene, plain), "diffuse");
    assert_false(coated(plain));
    const vkrt_scene_material *file_coat = find(&scene, "file_coat");
    assert_float_equal(file_coat->params[18], 0.5f, 1e-6);
    assert_float_equal(file_coat->params[19], 0.2f, 1e-6);
    assert_true(coated(file_coat));
    assert_false(coated(find(&scene, "file_bare")));
    vkrt_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(coat_numbers_and_flag),
        temp_dir_test(sheen_numbers_and_flag),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
