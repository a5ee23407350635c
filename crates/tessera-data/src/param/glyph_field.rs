//! Fields of SH glyphs like diffusion-MRI orientation distributions: per glyph one to three
//! fibre directions, each a sharp lobe `exp(-k (1 - (d·v)²))`, projected onto the SH basis of the
//! requested order. Deterministic in the seed, so scenes and benchmarks repeat.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::glyph::{extreme_directions, RadiusNormalization, ShGlyph};
use super::sh::{sh_basis, sh_basis_dir, sh_coefficient_count, ShBasis};
use crate::error::{DataError, Result};
use crate::nifti::ComponentVolume;

/// Lobe sharpness: large enough that crossing fibres stay apart at order 8 and up.
const SHARPNESS: f64 = 12.0;

/// One glyph of a field: its centre and shape. Centres of a generated grid are one unit
/// apart; those of a coefficient volume are in the file's physical units (its spacing).
#[derive(Debug, Clone)]
pub struct FieldGlyph {
    pub centre: Vec3,
    pub glyph: ShGlyph,
}

/// An `nx × ny` grid of glyphs of `order` in the `basis`, min-max normalized (DIPY's
/// convention for display), centred on the origin in the z = 0 plane.
pub fn sh_glyph_grid(
    nx: u32,
    ny: u32,
    order: u32,
    basis: ShBasis,
    seed: u64,
) -> Result<Vec<FieldGlyph>> {
    if nx == 0 || ny == 0 || u64::from(nx) * u64::from(ny) > 1 << 22 {
        return Err(DataError::Invalid(format!(
            "a glyph grid of {nx}x{ny}: both sides must be at least 1 and the count at most 4194304"
        )));
    }
    let count = sh_coefficient_count(order)?;
    let points = quadrature_points(4 * count + 64);
    let basis_at: Vec<Vec<f64>> = points
        .iter()
        .map(|&d| sh_basis_dir(basis, order, d))
        .collect::<Result<_>>()?;
    let shapes: Vec<(Vec3, Vec<f64>)> = (0..nx * ny)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % nx, i / nx);
            let fibres = fibres(seed, i);
            // Projection by equal-weight quadrature over nearly uniform points.
            let mut coeffs = vec![0.0; count];
            for (d, row) in points.iter().zip(&basis_at) {
                let f: f64 = fibres
                    .iter()
                    .map(|(v, w)| w * (-SHARPNESS * (1.0 - d.dot(*v).powi(2))).exp())
                    .sum();
                for (c, y) in coeffs.iter_mut().zip(row) {
                    *c += f * y;
                }
            }
            let scale = 4.0 * std::f64::consts::PI / points.len() as f64;
            coeffs.iter_mut().for_each(|c| *c *= scale);
            let centre = Vec3::new(
                x as f32 - (nx - 1) as f32 * 0.5,
                y as f32 - (ny - 1) as f32 * 0.5,
                0.0,
            );
            (centre, coeffs)
        })
        .collect();
    min_max_glyphs(shapes, basis, order)
}

/// The glyphs of an SH coefficient volume (e.g. DIPY's `shm_coeff` saved as NIfTI): one per
/// voxel whose coefficients are not all zero, of the order the component count implies, centred
/// on the volume's middle and spaced by the voxel spacing (physical units, as a scalar volume's
/// grid); only slice `z` if given. `what` names the file. Glyph shapes stay in the grid's
/// frame, as the coefficients were fitted in it: the orientation turns the view (see
/// [`ComponentVolume::up_axis`]), not each glyph.
pub fn sh_glyph_volume(
    volume: &ComponentVolume,
    basis: ShBasis,
    z_slice: Option<u32>,
    what: &str,
) -> Result<Vec<FieldGlyph>> {
    let n = volume.components as usize;
    let order = (0..=32u32)
        .step_by(2)
        .find(|&l| sh_coefficient_count(l).is_ok_and(|c| c == n))
        .ok_or_else(|| {
            DataError::Invalid(format!(
                "{what}: {n} values per voxel is no SH coefficient count ((L+1)(L+2)/2 for an \
                 even order L: 1, 6, 15, 28, 45, 66, 91, ...)"
            ))
        })?;
    let [nx, ny, nz] = volume.dims;
    if let Some(z) = z_slice.filter(|&z| z >= nz) {
        return Err(DataError::Invalid(format!(
            "{what}: slice {z} is outside the volume's {nz} slices"
        )));
    }
    let middle = Vec3::new(nx as f32 - 1.0, ny as f32 - 1.0, nz as f32 - 1.0) * 0.5;
    let spacing = Vec3::from(volume.spacing);
    let slices = z_slice.map_or(0..nz, |z| z..z + 1);
    let shapes: Vec<(Vec3, Vec<f64>)> = slices
        .flat_map(|z| (0..ny).flat_map(move |y| (0..nx).map(move |x| (x, y, z))))
        .filter_map(|(x, y, z)| {
            let coeffs: Vec<f64> = volume.voxel(x, y, z).into_iter().map(f64::from).collect();
            coeffs.iter().any(|&c| c != 0.0).then(|| {
                let centre = (Vec3::new(x as f32, y as f32, z as f32) - middle) * spacing;
                (centre, coeffs)
            })
        })
        .collect();
    if shapes.is_empty() {
        return Err(DataError::Invalid(format!(
            "{what}: every voxel's coefficients are zero: nothing to draw"
        )));
    }
    min_max_glyphs(shapes, basis, order)
}

/// Min-max normalized glyphs, their radius ranges from one basis table shared by all (sampling
/// each glyph's range on its own would cost thousands of basis evaluations per glyph).
fn min_max_glyphs(
    shapes: Vec<(Vec3, Vec<f64>)>,
    basis: ShBasis,
    order: u32,
) -> Result<Vec<FieldGlyph>> {
    let range_basis: Vec<Vec<f64>> = extreme_directions(order)
        .into_par_iter()
        .map(|(theta, phi)| sh_basis(basis, order, theta, phi))
        .collect::<Result<_>>()?;
    shapes
        .into_par_iter()
        .map(|(centre, coeffs)| {
            let range = range_basis
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |r, row| {
                    let v: f64 = row.iter().zip(&coeffs).map(|(y, c)| y * c).sum();
                    (r.0.min(v), r.1.max(v))
                });
            let glyph =
                ShGlyph::with_raw_range(basis, order, coeffs, RadiusNormalization::MinMax, range)?;
            Ok(FieldGlyph { centre, glyph })
        })
        .collect()
}

/// A Fibonacci lattice on the unit sphere: nearly uniform, so equal weights integrate well.
fn quadrature_points(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// One to three fibre directions with weights for glyph `i`.
fn fibres(seed: u64, i: u32) -> Vec<(DVec3, f64)> {
    let mut state = seed ^ (u64::from(i) + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 1 + (next() * 3.0) as usize;
    (0..n.min(3))
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * next();
            let r = (1.0 - z * z).sqrt();
            (DVec3::new(r * phi.cos(), r * phi.sin(), z), 0.5 + next())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_point_along_their_fibres() {
        let basis = ShBasis::Descoteaux07 { legacy: false };
        let field = sh_glyph_grid(3, 2, 8, basis, 5).unwrap();
        assert_eq!(field.len(), 6);
        assert_eq!(field[0].centre, Vec3::new(-1.0, -0.5, 0.0));
        for (i, g) in field.iter().enumerate() {
            let fibres = fibres(5, i as u32);
            // The radius along the heaviest fibre is near the glyph's maximum (1 after min-max).
            let (v, _) =
                fibres
                    .iter()
                    .copied()
                    .fold((DVec3::Z, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
            let theta = v.z.clamp(-1.0, 1.0).acos();
            let phi = v.y.atan2(v.x);
            assert!(g.glyph.radius(theta, phi) > 0.6, "glyph {i}");
        }
        let again = sh_glyph_grid(3, 2, 8, basis, 5).unwrap();
        assert_eq!(again[4].glyph, field[4].glyph);
        // The shared-table range equals the glyph's own sampling.
        let own = ShGlyph::new(
            basis,
            8,
            field[2].glyph.coefficients().to_vec(),
            RadiusNormalization::MinMax,
        )
        .unwrap();
        let (a, b) = (own.raw_range(), field[2].glyph.raw_range());
        assert!((a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12);
        assert!(sh_glyph_grid(0, 2, 8, basis, 5).is_err());
        assert!(sh_glyph_grid(2, 2, 7, basis, 5).is_err());
    }
}
