/*
 * emitters.c: the alias table over the emissive triangles (see emitters.h).
 *
 * Vose's method ("A linear algorithm for generating random numbers with a given distribution",
 * IEEE TSE 1991), written so that rounding cannot move probability between triangles: every
 * entry's probability is scaled to a mean of 1, entries below 1 ("small") are filled up from
 * entries above 1 ("large"), and what a large entry gives away is subtracted using the keep value
 * as it will be stored (a float), not the exact one. The GPU then sees a table whose probabilities
 * sum per triangle to power / total up to the rounding of that triangle's own keep, however many
 * entries alias to it. Entries left over when one list runs dry hold a mass of 1 up to rounding
 * and keep themselves.
 */
#include "emitters.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"
#include "colour.h"
#include "model.h"

/* The table's arrays are uploaded as Emitter records: keep the field types in step. */
_Static_assert(sizeof(Emitter) == 4 * sizeof(uint32_t), "Emitter is four 32-bit fields");


/* Fills keep and alias from power (count entries, all > 0, summing to total). */
static bool build_table(vkrt_emitters *e, const double *power, double total)
{
    uint32_t n = e->count;
    double *scaled = malloc((size_t)n * sizeof *scaled);
    /* One array for both work lists: small ones grow from the front, large ones from the back. */
    uint32_t *work = malloc((size_t)n * sizeof *work);
    if (!scaled || !work) {
        free(scaled);
        free(work);
        return false;
    }
    uint32_t small = 0, large = n; /* small: work[0, small); large: work[large, n) */
    double mean_to_one = (double)n / total;
    for (uint32_t i = 0; i < n; i++) {
        scaled[i] = power[i] * mean_to_one;
        if (scaled[i] < 1.0)
            work[small++] = i;
        else
            work[--large] = i;
    }
    /* Invariant: the entries on the lists hold the mass still to be placed, scaled[i] each, and
     * every entry off the lists has its keep and alias final. */
    while (small > 0 && large < n) {
        uint32_t s = work[--small];
        uint32_t l = work[large];
        float keep = (float)scaled[s];
        e->keep[s] = keep;
        e->alias[s] = l;
        /* The mass l gives to s is what the float keep leaves over, exactly. */
        scaled[l] -= 1.0 - (double)keep;
        if (scaled[l] < 1.0) {
            large++;
            work[small++] = l;
        }
    }
    /* Leftovers hold 1 up to rounding (the scaled masses sum to n): they keep themselves. */
    for (uint32_t k = 0; k < small; k++) {
        e->keep[work[k]] = 1.0f;
        e->alias[work[k]] = work[k];
    }
    for (uint32_t k = large; k < n; k++) {
        e->keep[work[k]] = 1.0f;
        e->alias[work[k]] = work[k];
    }
    free(scaled);
    free(work);
    return true;
}

bool vkrt_emitters_build(const float *positions, uint32_t triangle_count,
                         const uint32_t *triangle_material, const float *material_ke,
                         uint32_t material_count, vkrt_emitters *out, vkrt_error *err)
{
    if (!out)
        return vkrt_error_set(err, "emitters: no table to fill");
    memset(out, 0, sizeof *out);
    if (triangle_count > 0 && (!positions || !triangle_material))
        return vkrt_error_set(err, "emitters: no triangles given for a count of %u",
                              triangle_count);
    if (material_count > 0 && !material_ke)
        return vkrt_error_set(err, "emitters: no Ke given for %u materials", material_count);
    for (uint32_t m = 0; m < material_count; m++) {
        const float *ke = material_ke + (size_t)m * 3;
        for (int k = 0; k < 3; k++)
            if (!(ke[k] >= 0.0f && isfinite(ke[k])))
                return vkrt_error_set(err,
                                      "emitters: material %u has a negative or non-finite "
                                      "Ke (channel %d)",
                                      m, k);
    }

    /* First pass: count, so the arrays are allocated once. */
    uint32_t count = 0;
    for (uint32_t t = 0; t < triangle_count; t++) {
        uint32_t m = triangle_material[t];
        if (m >= material_count)
            return vkrt_error_set(err,
                                  "emitters: triangle %u has material %u, out of range "
                                  "(%u materials)",
                                  t, m, material_count);
        if (vkrt_luminance(material_ke + (size_t)m * 3) > 0.0 &&
            vkrt_triangle_area(positions, t) > 0.0)
            count++;
    }
    if (count == 0)
        return true;

    out->count = count;
    out->triangle = malloc((size_t)count * sizeof *out->triangle);
    out->keep = malloc((size_t)count * sizeof *out->keep);
    out->alias = malloc((size_t)count * sizeof *out->alias);
    out->power = malloc((size_t)count * sizeof *out->power);
    double *power = malloc((size_t)count * sizeof *power);
    if (!out->triangle || !out->keep || !out->alias || !out->power || !power) {
        free(power);
        vkrt_emitters_free(out);
        return vkrt_error_set(err, "emitters: out of memory for %u emissive triangles", count);
    }

    double total = 0.0;
    uint32_t i = 0;
    for (uint32_t t = 0; t < triangle_count; t++) {
        double lum = vkrt_luminance(material_ke + (size_t)triangle_material[t] * 3);
        double area = vkrt_triangle_area(positions, t);
        if (!(lum > 0.0 && area > 0.0))
            continue;
        double p = lum * area;
        /* The GPU reads power and the total as floats: refuse what they cannot hold. */
        if (!((float)p <= FLT_MAX)) {
            free(power);
            vkrt_emitters_free(out);
            return vkrt_error_set(err,
                                  "emitters: triangle %u: its power, luminance(Ke) * area = "
                                  "%g, does not fit a float",
                                  t, p);
        }
        out->triangle[i] = t;
        out->power[i] = (float)p;
        power[i] = p;
        total += p;
        i++;
    }
    if (!((float)total <= FLT_MAX)) {
        free(power);
        vkrt_emitters_free(out);
        return vkrt_error_set(err,
                              "emitters: the total power of %u emissive triangles, %g, does "
                              "not fit a float",
                              count, total);
    }
    out->total_power = total;
    bool ok = build_table(out, power, total);
    free(power);
    if (!ok) {
        vkrt_emitters_free(out);
        return vkrt_error_set(err, "emitters: out of memory for %u emissive triangles", count);
    }
    return true;
}

void vkrt_emitters_free(vkrt_emitters *e)
{
    if (!e)
        return;
    free(e->triangle);
    free(e->keep);
    free(e->alias);
    free(e->power);
    memset(e, 0, sizeof *e);
}
