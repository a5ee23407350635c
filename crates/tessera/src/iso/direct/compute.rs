//! The compute path of `direct`: the same block classification and marching cubes as the
//! task/mesh pipeline, in compute, feeding the shared compute rasterizer. Chosen where the
//! graphics stages are slow (DESIGN §3: on an H200 a fragment shader runs 33× slower than the
//! same compute shader).

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::error::Result;
use crate::iso::direct::DirectParams;
use crate::iso::PreparedVolume;
use tessera_data::ScalarType;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// Bytes per triangle in the rasterizer's list: three clip-space corners.
pub const TRIANGLE_BYTES: u64 = 48;
/// Bytes per triangle of shading attributes: three world normals and three world positions.
pub const ATTRIBUTE_BYTES: u64 = 96;

/// The generated triangles of a frame, sized for `capacity` triangles.
pub struct TriangleLists {
    pub triangles: Buffer,
    pub attributes: Buffer,
    /// `triangle_count` then the rasterizer's indirect dispatch arguments.
    pub counts: Buffer,
    pub capacity: u32,
}

impl TriangleLists {
    pub fn new(gpu: &Gpu, capacity: u32) -> Result<TriangleLists> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let n = capacity.max(1) as u64;
        let triangles = gpu.create_buffer(
            "direct triangles",
            n * TRIANGLE_BYTES,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        let attributes = gpu.create_buffer(
            "direct attributes",
            n * ATTRIBUTE_BYTES,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        let counts = gpu.create_buffer(
            "direct triangle counts",
            16,
            usage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        Ok(TriangleLists {
            triangles,
            attributes,
            counts,
            capacity,
        })
    }

    /// The capacity that fits a share of the device's memory, for frames of unknown size.
    pub fn default_capacity(gpu: &Gpu) -> u32 {
        let budget = gpu.caps().device_local_bytes / 8;
        (budget / (TRIANGLE_BYTES + ATTRIBUTE_BYTES)).min(64 << 20) as u32
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_buffer(self.triangles);
        gpu.destroy_buffer(self.attributes);
        gpu.destroy_buffer(self.counts);
    }
}

/// What the last extraction did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ExtractStats {
    /// Triangles generated; more than the lists' capacity means the frame lost some.
    pub triangles: u32,
    /// Blocks whose range held the isovalue and were classified cell by cell.
    pub blocks_classified: u32,
}

pub struct DirectExtract {
    extract: Pipeline,
    stats: Buffer,
}

impl DirectExtract {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<DirectExtract> {
        let spirv = compiler.compile(
            &builtin_shader!("extract.comp.glsl"),
            &volume_defines(scalar),
        )?;
        let extract = gpu.compute_pipeline(
            "direct extract",
            &spirv,
            &[
                Slot::Texture,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
            ],
        )?;
        let stats = gpu.create_buffer(
            "direct extract stats",
            8,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(DirectExtract { extract, stats })
    }

    /// Records the extraction of every occupied block's triangles into `lists`;
    /// `params.dims[3]` must be the lists' capacity.
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        lists: &TriangleLists,
        params: &DirectParams,
    ) {
        rec.fill_buffer(&self.stats, 0);
        rec.fill_buffer(&lists.counts, 0);
        rec.barrier();
        rec.dispatch_groups(
            &self.extract,
            &[
                Binding::Texture {
                    image: &prepared.volume.texture,
                    linear: false,
                },
                Binding::Buffer(&prepared.octree.nodes),
                Binding::Buffer(&lists.triangles),
                Binding::Buffer(&lists.attributes),
                Binding::Buffer(&lists.counts),
                Binding::Buffer(&self.stats),
            ],
            bytemuck::bytes_of(params),
            prepared.octree.level_dims[0],
        );
    }

    pub fn read_stats(&self, gpu: &Gpu) -> Result<ExtractStats> {
        let s: Vec<u32> = bytemuck::allocation::pod_collect_to_vec(&gpu.read_buffer(&self.stats)?);
        Ok(ExtractStats {
            triangles: s[0],
            blocks_classified: s[1],
        })
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_pipeline(self.extract);
        gpu.destroy_buffer(self.stats);
    }
}
