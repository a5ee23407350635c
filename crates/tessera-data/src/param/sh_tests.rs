//! Tests of `sh`.
use super::*;

const ALL_BASES: [ShBasis; 4] = [
    ShBasis::Descoteaux07 { legacy: true },
    ShBasis::Descoteaux07 { legacy: false },
    ShBasis::Tournier07 { legacy: true },
    ShBasis::Tournier07 { legacy: false },
];

/// Gauss–Legendre nodes and weights on [-1, 1] (Newton on P_n, Golub-free and plenty for n ≤ 64).
pub(crate) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let k = k as f64;
                let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// Gram matrix `∫ Y_i Y_j dΩ` by Gauss–Legendre in cos θ × uniform φ, exact for these degrees.
fn gram(basis: ShBasis, order: u32) -> Vec<Vec<f64>> {
    let n = sh_coefficient_count(order).unwrap();
    let nodes = gauss_legendre(order as usize + 8);
    let n_phi = 2 * order as usize + 8;
    let mut g = vec![vec![0.0; n]; n];
    let mut y = vec![0.0; n];
    for &(x, w) in &nodes {
        for k in 0..n_phi {
            let phi = 2.0 * PI * k as f64 / n_phi as f64;
            sh_basis_into(basis, order, x.acos(), phi, &mut y).unwrap();
            let wk = w * 2.0 * PI / n_phi as f64;
            for i in 0..n {
                for j in 0..n {
                    g[i][j] += wk * y[i] * y[j];
                }
            }
        }
    }
    g
}

fn assert_gram(basis: ShBasis, order: u32, tol: f64) {
    let g = gram(basis, order);
    let lm = sh_degrees_and_orders(order).unwrap();
    for (i, row) in g.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            let expected = if i != j {
                0.0
            } else if basis.is_orthonormal() || lm[i].1 == 0 {
                1.0
            } else {
                0.5
            };
            assert!(
                (v - expected).abs() < tol,
                "{basis:?} order {order}: G[{i}][{j}] = {v}, expected {expected}"
            );
        }
    }
}

#[test]
fn coefficient_counts_follow_the_formula() {
    for (order, count) in [
        (0, 1),
        (2, 6),
        (4, 15),
        (6, 28),
        (8, 45),
        (10, 66),
        (12, 91),
        (14, 120),
        (16, 153),
    ] {
        assert_eq!(sh_coefficient_count(order).unwrap(), count);
        assert_eq!(sh_degrees_and_orders(order).unwrap().len(), count);
    }
    // DIPY's sph_harm_ind_list order: l = 0, 2, 4 and m = -l..=l within each.
    let lm = sh_degrees_and_orders(4).unwrap();
    assert_eq!(
        &lm[..7],
        &[(0, 0), (2, -2), (2, -1), (2, 0), (2, 1), (2, 2), (4, -4)]
    );
    for (j, &(l, m)) in lm.iter().enumerate() {
        assert_eq!(sh_index(l, m).unwrap(), j);
    }
}

#[test]
fn invalid_orders_and_inputs_are_errors() {
    for order in [1, 3, 7, 15, MAX_SH_ORDER + 2] {
        assert!(sh_coefficient_count(order).is_err(), "{order}");
        assert!(sh_basis(ALL_BASES[0], order, 0.3, 0.2).is_err(), "{order}");
    }
    assert!(sh_index(3, 0).is_err());
    assert!(sh_index(2, 3).is_err());
    assert!(sh_basis(ALL_BASES[0], 4, f64::NAN, 0.0).is_err());
    assert!(sh_basis(ALL_BASES[0], 4, 0.0, f64::INFINITY).is_err());
    assert!(sh_basis_dir(ALL_BASES[0], 4, DVec3::ZERO).is_err());
    assert!(sh_real(ALL_BASES[0], 2, 3, 0.1, 0.1).is_err());
    assert!(sh_evaluate(ALL_BASES[0], 2, &[1.0; 5], 0.1, 0.1).is_err());
    assert!(sh_evaluate(
        ALL_BASES[0],
        2,
        &[1.0, 0.0, f64::NAN, 0.0, 0.0, 0.0],
        0.1,
        0.1
    )
    .is_err());
    let mut short = [0.0; 5];
    assert!(sh_basis_into(ALL_BASES[0], 2, 0.1, 0.1, &mut short).is_err());
}

#[test]
fn y00_is_one_over_two_sqrt_pi() {
    let expected = 1.0 / (2.0 * PI.sqrt());
    for basis in ALL_BASES {
        for (theta, phi) in [(0.0, 0.0), (1.0, 2.0), (PI, 5.0), (0.3, 6.1)] {
            let y = sh_basis(basis, 2, theta, phi).unwrap();
            assert!((y[0] - expected).abs() < 1e-15, "{basis:?}");
        }
    }
}

/// The l = 2 functions written out in Cartesian form (x, y, z of the unit direction).
#[test]
fn degree_two_matches_hand_derived_values() {
    let (theta, phi) = (0.7_f64, 2.3_f64);
    let (x, y, z) = (
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    );
    let c0 = 0.25 * (5.0 / PI).sqrt(); // K_2^0 = c0 (3z² - 1)
    let c1 = 0.5 * (15.0 / PI).sqrt(); // 1.0925484…: √2 |K_2^1| / (sin θ cos θ)
    let c2 = 0.25 * (15.0 / PI).sqrt(); // 0.5462742…: √2 K_2^2 / sin²θ
    let y20 = c0 * (3.0 * z * z - 1.0);

    // descoteaux07 legacy: m<0 → √2 Re(Y^{|m|}), m>0 → √2 Im(Y^m); K_2^1 carries the (-1) phase.
    let legacy = [
        c2 * (x * x - y * y),
        -c1 * x * z,
        y20,
        -c1 * y * z,
        c2 * 2.0 * x * y,
    ];
    let got = sh_basis(ShBasis::Descoteaux07 { legacy: true }, 2, theta, phi).unwrap();
    close(&got[1..], &legacy);
    // Non-legacy flips the odd negative order only (m = -1).
    let paper = [legacy[0], c1 * x * z, y20, legacy[3], legacy[4]];
    close(
        &sh_basis(ShBasis::Descoteaux07 { legacy: false }, 2, theta, phi).unwrap()[1..],
        &paper,
    );
    // tournier07 (MRtrix3): m<0 → √2 Im(Y^{|m|}), m>0 → √2 Re(Y^m).
    let mrtrix3 = [
        c2 * 2.0 * x * y,
        -c1 * y * z,
        y20,
        -c1 * x * z,
        c2 * (x * x - y * y),
    ];
    close(
        &sh_basis(ShBasis::Tournier07 { legacy: false }, 2, theta, phi).unwrap()[1..],
        &mrtrix3,
    );
    let mrtrix02: Vec<f64> = mrtrix3
        .iter()
        .enumerate()
        .map(|(i, v)| if i == 2 { *v } else { v / SQRT_2 })
        .collect();
    close(
        &sh_basis(ShBasis::Tournier07 { legacy: true }, 2, theta, phi).unwrap()[1..],
        &mrtrix02,
    );
    // The constants Peters et al. hard-code for their glyph shader (used by paper E's code).
    assert!((c1 - 1.092548431).abs() < 1e-9 && (c2 - 0.546274215).abs() < 1e-9);
}

fn close(got: &[f64], expected: &[f64]) {
    assert_eq!(got.len(), expected.len());
    for (i, (g, e)) in got.iter().zip(expected).enumerate() {
        assert!((g - e).abs() < 1e-14, "index {i}: {g} vs {e}");
    }
}

#[test]
fn legacy_differs_exactly_as_documented() {
    let lm = sh_degrees_and_orders(16).unwrap();
    for (theta, phi) in [(0.4, 1.1), (2.0, 4.0), (1.3, 0.2)] {
        let d_leg = sh_basis(ShBasis::Descoteaux07 { legacy: true }, 16, theta, phi).unwrap();
        let d_new = sh_basis(ShBasis::Descoteaux07 { legacy: false }, 16, theta, phi).unwrap();
        let t_leg = sh_basis(ShBasis::Tournier07 { legacy: true }, 16, theta, phi).unwrap();
        let t_new = sh_basis(ShBasis::Tournier07 { legacy: false }, 16, theta, phi).unwrap();
        for (j, &(_, m)) in lm.iter().enumerate() {
            let sign = if m < 0 && m % 2 != 0 { -1.0 } else { 1.0 };
            assert_eq!(d_new[j], sign * d_leg[j], "descoteaux m = {m}");
            let scale = if m == 0 { 1.0 } else { SQRT_2 };
            assert!(
                (t_new[j] - scale * t_leg[j]).abs() < 1e-15,
                "tournier m = {m}"
            );
        }
    }
}

#[test]
fn bases_are_orthonormal_at_order_8() {
    for basis in ALL_BASES {
        assert_gram(basis, 8, 1e-10);
    }
}

#[test]
fn order_16_is_orthonormal_too() {
    assert_gram(ShBasis::Descoteaux07 { legacy: true }, 16, 1e-9);
    assert_gram(ShBasis::Tournier07 { legacy: false }, 16, 1e-9);
}

/// Addition theorem: Σ_m Y_lm² = (2l+1)/4π for an orthonormal basis, here for large and odd l
/// where factorial-based formulas would have overflowed.
#[test]
fn high_degrees_stay_accurate() {
    for l in [17_u32, 60, 101, 160] {
        for (theta, phi) in [(0.01, 0.3), (1.2, 2.0), (3.1, 5.5)] {
            let sum: f64 = (-(l as i32)..=l as i32)
                .map(|m| {
                    sh_real(ShBasis::Descoteaux07 { legacy: false }, l, m, theta, phi)
                        .unwrap()
                        .powi(2)
                })
                .sum();
            let expected = f64::from(2 * l + 1) / (4.0 * PI);
            assert!(
                (sum - expected).abs() < 1e-10 * expected,
                "l = {l}: {sum} vs {expected}"
            );
        }
    }
}

#[test]
fn single_functions_match_the_basis_vector() {
    for basis in ALL_BASES {
        let all = sh_basis(basis, 6, 1.1, 4.2).unwrap();
        for (j, (l, m)) in sh_degrees_and_orders(6).unwrap().into_iter().enumerate() {
            let single = sh_real(basis, l, m, 1.1, 4.2).unwrap();
            assert!((single - all[j]).abs() < 1e-15, "{basis:?} l = {l} m = {m}");
        }
    }
}

#[test]
fn directions_and_angles_agree() {
    let dir = DVec3::new(0.3, -0.5, 0.8);
    let (theta, phi) = direction_to_angles(dir).unwrap();
    let unit = dir.normalize();
    let back = DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    );
    assert!((back - unit).length() < 1e-15);
    assert!((0.0..2.0 * PI).contains(&phi));
    let basis = ShBasis::Tournier07 { legacy: false };
    let scaled = sh_basis_dir(basis, 8, dir * 7.0).unwrap();
    for (a, b) in scaled.iter().zip(sh_basis(basis, 8, theta, phi).unwrap()) {
        assert!((a - b).abs() < 1e-14);
    }
    // Poles: any azimuth, only the m = 0 functions are non-zero.
    let north = sh_basis_dir(basis, 4, DVec3::Z).unwrap();
    for (j, (_, m)) in sh_degrees_and_orders(4).unwrap().into_iter().enumerate() {
        if m != 0 {
            assert_eq!(north[j], 0.0);
        }
    }
}

#[test]
fn evaluate_is_the_dot_product() {
    let basis = ShBasis::Descoteaux07 { legacy: true };
    let coeffs: Vec<f64> = (0..45).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.1).collect();
    let y = sh_basis(basis, 8, 0.9, 1.9).unwrap();
    let dot: f64 = coeffs.iter().zip(&y).map(|(c, y)| c * y).sum();
    let r = sh_evaluate(basis, 8, &coeffs, 0.9, 1.9).unwrap();
    assert!((r - dot).abs() < 1e-14);
    let dir = DVec3::new(
        0.9_f64.sin() * 1.9_f64.cos(),
        0.9_f64.sin() * 1.9_f64.sin(),
        0.9_f64.cos(),
    );
    assert!((sh_evaluate_dir(basis, 8, &coeffs, dir * 3.0).unwrap() - dot).abs() < 1e-13);
    assert!(sh_evaluate_dir(basis, 8, &coeffs, DVec3::ZERO).is_err());
}
