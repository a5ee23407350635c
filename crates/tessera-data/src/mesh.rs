//! Indexed triangle meshes as produced by isosurface extraction, with the exports and
//! comparisons the tests and the CLI need.

use std::io::{self, Write};

use glam::Vec3;

/// An indexed triangle mesh. Triangles are counter-clockwise seen from the side their
/// normal points to; `normals` is per vertex and either empty or as long as `positions`.
/// Isosurfaces face toward lower values, as VTK's do, so a closed surface around high
/// values faces outward and encloses a positive volume.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// A triangle in integer coordinates, see [`TriangleMesh::canonical_triangle_multiset`].
pub type QuantizedTriangle = [[i64; 3]; 3];

impl TriangleMesh {
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// True when there is nothing to draw (no triangles), whatever the vertex list holds.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    fn corners(&self, t: &[u32; 3]) -> [Vec3; 3] {
        t.map(|i| self.positions[i as usize])
    }

    /// Total triangle area in the units of the positions (grid units for marching cubes).
    pub fn surface_area(&self) -> f32 {
        self.surface_area_with_spacing([1.0; 3])
    }

    /// Total triangle area after scaling positions by `spacing` per axis: the physical area
    /// of a mesh in grid coordinates, given the volume's sample spacing. The scale is
    /// applied to the edge vectors before the cross product, since a non-uniform spacing
    /// changes each triangle's area by a different factor. Summed in `f64` because meshes
    /// with millions of tiny triangles lose several digits when accumulated in `f32`.
    pub fn surface_area_with_spacing(&self, spacing: [f32; 3]) -> f32 {
        let scale = Vec3::from_array(spacing).as_dvec3();
        let sum: f64 = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = self.corners(t).map(|p| p.as_dvec3() * scale);
                (b - a).cross(c - a).length() * 0.5
            })
            .sum();
        sum as f32
    }

    /// Signed volume enclosed by the mesh (divergence theorem), in cubed position units:
    /// positive when a closed mesh faces outward. Meaningful for closed meshes only.
    pub fn enclosed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = self.corners(t).map(|p| p.as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Axis-aligned `(min, max)` of all vertex positions, `None` without vertices.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }

    /// The mesh moved by `transform` (e.g. [`crate::Volume::grid_to_physical`]): positions
    /// as points, normals by the inverse transpose and renormalized, and, where the transform
    /// mirrors (negative determinant), every triangle's winding reversed so that triangles
    /// still face the way their normals point.
    pub fn transformed(mut self, transform: &glam::Affine3A) -> TriangleMesh {
        let moved = SurfaceTransform::new(transform);
        for p in &mut self.positions {
            *p = moved.point(*p);
        }
        for n in &mut self.normals {
            *n = moved.normal(*n);
        }
        if moved.mirrors() {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
        self
    }

    /// Writes a binary little-endian PLY: per vertex `float x y z nx ny nz`, per face a
    /// `uchar` count (always 3) and `uint` indices. Missing normals are written as zero
    /// so the file layout never depends on whether normals were computed.
    pub fn write_ply(&self, w: &mut impl Write) -> io::Result<()> {
        let header = format!(
            "ply\nformat binary_little_endian 1.0\ncomment written by tessera\n\
             element vertex {}\n\
             property float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
            self.positions.len(),
            self.triangles.len()
        );
        w.write_all(header.as_bytes())?;
        // Records are staged in a buffer because `w` may be an unbuffered file and a
        // write call per 4-byte field would dominate the export time.
        const FLUSH_AT: usize = 1 << 16;
        let mut buf = Vec::with_capacity(FLUSH_AT + 64);
        for (i, p) in self.positions.iter().enumerate() {
            let n = self.normals.get(i).copied().unwrap_or(Vec3::ZERO);
            for v in p.to_array().into_iter().chain(n.to_array()) {
                buf.extend_from_slice(&v.to_le_bytes());
            }
            if buf.len() >= FLUSH_AT {
                w.write_all(&buf)?;
                buf.clear();
            }
        }
        for t in &self.triangles {
            buf.push(3);
            for i in t {
                buf.extend_from_slice(&i.to_le_bytes());
            }
            if buf.len() >= FLUSH_AT {
                w.write_all(&buf)?;
                buf.clear();
            }
        }
        w.write_all(&buf)
    }

    /// Writes a Wavefront OBJ: `v` and `vn` lines (normals only when there are as many as
    /// positions), then `f` lines of 1-based indices, `a//a` when normals are written. Floats
    /// are printed in their shortest form that reads back to the same bits.
    pub fn write_obj(&self, w: &mut impl Write) -> io::Result<()> {
        writeln!(w, "# written by tessera")?;
        writeln!(
            w,
            "# {} vertices, {} triangles",
            self.positions.len(),
            self.triangles.len()
        )?;
        for p in &self.positions {
            writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
        }
        let with_normals = !self.positions.is_empty() && self.normals.len() == self.positions.len();
        if with_normals {
            for n in &self.normals {
                writeln!(w, "vn {} {} {}", n.x, n.y, n.z)?;
            }
        }
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| u64::from(i) + 1);
            if with_normals {
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
            } else {
                writeln!(w, "f {a} {b} {c}")?;
            }
        }
        Ok(())
    }

    /// Writes the mesh as `format`.
    pub fn write_as(&self, format: MeshFormat, w: &mut impl Write) -> io::Result<()> {
        match format {
            MeshFormat::Ply => self.write_ply(w),
            MeshFormat::Obj => self.write_obj(w),
        }
    }

    /// The triangles as an orientation-preserving, order-independent list, so that meshes
    /// built by different code (GPU vs CPU, different vertex numbering) compare with `==`.
    ///
    /// Each position is divided by `quantum` and rounded to integers; each triangle is
    /// rotated (not mirrored, which would flip it) so its lexicographically smallest
    /// vertex comes first; the list is then sorted. Duplicates are kept, hence
    /// "multiset". Values lying near a rounding boundary may still land on different
    /// integers, so pick `quantum` well above the expected numeric noise.
    pub fn canonical_triangle_multiset(&self, quantum: f32) -> Vec<QuantizedTriangle> {
        assert!(quantum > 0.0, "quantum must be positive, got {quantum}");
        let q = |p: Vec3| (p / quantum).round().to_array().map(|v| v as i64);
        let mut out: Vec<QuantizedTriangle> = self
            .triangles
            .iter()
            .map(|t| {
                let v = self.corners(t).map(q);
                let first = (0..3).min_by_key(|&i| v[i]).unwrap_or(0);
                [v[first], v[(first + 1) % 3], v[(first + 2) % 3]]
            })
            .collect();
        out.sort_unstable();
        out
    }
}

/// The mesh files Tessera writes and reads back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// Binary little-endian PLY ([`TriangleMesh::write_ply`]).
    Ply,
    /// Wavefront OBJ ([`TriangleMesh::write_obj`]).
    Obj,
}

impl MeshFormat {
    /// The format a file name asks for by its extension (`.ply`, `.obj`, any case).
    pub fn from_path(path: &std::path::Path) -> crate::error::Result<MeshFormat> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("ply") => Ok(MeshFormat::Ply),
            Some("obj") => Ok(MeshFormat::Obj),
            _ => Err(crate::error::DataError::Format {
                path: path.to_path_buf(),
                message: "a mesh file must end in .ply or .obj".into(),
            }),
        }
    }
}

/// How an affine transform moves a surface: positions as points, normals by the inverse
/// transpose (renormalized), and whether it mirrors, in which case every triangle's winding
/// must be reversed to keep facing the way its normals point. Shared by every mesh format so
/// that they all move alike.
pub(crate) struct SurfaceTransform {
    affine: glam::Affine3A,
    normal_matrix: glam::Mat3,
}

impl SurfaceTransform {
    pub(crate) fn new(affine: &glam::Affine3A) -> SurfaceTransform {
        SurfaceTransform {
            affine: *affine,
            normal_matrix: glam::Mat3::from(affine.matrix3).inverse().transpose(),
        }
    }

    pub(crate) fn point(&self, p: Vec3) -> Vec3 {
        self.affine.transform_point3(p)
    }

    pub(crate) fn normal(&self, n: Vec3) -> Vec3 {
        (self.normal_matrix * n).normalize_or_zero()
    }

    pub(crate) fn mirrors(&self) -> bool {
        self.affine.matrix3.determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> TriangleMesh {
        TriangleMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    #[test]
    fn measures() {
        let m = quad();
        assert_eq!((m.vertex_count(), m.triangle_count()), (4, 2));
        assert!(!m.is_empty());
        assert!((m.surface_area() - 2.0).abs() < 1e-6);
        // The quad lies in z = 0 and spans 2 × 1: spacing along z does not matter.
        assert!((m.surface_area_with_spacing([0.5, 3.0, 7.0]) - 3.0).abs() < 1e-6);
        assert_eq!(m.bounds(), Some((Vec3::ZERO, Vec3::new(2.0, 1.0, 0.0))));
        let empty = TriangleMesh::default();
        assert!(empty.is_empty());
        assert_eq!((empty.bounds(), empty.surface_area()), (None, 0.0));
    }

    #[test]
    fn area_with_spacing_scales_each_axis_before_the_cross_product() {
        // A right triangle in the xz plane with legs 1 (x) and 1 (z): spacing (2, 5, 3)
        // makes the legs 2 and 3, area 3; scaling the unit-spacing area by any single
        // factor would not give that.
        let m = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2]],
        };
        assert!((m.surface_area() - 0.5).abs() < 1e-6);
        assert!((m.surface_area_with_spacing([2.0, 5.0, 3.0]) - 3.0).abs() < 1e-6);
    }

    #[test]
    fn enclosed_volume_is_signed_by_orientation() {
        // A unit tetrahedron, faces counter-clockwise seen from outside.
        let mut m = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            normals: Vec::new(),
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        };
        assert!((m.enclosed_volume() - 1.0 / 6.0).abs() < 1e-12);
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
        assert!((m.enclosed_volume() + 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn transform_scales_area_and_keeps_facing() {
        let scale = glam::Affine3A::from_scale(Vec3::new(2.0, 3.0, 5.0));
        let m = quad().transformed(&scale);
        assert!((m.surface_area() - 12.0).abs() < 1e-5);
        assert_eq!(m.bounds(), Some((Vec3::ZERO, Vec3::new(4.0, 3.0, 0.0))));
        assert_eq!(m.normals[0], Vec3::Z);
        assert_eq!(m.triangles, quad().triangles);
        // A mirror keeps the triangles facing their normals.
        let mirror = glam::Affine3A::from_scale(Vec3::new(1.0, 1.0, -1.0))
            * glam::Affine3A::from_translation(Vec3::new(1.0, 0.0, 0.0));
        let m = quad().transformed(&mirror);
        assert_eq!(m.normals[0], -Vec3::Z);
        assert_eq!(m.triangles[0], [0, 2, 1]);
        assert_eq!(m.positions[1], Vec3::new(3.0, 0.0, 0.0));
        let [a, b, c] = m.corners(&m.triangles[0]);
        assert!((b - a).cross(c - a).dot(m.normals[0]) > 0.0);
    }

    #[test]
    fn ply_header_and_size() {
        let m = quad();
        let mut bytes = Vec::new();
        m.write_ply(&mut bytes).unwrap();
        let end = b"end_header\n";
        let body = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        let header = std::str::from_utf8(&bytes[..body]).unwrap();
        assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
        assert!(header.contains("element vertex 4\n"));
        assert!(header.contains("property float nz\n"));
        assert!(header.contains("element face 2\nproperty list uchar uint vertex_indices\n"));
        assert_eq!(bytes.len() - body, 4 * 24 + 2 * 13);
        // Second vertex's x, then the first face record.
        assert_eq!(bytes[body + 24..body + 28], 2.0f32.to_le_bytes());
        let face = &bytes[body + 4 * 24..body + 4 * 24 + 13];
        assert_eq!(face[0], 3);
        assert_eq!(face[5..9], 1u32.to_le_bytes());

        // Normals are optional but keep the record size.
        let bare = TriangleMesh {
            normals: Vec::new(),
            ..m
        };
        let mut again = Vec::new();
        bare.write_ply(&mut again).unwrap();
        assert_eq!(again.len(), bytes.len());
    }

    #[test]
    fn canonical_multiset_ignores_numbering_but_not_orientation() {
        let a = quad();
        // Same surface: vertices renumbered, triangles reordered and rotated.
        let b = TriangleMesh {
            positions: vec![
                a.positions[3],
                a.positions[2],
                a.positions[0],
                a.positions[1],
            ],
            normals: Vec::new(),
            triangles: vec![[1, 0, 2], [3, 1, 2]],
        };
        let ca = a.canonical_triangle_multiset(1e-3);
        assert_eq!(ca, b.canonical_triangle_multiset(1e-3));
        assert_eq!(ca[0][0], [0, 0, 0], "smallest vertex first");
        assert!(ca.windows(2).all(|w| w[0] <= w[1]));
        // A flipped triangle is a different triangle.
        let mut flipped = a.clone();
        flipped.triangles[0] = [0, 2, 1];
        assert_ne!(ca, flipped.canonical_triangle_multiset(1e-3));
        // Noise below the quantum disappears.
        let mut noisy = a.clone();
        noisy.positions[1] += Vec3::splat(1e-5);
        assert_eq!(ca, noisy.canonical_triangle_multiset(1e-3));
    }
}
