use super::*;

#[test]
fn pcg3d_follows_its_definition() {
    // (0, 0, 0) through the definition step by step.
    let a = 1_013_904_223u32;
    let x = a.wrapping_add(a.wrapping_mul(a));
    let y = a.wrapping_add(a.wrapping_mul(x));
    let z = a.wrapping_add(x.wrapping_mul(y));
    let [x, y, z] = [x ^ (x >> 16), y ^ (y >> 16), z ^ (z >> 16)];
    let x2 = x.wrapping_add(y.wrapping_mul(z));
    let y2 = y.wrapping_add(z.wrapping_mul(x2));
    let z2 = z.wrapping_add(x2.wrapping_mul(y2));
    assert_eq!(pcg3d([0, 0, 0]), [x2, y2, z2]);
    assert_ne!(pcg3d([1, 2, 3]), pcg3d([1, 2, 4]));
}

#[test]
fn noise_is_continuous_and_bounded() {
    let mut previous = value_noise(DVec3::new(-2.0, 0.3, 0.7), 5);
    for i in 1..2000 {
        let p = DVec3::new(-2.0 + i as f64 * 0.002, 0.3, 0.7);
        let v = value_noise(p, 5);
        assert!((0.0..1.0).contains(&v));
        assert!((v - previous).abs() < 0.01, "jump at {p}");
        previous = v;
    }
    for i in 0..500 {
        let f = fbm(DVec3::splat(i as f64 * 0.37), 9);
        assert!(f.abs() < 0.875);
    }
    assert_ne!(
        value_noise(DVec3::splat(0.5), 1),
        value_noise(DVec3::splat(0.5), 2)
    );
}

#[test]
fn asteroids_stay_inside_their_tets() {
    let mesh = asteroid_field(20, 7);
    let mut checked = mesh.clone();
    let report = checked.validate("field").unwrap();
    assert_eq!(report.degenerate, 0);
    let spheres = asteroid_spheres(&mesh);
    let frame = MeshFrame::of(&mesh);
    for (t, s) in spheres.iter().enumerate() {
        let c = world_tet(&mesh, &frame, t);
        let centre = DVec3::new(s[0].into(), s[1].into(), s[2].into());
        // Distance from the centre to each face plane is the inradius.
        for &(a, b, d) in &[(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)] {
            let n = (c[b] - c[a]).cross(c[d] - c[a]).normalize();
            let to_face = n.dot(centre - c[a]).abs();
            let largest = f64::from(s[3]) * (1.0 + AMPLITUDE * 0.875);
            assert!(largest < to_face, "asteroid {t} pokes out of its tet");
        }
    }
}

#[test]
fn tracing_hits_the_surface_from_outside_and_misses_beside() {
    let sphere = [0.0, 0.0, 0.0, 0.1];
    let eye = DVec3::new(0.0, 0.0, -1.0);
    let t = trace(eye, DVec3::Z, 0.0, 2.0, sphere, 3).expect("a central ray hits");
    let d = asteroid_distance(eye + DVec3::Z * t, sphere, 3);
    assert!(d.abs() < EPSILON * 0.1 + 1e-12, "hit at distance {d}");
    assert!((0.85..0.95).contains(&t));
    assert!(trace(eye + DVec3::X * 0.5, DVec3::Z, 0.0, 2.0, sphere, 3).is_none());
    // The interval ends before the surface: no hit.
    assert!(trace(eye, DVec3::Z, 0.0, 0.8, sphere, 3).is_none());
}

#[test]
fn reference_image_shows_asteroids() {
    let mesh = asteroid_field(30, 1);
    let spheres = asteroid_spheres(&mesh);
    let camera = OrbitCamera {
        distance: 1.6,
        ..OrbitCamera::default()
    };
    let (image, hits) = render_reference(&mesh, &spheres, &camera, (64, 48), [0.0; 3]);
    let hit_count = hits.iter().filter(|&&h| h).count();
    assert!(
        hit_count > 60 && hit_count < 64 * 48 / 2,
        "{hit_count} pixels hit"
    );
    let shades: std::collections::HashSet<u32> = image.pixels.iter().copied().collect();
    assert!(shades.len() > 30);
}
