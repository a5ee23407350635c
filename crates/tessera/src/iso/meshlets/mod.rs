//! Paper C's meshlet extraction on the GPU ("Real-Time Meshlet Extraction from Scalar
//! Volumes"): occupied blocks from the min-max octree, compacted (`occupied.comp.glsl`); per
//! block a region analysis that partitions it into 8×8×4, 4×4×4 or 2×2×2 subblocks whose
//! surfaces each fit a meshlet and reserves the block's output with one atomic per total
//! (`analysis.glsl`); per subblock a PMB-style extraction of one meshlet: f32 positions and
//! normals, 8-bit local indices, a descriptor with its bounds (`extraction.glsl`).
//!
//! Two producers write the same buffers ([`GpuMeshlets`]) in the same order:
//! * [`ExtractionPath::MeshShaders`], the paper's: the task stage analyses a block and hands
//!   the partition to one mesh workgroup per subblock in its payload; the pipeline draws
//!   nothing.
//! * [`ExtractionPath::Compute`]: one compute workgroup per block analyses it and extracts
//!   its subblocks one after the other, the payload in shared memory; in two passes, blocks
//!   that fit one meshlet whole first, then the others, listed by the first
//!   ([`GpuMeshlets::split_blocks`]), so that the first holds no partition code.
//!
//! Changes from the paper: the analysis sums over shared memory, not a subgroup (lavapipe's
//! subgroup has 8 invocations), and the extraction's prefix sums use subgroup arithmetic of
//! any subgroup size where the device has it; the compute path's workgroups have 128
//! invocations, four per eighth of a block ([`ExtractionPath::workgroup_size`]), and its
//! extraction reuses the cells' table rows its analysis found (and, for a block that fits one
//! meshlet whole, the analysis's counts and prefix sums); each vertex is computed by its own
//! invocation after numbering; a block's samples are read once into shared memory
//! (`samples.glsl`); the meshlet limits and the partition are
//! `tessera_data::meshlets`'s, whose CPU reference the output equals bit for bit once both are
//! sorted by block and subblock. A block whose reservation passes the buffers' capacity
//! writes nothing; the totals keep counting, so the host grows the buffers and extracts again.

pub mod buffers;

/// A finished meshlet extraction.
pub type Extraction = crate::iso::attempts::Extraction<MeshletCounters>;

pub use buffers::{
    GpuMeshlets, MeshletCapacity, MeshletCounters, OVERFLOW_CAPACITY, OVERFLOW_MISMATCH,
};

use crate::builtin_shader;
use crate::config::meshlet_defines;
use crate::error::{Error, Result};
use crate::iso::ablation::Ablation;
use crate::iso::attempts::extract_with_retries;
use crate::iso::direct::block_list;
use crate::iso::PreparedVolume;
use bytemuck::{Pod, Zeroable};
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::meshlets::{check_meshlet_dims, MeshletMesh};
use tessera_data::ScalarType;
use tessera_gpu::{
    vk, Binding, Gpu, GpuError, Image, Pipeline, Recorder, RenderTargets, ShaderCompiler, Slot,
};

/// Push constants of every meshlet extraction pass (`params.glsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct MeshletParams {
    pub volume_dims: [u32; 3],
    pub isovalue: f32,
    pub block_dims: [u32; 3],
    pub meshlet_capacity: u32,
    pub vertex_capacity: u32,
    pub triangle_capacity: u32,
}

/// Which pipeline produces the meshlets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExtractionPath {
    /// Region analysis and extraction in one compute workgroup per block.
    Compute,
    /// The paper's task (region analysis) and mesh (extraction) stages; needs
    /// `VK_EXT_mesh_shader`.
    MeshShaders,
}

impl ExtractionPath {
    /// Invocations per block. The paper's task and mesh workgroups have one per eighth of a
    /// block (32). The compute path runs both stages in one workgroup, with four per eighth:
    /// with 32, a block held too few threads to hide the latency of its dependent steps
    /// (docs/BENCHMARKS.md, H200 runs 41-43).
    pub fn workgroup_size(self) -> u32 {
        match self {
            ExtractionPath::Compute => 128,
            ExtractionPath::MeshShaders => 32,
        }
    }

    /// Whether the extraction's prefix sums use subgroup arithmetic (where the device has it
    /// for compute shaders) rather than a shared-memory scan. The mesh stage keeps the
    /// shared-memory scan: subgroup support there is a separate, rarer capability.
    pub fn subgroup_scan(self, subgroup_arithmetic: bool) -> bool {
        self == ExtractionPath::Compute && subgroup_arithmetic
    }
}

/// The slots of the extraction pipelines, as `buffers.glsl` binds them: the volume, then
/// buffers.
const EXTRACT_SLOTS: [Slot; 8] = texture_then_buffers();
/// The compute passes' slots: the extraction's, then the list of blocks that do not fit.
const COMPUTE_SLOTS: [Slot; 9] = texture_then_buffers();

const fn texture_then_buffers<const N: usize>() -> [Slot; N] {
    let mut slots = [Slot::StorageBuffer; N];
    slots[0] = Slot::Texture;
    slots
}

enum Producer {
    /// The pass over every occupied block, which extracts those that fit one meshlet whole,
    /// and the pass over the others (`extract.comp.glsl`, MESHLET_SPLIT_PASS 0 and 1).
    Compute { fits: Pipeline, split: Pipeline },
    /// The task/mesh pipeline and the 1×1 attachment its (empty) rendering needs.
    MeshShaders {
        pipeline: Pipeline,
        attachment: Image,
    },
}

/// The extraction pipelines for volumes of one sample type and one ambiguity rule.
pub struct MeshletExtractor {
    occupied: Pipeline,
    block_args: Pipeline,
    producer: Producer,
    scalar: ScalarType,
    /// Workgroups one dispatch may launch along x on this device.
    max_groups_x: u32,
    ablation: Ablation,
}

impl MeshletExtractor {
    /// Pipelines for `scalar` volumes, ambiguous faces cut by `rule` (as `direct` cuts them).
    /// The mesh-shader path is refused on a device without task and mesh shaders.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        path: ExtractionPath,
    ) -> Result<MeshletExtractor> {
        Self::ablated(gpu, compiler, scalar, rule, path, Ablation::None)
    }

    /// [`Self::new`] with a stage left out, for performance work: what it writes is not a
    /// surface.
    pub fn ablated(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        path: ExtractionPath,
        ablation: Ablation,
    ) -> Result<MeshletExtractor> {
        if path == ExtractionPath::MeshShaders
            && !(gpu.caps().mesh_shader && gpu.caps().task_shader)
        {
            return Err(Error::Gpu(GpuError::Unsupported {
                device: gpu.caps().device_name.clone(),
                what: "task and mesh shaders (VK_EXT_mesh_shader)".into(),
            }));
        }
        let mut defines = meshlet_defines(scalar, rule, path, gpu.caps().subgroup_arithmetic);
        defines.push(ablation.define());
        let occupied = compiler.compile(&builtin_shader!("occupied.comp.glsl"), &defines)?;
        let producer = match path {
            ExtractionPath::Compute => {
                let pass = |split: bool, name: &str| -> Result<Pipeline> {
                    let mut defines = defines.clone();
                    defines.push(("MESHLET_SPLIT_PASS".into(), u32::from(split).to_string()));
                    let spirv =
                        compiler.compile(&builtin_shader!("extract.comp.glsl"), &defines)?;
                    Ok(gpu.compute_pipeline(name, &spirv, &COMPUTE_SLOTS)?)
                };
                Producer::Compute {
                    fits: pass(false, "meshlet extraction")?,
                    split: pass(true, "meshlet extraction of split blocks")?,
                }
            }
            ExtractionPath::MeshShaders => {
                let task = compiler.compile(&builtin_shader!("extract.task.glsl"), &defines)?;
                let mesh = compiler.compile(&builtin_shader!("extract.mesh.glsl"), &defines)?;
                let format = vk::Format::R8G8B8A8_UNORM;
                let targets = RenderTargets {
                    color_write: false,
                    ..RenderTargets::color(format)
                };
                let pipeline = gpu.graphics_pipeline_for(
                    "meshlet extraction (task/mesh)",
                    &[&task, &mesh],
                    &EXTRACT_SLOTS,
                    &targets,
                )?;
                let attachment = gpu.create_image(
                    "meshlet extraction attachment",
                    [1, 1, 1],
                    format,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT,
                    false,
                )?;
                Producer::MeshShaders {
                    pipeline,
                    attachment,
                }
            }
        };
        Ok(MeshletExtractor {
            occupied: gpu.compute_pipeline(
                "meshlet occupied blocks",
                &occupied,
                &[Slot::StorageBuffer; 2],
            )?,
            block_args: block_list::args_pipeline(gpu, compiler, "meshlet block arguments")?,
            producer,
            scalar,
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
            ablation,
        })
    }

    /// Which pipeline produces the meshlets.
    pub fn path(&self) -> ExtractionPath {
        match self.producer {
            Producer::Compute { .. } => ExtractionPath::Compute,
            Producer::MeshShaders { .. } => ExtractionPath::MeshShaders,
        }
    }

    /// Output buffers of `capacity` for `prepared` (its block count sizes the block list).
    pub fn buffers(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        capacity: MeshletCapacity,
    ) -> Result<GpuMeshlets> {
        GpuMeshlets::new(gpu, block_count(prepared)?, capacity)
    }

    /// The push constants of an extraction of `prepared` at `iso` into `out`.
    pub fn params(prepared: &PreparedVolume, iso: f32, out: &GpuMeshlets) -> MeshletParams {
        MeshletParams {
            volume_dims: prepared.volume.dims,
            isovalue: iso,
            block_dims: prepared.octree.level_dims[0],
            meshlet_capacity: out.capacity.meshlets,
            vertex_capacity: out.capacity.vertices,
            triangle_capacity: out.capacity.triangles,
        }
    }

    /// Records one extraction attempt into `out` (counters reset first). After it, `out`'s
    /// counters say whether it fit ([`Self::extract_into`] reads them and retries).
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        iso: f32,
        out: &GpuMeshlets,
    ) -> Result<()> {
        check_meshlet_dims("the volume", prepared.volume.dims)?;
        let params = Self::params(prepared, iso, out);
        let push = bytemuck::bytes_of(&params);
        rec.fill_buffer(&out.counters, 0);
        // Emptied before the block list's reset, whose barrier covers both.
        rec.update_buffer(
            &out.split_blocks,
            bytemuck::bytes_of(&block_list::BlockListHeader::EMPTY),
        );
        let [bx, by, bz] = params.block_dims;
        block_list::record_occupied(
            rec,
            &self.occupied,
            &self.block_args,
            &prepared.octree.nodes,
            &out.blocks,
            push,
            bx * by * bz,
            self.max_groups_x,
        );
        if self.ablation == Ablation::FilteringOnly {
            return Ok(());
        }
        let bindings = [
            Binding::Texture {
                image: &prepared.volume.texture,
                linear: false,
            },
            Binding::Buffer(&out.blocks),
            Binding::Buffer(&out.counters),
            Binding::Buffer(&out.meshlets),
            Binding::Buffer(&out.positions),
            Binding::Buffer(&out.normals),
            Binding::Buffer(&out.local_indices),
            Binding::Buffer(&out.block_meshlets),
        ];
        match &self.producer {
            Producer::Compute { fits, split } => {
                let mut bindings = bindings.to_vec();
                bindings.push(Binding::Buffer(&out.split_blocks));
                rec.dispatch_indirect(fits, &bindings, push, &out.blocks, block_list::ARGS_OFFSET);
                rec.barrier();
                block_list::record_args(rec, &self.block_args, &out.split_blocks);
                rec.barrier();
                rec.dispatch_indirect(
                    split,
                    &bindings,
                    push,
                    &out.split_blocks,
                    block_list::ARGS_OFFSET,
                );
            }
            Producer::MeshShaders {
                pipeline,
                attachment,
            } => {
                rec.begin_rendering(attachment, [0.0; 4]);
                rec.draw_mesh_tasks_indirect(
                    pipeline,
                    &bindings,
                    push,
                    &out.blocks,
                    block_list::ARGS_OFFSET,
                )?;
                rec.end_rendering();
            }
        }
        Ok(())
    }

    /// Extracts the `iso` level set of `prepared` into `out`, growing its buffers and
    /// extracting again when they overflow; the meshlets stay on the GPU.
    pub fn extract_into(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        iso: f32,
        out: &mut GpuMeshlets,
    ) -> Result<Extraction> {
        self.check(prepared)?;
        let blocks = block_count(prepared)?;
        if blocks > out.block_capacity {
            *out = GpuMeshlets::new(gpu, blocks, out.capacity)?;
        }
        let out = std::cell::RefCell::new(out);
        extract_with_retries(
            gpu,
            "meshlet extraction",
            |rec| self.record(rec, prepared, iso, &out.borrow()),
            || {
                let mut out = out.borrow_mut();
                let counters: MeshletCounters =
                    bytemuck::pod_read_unaligned(&gpu.read_buffer(&out.counters)?);
                if counters.overflow & OVERFLOW_MISMATCH != 0 {
                    return Err(Error::Invalid(
                        "meshlet extraction: a subblock's extraction counted other vertices \
                         or triangles than its region analysis"
                            .into(),
                    ));
                }
                let grew = out.grow_for(gpu, &counters)?;
                let fit = counters.overflow & OVERFLOW_CAPACITY == 0 && !grew;
                if fit {
                    out.totals = counters;
                }
                Ok(fit.then_some(counters))
            },
        )
    }

    /// Extracts the `iso` level set of `prepared` and reads it back (blocks in the GPU's
    /// order; see [`MeshletMesh::in_origin_order`]).
    pub fn extract(&self, gpu: &Gpu, prepared: &PreparedVolume, iso: f32) -> Result<MeshletMesh> {
        let mut out = self.buffers(gpu, prepared, MeshletCapacity::default())?;
        self.extract_into(gpu, prepared, iso, &mut out)?;
        out.read(gpu)
    }

    fn check(&self, prepared: &PreparedVolume) -> Result<()> {
        prepared.require_scalar(self.scalar, "meshlet")?;
        Ok(check_meshlet_dims("the volume", prepared.volume.dims)?)
    }
}

/// Blocks of level 0 of `prepared`'s octree.
fn block_count(prepared: &PreparedVolume) -> Result<u32> {
    let [x, y, z] = prepared.octree.level_dims[0];
    x.checked_mul(y)
        .and_then(|xy| xy.checked_mul(z))
        .ok_or_else(|| Error::Invalid("the volume has more than 2^32 blocks".into()))
}
