//! Occlusion culling of the meshlet draw's compute path, two passes per frame and temporal, as
//! Nanite culls clusters:
//! 1. **Pass 1** draws the meshlets in view that owned a pixel last frame (their flags say so)
//!    and marks them drawn.
//! 2. A **max-depth pyramid** of pass 1's frame is built ([`crate::raster::hzb`]).
//! 3. **Pass 2** draws the meshlets in view that pass 1 did not draw and whose box the pyramid
//!    does not hide, into a second triangle list rasterized into the same frame with index
//!    base = the first list's capacity.
//! 4. The **resolve** (`direct`'s, with two lists) shades the frame and flags the meshlet of
//!    every drawn pixel's triangle as owning a pixel: next frame's pass 1.
//!
//! Everything pass 1 drew lies in the final image and the test is conservative, so the image
//! equals the unculled draw's (up to triangles tying in depth, which the rasterizer breaks by
//! index). The first frame, or one after [`MeshletOcclusion::forget`] (a new surface), draws
//! everything in view in pass 2 and skips pass 1 and the pyramid (a pyramid at the far plane
//! stands in). The flags are indexed by meshlet, so they mean nothing once
//! the meshlets are extracted or uploaded anew: forget then.

use super::{DrawCounters, MeshletDraw, MeshletDrawParams, COUNTER_BYTES, READ_SLOTS};
use crate::builtin_shader;
use crate::config::meshlet_draw_defines;
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, TriangleLists};
use crate::iso::direct::resolve::SurfaceResolve;
use crate::iso::meshlets::GpuMeshlets;
use crate::raster::hzb::{hzb_bytes, HzbBuilder};
use crate::target::Target;
use std::cell::Cell;
use tessera_gpu::{
    spread_groups, vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler,
    Slot,
};

/// The pipelines occlusion culling adds to the compute path.
pub(super) struct OcclusionPasses {
    first: Pipeline,
    second: Pipeline,
    resolve: SurfaceResolve,
    hzb: HzbBuilder,
}

impl OcclusionPasses {
    pub(super) fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<OcclusionPasses> {
        let with = |name: &str, value: &str| {
            let mut d = meshlet_draw_defines();
            d.push((name.into(), value.into()));
            d
        };
        let sb = Slot::StorageBuffer;
        let pass = |n: &str| -> Result<Pipeline> {
            let spirv = compiler.compile(
                &builtin_shader!("triangles.comp.glsl"),
                &with("OCCLUSION_PASS", n),
            )?;
            let slots = [sb; READ_SLOTS + 5];
            let used = if n == "1" {
                READ_SLOTS + 4
            } else {
                READ_SLOTS + 5
            };
            Ok(gpu.compute_pipeline(
                &format!("meshlet triangles (occlusion pass {n})"),
                &spirv,
                &slots[..used],
            )?)
        };
        let defines = meshlet_draw_defines();
        let name = "meshlet resolve (two lists)";
        Ok(OcclusionPasses {
            first: pass("1")?,
            second: pass("2")?,
            resolve: SurfaceResolve::new(gpu, compiler, &defines, true, name)?,
            hzb: HzbBuilder::new(gpu, compiler)?,
        })
    }
}

/// What each pass of the last culled frame drew.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OcclusionCounters {
    /// Pass 1: meshlets that owned a pixel last frame.
    pub first: DrawCounters,
    /// Pass 2: meshlets the pyramid did not hide.
    pub second: DrawCounters,
}

impl OcclusionCounters {
    pub fn total(&self) -> DrawCounters {
        DrawCounters {
            meshlets_drawn: self.first.meshlets_drawn + self.second.meshlets_drawn,
            triangles_drawn: self.first.triangles_drawn + self.second.triangles_drawn,
        }
    }
}

/// Culling state carried from frame to frame for one set of meshlet buffers and one frame
/// size: per-meshlet flags, the pyramid, pass 2's triangle list and counters.
pub struct MeshletOcclusion {
    /// Per meshlet: bit 0 owned a pixel last frame, bit 1 drawn in this frame's pass 1.
    flags: Buffer,
    hzb: Buffer,
    /// Pass 2's triangles.
    pub second: TriangleLists,
    second_counters: Buffer,
    meshlet_capacity: u32,
    width: u32,
    height: u32,
    /// Whether the next frame must clear the flags first.
    forget_pending: Cell<bool>,
}

impl MeshletOcclusion {
    /// State for up to `meshlet_capacity` meshlets drawn through `target`; pass 2's list gets
    /// the target's capacity (the first frame draws everything in view there).
    pub fn new(gpu: &Gpu, meshlet_capacity: u32, target: &ComputeTarget) -> Result<Self> {
        let (width, height) = (target.frame.width, target.frame.height);
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = |name: &str, bytes: u64| {
            gpu.create_buffer(name, bytes.max(4), usage, MemoryLocation::GpuOnly)
        };
        Ok(MeshletOcclusion {
            flags: buffer("meshlet flags", 4 * u64::from(meshlet_capacity))?,
            hzb: buffer("meshlet hzb", hzb_bytes(width, height))?,
            second: TriangleLists::new(gpu, target.lists.capacity)?,
            second_counters: buffer(
                "meshlet draw counters (pass 2)",
                std::mem::size_of::<DrawCounters>() as u64,
            )?,
            meshlet_capacity,
            width,
            height,
            forget_pending: Cell::new(true),
        })
    }

    /// Whether this state serves `meshlets` drawn through `target`.
    pub fn fits(&self, meshlets: &GpuMeshlets, target: &ComputeTarget) -> bool {
        self.meshlet_capacity >= meshlets.capacity.meshlets
            && (self.width, self.height) == (target.frame.width, target.frame.height)
            && self.second.capacity == target.lists.capacity
    }

    /// Forgets what earlier frames saw: the next frame draws nothing in pass 1.
    pub fn forget(&self) {
        self.forget_pending.set(true);
    }

    /// What the last recorded frame's passes drew (read after it was submitted; `draw` copied
    /// both to the host at the frame's end).
    pub fn read_counters(&self, draw: &MeshletDraw) -> OcclusionCounters {
        OcclusionCounters {
            first: draw.counters_at(0),
            second: draw.counters_at(COUNTER_BYTES),
        }
    }
}

impl MeshletDraw {
    /// Records the compute path's draw of `meshlets` with occlusion culling (module docs):
    /// pass 1 into `target`'s list, pass 2 into `occlusion`'s, both into `target`'s frame,
    /// shaded into `pixels`. `params.triangle_capacity` must be the lists' capacity; both
    /// counters keep counting past it, so the host sees an overflow.
    pub fn record_compute_culled(
        &self,
        rec: &Recorder,
        meshlets: &GpuMeshlets,
        target: &ComputeTarget,
        pixels: &Target,
        params: &MeshletDrawParams,
        occlusion: &MeshletOcclusion,
    ) -> Result<()> {
        let passes = self.compute_passes()?;
        let Some(culling) = &passes.occlusion else {
            return Err(Error::Invalid(
                "meshlet draw: built without occlusion culling".into(),
            ));
        };
        let frame = &target.frame;
        let size = (frame.width, frame.height);
        if size != (pixels.width, pixels.height)
            || size != (params.frame_width, params.frame_height)
            || !occlusion.fits(meshlets, target)
        {
            return Err(Error::Invalid(format!(
                "meshlet draw: a {}x{} frame with a {}x{} image, parameters for {}x{} and \
                 culling state for {}x{}",
                size.0,
                size.1,
                pixels.width,
                pixels.height,
                params.frame_width,
                params.frame_height,
                occlusion.width,
                occlusion.height
            )));
        }
        let base = target.lists.capacity;
        if base.checked_add(occlusion.second.capacity).is_none() {
            return Err(Error::Invalid(
                "meshlet draw: two triangle lists beyond 2^32 triangles".into(),
            ));
        }
        let (first, second) = (&target.lists, &occlusion.second);
        // Nothing seen yet: pass 1 would draw nothing, so it and the pyramid of its empty
        // frame are skipped; a pyramid of the far plane hides nothing from pass 2.
        let forgetting = occlusion.forget_pending.replace(false);
        if forgetting {
            rec.fill_buffer(&occlusion.flags, 0);
            rec.fill_buffer(&occlusion.hzb, 1.0f32.to_bits());
        }
        for buffer in [
            &self.counters,
            &occlusion.second_counters,
            &first.counts,
            &second.counts,
        ] {
            rec.fill_buffer(buffer, 0);
        }
        rec.barrier();
        let groups = spread_groups(meshlets.capacity.meshlets, self.max_groups_x);
        let pass = |pipeline: &Pipeline, lists: &TriangleLists, counters: &Buffer, hzb: bool| {
            let mut bindings: Vec<Binding> = self.read_bindings(meshlets).into();
            bindings[READ_SLOTS - 1] = Binding::Buffer(counters);
            bindings.extend([
                Binding::Buffer(&lists.triangles),
                Binding::Buffer(&lists.attributes),
                Binding::Buffer(&lists.counts),
                Binding::Buffer(&occlusion.flags),
            ]);
            if hzb {
                bindings.push(Binding::Buffer(&occlusion.hzb));
            }
            rec.dispatch_groups(pipeline, &bindings, bytemuck::bytes_of(params), groups);
            rec.barrier();
        };
        let rasterizer = passes.list.rasterizer();
        frame.record_begin(rec);
        rec.barrier();
        if !forgetting {
            pass(&culling.first, first, &self.counters, false);
            rasterizer.record_raster(rec, &first.triangles, &first.counts, frame);
            culling.hzb.record(rec, frame, &occlusion.hzb);
        }
        pass(&culling.second, second, &occlusion.second_counters, true);
        rasterizer.record_raster_with_base(rec, &second.triangles, &second.counts, frame, base);
        culling.resolve.record_two(
            rec,
            frame,
            (first.shaded(), second.shaded()),
            base,
            &occlusion.flags,
            pixels,
            params.lighting(),
        );
        rec.barrier();
        self.readback.record_copies(
            rec,
            &[
                (&self.counters, 0, COUNTER_BYTES),
                (&occlusion.second_counters, COUNTER_BYTES, COUNTER_BYTES),
            ],
        );
        Ok(())
    }
}
