//! The front door (`tessera::renderer`): techniques driven through the one trait give the images
//! of their own (separately tested) APIs, keep culling state from frame to frame, and change
//! their look without uploading data or building pipelines.

mod common;

use common::front_door::{camera, frame_pixels_of, load, with_data, SIZE};
use common::{assert_clean, gpu, skip, Need, TestGpu};
use tessera::path::PathChoice;
use tessera::renderer::{self, Culling, Frame, RendererOptions, Technique};
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{IsoValue, OrbitCamera};

#[test]
fn raymarch_through_the_trait_is_the_technique_s_own_image() {
    let gpu = gpu();
    let data = load("procedural:marschner-lobb:32");
    let Dataset::Volume(volume) = &data else {
        unreachable!()
    };
    let mut r = with_data(&gpu, Technique::Raymarch, RendererOptions::default(), &data);
    let look = Appearance {
        iso: IsoValue::Normalized(0.4),
        ..Appearance::default()
    };
    r.set_appearance(&gpu, &look).unwrap();
    let through = renderer::render_image(&gpu, r.as_mut(), &camera(), SIZE).unwrap();

    let compiler = tessera::shaders::compiler();
    let own = tessera::iso::raymarch::Raymarch::new(&gpu, &compiler, volume.scalar_type()).unwrap();
    let prepared = own.prepare(&gpu, volume).unwrap();
    let target = tessera::target::Target::new(&gpu, SIZE.0, SIZE.1).unwrap();
    let iso = volume.iso_to_texel(IsoValue::Normalized(0.4));
    let (expected, _) = own
        .render(&gpu, &prepared, &target, iso, &camera())
        .unwrap();
    assert_eq!(
        through.image.pixels, expected.pixels,
        "the same frame, pixel for pixel"
    );
    assert!(through.times.total_ms() > 0.0);
    assert_clean(&gpu);
}

#[test]
fn automatic_culling_culls_only_where_the_frame_s_counts_say_it_pays() {
    use tessera::iso::direct::cull_choice::{CullingCosts, PROBE_FRAMES, PROBE_INTERVAL};
    let gpu = gpu();
    let options = |culling| RendererOptions {
        path: PathChoice::Compute,
        culling,
        ..RendererOptions::default()
    };
    if renderer::create(&gpu, Technique::Direct, &options(Culling::Auto)).is_err() {
        skip(
            "automatic culling",
            "the device lacks the compute path's features",
        );
        return;
    }
    let data = load("procedural:head:64");
    // Close up, most of the head's blocks lie outside the view.
    let close = OrbitCamera {
        distance: 0.8,
        ..camera()
    };
    let pixels = u64::from(SIZE.0 * SIZE.1);
    let mut both_ways = [false; 2];
    // Above the range nothing is drawn, so culling's passes are pure cost.
    for fraction in [0.3, 1.01] {
        let look = Appearance {
            iso: IsoValue::Normalized(fraction),
            ..Appearance::default()
        };
        let mut unculled = with_data(&gpu, Technique::Direct, options(Culling::Off), &data);
        unculled.set_appearance(&gpu, &look).unwrap();
        let expected = renderer::render_image(&gpu, unculled.as_mut(), &close, SIZE).unwrap();
        let mut auto = with_data(&gpu, Technique::Direct, options(Culling::Auto), &data);
        auto.set_appearance(&gpu, &look).unwrap();
        let view = auto.view(&close, SIZE).unwrap();
        let mut frame = Frame::new(&gpu, SIZE).unwrap();
        let mut culled = Vec::new();
        let mut pays = None;
        for k in 0..PROBE_FRAMES + PROBE_INTERVAL + 2 {
            frame.render(&gpu, auto.as_mut(), &view).unwrap();
            let stats = auto.stats();
            let was_culled = stats.details["culled"] == 1;
            assert_eq!(was_culled, stats.blocks_drawn.is_some(), "frame {k}");
            if k + 1 == PROBE_FRAMES {
                let (first, new) = stats.blocks_drawn.expect("a probe frame culls");
                let occupied = stats.details["blocks_occupied"] as u32;
                pays =
                    Some(CullingCosts::H200.culling_pays((first + new) as u32, occupied, pixels));
            }
            culled.push(was_culled);
            let image = frame.target.read(&gpu).unwrap();
            assert_eq!(
                image.pixels, expected.image.pixels,
                "{fraction}: frame {k} as the unculled frame"
            );
        }
        let pays = pays.unwrap();
        both_ways[usize::from(pays)] = true;
        let probe = PROBE_FRAMES as usize;
        assert!(
            culled[..probe].iter().all(|&c| c),
            "{fraction}: the first frames probe"
        );
        if pays {
            assert!(culled.iter().all(|&c| c), "{fraction}: culled throughout");
        } else {
            let interval = PROBE_INTERVAL as usize;
            assert!(
                culled[probe..probe + interval].iter().all(|&c| !c),
                "{fraction}: unculled until the next probe: {culled:?}"
            );
            assert!(culled[probe + interval], "{fraction}: then probes again");
        }
        // A new look starts a probe at once.
        auto.set_appearance(&gpu, &look).unwrap();
        frame.render(&gpu, auto.as_mut(), &view).unwrap();
        assert_eq!(
            auto.stats().details["culled"],
            1,
            "{fraction}: a new look probes"
        );
    }
    assert_eq!(
        both_ways,
        [true, true],
        "one scene where culling pays, one where it does not"
    );
    assert_clean(&gpu);
}

#[test]
fn interval_s_automatic_scheme_measures_both_and_draws_the_same_sums() {
    use tessera::renderer::{ComputeScheme, IntervalTuning};
    let gpu = gpu();
    let options = |compute_scheme| RendererOptions {
        path: PathChoice::Compute,
        interval: IntervalTuning {
            compute_scheme,
            ..IntervalTuning::default()
        },
        ..RendererOptions::default()
    };
    if renderer::create(&gpu, Technique::Interval, &options(ComputeScheme::Auto)).is_err() {
        skip(
            "interval's automatic scheme",
            "no compute path for interval shading",
        );
        return;
    }
    let tets = load("tets:box:6");
    let mut binned = with_data(
        &gpu,
        Technique::Interval,
        options(ComputeScheme::Binned),
        &tets,
    );
    renderer::render_image(&gpu, binned.as_mut(), &camera(), SIZE).unwrap();
    let expected = binned.accumulated(&gpu).unwrap().unwrap();
    let mut auto = with_data(
        &gpu,
        Technique::Interval,
        options(ComputeScheme::Auto),
        &tets,
    );
    let view = auto.view(&camera(), SIZE).unwrap();
    let mut frame = Frame::new(&gpu, SIZE).unwrap();
    let mut schemes = Vec::new();
    for k in 0..6 {
        frame.render(&gpu, auto.as_mut(), &view).unwrap();
        schemes.push(auto.stats().details["binned"] == 1);
        let got = auto.accumulated(&gpu).unwrap().unwrap();
        let name = format!("frame {k}");
        let covered = common::interval::assert_same_sums(&name, &got.values, &expected.values);
        assert!(covered > 100, "frame {k}: {covered} pixels covered");
    }
    assert_eq!(schemes[..2], [true, false], "binned first, then per tet");
    // A new mesh is measured afresh.
    auto.set_data(&gpu, &tets).unwrap();
    frame.render(&gpu, auto.as_mut(), &view).unwrap();
    assert_eq!(auto.stats().details["binned"], 1);
    frame.render(&gpu, auto.as_mut(), &view).unwrap();
    assert_eq!(auto.stats().details["binned"], 0);
    assert_clean(&gpu);
}

#[test]
fn a_still_camera_draws_last_frame_s_visible_blocks_first() {
    let gpu = gpu();
    let data = load("procedural:head:48");
    for path in [PathChoice::Compute, PathChoice::Graphics] {
        let options = RendererOptions {
            path,
            culling: Culling::On,
            ..RendererOptions::default()
        };
        let Ok(mut culled) = renderer::create(&gpu, Technique::Direct, &options) else {
            skip(&format!("{path:?} path"), "the device lacks its features");
            continue;
        };
        culled.set_data(&gpu, &data).unwrap();
        let view = culled.view(&camera(), SIZE).unwrap();
        let mut frame = Frame::new(&gpu, SIZE).unwrap();
        frame.render(&gpu, culled.as_mut(), &view).unwrap();
        let first = (frame.target.read(&gpu).unwrap(), culled.stats());
        let times = frame.render(&gpu, culled.as_mut(), &view).unwrap();
        let second = (frame.target.read(&gpu).unwrap(), culled.stats());
        // The compute path's culled frame is four passes; the mesh path's is one.
        assert_eq!(
            times.scopes.len() > 1,
            path == PathChoice::Compute,
            "{times:?}"
        );
        assert!(
            times.total_ms() >= times.passes_ms() && times.passes_ms() > 0.0,
            "{path:?}: a frame takes at least its passes' sum: {times:?}"
        );
        let (drawn_first_1, drawn_new_1) = first.1.blocks_drawn.expect("culling counts blocks");
        let (drawn_first_2, drawn_new_2) = second.1.blocks_drawn.unwrap();
        assert_eq!(
            drawn_first_1, 0,
            "{path:?}: nothing was visible before frame 1"
        );
        assert!(
            drawn_first_2 > 0,
            "{path:?}: frame 2 starts from frame 1's visible set"
        );
        assert!(
            drawn_new_2 < drawn_new_1,
            "{path:?}: frame 2 tests fewer blocks anew"
        );
        if path == PathChoice::Graphics {
            // The compute path's second pass also redraws blocks that pass the depth-pyramid
            // test without owning a pixel; the mesh path's finds nothing new.
            assert_eq!(drawn_new_2, 0, "a still camera finds nothing new");
        }
        assert_eq!(first.0.pixels, second.0.pixels, "{path:?}: the same image");

        let mut unculled = with_data(
            &gpu,
            Technique::Direct,
            RendererOptions {
                culling: Culling::Off,
                ..options
            },
            &data,
        );
        let plain = renderer::render_image(&gpu, unculled.as_mut(), &camera(), SIZE).unwrap();
        assert_eq!(
            plain.image.pixels, second.0.pixels,
            "{path:?}: culling changes no pixel"
        );
        assert!(second.1.triangles.unwrap() <= plain.stats.triangles.unwrap());
    }
    assert_clean(&gpu);
}

#[test]
fn new_looks_upload_nothing_and_build_nothing() {
    let gpu = gpu();
    let volume = load("procedural:sphere:32");
    let mut iso = with_data(
        &gpu,
        Technique::Raymarch,
        RendererOptions::default(),
        &volume,
    );
    let tets = load("tets:sphere:3");
    let mut interval = with_data(&gpu, Technique::Interval, RendererOptions::default(), &tets);
    let scalar_look = |range: (f32, f32)| Appearance {
        integrand: tessera_data::scene::IntegrandChoice::Scalar(
            tessera_data::transfer::ScalarMode::Emission,
        ),
        range: Some(range),
        ..Appearance::default()
    };
    interval
        .set_appearance(&gpu, &scalar_look((0.0, 1.0)))
        .unwrap();
    let before = (iso.counters(), interval.counters());
    let mut images = Vec::new();
    for step in 0..4 {
        let t = step as f32 / 4.0;
        let look = Appearance {
            iso: IsoValue::Normalized(0.2 + 0.5 * t),
            ..Appearance::default()
        };
        iso.set_appearance(&gpu, &look).unwrap();
        interval
            .set_appearance(&gpu, &scalar_look((-0.5 * t, 1.0 - 0.4 * t)))
            .unwrap();
        let a = renderer::render_image(&gpu, iso.as_mut(), &camera(), SIZE).unwrap();
        let b = renderer::render_image(&gpu, interval.as_mut(), &camera(), SIZE).unwrap();
        images.push((a.image, b.image));
    }
    assert_eq!(
        (iso.counters(), interval.counters()),
        before,
        "no upload, no pipeline build"
    );
    assert_eq!(before.0.data_uploads, 1);
    for pair in images.windows(2) {
        assert_ne!(
            pair[0].0.pixels, pair[1].0.pixels,
            "the isovalue moved the surface"
        );
        assert_ne!(
            pair[0].1.pixels, pair[1].1.pixels,
            "the range moved the colours"
        );
    }
    assert_clean(&gpu);
}

#[test]
fn data_of_another_kind_is_refused_by_name() {
    let gpu = gpu();
    let mut r = renderer::create(&gpu, Technique::Raymarch, &RendererOptions::default()).unwrap();
    let error = r
        .set_data(&gpu, &load("tets:box:1"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("raymarch") && error.contains("volumes"),
        "{error}"
    );
    let choice = Technique::for_data(
        Some("interval"),
        tessera_data::scene::DataKind::Volume,
        "x.raw",
    );
    let error = choice.unwrap_err().to_string();
    assert!(
        error.contains("tetrahedral meshes") && error.contains("raymarch or direct"),
        "{error}"
    );
    assert_clean(&gpu);
}

/// `RendererOptions::ambiguity` reaches `direct`'s shaders: each rule draws exactly the
/// triangles the CPU marching cubes makes under that rule, and the two surfaces differ on a
/// volume full of saddles.
#[test]
fn the_ambiguity_rule_reaches_direct() {
    use tessera_data::marching_cubes::count_triangles_with;
    use tessera_data::mc_ambiguity::AmbiguityRule;
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let data = load("procedural:marschner-lobb:33:uint8");
    let tessera_data::scene::Dataset::Volume(volume) = &data else {
        unreachable!("a procedural volume")
    };
    let look = Appearance {
        iso: IsoValue::Normalized(0.4),
        ..Appearance::default()
    };
    let iso = look.iso_texel(volume).unwrap();
    let mut images = Vec::new();
    for rule in [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk] {
        let options = RendererOptions {
            path: PathChoice::Compute,
            culling: Culling::Off,
            ambiguity: rule,
            ..RendererOptions::default()
        };
        let mut r = renderer::create(&gpu, Technique::Direct, &options).unwrap();
        r.set_appearance(&gpu, &look).unwrap();
        r.set_data(&gpu, &data).unwrap();
        let view = r.view(&camera(), SIZE).unwrap();
        images.push(frame_pixels_of(&gpu, r.as_mut(), &view));
        assert_eq!(
            r.stats().triangles,
            Some(count_triangles_with(volume, iso, rule)),
            "{rule:?}"
        );
    }
    assert_ne!(images[0], images[1], "the rules cut the saddles alike");
}

/// Several frames recorded in one submission before one `finish_frame` (as a warm-up records
/// them) draw what one frame draws, on every technique's automatic path.
#[test]
fn frames_recorded_together_draw_what_one_frame_draws() {
    let gpu = gpu();
    let data_for = |technique: Technique| match technique.draws() {
        tessera_data::scene::DataKind::Volume => load("procedural:head:24"),
        tessera_data::scene::DataKind::Tets => load("tets:box:4"),
        tessera_data::scene::DataKind::Param => load("param:sh-glyphs:2x2:order4"),
    };
    for technique in Technique::ALL {
        if let Err(e) = renderer::path_for(gpu.caps(), technique, PathChoice::Auto) {
            skip(technique.name(), &e.to_string());
            continue;
        }
        let mut r = renderer::create(&gpu, technique, &RendererOptions::default()).unwrap();
        r.set_data(&gpu, &data_for(technique)).unwrap();
        let single = renderer::render_image(&gpu, r.as_mut(), &camera(), SIZE).unwrap();
        let view = r.view(&camera(), SIZE).unwrap();
        r.prepare_frame(&gpu, &view).unwrap();
        let target = tessera::target::Target::new(&gpu, SIZE.0, SIZE.1).unwrap();
        let frames = 3;
        let mut timer = tessera_gpu::Timer::new(&gpu, frames * renderer::MAX_TIMER_SCOPES).unwrap();
        timer.reset(&gpu);
        let mut recorded = Ok(());
        gpu.submit("frames together", |rec| {
            recorded = (0..frames).try_for_each(|_| r.record(rec, &view, &target, &mut timer));
        })
        .unwrap();
        recorded.unwrap_or_else(|e| panic!("{}: {e}", technique.name()));
        r.finish_frame(&gpu).unwrap();
        let together = target.read(&gpu).unwrap();
        let differing = together
            .pixels
            .iter()
            .zip(&single.image.pixels)
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differing == 0,
            "{}: {differing} pixels differ from a single frame's",
            technique.name()
        );
        let background = together.pixels[0];
        let covered = together.pixels.iter().filter(|&&p| p != background).count();
        assert!(covered > 50, "{}: {covered} pixels drawn", technique.name());
    }
    assert_clean(&gpu);
}

/// A surface larger than the compute path's triangle list holds on the device (lavapipe's
/// 128 MiB storage buffers: 2,796,202 triangles; the 512³ head has 3,741,616): with the path
/// left to the renderer, `direct` draws it on the graphics path, which keeps no list; asked for
/// the compute path, it says why it cannot. Where the lists hold it, it stays on the compute path.
#[test]
fn direct_takes_the_graphics_path_for_a_surface_the_lists_cannot_hold() {
    use tessera::iso::direct::compute::TriangleLists;
    use tessera::path::Path;
    const SURFACE: u64 = 3_741_616;
    let gpu = gpu();
    let data = load("procedural:head:512:uint8");
    let look = Appearance {
        iso: IsoValue::Normalized(0.3),
        ..Appearance::default()
    };
    let fits = SURFACE <= u64::from(TriangleLists::default_capacity(&gpu));
    let graphics = gpu.caps().mesh_shader && gpu.caps().task_shader;
    for choice in [PathChoice::Auto, PathChoice::Compute] {
        let options = RendererOptions {
            path: choice,
            culling: Culling::Off,
            ..RendererOptions::default()
        };
        let Ok(mut r) = renderer::create(&gpu, Technique::Direct, &options) else {
            skip("", "no path for direct");
            return;
        };
        r.set_data(&gpu, &data).unwrap();
        r.set_appearance(&gpu, &look).unwrap();
        let started_on = r.path();
        let drawn = renderer::render_image(&gpu, r.as_mut(), &camera(), SIZE);
        if started_on == Path::Graphics || fits || (choice == PathChoice::Auto && graphics) {
            let image = drawn.unwrap().image;
            assert_eq!(r.stats().triangles, Some(SURFACE), "{choice:?}");
            assert!(!image.pixels.contains(&u32::MAX), "{choice:?}");
            let moved = started_on == Path::Compute && !fits;
            let expected = if moved { Path::Graphics } else { started_on };
            assert_eq!(r.path(), expected, "{choice:?}");
            // New data starts again on the path chosen at first.
            r.set_data(&gpu, &load("procedural:head:32:uint8")).unwrap();
            renderer::render_image(&gpu, r.as_mut(), &camera(), SIZE).unwrap();
            assert_eq!(r.path(), started_on, "{choice:?}");
        } else {
            common::assert_refused_for_the_lists(drawn, SURFACE);
        }
    }
    assert_clean(&gpu);
}
