//! The tetrahedralized Stanford bunny (npm `bunny` through Debian's `tetgen -pq1.414`, made by
//! scripts/fetch-bunny.sh, which `make test` runs): loaded, checked against its surface, and
//! rendered by interval shading on every path against the CPU reference. Skipped with a note
//! where the files are missing.

mod common;

use common::{assert_clean, gpu, skip};
use std::path::PathBuf;
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{ComputeScheme, GpuTetMesh, Integrand, Interval, IntervalOptions};
use tessera_data::tet::optical::{edge_mask, optical_depth};
use tessera_data::tet::scalar_integral::{integrate_scalar, normalized_scalars};
use tessera_data::tet::{load_tet_mesh, TetMesh};
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction};
use tessera_data::OrbitCamera;

fn bunny_dir() -> PathBuf {
    tessera_test::data_file("bunny")
}

fn bunny() -> Option<TetMesh> {
    let node = bunny_dir().join("bunny.1.node");
    if !node.exists() {
        skip(
            "",
            &format!("{} not found (scripts/fetch-bunny.sh)", node.display()),
        );
        return None;
    }
    let (mesh, report) = load_tet_mesh(&node).expect("the bunny loads");
    assert_eq!(
        report.degenerate, 0,
        "tetgen's quality mesh has no flat tets"
    );
    Some(mesh)
}

/// The volume the OFF surface encloses (divergence theorem over its triangles).
fn enclosed_volume(off: &std::path::Path) -> f64 {
    let text = std::fs::read_to_string(off).unwrap();
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    assert_eq!(lines.next().map(str::trim), Some("OFF"));
    let counts: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let points: Vec<[f64; 3]> = (0..counts[0])
        .map(|_| {
            let v: Vec<f64> = lines
                .next()
                .unwrap()
                .split_whitespace()
                .map(|w| w.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let mut six_volume = 0.0;
    for _ in 0..counts[1] {
        let f: Vec<usize> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .skip(1)
            .map(|w| w.parse().unwrap())
            .collect();
        let [a, b, c] = [points[f[0]], points[f[1]], points[f[2]]].map(glam::DVec3::from);
        six_volume += a.dot(b.cross(c));
    }
    six_volume.abs() / 6.0
}

#[test]
fn bunny_fills_its_surface() {
    let Some(mesh) = bunny() else { return };
    assert!(
        (40_000..50_000).contains(&mesh.tets.len()),
        "{} tets",
        mesh.tets.len()
    );
    let surface = enclosed_volume(&bunny_dir().join("bunny.off"));
    let filled = mesh.total_volume();
    assert!(
        (filled - surface).abs() < 1e-5 * surface,
        "tets fill {filled}, the surface encloses {surface}"
    );
    // A closed, conforming mesh: boundary faces form a closed surface (each edge twice).
    let boundary = mesh.boundary_faces();
    assert!(boundary.len() >= 3_674, "{} boundary faces", boundary.len());
    let mut edges = std::collections::HashMap::new();
    for f in &boundary {
        for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 2),
        "the boundary is not closed"
    );
}

#[test]
fn bunny_renders_like_the_reference_on_every_path() {
    let Some(mut mesh) = bunny() else { return };
    let gpu = gpu();
    let compiler = shaders::compiler();
    let (w, h) = (160, 128);
    let cam = OrbitCamera {
        azimuth_deg: 20.0,
        elevation_deg: 15.0,
        distance: 1.8,
        ..OrbitCamera::default()
    };
    // Height as the vertex scalar, emitted through a transfer function.
    mesh.scalars = Some(mesh.vertices.iter().map(|v| v[1]).collect());
    let normalized = normalized_scalars(&mesh, None, "bunny").unwrap();
    let tf = TransferFunction::preset("hot").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Emission, 2.0, 64);
    // Tens of thousands of tets leave no pixel a whole pixel away from every projected edge, so
    // only centres within 1/32 pixel of one are left out: rasterizers snap vertices to 1/256
    // pixel (or use float edge functions), so beyond that both sides decide coverage alike.
    let edges = edge_mask(&mesh, &cam, w, h, 1.0 / 32.0);
    let lengths = optical_depth(&mesh, &cam, w, h);
    let emission = integrate_scalar(
        &mesh,
        &normalized,
        &cam,
        (w, h),
        &table,
        ScalarMode::Emission,
    );
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let support = tessera::tet::interval::path_support(gpu.caps());
    let paths = [
        (Path::Graphics, ComputeScheme::PerTet, support.graphics),
        (Path::Compute, ComputeScheme::PerTet, support.compute),
        (Path::Compute, ComputeScheme::Binned, support.compute),
    ];
    let mut compared_any = false;
    for (path, scheme, supported) in paths {
        if !supported {
            continue;
        }
        for (integrand, reference) in [
            (Integrand::TetAbsorption, &lengths),
            (
                Integrand::Scalar {
                    mode: ScalarMode::Emission,
                    table: table.clone(),
                },
                &emission,
            ),
        ] {
            let options = IntervalOptions {
                integrand,
                compute_scheme: scheme,
                ..IntervalOptions::new(path)
            };
            let name = format!("{} ({})", path.name(), scheme.name());
            let interval = Interval::new(&gpu, &compiler, &options).unwrap();
            let target = interval.target(&gpu, w, h).unwrap();
            let frame = interval.render(&gpu, &gpu_mesh, &target, &cam).unwrap();
            // Where proxies are below a pixel the image says nothing of their slopes: the
            // graphics path may miss by its snapping in up to 1 % of the values.
            let outliers = if path == Path::Graphics { 0.01 } else { 0.0 };
            let (_, inside) = common::interval::assert_mostly_close(
                &name,
                &frame.values,
                reference,
                &edges,
                w,
                common::interval::snap_px(&gpu, path),
                outliers,
            );
            // A dense mesh leaves few pixels away from every projected edge; some must be.
            assert!(inside > 100, "{name}: {inside} pixels compared inside");
            compared_any = true;
        }
    }
    assert!(compared_any || support.graphics || support.compute);
    assert_clean(&gpu);
}
