//! The shared compute rasterizer against the CPU reference (`tessera_data::rasterize`), on
//! lavapipe or a GPU, with validation on.

mod common;

use common::raster::{draw, draw_into, rasterizer, upload_triangles};
use common::raster_scene::{random_scene, Camera};
use common::Rng;
use common::{assert_clean, gpu};
use glam::{DVec2, DVec3, Vec4};
use tessera::raster::{
    create_counts_buffer, decode, ComputeRasterizer, RasterCounts, RasterFrame, RasterTriangle,
    RasterVariant, EMPTY,
};
use tessera_data::rasterize::{
    rasterize_clip_triangles, rasterize_clip_triangles_hiding, screen_polygon, ScreenWinding,
};
use tessera_gpu::{vk, Gpu};

/// Distance in pixels from `p` to the outline of a screen polygon.
fn distance_to_outline(p: DVec2, polygon: &[DVec3]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let a = polygon[i].truncate();
            let b = polygon[(i + 1) % n].truncate();
            let ab = b - a;
            let t = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn random_triangles_match_cpu_reference() {
    let gpu = gpu();
    let Some(mut rast) = rasterizer(&gpu) else {
        return;
    };
    let cam = Camera {
        width: 256,
        height: 192,
        tan_y: 0.45,
        near: 0.5,
        far: 8.0,
    };
    let (w, h) = (cam.width, cam.height);
    let tris = random_scene(&cam, &mut Rng::new(0x1234_5678_9abc_def1));
    let clipped = |f: fn(&Vec4) -> bool| tris.iter().filter(|t| t.iter().any(f)).count();
    let (behind_eye, near, far) = (
        clipped(|c| c.w < 0.0),
        clipped(|c| c.z < 0.0),
        clipped(|c| c.z > c.w),
    );
    let gpu_values = draw(&gpu, &rast, &tris, w, h);
    let cpu = rasterize_clip_triangles(&tris, w, h);

    // A pixel drawn on one side only must lie next to its triangle's outline: f32 clipping may
    // put a clipped corner on the neighbouring 1/256-pixel grid point of the reference's (f64)
    // one, which moves the edges ending there by at most one sub-pixel step.
    const OUTLINE_TOLERANCE: f64 = 1.0 / 256.0;
    let (mut same, mut index_differs, mut one_sided) = (0usize, 0usize, 0usize);
    let (mut max_depth_diff, mut max_tie_gap, mut max_outline) = (0f64, 0f64, 0f64);
    let mut drawn = 0usize;
    for (i, (&g, c)) in gpu_values.iter().zip(&cpu).enumerate() {
        let centre = DVec2::new((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
        match (decode(g), *c) {
            (None, None) => same += 1,
            (Some((gd, gi)), Some((cd, ci))) => {
                drawn += 1;
                let gap = (f64::from(gd) - f64::from(cd)).abs();
                if gi == ci {
                    same += 1;
                    max_depth_diff = max_depth_diff.max(gap);
                } else {
                    index_differs += 1;
                    max_tie_gap = max_tie_gap.max(gap);
                }
            }
            (g, c) => {
                one_sided += 1;
                let (_, t) = g.or(c).unwrap();
                let poly = screen_polygon(&tris[t as usize], w, h);
                let d = distance_to_outline(centre, &poly);
                max_outline = max_outline.max(d);
                assert!(
                    d <= OUTLINE_TOLERANCE,
                    "pixel {centre} drawn only by the {} (triangle {t}), {d} px inside/outside",
                    if g.is_some() { "GPU" } else { "CPU" }
                );
            }
        }
    }
    let total = gpu_values.len();
    eprintln!(
        "{} triangles ({near} crossing the near plane, {behind_eye} of them behind the eye, \
         {far} the far plane), {drawn} pixels drawn: {same}/{total} equal, {index_differs} with another \
         triangle (depth gap <= {max_tie_gap:e}), {one_sided} one-sided (<= {max_outline:e} px \
         from an outline), depth error <= {max_depth_diff:e}",
        tris.len()
    );
    assert!(drawn > total / 2, "the scene covers too little: {drawn}");
    assert!(near >= 20 && behind_eye >= 10 && far >= 10);
    assert!(
        same as f64 >= 0.999 * total as f64,
        "only {same} of {total} pixels agree"
    );
    assert!(max_depth_diff <= 1e-6, "depth differs by {max_depth_diff}");

    // The same through a 2-D grid of workgroups: bit for bit the same frame.
    rast.limit_groups_x(2);
    let frame = RasterFrame::new(&gpu, w, h).unwrap();
    let (grid_values, args) = draw_into(&gpu, &rast, &tris, tris.len() as u32, &frame);
    let groups = (tris.len() as u32).div_ceil(rast.group_size());
    assert_eq!(args.dispatch, [2, groups.div_ceil(2), 1]);
    assert!(grid_values == gpu_values, "2-D grid changed the frame");

    // Reading each pixel before its atomic leaves the same frame, bit for bit; the scene draws
    // over itself (many triangles per pixel), so most fragments find a nearer value held.
    let compiler = tessera::shaders::compiler();
    let reading =
        ComputeRasterizer::with_variant(&gpu, &compiler, RasterVariant::ReadBeforeAtomic).unwrap();
    let read_first = draw(&gpu, &reading, &tris, w, h);
    assert!(
        read_first == gpu_values,
        "reading before the atomic changed the frame"
    );

    // Triangles walked by their whole subgroup leave the same frame, bit for bit, whichever
    // boxes are walked that way: every box above one pixel, or the larger ones, the rest
    // walked alone, those the clip planes cut drawn alone.
    for above in [1, 16, 64] {
        let variant = RasterVariant::SubgroupWalk { above };
        if !variant.available(&gpu) {
            eprintln!(
                "SKIPPED: {}: no subgroup ballot and shuffle",
                variant.name()
            );
            continue;
        }
        let unclipped_above = tris
            .iter()
            .filter(|t| t.iter().all(|c| c.w > 0.0 && c.z >= 0.0 && c.z <= c.w))
            .filter(|t| {
                let poly = screen_polygon(t, w, h);
                let (lo, hi) = poly.iter().fold(
                    (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
                    |(lo, hi), p| (lo.min(p.truncate()), hi.max(p.truncate())),
                );
                let pixels = ((hi.x.min(f64::from(w)) - lo.x.max(0.0)).max(0.0)
                    * (hi.y.min(f64::from(h)) - lo.y.max(0.0)).max(0.0))
                    as u32;
                pixels > above + 8
            })
            .count();
        assert!(
            unclipped_above > 40,
            "{above}: {unclipped_above} large triangles"
        );
        let walking = ComputeRasterizer::with_variant(&gpu, &compiler, variant).unwrap();
        let walked = draw(&gpu, &walking, &tris, w, h);
        let differ = walked
            .iter()
            .zip(&gpu_values)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differ, 0, "{}: {differ} pixels differ", variant.name());
    }
    assert_clean(&gpu);
}

/// A frame that hides one winding draws what the reference draws without those triangles, for
/// either winding, and both sides again once nothing is hidden.
#[test]
fn hidden_windings_are_left_out_as_the_reference_leaves_them() {
    let gpu = gpu();
    let Some(rast) = rasterizer(&gpu) else {
        return;
    };
    let cam = Camera {
        width: 160,
        height: 120,
        tan_y: 0.45,
        near: 0.5,
        far: 8.0,
    };
    let (w, h) = (cam.width, cam.height);
    let tris = random_scene(&cam, &mut Rng::new(0x005e_ed0f_f1de));
    let both = rasterize_clip_triangles(&tris, w, h);
    let frame = RasterFrame::new(&gpu, w, h).unwrap();
    for hidden in [ScreenWinding::Positive, ScreenWinding::Negative] {
        frame.hide_winding(Some(hidden));
        let (values, _) = draw_into(&gpu, &rast, &tris, tris.len() as u32, &frame);
        let cpu = rasterize_clip_triangles_hiding(&tris, w, h, Some(hidden));
        let same = values
            .iter()
            .zip(&cpu)
            .filter(|(g, c)| decode(**g).map(|v| v.1) == c.map(|v| v.1))
            .count();
        let moved = cpu
            .iter()
            .zip(&both)
            .filter(|(c, b)| c.map(|v| v.1) != b.map(|v| v.1))
            .count();
        eprintln!(
            "{hidden:?} hidden: {same} of {} pixels as the reference, {moved} moved",
            cpu.len()
        );
        assert!(
            same as f64 >= 0.999 * cpu.len() as f64,
            "{hidden:?}: {same} agree"
        );
        assert!(
            moved > cpu.len() / 10,
            "{hidden:?}: hiding moved {moved} pixels"
        );
    }
    frame.hide_winding(None);
    let (values, _) = draw_into(&gpu, &rast, &tris, tris.len() as u32, &frame);
    let same = values
        .iter()
        .zip(&both)
        .filter(|(g, c)| decode(**g).map(|v| v.1) == c.map(|v| v.1))
        .count();
    assert!(
        same as f64 >= 0.999 * both.len() as f64,
        "with nothing hidden: {same} agree"
    );
    assert_clean(&gpu);
}

/// The drawn-tile marks a resolve relies on to skip the rest: after each frame, every drawn
/// pixel lies in a tile marked with the frame's number, and every tile so marked meets the
/// pixel box of a triangle of that frame (as the CPU reference clips and snaps it). The frame
/// is 250×190 (tiles cut at the right and bottom edges); the second frame draws the scene's
/// other half into the same frame, so marks of the first must not pass for the second's.
#[test]
fn raster_marks_the_tiles_it_draws_into() {
    let gpu = gpu();
    let Some(rast) = rasterizer(&gpu) else {
        return;
    };
    let cam = Camera {
        width: 250,
        height: 190,
        tan_y: 0.45,
        near: 0.5,
        far: 8.0,
    };
    let (w, h) = (cam.width, cam.height);
    let scene = random_scene(&cam, &mut Rng::new(0x0bad_cafe_f00d_1237));
    let (first, second) = scene.split_at(scene.len() / 2);
    let frame = RasterFrame::new(&gpu, w, h).unwrap();
    for (k, tris) in [first, second].into_iter().enumerate() {
        let (triangles, counts) = upload_triangles(&gpu, tris, tris.len() as u32);
        gpu.submit("marked tiles", |rec| {
            frame.record_begin(rec);
            rec.barrier();
            rast.record_prepare_dispatch(rec, &counts);
            rast.record_raster(rec, &triangles, &counts, &frame);
        })
        .unwrap();
        let number = frame.frame_number();
        let values = frame.read(&gpu).unwrap();
        let marks: Vec<u32> = gpu.read_buffer_as(&frame.tile_frames).unwrap();
        let marked = |x: u32, y: u32| marks[frame.tile_index(x, y)] == number;
        let mut drawn = 0;
        for (i, &v) in values.iter().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            if decode(v).is_some() {
                drawn += 1;
                assert!(
                    marked(x, y),
                    "frame {k}: pixel ({x}, {y}) drawn in an unmarked tile"
                );
            }
        }
        // The tiles the triangles' pixel boxes (with a pixel's slack) reach.
        let mut reached = vec![false; marks.len()];
        for t in tris {
            let polygon = screen_polygon(t, w, h);
            if polygon.is_empty() {
                continue;
            }
            let (lo, hi) = polygon.iter().fold(
                (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
                |(lo, hi), p| (lo.min(p.truncate()), hi.max(p.truncate())),
            );
            let first_pixel = (lo - 1.0).max(DVec2::ZERO).floor();
            let last_pixel = (hi + 1.0).min(DVec2::new(f64::from(w - 1), f64::from(h - 1)));
            for y in first_pixel.y as u32..=last_pixel.y as u32 {
                for x in first_pixel.x as u32..=last_pixel.x as u32 {
                    reached[frame.tile_index(x, y)] = true;
                }
            }
        }
        let stray = (0..marks.len())
            .filter(|&t| marks[t] == number && !reached[t])
            .count();
        let marked_count = marks.iter().filter(|&&m| m == number).count();
        assert_eq!(
            stray, 0,
            "frame {k}: {stray} tiles marked beyond every triangle"
        );
        assert!(drawn > 1000, "frame {k}: {drawn} pixels drawn");
        assert!(
            marked_count < marks.len(),
            "frame {k}: every one of {} tiles marked",
            marks.len()
        );
    }
    assert_clean(&gpu);
}

/// Renders each triangle alone and adds up the coverage; checks every pixel is drawn at most
/// once, per triangle exactly as the CPU reference draws it, and that drawing the whole fan at
/// once keeps, per pixel, the one triangle covering it.
fn check_fan(gpu: &Gpu, rast: &ComputeRasterizer, fan: &[[Vec4; 3]], size: (u32, u32)) -> Vec<u32> {
    let (w, h) = size;
    let mut owner = vec![None; (w * h) as usize];
    let mut counts = vec![0u32; (w * h) as usize];
    for (t, tri) in fan.iter().enumerate() {
        let alone = draw(gpu, rast, std::slice::from_ref(tri), w, h);
        let cpu = rasterize_clip_triangles(std::slice::from_ref(tri), w, h);
        for (i, v) in alone.iter().enumerate() {
            let covered = *v != EMPTY;
            assert_eq!(covered, cpu[i].is_some(), "triangle {t}, pixel {i}");
            if covered {
                counts[i] += 1;
                owner[i] = Some(t as u32);
            }
        }
    }
    assert!(counts.iter().all(|&c| c <= 1), "a pixel drawn twice");
    let together = draw(gpu, rast, fan, w, h);
    for (i, v) in together.iter().enumerate() {
        assert_eq!(decode(*v).map(|(_, t)| t), owner[i], "pixel {i}");
    }
    counts
}

/// Asserts every pixel centre clearly inside the fan around `centre` with corners `rim` (all in
/// pixels) was drawn once and none clearly outside was drawn; "clearly" is 0.01 pixel.
fn assert_fills(counts: &[u32], centre: DVec2, rim: &[DVec2], w: u32) {
    // Signed distance from the nearest edge of triangle t, positive inside.
    let inside_by = |t: [DVec2; 3], p: DVec2| {
        let sign = (t[1] - t[0]).perp_dot(t[2] - t[0]).signum();
        (0..3)
            .map(|i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                sign * (b - a).perp_dot(p - a) / (b - a).length()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let n = rim.len();
    for (i, &c) in counts.iter().enumerate() {
        let p = DVec2::new((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
        let d = (0..n)
            .map(|k| inside_by([centre, rim[k], rim[(k + 1) % n]], p))
            .fold(f64::NEG_INFINITY, f64::max);
        if d > 0.01 {
            assert_eq!(c, 1, "gap at {p}");
        } else if d < -0.01 {
            assert_eq!(c, 0, "spill at {p}");
        }
    }
}

#[test]
fn fans_cover_each_pixel_exactly_once() {
    let gpu = gpu();
    let Some(rast) = rasterizer(&gpu) else {
        return;
    };
    let (w, h) = (128u32, 128u32);
    // A corner at pixel position (px, py), NDC depth z, clip w.
    let at = |px: f64, py: f64, z: f64, cw: f64| {
        let ndc = [2.0 * px / f64::from(w) - 1.0, 2.0 * py / f64::from(h) - 1.0];
        Vec4::new(
            (ndc[0] * cw) as f32,
            (ndc[1] * cw) as f32,
            (z * cw) as f32,
            cw as f32,
        )
    };
    let fan_of = |centre: Vec4, rim: &[Vec4]| -> Vec<[Vec4; 3]> {
        (0..rim.len())
            .map(|k| [centre, rim[k], rim[(k + 1) % rim.len()]])
            .collect()
    };

    // Twelve triangles around a corner on a pixel centre, rim corners on pixel centres too
    // (power-of-two w keeps them exactly there), so the fill rule decides at every corner.
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
    let ws = [1.0, 2.0, 0.5, 4.0];
    let rim_px: Vec<DVec2> = spokes
        .iter()
        .map(|&(dx, dy)| DVec2::new(64.5 + f64::from(dx), 64.5 + f64::from(dy)))
        .collect();
    let rim: Vec<Vec4> = rim_px
        .iter()
        .enumerate()
        .map(|(k, p)| at(p.x, p.y, 0.3 + 0.04 * k as f64, ws[k % 4]))
        .collect();
    let counts = check_fan(&gpu, &rast, &fan_of(at(64.5, 64.5, 0.5, 2.0), &rim), (w, h));
    assert_eq!(counts[(64 * w + 64) as usize], 1, "shared corner pixel");
    assert_fills(&counts, DVec2::new(64.5, 64.5), &rim_px, w);

    // Irregular corners and w, partly off screen.
    let mut rng = Rng::new(77);
    let rim_px: Vec<DVec2> = (0..9)
        .map(|k| {
            let angle = (k as f64 + rng.range(-0.3, 0.3)) * std::f64::consts::TAU / 9.0;
            let r = rng.range(30.0, 80.0);
            DVec2::new(61.3 + r * angle.cos(), 70.9 + r * angle.sin())
        })
        .collect();
    let rim: Vec<Vec4> = rim_px
        .iter()
        .map(|p| at(p.x, p.y, rng.range(0.1, 0.9), rng.range(0.6, 3.0)))
        .collect();
    let fan = fan_of(at(61.3, 70.9, 0.4, 1.37), &rim);
    let counts = check_fan(&gpu, &rast, &fan, (w, h));
    assert_fills(&counts, DVec2::new(61.3, 70.9), &rim_px, w);
    assert!(counts.iter().filter(|&&c| c == 1).count() > 5000);

    // A fan crossing the near plane: shared edges cut by clipping must stay watertight.
    let cam = Camera {
        width: w,
        height: h,
        tan_y: 0.5,
        near: 0.5,
        far: 8.0,
    };
    let centre = cam.to_clip(cam.at_pixel(60.0, 66.0, 1.0));
    let rim: Vec<Vec4> = (0..10)
        .map(|k| {
            let angle = k as f64 * std::f64::consts::TAU / 10.0;
            let base = cam.at_pixel(60.0, 66.0, 1.0);
            let offset = DVec3::new(0.6 * angle.cos(), 0.6 * angle.sin(), 0.9 * angle.sin());
            cam.to_clip(base + offset)
        })
        .collect();
    let counts = check_fan(&gpu, &rast, &fan_of(centre, &rim), (w, h));
    assert!(counts.iter().filter(|&&c| c == 1).count() > 3000);
    assert_clean(&gpu);
}

#[test]
fn empty_lists_and_counts_beyond_capacity() {
    let gpu = gpu();
    let Some(mut rast) = rasterizer(&gpu) else {
        return;
    };
    let (w, h) = (64u32, 48u32);
    let full = |z: f32| {
        [
            Vec4::new(-3.0, -3.0, z, 1.0),
            Vec4::new(3.0, -3.0, z, 1.0),
            Vec4::new(0.0, 3.0, z, 1.0),
        ]
    };
    let tris = [full(0.5), full(0.25), full(0.75), full(0.1)];
    let frame = RasterFrame::new(&gpu, w, h).unwrap();
    // Something drawn first, so that clearing is seen to work.
    let (values, args) = draw_into(&gpu, &rast, &tris, 3, &frame);
    assert_eq!(args.dispatch, [1, 1, 1]);
    assert!(values.iter().all(|&v| decode(v) == Some((0.25, 1))));
    // No triangles: nothing drawn, no workgroups launched, whatever the buffer holds.
    let (values, args) = draw_into(&gpu, &rast, &tris, 0, &frame);
    assert_eq!(args.dispatch, [0, 1, 1]);
    assert!(values.iter().all(|&v| v == EMPTY), "an empty list drew");
    let (values, _) = draw_into(&gpu, &rast, &[], 0, &frame);
    assert!(values.iter().all(|&v| v == EMPTY));
    // A count past the buffer's end (an overflowing generator) draws what the buffer holds.
    let (values, args) = draw_into(&gpu, &rast, &tris, 100_000, &frame);
    assert_eq!(
        args.dispatch,
        [100_000u32.div_ceil(rast.group_size()), 1, 1]
    );
    assert!(values.iter().all(|&v| decode(v) == Some((0.1, 3))));
    // Dispatch arguments at the edges of a group and of a row.
    rast.limit_groups_x(3);
    let g = rast.group_size();
    for (count, expect) in [
        (1, [1, 1, 1]),
        (g, [1, 1, 1]),
        (g + 1, [2, 1, 1]),
        (3 * g, [3, 1, 1]),
        (3 * g + 1, [3, 2, 1]),
        (10 * g - 1, [3, 4, 1]),
    ] {
        let (_, args) = draw_into(&gpu, &rast, &tris, count, &frame);
        assert_eq!(args.dispatch, expect, "{count} triangles");
    }
    assert_clean(&gpu);
}

#[test]
fn index_base_lets_two_buffers_share_a_frame() {
    let gpu = gpu();
    let Some(rast) = rasterizer(&gpu) else {
        return;
    };
    let full = |z: f32| RasterTriangle {
        clip: [
            [-3.0, -3.0, z, 1.0],
            [3.0, -3.0, z, 1.0],
            [0.0, 3.0, z, 1.0],
        ],
    };
    let upload = |tris: &[RasterTriangle]| {
        let triangles = gpu
            .upload_buffer(
                "test triangles",
                bytemuck::cast_slice(tris),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )
            .unwrap();
        let counts = create_counts_buffer(&gpu, "test counts").unwrap();
        let n = RasterCounts {
            triangle_count: tris.len() as u32,
            dispatch: [0; 3],
        };
        gpu.write_buffer(&counts, bytemuck::bytes_of(&n)).unwrap();
        (triangles, counts)
    };
    let first = upload(&[full(0.5), full(0.6)]);
    let second = upload(&[full(0.75), full(0.25)]);
    let frame = RasterFrame::new(&gpu, 32, 24).unwrap();
    for (near_first, expect) in [(false, (0.25, 1001)), (true, (0.25, 1))] {
        let (a, b) = if near_first {
            (&second, &first)
        } else {
            (&first, &second)
        };
        gpu.submit("two buffers", |rec| {
            rast.record_clear(rec, &frame);
            rast.record_prepare_dispatch(rec, &a.1);
            rast.record_raster(rec, &a.0, &a.1, &frame);
            rast.record_prepare_dispatch(rec, &b.1);
            rast.record_raster_with_base(rec, &b.0, &b.1, &frame, 1000);
        })
        .unwrap();
        let values = frame.read(&gpu).unwrap();
        assert!(
            values.iter().all(|&v| decode(v) == Some(expect)),
            "{:?}",
            decode(values[0])
        );
    }
    assert_clean(&gpu);
}
