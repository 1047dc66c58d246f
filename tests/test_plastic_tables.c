/*
 * test_plastic_tables.c: @roughplastic's coat tables (src/render/renderer_plastic.c) stay
 * bounded as a scene's plastics multiply, and the shared table a plain roughness then reads
 * gives the picture the exact rows give.
 *
 * The layout, on the CPU: a row for each roughness of an index while there are at most 33 (the
 * mapped table's rows), one mapped table of 33 rows for all of them past that, so that 100 000
 * plastics of distinct roughness over three indices take 99 rows; smooth coats and an index of 1
 * take none. The picture: test_microfacet.c's white furnace with 40 plastic tiles of distinct
 * roughnesses, which fold into the mapped table, against the same tiles rendered in two halves
 * of 20 (exact rows; the other half smooth, which needs none). The pixels draw the same random
 * numbers in the three pictures (streams by pixel and sample), so the tiles differ by the
 * interpolation between rows 1/32 apart alone (0.0018 at most, measured; the coat's T is within
 * 2.5e-3 of its rows at any cosine): within 0.003 plus 4 standard errors of the pixels'
 * differences. A shader that read a shared table wrongly (a row off, the first row, the
 * roughness of a map that is not there) moves a tile by 0.01 or more.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "furnace.h"
#include "render/renderer_private.h"
#include "scene/scene.h"
#include "scene_dir.h"

/* ---- The layout ------------------------------------------------------------------------------ */

/* A roughplastic of index eta and roughness, mapped or not (shader 0 is @roughplastic). */
static vkrt_scene_material plastic(float eta, float roughness, bool mapped)
{
    vkrt_scene_material m = {.shader = 0};
    m.params[11] = eta;
    m.params[16] = roughness;
    for (int k = 0; k < VKRT_MATERIAL_TEXTURE_SLOTS; ++k)
        m.textures[k] = VKRT_SCENE_NO_TEXTURE;
    if (mapped)
        m.textures[2] = 0;
    return m;
}

/* Lays out the tables of mats, all of them @roughplastic, and checks each material's table:
 * that it starts a table of the material's index: where a map varies it, 33 rows to roughness
 * 1; else one row exactly at its roughness or 33 rows to one above it. None for a smooth coat or
 * an index of 1.
 * Returns the layout's rows, its tables in *tables. */
static uint32_t layout_rows_of(const vkrt_scene_materials *mats, uint32_t *tables)
{
    uint32_t count = mats->count;
    const vkrt_scene_material *list = mats->list;
    Material *materials = calloc(count, sizeof *materials);
    assert_non_null(materials);
    renderer_plastic_layout layout;
    vkrt_error err = {{0}};
    assert_true(renderer_plastic_layout_make(mats, materials, &layout, &err));
    for (uint32_t m = 0; m < count; ++m) {
        const char *builtin = mats->shaders[list[m].shader].builtin;
        if (!builtin || strcmp(builtin, "roughplastic") != 0)
            continue; /* the environment */
        float eta = list[m].params[11] > 0 ? list[m].params[11] : 1.5f, r = list[m].params[16];
        if (eta == 1.0f || r < 0.02f) {
            assert_true(materials[m].maps.w == -1.0f);
            continue;
        }
        const renderer_plastic_table *t = NULL;
        for (uint32_t k = 0; k < layout.count; ++k)
            if ((float)layout.tables[k].offset == materials[m].maps.w)
                t = &layout.tables[k];
        assert_non_null(t);
        assert_true(t->eta == eta);
        if (list[m].textures[2] != VKRT_SCENE_NO_TEXTURE)
            assert_true(t->rows == 33 && t->roughness == 1.0f);
        else
            assert_true(t->rows == 1 ? t->roughness == r : t->rows == 33 && r <= t->roughness);
    }
    uint32_t rows = layout.rows;
    *tables = layout.count;
    renderer_plastic_layout_free(&layout);
    free(materials);
    return rows;
}

/* layout_rows_of list[0..count), of shader 0, @roughplastic. */
static uint32_t layout_rows(vkrt_scene_material *list, uint32_t count, uint32_t *tables)
{
    vkrt_shader_source shader = {.builtin = "roughplastic"};
    vkrt_scene_materials mats = {
        .list = list, .count = count, .shaders = &shader, .shader_count = 1};
    return layout_rows_of(&mats, tables);
}

/* Few roughnesses keep their exact rows (the Mitsuba agreement relies on them); 34 fold into a
 * shared table; a map's table serves alongside exact rows, and alongside a shared table of 34
 * plain roughnesses; smooth coats and index 1 need none. */
static void layout_folds_many_roughnesses(void **state)
{
    (void)state;
    vkrt_scene_material list[40];
    uint32_t tables;
    for (uint32_t n = 33; n <= 34; ++n) {
        for (uint32_t m = 0; m < n; ++m)
            list[m] = plastic(0, 0.05f + 0.02f * (float)m, false);
        list[n] = plastic(1.5f, 0.05f, false); /* Ni 0 is 1.5: the same table as the first */
        uint32_t rows = layout_rows(list, n + 1, &tables);
        print_message("%u roughnesses of one index: %u rows in %u tables\n", n, rows, tables);
        assert_int_equal(rows, 33);
        assert_int_equal(tables, n == 33 ? 33 : 1);
    }
    list[0] = plastic(1.5f, 0.3f, true);
    list[1] = plastic(1.5f, 0.3f, false);
    list[2] = plastic(1.5f, 0.3f, false);
    list[3] = plastic(1.5f, 0.4f, false);
    list[4] = plastic(1.3f, 0.4f, false);
    list[5] = plastic(1.5f, 0.01f, false);
    list[6] = plastic(1.0f, 0.5f, false);
    list[7] = plastic(1.3f, 0.3f, true);
    assert_int_equal(layout_rows(list, 8, &tables), 33 + 2 + 1 + 33);
    assert_int_equal(tables, 5);
    for (uint32_t m = 0; m < 35; ++m)
        list[m] = plastic(1.5f, 0.05f + 0.01f * (float)m, m == 0);
    assert_int_equal(layout_rows(list, 35, &tables), 33 + 33);
    assert_int_equal(tables, 2);
}

/* 100 000 plastics of distinct roughness, in no order, over three indices: three shared tables
 * of 33 rows (the rows each would have taken: 1000 s of one core). */
static void layout_of_many_plastics_is_bounded(void **state)
{
    (void)state;
    enum { COUNT = 100000 };
    static const float etas[3] = {1.3f, 1.5f, 2.0f};
    vkrt_scene_material *list = calloc(COUNT, sizeof *list);
    assert_non_null(list);
    for (uint32_t m = 0; m < COUNT; ++m) {
        uint32_t k = (m * 7919u) % COUNT; /* a permutation: the roughnesses in no order */
        list[m] = plastic(etas[m % 3], 0.02f + 0.98f * (float)k / COUNT, false);
    }
    uint32_t tables, rows = layout_rows(list, COUNT, &tables);
    print_message("%d plastics of distinct roughness over 3 indices: %u rows in %u tables\n", COUNT,
                  rows, tables);
    assert_int_equal(rows, 3 * 33);
    assert_int_equal(tables, 3);
    free(list);
}

/* ---- The picture ----------------------------------------------------------------------------- */

enum { COLUMNS = 8, ROWS = 5, TILES = COLUMNS * ROWS, TILE = 8, MARGIN = 1, SPP = 16 };
static const double view_cos = 0.5;

/* Tile k's roughness: 40 of them from 0.04 to 0.99, a step of 0.024 that puts them at every
 * place between two of the shared table's rows (every 1/32). */
static double tile_roughness(int k)
{
    return 0.04 + 0.95 * k / (TILES - 1);
}

/* Writes the furnace with tiles [first, first + count) rough (the others smooth, which need no
 * table), and returns the rows of the layout its materials make. */
static uint32_t write_tiles(int first, int count)
{
    FILE *obj = scene_dir_open("tiles.obj");
    FILE *mtl = scene_dir_open("tiles.mtl");
    FILE *mat = scene_dir_open("tiles.mat");
    fprintf(obj, "mtllib tiles.mtl\n");
    for (int k = 0; k < TILES; ++k) {
        int row = k / COLUMNS, column = k % COLUMNS;
        furnace_write_tile(obj, COLUMNS, ROWS, row, column);
        fprintf(mtl, "newmtl t%d%d\n", row, column);
        double r = k >= first && k < first + count ? tile_roughness(k) : 0.01;
        fprintf(mat, "t%d%d 0 @roughplastic 1 1 1 0  1 1 1 0  0 0 0  1.5  0 0 0  0  %.9g\n", row,
                column, r);
    }
    fclose(obj);
    fclose(mtl);
    fclose(mat);
    furnace_write_cfg(ROWS, view_cos);
    char path[128];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("%s", err.msg);
    uint32_t tables, rows = layout_rows_of(&scene.materials, &tables);
    vkrt_scene_free(&scene);
    return rows;
}

/* Mean and standard error of the pixels' differences a - b over tile k. */
static void tile_difference(const float *a, const float *b, int k, double *mean, double *se)
{
    int w = COLUMNS * TILE, row = k / COLUMNS, column = k % COLUMNS, n = 0;
    double sum = 0, sum2 = 0;
    for (int y = row * TILE + MARGIN; y < (row + 1) * TILE - MARGIN; ++y)
        for (int x = column * TILE + MARGIN; x < (column + 1) * TILE - MARGIN; ++x) {
            const float *p = &a[3 * (y * w + x)], *q = &b[3 * (y * w + x)];
            double d = (p[0] + p[1] + p[2] - q[0] - q[1] - q[2]) / 3.0;
            sum += d;
            sum2 += d * d;
            ++n;
        }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0) / (n - 1));
}

static void shared_table_renders_as_exact_rows(void **state)
{
    (void)state;
    assert_int_equal(write_tiles(0, TILES), 33);
    float *shared =
        furnace_render(COLUMNS, ROWS, TILE, SPP, VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_MIS);
    float *exact[2];
    for (int half = 0; half < 2; ++half) {
        assert_int_equal(write_tiles(half * TILES / 2, TILES / 2), TILES / 2);
        exact[half] =
            furnace_render(COLUMNS, ROWS, TILE, SPP, VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_MIS);
    }
    bool all = true;
    double worst = 0;
    for (int k = 0; k < TILES; ++k) {
        double mean, se, pixel, pixel_se;
        tile_difference(shared, exact[k / (TILES / 2)], k, &mean, &se);
        furnace_tile_mean(shared, COLUMNS, TILE, MARGIN, k / COLUMNS, k % COLUMNS, &pixel,
                          &pixel_se);
        bool ok = fabs(mean) <= 3e-3 + 4 * se;
        if (!ok || k % 8 == 0)
            print_message("roughness %.4f: shared table %.5f, exact rows %.5f, difference "
                          "%+.5f (+- %.5f)%s\n",
                          tile_roughness(k), pixel, pixel - mean, mean, 4 * se, ok ? "" : " off");
        worst = fmax(worst, fabs(mean));
        all &= ok;
    }
    print_message("largest difference of a tile: %.5f\n", worst);
    free(shared);
    free(exact[0]);
    free(exact[1]);
    assert_true(all);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(layout_folds_many_roughnesses),
        cmocka_unit_test(layout_of_many_plastics_is_bounded),
        cmocka_unit_test(shared_table_renders_as_exact_rows),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
