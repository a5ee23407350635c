//! Holding interval shading's per-pixel values to the CPU reference.

use tessera::path::Path;
use tessera_gpu::Gpu;

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
