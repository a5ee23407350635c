//! The binned compute path of interval shading beyond what `tests/interval.rs` holds every
//! variant to (there the binned scheme meets the exact references, with lists too small and
//! too few tile counters too): lists that overflowed grow for the next frame, which then bins
//! every tet and draws the same image.

mod common;

use common::{assert_clean, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{
    BinCapacity, ComputeScheme, GpuTetMesh, Interval, IntervalFrame, IntervalOptions,
};
use tessera_data::tet::procedural::sphere_mesh;
use tessera_data::OrbitCamera;

/// Every pixel of `a` within a relative 1e-4 of `b` (the sums' order differs); returns how
/// many pixels hold something.
fn assert_same_values(name: &str, a: &IntervalFrame, b: &IntervalFrame) -> usize {
    assert_eq!(a.values.len(), b.values.len());
    let mut covered = 0;
    for (i, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
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
    let per_tet =
        render(&Interval::new(&gpu, &compiler, &IntervalOptions::new(Path::Compute)).unwrap());
    let small = BinCapacity {
        entries: 16,
        ..BinCapacity::default()
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
    assert!(first.unbinned > 0, "16 entries must not hold the sphere");
    assert!(binned.grow_buffers(&gpu, (w, h)).unwrap());
    let grown = binned.bin_capacity().unwrap();
    assert!(grown.entries > small.entries, "{grown:?}");
    let second = render(&binned);
    assert_eq!(second.unbinned, 0, "the grown lists hold every tet");
    assert!(!binned.grow_buffers(&gpu, (w, h)).unwrap());
    assert_eq!(binned.bin_capacity(), Some(grown));
    let covered = assert_same_values("overflowed frame", &first, &per_tet);
    assert_same_values("grown frame", &second, &per_tet);
    assert!(covered > (w * h / 4) as usize, "{covered} pixels covered");
    assert_clean(&gpu);
}
