#version 460
// POINT-BASED rendering (paper E §4.3): one workgroup per patch to render samples it on a
// regular (n_u + 1) x (n_v + 1) parameter grid, n = ceil(extent * density) cells per direction
// (about one sample per pixel of the patch's screen extent at density 1), tile by tile: the 9x9
// points of an 8x8-cell tile go to shared memory, then each invocation draws one cell. A patch
// may have several workgroups along z (lod_prepare spreads a short list), which split its tiles.
//
// FOOTPRINT_CELL: a cell is drawn as two triangles, every pixel centre inside them (edges
// widened by EDGE_SLACK pixels so that neighbouring patches' slightly different edges leave no
// crack) gets the depth and (u, v) interpolated there. FOOTPRINT_PIXEL (the paper's): each point
// writes the pixel it falls in with its own depth and (u, v). Either way a 64-bit atomicMin of
// depth bits << 32 | payload keeps the nearest.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define PARAM_STATE_BINDING 3
#include "param/functions.glsl"
#include "param/view.glsl"
#include "param/patch.glsl"
#include "param/payload.glsl"
#include "param/min_extent.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 4, std430) readonly buffer PatchesRender { Patch patches_render[]; };
layout(binding = 5, std430) buffer Frame { uint64_t depth_payload[]; };

layout(push_constant) uniform PointsParams {
    mat4 world_to_clip;
    vec2 viewport;         // raster size as floats
    float density;         // cells per pixel of extent
    uint max_side;         // most cells per direction of one patch
    uvec2 raster;          // raster width, height
    uint uv_bits;          // payload bits per parameter
    uint render_capacity;  // patches the render list holds
    uint footprint;        // FOOTPRINT_CELL or FOOTPRINT_PIXEL
    uint pad0;
    uint pad1;
    uint pad2;
    vec4 eye;              // xyz the camera's position in world space
} params;

const uint TILE = 8u;
const uint POINTS = (TILE + 1u) * (TILE + 1u);
const float EDGE_SLACK = 1.0 / 64.0;
const float OVERLAP_CELLS = 0.5;
// The sign of the pixel-space area of a triangle whose corners run counter-clockwise about
// the normal facing the eye (pixel y grows downwards from NDC's -1).
const float FRONT_AREA_SIGN = -1.0;
// A triangle whose pixel rectangle is larger than this is skipped (and counted).
const uint MAX_TRIANGLE_PIXELS = 4096u;

shared vec3 s_point[POINTS];  // pixel x, y, depth (depth < 0: unusable)
shared vec2 s_uv[POINTS];
// SH glyphs: a tile's points share TILE + 1 polar angles (u, one per column) and as many
// azimuths (v, one per row). The polar sums per order a (sh_polar_sums) of each column and
// the weights of order a at each row's azimuth (sh_weights) are made once per tile, so a
// point's radius takes 2(L + 1) products instead of the whole recurrence.
shared vec2 s_polar_sums[(TILE + 1u) * SH_TABLE_WIDTH];  // [column][a]
shared vec2 s_azimuth_weights[(TILE + 1u) * SH_TABLE_WIDTH];  // [row][a]

// A patch's parameter range `r` reaching OVERLAP_CELLS of a cell past each end into the
// neighbouring patch, inside the domain `d`: neighbours sample their shared edge at different
// counts, and the polylines part by up to a pixel (T-junctions); patches overlapping on the
// surface itself close those gaps without widening anything on screen.
vec2 overlapped(vec2 r, uint n, vec2 d) {
    float reach = OVERLAP_CELLS * (r.y - r.x) / float(n);
    return vec2(max(r.x - reach, d.x), min(r.y + reach, d.y));
}

float grid_param(vec2 r, uint i, uint n) {
    return i == 0u ? r.x : (i == n ? r.y : r.x + (r.y - r.x) * (float(i) / float(n)));
}

void splat(uint x, uint y, float depth, uint payload) {
    uint64_t value = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(payload);
    atomicMin(depth_payload[y * params.raster.x + x], value);
}

float cross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// `facing`: 0 draws the triangle whichever way it faces; else only where its pixel-space area
// has that sign (glyph_front_sign).
void draw_triangle(uint object, uint ia, uint ib, uint ic, float facing) {
    vec3 a = s_point[ia];
    vec3 b = s_point[ib];
    vec3 c = s_point[ic];
    float area = cross2(b.xy - a.xy, c.xy - a.xy);
    if (abs(area) < 1e-12 || area * facing < 0.0) {
        return;
    }
    // Barycentric slack per corner: EDGE_SLACK pixels across the opposite edge.
    vec3 slack = EDGE_SLACK * vec3(length(c.xy - b.xy), length(a.xy - c.xy), length(b.xy - a.xy)) / abs(area);
    vec2 lo = min(min(a.xy, b.xy), c.xy) - EDGE_SLACK;
    vec2 hi = max(max(a.xy, b.xy), c.xy) + EDGE_SLACK;
    ivec2 first = max(ivec2(ceil(lo - 0.5)), ivec2(0));
    ivec2 last = min(ivec2(floor(hi - 0.5)), ivec2(params.raster) - 1);
    if (any(lessThan(last, first))) {
        return;
    }
    if (uint(last.x - first.x + 1) * uint(last.y - first.y + 1) > MAX_TRIANGLE_PIXELS) {
        atomicAdd(skipped_cells, 1u);
        return;
    }
    for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) {
            vec2 p = vec2(x, y) + 0.5;
            vec3 l = vec3(cross2(c.xy - b.xy, p - b.xy), cross2(a.xy - c.xy, p - c.xy), cross2(b.xy - a.xy, p - a.xy)) / area;
            if (any(lessThan(l, -slack))) {
                continue;
            }
            l = max(l, vec3(0.0));
            l /= l.x + l.y + l.z;
            float depth = dot(l, vec3(a.z, b.z, c.z));
            if (!(depth >= 0.0 && depth < 1.0)) {
                continue;
            }
            vec2 uv = l.x * s_uv[ia] + l.y * s_uv[ib] + l.z * s_uv[ic];
            splat(uint(x), uint(y), depth, param_payload(object, uv.x, uv.y, params.uv_bits));
        }
    }
}

// Fills the SH tables of the tile at `origin` for glyph `o` (the polar sums only with
// `new_columns`: they depend on the columns alone); the caller's barrier publishes them.
void glyph_tables(ParamObject o, vec2 u_range, vec2 v_range, uvec2 origin, uvec2 n, bool new_columns) {
    uint lane = gl_LocalInvocationIndex;
    uint orders = o.order + 1u;
    uint polar_items = new_columns ? (TILE + 1u) * orders : 0u;
    for (uint item = lane; item < polar_items; item += TILE * TILE) {
        uint column = item % (TILE + 1u);
        uint a = item / (TILE + 1u);
        if (origin.x + column <= n.x) {
            float u = grid_param(u_range, origin.x + column, n.x);
            s_polar_sums[column * SH_TABLE_WIDTH + a] = sh_polar_sums(o.params, o.order, a, u);
        }
    }
    if (lane <= TILE && origin.y + lane <= n.y) {
        uint basis = (o.flags >> PARAM_BASIS_SHIFT) & 3u;
        float v = grid_param(v_range, origin.y + lane, n.y);
        vec2 step = vec2(cos(v), sin(v));
        vec2 cs = vec2(1.0, 0.0);  // cos, sin of a v
        for (uint a = 1u; a < orders; ++a) {
            cs = sh_next_azimuth(cs, step);
            s_azimuth_weights[lane * SH_TABLE_WIDTH + a] = sh_weights(a, basis, cs.x, cs.y);
        }
    }
}

// A glyph whose radius never goes negative (its clamp starts at 0) is star-shaped about its
// centre, so closed: seen from outside, every cell facing away lies behind one facing the eye
// and need not be drawn. The sign of the pixel-space area of a cell triangle (corners in the
// order of increasing u, then v) that faces the eye; 0 where the eye may be inside the glyph
// (within its bounding sphere).
float glyph_front_sign(ParamObject o) {
    if (o.radius_map.z < 0.0) {
        return 0.0;
    }
    vec3 centre = vec3(o.model[0].w, o.model[1].w, o.model[2].w);
    mat3 linear = mat3(o.model[0].xyz, o.model[1].xyz, o.model[2].xyz);
    float reach = o.radius_map.w * sqrt(dot(linear[0], linear[0]) + dot(linear[1], linear[1]) + dot(linear[2], linear[2]));
    if (!(distance(params.eye.xyz, centre) > reach)) {
        return 0.0;
    }
    // An object-to-world transform that mirrors turns the winding over.
    return determinant(linear) < 0.0 ? -FRONT_AREA_SIGN : FRONT_AREA_SIGN;
}

// The world position of glyph `object` at the tile's point in `column` and `row`.
vec3 glyph_world_position(uint object, ParamObject o, uint column, uint row, float u, float v) {
    float r = s_polar_sums[column * SH_TABLE_WIDTH].x;
    for (uint a = 1u; a <= o.order; ++a) {
        r += dot(s_azimuth_weights[row * SH_TABLE_WIDTH + a],
                 s_polar_sums[column * SH_TABLE_WIDTH + a]);
    }
    float radius = clamp(r * o.radius_map.x + o.radius_map.y, o.radius_map.z, o.radius_map.w);
    return param_to_world(object, param_sphere(u, v) * radius);
}

void main() {
    uint index = param_group_index();
    if (index >= min(entries[0].count, params.render_capacity)) {
        return;  // uniform over the workgroup
    }
    Patch p = patches_render[index];
    vec2 extent = max(p.extent, param_min_extent(p, params.world_to_clip, params.viewport));
    uvec2 n = uvec2(clamp(ceil(extent * params.density), vec2(1.0), vec2(float(params.max_side))));
    uvec2 tiles = (n + TILE - 1u) / TILE;
    uint lane = gl_LocalInvocationIndex;
    ParamObject o = param_objects[p.object];
    bool glyph = o.kind == PARAM_KIND_SH_GLYPH;  // uniform over the workgroup
    bool cells = params.footprint == FOOTPRINT_CELL;
    vec2 u_range = cells ? overlapped(p.u, n.x, o.domain.xy) : p.u;
    // A closed seam along v (a sphere's or glyph's azimuth): patches at its two ends overlap
    // across it.
    vec2 v_domain = (o.flags & PARAM_FLAG_PERIODIC_V) != 0u ? vec2(-1e30, 1e30) : o.domain.zw;
    vec2 v_range = cells ? overlapped(p.v, n.y, v_domain) : p.v;
    float facing = glyph ? glyph_front_sign(o) : 0.0;
    // The patch's workgroups along z (lod_prepare) split its tiles, taken column by column, into
    // runs of consecutive tiles, so that a workgroup's next tile mostly shares its columns' SH
    // polar sums (every z-th tile would share none: a spread patch is a large one).
    uint tile_count = tiles.x * tiles.y;
    uint run = (tile_count + gl_NumWorkGroups.z - 1u) / gl_NumWorkGroups.z;
    uint run_end = min(run * (gl_WorkGroupID.z + 1u), tile_count);
    uint tables_column = 0xffffffffu;  // the tile column the polar sums hold
    for (uint t = run * gl_WorkGroupID.z; t < run_end; ++t) {
        uvec2 tile = uvec2(t / tiles.y, t % tiles.y);
        uvec2 origin = tile * TILE;
        if (glyph) {
            glyph_tables(o, u_range, v_range, origin, n, tile.x != tables_column);
            tables_column = tile.x;
            barrier();
        }
        for (uint k = lane; k < POINTS; k += TILE * TILE) {
            uvec2 column_row = uvec2(k % (TILE + 1u), k / (TILE + 1u));
            uvec2 g = origin + column_row;
            if (any(greaterThan(g, n))) {
                continue;
            }
            float u = grid_param(u_range, g.x, n.x);
            float v = grid_param(v_range, g.y, n.y);
            vec3 world = glyph ? glyph_world_position(p.object, o, column_row.x, column_row.y, u, v)
                               : param_world_position(p.object, u, v);
            vec2 pixel;
            float depth;
            bool front = param_project(params.world_to_clip, params.viewport, world, pixel, depth);
            bool usable = front && !any(isnan(pixel)) && depth >= 0.0 && depth < 1.0;
            s_point[k] = vec3(pixel, usable ? depth : -1.0);
            s_uv[k] = vec2(u, v);
            // Each point belongs to the tile it starts, the patch's last row and column to the last.
            uvec2 local = g - origin;
            bool owned = all(lessThan(local, uvec2(TILE))) || (local.x == TILE && g.x == n.x && local.y < TILE)
                      || (local.y == TILE && g.y == n.y && (local.x < TILE || g.x == n.x));
            if (params.footprint == FOOTPRINT_PIXEL && usable && owned && all(greaterThanEqual(pixel, vec2(0.0)))
                && all(lessThan(pixel, params.viewport))) {
                uvec2 px = min(uvec2(pixel), params.raster - 1u);
                splat(px.x, px.y, depth, param_payload(p.object, u, v, params.uv_bits));
            }
        }
        barrier();
        uvec2 cell = origin + gl_LocalInvocationID.xy;
        if (params.footprint == FOOTPRINT_CELL && all(lessThan(cell, n))) {
            uint i00 = gl_LocalInvocationID.y * (TILE + 1u) + gl_LocalInvocationID.x;
            uint i10 = i00 + 1u;
            uint i01 = i00 + TILE + 1u;
            uint i11 = i01 + 1u;
            if (s_point[i00].z >= 0.0 && s_point[i10].z >= 0.0 && s_point[i01].z >= 0.0 && s_point[i11].z >= 0.0) {
                draw_triangle(p.object, i00, i10, i11, facing);
                draw_triangle(p.object, i00, i11, i01, facing);
            }
        }
        barrier();
    }
}
