//! Shared pieces of the parametric-object tests: the scenes they draw and how images are held
//! to the CPU reference.

use glam::{Mat4, Quat, Vec3};
use tessera::param::{ParamObject, ParamScene};
use tessera_data::image::{coverage_of, silhouette_iou};
use tessera_data::param::sh::{sh_coefficient_count, sh_index};
use tessera_data::param::{ParamFunction, RadiusNormalization, ShBasis, ShGlyph};
use tessera_data::shading::pack_rgba8;
use tessera_data::RgbaImage;

/// Whole 1/255 steps, so that the GPU's clear and the CPU's packing agree exactly.
pub const BACKGROUND: [f32; 3] = [20.0 / 255.0, 20.0 / 255.0, 26.0 / 255.0];
pub const SIZE: (u32, u32) = (160, 160);
/// Written into outputs before a pass, so pixels it never wrote are caught.
pub const POISON: u32 = 0xdead_beef;

/// An order-8 glyph with lobes in several directions (descoteaux07, non-legacy, min-max).
pub fn glyph8() -> ParamFunction {
    let mut c = vec![0.0; sh_coefficient_count(8).unwrap()];
    for (l, m, value) in [
        (0, 0, 1.0),
        (2, 0, 0.5),
        (2, 2, 0.4),
        (4, -3, 0.3),
        (6, 5, 0.25),
        (8, 8, 0.2),
        (8, -1, 0.15),
    ] {
        c[sh_index(l, m).unwrap()] = value;
    }
    let basis = ShBasis::Descoteaux07 { legacy: false };
    ParamFunction::ShGlyph(ShGlyph::new(basis, 8, c, RadiusNormalization::MinMax).unwrap())
}

pub fn one(function: ParamFunction) -> ParamScene {
    ParamScene::new(vec![ParamObject::new(function).with_colour([0.9, 0.6, 0.3])])
}

/// A sphere, a heart and a glyph side by side, turned and scaled.
pub fn trio() -> ParamScene {
    let place = |s: Vec3, r: Quat, t: Vec3| Mat4::from_scale_rotation_translation(s, r, t);
    ParamScene::new(vec![
        ParamObject::new(ParamFunction::Sphere)
            .with_transform(place(
                Vec3::splat(0.5),
                Quat::from_rotation_x(0.4),
                Vec3::new(-1.1, 0.0, 0.0),
            ))
            .with_colour([0.3, 0.8, 0.4]),
        ParamObject::new(ParamFunction::Heart)
            .with_transform(place(
                Vec3::new(0.7, 0.7, 1.2),
                Quat::from_rotation_y(0.7),
                Vec3::new(0.1, 0.2, 0.0),
            ))
            .with_colour([0.9, 0.3, 0.3]),
        ParamObject::new(glyph8()).with_transform(place(
            Vec3::splat(0.6),
            Quat::from_rotation_z(0.3),
            Vec3::new(1.1, -0.1, 0.2),
        )),
    ])
}

/// (silhouette IoU against the [`BACKGROUND`], fraction of co-covered pixels within 4/255,
/// co-covered pixels).
pub fn compare(image: &RgbaImage, reference: &RgbaImage) -> (f64, f64, usize) {
    let (a, b, both) = coverage(image, reference);
    let diff = image.compare_where(reference, &both, 4);
    (
        silhouette_iou(&a, &b),
        diff.fraction_within,
        both.iter().filter(|&&x| x).count(),
    )
}

/// Fraction of the co-covered pixels within 16/255: the rest show another surface than the
/// reference (a hole through to the far side, say), not a shading difference.
pub fn far_within(image: &RgbaImage, reference: &RgbaImage) -> f64 {
    let (_, _, both) = coverage(image, reference);
    image.compare_where(reference, &both, 16).fraction_within
}

/// The pixels `image` covers, those `reference` covers (not the [`BACKGROUND`]), and both.
fn coverage(image: &RgbaImage, reference: &RgbaImage) -> (Vec<bool>, Vec<bool>, Vec<bool>) {
    let bg = pack_rgba8([BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1.0]);
    let a = coverage_of(image, bg);
    let b = coverage_of(reference, bg);
    let both = a.iter().zip(&b).map(|(x, y)| *x && *y).collect();
    (a, b, both)
}

/// `ParamPointsOptions` with some fields changed from the defaults.
#[macro_export]
macro_rules! points_opts {
    ($($field:ident: $value:expr),*) => {
        tessera::param::ParamPointsOptions { $($field: $value,)* ..tessera::param::ParamPointsOptions::default() }
    };
}
