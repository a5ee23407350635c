// The secondary-ray effects of shell traversal as tessera_data::tet::shell::effects models
// them: per-tet lighting (gradient, transmittance towards the light, mean AO transmittance)
// written by lighting.comp.glsl, the ground plane, and the factor that scales a stretch's
// emission. SHELL_SHADOWS, SHELL_GRADIENT and SHELL_AO_SAMPLES say which effects are on; the
// model's constants come from the Rust side as defines.
// Needs buffers.glsl, common/shading.glsl and traverse.glsl (for infinity()).

layout(binding = 8) readonly buffer EffectParams {
    vec4 light;            // a point light's position (w = 1) or the direction towards the light (w = 0)
    vec4 ground;           // the ground plane: unit up axis, and in w its height along it
    float ao_radius;
    float max_absorption;  // the absorption table's largest value: what "dense" is measured against
} effect;
layout(binding = 9) readonly buffer TetVertices { uvec4 tet_vertices[]; };  // per tet, as ShellMesh::mesh
layout(binding = 10) buffer Gradients { vec4 gradients[]; };                 // per tet: scalar gradient
layout(binding = 11) buffer TetLight { vec4 tet_light[]; };                 // per tet: transmittance to the light
layout(binding = 12) buffer Occlusion { vec4 occlusion[]; };                // per tet: mean AO transmittance
layout(binding = 13) buffer GroundHits { vec4 ground_hits[]; };             // per pixel: colour behind the volume, t where it ends

// Unit direction from p towards the light and the distance to it (infinite for a directional
// light); a zero direction where p is the light.
vec4 towards_light(vec3 p) {
    vec3 d = effect.light.w > 0.5 ? effect.light.xyz - p : effect.light.xyz;
    float len = length(d);
    if (!(len > 0.0)) {
        return vec4(0.0);
    }
    return vec4(d / len, effect.light.w > 0.5 ? len : infinity());
}

// Two unit vectors completing unit n to a right-handed frame, as ray_space() builds its basis.
void hemisphere_frame(vec3 n, out vec3 u, out vec3 v) {
    vec3 helper = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    u = normalize(cross(n, helper));
    v = cross(n, u);
}

// The AO hemisphere's axis: down the gradient, towards lower scalars.
vec3 ao_normal(vec3 gradient) {
    return dot(gradient, gradient) > 0.0 ? normalize(-gradient) : AO_FALLBACK_NORMAL;
}

// How much gradient shading applies at a stretch of this mean absorption: a ramp up to
// GRADIENT_THRESHOLD; none where the gradient vanishes.
float gradient_weight(vec3 mean_absorption, vec3 gradient) {
    if (!(effect.max_absorption > 0.0) || gradient == vec3(0.0)) {
        return 0.0;
    }
    float relative = max(max(mean_absorption.r, mean_absorption.g), mean_absorption.b) / effect.max_absorption;
    return clamp((relative - (GRADIENT_THRESHOLD - GRADIENT_RAMP)) / GRADIENT_RAMP, 0.0, 1.0);
}

// StretchLighting::emission_factor.
vec3 emission_factor(vec3 occluded, vec3 light, float w, vec3 gradient, vec3 to_light, vec3 to_eye) {
    float diffuse = 1.0;
    float highlight = 0.0;
    if (w > 0.0 && dot(gradient, gradient) > 0.0) {
        vec3 n = facing(normalize(gradient), to_eye);
        diffuse = max(dot(n, to_light), 0.0);
        highlight = specular(n, to_light, to_eye);
    }
    diffuse = 1.0 + (diffuse - 1.0) * w;
    return occluded * (vec3(VOLUME_AMBIENT) + (1.0 - VOLUME_AMBIENT) * light * diffuse + light * (w * highlight));
}

// The emission factor of tet `tet`'s stretch around `midpoint` along unit `dir`.
vec3 shade_stretch(uint tet, vec3 midpoint, vec3 dir, vec3 mean_absorption) {
    vec3 occluded = vec3(1.0);
    vec3 light = vec3(1.0);
    vec3 gradient = vec3(0.0);
#if SHELL_AO_SAMPLES > 0
    occluded = occlusion[tet].rgb;
#endif
#if SHELL_SHADOWS
    light = tet_light[tet].rgb;
#endif
#if SHELL_GRADIENT
    gradient = gradients[tet].xyz;
#endif
    float w = gradient_weight(mean_absorption, gradient);
    return emission_factor(occluded, light, w, gradient, towards_light(midpoint).xyz, -dir);
}

// Where origin + t dir (unit dir) meets the square ground plane beyond t_min; infinity where
// it does not.
float ground_hit(vec3 origin, vec3 dir, float t_min) {
    vec3 up = effect.ground.xyz;
    float t = (effect.ground.w - dot(origin, up)) / dot(dir, up);
    if (!(t > t_min) || isinf(t) || isnan(t)) {
        return infinity();
    }
    vec3 p = origin + dir * t;
    vec3 across = abs(p - dot(p, up) * up);
    return max(max(across.x, across.y), across.z) <= GROUND_HALF_EXTENT ? t : infinity();
}

// The ground's colour where its transmittance towards the light (unit to_light) is `light`.
vec3 ground_colour(vec3 to_light, vec3 light) {
    float diffuse = max(dot(effect.ground.xyz, to_light), 0.0);
    return GROUND_ALBEDO * (vec3(VOLUME_AMBIENT) + (1.0 - VOLUME_AMBIENT) * diffuse * light);
}
