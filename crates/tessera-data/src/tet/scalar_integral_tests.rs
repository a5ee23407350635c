use super::*;
use crate::tet::optical::optical_depth;
use crate::tet::procedural::box_mesh;
use crate::transfer::TransferFunction;

fn camera() -> OrbitCamera {
    OrbitCamera {
        azimuth_deg: 30.0,
        elevation_deg: 20.0,
        distance: 2.4,
        ..OrbitCamera::default()
    }
}

#[test]
fn a_constant_field_integrates_to_length_times_the_table() {
    let mut mesh = box_mesh(3);
    mesh.absorption = None;
    mesh.scalars = Some(vec![0.25; mesh.vertices.len()]);
    let tf = TransferFunction::preset("cool-warm").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Absorption, 1.5, 64);
    let normalized = normalized_scalars(&mesh, Some((0.0, 1.0)), "box").unwrap();
    let got = integrate_scalar(
        &mesh,
        &normalized,
        &camera(),
        (40, 30),
        &table,
        ScalarMode::Absorption,
    );
    let lengths = optical_depth(&mesh, &camera(), 40, 30);
    let rate = table.value(0.25);
    let mut covered = 0;
    for (g, l) in got.iter().zip(&lengths) {
        for c in 0..3 {
            let expected = l[c] as f64 * rate[c];
            assert!((g[c] as f64 - expected).abs() < 1e-5 * (1.0 + expected));
        }
        covered += usize::from(l[0] > 0.0);
    }
    assert!(covered > 200);
}

#[test]
fn the_maximum_of_a_linear_field_is_where_the_ray_meets_it_highest() {
    // Scalar = x in mesh coordinates; the box spans [0, 1] in x, so the mesh's range is [0, 1].
    let mut mesh = box_mesh(2);
    mesh.scalars = Some(mesh.vertices.iter().map(|v| v[0]).collect());
    let normalized = normalized_scalars(&mesh, None, "box").unwrap();
    let tf = TransferFunction::preset("grey").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Maximum, 1.0, 16);
    // Looking down -z from +z (azimuth 0, elevation 90 would be singular; use a front view).
    let front = OrbitCamera {
        distance: 3.0,
        ..OrbitCamera::default()
    };
    let maxima = integrate_scalar(
        &mesh,
        &normalized,
        &front,
        (32, 32),
        &table,
        ScalarMode::Maximum,
    );
    let hit: Vec<&[f32; 3]> = maxima.iter().filter(|m| m[1] > 0.0).collect();
    assert!(hit.len() > 50);
    assert!(hit.iter().all(|m| (0.0..=1.0).contains(&m[0])));
    let spread = hit.iter().map(|m| m[0]).fold(0.0f32, f32::max)
        - hit.iter().map(|m| m[0]).fold(1.0f32, f32::min);
    assert!(spread > 0.3, "maxima vary across the image ({spread})");
}

#[test]
fn a_mesh_without_scalars_is_refused_by_name() {
    let mut mesh = box_mesh(1);
    mesh.scalars = None;
    let err = normalized_scalars(&mesh, None, "cube.vtu")
        .unwrap_err()
        .to_string();
    assert!(err.contains("cube.vtu") && err.contains("scalars"), "{err}");
}

#[test]
fn a_stretchs_ends_carry_the_linear_fields_values() {
    // A field linear in space is reproduced exactly by every tet's interpolation.
    let field = |p: DVec3| 0.3 + 0.2 * p.x - 0.1 * p.y + 0.25 * p.z;
    let mut mesh = box_mesh(2);
    let frame = MeshFrame::of(&mesh);
    let world = |v: &[f32; 3]| frame.to_world(glam::Vec3::from(*v)).as_dvec3();
    mesh.scalars = Some(
        mesh.vertices
            .iter()
            .map(|v| field(world(v)) as f32)
            .collect(),
    );
    let normalized = mesh.scalars.clone().unwrap();
    let linears = tet_linears(&mesh, &normalized);
    let stretch = RayStretch {
        eye: DVec3::new(-1.0, 0.1, 0.05),
        dir: DVec3::new(1.0, 0.2, -0.1).normalize(),
        enter: 0.7,
        exit: 0.9,
    };
    for linear in &linears {
        let (s_in, s_out) = linear.at_ends(&stretch);
        let want_in = field(stretch.eye + stretch.dir * stretch.enter);
        let want_out = field(stretch.eye + stretch.dir * stretch.exit);
        assert!((s_in - want_in).abs() < 1e-6, "{s_in} vs {want_in}");
        assert!((s_out - want_out).abs() < 1e-6, "{s_out} vs {want_out}");
    }
}
