//! Tests of the Morton reordering.
use super::*;
use crate::tet::procedural::box_mesh;
use crate::tet::shell::test_meshes::named_meshes;

#[test]
fn spreading_bits_interleaves_them() {
    assert_eq!(spread_bits(0b1011), 0b001_000_001_001);
    assert_eq!(spread_bits(0x1f_ffff), 0x1249_2492_4924_9249);
    let lo = Vec3::ZERO;
    let hi = Vec3::ONE;
    assert!(morton_code(Vec3::new(0.9, 0.1, 0.1), lo, hi) < morton_code(Vec3::splat(0.6), lo, hi));
}

#[test]
fn the_order_is_a_permutation_applied_to_everything() {
    for (name, mesh) in named_meshes() {
        let order = morton_order(&mesh);
        let mut seen = order.new_vertex_of_old.clone();
        seen.sort_unstable();
        assert!(
            seen.iter().enumerate().all(|(i, &v)| v as usize == i),
            "{name}"
        );
        let mut seen = order.new_tet_of_old.clone();
        seen.sort_unstable();
        assert!(
            seen.iter().enumerate().all(|(i, &t)| t as usize == i),
            "{name}"
        );

        let reordered = order.apply(&mesh);
        for (old, tet) in mesh.tets.iter().enumerate() {
            let new = order.new_tet_of_old[old] as usize;
            for (&v_new, &v_old) in reordered.tets[new].iter().zip(tet) {
                assert_eq!(
                    reordered.vertices[v_new as usize],
                    mesh.vertices[v_old as usize]
                );
            }
            assert!(
                (reordered.volume_of(new) - mesh.volume_of(old)).abs() < 1e-12,
                "{name}"
            );
        }
        let scalar = |m: &TetMesh, v: usize| m.scalars.as_ref().map(|s| s[v]);
        for old in 0..mesh.vertices.len() {
            let new = order.new_vertex_of_old[old] as usize;
            assert_eq!(scalar(&reordered, new), scalar(&mesh, old), "{name}");
        }
        assert_eq!(
            order.apply_to_neighbours(&mesh.neighbours()),
            reordered.neighbours(),
            "{name}"
        );
    }
}

#[test]
fn more_neighbouring_tets_end_up_close_in_memory() {
    // The generator's row-major order keeps x neighbours close but puts y and z neighbours a
    // row or a slab of cubes away; the curve keeps most neighbours within a few cache lines.
    let mesh = box_mesh(16);
    let close_fraction = |m: &TetMesh| {
        let (mut close, mut all) = (0u64, 0u64);
        for (t, across) in m.neighbours().iter().enumerate() {
            for &o in across.iter().filter(|&&o| o != NO_NEIGHBOUR) {
                close += u64::from((o as i64 - t as i64).unsigned_abs() < 64);
                all += 1;
            }
        }
        close as f64 / all as f64
    };
    let before = close_fraction(&mesh);
    let after = close_fraction(&morton_order(&mesh).apply(&mesh));
    assert!(
        after > before + 0.05,
        "neighbours within 64 ids: {before} -> {after}"
    );
}
