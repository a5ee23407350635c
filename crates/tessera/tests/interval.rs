//! Interval shading (paper A) against the CPU reference that integrates exact ray–tet path
//! lengths per pixel. Pixels within a pixel of a projected tet edge are left out: there the
//! rasterizer and the reference may legitimately disagree about which tets a pixel centre hits.

mod common;

use common::{assert_clean, gpu};
use tessera::shaders;
use tessera::tet::interval::compute::{IntervalCompute, OpticalBuffer};
use tessera::tet::interval::{GpuTetMesh, Interval, IntervalFrame, OpticalTarget};
use tessera_data::tet::optical::{edge_mask, optical_depth};
use tessera_data::tet::procedural::{box_mesh, deform, sphere_mesh};
use tessera_data::tet::TetMesh;
use tessera_data::OrbitCamera;

fn camera(az: f32, el: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg: az,
        elevation_deg: el,
        distance,
        ..OrbitCamera::default()
    }
}

/// Renders `mesh` and holds every pixel away from projected edges to the CPU optical depth:
/// relative error at most 1e-3 (absolute 1e-5 where the depth is tiny).
fn assert_matches_reference(
    name: &str,
    mesh: &TetMesh,
    cam: &OrbitCamera,
    (w, h): (u32, u32),
    clipped: bool,
) -> usize {
    let gpu = gpu();
    if !gpu.caps().mesh_shader {
        eprintln!("skipped: {} has no mesh shaders", gpu.caps().device_name);
        return 0;
    }
    let compiler = shaders::compiler();
    let gpu_mesh = GpuTetMesh::upload(&gpu, mesh).unwrap();
    let reference = optical_depth(mesh, cam, w, h);
    let edges = edge_mask(mesh, cam, w, h, 1.0);

    let interval = Interval::new(&gpu, &compiler).unwrap();
    let target = OpticalTarget::new(&gpu, w, h).unwrap();
    let frame = interval.render(&gpu, &gpu_mesh, &target, cam).unwrap();
    let covered = compare(
        &format!("{name} (mesh)"),
        &frame,
        &reference,
        &edges,
        w,
        clipped,
    );
    target.destroy(&gpu);
    interval.destroy(&gpu);

    // The compute path draws the same proxies with its own rasterizer.
    if gpu.caps().buffer_float32_atomic_add {
        let compute = IntervalCompute::new(&gpu, &compiler).unwrap();
        let target = OpticalBuffer::new(&gpu, w, h).unwrap();
        let frame = compute.render(&gpu, &gpu_mesh, &target, cam).unwrap();
        compare(
            &format!("{name} (compute)"),
            &frame,
            &reference,
            &edges,
            w,
            clipped,
        );
        target.destroy(&gpu);
        compute.destroy(&gpu);
    }
    gpu_mesh.destroy(&gpu);
    assert_clean(&gpu);
    covered
}

/// Every pixel away from projected edges within 1e-3 relative (1e-5 absolute) of the reference;
/// returns how many of them the mesh covers.
fn compare(
    name: &str,
    frame: &IntervalFrame,
    reference: &[[f32; 3]],
    edges: &[bool],
    w: u32,
    clipped: bool,
) -> usize {
    assert_eq!(
        frame.clipped_near > 0,
        clipped,
        "{name}: {} tets clipped at the near plane",
        frame.clipped_near
    );
    let mut compared = 0;
    let mut covered = 0;
    for (i, (g, r)) in frame.optical_depth.iter().zip(reference).enumerate() {
        if edges[i] {
            continue;
        }
        compared += 1;
        covered += usize::from(r[0] > 0.0);
        for c in 0..3 {
            let tolerance = (1e-3 * r[c].abs()).max(1e-5);
            assert!(
                (g[c] - r[c]).abs() <= tolerance,
                "{name}: pixel ({}, {}) channel {c}: GPU {} vs CPU {}",
                i as u32 % w,
                i as u32 / w,
                g[c],
                r[c]
            );
        }
    }
    assert!(
        compared > reference.len() / 4,
        "{name}: only {compared} pixels away from edges"
    );
    covered
}

fn single_tet(vertices: [[f32; 3]; 4]) -> TetMesh {
    let mut mesh = TetMesh::new(vertices.to_vec(), vec![[0, 1, 2, 3]]);
    mesh.validate("test tet").unwrap();
    mesh
}

#[test]
fn one_tet_with_a_triangle_silhouette() {
    // Seen from +z, the apex projects inside the base triangle: case 1.
    let mesh = single_tet([
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.1, -0.2, 1.0],
    ]);
    let covered =
        assert_matches_reference("case 1", &mesh, &camera(0.0, 0.0, 2.5), (96, 96), false);
    assert!(
        covered > 500,
        "the tet must fill part of the image ({covered} pixels)"
    );
}

#[test]
fn one_tet_with_a_quad_silhouette() {
    // Two opposite edges crossing in projection: case 2. Tilted and off-centre, so the depths
    // where the diagonals cross differ from every corner's (a symmetric tet hides errors there).
    let mesh = single_tet([
        [-1.0, 0.2, -0.8],
        [1.0, 0.1, -0.3],
        [0.3, -1.0, 0.5],
        [-0.2, 1.0, 0.2],
    ]);
    let covered =
        assert_matches_reference("case 2", &mesh, &camera(0.0, 0.0, 2.5), (96, 96), false);
    assert!(
        covered > 500,
        "the tet must fill part of the image ({covered} pixels)"
    );
}

#[test]
fn meshes_with_absorption_colours() {
    let mut sphere = sphere_mesh(5);
    deform(&mut sphere, 0.1);
    sphere.validate("sphere").unwrap();
    assert_matches_reference(
        "deformed sphere",
        &sphere,
        &camera(35.0, 20.0, 2.2),
        (80, 64),
        false,
    );
    let cube = box_mesh(3);
    assert!(
        cube.absorption.is_some(),
        "procedural box carries per-tet colours"
    );
    assert_matches_reference("box", &cube, &camera(-60.0, 40.0, 2.4), (80, 64), false);
}

#[test]
fn beer_lambert_post_pass_matches_cpu_composite() {
    let gpu = gpu();
    if !gpu.caps().mesh_shader {
        eprintln!("skipped: {} has no mesh shaders", gpu.caps().device_name);
        return;
    }
    let compiler = shaders::compiler();
    let interval = Interval::new(&gpu, &compiler).unwrap();
    let mesh = sphere_mesh(4);
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let (w, h) = (72, 56);
    let cam = camera(20.0, 10.0, 2.0);
    let background = [1.0, 0.95, 0.85];
    let target = OpticalTarget::new(&gpu, w, h).unwrap();
    let depth = interval.render(&gpu, &gpu_mesh, &target, &cam).unwrap();
    let (image, _ms) = interval
        .render_image(&gpu, &gpu_mesh, &cam, (w, h), background)
        .unwrap();
    let expected = tessera_data::tet::optical::composite(&depth.optical_depth, w, h, background);
    let diff = image.compare(&expected, 1);
    assert!(
        diff.fraction_within >= 0.999,
        "{} pixels differ",
        diff.pixels_outside
    );
    let darkened = image
        .pixels
        .iter()
        .filter(|&&p| p != expected.pixels[0])
        .count();
    assert!(
        darkened > (w * h / 10) as usize,
        "the mesh must absorb light somewhere"
    );
    target.destroy(&gpu);
    gpu_mesh.destroy(&gpu);
    interval.destroy(&gpu);
    assert_clean(&gpu);
}

#[test]
fn camera_inside_the_mesh_clips_tets_at_the_near_plane() {
    // The eye 0.3 from the centre of a box whose half-size is 0.5: tets around it cross the
    // near plane with one, two and three corners in front.
    let cube = box_mesh(4);
    assert_matches_reference(
        "inside box",
        &cube,
        &camera(20.0, 15.0, 0.3),
        (80, 64),
        true,
    );
    let mut sphere = sphere_mesh(4);
    deform(&mut sphere, 0.05);
    sphere.validate("sphere").unwrap();
    assert_matches_reference(
        "inside sphere",
        &sphere,
        &camera(-50.0, -30.0, 0.2),
        (80, 64),
        true,
    );
}

#[test]
fn a_single_clipped_tet() {
    // The eye sits inside this tet, so every view ray starts on the near plane within it.
    let mesh = single_tet([
        [-1.0, -1.0, -1.0],
        [1.2, -0.8, -0.9],
        [0.1, 1.1, -1.0],
        [0.0, 0.1, 1.2],
    ]);
    assert_matches_reference(
        "clipped tet",
        &mesh,
        &camera(10.0, 5.0, 0.05),
        (64, 64),
        true,
    );
}
