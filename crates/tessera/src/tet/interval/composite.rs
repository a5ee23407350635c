//! The post pass of interval shading: what the pixels accumulated, turned into colour
//! (`composite.comp.glsl`: Beer–Lambert, added emission, or the maximum's colour).

use super::mesh::{OpticalStore, OpticalTarget};
use crate::builtin_shader;
use crate::error::Result;
use crate::path::Path;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// Push constants of `composite.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CompositeParams {
    pub background: [f32; 4],
    pub size: [u32; 4],
}

pub struct Composite {
    pipeline: Pipeline,
}

/// The interval defines, and where the accumulation is read from (a buffer on the compute path).
pub(crate) fn composite_defines(defines: &[(String, String)], path: Path) -> Vec<(String, String)> {
    let mut defines = defines.to_vec();
    let from_buffer = path == Path::Compute;
    defines.push(("SOURCE_BUFFER".into(), u32::from(from_buffer).to_string()));
    defines
}

impl Composite {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        path: Path,
    ) -> Result<Composite> {
        let from_buffer = path == Path::Compute;
        let defines = composite_defines(defines, path);
        let spirv = compiler.compile(&builtin_shader!("composite.comp.glsl"), &defines)?;
        let source = if from_buffer {
            Slot::StorageBuffer
        } else {
            Slot::StorageImage
        };
        let pipeline = gpu.compute_pipeline(
            "interval composite",
            &spirv,
            &[source, Slot::StorageBuffer, Slot::StorageBuffer],
        )?;
        Ok(Composite { pipeline })
    }

    pub fn record(
        &self,
        rec: &Recorder,
        target: &OpticalTarget,
        pixels: &Target,
        table: &Buffer,
        background: [f32; 3],
    ) {
        let params = CompositeParams {
            background: [background[0], background[1], background[2], 1.0],
            size: [target.width, target.height, 0, 0],
        };
        let source = match &target.store {
            OpticalStore::Image { image, .. } => Binding::StorageImage(image),
            OpticalStore::Buffer(buffer) => Binding::Buffer(buffer),
        };
        rec.dispatch(
            &self.pipeline,
            &[
                source,
                Binding::Buffer(&pixels.pixels),
                Binding::Buffer(table),
            ],
            bytemuck::bytes_of(&params),
            [target.width, target.height, 1],
        );
    }
}
