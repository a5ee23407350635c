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
#[path = "volume_tests.rs"]
mod tests;
