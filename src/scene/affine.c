/* affine.c: 3x4 row-major affine transforms (see affine.h). */
#include "affine.h"

#include <math.h>
#include <string.h>

/* m = op * m for 3x4 row-major affine matrices (op applied after m). */
void vkrt_affine_then(double m[12], const double op[12])
{
    double r[12];
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 4; col++) {
            double v = col == 3 ? op[4 * row + 3] : 0.0;
            for (int k = 0; k < 3; k++)
                v += op[4 * row + k] * m[4 * k + col];
            r[4 * row + col] = v;
        }
    memcpy(m, r, sizeof r);
}

/* The rotation by deg degrees about the unit axis a, counter-clockwise looking down the axis
 * (right-handed, as Blender and glTF rotate), Rodrigues' formula. */
void vkrt_affine_rotation(const double a[3], double deg, double op[12])
{
    double rad = deg * (3.14159265358979323846 / 180.0), c = cos(rad), s = sin(rad), t = 1.0 - c;
    double r[12] = {t * a[0] * a[0] + c,        t * a[0] * a[1] - s * a[2], t * a[0] * a[2] + s * a[1], 0,
                    t * a[0] * a[1] + s * a[2], t * a[1] * a[1] + c,        t * a[1] * a[2] - s * a[0], 0,
                    t * a[0] * a[2] - s * a[1], t * a[1] * a[2] + s * a[0], t * a[2] * a[2] + c,        0};
    memcpy(op, r, sizeof r);
}
