//! Ray tracing of SH glyphs after Peters et al. 2023 ("Ray Tracing Spherical Harmonics Glyphs",
//! VMV 2023), on the CPU in f64: the ground truth of `tessera::param::raytrace`, whose shaders
//! follow the same steps in f32, and the source of the tables and grids they read.
//!
//! Method (Peters et al., as their published shader does it). In object space a glyph is
//! `|p| = r(p/|p|)` with `r` a sum of SH of even degrees up to `k`, which on the sphere equals a
//! homogeneous polynomial `R` of degree `k`; squaring, the surface is a zero of
//! `F(p) = R(p)² - |p|^(2k+2)`, positive inside. A ray and the glyph centre span a plane with
//! axes `d` (the ray) and `ĉ` (towards the ray's closest point, at distance `h`); in it,
//! `R(x, y) = Σ a_j x^j y^(k-j)`, whose `k + 1` coefficients come from `k + 1` samples of `r` on
//! a half circle times a fixed inverse Vandermonde matrix ([`inverse_vandermonde`]), and
//! `Σ |a_j| max|cos^j sin^(k-j)|` bounds the glyph in that plane ([`monomial_bound`]). Along the
//! ray `y = h`, so `F` is a polynomial of degree `2k + 2` in the ray coordinate `x`; its first
//! root inside the bound is the hit. Roots are isolated after Yuksel 2022: the roots of each
//! derivative bracket the intervals where the next higher one is monotonic, from the linear
//! derivative up to `F`, each root found by Newton steps safeguarded by bisection.
//!
//! Changes from Peters et al.:
//! * The ray coordinate is `u = x / L` with `L = max(h, B / 8)` (`B` the bound) where Peters
//!   uses `L = h`. Values of `F` span `(B / L)^(2k+2)`; with `L = h` a ray passing within
//!   `B / 30` of the centre of an order-12 glyph overflows f32, with this `L` the largest value
//!   stays below `8^(2k+2)` and rays far from the centre are unchanged.
//! * Peters stops Newton's method once a step is below 1e-4 of the interval. Near a root of
//!   high multiplicity (a ray through the centre gives `F` a `2k`-fold root there) Newton
//!   crawls, that test stops it far from the root, and the misplaced root of one derivative
//!   misplaces the brackets of the next. Here a bisection is forced whenever a Newton step does
//!   not halve the one before (after Numerical Recipes' `rtsafe`), to a tolerance near rounding.
//! * Normalised glyphs (`MinMax`, `MaxAbs`) are `clamp(r · s + o)`, with `(s, o)` from
//!   [`radius_scale_offset`] (`tessera::param::scene`'s radius map): the affine map is folded
//!   into the samples (a constant is an SH of degree 0), and the upper clamp, which flattens the
//!   few caps where the estimated range falls short of the true maximum, is honoured by taking
//!   `B` = the clamp: a ray that enters the bounding sphere inside the glyph hits that sphere.
//!   The lower clamp of `MinMax` (at 0) is not: where the unclamped radius dips below zero by
//!   the estimate's residual, a lobe of that tiny size appears through the centre.
//! * `PositiveLobes` glyphs (`max(r, 0)`): `F`'s roots are where `R = ±|p|^(k+1)`, and only
//!   those with `R > 0` lie on a positive lobe, so roots where the plane polynomial `R` along the
//!   ray is not positive are passed over, and a ray starts inside only where `R > 0` too.
//! * Only the first root is kept (no uncertainty glyphs or shadows), and the polynomial degree
//!   follows each glyph's own order, so one scene may mix orders.

use glam::{DVec3, Mat4, Vec3};

use super::glyph::{RadiusNormalization, ShGlyph};
use super::reference::ReferenceObject;
use super::sh::sh_degrees_and_orders;
use super::ParamFunction;
use crate::error::{DataError, Result};

/// Highest SH order ray traced: polynomials of degree 34, whose f32 roots are still good.
pub const MAX_RAYTRACE_ORDER: u32 = 16;
/// `L >= B / BOUND_DIVISOR`: keeps `F` below `8^(2k+2)` (see the module notes).
pub const BOUND_DIVISOR: f64 = 8.0;
/// Most grid cells per glyph: memory stays linear in the scene.
const MAX_CELLS_PER_GLYPH: usize = 8;

/// `M` with `a = M · r`: coefficients `a_j` of `R(x, y) = Σ a_j x^j y^(k-j)` from samples
/// `r_i = R(cos α_i, sin α_i)`, `α_i = iπ/(k+1)`; row-major `(k+1)²`, by Gauss–Jordan
/// elimination in f64 with partial pivoting.
pub fn inverse_vandermonde(order: u32) -> Vec<f64> {
    let n = order as usize + 1;
    let mut m = vec![0.0; n * 2 * n];
    for i in 0..n {
        let (s, c) = (i as f64 * std::f64::consts::PI / n as f64).sin_cos();
        for j in 0..n {
            m[i * 2 * n + j] = c.powi(j as i32) * s.powi((n - 1 - j) as i32);
        }
        m[i * 2 * n + n + i] = 1.0;
    }
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&a, &b| {
                m[a * 2 * n + col]
                    .abs()
                    .total_cmp(&m[b * 2 * n + col].abs())
            })
            .unwrap_or(col);
        for j in 0..2 * n {
            m.swap(col * 2 * n + j, pivot * 2 * n + j);
        }
        let p = m[col * 2 * n + col];
        m[col * 2 * n..(col + 1) * 2 * n]
            .iter_mut()
            .for_each(|v| *v /= p);
        for row in (0..n).filter(|&r| r != col) {
            let f = m[row * 2 * n + col];
            for j in 0..2 * n {
                m[row * 2 * n + j] -= f * m[col * 2 * n + j];
            }
        }
    }
    (0..n * n).map(|i| m[(i / n) * 2 * n + n + i % n]).collect()
}

/// Floats per order in [`vandermonde_table`]: the `(K+1)²` matrix, then the `K+1`
/// [`monomial_bound`]s, `K = max_order`.
pub fn vandermonde_stride(max_order: u32) -> usize {
    (max_order as usize + 1) * (max_order as usize + 2)
}

/// For every even order `k <= max_order`, at `(k/2) · stride`: [`inverse_vandermonde`]`(k)`
/// in f32, then at `+ (max_order+1)²` the bounds `monomial_bound(j, k)`.
pub fn vandermonde_table(max_order: u32) -> Vec<f32> {
    let (stride, square) = (
        vandermonde_stride(max_order),
        (max_order as usize + 1).pow(2),
    );
    let mut table = vec![0.0f32; (max_order as usize / 2 + 1) * stride];
    for k in (0..=max_order).step_by(2) {
        let base = k as usize / 2 * stride;
        for (i, v) in inverse_vandermonde(k).iter().enumerate() {
            table[base + i] = *v as f32;
        }
        for j in 0..=k {
            table[base + square + j as usize] = monomial_bound(j, k);
        }
    }
    table
}

/// `(scale, offset)`: the glyph's radius before clamping is `raw · scale + offset` (the first
/// two entries of `tessera::param::scene`'s radius map, from the same range estimate).
pub fn radius_scale_offset(g: &ShGlyph) -> (f64, f64) {
    let (lo, hi) = g.raw_range();
    match g.normalization() {
        RadiusNormalization::Raw => (1.0, 0.0),
        RadiusNormalization::MinMax if hi - lo <= 1e-12 * hi.abs().max(lo.abs()) => (0.0, 1.0),
        RadiusNormalization::MinMax => (1.0 / (hi - lo), -lo / (hi - lo)),
        RadiusNormalization::MaxAbs if hi.abs().max(lo.abs()) == 0.0 => (0.0, 0.0),
        RadiusNormalization::MaxAbs => (1.0 / hi.abs().max(lo.abs()), 0.0),
        RadiusNormalization::PositiveLobes if hi <= 0.0 => (0.0, 0.0),
        RadiusNormalization::PositiveLobes => (1.0 / hi, 0.0),
    }
}

/// Object-space bounding radius `B`: the clamp of normalised glyphs, else `Σ |c_lm| · max|Y_lm|`
/// with `|Y_l^m| <= sqrt(2 (2l+1) / 4π)` in every basis here.
pub fn glyph_bound(g: &ShGlyph) -> f64 {
    if g.normalization() != RadiusNormalization::Raw {
        return 1.0;
    }
    let lm = sh_degrees_and_orders(g.order()).unwrap_or_default();
    let to_bound =
        |l: u32| (2.0 * (2.0 * f64::from(l) + 1.0) / (4.0 * std::f64::consts::PI)).sqrt();
    lm.iter()
        .zip(g.coefficients())
        .map(|((l, _), c)| c.abs() * to_bound(*l))
        .sum()
}

/// The value and derivative of `poly` (`poly[i]` multiplies `x^i`) at `x`, by Horner.
fn horner(poly: &[f64], x: f64) -> (f64, f64) {
    let (mut v, mut d) = (0.0, 0.0);
    for &c in poly.iter().rev() {
        d = d * x + v;
        v = v * x + c;
    }
    (v, d)
}

/// A root of `poly` in `[a, b]`, where the signs of `poly(a) > 0` and `poly(b) > 0` differ and
/// `poly` is monotonic: Newton steps while they stay in the shrinking bracket and at least halve
/// the step before, bisection otherwise (after Numerical Recipes' `rtsafe`), so roots of high
/// multiplicity, where Newton crawls, are still bracketed to `tol`. Zero counts as negative.
fn bracketed_root(poly: &[f64], mut a: f64, mut b: f64, a_positive: bool, tol: f64) -> f64 {
    let mut x = 0.5 * (a + b);
    let mut step = b - a;
    for _ in 0..100 {
        let (v, d) = horner(poly, x);
        if (v > 0.0) == a_positive {
            a = x;
        } else {
            b = x;
        }
        let newton = x - v / d;
        let step_before = std::mem::replace(&mut step, (newton - x).abs());
        if !(newton > a && newton < b && 2.0 * step <= step_before) {
            step = 0.5 * (b - a);
            x = 0.5 * (a + b);
        } else {
            x = newton;
        }
        if step <= tol {
            break;
        }
    }
    x
}

/// The roots of `poly` (degree `poly.len() - 1`) in `[lo, hi]` where it changes sign, sorted;
/// with `first_only`, just the first. Each derivative `F^(n-m) / (n-m)!` (degree `m`) is
/// monotonic between the roots of the one below it.
pub fn polynomial_roots(poly: &[f64], lo: f64, hi: f64, first_only: bool) -> Vec<f64> {
    let n = poly.len() - 1;
    let tol = 1e-13 * (hi - lo).abs().max(f64::MIN_POSITIVE);
    let mut roots: Vec<f64> = Vec::new();
    for m in 1..=n {
        // Coefficients C(j + n - m, n - m) · F_(j+n-m), the binomial built up along j.
        let mut d = Vec::with_capacity(m + 1);
        let mut binomial = 1.0;
        for j in 0..=m {
            if j > 0 {
                binomial *= (j + n - m) as f64 / j as f64;
            }
            d.push(binomial * poly[j + n - m]);
        }
        let mut next = Vec::with_capacity(m);
        let (mut a, mut fa) = (lo, horner(&d, lo).0);
        for &b in roots.iter().chain(std::iter::once(&hi)) {
            let fb = horner(&d, b).0;
            if (fa > 0.0) != (fb > 0.0) && b > a {
                next.push(bracketed_root(&d, a, b, fa > 0.0, tol));
                if first_only && m == n {
                    break;
                }
            }
            (a, fa) = (b, fb);
        }
        roots = next;
    }
    roots
}

/// First hit of the ray `origin + t · dir` (object space, `dir` of unit length) with the glyph
/// for `t` in `[t_min, t_max]`.
pub fn intersect_glyph(
    g: &ShGlyph,
    origin: DVec3,
    dir: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<f64> {
    let k = g.order() as usize;
    let q = dir.dot(origin);
    let mut c = origin - q * dir;
    c -= c.dot(dir) * dir;
    let h = c.length();
    if h >= glyph_bound(g) {
        return None;
    }
    // A ray through the centre lies in every plane that contains it.
    let c_hat = if h > 0.0 {
        c / h
    } else {
        dir.any_orthonormal_vector()
    };
    let (scale, offset) = radius_scale_offset(g);
    let m = inverse_vandermonde(k as u32);
    let samples: Vec<f64> = (0..=k)
        .map(|i| {
            let (s, cs) = (i as f64 * std::f64::consts::PI / (k + 1) as f64).sin_cos();
            let (theta, phi) = angles(cs * dir + s * c_hat);
            g.raw_radius(theta, phi) * scale + offset
        })
        .collect();
    let a: Vec<f64> = (0..=k)
        .map(|j| (0..=k).map(|i| m[j * (k + 1) + i] * samples[i]).sum())
        .collect();
    // Peters' bound of the glyph in this plane: max |cos^j sin^(k-j)| = sqrt(j^j (k-j)^(k-j) / k^k).
    let plane_bound: f64 = (a.iter().enumerate())
        .map(|(j, aj)| aj.abs() * monomial_bound(j as u32, k as u32) as f64)
        .sum();
    let bound = glyph_bound(g).min(plane_bound);
    if h >= bound {
        return None;
    }
    let l = h.max(bound / BOUND_DIVISOR);
    let eta = h / l;
    let p: Vec<f64> = (a.iter().enumerate())
        .map(|(j, aj)| aj * eta.powi((k - j) as i32) / l)
        .collect();
    let mut poly = vec![0.0; 2 * k + 3];
    for (i, pi) in p.iter().enumerate() {
        for (j, pj) in p.iter().enumerate() {
            poly[i + j] += pi * pj;
        }
    }
    let mut binomial = 1.0;
    for i in 0..=k + 1 {
        poly[2 * i] -= binomial * eta.powi(2 * (k + 1 - i) as i32);
        binomial *= (k + 1 - i) as f64 / (i + 1) as f64;
    }
    let half = (bound * bound - h * h).sqrt();
    let (lo, hi) = ((q + t_min).max(-half) / l, (q + t_max).min(half) / l);
    if lo > hi {
        return None;
    }
    // R along the ray, in the ray coordinate: its sign tells a positive lobe from a negative one.
    let on_lobe =
        |x: f64| g.normalization() != RadiusNormalization::PositiveLobes || horner(&p, x).0 > 0.0;
    let starts_inside = horner(&poly, lo).0 > 0.0 && on_lobe(lo);
    let roots = polynomial_roots(&poly, lo, hi, false);
    let x = match roots.into_iter().find(|&x| on_lobe(x)).as_ref() {
        // Entering the bounding sphere inside the glyph: the upper clamp is the surface there.
        _ if starts_inside && q + t_min <= -half => lo,
        Some(&x) => x,
        // Starting inside, the way out may be through the clamp.
        None if starts_inside && q + t_max >= half => hi,
        None => return None,
    };
    Some(x * l - q)
}

/// `max |cos^j α sin^(k-j) α|` over `α` (0^0 = 1), in f32 as the shaders compute it.
pub fn monomial_bound(j: u32, k: u32) -> f32 {
    if j == 0 || j == k {
        return 1.0;
    }
    let (j, k) = (f64::from(j), f64::from(k));
    ((j / k).powf(j) * ((k - j) / k).powf(k - j)).sqrt() as f32
}

/// `(θ, φ)` of a non-zero direction, as `super::sh::direction_to_angles` without its checks.
fn angles(d: DVec3) -> (f64, f64) {
    (d.x.hypot(d.y).atan2(d.z), d.y.atan2(d.x))
}

/// A uniform grid over bounding spheres: cell `(x, y, z)` lists the spheres whose bounding
/// boxes overlap it, in `items[cell_start[i]..cell_start[i + 1]]`, `i = x + nx (y + ny z)`.
#[derive(Debug, Clone, PartialEq)]
pub struct GlyphGrid {
    pub lo: Vec3,
    pub cell: Vec3,
    pub dims: [u32; 3],
    pub cell_start: Vec<u32>,
    pub items: Vec<u32>,
}

impl GlyphGrid {
    /// Cells about `cell_scale` times the median sphere diameter on a side, at most
    /// `MAX_CELLS_PER_GLYPH` per sphere and 1024 per axis.
    pub fn build(spheres: &[(Vec3, f32)], cell_scale: f32) -> Result<GlyphGrid> {
        let finite = spheres
            .iter()
            .all(|(c, r)| c.is_finite() && r.is_finite() && *r >= 0.0);
        if spheres.is_empty() || !finite || !(cell_scale > 0.0 && cell_scale.is_finite()) {
            return Err(DataError::Invalid(format!(
                "a glyph grid needs finite spheres (got {}) and a positive cell scale (got {cell_scale})",
                spheres.len()
            )));
        }
        let lo = spheres
            .iter()
            .fold(Vec3::INFINITY, |a, (c, r)| a.min(*c - *r));
        let hi = spheres
            .iter()
            .fold(Vec3::NEG_INFINITY, |a, (c, r)| a.max(*c + *r));
        let extent = (hi - lo).max(Vec3::splat(1e-6 * (hi - lo).max_element().max(1e-6)));
        let mut radii: Vec<f32> = spheres.iter().map(|s| s.1).collect();
        radii.sort_by(f32::total_cmp);
        let mut edge =
            (2.0 * radii[radii.len() / 2] * cell_scale).max(extent.max_element() / 1024.0);
        let cap = (MAX_CELLS_PER_GLYPH * spheres.len()).max(64) as f64;
        let dims = loop {
            let d = (extent / edge).ceil().clamp(Vec3::ONE, Vec3::splat(1024.0));
            if f64::from(d.x) * f64::from(d.y) * f64::from(d.z) <= cap {
                break d.as_uvec3();
            }
            edge *= 1.25;
        };
        let cell = extent / dims.as_vec3();
        let range = |c: Vec3, r: f32| {
            let a = ((c - r - lo) / cell)
                .floor()
                .as_ivec3()
                .clamp(glam::IVec3::ZERO, dims.as_ivec3() - 1);
            let b = ((c + r - lo) / cell)
                .floor()
                .as_ivec3()
                .clamp(glam::IVec3::ZERO, dims.as_ivec3() - 1);
            (a.as_uvec3(), b.as_uvec3())
        };
        let index = |x: u32, y: u32, z: u32| (x + dims.x * (y + dims.y * z)) as usize;
        let cells = (dims.x * dims.y * dims.z) as usize;
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); cells];
        for (i, &(c, r)) in spheres.iter().enumerate() {
            let (a, b) = range(c, r);
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        lists[index(x, y, z)].push(i as u32);
                    }
                }
            }
        }
        let total: usize = lists.iter().map(Vec::len).sum();
        if total > u32::MAX as usize / 2 {
            return Err(DataError::Invalid(format!(
                "a glyph grid of {total} entries is too large"
            )));
        }
        let mut cell_start = Vec::with_capacity(cells + 1);
        cell_start.push(0);
        for l in &lists {
            cell_start.push(cell_start.last().copied().unwrap_or(0) + l.len() as u32);
        }
        Ok(GlyphGrid {
            lo,
            cell,
            dims: dims.to_array(),
            cell_start,
            items: lists.concat(),
        })
    }

    /// Visits the cells along `origin + t · dir` from `t = 0` in order (Amanatides & Woo), each
    /// with its spheres and the `t` where the ray leaves it, until `visit` returns true.
    pub fn walk(&self, origin: Vec3, dir: Vec3, mut visit: impl FnMut(&[u32], f32) -> bool) {
        // Axis-parallel rays: a tiny component of the same sign keeps every `t` finite.
        let tiny = Vec3::splat(1e-20).copysign(dir);
        let dir = Vec3::select(dir.abs().cmplt(Vec3::splat(1e-20)), tiny, dir);
        let inv = dir.recip();
        let dims = glam::UVec3::from(self.dims).as_ivec3();
        let hi = self.lo + self.cell * dims.as_vec3();
        let (t0, t1) = ((self.lo - origin) * inv, (hi - origin) * inv);
        let enter = t0.min(t1).max_element().max(0.0);
        let exit = t0.max(t1).min_element();
        if enter > exit {
            return;
        }
        let p = origin + enter * dir;
        let mut cell = ((p - self.lo) / self.cell)
            .floor()
            .as_ivec3()
            .clamp(glam::IVec3::ZERO, dims - 1);
        let step = dir.signum().as_ivec3();
        let boundary = self.lo + (cell + step.max(glam::IVec3::ZERO)).as_vec3() * self.cell;
        let mut next = (boundary - origin) * inv;
        let delta = self.cell * inv.abs();
        loop {
            let i = (cell.x + dims.x * (cell.y + dims.y * cell.z)) as usize;
            let items = &self.items[self.cell_start[i] as usize..self.cell_start[i + 1] as usize];
            let axis = next.min_position();
            if visit(items, next[axis].min(exit)) || next[axis] >= exit {
                return;
            }
            cell[axis] += step[axis];
            if cell[axis] < 0 || cell[axis] >= dims[axis] {
                return;
            }
            next[axis] += delta[axis];
        }
    }
}

/// The first SH glyph that the world ray `origin + t · dir` (`dir` of unit length) hits, with
/// its `t`, through `grid` (built over the scene's bounding spheres); other objects are not
/// seen.
pub fn trace_glyphs(
    objects: &[ReferenceObject],
    grid: &GlyphGrid,
    origin: Vec3,
    dir: Vec3,
) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    grid.walk(origin, dir, |items, exit| {
        for &i in items {
            let object = &objects[i as usize];
            let ParamFunction::ShGlyph(g) = object.function else {
                continue;
            };
            let (o, d, scale) = to_object(object.object_to_world, origin, dir);
            let limit = best.map_or(f64::INFINITY, |b| b.1);
            if let Some(t) = intersect_glyph(g, o, d, 0.0, limit * scale) {
                best = Some((i, t / scale));
            }
        }
        best.is_some_and(|b| b.1 <= f64::from(exit))
    });
    best
}

/// The ray in object space: origin, unit direction and object units per world unit along it.
pub fn to_object(object_to_world: Mat4, origin: Vec3, dir: Vec3) -> (DVec3, DVec3, f64) {
    let inverse = object_to_world.as_dmat4().inverse();
    let o = inverse.transform_point3(origin.as_dvec3());
    let d = inverse.transform_vector3(dir.as_dvec3());
    (o, d / d.length(), d.length())
}

#[cfg(test)]
#[path = "raytrace_tests.rs"]
mod tests;
