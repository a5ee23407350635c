use super::format::*;

/// One meshlet holding a unit quad in z = 0 as two triangles.
fn quad() -> MeshletMesh {
    MeshletMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        local_indices: vec![0, 1, 2, 0, 2, 3],
        meshlets: vec![Meshlet::new(
            0,
            4,
            0,
            2,
            ([0.0; 3], [1.0, 1.0, 0.0]),
            [0; 3],
            [2; 3],
        )],
    }
}

/// A way to break a well-formed mesh, and what the error must say.
type Corruption = (&'static str, fn(&mut MeshletMesh));

fn error_of(mesh: &MeshletMesh) -> String {
    match mesh.validate() {
        Ok(()) => panic!("{mesh:?} passed validation"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_well_formed_mesh_validates_and_lists_its_triangles() {
    let m = quad();
    m.validate().unwrap();
    let tris: Vec<_> = m.triangles().collect();
    assert_eq!(tris.len(), 2);
    assert_eq!(tris[1], [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
    let flat = m.to_triangle_mesh();
    assert_eq!(flat.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!((flat.surface_area() - 1.0).abs() < 1e-6);
}

#[test]
fn validation_names_each_broken_rule() {
    let broken: [Corruption; 8] = [
        ("normals for", |m| {
            m.normals.pop();
        }),
        ("whole number of triangles", |m| m.local_indices.push(0)),
        ("exceed the limits", |m| {
            m.meshlets[0].counts = 4 | (MAX_TRIANGLES + 1) << 16;
        }),
        ("vertex range outside", |m| m.meshlets[0].vertex_offset = 1),
        ("triangle range outside", |m| {
            m.meshlets[0].triangle_offset = 1
        }),
        ("local index 4", |m| m.local_indices[5] = 4),
        ("used by no triangle", |m| m.local_indices[5] = 2),
        ("outside the bounds", |m| m.meshlets[0].aabb_max[1] = 0.5),
    ];
    for (message, corrupt) in broken {
        let mut m = quad();
        corrupt(&mut m);
        let e = error_of(&m);
        assert!(e.contains(message), "'{e}' does not say '{message}'");
    }
    let mut repeated = quad();
    repeated.positions[3] = repeated.positions[1];
    assert!(error_of(&repeated).contains("repeats position"));
}

#[test]
fn broken_triangles_are_skipped_not_a_panic() {
    let mut m = quad();
    m.local_indices[5] = 200;
    assert_eq!(m.triangles().count(), 1);
    assert_eq!(m.to_triangle_mesh().triangle_count(), 1);
    m.meshlets[0].counts = 4 | 1000 << 16;
    assert_eq!(m.triangles().count(), 0);
}

#[test]
fn moving_scales_bounds_and_a_mirror_keeps_facing() {
    let mirror = glam::Affine3A::from_scale(glam::Vec3::new(2.0, -1.0, 1.0));
    let m = quad().transformed(&mirror);
    m.validate().unwrap();
    assert_eq!(m.meshlets[0].aabb_min, [0.0, -1.0, 0.0]);
    assert_eq!(m.meshlets[0].aabb_max, [2.0, 0.0, 0.0]);
    assert_eq!(m.local_indices, vec![0, 2, 1, 0, 3, 2]);
    let flat = m.to_triangle_mesh();
    let [a, b, c] = flat.triangles[0].map(|i| flat.positions[i as usize]);
    assert!((b - a).cross(c - a).dot(flat.normals[0]) > 0.0);
    assert_eq!(
        m.meshlets[0].subblock_size(),
        [2; 3],
        "cell boxes stay in cells"
    );
}

#[test]
fn packed_fields_read_back_what_was_packed() {
    let m = Meshlet::new(
        7,
        MAX_VERTICES,
        9,
        MAX_TRIANGLES,
        ([0.0; 3], [1.0; 3]),
        [65535, 1234, 40000],
        [8, 4, 2],
    );
    assert_eq!(
        (m.vertex_count(), m.triangle_count()),
        (MAX_VERTICES, MAX_TRIANGLES)
    );
    assert_eq!(m.subblock_origin(), [65535, 1234, 40000]);
    assert_eq!(m.subblock_size(), [8, 4, 2]);
    assert_eq!(m.block_origin(), [65528, 1232, 40000]);
    assert_eq!(std::mem::size_of::<Meshlet>(), 44);
}

#[test]
fn volumes_too_wide_for_the_packed_subblock_are_refused() {
    use crate::meshlets::check_meshlet_dims;
    assert!(check_meshlet_dims("v", [MAX_CELLS_PER_AXIS + 1, 2, 2]).is_ok());
    let e = check_meshlet_dims("wide.raw", [2, MAX_CELLS_PER_AXIS + 2, 2]).unwrap_err();
    assert!(
        e.to_string().contains("wide.raw") && e.to_string().contains("65537 cells"),
        "{e}"
    );
}
