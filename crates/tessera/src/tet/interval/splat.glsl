// The compute path's pixel work: which proxy triangle owns a pixel centre (the top-left rule,
// as the hardware rasterizer decides it), and adding the tet's value there (pixel_value.glsl)
// with atomics — for INTEGRAND_SDF a 64-bit atomic minimum of depth and colour. Needs
// buffers.glsl, params.glsl, proxy.glsl (its `edge` is the edge function here too),
// length.glsl, integrand.glsl (and sdf.glsl for INTEGRAND_SDF), compute_buffers.glsl and
// pixel_value.glsl.

// The top-left rule (y down) for an edge running along d: a pixel centre on an edge shared by
// two triangles belongs to the one for which the edge, taken counter-clockwise, is a top or a
// left edge.
bool top_left(vec2 d) {
    return (d.y == 0.0 && d.x < 0.0) || d.y > 0.0;
}

// a × b: the edge function of an edge running along a, at offset b from a point on its line.
float cross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

vec2 to_screen(vec2 ndc) {
    return (ndc + 1.0) * 0.5 * vec2(params.counts.yz);
}

// Whether fan triangle (corner a, corner b, the centre) owns the pixel centre at offset q from
// the centre, and its three edge functions there (`edges`; divided by |area| they are the
// weights of a, b and the centre). The edge functions are taken from the centre: `spoke_a` =
// (a - centre) × q and `spoke_b` likewise, the outer edge a → b as its value at the centre
// (`area`, the triangle's signed doubled area) plus (b - a) × q. A spoke's value is computed
// once for both triangles that share it (one negated), so that a pixel on a spoke belongs to
// exactly one of them, rounding or not. `tl_*`: top_left() of each spoke (centre → corner) and
// of the outer edge (a → b).
bool fan_triangle_owns(float spoke_a, float spoke_b, float area, vec2 outer, vec2 q, bool tl_a, bool tl_b,
                       bool tl_outer, out vec3 edges) {
    bool clockwise = area < 0.0;
    // Counter-clockwise, the edges b → centre, centre → a and a → b; clockwise, each reversed.
    vec3 w = vec3(-spoke_b, spoke_a, area + cross2(outer, q)) * (clockwise ? -1.0 : 1.0);
    bvec3 tl = bvec3(tl_b == clockwise, tl_a != clockwise, tl_outer != clockwise);
    edges = w;
    return area != 0.0 && (w.x > 0.0 || (w.x == 0.0 && tl.x)) && (w.y > 0.0 || (w.y == 0.0 && tl.y))
        && (w.z > 0.0 || (w.z == 0.0 && tl.z));
}

// The attributes at weights edges / |area| of a, b and the centre.
vec4 fan_triangle_attrs(vec3 edges, float area, vec4 attrs_a, vec4 attrs_b, vec4 attrs_centre) {
    vec3 w = edges / abs(area);
    return w.x * attrs_a + w.y * attrs_b + w.z * attrs_centre;
}

// fan_triangle_owns for corners a, b and the centre as they are, with the attributes
// interpolated where it owns the pixel; spoke_a and spoke_b as there.
bool fan_triangle_attrs_at(vec2 a, vec2 b, vec2 centre, float spoke_a, float spoke_b, vec2 q, vec4 attrs_a,
                           vec4 attrs_b, vec4 attrs_centre, out vec4 attrs) {
    vec3 edges;
    float area = edge(a, b, centre);
    bool owned = fan_triangle_owns(spoke_a, spoke_b, area, b - a, q, top_left(a - centre), top_left(b - centre),
                                   top_left(b - a), edges);
    // Interpolated whether owned or not: choosing before dividing made the binned shading pass,
    // which calls this, up to 3.7 % slower (run 85).
    vec4 interpolated = fan_triangle_attrs(edges, area, attrs_a, attrs_b, attrs_centre);
    attrs = owned ? interpolated : vec4(0.0);
    return owned;
}

#if INTEGRAND != INTEGRAND_SDF
void accumulate(uint pixel, vec3 value) {
#if INTEGRAND == INTEGRAND_MAXIMUM
    // Non-negative floats order as their bits do.
    atomicMax(optical[optical_index(pixel, 0u)], floatBitsToUint(value.x));
    atomicMax(optical[optical_index(pixel, 1u)], floatBitsToUint(value.y));
#else
    atomicAdd(optical[optical_index(pixel, 0u)], value.x);
    atomicAdd(optical[optical_index(pixel, 1u)], value.y);
    atomicAdd(optical[optical_index(pixel, 2u)], value.z);
#endif
}
#endif

void pixel_work(uint tet, uint pixel, vec4 attrs, vec2 ndc) {
    PixelValue value = tet_pixel_value(tet, attrs, ndc, empty_pixel_value());
#if INTEGRAND == INTEGRAND_SDF
    if (value != NO_HIT) {
        atomicMin(frame[pixel * 2u], value);
    }
#else
    accumulate(pixel, value);
#endif
}

// The pixel centre's normalized device coordinates.
vec2 pixel_ndc(uvec2 pixel) {
    vec2 p = vec2(pixel) + 0.5;
    return p / (0.5 * vec2(params.counts.yz)) - 1.0;
}

// Whether one of the proxy's fan triangles owns the pixel centre, and the attributes
// interpolated there: raster_attrs_at's test and arithmetic, with each triangle set up at the
// pixel and the first owner ending it. The binned shading pass uses it: its invocations are
// pixels that each test every tet of a tile, and the branch-free test over a set-up proxy made
// that pass 1.6× slower (more registers and shared memory). Written out per silhouette size:
// every index into the proxy is a constant, so that it stays in registers.
bool proxy_attrs_at(Proxy proxy, uvec2 pixel, out vec4 attrs) {
    attrs = vec4(0.0);
    uint s = proxy.silhouette;
    if (s == 0u) {
        return false;
    }
    bool quad = s == 4u;
    vec2 centre = to_screen(quad ? proxy.p[4] : proxy.p[3]);
    vec4 centre_attrs = quad ? proxy.attrs[4] : proxy.attrs[3];
    vec2 q = vec2(pixel) + 0.5 - centre;
    vec2 v0 = to_screen(proxy.p[0]);
    vec2 v1 = to_screen(proxy.p[1]);
    vec2 v2 = to_screen(proxy.p[2]);
    float s0 = cross2(v0 - centre, q);
    float s1 = cross2(v1 - centre, q);
    float s2 = cross2(v2 - centre, q);
    if (fan_triangle_attrs_at(v0, v1, centre, s0, s1, q, proxy.attrs[0], proxy.attrs[1], centre_attrs, attrs)
        || fan_triangle_attrs_at(v1, v2, centre, s1, s2, q, proxy.attrs[1], proxy.attrs[2], centre_attrs, attrs)) {
        return true;
    }
    if (!quad) {
        return fan_triangle_attrs_at(v2, v0, centre, s2, s0, q, proxy.attrs[2], proxy.attrs[0], centre_attrs, attrs);
    }
    vec2 v3 = to_screen(proxy.p[3]);
    float s3 = cross2(v3 - centre, q);
    return fan_triangle_attrs_at(v2, v3, centre, s2, s3, q, proxy.attrs[2], proxy.attrs[3], centre_attrs, attrs)
        || fan_triangle_attrs_at(v3, v0, centre, s3, s0, q, proxy.attrs[3], proxy.attrs[0], centre_attrs, attrs);
}

// A proxy made ready for many pixel tests: its fan triangles (silhouette corner i, corner
// i + 1, the centre) in screen pixels, with what fan_triangle_owns needs of each that does not
// depend on the pixel, computed as proxy_attrs_at computes it.
struct ProxyRaster {
    vec2 corner[5];  // the silhouette's corners, the first repeated after the last
    vec4 corner_attrs[5];
    vec2 centre;
    vec4 centre_attrs;
    vec2 spoke[5];  // corner[i] - centre
    vec4 area;  // edge(corner[i], corner[i + 1], centre): fan triangle i's signed doubled area
    uint top_left;  // bit i: top_left(spoke[i]); bit 8 + i: top_left(corner[i + 1] - corner[i])
    uint silhouette;
};

ProxyRaster proxy_raster(Proxy proxy) {
    ProxyRaster r;
    uint s = proxy.silhouette;
    bool quad = s == 4u;
    r.silhouette = s;
    // Constant indices throughout, so that the proxy stays in registers.
    for (uint j = 0u; j < 4u; ++j) {
        r.corner[j] = to_screen(proxy.p[j]);
        r.corner_attrs[j] = proxy.attrs[j];
    }
    r.centre = to_screen(quad ? proxy.p[4] : proxy.p[3]);
    r.centre_attrs = quad ? proxy.attrs[4] : proxy.attrs[3];
    if (!quad) {
        r.corner[3] = r.corner[0];
        r.corner_attrs[3] = r.corner_attrs[0];
    }
    r.corner[4] = r.corner[0];
    r.corner_attrs[4] = r.corner_attrs[0];
    r.top_left = 0u;
    for (uint j = 0u; j < 5u; ++j) {
        r.spoke[j] = r.corner[j] - r.centre;
        r.top_left |= top_left(r.spoke[j]) ? 1u << j : 0u;
    }
    for (uint i = 0u; i < 4u; ++i) {
        r.area[i] = edge(r.corner[i], r.corner[i + 1u], r.centre);
        r.top_left |= top_left(r.corner[i + 1u] - r.corner[i]) ? 1u << (8u + i) : 0u;
    }
    return r;
}

// Whether one of the proxy's fan triangles owns the pixel centre, with the attributes
// interpolated there. The triangles tile the silhouette and share their spokes' values, so at
// most one does. Every triangle is tested, without branching, so that a subgroup's invocations
// stay together. The owner's edge values are kept as the weights of the two corners it spans
// and of the centre, and the attributes summed once with every corner's weight (zero but for
// the owner's): choosing the owner's corner attributes took a selection per channel and
// triangle.
bool raster_attrs_at(ProxyRaster r, uvec2 pixel, out vec4 attrs) {
    vec2 q = vec2(pixel) + 0.5 - r.centre;
    float spoke_value[5];
    for (uint j = 0u; j < 5u; ++j) {
        spoke_value[j] = cross2(r.spoke[j], q);
    }
    bool found = false;
    float owner_area = 1.0;
    float corner_weight[5] = float[5](0.0, 0.0, 0.0, 0.0, 0.0);
    float centre_weight = 0.0;
    for (uint i = 0u; i < 4u; ++i) {
        vec3 edges;
        bool owned = fan_triangle_owns(spoke_value[i], spoke_value[i + 1u], r.area[i], r.corner[i + 1u] - r.corner[i], q,
                                       (r.top_left & (1u << i)) != 0u, (r.top_left & (1u << (i + 1u))) != 0u,
                                       (r.top_left & (1u << (8u + i))) != 0u, edges);
        bool owner = owned && i < r.silhouette && !found;
        found = found || owner;
        corner_weight[i] = owner ? edges.x : corner_weight[i];
        corner_weight[i + 1u] = owner ? edges.y : corner_weight[i + 1u];
        centre_weight = owner ? edges.z : centre_weight;
        owner_area = owner ? r.area[i] : owner_area;
    }
    vec4 sum = centre_weight * r.centre_attrs;
    for (uint k = 0u; k < 5u; ++k) {
        sum += corner_weight[k] * r.corner_attrs[k];
    }
    attrs = found ? sum * (1.0 / abs(owner_area)) : vec4(0.0);
    return found;
}

// The pixel work of tet `tet` at `pixel` where one of its proxy's triangles owns the pixel
// centre.
void shade_pixel(ProxyRaster proxy, uvec2 pixel, uint tet) {
    vec4 attrs;
    if (raster_attrs_at(proxy, pixel, attrs)) {
        pixel_work(tet, pixel.y * params.counts.y + pixel.x, attrs, pixel_ndc(pixel));
    }
}
