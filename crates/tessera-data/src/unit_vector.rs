//! Unit vectors in 32 bits, the octahedral way the GPU's lists store normals
//! (`common/unit_vector.glsl`): the sphere folded onto the square |u| + |v| <= 1, its lower
//! half unfolded into the corners, each coordinate a 16-bit snorm (u in the low half). Written
//! from the format, not from the shader, so that each checks the other.

use glam::{Vec2, Vec3};

/// What a zero or non-finite vector packs to; 16-bit snorms write -1 as 0x8001, so no
/// direction has it.
pub const PACKED_ZERO_VECTOR: u32 = 0x8000_8000;

fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

fn snorm16(x: f32) -> u32 {
    ((x.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32
}

fn from_snorm16(bits: u32) -> f32 {
    (bits as u16 as i16 as f32 / 32767.0).max(-1.0)
}

/// `v`'s direction in 32 bits.
pub fn pack(v: Vec3) -> u32 {
    let l1 = v.x.abs() + v.y.abs() + v.z.abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return PACKED_ZERO_VECTOR;
    }
    let mut p = Vec2::new(v.x, v.y) / l1;
    if v.z < 0.0 {
        p = (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign_not_zero(p);
    }
    snorm16(p.x) | snorm16(p.y) << 16
}

/// The unit vector `packed` holds (zero for [`PACKED_ZERO_VECTOR`]).
pub fn unpack(packed: u32) -> Vec3 {
    if packed == PACKED_ZERO_VECTOR {
        return Vec3::ZERO;
    }
    let p = Vec2::new(from_snorm16(packed & 0xffff), from_snorm16(packed >> 16));
    let z = 1.0 - p.x.abs() - p.y.abs();
    let xy = if z < 0.0 {
        (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign_not_zero(p)
    } else {
        p
    };
    Vec3::new(xy.x, xy.y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every direction, the poles and the folds included, comes back within 1e-4 rad.
    #[test]
    fn directions_come_back_within_a_ten_thousandth_of_a_radian() {
        let mut worst = 0.0f32;
        let mut check = |v: Vec3| {
            let back = unpack(pack(v));
            let u = v.normalize();
            let angle = u.cross(back).length().atan2(u.dot(back));
            worst = worst.max(angle);
            assert!(angle < 1e-4, "{v} came back as {back} ({angle} rad)");
        };
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            check(axis);
            check(-axis);
        }
        let steps = 200;
        for i in 0..=steps {
            let theta = std::f32::consts::PI * i as f32 / steps as f32;
            for j in 0..steps {
                let phi = std::f32::consts::TAU * j as f32 / steps as f32;
                let v = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                check(v * (0.01 + j as f32));
            }
        }
        assert!(worst > 1e-6, "a packing that loses nothing is not 32 bits");
    }

    #[test]
    fn zero_and_non_finite_vectors_pack_to_the_zero_code() {
        for v in [Vec3::ZERO, Vec3::NAN, Vec3::new(f32::INFINITY, 0.0, 1.0)] {
            assert_eq!(pack(v), PACKED_ZERO_VECTOR, "{v}");
        }
        assert_eq!(unpack(PACKED_ZERO_VECTOR), Vec3::ZERO);
        assert_ne!(pack(-Vec3::ONE), PACKED_ZERO_VECTOR);
        assert_ne!(pack(Vec3::new(-1.0, -1.0, 0.0)), PACKED_ZERO_VECTOR);
    }
}
