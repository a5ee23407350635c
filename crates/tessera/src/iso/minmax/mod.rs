//! Min-max octree built on the GPU (paper D's empty-space-skipping structure; DESIGN §4).
//!
//! Level 0 holds one (min, max) per block of 8×8×4 cells, computed in a single pass over the
//! volume, by one workgroup per block or ([`LevelZeroPass::Grouped`]) one per 2×2×2 blocks that
//! also writes level 1; or, where the samples are at hand in a buffer
//! ([`MinMaxBuilder::record_from_samples`]), by row walks over that buffer, which read it
//! in whole cache lines rather than one texel per fetch. Each further level is the 2×2×2
//! max-reduction of the one below, up to a single root, three levels per pass
//! (`minmax_levels.comp.glsl`). The CPU twin is `tessera_data::minmax`.

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::error::Result;
use crate::gpu_volume::GpuVolume;
use bytemuck::{Pod, Zeroable};
use tessera_data::minmax::level_dims;
use tessera_data::{ScalarType, Volume};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct BlockParams {
    pub volume_dims: [u32; 4],
    pub block_dims: [u32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GroupParams {
    pub volume_dims: [u32; 4],
    pub block_dims: [u32; 4],
    /// Level-1 nodes per axis, and in w the first one's index (0: the octree has no level 1).
    pub parent_dims: [u32; 4],
}

/// How level 0 is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelZeroPass {
    /// A workgroup per block, reduced by subgroup arithmetic where `subgroups`, else by a
    /// shared-memory tree.
    PerBlock { subgroups: bool },
    /// A workgroup per 2×2×2 blocks, its samples read once into shared memory, writing level 1
    /// too (`minmax_groups.comp.glsl`).
    Grouped,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LevelsParams {
    /// The level read; the three above it are written (those the octree has).
    pub child_level: u32,
    pub level_count: u32,
}

/// Levels one pass of `minmax_levels.comp.glsl` writes.
const LEVELS_PER_PASS: usize = 3;

/// The octree's storage: all levels' (min, max) pairs in one buffer, level 0 first, plus a
/// table of (nodes per axis, first node) per level.
pub struct MinMaxOctreeGpu {
    pub nodes: Buffer,
    pub levels: Buffer,
    pub level_dims: Vec<[u32; 3]>,
    pub level_offsets: Vec<u32>,
}

impl MinMaxOctreeGpu {
    pub fn allocate(gpu: &Gpu, volume_dims: [u32; 3]) -> Result<MinMaxOctreeGpu> {
        let level_dims = level_dims(volume_dims);
        let mut level_offsets = Vec::with_capacity(level_dims.len());
        let mut total = 0u32;
        for d in &level_dims {
            level_offsets.push(total);
            total += d[0] * d[1] * d[2];
        }
        let table: Vec<[u32; 4]> = level_dims
            .iter()
            .zip(&level_offsets)
            .map(|(d, &o)| [d[0], d[1], d[2], o])
            .collect();
        let nodes = gpu.create_buffer(
            "minmax_nodes",
            total as u64 * 8,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let levels = gpu.upload_buffer(
            "minmax_levels",
            bytemuck::cast_slice(&table),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        Ok(MinMaxOctreeGpu {
            nodes,
            levels,
            level_dims,
            level_offsets,
        })
    }

    pub fn node_count(&self) -> u64 {
        self.nodes.size / 8
    }

    /// Reads all levels back as (min, max) pairs, level 0 first.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<[f32; 2]>> {
        Ok(gpu.read_buffer_as(&self.nodes)?)
    }
}

/// The compute pipelines that build the octree for volumes of one scalar type.
pub struct MinMaxBuilder {
    blocks: Pipeline,
    /// Level 0 from a buffer of the samples (`minmax_rows.comp.glsl`).
    rows: Pipeline,
    /// Three levels from the one below (`minmax_levels.comp.glsl`).
    levels: Pipeline,
    scalar: ScalarType,
    pass: LevelZeroPass,
}

/// Defines of the block pass: the volume's, and which reduction it uses.
pub(crate) fn block_defines(scalar: ScalarType, subgroups: bool) -> Vec<(String, String)> {
    let mut defines = volume_defines(scalar);
    defines.push((
        "SUBGROUP_ARITHMETIC".into(),
        u32::from(subgroups).to_string(),
    ));
    defines
}

/// Defines of the buffer pass: the block size and how samples are packed in 32-bit words.
pub(crate) fn rows_defines(scalar: ScalarType) -> Vec<(String, String)> {
    let mut defines = crate::config::common_defines();
    defines.push(("SAMPLE_BYTES".into(), scalar.size_bytes().to_string()));
    defines.push((
        "SAMPLE_FLOAT".into(),
        u32::from(scalar == ScalarType::F32).to_string(),
    ));
    defines
}

impl MinMaxBuilder {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<MinMaxBuilder> {
        let subgroups = gpu.caps().subgroup_arithmetic;
        Self::with_pass(gpu, compiler, scalar, LevelZeroPass::PerBlock { subgroups })
    }

    /// `pass` picks how level 0 is computed; every pass gives identical results (tests run
    /// them all). `PerBlock { subgroups: true }` needs subgroup arithmetic.
    pub fn with_pass(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        pass: LevelZeroPass,
    ) -> Result<MinMaxBuilder> {
        let defines = volume_defines(scalar);
        let blocks = match pass {
            LevelZeroPass::PerBlock { subgroups } => compiler.compile(
                &builtin_shader!("minmax_blocks.comp.glsl"),
                &block_defines(scalar, subgroups),
            )?,
            LevelZeroPass::Grouped => {
                compiler.compile(&builtin_shader!("minmax_groups.comp.glsl"), &defines)?
            }
        };
        let levels = compiler.compile(&builtin_shader!("minmax_levels.comp.glsl"), &defines)?;
        let rows = compiler.compile(
            &builtin_shader!("minmax_rows.comp.glsl"),
            &rows_defines(scalar),
        )?;
        Ok(MinMaxBuilder {
            rows: gpu.compute_pipeline(
                "minmax rows",
                &rows,
                &[Slot::StorageBuffer, Slot::StorageBuffer],
            )?,
            blocks: gpu.compute_pipeline(
                "minmax blocks",
                &blocks,
                &[Slot::Texture, Slot::StorageBuffer],
            )?,
            levels: gpu.compute_pipeline("minmax levels", &levels, &[Slot::StorageBuffer; 2])?,
            scalar,
            pass,
        })
    }

    /// The sample type the pipelines read.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }

    /// Records the build of every level of `octree` from `volume`.
    pub fn record(&self, rec: &Recorder, volume: &GpuVolume, octree: &MinMaxOctreeGpu) {
        let d0 = octree.level_dims[0];
        let volume_dims = [volume.dims[0], volume.dims[1], volume.dims[2], 0];
        let block_dims = [d0[0], d0[1], d0[2], 0];
        let bindings = [
            Binding::Texture {
                image: &volume.texture,
                linear: false,
            },
            Binding::Buffer(&octree.nodes),
        ];
        let first_reduced = match self.pass {
            LevelZeroPass::PerBlock { .. } => {
                let params = BlockParams {
                    volume_dims,
                    block_dims,
                };
                rec.dispatch_groups(&self.blocks, &bindings, bytemuck::bytes_of(&params), d0);
                1
            }
            LevelZeroPass::Grouped => {
                let (parent_dims, groups) = match octree.level_dims.get(1) {
                    Some(d1) => ([d1[0], d1[1], d1[2], octree.level_offsets[1]], *d1),
                    None => ([1, 1, 1, 0], [1, 1, 1]),
                };
                let params = GroupParams {
                    volume_dims,
                    block_dims,
                    parent_dims,
                };
                rec.dispatch_groups(&self.blocks, &bindings, bytemuck::bytes_of(&params), groups);
                2
            }
        };
        self.record_levels(rec, octree, first_reduced);
    }

    /// Records the build of every level of `octree` from `samples`, a buffer of a volume of
    /// `dims` samples of this builder's type, packed x fastest and padded to whole 32-bit
    /// words (as [`samples_buffer_size`] sizes it).
    pub fn record_from_samples(
        &self,
        rec: &Recorder,
        samples: &Buffer,
        dims: [u32; 3],
        octree: &MinMaxOctreeGpu,
    ) -> Result<()> {
        self.record_level_zero_from_samples(rec, samples, dims, octree)?;
        self.record_levels(rec, octree, 1);
        Ok(())
    }

    /// [`Self::record_from_samples`] for level 0 alone, the rest of `octree` left as it was:
    /// what the benchmark times apart from the levels above.
    pub fn record_level_zero_from_samples(
        &self,
        rec: &Recorder,
        samples: &Buffer,
        dims: [u32; 3],
        octree: &MinMaxOctreeGpu,
    ) -> Result<()> {
        let needed = samples_buffer_size(self.scalar, dims);
        // The shader numbers samples with 32-bit integers.
        if needed > u64::from(u32::MAX) {
            return Err(crate::error::Error::Invalid(format!(
                "a {}x{}x{} {} volume is too large to build its octree from one buffer",
                dims[0],
                dims[1],
                dims[2],
                self.scalar.name()
            )));
        }
        if samples.size < needed {
            return Err(crate::error::Error::Invalid(format!(
                "the samples buffer holds {} bytes; a {}x{}x{} {} volume needs {needed}",
                samples.size,
                dims[0],
                dims[1],
                dims[2],
                self.scalar.name()
            )));
        }
        let d0 = octree.level_dims[0];
        let params = BlockParams {
            volume_dims: [dims[0], dims[1], dims[2], 0],
            block_dims: [d0[0], d0[1], d0[2], 0],
        };
        rec.dispatch_groups(
            &self.rows,
            &[Binding::Buffer(samples), Binding::Buffer(&octree.nodes)],
            bytemuck::bytes_of(&params),
            [d0[0].div_ceil(32), d0[1], d0[2]],
        );
        Ok(())
    }

    /// Records levels `first_reduced..` of `octree`, three per pass, each from the one below.
    fn record_levels(&self, rec: &Recorder, octree: &MinMaxOctreeGpu, first_reduced: usize) {
        let level_count = octree.level_dims.len();
        for child in (first_reduced - 1..level_count - 1).step_by(LEVELS_PER_PASS) {
            rec.barrier();
            let parent = octree.level_dims[child + 1];
            let params = LevelsParams {
                child_level: child as u32,
                level_count: level_count as u32,
            };
            rec.dispatch_groups(
                &self.levels,
                &[
                    Binding::Buffer(&octree.nodes),
                    Binding::Buffer(&octree.levels),
                ],
                bytemuck::bytes_of(&params),
                parent.map(|n| n.div_ceil(4)),
            );
        }
    }
}

/// A device buffer of `volume`'s samples as [`MinMaxBuilder::record_from_samples`] reads them
/// (padded to whole words), usable also as `usage` says (e.g. a copy source).
pub fn upload_samples(gpu: &Gpu, volume: &Volume, usage: vk::BufferUsageFlags) -> Result<Buffer> {
    let mut words = volume.bytes().to_vec();
    words.resize(
        samples_buffer_size(volume.scalar_type(), volume.dims()) as usize,
        0,
    );
    Ok(gpu.upload_buffer(
        &format!("{} samples", volume.name()),
        &words,
        usage | vk::BufferUsageFlags::STORAGE_BUFFER,
    )?)
}

/// Bytes of a buffer that holds a volume's samples for
/// [`MinMaxBuilder::record_from_samples`]: the samples, rounded up to whole 32-bit words.
pub fn samples_buffer_size(scalar: ScalarType, dims: [u32; 3]) -> u64 {
    let bytes = dims.iter().map(|&d| u64::from(d)).product::<u64>() * scalar.size_bytes() as u64;
    bytes.div_ceil(4) * 4
}
