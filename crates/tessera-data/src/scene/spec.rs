//! Which kind of data a spec names, and the volume and tet-mesh specs.

use std::path::Path;

use super::{DataKind, TetData};
use crate::error::{DataError, Result};
use crate::raw::{parse_scivis_name, scalar_from_name, RawOptions, SourceType};
use crate::sniff::{sniff, Sniffed};
use crate::tet::asteroids::asteroid_field;
use crate::tet::{load_tet_mesh, procedural as tet_procedural};
use crate::volume::Volume;
use crate::{load, procedural};

/// Extensions of the tetrahedral mesh files [`load_tet_mesh`] reads.
pub const MESH_EXTENSIONS: &[&str] = &["vtu", "vtk", "node", "ele", "msh"];

/// Largest `N` of `tets:box:N` / `tets:sphere:N` (N³ cells of 6 tets: 48 million tets).
pub const MAX_MESH_N: u32 = 200;
/// Most asteroids of `tets:asteroids:COUNT`.
pub const MAX_ASTEROIDS: u32 = 4_000_000;

impl DataKind {
    /// Parametric scenes (`param:`, `sh:`, `procedural:sh-glyphs:`, `*.glsl`), then tet meshes
    /// (`tets:`, mesh file extensions, or a file whose content is a mesh format although its
    /// extension names no format), and everything else is a volume. Parametric comes first
    /// because `procedural:sh-glyphs:` would otherwise read as a procedural volume.
    pub fn of_spec(spec: &str) -> DataKind {
        if spec.starts_with("param:")
            || spec.starts_with("sh:")
            || spec.starts_with("procedural:sh-glyphs:")
            || is_user_function(spec)
        {
            DataKind::Param
        } else if spec.starts_with("tets:") || has_mesh_extension(spec) || holds_mesh(spec) {
            DataKind::Tets
        } else {
            DataKind::Volume
        }
    }
}

/// Whether `spec` is a GLSL file of a user function.
pub fn is_user_function(spec: &str) -> bool {
    spec.to_ascii_lowercase().ends_with(".glsl")
}

fn has_mesh_extension(spec: &str) -> bool {
    Path::new(spec)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| MESH_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// Extensions of the volume formats with a header ([`load::load_volume`]).
pub const VOLUME_EXTENSIONS: &[&str] = &["nrrd", "nhdr", "nii", "gz", "vti"];

/// Whether `spec` is a file whose extension names no format but whose content is a mesh.
fn holds_mesh(spec: &str) -> bool {
    let path = Path::new(spec);
    let known = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| VOLUME_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()));
    !spec.starts_with("procedural:") && !known && sniff(path).is_some_and(Sniffed::is_mesh)
}

/// A volume spec: `procedural:NAME:SIZE[:TYPE]` or a volume file ([`load::load_volume`]).
/// `raw.spacing`, where given, is the spacing of the result whatever the source says.
pub fn load_volume_spec(spec: &str, raw: &RawOptions) -> Result<Volume> {
    match spec.strip_prefix("procedural:") {
        Some(rest) => procedural::parse_spec(rest)
            .and_then(|(kind, dims, scalar)| procedural::generate_grid(kind, dims, scalar))
            .and_then(|volume| match raw.spacing {
                Some(spacing) => volume.with_spacing(spacing),
                None => Ok(volume),
            })
            .map_err(|e| e.labelled(format!("procedural data '{spec}'"))),
        None => load::load_volume(Path::new(spec), raw),
    }
}

/// Bytes the volume `spec` names will take once loaded, when that is known before reading it
/// (so a front end can check it fits a device first); `None` for other kinds of data. Sizes
/// past `u64` (from a file name or `--dims`) give `u64::MAX`, which fits no device.
pub fn expected_volume_bytes(spec: &str, raw: &RawOptions) -> Option<u64> {
    if DataKind::of_spec(spec) != DataKind::Volume {
        return None;
    }
    if let Some(rest) = spec.strip_prefix("procedural:") {
        let (_, dims, scalar) = procedural::parse_spec(rest).ok()?;
        return Some(grid_bytes(dims, scalar.size_bytes() as u64));
    }
    let path = Path::new(spec);
    let name = path.file_name()?.to_str()?;
    let from_name = parse_scivis_name(name);
    let dims = raw.dims.or(from_name.as_ref().map(|n| n.0))?;
    let dtype = raw.dtype.clone().or(from_name.map(|n| n.1))?;
    let ty = scalar_from_name(path, &dtype).ok()?;
    // 8- and 16-bit unsigned data stay as they are; other types become 32-bit floats.
    let size = match ty {
        SourceType::U8 => 1,
        SourceType::U16 => 2,
        _ => 4,
    };
    Some(grid_bytes(dims, size))
}

/// Bytes of a `dims` grid of `sample_bytes`-byte samples, saturating at `u64::MAX`.
fn grid_bytes(dims: [u32; 3], sample_bytes: u64) -> u64 {
    dims.iter()
        .fold(sample_bytes, |bytes, &d| bytes.saturating_mul(u64::from(d)))
}

impl TetData {
    /// `tets:box:N`, `tets:sphere:N` (N³ cells of 6 tets), `tets:asteroids:COUNT`, or a mesh
    /// file (`.vtu`, `.vtk`, `.node`/`.ele`, `.msh`).
    pub fn load(spec: &str) -> Result<TetData> {
        let data = |mesh, asteroids, report| TetData {
            name: spec.to_string(),
            mesh,
            asteroids,
            report,
        };
        let Some(rest) = spec.strip_prefix("tets:") else {
            let (mesh, report) = load_tet_mesh(Path::new(spec))?;
            return Ok(data(mesh, false, Some(report)));
        };
        let invalid = |message: String| DataError::Invalid(format!("'{spec}': {message}"));
        let (kind, n) = rest.split_once(':').ok_or_else(|| {
            invalid(
                "expected tets:box:N, tets:sphere:N, tets:ring:N or tets:asteroids:COUNT".into(),
            )
        })?;
        if kind == "asteroids" {
            let count = parse_count(n, MAX_ASTEROIDS)
                .ok_or_else(|| invalid(format!("COUNT must be from 1 to {MAX_ASTEROIDS}")))?;
            return Ok(data(asteroid_field(count, 1), true, None));
        }
        let n = parse_count(n, MAX_MESH_N)
            .ok_or_else(|| invalid(format!("N must be a whole number from 1 to {MAX_MESH_N}")))?;
        let mesh = match kind {
            "box" => tet_procedural::box_mesh(n),
            "sphere" => tet_procedural::sphere_mesh(n),
            "ring" if n < 3 => {
                return Err(invalid(format!(
                    "a ring needs N of at least 3 (its hole is the middle third), not {n}"
                )))
            }
            "ring" => tet_procedural::ring_mesh(n),
            _ => {
                return Err(invalid(format!(
                    "unknown mesh '{kind}' (box, sphere, ring, asteroids)"
                )))
            }
        };
        Ok(data(mesh, false, None))
    }

    /// What loading repaired or skipped, worth telling the user; `None` when nothing was.
    pub fn repairs(&self) -> Option<String> {
        let r = self.report?;
        (r.reoriented + r.degenerate + r.skipped_cells > 0).then(|| {
            format!(
                "{}: {} inverted tets reoriented, {} degenerate, {} non-tet cells skipped",
                self.name, r.reoriented, r.degenerate, r.skipped_cells
            )
        })
    }
}

fn parse_count(text: &str, max: u32) -> Option<u32> {
    text.parse().ok().filter(|n| (1..=max).contains(n))
}

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;
