/*
 * srgb8_check.c: src/output/srgb8.h's table against its exact encoding on every one of the 2^32
 * float bit patterns (about a minute on one core): prints the patterns where they differ (none
 * is the claim srgb8.h makes) and exits 1 if there is one. tests/test_srgb8.c checks a sample
 * of them on every build; this is the whole proof, run when the table or the curve changes.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output/srgb8.h"

int main(void)
{
    srgb8_table *table = malloc(sizeof *table);
    if (!table)
        return 1;
    srgb8_table_init(table);
    enum { BATCH = 1 << 16 };
    static float values[BATCH];
    static uint8_t codes[BATCH];
    uint64_t wrong = 0;
    for (uint64_t base = 0; base < (1ull << 32); base += BATCH) {
        for (uint32_t i = 0; i < BATCH; ++i) {
            uint32_t bits = (uint32_t)(base + i);
            memcpy(&values[i], &bits, sizeof bits);
        }
        srgb8_encode_array(table, values, 1.0f, BATCH, codes);
        for (uint32_t i = 0; i < BATCH; ++i) {
            uint8_t exact = srgb8_encode(values[i]);
            if (codes[i] != exact && wrong++ < 20)
                printf("bits 0x%08" PRIx64 " (%.9g): table %u, exact %u\n", base + i,
                       (double)values[i], codes[i], exact);
        }
    }
    printf("srgb8-check: %" PRIu64 " of 2^32 float bit patterns differ\n", wrong);
    free(table);
    return wrong ? 1 : 0;
}
