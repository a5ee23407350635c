// The compute path's pixel work: which proxy triangle owns a pixel centre (the top-left rule,
// as the hardware rasterizer decides it), and adding the tet's value there (pixel_value.glsl)
// with atomics — for INTEGRAND_SDF a 64-bit atomic minimum of depth and colour. Needs
// buffers.glsl, params.glsl, proxy.glsl (its `edge` is the edge function here too),
// length.glsl, integrand.glsl (and sdf.glsl for INTEGRAND_SDF), compute_buffers.glsl and
// pixel_value.glsl.

// Top-left rule on a counter-clockwise triangle (y down): a pixel centre on an edge belongs to
// exactly one of the two triangles sharing it.
bool owns(float w, vec2 a, vec2 b) {
    vec2 d = b - a;
    return w > 0.0 || (w == 0.0 && ((d.y == 0.0 && d.x < 0.0) || d.y > 0.0));
}

vec2 to_screen(vec2 ndc) {
    return (ndc + 1.0) * 0.5 * vec2(params.counts.yz);
}

// Whether counter-clockwise triangle s0 s1 s2 owns pixel centre p, with its edge functions
// there (each the weight of the corner opposite, times the doubled area).
bool ccw_triangle_owns(vec2 s0, vec2 s1, vec2 s2, vec2 p, out vec3 w) {
    w = vec3(edge(s1, s2, p), edge(s2, s0, p), edge(s0, s1, p));
    return owns(w.x, s1, s2) && owns(w.y, s2, s0) && owns(w.z, s0, s1);
}

// Whether pixel centre p belongs to triangle s0 s1 s2 (either winding), with the weights of
// its corners there.
bool covers(vec2 s0, vec2 s1, vec2 s2, vec2 p, out vec3 weights) {
    weights = vec3(0.0);
    float area = edge(s0, s1, s2);
    if (area == 0.0) {
        return false;
    }
    bool flipped = area < 0.0;
    if (flipped) {
        vec2 t = s1;
        s1 = s2;
        s2 = t;
        area = -area;
    }
    vec3 w;
    if (!ccw_triangle_owns(s0, s1, s2, p, w)) {
        return false;
    }
    weights = (flipped ? w.xzy : w) / area;
    return true;
}

#if INTEGRAND != INTEGRAND_SDF
void accumulate(uint pixel, vec3 value) {
    uint i = pixel * 4u;
#if INTEGRAND == INTEGRAND_MAXIMUM
    // Non-negative floats order as their bits do.
    atomicMax(optical[i + 0u], floatBitsToUint(value.x));
    atomicMax(optical[i + 1u], floatBitsToUint(value.y));
#else
    atomicAdd(optical[i + 0u], value.x);
    atomicAdd(optical[i + 1u], value.y);
    atomicAdd(optical[i + 2u], value.z);
#endif
}
#endif

void pixel_work(uint tet, uint pixel, vec4 attrs, vec2 ndc) {
    PixelValue value = tet_pixel_value(tet, attrs, ndc);
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

// Whether triangle a b centre owns pixel centre p, with the attributes interpolated there.
bool triangle_attrs_at(vec2 a, vec2 b, vec2 centre, vec4 attrs_a, vec4 attrs_b, vec4 attrs_centre, vec2 p,
                       out vec4 attrs) {
    vec3 w;
    if (!covers(to_screen(a), to_screen(b), centre, p, w)) {
        attrs = vec4(0.0);
        return false;
    }
    attrs = w.x * attrs_a + w.y * attrs_b + w.z * attrs_centre;
    return true;
}

// Whether one of the proxy's triangles owns the pixel centre, and the attributes interpolated
// there: raster_attrs_at's test, with each triangle set up at the pixel and the first owner
// ending it. The binned shading pass uses it: its invocations are pixels that each test every
// tet of a tile, and the branch-free test over a set-up proxy made that pass 1.6× slower
// (more registers and shared memory). Written out per silhouette size rather than looped over
// with the size as bound: every index into the proxy is a constant, so that it stays in
// registers.
bool proxy_attrs_at(Proxy proxy, uvec2 pixel, out vec4 attrs) {
    attrs = vec4(0.0);
    uint s = proxy.silhouette;
    if (s == 0u) {
        return false;
    }
    vec2 p = vec2(pixel) + 0.5;
    bool quad = s == 4u;
    vec2 centre = to_screen(quad ? proxy.p[4] : proxy.p[3]);
    vec4 centre_attrs = quad ? proxy.attrs[4] : proxy.attrs[3];
    if (triangle_attrs_at(proxy.p[0], proxy.p[1], centre, proxy.attrs[0], proxy.attrs[1], centre_attrs, p, attrs)
        || triangle_attrs_at(proxy.p[1], proxy.p[2], centre, proxy.attrs[1], proxy.attrs[2], centre_attrs, p, attrs)) {
        return true;
    }
    if (!quad) {
        return triangle_attrs_at(proxy.p[2], proxy.p[0], centre, proxy.attrs[2], proxy.attrs[0], centre_attrs, p, attrs);
    }
    return triangle_attrs_at(proxy.p[2], proxy.p[3], centre, proxy.attrs[2], proxy.attrs[3], centre_attrs, p, attrs)
        || triangle_attrs_at(proxy.p[3], proxy.p[0], centre, proxy.attrs[3], proxy.attrs[0], centre_attrs, p, attrs);
}

// A proxy made ready for many pixel tests: its fan triangles (silhouette corner i, corner
// i + 1, the centre) in screen pixels, each with its doubled area and whether it runs clockwise.
struct ProxyRaster {
    vec2 corner[5];  // the silhouette's corners, the first repeated after the last
    vec4 corner_attrs[5];
    vec2 centre;
    vec4 centre_attrs;
    vec4 area;  // of each fan triangle, made positive
    uint clockwise;  // bit i: fan triangle i runs clockwise
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
    r.clockwise = 0u;
    r.area = vec4(0.0);
    for (uint i = 0u; i < 4u; ++i) {
        float area = edge(r.corner[i], r.corner[i + 1u], r.centre);
        r.clockwise |= area < 0.0 ? 1u << i : 0u;
        r.area[i] = abs(area);
    }
    return r;
}

// Whether one of the proxy's fan triangles owns the pixel centre (the top-left rule on each,
// taken counter-clockwise), with the attributes interpolated there. The triangles tile the
// silhouette, so at most one does but for rounding, and then the first. Every triangle is
// tested, without branching, so that a subgroup's invocations stay together.
bool raster_attrs_at(ProxyRaster r, uvec2 pixel, out vec4 attrs) {
    vec2 p = vec2(pixel) + 0.5;
    attrs = vec4(0.0);
    bool found = false;
    for (uint i = 0u; i < 4u; ++i) {
        bool clockwise = (r.clockwise & (1u << i)) != 0u;
        vec2 s0 = r.corner[i];
        vec2 s1 = clockwise ? r.centre : r.corner[i + 1u];
        vec2 s2 = clockwise ? r.corner[i + 1u] : r.centre;
        vec3 w;
        bool inside = ccw_triangle_owns(s0, s1, s2, p, w);
        if (inside && i < r.silhouette && r.area[i] != 0.0 && !found) {
            found = true;
            vec3 weights = (clockwise ? w.xzy : w) / r.area[i];
            attrs = weights.x * r.corner_attrs[i] + weights.y * r.corner_attrs[i + 1u] + weights.z * r.centre_attrs;
        }
    }
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
