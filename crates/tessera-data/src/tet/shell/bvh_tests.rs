//! The shell BVH holds every face once, in boxes that contain it, within the depth a GPU stack
//! allows.
use glam::Vec3;

use super::test_meshes::named_meshes;
use super::*;

/// Checks the hierarchy below `node` and returns the faces its leaves hold.
fn check_node(bvh: &ShellBvh, shell: &ShellMesh, node: usize, level: u32, seen: &mut [u32]) {
    let n = bvh.nodes[node];
    assert!(level <= bvh.depth, "node {node} below the reported depth");
    let (lo, hi) = (Vec3::from(n.lo), Vec3::from(n.hi));
    if n.count == 0 {
        let first = n.first as usize;
        assert!(first > node && first + 1 < bvh.nodes.len(), "node {node}");
        for child in [first, first + 1] {
            let c = bvh.nodes[child];
            assert!(
                lo.cmple(Vec3::from(c.lo)).all() && hi.cmpge(Vec3::from(c.hi)).all(),
                "child {child} outside node {node}"
            );
            check_node(bvh, shell, child, level + 1, seen);
        }
        return;
    }
    for &face in &bvh.faces[n.first as usize..(n.first + n.count) as usize] {
        seen[face as usize] += 1;
        for v in shell.faces[face as usize].vertices {
            let p = shell.world()[v as usize].as_vec3();
            assert!(
                lo.cmplt(p).all() && hi.cmpgt(p).all(),
                "face {face} not strictly inside leaf {node}"
            );
        }
    }
}

#[test]
fn every_face_sits_in_exactly_one_leaf_that_contains_it() {
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        let bvh = shell.bvh();
        let mut seen = vec![0; shell.faces.len()];
        check_node(&bvh, &shell, 0, 0, &mut seen);
        assert!(seen.iter().all(|&s| s == 1), "{name}: {seen:?}");
        assert_eq!(bvh.faces.len(), shell.faces.len(), "{name}");
        assert!(bvh.depth <= BVH_MAX_DEPTH, "{name}");
        // A split pays off for these meshes: the tree is neither one leaf nor a list.
        let leaves = bvh.nodes.iter().filter(|n| n.count > 0).count();
        assert!(leaves > 1, "{name}");
        assert!(
            bvh.depth < 4 * (shell.faces.len() as f32).log2().ceil() as u32,
            "{name}: depth {} for {} faces",
            bvh.depth,
            shell.faces.len()
        );
    }
}

#[test]
fn boxes_with_one_centroid_still_split_down_to_the_depth_limit() {
    let same = vec![(Vec3::splat(-1.0), Vec3::splat(1.0)); 100];
    let bvh = build_bvh(&same);
    assert!(bvh.depth <= BVH_MAX_DEPTH);
    let held: u32 = bvh.nodes.iter().map(|n| n.count).sum();
    assert_eq!(held, 100);
    assert!(bvh.nodes.iter().all(|n| n.count as usize <= BVH_LEAF_FACES));
}

#[test]
fn no_boxes_make_one_inverted_box() {
    let bvh = build_bvh(&[]);
    assert_eq!(bvh.nodes.len(), 1);
    assert!(bvh.nodes[0].lo[0] > bvh.nodes[0].hi[0]);
    assert!(bvh.faces.is_empty());
}
