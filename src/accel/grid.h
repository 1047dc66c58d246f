/*
 * grid.h: a uniform grid over triangles in compact form (Lagae and Dutré, "Compact, Fast and
 * Robust Grids for Ray Tracing", 2008): one array of cell starts and one of triangle references,
 * built in O(n) by counting, prefix sum and scatter (the seed thesis's Algorithm 1).
 */
#ifndef VKRT_GRID_H
#define VKRT_GRID_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"

typedef struct grid_build_desc {
    float density;        /* lambda: the grid has about density * N cells for N triangles; 0: default */
    uint32_t max_cells;   /* upper bound on the cell count; 0: 1 << 24 */
} grid_build_desc;

typedef struct grid {
    float lo[3], hi[3];        /* bounds of the grid (the scene's bounds, slightly padded) */
    float cell_size[3];        /* (hi - lo) / dims */
    uint32_t dims[3];          /* cells per axis, each >= 1 */
    uint32_t cell_count;       /* dims[0] * dims[1] * dims[2] */
    uint32_t *cell_start;      /* cell_count + 1 entries: cell c holds refs[cell_start[c] ..
                                  cell_start[c + 1] - 1]; cell c = x + dims[0] * (y + dims[1] * z) */
    uint32_t *refs;            /* triangle indices (original order), ref_count of them */
    uint32_t ref_count;
    uint32_t max_cell_refs;    /* the fullest cell's reference count */
    uint32_t occupied_cells;   /* cells with at least one reference */
    double build_ms;
} grid;

/* The default density (lambda), chosen by measurement: see grid.c. */
float grid_default_density(void);

/* Builds the grid over triangle_count triangles (positions: 9 floats each, all finite). Every
 * triangle is referenced by every cell it overlaps (and possibly a few it does not touch, when the
 * overlap test is conservative). desc may be NULL. On failure returns false with err set and *out
 * zeroed. */
bool grid_build(grid *out, const float *positions, uint32_t triangle_count,
                const grid_build_desc *desc, vkrt_error *err);

/* Frees what grid_build allocated and zeroes *g. Safe on a zeroed struct. */
void grid_free(grid *g);

#endif
