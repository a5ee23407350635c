// Shared by interval shading's mesh-shader and compute paths: the screen-space proxies of a
// tetrahedron (paper A §2.2) and its clipping at the near plane (§2.3). Needs
// tet/interval/params.glsl and the Vertices/Tets buffers bound as `vertices_world` (xyz world
// position, w the vertex's normalized scalar) and `tets`.
//
// Every proxy vertex carries one face's inverse view depth 1/z, the difference of the two faces'
// 1/z, and both faces' scalar times 1/z: on a plane all are affine in screen space, so the
// rasterizer interpolates them exactly, and a pixel recovers the scalar at the entry and exit
// as (s/z) / (1/z). The difference is interpolated itself rather than formed from two
// interpolated depths, which nearly cancel across thin tets.
//
// The graphics path's attributes are exact for the proxy with its corners snapped to the
// rasterizer's sub-pixel grid (on an H200: up to 0.3 % of a thin proxy's length where the
// length changes steeply); the compute path interpolates over the exact corners.

// A tet's screen-space proxy: `silhouette` outer vertices (3 or 4, 0 for none) then the inner one.
struct Proxy {
    vec2 p[5];
    vec4 attrs[5];  // 1/z of face A, 1/z of A - 1/z of B, s/z of A, s/z of B
    uint silhouette;
};

// Twice the signed area of (a, b, c): the edge function.
float edge(vec2 a, vec2 b, vec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool inside(vec2 p, vec2 a, vec2 b, vec2 c) {
    float w0 = edge(b, c, p);
    float w1 = edge(c, a, p);
    float w2 = edge(a, b, p);
    return (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) || (w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0);
}

// Whether segments p-q and r-s cross; t and u are the crossing's weights along each.
bool crossing(vec2 p, vec2 q, vec2 r, vec2 s, out float t, out float u) {
    vec2 d1 = q - p;
    vec2 d2 = s - r;
    float denom = d1.x * d2.y - d1.y * d2.x;
    t = 0.0;
    u = 0.0;
    if (abs(denom) < 1e-20) {
        return false;
    }
    vec2 w = r - p;
    t = (w.x * d2.y - w.y * d2.x) / denom;
    u = (w.x * d1.y - w.y * d1.x) / denom;
    return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}

// The proxy of a tet whose corners (clip space) all lie beyond the near plane.
Proxy make_proxy(vec4 c[4], float s[4]) {
    Proxy proxy;
    proxy.silhouette = 0u;
    vec2 p[4];
    float inv_z[4];
    float s_z[4];
    for (int i = 0; i < 4; ++i) {
        p[i] = c[i].xy / c[i].w;
        inv_z[i] = 1.0 / c[i].w;
        s_z[i] = s[i] * inv_z[i];
    }
    uint order[4] = uint[4](0u, 1u, 2u, 3u);
    for (uint d = 0u; d < 4u; ++d) {
        uint a = (d + 1u) & 3u, b = (d + 2u) & 3u, cc = (d + 3u) & 3u;
        if (inside(p[d], p[a], p[b], p[cc])) {
            float area = edge(p[a], p[b], p[cc]);
            vec3 lambda = abs(area) > 1e-20
                ? vec3(edge(p[b], p[cc], p[d]), edge(p[cc], p[a], p[d]), edge(p[a], p[b], p[d])) / area
                : vec3(1.0, 0.0, 0.0);
            order = uint[4](a, b, cc, d);
            proxy.silhouette = 3u;
            proxy.p[3] = p[d];
            // The inner vertex seen on the opposite face: 1/z is affine in screen space on a plane.
            float opposite = dot(lambda, vec3(inv_z[a], inv_z[b], inv_z[cc]));
            proxy.attrs[3] = vec4(inv_z[d], inv_z[d] - opposite, s_z[d],
                                  dot(lambda, vec3(s_z[a], s_z[b], s_z[cc])));
            break;
        }
    }
    if (proxy.silhouette == 0u) {
        float t;
        float s;
        // The quad's diagonals are the pair of opposite edges that cross on screen.
        if (crossing(p[0], p[2], p[1], p[3], t, s)) {
            order = uint[4](0u, 1u, 2u, 3u);
        } else if (crossing(p[0], p[1], p[2], p[3], t, s)) {
            order = uint[4](0u, 2u, 1u, 3u);
        } else if (crossing(p[0], p[3], p[1], p[2], t, s)) {
            order = uint[4](0u, 1u, 3u, 2u);
        } else {
            return proxy;  // degenerate on screen: covers no pixel
        }
        uint a = order[0], b = order[1], cc = order[2], d = order[3];
        proxy.silhouette = 4u;
        proxy.p[4] = p[a] + (p[cc] - p[a]) * t;
        float on_ac = mix(inv_z[a], inv_z[cc], t);
        proxy.attrs[4] = vec4(on_ac, on_ac - mix(inv_z[b], inv_z[d], s),
                              mix(s_z[a], s_z[cc], t), mix(s_z[b], s_z[d], s));
    }
    for (uint j = 0u; j < proxy.silhouette; ++j) {
        uint k = order[j];
        proxy.p[j] = p[k];
        proxy.attrs[j] = vec4(inv_z[k], 0.0, s_z[k], s_z[k]);
    }
    return proxy;
}

// Where edge a–b meets the plane w = near (clip coordinates and the scalar are affine along a
// world segment): clip position in xyzw, and the scalar from sa to sb.
vec4 cut(vec4 a, vec4 b, float near) {
    return mix(a, b, (near - a.w) / (b.w - a.w));
}

float cut_scalar(vec4 a, vec4 b, float sa, float sb, float near) {
    return mix(sa, sb, (near - a.w) / (b.w - a.w));
}


// A vertex scalar mapped onto [0, 1] over the push constants' range, clamped, as the CPU
// reference maps it (`normalize_scalar`): per corner, before interpolation.
float normalized_scalar(float value) {
    float extent = params.scalar_range.y - params.scalar_range.x;
    return extent > 0.0 ? clamp((value - params.scalar_range.x) / extent, 0.0, 1.0) : 0.0;
}

// The proxies (up to 3, after clipping) of tet `tet`; returns how many and whether it was clipped.
uint tet_proxies(uint tet, out Proxy proxies[3], out bool clipped) {
    uint proxy_count = 0u;
    clipped = false;
    uvec4 ids = tets[tet];
    vec4 c[4];
    float sc[4];
    uint front[4];
    uint back[4];
    uint n_front = 0u;
    uint n_back = 0u;
    float near = params.near_depth;
    for (uint i = 0u; i < 4u; ++i) {
        vec4 v = vertices_world[ids[i]];
        c[i] = params.world_to_clip * vec4(v.xyz, 1.0);
        sc[i] = normalized_scalar(v.w);
        if (c[i].w > near) {
            front[n_front++] = i;
        } else {
            back[n_back++] = i;
        }
    }
    if (n_front == 4u) {
        proxies[0] = make_proxy(c, sc);
        proxy_count = 1u;
    } else if (n_front > 0u) {
        clipped = true;
        if (n_front == 1u) {
            uint f = front[0];
            vec4 piece[4] = vec4[4](c[f], cut(c[f], c[back[0]], near), cut(c[f], c[back[1]], near),
                                    cut(c[f], c[back[2]], near));
            float piece_s[4] = float[4](sc[f], cut_scalar(c[f], c[back[0]], sc[f], sc[back[0]], near),
                                        cut_scalar(c[f], c[back[1]], sc[f], sc[back[1]], near),
                                        cut_scalar(c[f], c[back[2]], sc[f], sc[back[2]], near));
            proxies[0] = make_proxy(piece, piece_s);
            proxy_count = 1u;
        } else {
            // A prism: bottom triangle i0 i1 i2, top j0 j1 j2 with jk above ik.
            vec4 prism[6];
            float prism_s[6];
            if (n_front == 3u) {
                uint o = back[0];
                for (uint k = 0u; k < 3u; ++k) {
                    uint f = front[k];
                    prism[k] = c[f];
                    prism_s[k] = sc[f];
                    prism[k + 3u] = cut(c[f], c[o], near);
                    prism_s[k + 3u] = cut_scalar(c[f], c[o], sc[f], sc[o], near);
                }
            } else {
                for (uint k = 0u; k < 2u; ++k) {
                    uint f = front[k];
                    prism[3u * k] = c[f];
                    prism_s[3u * k] = sc[f];
                    for (uint m = 0u; m < 2u; ++m) {
                        uint b = back[m];
                        prism[3u * k + 1u + m] = cut(c[f], c[b], near);
                        prism_s[3u * k + 1u + m] = cut_scalar(c[f], c[b], sc[f], sc[b], near);
                    }
                }
            }
            for (uint k = 0u; k < 3u; ++k) {
                vec4 piece[4] = vec4[4](prism[k], prism[k + 1u], prism[k + 2u], prism[k + 3u]);
                float piece_s[4] = float[4](prism_s[k], prism_s[k + 1u], prism_s[k + 2u], prism_s[k + 3u]);
                proxies[k] = make_proxy(piece, piece_s);
            }
            proxy_count = 3u;
        }
    }
    return proxy_count;
}

// tet_proxies in the pass that makes each tet's proxies first in a frame: counts a tet the
// near plane clipped in stats[STAT_CLIPPED]; no proxies past the mesh's tets.
uint first_tet_proxies(uint tet, out Proxy proxies[3]) {
    if (tet >= params.counts.x) {
        return 0u;
    }
    bool clipped;
    uint n = tet_proxies(tet, proxies, clipped);
    if (clipped) {
        atomicAdd(stats[STAT_CLIPPED], 1u);
    }
    return n;
}
