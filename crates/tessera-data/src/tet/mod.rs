//! Tetrahedral meshes: the in-memory [`TetMesh`], its consistency checks, face connectivity
//! ([`topology`]), loaders and writers for VTK XML (`.vtu`), legacy VTK (`.vtk`), TetGen
//! (`.node`/`.ele`) and Gmsh 4.1 and 2.2 (`.msh`), and procedural meshes of any size.
//!
//! Orientation convention: a tet `[a, b, c, d]` is positive when
//! `(b - a) · ((c - a) × (d - a)) > 0`. [`TetMesh::validate`] (which every loader runs)
//! reorients negative tets, so code downstream may rely on it.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};

use crate::error::{DataError, Result};
use crate::sniff::{sniff, Sniffed};

pub mod asteroids;
mod cells;
pub mod emission_absorption;
pub mod gmsh;
pub mod optical;
pub mod procedural;
pub mod scalar_integral;
pub mod shell;
pub mod tetgen;
mod text;
pub mod topology;
pub mod vtk_legacy;
pub mod vtu;

pub use gmsh::{load_msh, write_msh41};
pub use tetgen::{load_tetgen, write_tetgen};
pub use vtk_legacy::{load_vtk_legacy, write_vtk_legacy_ascii};
pub use vtu::{load_vtu, write_vtu_ascii};

/// A tetrahedral mesh with optional per-vertex scalars and per-tet attributes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TetMesh {
    pub vertices: Vec<[f32; 3]>,
    /// Four vertex indices per tet.
    pub tets: Vec<[u32; 4]>,
    /// One value per vertex, named by `scalar_name`.
    pub scalars: Option<Vec<f32>>,
    pub scalar_name: String,
    /// Absorption colour per tet (for projected-tetrahedra style rendering).
    pub absorption: Option<Vec<[f32; 3]>>,
    /// Region (or tet id) per tet.
    pub regions: Option<Vec<u32>>,
}

/// What validation and loading found and fixed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshReport {
    /// Tets with negative signed volume that had two vertices swapped.
    pub reoriented: usize,
    /// Tets whose volume is negligible compared to the mesh size (kept as they are).
    pub degenerate: usize,
    pub first_degenerate: Option<usize>,
    /// Cells of other types (triangles, hexahedra, ...) a loader skipped.
    pub skipped_cells: usize,
}

/// A tet is degenerate when `|volume| < DEGENERATE_FACTOR * diagonal^3`.
pub const DEGENERATE_FACTOR: f64 = 1e-12;

impl TetMesh {
    /// A mesh without scalars or attributes.
    pub fn new(vertices: Vec<[f32; 3]>, tets: Vec<[u32; 4]>) -> Self {
        TetMesh {
            vertices,
            tets,
            ..TetMesh::default()
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    pub fn tet_count(&self) -> usize {
        self.tets.len()
    }

    /// True without tets.
    pub fn is_empty(&self) -> bool {
        self.tets.is_empty()
    }

    /// Axis-aligned `(min, max)` of the vertices, `None` without vertices.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = Vec3::from(*self.vertices.first()?);
        Some(self.vertices.iter().fold((first, first), |(lo, hi), p| {
            (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p)))
        }))
    }

    /// The corners of tet `tet` in `f64`. Panics on out-of-range indices.
    pub fn corners(&self, tet: usize) -> [DVec3; 4] {
        self.tets[tet].map(|v| Vec3::from(self.vertices[v as usize]).as_dvec3())
    }

    /// Signed volume of tet `tet` (positive for the orientation described in the module
    /// documentation). Computed in `f64`. Panics on out-of-range indices.
    pub fn volume_of(&self, tet: usize) -> f64 {
        let [a, b, c, d] = self.corners(tet);
        (b - a).dot((c - a).cross(d - a)) / 6.0
    }

    /// Sum of the signed tet volumes.
    pub fn total_volume(&self) -> f64 {
        (0..self.tets.len()).map(|t| self.volume_of(t)).sum()
    }

    /// Per-vertex values from one value per tet, as VTK's `vtkCellDataToPointData` makes
    /// them: each vertex gets the plain (unweighted) mean of the values of the tets that use
    /// it. Plain rather than volume-weighted, so that the result matches what VTK and
    /// ParaView show for the same data, and so that degenerate (zero-volume) tets, which
    /// validation keeps, still count instead of leaving a vertex used only by them with 0/0.
    /// A vertex no tet uses gets NaN: it is never drawn, and the scalar range leaves
    /// non-finite values out (VTK's 0 would widen the range). Non-finite tet values are kept
    /// and reach the vertices of their tet, as non-finite vertex scalars are kept. Sums run
    /// in `f64`, in tet order.
    ///
    /// Errors: `values` not one per tet, or a tet whose vertex index is out of range.
    pub fn point_values_from_cells(&self, values: &[f32]) -> Result<Vec<f32>> {
        if values.len() != self.tets.len() {
            return Err(DataError::Invalid(format!(
                "{} cell values for {} tets",
                values.len(),
                self.tets.len()
            )));
        }
        let n = self.vertices.len();
        let mut sums = vec![0.0f64; n];
        let mut uses = vec![0u32; n];
        for (t, (tet, &value)) in self.tets.iter().zip(values).enumerate() {
            for &v in tet {
                let v = v as usize;
                if v >= n {
                    return Err(DataError::Invalid(format!(
                        "tet {t}: vertex index {v} out of range (mesh has {n} vertices)"
                    )));
                }
                sums[v] += f64::from(value);
                uses[v] += 1;
            }
        }
        Ok(sums
            .iter()
            .zip(&uses)
            .map(|(&sum, &count)| match count {
                0 => f32::NAN,
                c => (sum / f64::from(c)) as f32,
            })
            .collect())
    }

    /// Checks the mesh and repairs what can be repaired; `source` (a file name, or a
    /// generator's name) labels the errors.
    ///
    /// Errors: no tets, non-finite coordinates (names the vertex), indices out of range
    /// (names the tet), attribute arrays of the wrong length. Inverted tets are reoriented
    /// by swapping their last two vertices; degenerate tets are counted and kept.
    pub fn validate(&mut self, source: &str) -> Result<MeshReport> {
        let fail = |msg: String| DataError::Format {
            path: PathBuf::from(source),
            message: msg,
        };
        if self.tets.is_empty() {
            return Err(fail(format!(
                "empty mesh: no tetrahedra ({} vertices)",
                self.vertices.len()
            )));
        }
        if let Some(v) = self
            .vertices
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            let p = self.vertices[v];
            return Err(fail(format!(
                "vertex {v} has a non-finite coordinate ({}, {}, {})",
                p[0], p[1], p[2]
            )));
        }
        let n = self.vertices.len();
        for (t, tet) in self.tets.iter().enumerate() {
            if let Some(&bad) = tet.iter().find(|&&v| v as usize >= n) {
                return Err(fail(format!(
                    "tet {t}: vertex index {bad} out of range (mesh has {n} vertices)"
                )));
            }
        }
        let lengths = [
            ("scalars", self.scalars.as_ref().map(Vec::len), n),
            (
                "absorption",
                self.absorption.as_ref().map(Vec::len),
                self.tets.len(),
            ),
            (
                "regions",
                self.regions.as_ref().map(Vec::len),
                self.tets.len(),
            ),
        ];
        for (what, len, want) in lengths {
            if let Some(len) = len.filter(|&l| l != want) {
                return Err(fail(format!("{what} has {len} entries, expected {want}")));
            }
        }

        let (lo, hi) = self.bounds().expect("vertices exist");
        let diagonal = f64::from((hi - lo).length());
        let threshold = DEGENERATE_FACTOR * diagonal.powi(3);
        let mut report = MeshReport::default();
        for t in 0..self.tets.len() {
            let volume = self.volume_of(t);
            if volume.abs() < threshold || volume == 0.0 {
                report.degenerate += 1;
                report.first_degenerate.get_or_insert(t);
            } else if volume < 0.0 {
                self.tets[t].swap(2, 3);
                report.reoriented += 1;
            }
        }
        Ok(report)
    }
}

/// Loads a tetrahedral mesh, choosing the format by extension: `.vtu`, `.vtk`,
/// `.node`/`.ele` (TetGen; the sibling file is found) or `.msh` (Gmsh); files with another
/// extension by their content ([`crate::sniff`]).
pub fn load_tet_mesh(path: &Path) -> Result<(TetMesh, MeshReport)> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "vtu" => load_vtu(path),
        "vtk" => load_vtk_legacy(path),
        "node" | "ele" => load_tetgen(path),
        "msh" => load_msh(path),
        _ => {
            std::fs::metadata(path).map_err(|e| DataError::io(path, e))?;
            match sniff(path) {
                Some(Sniffed::VtkXmlMesh) => load_vtu(path),
                Some(Sniffed::LegacyVtk) => load_vtk_legacy(path),
                Some(Sniffed::Gmsh) => load_msh(path),
                found => Err(DataError::format(
                    path,
                    format!(
                        "not a tetrahedral mesh file: the extension '{ext}' is none of .vtu, \
                         .vtk, .node, .ele or .msh, and the content {}",
                        match found {
                            Some(format) => format!("is {}", format.describe()),
                            None => "does not start like any of them".to_string(),
                        }
                    ),
                )),
            }
        }
    }
}

/// Validates a freshly parsed mesh on behalf of a loader.
pub(crate) fn finish(
    mut mesh: TetMesh,
    path: &Path,
    skipped_cells: usize,
) -> Result<(TetMesh, MeshReport)> {
    if mesh.tets.is_empty() && skipped_cells > 0 {
        // Say why there is nothing: a mesh of hexahedra, wedges or surface triangles only.
        return Err(DataError::format(
            path,
            format!(
                "empty mesh: no tetrahedra; all {skipped_cells} cell(s) are of other types (hexahedra, \
                 wedges, triangles, ...), which are skipped; tetrahedralize the mesh first \
                 (e.g. TetGen, or VTK's vtkDataSetTriangleFilter)"
            ),
        ));
    }
    let mut report = mesh.validate(&path.display().to_string())?;
    report.skipped_cells = skipped_cells;
    Ok((mesh, report))
}

/// Reads a whole file, naming it in the error.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| DataError::io(path, e))
}

/// Writes a file, naming it in the error.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).map_err(|e| DataError::io(path, e))
}

/// Region values stored as floating point in a file: kept when every value is a
/// non-negative integer that fits `u32`, dropped otherwise.
pub(crate) fn integral_regions(values: &[f64]) -> Option<Vec<u32>> {
    values
        .iter()
        .map(|&v| {
            (v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&v)).then_some(v as u32)
        })
        .collect()
}

#[cfg(test)]
#[path = "mesh_tests.rs"]
mod tests;
