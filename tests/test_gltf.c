/*
 * test_gltf.c: the glTF 2.0 loader (src/scene/gltf/). Small files the test writes itself (JSON
 * with its buffers as base64 data URIs, a .glb built byte by byte) are held against numbers
 * worked out by hand: the geometry with v flipped, node hierarchies, EXT_mesh_gpu_instancing and
 * a mirrored node's reversed winding; the material mapping and KHR_texture_transform (against
 * the extension's own matrix); the lights' 683 lm/W; camera bases; an animated camera's frames
 * (LINEAR, STEP, a CUBICSPLINE that is t^3, a slerp's midpoint); and every kind of bad input,
 * each a message naming the file and what is wrong.
 */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene/gltf/gltf_load.h"
#include "scene/materials.h"
#include "scene/model.h"
#include "temp_dir.h"

/* ---------------------------------------------------------------- building files */

/* A buffer being filled: floats, then 16-bit indices, each view 4-byte aligned. */
typedef struct buf {
    unsigned char data[8192];
    size_t size;
} buf;

static size_t put_floats(buf *b, const float *v, size_t n)
{
    size_t at = b->size;
    memcpy(b->data + b->size, v, n * sizeof(float));
    b->size += n * sizeof(float);
    return at;
}

static size_t put_u16(buf *b, const uint16_t *v, size_t n)
{
    size_t at = b->size;
    memcpy(b->data + b->size, v, n * sizeof(uint16_t));
    b->size += n * sizeof(uint16_t);
    b->size = (b->size + 3) & ~(size_t)3;
    return at;
}

/* The buffer as "data:application/octet-stream;base64,...". */
static const char *data_uri(const buf *b)
{
    static char out[12000];
    static const char *a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *o = out + sprintf(out, "data:application/octet-stream;base64,");
    for (size_t i = 0; i < b->size; i += 3) {
        uint32_t v = (uint32_t)b->data[i] << 16;
        if (i + 1 < b->size)
            v |= (uint32_t)b->data[i + 1] << 8;
        if (i + 2 < b->size)
            v |= b->data[i + 2];
        *o++ = a[v >> 18];
        *o++ = a[(v >> 12) & 63];
        *o++ = i + 1 < b->size ? a[(v >> 6) & 63] : '=';
        *o++ = i + 2 < b->size ? a[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

/* A 2x2 PNG (red, green; blue, white). */
static const char *PNG_URI =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAEklEQVR4nGP4z8DAAMIM/"
    "4EAAB/uBfsL2WiLAAAAAElFTkSuQmCC";

/* The triangle (0,0,0) (1,0,0) (0,1,0) with uv (0,0) (1,0) (0,1): accessors 0 (POSITION),
 * 1 (TEXCOORD_0), 2 (indices), in buffer 0, bufferViews 0-2; `extra` is more JSON after them. */
static char *triangle_json(const char *nodes, const char *meshes, const char *extra)
{
    buf b = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uv[] = {0, 0, 1, 0, 0, 1};
    const uint16_t idx[] = {0, 1, 2};
    size_t p = put_floats(&b, pos, 9), t = put_floats(&b, uv, 6), i = put_u16(&b, idx, 3);
    char *json = malloc(40000);
    snprintf(json, 40000,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":24},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":6}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"},"
             "{\"bufferView\":2,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}],"
             "\"nodes\":[%s],\"meshes\":[%s]%s}",
             b.size, data_uri(&b), p, t, i, nodes, meshes, extra ? extra : "");
    return json;
}

static const char *TRIANGLE_MESH =
    "{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2}]}";

static bool parse_fps(const char *json, float fps, vkrt_model *m, vkrt_error *err)
{
    vkrt_load_options options = {.fps = fps};
    return vkrt_gltf_parse(json, strlen(json), "t.gltf", NULL, &options, m, err);
}

static void load_ok(const char *json, vkrt_model *m)
{
    vkrt_error err = {{0}};
    if (!parse_fps(json, 0, m, &err))
        fail_msg("load failed: %s", err.msg);
}

/* The load fails with a message starting with "t.gltf: " and holding want. */
static void load_fails(const char *json, size_t size, const char *want)
{
    vkrt_model m;
    vkrt_error err = {{0}};
    bool ok = vkrt_gltf_parse(json, size, "t.gltf", NULL, NULL, &m, &err);
    if (ok)
        fail_msg("loaded; wanted an error with '%s'", want);
    if (strncmp(err.msg, "t.gltf: ", 8) != 0 || !strstr(err.msg, want))
        fail_msg("message '%s' does not name the file and '%s'", err.msg, want);
    assert_int_equal(m.mesh_count, 0);
    assert_null(m.meshes);
}

static void assert_near(double got, double want, double tolerance)
{
    if (!(fabs(got - want) <= tolerance))
        fail_msg("got %.9g, want %.9g", got, want);
}

static void assert_vec3(const float *got, double x, double y, double z)
{
    assert_near(got[0], x, 1e-5);
    assert_near(got[1], y, 1e-5);
    assert_near(got[2], z, 1e-5);
}

static const double S45 = 0.70710678118654752;

/* ---------------------------------------------------------------- geometry and nodes */

static void triangle_corners_and_flipped_uv(void **state)
{
    (void)state;
    char *json = triangle_json("{\"mesh\":0,\"translation\":[1,2,3]}", TRIANGLE_MESH, NULL);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.instance_count, 1);
    const vkrt_mesh *mesh = &m.meshes[0];
    assert_int_equal(mesh->triangle_count, 1);
    assert_vec3(mesh->positions + 3, 1, 0, 0);
    assert_vec3(mesh->positions + 6, 0, 1, 0);
    /* v flipped: (0,0) (1,0) (0,1) in glTF is (0,1) (1,1) (0,0) in vkrt. */
    const float want_uv[] = {0, 1, 1, 1, 0, 0};
    for (int k = 0; k < 6; ++k)
        assert_near(mesh->texcoords[k], want_uv[k], 0);
    assert_null(mesh->normals);
    assert_int_equal(mesh->material[0], -1);
    const float want[12] = {1, 0, 0, 1, 0, 1, 0, 2, 0, 0, 1, 3};
    for (int k = 0; k < 12; ++k)
        assert_near(m.instances[0].transform[k], want[k], 1e-6);
    assert_int_equal(m.triangle_count, 1);
    vkrt_model_free(&m);
    free(json);
}

static void hierarchy_and_shared_mesh(void **state)
{
    (void)state;
    /* Parent: translation (1,2,3), 90 degrees about z; child: translation (1,0,0), scale 2. World
     * of the child = T R T_c S_c: rotation columns (0,1,0) (-1,0,0) (0,0,1) times 2, origin
     * (1,2,3) + R (1,0,0) = (1,3,3). */
    char nodes[400];
    snprintf(nodes, sizeof nodes,
             "{\"children\":[1,2],\"translation\":[1,2,3],\"rotation\":[0,0,%.17g,%.17g]},"
             "{\"mesh\":0,\"translation\":[1,0,0],\"scale\":[2,2,2]},{\"mesh\":0}",
             S45, S45);
    char *json = triangle_json(nodes, TRIANGLE_MESH, NULL);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.instance_count, 2);
    const float want[12] = {0, -2, 0, 1, 2, 0, 0, 3, 0, 0, 2, 3};
    for (int k = 0; k < 12; ++k)
        assert_near(m.instances[0].transform[k], want[k], 1e-6);
    const float want2[12] = {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3};
    for (int k = 0; k < 12; ++k)
        assert_near(m.instances[1].transform[k], want2[k], 1e-6);
    assert_int_equal(m.instances[0].mesh, m.instances[1].mesh);
    vkrt_model_free(&m);
    free(json);
}

static void gpu_instancing_adds_one_instance_per_element(void **state)
{
    (void)state;
    buf b = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float tr[] = {10, 0, 0, 20, 0, 0, 30, 0, 5};
    put_floats(&b, pos, 9);
    put_floats(&b, tr, 9);
    char json[20000];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"EXT_mesh_gpu_instancing\"],"
             "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
             "\"nodes\":[{\"mesh\":0,\"scale\":[2,2,2],\"extensions\":{\"EXT_mesh_gpu_instancing\":"
             "{\"attributes\":{\"TRANSLATION\":1}}}}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}]}",
             b.size, data_uri(&b));
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.instance_count, 3);
    /* node * element: scale 2 after the element's translation. */
    assert_near(m.instances[0].transform[0], 2, 0);
    assert_near(m.instances[0].transform[3], 20, 1e-6);
    assert_near(m.instances[1].transform[3], 40, 1e-6);
    assert_near(m.instances[2].transform[3], 60, 1e-6);
    assert_near(m.instances[2].transform[11], 10, 1e-6);
    assert_int_equal(m.triangle_count, 3);
    vkrt_model_free(&m);
}

static void mirrored_node_gets_reversed_winding(void **state)
{
    (void)state;
    char *json = triangle_json("{\"mesh\":0},{\"mesh\":0,\"scale\":[-1,1,1]}", TRIANGLE_MESH, NULL);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.mesh_count, 2);
    assert_int_equal(m.instances[0].mesh, 0);
    assert_int_equal(m.instances[1].mesh, 1);
    /* Corners 1 and 2 swapped: after the mirror x -> -x the world winding is counter-clockwise
     * about +z again, as the file's front face is. */
    assert_vec3(m.meshes[1].positions + 3, 0, 1, 0);
    assert_vec3(m.meshes[1].positions + 6, 1, 0, 0);
    assert_near(m.meshes[1].texcoords[2], 0, 0);
    assert_near(m.meshes[1].texcoords[3], 0, 0);
    vkrt_model_free(&m);
    free(json);
}

static void strips_fans_and_skipped_lines(void **state)
{
    (void)state;
    buf b = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    put_floats(&b, pos, 12);
    char json[20000];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":["
             "{\"attributes\":{\"POSITION\":0},\"mode\":5},{\"attributes\":{\"POSITION\":0},\"mode\":6},"
             "{\"attributes\":{\"POSITION\":0},\"mode\":1}]}]}",
             b.size, data_uri(&b));
    vkrt_model m;
    load_ok(json, &m);
    const vkrt_mesh *mesh = &m.meshes[0];
    assert_int_equal(mesh->triangle_count, 4);
    /* Strip 0 1 2 3: (0 1 2), (2 1 3); fan: (0 1 2), (0 2 3). */
    const int want[12] = {0, 1, 2, 2, 1, 3, 0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 12; ++k)
        assert_vec3(mesh->positions + 3 * k, pos[3 * want[k]], pos[3 * want[k] + 1], 0);
    assert_non_null(strstr(m.warnings, "t.gltf: warning: "));
    assert_non_null(strstr(m.warnings, "points or lines"));
    vkrt_model_free(&m);
}

/* Non-indexed triangles of the given corners (count a multiple of 3), one mesh, one node. */
static void corners_json(char *json, size_t size, const float *pos, size_t corners)
{
    buf b = {0};
    put_floats(&b, pos, 3 * corners);
    snprintf(json, size,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,"
             "\"type\":\"VEC3\"}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}]}",
             b.size, data_uri(&b), b.size, corners);
}

/* Zero-area triangles (corners on a line, or one point twice) are dropped with a warning, as the
 * OBJ loader drops them; a file of nothing else is an error. */
static void zero_area_triangles(void **state)
{
    (void)state;
    char json[4000];
    const float line[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, /* a line */
                          0, 0, 0, 0, 1, 0, 0, 1, 0, /* a repeated corner */
                          0, 0, 0, 1, 0, 0, 0, 1, 0};
    corners_json(json, sizeof json, line, 6);
    load_fails(json, strlen(json), "all 2 triangles have zero area");
    corners_json(json, sizeof json, line, 9);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.meshes[0].triangle_count, 1);
    assert_vec3(m.meshes[0].positions + 6, 0, 1, 0);
    assert_non_null(strstr(m.warnings, "t.gltf: warning: 2 triangles have zero area"));
    vkrt_model_free(&m);
}

/* ---------------------------------------------------------------- materials */

static void material_mapping(void **state)
{
    (void)state;
    char extra[4000];
    snprintf(extra, sizeof extra,
             ",\"images\":[{\"uri\":\"%s\"},{\"uri\":\"maps/rough%%20metal.png\"}],"
             "\"samplers\":[{\"wrapS\":33071,\"wrapT\":33648}],"
             "\"textures\":[{\"source\":0,\"sampler\":0},{\"source\":1}],"
             "\"materials\":[{\"name\":\"paint\",\"pbrMetallicRoughness\":{"
             "\"baseColorFactor\":[0.5,0.25,1,0.4],\"baseColorTexture\":{\"index\":0,"
             "\"extensions\":{\"KHR_texture_transform\":{\"offset\":[0.25,0.5],\"rotation\":0.3,"
             "\"scale\":[2,3],\"texCoord\":1}}},"
             "\"metallicFactor\":0.7,\"roughnessFactor\":0.3,\"metallicRoughnessTexture\":{\"index\":1}},"
             "\"normalTexture\":{\"index\":1,\"scale\":0.5},\"occlusionTexture\":{\"index\":1},"
             "\"emissiveFactor\":[1,0.5,0],\"alphaMode\":\"BLEND\",\"extensions\":{"
             "\"KHR_materials_emissive_strength\":{\"emissiveStrength\":4},"
             "\"KHR_materials_clearcoat\":{\"clearcoatFactor\":0.6,\"clearcoatRoughnessFactor\":0.2},"
             "\"KHR_materials_sheen\":{\"sheenColorFactor\":[0.1,0.9,0.3]},"
             "\"KHR_materials_specular\":{\"specularFactor\":0.5,\"specularColorFactor\":[1,0.5,0.5]}}},"
             "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,1,1,0.4]},\"alphaMode\":\"MASK\","
             "\"alphaCutoff\":0.5},"
             "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.9,0.8,0.7,1],\"roughnessFactor\":0},"
             "\"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":1},"
             "\"KHR_materials_ior\":{\"ior\":1.33},\"KHR_materials_volume\":{}}}]",
             PNG_URI);
    const char *meshes = "{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"material\":0},"
                         "{\"attributes\":{\"POSITION\":0},\"material\":1},"
                         "{\"attributes\":{\"POSITION\":0},\"material\":2}]}";
    char *json = triangle_json("{\"mesh\":0}", meshes, extra);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.material_count, 3);
    const int32_t want_material[3] = {0, 1, 2};
    for (int k = 0; k < 3; ++k)
        assert_int_equal(m.meshes[0].material[k], want_material[k]);
    const vkrt_material *p = &m.materials[0];
    assert_string_equal(p->name, "paint");
    assert_int_equal(p->bsdf, VKRT_BSDF_PRINCIPLED);
    assert_vec3(p->base_colour, 0.5, 0.25, 1);
    assert_near(p->opacity, 0.4, 1e-6);
    assert_near(p->metallic, 0.7, 1e-6);
    assert_near(p->roughness, 0.3, 1e-6);
    assert_vec3(p->emission, 4, 2, 0);
    assert_near(p->coat, 0.6, 1e-6);
    assert_near(p->coat_roughness, 0.2, 1e-6);
    assert_near(p->sheen, 0.9, 1e-6);
    /* F0 of ior 1.5 is 0.04; times 0.5 and max(colour) 1: 0.02, whose index is
     * (1 + sqrt 0.02) / (1 - sqrt 0.02). */
    assert_near(p->ior, (1 + sqrt(0.02)) / (1 - sqrt(0.02)), 1e-5);
    const vkrt_texture_ref *base = &p->maps[VKRT_MAP_BASE_COLOUR];
    assert_int_equal(base->embedded, 0);
    assert_int_equal(m.image_count, 1);
    assert_int_equal(m.images[0].size, 75);
    assert_memory_equal(m.images[0].bytes, "\x89PNG", 4);
    assert_string_equal(base->path, "t.gltf: images[0]");
    assert_int_equal(base->space, VKRT_TEXTURE_COLOUR);
    assert_int_equal(base->sampler.wrap_u, VKRT_WRAP_CLAMP);
    assert_int_equal(base->sampler.wrap_v, VKRT_WRAP_MIRROR);
    assert_int_equal(base->uv_set, 1);
    /* The transform kept as the file gives it (model.h: applied in glTF's own uv, texture.h's
     * vkrt_texture_uv_transform and test_texture check the arithmetic). */
    assert_near(base->uv_offset[0], 0.25, 0);
    assert_near(base->uv_offset[1], 0.5, 0);
    assert_near(base->uv_scale[0], 2, 0);
    assert_near(base->uv_scale[1], 3, 0);
    assert_near(base->uv_rotation, 0.3, 1e-7);
    const vkrt_texture_ref *rough = &p->maps[VKRT_MAP_ROUGHNESS], *metal = &p->maps[VKRT_MAP_METALLIC];
    assert_int_equal(rough->channel, 1);
    assert_int_equal(metal->channel, 2);
    assert_int_equal(rough->embedded, -1);
    assert_string_equal(rough->path, "maps/rough metal.png"); /* no folder: the uri, decoded */
    assert_int_equal(rough->space, VKRT_TEXTURE_DATA);
    assert_int_equal(p->maps[VKRT_MAP_DETAIL].embedded, -1);
    assert_int_equal(p->detail_kind, VKRT_DETAIL_NORMAL);
    assert_near(p->detail_scale, 0.5, 0);
    assert_non_null(strstr(m.warnings, "occlusionTexture"));
    /* MASK: the factor's alpha 0.4 under the cutoff 0.5 hides the surface. */
    assert_near(m.materials[1].opacity, 0, 0);
    const vkrt_material *glass = &m.materials[2];
    assert_int_equal(glass->bsdf, VKRT_BSDF_DIELECTRIC);
    assert_near(glass->ior, 1.33, 1e-6);
    assert_vec3(glass->transmission_filter, 0.9, 0.8, 0.7);
    vkrt_model_free(&m);
    free(json);
}

/* An embedded image decodes through the texture set like a file (materials.c). */
static void embedded_image_decodes(void **state)
{
    (void)state;
    char extra[1000];
    snprintf(extra, sizeof extra,
             ",\"images\":[{\"uri\":\"%s\"}],\"textures\":[{\"source\":0}],"
             "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]",
             PNG_URI);
    const char *meshes = "{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},"
                         "\"material\":0}]}";
    char *json = triangle_json("{\"mesh\":0}", meshes, extra);
    vkrt_model m;
    load_ok(json, &m);
    vkrt_config cfg = {0};
    vkrt_scene_materials mats;
    vkrt_error err = {{0}};
    if (!vkrt_scene_materials_resolve(&cfg, &m, NULL, &mats, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(mats.textures.count, 1);
    assert_int_equal(mats.textures.info[0].width, 2);
    float rgba[4];
    vkrt_texture_texel(&mats.textures, 0, 0, 0, rgba); /* the top left texel: red */
    assert_vec3(rgba, 1, 0, 0);
    vkrt_scene_materials_free(&mats);
    vkrt_model_free(&m);
    free(json);
}

/* ---------------------------------------------------------------- lights and cameras */

static void lights_in_radiometric_units(void **state)
{
    (void)state;
    char nodes[600];
    snprintf(nodes, sizeof nodes,
             "{\"mesh\":0},{\"translation\":[1,2,3],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
             "{\"rotation\":[%.17g,0,0,%.17g],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
             "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}}",
             S45, S45);
    const char *extra =
        ",\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
        "{\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":683,\"range\":10},"
        "{\"type\":\"directional\",\"intensity\":6.83},"
        "{\"type\":\"spot\",\"intensity\":1366,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.5}}]}}";
    char *json = triangle_json(nodes, TRIANGLE_MESH, extra);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.light_count, 3);
    /* 683 cd of colour (1, 0.5, 0.25) is (1, 0.5, 0.25) W/sr. */
    assert_int_equal(m.lights[0].kind, VKRT_LIGHT_POINT);
    assert_vec3(m.lights[0].colour, 1, 0.5, 0.25);
    assert_vec3(m.lights[0].position, 1, 2, 3);
    /* 6.83 lux is 0.01 W/m^2; -z turned 90 degrees about x points along +y. */
    assert_int_equal(m.lights[1].kind, VKRT_LIGHT_DIRECTIONAL);
    assert_vec3(m.lights[1].colour, 0.01, 0.01, 0.01);
    assert_vec3(m.lights[1].direction, 0, 1, 0);
    assert_int_equal(m.lights[2].kind, VKRT_LIGHT_SPOT);
    assert_vec3(m.lights[2].colour, 2, 2, 2);
    assert_vec3(m.lights[2].direction, 0, 0, -1);
    assert_near(m.lights[2].half_angle_deg, 0.5 * 180 / M_PI, 1e-4);
    assert_non_null(strstr(m.warnings_all, "range is ignored"));
    vkrt_model_free(&m);
    free(json);
}

static void camera_bases(void **state)
{
    (void)state;
    char nodes[600];
    snprintf(nodes, sizeof nodes,
             "{\"mesh\":0},{\"camera\":0,\"translation\":[4,5,6],\"rotation\":[0,%.17g,0,%.17g]},"
             "{\"camera\":1,\"name\":\"top\",\"translation\":[0,10,0]}",
             S45, S45);
    const char *extra = ",\"cameras\":[{\"type\":\"perspective\",\"name\":\"main\","
                        "\"perspective\":{\"yfov\":0.5,\"znear\":0.1}},"
                        "{\"type\":\"orthographic\",\"orthographic\":{\"xmag\":3,\"ymag\":2,"
                        "\"znear\":0.1,\"zfar\":100}}]";
    char *json = triangle_json(nodes, TRIANGLE_MESH, extra);
    vkrt_model m;
    load_ok(json, &m);
    assert_int_equal(m.camera_count, 2);
    const vkrt_config_camera *c = &m.cameras[0];
    assert_string_equal(c->name, "main");
    assert_vec3(c->eye, 4, 5, 6);
    /* -z turned 90 degrees about y looks along -x; +y stays up. */
    assert_vec3(c->look, 3, 5, 6);
    assert_vec3(c->up, 0, 1, 0);
    assert_near(c->fov_deg, 0.5 * 180 / M_PI, 1e-4);
    assert_near(c->ortho_width, 0, 0);
    assert_string_equal(m.cameras[1].name, "top");
    assert_near(m.cameras[1].ortho_width, 6, 0);
    vkrt_model_free(&m);
    free(json);
}

/* A camera under node 1, animated by sampler `sampler` (JSON) on `path` of node 1 (or node 2,
 * the camera itself, with on_camera), keys `times` and `values` given as float arrays. */
static char *animated_json(const char *path, const char *interpolation, const float *times,
                           size_t keys, const float *values, size_t value_count, int components)
{
    buf b = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    put_floats(&b, pos, 9);
    size_t t = put_floats(&b, times, keys), v = put_floats(&b, values, value_count);
    char *json = malloc(30000);
    snprintf(json, 30000,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
             "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"SCALAR\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":%zu,\"type\":\"%s\"}],"
             "\"nodes\":[{\"mesh\":0},{\"children\":[2]},{\"camera\":0,\"name\":\"fly\"}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":1,\"znear\":0.1}}],"
             "\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"%s\"}}],"
             "\"samplers\":[{\"input\":1,\"output\":2,\"interpolation\":\"%s\"}]}]}",
             b.size, data_uri(&b), t, keys * 4, v, value_count * 4, keys,
             value_count / (size_t)components, components == 4 ? "VEC4" : "VEC3", path,
             interpolation);
    return json;
}

static void animated_camera_linear_and_step(void **state)
{
    (void)state;
    const float times[] = {0, 1};
    const float values[] = {0, 0, 0, 24, 0, 0};
    char *json = animated_json("translation", "LINEAR", times, 2, values, 6, 3);
    vkrt_model m;
    load_ok(json, &m); /* the default 24 frames per second */
    assert_int_equal(m.camera_count, 25);
    for (uint32_t k = 0; k < 25; ++k) {
        assert_vec3(m.cameras[k].eye, k, 0, 0);
        assert_string_equal(m.cameras[k].name, "fly");
    }
    vkrt_model_free(&m);
    free(json);

    const float step_times[] = {0, 0.5f, 1};
    const float step_values[] = {0, 0, 0, 10, 0, 0, 20, 0, 0};
    json = animated_json("translation", "STEP", step_times, 3, step_values, 9, 3);
    vkrt_error err = {{0}};
    assert_true(parse_fps(json, 4, &m, &err));
    assert_int_equal(m.camera_count, 5);
    const float want[5] = {0, 0, 10, 10, 20};
    for (int k = 0; k < 5; ++k)
        assert_vec3(m.cameras[k].eye, want[k], 0, 0);
    vkrt_model_free(&m);
    free(json);
}

static void animated_camera_cubic_and_slerp(void **state)
{
    (void)state;
    /* Keys 0 and 1 with values 0 and 1, out-tangent 0 and in-tangent 3: the Hermite curve is
     * x = t^3. Each key is (in-tangent, value, out-tangent). */
    const float times[] = {0, 1};
    const float values[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 1, 0, 0, 0, 0, 0};
    char *json = animated_json("translation", "CUBICSPLINE", times, 2, values, 18, 3);
    vkrt_model m;
    vkrt_error err = {{0}};
    assert_true(parse_fps(json, 4, &m, &err));
    assert_int_equal(m.camera_count, 5);
    for (int k = 0; k < 5; ++k)
        assert_vec3(m.cameras[k].eye, pow(k / 4.0, 3), 0, 0);
    vkrt_model_free(&m);
    free(json);

    /* Identity to 90 degrees about y: the midpoint is 45 degrees, looking along
     * (-sin 45, 0, -cos 45). */
    const float rotations[] = {0, 0, 0, 1, 0, (float)S45, 0, (float)S45};
    json = animated_json("rotation", "LINEAR", times, 2, rotations, 8, 4);
    assert_true(parse_fps(json, 2, &m, &err));
    assert_int_equal(m.camera_count, 3);
    assert_vec3(m.cameras[1].look, -S45, 0, -S45);
    assert_vec3(m.cameras[2].look, -1, 0, 0);
    vkrt_model_free(&m);
    free(json);
}

/* ---------------------------------------------------------------- bad input */

static void bad_input_is_named(void **state)
{
    (void)state;
    load_fails("{\"asset\":{\"version\":\"2.0\"", 25, "malformed JSON");
    char *json = triangle_json("{\"mesh\":0}", TRIANGLE_MESH, NULL);
    char *bad = malloc(strlen(json) + 100);
    struct {
        const char *from, *to, *want;
    } edits[] = {
        /* accessor past its buffer view */
        {"\"count\":3,\"type\":\"VEC3\"", "\"count\":4,\"type\":\"VEC3\"",
         "meshes[0].primitives[0]: POSITION: accessors[0]: 4 elements"},
        /* buffer view past its buffer */
        {"\"byteLength\":36}", "\"byteLength\":3600}", "bufferViews[0]: bytes 0 to 3600"},
        /* byteStride below an element */
        {"\"byteLength\":36}", "\"byteLength\":36,\"byteStride\":4}", "byteStride 4"},
        /* a count that overflows */
        {"\"count\":3,\"type\":\"VEC3\"", "\"count\":4294967296,\"type\":\"VEC3\"",
         "more than vkrt reads"},
        /* an index past the vertices: the u16 3 in place of 2 */
        {"\"componentType\":5123,\"count\":3", "\"componentType\":5123,\"count\":3,\"byteOffset\":2",
         "6 bytes of bufferViews[2]"},
        {"\"nodes\":[{\"mesh\":0}]", "\"nodes\":[{\"mesh\":4}]", "nodes[0]: mesh 4"},
        {"\"asset\":{", "\"extensionsRequired\":[\"KHR_draco_mesh_compression\",\"KHR_texture_basisu\"],\"asset\":{",
         "requires extensions vkrt does not support: KHR_draco_mesh_compression, KHR_texture_basisu"},
        {"\"nodes\":[{\"mesh\":0}]", "\"nodes\":[{\"mesh\":0,\"children\":[0]}]", "two parents"},
        {"\"indices\":2", "\"indices\":2,\"mode\":0", "no triangles"},
    };
    for (size_t i = 0; i < sizeof edits / sizeof *edits; ++i) {
        const char *at = strstr(json, edits[i].from);
        assert_non_null(at);
        size_t head = (size_t)(at - json);
        snprintf(bad, strlen(json) + 100, "%.*s%s%s", (int)head, json, edits[i].to,
                 at + strlen(edits[i].from));
        load_fails(bad, strlen(bad), edits[i].want);
    }
    free(bad);
    free(json);
}

static void index_past_the_vertices(void **state)
{
    (void)state;
    buf b = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t idx[] = {0, 1, 3};
    put_floats(&b, pos, 9);
    put_u16(&b, idx, 3);
    char json[8000];
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,"
             "\"byteLength\":6}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,"
             "\"type\":\"VEC3\"},{\"bufferView\":1,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},"
             "\"indices\":1}]}]}",
             b.size, data_uri(&b));
    load_fails(json, strlen(json), "meshes[0].primitives[0]: indices accessors[1]: index 2 is 3, "
                                   "past the 3 vertices of POSITION");
}

static void missing_files_are_named(void **state)
{
    temp_dir *fx = *state;
    const char *text =
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"gone.bin\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"material\":0}]}],"
        "\"images\":[{\"uri\":\"lost.png\"}],\"textures\":[{\"source\":0}],"
        "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]}";
    const char *path = temp_dir_write_text(fx, "m.gltf", text);
    char gltf[512];
    snprintf(gltf, sizeof gltf, "%s", path);
    vkrt_model m;
    vkrt_error err = {{0}};
    assert_false(vkrt_gltf_load(gltf, NULL, &m, &err));
    assert_non_null(strstr(err.msg, gltf));
    assert_non_null(strstr(err.msg, "gone.bin"));
    /* With the .bin there, the image is what is missing. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    temp_dir_write(fx, "gone.bin", pos, sizeof pos);
    assert_false(vkrt_gltf_load(gltf, NULL, &m, &err));
    assert_non_null(strstr(err.msg, "materials[0]: image '"));
    assert_non_null(strstr(err.msg, "lost.png' not found"));
    /* And with it, the model names the .bin as an input and the image by its path. */
    temp_dir_write(fx, "lost.png", "x", 1);
    if (!vkrt_gltf_load(gltf, NULL, &m, &err))
        fail_msg("%s", err.msg);
    assert_non_null(strstr(m.inputs, "gone.bin\n"));
    assert_string_equal(m.materials[0].maps[VKRT_MAP_BASE_COLOUR].path, temp_dir_path(fx, "lost.png"));
    vkrt_model_free(&m);
}

/* ---------------------------------------------------------------- .glb */

static size_t glb(unsigned char *out, const char *json, const void *bin, size_t bin_size)
{
    size_t json_size = (strlen(json) + 3) & ~(size_t)3, bin_padded = (bin_size + 3) & ~(size_t)3;
    uint32_t total = (uint32_t)(12 + 8 + json_size + (bin ? 8 + bin_padded : 0));
    uint32_t head[5] = {0x46546C67u, 2, total, (uint32_t)json_size, 0x4E4F534Au};
    memcpy(out, head, 20);
    memset(out + 20, ' ', json_size);
    memcpy(out + 20, json, strlen(json));
    size_t at = 20 + json_size;
    if (bin) {
        uint32_t chunk[2] = {(uint32_t)bin_padded, 0x004E4942u};
        memcpy(out + at, chunk, 8);
        memset(out + at + 8, 0, bin_padded);
        memcpy(out + at + 8, bin, bin_size);
    }
    return total;
}

static void glb_with_an_embedded_image(void **state)
{
    (void)state;
    unsigned char bin[200] = {0};
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(bin, pos, sizeof pos);
    memcpy(bin + 36, "\x89PNG-not-decoded-here", 21);
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":60}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":21}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
        "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"material\":0}]}],"
        "\"images\":[{\"bufferView\":1,\"mimeType\":\"image/png\",\"name\":\"wood\"}],\"textures\":[{\"source\":0}],"
        "\"materials\":[{\"emissiveTexture\":{\"index\":0}}]}";
    unsigned char file[2000];
    size_t size = glb(file, json, bin, 60);
    vkrt_model m;
    vkrt_error err = {{0}};
    if (!vkrt_gltf_parse(file, size, "t.glb", NULL, NULL, &m, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(m.image_count, 1);
    assert_int_equal(m.images[0].size, 21);
    assert_memory_equal(m.images[0].bytes, bin + 36, 21);
    assert_string_equal(m.images[0].name, "t.glb: images[0] (\"wood\")");
    assert_int_equal(m.materials[0].maps[VKRT_MAP_EMISSION].embedded, 0);
    vkrt_model_free(&m);

    /* A header length that is not the file's, a BIN chunk running past the end (by less than its
     * 8-byte header), an image's buffer view past its buffer. */
    unsigned char broken[2000];
    memcpy(broken, file, size);
    uint32_t wrong = (uint32_t)size + 4;
    memcpy(broken + 8, &wrong, 4);
    assert_false(vkrt_gltf_parse(broken, size, "t.glb", NULL, NULL, &m, &err));
    assert_non_null(strstr(err.msg, "t.glb: the .glb header says"));
    memcpy(broken, file, size);
    size_t bin_at = 20 + ((strlen(json) + 3) & ~(size_t)3);
    uint32_t long_chunk = 64;
    memcpy(broken + bin_at, &long_chunk, 4);
    assert_false(vkrt_gltf_parse(broken, size, "t.glb", NULL, NULL, &m, &err));
    assert_non_null(strstr(err.msg, "second chunk length 64 runs past the end"));
    char *far = strdup(json);
    char *at = strstr(far, "\"byteOffset\":36");
    memcpy(at, "\"byteOffset\":56", 15);
    size = glb(file, far, bin, 60);
    assert_false(vkrt_gltf_parse(file, size, "t.glb", NULL, NULL, &m, &err));
    assert_non_null(strstr(err.msg, "t.glb: images[0]: bufferViews[1] runs past the end"));
    free(far);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(triangle_corners_and_flipped_uv),
        cmocka_unit_test(hierarchy_and_shared_mesh),
        cmocka_unit_test(gpu_instancing_adds_one_instance_per_element),
        cmocka_unit_test(mirrored_node_gets_reversed_winding),
        cmocka_unit_test(strips_fans_and_skipped_lines),
        cmocka_unit_test(zero_area_triangles),
        cmocka_unit_test(material_mapping),
        cmocka_unit_test(embedded_image_decodes),
        cmocka_unit_test(lights_in_radiometric_units),
        cmocka_unit_test(camera_bases),
        cmocka_unit_test(animated_camera_linear_and_step),
        cmocka_unit_test(animated_camera_cubic_and_slerp),
        cmocka_unit_test(bad_input_is_named),
        cmocka_unit_test(index_past_the_vertices),
        temp_dir_test(missing_files_are_named),
        cmocka_unit_test(glb_with_an_embedded_image),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
