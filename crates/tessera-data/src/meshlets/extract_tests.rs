use std::collections::{HashMap, HashSet};

use super::extract::{extract_meshlets, extract_meshlets_physical};
use super::format::MeshletMesh;
use crate::marching_cubes::{marching_cubes_physical, marching_cubes_with, AmbiguityRule};
use crate::mesh::TriangleMesh;
use crate::procedural::{generate, ProceduralKind};
use crate::test_volumes::{field, noise};
use crate::volume::{Samples, ScalarType, Volume};

const RULES: [AmbiguityRule; 2] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk];

/// Positions agree within this (they are computed by the same function, so in practice
/// they agree exactly; `assert_same_vertices` checks that).
const QUANTUM: f32 = 1e-5;

/// Volumes of several characters, with isovalues that no sample equals (so no two crossings
/// share a point, see `MeshletMesh::validate`). Sizes are not all multiples of the 8×8×4
/// block, so partial blocks along every axis are covered.
fn volumes() -> Vec<(Volume, f32)> {
    let procedural = |kind, size, scalar| generate(kind, size, scalar).unwrap();
    vec![
        (
            procedural(ProceduralKind::Sphere, 27, ScalarType::F32),
            0.6123,
        ),
        (
            procedural(ProceduralKind::MarschnerLobb, 33, ScalarType::F32),
            0.5013,
        ),
        (
            procedural(ProceduralKind::Turbulence, 30, ScalarType::U8),
            127.5,
        ),
        (
            procedural(ProceduralKind::HeadPhantom, 36, ScalarType::U16),
            29491.5,
        ),
        (
            Volume::new(
                "noise",
                [13, 21, 7],
                [1.0; 3],
                Samples::F32(noise([13, 21, 7], 3)),
            )
            .unwrap(),
            0.5,
        ),
    ]
}

/// The meshlets hold exactly marching cubes' triangles (as a multiset) with its vertices:
/// every meshlet vertex is one of the reference's, normal included, bit for bit.
fn assert_same_surface(meshlets: &MeshletMesh, reference: &TriangleMesh, what: &str) {
    meshlets
        .validate()
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let ours = meshlets.to_triangle_mesh();
    assert_eq!(
        ours.triangle_count(),
        reference.triangle_count(),
        "{what}: triangle count"
    );
    assert!(
        ours.canonical_triangle_multiset(QUANTUM) == reference.canonical_triangle_multiset(QUANTUM),
        "{what}: triangles differ"
    );
    assert_same_vertices(&ours, reference, what);
}

fn assert_same_vertices(ours: &TriangleMesh, reference: &TriangleMesh, what: &str) {
    let bits = |v: glam::Vec3| v.to_array().map(f32::to_bits);
    let normal_at: HashMap<_, _> = reference
        .positions
        .iter()
        .zip(&reference.normals)
        .map(|(&p, &n)| (bits(p), bits(n)))
        .collect();
    for (&p, &n) in ours.positions.iter().zip(&ours.normals) {
        assert_eq!(
            normal_at.get(&bits(p)),
            Some(&bits(n)),
            "{what}: vertex {p} is not the reference's"
        );
    }
}

#[test]
fn meshlets_hold_the_marching_cubes_triangles() {
    let mut sizes = HashSet::new();
    for (volume, iso) in volumes() {
        for rule in RULES {
            let what = format!("{} at {iso} ({rule:?})", volume.name());
            let reference = marching_cubes_with(&volume, iso, rule);
            assert!(
                reference.triangle_count() > 100,
                "{what}: too little surface"
            );
            let meshlets = extract_meshlets(&volume, iso, rule).unwrap();
            assert_same_surface(&meshlets, &reference, &what);
            sizes.extend(meshlets.meshlets.iter().map(|m| m.subblock_size()));
        }
    }
    for size in [[8, 8, 4], [4, 4, 4], [2, 2, 2]] {
        assert!(sizes.contains(&size), "no meshlet from a {size:?} subblock");
    }
}

#[test]
fn the_ambiguity_rule_changes_the_surface_and_the_meshlets_follow() {
    let dims = [12, 12, 12];
    let volume = Volume::new("noise", dims, [1.0; 3], Samples::F32(noise(dims, 11))).unwrap();
    let [decider, vtk] = RULES.map(|rule| {
        let meshlets = extract_meshlets(&volume, 0.5, rule).unwrap();
        meshlets
            .to_triangle_mesh()
            .canonical_triangle_multiset(QUANTUM)
    });
    assert!(decider != vtk, "both rules cut every ambiguous face alike");
}

#[test]
fn meshlets_keep_within_their_subblocks() {
    for (volume, iso) in volumes().into_iter().take(2) {
        let meshlets = extract_meshlets(&volume, iso, AmbiguityRule::default()).unwrap();
        for m in &meshlets.meshlets {
            let (origin, size) = (m.subblock_origin(), m.subblock_size());
            for a in 0..3 {
                let lo = origin[a] as f32;
                let hi = (origin[a] + size[a]) as f32;
                assert!(lo <= m.aabb_min[a] && m.aabb_max[a] <= hi, "{m:?}");
                assert_eq!(m.block_origin()[a] % [8, 8, 4][a], 0);
                // A subblock lies in one block.
                assert!(origin[a] + size[a] <= m.block_origin()[a] + [8, 8, 4][a]);
            }
        }
    }
}

#[test]
fn no_surface_gives_no_meshlets() {
    let sphere = generate(ProceduralKind::Sphere, 20, ScalarType::F32).unwrap();
    for iso in [-1.0, 2.0, f32::NAN] {
        let m = extract_meshlets(&sphere, iso, AmbiguityRule::default()).unwrap();
        assert_eq!(m, MeshletMesh::default(), "iso {iso}");
    }
    // The min-max grid calls every block occupied (its range is [1, 1]) yet nothing crosses.
    let flat = field([17, 9, 9], |_| 1.0);
    let m = extract_meshlets(&flat, 1.0, AmbiguityRule::default()).unwrap();
    assert_eq!(m, MeshletMesh::default());
}

#[test]
fn a_fully_occupied_volume_matches_too() {
    // Every cell crossed, in blocks both whole and cut by the volume's end.
    let volume = field([11, 10, 7], |p| ((p.x + p.y + p.z) as u32 % 2) as f32);
    for rule in RULES {
        let meshlets = extract_meshlets(&volume, 0.5, rule).unwrap();
        let reference = marching_cubes_with(&volume, 0.5, rule);
        assert_same_surface(&meshlets, &reference, &format!("checkerboard ({rule:?})"));
        // Whole blocks must go down to 2×2×2; those cut short may fit at 4×4×4.
        assert!(meshlets
            .meshlets
            .iter()
            .any(|m| m.subblock_size() == [2; 3]));
    }
}

#[test]
fn physical_meshlets_are_placed_like_the_physical_mesh() {
    let volume = generate(ProceduralKind::Sphere, 19, ScalarType::F32)
        .unwrap()
        .with_spacing([0.5, 1.0, 2.5])
        .unwrap();
    let rule = AmbiguityRule::default();
    let meshlets = extract_meshlets_physical(&volume, 0.6123, rule).unwrap();
    let reference = marching_cubes_physical(&volume, 0.6123, rule);
    assert_same_surface(&meshlets, &reference, "sphere with spacing");
    let area = meshlets.to_triangle_mesh().surface_area();
    assert!((area / reference.surface_area() - 1.0).abs() < 1e-5);
}

#[test]
fn an_isovalue_hitting_samples_still_gives_the_marching_cubes_triangles() {
    // Integer data at an integer isovalue: crossings land on samples equal to it, where
    // several edges' vertices coincide. They stay distinct vertices, as in marching cubes,
    // which `validate` reports as repeated positions and nothing else.
    let volume = generate(ProceduralKind::HeadPhantom, 32, ScalarType::U8).unwrap();
    let iso = 64.0;
    assert!((0..32 * 32 * 32).any(|i| volume.texel(i % 32, i / 32 % 32, i / 1024) == iso));
    for rule in RULES {
        let meshlets = extract_meshlets(&volume, iso, rule).unwrap();
        let reference = marching_cubes_with(&volume, iso, rule);
        if let Err(e) = meshlets.validate() {
            assert!(e.to_string().contains("repeats position"), "{e}");
        }
        assert!(
            meshlets
                .to_triangle_mesh()
                .canonical_triangle_multiset(QUANTUM)
                == reference.canonical_triangle_multiset(QUANTUM),
            "{rule:?}: triangles differ"
        );
    }
}

#[test]
fn origin_order_undoes_block_order_and_triangle_gaps() {
    // As the GPU writes them: meshlets in another order, unused triangles between them.
    for (volume, iso) in volumes() {
        let reference = extract_meshlets(&volume, iso, AmbiguityRule::default()).unwrap();
        let mut scrambled = MeshletMesh {
            positions: reference.positions.clone(),
            normals: reference.normals.clone(),
            ..MeshletMesh::default()
        };
        for m in reference.meshlets.iter().rev() {
            let start = 3 * m.triangle_offset as usize;
            let indices = &reference.local_indices[start..start + 3 * m.triangle_count() as usize];
            let mut moved = *m;
            moved.triangle_offset = scrambled.triangle_count() as u32 + 1;
            scrambled.local_indices.extend_from_slice(&[0, 0, 0]);
            scrambled.local_indices.extend_from_slice(indices);
            scrambled.meshlets.push(moved);
        }
        scrambled.validate().unwrap();
        let sorted = scrambled.in_origin_order().unwrap();
        assert_eq!(
            sorted,
            reference.in_origin_order().unwrap(),
            "{}",
            volume.name()
        );
        assert_eq!(sorted.triangle_count(), reference.triangle_count());
        assert_eq!(sorted.in_origin_order().unwrap(), sorted);
    }
}

#[test]
fn origin_order_refuses_ranges_outside_the_arrays() {
    let (volume, iso) = volumes().swap_remove(0);
    let mut mesh = extract_meshlets(&volume, iso, AmbiguityRule::default()).unwrap();
    mesh.meshlets[0].vertex_offset += mesh.positions.len() as u32;
    let error = mesh.in_origin_order().unwrap_err().to_string();
    assert!(error.contains("outside the arrays"), "{error}");
}
