//! Small triangles: a grid of right triangles a few pixels big (geometry in
//! `common/throughput.glsl`, generated in the shaders, no vertex buffers) rasterized by a
//! mesh-shader pipeline ("mesh") or splatted by a compute shader that writes the pixels each
//! triangle covers ("compute"). Triangles this small leave the rasterizer's per-triangle setup
//! as the cost, which is what the compute splat, the core of software rasterizers, avoids.
//!
//! The grid is built so that coverage is unambiguous: leg lengths are half-integers, so every
//! pixel centre lies at least 0.35 px from every edge and the two paths, and the CPU reference
//! here, must cover exactly the same pixels. Both timings include clearing the output (the
//! render pass's clear, the splat's fill), which any real frame of either kind pays.

use super::TARGET_FORMAT;
use super::{create_target, record, shader_defines, spread_groups, ThroughputOptions};
use crate::bench::{time_frames, BenchRecord};
use crate::builtin_shader;
use crate::error::{Error, Result};
use bytemuck::{Pod, Zeroable};
use tessera_gpu::{vk, Binding, Buffer, Gpu, Image, MemoryLocation, Pipeline, Recorder};
use tessera_gpu::{ShaderCompiler, Slot};

/// The `technique` field of the records.
pub const TECHNIQUE: &str = "triangles";

/// Side of a grid cell in pixels; each cell holds two triangles.
pub const CELL_PX: u32 = 3;
/// Leg length of the triangles in pixels. A half-integer keeps the hypotenuse half a unit of
/// x + y away from every pixel centre; shorter than the cell, so triangles stay inside it and
/// cover 3 pixels each.
pub const LEG_PX: f32 = 2.5;
/// Triangles per mesh workgroup: 64 triangles of 3 unshared vertices is 192 vertices, inside the
/// 256 every `VK_EXT_mesh_shader` device allows, with one cell per invocation giving NVIDIA's
/// preferred 32 invocations.
pub const MESH_TRIANGLES: u32 = 64;

// The constants' stated reasons, checked when compiling: triangles inside their cell, a
// workgroup's vertices within the guaranteed mesh-output limit, one cell per invocation.
const _: () = {
    assert!(LEG_PX < CELL_PX as f32);
    assert!(3 * MESH_TRIANGLES <= 256 && MESH_TRIANGLES.is_multiple_of(2));
};

/// What the mesh path's fragment shader and the compute splat write into covered pixels (all
/// bits set, i.e. RGBA8 white); uncovered pixels stay 0.
pub const COVERED: u32 = u32::MAX;

/// Push constants of `grid.mesh.glsl` and `splat.comp.glsl` (their `TriangleParams` block).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TriangleParams {
    pub size: [u32; 2],
    pub triangles: u32,
}

/// Pixels covered by one triangle, as offsets from its cell's top-left pixel. A centre at
/// (i + ½, j + ½) from the right-angle corner is inside the triangle iff i + j + 1 < LEG_PX;
/// odd triangles are the same shape turned by 180° about the cell's centre.
pub fn covered_offsets(odd: bool) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    for j in 0..CELL_PX {
        for i in 0..CELL_PX {
            if ((i + j + 1) as f32) < LEG_PX {
                out.push(if odd {
                    [CELL_PX - 1 - i, CELL_PX - 1 - j]
                } else {
                    [i, j]
                });
            }
        }
    }
    out
}

/// The CPU reference: which pixels of a `width`×`height` target `triangles` grid triangles
/// cover, row-major.
pub fn reference_coverage(width: u32, height: u32, triangles: u32) -> Vec<bool> {
    let cols = width / CELL_PX;
    let cells = cols * (height / CELL_PX);
    let mut covered = vec![false; (width * height) as usize];
    // Past two per cell the triangles wrap round onto pixels already covered.
    for t in 0..triangles.min(cells * 2) {
        let cell = t / 2;
        let origin = [(cell % cols) * CELL_PX, (cell / cols) * CELL_PX];
        for [i, j] in covered_offsets(t % 2 == 1) {
            covered[((origin[1] + j) * width + origin[0] + i) as usize] = true;
        }
    }
    covered
}

/// The splat pipeline, and the mesh pipeline where the device has mesh shaders.
pub struct Triangles {
    mesh: Option<Pipeline>,
    splat: Pipeline,
}

impl Triangles {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<Triangles> {
        let defines = shader_defines();
        let comp = compiler.compile(&builtin_shader!("splat.comp.glsl"), &defines)?;
        let splat = gpu.compute_pipeline("throughput splat", &comp, &[Slot::StorageBuffer])?;
        if !gpu.caps().mesh_shader {
            return Ok(Triangles { mesh: None, splat });
        }
        let mesh = compiler.compile(&builtin_shader!("grid.mesh.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("grid.frag.glsl"), &defines)?;
        let mesh = gpu.graphics_pipeline(
            "throughput grid mesh",
            &[&mesh, &frag],
            &[],
            TARGET_FORMAT,
            false,
        )?;
        Ok(Triangles {
            mesh: Some(mesh),
            splat,
        })
    }

    pub fn has_mesh(&self) -> bool {
        self.mesh.is_some()
    }

    /// Rasterizes `triangles` grid triangles into `target` (in `GENERAL` layout), cleared to 0
    /// first. Fails where the device has no mesh shaders.
    pub fn record_mesh(&self, rec: &Recorder, target: &Image, triangles: u32) -> Result<()> {
        let mesh = self
            .mesh
            .as_ref()
            .ok_or_else(|| Error::Invalid("the mesh path needs VK_EXT_mesh_shader".into()))?;
        let params = TriangleParams {
            size: [target.extent.width, target.extent.height],
            triangles,
        };
        let groups = spread_groups(triangles.div_ceil(MESH_TRIANGLES));
        rec.begin_rendering(target, [0.0; 4]);
        let drawn = rec.draw_mesh_tasks(mesh, &[], bytemuck::bytes_of(&params), groups);
        rec.end_rendering();
        Ok(drawn?)
    }

    /// Splats `triangles` grid triangles into `pixels` (one `u32` per pixel of a
    /// `size[0]`×`size[1]` target, row-major), cleared to 0 first.
    pub fn record_splat(&self, rec: &Recorder, pixels: &Buffer, size: [u32; 2], triangles: u32) {
        let params = TriangleParams { size, triangles };
        rec.fill_buffer(pixels, 0);
        rec.barrier();
        let groups = spread_groups(triangles.div_ceil(self.splat.local_size[0]));
        rec.dispatch_groups(
            &self.splat,
            &[Binding::Buffer(pixels)],
            bytemuck::bytes_of(&params),
            groups,
        );
    }
}

/// A buffer of one `u32` per pixel for the splat, readable with [`read_splat`].
pub fn create_splat_buffer(gpu: &Gpu, width: u32, height: u32) -> Result<Buffer> {
    Ok(gpu.create_buffer(
        "throughput splat pixels",
        u64::from(width) * u64::from(height) * 4,
        vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
    )?)
}

pub fn read_splat(gpu: &Gpu, pixels: &Buffer) -> Result<Vec<u32>> {
    Ok(gpu.read_buffer_as(pixels)?)
}

/// Times the mesh path (where available) and the compute splat, and returns their records.
pub fn measure(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    opts: &ThroughputOptions,
) -> Result<Vec<BenchRecord>> {
    let (w, h, n) = (opts.width, opts.height, opts.triangles);
    let triangles = Triangles::new(gpu, compiler)?;
    let pixels = create_splat_buffer(gpu, w, h)?;
    let target = if triangles.has_mesh() {
        Some(create_target(gpu, "throughput grid target", w, h)?)
    } else {
        None
    };
    let mut records = Vec::new();
    if let Some(target) = &target {
        // time_frames' recorder callback cannot fail; keep the first error for afterwards.
        let mut failure = None;
        let stages = time_frames(gpu, opts.plan, 1, |rec, timer| {
            rec.discard_to_general(target);
            timer.scope(rec, TECHNIQUE, |rec| {
                if let Err(e) = triangles.record_mesh(rec, target, n) {
                    failure.get_or_insert(e);
                }
            });
        })?;
        if let Some(e) = failure {
            return Err(e);
        }
        records.push(triangle_record(gpu, opts, "mesh", stages));
    }
    let stages = time_frames(gpu, opts.plan, 1, |rec, timer| {
        timer.scope(rec, TECHNIQUE, |rec| {
            triangles.record_splat(rec, &pixels, [w, h], n)
        });
    })?;
    records.push(triangle_record(gpu, opts, "compute", stages));
    Ok(records)
}

fn triangle_record(
    gpu: &Gpu,
    opts: &ThroughputOptions,
    path: &str,
    stages: Vec<crate::bench::StageStats>,
) -> BenchRecord {
    let mut r = record(
        gpu,
        opts,
        TECHNIQUE,
        path,
        format!("{} grid triangles", opts.triangles),
    );
    let n = f64::from(opts.triangles);
    r.counts.insert("triangles".into(), n);
    r.counts.insert(
        "pixels_per_triangle".into(),
        covered_offsets(false).len() as f64,
    );
    if let Some(ms) = stages.first().map(|s| s.median_ms) {
        r.counts.insert("mtri_per_s".into(), n / (ms * 1e-3) / 1e6);
    }
    r.stages = stages;
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leg_length_keeps_pixel_centres_off_edges() {
        // Centres have integer x + y relative to a corner; a half-integer leg keeps the
        // hypotenuse off them, and a leg shorter than the cell keeps triangles inside it.
        assert_eq!(LEG_PX.fract(), 0.5);
    }

    #[test]
    fn both_triangle_kinds_cover_three_disjoint_pixels() {
        let even = covered_offsets(false);
        let odd = covered_offsets(true);
        assert_eq!(even, vec![[0, 0], [1, 0], [0, 1]]);
        assert_eq!(odd.len(), 3);
        assert!(odd.iter().all(|p| !even.contains(p)));
    }

    #[test]
    fn reference_wraps_and_stays_in_whole_cells() {
        let (w, h) = (10, 7); // 3x2 whole cells, a ragged right column and bottom row
        let full = reference_coverage(w, h, 12);
        assert_eq!(full.iter().filter(|&&c| c).count(), 6 * 6);
        assert_eq!(reference_coverage(w, h, 1000), full);
        assert!((0..h).all(|y| !full[(y * w + 9) as usize]));
        assert_eq!(
            reference_coverage(w, h, 3).iter().filter(|&&c| c).count(),
            9
        );
    }
}
