//! One shell pass (pixel rays, given rays, or an effect's lighting) on either way of tracing
//! the shell: a compute shader walking the BVH, or the ray-tracing pipeline (the paper's way)
//! whose ray-generation shader is the same source and whose hit groups test the faces in the
//! mesh's acceleration structure (`rt_trace.glsl`). Both find the same faces, so everything
//! after the traces is the same code.

use super::GpuShellMesh;
use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::path::Path;
use tessera_gpu::{
    Binding, Gpu, Pipeline, ProceduralHitGroup, RayTracingPipeline, RayTracingShaders, Recorder,
    ShaderCompiler, Slot, Source,
};

/// The hit groups of `rt_trace.glsl`, by their record offset.
const HIT_GROUPS: [&str; 3] = [
    "HIT_GROUP_EXIT",
    "HIT_GROUP_ENTRY_AHEAD",
    "HIT_GROUP_ENTRY_BEHIND",
];

/// The defines that pick the way of tracing; every shell shader gets them.
pub(crate) fn tracing_defines(path: Path) -> Vec<(String, String)> {
    let mut defines = vec![(
        "SHELL_RAY_TRACING".to_string(),
        u32::from(path == Path::Graphics).to_string(),
    )];
    defines.extend(
        HIT_GROUPS
            .iter()
            .enumerate()
            .map(|(i, name)| (name.to_string(), i.to_string())),
    );
    defines
}

pub(crate) enum ShellPass {
    Compute(Pipeline),
    RayTracing(RayTracingPipeline),
}

impl ShellPass {
    /// The pass compiled from `source` (a `.comp.glsl` file) with `defines` (which include
    /// [`tracing_defines`] of `path`) over `buffers` storage buffers; on the ray-tracing
    /// pipeline the acceleration structure is bound after them.
    pub(crate) fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        name: &str,
        source: Source,
        defines: &[(String, String)],
        buffers: usize,
        path: Path,
    ) -> Result<ShellPass> {
        let mut slots = vec![Slot::StorageBuffer; buffers];
        if path == Path::Compute {
            let spirv = compiler.compile(&source, defines)?;
            return Ok(ShellPass::Compute(
                gpu.compute_pipeline(name, &spirv, &slots)?,
            ));
        }
        slots.push(Slot::AccelerationStructure);
        let mut defines = defines.to_vec();
        defines.push(("SHELL_SCENE_BINDING".into(), buffers.to_string()));
        let ray_generation =
            Source::new(source.path.replace(".comp.glsl", ".rgen.glsl"), source.text);
        let ray_generation = compiler.compile(&ray_generation, &defines)?;
        let miss = compiler.compile(&builtin_shader!("shell.rmiss.glsl"), &[])?;
        let mut hit_shaders = Vec::new();
        for group in HIT_GROUPS {
            let mut group_defines = defines.clone();
            group_defines.push(("SHELL_HIT_GROUP".into(), group.into()));
            hit_shaders.push((
                compiler.compile(&builtin_shader!("face_hit.rint.glsl"), &group_defines)?,
                compiler.compile(&builtin_shader!("face_hit.rahit.glsl"), &group_defines)?,
            ));
        }
        let hit_groups: Vec<ProceduralHitGroup> = hit_shaders
            .iter()
            .map(|(intersection, any_hit)| ProceduralHitGroup {
                intersection,
                any_hit: Some(any_hit),
                closest_hit: None,
            })
            .collect();
        let shaders = RayTracingShaders {
            ray_generation: &ray_generation,
            misses: &[&miss],
            hit_groups: &hit_groups,
        };
        Ok(ShellPass::RayTracing(
            gpu.ray_tracing_pipeline(name, &shaders, &slots)?,
        ))
    }

    pub(crate) fn path(&self) -> Path {
        match self {
            ShellPass::Compute(_) => Path::Compute,
            ShellPass::RayTracing(_) => Path::Graphics,
        }
    }

    /// Records the pass over `threads` invocations (pixels, rays or tets) with `bindings`
    /// (the storage buffers) and `push` constants.
    pub(crate) fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuShellMesh,
        bindings: &[Binding],
        push: &[u8],
        threads: [u32; 3],
    ) -> Result<()> {
        match self {
            ShellPass::Compute(pipeline) => {
                rec.dispatch(pipeline, bindings, push, threads);
                Ok(())
            }
            ShellPass::RayTracing(pipeline) => {
                let scene = mesh.scene.as_ref().ok_or_else(|| {
                    Error::Invalid(
                        "shell traversal: a mesh uploaded without its acceleration structure \
                         for a pass on the ray-tracing pipeline"
                            .into(),
                    )
                })?;
                let mut bindings = bindings.to_vec();
                bindings.push(Binding::AccelerationStructure(scene));
                Ok(rec.trace_rays(pipeline, &bindings, push, threads)?)
            }
        }
    }
}
