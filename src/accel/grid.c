/*
 * grid.c: the compact uniform grid builder (see grid.h).
 *
 * Method: Lagae and Dutré, "Compact, Fast and Robust Grids for Ray Tracing" (EGSR 2008), the
 * seed thesis's Algorithm 1. Three passes over the triangles, O(n) work, two allocations:
 *   1. for every triangle, the cells it overlaps are found and each gets its count incremented
 *      (the counts live in cell_start itself);
 *   2. an exclusive prefix sum turns the counts into cell starts (cell_start[cell_count] is the
 *      reference count);
 *   3. the triangles are scattered into refs in increasing index order, using cell_start[c] as
 *      the write cursor of cell c; afterwards cell_start[c] holds the end of cell c, i.e. the
 *      start of cell c + 1, and one shift by one entry restores the starts. No per-cell
 *      allocation and no second cursor array, and triangle indices within a cell come out sorted.
 *
 * Resolution: the usual density rule (as in Wald et al., "Ray Tracing Animated Scenes using
 * Coherent Grid Traversal", 2006): about density * N cells, as close to cubes as possible,
 * dims[i] = max(1, round(extent[i] * k)) with k = cbrt(density * N / volume). Axes whose rule gives
 * less than one cell (flat or thin scenes) are fixed at one cell and the rule is solved again on
 * the remaining axes (k = (density * N / area)^(1/2), or density * N / length), so a flat plane
 * still gets about density * N cells. If the product exceeds max_cells, k is scaled down.
 *
 * Overlap: each triangle's bounding box gives a range of cells (by the same point-to-cell formula
 * the GPU traversal uses, grid_point_cell below); when that range spans several cells along two
 * or three axes, cells are checked with the exact triangle-box separating axis test of
 * Akenine-Möller ("Fast 3D Triangle-Box Overlap Testing", 2001) in double precision, row by row
 * (see for_each_overlapped_cell), against the cell enlarged by
 * OVERLAP_EPS_CELL of a cell plus a few float ulps of the coordinates. The enlargement makes the
 * test conservative: a cell that the triangle touches, or that float rounding of the point-to-cell
 * formula may put one of its points in, is never rejected; the price is an occasional reference
 * to a cell the triangle only grazes within the epsilon.
 */
#include "grid.h"
#include "../clock.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Why 2: the per-ray cost is about (cells stepped) * c_step + (triangles tested) * c_tri. Cells
 * stepped grow like cbrt(density), triangles tested fall like 1/density until a cell holds about
 * one triangle. The test's density sweep (VKRT_GRID_SWEEP=1, 100k random rays, CPU DDA) gives
 * steps + tests per ray for density 0.5 / 1 / 2 / 4 / 8:
 *   bunny (69k):        18.7+47.8  23.3+33.5  29.3+23.5  36.6+17.0  46.2+12.4
 *   lost empire (225k): 18.1+35.5  22.6+24.5  28.2+17.0  35.4+12.2  44.4+9.3
 * With c_tri / c_step = 1 (a step costing as much as a test) the minimum of the model is at 2 for
 * both scenes; with 2.5 (a GPU, where a test gathers 36+ bytes per triangle and a step reads one
 * cell_start pair) it moves to 4..8, and 2 is 7% (lost empire) to 14% (bunny) above it, at a
 * quarter of the cell memory of 8 (4 bytes per cell). The CPU sweep's wall time per ray is lowest
 * at 0.5..1 (its steps recompute boundaries with divisions, so c_step is large there). Hence 2,
 * a middle value. Denser grids trace faster on GPUs at more memory, but `accel auto` picks the
 * grid only on CPU devices, where 2 is the configuration it was chosen for, so 2 stays the
 * default. */
#define GRID_DEFAULT_DENSITY 2.0f
#define GRID_DEFAULT_MAX_CELLS (1u << 24)

/* Bounds padding, so that triangles on the scene's boundary lie strictly inside the grid:
 * relative to the largest extent, plus a few ulps of the largest coordinate magnitude (a scene far
 * from the origin), plus a tiny absolute amount (a scene that is a single point). */
#define PAD_REL_EXTENT 1e-5
#define PAD_REL_MAGNITUDE (8.0 * FLT_EPSILON)
#define PAD_ABS 1e-30

/* Overlap test enlargement of each cell, per axis: a fraction of the cell size plus a few float
 * ulps of the coordinates' magnitude. Float rounding in grid_point_cell moves a point by far less
 * than either, so a cell that can receive one of the triangle's points is never rejected. */
#define OVERLAP_EPS_CELL 1e-4
#define OVERLAP_EPS_MAGNITUDE (8.0 * FLT_EPSILON)

float grid_default_density(void)
{
    return GRID_DEFAULT_DENSITY;
}

/* The cell of coordinate p along one axis: clamp(floor((p - lo) / cell_size), 0, dims - 1), in
 * float, the formula the GPU traversal uses (glsl/lib/traverse_grid.glsl). Clamping in float
 * before converting keeps far-away or NaN values from overflowing the integer conversion; for
 * f >= 0 the truncating conversion is floor (and avoids a libm call on baseline x86-64). */
static uint32_t grid_point_cell(float p, float lo, float cell_size, uint32_t dims)
{
    float f = (p - lo) / cell_size;
    if (!(f >= 0.0f))
        return 0;
    if (f >= (float)dims)
        return dims - 1;
    uint32_t c = (uint32_t)f;
    return c < dims ? c : dims - 1;
}

/* Plain comparisons: fminf/fmaxf are libm calls without -ffast-math, and inputs are finite. */
static float min3f(float a, float b, float c)
{
    float m = a < b ? a : b;
    return m < c ? m : c;
}

static float max3f(float a, float b, float c)
{
    float m = a > b ? a : b;
    return m > c ? m : c;
}

/* ------------------------------------------------------------------------ bounds and resolution */

static bool scene_bounds(const float *positions, uint32_t triangle_count, double lo[3],
                         double hi[3], vkrt_error *err)
{
    for (int a = 0; a < 3; ++a) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (uint64_t i = 0; i < (uint64_t)triangle_count * 3; ++i) {
        const float *v = positions + 3 * i;
        for (int a = 0; a < 3; ++a) {
            if (!isfinite(v[a]))
                return vkrt_error_set(err, "triangle %llu has a non-finite coordinate",
                                      (unsigned long long)(i / 3));
            lo[a] = v[a] < lo[a] ? v[a] : lo[a];
            hi[a] = v[a] > hi[a] ? v[a] : hi[a];
        }
    }
    return true;
}

/* Pads the bounds (see PAD_*) and stores them as floats in g, rounded outwards. */
static void set_padded_bounds(grid *g, const double lo[3], const double hi[3])
{
    double max_extent = 0.0, magnitude = 0.0;
    for (int a = 0; a < 3; ++a) {
        max_extent = fmax(max_extent, hi[a] - lo[a]);
        magnitude = fmax(magnitude, fmax(fabs(lo[a]), fabs(hi[a])));
    }
    double pad = PAD_REL_EXTENT * max_extent + PAD_REL_MAGNITUDE * magnitude + PAD_ABS;
    for (int a = 0; a < 3; ++a) {
        g->lo[a] = nextafterf((float)(lo[a] - pad), -INFINITY);
        g->hi[a] = nextafterf((float)(hi[a] + pad), INFINITY);
    }
}

/* dims[a] = max(1, round(extent[a] * k)) on the active axes, 1 elsewhere; returns the product. */
static uint64_t dims_for_scale(const double extent[3], const bool active[3], double k,
                               bool round_down, uint32_t dims[3])
{
    uint64_t product = 1;
    for (int a = 0; a < 3; ++a) {
        double d = active[a] ? extent[a] * k : 1.0;
        d = round_down ? floor(d) : floor(d + 0.5);
        /* Cap each axis at a value whose product with the others still fits in 64 bits. */
        d = fmin(fmax(d, 1.0), (double)(1u << 20));
        dims[a] = (uint32_t)d;
        product *= dims[a];
    }
    return product;
}

/* The density rule on the axes that get at least one cell from it (see the top comment). */
static void choose_dims(const float glo[3], const float ghi[3], double target_cells,
                        uint32_t max_cells, uint32_t dims[3])
{
    double extent[3];
    bool active[3];
    for (int a = 0; a < 3; ++a) {
        extent[a] = (double)ghi[a] - (double)glo[a];
        active[a] = true;
    }
    double k = 0.0;
    /* At most three rounds: each round fixes at least one more axis at one cell, or stops. */
    for (int round_i = 0; round_i < 3; ++round_i) {
        double measure = 1.0;
        int n = 0;
        for (int a = 0; a < 3; ++a)
            if (active[a]) {
                measure *= extent[a];
                ++n;
            }
        if (n == 0)
            break;
        k = pow(target_cells / measure, 1.0 / n);
        bool changed = false;
        for (int a = 0; a < 3; ++a)
            if (active[a] && extent[a] * k < 1.0) {
                active[a] = false;
                changed = true;
            }
        if (!changed)
            break;
    }
    int n_active = (int)active[0] + (int)active[1] + (int)active[2];
    uint64_t product = dims_for_scale(extent, active, k, false, dims);
    /* Too many cells: shrink k in proportion, rounding down, until the grid fits. */
    for (int tries = 0; product > max_cells && tries < 64; ++tries) {
        k *= pow((double)max_cells / (double)product, 1.0 / (n_active > 0 ? n_active : 1)) * 0.999;
        product = dims_for_scale(extent, active, k, true, dims);
    }
    while (product > max_cells) { /* last resort: halve the largest axis */
        int big = dims[0] >= dims[1] ? (dims[0] >= dims[2] ? 0 : 2) : (dims[1] >= dims[2] ? 1 : 2);
        dims[big] = dims[big] / 2 > 0 ? dims[big] / 2 : 1;
        product = (uint64_t)dims[0] * dims[1] * dims[2];
    }
}

/* ------------------------------------------------------------------------ triangle-box overlap */

/* The separating axis test of Akenine-Möller, arranged for many boxes of one size: all cells
 * have the same half sizes h, so each candidate axis, the triangle's projection interval on it and
 * the box's projection radius are computed once per triangle (sat_setup), and each cell then costs
 * one dot product per axis (sat_overlaps). Of the 13 axes (3 box normals, the triangle's normal,
 * 9 products edge x box axis) those parallel to a coordinate axis are dropped: they are box
 * normals, and the cells visited lie in the triangle's bounding-box cell range, which they
 * overlap along every coordinate axis already (up to rounding, which the enlargement covers).
 * Zero axes (parallel edges, degenerate triangles) never separate and are dropped too. Dropping an
 * axis can only turn a rejection into an acceptance, so the test stays conservative; it remains
 * exact for segments and points, whose separating axes are a subset of the 13. Axis-aligned
 * triangles (common in architectural and voxel scenes) keep only one or two axes. */
#define SAT_MAX_AXES 10

typedef struct sat_triangle {
    double ax[SAT_MAX_AXES], ay[SAT_MAX_AXES], az[SAT_MAX_AXES];
    double pmin[SAT_MAX_AXES], pmax[SAT_MAX_AXES]; /* triangle's projection interval */
    double r[SAT_MAX_AXES];                        /* box's projection radius around its centre */
    int count;
} sat_triangle;

static void sat_add_axis(sat_triangle *s, const double v[3][3], const double h[3], double x,
                         double y, double z)
{
    int nonzero = (x != 0.0) + (y != 0.0) + (z != 0.0);
    if (nonzero <= 1)
        return;
    double p0 = v[0][0] * x + v[0][1] * y + v[0][2] * z;
    double p1 = v[1][0] * x + v[1][1] * y + v[1][2] * z;
    double p2 = v[2][0] * x + v[2][1] * y + v[2][2] * z;
    int k = s->count++;
    s->ax[k] = x;
    s->ay[k] = y;
    s->az[k] = z;
    double lo = p0 < p1 ? p0 : p1, hi = p0 < p1 ? p1 : p0;
    s->pmin[k] = lo < p2 ? lo : p2;
    s->pmax[k] = hi > p2 ? hi : p2;
    s->r[k] = h[0] * fabs(x) + h[1] * fabs(y) + h[2] * fabs(z);
}

static void sat_setup(sat_triangle *s, const double v[3][3], const double h[3])
{
    s->count = 0;
    double e[3][3];
    for (int i = 0; i < 3; ++i)
        for (int a = 0; a < 3; ++a)
            e[i][a] = v[(i + 1) % 3][a] - v[i][a];
    sat_add_axis(s, v, h, e[0][1] * e[1][2] - e[0][2] * e[1][1],
                 e[0][2] * e[1][0] - e[0][0] * e[1][2], e[0][0] * e[1][1] - e[0][1] * e[1][0]);
    for (int i = 0; i < 3; ++i) {
        sat_add_axis(s, v, h, 0.0, e[i][2], -e[i][1]);  /* e x (1, 0, 0) */
        sat_add_axis(s, v, h, -e[i][2], 0.0, e[i][0]);  /* e x (0, 1, 0) */
        sat_add_axis(s, v, h, e[i][1], -e[i][0], 0.0);  /* e x (0, 0, 1) */
    }
}

/* Whether the box with centre (cx, cy, cz) and the half sizes given to sat_setup overlaps the
 * triangle. */
static bool sat_overlaps(const sat_triangle *s, double cx, double cy, double cz)
{
    for (int k = 0; k < s->count; ++k) {
        double cp = s->ax[k] * cx + s->ay[k] * cy + s->az[k] * cz;
        if (s->pmin[k] - cp > s->r[k] || s->pmax[k] - cp < -s->r[k])
            return false;
    }
    return true;
}

/* ------------------------------------------------------------------------ the three passes */

/* What the passes need to know about the grid, precomputed once. */
typedef struct build_ctx {
    const grid *g;
    double eps[3];     /* overlap test enlargement per axis */
} build_ctx;

/* The triangle's bounding-box cell range [c0, c1] per axis. */
static void triangle_cell_range(const grid *g, const float *t, uint32_t c0[3], uint32_t c1[3])
{
    for (int a = 0; a < 3; ++a) {
        float mn = min3f(t[a], t[3 + a], t[6 + a]);
        float mx = max3f(t[a], t[3 + a], t[6 + a]);
        c0[a] = grid_point_cell(mn, g->lo[a], g->cell_size[a], g->dims[a]);
        c1[a] = grid_point_cell(mx, g->lo[a], g->cell_size[a], g->dims[a]);
    }
}

/* Calls visit(cell, tri_index, user) for each cell that triangle tri_index overlaps. Written as
 * one function for the counting and the scatter pass, so both see exactly the same cells. */
typedef void (*cell_visitor)(uint32_t cell, uint32_t tri_index, void *user);

/* Whether cell (x, y, z) passes the separating axis test. */
static bool cell_overlaps(const grid *g, const sat_triangle *sat, const uint32_t cell[3])
{
    return sat_overlaps(sat, g->lo[0] + ((double)cell[0] + 0.5) * g->cell_size[0],
                        g->lo[1] + ((double)cell[1] + 0.5) * g->cell_size[1],
                        g->lo[2] + ((double)cell[2] + 0.5) * g->cell_size[2]);
}

static uint32_t linear_index(const grid *g, const uint32_t cell[3])
{
    return cell[0] + g->dims[0] * (cell[1] + g->dims[1] * cell[2]);
}

static void for_each_overlapped_cell(const build_ctx *ctx, const float *t, uint32_t tri_index,
                                     cell_visitor visit, void *user)
{
    const grid *g = ctx->g;
    uint32_t c0[3], c1[3], cell[3];
    triangle_cell_range(g, t, c0, c1);
    /* The separating axis test is needed only when the range spans several cells along two or
     * three axes. Within one cell, or a row of cells along a single axis, the triangle touches
     * every cell of the range: it is connected and reaches from the first cell of the row to the
     * last, while the other axes hold one cell each. */
    int spanning_axes = (c0[0] != c1[0]) + (c0[1] != c1[1]) + (c0[2] != c1[2]);
    if (spanning_axes <= 1) {
        for (cell[2] = c0[2]; cell[2] <= c1[2]; ++cell[2])
            for (cell[1] = c0[1]; cell[1] <= c1[1]; ++cell[1])
                for (cell[0] = c0[0]; cell[0] <= c1[0]; ++cell[0])
                    visit(linear_index(g, cell), tri_index, user);
        return;
    }
    sat_triangle sat;
    double tri[3][3], h[3];
    for (int i = 0; i < 3; ++i)
        for (int a = 0; a < 3; ++a)
            tri[i][a] = t[3 * i + a];
    for (int a = 0; a < 3; ++a)
        h[a] = 0.5 * (double)g->cell_size[a] + ctx->eps[a];
    sat_setup(&sat, tri, h);
    /* Rows along the axis of the longest span. The cells of a row that the triangle overlaps are
     * contiguous (the triangle's intersection with the row's box is convex, so its projection on
     * the row axis is one interval), so only the cells from each end up to the first overlap are
     * tested and the ones between are taken as they are. Taking the cells between can only add
     * references, so rounding can never make this drop one. */
    int ra = 0;
    for (int a = 1; a < 3; ++a)
        if (c1[a] - c0[a] > c1[ra] - c0[ra])
            ra = a;
    int oa = (ra + 1) % 3, ob = (ra + 2) % 3;
    for (cell[ob] = c0[ob]; cell[ob] <= c1[ob]; ++cell[ob])
        for (cell[oa] = c0[oa]; cell[oa] <= c1[oa]; ++cell[oa]) {
            cell[ra] = c0[ra];
            while (cell[ra] <= c1[ra] && !cell_overlaps(g, &sat, cell))
                ++cell[ra];
            if (cell[ra] > c1[ra])
                continue;
            uint32_t first = cell[ra];
            cell[ra] = c1[ra];
            while (cell[ra] > first && !cell_overlaps(g, &sat, cell))
                --cell[ra];
            uint32_t last = cell[ra];
            for (cell[ra] = first; cell[ra] <= last; ++cell[ra])
                visit(linear_index(g, cell), tri_index, user);
        }
}

static void count_visit(uint32_t cell, uint32_t tri_index, void *user)
{
    (void)tri_index;
    ((uint32_t *)user)[cell]++;
}

typedef struct scatter_state {
    uint32_t *cursor; /* cell_start, used as per-cell write position */
    uint32_t *refs;
} scatter_state;

static void scatter_visit(uint32_t cell, uint32_t tri_index, void *user)
{
    scatter_state *s = user;
    s->refs[s->cursor[cell]++] = tri_index;
}

/* Pass 2: counts to exclusive starts, in 64 bits; false if the total exceeds UINT32_MAX. */
static bool exclusive_scan(uint32_t *cell_start, uint32_t cell_count, uint64_t *total,
                           uint32_t *max_count, uint32_t *occupied)
{
    uint64_t sum = 0;
    *max_count = 0;
    *occupied = 0;
    for (uint32_t c = 0; c < cell_count; ++c) {
        uint32_t n = cell_start[c];
        *max_count = n > *max_count ? n : *max_count;
        *occupied += n > 0;
        cell_start[c] = (uint32_t)sum; /* only stored while sum fits; checked below */
        sum += n;
        if (sum > UINT32_MAX)
            return false;
    }
    cell_start[cell_count] = (uint32_t)sum;
    *total = sum;
    return true;
}

static bool setup_frame(grid *g, const float *positions, uint32_t triangle_count,
                        const grid_build_desc *desc, vkrt_error *err)
{
    float density = desc && desc->density > 0.0f ? desc->density : GRID_DEFAULT_DENSITY;
    uint32_t max_cells = desc && desc->max_cells > 0 ? desc->max_cells : GRID_DEFAULT_MAX_CELLS;
    if (!isfinite(density))
        return vkrt_error_set(err, "grid density %g is not finite", (double)density);
    if (max_cells == UINT32_MAX) /* cell_start needs cell_count + 1 entries */
        max_cells = UINT32_MAX - 1;
    double lo[3], hi[3];
    if (!scene_bounds(positions, triangle_count, lo, hi, err))
        return false;
    set_padded_bounds(g, lo, hi);
    double target = fmax(1.0, (double)density * (double)triangle_count);
    choose_dims(g->lo, g->hi, target, max_cells, g->dims);
    for (int a = 0; a < 3; ++a)
        g->cell_size[a] = (g->hi[a] - g->lo[a]) / (float)g->dims[a];
    g->cell_count = g->dims[0] * g->dims[1] * g->dims[2];
    return true;
}

bool grid_build(grid *out, const float *positions, uint32_t triangle_count,
                const grid_build_desc *desc, vkrt_error *err)
{
    double t_start = vkrt_clock_ms();
    memset(out, 0, sizeof *out);
    if (triangle_count == 0 || !positions)
        return vkrt_error_set(err, "grid: no triangles");
    grid g;
    memset(&g, 0, sizeof g);
    if (!setup_frame(&g, positions, triangle_count, desc, err))
        return vkrt_error_prefix(err, "grid");

    g.cell_start = calloc((size_t)g.cell_count + 1, sizeof *g.cell_start);
    if (!g.cell_start)
        return vkrt_error_set(err, "grid: out of memory for %u cells", g.cell_count);

    build_ctx ctx = { .g = &g };
    for (int a = 0; a < 3; ++a)
        ctx.eps[a] = OVERLAP_EPS_CELL * g.cell_size[a] +
                     OVERLAP_EPS_MAGNITUDE * fmax(fabs(g.lo[a]), fabs(g.hi[a]));

    /* Pass 1: count. */
    for (uint32_t i = 0; i < triangle_count; ++i)
        for_each_overlapped_cell(&ctx, positions + 9 * (size_t)i, i, count_visit, g.cell_start);

    /* Pass 2: prefix sum. */
    uint64_t total = 0;
    if (!exclusive_scan(g.cell_start, g.cell_count, &total, &g.max_cell_refs, &g.occupied_cells)) {
        grid_free(&g);
        return vkrt_error_set(err, "grid: more than %u triangle references (density too high?)",
                              UINT32_MAX);
    }
    g.ref_count = (uint32_t)total;
    g.refs = malloc((size_t)(total > 0 ? total : 1) * sizeof *g.refs);
    if (!g.refs) {
        grid_free(&g);
        return vkrt_error_set(err, "grid: out of memory for %llu triangle references",
                              (unsigned long long)total);
    }

    /* Pass 3: scatter in triangle order, then shift the ends back into starts. */
    scatter_state s = { .cursor = g.cell_start, .refs = g.refs };
    for (uint32_t i = 0; i < triangle_count; ++i)
        for_each_overlapped_cell(&ctx, positions + 9 * (size_t)i, i, scatter_visit, &s);
    memmove(g.cell_start + 1, g.cell_start, (size_t)g.cell_count * sizeof *g.cell_start);
    g.cell_start[0] = 0;

    g.build_ms = vkrt_clock_ms() - t_start;
    *out = g;
    return true;
}

void grid_free(grid *g)
{
    if (!g)
        return;
    free(g->cell_start);
    free(g->refs);
    memset(g, 0, sizeof *g);
}
