//! Holding interval shading's per-pixel values to the CPU reference: the variants of each
//! path the tests run, and the comparison of a frame with the reference.

use super::{assert_clean, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{
    BinCapacity, ComputeScheme, GpuTetMesh, Integrand, Interval, IntervalFrame, IntervalOptions,
    SubgroupDraw, TileCapacity,
};
use tessera_data::tet::optical::{edge_mask, optical_depth};
use tessera_data::tet::TetMesh;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// Every value of `a` within a relative 1e-4 of `b`'s (1e-7 absolute where tiny): the same
/// sums taken in another order. Returns how many pixels hold something.
pub fn assert_same_sums(name: &str, a: &[[f32; 3]], b: &[[f32; 3]]) -> usize {
    assert_eq!(a.len(), b.len(), "{name}: pixel counts");
    let mut covered = 0;
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        for c in 0..3 {
            let tolerance = 1e-4 * x[c].abs().max(y[c].abs()) + 1e-7;
            assert!(
                (x[c] - y[c]).abs() <= tolerance,
                "{name}: pixel {i} channel {c}: {} against {}",
                x[c],
                y[c]
            );
        }
        covered += usize::from(x[0] > 0.0);
    }
    covered
}

/// How far the path's rasterizer may move a proxy's corners, in pixels: the graphics path
/// interpolates attributes over the triangle with its corners snapped to the sub-pixel grid
/// (NVIDIA does; lavapipe interpolates from the exact corners), the compute path draws the
/// exact corners.
pub fn snap_px(gpu: &Gpu, path: Path) -> f32 {
    match path {
        Path::Graphics => (-(gpu.caps().sub_pixel_precision_bits as f32)).exp2(),
        Path::Compute => 0.0,
    }
}

/// Every pixel not in `edges` within 1e-3 of the reference (relative; 1e-5 absolute where it is
/// tiny), plus what snapping corners by `snap_px` may change: up to three corners moving, each
/// by at most the value's change per pixel times `snap_px`. Returns (pixels compared, of those
/// the reference covers).
pub fn assert_close(
    name: &str,
    values: &[[f32; 3]],
    reference: &[[f32; 3]],
    edges: &[bool],
    width: u32,
    snap_px: f32,
) -> (usize, usize) {
    assert_mostly_close(name, values, reference, edges, width, snap_px, 0.0)
}

/// [`assert_close`], but a fraction `outliers` of the compared pixels may exceed that tolerance
/// as long as they stay within 2 %: where proxies are smaller than a pixel (dense meshes), the
/// reference's change between pixels says nothing of the change inside one proxy, which is
/// what snapping scales.
pub fn assert_mostly_close(
    name: &str,
    values: &[[f32; 3]],
    reference: &[[f32; 3]],
    edges: &[bool],
    width: u32,
    snap_px: f32,
    outliers: f64,
) -> (usize, usize) {
    let w = width as usize;
    let h = reference.len() / w.max(1);
    // The reference's largest change to a neighbouring pixel, per channel.
    let slope = |i: usize, c: usize| {
        let (x, y) = (i % w, i / w);
        let mut s = 0.0f32;
        for (nx, ny) in [
            (x.wrapping_sub(1), y),
            (x + 1, y),
            (x, y.wrapping_sub(1)),
            (x, y + 1),
        ] {
            if nx < w && ny < h {
                s = s.max((reference[ny * w + nx][c] - reference[i][c]).abs());
            }
        }
        s
    };
    let mut compared = 0;
    let mut covered = 0;
    let mut outside = 0;
    for (i, (g, r)) in values.iter().zip(reference).enumerate() {
        if edges[i] {
            continue;
        }
        compared += 1;
        covered += usize::from(r[0] > 0.0);
        for c in 0..3 {
            let tolerance = (1e-3 * r[c].abs()).max(1e-5) + 3.0 * snap_px * slope(i, c);
            let error = (g[c] - r[c]).abs();
            if error > tolerance && outliers > 0.0 && error <= 0.02 * r[c].abs() {
                outside += 1;
                continue;
            }
            assert!(
                error <= tolerance,
                "{name}: pixel ({}, {}) channel {c}: GPU {} vs CPU {} (tolerance {tolerance})",
                i % w,
                i / w,
                g[c],
                r[c]
            );
        }
    }
    assert!(
        outside as f64 <= outliers * (3 * compared) as f64,
        "{name}: {outside} of {} values beyond tolerance",
        3 * compared
    );
    (compared, covered)
}

/// The paths this device runs: the mesh-shader path where it has mesh shaders, the compute
/// path where it has float atomics.
pub fn paths(gpu: &Gpu) -> Vec<Path> {
    let mut paths = Vec::new();
    if gpu.caps().mesh_shader {
        paths.push(Path::Graphics);
    }
    if gpu.caps().buffer_float32_atomic_add {
        paths.push(Path::Compute);
    }
    paths
}

/// The default options of every path, the compute path with each of its schemes.
pub fn defaults(gpu: &Gpu) -> Vec<(String, IntervalOptions)> {
    let mut out = Vec::new();
    for path in paths(gpu) {
        if path == Path::Compute {
            for scheme in [ComputeScheme::PerTet, ComputeScheme::Binned] {
                out.push((
                    format!("compute, {}", scheme.name()),
                    IntervalOptions {
                        compute_scheme: scheme,
                        ..IntervalOptions::new(path)
                    },
                ));
            }
        } else {
            out.push((path.name().to_string(), IntervalOptions::new(path)));
        }
    }
    out
}

/// The binned scheme with lists too small for the view (tets beyond them drawn per tet, every
/// one of those through the tile pass), and with fewer tile counters than the screen has
/// tiles (every tet drawn per tet).
pub fn binned_overflow_variants(base: &IntervalOptions) -> Vec<(String, IntervalOptions)> {
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
pub fn variants(gpu: &Gpu, integrand: &Integrand, all: bool) -> Vec<(String, IntervalOptions)> {
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
                    "compute, each tet drawn by its invocation".into(),
                    IntervalOptions {
                        subgroup_draw: SubgroupDraw::Off,
                        ..base.clone()
                    },
                ));
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
pub struct Expected<'a> {
    pub reference: &'a [[f32; 3]],
    pub edges: &'a [bool],
    pub clipped: bool,
}

/// Renders `mesh` with each variant and holds every pixel away from projected edges to the
/// reference; returns how many of those pixels the mesh covers.
pub fn assert_variants_match(
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
        let snap = snap_px(gpu, options.path);
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
pub fn assert_matches_reference(
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
/// ([`assert_close`]); returns how many of them the mesh covers.
pub fn compare(
    name: &str,
    frame: &IntervalFrame,
    expected: &Expected,
    w: u32,
    snap_px: f32,
) -> usize {
    assert_eq!(
        frame.clipped_near > 0,
        expected.clipped,
        "{name}: {} tets clipped at the near plane",
        frame.clipped_near
    );
    let (compared, covered) = assert_close(
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
