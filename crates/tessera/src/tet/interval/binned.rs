//! The binned variant of the compute path: tets are sorted into per-tile lists of screen tiles
//! (count per tile, exclusive scan, scatter), then one workgroup per tile walks its list with
//! one invocation per pixel, combines the tets' values in registers and writes each pixel once,
//! with no global atomics. The per-tet passes ([`super::compute`]) draw the tets the lists have
//! no room for, and the lists grow for the next frame ([`TetBins::grow_for`]).

use super::compute::TILE;
use crate::builtin_shader;
use crate::error::Result;
use crate::raster::{create_counts_buffer, IndirectArgs};
use crate::scan::ExclusiveScan;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// Tets whose proxies a tile's workgroup makes at once into shared memory (3 proxies each).
pub const BIN_BATCH: u32 = 32;
/// Longest list a tile sorts (in shared memory, 4 bytes each): by tet id, so that its sums are
/// the same from frame to frame, or for SDF integrands front to back, with the list position
/// in the key's low bits (hence a power of two); longer lists keep the scatter's order.
pub const BIN_SORT_CAPACITY: u32 = 2048;
const _: () = assert!(BIN_SORT_CAPACITY.is_power_of_two());
/// Largest pixel rectangle, in tiles, whose tiles the counting pass tests against the tet's
/// proxies; a larger one is listed whole, since one invocation walks it (a tet clipped near
/// the eye may span the screen, and the shade pass skips pixels outside its proxies anyway).
pub const BIN_TESTED_TILES: u32 = 64;
/// Entries per workgroup of the scatter pass.
const BIN_SCATTER_WORKGROUP: u32 = 64;

/// How much room the bins have; tets beyond it are drawn by the per-tet passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BinCapacity {
    /// (tet, tile) pairs (8 bytes each, and 4 in the lists).
    pub entries: u32,
    /// Screen tiles (4 bytes each); a larger screen draws every tet per tet.
    pub tiles: u32,
}

impl Default for BinCapacity {
    fn default() -> Self {
        BinCapacity {
            entries: 1 << 22,
            // 3840 × 2160 has 32,400 tiles of 16 × 16 pixels, 7680 × 4320 has 129,600.
            tiles: 1 << 18,
        }
    }
}

impl BinCapacity {
    /// Room for `entries` pairs and `tiles` tiles with a quarter of headroom (the rule every
    /// growing buffer of the crate follows), never less than now.
    fn grown_to(self, entries: u32, tiles: u32) -> BinCapacity {
        let grow = crate::capacity::grown_capacity;
        BinCapacity {
            entries: grow(self.entries, entries),
            tiles: grow(self.tiles, tiles),
        }
    }
}

/// Columns and rows of screen tiles of a `width` × `height` image.
pub fn tile_grid(width: u32, height: u32) -> [u32; 2] {
    [width.div_ceil(TILE), height.div_ceil(TILE)]
}

/// The buffers a capacity needs: entries, per-tile counters, lists.
struct BinBuffers {
    entries: Buffer,
    tile_bins: Buffer,
    list: Buffer,
    capacity: BinCapacity,
}

impl BinBuffers {
    fn new(gpu: &Gpu, capacity: BinCapacity) -> Result<BinBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Vulkan refuses empty buffers; a capacity of 0 still needs one element.
        let entries = u64::from(capacity.entries.max(1));
        let buffer = |name: &str, bytes: u64, usage| {
            gpu.create_buffer(name, bytes, usage, MemoryLocation::GpuOnly)
        };
        Ok(BinBuffers {
            entries: buffer("interval bin entries", 8 * entries, storage)?,
            tile_bins: buffer(
                "interval tile bins",
                4 * u64::from(capacity.tiles.max(1)),
                storage | vk::BufferUsageFlags::TRANSFER_DST,
            )?,
            list: buffer("interval bin lists", 4 * entries, storage)?,
            capacity,
        })
    }
}

pub struct TetBins {
    count: Pipeline,
    scatter: Pipeline,
    shade: Pipeline,
    scan: ExclusiveScan,
    /// Entries reserved (`bin_buffers.glsl`'s `BinCount`), and the scatter's dispatch.
    reserved: Buffer,
    buffers: BinBuffers,
}

/// The compute defines, and the binned passes' sizes.
pub(crate) fn binned_defines(defines: &[(String, String)]) -> Vec<(String, String)> {
    let mut defines = defines.to_vec();
    defines.extend([
        ("BIN_BATCH".into(), BIN_BATCH.to_string()),
        ("BIN_SORT_CAPACITY".into(), BIN_SORT_CAPACITY.to_string()),
        ("BIN_TESTED_TILES".into(), BIN_TESTED_TILES.to_string()),
        (
            "BIN_SCATTER_WORKGROUP".into(),
            BIN_SCATTER_WORKGROUP.to_string(),
        ),
    ]);
    defines
}

impl TetBins {
    /// `defines`: the compute path's; `slots`: those of the per-tet passes, to which the bins'
    /// four buffers are added.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        slots: &[Slot],
        capacity: BinCapacity,
    ) -> Result<TetBins> {
        let defines = binned_defines(defines);
        let mut slots = slots.to_vec();
        slots.extend([Slot::StorageBuffer; 4]);
        let pipeline = |name: &str, spirv| gpu.compute_pipeline(name, &spirv, &slots);
        let count = compiler.compile(&builtin_shader!("interval_bin_count.comp.glsl"), &defines)?;
        let scatter =
            compiler.compile(&builtin_shader!("interval_bin_scatter.comp.glsl"), &defines)?;
        let shade = compiler.compile(&builtin_shader!("interval_bin_shade.comp.glsl"), &defines)?;
        Ok(TetBins {
            count: pipeline("interval bin count (compute)", count)?,
            scatter: pipeline("interval bin scatter (compute)", scatter)?,
            shade: pipeline("interval bin shade (compute)", shade)?,
            scan: ExclusiveScan::new(gpu, compiler)?,
            reserved: create_counts_buffer(gpu, "interval bin entries reserved")?,
            buffers: BinBuffers::new(gpu, capacity)?,
        })
    }

    pub fn capacity(&self) -> BinCapacity {
        self.buffers.capacity
    }

    /// The per-tet passes' `bindings` followed by the bins' buffers.
    fn bindings<'a>(&'a self, bindings: &[Binding<'a>]) -> Vec<Binding<'a>> {
        let mut all = bindings.to_vec();
        all.extend([
            Binding::Buffer(&self.reserved),
            Binding::Buffer(&self.buffers.entries),
            Binding::Buffer(&self.buffers.tile_bins),
            Binding::Buffer(&self.buffers.list),
        ]);
        all
    }

    /// Clears the counters; the caller's barrier follows.
    pub fn record_clear(&self, rec: &Recorder) {
        rec.fill_buffer(&self.reserved, 0);
        rec.fill_buffer(&self.buffers.tile_bins, 0);
    }

    /// Counts the tets into the tiles of a `width` × `height` image (drawing those that do
    /// not fit per tet, over `bindings`), scans and scatters them into the lists; `groups`
    /// covers the tets at `TETS_PER_WORKGROUP` per workgroup. Ends with a barrier.
    pub fn record_binning(
        &self,
        rec: &Recorder,
        bindings: &[Binding],
        push: &[u8],
        groups: [u32; 3],
        indirect: &IndirectArgs,
        (width, height): (u32, u32),
    ) {
        let all = self.bindings(bindings);
        rec.dispatch_groups(&self.count, &all, push, groups);
        rec.barrier();
        let [columns, rows] = tile_grid(width, height);
        let tiles = (columns * rows).min(self.buffers.capacity.tiles);
        self.scan.record(rec, &self.buffers.tile_bins, tiles);
        indirect.record(rec, &self.reserved, BIN_SCATTER_WORKGROUP);
        rec.dispatch_indirect(&self.scatter, &all, push, &self.reserved, 4);
        rec.barrier();
    }

    /// Shades every tile from its list, after the per-tet passes; ends with a barrier.
    pub fn record_shade(
        &self,
        rec: &Recorder,
        bindings: &[Binding],
        push: &[u8],
        (width, height): (u32, u32),
    ) {
        let [columns, rows] = tile_grid(width, height);
        rec.dispatch_groups(
            &self.shade,
            &self.bindings(bindings),
            push,
            [columns, rows, 1],
        );
        rec.barrier();
    }

    /// The (tet, tile) entries the last frame reserved, those that did not fit included.
    pub fn read_reserved(&self, gpu: &Gpu) -> Result<u32> {
        Ok(gpu.read_buffer_as::<u32>(&self.reserved)?[0])
    }

    /// Replaces the bins by larger ones when the last frame, of a `width` × `height` image,
    /// reserved more than they hold; whether it did. The frame itself was complete: the
    /// per-tet passes drew what did not fit.
    pub fn grow_for(&mut self, gpu: &Gpu, (width, height): (u32, u32)) -> Result<bool> {
        let reserved = self.read_reserved(gpu)?;
        let [columns, rows] = tile_grid(width, height);
        let capacity = self.buffers.capacity;
        let grown = capacity.grown_to(reserved, columns.saturating_mul(rows));
        if grown == capacity {
            return Ok(false);
        }
        self.buffers = BinBuffers::new(gpu, grown)?;
        Ok(true)
    }
}
