//! Ray-traced shell traversal of tet meshes — paper B (Sahistan et al.): per pixel, the
//! nearest shell face the ray leaves through is found among the shell triangles (front faces
//! culled), the backward trace from there finds the segment's entry face, and the ray marches tet to tet through the compact layout (Tet32, Tet20 or Tet16)
//! with the ray-centric projection and exit decision of the CPU reference
//! (`tessera_data::tet::shell`), integrating emission–absorption per tet stretch through the
//! transfer function's tables, until 98 % opacity; then on past the exit for the next segment
//! of a non-convex mesh. The eye may sit inside the mesh. A loop guard ends a segment after a
//! step limit and counts it.
//!
//! The traces run either in compute shaders walking a BVH over the shell triangles (the
//! compute path) or on the ray-tracing pipeline through an acceleration structure over boxes
//! around them (the graphics path, the paper's way; [`pass`]); both judge faces alike and find
//! the same ones.
//!
//! [`ShellRays`] runs the same traversal for given rays (shadow rays; per-ray checks against
//! the CPU traversal). [`Shell::with_effects`] adds the secondary-ray effects ([`effects`]):
//! volumetric shadows with a ground plane, ambient occlusion and gradient shading.

pub mod effects;
pub mod mesh;
mod pass;
pub mod rays;
mod tables;

pub use effects::{EffectBuffers, EffectParams};
pub use mesh::GpuShellMesh;
pub use rays::{shadow_ray, GpuRay, RayResult, ShellRays, TracedRay, VisitedTet, RECORDED_STEPS};

use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::path::Path;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use effects::LightingPass;
use pass::ShellPass;
use tables::{ShellTables, STATS};
use tessera_data::tet::emission_absorption::{EmissionAbsorption, EARLY_TERMINATION_OPACITY};
use tessera_data::tet::shell::{
    LayoutKind, SecondaryStats, ShellEffects, ShellMesh, Tet16, Tet20, Tet32, TraversalOptions,
    TraversalStats, BVH_MAX_DEPTH,
};
use tessera_data::{OrbitCamera, RgbaImage, View};
use tessera_gpu::{vk, Binding, Buffer, Gpu, Recorder, ShaderCompiler, Timer};

/// Bindings every shell pass shares (`buffers.glsl`).
const COMMON_BINDINGS: usize = 6;
/// What the pixel pass writes after them: the packed colours and their float radiance.
const OUTPUT_BINDINGS: usize = 2;

/// The light reaching the eye per pixel, three floats, before the pixel pass clamps it to
/// [0, 1] and packs it into the target's 8-bit colours.
pub struct RadianceBuffer {
    buffer: Buffer,
    pub width: u32,
    pub height: u32,
}

impl RadianceBuffer {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<RadianceBuffer> {
        let buffer = gpu.create_buffer(
            "shell radiance",
            u64::from(width) * u64::from(height) * 12,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            tessera_gpu::MemoryLocation::GpuOnly,
        )?;
        Ok(RadianceBuffer {
            buffer,
            width,
            height,
        })
    }

    /// Per pixel, rows top to bottom.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        Ok(gpu.read_buffer_as(&self.buffer)?)
    }
}

/// Push constants (`params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ShellParams {
    pub eye: [f32; 3],
    /// View-space depth where pixel rays begin.
    pub near_depth: f32,
    pub forward: [f32; 3],
    pub tan_half_fov_x: f32,
    pub right: [f32; 3],
    pub tan_half_fov_y: f32,
    pub up: [f32; 3],
    /// Steps per segment before the loop guard ends it.
    pub max_steps: u32,
    pub background: [f32; 3],
    pub tet_count: u32,
    pub scalar_range: [f32; 2],
    /// Image width and height, or (rays, 1).
    pub size: [u32; 2],
    pub vertex_count: u32,
    pub pad: [u32; 3],
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShellOptions {
    pub layout: LayoutKind,
    pub traversal: TraversalOptions,
    /// How the shell is traced: [`Path::Compute`] (a BVH walked in compute shaders) or
    /// [`Path::Graphics`] (the ray-tracing pipeline; meshes then need their acceleration
    /// structure, [`GpuShellMesh::upload_for`]).
    pub path: Path,
    /// Find each segment's exit and entry faces but march no tets: what the shell traces
    /// alone cost (benchmarks; the image shows the background).
    pub traces_only: bool,
}

impl ShellOptions {
    pub fn new(layout: LayoutKind) -> ShellOptions {
        ShellOptions::on(layout, Path::Compute)
    }

    pub fn on(layout: LayoutKind, path: Path) -> ShellOptions {
        ShellOptions {
            layout,
            traversal: TraversalOptions::default(),
            path,
            traces_only: false,
        }
    }
}

/// The defines of every shell pass for `options` with tables of `knots` knots.
pub(crate) fn defines(options: &ShellOptions, knots: usize) -> Vec<(String, String)> {
    let (code, bytes) = match options.layout {
        LayoutKind::Tet32 => (0, std::mem::size_of::<Tet32>()),
        LayoutKind::Tet20 => (1, std::mem::size_of::<Tet20>()),
        LayoutKind::Tet16 => (2, std::mem::size_of::<Tet16>()),
    };
    let mut defines = crate::config::common_defines();
    defines.extend([
        ("TET_LAYOUT_TET32".into(), "0".into()),
        ("TET_LAYOUT_TET20".into(), "1".into()),
        ("TET_LAYOUT_TET16".into(), "2".into()),
        ("TET_LAYOUT".into(), code.to_string()),
        ("TET_WORDS".into(), (bytes / 4).to_string()),
        ("BVH_MAX_DEPTH".into(), BVH_MAX_DEPTH.to_string()),
        ("TABLE_KNOTS".into(), knots.to_string()),
        ("ABSORPTION_TABLE".into(), "0u".into()),
        ("EMISSION_TABLE".into(), format!("{}u", 2 * knots)),
        (
            "EARLY_TERMINATION_OPACITY".into(),
            format!("{:?}", EARLY_TERMINATION_OPACITY as f32),
        ),
    ]);
    defines.extend(
        STATS
            .iter()
            .enumerate()
            .map(|(i, name)| (name.to_string(), format!("{i}u"))),
    );
    defines.extend(pass::tracing_defines(options.path));
    defines.push((
        "SHELL_TRACES_ONLY".into(),
        u32::from(options.traces_only).to_string(),
    ));
    defines
}

/// What each way of tracing the shell needs of a device.
pub fn path_support(caps: &tessera_gpu::Capabilities) -> crate::path::Support {
    crate::path::Support {
        graphics: caps.ray_tracing_pipeline && caps.acceleration_structure,
        graphics_needs: "ray-tracing pipelines",
        compute: true,
        compute_needs: "nothing",
    }
}

/// Refuses a mesh uploaded in another layout than the pipelines decode, or without the
/// acceleration structure they trace.
fn check_layout(mesh: &GpuShellMesh, options: &ShellOptions) -> Result<()> {
    if options.path == Path::Graphics && mesh.scene.is_none() {
        return Err(Error::Invalid(
            "shell traversal: the ray-tracing pipeline needs the mesh uploaded with its \
             acceleration structure"
                .into(),
        ));
    }
    if mesh.layout != options.layout {
        return Err(Error::Invalid(format!(
            "shell traversal: a {} mesh for {} pipelines",
            mesh.layout.name(),
            options.layout.name()
        )));
    }
    Ok(())
}

/// The push constants of a pass over `mesh` (the view's fields are zero for given rays).
fn base_params(mesh: &GpuShellMesh, options: &ShellOptions) -> ShellParams {
    ShellParams {
        max_steps: options
            .traversal
            .max_steps_per_segment
            .min(u64::from(u32::MAX)) as u32,
        tet_count: mesh.tet_count,
        vertex_count: mesh.vertex_count,
        scalar_range: [mesh.scalar_range.0, mesh.scalar_range.1],
        ..ShellParams::default()
    }
}

/// The pixel pass: one image of emission–absorption by shell traversal, with the passes of
/// its effects before it.
pub struct Shell {
    pipeline: ShellPass,
    /// The effects' passes in the order they run.
    lighting: Vec<(LightingPass, ShellPass)>,
    tables: ShellTables,
    options: ShellOptions,
    effects: ShellEffects,
}

/// A frame's image, counters and GPU times.
pub struct ShellImage {
    pub image: RgbaImage,
    pub stats: TraversalStats,
    pub secondary: SecondaryStats,
    /// Milliseconds per timer scope, in recording order.
    pub times: Vec<(String, f64)>,
}

impl Shell {
    /// Pipelines for `options.layout` with `optics`' tables (later tables of the same knot
    /// count are a buffer write: [`Shell::set_optics`]).
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: &ShellOptions,
        optics: &EmissionAbsorption,
    ) -> Result<Shell> {
        Shell::with_effects(gpu, compiler, options, optics, &ShellEffects::default())
    }

    /// [`Shell::new`] shading with `effects`; with none, exactly [`Shell::new`]'s pipeline.
    pub fn with_effects(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: &ShellOptions,
        optics: &EmissionAbsorption,
        effects: &ShellEffects,
    ) -> Result<Shell> {
        let tables = ShellTables::new(gpu, optics)?;
        let mut base = defines(options, tables.knots);
        base.extend(effects::effect_defines(effects));
        let slots = if effects.any() {
            COMMON_BINDINGS + OUTPUT_BINDINGS + effects::EFFECT_BINDINGS
        } else {
            COMMON_BINDINGS + OUTPUT_BINDINGS
        };
        let pipeline = ShellPass::new(
            gpu,
            compiler,
            "shell traversal",
            builtin_shader!("shell.comp.glsl"),
            &base,
            slots,
            options.path,
        )?;
        let mut lighting = Vec::new();
        for pass in LightingPass::ALL.into_iter().filter(|p| p.needed(effects)) {
            let mut defines = defines(options, tables.knots);
            defines.extend(effects::pass_defines(effects, pass));
            let pipeline = ShellPass::new(
                gpu,
                compiler,
                pass.scope(),
                builtin_shader!("lighting.comp.glsl"),
                &defines,
                slots,
                options.path,
            )?;
            lighting.push((pass, pipeline));
        }
        Ok(Shell {
            pipeline,
            lighting,
            tables,
            options: *options,
            effects: *effects,
        })
    }

    pub fn options(&self) -> &ShellOptions {
        &self.options
    }

    pub fn effects(&self) -> &ShellEffects {
        &self.effects
    }

    pub fn set_optics(&self, gpu: &Gpu, optics: &EmissionAbsorption) -> Result<()> {
        self.tables.write(gpu, optics)
    }

    /// The push constants of a frame of `view` (pixel rays as the CPU reference casts them:
    /// from the eye, starting at the near plane).
    pub fn params(&self, mesh: &GpuShellMesh, view: &View, background: [f32; 3]) -> ShellParams {
        ShellParams {
            eye: view.eye.to_array(),
            near_depth: view.near,
            forward: view.forward.to_array(),
            tan_half_fov_x: view.tan_half_fov.x,
            right: view.right.to_array(),
            tan_half_fov_y: view.tan_half_fov.y,
            up: view.up.to_array(),
            background,
            size: [view.size.0, view.size.1],
            ..base_params(mesh, &self.options)
        }
    }

    fn check_target(
        target: &Target,
        radiance: &RadianceBuffer,
        params: &ShellParams,
    ) -> Result<()> {
        if params.size != [target.width, target.height]
            || params.size != [radiance.width, radiance.height]
        {
            return Err(Error::Invalid(
                "shell traversal: target of another size".into(),
            ));
        }
        Ok(())
    }

    /// Records one frame into `target` and `radiance`, counters cleared first (a pass without
    /// effects).
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuShellMesh,
        target: &Target,
        radiance: &RadianceBuffer,
        params: &ShellParams,
    ) -> Result<()> {
        check_layout(mesh, &self.options)?;
        Self::check_target(target, radiance, params)?;
        if self.effects.any() {
            return Err(Error::Invalid(
                "shell traversal: a pass with effects records through record_effects".into(),
            ));
        }
        rec.fill_buffer(&self.tables.stats, 0);
        rec.barrier();
        let mut bindings = self.tables.bindings(mesh).to_vec();
        bindings.extend([
            Binding::Buffer(&target.pixels),
            Binding::Buffer(&radiance.buffer),
        ]);
        self.pipeline.record(
            rec,
            mesh,
            &bindings,
            bytemuck::bytes_of(params),
            [target.width, target.height, 1],
        )?;
        rec.barrier();
        Ok(())
    }

    /// Records one frame with the effects into `target`: counters cleared and `effect` written
    /// first, then each effect's pass and the pixel pass, each in a scope of `timer` (the
    /// pixel pass's is "shell traversal"). Without `relight` the per-tet passes are left out
    /// (their scopes stay, empty): `buffers` still hold the lighting of an earlier frame with
    /// the same `effect`, mesh and optics, which does not depend on the eye.
    #[allow(clippy::too_many_arguments)]
    pub fn record_effects(
        &self,
        rec: &Recorder,
        mesh: &GpuShellMesh,
        buffers: &EffectBuffers,
        output: (&Target, &RadianceBuffer),
        params: &ShellParams,
        effect: &EffectParams,
        relight: bool,
        timer: &mut Timer,
    ) -> Result<()> {
        let (target, radiance) = output;
        check_layout(mesh, &self.options)?;
        Self::check_target(target, radiance, params)?;
        if buffers.effects() != &self.effects
            || buffers.pixels() != u64::from(target.width) * u64::from(target.height)
        {
            return Err(Error::Invalid(
                "shell traversal: effect buffers made for other effects or another size".into(),
            ));
        }
        rec.fill_buffer(&self.tables.stats, 0);
        rec.update_buffer(&buffers.params, bytemuck::bytes_of(effect));
        rec.barrier();
        let mut bindings = self.tables.bindings(mesh).to_vec();
        bindings.extend([
            Binding::Buffer(&target.pixels),
            Binding::Buffer(&radiance.buffer),
        ]);
        if self.effects.any() {
            bindings.extend(buffers.bindings());
        }
        let push = bytemuck::bytes_of(params);
        for (pass, pipeline) in &self.lighting {
            let threads = if pass.per_pixel() {
                [target.width, target.height, 1]
            } else {
                [mesh.tet_count, 1, 1]
            };
            if !relight && !pass.per_pixel() {
                timer.scope(rec, pass.scope(), |_| ());
                continue;
            }
            timer.scope(rec, pass.scope(), |rec| {
                let recorded = pipeline.record(rec, mesh, &bindings, push, threads);
                rec.barrier();
                recorded
            })?;
        }
        timer.scope(rec, "shell traversal", |rec| {
            let recorded =
                self.pipeline
                    .record(rec, mesh, &bindings, push, [target.width, target.height, 1]);
            rec.barrier();
            recorded
        })
    }

    /// The counters of the last frame.
    pub fn read_stats(&self, gpu: &Gpu) -> Result<TraversalStats> {
        self.tables.read_stats(gpu)
    }

    /// The secondary-ray counters of the last frame.
    pub fn read_secondary(&self, gpu: &Gpu) -> Result<SecondaryStats> {
        Ok(self.tables.read_all_stats(gpu)?.1)
    }

    /// Renders `mesh` seen by `camera` at `size` over `background`: the image, what the
    /// traversal counted and the GPU time.
    pub fn render_image(
        &self,
        gpu: &Gpu,
        mesh: &GpuShellMesh,
        camera: &OrbitCamera,
        size: (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, TraversalStats, f64)> {
        let view = View::of_unit_box(camera, size);
        let target = Target::new(gpu, size.0, size.1)?;
        let radiance = RadianceBuffer::new(gpu, size.0, size.1)?;
        let params = self.params(mesh, &view, background);
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        let mut recorded = Ok(());
        gpu.submit("shell traversal image", |rec| {
            recorded = timer.scope(rec, "shell", |rec| {
                self.record(rec, mesh, &target, &radiance, &params)
            });
        })?;
        recorded?;
        let ms = timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0);
        Ok((target.read(gpu)?, self.read_stats(gpu)?, ms))
    }

    /// Renders `mesh` (`shell` on the GPU) with the effects, lit as the CPU reference lights
    /// it: the view of `camera` at `size` over `background`, through `optics` (the tables
    /// this pass holds). `buffers` must be made for this pass's effects and `size`.
    #[allow(clippy::too_many_arguments)]
    pub fn render_effects_image(
        &self,
        gpu: &Gpu,
        mesh: &GpuShellMesh,
        buffers: &EffectBuffers,
        shell: &ShellMesh,
        optics: &EmissionAbsorption,
        camera: &OrbitCamera,
        size: (u32, u32),
        background: [f32; 3],
    ) -> Result<ShellImage> {
        let view = View::of_unit_box(camera, size);
        let target = Target::new(gpu, size.0, size.1)?;
        let radiance = RadianceBuffer::new(gpu, size.0, size.1)?;
        let params = self.params(mesh, &view, background);
        let effect = EffectParams::new(&self.effects, &view, shell.world_bounds(), optics);
        let mut timer = Timer::new(gpu, 1 + self.lighting.len() as u32)?;
        timer.reset(gpu);
        let mut recorded = Ok(());
        gpu.submit("shell traversal image with effects", |rec| {
            recorded = self.record_effects(
                rec,
                mesh,
                buffers,
                (&target, &radiance),
                &params,
                &effect,
                true,
                &mut timer,
            );
        })?;
        recorded?;
        let (stats, secondary) = self.tables.read_all_stats(gpu)?;
        Ok(ShellImage {
            image: target.read(gpu)?,
            stats,
            secondary,
            times: timer.read_ms(gpu)?,
        })
    }
}
