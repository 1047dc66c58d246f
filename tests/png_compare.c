/*
 * png_compare.c: compares two PNGs of the same size channel by channel, for the shell tests.
 *   usage: png_compare A.png B.png MAX_DIFFERENCE
 * Prints the size, the largest difference of one 8-bit channel, how many channels differ and the
 * root mean square of the differences (in 8-bit steps: how far a noisy picture is from a
 * converged one); exits 0 when the sizes match and no channel differs by more than
 * MAX_DIFFERENCE, else 1.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <stb_image.h>

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: png_compare A.png B.png MAX_DIFFERENCE\n");
        return 2;
    }
    int wa, ha, wb, hb, channels;
    unsigned char *a = stbi_load(argv[1], &wa, &ha, &channels, 3);
    unsigned char *b = stbi_load(argv[2], &wb, &hb, &channels, 3);
    int max_allowed = atoi(argv[3]);
    int status = 1;
    if (!a || !b) {
        fprintf(stderr, "png_compare: cannot read %s\n", !a ? argv[1] : argv[2]);
    } else if (wa != wb || ha != hb) {
        fprintf(stderr, "png_compare: sizes differ: %dx%d and %dx%d\n", wa, ha, wb, hb);
    } else {
        size_t count = (size_t)wa * ha * 3, differing = 0;
        int largest = 0;
        double squares = 0;
        for (size_t i = 0; i < count; ++i) {
            int d = abs((int)a[i] - (int)b[i]);
            differing += d != 0;
            largest = d > largest ? d : largest;
            squares += (double)d * d;
        }
        printf("%dx%d: largest difference %d, %zu of %zu channels differ, rms %.3f\n", wa, ha,
               largest, differing, count, sqrt(squares / (double)count));
        status = largest <= max_allowed ? 0 : 1;
    }
    stbi_image_free(a);
    stbi_image_free(b);
    return status;
}
