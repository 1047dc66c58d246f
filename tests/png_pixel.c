/*
 * png_pixel.c: prints one pixel of a PNG as 8-bit code values, for the shell tests.
 *   usage: png_pixel A.png X Y
 * Prints "R G B" (the top row is y = 0); exits 1 when the file cannot be read or the pixel is
 * outside it.
 */
#include <stdio.h>
#include <stdlib.h>

#include <stb_image.h>

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: png_pixel A.png X Y\n");
        return 2;
    }
    int w, h, channels;
    unsigned char *rgb = stbi_load(argv[1], &w, &h, &channels, 3);
    int x = atoi(argv[2]), y = atoi(argv[3]);
    if (!rgb || x < 0 || y < 0 || x >= w || y >= h) {
        fprintf(stderr, "png_pixel: cannot read pixel %d %d of %s\n", x, y, argv[1]);
        stbi_image_free(rgb);
        return 1;
    }
    const unsigned char *p = rgb + 3 * ((size_t)y * w + x);
    printf("%d %d %d\n", p[0], p[1], p[2]);
    stbi_image_free(rgb);
    return 0;
}
