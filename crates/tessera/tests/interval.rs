//! Interval shading (paper A) against the CPU reference that integrates exact ray–tet path
//! lengths per pixel. Pixels within a pixel of a projected tet edge are left out: there the
//! rasterizer and the reference may legitimately disagree about which tets a pixel centre hits.

mod common;

use common::{assert_clean, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{
    BinCapacity, ComputeScheme, GpuTetMesh, Integrand, Interval, IntervalFrame, IntervalOptions,
    TileCapacity,
};
use tessera_data::tet::optical::{edge_mask, optical_depth};
use tessera_data::tet::procedural::{box_mesh, deform, sphere_mesh};
use tessera_data::tet::scalar_integral::{integrate_scalar, normalized_scalars};
use tessera_data::tet::TetMesh;
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

fn camera(az: f32, el: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg: az,
        elevation_deg: el,
        distance,
        ..OrbitCamera::default()
    }
}

/// The paths this device runs: the mesh-shader path where it has mesh shaders, the compute
/// path where it has float atomics.
fn paths(gpu: &Gpu) -> Vec<Path> {
    let mut paths = Vec::new();
    if gpu.caps().mesh_shader {
        paths.push(Path::Graphics);
    }
    if gpu.caps().buffer_float32_atomic_add {
        paths.push(Path::Compute);
    }
    paths
}

/// The default options of every path, and the compute path's binned scheme.
fn defaults(gpu: &Gpu) -> Vec<(String, IntervalOptions)> {
    let mut out = Vec::new();
    for path in paths(gpu) {
        out.push((path.name().to_string(), IntervalOptions::new(path)));
        if path == Path::Compute {
            out.push((
                "compute, binned".into(),
                IntervalOptions {
                    compute_scheme: ComputeScheme::Binned,
                    ..IntervalOptions::new(path)
                },
            ));
        }
    }
    out
}

/// The binned scheme with lists too small for the view (tets beyond them drawn per tet, every
/// one of those through the tile pass), and with fewer tile counters than the screen has
/// tiles (every tet drawn per tet).
fn binned_overflow_variants(base: &IntervalOptions) -> Vec<(String, IntervalOptions)> {
    let binned = IntervalOptions {
        compute_scheme: ComputeScheme::Binned,
        ..base.clone()
    };
    vec![
        (
            "compute, binned, lists full".into(),
            IntervalOptions {
                bin_capacity: BinCapacity {
                    entries: 5,
                    ..BinCapacity::default()
                },
                ..binned.clone()
            },
        ),
        (
            "compute, binned, lists full, all tiled".into(),
            IntervalOptions {
                inline_pixel_limit: Some(0),
                bin_capacity: BinCapacity {
                    entries: 5,
                    ..BinCapacity::default()
                },
                ..binned.clone()
            },
        ),
        (
            "compute, binned, screen beyond the tile counters".into(),
            IntervalOptions {
                bin_capacity: BinCapacity {
                    tiles: 3,
                    ..BinCapacity::default()
                },
                ..binned
            },
        ),
    ]
}

/// The defaults ([`defaults`]), plus on request the variants that exercise the compute path's
/// tile pass (every tet tiled; tile buffers too small, so some tets fall back to single
/// invocations), the binned scheme's overflow and one tet per mesh workgroup.
fn variants(gpu: &Gpu, integrand: &Integrand, all: bool) -> Vec<(String, IntervalOptions)> {
    let mut out = Vec::new();
    for (name, options) in defaults(gpu) {
        let base = IntervalOptions {
            integrand: integrand.clone(),
            ..options
        };
        let path = base.path;
        let per_tet = base.compute_scheme == ComputeScheme::PerTet;
        out.push((name, base.clone()));
        if !all || !per_tet {
            continue;
        }
        match path {
            Path::Graphics => out.push((
                "graphics, 1 tet per workgroup".into(),
                IntervalOptions {
                    tets_per_workgroup: 1,
                    ..base
                },
            )),
            Path::Compute => {
                out.push((
                    "compute, all tiled".into(),
                    IntervalOptions {
                        inline_pixel_limit: Some(0),
                        ..base.clone()
                    },
                ));
                out.push((
                    "compute, tile buffers full".into(),
                    IntervalOptions {
                        inline_pixel_limit: Some(0),
                        tile_capacity: TileCapacity { tets: 3, tiles: 8 },
                        ..base.clone()
                    },
                ));
                out.extend(binned_overflow_variants(&base));
            }
        }
    }
    out
}

/// What a view should give: the CPU reference per pixel, the pixels near projected edges (left
/// out), and whether tets cross the near plane.
struct Expected<'a> {
    reference: &'a [[f32; 3]],
    edges: &'a [bool],
    clipped: bool,
}

/// Renders `mesh` with each variant and holds every pixel away from projected edges to the
/// reference; returns how many of those pixels the mesh covers.
fn assert_variants_match(
    gpu: &Gpu,
    name: &str,
    gpu_mesh: &GpuTetMesh,
    variants: &[(String, IntervalOptions)],
    cam: &OrbitCamera,
    (w, h): (u32, u32),
    expected: &Expected,
) -> usize {
    let compiler = shaders::compiler();
    let mut covered = 0;
    for (variant, options) in variants {
        let interval = Interval::new(gpu, &compiler, options).unwrap();
        let target = interval.target(gpu, w, h).unwrap();
        let frame = interval.render(gpu, gpu_mesh, &target, cam).unwrap();
        let label = format!("{name} ({variant})");
        let snap = common::interval::snap_px(gpu, options.path);
        covered = compare(&label, &frame, expected, w, snap);
        // Tets reach the per-tet passes in the binned scheme only where its lists are full.
        let binned = options.compute_scheme == ComputeScheme::Binned;
        let lists_full = binned && {
            let capacity = options.bin_capacity;
            capacity.entries < 10 || capacity.tiles < 10
        };
        assert_eq!(
            frame.unbinned > 0,
            lists_full,
            "{label}: {} tets drawn unbinned",
            frame.unbinned
        );
        let per_tet = !binned || lists_full;
        if options.path == Path::Compute && options.inline_pixel_limit == Some(0) && per_tet {
            assert!(frame.tiled > 0, "{label}: no tet reached the tile pass");
            let full = options.tile_capacity.tets < 10;
            assert_eq!(
                frame.overflowed > 0,
                full,
                "{label}: {} overflowed",
                frame.overflowed
            );
        }
    }
    assert_clean(gpu);
    covered
}

/// Renders `mesh`'s per-tet optical depth on every path and holds every pixel away from
/// projected edges to the CPU reference: relative error at most 1e-3 (absolute 1e-5 where the
/// depth is tiny).
fn assert_matches_reference(
    name: &str,
    mesh: &TetMesh,
    cam: &OrbitCamera,
    (w, h): (u32, u32),
    clipped: bool,
    all_variants: bool,
) -> usize {
    let gpu = gpu();
    let variants = variants(&gpu, &Integrand::TetAbsorption, all_variants);
    if variants.is_empty() {
        let reason = format!(
            "{} has neither mesh shaders nor float atomics",
            gpu.caps().device_name
        );
        skip("", &reason);
        return 0;
    }
    let gpu_mesh = GpuTetMesh::upload(&gpu, mesh).unwrap();
    let reference = optical_depth(mesh, cam, w, h);
    let edges = edge_mask(mesh, cam, w, h, 1.0);
    assert_variants_match(
        &gpu,
        name,
        &gpu_mesh,
        &variants,
        cam,
        (w, h),
        &Expected {
            reference: &reference,
            edges: &edges,
            clipped,
        },
    )
}

/// Every pixel away from projected edges within tolerance of the reference
/// ([`common::interval::assert_close`]); returns how many of them the mesh covers.
fn compare(name: &str, frame: &IntervalFrame, expected: &Expected, w: u32, snap_px: f32) -> usize {
    assert_eq!(
        frame.clipped_near > 0,
        expected.clipped,
        "{name}: {} tets clipped at the near plane",
        frame.clipped_near
    );
    let (compared, covered) = common::interval::assert_close(
        name,
        &frame.values,
        expected.reference,
        expected.edges,
        w,
        snap_px,
    );
    assert!(
        compared > expected.reference.len() / 4,
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
    let covered = assert_matches_reference(
        "case 1",
        &mesh,
        &camera(0.0, 0.0, 2.5),
        (96, 96),
        false,
        false,
    );
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
    let covered = assert_matches_reference(
        "case 2",
        &mesh,
        &camera(0.0, 0.0, 2.5),
        (96, 96),
        false,
        true,
    );
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
        false,
    );
    let cube = box_mesh(3);
    assert!(
        cube.absorption.is_some(),
        "procedural box carries per-tet colours"
    );
    assert_matches_reference(
        "box",
        &cube,
        &camera(-60.0, 40.0, 2.4),
        (80, 64),
        false,
        false,
    );
}

#[test]
fn beer_lambert_post_pass_matches_cpu_composite() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let mesh = sphere_mesh(4);
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let (w, h) = (72, 56);
    let cam = camera(20.0, 10.0, 2.0);
    let background = [1.0, 0.95, 0.85];
    for (name, options) in defaults(&gpu) {
        let interval = Interval::new(&gpu, &compiler, &options).unwrap();
        let target = interval.target(&gpu, w, h).unwrap();
        let depth = interval.render(&gpu, &gpu_mesh, &target, &cam).unwrap();
        let (image, _ms) = interval
            .render_image(&gpu, &gpu_mesh, &cam, (w, h), background)
            .unwrap();
        let expected = tessera_data::tet::optical::composite(&depth.values, w, h, background);
        let diff = image.compare(&expected, 1);
        assert!(
            diff.fraction_within >= 0.999,
            "{name}: {} pixels differ",
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
    }
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
        false,
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
        true,
    );
}

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
