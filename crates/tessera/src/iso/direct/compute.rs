//! The compute path of `direct`: the same block classification and marching cubes as the
//! task/mesh pipeline, in compute, feeding the shared compute rasterizer. Chosen where the
//! graphics stages are slow (DESIGN §3: on an H200 a fragment shader runs 33× slower than the
//! same compute shader).

use crate::builtin_shader;
use crate::config::{marching_cubes_defines, volume_defines};
use crate::error::{Error, Result};
use crate::iso::direct::compute_cull::ComputeCullPipelines;
use crate::iso::direct::resolve::{ShadedList, SurfaceResolve};
use crate::iso::direct::{Direct, DirectParams};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::PreparedVolume;
use crate::raster::{
    raster_defines, ComputeRasterizer, RasterFrame, RasterVariant, RASTER_PASS_PARAMS_BYTES,
    TRIANGLE_BYTES,
};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::{OrbitCamera, RgbaImage, ScalarType};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot, Timer,
};

/// One corner of a list triangle's shading attributes (`iso/direct/attributes.glsl`): its world
/// normal and the id of the block or meshlet that made the triangle (the same in all three).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct CornerAttributes {
    pub normal_world: [f32; 3],
    pub maker: u32,
}

/// A list triangle's shading attributes. Positions come from the clip-space corners.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleAttributes {
    pub corners: [CornerAttributes; 3],
}

/// Bytes per triangle of shading attributes.
pub const ATTRIBUTE_BYTES: u64 = std::mem::size_of::<TriangleAttributes>() as u64;

/// Where the compute path's triangles are drawn into the frame: by the rasterizer's pass after
/// the extraction (one invocation a triangle), or by the extraction's workgroup that made them,
/// with no pass, barrier or list read between. The frames are the same; which is faster is
/// measured (`tessera bench isosurface --variants raster-in-extraction`): the pass stays the
/// default, faster at 4K on the 256³ head, the extraction only on larger volumes (timed with
/// 32 invocations per block, docs/BENCHMARKS.md runs 119–120).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum DirectRaster {
    #[default]
    Pass,
    InExtraction,
}

/// The generated triangles of a frame, sized for `capacity` triangles.
pub struct TriangleLists {
    pub triangles: Buffer,
    pub attributes: Buffer,
    /// `triangle_count` then the rasterizer's indirect dispatch arguments.
    pub counts: Buffer,
    pub capacity: u32,
    /// How an extraction that draws the list's triangles draws them
    /// ([`RasterFrame::record_pass_params`]).
    pub raster_pass: Buffer,
}

impl TriangleLists {
    /// The triangles and attributes, as the resolve reads them.
    pub fn shaded(&self) -> ShadedList<'_> {
        ShadedList {
            triangles: &self.triangles,
            attributes: &self.attributes,
        }
    }

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
        let raster_pass = gpu.create_buffer(
            "direct raster pass",
            RASTER_PASS_PARAMS_BYTES,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(TriangleLists {
            triangles,
            attributes,
            counts,
            capacity,
            raster_pass,
        })
    }

    /// The capacity that fits a share of the device's memory and its largest storage buffer
    /// (the triangles are the larger list), for frames of unknown size; no list holds more.
    pub fn default_capacity(gpu: &Gpu) -> u32 {
        let caps = gpu.caps();
        let budget = caps.device_local_bytes / 8;
        (budget / (TRIANGLE_BYTES + ATTRIBUTE_BYTES))
            .min(caps.max_storage_buffer_range / TRIANGLE_BYTES.max(ATTRIBUTE_BYTES))
            .min(64 << 20) as u32
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

/// The bindings of the extraction over the block grid.
const EXTRACT_SLOTS: [Slot; 6] = [
    Slot::Texture,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
    Slot::StorageBuffer,
];

pub struct DirectExtract {
    extract: Pipeline,
    stats: Buffer,
}

impl DirectExtract {
    /// Extraction with ambiguous faces cut by the asymptotic decider.
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<DirectExtract> {
        Self::with_rule(gpu, compiler, scalar, AmbiguityRule::default())
    }

    /// Extraction with ambiguous faces cut by `rule`.
    pub fn with_rule(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
    ) -> Result<DirectExtract> {
        let spirv = compiler.compile(
            &builtin_shader!("extract.comp.glsl"),
            &extract_defines(scalar, rule, gpu.caps().subgroup_arithmetic),
        )?;
        let extract = gpu.compute_pipeline("direct extract", &spirv, &EXTRACT_SLOTS)?;
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
    /// `params.triangle_capacity` must be the lists' capacity.
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        lists: &TriangleLists,
        params: &DirectParams,
    ) {
        self.record_with(rec, &self.extract, prepared, lists, None, params);
    }

    /// Records the extraction with `pipeline`: this one, or one made by
    /// [`drawing_extraction`] that also draws the triangles into `frame`.
    fn record_with(
        &self,
        rec: &Recorder,
        pipeline: &Pipeline,
        prepared: &PreparedVolume,
        lists: &TriangleLists,
        frame: Option<&RasterFrame>,
        params: &DirectParams,
    ) {
        rec.fill_buffer(&self.stats, 0);
        rec.fill_buffer(&lists.counts, 0);
        if let Some(frame) = frame {
            frame.record_pass_params(rec, &lists.raster_pass, lists.capacity, 0);
        }
        rec.barrier();
        let mut bindings = extraction_bindings(prepared, lists, &self.stats);
        if let Some(frame) = frame {
            bindings.extend(frame_bindings(frame, lists));
        }
        rec.dispatch_groups(
            pipeline,
            &bindings,
            bytemuck::bytes_of(params),
            prepared.octree.level_dims[0],
        );
    }

    pub fn read_stats(&self, gpu: &Gpu) -> Result<ExtractStats> {
        let s: Vec<u32> = gpu.read_buffer_as(&self.stats)?;
        Ok(ExtractStats {
            triangles: s[0],
            blocks_classified: s[1],
        })
    }
}

/// The bindings every `extract.comp.glsl` pipeline begins with: the volume, its octree's
/// nodes, the lists' triangles, attributes and counts, and the extraction's statistics.
pub(crate) fn extraction_bindings<'a>(
    prepared: &'a PreparedVolume,
    lists: &'a TriangleLists,
    stats: &'a Buffer,
) -> Vec<Binding<'a>> {
    vec![
        Binding::Texture {
            image: &prepared.volume.texture,
            linear: false,
        },
        Binding::Buffer(&prepared.octree.nodes),
        Binding::Buffer(&lists.triangles),
        Binding::Buffer(&lists.attributes),
        Binding::Buffer(&lists.counts),
        Binding::Buffer(stats),
    ]
}

/// Defines of `extract.comp.glsl`: marching cubes', the raster pass's, whose dispatch
/// arguments it writes, and whether its prefix sums use subgroup arithmetic (`subgroup_scan`,
/// where the device has it for compute shaders: two barriers instead of the shared-memory
/// scan's sixteen, as the meshlet and PMB extractions do).
pub(crate) fn extract_defines(
    scalar: ScalarType,
    rule: AmbiguityRule,
    subgroup_scan: bool,
) -> Vec<(String, String)> {
    let mut defines = [marching_cubes_defines(scalar, rule), raster_defines()].concat();
    // A preprocessor condition: a plain 0 or 1.
    defines.push((
        "DIRECT_SUBGROUP_SCAN".into(),
        u32::from(subgroup_scan).to_string(),
    ));
    defines
}

/// `extract.comp.glsl` with the given defines (`extract_defines`, and the culling's), also
/// drawing its triangles into a frame: [`frame_bindings`] follow the extraction's own.
pub(crate) fn drawing_extraction(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    defines: &[(String, String)],
    slots: &[Slot],
    name: &str,
    variant: RasterVariant,
) -> Result<Pipeline> {
    let mut defines = defines.to_vec();
    defines.push(("RASTER_IN_EXTRACTION".into(), "1".into()));
    defines.extend(variant.defines());
    let spirv = compiler.compile(&builtin_shader!("extract.comp.glsl"), &defines)?;
    let slots = [slots, &[Slot::StorageBuffer; 3]].concat();
    Ok(gpu.compute_pipeline(name, &spirv, &slots)?)
}

/// What an extraction that draws its triangles binds after its own bindings: the frame, its
/// tiles, and how it draws `lists` ([`RasterFrame::record_pass_params`]).
pub(crate) fn frame_bindings<'a>(
    frame: &'a RasterFrame,
    lists: &'a TriangleLists,
) -> [Binding<'a>; 3] {
    [
        Binding::Buffer(&frame.depth_payload),
        Binding::Buffer(&frame.tile_frames),
        Binding::Buffer(&lists.raster_pass),
    ]
}

/// What a compute-path frame writes besides its pixels (which go to a [`Target`] of the
/// caller's): the triangle lists and the rasterizer's depth|index frame.
pub struct ComputeTarget {
    pub lists: TriangleLists,
    pub frame: RasterFrame,
}

impl ComputeTarget {
    /// `capacity` triangles per frame; see [`TriangleLists::default_capacity`].
    pub fn new(gpu: &Gpu, width: u32, height: u32, capacity: u32) -> Result<ComputeTarget> {
        let lists = TriangleLists::new(gpu, capacity)?;
        let frame = RasterFrame::new(gpu, width, height)?;
        Ok(ComputeTarget { lists, frame })
    }
}

/// Refuses an image of another size than the frame's (the resolve would write past it).
pub(super) fn check_pixels(target: &ComputeTarget, pixels: &Target) -> Result<()> {
    let frame = (target.frame.width, target.frame.height);
    if frame != (pixels.width, pixels.height) {
        return Err(Error::Invalid(format!(
            "direct: a {}x{} image for a {}x{} frame",
            pixels.width, pixels.height, frame.0, frame.1
        )));
    }
    Ok(())
}

/// `direct` on compute alone: extraction, the shared compute rasterizer, a shading resolve;
/// with occlusion culling through [`Self::record_culled`] (`compute_cull`).
pub struct DirectCompute {
    extract: DirectExtract,
    /// The extraction that also draws its triangles ([`DirectRaster::InExtraction`]).
    drawing_extract: Option<Pipeline>,
    pub(super) rasterizer: ComputeRasterizer,
    pub(super) cull: ComputeCullPipelines,
    resolve: SurfaceResolve,
    reproject: Pipeline,
    builder: MinMaxBuilder,
}

/// Push constants of `reproject.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ReprojectParams {
    pub first_clip_to_second_clip: [[f32; 4]; 4],
    pub capacity: [u32; 4],
}

impl DirectCompute {
    /// The compute path with ambiguous faces cut by the asymptotic decider.
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<DirectCompute> {
        Self::with_rule(gpu, compiler, scalar, AmbiguityRule::default())
    }

    /// The compute path with ambiguous faces cut by `rule`.
    pub fn with_rule(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
    ) -> Result<DirectCompute> {
        Self::with_raster(gpu, compiler, scalar, rule, DirectRaster::Pass)
    }

    /// The compute path with ambiguous faces cut by `rule`, its triangles drawn as `raster` says.
    pub fn with_raster(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        raster: DirectRaster,
    ) -> Result<DirectCompute> {
        Self::build(gpu, compiler, scalar, rule, raster, RasterVariant::Exact)
    }

    /// The compute path drawing as `raster` and `variant` say, for performance work: with a
    /// variant that is not [`RasterVariant::is_exact`] its images are wrong.
    pub fn for_measuring(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        raster: DirectRaster,
        variant: RasterVariant,
    ) -> Result<DirectCompute> {
        Self::build(
            gpu,
            compiler,
            scalar,
            AmbiguityRule::default(),
            raster,
            variant,
        )
    }

    fn build(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        raster: DirectRaster,
        variant: RasterVariant,
    ) -> Result<DirectCompute> {
        let drawing_extract = match raster {
            DirectRaster::Pass => None,
            DirectRaster::InExtraction => Some(drawing_extraction(
                gpu,
                compiler,
                &extract_defines(scalar, rule, gpu.caps().subgroup_arithmetic),
                &EXTRACT_SLOTS,
                "direct extract (drawing)",
                variant,
            )?),
        };
        let rasterizer = ComputeRasterizer::with_variant(gpu, compiler, variant)?;
        let defines = volume_defines(scalar);
        let resolve = SurfaceResolve::new(gpu, compiler, &defines, false, "direct resolve")?;
        let reproject = compiler.compile(&builtin_shader!("reproject.comp.glsl"), &defines)?;
        let reproject =
            gpu.compute_pipeline("direct reproject", &reproject, &[Slot::StorageBuffer; 4])?;
        Ok(DirectCompute {
            extract: DirectExtract::with_rule(gpu, compiler, scalar, rule)?,
            drawing_extract,
            rasterizer,
            cull: ComputeCullPipelines::new(gpu, compiler, scalar, rule, (raster, variant))?,
            resolve,
            reproject,
            builder: MinMaxBuilder::new(gpu, compiler, scalar)?,
        })
    }

    pub fn prepare(&self, gpu: &Gpu, volume: &tessera_data::Volume) -> Result<PreparedVolume> {
        PreparedVolume::new(gpu, &self.builder, volume)
    }

    /// Where the triangles are drawn.
    pub fn raster(&self) -> DirectRaster {
        match self.drawing_extract {
            Some(_) => DirectRaster::InExtraction,
            None => DirectRaster::Pass,
        }
    }

    /// Records a frame shaded into `pixels` (of the frame's size); `params.triangle_capacity` must be
    /// `target.lists.capacity`.
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
        pixels: &Target,
        params: &DirectParams,
    ) {
        // The frame begins with the extraction's counters (one barrier), and the
        // extraction writes the raster pass's dispatch arguments as it reserves slots.
        target.frame.record_begin(rec);
        target
            .frame
            .hide_winding(Direct::hidden_winding(prepared, params));
        let lists = &target.lists;
        match &self.drawing_extract {
            Some(drawing) => {
                let frame = Some(&target.frame);
                self.extract
                    .record_with(rec, drawing, prepared, lists, frame, params);
                rec.barrier();
            }
            None => {
                self.extract.record(rec, prepared, lists, params);
                rec.barrier();
                let frame = &target.frame;
                self.rasterizer
                    .record_raster(rec, &lists.triangles, &lists.counts, frame);
            }
        }
        self.record_resolve(rec, target, &target.lists.attributes, pixels, params);
    }

    /// Records the second view of a stereo pair after [`Self::record`] drew the first of
    /// `prepared` into `first` with `first_params`: the extracted triangles are re-projected for
    /// `params` (the second eye's) into `second`, rasterized (the side no pixel of this eye
    /// shows left out, as [`Self::record`] does) and shaded; nothing is extracted again.
    pub fn record_second_view(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        (first, first_params): (&ComputeTarget, &DirectParams),
        second: &ComputeTarget,
        second_pixels: &Target,
        params: &DirectParams,
    ) {
        let grid_to_clip = |p: &DirectParams| glam::Mat4::from_cols_array_2d(&p.grid_to_clip);
        let first_to_second =
            grid_to_clip(params).as_dmat4() * grid_to_clip(first_params).as_dmat4().inverse();
        let reproject = ReprojectParams {
            first_clip_to_second_clip: first_to_second.as_mat4().to_cols_array_2d(),
            capacity: [second.lists.capacity, 0, 0, 0],
        };
        rec.dispatch_indirect(
            &self.reproject,
            &[
                Binding::Buffer(&first.lists.triangles),
                Binding::Buffer(&first.lists.counts),
                Binding::Buffer(&second.lists.triangles),
                Binding::Buffer(&second.lists.counts),
            ],
            bytemuck::bytes_of(&reproject),
            &first.lists.counts,
            4,
        );
        second.frame.record_begin(rec);
        second
            .frame
            .hide_winding(Direct::hidden_winding(prepared, params));
        rec.barrier();
        self.rasterizer
            .record_prepare_dispatch(rec, &second.lists.counts);
        self.rasterizer.record_raster(
            rec,
            &second.lists.triangles,
            &second.lists.counts,
            &second.frame,
        );
        self.record_resolve(rec, second, &first.lists.attributes, second_pixels, params);
    }

    fn record_resolve(
        &self,
        rec: &Recorder,
        target: &ComputeTarget,
        attributes: &Buffer,
        pixels: &Target,
        params: &DirectParams,
    ) {
        let list = ShadedList {
            triangles: &target.lists.triangles,
            attributes,
        };
        self.resolve
            .record(rec, &target.frame, list, pixels, params.lighting());
    }

    /// Renders one frame into `pixels`: the image, the GPU time in milliseconds and what
    /// extraction did.
    pub fn render(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
        pixels: &Target,
        iso: f32,
        camera: &OrbitCamera,
    ) -> Result<(RgbaImage, f64, ExtractStats)> {
        let (w, h) = (target.frame.width, target.frame.height);
        check_pixels(target, pixels)?;
        let params = Direct::params(prepared, iso, camera, w, h, target.lists.capacity);
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        let submitted = gpu.submit("direct (compute path)", |rec| {
            timer.scope(rec, "direct-compute", |rec| {
                self.record(rec, prepared, target, pixels, &params)
            });
        });
        let ms = submitted
            .map_err(Error::from)
            .and_then(|_| Ok(timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0)))?;
        let stats = self.extract.read_stats(gpu)?;
        if stats.triangles > target.lists.capacity {
            return Err(Error::Invalid(format!(
                "the isosurface has {} triangles, the frame holds {}: raise the capacity",
                stats.triangles, target.lists.capacity
            )));
        }
        Ok((pixels.read(gpu)?, ms, stats))
    }

    pub fn read_stats(&self, gpu: &Gpu) -> Result<ExtractStats> {
        self.extract.read_stats(gpu)
    }
}
