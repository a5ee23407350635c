//! Stereo through the front door: a pair drawn in one pass (the compute path re-projects one
//! extraction, the mesh path draws both eyes with multiview) equals two mono frames.

mod common;

use common::front_door::{camera, frame_pixels_of, load, with_data, SIZE};
use common::{Need, TestGpu};
use tessera::path::PathChoice;
use tessera::renderer::{self, Culling, Frame, RendererOptions, Technique};
use tessera_data::scene::Dataset;
use tessera_gpu::Gpu;

#[test]
fn compute_stereo_through_the_trait_equals_two_mono_frames() {
    if let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) {
        stereo_equals_two_mono_frames(&gpu, PathChoice::Compute);
    }
}

#[test]
fn multiview_stereo_through_the_trait_equals_two_mono_frames() {
    if let Some(gpu) = TestGpu::with(&[Need::MeshShaders, Need::MultiviewMeshShaders]) {
        stereo_equals_two_mono_frames(&gpu, PathChoice::Graphics);
    }
}

/// A stereo pair drawn in one pass (the compute path re-projects one extraction, the mesh
/// path draws both eyes with multiview) equals two mono frames of the eyes; on a closed
/// surface (the head) seen from outside, with the side neither eye sees left out.
fn stereo_equals_two_mono_frames(gpu: &Gpu, path: PathChoice) {
    for (spec, closed) in [
        ("procedural:marschner-lobb:33:uint8", false),
        ("procedural:head:40:uint8", true),
    ] {
        stereo_pair_equals_two_mono_frames(gpu, path, &load(spec), closed);
    }
}

fn stereo_pair_equals_two_mono_frames(gpu: &Gpu, path: PathChoice, data: &Dataset, closed: bool) {
    let options = RendererOptions {
        path,
        ..RendererOptions::default()
    };
    let mut stereo = with_data(gpu, Technique::Direct, options, data);
    let eyes = stereo.view(&camera(), SIZE).unwrap().stereo_pair(0.3);
    assert!(
        stereo.prepare_stereo(gpu, &eyes).unwrap(),
        "{path:?}: one pass for both eyes"
    );
    let (mut left, mut right) = (
        Frame::new(gpu, SIZE).unwrap(),
        Frame::new(gpu, SIZE).unwrap(),
    );
    for frame in [&left, &right] {
        frame.target.poison(gpu, u32::MAX).unwrap();
    }
    let times =
        renderer::render_stereo(gpu, stereo.as_mut(), &eyes, &mut left, &mut right).unwrap();
    assert_eq!(
        stereo.stats().details.get("one_side_drawn"),
        Some(&u64::from(closed)),
        "{path:?} {}",
        data.name()
    );
    assert_eq!(
        times.scopes.len(),
        1,
        "one pass for both eyes: {:?}",
        times.scopes
    );
    let pair = [
        left.target.read(gpu).unwrap(),
        right.target.read(gpu).unwrap(),
    ];
    assert_ne!(pair[0], pair[1], "the eyes see different images");
    let no_culling = RendererOptions {
        culling: Culling::Off,
        ..options
    };
    let mut mono = with_data(gpu, Technique::Direct, no_culling, data);
    let mut frame = Frame::new(gpu, SIZE).unwrap();
    for (eye, image) in eyes.iter().zip(&pair) {
        assert!(!image.pixels.contains(&u32::MAX), "unwritten pixels");
        frame.render(gpu, mono.as_mut(), eye).unwrap();
        let expected = frame.target.read(gpu).unwrap();
        let diff = image.compare(&expected, 2);
        assert!(
            diff.fraction_within >= 0.999,
            "{} pixels differ",
            diff.pixels_outside
        );
    }
    if path == PathChoice::Compute {
        assert_eq!(
            pair[0].pixels,
            frame_pixels_of(gpu, mono.as_mut(), &eyes[0])
        );
    }
}
