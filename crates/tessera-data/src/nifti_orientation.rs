//! Where a NIfTI header places the grid in (RAS) world space. The sform affine
//! (`sform_code` > 0) takes precedence over the qform (`qform_code` > 0), as in the reference
//! library nifti1_io; with neither the orientation is the default.
//!
//! Leniency: an sform or qform that cannot be normalized (an axis of no length, a value that
//! is not finite) is skipped as if its code were 0, since the samples load fine without it;
//! the orientation records the first one skipped ([`Orientation::unusable`]) so that a front
//! end can say so.

use super::RawHeader;
use crate::orientation::{AnatomicalSpace, Orientation, OrientationSource};

/// The orientation the header's sform, else qform, gives.
pub(super) fn placement(raw: &RawHeader) -> Orientation {
    let sform = if raw.sform_code > 0 { sform(raw) } else { None };
    if let Some(placed) = sform {
        return placed;
    }
    let qform = if raw.qform_code > 0 { qform(raw) } else { None };
    let placed = qform.unwrap_or_default();
    let skipped = if raw.sform_code > 0 {
        Some(OrientationSource::NiftiSform)
    } else if raw.qform_code > 0 && qform.is_none() {
        Some(OrientationSource::NiftiQform)
    } else {
        None
    };
    match skipped {
        Some(declared) => placed.passing_over(declared),
        None => placed,
    }
}

/// The affine's columns are the world vectors of the grid axes, its last column the origin.
fn sform(raw: &RawHeader) -> Option<Orientation> {
    let [x, y, z] = raw.srow;
    let axes = [0, 1, 2].map(|c| [x[c], y[c], z[c]]);
    Orientation::new(
        [x[3], y[3], z[3]],
        axes,
        Some(AnatomicalSpace::Ras),
        OrientationSource::NiftiSform,
    )
}

/// The rotation of the unit quaternion (a, b, c, d), a = sqrt(1 - b² - c² - d²), with the
/// k axis reversed when `qfac` (`pixdim[0]`) is negative.
fn qform(raw: &RawHeader) -> Option<Orientation> {
    let [b, c, d] = raw.quatern;
    let norm2 = b * b + c * c + d * d;
    // As nifti1_io does: (b, c, d) of length 1 or more is a half turn (a = 0), normalized.
    let (a, b, c, d) = if 1.0 - norm2 > 1e-7 {
        ((1.0 - norm2).sqrt(), b, c, d)
    } else {
        let n = norm2.sqrt();
        (0.0, b / n, c / n, d / n)
    };
    let qfac = if raw.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
    let axes = [
        [
            a * a + b * b - c * c - d * d,
            2.0 * (b * c + a * d),
            2.0 * (b * d - a * c),
        ],
        [
            2.0 * (b * c - a * d),
            a * a + c * c - b * b - d * d,
            2.0 * (c * d + a * b),
        ],
        [
            2.0 * (b * d + a * c),
            2.0 * (c * d - a * b),
            a * a + d * d - c * c - b * b,
        ]
        .map(|v| v * qfac),
    ];
    Orientation::new(
        raw.qoffset,
        axes,
        Some(AnatomicalSpace::Ras),
        OrientationSource::NiftiQform,
    )
}
