/*
 * affine.h: 3x4 row-major affine transforms, world = m * (x, y, z, 1), as scene.cfg's placements
 * and the model's instances hold them. Pure arithmetic in double.
 */
#ifndef VKRT_AFFINE_H
#define VKRT_AFFINE_H

/* m = op * m: op applied after m. */
void vkrt_affine_then(double m[12], const double op[12]);

/* The rotation by deg degrees about the unit axis a, counter-clockwise looking down the axis
 * towards the origin (right-handed, as Blender and glTF turn), by Rodrigues' formula. */
void vkrt_affine_rotation(const double a[3], double deg, double op[12]);

#endif
