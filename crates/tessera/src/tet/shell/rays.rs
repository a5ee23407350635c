//! Shell traversal of given rays: shadow rays towards a light, and the per-ray record of the
//! tets visited that the tests hold to the CPU traversal.

use super::pass::ShellPass;
use super::{
    base_params, check_layout, defines, GpuShellMesh, ShellOptions, ShellTables, COMMON_BINDINGS,
};
use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::path::Path;
use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::shell::{Light, Ray, TraversalStats};
use tessera_gpu::{vk, Binding, Gpu, MemoryLocation, ShaderCompiler};

/// Tets recorded per ray, in order; the rest are counted only.
pub const RECORDED_STEPS: usize = 256;

/// A ray as `shell_rays.comp.glsl` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuRay {
    pub origin: [f32; 3],
    pub t_min: f32,
    pub dir: [f32; 3],
    pub t_max: f32,
}

/// What one ray gathered.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayResult {
    pub colour: [f32; 3],
    /// Tets the ray crossed within its range (the first [`RECORDED_STEPS`] are recorded).
    pub steps: u32,
    pub transmittance: [f32; 3],
    pub segments: u32,
}

/// One tet crossed, in the order of the ray.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct VisitedTet {
    pub tet: u32,
    /// Which volume segment of the ray (from 0, among those within its range).
    pub segment: u32,
}

/// A ray's result and its recorded tets.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedRay {
    pub result: RayResult,
    pub visited: Vec<VisitedTet>,
}

pub struct ShellRays {
    pipeline: ShellPass,
    tables: ShellTables,
    options: ShellOptions,
}

/// The shadow ray from `point` towards `light`, as the CPU reference casts it.
pub fn shadow_ray(point: DVec3, light: Light) -> Ray {
    let (dir, t_max) = match light {
        Light::Point(at) => (at - point, point.distance(at)),
        Light::Directional(towards) => (towards, f64::INFINITY),
    };
    Ray {
        origin: point,
        dir: dir.normalize_or_zero(),
        t_min: 0.0,
        t_max,
    }
}

impl ShellRays {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: &ShellOptions,
        optics: &EmissionAbsorption,
    ) -> Result<ShellRays> {
        let tables = ShellTables::new(gpu, optics)?;
        let mut defines = defines(options, tables.knots);
        defines.push(("RECORDED_STEPS".into(), RECORDED_STEPS.to_string()));
        let pipeline = ShellPass::new(
            gpu,
            compiler,
            "shell traversal rays",
            builtin_shader!("shell_rays.comp.glsl"),
            &defines,
            COMMON_BINDINGS + 3,
            options.path,
        )?;
        Ok(ShellRays {
            pipeline,
            tables,
            options: *options,
        })
    }

    /// Traverses `rays` (world space, `dir` of unit length) through `mesh`; outputs start
    /// poisoned, so a ray the shader skipped shows.
    pub fn trace(
        &self,
        gpu: &Gpu,
        mesh: &GpuShellMesh,
        rays: &[Ray],
    ) -> Result<(Vec<TracedRay>, TraversalStats)> {
        check_layout(mesh, &self.options)?;
        if rays.is_empty() {
            return Ok((Vec::new(), TraversalStats::default()));
        }
        // A trace through the acceleration structure cannot start behind its origin.
        if self.pipeline.path() == Path::Graphics
            && rays.iter().any(|r| r.t_min < 0.0 || r.t_min.is_nan())
        {
            return Err(Error::Invalid(
                "shell traversal on the ray-tracing pipeline: rays must start at t_min >= 0".into(),
            ));
        }
        let gpu_rays: Vec<GpuRay> = rays
            .iter()
            .map(|r| GpuRay {
                origin: r.origin.as_vec3().to_array(),
                t_min: r.t_min as f32,
                dir: r.dir.as_vec3().to_array(),
                t_max: r.t_max as f32,
            })
            .collect();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let input = gpu.upload_buffer("shell rays", bytemuck::cast_slice(&gpu_rays), storage)?;
        let n = rays.len() as u64;
        let results = gpu.create_buffer(
            "shell ray results",
            n * std::mem::size_of::<RayResult>() as u64,
            storage | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let visited = gpu.create_buffer(
            "shell visited tets",
            n * (RECORDED_STEPS * std::mem::size_of::<VisitedTet>()) as u64,
            storage | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let params = super::ShellParams {
            size: [rays.len() as u32, 1],
            ..base_params(mesh, &self.options)
        };
        let mut bindings = self.tables.bindings(mesh).to_vec();
        bindings.extend([
            Binding::Buffer(&input),
            Binding::Buffer(&results),
            Binding::Buffer(&visited),
        ]);
        let mut recorded = Ok(());
        gpu.submit("shell traversal rays", |rec| {
            rec.fill_buffer(&self.tables.stats, 0);
            rec.fill_buffer(&results, 0xdead_beef);
            rec.fill_buffer(&visited, 0xdead_beef);
            rec.barrier();
            recorded = self.pipeline.record(
                rec,
                mesh,
                &bindings,
                bytemuck::bytes_of(&params),
                [rays.len() as u32, 1, 1],
            );
            rec.barrier();
        })?;
        recorded?;
        let results: Vec<RayResult> = gpu.read_buffer_as(&results)?;
        let visited: Vec<VisitedTet> = gpu.read_buffer_as(&visited)?;
        let traced = results
            .into_iter()
            .zip(visited.chunks(RECORDED_STEPS))
            .map(|(result, visited)| TracedRay {
                result,
                visited: visited[..(result.steps as usize).min(RECORDED_STEPS)].to_vec(),
            })
            .collect();
        Ok((traced, self.tables.read_stats(gpu)?))
    }

    /// Counters of the last [`ShellRays::trace`].
    pub fn read_stats(&self, gpu: &Gpu) -> Result<TraversalStats> {
        self.tables.read_stats(gpu)
    }
}
