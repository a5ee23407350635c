//! Recording of a culled compute-path frame (see `compute_cull` for the method).

use crate::error::{Error, Result};
use crate::iso::direct::block_list::{self, BlockListHeader};
use crate::iso::direct::compute::{
    extraction_bindings, frame_bindings, ComputeTarget, DirectCompute, DirectRaster, TriangleLists,
};
use crate::iso::direct::compute_cull::{
    groups_2d, ComputeCullState, ComputeCullStats, HzbTestParams,
};
use crate::iso::direct::{Direct, DirectParams};
use crate::iso::PreparedVolume;
use crate::raster::hzb::hzb_levels;
use crate::raster::RasterFrame;
use crate::target::Target;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, Timer};

impl DirectCompute {
    /// Records a culled frame into `target` and `pixels` with `state` (made for this target and
    /// volume); `params.triangle_capacity` must be `target.lists.capacity`. With a `timer`, its stages
    /// are timed in four scopes: `cull-pass-a`, `cull-test`, `cull-pass-b`, `cull-resolve`.
    /// See the module's description.
    #[allow(clippy::too_many_arguments)]
    pub fn record_culled(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
        pixels: &Target,
        params: &DirectParams,
        state: &ComputeCullState,
        mut timer: Option<&mut Timer>,
    ) -> Result<()> {
        let mut stage = |name: &str, body: &dyn Fn(&Recorder)| match timer.as_deref_mut() {
            Some(t) => t.scope(rec, name, body),
            None => body(rec),
        };
        super::compute::check_pixels(target, pixels)?;
        check_state(state, prepared, target)?;
        let (w, h) = (target.frame.width, target.frame.height);
        let base = target.lists.capacity;
        if base.checked_add(state.new_lists.capacity).is_none() {
            return Err(Error::Invalid(
                "two triangle lists beyond 2^32 triangles".into(),
            ));
        }
        let c = &self.cull;
        let (first, next) = (state.first(), state.next());
        // Where the extraction draws its triangles itself, no raster pass follows it.
        let drawing = c.raster == DirectRaster::InExtraction;
        // Pass B's extraction (`pass_b`) tests its cells against the pyramid.
        let extract = |rec: &Recorder, pass_b: bool, stats: &Buffer, blocks: &Buffer| {
            let pipeline = if pass_b {
                &c.extract_new
            } else {
                &c.extract_list
            };
            let lists = if pass_b {
                &state.new_lists
            } else {
                &target.lists
            };
            let frame = (drawing || pass_b).then_some(&target.frame);
            let hzb = pass_b.then_some(&state.hzb);
            record_list_extraction(
                rec,
                pipeline,
                prepared,
                (lists, stats),
                (blocks, state),
                (frame, hzb),
                params,
            );
            rec.barrier();
        };

        // Pass A: last frame's visible blocks (their list written by last frame's resolve, its
        // dispatch arguments by its finishing pass). Every list and count this frame fills starts
        // empty: the passes that fill them grow their own dispatch arguments. Last frame's
        // finishing pass emptied them where it was this state's frame into this target (no
        // other frame begun in it since); otherwise they are emptied here.
        let (a, b_lists) = (&target.lists, &state.new_lists);
        let per_block =
            |p: &Pipeline| groups_2d(state.block_count, p.local_size[0], c.max_groups_x);
        let emptied = state.emptied_after.get() == Some(target.frame.frame_stamp());
        stage("cull-pass-a", &|rec| {
            let mut recorded = false;
            if !emptied {
                for list in [&state.new_blocks, next] {
                    rec.update_buffer(list, bytemuck::bytes_of(&BlockListHeader::EMPTY));
                }
                for buffer in [&a.counts, &b_lists.counts, &state.stats] {
                    rec.fill_buffer(buffer, 0);
                }
                state
                    .extract_stats
                    .iter()
                    .for_each(|s| rec.fill_buffer(s, 0));
                recorded = true;
            }
            recorded |= target.frame.record_begin(rec);
            target
                .frame
                .hide_winding(Direct::hidden_winding(prepared, params));
            // Pass B's extraction reads the frame's size from its pass parameters, which stay
            // as written until the state meets another target; a drawing extraction also
            // reads the frame's number, new every frame.
            let frame = &target.frame;
            if drawing {
                frame.record_pass_params(rec, &a.raster_pass, a.capacity, 0);
            }
            if drawing || !emptied {
                frame.record_pass_params(rec, &b_lists.raster_pass, b_lists.capacity, base);
                recorded = true;
            }
            // Boxes made from another volume (the same block grid says nothing about this one).
            recorded |= state.cell_boxes.record_keep_for(rec, prepared);
            if recorded {
                rec.barrier();
            }
            extract(rec, false, &state.extract_stats[0], first);
            if !drawing {
                self.rasterizer
                    .record_raster(rec, &a.triangles, &a.counts, &target.frame);
            }
        });
        // The pyramid and the occlusion test.
        stage("cull-test", &|rec| {
            c.hzb.record(rec, &target.frame, &state.hzb);
            let test = HzbTestParams {
                grid_to_clip: params.grid_to_clip,
                dims: [
                    params.dims[0],
                    params.dims[1],
                    params.dims[2],
                    hzb_levels(w, h).len() as u32,
                ],
                size: [w, h, 0, 0],
                iso: [params.isovalue, 0.0, 0.0, 0.0],
                first_pass_number: state.first_pass_number(),
                pad: [0; 3],
            };
            rec.dispatch_groups(
                &c.test,
                &[
                    Binding::Buffer(&prepared.octree.nodes),
                    Binding::Buffer(&state.flags),
                    Binding::Buffer(&state.hzb),
                    Binding::Buffer(&state.new_blocks),
                    Binding::Buffer(&state.stats),
                    Binding::Buffer(&state.cell_boxes.buffer),
                ],
                bytemuck::bytes_of(&test),
                per_block(&c.test),
            );
            rec.barrier();
        });
        // Pass B: blocks that may have come into view, into the same frame.
        stage("cull-pass-b", &|rec| {
            extract(rec, true, &state.extract_stats[1], &state.new_blocks);
            if !drawing {
                self.rasterizer.record_raster_with_base(
                    rec,
                    &b_lists.triangles,
                    &b_lists.counts,
                    &target.frame,
                    base,
                );
            }
        });
        // Shade, list the blocks that own pixels for next frame, and write the frame's counts
        // to the host: inside the last scope, so that a frame timed pass by pass spans all its
        // work.
        stage("cull-resolve", &|rec| {
            c.resolve.record_two_listing_seen(
                rec,
                &target.frame,
                (a.shaded(), b_lists.shaded()),
                base,
                (&state.flags, state.seen_number(), next),
                pixels,
                params.lighting(),
            );
            rec.barrier();
            rec.dispatch_groups(
                &c.finish,
                &[
                    Binding::Buffer(next),
                    Binding::Buffer(&state.stats),
                    Binding::Buffer(first),
                    Binding::Buffer(&state.extract_stats[0]),
                    Binding::Buffer(&state.extract_stats[1]),
                    Binding::Buffer(state.readback.storage()),
                    Binding::Buffer(&a.counts),
                    Binding::Buffer(&b_lists.counts),
                    Binding::Buffer(&state.new_blocks),
                ],
                &[],
                [1, 1, 1],
            );
            rec.barrier();
        });
        state.frame.set(state.frame.get() + 1);
        state.emptied_after.set(Some(target.frame.frame_stamp()));
        Ok(())
    }

    /// Records pass A's extraction alone with `pipeline` (the culling's own, or
    /// [`super::compute_cull::measured_list_extraction`]) over the blocks `state`'s next frame
    /// would draw first, into `target`'s lists, timed in a scope `name`: its counts emptied
    /// before the scope, a barrier after it. For measuring: nothing is drawn or resolved, and
    /// the state is left as it was but for its cell boxes. `state` must be made for `prepared`
    /// and `target`'s size.
    #[allow(clippy::too_many_arguments)]
    pub fn record_first_extraction(
        &self,
        rec: &Recorder,
        (timer, name): (&mut Timer, &str),
        pipeline: &Pipeline,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
        params: &DirectParams,
        state: &ComputeCullState,
    ) -> Result<()> {
        check_state(state, prepared, target)?;
        let stats = &state.extract_stats[0];
        rec.fill_buffer(&target.lists.counts, 0);
        rec.fill_buffer(stats, 0);
        rec.barrier();
        timer.scope(rec, name, |rec| {
            record_list_extraction(
                rec,
                pipeline,
                prepared,
                (&target.lists, stats),
                (state.first(), state),
                (None, None),
                params,
            )
        });
        rec.barrier();
        // The next frame's fills are due: this wrote the counts its finishing pass emptied.
        state.emptied_after.set(None);
        Ok(())
    }

    /// Renders one culled frame: the image, the GPU time in milliseconds and what culling did.
    #[allow(clippy::too_many_arguments)]
    pub fn render_culled(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
        pixels: &Target,
        state: &ComputeCullState,
        iso: f32,
        camera: &OrbitCamera,
    ) -> Result<(RgbaImage, f64, ComputeCullStats)> {
        let (w, h) = (target.frame.width, target.frame.height);
        let params = Direct::params(prepared, iso, camera, w, h, target.lists.capacity);
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        let mut recorded = Ok(());
        let submitted = gpu.submit("direct (compute path, culled)", |rec| {
            recorded = timer.scope(rec, "direct-compute-culled", |rec| {
                self.record_culled(rec, prepared, target, pixels, &params, state, None)
            });
        });
        let ms = submitted
            .map_err(Error::from)
            .and(recorded)
            .and_then(|_| Ok(timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0)))?;
        let stats = state.read_stats();
        for (made, capacity) in [
            (stats.triangles_first, target.lists.capacity),
            (stats.triangles_new, state.new_lists.capacity),
        ] {
            if made > capacity {
                return Err(Error::Invalid(format!(
                    "a culling pass made {made} triangles, its list holds {capacity}: raise the capacity"
                )));
            }
        }
        Ok((pixels.read(gpu)?, ms, stats))
    }
}

/// Records one workgroup per listed block of `blocks` extracting into `lists` with `pipeline`
/// (one of the culling's list extractions), counting into `stats`; a drawing or pass-B
/// extraction also binds `frame` (and the lists' raster parameters), pass B the pyramid `hzb`.
pub(super) fn record_list_extraction(
    rec: &Recorder,
    pipeline: &Pipeline,
    prepared: &PreparedVolume,
    (lists, stats): (&TriangleLists, &Buffer),
    (blocks, state): (&Buffer, &ComputeCullState),
    (frame, hzb): (Option<&RasterFrame>, Option<&Buffer>),
    params: &DirectParams,
) {
    let mut p = *params;
    p.triangle_capacity = lists.capacity;
    let mut bindings = extraction_bindings(prepared, lists, stats);
    bindings.extend([
        Binding::Buffer(blocks),
        Binding::Buffer(&state.cell_boxes.buffer),
    ]);
    if let Some(frame) = frame {
        bindings.extend(frame_bindings(frame, lists));
    }
    if let Some(hzb) = hzb {
        bindings.push(Binding::Buffer(hzb));
    }
    rec.dispatch_indirect(
        pipeline,
        &bindings,
        bytemuck::bytes_of(&p),
        blocks,
        block_list::ARGS_OFFSET,
    );
}

/// Refuses a culling state made for another frame size or volume than `target`'s and
/// `prepared`'s (its flags, lists and pyramid would be read out of their bounds).
fn check_state(
    state: &ComputeCullState,
    prepared: &PreparedVolume,
    target: &ComputeTarget,
) -> Result<()> {
    let b = prepared.octree.level_dims[0];
    let (w, h) = (target.frame.width, target.frame.height);
    if (w, h) != (state.width, state.height) || b[0] * b[1] * b[2] != state.block_count {
        return Err(Error::Invalid(
            "the culling state was made for another frame size or volume".into(),
        ));
    }
    Ok(())
}
