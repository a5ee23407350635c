//! Interval shading (paper A) of scalar fields and the asteroid field against their CPU
//! references: a vertex scalar through a transfer function (absorption, emission, maximum,
//! exact per stretch) and asteroids sphere-traced within their bounding tets.

mod common;

use common::interval::{assert_variants_match, defaults, variants, Expected};
use common::{assert_clean, camera, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{GpuTetMesh, Integrand, Interval, IntervalOptions};
use tessera_data::tet::optical::edge_mask;
use tessera_data::tet::procedural::{deform, sphere_mesh};
use tessera_data::tet::scalar_integral::{integrate_scalar, normalized_scalars};
use tessera_data::tet::TetMesh;
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction};
use tessera_data::OrbitCamera;

/// A deformed sphere whose vertex scalar is the distance from a point off-centre, so the field
/// varies inside every tet.
fn scalar_sphere() -> TetMesh {
    // Coarse, so that most covered pixels lie away from projected edges.
    let mut mesh = sphere_mesh(2);
    deform(&mut mesh, 0.08);
    mesh.absorption = None;
    mesh.scalars = Some(
        mesh.vertices
            .iter()
            .map(|v| ((v[0] - 0.3).powi(2) + (v[1] + 0.2).powi(2) + v[2].powi(2)).sqrt())
            .collect(),
    );
    mesh.validate("scalar sphere").unwrap();
    mesh
}

/// `min_covered`: pixels away from edges the integrand must be non-zero on (a sparse table
/// leaves fewer).
fn scalar_matches_reference(
    mode: ScalarMode,
    tf: &str,
    scale: f32,
    cam: &OrbitCamera,
    all: bool,
    min_covered: usize,
) {
    let gpu = gpu();
    let mesh = scalar_sphere();
    let (w, h) = (96, 80);
    let normalized = normalized_scalars(&mesh, None, "scalar sphere").unwrap();
    let tf = TransferFunction::preset(tf).unwrap();
    let table = IntegrandTable::new(&tf, mode, scale, 64);
    let reference = integrate_scalar(&mesh, &normalized, cam, (w, h), &table, mode);
    let edges = edge_mask(&mesh, cam, w, h, 1.0);
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let integrand = Integrand::Scalar { mode, table };
    let variants = variants(&gpu, &integrand, all);
    let covered = assert_variants_match(
        &gpu,
        &format!("{mode:?}"),
        &gpu_mesh,
        &variants,
        cam,
        (w, h),
        &Expected {
            reference: &reference,
            edges: &edges,
            clipped: cam.distance < 1.0,
        },
    );
    assert!(
        variants.is_empty() || covered >= min_covered,
        "{mode:?}: {covered} pixels covered"
    );
}

#[test]
fn scalar_absorption_through_a_transfer_function() {
    // "bands" has opaque ramps two knots wide: the mean over a stretch must resolve them.
    scalar_matches_reference(
        ScalarMode::Absorption,
        "bands",
        4.0,
        &camera(30.0, 20.0, 2.2),
        false,
        150,
    );
}

#[test]
fn scalar_emission_and_maximum_from_inside() {
    let inside = camera(-40.0, 10.0, 0.25);
    scalar_matches_reference(ScalarMode::Emission, "hot", 2.0, &inside, true, 1500);
    scalar_matches_reference(ScalarMode::Maximum, "cool-warm", 1.0, &inside, false, 1500);
}

#[test]
fn maximum_post_pass_shows_the_table_colour() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let mesh = scalar_sphere();
    let (w, h) = (64, 48);
    let cam = camera(10.0, 30.0, 2.0);
    let tf = TransferFunction::preset("cool-warm").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Maximum, 1.0, 64);
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let background = [0.1, 0.1, 0.1];
    for (name, options) in defaults(&gpu) {
        let options = IntervalOptions {
            integrand: Integrand::Scalar {
                mode: ScalarMode::Maximum,
                table: table.clone(),
            },
            ..options
        };
        let interval = Interval::new(&gpu, &compiler, &options).unwrap();
        let target = interval.target(&gpu, w, h).unwrap();
        let maxima = interval.render(&gpu, &gpu_mesh, &target, &cam).unwrap();
        let (image, _) = interval
            .render_image(&gpu, &gpu_mesh, &cam, (w, h), background)
            .unwrap();
        let colours =
            tessera_data::tet::scalar_integral::maximum_colours(&maxima.values, &table, background);
        let expected = tessera_data::RgbaImage {
            width: w,
            height: h,
            pixels: colours
                .iter()
                .map(|c| tessera_data::shading::pack_rgba8([c[0], c[1], c[2], 1.0]))
                .collect(),
        };
        let diff = image.compare(&expected, 1);
        assert!(
            diff.fraction_within >= 0.999,
            "{name}: {} pixels differ",
            diff.pixels_outside
        );
        let distinct: std::collections::HashSet<u32> = image.pixels.iter().copied().collect();
        assert!(
            distinct.len() > 20,
            "{name}: the colour must vary with the maximum"
        );
    }
    assert_clean(&gpu);
}

/// The asteroid field (paper A §3.2): each tet's asteroid sphere-traced along its interval,
/// nearest hit by depth, against the CPU tracer of the same distance function.
#[test]
fn asteroid_field_matches_the_cpu_sphere_tracer() {
    use tessera_data::image::{coverage_of, silhouette_iou};
    use tessera_data::tet::asteroids::{asteroid_field, asteroid_spheres, render_reference};
    let gpu = gpu();
    let compiler = shaders::compiler();
    let mesh = asteroid_field(60, 3);
    let spheres = asteroid_spheres(&mesh);
    let (w, h) = (96, 72);
    let background = [0.0, 0.0, 0.0];
    // Outside the field, and inside it (tets clipped at the near plane).
    for cam in [camera(30.0, 20.0, 1.5), camera(-20.0, 10.0, 0.15)] {
        let (expected, hits) = render_reference(&mesh, &spheres, &cam, (w, h), background);
        let hit_count = hits.iter().filter(|&&h| h).count();
        assert!(
            hit_count > 500,
            "the view must show asteroids ({hit_count} pixels)"
        );
        let gpu_mesh = GpuTetMesh::upload_asteroids(&gpu, &mesh).unwrap();
        for (name, options) in defaults(&gpu) {
            if options.path == Path::Compute && !gpu.caps().buffer_int64_atomics {
                skip(&name, "no 64-bit buffer atomics");
                continue;
            }
            let options = IntervalOptions {
                integrand: Integrand::Asteroids,
                ..options
            };
            let interval = Interval::new(&gpu, &compiler, &options).unwrap();
            let (image, _) = interval
                .render_image(&gpu, &gpu_mesh, &cam, (w, h), background)
                .unwrap();
            let empty = expected.pixels[hits.iter().position(|&h| !h).unwrap()];
            let covered = coverage_of(&image, empty);
            let iou = silhouette_iou(&covered, &hits);
            assert!(
                iou >= 0.99,
                "{name} at {}: silhouette IoU {iou}",
                cam.distance
            );
            let both: Vec<bool> = covered.iter().zip(&hits).map(|(a, b)| *a && *b).collect();
            let diff = image.compare_where(&expected, &both, 4);
            assert!(
                diff.fraction_within >= 0.98,
                "{name} at {}: {} of the shared pixels differ by more than 4/255",
                cam.distance,
                diff.pixels_outside
            );
        }
    }
    assert_clean(&gpu);
}
