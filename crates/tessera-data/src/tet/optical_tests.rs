use glam::{DMat3, DVec3, Vec3};

use super::*;
use crate::camera::{GridFrame, OrbitCamera, Projection};
use crate::tet::procedural::box_mesh;
use crate::tet::TetMesh;

fn camera(azimuth_deg: f32, elevation_deg: f32, distance: f32, fov_y_deg: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg,
        elevation_deg,
        distance,
        fov_y_deg,
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
    }
}

/// A camera whose vertical field of view shows `half_extent` world units either side of the
/// origin.
fn framing(azimuth_deg: f32, elevation_deg: f32, distance: f32, half_extent: f32) -> OrbitCamera {
    let fov = 2.0 * (half_extent / distance).atan().to_degrees();
    camera(azimuth_deg, elevation_deg, distance, fov)
}

/// World-space unit ray of pixel (x, y), written out from the pixel model.
fn pixel_ray(cam: &OrbitCamera, x: u32, y: u32, w: u32, h: u32) -> (DVec3, DVec3) {
    let (f, r, u) = cam.basis();
    let tan_y = f64::from((cam.fov_y_deg.to_radians() * 0.5).tan());
    let tan_x = tan_y * f64::from(w) / f64::from(h);
    let sx = (2.0 * (f64::from(x) + 0.5) / f64::from(w) - 1.0) * tan_x;
    let sy = (1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(h)) * tan_y;
    let d = (f.as_dvec3() + sx * r.as_dvec3() + sy * u.as_dvec3()).normalize();
    (cam.eye().as_dvec3(), d)
}

/// The chord of a ray through a tet found from barycentric coordinates: each is affine in
/// the ray parameter and must stay non-negative. Independent of the half-space code.
fn barycentric_interval(o: DVec3, d: DVec3, c: [DVec3; 4]) -> Option<(f64, f64)> {
    let inv = DMat3::from_cols(c[1] - c[0], c[2] - c[0], c[3] - c[0]).inverse();
    let l0 = inv * (o - c[0]);
    let l1 = inv * (o + d - c[0]);
    let at0 = [1.0 - l0.x - l0.y - l0.z, l0.x, l0.y, l0.z];
    let at1 = [1.0 - l1.x - l1.y - l1.z, l1.x, l1.y, l1.z];
    let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
    for k in 0..4 {
        let (a, b) = (at0[k], at1[k] - at0[k]);
        // a + t b >= 0
        if b > 0.0 {
            lo = lo.max(-a / b);
        } else if b < 0.0 {
            hi = hi.min(-a / b);
        } else if a < 0.0 {
            return None;
        }
    }
    (hi > lo).then_some((lo, hi))
}

/// Chord of a ray through the world cube [-0.5, 0.5]^3 from `t_min` on (slab method).
fn cube_chord(o: DVec3, d: DVec3, t_min: f64) -> f64 {
    let t0 = (DVec3::splat(-0.5) - o) / d;
    let t1 = (DVec3::splat(0.5) - o) / d;
    let enter = t0.min(t1).max_element().max(t_min);
    let exit = t0.max(t1).min_element();
    (exit - enter).max(0.0)
}

/// Apex above the interior of its base: seen from +Z the apex projects onto the bounds'
/// centre, so the centre pixel's ray runs down the apex axis through the apex vertex.
fn face_on_tet() -> TetMesh {
    TetMesh::new(
        vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.5],
        ],
        vec![[0, 1, 2, 3]],
    )
}

fn unit(mut mesh: TetMesh) -> TetMesh {
    mesh.absorption = None;
    mesh
}

fn channel(od: &[[f32; 3]], c: usize) -> Vec<f32> {
    od.iter().map(|p| p[c]).collect()
}

#[test]
fn mesh_frame_centres_and_scales_to_unit_longest_side() {
    let mesh = box_mesh(4);
    let frame = MeshFrame::of(&mesh);
    assert!(frame.centre.length() < 1e-6);
    assert!((frame.scale - 0.5).abs() < 1e-7);
    let mut shifted = face_on_tet();
    for p in &mut shifted.vertices {
        p[0] = p[0] * 3.0 + 10.0;
    }
    let frame = MeshFrame::of(&shifted);
    assert!((frame.centre - Vec3::new(10.0, 0.0, 0.75)).length() < 1e-6);
    assert!((frame.scale - 1.0 / 6.0).abs() < 1e-7);
    for p in &shifted.vertices {
        let p = Vec3::from(*p);
        let m = frame.mesh_to_world().transform_point3(p);
        assert!((m - frame.to_world(p)).length() < 1e-6);
        assert!(frame.to_world(p).abs().max_element() <= 0.5 + 1e-6);
    }
}

#[test]
fn near_plane_matches_projection() {
    for d in [0.05, 0.2, 0.87, 1.8, 20.0] {
        let cam = camera(10.0, 5.0, d, 40.0);
        let proj = Projection::new(&cam, &GridFrame::new([8, 8, 8], [1.0; 3]), 64, 48);
        assert_eq!(near_plane(&cam), proj.near);
        assert_eq!(Projection::near_far(&cam), (proj.near, proj.far));
    }
}

#[test]
fn regular_tet_axis_chord_is_its_height() {
    let a = 0.8_f32;
    let r = a / 3.0_f32.sqrt();
    let h = a * (2.0_f32 / 3.0).sqrt();
    let base = [0.0_f32, 120.0, 240.0].map(|deg: f32| {
        let t = deg.to_radians();
        Vec3::new(r * t.cos(), r * t.sin(), 0.0)
    });
    let corners = [base[0], base[1], base[2], Vec3::new(0.0, 0.0, h)];
    // Through the centroid of the base, from above and from below.
    let (t0, t1) = ray_tet_interval(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, corners).unwrap();
    assert!((t0 - (5.0 - h)).abs() < 1e-5 && (t1 - 5.0).abs() < 1e-5);
    let (t0, t1) = ray_tet_interval(Vec3::new(0.0, 0.0, -2.0), Vec3::Z, corners).unwrap();
    assert!((t0 - 2.0).abs() < 1e-5 && (t1 - (2.0 + h)).abs() < 1e-5);
    // Origin inside enters at 0; either orientation works.
    let flipped = [base[0], base[2], base[1], corners[3]];
    let (t0, t1) = ray_tet_interval(Vec3::new(0.0, 0.0, 0.1), Vec3::Z, flipped).unwrap();
    assert_eq!(t0, 0.0);
    assert!((t1 - (h - 0.1)).abs() < 1e-5);
    // Misses: beside it, pointing away from it, and a flat tet.
    assert!(ray_tet_interval(Vec3::new(2.0, 0.0, 5.0), -Vec3::Z, corners).is_none());
    assert!(ray_tet_interval(Vec3::new(0.0, 0.0, 5.0), Vec3::Z, corners).is_none());
    let flat = [base[0], base[1], base[2], Vec3::ZERO];
    assert!(ray_tet_interval(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, flat).is_none());
}

#[test]
fn rays_through_edges_and_vertices_are_finite() {
    let c = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    // Along an edge's line, through a vertex, grazing a face: zero or finite lengths.
    let cases = [
        (Vec3::new(-1.0, 0.0, 0.0), Vec3::X),
        (Vec3::new(1.0, 1.0, 1.0), -Vec3::ONE.normalize()),
        (Vec3::new(0.5, 0.5, 5.0), -Vec3::Z),
        (Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
    ];
    for (o, d) in cases {
        if let Some((a, b)) = ray_tet_interval(o, d, c) {
            assert!(a.is_finite() && b.is_finite() && b > a, "{o} {d}: {a} {b}");
        }
    }
    let (a, b) = ray_tet_interval(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z, c).unwrap();
    assert!((b - a - 0.5).abs() < 1e-6);
    // Through the vertex at the origin along the diagonal: it enters there.
    let (a, b) = ray_tet_interval(Vec3::splat(-1.0), Vec3::ONE.normalize(), c).unwrap();
    assert!((a - 3.0_f32.sqrt()).abs() < 1e-5);
    assert!((b - a - 3.0_f32.sqrt() / 3.0).abs() < 1e-5);
}

#[test]
fn interval_agrees_with_barycentric_clipping() {
    let mut seed = 12345_u64;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let mut hits = 0;
    for _ in 0..2000 {
        let c = [0; 4].map(|_| DVec3::new(rnd(), rnd(), rnd()));
        let vol = (c[1] - c[0]).dot((c[2] - c[0]).cross(c[3] - c[0]));
        if vol.abs() < 1e-2 {
            continue;
        }
        let o = DVec3::new(rnd(), rnd(), rnd()) * 3.0;
        let target = (c[0] + c[1] + c[2] + c[3]) * 0.25 + DVec3::new(rnd(), rnd(), rnd()) * 0.3;
        let d = (target - o).normalize();
        let ours = ray_tet_interval(o.as_vec3(), d.as_vec3(), c.map(|p| p.as_vec3()));
        let theirs = barycentric_interval(o, d, c);
        match (ours, theirs) {
            (Some((a, b)), Some((p, q))) => {
                hits += 1;
                assert!((f64::from(a) - p).abs() < 1e-4, "{a} vs {p}");
                assert!((f64::from(b) - q).abs() < 1e-4, "{b} vs {q}");
            }
            (None, None) => {}
            (Some((a, b)), None) => assert!(b - a < 1e-4, "only ours: {a} {b}"),
            (None, Some((p, q))) => assert!(q - p < 1e-4, "only theirs: {p} {q}"),
        }
    }
    assert!(hits > 500, "{hits} hits");
}

#[test]
fn face_on_tet_centre_pixel_is_the_apex_height() {
    // Case 1: the whole base faces the camera on +Z; the centre pixel's ray runs from the
    // apex straight down to the base: 1.5 mesh units, scale 1/2, so 0.75 world units.
    let mesh = face_on_tet();
    let cam = camera(0.0, 0.0, 3.0, 40.0);
    let (w, h) = (65, 65);
    let od = optical_depth(&mesh, &cam, w, h);
    assert_eq!(od.len(), (w * h) as usize);
    let centre = od[(32 * w + 32) as usize];
    for c in centre {
        assert!((c - 0.75).abs() < 1e-5, "{centre:?}");
    }
    // Every pixel agrees with barycentric clipping of its ray in world space.
    let frame = MeshFrame::of(&mesh);
    let corners = [0, 1, 2, 3].map(|v| frame.to_world(Vec3::from(mesh.vertices[v])).as_dvec3());
    let mut covered = 0;
    for y in 0..h {
        for x in 0..w {
            let (o, d) = pixel_ray(&cam, x, y, w, h);
            let expect = barycentric_interval(o, d, corners).map_or(0.0, |(a, b)| b - a);
            let got = od[(y * w + x) as usize];
            assert!(
                (f64::from(got[0]) - expect).abs() < 1e-5,
                "({x},{y}) {got:?} {expect}"
            );
            assert_eq!(got[0], got[1]);
            covered += usize::from(expect > 0.0);
        }
    }
    assert!(covered > 200, "{covered}");
}

/// Sum over pixels of optical depth (channel 0) times the pixel's area at the origin's depth.
fn integrate(od: &[[f32; 3]], cam: &OrbitCamera, w: u32, h: u32) -> f64 {
    let tan_y = f64::from((cam.fov_y_deg.to_radians() * 0.5).tan());
    let tan_x = tan_y * f64::from(w) / f64::from(h);
    let d = f64::from(cam.distance);
    let area = (2.0 * tan_x * d / f64::from(w)) * (2.0 * tan_y * d / f64::from(h));
    od.iter().map(|p| f64::from(p[0])).sum::<f64>() * area
}

#[test]
fn quad_projection_integrates_to_volume() {
    // Case 2: opposite edges along x (at z = 0.5) and y (at z = -0.5) both perpendicular to
    // the view along -Z, so the tet projects to a quad. Volume 2/3, scale 1/2: 1/12.
    let mesh = TetMesh::new(
        vec![
            [-1.0, 0.0, 0.5],
            [1.0, 0.0, 0.5],
            [0.0, -1.0, -0.5],
            [0.0, 1.0, -0.5],
        ],
        vec![[0, 1, 2, 3]],
    );
    assert!((mesh.volume_of(0).abs() - 2.0 / 3.0).abs() < 1e-9);
    let cam = framing(0.0, 0.0, 40.0, 0.55);
    let (w, h) = (128, 128);
    let od = optical_depth(&mesh, &cam, w, h);
    let volume = integrate(&od, &cam, w, h);
    assert!((volume / (1.0 / 12.0) - 1.0).abs() < 0.005, "{volume}");
}

#[test]
fn box_mesh_integrates_to_world_volume() {
    let mesh = unit(box_mesh(4));
    let cam = framing(30.0, 20.0, 40.0, 0.9);
    let (w, h) = (128, 128);
    let od = optical_depth(&mesh, &cam, w, h);
    let volume = integrate(&od, &cam, w, h);
    assert!((volume - 1.0).abs() < 0.005, "{volume}");
}

#[test]
fn differently_split_cubes_give_the_same_depths() {
    let (a, b) = (unit(box_mesh(2)), unit(box_mesh(3)));
    let cam = OrbitCamera::default();
    let (w, h) = (96, 80);
    let (oa, ob) = (optical_depth(&a, &cam, w, h), optical_depth(&b, &cam, w, h));
    let (ma, mb) = (
        edge_mask(&a, &cam, w, h, 1.0),
        edge_mask(&b, &cam, w, h, 1.0),
    );
    let near = f64::from(near_plane(&cam));
    let mut compared = 0;
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let (o, d) = pixel_ray(&cam, x, y, w, h);
            let chord = cube_chord(o, d, near / d.dot(cam.basis().0.as_dvec3()));
            // Everywhere: both match the analytic chord of the cube.
            for od in [oa[i][0], ob[i][0]] {
                assert!(
                    (f64::from(od) - chord).abs() < 1e-5,
                    "({x},{y}) {od} {chord}"
                );
            }
            if ma[i] || mb[i] {
                continue;
            }
            let (p, q) = (oa[i][0], ob[i][0]);
            assert!(
                (p - q).abs() <= 1e-4 * p.abs().max(q.abs()),
                "({x},{y}) {p} {q}"
            );
            compared += usize::from(p > 0.0);
        }
    }
    assert!(compared > 600, "{compared}");
}

#[test]
fn rays_along_shared_faces_and_edges_count_once() {
    // Looking down -Z with an odd image: the centre column's rays lie in the plane x = 0 and
    // the centre pixel's ray runs along the grid line x = y = 0, both shared by many tets.
    let cam = camera(0.0, 0.0, 2.0, 40.0);
    let (w, h) = (65, 65);
    let near = f64::from(near_plane(&cam));
    let forward = cam.basis().0.as_dvec3();
    for mesh in [unit(box_mesh(2)), unit(box_mesh(4))] {
        let od = optical_depth(&mesh, &cam, w, h);
        for y in 0..h {
            for x in 0..w {
                let (o, d) = pixel_ray(&cam, x, y, w, h);
                let chord = cube_chord(o, d, near / d.dot(forward));
                let got = od[(y * w + x) as usize][0];
                assert!(
                    (f64::from(got) - chord).abs() < 1e-5,
                    "({x},{y}) {got} {chord}"
                );
            }
        }
        assert!((od[(32 * w + 32) as usize][0] - 1.0).abs() < 1e-6);
    }
}

#[test]
fn ray_in_a_shared_face_belongs_to_one_tet() {
    // Two tets sharing the face in the plane x = 0; the ray runs inside that face.
    let shared = [
        Vec3::new(0.0, -1.0, -1.0),
        Vec3::new(0.0, 1.0, -1.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    let left = [shared[0], shared[1], shared[2], Vec3::new(-1.0, 0.0, 0.0)];
    let right = [shared[0], shared[2], shared[1], Vec3::new(1.0, 0.0, 0.0)];
    let (o, d) = (Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
    let a = ray_tet_interval(o, d, left);
    let b = ray_tet_interval(o, d, right);
    assert!(a.is_some() != b.is_some(), "{a:?} {b:?}");
    let (t0, t1) = a.or(b).unwrap();
    assert!((t1 - t0 - 2.0).abs() < 1e-6);
}

#[test]
fn camera_inside_counts_from_the_near_plane() {
    let mesh = unit(box_mesh(4));
    // Eye at (0, 0, 0.2) looking down -Z: the wall at z = -0.5 is 0.7 away.
    let cam = camera(0.0, 0.0, 0.2, 60.0);
    let near = f64::from(near_plane(&cam));
    assert!(near > 0.0 && near < 1e-3);
    let (w, h) = (33, 25);
    let od = optical_depth(&mesh, &cam, w, h);
    let centre = od[(12 * w + 16) as usize];
    assert!(
        (f64::from(centre[0]) - (0.7 - near)).abs() < 1e-5,
        "{centre:?}"
    );
    let forward = cam.basis().0.as_dvec3();
    for (x, y) in [(0, 0), (32, 24), (5, 20), (16, 12), (30, 3)] {
        let (o, d) = pixel_ray(&cam, x, y, w, h);
        let expect = cube_chord(o, d, near / d.dot(forward));
        let got = od[(y * w + x) as usize][0];
        assert!(
            (f64::from(got) - expect).abs() < 1e-5,
            "({x},{y}) {got} {expect}"
        );
    }
    // Far enough inside, the near plane cuts a noticeable slice off: camera near the wall.
    let cam = camera(0.0, 0.0, 0.45, 60.0);
    let od = optical_depth(&mesh, &cam, w, h);
    let expect = 0.95 - f64::from(near_plane(&cam));
    assert!((f64::from(od[(12 * w + 16) as usize][0]) - expect).abs() < 1e-5);
}

#[test]
fn absorption_scales_channels_independently() {
    let plain = unit(box_mesh(2));
    let cam = OrbitCamera::default();
    let (w, h) = (48, 40);
    let base = channel(&optical_depth(&plain, &cam, w, h), 0);

    let mut tinted = plain.clone();
    tinted.absorption = Some(vec![[1.0, 2.0, 0.0]; plain.tet_count()]);
    let od = optical_depth(&tinted, &cam, w, h);
    for (p, b) in od.iter().zip(&base) {
        assert!((p[0] - b).abs() <= 1e-6 * b.max(1.0));
        assert!((p[1] - 2.0 * b).abs() <= 2e-6 * b.max(1.0));
        assert_eq!(p[2], 0.0);
    }

    // Red for the tets with x < 0 (even regions), green for the rest: red + green = plain.
    let regions = box_mesh(2).regions.unwrap();
    let mut split = plain.clone();
    split.absorption = Some(
        regions
            .iter()
            .map(|r| {
                if r & 1 == 0 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                }
            })
            .collect(),
    );
    let od = optical_depth(&split, &cam, w, h);
    for (p, b) in od.iter().zip(&base) {
        assert!((p[0] + p[1] - b).abs() <= 1e-5 * b.max(1.0));
        assert_eq!(p[2], 0.0);
    }
    assert!(od.iter().any(|p| p[0] > 0.1 && p[1] == 0.0));
    assert!(od.iter().any(|p| p[1] > 0.1 && p[0] == 0.0));
}

#[test]
fn transmittance_and_composite_follow_beer_lambert() {
    let od = vec![[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [50.0, 50.0, 50.0]];
    let t = transmittance(&od);
    assert_eq!(t[0], [1.0, 1.0, 1.0]);
    assert!((t[1][0] - (-1.0_f32).exp()).abs() < 1e-7);
    assert!((t[1][1] - (-2.0_f32).exp()).abs() < 1e-7);
    assert!((t[1][2] - (-0.5_f32).exp()).abs() < 1e-7);
    let bg = [1.0, 0.5, 0.2];
    let img = composite(&od, 3, 1, bg);
    assert_eq!((img.width, img.height), (3, 1));
    assert_eq!(img.pixels[0], pack_rgba8([1.0, 0.5, 0.2, 1.0]));
    assert_eq!(
        img.pixels[1],
        pack_rgba8([
            (-1.0_f32).exp(),
            0.5 * (-2.0_f32).exp(),
            0.2 * (-0.5_f32).exp(),
            1.0
        ])
    );
    assert_eq!(img.pixels[2], pack_rgba8([0.0, 0.0, 0.0, 1.0]));
}

#[test]
fn edge_mask_marks_projected_edges_only() {
    let mesh = face_on_tet();
    let cam = camera(20.0, 15.0, 3.0, 40.0);
    let (w, h) = (80, 64);
    let margin = 1.5_f32;
    let mask = edge_mask(&mesh, &cam, w, h, margin);
    // Project the corners with the GPU's matrices (Projection's world_to_clip after the
    // mesh frame) and sample the projected edges densely.
    let frame = MeshFrame::of(&mesh);
    let proj = Projection::new(&cam, &GridFrame::new([2, 2, 2], [1.0; 3]), w, h);
    let to_clip = proj.world_to_clip * frame.mesh_to_world();
    let px: Vec<(f32, f32)> = mesh
        .vertices
        .iter()
        .map(|p| {
            let c = to_clip * Vec3::from(*p).extend(1.0);
            let ndc = c.truncate() / c.w;
            (
                (ndc.x + 1.0) * 0.5 * w as f32,
                (ndc.y + 1.0) * 0.5 * h as f32,
            )
        })
        .collect();
    let mut samples = Vec::new();
    for i in 0..4 {
        for j in i + 1..4 {
            for k in 0..=2000 {
                let s = k as f32 / 2000.0;
                samples.push((
                    px[i].0 + (px[j].0 - px[i].0) * s,
                    px[i].1 + (px[j].1 - px[i].1) * s,
                ));
            }
        }
    }
    let (mut marked, mut clear) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let c = (x as f32 + 0.5, y as f32 + 0.5);
            let dist = samples
                .iter()
                .map(|s| (s.0 - c.0).hypot(s.1 - c.1))
                .fold(f32::INFINITY, f32::min);
            let m = mask[(y * w + x) as usize];
            if dist < margin - 0.1 {
                assert!(m, "({x},{y}) at {dist} px not marked");
                marked += 1;
            } else if dist > margin + 0.1 {
                assert!(!m, "({x},{y}) at {dist} px marked");
                clear += 1;
            }
        }
    }
    assert!(marked > 100 && clear > 2000, "{marked} {clear}");
}

#[test]
fn empty_images_and_meshes() {
    let cam = OrbitCamera::default();
    assert!(optical_depth(&box_mesh(1), &cam, 0, 10).is_empty());
    assert!(edge_mask(&box_mesh(1), &cam, 10, 0, 1.0).is_empty());
    let od = optical_depth(&TetMesh::default(), &cam, 4, 3);
    assert_eq!(od, vec![[0.0; 3]; 12]);
}

/// `cargo test --release -p tessera-data optical_speed -- --ignored --nocapture`
#[test]
#[ignore]
fn optical_speed() {
    for mesh in [box_mesh(20), crate::tet::procedural::sphere_mesh(20)] {
        let cam = OrbitCamera::default();
        let start = std::time::Instant::now();
        let od = optical_depth(&mesh, &cam, 128, 128);
        let t = start.elapsed();
        let start = std::time::Instant::now();
        let mask = edge_mask(&mesh, &cam, 128, 128, 1.0);
        println!(
            "{} tets: optical_depth {t:?}, edge_mask {:?} ({} masked, sum {})",
            mesh.tet_count(),
            start.elapsed(),
            mask.iter().filter(|&&m| m).count(),
            od.iter().map(|p| p[0]).sum::<f32>()
        );
    }
    let cam = camera(10.0, 5.0, 0.3, 70.0);
    let mesh = box_mesh(20);
    let start = std::time::Instant::now();
    optical_depth(&mesh, &cam, 128, 128);
    println!("camera inside: {:?}", start.elapsed());
}
