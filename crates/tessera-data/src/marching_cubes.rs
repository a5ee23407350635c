//! CPU reference marching cubes. GPU extraction is tested against this, so it favours
//! clarity and exact reproducibility over speed; the case tables and every convention
//! (corners, edges, case bits, orientation) are those of [`crate::mc_tables`], and
//! ambiguous faces are cut by an [`AmbiguityRule`] (the asymptotic decider by default).
//!
//! Output is in grid coordinates: sample `(x, y, z)` sits at position `(x, y, z)`, with
//! no spacing or origin applied. Each crossed grid edge yields exactly one vertex shared
//! by all cells around it, placed at `t = (iso - a) / (b - a)` from the edge's
//! lower-coordinate sample `a` toward `b`. Normals are the central-difference gradient
//! (one-sided at the border) interpolated with the same `t` and negated, so they point from
//! above-iso toward below-iso values, the same way the triangles face (VTK's convention:
//! out of the tissue of a scan).

use glam::Vec3;

pub use crate::mc_ambiguity::AmbiguityRule;
use crate::mc_tables::{mc_tables, CORNER_OFFSETS, EDGE_AXIS, EDGE_CORNERS};
use crate::mesh::TriangleMesh;
use crate::volume::Volume;

const NO_VERTEX: u32 = u32::MAX;

/// Case index of the cell whose minimum corner is sample `(x, y, z)`: bit `i` is set
/// when corner `i` is `< iso`. Panics when the cell reaches past the volume.
pub fn classify_cell(volume: &Volume, x: u32, y: u32, z: u32, iso: f32) -> u8 {
    // Checked here because an out-of-range x would silently wrap into the next row.
    let [nx, ny, nz] = volume.dims();
    assert!(
        x + 1 < nx && y + 1 < ny && z + 1 < nz,
        "cell ({x}, {y}, {z}) outside {nx}x{ny}x{nz}"
    );
    case_of(&cell_values(volume, x, y, z), iso)
}

/// The values at the eight corners of the cell whose minimum corner is sample `(x, y, z)`.
pub(crate) fn cell_values(volume: &Volume, x: u32, y: u32, z: u32) -> [f32; 8] {
    CORNER_OFFSETS.map(|o| {
        volume.texel(
            x + u32::from(o[0]),
            y + u32::from(o[1]),
            z + u32::from(o[2]),
        )
    })
}

pub(crate) fn case_of(values: &[f32; 8], iso: f32) -> u8 {
    (0..8).fold(0, |case, c| case | u8::from(values[c] < iso) << c)
}

/// Number of triangles [`marching_cubes`] would produce, without building the mesh.
pub fn count_triangles(volume: &Volume, iso: f32) -> u64 {
    count_triangles_with(volume, iso, AmbiguityRule::default())
}

/// Number of triangles [`marching_cubes_with`] would produce with `rule`.
pub fn count_triangles_with(volume: &Volume, iso: f32, rule: AmbiguityRule) -> u64 {
    let [nx, ny, nz] = volume.dims();
    let tables = mc_tables();
    let mut total = 0;
    for z in 0..nz.saturating_sub(1) {
        for y in 0..ny.saturating_sub(1) {
            for x in 0..nx.saturating_sub(1) {
                let values = cell_values(volume, x, y, z);
                let case = case_of(&values, iso);
                let row = tables.row(case, rule.joined_faces(case, &values, iso));
                total += u64::from(tables.tri_count[row]);
            }
        }
    }
    total
}

/// [`marching_cubes`] in physical units: vertices at the volume's origin plus spacing ×
/// index along its axis directions ([`Volume::grid_to_physical`]), so that lengths and areas
/// are the file's (e.g. millimetres). This is what exports write.
pub fn marching_cubes_physical(volume: &Volume, iso: f32, rule: AmbiguityRule) -> TriangleMesh {
    marching_cubes_with(volume, iso, rule).transformed(&volume.grid_to_physical())
}

/// Extracts the `iso` level set of `volume` as an indexed, watertight mesh (see the
/// module docs), ambiguous faces cut by the asymptotic decider. A volume with fewer than
/// two samples along any axis has no cells and gives an empty mesh, as does an iso value
/// that no edge crosses.
pub fn marching_cubes(volume: &Volume, iso: f32) -> TriangleMesh {
    marching_cubes_with(volume, iso, AmbiguityRule::default())
}

/// [`marching_cubes`] with ambiguous faces cut by `rule`.
pub fn marching_cubes_with(volume: &Volume, iso: f32, rule: AmbiguityRule) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let [nx, ny, nz] = volume.dims();
    if nx < 2 || ny < 2 || nz < 2 {
        return mesh;
    }
    let tables = mc_tables();
    let (w, h) = (nx as usize, ny as usize);
    let plane = |z: u32| -> Vec<f32> {
        (0..ny)
            .flat_map(|y| (0..nx).map(move |x| volume.texel(x, y, z)))
            .collect()
    };
    // Only two sample planes and the vertex ids of edges starting in them are live at a
    // time, so memory stays O(nx * ny) however deep the volume is. Vertex ids are keyed
    // by (start sample, axis): slot `(x + w * y) * 3 + axis` in the start's plane.
    let mut vals = [plane(0), Vec::new()];
    let mut ids = [vec![NO_VERTEX; w * h * 3], vec![NO_VERTEX; w * h * 3]];
    for z in 0..nz - 1 {
        vals[1] = plane(z + 1);
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let corner = |c: usize| {
                    let o = CORNER_OFFSETS[c].map(usize::from);
                    let (px, py) = (x as usize + o[0], y as usize + o[1]);
                    (o[2], px + w * py, vals[o[2]][px + w * py])
                };
                let values: [f32; 8] = std::array::from_fn(|c| corner(c).2);
                let case = case_of(&values, iso);
                let mask = tables.edge_mask[usize::from(case)];
                if mask == 0 {
                    continue;
                }
                let row = tables.row(case, rule.joined_faces(case, &values, iso));
                let mut edge_ids = [NO_VERTEX; 12];
                for (e, id) in edge_ids.iter_mut().enumerate() {
                    if mask & (1 << e) == 0 {
                        continue;
                    }
                    let [a, b] = EDGE_CORNERS[e].map(usize::from);
                    let ((pa, ia, va), (_, _, vb)) = (corner(a), corner(b));
                    let axis = usize::from(EDGE_AXIS[e]);
                    let slot = &mut ids[pa][ia * 3 + axis];
                    if *slot == NO_VERTEX {
                        let o = CORNER_OFFSETS[a].map(u32::from);
                        let start = [x + o[0], y + o[1], z + o[2]];
                        *slot = push_vertex(&mut mesh, volume, start, axis, va, vb, iso);
                    }
                    *id = *slot;
                }
                mesh.triangles
                    .extend(tables.row_triangles(row).map(|t| t.map(|e| edge_ids[e])));
            }
        }
        // The upper plane becomes the lower one; its vertex ids carry over.
        vals.swap(0, 1);
        ids.swap(0, 1);
        ids[1].fill(NO_VERTEX);
    }
    mesh
}

/// Adds the vertex on the grid edge from sample `start` one step along `axis`, whose end
/// values are `a` and `b`, and returns its index.
fn push_vertex(
    mesh: &mut TriangleMesh,
    volume: &Volume,
    start: [u32; 3],
    axis: usize,
    a: f32,
    b: f32,
    iso: f32,
) -> u32 {
    let (position, normal) = edge_vertex(volume, start, axis, a, b, iso);
    let index = u32::try_from(mesh.positions.len()).expect("more than 2^32 vertices");
    mesh.positions.push(position);
    mesh.normals.push(normal);
    index
}

/// Position and normal of the vertex on the grid edge from sample `start` one step along
/// `axis`, whose end values are `a` and `b`. Every extractor that must agree with this
/// reference bit for bit (the meshlet references among them) places its vertices here.
pub(crate) fn edge_vertex(
    volume: &Volume,
    start: [u32; 3],
    axis: usize,
    a: f32,
    b: f32,
    iso: f32,
) -> (Vec3, Vec3) {
    // Exactly one end is below iso, so b != a. Volumes are validated finite, but a NaN
    // iso would still make t NaN; the midpoint keeps the vertex on its edge then.
    let t = (iso - a) / (b - a);
    let t = if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) };
    let mut end = start;
    end[axis] += 1;
    let dir = Vec3::AXES[axis];
    let p0 = Vec3::from_array(start.map(|v| v as f32));
    let g = gradient(volume, start).lerp(gradient(volume, end), t);
    // A flat or NaN gradient still needs a usable normal; the edge direction from its
    // above end to its below end points the right way by construction.
    let fallback = if a < iso { -dir } else { dir };
    let normal = (-g).try_normalize().unwrap_or(fallback);
    (p0 + dir * t, normal)
}

/// Gradient of the samples at grid point `p`: central differences inside, one-sided
/// differences on the border (every axis has at least two samples here).
fn gradient(volume: &Volume, p: [u32; 3]) -> Vec3 {
    let dims = volume.dims();
    let mut g = [0.0; 3];
    for (axis, g) in g.iter_mut().enumerate() {
        let (mut lo, mut hi) = (p, p);
        lo[axis] = p[axis].saturating_sub(1);
        hi[axis] = (p[axis] + 1).min(dims[axis] - 1);
        let span = (hi[axis] - lo[axis]) as f32;
        *g = (volume.texel(hi[0], hi[1], hi[2]) - volume.texel(lo[0], lo[1], lo[2])) / span;
    }
    Vec3::from_array(g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_volumes::{field, noise};
    use crate::volume::Samples;
    use std::collections::{HashMap, HashSet};

    /// Directed mesh edge -> uses.
    fn directed_edges(m: &TriangleMesh) -> HashMap<(u32, u32), u32> {
        let mut d = HashMap::new();
        for &[a, b, c] in &m.triangles {
            for e in [(a, b), (b, c), (c, a)] {
                *d.entry(e).or_insert(0) += 1;
            }
        }
        d
    }

    /// Asserts every edge not exempted by `open_ok` is used once in each direction,
    /// i.e. shared by exactly two consistently oriented triangles; returns the number
    /// of undirected edges.
    fn assert_watertight(m: &TriangleMesh, open_ok: impl Fn(Vec3, Vec3) -> bool) -> usize {
        let d = directed_edges(m);
        assert!(d.values().all(|&n| n == 1), "directed edge used twice");
        for &(a, b) in d.keys() {
            let (pa, pb) = (m.positions[a as usize], m.positions[b as usize]);
            assert!(
                d.contains_key(&(b, a)) || open_ok(pa, pb),
                "open edge {pa} {pb}"
            );
        }
        d.keys()
            .map(|&(a, b)| (a.min(b), a.max(b)))
            .collect::<HashSet<_>>()
            .len()
    }

    #[test]
    fn ball_is_a_closed_outward_facing_sphere() {
        // High inside, like tissue in a scan: the surface faces out, toward lower values.
        let (c, r, peak) = (Vec3::new(15.3, 15.6, 15.45), 10.0, 20.0);
        let vol = field([32; 3], |p| peak - p.distance(c));
        let m = marching_cubes(&vol, peak - r);
        assert_eq!(m.triangle_count() as u64, count_triangles(&vol, peak - r));
        let edges = assert_watertight(&m, |_, _| false);
        let euler = m.vertex_count() as i64 - edges as i64 + m.triangle_count() as i64;
        assert_eq!(euler, 2);
        let area = f64::from(m.surface_area());
        let exact = 4.0 * std::f64::consts::PI * f64::from(r * r);
        assert!((area / exact - 1.0).abs() < 0.03, "area {area} vs {exact}");
        let enclosed = m.enclosed_volume();
        let ball = 4.0 / 3.0 * std::f64::consts::PI * f64::from(r * r * r);
        assert!(
            (enclosed / ball - 1.0).abs() < 0.03,
            "volume {enclosed} vs {ball}"
        );
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!(
                (p.distance(c) - r).abs() < 0.02,
                "vertex {p} off the sphere"
            );
            assert!(n.dot((*p - c).normalize()) > 0.99, "normal {n} at {p}");
        }
        for &t in &m.triangles {
            let [a, b, d] = t.map(|i| m.positions[i as usize]);
            assert!(
                (b - a).cross(d - a).dot((a + b + d) / 3.0 - c) > 0.0,
                "inward triangle"
            );
        }
        let unique: HashSet<[u32; 3]> = m
            .positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        assert_eq!(unique.len(), m.vertex_count(), "duplicated vertices");
    }

    #[test]
    fn physical_mesh_scales_with_spacing_and_moves_to_the_origin() {
        use crate::orientation::{Orientation, OrientationSource};
        let (c, r) = (Vec3::new(10.3, 10.6, 10.45), 6.0);
        let vol = field([22; 3], |p| p.distance(c));
        let grid = marching_cubes(&vol, r);
        let spacing = [0.5, 1.0, 2.0];
        let vol = vol.with_spacing(spacing).unwrap().with_orientation(
            Orientation::new(
                [100.0, 0.0, -50.0],
                [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                None,
                OrientationSource::Nrrd,
            )
            .unwrap(),
        );
        let phys = marching_cubes_physical(&vol, r, AmbiguityRule::default());
        assert_eq!(phys.triangle_count(), grid.triangle_count());
        let (glo, ghi) = grid.bounds().unwrap();
        let (plo, phi) = phys.bounds().unwrap();
        let s = Vec3::from(spacing);
        let o = Vec3::new(100.0, 0.0, -50.0);
        assert!((plo - (o + glo * s)).length() < 1e-4, "{plo}");
        assert!(((phi - plo) - (ghi - glo) * s).length() < 1e-4, "{phi}");
        // An ellipsoid of semi-axes 3, 6, 12: Knud Thomsen's area formula within 3 %.
        let p = 1.6075f64;
        let (a, b, cc) = (3.0f64, 6.0f64, 12.0f64);
        let exact = 4.0
            * std::f64::consts::PI
            * (((a * b).powf(p) + (a * cc).powf(p) + (b * cc).powf(p)) / 3.0).powf(1.0 / p);
        let area = f64::from(phys.surface_area());
        assert!((area / exact - 1.0).abs() < 0.03, "area {area} vs {exact}");
    }

    #[test]
    fn plane_gives_two_triangles_per_crossed_cell() {
        let dims = [6, 5, 4];
        let vol = field(dims, |p| p.x);
        let m = marching_cubes(&vol, 2.25);
        assert_eq!(m.triangle_count(), 2 * 4 * 3);
        assert_eq!(count_triangles(&vol, 2.25), 24);
        assert_eq!(m.vertex_count(), 5 * 4);
        assert!(m.positions.iter().all(|p| p.x == 2.25));
        assert!(m.normals.iter().all(|&n| n == -Vec3::X), "toward lower x");
        assert!((m.surface_area() - 12.0).abs() < 1e-5);
        // Integer data is thresholded in texel space (the raw u8 value), like the GPU sees it.
        let bytes = (0..6 * 5 * 4).map(|i| (i % 6) as u8 * 50).collect();
        let u8_vol = Volume::new("ramp", dims, [1.0; 3], Samples::U8(bytes)).unwrap();
        let mu = marching_cubes(&u8_vol, 127.5);
        assert_eq!(mu.triangle_count(), 24);
        assert!(mu.positions.iter().all(|p| (p.x - 2.55).abs() < 1e-5));
        for &t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!(
                (b - a).cross(c - a).x < 0.0,
                "triangle faces down the gradient"
            );
        }
    }

    #[test]
    fn iso_outside_the_range_gives_nothing() {
        let vol = field([5, 6, 7], |p| p.x + p.y * p.z);
        for iso in [-1.0, 100.0] {
            assert!(marching_cubes(&vol, iso).is_empty());
            assert_eq!(marching_cubes(&vol, iso).vertex_count(), 0);
            assert_eq!(count_triangles(&vol, iso), 0);
        }
    }

    #[test]
    fn single_cell_cases() {
        for (corner, offset) in CORNER_OFFSETS.iter().enumerate() {
            let o = Vec3::from_array(offset.map(f32::from));
            let vol = field([2; 3], |p| if p == o { 0.0 } else { 1.0 });
            assert_eq!(classify_cell(&vol, 0, 0, 0, 0.5), 1 << corner);
            let m = marching_cubes(&vol, 0.5);
            assert_eq!((m.triangle_count(), m.vertex_count()), (1, 3));
            let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
            assert!(
                (b - a).cross(c - a).dot(a - o) < 0.0,
                "faces the low corner"
            );
        }
        let flat = field([2, 3, 2], |_| 0.0);
        assert!(marching_cubes(&flat, 0.5).is_empty());
    }

    #[test]
    fn random_noise_is_watertight_inside() {
        // Noise hits every case, ambiguous faces included; cells on either side of a
        // face must cut it the same way for each interior edge to close up.
        let dims = [16; 3];
        for (seed, rule) in (1..4).flat_map(|s| RULES.map(|r| (s, r))) {
            let vol =
                Volume::new("noise", dims, [1.0; 3], Samples::F32(noise(dims, seed))).unwrap();
            let m = marching_cubes_with(&vol, 0.5, rule);
            assert!(m.triangle_count() > 1000);
            assert_eq!(
                m.triangle_count() as u64,
                count_triangles_with(&vol, 0.5, rule)
            );
            let on_border = |p: Vec3, q: Vec3| {
                (0..3).any(|i| (p[i] == 0.0 && q[i] == 0.0) || (p[i] == 15.0 && q[i] == 15.0))
            };
            assert_watertight(&m, on_border);
            let cases: HashSet<u8> = (0..15 * 15 * 15)
                .map(|i| classify_cell(&vol, i % 15, i / 15 % 15, i / 225, 0.5))
                .collect();
            assert!(cases.len() > 200, "noise covers only {} cases", cases.len());
        }
    }

    #[test]
    fn random_noise_with_a_high_border_is_closed() {
        let dims = [16; 3];
        let mut v = noise(dims, 7);
        for (i, s) in v.iter_mut().enumerate() {
            let p = [i % 16, i / 16 % 16, i / 256];
            if p.iter().any(|&c| c == 0 || c == 15) {
                *s = 1.0;
            }
        }
        let vol = Volume::new("noise", dims, [1.0; 3], Samples::F32(v)).unwrap();
        for rule in RULES {
            let m = marching_cubes_with(&vol, 0.5, rule);
            assert_watertight(&m, |_, _| false);
            assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
            // Closed around the low pockets inside the high border and facing into them,
            // toward lower values: the enclosed volume is negative.
            assert!(m.enclosed_volume() < 0.0, "{rule:?}");
        }
    }

    const RULES: [AmbiguityRule; 2] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk];

    /// One cell with 1 at two diagonal corners of the face z = 0 and 0 elsewhere.
    fn face_diagonal_cell() -> Volume {
        field([2; 3], |p| f32::from(p.z == 0.0 && p.x == p.y))
    }

    #[test]
    fn face_diagonal_cell_matches_vtk_with_its_rule() {
        // Areas from vtkMarchingCubes (VTK 9.7.2) on the same 2×2×2 float32 volume:
        // scripts/vtk-marching-cubes.py --diagonal-cell. VTK separates the two high
        // corners at every iso; the decider joins them while the face's saddle value (0.5)
        // is above iso.
        const VTK_AREA: [(f32, f64); 2] = [(0.2, 1.108513), (0.8, 0.06928203)];
        let vol = face_diagonal_cell();
        for (iso, vtk_area) in VTK_AREA {
            let vtk_rule =
                f64::from(marching_cubes_with(&vol, iso, AmbiguityRule::Vtk).surface_area());
            assert!(
                (vtk_rule / vtk_area - 1.0).abs() < 1e-4,
                "iso {iso}: {vtk_rule} vs VTK {vtk_area}"
            );
            let decider = f64::from(marching_cubes(&vol, iso).surface_area());
            println!("iso {iso}: VTK {vtk_area}, VTK rule {vtk_rule}, decider {decider}");
            let joined = iso < 0.5;
            assert_eq!(
                decider == vtk_rule,
                !joined,
                "iso {iso}: decider {decider}, VTK rule {vtk_rule}"
            );
        }
    }
}
