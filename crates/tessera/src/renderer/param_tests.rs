//! The parametric renderer's patch lists: raised for a scene's initial patches, grown and the
//! frame recorded again when they overflow, with the image of lists large enough from the start.

use super::*;
use crate::renderer::{render_image, Renderer};
use tessera_data::scene::{Dataset, LoadOptions};
use tessera_data::OrbitCamera;
use tessera_test::TestGpu;

#[test]
fn full_patch_lists_grow_and_the_frame_is_drawn_again() {
    let gpu = TestGpu::new();
    let data = Dataset::load("param:sh-glyphs:4x4:order8", &LoadOptions::default()).unwrap();
    let camera = OrbitCamera {
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        distance: 1.2,
        ..OrbitCamera::default()
    };
    // 16 glyphs of order 8 pre-split 8 × 8 start as 1024 patches: lists of 300 overflow at once.
    let options = RendererOptions {
        pre_split: Some(8),
        ..RendererOptions::default()
    };
    let draw = |renderer: &mut ParamRenderer| {
        render_image(&gpu, renderer, &camera, (96, 96))
            .unwrap()
            .image
    };
    let mut roomy = ParamRenderer::new(&gpu, Technique::ParamPoints, &options).unwrap();
    roomy.set_data(&gpu, &data).unwrap();
    let expected = draw(&mut roomy);

    let mut tight = ParamRenderer::new(&gpu, Technique::ParamPoints, &options).unwrap();
    tight.set_data(&gpu, &data).unwrap();
    tight.patch_capacity = 300;
    tight.build(&gpu, None).unwrap();
    let builds = tight.counters().pipeline_builds;
    let image = draw(&mut tight);
    assert!(tight.patch_capacity > 1024, "{}", tight.patch_capacity);
    assert!(tight.counters().pipeline_builds > builds);
    assert!(image == expected, "the grown lists drew another image");
    gpu.assert_clean();
}
