//! Shared set-up for GPU tests: a device with the validation layer on, and image checks that
//! leave evidence behind when they fail.
#![allow(dead_code)]

pub mod front_door;
pub mod interval;
pub mod param;
pub mod raster;
pub mod raster_scene;
pub mod shell;
pub mod surface;
pub mod volumes;

use glam::Vec3;
use std::collections::HashMap;
use std::path::PathBuf;
use tessera_data::RgbaImage;
use tessera_data::{Samples, Volume};
use tessera_gpu::Gpu;

// Not every test binary uses every piece.
#[allow(unused_imports)]
pub use tessera_test::{skip, Need, Rng, TestGpu};

/// An orbit camera at `azimuth_deg`, `elevation_deg` and `distance`, the rest default.
pub fn camera(azimuth_deg: f32, elevation_deg: f32, distance: f32) -> tessera_data::OrbitCamera {
    tessera_data::OrbitCamera {
        azimuth_deg,
        elevation_deg,
        distance,
        ..tessera_data::OrbitCamera::default()
    }
}

/// Opens the default device with validation; its validation errors fail the test when it is
/// dropped, after the test's GPU objects.
pub fn gpu() -> TestGpu {
    TestGpu::new()
}

/// Fails on the validation errors seen so far (the device checks again when dropped).
pub fn assert_clean(gpu: &Gpu) {
    let errors = gpu.validation_errors();
    assert!(
        errors.is_empty(),
        "{} validation error(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

pub fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("images");
    let _ = std::fs::create_dir_all(&dir);
    dir
}

pub fn write_png(path: &std::path::Path, img: &RgbaImage) {
    let file = std::fs::File::create(path).expect("create png");
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), img.width, img.height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().expect("png header");
    w.write_image_data(&img.to_rgba_bytes()).expect("png data");
}

/// Holds `actual` to `expected`: at least `min_fraction` of pixels within `tolerance` per
/// channel. On failure writes NAME-expected.png, NAME-actual.png and NAME-diff.png.
pub fn assert_images_match(
    name: &str,
    actual: &RgbaImage,
    expected: &RgbaImage,
    tolerance: u8,
    min_fraction: f64,
) {
    let diff = actual.compare(expected, tolerance);
    eprintln!(
        "{name}: {:.3}% within {tolerance}/255, {} pixel(s) outside, max diff {}",
        diff.fraction_within * 100.0,
        diff.pixels_outside,
        diff.max_channel_diff
    );
    if std::env::var_os("TESSERA_KEEP_IMAGES").is_some() {
        write_png(&out_dir().join(format!("{name}-actual.png")), actual);
    }
    if diff.fraction_within < min_fraction {
        let dir = out_dir();
        write_png(&dir.join(format!("{name}-expected.png")), expected);
        write_png(&dir.join(format!("{name}-actual.png")), actual);
        write_png(
            &dir.join(format!("{name}-diff.png")),
            &actual.diff_image(expected),
        );
        panic!(
            "{name}: only {:.3}% of pixels within {tolerance}/255 (need {:.1}%), max diff {}; images in {}",
            diff.fraction_within * 100.0,
            min_fraction * 100.0,
            diff.max_channel_diff,
            dir.display()
        );
    }
}

/// Holds a rendered isosurface to the CPU rasterization of the CPU marching-cubes mesh:
/// silhouette IoU >= 0.99, >= 99 % of co-covered pixels within 2/255, and enough surface in
/// view. Writes actual/expected/diff PNGs when it fails.
pub fn assert_matches_cpu_raster(
    name: &str,
    image: &RgbaImage,
    volume: &tessera_data::Volume,
    iso: f32,
    camera: &tessera_data::OrbitCamera,
) {
    let (w, h) = (image.width, image.height);
    let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
    let mesh = tessera_data::marching_cubes::marching_cubes(volume, iso);
    let frame = tessera_data::GridFrame::new(volume.dims(), volume.spacing());
    let reference = tessera_data::rasterize::rasterize_mesh(&mesh, &frame, camera, w, h);
    let coverage = tessera_data::image::coverage_of(image, background);
    let iou = tessera_data::image::silhouette_iou(&coverage, &reference.coverage);
    let both: Vec<bool> = coverage
        .iter()
        .zip(&reference.coverage)
        .map(|(a, b)| *a && *b)
        .collect();
    let diff = image.compare_where(&reference.image, &both, 2);
    eprintln!(
        "{name}: IoU {iou:.4}, {:.3}% of co-covered pixels within 2/255 (max {})",
        diff.fraction_within * 100.0,
        diff.max_channel_diff
    );
    let covered = both.iter().filter(|&&b| b).count();
    if iou < 0.99 || diff.fraction_within < 0.99 || covered < (w * h / 20) as usize {
        let dir = out_dir();
        write_png(&dir.join(format!("{name}-actual.png")), image);
        write_png(&dir.join(format!("{name}-expected.png")), &reference.image);
        write_png(
            &dir.join(format!("{name}-diff.png")),
            &image.diff_image(&reference.image),
        );
        panic!(
            "{name}: IoU {iou}, within {}, covered {covered}; images in {}",
            diff.fraction_within,
            dir.display()
        );
    }
}

/// A float volume of spacing 1 whose sample at grid point `p` is `f(p)`.
pub fn field(name: &str, dims: [u32; 3], f: impl Fn(Vec3) -> f32) -> Volume {
    let mut v = Vec::new();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                v.push(f(Vec3::new(x as f32, y as f32, z as f32)));
            }
        }
    }
    Volume::new(name, dims, [1.0; 3], Samples::F32(v)).unwrap()
}

/// Every cell has a sign change on every edge: 12 vertices and 4 triangles per cell, so each
/// block is fully occupied and lists are cut by the vertex limit, not the cell limit.
pub fn checkerboard(dims: [u32; 3]) -> Volume {
    field("checkerboard", dims, |p| {
        ((p.x + p.y + p.z) as u32 % 2) as f32
    })
}

/// The no-vertex-arithmetic ablation's vertices: each at a grid point (its edge's start) with
/// the normal +z. Where `exact` (the whole extraction's vertices in the same order) is given,
/// each exact vertex lies on the edge from that start: equal on two axes, at most one sample
/// further on the third.
pub fn assert_vertices_at_edge_starts(
    what: &str,
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    exact: Option<&[[f32; 3]]>,
) {
    assert!(!positions.is_empty(), "{what}: no vertices");
    assert!(
        normals.iter().all(|n| *n == [0.0, 0.0, 1.0]),
        "{what}: a normal is not the stand-in's"
    );
    for (k, p) in positions.iter().enumerate() {
        assert!(
            p.iter().all(|c| c.fract() == 0.0),
            "{what}: vertex {k} at {p:?}"
        );
        if let Some(exact) = exact {
            let e = exact[k];
            let along: Vec<usize> = (0..3).filter(|&a| e[a] != p[a]).collect();
            assert!(
                along.len() <= 1 && along.iter().all(|&a| e[a] > p[a] && e[a] <= p[a] + 1.0),
                "{what}: vertex {k} at {e:?} is not on an edge from {p:?}"
            );
        }
    }
}

/// Asserts the two triangle lists are the same multiset: each GPU triangle matches one
/// unmatched CPU triangle in some cyclic order (orientation kept), every coordinate within `tol`.
pub fn assert_same_triangles(
    name: &str,
    gpu_tris: &[[Vec3; 3]],
    cpu: &tessera_data::mesh::TriangleMesh,
    tol: f32,
) {
    let cpu_tris: Vec<[Vec3; 3]> = cpu
        .triangles
        .iter()
        .map(|t| t.map(|i| cpu.positions[i as usize]))
        .collect();
    assert_eq!(
        gpu_tris.len(),
        cpu_tris.len(),
        "{name}: triangle counts differ"
    );
    // Bucket CPU triangles by the cell holding their centroid (half-cell grid, searched with
    // neighbours, so a centroid near a bucket border is still found).
    let key = |t: &[Vec3; 3]| ((t[0] + t[1] + t[2]) / 3.0 * 2.0).floor().as_ivec3();
    let mut buckets: HashMap<glam::IVec3, Vec<usize>> = HashMap::new();
    for (i, t) in cpu_tris.iter().enumerate() {
        buckets.entry(key(t)).or_default().push(i);
    }
    let mut used = vec![false; cpu_tris.len()];
    let same = |a: &[Vec3; 3], b: &[Vec3; 3]| {
        (0..3).any(|r| (0..3).all(|j| (a[(j + r) % 3] - b[j]).abs().max_element() <= tol))
    };
    for (n, t) in gpu_tris.iter().enumerate() {
        let k = key(t);
        let mut found = false;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(list) = buckets.get(&(k + glam::IVec3::new(dx, dy, dz))) {
                        for &i in list {
                            if !used[i] && same(t, &cpu_tris[i]) {
                                used[i] = true;
                                found = true;
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        assert!(
            found,
            "{name}: GPU triangle {n} {t:?} has no CPU counterpart"
        );
    }
}

/// The triangles of a compute-path list drawn with `params`, in grid coordinates: each
/// clip-space corner taken back through the inverse of `params.grid_to_clip`.
pub fn list_triangles_in_grid(
    gpu: &Gpu,
    lists: &tessera::iso::direct::compute::TriangleLists,
    params: &tessera::iso::direct::DirectParams,
) -> Vec<[Vec3; 3]> {
    let clip_to_grid = glam::Mat4::from_cols_array_2d(&params.grid_to_clip)
        .as_dmat4()
        .inverse();
    let corners: Vec<[[f32; 4]; 3]> = gpu.read_buffer_as(&lists.triangles).unwrap();
    corners
        .iter()
        .map(|t| {
            t.map(|c| {
                let grid = clip_to_grid * glam::Vec4::from(c).as_dvec4();
                (grid.truncate() / grid.w).as_vec3()
            })
        })
        .collect()
}

/// Asserts `drawn` is the compute path's refusal of a surface of `triangles` triangles that its
/// triangle list cannot hold on the device: the error names the count and the limit.
pub fn assert_refused_for_the_lists<T>(drawn: tessera::error::Result<T>, triangles: u64) {
    let message = match drawn {
        Ok(_) => panic!("a surface of {triangles} triangles, larger than a list, was drawn"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains(&format!("{triangles} triangles"))
            && message.contains("largest storage buffer"),
        "{message}"
    );
}
