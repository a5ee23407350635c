//! The in-memory scalar volume every technique renders, and the "texel space" convention that
//! lets CPU reference code be compared with what the GPU samples.
//!
//! Texel space is the raw sample value as `f32`: `u8` spans 0..255, `u16` 0..65535 and `f32`
//! is unchanged. The GPU fetches integer data from `R8_UINT`/`R16_UINT` textures through a
//! `usampler3D` and converts with `float()`, which is exact, so CPU and GPU agree bit for bit.
//! (Normalizing by 255 or 65535 is deliberately avoided: a division on the GPU is not
//! correctly rounded.)

use rayon::prelude::*;

use crate::error::{DataError, Result};
use crate::orientation::Orientation;

/// Sample types kept on the GPU. Anything else is converted to `F32` by the loaders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ScalarType {
    U8,
    U16,
    F32,
}

impl ScalarType {
    pub fn size_bytes(self) -> usize {
        match self {
            ScalarType::U8 => 1,
            ScalarType::U16 => 2,
            ScalarType::F32 => 4,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ScalarType::U8 => "uint8",
            ScalarType::U16 => "uint16",
            ScalarType::F32 => "float32",
        }
    }

    /// Parses `uint8`/`u8`, `uint16`/`u16`, `float32`/`f32`/`float` (case-insensitive).
    pub fn from_name(name: &str) -> Option<ScalarType> {
        match name.trim().to_ascii_lowercase().as_str() {
            "uint8" | "u8" => Some(ScalarType::U8),
            "uint16" | "u16" => Some(ScalarType::U16),
            "float32" | "f32" | "float" => Some(ScalarType::F32),
            _ => None,
        }
    }
}

/// Sample storage, x fastest, then y, then z.
#[derive(Clone, Debug, PartialEq)]
pub enum Samples {
    U8(Vec<u8>),
    U16(Vec<u16>),
    F32(Vec<f32>),
}

impl Samples {
    pub fn len(&self) -> usize {
        match self {
            Samples::U8(v) => v.len(),
            Samples::U16(v) => v.len(),
            Samples::F32(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn scalar_type(&self) -> ScalarType {
        match self {
            Samples::U8(_) => ScalarType::U8,
            Samples::U16(_) => ScalarType::U16,
            Samples::F32(_) => ScalarType::F32,
        }
    }
}

/// An isovalue as the user states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IsoValue {
    /// Fraction of the volume's `[min, max]` value range (0 = min, 1 = max).
    Normalized(f32),
    /// A value in the data's own units (e.g. 0..255 for uint8 data).
    Raw(f32),
}

impl IsoValue {
    /// The isovalue in the units of data whose values span `(lo, hi)`.
    pub fn in_range(self, (lo, hi): (f32, f32)) -> f32 {
        match self {
            IsoValue::Raw(r) => r,
            IsoValue::Normalized(n) => lo + n * (hi - lo),
        }
    }
}

/// What to do with NaN/Inf samples in floating-point data.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum NanPolicy {
    /// Fail with [`DataError::NonFinite`].
    #[default]
    Reject,
    /// Substitute this (finite) value for every non-finite sample.
    Replace(f32),
}

/// A validated 3-D scalar field.
///
/// Every axis has at least 2 samples, the spacing is finite and positive, and every sample is
/// finite. Non-finite samples (NaN, ±Inf) are rejected by default: construction fails with
/// [`DataError::NonFinite`], which names the source (file or volume name), how many samples
/// are bad and the first bad voxel as (x, y, z). Constructing with [`NanPolicy::Replace`]
/// fills them with the given value instead.
///
/// Values are in *raw* units (what the file stores, see [`Volume::value_range`]), and *texel
/// space* is the same scale as `f32`: what the GPU's integer (`usampler3D`) or float texture
/// fetch returns after an exact `float()` conversion (see [`Volume::texel`]). Code that
/// compares GPU output with CPU references works in texel space.
///
/// Its [`Orientation`] places the grid in the world space the file names (origin, axis
/// directions, anatomical space); volumes built in code get the default, and loaders set what
/// the header gives with [`Volume::with_orientation`].
#[derive(Clone, Debug)]
pub struct Volume {
    name: String,
    dims: [u32; 3],
    spacing: [f32; 3],
    samples: Samples,
    value_range: (f32, f32),
    orientation: Orientation,
    /// The spacing the data carried before [`Volume::with_spacing`] replaced it.
    replaced_spacing: Option<[f32; 3]>,
}

impl Volume {
    /// Validates and wraps `samples`, rejecting non-finite values.
    pub fn new(
        name: impl Into<String>,
        dims: [u32; 3],
        spacing: [f32; 3],
        samples: Samples,
    ) -> Result<Volume> {
        Self::with_nan_policy(name, dims, spacing, samples, NanPolicy::Reject)
    }

    /// Like [`Volume::new`], but `NanPolicy::Replace(v)` first substitutes `v` for every
    /// non-finite `F32` sample.
    pub fn with_nan_policy(
        name: impl Into<String>,
        dims: [u32; 3],
        spacing: [f32; 3],
        mut samples: Samples,
        policy: NanPolicy,
    ) -> Result<Volume> {
        let name = name.into();
        if dims.iter().any(|&d| d < 2) {
            return Err(DataError::InvalidDims {
                what: name,
                dims: dims.map(u64::from),
            });
        }
        let expected = dims.iter().map(|&d| d as u128).product::<u128>();
        if samples.len() as u128 != expected {
            return Err(DataError::Invalid(format!(
                "{name}: {} samples given for dimensions {}x{}x{} ({expected} needed)",
                samples.len(),
                dims[0],
                dims[1],
                dims[2]
            )));
        }
        if spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
            return Err(DataError::Invalid(format!(
                "{name}: spacing {spacing:?} must be finite and positive on every axis"
            )));
        }
        if let (NanPolicy::Replace(fill), Samples::F32(values)) = (policy, &mut samples) {
            if !fill.is_finite() {
                return Err(DataError::Invalid(format!(
                    "{name}: NaN replacement value {fill} is not finite"
                )));
            }
            values.par_iter_mut().for_each(|v| {
                if !v.is_finite() {
                    *v = fill;
                }
            });
        }
        let value_range = match &samples {
            Samples::U8(v) => int_range(v),
            Samples::U16(v) => int_range(v),
            Samples::F32(v) => float_range(v, &name, dims)?,
        };
        Ok(Volume {
            name,
            dims,
            spacing,
            samples,
            value_range,
            orientation: Orientation::default(),
            replaced_spacing: None,
        })
    }

    /// This volume placed as `orientation` says (loaders set what the file's header gives).
    pub fn with_orientation(mut self, orientation: Orientation) -> Volume {
        self.orientation = orientation;
        self
    }

    /// This volume with `spacing` in place of the spacing it has (a user's value for a file
    /// whose header says otherwise); [`Volume::replaced_spacing`] then tells what it was.
    /// The same spacing changes nothing. Fails when a value is not finite and positive.
    pub fn with_spacing(mut self, spacing: [f32; 3]) -> Result<Volume> {
        if spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
            return Err(DataError::Invalid(format!(
                "{}: spacing {spacing:?} must be finite and positive on every axis",
                self.name
            )));
        }
        if spacing != self.spacing {
            self.replaced_spacing = Some(self.replaced_spacing.unwrap_or(self.spacing));
            self.spacing = spacing;
        }
        Ok(self)
    }

    /// The spacing the file (or generator) gave, when [`Volume::with_spacing`] replaced it.
    pub fn replaced_spacing(&self) -> Option<[f32; 3]> {
        self.replaced_spacing
    }

    /// Grid point (sample `(x, y, z)` at `(x, y, z)`) to physical position: the origin plus
    /// each index times its spacing along its axis direction ([`Volume::orientation`]). Units
    /// are the file's (millimetres for medical data); without placement in the header this is
    /// spacing × index.
    pub fn grid_to_physical(&self) -> glam::Affine3A {
        let o = &self.orientation;
        let d = o.direction();
        let s = self.spacing;
        glam::Affine3A::from_cols(
            (glam::Vec3::from(d[0]) * s[0]).into(),
            (glam::Vec3::from(d[1]) * s[1]).into(),
            (glam::Vec3::from(d[2]) * s[2]).into(),
            glam::Vec3::from(o.origin()).into(),
        )
    }

    /// Where the grid lies in the file's world space; the default (identity, origin 0) when
    /// the file does not say.
    pub fn orientation(&self) -> &Orientation {
        &self.orientation
    }

    /// The grid axis pointing towards the patient's head and its sign (+1: increasing index
    /// goes up), for medical volumes whose header names an anatomical space; see
    /// [`Orientation::up_axis`].
    pub fn up_axis(&self) -> Option<(usize, i8)> {
        self.orientation.up_axis()
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    pub fn spacing(&self) -> [f32; 3] {
        self.spacing
    }

    pub fn scalar_type(&self) -> ScalarType {
        self.samples.scalar_type()
    }

    pub fn samples(&self) -> &Samples {
        &self.samples
    }

    /// `(min, max)` over all samples in raw units.
    pub fn value_range(&self) -> (f32, f32) {
        self.value_range
    }

    pub fn sample_count(&self) -> u64 {
        self.samples.len() as u64
    }

    pub fn size_bytes(&self) -> u64 {
        self.sample_count() * self.scalar_type().size_bytes() as u64
    }

    /// The samples as bytes in host order (little-endian on every GPU host we target), ready
    /// for upload.
    pub fn bytes(&self) -> &[u8] {
        match &self.samples {
            Samples::U8(v) => v,
            Samples::U16(v) => bytemuck::cast_slice(v),
            Samples::F32(v) => bytemuck::cast_slice(v),
        }
    }

    /// Linear index of voxel (x, y, z), x fastest.
    pub fn index(&self, x: u32, y: u32, z: u32) -> usize {
        debug_assert!(x < self.dims[0] && y < self.dims[1] && z < self.dims[2]);
        let [nx, ny, _] = self.dims.map(|d| d as usize);
        x as usize + nx * (y as usize + ny * z as usize)
    }

    /// The value the GPU sees for voxel (x, y, z): the raw sample as `f32` (`u8` in 0..255,
    /// `u16` in 0..65535, `f32` unchanged), exactly what `float()` of a `usampler3D` fetch
    /// gives.
    pub fn texel(&self, x: u32, y: u32, z: u32) -> f32 {
        let i = self.index(x, y, z);
        match &self.samples {
            Samples::U8(v) => f32::from(v[i]),
            Samples::U16(v) => f32::from(v[i]),
            Samples::F32(v) => v[i],
        }
    }

    /// Maps a value in raw units to texel space (same scale as [`Volume::texel`]); texel
    /// space is raw units, so this is the identity.
    pub fn raw_to_texel(&self, raw: f32) -> f32 {
        raw
    }

    /// Resolves a user isovalue to texel space (raw units); `Normalized(n)` is
    /// `min + n * (max - min)`.
    pub fn iso_to_texel(&self, iso: IsoValue) -> f32 {
        self.raw_to_texel(iso.in_range(self.value_range))
    }

    /// A warning when `iso` (raw units) lies outside the volume's values, where no surface
    /// can be found: it names the volume and its range. `None` when some surface may exist.
    pub fn isovalue_warning(&self, iso: f32) -> Option<String> {
        let (lo, hi) = self.value_range;
        // A corner is inside when its value is below the isovalue, so `lo` itself finds
        // nothing and `hi` still separates the samples below it.
        (!(iso > lo && iso <= hi)).then(|| {
            format!(
                "isovalue {iso} is outside the values of {} ({lo}..{hi}): the surface is empty",
                self.name
            )
        })
    }

    /// [`Volume::value_range`] in texel space, i.e. the same values.
    pub fn texel_range(&self) -> (f32, f32) {
        self.value_range
    }
}

fn int_range<T>(values: &[T]) -> (f32, f32)
where
    T: Copy + Ord + Into<f32> + Send + Sync,
{
    let (lo, hi) = values
        .par_iter()
        .fold(
            || (None::<T>, None::<T>),
            |(lo, hi), &v| {
                (
                    Some(lo.map_or(v, |l| l.min(v))),
                    Some(hi.map_or(v, |h| h.max(v))),
                )
            },
        )
        .reduce(
            || (None, None),
            |a, b| (opt_min(a.0, b.0), opt_max(a.1, b.1)),
        );
    // Validation guarantees at least 8 samples, so both are present.
    (lo.map_or(0.0, Into::into), hi.map_or(0.0, Into::into))
}

fn opt_min<T: Ord>(a: Option<T>, b: Option<T>) -> Option<T> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

fn opt_max<T: Ord>(a: Option<T>, b: Option<T>) -> Option<T> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    }
}

/// Range and non-finite scan in one parallel pass, since float volumes can be gigabytes.
fn float_range(values: &[f32], name: &str, dims: [u32; 3]) -> Result<(f32, f32)> {
    #[derive(Clone, Copy)]
    struct Acc {
        lo: f32,
        hi: f32,
        bad: u64,
        first_bad: usize,
    }
    let empty = || Acc {
        lo: f32::INFINITY,
        hi: f32::NEG_INFINITY,
        bad: 0,
        first_bad: usize::MAX,
    };
    let acc = values
        .par_iter()
        .enumerate()
        .fold(empty, |mut a, (i, &v)| {
            if v.is_finite() {
                a.lo = a.lo.min(v);
                a.hi = a.hi.max(v);
            } else {
                a.bad += 1;
                a.first_bad = a.first_bad.min(i);
            }
            a
        })
        .reduce(empty, |a, b| Acc {
            lo: a.lo.min(b.lo),
            hi: a.hi.max(b.hi),
            bad: a.bad + b.bad,
            first_bad: a.first_bad.min(b.first_bad),
        });
    if acc.bad > 0 {
        let plane = dims[0] as usize * dims[1] as usize;
        let i = acc.first_bad;
        let first = [
            i % dims[0] as usize,
            (i % plane) / dims[0] as usize,
            i / plane,
        ];
        return Err(DataError::NonFinite {
            path_or_name: name.to_string(),
            count: acc.bad,
            first: first.map(|c| c as u32),
        });
    }
    Ok((acc.lo, acc.hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp_u8() -> Volume {
        let v: Vec<u8> = (0..27).map(|i| (i * 9) as u8).collect();
        Volume::new("ramp", [3, 3, 3], [1.0, 2.0, 0.5], Samples::U8(v)).expect("valid")
    }

    #[test]
    fn spacing_can_be_replaced_and_says_what_it_was() {
        let v = ramp_u8();
        assert_eq!(v.replaced_spacing(), None);
        let same = v.clone().with_spacing([1.0, 2.0, 0.5]).expect("same");
        assert_eq!(same.replaced_spacing(), None);
        let v = v.with_spacing([3.0, 3.0, 3.0]).expect("new");
        assert_eq!(v.spacing(), [3.0; 3]);
        assert_eq!(v.replaced_spacing(), Some([1.0, 2.0, 0.5]));
        // A second replacement still names the data's own spacing.
        let v = v.with_spacing([4.0, 4.0, 4.0]).expect("again");
        assert_eq!(v.replaced_spacing(), Some([1.0, 2.0, 0.5]));
        for bad in [[0.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, f32::NAN]] {
            let err = ramp_u8().with_spacing(bad).expect_err("bad spacing");
            assert!(err.to_string().contains("ramp"), "{err}");
        }
    }

    #[test]
    fn grid_to_physical_applies_spacing_direction_and_origin() {
        use crate::orientation::OrientationSource;
        let v = ramp_u8();
        let p = v
            .grid_to_physical()
            .transform_point3(glam::Vec3::new(2.0, 1.0, 2.0));
        assert_eq!(p, glam::Vec3::new(2.0, 2.0, 1.0));
        // Grid x along world -y, y along world x, z along z; origin (10, 20, 30).
        let placed = Orientation::new(
            [10.0, 20.0, 30.0],
            [[0.0, -5.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            None,
            OrientationSource::Nrrd,
        )
        .expect("valid");
        let v = v.with_orientation(placed);
        let p = v
            .grid_to_physical()
            .transform_point3(glam::Vec3::new(2.0, 1.0, 2.0));
        assert!(
            (p - glam::Vec3::new(12.0, 18.0, 31.0)).length() < 1e-5,
            "{p}"
        );
    }

    #[test]
    fn isovalue_outside_the_values_is_named() {
        let v = ramp_u8();
        assert_eq!(v.isovalue_warning(100.0), None);
        assert_eq!(v.isovalue_warning(234.0), None);
        for iso in [-300.0, 0.0, 234.5, 1000.0, f32::NAN] {
            let w = v.isovalue_warning(iso).expect("warning");
            assert!(w.contains("ramp") && w.contains("0..234"), "{w}");
        }
    }

    #[test]
    fn scalar_type_names_and_sizes() {
        assert_eq!(ScalarType::U8.name(), "uint8");
        assert_eq!(ScalarType::U16.name(), "uint16");
        assert_eq!(ScalarType::F32.name(), "float32");
        assert_eq!(ScalarType::U16.size_bytes(), 2);
        assert_eq!(ScalarType::from_name("F32"), Some(ScalarType::F32));
        assert_eq!(ScalarType::from_name("int8"), None);
    }

    #[test]
    fn accessors_and_indexing() {
        let v = ramp_u8();
        assert_eq!(v.name(), "ramp");
        assert_eq!(v.dims(), [3, 3, 3]);
        assert_eq!(v.spacing(), [1.0, 2.0, 0.5]);
        assert_eq!(v.scalar_type(), ScalarType::U8);
        assert_eq!(v.sample_count(), 27);
        assert_eq!(v.size_bytes(), 27);
        assert_eq!(v.bytes().len(), 27);
        assert_eq!(v.index(1, 2, 1), 1 + 3 * (2 + 3));
        assert_eq!(v.value_range(), (0.0, 234.0));
        assert_eq!(v.texel(2, 2, 2), 234.0);
        assert_eq!(v.texel(1, 0, 0), 9.0);
        assert_eq!(v.texel_range(), (0.0, 234.0));
    }

    #[test]
    fn orientation_defaults_and_can_be_set() {
        use crate::orientation::{AnatomicalSpace, OrientationSource};
        let v = ramp_u8();
        assert_eq!(v.orientation(), &Orientation::default());
        assert_eq!(v.up_axis(), None);
        let coronal = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]];
        let placed = Orientation::new(
            [1.0, 2.0, 3.0],
            coronal,
            Some(AnatomicalSpace::Ras),
            OrientationSource::NiftiSform,
        )
        .expect("valid");
        let v = v.with_orientation(placed);
        assert_eq!(v.orientation().origin(), [1.0, 2.0, 3.0]);
        assert_eq!(v.up_axis(), Some((1, 1)));
        // The samples are untouched.
        assert_eq!(v.texel(1, 0, 0), 9.0);
    }

    #[test]
    fn texel_space_conversions() {
        let u16s: Vec<u16> = (0..8).map(|i| i * 1000).collect();
        let v = Volume::new("w", [2, 2, 2], [1.0; 3], Samples::U16(u16s)).expect("valid");
        assert_eq!(v.bytes().len(), 16);
        assert_eq!(v.size_bytes(), 16);
        assert_eq!(v.texel(1, 1, 1), 7000.0);
        assert_eq!(v.raw_to_texel(65535.0), 65535.0);
        assert_eq!(v.texel_range(), (0.0, 7000.0));
        // Normalized 0.5 of [0, 7000] is 3500 raw, which is also its texel value.
        assert_eq!(v.iso_to_texel(IsoValue::Normalized(0.5)), 3500.0);
        assert_eq!(v.iso_to_texel(IsoValue::Normalized(0.0)), 0.0);
        assert_eq!(v.iso_to_texel(IsoValue::Normalized(1.0)), 7000.0);
        assert_eq!(v.iso_to_texel(IsoValue::Raw(100.0)), 100.0);

        let full: Vec<u16> = vec![0, 1, 2, 3, 4, 5, 6, 65535];
        let v = Volume::new("full", [2, 2, 2], [1.0; 3], Samples::U16(full)).expect("valid");
        assert_eq!(v.texel(1, 1, 1), 65535.0);
        assert_eq!(v.texel_range(), (0.0, 65535.0));

        let f: Vec<f32> = (0..8).map(|i| i as f32 - 2.0).collect();
        let v = Volume::new("f", [2, 2, 2], [1.0; 3], Samples::F32(f)).expect("valid");
        assert_eq!(v.value_range(), (-2.0, 5.0));
        assert_eq!(v.texel_range(), (-2.0, 5.0));
        assert_eq!(v.iso_to_texel(IsoValue::Normalized(1.0)), 5.0);
        assert_eq!(v.texel(1, 0, 0), -1.0);
    }

    #[test]
    fn rejects_bad_dims_len_and_spacing() {
        let err = Volume::new("thin", [4, 1, 4], [1.0; 3], Samples::U8(vec![0; 16])).unwrap_err();
        assert!(matches!(err, DataError::InvalidDims { .. }), "{err}");
        assert!(err.to_string().contains("thin"));

        let err = Volume::new("short", [2, 2, 2], [1.0; 3], Samples::U8(vec![0; 7])).unwrap_err();
        assert!(matches!(err, DataError::Invalid(_)), "{err}");
        assert!(err.to_string().contains("short"));

        for bad in [0.0, -1.0, f32::NAN] {
            let err = Volume::new("sp", [2, 2, 2], [1.0, bad, 1.0], Samples::U8(vec![0; 8]));
            assert!(matches!(err, Err(DataError::Invalid(_))));
        }
    }

    #[test]
    fn non_finite_rejected_with_first_voxel() {
        let mut f = vec![0.5f32; 4 * 3 * 2];
        f[1 + 4 * (2 + 3)] = f32::NAN; // voxel (1, 2, 1)
        f[23] = f32::INFINITY;
        let err = Volume::new("nanvol", [4, 3, 2], [1.0; 3], Samples::F32(f.clone())).unwrap_err();
        match &err {
            DataError::NonFinite { count, first, .. } => {
                assert_eq!(*count, 2);
                assert_eq!(*first, [1, 2, 1]);
            }
            other => panic!("unexpected {other}"),
        }
        assert!(err.to_string().contains("nanvol"));

        let v = Volume::with_nan_policy(
            "nanvol",
            [4, 3, 2],
            [1.0; 3],
            Samples::F32(f),
            NanPolicy::Replace(-1.0),
        )
        .expect("replaced");
        assert_eq!(v.texel(1, 2, 1), -1.0);
        assert_eq!(v.value_range(), (-1.0, 0.5));

        let err = Volume::with_nan_policy(
            "n",
            [2, 2, 2],
            [1.0; 3],
            Samples::F32(vec![0.0; 8]),
            NanPolicy::Replace(f32::NAN),
        );
        assert!(matches!(err, Err(DataError::Invalid(_))));
    }

    #[test]
    fn default_policy_is_reject() {
        assert_eq!(NanPolicy::default(), NanPolicy::Reject);
    }
}
