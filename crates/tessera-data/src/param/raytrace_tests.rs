//! Tests of `raytrace`: the polynomial method against marching the glyphs' radius functions in
//! f64, the inverse Vandermonde matrices, and grid traversal against testing every glyph.
use super::*;
use crate::param::sh::sh_coefficient_count;
use crate::param::ShBasis;
use tessera_test::Rng;

/// Three numbers uniform in [-1, 1).
fn random_vec(rng: &mut Rng) -> DVec3 {
    DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
}

fn glyph(rng: &mut Rng, order: u32, norm: RadiusNormalization) -> ShGlyph {
    let n = sh_coefficient_count(order).unwrap();
    let c = (0..n)
        .map(|j| {
            if j == 0 {
                2.0
            } else {
                0.4 * rng.range(-1.0, 1.0)
            }
        })
        .collect();
    ShGlyph::new(ShBasis::Descoteaux07 { legacy: false }, order, c, norm).unwrap()
}

/// A glyph whose radius is negative in some directions: a small constant term.
fn negative_lobed(rng: &mut Rng, order: u32, norm: RadiusNormalization) -> ShGlyph {
    let n = sh_coefficient_count(order).unwrap();
    let c = (0..n)
        .map(|j| {
            if j == 0 {
                0.3
            } else {
                rng.range(-1.0, 1.0) - 0.3
            }
        })
        .collect();
    ShGlyph::new(ShBasis::Descoteaux07 { legacy: false }, order, c, norm).unwrap()
}

/// The drawn radius of the raw value `raw`: `max(v, 0)` for positive lobes, else `|v|` (what
/// the squared implicit form describes), `v = raw · scale + offset`.
fn drawn_radius(g: &ShGlyph, raw: f64) -> f64 {
    let (scale, offset) = radius_scale_offset(g);
    let v = raw * scale + offset;
    if g.normalization() == RadiusNormalization::PositiveLobes {
        v.max(0.0)
    } else {
        v.abs()
    }
}

/// The first `t >= 0` where `|p| < min(|r(p̂)|, B)` (the surface the polynomial describes)
/// changes from its value at the start, by marching 4000 steps over the bounding sphere
/// and bisecting.
fn march(g: &ShGlyph, o: DVec3, d: DVec3) -> Option<f64> {
    let bound = glyph_bound(g);
    let inside = |t: f64| {
        let p = o + t * d;
        let (theta, phi) = angles(p);
        p.length() < drawn_radius(g, g.raw_radius(theta, phi)).min(bound)
    };
    let (q, h2) = (d.dot(o), (o - d.dot(o) * d).length_squared());
    let half = (bound * bound - h2).max(0.0).sqrt();
    let (t0, t1) = ((-q - half).max(0.0), -q + half);
    let start = inside(t0);
    if start && t0 > 0.0 {
        return Some(t0); // entering the bounding sphere inside the glyph
    }
    let mut prev = t0;
    for i in 1..=4000 {
        let t = t0 + (t1 - t0) * f64::from(i) / 4000.0;
        if inside(t) != start {
            let (mut a, mut b) = (prev, t);
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if inside(m) == start {
                    a = m
                } else {
                    b = m
                }
            }
            return Some(b);
        }
        prev = t;
    }
    start.then_some(t1)
}

#[test]
fn inverse_vandermonde_recovers_homogeneous_polynomials() {
    let mut rng = Rng::new(7);
    for k in (0..=MAX_RAYTRACE_ORDER).step_by(2) {
        let n = k as usize + 1;
        let a: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
        let r: Vec<f64> = (0..n)
            .map(|i| {
                let (s, c) = (i as f64 * std::f64::consts::PI / n as f64).sin_cos();
                (0..n)
                    .map(|j| a[j] * c.powi(j as i32) * s.powi((n - 1 - j) as i32))
                    .sum()
            })
            .collect();
        let m = inverse_vandermonde(k);
        for j in 0..n {
            let got: f64 = (0..n).map(|i| m[j * n + i] * r[i]).sum();
            assert!(
                (got - a[j]).abs() < 1e-9,
                "order {k}: a_{j} = {got}, not {}",
                a[j]
            );
        }
    }
    let table = vandermonde_table(4);
    assert_eq!(table.len(), 3 * 30);
    assert_eq!(table[30 + 2 * 3 + 2], inverse_vandermonde(2)[8] as f32);
    assert_eq!(table[30 + 25..30 + 28], [1.0, 0.5, 1.0]);
}

/// The polynomial's first root against marching the glyph's own radius function, for every
/// order, each normalisation, rays through the centre and rays starting inside.
#[test]
fn first_roots_match_marching() {
    let mut rng = Rng::new(11);
    let (mut hits, mut mismatched, mut worst) = (0, 0, 0.0f64);
    for k in (0..=MAX_RAYTRACE_ORDER).step_by(2) {
        for norm in [
            RadiusNormalization::MinMax,
            RadiusNormalization::MaxAbs,
            RadiusNormalization::Raw,
            RadiusNormalization::PositiveLobes,
        ] {
            let g = if norm == RadiusNormalization::PositiveLobes {
                negative_lobed(&mut rng, k, norm)
            } else {
                glyph(&mut rng, k, norm)
            };
            let b = glyph_bound(&g);
            for ray in 0..40 {
                let o = random_vec(&mut rng).normalize() * 3.0 * b;
                let target = if ray == 0 {
                    DVec3::ZERO
                } else {
                    random_vec(&mut rng) * 0.6 * b
                };
                let d = (target - o).normalize();
                let got = intersect_glyph(&g, o, d, 0.0, f64::INFINITY);
                match (got, march(&g, o, d)) {
                    (Some(t), Some(m)) => {
                        hits += 1;
                        worst = worst.max((t - m).abs() / b);
                        assert!((t - m).abs() <= 1e-7 * b, "order {k} {norm:?}: {t} vs {m}");
                    }
                    (None, None) => {}
                    _ => mismatched += 1,
                }
            }
            // From inside outwards: the first root is the way out. The start is halfway
            // out along the longest of a few directions: near the centre of a glyph much
            // smaller than its coefficients, `F` cancels to noise (cameras are not there).
            let radius = |d: DVec3| {
                let (theta, phi) = angles(d);
                drawn_radius(&g, g.raw_radius(theta, phi)).min(b)
            };
            let start = (0..8)
                .map(|_| random_vec(&mut rng).normalize())
                .max_by(|x, y| radius(*x).total_cmp(&radius(*y)))
                .unwrap();
            let o = start * 0.5 * radius(start);
            let d = random_vec(&mut rng).normalize();
            let t = intersect_glyph(&g, o, d, 0.0, f64::INFINITY);
            let m = march(&g, o, d);
            assert!(
                t.zip(m).is_some_and(|(t, m)| (t - m).abs() < 1e-7 * b),
                "order {k} {norm:?} from inside: {t:?} vs {m:?}, |o| {}, B {b}",
                o.length()
            );
        }
    }
    eprintln!("{hits} hits, {mismatched} grazing mismatches, worst |Δt| / B = {worst:.1e}");
    assert!(
        hits > 600 && mismatched * 100 <= hits,
        "{hits} hits, {mismatched} mismatched"
    );
}

fn field(nx: u32, ny: u32) -> Vec<ParamFunction> {
    let mut rng = Rng::new(3);
    (0..nx * ny)
        .map(|i| ParamFunction::ShGlyph(glyph(&mut rng, 2 * (i % 7), RadiusNormalization::MinMax)))
        .collect()
}

/// Traversal through a fine grid finds what testing every glyph finds (a single cell).
#[test]
fn grid_walk_matches_testing_every_glyph() {
    let (nx, ny) = (6u32, 5u32);
    let functions = field(nx, ny);
    let objects: Vec<ReferenceObject> = functions
        .iter()
        .enumerate()
        .map(|(i, f)| ReferenceObject {
            function: f,
            object_to_world: Mat4::from_scale_rotation_translation(
                Vec3::splat(0.45),
                glam::Quat::from_rotation_z(i as f32),
                Vec3::new((i as u32 % nx) as f32, (i as u32 / nx) as f32, 0.0),
            ),
            colour: Vec3::ONE,
        })
        .collect();
    let spheres: Vec<(Vec3, f32)> = objects
        .iter()
        .map(|o| (o.object_to_world.w_axis.truncate(), 0.45 * 3f32.sqrt()))
        .collect();
    let fine = GlyphGrid::build(&spheres, 0.5).unwrap();
    let single = GlyphGrid::build(&spheres, 1e6).unwrap();
    assert!(fine.dims.iter().product::<u32>() >= 30, "{:?}", fine.dims);
    assert_eq!(single.dims, [1, 1, 1]);
    let mut rng = Rng::new(5);
    let mut hits = 0;
    for _ in 0..300 {
        let eye =
            Vec3::new(2.5, 2.0, 6.0) + random_vec(&mut rng).as_vec3() * Vec3::new(4.0, 4.0, 1.0);
        let target =
            Vec3::new(2.5, 2.0, 0.0) + random_vec(&mut rng).as_vec3() * Vec3::new(3.0, 2.5, 0.3);
        let dir = (target - eye).normalize();
        let a = trace_glyphs(&objects, &fine, eye, dir);
        let b = trace_glyphs(&objects, &single, eye, dir);
        hits += usize::from(a.is_some());
        assert_eq!(a.map(|h| h.0), b.map(|h| h.0));
        assert!(a.zip(b).is_none_or(|(a, b)| (a.1 - b.1).abs() < 1e-9));
    }
    assert!(hits > 100, "{hits} hits");
    assert!(GlyphGrid::build(&[], 1.0).is_err());
    assert!(GlyphGrid::build(&spheres, 0.0).is_err());
    assert!(GlyphGrid::build(&[(Vec3::NAN, 1.0)], 1.0).is_err());
}
