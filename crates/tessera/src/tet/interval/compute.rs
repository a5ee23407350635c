//! The compute path of interval shading: the mesh shader's proxies (shared GLSL) rasterized by
//! compute invocations that add their pixels' integrands with float atomics. Small tets are
//! drawn by one invocation each; a tet whose screen rectangle exceeds a pixel limit is split
//! into 16 × 16-pixel tiles drawn by one workgroup each (indirect dispatch), so that the huge
//! proxies near an eye inside the mesh spread over the GPU. The binned variant
//! ([`super::binned`]) draws through per-tile lists instead and leaves these passes only the
//! tets its lists have no room for.

use super::binned::{BinCapacity, TetBins};
use super::mesh::GpuTetMesh;
use super::scheme_choice::DrawScheme;
use super::subgroup_draw::{subgroup_draw_defines, SubgroupDraw};
use super::{ComputeScheme, IntervalParams};
use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::raster::{create_counts_buffer, IndirectArgs};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot, Timer,
};

/// Tets per workgroup of `interval_raster.comp.glsl` and `interval_bin_count.comp.glsl`.
const TETS_PER_WORKGROUP: u32 = 64;
/// Side of a tile in pixels (`TILE` in the shaders): one invocation per pixel.
pub const TILE: u32 = 16;

/// How much room the tile pass has; tets beyond it are drawn by single invocations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileCapacity {
    /// Large tets at once (16 bytes each).
    pub tets: u32,
    /// Tiles at once (4 bytes each).
    pub tiles: u32,
}

impl Default for TileCapacity {
    fn default() -> Self {
        TileCapacity {
            tets: 1 << 20,
            tiles: 1 << 24,
        }
    }
}

pub struct IntervalCompute {
    raster: Pipeline,
    tiles: Pipeline,
    indirect: IndirectArgs,
    tiled_tets: Buffer,
    tile_owner: Buffer,
    tile_count: Buffer,
    max_groups_x: u32,
    /// The binned scheme's lists; `None` where only the per-tet scheme is drawn.
    bins: Option<TetBins>,
}

/// The interval defines, the tile pass's sizes, and which tets the per-tet pass's subgroups
/// draw together ([`subgroup_draw_defines`]).
pub(crate) fn compute_defines(
    defines: &[(String, String)],
    capacity: TileCapacity,
    subgroup_draw: SubgroupDraw,
) -> Vec<(String, String)> {
    let mut defines = defines.to_vec();
    defines.extend([
        ("TILE".into(), TILE.to_string()),
        ("TETS_PER_WORKGROUP".into(), TETS_PER_WORKGROUP.to_string()),
        ("TILED_CAPACITY".into(), format!("{}u", capacity.tets)),
        ("TILE_CAPACITY".into(), format!("{}u", capacity.tiles)),
    ]);
    defines.extend(subgroup_draw_defines(subgroup_draw));
    defines
}

impl IntervalCompute {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        capacity: TileCapacity,
        scheme: ComputeScheme,
        bin_capacity: BinCapacity,
        subgroup_draw: SubgroupDraw,
    ) -> Result<IntervalCompute> {
        let caps = gpu.caps();
        if !caps.buffer_float32_atomic_add {
            return Err(Error::Invalid(format!(
                "interval shading's compute path needs float atomics, which {} lacks",
                caps.device_name
            )));
        }
        // Asked for and possible on the device; otherwise each invocation draws its own tet.
        let subgroup_draw = if caps.subgroup_arithmetic && caps.subgroup_ballot_and_shuffle {
            subgroup_draw
        } else {
            SubgroupDraw::Off
        };
        let defines = compute_defines(defines, capacity, subgroup_draw);
        let slots = [Slot::StorageBuffer; super::COMMON_BINDINGS + 4];
        let raster = compiler.compile(&builtin_shader!("interval_raster.comp.glsl"), &defines)?;
        let tiles = compiler.compile(&builtin_shader!("interval_tiles.comp.glsl"), &defines)?;
        // The integrand in the names, so that pipeline statistics tell the variants apart.
        let integrand = defines
            .iter()
            .find(|(name, _)| name == "INTEGRAND")
            .map_or("?", |(_, code)| code.as_str());
        let raster = gpu.compute_pipeline(
            &format!("interval (compute, integrand {integrand})"),
            &raster,
            &slots,
        )?;
        let tiles = gpu.compute_pipeline(
            &format!("interval tiles (compute, integrand {integrand})"),
            &tiles,
            &slots,
        )?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Vulkan refuses empty buffers; a capacity of 0 still needs one element.
        let tiled_tets = gpu.create_buffer(
            "interval tiled tets",
            16 * u64::from(capacity.tets.max(1)),
            storage,
            MemoryLocation::GpuOnly,
        )?;
        let tile_owner = gpu.create_buffer(
            "interval tile owners",
            4 * u64::from(capacity.tiles.max(1)),
            storage,
            MemoryLocation::GpuOnly,
        )?;
        let bins = match scheme {
            ComputeScheme::PerTet => None,
            ComputeScheme::Binned | ComputeScheme::Auto => {
                Some(TetBins::new(gpu, compiler, &defines, &slots, bin_capacity)?)
            }
        };
        Ok(IntervalCompute {
            bins,
            raster,
            tiles,
            indirect: IndirectArgs::new(gpu, compiler)?,
            tiled_tets,
            tile_owner,
            tile_count: create_counts_buffer(gpu, "interval tile count")?,
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
        })
    }

    /// Records one frame into `target` (cleared to words of `clear` first) with `scheme` (the
    /// binned one needs lists: built unless this was made for the per-tet scheme alone);
    /// `common` are the technique's first bindings (`buffers.glsl`). With a `timer`, the frame
    /// is one scope, `interval`, or for the binned scheme two: `binning` (clearing, counting,
    /// scanning and scattering; tets the lists cannot hold drawn there) and `interval` (the
    /// tile pass and the per-tile shading).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        common: &[Binding],
        target: &Buffer,
        params: &IntervalParams,
        clear: u32,
        scheme: DrawScheme,
        timer: Option<&mut Timer>,
    ) {
        let bins = self.bins.as_ref().filter(|_| scheme == DrawScheme::Binned);
        let mut bindings = common.to_vec();
        bindings.extend([
            Binding::Buffer(target),
            Binding::Buffer(&self.tiled_tets),
            Binding::Buffer(&self.tile_owner),
            Binding::Buffer(&self.tile_count),
        ]);
        let frame = FramePasses {
            bindings: &bindings,
            push: bytemuck::bytes_of(params),
            size: (params.counts[1], params.counts[2]),
        };
        let first = |rec: &Recorder| self.record_first_pass(rec, mesh, &frame, target, clear, bins);
        let rest = |rec: &Recorder| self.record_tiles_and_shading(rec, &frame, bins);
        match (timer, bins.is_some()) {
            (None, _) => {
                first(rec);
                rest(rec);
            }
            (Some(t), false) => t.scope(rec, "interval", |rec| {
                first(rec);
                rest(rec);
            }),
            (Some(t), true) => {
                t.scope(rec, "binning", first);
                t.scope(rec, "interval", rest);
            }
        }
    }

    /// Clears the frame and runs the per-tet pass, or the binned scheme's counting, scan and
    /// scatter.
    fn record_first_pass(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        frame: &FramePasses,
        target: &Buffer,
        clear: u32,
        bins: Option<&TetBins>,
    ) {
        rec.fill_buffer(target, clear);
        rec.fill_buffer(&self.tile_count, 0);
        if let Some(bins) = bins {
            bins.record_clear(rec);
        }
        rec.barrier();
        let groups = tessera_gpu::spread_groups(
            mesh.tet_count.div_ceil(TETS_PER_WORKGROUP),
            self.max_groups_x,
        );
        match bins {
            None => rec.dispatch_groups(&self.raster, frame.bindings, frame.push, groups),
            Some(bins) => bins.record_binning(
                rec,
                frame.bindings,
                frame.push,
                groups,
                &self.indirect,
                frame.size,
            ),
        }
        rec.barrier();
    }

    /// The tile pass of the tets handed to it, then the binned scheme's per-tile shading.
    fn record_tiles_and_shading(
        &self,
        rec: &Recorder,
        frame: &FramePasses,
        bins: Option<&TetBins>,
    ) {
        self.indirect.record(rec, &self.tile_count, 1);
        rec.dispatch_indirect(&self.tiles, frame.bindings, frame.push, &self.tile_count, 4);
        rec.barrier();
        if let Some(bins) = bins {
            bins.record_shade(rec, frame.bindings, frame.push, frame.size);
        }
    }

    /// The binned variant's capacity (`None` for the per-tet variant).
    pub fn bin_capacity(&self) -> Option<BinCapacity> {
        self.bins.as_ref().map(TetBins::capacity)
    }

    /// The (tet, tile) entries of the last frame drawn binned (0 where only the per-tet scheme
    /// is built; the automatic choice's per-tet frames leave the count of the last binned one).
    pub fn bin_entries(&self, gpu: &Gpu) -> Result<u32> {
        self.bins
            .as_ref()
            .map_or(Ok(0), |bins| bins.read_reserved(gpu))
    }

    /// Grows the binned variant's lists when the last frame, of a `width` × `height` image,
    /// overflowed them; whether it did.
    pub fn grow_bins(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<bool> {
        match &mut self.bins {
            Some(bins) => bins.grow_for(gpu, size),
            None => Ok(false),
        }
    }
}

/// What every pass of one compute frame binds and pushes.
struct FramePasses<'a> {
    bindings: &'a [Binding<'a>],
    push: &'a [u8],
    /// The frame's pixels.
    size: (u32, u32),
}
