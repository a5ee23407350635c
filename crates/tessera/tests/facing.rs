//! The compute path's surface draws (`direct`, `meshlets`, `offline`, `pmb`) leave out the
//! side of a closed surface no pixel shows (`tessera_data::facing`) through the front door:
//! the head phantom seen from outside draws one side, with the image of the CPU mesh; seen
//! from inside the grid, or where the surface meets the grid's boundary (Marschner–Lobb), both.

mod common;

use common::surface::{camera, detail, load, render_counting, renderer_for};
use common::{assert_clean, assert_matches_cpu_raster, gpu, skip};
use tessera::path::PathChoice;
use tessera::renderer::Technique;
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
