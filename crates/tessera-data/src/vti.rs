//! VTK XML image data (`.vti`) as a volume: `WholeExtent`, `Spacing`, `Origin` and
//! `Direction` of the `<ImageData>`, and one point-data array per `<Piece>`, in any
//! encoding VTK writes (see [`crate::vtk_xml`]).
//!
//! The scalars are the array the `PointData`'s `Scalars` attribute names, else its first
//! one-component array. `UInt8` and `UInt16` samples stay as they are; every other type
//! becomes `f32` (as in [`crate::raw`]). Pieces are placed by their `Extent` and must
//! together cover the whole extent.
//!
//! The volume carries the placement as its [`Orientation`] (the first sample's position and
//! the axis directions); [`VtiImage`] also gives the file's own `Origin` and `Direction`.

use std::path::Path;

use crate::error::Result;
use crate::orientation::{Orientation, OrientationSource};
use crate::sample_data::sample_count;
use crate::tet::read_file;
use crate::volume::{NanPolicy, Samples, Volume};
use crate::vtk_xml::{Contents, DataType, Need, VtkXml};

/// A `.vti` volume and where it sits.
#[derive(Clone, Debug)]
pub struct VtiImage {
    pub volume: Volume,
    /// Position of the first sample.
    pub origin: [f64; 3],
    /// The `Direction` matrix by rows, as the file lists it (identity when absent): sample
    /// `(i, j, k)` lies at `origin + direction · (i·sx, j·sy, k·sz)`, so its columns are the
    /// directions of the sample axes.
    pub direction: [[f64; 3]; 3],
}

/// Loads the volume of a `.vti` file.
pub fn load_vti(path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    read_vti(path, nan_policy).map(|image| image.volume)
}

/// Loads a `.vti` file with its origin and direction.
pub fn read_vti(path: &Path, nan_policy: NanPolicy) -> Result<VtiImage> {
    parse_bytes(&read_file(path)?, path, nan_policy)
}

/// Parses the bytes of a `.vti` file; `path` names the file in errors and the volume.
pub fn parse_bytes(data: &[u8], path: &Path, nan_policy: NanPolicy) -> Result<VtiImage> {
    let file = VtkXml::open(data, path, "ImageData", "a volume (VTK XML image data)")?;
    let image = file
        .child(file.root(), "ImageData")
        .ok_or_else(|| file.err(file.root(), "no <ImageData> in the VTKFile"))?;
    let whole = extent(&file, image, "WholeExtent")?;
    let origin: [f64; 3] = numbers(&file, image, "Origin", "0 0 0")?;
    let spacing: [f64; 3] = numbers(&file, image, "Spacing", "1 1 1")?;
    let direction: [f64; 9] = numbers(&file, image, "Direction", "1 0 0 0 1 0 0 0 1")?;
    let direction = [0, 1, 2].map(|r| [0, 1, 2].map(|c| direction[3 * r + c]));

    let dims = whole.dims();
    let total = sample_count(path, dims)?;
    let mut pieces = Vec::new();
    let mut covered = 0usize;
    for p in file.children(image, "Piece") {
        let (piece, samples) = read_piece(&file, path, p, whole)?;
        covered = covered.saturating_add(samples.len());
        pieces.push((piece, samples));
    }
    // Pieces of point data share their boundary planes, so together they hold at least
    // the whole grid; checked before the whole grid is allocated.
    if covered < total {
        return Err(file.err(
            image,
            format!("the pieces do not cover WholeExtent {whole}"),
        ));
    }
    let samples = assemble(pieces, whole, total);
    let name = path
        .file_stem()
        .map_or_else(|| "volume".into(), |s| s.to_string_lossy().into_owned());
    let volume =
        Volume::with_nan_policy(name, dims, spacing.map(|s| s as f32), samples, nan_policy)
            .map_err(|e| e.in_file(path))?;
    // The grid's first sample sits at the extent's lower corner, not at `Origin`.
    let columns = [0, 1, 2].map(|c| [0, 1, 2].map(|r| direction[r][c]));
    let first = [0, 1, 2].map(|r| {
        origin[r]
            + (0..3)
                .map(|c| direction[r][c] * whole.lo[c] as f64 * spacing[c])
                .sum::<f64>()
    });
    let volume = match Orientation::new(first, columns, None, OrientationSource::Vti) {
        Some(placed) => volume.with_orientation(placed),
        None => {
            volume.with_orientation(Orientation::default().passing_over(OrientationSource::Vti))
        }
    };
    Ok(VtiImage {
        volume,
        origin,
        direction,
    })
}

/// The extent and samples of `<Piece>` `p`.
fn read_piece(file: &VtkXml, path: &Path, p: usize, whole: Extent) -> Result<(Extent, Samples)> {
    let piece = extent(file, p, "Extent")?;
    if (0..3).any(|a| piece.lo[a] < whole.lo[a] || piece.hi[a] > whole.hi[a]) {
        return Err(file.err(
            p,
            format!("piece Extent {piece} lies outside WholeExtent {whole}"),
        ));
    }
    let array = *file
        .scalar_candidates(p, "PointData")?
        .first()
        .ok_or_else(|| {
            file.err(
                p,
                "<Piece> has no one-component point data array to take as the volume's samples",
            )
        })?;
    let source = format!("the piece Extent {piece}");
    let need = Need {
        tuples: sample_count(path, piece.dims())?,
        components: 1,
        source: &source,
    };
    let ty = file.data_type(array)?;
    let samples = to_samples(ty, file.contents(array, need)?, file.big_endian())
        .ok_or_else(|| file.array_err(array, format!("an ascii value does not fit {ty:?}")))?;
    Ok((piece, samples))
}

/// `N` finite numbers of attribute `name` of element `index`, `default` when it is absent.
fn numbers<const N: usize>(
    file: &VtkXml,
    index: usize,
    name: &str,
    default: &str,
) -> Result<[f64; N]> {
    let text = file.element(index).attr(name).unwrap_or(default);
    let values = text
        .split_whitespace()
        .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| file.err(index, format!("{name}={text:?} is not a list of numbers")))?;
    values.as_slice().try_into().map_err(|_| {
        file.err(
            index,
            format!("{name} needs {N} numbers, found {}", values.len()),
        )
    })
}

/// An inclusive index range per axis, as VTK states extents.
#[derive(Clone, Copy)]
struct Extent {
    lo: [i64; 3],
    hi: [i64; 3],
}

impl Extent {
    fn dims(&self) -> [u32; 3] {
        [0, 1, 2].map(|a| (self.hi[a] - self.lo[a] + 1) as u32)
    }
}

impl std::fmt::Display for Extent {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let [a, b, c] = self.lo;
        let [x, y, z] = self.hi;
        write!(f, "\"{a} {x} {b} {y} {c} {z}\"")
    }
}

fn extent(file: &VtkXml, element: usize, name: &str) -> Result<Extent> {
    let text = file.element(element).attr(name).unwrap_or("");
    let v: Vec<i64> = text
        .split_whitespace()
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| file.err(element, format!("{name}={text:?} is not six integers")))?;
    let [x0, x1, y0, y1, z0, z1] = v[..] else {
        return Err(file.err(element, format!("{name}={text:?} is not six integers")));
    };
    let e = Extent {
        lo: [x0, y0, z0],
        hi: [x1, y1, z1],
    };
    if (0..3).any(|a| e.hi[a] < e.lo[a] || e.hi[a] - e.lo[a] >= i64::from(u32::MAX)) {
        return Err(file.err(element, format!("{name} {e} is empty or too large")));
    }
    Ok(e)
}

/// The whole grid from its pieces; pieces of different types meet as `f32`.
fn assemble(mut pieces: Vec<(Extent, Samples)>, whole: Extent, total: usize) -> Samples {
    if let [(piece, _)] = pieces.as_slice() {
        if piece.lo == whole.lo && piece.hi == whole.hi {
            return pieces.remove(0).1;
        }
    }
    let first = pieces[0].1.scalar_type();
    if pieces.iter().any(|(_, s)| s.scalar_type() != first) {
        for (_, samples) in &mut pieces {
            *samples = Samples::F32(widen(samples));
        }
    }
    let mut out = match &pieces[0].1 {
        Samples::U8(_) => Samples::U8(vec![0; total]),
        Samples::U16(_) => Samples::U16(vec![0; total]),
        Samples::F32(_) => Samples::F32(vec![0.0; total]),
    };
    let [nx, ny, _] = whole.dims().map(|d| d as usize);
    for (piece, samples) in &pieces {
        let [px, py, pz] = piece.dims().map(|d| d as usize);
        let at = |a: usize| (piece.lo[a] - whole.lo[a]) as usize;
        for z in 0..pz {
            for y in 0..py {
                let src = (z * py + y) * px..(z * py + y + 1) * px;
                let dst = ((at(2) + z) * ny + at(1) + y) * nx + at(0);
                let dst = dst..dst + px;
                match (&mut out, samples) {
                    (Samples::U8(d), Samples::U8(s)) => d[dst].copy_from_slice(&s[src]),
                    (Samples::U16(d), Samples::U16(s)) => d[dst].copy_from_slice(&s[src]),
                    (Samples::F32(d), Samples::F32(s)) => d[dst].copy_from_slice(&s[src]),
                    _ => unreachable!("pieces were brought to one type"),
                }
            }
        }
    }
    out
}

fn widen(samples: &Samples) -> Vec<f32> {
    match samples {
        Samples::U8(v) => v.iter().map(|&x| f32::from(x)).collect(),
        Samples::U16(v) => v.iter().map(|&x| f32::from(x)).collect(),
        Samples::F32(v) => v.clone(),
    }
}

/// Samples of one array: `UInt8` and `UInt16` kept, everything else as `f32`. `None` when
/// an ascii value does not fit the array's type.
fn to_samples(ty: DataType, values: Contents, big_endian: bool) -> Option<Samples> {
    Some(match (ty, values) {
        (DataType::UInt8, Contents::Binary(bytes)) => Samples::U8(bytes),
        (DataType::UInt16, Contents::Binary(bytes)) => Samples::U16(
            bytes
                .chunks_exact(2)
                .map(|b| {
                    let b = [b[0], b[1]];
                    if big_endian {
                        u16::from_be_bytes(b)
                    } else {
                        u16::from_le_bytes(b)
                    }
                })
                .collect(),
        ),
        (_, Contents::Binary(bytes)) => Samples::F32(
            bytes
                .chunks_exact(ty.size())
                .map(|c| ty.value(c, big_endian) as f32)
                .collect(),
        ),
        (DataType::UInt8, Contents::Text(v)) => Samples::U8(
            v.iter()
                .map(|&x| (x.fract() == 0.0 && (0.0..=255.0).contains(&x)).then_some(x as u8))
                .collect::<Option<_>>()?,
        ),
        (DataType::UInt16, Contents::Text(v)) => Samples::U16(
            v.iter()
                .map(|&x| (x.fract() == 0.0 && (0.0..=65535.0).contains(&x)).then_some(x as u16))
                .collect::<Option<_>>()?,
        ),
        (_, Contents::Text(v)) => Samples::F32(v.iter().map(|&x| x as f32).collect()),
    })
}

#[cfg(test)]
#[path = "vti_tests.rs"]
mod tests;
