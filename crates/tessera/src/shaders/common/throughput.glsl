// Workloads of the pipeline-throughput scenario (tessera::throughput). Both the graphics and the
// compute path include this one header, so they run literally the same code and a difference in
// time belongs to the pipeline, not to the shader. GRID_CELL_PX, GRID_LEG_PX and MESH_TRIANGLES
// come from the Rust side (throughput/triangles.rs) as #defines.

// A chain of dependent sin/fma steps per pixel. Every step reads the previous one, so the
// compiler can neither drop nor reorder iterations. The step contracts in v (each component moves
// by at most 0.5 * 0.8 + 0.45 = 0.85 of the largest input change), so rounding differences
// between two compilations shrink instead of growing; the uv forcing keeps the result a smooth,
// position-dependent function. |v| stays below 0.5 / (1 - 0.45) < 0.91 after the first step,
// so for iterations >= 1 every channel lies strictly inside (0, 1) and never encodes to the
// bytes 0 or 255, which tests use as "never written" markers.
vec4 busy_work(vec2 uv, uint iterations) {
    vec4 v = vec4(uv, 1.0 - uv);
    vec4 forcing = vec4(uv * 3.1, uv.yx * 2.3);
    for (uint i = 0u; i < iterations; ++i) {
        v = fma(sin(v * 0.8 + forcing), vec4(0.5), v.yzwx * 0.45);
    }
    return 0.5 + 0.5 * v;
}

// The small-triangle grid. The screen is cut into GRID_CELL_PX-square cells (whole cells only);
// triangle t lies in cell (t / 2) mod cells, wrapping round when there are more triangles than
// two per cell. Even triangles are right triangles at the cell's top-left corner, odd ones the
// same shape turned by 180 degrees at the bottom-right corner. Legs are GRID_LEG_PX long, a
// half-integer: pixel centres have integer x + y, so no centre lies on any edge and coverage
// does not depend on subpixel snapping or the tie-breaking rule (see triangles.rs).
uint grid_cells(uvec2 size) {
    return (size.x / GRID_CELL_PX) * (size.y / GRID_CELL_PX);
}

// Corners of triangle t in pixel coordinates (origin top-left, y down).
void grid_triangle(uint t, uvec2 size, out vec2 a, out vec2 b, out vec2 c) {
    uint cols = size.x / GRID_CELL_PX;
    uint cell = (t / 2u) % grid_cells(size);
    vec2 origin = vec2(uvec2(cell % cols, cell / cols) * GRID_CELL_PX);
    if ((t & 1u) == 0u) {
        a = origin;
        b = origin + vec2(GRID_LEG_PX, 0.0);
        c = origin + vec2(0.0, GRID_LEG_PX);
    } else {
        vec2 far_corner = origin + vec2(float(GRID_CELL_PX));
        a = far_corner;
        b = far_corner - vec2(GRID_LEG_PX, 0.0);
        c = far_corner - vec2(0.0, GRID_LEG_PX);
    }
}
