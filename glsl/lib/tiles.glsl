/*
 * tiles.glsl: the order in which consecutive invocations take the pixels of an image (raygen.comp
 * for its camera rays, adapt.comp for the list of pixels the next pass samples): TILE x TILE
 * tiles rather than raster rows, so a subgroup's rays (32 lanes: 8 x 4 pixels) leave the camera
 * close together and walk the same nodes.
 */
#ifndef VKRT_TILES_GLSL
#define VKRT_TILES_GLSL

const uint TILE = 8u;

/* The pixel of primary ray `index`: the image is cut into bands of TILE rows, each band into
 * tiles of TILE columns, the tiles of a band and the pixels of a tile in raster order. The last
 * band and the last tile of each band may be narrower; the numbering stays dense. */
uvec2 tile_pixel(uint index, uint width, uint height)
{
    uint band_pixels = TILE * width;
    uint band = index / band_pixels;
    uint in_band = index - band * band_pixels;
    uint rows = min(TILE, height - band * TILE);
    uint tile_pixels = TILE * rows;
    uint tile = in_band / tile_pixels;
    uint cols = min(TILE, width - tile * TILE);
    uint in_tile = in_band - tile * tile_pixels;
    return uvec2(tile * TILE + in_tile % cols, band * TILE + in_tile / cols);
}

#endif
