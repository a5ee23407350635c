//! The binned compute path of interval shading beyond what `tests/interval.rs` holds every
//! variant to (there the binned scheme meets the exact references, with lists too small and
//! too few tile counters too): lists that overflowed grow for the next frame, which then bins
//! every tet and draws the same image; sorted lists give the same sums every frame; a tile
//! holding more tets than it sorts still draws them all; a tet is listed in the tiles its
//! proxies touch, not every tile of its rectangle, unless that is large.

mod common;

use common::{assert_clean, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::binned::{BIN_SORT_CAPACITY, BIN_TESTED_TILES};
use tessera::tet::interval::{
    BinCapacity, ComputeScheme, GpuTetMesh, Interval, IntervalFrame, IntervalOptions,
};
use tessera_data::tet::procedural::{box_mesh, sphere_mesh};
use tessera_data::tet::TetMesh;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

fn assert_same_values(name: &str, a: &IntervalFrame, b: &IntervalFrame) -> usize {
    common::interval::assert_same_sums(name, &a.values, &b.values)
}

#[test]
fn overflowing_lists_grow_and_the_next_frame_bins_every_tet() {
    let gpu = gpu();
    if !gpu.caps().buffer_float32_atomic_add {
        skip("", "no float atomics for the compute path");
        return;
    }
    let compiler = shaders::compiler();
    let mesh = GpuTetMesh::upload(&gpu, &sphere_mesh(4)).unwrap();
    let (w, h) = (64, 48);
    let cam = OrbitCamera {
        azimuth_deg: 20.0,
        elevation_deg: 10.0,
        distance: 2.0,
        ..OrbitCamera::default()
    };
    let render = |interval: &Interval| {
        let target = interval.target(&gpu, w, h).unwrap();
        interval.render(&gpu, &mesh, &target, &cam).unwrap()
    };
    let per_tet = render(&Interval::new(&gpu, &compiler, &per_tet_options()).unwrap());
    // Too few entries, and too few tile counters for the screen's 4 × 3 tiles.
    let small = BinCapacity {
        entries: 16,
        tiles: 3,
    };
    let mut binned = Interval::new(
        &gpu,
        &compiler,
        &IntervalOptions {
            compute_scheme: ComputeScheme::Binned,
            bin_capacity: small,
            ..IntervalOptions::new(Path::Compute)
        },
    )
    .unwrap();
    let first = render(&binned);
    assert!(
        first.unbinned > 0,
        "the small bins must not hold the sphere"
    );
    assert!(binned.grow_buffers(&gpu, (w, h)).unwrap());
    let grown = binned.bin_capacity().unwrap();
    assert!(grown.entries > small.entries, "{grown:?}");
    assert!(grown.tiles >= 12, "{grown:?}");
    let second = render(&binned);
    assert_eq!(second.unbinned, 0, "the grown lists hold every tet");
    assert!(!binned.grow_buffers(&gpu, (w, h)).unwrap());
    assert_eq!(binned.bin_capacity(), Some(grown));
    let covered = assert_same_values("overflowed frame", &first, &per_tet);
    assert_same_values("grown frame", &second, &per_tet);
    assert!(covered > (w * h / 4) as usize, "{covered} pixels covered");
    assert_clean(&gpu);
}

fn per_tet_options() -> IntervalOptions {
    IntervalOptions {
        compute_scheme: ComputeScheme::PerTet,
        ..IntervalOptions::new(Path::Compute)
    }
}

fn binned_options() -> IntervalOptions {
    IntervalOptions {
        compute_scheme: ComputeScheme::Binned,
        ..IntervalOptions::new(Path::Compute)
    }
}

/// Frames of `mesh` seen from `distance`: per tet, then binned twice.
fn per_tet_and_binned_twice(
    gpu: &Gpu,
    mesh: &TetMesh,
    distance: f32,
    (w, h): (u32, u32),
) -> [IntervalFrame; 3] {
    let compiler = shaders::compiler();
    let gpu_mesh = GpuTetMesh::upload(gpu, mesh).unwrap();
    let cam = OrbitCamera {
        azimuth_deg: -30.0,
        elevation_deg: 25.0,
        distance,
        ..OrbitCamera::default()
    };
    let per_tet = Interval::new(gpu, &compiler, &per_tet_options()).unwrap();
    let binned = Interval::new(gpu, &compiler, &binned_options()).unwrap();
    let render = |interval: &Interval| {
        let target = interval.target(gpu, w, h).unwrap();
        interval.render(gpu, &gpu_mesh, &target, &cam).unwrap()
    };
    [render(&per_tet), render(&binned), render(&binned)]
}

#[test]
fn sorted_lists_give_the_same_sums_every_frame() {
    let gpu = gpu();
    if !gpu.caps().buffer_float32_atomic_add {
        skip("", "no float atomics for the compute path");
        return;
    }
    // From inside, so that tiles hold tets of every size, clipped ones too; enough entries
    // that the scatter's order varies from frame to frame (unsorted, the frames differ).
    let [per_tet, first, second] = per_tet_and_binned_twice(&gpu, &box_mesh(8), 0.3, (64, 48));
    assert_eq!(first.unbinned, 0);
    assert!(first.clipped_near > 0);
    assert_eq!(first.values, second.values, "two binned frames differ");
    let covered = assert_same_values("binned against per tet", &first, &per_tet);
    assert_eq!(covered, first.values.len(), "the eye is inside the box");
    assert_clean(&gpu);
}

#[test]
fn a_tile_holding_more_tets_than_it_sorts_draws_them_all() {
    let gpu = gpu();
    if !gpu.caps().buffer_float32_atomic_add {
        skip("", "no float atomics for the compute path");
        return;
    }
    // 3,072 tets on one 16 × 16 tile.
    let mesh = box_mesh(8);
    assert!(mesh.tets.len() > BIN_SORT_CAPACITY as usize);
    let [per_tet, binned, _] = per_tet_and_binned_twice(&gpu, &mesh, 2.4, (16, 16));
    assert_eq!(binned.unbinned, 0);
    let covered = assert_same_values("binned against per tet", &binned, &per_tet);
    assert!(covered > 100, "{covered} pixels covered");
    assert_clean(&gpu);
}

/// One tet whose projection is a triangle (`tests/interval.rs`'s case 1), about half of its
/// bounding rectangle, seen from `distance` on a `size` × `size` image: checks the binned frame
/// against the per-tet one and returns the entries listed, the tiles holding a covered pixel
/// and those of the covered pixels' bounding rectangle.
fn one_tet_listed(distance: f32, size: u32) -> Option<(usize, usize, usize)> {
    let gpu = gpu();
    if !gpu.caps().buffer_float32_atomic_add {
        skip("", "no float atomics for the compute path");
        return None;
    }
    let vertices = vec![
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.1, -0.2, 1.0],
    ];
    let mesh = TetMesh::new(vertices, vec![[0, 1, 2, 3]]);
    let [per_tet, binned, _] = per_tet_and_binned_twice(&gpu, &mesh, distance, (size, size));
    assert_same_values("binned against per tet", &binned, &per_tet);
    let tile = |i: usize| ((i as u32 % size) / 16, (i as u32 / size) / 16);
    let touched: std::collections::BTreeSet<(u32, u32)> = (0..per_tet.values.len())
        .filter(|&i| per_tet.values[i][0] > 0.0)
        .map(tile)
        .collect();
    let (xs, ys): (Vec<u32>, Vec<u32>) = touched.iter().copied().unzip();
    let span = |v: &[u32]| v.iter().max().unwrap() - v.iter().min().unwrap() + 1;
    let rectangle = (span(&xs) * span(&ys)) as usize;
    assert_clean(&gpu);
    Some((binned.bin_entries as usize, touched.len(), rectangle))
}

#[test]
fn a_tet_is_listed_in_the_tiles_its_proxies_touch() {
    let Some((entries, touched, rectangle)) = one_tet_listed(2.5, 96) else {
        return;
    };
    assert!(
        entries >= touched && entries < rectangle,
        "{entries} entries: {touched} tiles touched, {rectangle} in the rectangle"
    );
}

#[test]
fn a_tet_spanning_many_tiles_is_listed_in_its_whole_rectangle() {
    // More tiles than the counting pass tests one by one.
    let Some((entries, touched, rectangle)) = one_tet_listed(1.6, 192) else {
        return;
    };
    assert!(rectangle > BIN_TESTED_TILES as usize, "{rectangle} tiles");
    assert!(
        entries >= rectangle && entries > touched,
        "{entries} entries: {touched} tiles touched, {rectangle} in the rectangle"
    );
}
