//! The resolve helpers of the shared compute rasterizer (`raster/raster.glsl`): perspective-
//! correct barycentrics of pixel centres, against an independent f64 computation.

mod common;

use common::raster::{draw, rasterizer};
use common::{assert_clean, gpu};
use glam::{DVec3, Vec4};
use tessera::raster::decode;
use tessera::shaders;
use tessera_gpu::{vk, Binding, Slot, Source};

const BARYCENTRICS: &str = r#"#version 460
#include "raster/raster.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) writeonly buffer Weights { vec4 weights[]; };
layout(push_constant) uniform Params { vec4 clip[3]; uvec2 size; } params;
void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    vec3 b = raster_barycentrics(params.clip[0], params.clip[1], params.clip[2],
                                 raster_pixel_centre(pixel), params.size);
    weights[pixel.y * params.size.x + pixel.x] = vec4(b, 0.0);
}
"#;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BaryParams {
    clip: [[f32; 4]; 3],
    size: [u32; 2],
    _pad: [u32; 2],
}

/// Weights of the corners at the point pixel (px, py) sees, by ray-triangle intersection in
/// homogeneous pixel space (independent of the shader's formula); `None` when the triangle's
/// plane is met behind the eye.
fn ray_weights(clip: &[Vec4; 3], px: f64, py: f64, w: u32, h: u32) -> Option<[f64; 3]> {
    let corner = |c: Vec4| {
        let c = c.as_dvec4();
        DVec3::new(
            (c.x + c.w) * f64::from(w) / 2.0,
            (c.y + c.w) * f64::from(h) / 2.0,
            c.w,
        )
    };
    let [a, b, c] = clip.map(corner);
    let dir = DVec3::new(px, py, 1.0);
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    let s = -a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let t = e2.dot(q) / det;
    (t > 0.0).then_some([1.0 - u - v, u, v])
}

#[test]
fn resolve_barycentrics_are_perspective_correct() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let spirv = compiler
        .compile(
            &Source::new("tests/raster_barycentrics.comp.glsl", BARYCENTRICS),
            &[],
        )
        .unwrap();
    let pipeline = gpu
        .compute_pipeline("barycentrics", &spirv, &[Slot::StorageBuffer])
        .unwrap();
    let (w, h) = (128u32, 96u32);
    let out = gpu
        .create_buffer(
            "weights",
            u64::from(w * h) * 16,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            tessera_gpu::MemoryLocation::GpuOnly,
        )
        .unwrap();
    let cases = [
        // In front, strongly varying w.
        [
            Vec4::new(-0.55, -0.6, 0.3, 0.7),
            Vec4::new(1.9, -0.4, 1.2, 1.6),
            Vec4::new(0.3, 2.5, 2.2, 2.9),
        ],
        // One corner behind the eye: the visible part's weights still refer to all three.
        [
            Vec4::new(-0.5, -0.3, 0.4, 1.1),
            Vec4::new(0.6, -0.2, 0.8, 1.5),
            Vec4::new(0.4, 0.9, -0.7, -0.4),
        ],
    ];
    let rast = rasterizer(&gpu);
    for clip in cases {
        let params = BaryParams {
            clip: clip.map(|c| c.to_array()),
            size: [w, h],
            _pad: [0; 2],
        };
        gpu.submit("barycentrics", |rec| {
            rec.dispatch(
                &pipeline,
                &[Binding::Buffer(&out)],
                bytemuck::bytes_of(&params),
                [w, h, 1],
            )
        })
        .unwrap();
        let got: Vec<[f32; 4]> = gpu.read_buffer_as(&out).unwrap();
        let mut compared = 0;
        let mut max_err = 0f64;
        for y in 0..h {
            for x in 0..w {
                let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                let Some(want) = ray_weights(&clip, px, py, w, h) else {
                    continue;
                };
                // Near the triangle, where weights are what a resolve pass uses.
                if want.iter().any(|&b| !(-0.5..=1.5).contains(&b)) {
                    continue;
                }
                let g = got[(y * w + x) as usize];
                for k in 0..3 {
                    max_err = max_err.max((f64::from(g[k]) - want[k]).abs());
                }
                compared += 1;
            }
        }
        eprintln!("barycentrics: {compared} pixels, max error {max_err:e}");
        assert!(compared > 1000, "only {compared} pixels compared");
        assert!(max_err <= 1e-5, "barycentrics off by {max_err}");

        // Where the rasterizer draws the triangle, its depth is the weights' perspective mix.
        if let Some(rast) = &rast {
            let frame = draw(&gpu, rast, &[clip], w, h);
            let mut drawn = 0;
            for (i, v) in frame.iter().enumerate() {
                let Some((depth, _)) = decode(*v) else {
                    continue;
                };
                drawn += 1;
                let (px, py) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
                let b = ray_weights(&clip, px, py, w, h).expect("a drawn pixel sees the plane");
                let c = clip.map(|c| c.as_dvec4());
                let z: f64 = (0..3).map(|k| b[k] * c[k].z).sum::<f64>();
                let cw: f64 = (0..3).map(|k| b[k] * c[k].w).sum::<f64>();
                assert!(b.iter().all(|&b| b > -0.01), "pixel {i} weights {b:?}");
                assert!((z / cw - f64::from(depth)).abs() < 1e-4, "pixel {i} depth");
            }
            assert!(drawn > 500, "triangle drew {drawn} pixels");
        }
    }
    assert_clean(&gpu);
}
