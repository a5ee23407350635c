//! The compute path of direct isosurface rasterization against the CPU marching cubes: compute
//! extraction, the shared compute rasterizer and resolve, and stereo by re-projection.

mod common;

use common::{
    assert_clean, assert_matches_cpu_raster, assert_same_triangles, checkerboard, gpu,
    list_triangles_in_grid, Need, TestGpu,
};
use std::collections::HashMap;
use tessera::iso::direct::compute::{
    ComputeTarget, DirectCompute, DirectExtract, TriangleAttributes, TriangleLists,
};
use tessera::iso::direct::{Direct, DirectParams};
use tessera::iso::minmax::MinMaxBuilder;
use tessera::iso::PreparedVolume;
use tessera::raster::{decode, RASTER_GROUP_SIZE};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::marching_cubes::marching_cubes;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::rasterize::{
    rasterize_clip_triangles, rasterize_clip_triangles_hiding, screen_polygon, ScreenWinding,
};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};

#[test]
fn compute_extraction_equals_cpu_marching_cubes() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let cases: Vec<(Volume, f32)> = vec![
        (
            generate(ProceduralKind::HeadPhantom, 26, ScalarType::U8).unwrap(),
            0.3,
        ),
        (
            generate(ProceduralKind::MarschnerLobb, 19, ScalarType::U16).unwrap(),
            0.5,
        ),
        (
            generate(ProceduralKind::Turbulence, 23, ScalarType::F32).unwrap(),
            0.45,
        ),
        (checkerboard([18, 11, 9]), 0.5),
    ];
    for (volume, fraction) in &cases {
        let iso = volume.iso_to_texel(IsoValue::Normalized(*fraction));
        let cpu = marching_cubes(volume, iso);
        let builder = MinMaxBuilder::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = PreparedVolume::new(&gpu, &builder, volume).unwrap();
        let extract = DirectExtract::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let capacity = cpu.triangle_count() as u32;
        let lists = TriangleLists::new(&gpu, capacity).unwrap();
        let params = Direct::params(&prepared, iso, &OrbitCamera::default(), 64, 64, capacity);
        gpu.submit("poison", |rec| {
            rec.fill_buffer(&lists.attributes, 0x7fc0_0000);
            rec.fill_buffer(&lists.triangles, 0x7fc0_0000);
        })
        .unwrap();
        gpu.submit("extract", |rec| {
            extract.record(rec, &prepared, &lists, &params)
        })
        .unwrap();
        let stats = extract.read_stats(&gpu).unwrap();
        assert_eq!(
            stats.triangles as usize,
            cpu.triangle_count(),
            "{}",
            volume.name()
        );
        let counts: Vec<u32> = gpu.read_buffer_as(&lists.counts).unwrap();
        assert_eq!(counts[0], capacity);
        // The extraction leaves the raster pass's dispatch arguments for its triangles (none
        // at all for an empty list).
        let args = |n: u32| match n {
            0 => [0, 0, 0],
            n => [n.div_ceil(RASTER_GROUP_SIZE), 1, 1],
        };
        assert_eq!(counts[1..4], args(capacity), "{}", volume.name());
        let tris = list_triangles_in_grid(&gpu, &lists, &params);
        assert_same_triangles(volume.name(), &tris, &cpu, 1e-4);
        let attributes: Vec<TriangleAttributes> = gpu.read_buffer_as(&lists.attributes).unwrap();
        assert_attributes_match(volume, &tris, &attributes, &cpu, &params);
        // One triangle short of what is needed: the count still says how many there were.
        if capacity > 1 {
            let small = TriangleLists::new(&gpu, capacity - 1).unwrap();
            let params = Direct::params(
                &prepared,
                iso,
                &OrbitCamera::default(),
                64,
                64,
                capacity - 1,
            );
            gpu.submit("extract", |rec| {
                extract.record(rec, &prepared, &small, &params)
            })
            .unwrap();
            assert_eq!(extract.read_stats(&gpu).unwrap().triangles, capacity);
            let counts: Vec<u32> = gpu.read_buffer_as(&small.counts).unwrap();
            assert_eq!(counts[0], capacity - 1);
            assert_eq!(counts[1..4], args(capacity - 1));
        }
    }
    assert_clean(&gpu);
}

/// Each listed triangle's attributes: every corner's normal is the CPU's normal at that vertex
/// taken to world space (within 1e-3 rad), and every corner names the block holding it.
fn assert_attributes_match(
    volume: &Volume,
    tris: &[[glam::Vec3; 3]],
    attributes: &[TriangleAttributes],
    cpu: &tessera_data::mesh::TriangleMesh,
    params: &DirectParams,
) {
    let mut vertices: HashMap<glam::IVec3, Vec<usize>> = HashMap::new();
    for (i, p) in cpu.positions.iter().enumerate() {
        vertices.entry(p.floor().as_ivec3()).or_default().push(i);
    }
    let nearest = |p: glam::Vec3| {
        let cell = p.floor().as_ivec3();
        (0..27)
            .map(|n| cell + glam::IVec3::new(n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1))
            .filter_map(|c| vertices.get(&c))
            .flatten()
            .copied()
            .min_by(|&a, &b| {
                let (da, db) = (cpu.positions[a].distance(p), cpu.positions[b].distance(p));
                da.total_cmp(&db)
            })
            .filter(|&i| cpu.positions[i].distance(p) < 1e-3)
            .unwrap_or_else(|| panic!("{}: no CPU vertex at {p}", volume.name()))
    };
    let grid_to_world = glam::Vec4::from(params.grid_to_world).truncate();
    let [bx, by, bz] = tessera_data::minmax::BLOCK_CELLS;
    let dims = volume.dims();
    let blocks = [(dims[0] - 2) / bx + 1, (dims[1] - 2) / by + 1];
    for (t, (corners, a)) in tris.iter().zip(attributes).enumerate() {
        let cell = ((corners[0] + corners[1] + corners[2]) / 3.0)
            .floor()
            .as_uvec3();
        let block = [cell.x / bx, cell.y / by, cell.z / bz];
        let id = block[0] + blocks[0] * (block[1] + blocks[1] * block[2]);
        for (j, (&p, corner)) in corners.iter().zip(&a.corners).enumerate() {
            let expected = (cpu.normals[nearest(p)] / grid_to_world).normalize();
            let got = glam::Vec3::from(corner.normal_world);
            let angle = expected.cross(got).length().atan2(expected.dot(got));
            assert!(
                angle < 1e-3 && (got.length() - 1.0).abs() < 1e-5,
                "{}: triangle {t} corner {j}: normal {got}, CPU {expected}",
                volume.name()
            );
            assert_eq!(corner.maker, id, "{}: triangle {t}'s maker", volume.name());
        }
    }
}

#[test]
fn compute_path_images_match_cpu_rasterized_marching_cubes() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let compiler = shaders::compiler();
    let camera = OrbitCamera {
        azimuth_deg: 50.0,
        elevation_deg: -20.0,
        distance: 1.7,
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
        fov_y_deg: 45.0,
    };
    let volumes = [
        generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap(),
        generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U16).unwrap(),
        generate(ProceduralKind::Turbulence, 29, ScalarType::F32).unwrap(),
    ];
    // 301 pixels wide: a resolve row of two workgroups, the second cut short.
    for (volume, (w, h)) in volumes.iter().zip([(120, 96), (301, 110), (120, 96)]) {
        let compute = DirectCompute::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let builder = MinMaxBuilder::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = PreparedVolume::new(&gpu, &builder, volume).unwrap();
        for fraction in [0.3f32, 0.6] {
            let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
            let mesh = marching_cubes(volume, iso);
            let target = ComputeTarget::new(&gpu, w, h, mesh.triangle_count() as u32 + 16).unwrap();
            let pixels = Target::new(&gpu, w, h).unwrap();
            pixels.poison(&gpu, u32::MAX).unwrap();
            let (image, _ms, stats) = compute
                .render(&gpu, &prepared, &target, &pixels, iso, &camera)
                .unwrap();
            assert_eq!(stats.triangles as usize, mesh.triangle_count());
            assert!(!image.pixels.contains(&u32::MAX), "unwritten pixels");
            let name = format!("direct-compute-{}-{fraction}", volume.name());
            assert_matches_cpu_raster(&name, &image, volume, iso, &camera);
        }
    }
    assert_clean(&gpu);
}

/// The second eye's view re-projects the first eye's triangles; it equals a mono render from
/// that eye, on an open surface (Marschner–Lobb) and on a closed one (the head), where both
/// views leave out the side their eye cannot see.
#[test]
fn compute_stereo_second_view_equals_a_mono_render_from_that_eye() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let compiler = shaders::compiler();
    for (volume, fraction, closed) in [
        (
            generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U8).unwrap(),
            0.5,
            false,
        ),
        (
            generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap(),
            0.3,
            true,
        ),
    ] {
        let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
        let compute = DirectCompute::new(&gpu, &compiler, ScalarType::U8).unwrap();
        let prepared = compute.prepare(&gpu, &volume).unwrap();
        let capacity = marching_cubes(&volume, iso).triangle_count() as u32;
        let (w, h) = (96, 72);
        let [left, right] = OrbitCamera::default().stereo_pair(0.3);
        let first = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
        let second = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
        let pixels = [(); 2].map(|_| Target::new(&gpu, w, h).unwrap());
        let params = [left, right].map(|c| Direct::params(&prepared, iso, &c, w, h, capacity));
        gpu.submit("stereo", |rec| {
            compute.record(rec, &prepared, &first, &pixels[0], &params[0]);
            rec.barrier();
            compute.record_second_view(
                rec,
                &prepared,
                (&first, &params[0]),
                &second,
                &pixels[1],
                &params[1],
            );
        })
        .unwrap();
        let hidden = Direct::hidden_winding(&prepared, &params[1]);
        assert_eq!(hidden.is_some(), closed, "{}", volume.name());
        assert_eq!(second.frame.hidden_winding(), hidden, "{}", volume.name());
        let left_image = pixels[0].read(&gpu).unwrap();
        let right_image = pixels[1].read(&gpu).unwrap();
        let mono = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
        let mono_pixels = Target::new(&gpu, w, h).unwrap();
        let render = |camera| compute.render(&gpu, &prepared, &mono, &mono_pixels, iso, camera);
        let (mono_right, _, _) = render(&right).unwrap();
        let (mono_left, _, _) = render(&left).unwrap();
        assert_eq!(left_image, mono_left, "{}", volume.name());
        let diff = right_image.compare(&mono_right, 2);
        assert!(
            diff.fraction_within >= 0.999,
            "{}: {} pixels differ",
            volume.name(),
            diff.pixels_outside
        );
        assert_ne!(
            left_image, right_image,
            "the eyes must see different images"
        );
    }
    assert_clean(&gpu);
}

/// Seen from outside, the head's closed surfaces draw with the triangles turned away from the
/// eye left out (most of the list's triangles on screen): each pixel shows the triangle the
/// CPU reference shows with every triangle drawn. The Marschner–Lobb surface meets the grid's
/// boundary, so it keeps both sides.
#[test]
fn compute_frames_of_closed_surfaces_leave_out_the_side_turned_away() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let compiler = shaders::compiler();
    let (w, h) = (128, 96);
    for (volume, closed) in [
        (
            generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap(),
            true,
        ),
        (
            generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U16).unwrap(),
            false,
        ),
    ] {
        let compute = DirectCompute::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let builder = MinMaxBuilder::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = PreparedVolume::new(&gpu, &builder, &volume).unwrap();
        let iso = volume.iso_to_texel(IsoValue::Normalized(0.3));
        for camera in ["30,20,1.8", "210,-40,1.6"] {
            let camera = OrbitCamera::parse(camera).unwrap();
            let capacity = marching_cubes(&volume, iso).triangle_count() as u32;
            let target = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
            target.frame.keep_after_resolve(true);
            let pixels = Target::new(&gpu, w, h).unwrap();
            compute
                .render(&gpu, &prepared, &target, &pixels, iso, &camera)
                .unwrap();
            let params = Direct::params(&prepared, iso, &camera, w, h, capacity);
            let hidden = Direct::hidden_winding(&prepared, &params);
            assert_eq!(hidden.is_some(), closed, "{}", volume.name());
            assert_eq!(
                target.frame.hidden_winding(),
                hidden,
                "what the raster passes hid"
            );
            let tris: Vec<[glam::Vec4; 3]> = gpu
                .read_buffer_as::<[[f32; 4]; 3]>(&target.lists.triangles)
                .unwrap()
                .iter()
                .map(|t| t.map(glam::Vec4::from))
                .collect();
            let every = rasterize_clip_triangles(&tris, w, h);
            let frame = target.frame.read(&gpu).unwrap();
            let same = frame
                .iter()
                .zip(&every)
                .filter(|(g, c)| decode(**g).map(|v| v.1) == c.map(|v| v.1))
                .count();
            let covered = every.iter().filter(|c| c.is_some()).count();
            eprintln!(
                "{} {camera:?}: {same} of {} pixels as every triangle drawn",
                volume.name(),
                frame.len()
            );
            assert!(covered > 1000 && same as f64 >= 0.999 * frame.len() as f64);
            if let Some(hidden) = hidden {
                let turned = tris
                    .iter()
                    .filter(|t| {
                        let p = screen_polygon(t, w, h);
                        let area = (p.len() >= 3).then(|| {
                            (p[1].x - p[0].x) * (p[2].y - p[0].y)
                                - (p[1].y - p[0].y) * (p[2].x - p[0].x)
                        });
                        area.and_then(ScreenWinding::of_area) == Some(hidden)
                    })
                    .count();
                let on_screen = tris
                    .iter()
                    .filter(|t| screen_polygon(t, w, h).len() >= 3)
                    .count();
                eprintln!("  {turned} of {on_screen} triangles on screen left out");
                assert!(turned * 10 > on_screen * 3, "{turned} of {on_screen}");
                // Those triangles do draw when not left out: leaving out the other side moves
                // most pixels.
                let other = rasterize_clip_triangles_hiding(&tris, w, h, Some(hidden.opposite()));
                let moved = other
                    .iter()
                    .zip(&every)
                    .filter(|(a, b)| a.map(|v| v.1) != b.map(|v| v.1))
                    .count();
                assert!(moved * 2 > covered, "{moved} of {covered}");
            }
        }
    }
    assert_clean(&gpu);
}
