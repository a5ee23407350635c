//! Ray-tracing pipelines over box acceleration structures: an intersection shader reports each
//! box it meets, an any-hit shader rejects some, the closest-hit and miss shaders say what the
//! ray found; every ray's answer is checked against the same rules on the CPU.

use tessera_gpu::{
    vk, Binding, MemoryLocation, ProceduralHitGroup, RayTracingShaders, ShaderCompiler, Slot,
    Source,
};
use tessera_test::{Need, TestGpu};

/// Rays per row of boxes, and boxes per row.
const ROWS: u32 = 16;
const BOXES_PER_ROW: u32 = 4;
const NO_HIT: u32 = 0xffff_ffff;

const PAYLOAD: &str = r#"
struct Found { uint primitive; float t; };
"#;

const RAY_GEN: &str = r#"
#version 460
#extension GL_EXT_ray_tracing : require
layout(binding = 0) uniform accelerationStructureEXT scene;
layout(binding = 1) buffer Out { uvec2 found[]; };
#include "payload.glsl"
layout(location = 0) rayPayloadEXT Found result;
void main() {
    uint ray = gl_LaunchIDEXT.x;
    // One ray along +x per row of boxes; the last ray passes above every row.
    vec3 origin = vec3(-1.0, float(ray) + 0.5, 0.5);
    result = Found(0xffffffffu, -1.0);
    traceRayEXT(scene, gl_RayFlagsNoneEXT, 0xff, 0, 0, 0, origin, 0.0, vec3(1.0, 0.0, 0.0), 1000.0, 0);
    found[ray] = uvec2(result.primitive, floatBitsToUint(result.t));
}
"#;

const INTERSECTION: &str = r#"
#version 460
#extension GL_EXT_ray_tracing : require
layout(binding = 2) readonly buffer Boxes { float boxes[]; };
void main() {
    uint b = 6u * uint(gl_PrimitiveID);
    vec3 lo = vec3(boxes[b], boxes[b + 1u], boxes[b + 2u]);
    vec3 hi = vec3(boxes[b + 3u], boxes[b + 4u], boxes[b + 5u]);
    vec3 o = gl_WorldRayOriginEXT;
    // Rays run along +x: inside the box's y-z square, they enter at its low x face.
    if (o.y > lo.y && o.y < hi.y && o.z > lo.z && o.z < hi.z) {
        reportIntersectionEXT(lo.x - o.x, 0u);
    }
}
"#;

const ANY_HIT: &str = r#"
#version 460
#extension GL_EXT_ray_tracing : require
void main() {
    if ((uint(gl_PrimitiveID) * 7u) % 3u == 0u) {
        ignoreIntersectionEXT;
    }
}
"#;

const CLOSEST_HIT: &str = r#"
#version 460
#extension GL_EXT_ray_tracing : require
#include "payload.glsl"
layout(location = 0) rayPayloadInEXT Found result;
void main() {
    result = Found(uint(gl_PrimitiveID), gl_HitTEXT);
}
"#;

const MISS: &str = r#"
#version 460
#extension GL_EXT_ray_tracing : require
#include "payload.glsl"
layout(location = 0) rayPayloadInEXT Found result;
void main() {
    result = Found(0xfffffffeu, -2.0);
}
"#;

/// Row r's box k spans x in [2k, 2k + 1], y in [r, r + 1], z in [0, 1].
fn boxes() -> Vec<[f32; 6]> {
    (0..ROWS)
        .flat_map(|r| {
            (0..BOXES_PER_ROW).map(move |k| {
                let (x, y) = (2.0 * k as f32, r as f32);
                [x, y, 0.0, x + 1.0, y + 1.0, 1.0]
            })
        })
        .collect()
}

/// What each ray should find: the first box of its row the any-hit shader keeps, at its
/// distance; the miss shader's mark for the ray above the rows and rows with none kept.
fn expected() -> Vec<(u32, f32)> {
    (0..=ROWS)
        .map(|r| {
            (0..BOXES_PER_ROW)
                .map(|k| r * BOXES_PER_ROW + k)
                .find(|&p| r < ROWS && (p * 7) % 3 != 0)
                .map_or((NO_HIT - 1, -2.0), |p| {
                    (p, 2.0 * (p % BOXES_PER_ROW) as f32 + 1.0)
                })
        })
        .collect()
}

#[test]
fn rays_find_the_nearest_box_the_any_hit_shader_keeps() {
    let Some(gpu) = TestGpu::with(&[Need::RayTracingPipeline]) else {
        return;
    };
    let mut compiler = ShaderCompiler::new().without_disk_cache();
    compiler.add_header("payload.glsl", PAYLOAD);
    let compile = |path: &str, text: &str| compiler.compile(&Source::new(path, text), &[]).unwrap();
    let ray_gen = compile("boxes.rgen.glsl", RAY_GEN);
    let intersection = compile("boxes.rint.glsl", INTERSECTION);
    let any_hit = compile("boxes.rahit.glsl", ANY_HIT);
    let closest = compile("boxes.rchit.glsl", CLOSEST_HIT);
    let miss = compile("boxes.rmiss.glsl", MISS);
    let pipeline = gpu
        .ray_tracing_pipeline(
            "boxes",
            &RayTracingShaders {
                ray_generation: &ray_gen,
                misses: &[&miss],
                hit_groups: &[ProceduralHitGroup {
                    intersection: &intersection,
                    any_hit: Some(&any_hit),
                    closest_hit: Some(&closest),
                }],
            },
            &[
                Slot::AccelerationStructure,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
            ],
        )
        .unwrap();
    let boxes = boxes();
    let scene = gpu.build_box_acceleration("boxes", &boxes).unwrap();
    assert!(scene.bytes() > 0);
    let box_words = gpu
        .upload_buffer(
            "box words",
            bytemuck::cast_slice(&boxes),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )
        .unwrap();
    let rays = ROWS + 1;
    let found = gpu
        .create_buffer(
            "found",
            u64::from(rays) * 8,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )
        .unwrap();
    let mut traced = Ok(());
    gpu.submit("trace boxes", |rec| {
        // Poison: a ray the pipeline never answers keeps this.
        rec.fill_buffer(&found, 0xdead_beef);
        rec.barrier();
        traced = rec.trace_rays(
            &pipeline,
            &[
                Binding::AccelerationStructure(&scene),
                Binding::Buffer(&found),
                Binding::Buffer(&box_words),
            ],
            &[],
            [rays, 1, 1],
        );
    })
    .unwrap();
    traced.unwrap();
    let words: Vec<u32> = gpu.read_buffer_as(&found).unwrap();
    let got: Vec<(u32, f32)> = words
        .chunks_exact(2)
        .map(|w| (w[0], f32::from_bits(w[1])))
        .collect();
    assert_eq!(got, expected());
    // The expectation has both kinds of answer, and rejected nearer boxes.
    let expect = expected();
    assert!(expect.iter().any(|e| e.0 == NO_HIT - 1));
    assert!(expect
        .iter()
        .any(|e| e.0 % BOXES_PER_ROW != 0 && e.0 < NO_HIT - 1));
}
