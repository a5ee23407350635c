//! Where a volume's grid lies in the space its file refers to: the world position of voxel
//! (0, 0, 0), the world direction of each grid axis and, for medical data, which anatomical
//! space the world axes are. Spacing stays on [`crate::Volume`]; directions here are unit
//! vectors.

/// Which header fields an [`Orientation`] came from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OrientationSource {
    /// The file says nothing (or nothing usable): grid axes are world x, y, z, origin 0.
    #[default]
    Default,
    /// NRRD `space directions` and `space origin` (and `space`, naming the space).
    Nrrd,
    /// NIfTI sform (`sform_code` > 0): an affine matrix.
    NiftiSform,
    /// NIfTI qform (`qform_code` > 0, no sform): quaternion, `qfac` and offsets.
    NiftiQform,
    /// VTK image data's `Origin` and `Direction` (VTK names no anatomical space).
    Vti,
    /// A voxel-to-world affine given with an array (nibabel's `img.affine`, RAS+ like NIfTI).
    Affine,
}

impl OrientationSource {
    /// The header fields, as a message names them.
    pub fn name(self) -> &'static str {
        match self {
            OrientationSource::Default => "no placement",
            OrientationSource::Nrrd => "NRRD space directions and origin",
            OrientationSource::NiftiSform => "NIfTI sform",
            OrientationSource::NiftiQform => "NIfTI qform",
            OrientationSource::Vti => "VTK Origin and Direction",
            OrientationSource::Affine => "the given affine",
        }
    }
}

/// The patient-based space a medical file's world axes are in, named by where +x, +y and +z
/// point (RAS: +x right, +y anterior, +z superior).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnatomicalSpace {
    /// Right, anterior, superior: NIfTI's space, and NRRD's `right-anterior-superior`.
    Ras,
    /// Left, anterior, superior (NRRD `left-anterior-superior`).
    Las,
    /// Left, posterior, superior: DICOM's space (NRRD `left-posterior-superior`).
    Lps,
}

impl AnatomicalSpace {
    /// A NRRD `space` value: long or short names, with or without a time axis, any case.
    /// `None` for spaces that are not anatomical (`scanner-xyz`, `3D-right-handed`, ...).
    pub fn from_nrrd(value: &str) -> Option<AnatomicalSpace> {
        let name = value.trim().to_ascii_lowercase();
        let name = name
            .strip_suffix("-time")
            .or_else(|| (name.len() == 4).then(|| name.strip_suffix('t')).flatten())
            .unwrap_or(&name);
        match name {
            "right-anterior-superior" | "ras" => Some(AnatomicalSpace::Ras),
            "left-anterior-superior" | "las" => Some(AnatomicalSpace::Las),
            "left-posterior-superior" | "lps" => Some(AnatomicalSpace::Lps),
            _ => None,
        }
    }

    /// The world axis (0 = x, 1 = y, 2 = z) and sign pointing towards the patient's head.
    pub fn superior(self) -> (usize, f32) {
        // Every space above names +z superior; they differ in x and y only.
        (2, 1.0)
    }
}

/// The placement of a volume's grid in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientation {
    origin: [f32; 3],
    /// Column `i` is the unit world direction of grid axis `i`.
    direction: [[f32; 3]; 3],
    space: Option<AnatomicalSpace>,
    source: OrientationSource,
    /// A placement the header declared but that could not be used (an axis of no length, a
    /// value that is not finite), passed over for `source`.
    unusable: Option<OrientationSource>,
}

impl Default for Orientation {
    fn default() -> Self {
        Orientation {
            origin: [0.0; 3],
            direction: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            space: None,
            source: OrientationSource::Default,
            unusable: None,
        }
    }
}

impl Orientation {
    /// An orientation from the world origin and the world vectors of the three grid axes
    /// (any length: they are normalized). `None` when a value is not finite or an axis has no
    /// length, so that loaders can fall back to the default.
    pub fn new(
        origin: [f64; 3],
        axes: [[f64; 3]; 3],
        space: Option<AnatomicalSpace>,
        source: OrientationSource,
    ) -> Option<Orientation> {
        if !origin.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mut direction = [[0f32; 3]; 3];
        for (out, axis) in direction.iter_mut().zip(axes) {
            let length = axis.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !length.is_finite() || length == 0.0 {
                return None;
            }
            *out = axis.map(|v| (v / length) as f32);
        }
        Some(Orientation {
            origin: origin.map(|v| v as f32),
            direction,
            space,
            source,
            unusable: None,
        })
    }

    /// The placement and voxel spacing of a voxel-to-world affine in NIfTI's RAS+ world, as
    /// nibabel gives it (`img.affine`): rows are world x, y, z; columns 0-2 the world vectors
    /// of the grid axes (their lengths the spacing), column 3 the origin. `None` when a value
    /// is not finite or an axis has no length.
    pub fn from_affine(rows: [[f64; 4]; 3]) -> Option<(Orientation, [f32; 3])> {
        let axis = |i: usize| [rows[0][i], rows[1][i], rows[2][i]];
        let axes = [axis(0), axis(1), axis(2)];
        let spacing = axes.map(|a| a.iter().map(|v| v * v).sum::<f64>().sqrt() as f32);
        let orientation = Orientation::new(
            axis(3),
            axes,
            Some(AnatomicalSpace::Ras),
            OrientationSource::Affine,
        )?;
        spacing
            .iter()
            .all(|s| s.is_finite() && *s > 0.0)
            .then_some((orientation, spacing))
    }

    /// The same placement, noting that the header's `declared` placement was passed over.
    pub fn passing_over(mut self, declared: OrientationSource) -> Orientation {
        self.unusable = Some(declared);
        self
    }

    /// The placement the header declared but that could not be used, if any: the volume is
    /// placed by [`Orientation::source`] instead, and a front end should say so.
    pub fn unusable(&self) -> Option<OrientationSource> {
        self.unusable
    }

    /// World position of the centre of voxel (0, 0, 0).
    pub fn origin(&self) -> [f32; 3] {
        self.origin
    }

    /// The direction matrix by columns: `direction()[i]` is the unit world vector of grid
    /// axis `i` (0 = x, the fastest in memory).
    pub fn direction(&self) -> [[f32; 3]; 3] {
        self.direction
    }

    /// The anatomical space of the world axes, when the file names one.
    pub fn space(&self) -> Option<AnatomicalSpace> {
        self.space
    }

    /// Which header fields this came from.
    pub fn source(&self) -> OrientationSource {
        self.source
    }

    /// The grid axis (0, 1 or 2) that points most nearly towards the patient's head, and
    /// whether increasing indices along it go up (+1) or down (-1); `None` unless the file
    /// names an anatomical space. A viewer turns this axis up on screen.
    pub fn up_axis(&self) -> Option<(usize, i8)> {
        let (world_axis, world_sign) = self.space?.superior();
        let (axis, along) = self
            .direction
            .iter()
            .map(|column| column[world_axis] * world_sign)
            .enumerate()
            .fold((0, 0.0f32), |best, (i, v)| {
                if v.abs() > best.1.abs() {
                    (i, v)
                } else {
                    best
                }
            });
        (along != 0.0).then_some((axis, if along > 0.0 { 1 } else { -1 }))
    }
}

#[cfg(test)]
#[path = "orientation_tests.rs"]
mod tests;
