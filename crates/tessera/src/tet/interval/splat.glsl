// The compute path's pixel work: which proxy triangle owns a pixel centre (the top-left rule,
// as the hardware rasterizer decides it), and adding the tet's value there (pixel_value.glsl)
// with atomics — for INTEGRAND_SDF a 64-bit atomic minimum of depth and colour. Needs
// buffers.glsl, params.glsl, proxy.glsl, length.glsl, integrand.glsl (and sdf.glsl for
// INTEGRAND_SDF), compute_buffers.glsl and pixel_value.glsl.

float edge_at(vec2 a, vec2 b, vec2 p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Top-left rule on a counter-clockwise triangle (y down): a pixel centre on an edge belongs to
// exactly one of the two triangles sharing it.
bool owns(float w, vec2 a, vec2 b) {
    vec2 d = b - a;
    return w > 0.0 || (w == 0.0 && ((d.y == 0.0 && d.x < 0.0) || d.y > 0.0));
}

vec2 to_screen(vec2 ndc) {
    return (ndc + 1.0) * 0.5 * vec2(params.counts.yz);
}

// Whether pixel centre p belongs to triangle s0 s1 s2 (either winding), with the weights of
// its corners there.
bool covers(vec2 s0, vec2 s1, vec2 s2, vec2 p, out vec3 weights) {
    weights = vec3(0.0);
    float area = edge_at(s0, s1, s2);
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
    float w0 = edge_at(s1, s2, p);
    float w1 = edge_at(s2, s0, p);
    float w2 = edge_at(s0, s1, p);
    if (!(owns(w0, s1, s2) && owns(w1, s2, s0) && owns(w2, s0, s1))) {
        return false;
    }
    weights = (flipped ? vec3(w0, w2, w1) : vec3(w0, w1, w2)) / area;
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
// there. The triangles of one proxy tile its silhouette, so at most one does. Written out per
// silhouette size rather than looped over with the size as bound: every index into the proxy
// is a constant, so that it stays in registers.
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

// The pixel work of tet `tet` at `pixel` where one of its proxy's triangles owns the pixel
// centre.
void shade_pixel(Proxy proxy, uvec2 pixel, uint tet) {
    vec4 attrs;
    if (proxy_attrs_at(proxy, pixel, attrs)) {
        pixel_work(tet, pixel.y * params.counts.y + pixel.x, attrs, pixel_ndc(pixel));
    }
}
