//! The compute path of interval shading: the mesh shader's proxies rasterized by compute
//! invocations that add their pixels' interval lengths with float atomics. Same placement,
//! proxies and clipping as the mesh-shader path (shared GLSL), so images agree.

use super::{GpuTetMesh, Interval, IntervalFrame};
use crate::builtin_shader;
use crate::error::{Error, Result};
use tessera_data::OrbitCamera;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// Tets per workgroup of `interval_raster.comp.glsl`.
const TETS_PER_WORKGROUP: u32 = 64;

/// Per-pixel optical depth as four floats (rgb + unused), row-major.
pub struct OpticalBuffer {
    pub depth: Buffer,
    pub width: u32,
    pub height: u32,
}

impl OpticalBuffer {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<OpticalBuffer> {
        crate::error::check_image_size(width, height)?;
        let depth = gpu.create_buffer(
            "optical depth (compute)",
            width as u64 * height as u64 * 16,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(OpticalBuffer {
            depth,
            width,
            height,
        })
    }

    pub fn read(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        let texels: Vec<[f32; 4]> =
            bytemuck::allocation::pod_collect_to_vec(&gpu.read_buffer(&self.depth)?);
        Ok(texels.into_iter().map(|t| [t[0], t[1], t[2]]).collect())
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_buffer(self.depth);
    }
}

pub struct IntervalCompute {
    pipeline: Pipeline,
    stats: Buffer,
    max_groups_x: u32,
}

impl IntervalCompute {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<IntervalCompute> {
        if !gpu.caps().buffer_float32_atomic_add {
            return Err(Error::Invalid(format!(
                "interval shading's compute path needs float atomics, which {} lacks",
                gpu.caps().device_name
            )));
        }
        let spirv = compiler.compile(
            &builtin_shader!("interval_raster.comp.glsl"),
            &crate::config::common_defines(),
        )?;
        let pipeline =
            gpu.compute_pipeline("interval (compute)", &spirv, &[Slot::StorageBuffer; 5])?;
        let stats = gpu.create_buffer(
            "interval compute stats",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(IntervalCompute {
            pipeline,
            stats,
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
        })
    }

    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        target: &OpticalBuffer,
        params: &super::IntervalParams,
    ) -> Result<()> {
        let groups = tessera_gpu::spread_groups(
            mesh.tet_count.div_ceil(TETS_PER_WORKGROUP),
            self.max_groups_x,
        );
        rec.fill_buffer(&self.stats, 0);
        rec.fill_buffer(&target.depth, 0);
        rec.barrier();
        rec.dispatch_groups(
            &self.pipeline,
            &[
                Binding::Buffer(&mesh.vertices),
                Binding::Buffer(&mesh.tets),
                Binding::Buffer(&mesh.absorption),
                Binding::Buffer(&self.stats),
                Binding::Buffer(&target.depth),
            ],
            bytemuck::bytes_of(params),
            groups,
        );
        rec.barrier();
        Ok(())
    }

    pub fn render(
        &self,
        gpu: &Gpu,
        mesh: &GpuTetMesh,
        target: &OpticalBuffer,
        camera: &OrbitCamera,
    ) -> Result<IntervalFrame> {
        let params = Interval::params(mesh, camera, target.width, target.height);
        let gpu_ms = crate::bench::time_once(gpu, "interval shading (compute)", |rec| {
            self.record(rec, mesh, target, &params)
        })?;
        Ok(IntervalFrame {
            optical_depth: target.read(gpu)?,
            gpu_ms,
            clipped_near: crate::bench::read_words(gpu, &self.stats)?[0],
        })
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_pipeline(self.pipeline);
        gpu.destroy_buffer(self.stats);
    }
}
