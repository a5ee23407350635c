// The compute rasterizer's data, shared by its passes and by the resolve shaders that read its
// frames (layouts documented in raster/mod.rs).
//
// A frame holds one 64-bit value per pixel, row-major: NDC depth bits in the high word, the index
// of the visible triangle in the low word, all ones where nothing was drawn. Resolve shaders need
// no 64-bit types: bind the frame as `uvec2 depth_payload[]` (x = low word = triangle index,
// y = high word = depth bits) and decode it with the helpers below.

#ifndef RASTER_RASTER_GLSL
#define RASTER_RASTER_GLSL

// One input triangle: its corners in clip space (std430: 48 bytes, no padding).
struct RasterTriangle {
    vec4 clip[3];
};

// The high word of a pixel nothing was drawn to; drawn depths lie in [0, 1).
const uint RASTER_EMPTY_WORD = 0xffffffffu;

bool raster_is_empty(uvec2 value) {
    return value.y == RASTER_EMPTY_WORD;
}

// NDC depth of the visible fragment (meaningless for an empty pixel).
float raster_depth(uvec2 value) {
    return uintBitsToFloat(value.y);
}

// Index of the visible triangle in the rasterized list (meaningless for an empty pixel).
uint raster_index(uvec2 value) {
    return value.x;
}

#ifdef RASTER_TILE
// RASTER_TILE-square tiles per row of a frame `width` pixels wide (raster/mod.rs: the tiles'
// frame numbers, row-major).
uint raster_tiles_per_row(uint width) {
    return (width + RASTER_TILE - 1u) / RASTER_TILE;
}

// The index of the tile holding pixel `pixel` of a frame `width` pixels wide.
uint raster_tile_index(uvec2 pixel, uint width) {
    uvec2 tile = pixel / RASTER_TILE;
    return tile.y * raster_tiles_per_row(width) + tile.x;
}
#endif

// The centre of pixel `pixel`, in pixels; what the rasterizer samples.
vec2 raster_pixel_centre(uvec2 pixel) {
    return vec2(pixel) + 0.5;
}

// Perspective-correct barycentric weights (summing to 1) of the point of triangle
// (clip0, clip1, clip2) seen at `pixel_centre` (in pixels) in a `size`-pixel viewport: the weights
// that interpolate per-vertex attributes as the fixed-function pipeline does. They refer to the
// triangle as given, also where the rasterizer drew only a clipped part of it, so a resolve shader
// interpolates the original corners' attributes. Corners behind the eye are fine.
//
// The sample's ray is (X, Y, 1) in homogeneous pixel space, where a corner is
// (X, Y, w) = ((x + w) W/2, (y + w) H/2, w). Each corner's weight is proportional to the signed
// area the sample spans with the other two, measured after moving every corner along the ray to
// w = 0: u_i = (X_i, Y_i) - w_i * sample. Working relative to the sample keeps small triangles
// accurate; the weights are then the 2-D cross products of the u_i, normalized.
vec3 raster_barycentrics(vec4 clip0, vec4 clip1, vec4 clip2, vec2 pixel_centre, uvec2 size) {
    vec2 half_size = vec2(size) * 0.5;
    vec2 u0 = (clip0.xy + clip0.w) * half_size - clip0.w * pixel_centre;
    vec2 u1 = (clip1.xy + clip1.w) * half_size - clip1.w * pixel_centre;
    vec2 u2 = (clip2.xy + clip2.w) * half_size - clip2.w * pixel_centre;
    vec3 weights = vec3(u1.x * u2.y - u1.y * u2.x,
                        u2.x * u0.y - u2.y * u0.x,
                        u0.x * u1.y - u0.y * u1.x);
    float sum = weights.x + weights.y + weights.z;
    // Zero only when the triangle is seen edge-on, and then it covers no pixel.
    return sum != 0.0 ? weights / sum : vec3(1.0 / 3.0);
}

#endif
