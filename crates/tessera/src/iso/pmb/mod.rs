//! Parallel Marching Blocks (Liu et al.), paper C's real-time reference, in compute: occupied
//! blocks from the min-max octree, compacted (`occupied.comp.glsl`); per occupied block one
//! workgroup that gives every crossed edge of the block's closed box one vertex and writes the
//! block's triangles as 16-bit indices local to it, with a descriptor (`extract.comp.glsl`).
//! The block size is fixed per pipeline ([`PmbBlockSize`]); the format read back is
//! `tessera_data::pmb`'s.
//!
//! Changes from the paper: by default invocations take runs of a block's samples instead of
//! one each ([`PmbInvocations`]; see `extract.comp.glsl`), the counts' prefix sums use
//! subgroup arithmetic where the device has it, and the output is reserved per block with atomics, growing the
//! buffers and extracting again when it does not fit, as the meshlet extraction does, rather
//! than sized conservatively up front.

pub mod buffers;

pub use buffers::{GpuPmb, PmbCapacity, PmbCounters};
pub use tessera_data::pmb::{PmbBlock, PmbBlockSize, PmbMesh};

use crate::builtin_shader;
use crate::config::pmb_defines;
use crate::error::{Error, Result};
use crate::iso::ablation::Ablation;
use crate::iso::attempts::{extract_with_retries, Extraction};
use crate::iso::direct::block_list;
use crate::iso::PreparedVolume;
use bytemuck::{Pod, Zeroable};
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::ScalarType;
use tessera_gpu::{Binding, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// How a PMB workgroup's invocations share its block's samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PmbInvocations {
    /// 128 invocations (what every Vulkan device accepts), each taking a run of consecutive
    /// samples of the block's closed box.
    #[default]
    Runs,
    /// One invocation per sample of the block's closed box, as Liu et al.'s supplementary
    /// pseudocode launches it (and paper C's reference with it): up to 729 for 8×8×8 blocks.
    OnePerSample,
}

impl PmbInvocations {
    /// Invocations per workgroup for blocks of `size` (`PMB_WORKGROUP`).
    pub fn workgroup_size(self, size: PmbBlockSize) -> u32 {
        match self {
            PmbInvocations::Runs => 128,
            PmbInvocations::OnePerSample => size.cells().iter().map(|c| c + 1).product(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            PmbInvocations::Runs => "runs of samples",
            PmbInvocations::OnePerSample => "one invocation per sample",
        }
    }
}

/// How an extractor is built beyond its block size: the invocations' layout, and for
/// performance work a stage left out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PmbTuning {
    pub invocations: PmbInvocations,
    pub ablation: Ablation,
}

/// Push constants of both PMB passes (`params.glsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct PmbParams {
    pub volume_dims: [u32; 3],
    pub isovalue: f32,
    pub block_dims: [u32; 3],
    pub vertex_capacity: u32,
    pub node_dims: [u32; 3],
    pub triangle_capacity: u32,
}

/// The slots of the extraction pipeline, as `extract.comp.glsl` binds them.
const EXTRACT_SLOTS: [Slot; 7] = [
    Slot::Texture,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
];

/// The PMB pipelines for volumes of one sample type, one ambiguity rule and one block size.
pub struct PmbExtractor {
    occupied: Pipeline,
    block_args: Pipeline,
    extract: Pipeline,
    scalar: ScalarType,
    block_size: PmbBlockSize,
    /// Workgroups one dispatch may launch along x on this device.
    max_groups_x: u32,
    ablation: Ablation,
}

impl PmbExtractor {
    /// Pipelines for `scalar` volumes, ambiguous faces cut by `rule`, blocks of `block_size`.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        block_size: PmbBlockSize,
    ) -> Result<PmbExtractor> {
        Self::tuned(
            gpu,
            compiler,
            scalar,
            rule,
            block_size,
            PmbTuning::default(),
        )
    }

    /// [`Self::new`] with its invocations laid out as `tuning` says; an ablated extractor
    /// (for performance work) writes no surface. PMB has no region analysis to keep alone.
    pub fn tuned(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        block_size: PmbBlockSize,
        tuning: PmbTuning,
    ) -> Result<PmbExtractor> {
        if tuning.ablation == Ablation::AnalysisOnly {
            return Err(Error::Invalid(
                "PMB has no region analysis to time alone".into(),
            ));
        }
        let caps = gpu.caps();
        let workgroup = tuning.invocations.workgroup_size(block_size);
        if workgroup > caps.max_compute_workgroup_invocations {
            return Err(Error::Gpu(tessera_gpu::GpuError::Unsupported {
                device: caps.device_name.clone(),
                what: format!(
                    "{workgroup} invocations per workgroup (PMB {})",
                    block_size.name()
                ),
            }));
        }
        let mut defines = pmb_defines(
            scalar,
            rule,
            block_size,
            workgroup,
            caps.subgroup_arithmetic,
        );
        defines.push(tuning.ablation.define());
        let occupied = compiler.compile(&builtin_shader!("occupied.comp.glsl"), &defines)?;
        let extract = compiler.compile(&builtin_shader!("extract.comp.glsl"), &defines)?;
        Ok(PmbExtractor {
            occupied: gpu.compute_pipeline(
                "PMB occupied blocks",
                &occupied,
                &[Slot::StorageBuffer; 2],
            )?,
            block_args: block_list::args_pipeline(gpu, compiler, "PMB block arguments")?,
            extract: gpu.compute_pipeline("PMB extraction", &extract, &EXTRACT_SLOTS)?,
            scalar,
            block_size,
            max_groups_x: caps.max_compute_workgroup_count[0],
            ablation: tuning.ablation,
        })
    }

    pub fn block_size(&self) -> PmbBlockSize {
        self.block_size
    }

    /// Output buffers of `capacity` for `prepared` (its block count sizes the block list and
    /// the descriptors).
    pub fn buffers(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        capacity: PmbCapacity,
    ) -> Result<GpuPmb> {
        GpuPmb::new(
            gpu,
            self.block_size.cells(),
            self.block_count(prepared)?,
            capacity,
        )
    }

    /// The push constants of an extraction of `prepared` at `iso` into `out`.
    pub fn params(&self, prepared: &PreparedVolume, iso: f32, out: &GpuPmb) -> PmbParams {
        PmbParams {
            volume_dims: prepared.volume.dims,
            isovalue: iso,
            block_dims: self.block_size.grid(prepared.volume.dims),
            vertex_capacity: out.capacity.vertices,
            node_dims: prepared.octree.level_dims[0],
            triangle_capacity: out.capacity.triangles,
        }
    }

    /// Records one extraction attempt into `out` (counters reset first). After it, `out`'s
    /// counters say whether it fit ([`Self::extract_into`] reads them and retries).
    pub fn record(&self, rec: &Recorder, prepared: &PreparedVolume, iso: f32, out: &GpuPmb) {
        let params = self.params(prepared, iso, out);
        let push = bytemuck::bytes_of(&params);
        rec.fill_buffer(&out.counters, 0);
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
            return;
        }
        rec.dispatch_indirect(
            &self.extract,
            &[
                Binding::Texture {
                    image: &prepared.volume.texture,
                    linear: false,
                },
                Binding::Buffer(&out.blocks),
                Binding::Buffer(&out.counters),
                Binding::Buffer(&out.descriptors),
                Binding::Buffer(&out.positions),
                Binding::Buffer(&out.normals),
                Binding::Buffer(&out.indices),
            ],
            push,
            &out.blocks,
            block_list::ARGS_OFFSET,
        );
    }

    /// Extracts the `iso` level set of `prepared` into `out`, growing its buffers and
    /// extracting again when they overflow; the surface stays on the GPU. Returns the totals
    /// (also kept in `out.totals`).
    pub fn extract_into(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        iso: f32,
        out: &mut GpuPmb,
    ) -> Result<Extraction<PmbCounters>> {
        self.check(prepared)?;
        let blocks = self.block_count(prepared)?;
        if blocks > out.block_capacity || out.block_size != self.block_size.cells() {
            *out = GpuPmb::new(gpu, self.block_size.cells(), blocks, out.capacity)?;
        }
        let out = std::cell::RefCell::new(out);
        extract_with_retries(
            gpu,
            "PMB extraction",
            |rec| {
                self.record(rec, prepared, iso, &out.borrow());
                Ok(())
            },
            || {
                let mut out = out.borrow_mut();
                let counters: PmbCounters =
                    bytemuck::pod_read_unaligned(&gpu.read_buffer(&out.counters)?);
                let grew = out.grow_for(gpu, &counters)?;
                let fit = counters.overflow == 0 && !grew;
                if fit {
                    out.totals = counters;
                }
                Ok(fit.then_some(counters))
            },
        )
    }

    /// Extracts the `iso` level set of `prepared` and reads it back (blocks in the GPU's
    /// order).
    pub fn extract(&self, gpu: &Gpu, prepared: &PreparedVolume, iso: f32) -> Result<PmbMesh> {
        let mut out = self.buffers(gpu, prepared, PmbCapacity::default())?;
        self.extract_into(gpu, prepared, iso, &mut out)?;
        out.read(gpu)
    }

    fn check(&self, prepared: &PreparedVolume) -> Result<()> {
        prepared.require_scalar(self.scalar, "PMB")
    }

    /// PMB blocks covering `prepared`'s cells.
    fn block_count(&self, prepared: &PreparedVolume) -> Result<u32> {
        let [x, y, z] = self.block_size.grid(prepared.volume.dims);
        x.checked_mul(y)
            .and_then(|xy| xy.checked_mul(z))
            .ok_or_else(|| Error::Invalid("the volume has more than 2^32 PMB blocks".into()))
    }
}
