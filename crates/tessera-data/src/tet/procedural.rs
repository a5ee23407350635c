//! Deterministic tetrahedral meshes of any size for tests, demos and benchmarks. Each carries
//! a per-vertex scalar field, per-tet regions and absorption colours, so every technique has
//! data to show.

use std::f32::consts::PI;

use glam::Vec3;

use super::TetMesh;

/// Largest `n` accepted by [`box_mesh`] and [`sphere_mesh`] (vertex indices must fit `u32`).
pub const MAX_CELLS_PER_AXIS: u32 = 1600;

/// Point the `distance` scalar of [`box_mesh`] is measured from.
pub const DISTANCE_ORIGIN: [f32; 3] = [0.25, 0.1, -0.2];

/// The six tets of the Freudenthal (Kuhn) split of a unit cube: each walks from corner 0 to
/// corner 7 along the axes in one of the six orders, so all share the main diagonal and
/// neighbouring cubes agree on the diagonals of shared faces. Corners are numbered
/// `x + 2y + 4z`; the orders are arranged so every tet is positively oriented.
const CUBE_TETS: [[usize; 4]; 6] = cube_tets();

const fn cube_tets() -> [[usize; 4]; 6] {
    // Axis orders (as corner bit values) and their permutation parity.
    let orders: [([usize; 3], bool); 6] = [
        ([1, 2, 4], true),
        ([2, 4, 1], true),
        ([4, 1, 2], true),
        ([1, 4, 2], false),
        ([4, 2, 1], false),
        ([2, 1, 4], false),
    ];
    let mut tets = [[0; 4]; 6];
    let mut i = 0;
    while i < 6 {
        let (o, even) = orders[i];
        let (a, b, c) = (o[0], o[0] + o[1], 7);
        // Even orders give positive volume as (0, a, b, 7); odd ones need a swap.
        tets[i] = if even { [0, a, b, c] } else { [0, a, c, b] };
        i += 1;
    }
    tets
}

/// `n³` cubes filling `[-1, 1]³`, each split into 6 tets (conforming). The scalar
/// `distance` is the distance from [`DISTANCE_ORIGIN`]; regions are the octant of each tet
/// (bit 0: x > 0, bit 1: y > 0, bit 2: z > 0) and the absorption colour varies smoothly with
/// position. `n` is clamped to `1..=MAX_CELLS_PER_AXIS`.
pub fn box_mesh(n: u32) -> TetMesh {
    let n = n.clamp(1, MAX_CELLS_PER_AXIS) as usize;
    let side = n + 1;
    let coord = |i: usize| -1.0 + 2.0 * i as f32 / n as f32;
    let mut vertices = Vec::with_capacity(side * side * side);
    for k in 0..side {
        for j in 0..side {
            for i in 0..side {
                vertices.push([coord(i), coord(j), coord(k)]);
            }
        }
    }
    let index = |i: usize, j: usize, k: usize| (i + side * (j + side * k)) as u32;
    let mut tets = Vec::with_capacity(6 * n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let corner = |c: usize| index(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                tets.extend(CUBE_TETS.iter().map(|t| t.map(corner)));
            }
        }
    }
    let mut mesh = TetMesh::new(vertices, tets);
    let origin = Vec3::from(DISTANCE_ORIGIN);
    set_scalars(&mut mesh, "distance", |p| p.distance(origin));
    set_tet_attributes(&mut mesh);
    mesh
}

/// A square ring: the [`box_mesh`] of `n³` cubes (`n` at least 3) without the cubes of the
/// middle third in x and z, so a hole runs through it along y. Non-convex with a hole (a
/// torus's topology): rays through the hole meet the mesh twice or not at all. Scalars,
/// regions and absorption as the box's.
pub fn ring_mesh(n: u32) -> TetMesh {
    let n = n.clamp(3, MAX_CELLS_PER_AXIS);
    let full = box_mesh(n);
    let (lo, hi) = (n / 3, n - n / 3);
    let in_hole = |cell: usize| {
        let (i, k) = (cell as u32 % n, cell as u32 / (n * n));
        (lo..hi).contains(&i) && (lo..hi).contains(&k)
    };
    // box_mesh emits each cube's 6 tets together, cube after cube in x, y, z order.
    let kept: Vec<usize> = (0..full.tets.len()).filter(|&t| !in_hole(t / 6)).collect();
    let mut remap = vec![u32::MAX; full.vertices.len()];
    let mut vertices = Vec::new();
    let mut used = Vec::new();
    let tets: Vec<[u32; 4]> = kept
        .iter()
        .map(|&t| {
            full.tets[t].map(|v| {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = vertices.len() as u32;
                    vertices.push(full.vertices[v as usize]);
                    used.push(v as usize);
                }
                *slot
            })
        })
        .collect();
    let mut mesh = TetMesh::new(vertices, tets);
    mesh.scalar_name = full.scalar_name.clone();
    mesh.scalars = full
        .scalars
        .as_ref()
        .map(|s| used.iter().map(|&v| s[v]).collect());
    mesh.regions = full
        .regions
        .as_ref()
        .map(|r| kept.iter().map(|&t| r[t]).collect());
    mesh.absorption = full
        .absorption
        .as_ref()
        .map(|a| kept.iter().map(|&t| a[t]).collect());
    mesh
}

/// A ball of radius 1: the [`box_mesh`] with its vertices mapped from the cube onto the ball
/// by the smooth "elliptical grid" mapping, so the boundary lies on the sphere. The scalar
/// `radius` is the distance from the centre.
pub fn sphere_mesh(n: u32) -> TetMesh {
    let mut mesh = box_mesh(n);
    for p in &mut mesh.vertices {
        let [x, y, z] = *p;
        let (x2, y2, z2) = (x * x, y * y, z * z);
        *p = [
            x * (1.0 - y2 / 2.0 - z2 / 2.0 + y2 * z2 / 3.0).max(0.0).sqrt(),
            y * (1.0 - z2 / 2.0 - x2 / 2.0 + z2 * x2 / 3.0).max(0.0).sqrt(),
            z * (1.0 - x2 / 2.0 - y2 / 2.0 + x2 * y2 / 3.0).max(0.0).sqrt(),
        ];
    }
    set_scalars(&mut mesh, "radius", |p| p.length());
    set_tet_attributes(&mut mesh);
    mesh
}

/// Moves every vertex by a smooth sinusoidal displacement of at most `amount` per axis.
/// Scalars and attributes are kept. Amounts below about a tenth of the mesh size keep the
/// tets of the procedural meshes positively oriented.
pub fn deform(mesh: &mut TetMesh, amount: f32) {
    for p in &mut mesh.vertices {
        let v = Vec3::from(*p);
        let d = Vec3::new(
            (PI * v.y).sin() * (PI * 0.5 * v.z).cos(),
            (PI * v.z).sin() * (PI * 0.5 * v.x).cos(),
            (PI * v.x).sin() * (PI * 0.5 * v.y).cos(),
        );
        *p = (v + amount * d).to_array();
    }
}

/// Splits the mesh into at most `parts` pieces and moves each `distance` away from the
/// mesh centre. Pieces are the regions (`region % parts`) when the mesh has regions,
/// otherwise the octant of each tet's centroid (`octant % parts`). Each piece gets its own
/// copies of its vertices; the result's regions are the piece numbers.
pub fn exploded(mesh: &TetMesh, parts: u32, distance: f32) -> TetMesh {
    let parts = parts.max(1);
    let centre = mesh.bounds().map_or(Vec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
    let centroid = |t: &[u32; 4]| {
        t.iter()
            .map(|&v| Vec3::from(mesh.vertices[v as usize]))
            .sum::<Vec3>()
            * 0.25
    };
    let part_of: Vec<u32> = mesh
        .tets
        .iter()
        .enumerate()
        .map(|(t, tet)| match &mesh.regions {
            Some(r) => r[t] % parts,
            None => {
                let d = centroid(tet) - centre;
                (u32::from(d.x > 0.0) | u32::from(d.y > 0.0) << 1 | u32::from(d.z > 0.0) << 2)
                    % parts
            }
        })
        .collect();

    let mut out = TetMesh {
        scalar_name: mesh.scalar_name.clone(),
        scalars: mesh.scalars.as_ref().map(|_| Vec::new()),
        absorption: mesh.absorption.as_ref().map(|_| Vec::new()),
        regions: Some(Vec::new()),
        ..TetMesh::default()
    };
    let mut remap = vec![u32::MAX; mesh.vertices.len()];
    for part in 0..parts {
        let members: Vec<usize> = (0..mesh.tets.len())
            .filter(|&t| part_of[t] == part)
            .collect();
        if members.is_empty() {
            continue;
        }
        let middle = members
            .iter()
            .map(|&t| centroid(&mesh.tets[t]))
            .sum::<Vec3>()
            / members.len() as f32;
        let offset = (middle - centre).try_normalize().unwrap_or(Vec3::X) * distance;
        remap.fill(u32::MAX);
        for &t in &members {
            let tet = mesh.tets[t].map(|v| {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = out.vertices.len() as u32;
                    out.vertices
                        .push((Vec3::from(mesh.vertices[v as usize]) + offset).to_array());
                    if let (Some(dst), Some(src)) = (out.scalars.as_mut(), &mesh.scalars) {
                        dst.push(src[v as usize]);
                    }
                }
                *slot
            });
            out.tets.push(tet);
            if let (Some(dst), Some(src)) = (out.absorption.as_mut(), &mesh.absorption) {
                dst.push(src[t]);
            }
            out.regions.as_mut().expect("set above").push(part);
        }
    }
    out
}

fn set_scalars(mesh: &mut TetMesh, name: &str, f: impl Fn(Vec3) -> f32) {
    mesh.scalars = Some(mesh.vertices.iter().map(|p| f(Vec3::from(*p))).collect());
    mesh.scalar_name = name.into();
}

/// Octant regions and a position-dependent absorption colour.
fn set_tet_attributes(mesh: &mut TetMesh) {
    let centroids: Vec<Vec3> = mesh
        .tets
        .iter()
        .map(|t| {
            t.iter()
                .map(|&v| Vec3::from(mesh.vertices[v as usize]))
                .sum::<Vec3>()
                * 0.25
        })
        .collect();
    mesh.regions = Some(
        centroids
            .iter()
            .map(|c| u32::from(c.x > 0.0) | u32::from(c.y > 0.0) << 1 | u32::from(c.z > 0.0) << 2)
            .collect(),
    );
    mesh.absorption = Some(
        centroids
            .iter()
            .map(|c| (Vec3::splat(0.5) + 0.4 * c.clamp(Vec3::NEG_ONE, Vec3::ONE)).to_array())
            .collect(),
    );
}

#[cfg(test)]
#[path = "procedural_tests.rs"]
mod tests;
