//! Interval shading of tetrahedral meshes — paper A (Sinclair et al.): each tetrahedron becomes
//! screen-space proxy triangles (3 when its projection is a triangle, 4 when it is a quad) whose
//! vertices carry the inverse view depths of the front and back faces, so every pixel knows the
//! interval its ray spends in the tet, and a post pass turns the accumulation into colour.
//!
//! What a pixel accumulates ([`Integrand`]): the interval's length times a per-tet absorption
//! colour (the paper's optical depth, Beer–Lambert afterwards), or — beyond the paper — a
//! per-vertex scalar field integrated through a transfer function: absorption, added emission,
//! or the maximum. The proxies also carry s/z of both faces, interpolated like 1/z, so a pixel
//! recovers the scalar where its ray enters and leaves the tet without fetching the tet again.
//!
//! Two paths ([`Path`]): the paper's mesh shader + rasterizer + blending ([`graphics`]), and a
//! compute rasterization of the same proxies, in two variants ([`ComputeScheme`]): per tet with
//! float atomics ([`compute`]), or binned into per-tile lists shaded one workgroup per tile
//! ([`binned`]). Tets crossing the near plane are clipped into 1 or 3 tets, so the camera may be
//! inside the mesh.

pub mod binned;
pub mod composite;
pub mod compute;
pub mod graphics;
pub mod mesh;
pub mod scheme_choice;
pub mod subgroup_draw;

pub use binned::BinCapacity;
pub use compute::TileCapacity;
pub use mesh::{GpuTetMesh, OpticalTarget};
pub use subgroup_draw::{SubgroupDraw, SUBGROUP_DRAW_ABOVE_PIXELS, SUBGROUP_DRAW_CHOICES};

use crate::error::{Error, Result};
use crate::path::Path;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use composite::Composite;
use compute::IntervalCompute;
use graphics::{Combine, IntervalGraphics};
use mesh::OpticalStore;
use scheme_choice::DrawScheme;
use tessera_data::transfer::{IntegrandTable, ScalarMode};
use tessera_data::{OrbitCamera, RgbaImage, View};
use tessera_gpu::{vk, Binding, Buffer, Gpu, Recorder, ShaderCompiler, Timer};

/// Bindings every pass shares (`buffers.glsl`): vertices, tets, absorption, table, stats.
pub(crate) const COMMON_BINDINGS: usize = 5;

/// Push constants (`tet/interval/params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct IntervalParams {
    pub world_to_clip: [[f32; 4]; 4],
    pub tan_half_fov: [f32; 2],
    /// View-space depth of the near plane.
    pub near_depth: f32,
    pub pad0: f32,
    /// Tets, width, height, and the compute path's limit on pixels drawn by one invocation.
    pub counts: [u32; 4],
    /// The eye in world space (w unused).
    pub eye: [f32; 4],
    /// The scalar range mapped onto [0, 1] (`GpuTetMesh::scalar_range`).
    pub scalar_range: [f32; 2],
}

/// What each pixel accumulates along its ray.
#[derive(Clone, Debug, PartialEq)]
pub enum Integrand {
    /// Interval length × the tet's absorption colour (white where the mesh has none).
    TetAbsorption,
    /// The vertex scalars, mapped onto [0, 1] over `GpuTetMesh::scalar_range`, through a table.
    Scalar {
        mode: ScalarMode,
        table: IntegrandTable,
    },
    /// No integral: the asteroid inside each tet ([`GpuTetMesh::upload_asteroids`]),
    /// sphere-traced along the interval; the nearest hit wins.
    Asteroids,
}

impl Integrand {
    fn code(&self) -> u32 {
        match self {
            Integrand::TetAbsorption => 0,
            Integrand::Asteroids => 4,
            Integrand::Scalar { mode, .. } => match mode {
                ScalarMode::Absorption => 1,
                ScalarMode::Emission => 2,
                ScalarMode::Maximum => 3,
            },
        }
    }

    fn table_words(&self) -> Vec<[f32; 4]> {
        match self {
            Integrand::TetAbsorption | Integrand::Asteroids => IntegrandTable {
                values: vec![[0.0; 3]; 2],
            }
            .gpu_words(),
            Integrand::Scalar { table, .. } => table.gpu_words(),
        }
    }

    fn knots(&self) -> usize {
        match self {
            Integrand::TetAbsorption | Integrand::Asteroids => 2,
            Integrand::Scalar { table, .. } => table.values.len(),
        }
    }
}

/// How the compute path adds the tets' pixels into the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ComputeScheme {
    /// One invocation per tet adds its pixels with global float atomics; tets above the pixel
    /// limit go to the tile pass ([`compute`]). Faster than binning only where a huge mesh
    /// is seen small (on the H200 at 3840×2160, the 944 k- and 2.4 M-tet boxes from afar:
    /// 19.1 against 21.8 ms and 26.2 against 36.2 ms, docs/BENCHMARKS.md run 62).
    PerTet,
    /// Tets binned into per-tile lists of 16 × 16-pixel screen tiles, one workgroup per tile
    /// combining its tets in registers and writing each pixel once ([`binned`]): 1.08–2.5×
    /// faster than per tet in every other view measured.
    Binned,
    /// Frame by frame the scheme whose last frame took the least GPU time, the other measured
    /// again every so often ([`scheme_choice`]). The default.
    #[default]
    Auto,
}

impl ComputeScheme {
    pub fn name(self) -> &'static str {
        match self {
            ComputeScheme::PerTet => "per tet",
            ComputeScheme::Binned => "binned",
            ComputeScheme::Auto => "auto",
        }
    }

    /// The scheme a frame is drawn with when nothing has been measured (`Auto`: binning, the
    /// faster in most views).
    pub fn first_draw(self) -> DrawScheme {
        match self {
            ComputeScheme::PerTet => DrawScheme::PerTet,
            ComputeScheme::Binned | ComputeScheme::Auto => DrawScheme::Binned,
        }
    }
}

#[derive(Clone, Debug)]
pub struct IntervalOptions {
    pub path: Path,
    pub integrand: Integrand,
    /// Graphics path: tets per mesh workgroup (1 to 16).
    pub tets_per_workgroup: u32,
    /// Compute path: tets whose screen rectangle holds more pixels go to the tile pass; `None`
    /// takes [`DEFAULT_INLINE_PIXEL_LIMIT`].
    pub inline_pixel_limit: Option<u32>,
    pub tile_capacity: TileCapacity,
    /// Compute path: per tet or binned.
    pub compute_scheme: ComputeScheme,
    /// Binned compute path: the lists' first capacity (they grow, see [`Interval::grow_buffers`]).
    pub bin_capacity: BinCapacity,
    /// Compute path: which tets the per-tet pass's subgroups draw together.
    pub subgroup_draw: SubgroupDraw,
}

/// The settings of interval shading that trade speed between meshes and views, without
/// changing the image (the benchmarks compare them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IntervalTuning {
    /// Graphics path: tets per mesh workgroup (1 to 16).
    pub tets_per_workgroup: u32,
    /// Compute path: the tile pass's pixel limit (`None`: automatic); in the binned scheme it
    /// applies to the tets the lists have no room for.
    pub inline_pixel_limit: Option<u32>,
    /// Compute path: per tet or binned.
    pub compute_scheme: ComputeScheme,
    /// Compute path: which tets the per-tet pass's subgroups draw together.
    pub subgroup_draw: SubgroupDraw,
}

impl Default for IntervalTuning {
    fn default() -> Self {
        IntervalTuning {
            tets_per_workgroup: graphics::MAX_TETS_PER_WORKGROUP,
            inline_pixel_limit: None,
            compute_scheme: ComputeScheme::default(),
            subgroup_draw: SubgroupDraw::default(),
        }
    }
}

impl IntervalOptions {
    pub fn new(path: Path) -> IntervalOptions {
        Self::tuned(path, IntervalTuning::default())
    }

    pub fn tuned(path: Path, tuning: IntervalTuning) -> IntervalOptions {
        IntervalOptions {
            path,
            integrand: Integrand::TetAbsorption,
            tets_per_workgroup: tuning.tets_per_workgroup,
            inline_pixel_limit: tuning.inline_pixel_limit,
            tile_capacity: TileCapacity::default(),
            compute_scheme: tuning.compute_scheme,
            bin_capacity: BinCapacity::default(),
            subgroup_draw: tuning.subgroup_draw,
        }
    }
}

/// What the passes of a frame counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IntervalCounts {
    /// Tets clipped at the near plane.
    pub clipped_near: u32,
    /// Compute path: tets handed to the tile pass, and those drawn by one invocation because
    /// the tile buffers were full.
    pub tiled: u32,
    pub overflowed: u32,
    /// Binned compute path: tets drawn per tet because the bins were full.
    pub unbinned: u32,
    /// Binned compute path: (tet, tile) entries the tets reserved, those that did not fit
    /// included.
    pub bin_entries: u32,
}

/// One frame's accumulation, its GPU time and what the passes counted.
pub struct IntervalFrame {
    /// Per pixel, rows top to bottom: optical depth or emission (rgb), or for the maximum
    /// `[largest scalar, coverage, 0]`.
    pub values: Vec<[f32; 3]>,
    pub gpu_ms: f64,
    /// Tets clipped at the near plane.
    pub clipped_near: u32,
    /// Compute path: tets handed to the tile pass, and those drawn by one invocation because
    /// the tile buffers were full.
    pub tiled: u32,
    pub overflowed: u32,
    /// Binned compute path: tets drawn per tet because the bins were full.
    pub unbinned: u32,
    /// Binned compute path: (tet, tile) entries the tets reserved, those that did not fit
    /// included.
    pub bin_entries: u32,
}

enum Renderer {
    Graphics(IntervalGraphics),
    Compute(Box<IntervalCompute>),
}

pub struct Interval {
    renderer: Renderer,
    composite: Composite,
    table: Buffer,
    stats: Buffer,
    options: IntervalOptions,
}

/// The compute path's pixel limit when none is given: tets whose screen rectangle holds more
/// pixels go to the tile pass. Since a subgroup draws its tets' row spans together, large tets
/// cost the per-tet pass less and the limit moved up from 4096: 16,384 is 13 % faster on the
/// 944 k-tet box close (19.46 to 16.91 ms) and 10 % on the 64 k-tet box far (3.58 to 3.22),
/// within 1 % on the other boxes far and close (docs/BENCHMARKS.md, run 95, 4K). Where it
/// is slower (the bunny far and inside, the 64 k-tet box inside, the asteroid field) binning is
/// faster than either, and the automatic scheme takes it.
pub const DEFAULT_INLINE_PIXEL_LIMIT: u32 = 16384;

/// The paths interval shading can run on `caps`'s device: mesh shaders for the graphics path,
/// float atomics for the compute path.
pub fn path_support(caps: &tessera_gpu::Capabilities) -> crate::path::Support {
    crate::path::Support {
        graphics: caps.mesh_shader,
        graphics_needs: "mesh shaders",
        compute: caps.buffer_float32_atomic_add,
        compute_needs: "32-bit float buffer atomics",
    }
}

impl Interval {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, options: &IntervalOptions) -> Result<Self> {
        let defines = Interval::defines(options);
        let combine = match options.integrand {
            Integrand::Asteroids => Combine::Nearest,
            Integrand::Scalar {
                mode: ScalarMode::Maximum,
                ..
            } => Combine::Max,
            _ => Combine::Add,
        };
        if options.path == Path::Compute
            && combine == Combine::Nearest
            && !gpu.caps().buffer_int64_atomics
        {
            return Err(Error::Invalid(format!(
                "the asteroid field's compute path needs 64-bit atomics, which {} lacks",
                gpu.caps().device_name
            )));
        }
        let renderer = match options.path {
            Path::Graphics => Renderer::Graphics(IntervalGraphics::new(
                gpu,
                compiler,
                &defines,
                options.tets_per_workgroup,
                combine,
            )?),
            Path::Compute => Renderer::Compute(Box::new(IntervalCompute::new(
                gpu,
                compiler,
                &defines,
                options.tile_capacity,
                options.compute_scheme,
                options.bin_capacity,
                options.subgroup_draw,
            )?)),
        };
        let composite = Composite::new(gpu, compiler, &defines, options.path)?;
        let table = gpu.upload_buffer(
            "interval integrand table",
            bytemuck::cast_slice(&options.integrand.table_words()),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let stats = crate::raster::create_counts_buffer(gpu, "interval stats")?;
        Ok(Interval {
            renderer,
            composite,
            table,
            stats,
            options: options.clone(),
        })
    }

    pub(crate) fn defines(options: &IntervalOptions) -> Vec<(String, String)> {
        let mut defines = crate::config::common_defines();
        defines.extend([
            ("INTEGRAND_TET_ABSORPTION".into(), "0".into()),
            ("INTEGRAND_ABSORPTION".into(), "1".into()),
            ("INTEGRAND_EMISSION".into(), "2".into()),
            ("INTEGRAND_MAXIMUM".into(), "3".into()),
            ("INTEGRAND_SDF".into(), "4".into()),
            ("INTEGRAND".into(), options.integrand.code().to_string()),
            ("TABLE_KNOTS".into(), options.integrand.knots().to_string()),
            ("STAT_CLIPPED".into(), "0".into()),
            ("STAT_TILED".into(), "1".into()),
            ("STAT_OVERFLOW".into(), "2".into()),
            ("STAT_UNBINNED".into(), "3".into()),
        ]);
        defines.extend(crate::config::asteroid_defines());
        defines
    }

    pub fn path(&self) -> Path {
        self.options.path
    }

    /// What each pixel accumulates with these pipelines.
    pub fn integrand(&self) -> &Integrand {
        &self.options.integrand
    }

    /// A target of the kind this path accumulates into.
    pub fn target(&self, gpu: &Gpu, width: u32, height: u32) -> Result<OpticalTarget> {
        let nearest = self.options.integrand == Integrand::Asteroids;
        OpticalTarget::new(gpu, width, height, self.options.path, nearest)
    }

    pub fn params(
        &self,
        mesh: &GpuTetMesh,
        camera: &OrbitCamera,
        width: u32,
        height: u32,
    ) -> IntervalParams {
        self.params_for_view(mesh, &View::of_unit_box(camera, (width, height)))
    }

    /// The push constants of a frame of `view` (whose depth range must be the unit box's: the
    /// CPU references clip at that near plane).
    pub fn params_for_view(&self, mesh: &GpuTetMesh, view: &View) -> IntervalParams {
        let (width, height) = view.size;
        IntervalParams {
            world_to_clip: view.world_to_clip.to_cols_array_2d(),
            tan_half_fov: view.tan_half_fov.to_array(),
            near_depth: view.near,
            pad0: 0.0,
            counts: [
                mesh.tet_count,
                width,
                height,
                self.options
                    .inline_pixel_limit
                    .unwrap_or(DEFAULT_INLINE_PIXEL_LIMIT),
            ],
            eye: view.eye.extend(1.0).to_array(),
            scalar_range: [mesh.scalar_range.0, mesh.scalar_range.1],
        }
    }

    /// Whether `integrand` runs on these pipelines (same kind and table size): then
    /// [`Self::set_table`] switches to it without building anything.
    pub fn can_switch_to(&self, integrand: &Integrand) -> bool {
        integrand.code() == self.options.integrand.code()
            && integrand.knots() == self.options.integrand.knots()
    }

    /// Writes `integrand`'s table (see [`Self::can_switch_to`]).
    pub fn set_table(&mut self, gpu: &Gpu, integrand: &Integrand) -> Result<()> {
        if !self.can_switch_to(integrand) {
            return Err(Error::Invalid(
                "interval: another integrand kind needs other pipelines".into(),
            ));
        }
        gpu.write_buffer(&self.table, bytemuck::cast_slice(&integrand.table_words()))?;
        self.options.integrand = integrand.clone();
        Ok(())
    }

    /// The counters of the last frame.
    pub fn read_counts(&self, gpu: &Gpu) -> Result<IntervalCounts> {
        let stats = gpu.read_buffer_as::<u32>(&self.stats)?;
        Ok(IntervalCounts {
            clipped_near: stats[0],
            tiled: stats[1].min(self.options.tile_capacity.tets),
            overflowed: stats[2],
            unbinned: stats[3],
            bin_entries: match &self.renderer {
                Renderer::Compute(c) => c.bin_entries(gpu)?,
                Renderer::Graphics(_) => 0,
            },
        })
    }

    /// Grows the buffers the last frame, of a `width` × `height` image, overflowed, for the
    /// next frame (the binned compute path's lists: the frame itself drew what did not fit per
    /// tet); whether any grew.
    pub fn grow_buffers(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<bool> {
        match &mut self.renderer {
            Renderer::Compute(c) => c.grow_bins(gpu, size),
            Renderer::Graphics(_) => Ok(false),
        }
    }

    /// The binned compute path's current capacity (`None` on the other variants).
    pub fn bin_capacity(&self) -> Option<BinCapacity> {
        match &self.renderer {
            Renderer::Compute(c) => c.bin_capacity(),
            Renderer::Graphics(_) => None,
        }
    }

    /// Records one frame into `target` (cleared first), on the compute path with the scheme's
    /// first choice ([`ComputeScheme::first_draw`]). With a `timer`, the frame is timed as
    /// `interval`, or on the binned compute scheme as `binning` and `interval`
    /// ([`compute::IntervalCompute::record`]).
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        target: &OpticalTarget,
        params: &IntervalParams,
        timer: Option<&mut Timer>,
    ) -> Result<()> {
        let scheme = self.options.compute_scheme.first_draw();
        self.record_with(rec, mesh, target, params, scheme, timer)
    }

    /// [`Self::record`] with the compute path's `scheme` given (binned only where this was
    /// built for binning or the automatic choice).
    pub fn record_with(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        target: &OpticalTarget,
        params: &IntervalParams,
        scheme: DrawScheme,
        timer: Option<&mut Timer>,
    ) -> Result<()> {
        let common = [
            Binding::Buffer(&mesh.vertices),
            Binding::Buffer(&mesh.tets),
            Binding::Buffer(&mesh.absorption),
            Binding::Buffer(&self.table),
            Binding::Buffer(&self.stats),
        ];
        rec.fill_buffer(&self.stats, 0);
        rec.barrier();
        match (&self.renderer, &target.store) {
            (Renderer::Graphics(g), OpticalStore::Image { image, depth, .. }) => {
                let draw = |rec: &Recorder| {
                    g.record(rec, mesh, &common, (image, depth.as_deref()), params)
                };
                match timer {
                    Some(t) => t.scope(rec, "interval", draw),
                    None => draw(rec),
                }
            }
            (Renderer::Compute(c), OpticalStore::Buffer(buffer)) => {
                // The asteroid field keeps a minimum: empty pixels start at all ones.
                let clear = match self.options.integrand {
                    Integrand::Asteroids => u32::MAX,
                    _ => 0,
                };
                c.record(rec, mesh, &common, buffer, params, clear, scheme, timer);
                Ok(())
            }
            _ => Err(Error::Invalid(
                "interval target made for the other path (use Interval::target)".into(),
            )),
        }
    }

    /// One frame's accumulation and counters, timed.
    pub fn render(
        &self,
        gpu: &Gpu,
        mesh: &GpuTetMesh,
        target: &OpticalTarget,
        camera: &OrbitCamera,
    ) -> Result<IntervalFrame> {
        let params = self.params(mesh, camera, target.width, target.height);
        let gpu_ms = tessera_gpu::timing::time_once(gpu, "interval shading", |rec| {
            self.record(rec, mesh, target, &params, None)
        })?;
        let counts = self.read_counts(gpu)?;
        Ok(IntervalFrame {
            values: target.read(gpu)?,
            gpu_ms,
            clipped_near: counts.clipped_near,
            tiled: counts.tiled,
            overflowed: counts.overflowed,
            unbinned: counts.unbinned,
            bin_entries: counts.bin_entries,
        })
    }

    /// Records the post pass from `target` into `pixels`.
    pub fn record_composite(
        &self,
        rec: &Recorder,
        target: &OpticalTarget,
        pixels: &Target,
        background: [f32; 3],
    ) {
        self.composite
            .record(rec, target, pixels, &self.table, background);
    }

    /// Renders the mesh in front of a `background` of that colour; returns the image and the
    /// GPU time of the frame (accumulation and post pass).
    pub fn render_image(
        &self,
        gpu: &Gpu,
        mesh: &GpuTetMesh,
        camera: &OrbitCamera,
        (width, height): (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, f64)> {
        let target = self.target(gpu, width, height)?;
        let pixels = Target::new(gpu, width, height)?;
        let params = self.params(mesh, camera, width, height);
        let result = Timer::new(gpu, 1)
            .map_err(Error::from)
            .and_then(|mut timer| {
                timer.reset(gpu);
                let mut drawn = Ok(());
                let submitted = gpu.submit("interval shading image", |rec| {
                    drawn = timer.scope(rec, "interval", |rec| {
                        let r = self.record(rec, mesh, &target, &params, None);
                        self.record_composite(rec, &target, &pixels, background);
                        r
                    });
                });
                let result = submitted.map_err(Error::from).and(drawn).and_then(|_| {
                    Ok((
                        pixels.read(gpu)?,
                        timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0),
                    ))
                });
                result
            });
        result
    }
}
