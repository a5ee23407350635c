//! Tests of the procedural tet meshes.
use super::*;
use crate::tet::MeshReport;

#[test]
fn box_volume_and_orientation() {
    for n in [1u32, 2, 4, 7] {
        let mut mesh = box_mesh(n);
        assert_eq!(mesh.tet_count(), 6 * (n * n * n) as usize);
        assert_eq!(mesh.vertex_count(), ((n + 1) * (n + 1) * (n + 1)) as usize);
        assert!((mesh.total_volume() - 8.0).abs() < 1e-4, "n = {n}");
        assert!((0..mesh.tet_count()).all(|t| mesh.volume_of(t) > 0.0));
        let report = mesh.validate("box").expect("valid");
        assert_eq!(report, MeshReport::default());
        assert_eq!(mesh.scalar_name, "distance");
        let s = mesh.scalars.as_ref().expect("scalars");
        assert_eq!(s.len(), mesh.vertex_count());
        assert!(mesh
            .regions
            .as_ref()
            .expect("regions")
            .iter()
            .all(|&r| r < 8));
    }
}

#[test]
fn sphere_is_a_ball() {
    let mut mesh = sphere_mesh(10);
    let report = mesh.validate("sphere").expect("valid");
    assert_eq!((report.reoriented, report.degenerate), (0, 0));
    let volume = mesh.total_volume();
    let ball = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((volume - ball).abs() < 0.03 * ball, "volume {volume}");
    for f in mesh.boundary_faces() {
        for v in f {
            let r = Vec3::from(mesh.vertices[v as usize]).length();
            assert!((r - 1.0).abs() < 1e-5, "boundary vertex at radius {r}");
        }
    }
    let s = mesh.scalars.as_ref().expect("radius");
    assert!(s.iter().all(|&r| (0.0..=1.0 + 1e-5).contains(&r)));
}

#[test]
fn deform_keeps_tets_valid() {
    let mut mesh = box_mesh(6);
    let before = mesh.clone();
    deform(&mut mesh, 0.08);
    assert_ne!(mesh.vertices, before.vertices);
    assert_eq!(mesh.tets, before.tets);
    let report = mesh.validate("deformed").expect("valid");
    assert_eq!((report.reoriented, report.degenerate), (0, 0));
    let mut again = before.clone();
    deform(&mut again, 0.08);
    assert_eq!(again, mesh, "deterministic");
}

#[test]
fn exploded_separates_parts() {
    let mesh = box_mesh(4);
    let parts = exploded(&mesh, 8, 0.5);
    assert_eq!(parts.tet_count(), mesh.tet_count());
    assert!(parts.vertex_count() > mesh.vertex_count());
    assert!((parts.total_volume() - 8.0).abs() < 1e-4);
    let regions = parts.regions.as_ref().expect("parts");
    assert!(regions.iter().all(|&r| r < 8));
    // Octant pieces moved outwards: no tet of the +x pieces reaches x < 0.2.
    for (t, tet) in parts.tets.iter().enumerate() {
        if regions[t] & 1 == 1 {
            assert!(tet.iter().all(|&v| parts.vertices[v as usize][0] > 0.2));
        }
    }
    assert_eq!(
        parts.scalars.as_ref().map(Vec::len),
        Some(parts.vertex_count())
    );

    let mut plain = box_mesh(2);
    plain.regions = None;
    let two = exploded(&plain, 2, 1.0);
    assert_eq!(two.tet_count(), plain.tet_count());
    assert!(two.regions.as_ref().expect("parts").iter().all(|&r| r < 2));
    let one = exploded(&plain, 1, 0.0);
    assert_eq!(one.vertex_count(), plain.vertex_count());
    assert!((one.total_volume() - 8.0).abs() < 1e-4);
}

#[test]
fn ring_has_a_hole_through_it() {
    let mut ring = ring_mesh(6);
    let cubes = 6 * 6 * 6 - 2 * 6 * 2;
    assert_eq!(ring.tets.len(), 6 * cubes);
    let report = ring.validate("ring").unwrap();
    assert_eq!((report.reoriented, report.degenerate), (0, 0));
    // Every vertex is used and carries its scalar; the hole's axis is empty.
    assert_eq!(ring.scalars.as_ref().unwrap().len(), ring.vertices.len());
    let mut used = vec![false; ring.vertices.len()];
    for t in &ring.tets {
        for &v in t {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
    assert!(ring
        .vertices
        .iter()
        .all(|p| p[0].abs() > 0.3 || p[2].abs() > 0.3));
    assert_eq!(ring.regions.as_ref().unwrap().len(), ring.tets.len());
}
