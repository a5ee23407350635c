// Shared by interval shading's mesh-shader and compute paths: the screen-space proxies of a
// tetrahedron (paper A §2.2) and its clipping at the near plane (§2.3). Needs
// tet/interval/params.glsl and the Vertices/Tets buffers bound as `vertices_world` and `tets`.

// A tet's screen-space proxy: `silhouette` outer vertices (3 or 4, 0 for none) then the inner one.
struct Proxy {
    vec2 p[5];
    vec2 depths[5];
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
Proxy make_proxy(vec4 c[4]) {
    Proxy proxy;
    proxy.silhouette = 0u;
    vec2 p[4];
    float inv_z[4];
    for (int i = 0; i < 4; ++i) {
        p[i] = c[i].xy / c[i].w;
        inv_z[i] = 1.0 / c[i].w;
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
            proxy.depths[3] = vec2(inv_z[d], dot(lambda, vec3(inv_z[a], inv_z[b], inv_z[cc])));
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
        proxy.depths[4] = vec2(inv_z[a] + (inv_z[cc] - inv_z[a]) * t, inv_z[b] + (inv_z[d] - inv_z[b]) * s);
    }
    for (uint j = 0u; j < proxy.silhouette; ++j) {
        proxy.p[j] = p[order[j]];
        proxy.depths[j] = vec2(inv_z[order[j]]);
    }
    return proxy;
}

// Where edge a–b meets the plane w = near (clip coordinates are affine along a world segment).
vec4 cut(vec4 a, vec4 b, float near) {
    return mix(a, b, (near - a.w) / (b.w - a.w));
}


// The proxies (up to 3, after clipping) of tet `tet`; returns how many and whether it was clipped.
uint tet_proxies(uint tet, out Proxy proxies[3], out bool clipped) {
    uint proxy_count = 0u;
    clipped = false;
    uvec4 ids = tets[tet];
    vec4 c[4];
    uint front[4];
    uint back[4];
    uint n_front = 0u;
    uint n_back = 0u;
    float near = params.view.w;
    for (uint i = 0u; i < 4u; ++i) {
        c[i] = params.world_to_clip * vec4(vertices_world[ids[i]].xyz, 1.0);
        if (c[i].w > near) {
            front[n_front++] = i;
        } else {
            back[n_back++] = i;
        }
    }
    if (n_front == 4u) {
        proxies[0] = make_proxy(c);
        proxy_count = 1u;
    } else if (n_front > 0u) {
        clipped = true;
        vec4 prism[6];
        if (n_front == 1u) {
            vec4 apex = c[front[0]];
            vec4 piece[4] = vec4[4](apex, cut(apex, c[back[0]], near), cut(apex, c[back[1]], near),
                                    cut(apex, c[back[2]], near));
            proxies[0] = make_proxy(piece);
            proxy_count = 1u;
        } else {
            // A prism: bottom triangle i0 i1 i2, top j0 j1 j2 with jk above ik.
            if (n_front == 3u) {
                vec4 o = c[back[0]];
                prism = vec4[6](c[front[0]], c[front[1]], c[front[2]],
                                cut(c[front[0]], o, near), cut(c[front[1]], o, near), cut(c[front[2]], o, near));
            } else {
                vec4 a = c[front[0]];
                vec4 b = c[front[1]];
                vec4 x = c[back[0]];
                vec4 y = c[back[1]];
                prism = vec4[6](a, cut(a, x, near), cut(a, y, near), b, cut(b, x, near), cut(b, y, near));
            }
            vec4 t0[4] = vec4[4](prism[0], prism[1], prism[2], prism[3]);
            vec4 t1[4] = vec4[4](prism[1], prism[2], prism[3], prism[4]);
            vec4 t2[4] = vec4[4](prism[2], prism[3], prism[4], prism[5]);
            proxies[0] = make_proxy(t0);
            proxies[1] = make_proxy(t1);
            proxies[2] = make_proxy(t2);
            proxy_count = 3u;
        }
    }
    return proxy_count;
}
