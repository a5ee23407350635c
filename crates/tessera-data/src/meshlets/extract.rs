//! CPU reference of paper C's meshlet extraction: occupied blocks from the min-max grid,
//! each partitioned by the region analysis ([`super::partition`]), one meshlet per subblock
//! built PMB-style ([`super::subblock`]). Vertices and normals come from
//! [`crate::marching_cubes`]'s own edge-vertex function and triangles from the same table
//! rows, so the triangles equal the marching-cubes mesh's bit for bit, grouped differently.
//!
//! Output order: blocks x fastest, subblocks of a block in Morton order, a meshlet's
//! triangles by occupied cell in Morton order (each cell's in table order) and its vertices
//! as [`super::subblock::SubblockSurface::edges`] lists them.

use crate::error::{DataError, Result};
use crate::marching_cubes::{edge_vertex, AmbiguityRule};
use crate::mc_tables::{mc_tables, CORNER_OFFSETS, EDGE_AXIS, EDGE_CORNERS};
use crate::meshlets::format::{bounds, Meshlet, MeshletMesh, MAX_CELLS_PER_AXIS};
use crate::meshlets::partition::partition_block;
use crate::meshlets::subblock::{cell_box, edge_values, SubblockSurface};
use crate::minmax::{MinMaxOctree, BLOCK_CELLS};
use crate::volume::Volume;

/// The `iso` level set of `volume` as meshlets, in grid coordinates like
/// [`crate::marching_cubes::marching_cubes_with`], ambiguous faces cut by `rule`.
pub fn extract_meshlets(volume: &Volume, iso: f32, rule: AmbiguityRule) -> Result<MeshletMesh> {
    let mut mesh = MeshletMesh::default();
    let [nx, ny, nz] = volume.dims();
    if nx < 2 || ny < 2 || nz < 2 {
        return Ok(mesh);
    }
    check_meshlet_dims(volume.name(), volume.dims())?;
    let grid = MinMaxOctree::build(volume);
    for block in grid.occupied_blocks(iso) {
        let block_origin = std::array::from_fn(|a| block[a] * BLOCK_CELLS[a]);
        for surface in partition_block(volume, iso, rule, block_origin)? {
            append_meshlet(&mut mesh, volume, iso, &surface)?;
        }
    }
    Ok(mesh)
}

/// Refuses a volume of more cells along an axis than a [`Meshlet`] can place
/// ([`MAX_CELLS_PER_AXIS`]).
pub fn check_meshlet_dims(name: &str, dims: [u32; 3]) -> Result<()> {
    match dims
        .iter()
        .find(|&&d| d.saturating_sub(1) > MAX_CELLS_PER_AXIS)
    {
        Some(d) => Err(DataError::Invalid(format!(
            "{name}: {} cells along an axis; meshlets place subblocks in volumes of at most \
             {MAX_CELLS_PER_AXIS} cells per axis",
            d - 1
        ))),
        None => Ok(()),
    }
}

/// [`extract_meshlets`] in physical units, placed as
/// [`crate::marching_cubes::marching_cubes_physical`] places its mesh (what exports write).
pub fn extract_meshlets_physical(
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
) -> Result<MeshletMesh> {
    Ok(extract_meshlets(volume, iso, rule)?.transformed(&volume.grid_to_physical()))
}

/// No vertex on that edge of the subblock's box.
const NO_VERTEX: u8 = u8::MAX;

fn append_meshlet(
    mesh: &mut MeshletMesh,
    volume: &Volume,
    iso: f32,
    surface: &SubblockSurface,
) -> Result<()> {
    let too_many = || {
        DataError::Invalid(format!(
            "{}: the isosurface needs more than 2^32 meshlet vertices or triangles",
            volume.name()
        ))
    };
    let vertex_offset = u32::try_from(mesh.positions.len()).map_err(|_| too_many())?;
    let triangle_offset = u32::try_from(mesh.triangle_count()).map_err(|_| too_many())?;
    if vertex_offset.checked_add(surface.vertex_count()).is_none()
        || triangle_offset
            .checked_add(surface.triangle_count)
            .is_none()
    {
        return Err(too_many());
    }

    let slots = EdgeSlots::new(volume, surface);
    let mut local = slots.empty();
    for (k, &edge) in surface.edges.iter().enumerate() {
        let [a, b] = edge_values(volume, edge);
        let (position, normal) = edge_vertex(volume, edge.start, edge.axis, a, b, iso);
        mesh.positions.push(position.to_array());
        mesh.normals.push(normal.to_array());
        // `fits` keeps k below MAX_VERTICES (128), so it is a valid u8 below NO_VERTEX.
        local[slots.index(edge.start, edge.axis)] = k as u8;
    }
    let tables = mc_tables();
    for cell in &surface.cells {
        for triangle in tables.row_triangles(cell.row) {
            for e in triangle {
                let corner = CORNER_OFFSETS[usize::from(EDGE_CORNERS[e][0])];
                let start = std::array::from_fn(|a| cell.cell[a] + u32::from(corner[a]));
                let i = local[slots.index(start, usize::from(EDGE_AXIS[e]))];
                if i == NO_VERTEX {
                    return Err(DataError::Invalid(format!(
                        "{}: cell {:?} uses edge {e}, which has no crossing",
                        volume.name(),
                        cell.cell
                    )));
                }
                mesh.local_indices.push(i);
            }
        }
    }
    let vertices = &mesh.positions[vertex_offset as usize..];
    let (aabb_min, aabb_max) = bounds(vertices);
    mesh.meshlets.push(Meshlet::new(
        vertex_offset,
        surface.vertex_count(),
        triangle_offset,
        surface.triangle_count,
        (aabb_min, aabb_max),
        surface.subblock.origin(),
        surface.subblock.size(),
    ));
    Ok(())
}

/// Dense numbering of the grid edges of a subblock's closed box: three per sample point
/// (x, y, z edge), x fastest, so a triangle finds its vertices without hashing.
struct EdgeSlots {
    lo: [u32; 3],
    points: [usize; 3],
}

impl EdgeSlots {
    fn new(volume: &Volume, surface: &SubblockSurface) -> EdgeSlots {
        let (lo, hi) = cell_box(volume, &surface.subblock);
        let points = std::array::from_fn(|a| (hi[a].saturating_sub(lo[a]) + 1) as usize);
        EdgeSlots { lo, points }
    }

    fn empty(&self) -> Vec<u8> {
        vec![NO_VERTEX; self.points.iter().product::<usize>() * 3]
    }

    fn index(&self, start: [u32; 3], axis: usize) -> usize {
        let p: [usize; 3] = std::array::from_fn(|a| (start[a] - self.lo[a]) as usize);
        ((p[2] * self.points[1] + p[1]) * self.points[0] + p[0]) * 3 + axis
    }
}
