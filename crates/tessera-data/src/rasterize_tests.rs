//! Tests of `rasterize`.
use super::*;
use crate::image::{coverage_of, silhouette_iou};
use crate::marching_cubes::marching_cubes;
use crate::raycast;
use crate::volume::{Samples, Volume};

const W: u32 = 128;
const H: u32 = 128;

fn frame() -> GridFrame {
    GridFrame::new([33, 33, 33], [1.0; 3])
}

/// Grid point at view depth `depth` (world units along the view axis) that projects to the
/// continuous pixel position `(px, py)`.
fn unproject(cam: &OrbitCamera, frame: &GridFrame, px: f64, py: f64, depth: f32) -> Vec3 {
    let (forward, right, up) = cam.basis();
    let tan_y = (cam.fov_y_deg.to_radians() * 0.5).tan();
    let tan_x = tan_y * W as f32 / H as f32;
    let sx = (2.0 * px / f64::from(W) - 1.0) as f32 * tan_x;
    let sy = (1.0 - 2.0 * py / f64::from(H)) as f32 * tan_y;
    frame.world_to_grid_point(cam.eye() + depth * (forward + sx * right + sy * up))
}

/// A mesh of screen-space polygons at `depth`, facing the camera.
fn screen_mesh(
    cam: &OrbitCamera,
    frame: &GridFrame,
    corners: &[(f64, f64)],
    triangles: Vec<[u32; 3]>,
    depth: f32,
) -> TriangleMesh {
    let (forward, _, _) = cam.basis();
    TriangleMesh {
        positions: corners
            .iter()
            .map(|&(x, y)| unproject(cam, frame, x, y, depth))
            .collect(),
        normals: vec![-forward * frame.grid_to_world; corners.len()],
        triangles,
    }
}

fn render_counts(mesh: &TriangleMesh, frame: &GridFrame) -> (RasterOutput, Vec<u32>) {
    let mut counts = vec![0; (W * H) as usize];
    let out = rasterize_counting(
        mesh,
        frame,
        &OrbitCamera::default(),
        W,
        H,
        Some(&mut counts),
    );
    (out, counts)
}

fn shoelace(p: &[(f64, f64)]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| p[i].0 * p[(i + 1) % n].1 - p[(i + 1) % n].0 * p[i].1)
        .sum::<f64>()
        .abs()
        * 0.5
}

#[test]
fn single_triangle_covers_its_area_from_either_side() {
    let cam = OrbitCamera::default();
    let f = frame();
    let p = [(20.3, 15.7), (100.2, 40.1), (50.6, 110.9)];
    let area = shoelace(&p);
    let mut covered = Vec::new();
    for tri in [[0, 1, 2], [0, 2, 1]] {
        let mesh = screen_mesh(&cam, &f, &p, vec![tri], 1.7);
        let (out, counts) = render_counts(&mesh, &f);
        let n = out.coverage.iter().filter(|&&c| c).count();
        assert!((n as f64 - area).abs() < 4.0, "{n} pixels, area {area}");
        assert!(counts.iter().all(|&c| c <= 1));
        assert!(out.depth.iter().all(|d| (0.0..=1.0).contains(d)));
        covered.push(out.coverage);
    }
    assert_eq!(covered[0], covered[1], "winding must not matter");
}

/// Asserts that no pixel was drawn twice, every pixel centre clearly inside the convex
/// screen polygon `poly` (clockwise on screen) was drawn and none clearly outside was.
fn assert_once_inside(counts: &[u32], poly: &[(f64, f64)]) {
    // Signed distance (pixels) of a point from the outline, positive inside.
    let inside_by = |x: f64, y: f64| {
        (0..poly.len())
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                (dx * (y - a.1) - dy * (x - a.0)) / dx.hypot(dy)
            })
            .fold(f64::INFINITY, f64::min)
    };
    for y in 0..H {
        for x in 0..W {
            let n = counts[(y * W + x) as usize];
            let d = inside_by(x as f64 + 0.5, y as f64 + 0.5);
            assert!(n <= 1, "pixel ({x}, {y}) drawn {n} times");
            if d > 0.01 {
                assert_eq!(n, 1, "gap at ({x}, {y})");
            } else if d < -0.01 {
                assert_eq!(n, 0, "spill at ({x}, {y})");
            }
        }
    }
}

#[test]
fn shared_diagonal_and_fan_cover_each_pixel_once() {
    let cam = OrbitCamera::default();
    let f = frame();
    // The diagonal (10.5, 20.5)-(110.5, 100.5) runs through a pixel centre every 5 pixels.
    let quad = [(10.5, 20.5), (113.2, 12.7), (110.5, 100.5), (17.9, 118.3)];
    let mesh = screen_mesh(&cam, &f, &quad, vec![[0, 1, 2], [0, 2, 3]], 1.6);
    let (out, counts) = render_counts(&mesh, &f);
    assert_once_inside(&counts, &quad);
    for (c, n) in out.coverage.iter().zip(&counts) {
        assert_eq!(*c, *n == 1);
    }

    // Twelve triangles around a vertex on a pixel centre, rim vertices on pixel centres.
    let mut rim = vec![(64.5, 64.5)];
    let spokes = [
        (40, 0),
        (40, 20),
        (30, 30),
        (10, 40),
        (0, 40),
        (-25, 30),
        (-40, 10),
        (-40, -15),
        (-20, -40),
        (0, -40),
        (20, -40),
        (35, -35),
    ];
    rim.extend(
        spokes
            .iter()
            .map(|&(dx, dy)| (64.5 + dx as f64, 64.5 + dy as f64)),
    );
    let tris = (0..12).map(|k| [0, 1 + k, 1 + (k + 1) % 12]).collect();
    let fan = screen_mesh(&cam, &f, &rim, tris, 1.6);
    let (_, counts) = render_counts(&fan, &f);
    assert_eq!(counts[(64 * W + 64) as usize], 1, "shared vertex pixel");
    assert_once_inside(&counts, &rim[1..]);
}

#[test]
fn top_left_rule_on_a_square_through_pixel_centres() {
    let cam = OrbitCamera::default();
    let f = frame();
    let square = [(10.5, 10.5), (30.5, 10.5), (30.5, 40.5), (10.5, 40.5)];
    for tris in [vec![[0, 1, 2], [0, 2, 3]], vec![[1, 2, 3], [3, 0, 1]]] {
        let mesh = screen_mesh(&cam, &f, &square, tris, 1.5);
        let (out, counts) = render_counts(&mesh, &f);
        // Top and left edges are in, right and bottom edges out: exactly 20 x 30 pixels.
        for y in 0..H {
            for x in 0..W {
                let expect = (10..30).contains(&x) && (10..40).contains(&y);
                let i = (y * W + x) as usize;
                assert_eq!(counts[i], u32::from(expect), "pixel ({x}, {y})");
                assert_eq!(out.coverage[i], expect);
            }
        }
    }
}

#[test]
fn screen_space_top_left_rule_exactly() {
    // Straight on the core: a right triangle with its corners on pixel centres.
    let at = |x: f64, y: f64| ScreenVertex {
        x: x * SUBPIXEL,
        y: y * SUBPIXEL,
        z: 0.5,
        inv_w: 1.0,
        position: DVec3::ZERO,
        normal: DVec3::ZERO,
    };
    let mut hits = Vec::new();
    let tri = [at(2.5, 2.5), at(6.5, 2.5), at(2.5, 6.5)];
    raster_triangle(&tri, 16, 16, |i, b| {
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        hits.push((i % 16, i / 16));
    });
    // Top row (y = 2) and left column (x = 2) are in; the hypotenuse x + y = 8 (a right
    // edge) is out.
    let expect: Vec<(usize, usize)> = (2..6)
        .flat_map(|y| (2..6).map(move |x| (x, y)))
        .filter(|&(x, y)| x + y < 8)
        .collect();
    assert_eq!(hits, expect);
}

/// `|p - c|` sampled on a `dims` grid with the given spacing.
fn sphere_field(dims: [u32; 3], spacing: [f32; 3], c: Vec3) -> Volume {
    let mut v = Vec::new();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                v.push(Vec3::new(x as f32, y as f32, z as f32).distance(c));
            }
        }
    }
    Volume::new("sphere", dims, spacing, Samples::F32(v)).unwrap()
}

#[test]
fn marching_cubes_sphere_matches_ray_caster() {
    let cam = OrbitCamera::default();
    let dims = [48; 3];
    let r = 18.0;
    for spacing in [[1.0; 3], [1.0, 1.4, 0.8]] {
        let f = GridFrame::new(dims, spacing);
        let vol = sphere_field(dims, spacing, f.centre() + Vec3::new(0.3, -0.2, 0.1));
        let mesh = marching_cubes(&vol, r);
        let mut counts = vec![0; (W * H) as usize];
        let out = rasterize_counting(&mesh, &f, &cam, W, H, Some(&mut counts));
        let covered = out.coverage.iter().filter(|&&c| c).count();
        // A closed surface is entered and left: every pixel is drawn an even number of
        // times, or the mesh leaks through a shared edge or vertex.
        assert!(counts.iter().all(|&c| c % 2 == 0), "odd overdraw");

        if spacing == [1.0; 3] {
            // A sphere on the view axis projects to a disc of radius tan(asin(R / D)).
            let world_r = f64::from(r * f.grid_to_world.x);
            let offset = (Vec3::new(0.3, -0.2, 0.1) * f.grid_to_world).as_dvec3();
            let d = (cam.eye().as_dvec3() - offset).length();
            let tan_half = (f64::from(cam.fov_y_deg).to_radians() * 0.5).tan();
            let disc_r = (world_r / d).asin().tan() / tan_half * f64::from(H) * 0.5;
            let disc = std::f64::consts::PI * disc_r * disc_r;
            let ratio = covered as f64 / disc;
            assert!(
                (ratio - 1.0).abs() < 0.02,
                "{covered} pixels vs disc {disc}"
            );
        }

        let traced = raycast::render(&vol, r, &cam, W, H);
        let traced_cov = coverage_of(&traced, pack_rgba8(BACKGROUND));
        let iou = silhouette_iou(&out.coverage, &traced_cov);
        assert!(iou >= 0.98, "silhouette IoU {iou}");
        let both: Vec<bool> = out
            .coverage
            .iter()
            .zip(&traced_cov)
            .map(|(a, b)| *a && *b)
            .collect();
        let diff = out.image.compare_where(&traced, &both, 8);
        assert!(
            diff.fraction_within >= 0.95,
            "spacing {spacing:?}: {diff:?}, {covered} pixels"
        );
        // Measured: every co-covered pixel within 1/255; keep a margin below that.
        let close = out.image.compare_where(&traced, &both, 2);
        assert!(
            close.fraction_within >= 0.99,
            "spacing {spacing:?}: {close:?}"
        );
    }
}

/// Where the ray through a pixel centre meets a triangle's plane.
struct RayHit {
    /// Whether the point lies inside the triangle and between the near and far planes.
    inside: bool,
    /// Barycentric weights of the triangle's corners at the point.
    weights: [f64; 3],
    point: DVec3,
    /// View depth of the point.
    depth: f64,
}

/// Intersects the ray through pixel (x, y)'s centre with world triangle `t`, independently
/// of the rasterizer; `None` when the ray passes too close to an edge or a clip plane for
/// rounding to leave the coverage certain.
fn ray_hits(cam: &OrbitCamera, proj: &Projection, t: [DVec3; 3], x: u32, y: u32) -> Option<RayHit> {
    let (forward, right, up) = cam.basis();
    let tan_y = (f64::from(cam.fov_y_deg).to_radians() * 0.5).tan();
    let sx = (2.0 * (f64::from(x) + 0.5) / f64::from(W) - 1.0) * tan_y;
    let sy = (1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(H)) * tan_y;
    let dir = forward.as_dvec3() + sx * right.as_dvec3() + sy * up.as_dvec3();
    let o = cam.eye().as_dvec3();
    // Möller–Trumbore; `dir` has unit length along `forward`, so `s` is the view depth.
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    let tv = o - t[0];
    let u = tv.dot(p) / det;
    let q = tv.cross(e1);
    let v = dir.dot(q) / det;
    let s = e2.dot(q) / det;
    let (near, far) = (f64::from(proj.near), f64::from(proj.far));
    let margins = [u, v, 1.0 - u - v, s - near, far - s];
    let eps = 1e-4;
    if margins.iter().any(|m| m.abs() < eps) {
        return None;
    }
    Some(RayHit {
        inside: margins.iter().all(|&m| m > 0.0),
        weights: [1.0 - u - v, u, v],
        point: o + dir * s,
        depth: s,
    })
}

#[test]
fn triangles_crossing_near_and_far_planes_are_clipped() {
    let cam = OrbitCamera::default();
    // Anisotropic, so grid-space normals must be carried to world space properly.
    let f = GridFrame::new([33, 25, 41], [1.0, 1.3, 0.7]);
    let proj = Projection::new(&cam, &f, W, H);
    let light = GridCamera::new(&cam, &f, W, H).light_world;
    let normals = [Vec3::X, Vec3::new(0.0, 1.0, 0.5), Vec3::new(0.3, -0.2, 1.0)];
    let world_normals = normals.map(|n| (n / f.grid_to_world).normalize().as_dvec3());
    let far_ndc = f64::from(proj.far) / f64::from(proj.far - proj.near);
    let (forward, right, up) = cam.basis();
    let eye = cam.eye();
    let at = |depth: f32, x: f32, y: f32| eye + depth * forward + x * right + y * up;
    let cases = [
        // Two corners in front, one behind the eye (above it): unclipped, the far corner
        // would project upside down and smear the triangle over the top of the image.
        [
            at(1.5, -0.3, -0.3),
            at(1.5, 0.3, -0.25),
            at(-0.5, 0.05, 0.5),
        ],
        // One corner behind the eye, two in front, off to the side.
        [at(-0.4, -0.6, 0.0), at(1.2, 0.2, 0.2), at(1.3, 0.1, -0.3)],
        // One corner past the far plane.
        [at(1.4, -0.3, 0.2), at(1.5, 0.3, 0.25), at(4.0, 0.0, -1.0)],
    ];
    for corners in cases {
        let mesh = TriangleMesh {
            positions: corners.map(|p| f.world_to_grid_point(p)).to_vec(),
            normals: normals.to_vec(),
            triangles: vec![[0, 1, 2]],
        };
        let (out, counts) = render_counts(&mesh, &f);
        assert!(out.depth.iter().all(|d| (0.0..=1.0).contains(d)));
        assert!(counts.iter().all(|&c| c <= 1));
        let world = corners.map(|p| p.as_dvec3());
        let mut covered = 0;
        let mut mismatches = 0;
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let c = out.coverage[i];
                covered += usize::from(c);
                let Some(hit) = ray_hits(&cam, &proj, world, x, y) else {
                    continue;
                };
                mismatches += usize::from(c != hit.inside);
                if !(c && hit.inside) {
                    continue;
                }
                // Depth is NDC z of the hit; attributes are its true 3D barycentric mix
                // (what perspective-correct interpolation reproduces).
                let z = far_ndc * (1.0 - f64::from(proj.near) / hit.depth);
                assert!(
                    (f64::from(out.depth[i]) - z).abs() < 1e-4,
                    "depth at {x},{y}: {} vs {z}",
                    out.depth[i]
                );
                let n = (0..3)
                    .map(|k| world_normals[k] * hit.weights[k])
                    .sum::<DVec3>();
                let expect = shade_fragment(n.as_vec3(), hit.point.as_vec3(), cam.eye(), light);
                let (got, want) = (out.image.pixels[i].to_le_bytes(), expect.to_le_bytes());
                let diff = (0..4).map(|k| got[k].abs_diff(want[k])).max();
                assert!(diff <= Some(1), "colour at {x},{y}: {got:?} vs {want:?}");
            }
        }
        assert!(covered > 200, "only {covered} pixels");
        assert_eq!(mismatches, 0, "pixels disagree with ray casting");
    }

    // Entirely behind the camera: nothing.
    let behind = TriangleMesh {
        positions: [at(-0.5, -0.3, 0.0), at(-0.5, 0.3, 0.0), at(-0.7, 0.0, 0.3)]
            .map(|p| f.world_to_grid_point(p))
            .to_vec(),
        normals: Vec::new(),
        triangles: vec![[0, 1, 2]],
    };
    let (out, counts) = render_counts(&behind, &f);
    assert!(counts.iter().all(|&c| c == 0));
    assert!(out.depth.iter().all(|&d| d == 1.0));
}

#[test]
fn nearer_triangle_occludes_farther_one() {
    let cam = OrbitCamera::default();
    let f = frame();
    let near = [(20.0, 30.0), (100.0, 25.0), (60.0, 100.0)];
    let far = [(10.0, 60.0), (110.0, 50.0), (70.0, 120.0)];
    let mut a = screen_mesh(&cam, &f, &near, vec![[0, 1, 2]], 1.3);
    let mut b = screen_mesh(&cam, &f, &far, vec![[0, 1, 2]], 2.2);
    // Tilt the far triangle's normals so the two shade differently.
    b.normals = vec![Vec3::new(1.0, 0.5, 0.0); 3];
    a.normals[1] = Vec3::new(0.0, 1.0, 1.0);
    let alone = [&a, &b].map(|m| render_counts(m, &f).0);
    for order in [[&a, &b], [&b, &a]] {
        let mut both = order[0].clone();
        let base = both.positions.len() as u32;
        both.positions.extend(&order[1].positions);
        both.normals.extend(&order[1].normals);
        both.triangles.push([base, base + 1, base + 2]);
        let out = render_counts(&both, &f).0;
        let mut overlap = 0;
        for i in 0..(W * H) as usize {
            let expect = if alone[0].coverage[i] {
                overlap += usize::from(alone[1].coverage[i]);
                &alone[0]
            } else {
                &alone[1]
            };
            assert_eq!(out.image.pixels[i], expect.image.pixels[i], "pixel {i}");
            assert_eq!(out.depth[i], expect.depth[i]);
            assert_eq!(out.coverage[i], expect.coverage[i]);
        }
        assert!(overlap > 1000, "triangles barely overlap ({overlap})");
    }
    let differ = (0..(W * H) as usize)
        .filter(|&i| alone[0].coverage[i] && alone[1].coverage[i])
        .filter(|&i| alone[0].image.pixels[i] != alone[1].image.pixels[i])
        .count();
    assert!(differ > 1000, "the triangles shade alike ({differ})");
}

#[test]
fn shade_fragment_rules() {
    let eye = Vec3::new(0.0, 0.0, 2.0);
    let light = Vec3::new(0.3, 0.5, 0.8).normalize();
    let p = Vec3::new(0.1, -0.2, 0.0);
    let n = Vec3::new(0.2, 0.1, 1.0);
    let c = shade_fragment(n * 3.0, p, eye, light);
    let view = (eye - p).normalize();
    let g = gooch(n.normalize(), light, view);
    assert_eq!(c, pack_rgba8([g.x, g.y, g.z, 1.0]));
    assert_eq!(shade_fragment(-n, p, eye, light), c, "double-sided");
    let fallback = gooch(view, light, view);
    assert_eq!(
        shade_fragment(Vec3::ZERO, p, eye, light),
        pack_rgba8([fallback.x, fallback.y, fallback.z, 1.0])
    );
}

#[test]
fn flipping_a_surface_leaves_its_image_unchanged() {
    // Shading is two-sided (gooch turns the normal toward the viewer) and nothing is culled,
    // so the orientation convention of marching cubes cannot change a rendered pixel: the
    // mesh with every triangle reversed and every normal negated draws the same image.
    let cam = OrbitCamera::default();
    let dims = [40; 3];
    let f = GridFrame::new(dims, [1.0, 1.2, 0.9]);
    let vol = sphere_field(
        dims,
        [1.0, 1.2, 0.9],
        f.centre() + Vec3::new(0.4, -0.3, 0.2),
    );
    let mesh = marching_cubes(&vol, 14.0);
    let flipped = TriangleMesh {
        positions: mesh.positions.clone(),
        normals: mesh.normals.iter().map(|&n| -n).collect(),
        triangles: mesh.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
    };
    let (a, b) = (
        rasterize_mesh(&mesh, &f, &cam, W, H),
        rasterize_mesh(&flipped, &f, &cam, W, H),
    );
    assert!(a.coverage.iter().filter(|&&c| c).count() > 1000);
    assert_eq!(a.image.pixels, b.image.pixels);
}
