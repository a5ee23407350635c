//! Real spherical harmonics (SH) as DIPY defines them, for SH glyphs of diffusion MRI data.
//!
//! Angles follow DIPY: `theta` is the polar angle from +z (colatitude, `[0, π]`) and `phi` the
//! azimuth from +x towards +y (`[0, 2π)`), so a direction is
//! `(sin θ cos φ, sin θ sin φ, cos θ)`.
//!
//! Let `K_l^m(θ) = sqrt((2l+1)/(4π) · (l-m)!/(l+m)!) · P_l^m(cos θ)` for `m >= 0`, where `P_l^m`
//! carries the Condon–Shortley phase `(-1)^m` (as scipy's `lpmv` / `sph_harm_y`, which DIPY
//! calls). The complex harmonic is `Y_l^m = K_l^m e^{imφ}` and `Y_l^{-m} = (-1)^m conj(Y_l^m)`.
//! The bases, as implemented in `dipy/reconst/shm.py` (`real_sh_descoteaux_from_index`,
//! `real_sh_tournier_from_index`), are, with `a = |m|`:
//!
//! | basis                    | m < 0                          | m = 0     | m > 0              |
//! |--------------------------|--------------------------------|-----------|--------------------|
//! | descoteaux07, legacy     | `√2 K_l^a cos(aφ)`             | `K_l^0`   | `√2 K_l^m sin(mφ)` |
//! | descoteaux07, non-legacy | `(-1)^a √2 K_l^a cos(aφ)`      | `K_l^0`   | `√2 K_l^m sin(mφ)` |
//! | tournier07, legacy       | `K_l^a sin(aφ)`                | `K_l^0`   | `K_l^m cos(mφ)`    |
//! | tournier07, non-legacy   | `√2 K_l^a sin(aφ)`             | `K_l^0`   | `√2 K_l^m cos(mφ)` |
//!
//! DIPY's legacy descoteaux07 takes `Re(Y_l^{|m|})` for `m < 0` where the paper's definition
//! takes `Re(Y_l^m)`; the two differ by `(-1)^m`, i.e. only the odd negative orders flip sign.
//! Legacy tournier07 (MRtrix 0.2) omits the `√2`, so its `m ≠ 0` functions have norm `1/√2`;
//! the other three bases are orthonormal.
//!
//! Coefficients are ordered as DIPY's `sph_harm_ind_list`: even `l = 0, 2, …, L`, and within
//! each `l`, `m = -l, …, l`. An order `L` basis has `(L+1)(L+2)/2` functions.

use std::f64::consts::{PI, SQRT_2};

use glam::DVec3;

use crate::error::{DataError, Result};

/// Largest SH order the symmetric-basis functions accept. The recurrences stay accurate far
/// beyond it; the cap only bounds the size of coefficient vectors built from user input.
pub const MAX_SH_ORDER: u32 = 128;

/// One of DIPY's two real SH bases, with its `legacy` flag (DIPY's default is `legacy=True`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShBasis {
    Descoteaux07 { legacy: bool },
    Tournier07 { legacy: bool },
}

impl ShBasis {
    /// Whether `∫ Y_i Y_j dΩ = δ_ij` (all bases but legacy tournier07).
    pub fn is_orthonormal(self) -> bool {
        !matches!(self, ShBasis::Tournier07 { legacy: true })
    }
}

/// Number of coefficients of the even (antipodally symmetric) basis of order `order`.
pub fn sh_coefficient_count(order: u32) -> Result<usize> {
    check_order(order)?;
    Ok(count_unchecked(order))
}

/// Index of `(l, m)` in the coefficient vector (`l` even, `|m| <= l`).
pub fn sh_index(l: u32, m: i32) -> Result<usize> {
    if !l.is_multiple_of(2) || m.unsigned_abs() > l {
        return Err(DataError::Invalid(format!(
            "no symmetric SH coefficient for l = {l}, m = {m} (l must be even and |m| <= l)"
        )));
    }
    Ok(offset_of_degree(l) + (i64::from(m) + i64::from(l)) as usize)
}

/// `(l, m)` of every coefficient of an order-`order` basis, in coefficient order.
pub fn sh_degrees_and_orders(order: u32) -> Result<Vec<(u32, i32)>> {
    check_order(order)?;
    let mut out = Vec::with_capacity(count_unchecked(order));
    for l in (0..=order).step_by(2) {
        let l_i = l as i32;
        out.extend((-l_i..=l_i).map(|m| (l, m)));
    }
    Ok(out)
}

/// All basis functions of order `order` at polar angle `theta`, azimuth `phi`.
pub fn sh_basis(basis: ShBasis, order: u32, theta: f64, phi: f64) -> Result<Vec<f64>> {
    let mut out = vec![0.0; sh_coefficient_count(order)?];
    sh_basis_into(basis, order, theta, phi, &mut out)?;
    Ok(out)
}

/// [`sh_basis`] for a direction (any non-zero length).
pub fn sh_basis_dir(basis: ShBasis, order: u32, dir: DVec3) -> Result<Vec<f64>> {
    let (theta, phi) = direction_to_angles(dir)?;
    sh_basis(basis, order, theta, phi)
}

/// [`sh_basis`] into a caller-provided slice of exactly the right length.
pub fn sh_basis_into(
    basis: ShBasis,
    order: u32,
    theta: f64,
    phi: f64,
    out: &mut [f64],
) -> Result<()> {
    let count = sh_coefficient_count(order)?;
    check_angles(theta, phi)?;
    if out.len() != count {
        return Err(DataError::Invalid(format!(
            "order {order} has {count} SH coefficients, output has room for {}",
            out.len()
        )));
    }
    visit_basis(basis, order, theta, phi, |j, y| out[j] = y);
    Ok(())
}

/// `Σ_j c_j Y_j(θ, φ)`: the radius of an SH glyph in direction `(theta, phi)`.
pub fn sh_evaluate(
    basis: ShBasis,
    order: u32,
    coeffs: &[f64],
    theta: f64,
    phi: f64,
) -> Result<f64> {
    check_coefficients(order, coeffs)?;
    check_angles(theta, phi)?;
    Ok(evaluate_unchecked(basis, order, coeffs, theta, phi))
}

/// [`sh_evaluate`] for a direction (any non-zero length).
pub fn sh_evaluate_dir(basis: ShBasis, order: u32, coeffs: &[f64], dir: DVec3) -> Result<f64> {
    let (theta, phi) = direction_to_angles(dir)?;
    sh_evaluate(basis, order, coeffs, theta, phi)
}

/// One real harmonic of any degree `l` (odd too) and order `|m| <= l`.
pub fn sh_real(basis: ShBasis, l: u32, m: i32, theta: f64, phi: f64) -> Result<f64> {
    if m.unsigned_abs() > l {
        return Err(DataError::Invalid(format!(
            "SH order |m| = {} exceeds degree l = {l}",
            m.unsigned_abs()
        )));
    }
    check_angles(theta, phi)?;
    let a = m.unsigned_abs();
    let mut k = 0.0;
    visit_legendre_column(l, a, theta, |deg, value| {
        if deg == l {
            k = value;
        }
    });
    Ok(combine(basis, m, k, phi))
}

/// `(theta, phi)` of a non-zero direction, `phi` in `[0, 2π)`.
pub fn direction_to_angles(dir: DVec3) -> Result<(f64, f64)> {
    if !dir.is_finite() || dir.length_squared() == 0.0 {
        return Err(DataError::Invalid(format!(
            "SH direction must be finite and non-zero, got {dir}"
        )));
    }
    // atan2 keeps full precision near the poles, where acos(z / |d|) loses it.
    let theta = dir.x.hypot(dir.y).atan2(dir.z);
    let mut phi = dir.y.atan2(dir.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    Ok((theta, phi))
}

/// Checks that `coeffs` is a coefficient vector of an order-`order` basis with finite values.
pub fn check_coefficients(order: u32, coeffs: &[f64]) -> Result<()> {
    let count = sh_coefficient_count(order)?;
    if coeffs.len() != count {
        return Err(DataError::Invalid(format!(
            "SH order {order} needs {count} coefficients, got {}",
            coeffs.len()
        )));
    }
    if let Some(i) = coeffs.iter().position(|c| !c.is_finite()) {
        return Err(DataError::Invalid(format!(
            "SH coefficient {i} is not finite ({})",
            coeffs[i]
        )));
    }
    Ok(())
}

/// [`sh_evaluate`] without validation, for callers that validated `order` and `coeffs` once.
/// Non-finite angles give NaN.
pub(crate) fn evaluate_unchecked(
    basis: ShBasis,
    order: u32,
    coeffs: &[f64],
    theta: f64,
    phi: f64,
) -> f64 {
    let mut sum = 0.0;
    visit_basis(basis, order, theta, phi, |j, y| sum += coeffs[j] * y);
    sum
}

fn check_order(order: u32) -> Result<()> {
    if !order.is_multiple_of(2) || order > MAX_SH_ORDER {
        return Err(DataError::Invalid(format!(
            "SH order must be even and at most {MAX_SH_ORDER} (symmetric basis), got {order}"
        )));
    }
    Ok(())
}

fn check_angles(theta: f64, phi: f64) -> Result<()> {
    if !theta.is_finite() || !phi.is_finite() {
        return Err(DataError::Invalid(format!(
            "SH angles must be finite, got θ = {theta}, φ = {phi}"
        )));
    }
    Ok(())
}

fn count_unchecked(order: u32) -> usize {
    let l = order as usize;
    (l + 1) * (l + 2) / 2
}

/// Coefficients of all even degrees below `l`.
fn offset_of_degree(l: u32) -> usize {
    let l = l as usize;
    l * l.saturating_sub(1) / 2
}

/// Calls `f(index, Y_index)` for every function of the even basis of order `order`.
fn visit_basis(basis: ShBasis, order: u32, theta: f64, phi: f64, mut f: impl FnMut(usize, f64)) {
    for a in 0..=order {
        visit_legendre_column(order, a, theta, |l, k| {
            if !l.is_multiple_of(2) {
                return;
            }
            let base = offset_of_degree(l) + l as usize;
            if a == 0 {
                f(base, k);
            } else {
                f(base + a as usize, combine(basis, a as i32, k, phi));
                f(base - a as usize, combine(basis, -(a as i32), k, phi));
            }
        });
    }
}

/// The real basis function of order `m` from `K_l^{|m|}` (see the module table).
fn combine(basis: ShBasis, m: i32, k: f64, phi: f64) -> f64 {
    if m == 0 {
        return k;
    }
    let a = m.unsigned_abs();
    let (sin, cos) = (f64::from(a) * phi).sin_cos();
    match basis {
        ShBasis::Descoteaux07 { legacy } => {
            if m > 0 {
                SQRT_2 * k * sin
            } else if !legacy && !a.is_multiple_of(2) {
                -SQRT_2 * k * cos
            } else {
                SQRT_2 * k * cos
            }
        }
        ShBasis::Tournier07 { legacy } => {
            let scale = if legacy { 1.0 } else { SQRT_2 };
            if m > 0 {
                scale * k * cos
            } else {
                scale * k * sin
            }
        }
    }
}

/// Calls `f(l, K_l^a(θ))` for `l = a, …, lmax` using the fully normalised three-term recurrence.
///
/// Normalised values are carried throughout, so no factorial is ever formed (they overflow `f64`
/// beyond l ≈ 85); the sectoral start `K_a^a` is built by a product of `sin θ` factors. Using
/// `sin θ` directly (not `sqrt(1 - cos²θ)`) keeps full relative precision near the poles, and a
/// negative `sin θ` (θ outside `[0, π]`) still gives the right value because the sign change
/// `(-1)^a` is matched by the azimuth shift `φ + π` of that direction.
fn visit_legendre_column(lmax: u32, a: u32, theta: f64, mut f: impl FnMut(u32, f64)) {
    if a > lmax {
        return;
    }
    let (s, x) = theta.sin_cos();
    let mut kaa = 1.0 / (4.0 * PI).sqrt();
    for j in 1..=a {
        let j = f64::from(j);
        kaa *= -((2.0 * j + 1.0) / (2.0 * j)).sqrt() * s;
    }
    f(a, kaa);
    if a == lmax {
        return;
    }
    let af = f64::from(a);
    let mut prev = kaa;
    let mut cur = (2.0 * af + 3.0).sqrt() * x * kaa;
    f(a + 1, cur);
    for l in a + 2..=lmax {
        let lf = f64::from(l);
        let alm = ((4.0 * lf * lf - 1.0) / (lf * lf - af * af)).sqrt();
        let lm1 = lf - 1.0;
        let blm = ((lm1 * lm1 - af * af) / (4.0 * lm1 * lm1 - 1.0)).sqrt();
        let next = alm * (x * cur - blm * prev);
        prev = cur;
        cur = next;
        f(l, cur);
    }
}

#[cfg(test)]
#[path = "sh_tests.rs"]
mod tests;
