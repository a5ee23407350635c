//! Drawing Parallel Marching Blocks meshes (`tessera::iso::pmb_draw`, technique `pmb`) on both
//! paths and with every block size: the image is the CPU rasterization of the CPU
//! marching-cubes mesh, and `direct`'s, with exactly marching cubes' triangles; the graphics
//! path's draw commands are the block descriptors; frustum culling changes counts, never the
//! image; a new isovalue extracts again without uploading the volume again; a surface larger
//! than the first buffers grows them within the frame.

mod common;

use common::surface::{
    camera, detail, load, look, meshlet_paths, render_counting, renderer_for, renderer_with,
    supported_paths, SIZE,
};
use common::volumes::{poison_pmb, prepare};
use common::{assert_clean, assert_images_match, assert_matches_cpu_raster, gpu};
use std::collections::BTreeMap;
use tessera::iso::meshlet_draw::{MeshletBounds, MeshletDrawParams};
use tessera::iso::pmb::{PmbBlockSize, PmbExtractor};
use tessera::iso::pmb_draw::{path_support, DrawIndexedIndirectCommand, PmbDraw};
use tessera::path::{Path, PathChoice};
use tessera::renderer::{Culling, RendererOptions, Technique};
use tessera_data::marching_cubes::{marching_cubes_with, AmbiguityRule};
use tessera_data::scene::Dataset;
use tessera_data::IsoValue;
use tessera_gpu::Gpu;

/// The paths this device can draw PMB meshes on, the others reported as skipped.
fn paths(gpu: &Gpu) -> Vec<PathChoice> {
    supported_paths(&path_support(gpu.caps()))
}

fn options(path: PathChoice, culling: bool, block: PmbBlockSize) -> RendererOptions {
    RendererOptions {
        path,
        culling: if culling { Culling::On } else { Culling::Off },
        pmb_block: block,
        ..RendererOptions::default()
    }
}

#[test]
fn pmb_images_are_the_marching_cubes_surface_for_every_block_size_on_both_paths() {
    let gpu = gpu();
    let (spec, iso) = ("procedural:marschner-lobb:40:f32", 0.43);
    let data = load(spec);
    let Dataset::Volume(volume) = &data else {
        unreachable!()
    };
    let texel = volume.iso_to_texel(IsoValue::Normalized(iso));
    let cpu_triangles = marching_cubes_with(volume, texel, AmbiguityRule::default())
        .triangles
        .len() as u64;
    // direct on the same path where it has it (its graphics path needs mesh shaders).
    let direct_paths = meshlet_paths(&gpu);
    for path in paths(&gpu) {
        let direct_path = if direct_paths.contains(&path) {
            path
        } else {
            direct_paths[0]
        };
        let mut direct = renderer_for(&gpu, Technique::Direct, direct_path, false, &data, iso);
        let (direct_image, _) = render_counting(&gpu, direct.as_mut(), 1.9);
        for block in PmbBlockSize::ALL {
            let what = format!("{spec} {path:?} pmb {}", block.name());
            let mut r = renderer_with(
                &gpu,
                Technique::Pmb,
                &options(path, true, block),
                &data,
                iso,
            );
            let expected_path = match path {
                PathChoice::Compute => Path::Compute,
                _ => Path::Graphics,
            };
            assert_eq!(r.path(), expected_path, "{what}");
            let (image, stats) = render_counting(&gpu, r.as_mut(), 1.9);
            let (blocks, drawn) = (detail(&stats, "blocks"), detail(&stats, "blocks_drawn"));
            assert!(
                blocks > 10 && drawn == blocks,
                "{what}: {drawn} of {blocks}"
            );
            assert_eq!(stats.triangles, Some(cpu_triangles), "{what}: triangles");
            assert_eq!(detail(&stats, "surface_triangles"), cpu_triangles, "{what}");
            assert_matches_cpu_raster(&what, &image, volume, texel, &camera(1.9));
            // direct computes its vertices with other rounding; silhouettes may move a
            // pixel, the shading a step.
            assert_images_match(&format!("{what} vs direct"), &image, &direct_image, 2, 0.99);
        }
    }
    assert_clean(&gpu);
}

#[test]
fn graphics_draw_commands_are_the_block_descriptors() {
    let gpu = gpu();
    if !path_support(gpu.caps()).graphics {
        common::skip("", "no indirect draw counts");
        return;
    }
    let Dataset::Volume(volume) = load("procedural:head:48") else {
        unreachable!()
    };
    let compiler = tessera::shaders::compiler();
    let prepared = prepare(&gpu, &volume);
    let block = PmbBlockSize::B844;
    let extractor = PmbExtractor::new(
        &gpu,
        &compiler,
        volume.scalar_type(),
        AmbiguityRule::default(),
        block,
    )
    .unwrap();
    let iso = volume.iso_to_texel(IsoValue::Normalized(0.37));
    let mut pmb = extractor
        .buffers(&gpu, &prepared, Default::default())
        .unwrap();
    poison_pmb(&gpu, &pmb);
    extractor
        .extract_into(&gpu, &prepared, iso, &mut pmb)
        .unwrap();
    let mesh = pmb.read(&gpu).unwrap();
    let mut draw = PmbDraw::new(&gpu, &compiler, Path::Graphics, block).unwrap();
    draw.prepare(&gpu, &pmb).unwrap();
    let target = tessera::iso::direct::RasterTarget::new(&gpu, SIZE.0, SIZE.1).unwrap();
    let view = tessera_data::View::of_unit_box(&camera(0.5), SIZE);
    // Each descriptor as the indexed draw it must become.
    let expected: BTreeMap<u32, DrawIndexedIndirectCommand> = mesh
        .blocks
        .iter()
        .map(|b| {
            let command = DrawIndexedIndirectCommand {
                index_count: 3 * b.triangle_count,
                instance_count: 1,
                first_index: b.first_index,
                vertex_offset: b.first_vertex as i32,
                first_instance: 0,
            };
            (b.first_index, command)
        })
        .collect();
    assert_eq!(expected.len(), mesh.blocks.len());
    let mut drawn = Vec::new();
    for bounds in [MeshletBounds::None, MeshletBounds::Implicit] {
        let params = MeshletDrawParams::new(&view, volume.dims(), volume.spacing(), bounds, 0);
        gpu.submit("PMB draw", |rec| {
            draw.record_graphics(rec, &pmb, &target, &params).unwrap()
        })
        .unwrap();
        let counters = draw.read_counters();
        let commands = draw.read_commands(&gpu).unwrap();
        assert_eq!(commands.len(), counters.blocks_drawn as usize, "{bounds:?}");
        let mut seen = std::collections::BTreeSet::new();
        for c in &commands {
            assert_eq!(expected.get(&c.first_index), Some(c), "{bounds:?}");
            assert!(
                seen.insert(c.first_index),
                "{bounds:?}: a block drawn twice"
            );
        }
        let triangles: u32 = commands.iter().map(|c| c.index_count / 3).sum();
        assert_eq!(counters.triangles_drawn, triangles, "{bounds:?}");
        drawn.push(counters.blocks_drawn);
    }
    // Close up, much of the head is outside the view.
    assert_eq!(drawn[0] as usize, mesh.blocks.len(), "no culling draws all");
    assert!(
        drawn[1] < drawn[0] * 3 / 4 && drawn[1] > 0,
        "culled: {} of {}",
        drawn[1],
        drawn[0]
    );
    assert_clean(&gpu);
}

#[test]
fn frustum_culling_drops_blocks_but_no_pixels() {
    let gpu = gpu();
    let data = load("procedural:head:48");
    for path in paths(&gpu) {
        let block = PmbBlockSize::default();
        let mut culled = renderer_with(
            &gpu,
            Technique::Pmb,
            &options(path, true, block),
            &data,
            0.37,
        );
        let mut all = renderer_with(
            &gpu,
            Technique::Pmb,
            &options(path, false, block),
            &data,
            0.37,
        );
        let (image, stats) = render_counting(&gpu, culled.as_mut(), 0.5);
        let (reference, all_stats) = render_counting(&gpu, all.as_mut(), 0.5);
        let blocks = detail(&stats, "blocks");
        let drawn = detail(&stats, "blocks_drawn");
        assert_eq!(
            detail(&all_stats, "blocks_drawn"),
            blocks,
            "{path:?}: no culling draws every block"
        );
        assert!(
            drawn < blocks * 3 / 4 && drawn > 0,
            "{path:?}: {drawn} of {blocks} drawn"
        );
        assert!(stats.triangles < all_stats.triangles, "{path:?}");
        assert_images_match(
            &format!("pmb {path:?} culled"),
            &image,
            &reference,
            0,
            0.999,
        );
    }
    assert_clean(&gpu);
}

#[test]
fn a_new_isovalue_extracts_again_without_a_new_upload() {
    let gpu = gpu();
    let data = load("procedural:marschner-lobb:40:f32");
    let Dataset::Volume(volume) = &data else {
        unreachable!()
    };
    for path in paths(&gpu) {
        let mut r = renderer_for(&gpu, Technique::Pmb, path, true, &data, 0.43);
        let (first, stats) = render_counting(&gpu, r.as_mut(), 1.9);
        let builds = r.counters().pipeline_builds;
        r.set_appearance(&gpu, &look(0.6)).unwrap();
        let (second, other_stats) = render_counting(&gpu, r.as_mut(), 1.9);
        let counters = r.counters();
        assert_eq!(counters.data_uploads, 1, "{path:?}");
        assert_eq!(
            counters.pipeline_builds, builds,
            "{path:?}: pipelines rebuilt"
        );
        assert_ne!(
            stats.triangles, other_stats.triangles,
            "{path:?}: the same surface"
        );
        assert_ne!(first.pixels, second.pixels, "{path:?}: the same image");
        let texel = volume.iso_to_texel(IsoValue::Normalized(0.6));
        let cpu = marching_cubes_with(volume, texel, AmbiguityRule::default());
        assert_eq!(
            other_stats.triangles,
            Some(cpu.triangles.len() as u64),
            "{path:?}"
        );
        assert_matches_cpu_raster(
            &format!("pmb {path:?} iso 0.6"),
            &second,
            volume,
            texel,
            &camera(1.9),
        );
        // Back to the first isovalue: extracted again, the first image again.
        r.set_appearance(&gpu, &look(0.43)).unwrap();
        let (again, again_stats) = render_counting(&gpu, r.as_mut(), 1.9);
        assert_eq!(again_stats.triangles, stats.triangles, "{path:?}");
        assert_images_match(
            &format!("pmb {path:?} iso 0.43 again"),
            &again,
            &first,
            0,
            1.0,
        );
    }
    assert_clean(&gpu);
}

#[test]
fn a_surface_larger_than_the_first_buffers_grows_them_within_the_frame() {
    let gpu = gpu();
    // Every edge crossed: 4×4×4 blocks each with all 300 edges of their closed box, 300 000
    // vertices in all, more than the first buffers' 262 144.
    let volume = common::checkerboard([41, 41, 41]);
    let cells = 40u64 * 40 * 40;
    let data = Dataset::Volume(volume);
    for path in paths(&gpu) {
        let mut r = renderer_with(
            &gpu,
            Technique::Pmb,
            &options(path, false, PmbBlockSize::B444),
            &data,
            0.5,
        );
        let (image, stats) = render_counting(&gpu, r.as_mut(), 1.9);
        assert_eq!(stats.triangles, Some(4 * cells), "{path:?}");
        assert_eq!(detail(&stats, "blocks"), cells / 64, "{path:?}");
        assert_eq!(
            detail(&stats, "surface_vertices"),
            300 * cells / 64,
            "{path:?}"
        );
        let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
        let covered = image.pixels.iter().filter(|&&p| p != background).count();
        assert!(
            covered > (SIZE.0 * SIZE.1 / 4) as usize,
            "{path:?}: {covered} pixels"
        );
    }
    assert_clean(&gpu);
}

#[test]
fn auto_takes_a_path_the_device_has() {
    let gpu = gpu();
    let support = path_support(gpu.caps());
    let chosen = tessera::renderer::path_for(gpu.caps(), Technique::Pmb, PathChoice::Auto);
    match chosen {
        Ok(Path::Graphics) => assert!(support.graphics),
        Ok(Path::Compute) => assert!(support.compute),
        Err(e) => assert!(!support.graphics && !support.compute, "{e}"),
    }
    // A path the device lacks is refused when the renderer is made, not at the first frame.
    for (path, has) in [
        (PathChoice::Graphics, support.graphics),
        (PathChoice::Compute, support.compute),
    ] {
        let made = tessera::renderer::create(
            &gpu,
            Technique::Pmb,
            &options(path, true, PmbBlockSize::default()),
        );
        assert_eq!(made.is_ok(), has, "{path:?}");
    }
    assert_clean(&gpu);
}
