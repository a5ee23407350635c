use super::*;

/// Two 4×4×4 blocks side by side along x, one triangle each, sharing the vertex at x = 4.
fn two_blocks() -> PmbMesh {
    PmbMesh {
        block_size: [4, 4, 4],
        positions: vec![
            [3.5, 1.0, 1.0],
            [4.0, 1.5, 1.0],
            [3.5, 2.0, 1.0],
            [4.0, 1.5, 1.0],
            [4.5, 1.0, 1.0],
            [4.5, 2.0, 1.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 6],
        indices: vec![0, 1, 2, 0, 1, 2],
        blocks: vec![
            PmbBlock {
                block: [0, 0, 0],
                first_vertex: 0,
                vertex_count: 3,
                first_index: 0,
                triangle_count: 1,
            },
            PmbBlock {
                block: [1, 0, 0],
                first_vertex: 3,
                vertex_count: 3,
                first_index: 3,
                triangle_count: 1,
            },
        ],
    }
}

#[test]
fn triangles_are_in_global_positions() {
    let mesh = two_blocks();
    mesh.validate().unwrap();
    let triangles: Vec<_> = mesh.triangles().collect();
    assert_eq!(triangles.len(), 2);
    assert_eq!(
        triangles[1],
        [[4.0, 1.5, 1.0], [4.5, 1.0, 1.0], [4.5, 2.0, 1.0]]
    );
    assert_eq!(
        mesh.to_triangle_mesh().triangles,
        vec![[0, 1, 2], [3, 4, 5]]
    );
}

#[test]
fn welding_merges_the_vertex_both_blocks_hold() {
    let welded = two_blocks().welded();
    assert_eq!(welded.vertex_count(), 5);
    assert_eq!(welded.triangles, vec![[0, 1, 2], [1, 3, 4]]);
}

#[test]
fn validation_reports_what_consumers_rely_on() {
    let expect = |mesh: PmbMesh, what: &str| {
        let error = mesh.validate().unwrap_err().to_string();
        assert!(error.contains(what), "{error}");
    };
    let mut m = two_blocks();
    m.indices[4] = 3;
    expect(m, "local index 3 of 3");
    let mut m = two_blocks();
    m.positions[2] = m.positions[0];
    expect(m, "repeats position");
    let mut m = two_blocks();
    m.indices[5] = 1;
    expect(m, "vertex 2 is used by no triangle");
    let mut m = two_blocks();
    m.positions[4][0] = 9.0;
    expect(m, "outside the box");
    let mut m = two_blocks();
    m.blocks[1].block = [0, 0, 0];
    expect(m, "listed twice");
    let mut m = two_blocks();
    m.blocks[1].first_index = 4;
    expect(m, "triangle range outside");
    let mut m = two_blocks();
    m.normals.pop();
    expect(m, "5 normals for 6 positions");
}

#[test]
fn every_block_size_keeps_indices_16_bit() {
    for size in PmbBlockSize::ALL {
        assert!(size.max_vertices() <= 1 << 16, "{}", size.name());
    }
    assert_eq!(PmbBlockSize::B888.box_points(), 729);
    assert_eq!(PmbBlockSize::B844.grid([18, 9, 2]), [3, 2, 1]);
}
