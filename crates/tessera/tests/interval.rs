//! Interval shading (paper A) against the CPU reference that integrates exact ray–tet path
//! lengths per pixel: single tets, meshes, the Beer–Lambert post pass and tets clipped at the
//! near plane; and the compute path's subgroup drawing against each invocation drawing its own
//! tet, every pixel. Against the reference, pixels within a pixel of a projected tet edge are
//! left out: there the rasterizer and the reference may legitimately disagree about which tets
//! a pixel centre hits.

mod common;

use common::interval::{
    assert_matches_reference, assert_same_sums, assert_variants_match, defaults, variants, Expected,
};
use common::{assert_clean, camera, gpu, skip};
use tessera::path::Path;
use tessera::shaders;
use tessera::tet::interval::{
    ComputeScheme, GpuTetMesh, Integrand, Interval, IntervalOptions, OpticalTarget, SubgroupDraw,
    SUBGROUP_DRAW_ABOVE_PIXELS,
};
use tessera_data::tet::optical::{edge_mask, optical_depth};
use tessera_data::tet::procedural::{box_mesh, deform, sphere_mesh};
use tessera_data::tet::TetMesh;

fn single_tet(vertices: [[f32; 3]; 4]) -> TetMesh {
    let mut mesh = TetMesh::new(vertices.to_vec(), vec![[0, 1, 2, 3]]);
    mesh.validate("test tet").unwrap();
    mesh
}

#[test]
fn one_tet_with_a_triangle_silhouette() {
    // Seen from +z, the apex projects inside the base triangle: case 1.
    let mesh = single_tet([
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.1, -0.2, 1.0],
    ]);
    let covered = assert_matches_reference(
        "case 1",
        &mesh,
        &camera(0.0, 0.0, 2.5),
        (96, 96),
        false,
        false,
    );
    assert!(
        covered > 500,
        "the tet must fill part of the image ({covered} pixels)"
    );
}

/// Holds `mesh`'s pixels to the reference as usual, and also the pixels of the image's middle
/// column (or row, `along_x`) whose neighbours across it lie inside the tet, though a projected
/// edge runs through their centres.
fn assert_middle_line_matches(name: &str, mesh: &TetMesh, along_x: bool) {
    let cam = camera(0.0, 0.0, 2.5);
    let (w, h) = (65u32, 65u32);
    let gpu = gpu();
    let variants = variants(&gpu, &Integrand::TetAbsorption, false);
    if variants.is_empty() {
        skip("", "neither mesh shaders nor float atomics");
        return;
    }
    let reference = optical_depth(mesh, &cam, w, h);
    let mut edges = edge_mask(mesh, &cam, w, h, 1.0);
    let (width, middle) = (w as usize, (w / 2) as usize);
    let mut on_line = 0;
    for t in 0..width {
        let (i, step) = if along_x {
            (middle * width + t, width)
        } else {
            (t * width + middle, 1)
        };
        let inside = |j: usize| reference[j][0] > 0.0;
        if t > 0 && t + 1 < width && inside(i - step) && inside(i) && inside(i + step) {
            edges[i] = false;
            on_line += 1;
        }
    }
    assert!(
        on_line > 15,
        "{name}: {on_line} pixels of the middle line inside the tet"
    );
    let gpu_mesh = GpuTetMesh::upload(&gpu, mesh).unwrap();
    let expected = Expected {
        reference: &reference,
        edges: &edges,
        clipped: false,
    };
    assert_variants_match(&gpu, name, &gpu_mesh, &variants, &cam, (w, h), &expected);
}

#[test]
fn pixel_centres_on_a_spoke_count_once() {
    // The apex and one corner on x = 0 (then on y = 0), which projects onto the pixel centres of
    // the middle column (row) of an odd-sized image: the spoke of the proxy between them runs
    // exactly through those centres, and the top-left rule must give each to one of the two
    // triangles sharing it (a tie neither takes is a hole in the tet). The two cases differ in
    // the spoke's direction and the proxy's winding, which the rule's ties depend on.
    let vertical = single_tet([
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -0.2, 1.0],
    ]);
    assert_middle_line_matches("vertical spoke", &vertical, false);
    let horizontal = single_tet([
        [-1.0, -1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [-0.2, 0.0, 1.0],
    ]);
    assert_middle_line_matches("horizontal spoke", &horizontal, true);
}

#[test]
fn one_tet_with_a_quad_silhouette() {
    // Two opposite edges crossing in projection: case 2. Tilted and off-centre, so the depths
    // where the diagonals cross differ from every corner's (a symmetric tet hides errors there).
    let mesh = single_tet([
        [-1.0, 0.2, -0.8],
        [1.0, 0.1, -0.3],
        [0.3, -1.0, 0.5],
        [-0.2, 1.0, 0.2],
    ]);
    let covered = assert_matches_reference(
        "case 2",
        &mesh,
        &camera(0.0, 0.0, 2.5),
        (96, 96),
        false,
        true,
    );
    assert!(
        covered > 500,
        "the tet must fill part of the image ({covered} pixels)"
    );
}

#[test]
fn meshes_with_absorption_colours() {
    let mut sphere = sphere_mesh(5);
    deform(&mut sphere, 0.1);
    sphere.validate("sphere").unwrap();
    assert_matches_reference(
        "deformed sphere",
        &sphere,
        &camera(35.0, 20.0, 2.2),
        (80, 64),
        false,
        false,
    );
    let cube = box_mesh(3);
    assert!(
        cube.absorption.is_some(),
        "procedural box carries per-tet colours"
    );
    assert_matches_reference(
        "box",
        &cube,
        &camera(-60.0, 40.0, 2.4),
        (80, 64),
        false,
        false,
    );
}

#[test]
fn beer_lambert_post_pass_matches_cpu_composite() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let mesh = sphere_mesh(4);
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let (w, h) = (72, 56);
    let cam = camera(20.0, 10.0, 2.0);
    let background = [1.0, 0.95, 0.85];
    for (name, options) in defaults(&gpu) {
        let interval = Interval::new(&gpu, &compiler, &options).unwrap();
        let target = interval.target(&gpu, w, h).unwrap();
        let depth = interval.render(&gpu, &gpu_mesh, &target, &cam).unwrap();
        let (image, _ms) = interval
            .render_image(&gpu, &gpu_mesh, &cam, (w, h), background)
            .unwrap();
        let expected = tessera_data::tet::optical::composite(&depth.values, w, h, background);
        let diff = image.compare(&expected, 1);
        assert!(
            diff.fraction_within >= 0.999,
            "{name}: {} pixels differ",
            diff.pixels_outside
        );
        let darkened = image
            .pixels
            .iter()
            .filter(|&&p| p != expected.pixels[0])
            .count();
        assert!(
            darkened > (w * h / 10) as usize,
            "the mesh must absorb light somewhere"
        );
    }
    assert_clean(&gpu);
}

#[test]
fn camera_inside_the_mesh_clips_tets_at_the_near_plane() {
    // The eye 0.3 from the centre of a box whose half-size is 0.5: tets around it cross the
    // near plane with one, two and three corners in front.
    let cube = box_mesh(4);
    assert_matches_reference(
        "inside box",
        &cube,
        &camera(20.0, 15.0, 0.3),
        (80, 64),
        true,
        true,
    );
    let mut sphere = sphere_mesh(4);
    deform(&mut sphere, 0.05);
    sphere.validate("sphere").unwrap();
    assert_matches_reference(
        "inside sphere",
        &sphere,
        &camera(-50.0, -30.0, 0.2),
        (80, 64),
        true,
        false,
    );
}

#[test]
fn a_single_clipped_tet() {
    // The eye sits inside this tet, so every view ray starts on the near plane within it.
    let mesh = single_tet([
        [-1.0, -1.0, -1.0],
        [1.2, -0.8, -0.9],
        [0.1, 1.1, -1.0],
        [0.0, 0.1, 1.2],
    ]);
    assert_matches_reference(
        "clipped tet",
        &mesh,
        &camera(10.0, 5.0, 0.05),
        (64, 64),
        true,
        true,
    );
}

#[test]
fn a_subgroup_drawing_its_tets_together_adds_what_each_invocation_adds() {
    // Every pixel, edges included: both ways test each pixel with the same arithmetic, so only
    // the order of the atomic sums differs. Far and near, tets span several rows and share a
    // subgroup, and with the default limit a subgroup draws some together and leaves the rest
    // to their invocations (in both views, breaking either way's drawing fails the default's
    // comparison); from inside, large tets, and clipped ones drawn per invocation either way.
    // Where each subgroup chooses its limit, the choice calls subgroup operations before any
    // invocation branches off.
    let gpu = gpu();
    let caps = gpu.caps();
    if !caps.buffer_float32_atomic_add {
        skip("", "no float atomics for the compute path");
        return;
    }
    if !(caps.subgroup_arithmetic && caps.subgroup_ballot_and_shuffle) {
        skip(
            "",
            &format!(
                "{} lacks subgroup ballot, shuffle or arithmetic",
                caps.device_name
            ),
        );
        return;
    }
    let compiler = shaders::compiler();
    let mut mesh = box_mesh(6);
    deform(&mut mesh, 0.08);
    mesh.validate("deformed box").unwrap();
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
    let (w, h) = (96, 72);
    let interval = |subgroup_draw: SubgroupDraw| {
        let options = IntervalOptions {
            subgroup_draw,
            compute_scheme: ComputeScheme::PerTet,
            ..IntervalOptions::new(Path::Compute)
        };
        let interval = Interval::new(&gpu, &compiler, &options).unwrap();
        let target = interval.target(&gpu, w, h).unwrap();
        (interval, target)
    };
    let views = [
        ("far", 2.6, 1500),
        ("near", 1.2, 4000),
        ("inside", 0.3, 96 * 72),
    ];
    let render = |(interval, target): &(Interval, OpticalTarget), distance: f32| {
        let cam = camera(-35.0, 25.0, distance);
        interval.render(&gpu, &gpu_mesh, target, &cam).unwrap()
    };
    let reference = interval(SubgroupDraw::Off);
    let alone: Vec<_> = views.iter().map(|v| render(&reference, v.1)).collect();
    drop(reference);
    // Every tet by the subgroup, the default's mix of both within one subgroup, and limits
    // each subgroup chooses: with no set-up cost (mostly the smallest limit), a middling one,
    // and one so large that the largest limit wins (most tets alone).
    let ways = [
        SubgroupDraw::Above(0),
        SubgroupDraw::Above(SUBGROUP_DRAW_ABOVE_PIXELS),
        SubgroupDraw::Chosen { setup_pixels: 0 },
        SubgroupDraw::Chosen { setup_pixels: 64 },
        SubgroupDraw::Chosen {
            setup_pixels: 1 << 20,
        },
    ];
    for way in ways {
        let drawn = interval(way);
        for ((view, distance, min_covered), alone) in views.iter().zip(&alone) {
            let together = render(&drawn, *distance);
            let view = format!("{view}, {}", way.name());
            let covered = assert_same_sums(&view, &together.values, &alone.values);
            assert!(covered >= *min_covered, "{view}: {covered} pixels covered");
            assert_eq!(together.tiled, alone.tiled, "{view}: tiled tets");
            assert_eq!(together.clipped_near, alone.clipped_near, "{view}");
        }
    }
    assert_clean(&gpu);
}
