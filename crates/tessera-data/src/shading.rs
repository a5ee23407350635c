//! Gooch shading constants and the CPU version of the shading the GPU techniques apply. The GPU
//! receives these constants as `#define`s, so the two cannot drift apart.

use glam::Vec3;

/// Tone for surfaces facing away from the light (blue-ish, Gooch et al. 1998 with kd = 0.8).
pub const GOOCH_COOL: [f32; 3] = [0.2, 0.2, 0.75];
/// Tone for surfaces facing the light.
pub const GOOCH_WARM: [f32; 3] = [0.9, 0.75, 0.4];
pub const SPECULAR_STRENGTH: f32 = 0.25;
pub const SPECULAR_EXPONENT: f32 = 32.0;
/// Colour of pixels whose ray misses the surface. Whole multiples of 1/255, so every path
/// (a shader's `packUnorm4x8`, an attachment clear, the CPU) stores exactly the same bytes.
pub const BACKGROUND: [f32; 4] = [20.0 / 255.0, 20.0 / 255.0, 26.0 / 255.0, 1.0];

/// Shades a surface with unit normal `n` (any orientation: it is turned to face the viewer),
/// unit `light` direction and unit `view` direction (from the surface towards the eye).
pub fn gooch(n: Vec3, light: Vec3, view: Vec3) -> Vec3 {
    let n = facing(n, view);
    let t = (1.0 + n.dot(light)) * 0.5;
    let cool = Vec3::from(GOOCH_COOL);
    let warm = Vec3::from(GOOCH_WARM);
    let base = cool + (warm - cool) * t;
    base + Vec3::splat(specular(n, light, view))
}

/// `n` turned towards the viewer: surfaces and volume gradients are shaded two-sided.
pub fn facing(n: Vec3, view: Vec3) -> Vec3 {
    if n.dot(view) < 0.0 {
        -n
    } else {
        n
    }
}

/// The Phong highlight of every shaded thing (surfaces and gradient-shaded volumes): unit
/// normal `n` facing the viewer, unit `light` and `view` directions.
pub fn specular(n: Vec3, light: Vec3, view: Vec3) -> f32 {
    let r = 2.0 * n.dot(light) * n - light;
    r.dot(view).max(0.0).powf(SPECULAR_EXPONENT) * SPECULAR_STRENGTH
}

/// Packs a colour the way GLSL's `packUnorm4x8` does: clamp, scale by 255, round.
pub fn pack_rgba8(c: [f32; 4]) -> u32 {
    let b = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u32);
    b[0] | (b[1] << 8) | (b[2] << 16) | (b[3] << 24)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn background_is_exact_in_eight_bits() {
        for v in BACKGROUND {
            let scaled = v * 255.0;
            assert_eq!(scaled, scaled.round(), "{v}");
        }
    }
}
