//! The meshlet format every meshlet producer writes (the CPU references here, later the GPU
//! paths and `extract`'s meshlet output) and every consumer reads.

use glam::Vec3;

use crate::clusters::{self, ClusterRanges};
use crate::error::{DataError, Result};
use crate::mesh::{SurfaceTransform, TriangleMesh};

/// Most vertices in one meshlet: local indices must fit in a byte, and 128 is the paper's
/// trade-off between vertex reuse and culling granularity.
pub const MAX_VERTICES: u32 = 128;
/// Most triangles in one meshlet (the paper's limit, and below what mesh shaders may emit).
pub const MAX_TRIANGLES: u32 = 254;
/// Most occupied cells one subblock may hand to a single extraction workgroup (the paper's
/// `C`): it bounds the task-to-mesh payload and the cells each invocation walks.
pub const MAX_OCCUPIED_CELLS: u32 = 128;

/// Cells per axis of the largest volume whose meshlets [`Meshlet`] can describe: a subblock's
/// minimum cell is stored in 16 bits per axis.
pub const MAX_CELLS_PER_AXIS: u32 = 1 << 16;

/// One meshlet: a range of [`MeshletMesh::positions`] / [`MeshletMesh::normals`] and a range
/// of triangles in [`MeshletMesh::local_indices`], with its bounds, in 44 bytes.
///
/// `#[repr(C)]` of 4-byte fields, so a slice of them is plain bytes for an upload; the counts
/// and the subblock are packed (read them with the methods).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Meshlet {
    /// First vertex in the mesh's vertex arrays.
    pub vertex_offset: u32,
    /// First triangle; its local indices start at `3 * triangle_offset`.
    pub triangle_offset: u32,
    /// Vertex count (bits 0–15) and triangle count (bits 16–31).
    pub counts: u32,
    /// Bounds of the meshlet's vertices (the explicit AABB).
    pub aabb_min: [f32; 3],
    pub aabb_max: [f32; 3],
    /// The subblock it was extracted from (8×8×4, 4×4×4 or 2×2×2 cells, not clipped to the
    /// volume: the implicit AABB): its minimum cell x | y << 16 and z | size x << 16 |
    /// size y << 20 | size z << 24. A size of zero says the meshlet has no cell box (the
    /// offline reference's meshlets).
    pub subblock: [u32; 2],
}

impl Meshlet {
    /// A meshlet from its parts; counts past 16 bits, origins past [`MAX_CELLS_PER_AXIS`] and
    /// sizes past 15 do not fit (callers check their volume first).
    pub fn new(
        vertex_offset: u32,
        vertex_count: u32,
        triangle_offset: u32,
        triangle_count: u32,
        (aabb_min, aabb_max): ([f32; 3], [f32; 3]),
        subblock_origin: [u32; 3],
        subblock_size: [u32; 3],
    ) -> Meshlet {
        debug_assert!(vertex_count < 1 << 16 && triangle_count < 1 << 16);
        debug_assert!(subblock_origin.iter().all(|&c| c < MAX_CELLS_PER_AXIS));
        debug_assert!(subblock_size.iter().all(|&c| c < 16));
        let [x, y, z] = subblock_origin;
        let [sx, sy, sz] = subblock_size;
        Meshlet {
            vertex_offset,
            triangle_offset,
            counts: vertex_count | triangle_count << 16,
            aabb_min,
            aabb_max,
            subblock: [x | y << 16, z | sx << 16 | sy << 20 | sz << 24],
        }
    }

    pub fn vertex_count(&self) -> u32 {
        self.counts & 0xffff
    }

    pub fn triangle_count(&self) -> u32 {
        self.counts >> 16
    }

    /// Minimum cell of the subblock it was extracted from.
    pub fn subblock_origin(&self) -> [u32; 3] {
        [
            self.subblock[0] & 0xffff,
            self.subblock[0] >> 16,
            self.subblock[1] & 0xffff,
        ]
    }

    /// Size in cells of the subblock it was extracted from; zero for meshlets without a box.
    pub fn subblock_size(&self) -> [u32; 3] {
        [16, 20, 24].map(|shift| (self.subblock[1] >> shift) & 15)
    }

    /// Minimum cell of the 8×8×4 block the subblock lies in.
    pub fn block_origin(&self) -> [u32; 3] {
        let origin = self.subblock_origin();
        std::array::from_fn(|a| origin[a] - origin[a] % crate::minmax::BLOCK_CELLS[a])
    }
}

/// An isosurface as meshlets. Triangles face the way [`crate::marching_cubes`]'s do.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshletMesh {
    pub positions: Vec<[f32; 3]>,
    /// One per position.
    pub normals: Vec<[f32; 3]>,
    /// Three per triangle, each an index into its meshlet's vertex range.
    pub local_indices: Vec<u8>,
    pub meshlets: Vec<Meshlet>,
}

impl MeshletMesh {
    pub fn triangle_count(&self) -> usize {
        self.local_indices.len() / 3
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Every triangle's corner positions, meshlet by meshlet. Triangles whose indices reach
    /// outside their meshlet or the arrays are skipped; [`Self::validate`] reports them.
    pub fn triangles(&self) -> impl Iterator<Item = [[f32; 3]; 3]> + '_ {
        self.global_triangles()
            .map(|t| t.map(|i| self.positions[i as usize]))
    }

    /// The same surface as one indexed mesh (indices made global), e.g. to compare it with
    /// [`crate::marching_cubes`]'s output or to export it. Out-of-range triangles are dropped
    /// as in [`Self::triangles`].
    pub fn to_triangle_mesh(&self) -> TriangleMesh {
        clusters::triangle_mesh(&self.positions, &self.normals, self.global_triangles())
    }

    /// The same surface as one welded indexed mesh: vertices at the same position (the
    /// copies of a border vertex in each meshlet that uses it) become one, keeping the first
    /// copy's normal. Every producer gives a crossed grid edge one position, bit for bit, so
    /// this is the vertex list of [`crate::marching_cubes`] up to order, except that vertices
    /// of distinct edges meeting at a sample that equals the isovalue merge too.
    pub fn welded(&self) -> TriangleMesh {
        clusters::welded(&self.positions, &self.normals, self.global_triangles())
    }

    /// The meshlet's vertex and index ranges, or which one leaves its array.
    fn ranges(&self, m: &Meshlet) -> std::result::Result<ClusterRanges, &'static str> {
        ClusterRanges::new(
            (m.vertex_offset, m.vertex_count()),
            (
                3 * u64::from(m.triangle_offset),
                3 * u64::from(m.triangle_count()),
            ),
            self.positions.len(),
            self.local_indices.len(),
        )
    }

    /// Triangles as indices into the vertex arrays, those out of range left out.
    fn global_triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        let ranges = self.meshlets.iter().map(|m| self.ranges(m).ok());
        clusters::global_triangles(&self.local_indices, ranges)
    }

    /// Checks what every consumer relies on: one normal per position, the limits, ranges
    /// inside the arrays, local indices inside their meshlet, every vertex of a meshlet used
    /// by one of its triangles and none repeated (two vertices at one position), and bounds
    /// that hold their vertices.
    ///
    /// Extraction gives each crossed grid edge its own vertex, so two vertices share a
    /// position only where a sample equals the isovalue exactly (the crossing then sits on
    /// that sample for every edge through it); marching cubes keeps those apart too, and this
    /// check reports them as repeated.
    pub fn validate(&self) -> Result<()> {
        self.check(true)
    }

    /// What every consumer needs to index safely, without [`Self::validate`]'s checks of
    /// the producer (repeated positions, bounds): one normal per position, the limits,
    /// ranges inside the arrays, local indices inside their meshlet, no unused vertex.
    pub fn validate_structure(&self) -> Result<()> {
        self.check(false)
    }

    fn check(&self, producer: bool) -> Result<()> {
        let invalid = |what: String| Err(DataError::Invalid(format!("meshlet mesh: {what}")));
        let (positions, indices) = (self.positions.len(), self.local_indices.len());
        if let Err(why) = clusters::check_arrays(positions, self.normals.len(), indices) {
            return invalid(why);
        }
        for (k, m) in self.meshlets.iter().enumerate() {
            if let Err(why) = self.check_meshlet(m, producer) {
                return invalid(format!("meshlet {k}: {why}"));
            }
        }
        Ok(())
    }

    fn check_meshlet(&self, m: &Meshlet, producer: bool) -> std::result::Result<(), String> {
        if m.vertex_count() > MAX_VERTICES || m.triangle_count() > MAX_TRIANGLES {
            return Err(format!(
                "{} vertices and {} triangles exceed the limits {MAX_VERTICES} and \
                 {MAX_TRIANGLES}",
                m.vertex_count(),
                m.triangle_count()
            ));
        }
        let ranges = self.ranges(m)?;
        clusters::check_indices(&self.local_indices[ranges.indices], ranges.vertices.len())?;
        if producer {
            let bounds = (m.aabb_min, m.aabb_max);
            clusters::check_positions(&self.positions[ranges.vertices], "bounds", bounds)?;
        }
        Ok(())
    }

    /// The same meshlets sorted by `(block_origin, subblock_origin)` (z, then y, then x of
    /// each), their vertices and triangles copied in that order without gaps. Producers that
    /// place blocks in scheduling order, and leave unused triangles between meshlets as the
    /// GPU paths do, then compare with [`super::extract_meshlets`] with `==`. Meshlets whose
    /// ranges leave the arrays are an error ([`Self::validate`] says why).
    pub fn in_origin_order(&self) -> Result<MeshletMesh> {
        let mut order: Vec<&Meshlet> = self.meshlets.iter().collect();
        let zyx = |p: [u32; 3]| [p[2], p[1], p[0]];
        order.sort_by_key(|m| (zyx(m.block_origin()), zyx(m.subblock_origin())));
        let mut out = MeshletMesh::default();
        for m in order {
            let Ok(ClusterRanges { vertices, indices }) = self.ranges(m) else {
                return Err(DataError::Invalid(format!(
                    "meshlet mesh: the meshlet of block {:?}, subblock {:?} reaches outside \
                     the arrays",
                    m.block_origin(),
                    m.subblock_origin()
                )));
            };
            let mut moved = *m;
            moved.vertex_offset = out.positions.len() as u32;
            moved.triangle_offset = out.triangle_count() as u32;
            out.positions
                .extend_from_slice(&self.positions[vertices.clone()]);
            out.normals
                .extend_from_slice(self.normals.get(vertices).unwrap_or_default());
            out.local_indices
                .extend_from_slice(&self.local_indices[indices]);
            out.meshlets.push(moved);
        }
        Ok(out)
    }

    /// The mesh moved by `transform` as [`TriangleMesh::transformed`] moves one (e.g. by
    /// [`crate::Volume::grid_to_physical`]), with every meshlet's bounds recomputed. The
    /// cell boxes stay in cells.
    pub fn transformed(mut self, transform: &glam::Affine3A) -> MeshletMesh {
        let moved = SurfaceTransform::new(transform);
        for p in &mut self.positions {
            *p = moved.point(Vec3::from(*p)).to_array();
        }
        for n in &mut self.normals {
            *n = moved.normal(Vec3::from(*n)).to_array();
        }
        if moved.mirrors() {
            for t in self.local_indices.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        for m in &mut self.meshlets {
            let start = m.vertex_offset as usize;
            let end = start + m.vertex_count() as usize;
            if let Some(vertices) = self.positions.get(start..end) {
                (m.aabb_min, m.aabb_max) = bounds(vertices);
            }
        }
        self
    }
}

/// `(min, max)` over `points`; empty gives an inverted box that holds nothing.
pub(crate) fn bounds(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    points.iter().fold(
        ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                std::array::from_fn(|a| lo[a].min(p[a])),
                std::array::from_fn(|a| hi[a].max(p[a])),
            )
        },
    )
}
