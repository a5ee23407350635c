//! Tests of shell-to-shell traversal and tet marching against brute force.
use glam::DVec3;

use super::test_meshes::{named_meshes, two_boxes};
use super::*;
use crate::tet::emission_absorption::{ExactRayIntegrator, TetStretch};
use crate::tet::procedural::box_mesh;

/// Stretches shorter than this are a ray grazing an edge or a vertex: brute force drops them
/// (no length inside), marching may report them, so comparisons leave them out.
const GRAZING: f64 = 1e-9;

/// Tolerance on entry and exit distances (world units: the mesh's longest side is 1). Both
/// sides compute in f64 by different formulas: plane distances vs barycentric depths.
const T_TOLERANCE: f64 = 1e-9;

/// A small deterministic generator of numbers in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn in_box(&mut self, half: f64) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * (2.0 * half) - DVec3::splat(half)
    }

    fn direction(&mut self) -> DVec3 {
        loop {
            let d = self.in_box(1.0);
            if d.length() > 0.1 && d.length() < 1.0 {
                return d.normalize();
            }
        }
    }
}

/// Rays from outside the unit box at the origin towards points inside it.
fn outside_rays(count: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Lcg(seed);
    (0..count)
        .map(|_| {
            let origin = rng.direction() * 1.5;
            let target = rng.in_box(0.45);
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

/// Rays starting at points inside `half` of the origin, in all directions.
fn inside_rays(count: usize, seed: u64, half: f64) -> Vec<Ray> {
    let mut rng = Lcg(seed);
    (0..count)
        .map(|_| Ray::new(rng.in_box(half), rng.direction()))
        .collect()
}

fn steps_of(segments: &[Segment]) -> Vec<TetStretch> {
    segments
        .iter()
        .flat_map(|s| &s.steps)
        .filter(|s| s.t_exit - s.t_enter > GRAZING)
        .map(|s| (s.tet as usize, s.t_enter, s.t_exit))
        .collect()
}

fn assert_same_stretches(got: &[TetStretch], want: &[TetStretch], what: &str) {
    let want: Vec<TetStretch> = want
        .iter()
        .copied()
        .filter(|s| s.2 - s.1 > GRAZING)
        .collect();
    let tets = |s: &[TetStretch]| s.iter().map(|s| s.0).collect::<Vec<_>>();
    assert_eq!(tets(got), tets(&want), "{what}: tet sequence");
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g.1 - w.1).abs() < T_TOLERANCE && (g.2 - w.2).abs() < T_TOLERANCE,
            "{what}: tet {} at {:?}, brute force {:?}",
            g.0,
            (g.1, g.2),
            (w.1, w.2)
        );
    }
}

fn brute_force(shell: &ShellMesh) -> ExactRayIntegrator {
    let zeros = vec![0.0; shell.mesh.vertices.len()];
    ExactRayIntegrator::new(&shell.mesh, &zeros)
}

fn check_against_brute_force(shell: &ShellMesh, rays: &[Ray], what: &str) -> usize {
    let reference = brute_force(shell);
    let layout = shell.layout(LayoutKind::Tet20);
    let mut stats = TraversalStats::default();
    let mut crossed = 0;
    for (i, ray) in rays.iter().enumerate() {
        let segments = trace_segments(
            shell,
            &*layout,
            ray,
            &TraversalOptions::default(),
            &mut stats,
        );
        let want = reference.crossed(ray.origin, ray.dir, ray.t_min, ray.t_max);
        assert_same_stretches(&steps_of(&segments), &want, &format!("{what}, ray {i}"));
        crossed += usize::from(!want.is_empty());
    }
    assert_eq!(stats.guard_hits(), 0, "{what}: {stats:?}");
    assert_eq!(stats.backward_steps, 0, "{what}: {stats:?}");
    crossed
}

#[test]
fn a_convex_box_from_outside_visits_the_tets_brute_force_finds() {
    let shell = ShellMesh::build(&box_mesh(4)).unwrap();
    let crossed = check_against_brute_force(&shell, &outside_rays(200, 1), "box, outside");
    assert!(crossed > 150, "{crossed} of 200 rays hit the box");
}

#[test]
fn a_convex_box_from_inside_visits_the_tets_brute_force_finds() {
    let shell = ShellMesh::build(&box_mesh(4)).unwrap();
    let rays = inside_rays(200, 2, 0.45);
    assert_eq!(check_against_brute_force(&shell, &rays, "box, inside"), 200);
    // The first tet starts at the origin, not at the shell behind it.
    let layout = shell.layout(LayoutKind::Tet16);
    let mut stats = TraversalStats::default();
    for ray in &rays {
        let segments = trace_segments(
            &shell,
            &*layout,
            ray,
            &TraversalOptions::default(),
            &mut stats,
        );
        assert_eq!(segments.len(), 1);
        assert_eq!(segments[0].steps[0].t_enter, 0.0);
    }
}

#[test]
fn every_mesh_matches_brute_force_from_outside_and_inside() {
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        check_against_brute_force(&shell, &outside_rays(60, 3), &format!("{name}, outside"));
        check_against_brute_force(&shell, &inside_rays(60, 4, 0.3), &format!("{name}, inside"));
    }
}

#[test]
fn a_gap_splits_the_ray_into_two_segments() {
    let shell = ShellMesh::build(&two_boxes()).unwrap();
    let layout = shell.layout(LayoutKind::Tet32);
    let mut stats = TraversalStats::default();
    let options = TraversalOptions::default();
    // The mesh spans 3 units along x, so in world space the boxes sit at -1/2 ≤ x ≤ -1/6 and
    // 1/6 ≤ x ≤ 1/2; rays along x cross both.
    let across = DVec3::new(1.0, 0.013, -0.021).normalize();
    for origin in [DVec3::new(-1.0, 0.05, 0.07), DVec3::new(-0.3, -0.1, 0.11)] {
        let ray = Ray::new(origin, across);
        let segments = trace_segments(&shell, &*layout, &ray, &options, &mut stats);
        assert_eq!(segments.len(), 2, "{origin}");
        assert!(segments.iter().all(|s| s.end == SegmentEnd::Shell));
        let first_exit = segments[0].steps.last().unwrap().t_exit;
        let second_entry = segments[1].steps[0].t_enter;
        let gap = second_entry - first_exit;
        // The vertices are f32.
        assert!((gap - 1.0 / 3.0 / across.x).abs() < 1e-6, "gap {gap}");
        check_against_brute_force(&shell, &[ray], "two boxes");
    }
    // Starting in the gap, only the second box is ahead.
    let ray = Ray::new(DVec3::new(0.0, 0.05, 0.07), across);
    assert_eq!(
        trace_segments(&shell, &*layout, &ray, &options, &mut stats).len(),
        1
    );
    assert_eq!(stats.segments, 5);
}

#[test]
fn all_layouts_visit_the_same_tets_through_the_same_faces() {
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        let mut rays = outside_rays(40, 5);
        rays.extend(inside_rays(40, 6, 0.3));
        let layouts: Vec<Box<dyn TetLayout>> =
            LayoutKind::ALL.iter().map(|&k| shell.layout(k)).collect();
        for (i, ray) in rays.iter().enumerate() {
            let traced: Vec<Vec<Segment>> = layouts
                .iter()
                .map(|l| {
                    let mut stats = TraversalStats::default();
                    trace_segments(&shell, &**l, ray, &TraversalOptions::default(), &mut stats)
                })
                .collect();
            assert_eq!(traced[0], traced[1], "{name} ray {i}: tet32 vs tet20");
            assert_eq!(traced[0], traced[2], "{name} ray {i}: tet32 vs tet16");
        }
    }
}

#[test]
fn entered_faces_chain_from_tet_to_tet() {
    let shell = ShellMesh::build(&box_mesh(3)).unwrap();
    let layout = shell.layout(LayoutKind::Tet16);
    let mut stats = TraversalStats::default();
    for ray in outside_rays(50, 7) {
        for segment in trace_segments(
            &shell,
            &*layout,
            &ray,
            &TraversalOptions::default(),
            &mut stats,
        ) {
            for pair in segment.steps.windows(2) {
                let (a, b) = (&pair[0], &pair[1]);
                assert_eq!(a.t_exit, b.t_enter, "a shared face gives one distance");
                let mut face = b.entered_face;
                face.sort_unstable();
                let shared: Vec<u32> = shell.mesh.tets[a.tet as usize]
                    .iter()
                    .copied()
                    .filter(|v| shell.mesh.tets[b.tet as usize].contains(v))
                    .collect();
                let mut shared_sorted = shared.clone();
                shared_sorted.sort_unstable();
                assert_eq!(face.to_vec(), shared_sorted);
            }
        }
    }
}

/// Rays along the grid lines and face diagonals of an axis-aligned box run exactly through
/// vertices and along edges and faces: the perturbation must still carry them through the
/// whole box once, neither stopping nor leaking.
#[test]
fn rays_along_edges_and_through_vertices_cross_the_box_exactly_once() {
    let n = 4;
    let shell = ShellMesh::build(&box_mesh(n)).unwrap();
    let mut stats = TraversalStats::default();
    for kind in LayoutKind::ALL {
        let layout = shell.layout(kind);
        // Interior grid lines only: those on the boundary run along the shell itself.
        for i in 1..n {
            for j in 1..n {
                let a = -0.5 + f64::from(i) / f64::from(n);
                let b = -0.5 + f64::from(j) / f64::from(n);
                for (origin, dir) in [
                    (DVec3::new(-1.0, a, b), DVec3::X),
                    (DVec3::new(a, 1.0, b), -DVec3::Y),
                    (DVec3::new(a, b, -1.0), DVec3::Z),
                    (DVec3::new(-1.0, -1.0, a), DVec3::new(1.0, 1.0, 0.0)),
                ] {
                    let ray = Ray::new(origin, dir.normalize());
                    let segments = trace_segments(
                        &shell,
                        &*layout,
                        &ray,
                        &TraversalOptions::default(),
                        &mut stats,
                    );
                    let length: f64 = segments
                        .iter()
                        .flat_map(|s| &s.steps)
                        .map(|s| s.t_exit - s.t_enter)
                        .sum();
                    let inside = if dir.y != 0.0 && dir.x != 0.0 {
                        std::f64::consts::SQRT_2
                    } else {
                        1.0
                    };
                    assert!(segments.len() <= 1, "{kind:?} {origin} {dir}");
                    assert!(
                        (length - inside).abs() < 1e-9,
                        "{kind:?} {origin} {dir}: {length}"
                    );
                }
            }
        }
    }
    assert_eq!(stats.guard_hits(), 0, "{stats:?}");
}

/// Degenerate meshes as they come: a vertex moved onto others' planes (flat tets, some
/// inverted) or beyond them (inverted), an edge collapsed so that tets repeat a vertex (flat,
/// with faces glued to each other). The walk's decisions stay consistent, so every ray ends
/// at the shell, and inverted tets are counted.
#[test]
fn flat_collapsed_and_inverted_tets_do_not_hang_the_walk() {
    let rays: Vec<Ray> = outside_rays(300, 11)
        .into_iter()
        .chain(inside_rays(300, 12, 0.4))
        .collect();
    let mesh = box_mesh(2);
    let centre = mesh.vertices.iter().position(|p| *p == [0.0; 3]).unwrap();
    let corner = mesh.vertices.iter().position(|p| *p == [1.0; 3]).unwrap() as u32;
    let moved = |to: [f32; 3]| {
        let mut m = mesh.clone();
        m.vertices[centre] = to;
        m
    };
    let mut collapsed = mesh.clone();
    for v in collapsed.tets.iter_mut().flatten() {
        if *v == centre as u32 {
            *v = corner;
        }
    }
    let cases = [
        ("flat", moved([1.0, 1.0, 0.0])),
        ("inverted", moved([0.9, 0.2, -0.7])),
        ("collapsed", collapsed),
    ];
    for (name, degenerate) in cases {
        let flat = (0..degenerate.tets.len())
            .filter(|&t| degenerate.volume_of(t) == 0.0)
            .count();
        assert_eq!(flat > 0, name != "inverted", "{name}: {flat} flat tets");
        let shell = ShellMesh::build(&degenerate).unwrap();
        for kind in LayoutKind::ALL {
            let layout = shell.layout(kind);
            let mut stats = TraversalStats::default();
            let options = TraversalOptions {
                max_steps_per_segment: 100,
            };
            for ray in &rays {
                trace_segments(&shell, &*layout, ray, &options, &mut stats);
            }
            assert_eq!(stats.guard_hits(), 0, "{name} {kind:?}: {stats:?}");
            if name != "collapsed" {
                assert!(stats.backward_steps > 0, "{name} {kind:?}: {stats:?}");
            }
        }
    }
}

/// A neighbour table that glues the first and the second tet of a ray's path to themselves
/// (as a collapsed tet's two copies of one face are glued) sends the walk back and forth
/// between them for ever: the loop guard ends it and counts it.
#[test]
fn a_walk_that_circles_is_ended_by_the_loop_guard_and_counted() {
    let shell = ShellMesh::build(&box_mesh(2)).unwrap();
    let ray = Ray::new(
        DVec3::new(-1.0, 0.013, 0.021),
        DVec3::new(1.0, 0.011, -0.007).normalize(),
    );
    let mut stats = TraversalStats::default();
    let options = TraversalOptions {
        max_steps_per_segment: 50,
    };
    let clean = shell.layout(LayoutKind::Tet32);
    let path = trace_segments(&shell, &*clean, &ray, &options, &mut stats);
    assert_eq!(stats.guard_hits(), 0);
    let steps = &path[0].steps;
    assert!(steps.len() > 3);
    let face_of = |tet: u32, face: [u32; 3]| {
        let t = shell.mesh.tets[tet as usize];
        (0..4).find(|&f| !face.contains(&t[f])).unwrap()
    };
    let mut glued = shell.neighbours.clone();
    let (first, second) = (steps[0].tet, steps[1].tet);
    glued[first as usize][face_of(first, steps[0].entered_face)] = first;
    glued[second as usize][face_of(second, steps[2].entered_face)] = second;
    for kind in LayoutKind::ALL {
        let layout = build_layout(kind, &shell.mesh.tets, &glued);
        let mut stats = TraversalStats::default();
        let segments = trace_segments(&shell, &*layout, &ray, &options, &mut stats);
        assert!(stats.guard_hits() >= 1, "{kind:?}: {stats:?}");
        assert_eq!(segments[0].end, SegmentEnd::Guard, "{kind:?}");
    }
}
