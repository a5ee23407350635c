// Volume sampling shared by every technique that reads a scalar grid. The includer defines
// VOLUME_SAMPLER (usampler3D for integer data, sampler3D for float data): texel values are the
// raw sample values, exact for 8- and 16-bit data, and interpolation is done here rather than
// by the texture unit so that results match the CPU reference bit for bit where possible.

float volume_texel(VOLUME_SAMPLER vol, ivec3 p) {
    return float(texelFetch(vol, p, 0).r);
}

// Trilinear interpolation at grid position p (sample (x,y,z) sits at (x,y,z)), clamped to the
// grid. `precise` keeps the compiler from fusing the lerps, which the CPU does not do either.
float sample_volume(VOLUME_SAMPLER vol, vec3 p, uvec3 dims) {
    vec3 hi = vec3(dims - 1u);
    p = clamp(p, vec3(0.0), hi);
    ivec3 i = min(ivec3(floor(p)), ivec3(dims) - 2);
    precise vec3 f = p - vec3(i);
    float s000 = volume_texel(vol, i);
    float s100 = volume_texel(vol, i + ivec3(1, 0, 0));
    float s010 = volume_texel(vol, i + ivec3(0, 1, 0));
    float s110 = volume_texel(vol, i + ivec3(1, 1, 0));
    float s001 = volume_texel(vol, i + ivec3(0, 0, 1));
    float s101 = volume_texel(vol, i + ivec3(1, 0, 1));
    float s011 = volume_texel(vol, i + ivec3(0, 1, 1));
    float s111 = volume_texel(vol, i + ivec3(1, 1, 1));
    precise float x00 = s000 + (s100 - s000) * f.x;
    precise float x10 = s010 + (s110 - s010) * f.x;
    precise float x01 = s001 + (s101 - s001) * f.x;
    precise float x11 = s011 + (s111 - s011) * f.x;
    precise float y0 = x00 + (x10 - x00) * f.y;
    precise float y1 = x01 + (x11 - x01) * f.y;
    precise float v = y0 + (y1 - y0) * f.z;
    return v;
}

// Entry and exit distance of a ray with the box [lo, hi]; no hit when x > y.
vec2 ray_box(vec3 origin, vec3 inv_dir, vec3 lo, vec3 hi) {
    vec3 t0 = (lo - origin) * inv_dir;
    vec3 t1 = (hi - origin) * inv_dir;
    vec3 tmin = min(t0, t1);
    vec3 tmax = max(t0, t1);
    return vec2(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

vec3 volume_gradient(VOLUME_SAMPLER vol, vec3 p, uvec3 dims) {
    return vec3(
        sample_volume(vol, p + vec3(1, 0, 0), dims) - sample_volume(vol, p - vec3(1, 0, 0), dims),
        sample_volume(vol, p + vec3(0, 1, 0), dims) - sample_volume(vol, p - vec3(0, 1, 0), dims),
        sample_volume(vol, p + vec3(0, 0, 1), dims) - sample_volume(vol, p - vec3(0, 0, 1), dims));
}
