//! The compute path's surface draws (`direct`, `meshlets`, `offline`, `pmb`) leave out the
//! side of a closed surface no pixel shows (`tessera_data::facing`) through the front door:
//! the head phantom seen from outside draws one side, with the image of the CPU mesh; seen
//! from inside the grid, or where the surface meets the grid's boundary (Marschner–Lobb), both.
//! `direct`'s mesh path culls the same side in the hardware rasterizer, and
//! `RendererOptions::hidden_side` draws it again on either path.

mod common;

use common::surface::{camera, detail, load, render_counting, renderer_for, renderer_with};
use common::{assert_clean, assert_matches_cpu_raster, gpu, skip};
use tessera::path::PathChoice;
use tessera::renderer::{Culling, HiddenSide, RendererOptions, Technique};
use tessera_data::scene::Dataset;
use tessera_data::IsoValue;

#[test]
fn closed_surfaces_seen_from_outside_draw_one_side_on_the_compute_path() {
    let gpu = gpu();
    if !gpu.caps().buffer_int64_atomics {
        skip("compute path", "no 64-bit buffer atomics");
        return;
    }
    let iso = 0.3;
    for (spec, distance, one_side) in [
        ("procedural:head:40:uint8", 1.9, true),
        ("procedural:head:40:uint8", 0.3, false),
        ("procedural:marschner-lobb:33:uint16", 1.9, false),
    ] {
        let data = load(spec);
        let Dataset::Volume(volume) = &data else {
            unreachable!()
        };
        let texel = volume.iso_to_texel(IsoValue::Normalized(iso));
        for technique in [
            Technique::Direct,
            Technique::Meshlets,
            Technique::Offline,
            Technique::Pmb,
        ] {
            for culling in [false, true] {
                if culling && technique == Technique::Pmb {
                    continue;
                }
                let what = format!(
                    "{spec} at {distance} {} culling {culling}",
                    technique.name()
                );
                let mut r = renderer_for(&gpu, technique, PathChoice::Compute, culling, &data, iso);
                let (image, stats) = render_counting(&gpu, r.as_mut(), distance);
                assert_eq!(
                    detail(&stats, "one_side_drawn"),
                    u64::from(one_side),
                    "{what}"
                );
                assert!(stats.details.contains_key("one_side_drawn"), "{what}");
                if distance > 1.0 {
                    assert_matches_cpu_raster(&what, &image, volume, texel, &camera(distance));
                }
            }
        }
    }
    assert_clean(&gpu);
}

/// Asked to draw the hidden side, every draw that leaves it out draws both sides, with the
/// same image: on the compute path all four techniques, on the mesh path `direct`.
#[test]
fn the_hidden_side_drawn_on_request_leaves_the_image_unchanged() {
    let gpu = gpu();
    let caps = gpu.caps();
    let mut draws = Vec::new();
    if caps.buffer_int64_atomics {
        for technique in [
            Technique::Direct,
            Technique::Meshlets,
            Technique::Offline,
            Technique::Pmb,
        ] {
            draws.push((technique, PathChoice::Compute, Culling::Off));
        }
        draws.push((Technique::Direct, PathChoice::Compute, Culling::On));
    } else {
        skip("compute path", "no 64-bit buffer atomics");
    }
    if caps.mesh_shader && caps.task_shader {
        draws.push((Technique::Direct, PathChoice::Graphics, Culling::Off));
        draws.push((Technique::Direct, PathChoice::Graphics, Culling::On));
    } else {
        skip("direct's mesh path", "no task/mesh shaders");
    }
    let (spec, iso, distance) = ("procedural:head:40:uint8", 0.3, 1.9);
    let data = load(spec);
    for (technique, path, culling) in draws {
        let mut images = Vec::new();
        for hidden_side in [HiddenSide::Skip, HiddenSide::Draw] {
            let what = format!(
                "{} {path:?} culling {culling:?} hidden side {}",
                technique.name(),
                hidden_side.name()
            );
            let options = RendererOptions {
                path,
                culling,
                hidden_side,
                ..RendererOptions::default()
            };
            let mut r = renderer_with(&gpu, technique, &options, &data, iso);
            // A culled frame settles on its second (its first pass draws last frame's blocks).
            render_counting(&gpu, r.as_mut(), distance);
            let (image, stats) = render_counting(&gpu, r.as_mut(), distance);
            assert!(stats.details.contains_key("one_side_drawn"), "{what}");
            assert_eq!(
                detail(&stats, "one_side_drawn"),
                u64::from(hidden_side == HiddenSide::Skip),
                "{what}"
            );
            images.push(image);
        }
        let what = format!("{} {path:?} culling {culling:?}", technique.name());
        let moved = images[0].compare(&images[1], 0).pixels_outside;
        assert_eq!(
            moved, 0,
            "{what}: pixels moved when the hidden side was drawn"
        );
    }
    assert_clean(&gpu);
}
