//! The pass that shades a compute-rasterized surface frame (`resolve.comp.glsl`): `direct`'s
//! compute path and the stored meshlet and PMB draws all shade their frames with it, from one
//! triangle list or, with occlusion culling, from two drawn into one frame. It reads only the
//! tiles the frame's raster passes marked and empties the pixels it reads, so the frame's
//! next [`RasterFrame::record_begin`] fills nothing.

use crate::builtin_shader;
use crate::error::Result;
use crate::raster::{resolve_groups, RasterFrame};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::GridFrame;
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// Push constants of `resolve.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ResolveParams {
    pub clip_to_world: [[f32; 4]; 4],
    pub eye_world: [f32; 4],
    pub light: [f32; 4],
    pub size: [u32; 2],
    /// The first index of the second list (two lists).
    pub second_base: u32,
    /// [`RasterFrame::frame_number`].
    pub frame_number: u32,
    /// 1: empty each drawn pixel read; 0: leave it ([`RasterFrame::keep_after_resolve`]).
    pub empties: u32,
    /// What a resolve that lists the blocks seen writes into their flags (the frame's number).
    pub seen_number: u32,
}

/// A triangle list as the resolve reads it: the rasterizer's triangles (for the
/// barycentrics) and their shading attributes.
#[derive(Clone, Copy)]
pub struct ShadedList<'a> {
    pub triangles: &'a Buffer,
    pub attributes: &'a Buffer,
}

/// How a frame's pixels are lit: from `eye` (world space), with `light` the direction towards
/// the light; `clip_to_world` takes the rasterizer's clip space to the world positions shaded
/// ([`clip_to_world`]).
#[derive(Clone, Copy, Debug)]
pub struct Lighting {
    pub eye: [f32; 3],
    pub light: [f32; 3],
    pub clip_to_world: [[f32; 4]; 4],
}

/// The map from clip space to world space of a surface whose grid points (sample-index units)
/// reach clip space through `grid_to_clip` and world space as `common/grid_world.glsl` places
/// them: centred at the origin, `grid_to_world` world units per grid unit
/// ([`GridFrame::grid_to_world_matrix`]). Inverted in f64.
pub fn clip_to_world(
    grid_to_clip: &[[f32; 4]; 4],
    grid_to_world: [f32; 3],
    dims: [u32; 3],
) -> [[f32; 4]; 4] {
    let frame = GridFrame {
        dims,
        grid_to_world: grid_to_world.into(),
    };
    let grid_to_clip = glam::Mat4::from_cols_array_2d(grid_to_clip).as_dmat4();
    (frame.grid_to_world_matrix().as_dmat4() * grid_to_clip.inverse())
        .as_mat4()
        .to_cols_array_2d()
}

/// The bindings of a two-list resolve, in its slots' order.
fn two_list_bindings<'a>(
    frame: &'a RasterFrame,
    (first, second): (ShadedList<'a>, ShadedList<'a>),
    block_flags: &'a Buffer,
    pixels: &'a Target,
) -> [Binding<'a>; 8] {
    [
        Binding::Buffer(&frame.depth_payload),
        Binding::Buffer(first.triangles),
        Binding::Buffer(first.attributes),
        Binding::Buffer(&pixels.pixels),
        Binding::Buffer(second.triangles),
        Binding::Buffer(second.attributes),
        Binding::Buffer(block_flags),
        Binding::Buffer(&frame.tile_frames),
    ]
}

/// The resolve pipeline for one list, or for two (`TWO_LISTS`: the second list's indices
/// start at a base, and each drawn pixel flags its triangle's block as seen), optionally
/// listing the blocks seen (`SEEN_BLOCK_LIST`).
pub struct SurfaceResolve {
    pipeline: Pipeline,
    two_lists: bool,
    lists_seen: bool,
}

impl SurfaceResolve {
    /// The pass compiled with `defines` (plus `TWO_LISTS` when `two_lists`), its pipeline
    /// named `name`.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        two_lists: bool,
        name: &str,
    ) -> Result<SurfaceResolve> {
        Self::build(gpu, compiler, defines, (two_lists, false), name)
    }

    /// The two-list pass that also lists each block seen for the first time this frame
    /// ([`Self::record_two_listing_seen`]).
    pub fn new_listing_seen(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        name: &str,
    ) -> Result<SurfaceResolve> {
        Self::build(gpu, compiler, defines, (true, true), name)
    }

    fn build(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        (two_lists, lists_seen): (bool, bool),
        name: &str,
    ) -> Result<SurfaceResolve> {
        let mut defines = defines.to_vec();
        if two_lists {
            defines.push(("TWO_LISTS".into(), "1".into()));
        }
        if lists_seen {
            defines.push(("SEEN_BLOCK_LIST".into(), "1".into()));
        }
        let spirv = compiler.compile(&builtin_shader!("resolve.comp.glsl"), &defines)?;
        let slots = match (two_lists, lists_seen) {
            (false, _) => 5,
            (true, false) => 8,
            (true, true) => 9,
        };
        let pipeline = gpu.compute_pipeline(name, &spirv, &[Slot::StorageBuffer; 9][..slots])?;
        Ok(SurfaceResolve {
            pipeline,
            two_lists,
            lists_seen,
        })
    }

    /// Records the shading of `frame`, drawn from `list`, into `pixels`, emptying the frame (no
    /// barrier after it).
    /// The pipeline must be a one-list one.
    pub fn record(
        &self,
        rec: &Recorder,
        frame: &RasterFrame,
        list: ShadedList,
        pixels: &Target,
        lighting: Lighting,
    ) {
        debug_assert!(!self.two_lists, "a two-list resolve given one list");
        let bindings = [
            Binding::Buffer(&frame.depth_payload),
            Binding::Buffer(list.triangles),
            Binding::Buffer(list.attributes),
            Binding::Buffer(&pixels.pixels),
            Binding::Buffer(&frame.tile_frames),
        ];
        self.dispatch(rec, frame, &bindings, lighting, (0, 0));
    }

    /// Records the shading of `frame`, drawn from `first` and from `second` with its indices
    /// from `second_base`, into `pixels`, flagging in `block_flags` each block whose triangle
    /// owns a pixel and emptying the frame (no barrier after it). The pipeline must be a two-list one.
    #[allow(clippy::too_many_arguments)]
    pub fn record_two(
        &self,
        rec: &Recorder,
        frame: &RasterFrame,
        (first, second): (ShadedList, ShadedList),
        second_base: u32,
        block_flags: &Buffer,
        pixels: &Target,
        lighting: Lighting,
    ) {
        debug_assert!(
            self.two_lists && !self.lists_seen,
            "a two-list resolve that flags blocks wanted"
        );
        let bindings = two_list_bindings(frame, (first, second), block_flags, pixels);
        self.dispatch(rec, frame, &bindings, lighting, (second_base, 0));
    }

    /// As [`Self::record_two`], but each block whose triangle owns a pixel gets `seen_number`
    /// in `block_flags`, and the first pixel to give it that number appends the block to
    /// `next_list` (a block list, `block_list.glsl`; its dispatch arguments are left to a pass
    /// after this one). The pipeline must be [`Self::new_listing_seen`]'s.
    #[allow(clippy::too_many_arguments)]
    pub fn record_two_listing_seen(
        &self,
        rec: &Recorder,
        frame: &RasterFrame,
        (first, second): (ShadedList, ShadedList),
        second_base: u32,
        (block_flags, seen_number, next_list): (&Buffer, u32, &Buffer),
        pixels: &Target,
        lighting: Lighting,
    ) {
        debug_assert!(self.lists_seen, "a resolve that lists no blocks");
        let mut bindings = two_list_bindings(frame, (first, second), block_flags, pixels).to_vec();
        bindings.push(Binding::Buffer(next_list));
        self.dispatch(rec, frame, &bindings, lighting, (second_base, seen_number));
    }

    fn dispatch(
        &self,
        rec: &Recorder,
        frame: &RasterFrame,
        bindings: &[Binding],
        lighting: Lighting,
        (second_base, seen_number): (u32, u32),
    ) {
        let (e, l) = (lighting.eye, lighting.light);
        let params = ResolveParams {
            clip_to_world: lighting.clip_to_world,
            eye_world: [e[0], e[1], e[2], 0.0],
            light: [l[0], l[1], l[2], 0.0],
            size: [frame.width, frame.height],
            second_base,
            frame_number: frame.frame_number(),
            empties: u32::from(frame.emptied_by_resolve()),
            seen_number,
        };
        rec.dispatch_groups(
            &self.pipeline,
            bindings,
            bytemuck::bytes_of(&params),
            resolve_groups(frame.width, frame.height, self.pipeline.local_size[0]),
        );
        if frame.emptied_by_resolve() {
            frame.note_emptied();
        }
    }
}
